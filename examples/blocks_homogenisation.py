"""The homogenisation limit, measured: the Table 1 T-section B1 (ρ = 12, c/a = 2/3, f = 0.6) in
rigid blocks shrunk (a, c) → (a, c)/k, k = 1, 2, 4, 8, at fixed c/a, against the homogenised
hinge + fan (``fan.optimise_fan``), for both façade bonds:

- "through": the paper's façade, one block across its thickness per course (bed joints only);
- "running-bond": the wall's bond continued through the façade (the discrete counterpart of
  the homogenised façade of eq. 15, which the hinge + fan assumes).

Writes
    <out>/blocks_homogenisation.csv            one record per (façade, k)
    <out>/blocks_homogenisation.png            λ against the block size, fan line, trends
    <out>/blocks_homogenisation_fe.json        the FE multipliers (with --fe)
    <out>/blocks_homogenisation_<facade>_k<k>.png   each mechanism (blocks coloured by speed)

Usage: python examples/blocks_homogenisation.py [--out docs/figures] [--factors 1 2 4 8]
[--fe]  (k = 8 has 29–31 thousand blocks and takes 7–12 minutes per façade on 2 shared cores;
--fe adds the FE multipliers of the homogenised and bed-joints façades at h = 0.25, 0.125 m,
about 3 minutes; --plot-only redraws the summary PNG from the files already in --out). The
write-up is docs/blocks.md.
"""

from __future__ import annotations

import argparse
import logging
import math
from pathlib import Path

from homlimit._io import write_json
from homlimit.app.report import format_table, write
from homlimit.blocks.studies import homogenisation_study
from homlimit.params import Case, Masonry, Wall

B1 = Case(Wall(H=9, L=6, s=0.5, b=0.5, l=6), Masonry(a=0.3, c=0.2, f=0.6), name="B1")


def richardson(recs: list[dict]) -> float:
    """λ∞ from the last three sizes, error ∝ (block size)^p with the observed p."""
    if len(recs) < 3:
        return math.nan
    l1, l2, l3 = (r["multiplier"] for r in recs[-3:])
    d1, d2 = l1 - l2, l2 - l3
    if d1 * d2 <= 0:
        return math.nan
    q = d2 / d1                        # error ratio per halving
    return l3 - d2 * q / (1 - q)


def plot(path: Path, recs: list[dict], fe: dict) -> Path:
    from homlimit.app.plots import pyplot, save_png

    plt = pyplot()
    fig, ax = plt.subplots(figsize=(10.5, 4.8))
    for facade, marker in (("through", "o"), ("running-bond", "s")):
        sel = [r for r in recs if r["facade"] == facade]
        if sel:
            ax.plot([r["a"] for r in sel], [r["multiplier"] for r in sel], marker=marker,
                    label=f"blocks, {facade} façade")
        lam = richardson(sel)
        if math.isfinite(lam):
            ax.plot([0.0], [lam], marker=marker, mfc="none", ls="none",
                    color=ax.lines[-1].get_color(),
                    label=f"extrapolated ({facade}): {lam:.4f}")
    ax.axhline(recs[0]["fan_multiplier"], color="k", ls="--",
               label=f"hinge + fan (homogenised façade) {recs[0]['fan_multiplier']:.4f}")
    for key, lam in fe.items():
        name, h = key.split("@")
        ax.plot([0.0], [lam], marker="x" if name == "bedjoints" else "+", color="tab:red"
                if name == "bedjoints" else "tab:green", ls="none", ms=9,
                label=f"FE {name} façade, h = {h} m: {lam:.4f}")
    ax.set_xlabel("block height a [m] (2c = 4a/3)")
    ax.set_ylabel("collapse multiplier λ (whole wall)")
    ax.set_xlim(left=-0.01)
    ax.set_title("B1 in rigid blocks: the homogenisation limit (a, c)/k")
    ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    fig.tight_layout()
    return save_png(fig, path)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default="docs/figures")
    ap.add_argument("--factors", type=float, nargs="+", default=[1, 2, 4, 8])
    ap.add_argument("--facades", nargs="+", default=["through", "running-bond"])
    ap.add_argument("--fe", action="store_true")
    ap.add_argument("--plot-only", action="store_true",
                    help="redraw the summary PNG from the CSV and FE JSON already in --out")
    logging.basicConfig(level=logging.INFO, format="%(message)s")
    args = ap.parse_args(argv)
    out = Path(args.out)
    if args.plot_only:
        import csv
        import json

        with open(out / "blocks_homogenisation.csv", newline="") as fh:
            recs = [{k: (v if k == "facade" else float(v)) for k, v in r.items()}
                    for r in csv.DictReader(fh)]
        fe_path = out / "blocks_homogenisation_fe.json"
        fe = json.loads(fe_path.read_text()) if fe_path.exists() else {}
        plot(out / "blocks_homogenisation.png", recs, fe)
        return
    recs = homogenisation_study(B1, args.factors, args.facades, figures_dir=out)
    fe = {}
    if args.fe:
        from homlimit.fe.kinematic import solve_kinematic
        from homlimit.fe.problems import t_section

        for name in ("homogenised", "bedjoints"):
            for h in (0.25, 0.125):
                lam = solve_kinematic(t_section(B1, facade=name, h=h)).multiplier
                fe[f"{name}@{h}"] = lam
                print(f"  FE {name} façade, h = {h} m: λ = {lam:.5f}", flush=True)
        write_json(out / "blocks_homogenisation_fe.json", fe)
    elif (out / "blocks_homogenisation_fe.json").exists():     # from an earlier --fe run
        import json

        fe = json.loads((out / "blocks_homogenisation_fe.json").read_text())
    write(out / "blocks_homogenisation.csv", recs)
    plot(out / "blocks_homogenisation.png", recs, fe)
    rows = [[r["facade"], int(r["k"]), r["a"], r["blocks"], r["multiplier"],
             100 * r["diff"], r["z_hinge"], r["slope_90"], r["slope_50"], r["slope_10"],
             r["solve_time"]] for r in recs]
    print(format_table(["facade", "k", "a [m]", "blocks", "lambda", "diff vs fan [%]",
                        "z_O [m]", "T 90%", "T 50%", "T 10%", "solve [s]"], rows,
                       title=f"hinge + fan: lambda = {recs[0]['fan_multiplier']:.5f}, "
                             f"z0 = {recs[0]['fan_z0']:.2f} m, T1 = {recs[0]['fan_T1']:.3f}, "
                             f"T2 = {recs[0]['fan_T2']:.3f}"))
    for facade in args.facades:
        sel = [r for r in recs if r["facade"] == facade]
        lam = richardson(sel)
        if math.isfinite(lam):
            print(f"{facade}: extrapolated lambda = {lam:.5f} "
                  f"({100 * (lam / recs[0]['fan_multiplier'] - 1):+.2f} % against the fan)")


if __name__ == "__main__":
    main()
