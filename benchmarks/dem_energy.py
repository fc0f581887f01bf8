"""Where the ideal impulse's energy goes in the DEM (docs/dem.md, section 21): for each Table 1
wall, the highest safe and the lowest collapsing trial of its threshold bracket, run again with
the kernel's energy terms (``Outcome.energy``): friction work with the ground, in the façade's
bed joints, in the wall's and in the other joints (head joints and the façade's inner face),
as fractions of the kinetic energy E0 = ½ Σ m v_g² the impulse gives the free blocks (the
watched blocks', façade and toothing, share of it beside). One JSON line per trial;
``--table`` prints them, ``--plot`` draws the safe trials' energies against time.

    python benchmarks/dem_energy.py B1 B4                  # bisection as table1 --dem, then
                                                           # the bracket's two trials again
    python benchmarks/dem_energy.py --table docs/figures/dem_energy.jsonl \
        --plot docs/figures/dem_energy.png

The bracket comes from a bisection run here (``collapse_threshold``: first trial UDEC's v̄_g
rounded to 0.1 m/s, ±1 %, t_max 5 s, as ``homlimit table1 --dem``), not from a result file:
a file's amplitudes carry 15 significant digits, and near the threshold a trial can turn on
less (B6: 1.0697916666666667 m/s stands for 5 s, 1.06979166666667 collapses at 3.6 s).
About 2–7 min of CPU per wall on one core.
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

import numpy as np
from dem_table1 import add_overrides, settled_wall

TERMS = ("friction_base", "friction_bed_facade", "friction_bed", "friction_head")


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
            # the series to 5 decimals (a figure's resolution), so the JSON stays small
            "t": np.round(r[:, 0], 5).tolist(), "ke/E0": np.round(r[:, 1] / e0, 5).tolist(),
            "pe/E0": np.round(r[:, 2] / e0, 5).tolist(),
            "d/E0": np.round(r[:, 6] / e0, 5).tolist(),
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
    ap.add_argument("--t-max", type=float, default=5.0, help="trial length [s]")
    ap.add_argument("--sample", type=float, default=0.01,
                    help="record the energies every this many seconds [s]")
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
    from homlimit.closed_form.paper import table1
    from homlimit.dem.threshold import collapse_threshold

    rows = {r.test: r for r in table1()}
    for w in args.walls:
        if w not in rows:
            ap.error(f"wall {w!r}: not a Table 1 test (allowed: {', '.join(rows)})")
    over = dict(args.over)
    for w in args.walls:
        model, settled = settled_wall(w, over)
        th = collapse_threshold(model, settled, guess=round(rows[w].vg, 1), t_max=args.t_max)
        every = max(1, round(args.sample / model.dt))
        for v, expect in ((th.lo, False), (th.hi, True)):
            d = trial(w, model, settled, v, args.t_max, every)
            d.update(threshold=th.v, reproduced=d["collapsed"] == expect, overrides=over)
            print(json.dumps(d), flush=True)


if __name__ == "__main__":
    main()
