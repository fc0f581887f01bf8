"""Speed of the rigid-block DEM (homlimit.dem) on the T-section of the default Case (B1: H = 9 m,
L = 6 m, b = 0.5 m, ρ = 12, a = 0.3 m, c = 0.2 m, 480 blocks), one core.

Printed: blocks, contact candidates, dt and steps per simulated second, the settling's steps
and CPU time, then for an ideal impulse v_g (default 0.8 m/s, near UDEC's 0.83 m/s threshold)
run for --seconds of simulated time without stopping at collapse: µs of CPU per time step,
CPU seconds per simulated second, Verlet rebuilds; and the kernels' first-call time (numba
compiles on a cold cache, ~30 s, or loads the cached machine code).

    python benchmarks/bench_dem.py [--seconds 0.5] [--vg 0.8]
    python benchmarks/bench_dem.py --table1 [--workers 2]    # and `homlimit table1 --dem`

Targets (issue 29): <= 150 µs per step, goal 60 µs. The machine is shared with other work: CPU
seconds (process time) are printed, not wall clock. With ``--table1`` it also runs ``homlimit
table1 --dem`` (all twelve walls, the Dask engine, into a temporary folder) and prints its wall
clock and the CPU of it and its workers, the trials per wall and their CPU (target:
<= 15 min on 2 cores; about 12 min on an idle machine).
"""

from __future__ import annotations

import argparse
import time


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seconds", type=float, default=0.5, help="simulated time [s]")
    ap.add_argument("--vg", type=float, default=0.8, help="ideal impulse [m/s]")
    ap.add_argument("--table1", action="store_true",
                    help="also time `homlimit table1 --dem` (about 12 min on 2 cores)")
    ap.add_argument("--workers", type=int, default=2, help="its Dask workers (with --table1)")
    ap.add_argument("--test", "-t", action="append", default=[],
                    help="with --table1: only this wall (repeatable) [default: all 12]")
    args = ap.parse_args(argv)

    t0 = time.process_time()
    from homlimit.dem import run, settle, t_section_model
    from homlimit.params import Case

    model = t_section_model(Case())
    state = model.initial_state()          # the first kernel call: compile or load
    t_first = time.process_time() - t0
    print(f"blocks {model.n_blocks} (free {model.assembly.n_free}), candidates "
          f"{state.contacts[0].size}; first kernel call (import + compile/load) "
          f"{t_first:.1f} s CPU")
    print(f"dt {model.dt:.4g} s = {model.params.dt_fraction:g} sqrt(m_min/k_max), m_min "
          f"{model.m_min:.4g} kg, k_max {model.k_max:.4g} N/m; {1 / model.dt:.0f} steps per "
          "simulated second")
    t0 = time.process_time()
    settled, info = settle(model, state)
    t_set = time.process_time() - t0
    print(f"settling: {info['steps']} steps, {info['time']:.3f} s simulated, converged "
          f"{info['converged']}, {t_set:.2f} s CPU ({1e6 * t_set / max(info['steps'], 1):.1f} "
          "µs/step with damping)")
    out = run(model, settled, v_g=args.vg, t_max=args.seconds, stop_on_collapse=False)
    us = 1e6 * out.cpu / out.steps
    print(f"impulse v_g = {args.vg:g} m/s, {out.t_end:.3f} s simulated: {out.steps} steps, "
          f"{us:.1f} µs/step, {out.cpu / out.t_end:.2f} s CPU per simulated second, "
          f"{out.builds} Verlet rebuilds, {out.state.contacts[0].size} candidates at the end")
    if args.table1:
        table1_dem(args.workers, args.test)


def table1_dem(workers: int, tests: list[str]) -> None:
    """Time ``homlimit table1 --dem`` in a child process (its CPU is the children's, the
    engine's workers included) and print per wall its trials and their CPU."""
    import csv
    import os
    import subprocess
    import sys
    import tempfile
    from pathlib import Path

    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "table1-dem"
        c0, w0 = os.times(), time.perf_counter()
        subprocess.run([sys.executable, "-m", "homlimit", "table1", "--dem", "--workers",
                        str(workers), "--quiet", "--out", str(out),
                        *[a for t in tests for a in ("-t", t)]], check=True,
                       stdout=subprocess.DEVNULL)
        wall, c1 = time.perf_counter() - w0, os.times()
        rows = list(csv.DictReader(open(out / "table1_dem.csv", encoding="utf-8")))
    cpu = (c1.children_user - c0.children_user) + (c1.children_system - c0.children_system)
    print(f"table1 --dem ({', '.join(tests) or 'all 12 walls'}), {workers} workers: "
          f"{wall / 60:.1f} min wall clock ({wall:.0f} s), "
          f"{cpu:.0f} s CPU with its workers")
    for r in rows:
        print(f"  {r['test']}: {r['n_trials [-]']} trials, {float(r['cpu [s]']):.0f} s CPU in "
              f"them, v_g {float(r['vg [m/s]']):.4g} m/s")


if __name__ == "__main__":
    main()
