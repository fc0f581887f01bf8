"""Single DEM trials of a Table 1 wall with a longer t_max (docs/dem.md, section 12): does a
trial that stood for 5 s still stand for longer? One settling, then one ideal-impulse run per
v_g; one JSON line per trial (collapsed, t_collapse, CPU).

    python benchmarks/dem_long_trials.py B1 0.75 0.7667 --t-max 10 --set kn=0.3e9 --set ks_over_kn=1
"""

from __future__ import annotations

import argparse
import json
import time

from dem_table1 import override


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("wall", help="Table 1 test name, e.g. B1")
    ap.add_argument("v", type=float, nargs="+", help="ideal impulses v_g [m/s]")
    ap.add_argument("--t-max", type=float, default=10.0, help="trial length [s]")
    ap.add_argument("--set", type=override, action="append", default=[], dest="over",
                    metavar="KEY=VALUE", help="a DEMParams override (repeatable)")
    args = ap.parse_args(argv)

    from homlimit.blocks.geometry import t_section_blocks
    from homlimit.closed_form.paper import table1
    from homlimit.dem import DEMParams, build_model, run, settle

    over = dict(args.over)
    row = {r.test: r for r in table1()}[args.wall]
    model = build_model(t_section_blocks(row.case, facade="through"), DEMParams(**over))
    settled, _ = settle(model)
    for v in args.v:
        c0 = time.process_time()
        out = run(model, settled, v_g=v, t_max=args.t_max)
        print(json.dumps({"test": args.wall, "overrides": over, "v": v, "t_max": args.t_max,
                          "collapsed": bool(out.collapsed),
                          "t_collapse": out.t_collapse if out.collapsed else None,
                          "t_end": out.t_end, "cpu": time.process_time() - c0}), flush=True)


if __name__ == "__main__":
    main()
