"""Table 1 with the rigid-block column: for the paper's 12 walls, the closed forms I and II,
the DEM and the rigid-block model (the paper's façade, one block through its thickness,
toothed into the wall with overlap c; associative friction; h-scan over every course
boundary; the non-associative check of Gilbert et al. 2006 at the critical height).

Writes
    <out>/blocks_table1.csv      one row per wall (columns: studies.table1_blocks)
    <out>/blocks_table1.png      v̄_g/√(gb) of every model against the DEM, and λ = h/b
    <out>/blocks_table1_ratios.json   B4/B1, B5/B2, B6/B3 for every model
    <out>/blocks_table1_<test>_critical.png, _whole.png   mechanisms of --figures (B1 B4)

Usage: python examples/blocks_table1.py [--out docs/figures] [--tests B1 B4]
[--figures B1 B4] [--plot-only]
(about 6 minutes on 2 shared cores). The write-up is docs/blocks.md.
"""

from __future__ import annotations

import argparse
import logging
from pathlib import Path

from homlimit.app.report import format_table, write
from homlimit.blocks.studies import table1_blocks


def plot(path: Path, rows: list[dict]) -> Path:
    from homlimit.app.plots import pyplot, save_png

    plt = pyplot()
    fig, axes = plt.subplots(1, 2, figsize=(12, 5.6))
    x = range(len(rows))
    labels = [r["test"] for r in rows]
    ax = axes[0]
    for key, lab, m in (("vnorm_dem", "DEM (paper)", "k*"), ("vnorm_I", "mechanism I", "v"),
                        ("vnorm_II", "mechanism II", "^"),
                        ("vnorm_blocks", "blocks, one-DOF", "o"),
                        ("vnorm_blocks_rigid", "blocks, body only (eq. 19)", "s"),
                        ("vnorm_na", "blocks, non-associative", "D")):
        if key in rows[0]:
            ax.plot(x, [r[key] for r in rows], m, ls="none" if m != "k*" else "none",
                    label=lab, mfc="none" if m not in ("k*", "o") else None)
    ax.set_xticks(list(x), labels)
    ax.set_ylabel("v̄_g / √(g b)")
    ax.legend(fontsize=8, loc="upper center", bbox_to_anchor=(0.5, -0.08), ncol=3)
    ax.set_title("collapse ground velocity")
    ax = axes[1]
    for key, lab, m in (("lam_dem", "DEM (paper)", "k*"), ("lam_I", "mechanism I", "v"),
                        ("lam_II", "mechanism II", "^"), ("lam_blocks", "blocks, h-scan", "o"),
                        ("lam_whole", "blocks, whole-wall mechanism", "s")):
        ax.plot(x, [r[key] for r in rows], m, ls="none", label=lab,
                mfc="none" if m not in ("k*", "o") else None)
    ax.set_xticks(list(x), labels)
    ax.set_ylabel("λ = h / b")
    ax.legend(fontsize=8, loc="upper center", bbox_to_anchor=(0.5, -0.08), ncol=3)
    ax.set_title("height of the failing part")
    fig.tight_layout()
    return save_png(fig, path)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default="docs/figures")
    ap.add_argument("--tests", nargs="+", default=None)
    ap.add_argument("--step", type=int, default=1)
    ap.add_argument("--figures", nargs="*", default=["B1", "B4"])
    ap.add_argument("--plot-only", action="store_true",
                    help="redraw blocks_table1.png from the CSV already in --out")
    logging.basicConfig(level=logging.INFO, format="%(message)s")
    args = ap.parse_args(argv)
    out = Path(args.out)
    if args.plot_only:
        import csv

        def num(v):
            try:
                return float(v)
            except ValueError:
                return v

        with open(out / "blocks_table1.csv", newline="") as fh:
            plot(out / "blocks_table1.png", [{k: num(v) for k, v in r.items()}
                                             for r in csv.DictReader(fh)])
        return
    rows, ratios = table1_blocks(step=args.step, tests=args.tests,
                                 figures_dir=out, figures_for=tuple(args.figures))
    for r in rows:
        r["lam_whole"] = r["h_whole"] / (r["h_dem"] / r["lam_dem"])
    write(out / "blocks_table1.csv", rows)
    write(out / "blocks_table1_ratios.json", ratios)
    plot(out / "blocks_table1.png", rows)
    print(format_table(
        ["test", "blocks", "mult whole", "h_whole", "h crit", "lam crit", "vn blocks",
         "vn rigid", "vn non-assoc", "lam I", "vn I", "lam II", "vn II", "lam DEM", "vn DEM"],
        [[r["test"], r["blocks"], r["multiplier_whole"], r["h_whole"], r["h_blocks"],
          r["lam_blocks"], r["vnorm_blocks"], r["vnorm_blocks_rigid"], r.get("vnorm_na"),
          r["lam_I"], r["vnorm_I"], r["lam_II"], r["vnorm_II"], r["lam_dem"],
          r["vnorm_dem"]] for r in rows]))
    for pair, vals in ratios.items():
        print(pair, "  ".join(f"{k.removeprefix('vnorm_')} {v:.3f}" for k, v in vals.items()))


if __name__ == "__main__":
    main()
