"""The DEM's ideal-impulse collapse threshold of Table 1 walls beside UDEC's (docs/dem.md, section
5): default DEMParams for every wall, the T-section with the façade "through", bisection to
±1 %, t_max 5 s. One JSON line per wall: v (lo, hi), h, slide flags and slips, trials, CPU.
About 1.5–5 min of CPU per wall on one core.

    python benchmarks/dem_table1.py B1 B4 [--guess 0.8] [--t-max 5]

The guess only sets where the bracket search starts (steps of ×1.5); it does not change the
threshold beyond the bisection's tolerance.
"""

from __future__ import annotations

import argparse
import json
import time


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("walls", nargs="+", help="Table 1 test names, e.g. B1 B4")
    ap.add_argument("--guess", type=float, default=None,
                    help="first trial [m/s] (default: UDEC's value rounded to 0.1)")
    ap.add_argument("--t-max", type=float, default=5.0, help="trial length [s]")
    args = ap.parse_args(argv)

    from homlimit.blocks.geometry import t_section_blocks
    from homlimit.closed_form.paper import table1
    from homlimit.dem import build_model
    from homlimit.dem.threshold import collapse_threshold

    rows = {r.test: r for r in table1()}
    for name in args.walls:
        row = rows[name]
        model = build_model(t_section_blocks(row.case, facade="through"))
        guess = args.guess if args.guess is not None else round(row.vg, 1)
        t0 = time.perf_counter()
        th = collapse_threshold(model, guess=guess, t_max=args.t_max)
        out = {**th.as_dict(), "test": name, "udec_vg": row.vg, "udec_h": row.h_v,
               "ratio": th.v / row.vg, "vg_norm": th.v / (row.case.wall.g
                                                         * row.case.wall.b) ** 0.5,
               "wall_clock": time.perf_counter() - t0, "trials": th.trials,
               "settle": th.settle}
        print(json.dumps(out, default=str), flush=True)


if __name__ == "__main__":
    main()
