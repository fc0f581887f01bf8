"""The façade's and the wall's outward momentum after an impulse on all, or part, of a Table 1
wall (docs/dem.md section 22): one v_g, three loads (every block, the façade's and toothing
blocks alone, the wall's blocks alone; ``dem_table1.part_impulse``), the state every
``--interval`` s (``dem.output.record_frames``). Printed per load and time: the horizontal
momentum of the watched blocks (the façade's and toothing blocks) over M_façade·v_g, and of
the wall's free blocks over M_wall·v_g (−1: all of the impulse's, outwards).

    python benchmarks/dem_momentum.py B1 0.875 B4 0.796875      # wall, v_g pairs

About 15 s of CPU per wall and load for 1 s of simulated time.
"""

from __future__ import annotations

import argparse

import numpy as np
from dem_table1 import part_impulse, settled_wall

TIMES = (0.0, 0.04, 0.1, 0.2, 0.3, 0.5, 0.8, 1.0)


def momenta(model, frames, v: float) -> list[tuple[float, float, float]]:
    """(t, façade's, wall's) outward momentum of each frame, as fractions (module docstring)."""
    m = model.assembly.mass
    fac = model.watch
    wall = ~fac & ~model.assembly.fixed
    rows = []
    for f in frames:
        u = f.state.vel[:, 0]
        rows.append((f.t, (m[fac] * u[fac]).sum() / (m[fac].sum() * v),
                     (m[wall] * u[wall]).sum() / (m[wall].sum() * v)))
    return rows


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("pairs", nargs="+", help="wall and v_g [m/s], e.g. B1 0.875 B4 0.796875")
    ap.add_argument("--t-max", type=float, default=1.0, help="simulated time [s]")
    ap.add_argument("--interval", type=float, default=0.02, help="frame interval [s]")
    args = ap.parse_args(argv)
    if len(args.pairs) % 2:
        ap.error("pairs: a wall and a v_g each")
    from homlimit.dem.output import record_frames

    print("| wall | v_g [m/s] | load | " + " | ".join(f"t = {t:g} s" for t in TIMES) + " |")
    print("|---|---|---|" + "---|" * len(TIMES))
    for wall, v in zip(args.pairs[::2], map(float, args.pairs[1::2])):
        model, settled = settled_wall(wall, {})
        loads = {"every block": {"v_g": v},
                 "façade alone": part_impulse(model, facade=True)(v),
                 "wall alone": part_impulse(model, facade=False)(v)}
        for name, load in loads.items():
            frames = record_frames(model, settled, t_max=args.t_max, interval=args.interval,
                                   stop_on_collapse=False, **load)
            rows = momenta(model, frames, v)
            t = np.array([r[0] for r in rows])
            cells = []
            for tt in TIMES:
                k = int(np.argmin(np.abs(t - tt)))
                cells.append(f"{rows[k][1]:+.2f} / {rows[k][2]:+.2f}")
            print(f"| {wall} | {v:g} | {name} | " + " | ".join(cells) + " |", flush=True)


if __name__ == "__main__":
    main()
