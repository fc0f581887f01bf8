"""Peak memory per triangle of both bounds, and the triangle-count estimate of the budget.

Sizes the ``[mesh] max_triangles`` default (``homlimit.app.budget``). Every (bound, mesher,
mesh size) runs in a fresh subprocess, so its peak resident memory (``ru_maxrss``) is its own;
the baseline is the peak after the imports and the mesh (before the solve), so the figure is
what the conic program and its factorisation add. Printed per run: triangles, the budget's
estimate and its ratio to the count, baseline and peak MiB, KiB per triangle of the solve, wall
seconds. At the end: per bound, the slope of peak memory against triangles (least squares over
the sizes, both meshers) and the triangle count that fits the memory budget used for the
default (``budget.MEMORY_BUDGET_GIB``).

    python benchmarks/bench_memory.py [--h 0.25 0.15 0.1] [--mesher crossed gmsh]
                                      [--bound kinematic static]
"""

from __future__ import annotations

import argparse
import json
import resource
import subprocess
import sys
import time

import numpy as np


def one(bound: str, mesher: str, h: float) -> dict:
    from homlimit.app.budget import estimate_triangles
    from homlimit.fe.problems import t_section
    from homlimit.fe.solver import SolverOptions
    from homlimit.params import Case

    case = Case(name="B1")                       # Table 1's B1 (the defaults)
    prob = t_section(case, h=h, mesher=mesher)
    if bound == "kinematic":
        from homlimit.fe.kinematic import solve_kinematic as solve
    else:
        from homlimit.fe.static import solve_static as solve
    base = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    t0 = time.perf_counter()
    sol = solve(prob, SolverOptions())
    dt = time.perf_counter() - t0
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    n = prob.n_triangles
    w = case.wall
    est = estimate_triangles(w.H, w.b, w.L, h, mesher)
    return {"bound": bound, "mesher": mesher, "h": h, "triangles": n, "estimate": est,
            "base_MiB": base, "peak_MiB": peak, "seconds": dt, "multiplier": sol.multiplier}


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--h", type=float, nargs="+", default=[0.25, 0.15, 0.1])
    ap.add_argument("--mesher", nargs="+", default=["crossed", "gmsh"])
    ap.add_argument("--bound", nargs="+", default=["kinematic", "static"])
    ap.add_argument("--one", nargs=3, help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.one:
        bound, mesher, h = args.one
        print(json.dumps(one(bound, mesher, float(h))))
        return
    from homlimit.app.budget import DEFAULT_MAX_TRIANGLES, MEMORY_BUDGET_GIB

    print(f"{'bound':9} {'mesher':7} {'h':>5} {'tri':>7} {'estimate':>8} {'est/n':>5} "
          f"{'base':>6} {'peak':>6} {'KiB/tri':>7} {'s':>6}  multiplier")
    rows = []
    for bound in args.bound:
        for mesher in args.mesher:
            for h in args.h:
                out = subprocess.run([sys.executable, __file__, "--one", bound, mesher, str(h)],
                                     capture_output=True, text=True)
                if out.returncode:
                    print(f"{bound:9} {mesher:7} {h:5.3f} failed: "
                          f"{out.stderr.strip().splitlines()[-1]}", flush=True)
                    continue
                r = json.loads(out.stdout.strip().splitlines()[-1])
                rows.append(r)
                kib = (r["peak_MiB"] - r["base_MiB"]) * 1024 / r["triangles"]
                print(f"{bound:9} {mesher:7} {h:5.3f} {r['triangles']:7d} {r['estimate']:8.0f} "
                      f"{r['estimate'] / r['triangles']:5.2f} {r['base_MiB']:6.0f} "
                      f"{r['peak_MiB']:6.0f} {kib:7.1f} {r['seconds']:6.1f}  "
                      f"{r['multiplier']:.6f}", flush=True)
    print()
    for bound in args.bound:
        sel = [r for r in rows if r["bound"] == bound]
        n = np.array([r["triangles"] for r in sel], float)
        peak = np.array([r["peak_MiB"] for r in sel])
        slope, icpt = np.polyfit(n, peak, 1)
        fits = (MEMORY_BUDGET_GIB * 1024 - icpt) / slope
        print(f"{bound}: peak MiB ~ {icpt:.0f} + {slope * 1024:.1f} KiB x triangles; "
              f"{MEMORY_BUDGET_GIB:g} GiB fits {fits:,.0f} triangles")
    print(f"default [mesh] max_triangles = {DEFAULT_MAX_TRIANGLES:,}")


if __name__ == "__main__":
    main()
