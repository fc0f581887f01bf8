"""Where the ideal impulse's energy goes in the DEM (docs/dem.md, section 21): for each Table 1
wall, the highest safe and the lowest collapsing trial of its threshold bracket, run with the
kernel's energy terms (``Outcome.energy``): friction work with the ground, in bed joints and in
the other joints (head joints and the façade's inner face), as fractions of the kinetic energy
E0 = ½ Σ m v_g² the impulse gives the free blocks (E0 split into the façade's and toothing
blocks' share, the watched blocks, and the wall's). One JSON line per trial; ``--plot`` draws
the energies against time for the safe trials.

    python benchmarks/dem_energy.py B1 B4                  # brackets from the defaults' table
    python benchmarks/dem_energy.py --table docs/figures/dem_energy.jsonl \
        --plot docs/figures/dem_energy.png

The brackets (vg_lo, vg_hi) are read from ``--brackets`` (default
docs/figures/dem_table1_after_fix.csv, the defaults' ``homlimit table1 --dem`` of section 19).
About 10–70 s of CPU per trial on one core.
"""

from __future__ import annotations

import argparse
import csv
import json
import time
from pathlib import Path

import numpy as np
from dem_table1 import add_overrides, settled_wall

ROOT = Path(__file__).resolve().parents[1]
BRACKETS = ROOT / "docs" / "figures" / "dem_table1_after_fix.csv"
TERMS = ("friction_base", "friction_bed_facade", "friction_bed", "friction_head")


def brackets(path: Path) -> dict[str, tuple[float, float]]:
    """{wall: (vg_lo, vg_hi)} of a ``table1 --dem`` CSV."""
    with open(path, newline="") as fh:
        rows = list(csv.DictReader(fh))
    return {r["test"]: (float(r["vg_lo [m/s]"]), float(r["vg_hi [m/s]"])) for r in rows}


def trial(wall: str, model, settled, v: float, t_max: float, every: int) -> dict:
    """One ideal-impulse trial's energy budget (module docstring)."""
    from homlimit.dem import run

    free = ~model.assembly.fixed
    m = model.assembly.mass
    e0 = 0.5 * m[free].sum() * v * v
    e0_watched = 0.5 * m[model.watch].sum() * v * v
    c0 = time.process_time()
    out = run(model, settled, v_g=v, t_max=t_max, record_every=every)
    r = out.record
    k = int(np.argmax(r[:, 2]))                       # the highest potential energy
    e = out.energy
    return {"test": wall, "v": v, "collapsed": bool(out.collapsed),
            "t_end": out.t_end, "E0": e0, "E0_watched": e0_watched,
            **{f"{t}/E0": e[t] / e0 for t in TERMS},
            "dissipated/E0": sum(e[t] for t in TERMS) / e0,
            "t_pe_max": float(r[k, 0]), "pe_max/E0": float(r[k, 2] / e0),
            "dissipated_at_pe_max/E0": float(r[k, 6] / e0),
            "balance_drift/E0": float(np.ptp(out.energy_balance()) / e0),
            "t": r[:, 0].tolist(), "ke/E0": (r[:, 1] / e0).tolist(),
            "pe/E0": (r[:, 2] / e0).tolist(), "d/E0": (r[:, 6] / e0).tolist(),
            "cpu": time.process_time() - c0}


def table(lines: list[dict]) -> str:
    head = ("| wall | v_g [m/s] | collapsed | E0 watched / E0 | base | façade's bed joints "
            "| wall's bed joints | other joints | dissipated "
            "| at the highest PE (t [s]): PE, dissipated | balance drift |\n"
            "|---|---|---|---|---|---|---|---|---|---|---|")
    rows = [f"| {d['test']} | {d['v']:.4g} | {'yes' if d['collapsed'] else 'no'} "
            f"| {d['E0_watched'] / d['E0']:.3f} | {d['friction_base/E0']:.3f} "
            f"| {d['friction_bed_facade/E0']:.3f} | {d['friction_bed/E0']:.3f} "
            f"| {d['friction_head/E0']:.3f} "
            f"| {d['dissipated/E0']:.3f} | ({d['t_pe_max']:.2f}) {d['pe_max/E0']:.3f}, "
            f"{d['dissipated_at_pe_max/E0']:.3f} | {d['balance_drift/E0']:.1e} |"
            for d in lines]
    return "\n".join([head, *rows])


def plot(lines: list[dict], path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    safe = [d for d in lines if not d["collapsed"]]
    fig, axs = plt.subplots(1, 3, figsize=(13, 3.8), sharey=True)
    for ax, key, name in zip(axs, ("ke/E0", "pe/E0", "d/E0"),
                             ("kinetic", "potential", "dissipated by friction")):
        for d in safe:
            ax.plot(d["t"], d[key], label=f"{d['test']} ({d['v']:.3g} m/s)")
        ax.set_title(f"{name} / E0")
        ax.set_xlabel("t [s]")
        ax.grid(alpha=0.3)
    axs[0].legend(fontsize=8)
    fig.suptitle("Highest safe trial of each wall: energies over the impulse's E0")
    fig.tight_layout()
    fig.savefig(path, dpi=110)


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("walls", nargs="*", help="Table 1 test names, e.g. B1 B4")
    ap.add_argument("--brackets", type=Path, default=BRACKETS)
    ap.add_argument("--t-max", type=float, default=5.0, help="trial length [s]")
    ap.add_argument("--every", type=int, default=200, help="record every this many steps")
    ap.add_argument("--table", type=Path, help="print the table of these JSON lines")
    ap.add_argument("--plot", type=Path, help="with --table: draw the safe trials")
    add_overrides(ap)
    args = ap.parse_args(argv)
    if args.table:
        lines = [json.loads(s) for s in args.table.read_text().splitlines() if s.strip()]
        print(table(lines))
        if args.plot:
            plot(lines, args.plot)
        return
    known = brackets(args.brackets)
    for w in args.walls:
        if w not in known:
            ap.error(f"wall {w!r}: not in {args.brackets} (allowed: {', '.join(known)})")
    over = dict(args.over)
    for w in args.walls:
        model, settled = settled_wall(w, over)
        for v in known[w]:
            d = trial(w, model, settled, v, args.t_max, args.every)
            print(json.dumps({**d, "overrides": over}), flush=True)


if __name__ == "__main__":
    main()
