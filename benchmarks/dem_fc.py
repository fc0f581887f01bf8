"""B1's DEM threshold with a finite compressive strength (docs/dem.md section 10; issue 30): the
ideal impulse's v̄_g of B1 (the T-section, façade "through", default ``DEMParams``) for given
``[masonry] fc``, every run on the same contact points along the bed joints (``joint_segments``,
default 8, so f_c infinite is compared on the same layout: the points alone change the joints'
rotational stiffness).

Each threshold is ``collapse_threshold`` with the bracket searched by steps of ×1.1 from a guess
(default 0.9 m/s, near the corners' 0.881), bisection to ±rel_tol (default 2 %: with 8 points
per joint a step costs 2.3 × the corners', ~9 s of CPU per simulated second), t_max 5 s. One
JSON line per f_c (v̄_g with its bracket, h, slips, trials, CPU); one process per f_c keeps
a run near 3–4 min of CPU.

    python benchmarks/dem_fc.py --fc 0 2e6 [--segments 8] [--rel-tol 0.02] [--guess 0.9]
"""

from __future__ import annotations

import argparse
import json
import time


def one(fc: float, segments: int, rel_tol: float, guess: float, t_max: float) -> dict:
    from homlimit.dem import DEMParams, t_section_model
    from homlimit.dem.threshold import collapse_threshold
    from homlimit.params import Case, Masonry

    model = t_section_model(Case(masonry=Masonry(fc=fc)), DEMParams(joint_segments=segments))
    t0 = time.process_time()
    th = collapse_threshold(model, guess=guess, rel_tol=rel_tol, t_max=t_max, step=1.1)
    cpu = time.process_time() - t0
    return {"fc": fc, "joint_segments": segments, "joint_points": model.info["joint_points"],
            "dt": model.dt, "v": th.v, "lo": th.lo, "hi": th.hi, "rel_tol": rel_tol,
            "h": th.h, "base_slip_mm": 1e3 * th.base_slip, "hinge_slip_mm": 1e3 * th.hinge_slip,
            "trials": [[v, bool(c), t] for v, c, t in th.trials], "cpu_threshold": cpu,
            "cpu_trials": th.cpu, "settle_s": th.settle.get("time")}


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--fc", type=float, nargs="+", default=[0.0, 2e6],
                    help="compressive strengths [Pa] (0: infinite)")
    ap.add_argument("--segments", type=int, default=8, help="[dem] joint_segments")
    ap.add_argument("--rel-tol", type=float, default=0.02, help="bisection tolerance")
    ap.add_argument("--guess", type=float, default=0.9, help="first trial [m/s]")
    ap.add_argument("--t-max", type=float, default=5.0, help="trial length [s]")
    args = ap.parse_args(argv)
    for fc in args.fc:
        print(json.dumps(one(fc, args.segments, args.rel_tol, args.guess, args.t_max)),
              flush=True)


if __name__ == "__main__":
    main()
