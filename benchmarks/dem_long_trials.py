"""Single DEM trials of a Table 1 wall with a longer t_max (docs/dem.md, section 12): does a
trial that stood for 5 s still stand for longer? One settling, then one ideal-impulse run per
v_g; one JSON line per trial (collapsed, t_collapse, CPU).

    python benchmarks/dem_long_trials.py B1 0.75 0.7667 --t-max 10 --set kn=0.3e9 --set ks_over_kn=1
"""

from __future__ import annotations

import argparse
import json
import time

from dem_table1 import add_overrides, settled_wall


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("wall", help="Table 1 test name, e.g. B1")
    ap.add_argument("v", type=float, nargs="+", help="ideal impulses v_g [m/s]")
    ap.add_argument("--t-max", type=float, default=10.0, help="trial length [s]")
    add_overrides(ap)
    args = ap.parse_args(argv)

    from homlimit.dem import run

    over = dict(args.over)
    model, settled = settled_wall(args.wall, over)
    for v in args.v:
        c0 = time.process_time()
        out = run(model, settled, v_g=v, t_max=args.t_max)
        print(json.dumps({"test": args.wall, "overrides": over, "v": v, "t_max": args.t_max,
                          "collapsed": bool(out.collapsed),
                          "t_collapse": out.t_collapse if out.collapsed else None,
                          "t_end": out.t_end, "cpu": time.process_time() - c0}), flush=True)


if __name__ == "__main__":
    main()
