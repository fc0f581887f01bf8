"""The DEM's collapse threshold of Table 1 walls beside UDEC's (docs/dem.md, sections 5, 12, 13),
under the ideal impulse or a pulse: one DEMParams for every wall (the defaults, or those with
``--set KEY=VALUE`` overrides, the same for all walls listed), the T-section with the façade
"through", bisection to ±1 %, t_max 5 s. One JSON line per wall: v (lo, hi), h, slide flags
and slips, trials, the overrides, CPU (the trials' and the process's, settling included).
About 1–5 min of CPU per wall on one core.

    python benchmarks/dem_table1.py B1 B4 [--guess 0.8] [--t-max 5]
    python benchmarks/dem_table1.py B1 B4 --set kn=0.3e9 --set ks_over_kn=1   # section 12
    python benchmarks/dem_table1.py B1 B4 --loading rectangular --pulse-period 0.1  # section 13

The guess only sets where the bracket search starts (steps of ×1.5); it does not change the
threshold beyond the bisection's tolerance. With ``--loading`` a pulse (``dynamics.pulses``,
polarity +1: the façade's inertia outwards) replaces the ideal impulse; the threshold is its
amplitude a_g, reported with its pgv (rectangular: a_g·Δt; ``pulse_loading``) as "pgv",
"ratio" and "vg_norm", and the first trial is the a_g whose pgv is the guess (UDEC's v̄_g
over pgv/a_g, Δt for the rectangle), so a rectangular pulse's trials in pgv are the
impulse's.
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
                    metavar="KEY=VALUE", help="a DEMParams override, the same for every wall "
                    "(repeatable), e.g. kn=0.3e9, ks_over_kn=1, facade_stiffness=1")


def pulse_loading(kind: str, period: float, polarity: int = 1):
    """(load, pgv, pgv_per_ag) of the pulse ``kind`` of period T_p [s] (``make_pulse``;
    polarity +1: the first or main lobe throws the façade outwards, −1 the pulse flipped, whose
    last lobe does): load(a_g) -> the
    keywords of ``run``; pgv(a_g) -> its peak |∫a_g dt| [m/s] (``Pulse.pgv``: the pulses'
    closed forms, a_g T_p for the rectangle, a_g T_p/π one-sine, a_g T_p/(2π) one-cosine,
    a_g T_p e^{-1/2}/(π√2) Ricker, checked against the numerical integral in
    tests/test_dynamics_pulses.py); pgv_per_ag = pgv(1), the factor that turns a velocity
    guess into a first trial a_g."""
    from homlimit.dynamics.pulses import make_pulse

    def load(a):
        return {"pulse": make_pulse(kind, period, a, polarity)}

    def pgv(a):
        return make_pulse(kind, period, a, polarity).pgv

    return load, pgv, pgv(1.0)


def part_impulse(model, facade: bool = True):
    """load(v) -> the keywords of ``run`` that give −v x̂ to the watched blocks (the façade's
    and toothing blocks) alone, the wall at rest (``facade``: the ideal impulse as the closed
    forms see it, the rest of the structure fixed), or to the wall's free blocks alone, the
    façade at rest. Diagnostics (docs/dem.md section 22), not Table 1's load, under which
    every block moves."""
    import numpy as np

    moved = model.watch if facade else ~model.watch & ~model.assembly.fixed

    def load(v):
        q = np.zeros((model.n_blocks, 3))
        q[moved, 0] = -v
        return {"velocity": q}

    return load


def settled_wall(wall: str, over: dict):
    """(model, settled state) of Table 1's ``wall`` (the T-section, façade through) with the
    DEMParams ``over``rides, settled under gravity."""
    from homlimit.closed_form.paper import table1
    from homlimit.dem import DEMParams, settle, t_section_model

    row = {r.test: r for r in table1()}[wall]
    model = t_section_model(row.case, DEMParams(**over))
    return model, settle(model)[0]


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("walls", nargs="+", help="Table 1 test names, e.g. B1 B4")
    ap.add_argument("--guess", type=float, default=None,
                    help="first trial [m/s] (default: UDEC's value rounded to 0.1)")
    ap.add_argument("--t-max", type=float, default=5.0, help="trial length [s]")
    add_overrides(ap)
    ap.add_argument("--loading", default="impulse",
                    choices=("impulse", "facade-impulse", "wall-impulse", "rectangular",
                             "one-sine", "one-cosine", "ricker"),
                    help="the ideal impulse (default), the same given to the façade's and "
                    "toothing blocks alone (a diagnostic: the wall at rest, as the closed "
                    "forms' fixed rest of the structure) or to the wall's blocks alone, or a "
                    "base-acceleration pulse")
    ap.add_argument("--pulse-period", type=float, default=None,
                    help="Δt of the pulse [s] (rectangular: its duration); needed with a pulse")
    ap.add_argument("--polarity", type=int, default=1, choices=(1, -1),
                    help="the pulse's polarity (+1: its first lobe throws the façade out)")
    args = ap.parse_args(argv)
    pulse = args.loading not in ("impulse", "facade-impulse", "wall-impulse")
    if pulse and (args.pulse_period is None or not 0 < args.pulse_period <= 100):
        ap.error(f"--pulse-period {args.pulse_period}: a pulse needs 0 < Δt <= 100 s")
    if not pulse and args.pulse_period is not None:
        ap.error("--pulse-period: only with --loading other than impulse")

    from homlimit.closed_form.paper import table1
    from homlimit.dem import DEMParams, t_section_model
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
        model = t_section_model(row.case, params)
        guess = args.guess if args.guess is not None else round(row.vg, 1)
        load, pgv = None, (lambda a: a)
        if args.loading in ("facade-impulse", "wall-impulse"):
            load = part_impulse(model, facade=args.loading == "facade-impulse")
        if pulse:
            load, pgv, per_ag = pulse_loading(args.loading, args.pulse_period, args.polarity)
            guess /= per_ag
        th = collapse_threshold(model, guess=guess, t_max=args.t_max, load=load)
        v = pgv(th.v)
        out = {**th.as_dict(), "test": name, "udec_vg": row.vg, "udec_h": row.h_v,
               "loading": args.loading, "pulse_period": args.pulse_period,
               "polarity": args.polarity,
               "pgv": v, "pgv_lo": pgv(th.lo), "pgv_hi": pgv(th.hi),
               "ratio": v / row.vg, "vg_norm": v / (row.case.wall.g
                                                    * row.case.wall.b) ** 0.5,
               "overrides": over, "cpu_process": time.process_time() - c0,
               "wall_clock": time.perf_counter() - t0, "trials": th.trials,
               "settle": th.settle}
        print(json.dumps(out, default=str), flush=True)


if __name__ == "__main__":
    main()
