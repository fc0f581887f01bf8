"""The DEM's ideal-impulse collapse threshold of Table 1 walls beside UDEC's (docs/dem.md, section
5): one DEMParams for every wall (the defaults, or those with ``--set KEY=VALUE`` overrides,
the same for all walls listed), the T-section with the façade "through", bisection to ±1 %,
t_max 5 s. One JSON line per wall: v (lo, hi), h, slide flags and slips, trials, the
overrides, CPU (the trials' and the process's, settling included). About 1–5 min of CPU per
wall on one core.

    python benchmarks/dem_table1.py B1 B4 [--guess 0.8] [--t-max 5]
    python benchmarks/dem_table1.py B1 B4 --set kn=0.3e9 --set ks_over_kn=1   # section 12

The guess only sets where the bracket search starts (steps of ×1.5); it does not change the
threshold beyond the bisection's tolerance.
"""

from __future__ import annotations

import argparse
import json
import time


def override(text: str) -> tuple[str, object]:
    """``KEY=VALUE`` of a DEMParams field: VALUE as int, float or else the string."""
    key, sep, value = text.partition("=")
    if not sep:
        raise argparse.ArgumentTypeError(f"--set {text!r}: expected KEY=VALUE")
    for kind in (int, float):
        try:
            return key.strip(), kind(value)
        except ValueError:
            pass
    return key.strip(), value.strip()


def add_overrides(ap: argparse.ArgumentParser) -> None:
    """The repeatable ``--set KEY=VALUE`` option (``override``), into ``args.over``."""
    ap.add_argument("--set", type=override, action="append", default=[], dest="over",
                    metavar="KEY=VALUE", help="a DEMParams override (repeatable)")


def settled_wall(wall: str, over: dict):
    """(model, settled state) of Table 1's ``wall`` (the T-section, façade through) with the
    DEMParams ``over``rides, settled under gravity."""
    from homlimit.blocks.geometry import t_section_blocks
    from homlimit.closed_form.paper import table1
    from homlimit.dem import DEMParams, build_model, settle

    row = {r.test: r for r in table1()}[wall]
    model = build_model(t_section_blocks(row.case, facade="through"), DEMParams(**over))
    return model, settle(model)[0]


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("walls", nargs="+", help="Table 1 test names, e.g. B1 B4")
    ap.add_argument("--guess", type=float, default=None,
                    help="first trial [m/s] (default: UDEC's value rounded to 0.1)")
    ap.add_argument("--t-max", type=float, default=5.0, help="trial length [s]")
    ap.add_argument("--set", type=override, action="append", default=[], dest="over",
                    metavar="KEY=VALUE", help="a DEMParams override, the same for every wall "
                    "(repeatable), e.g. kn=0.3e9, ks_over_kn=1, facade_stiffness=1")
    args = ap.parse_args(argv)

    from homlimit.blocks.geometry import t_section_blocks
    from homlimit.closed_form.paper import table1
    from homlimit.dem import DEMParams, build_model
    from homlimit.dem.threshold import collapse_threshold
    from homlimit.errors import ParameterError

    over = dict(args.over)
    fields = DEMParams.__dataclass_fields__
    for key in over:
        if key not in fields:
            ap.error(f"--set {key}: not a DEMParams field (allowed: {', '.join(fields)})")
    try:
        params = DEMParams(**over)       # values checked before any wall runs
    except ParameterError as err:
        ap.error(str(err))
    rows = {r.test: r for r in table1()}
    for name in args.walls:
        if name not in rows:
            ap.error(f"wall {name!r}: not a Table 1 test (allowed: {', '.join(rows)})")
    for name in args.walls:
        row = rows[name]
        t0 = time.perf_counter()
        c0 = time.process_time()
        model = build_model(t_section_blocks(row.case, facade="through"), params)
        guess = args.guess if args.guess is not None else round(row.vg, 1)
        th = collapse_threshold(model, guess=guess, t_max=args.t_max)
        out = {**th.as_dict(), "test": name, "udec_vg": row.vg, "udec_h": row.h_v,
               "ratio": th.v / row.vg, "vg_norm": th.v / (row.case.wall.g
                                                         * row.case.wall.b) ** 0.5,
               "overrides": over, "cpu_process": time.process_time() - c0,
               "wall_clock": time.perf_counter() - t0, "trials": th.trials,
               "settle": th.settle}
        print(json.dumps(out, default=str), flush=True)


if __name__ == "__main__":
    main()
