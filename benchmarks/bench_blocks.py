"""Scaling of the rigid-block limit analysis: blocks, interfaces, build and solve time.

The Table 1 T-section B1 (H = 9 m, L = 6 m, b = 0.5 m, ρ = 12, f = 0.6) with its blocks shrunk
(a, c) → (a, c)/k at fixed c/a = 2/3 (the paper's façade bond), so that the assembly grows to
about 20 000 blocks. Every size runs in a fresh subprocess, so the peak resident memory is that
run's own. Printed per size: free blocks, interfaces, contact points, LP unknowns and rows,
seconds to generate the blocks and find the interfaces, to assemble the contact operator, for
cvxpy to build the program, for Clarabel to solve it (wall clock and CPU), interior-point
iterations, peak memory, λ; then the fitted exponent p of solve time ∝ blocks^p (wall clock
and CPU). Above fe.solver.FAER_ABOVE unknowns the solve uses faer on one thread.

    python benchmarks/bench_blocks.py [--k 1 2 3 4 5 6.45] [--generator-only 100000]

The machine is shared with other work: wall-clock seconds vary with its load (CPU seconds are
printed beside them).
"""

from __future__ import annotations

import argparse
import json
import resource
import subprocess
import sys
import time

import numpy as np


def one(k: float) -> dict:
    from homlimit.blocks.geometry import t_section_blocks
    from homlimit.blocks.limit import contact_operator, solve_blocks
    from homlimit.params import Case, Masonry, Wall

    case = Case(Wall(H=9, L=6, s=0.5, b=0.5, l=6), Masonry(a=0.3 / k, c=0.2 / k, f=0.6))
    t0 = time.perf_counter()
    A = t_section_blocks(case)
    t_gen = time.perf_counter() - t0
    t0 = time.perf_counter()
    contact_operator(A)
    t_op = time.perf_counter() - t0
    c0 = time.process_time()
    r = solve_blocks(A)
    cpu = time.process_time() - c0
    return {"k": k, "blocks": A.n_free, "interfaces": A.interfaces.count,
            "points": r.sizes["contact_points"], "unknowns": r.sizes["unknowns"],
            "rows": r.sizes["rows"], "nnz": r.sizes["nnz"], "generate": t_gen,
            "operator": t_op, "build": r.times["build"], "solve": r.times["solve"],
            "solve_cpu": cpu - r.times["build"] - r.times["assembly"],
            "iters": r.iterations,
            "mem_MiB": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024,
            "lam": r.multiplier}


def generator_only(n_target: int) -> dict:
    from homlimit.blocks.geometry import t_section_blocks
    from homlimit.params import Case, Masonry, Wall

    k = float(np.sqrt(n_target / 480.0))
    case = Case(Wall(H=9, L=6, s=0.5, b=0.5, l=6), Masonry(a=0.3 / k, c=0.2 / k, f=0.6))
    t0 = time.perf_counter()
    A = t_section_blocks(case)
    return {"blocks": A.n_free, "interfaces": A.interfaces.count,
            "generate": time.perf_counter() - t0}


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--k", type=float, nargs="+", default=[1, 2, 3, 4, 5, 6.45])
    ap.add_argument("--generator-only", type=int, default=100_000)
    ap.add_argument("--child", type=float, default=None, help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.child is not None:
        print(json.dumps(one(args.child)))
        return
    rows = []
    hdr = ("k", "blocks", "interfaces", "points", "unknowns", "rows", "generate [s]",
           "operator [s]", "build [s]", "solve [s]", "solve CPU [s]", "iters", "peak MiB",
           "lambda")
    print("  ".join(hdr))
    for k in args.k:
        out = subprocess.run([sys.executable, __file__, "--child", str(k)], check=True,
                             capture_output=True, text=True).stdout
        r = json.loads(out.strip().splitlines()[-1])
        rows.append(r)
        print(f"{r['k']:<4g}  {r['blocks']:6d}  {r['interfaces']:10d}  {r['points']:6d}  "
              f"{r['unknowns']:8d}  {r['rows']:6d}  {r['generate']:12.3f}  "
              f"{r['operator']:12.3f}  {r['build']:9.2f}  {r['solve']:9.1f}  "
              f"{r['solve_cpu']:13.1f}  {r['iters']:5d}  {r['mem_MiB']:8.0f}  "
              f"{r['lam']:.5f}", flush=True)
    if len(rows) >= 3:
        n = np.array([r["blocks"] for r in rows], float)
        big = n >= 1000
        for key, what in (("solve", "wall clock"), ("solve_cpu", "CPU")):
            t = np.array([r[key] for r in rows], float)
            p = np.polyfit(np.log(n[big]), np.log(t[big]), 1)[0] if big.sum() >= 2 else np.nan
            print(f"solve time ({what}) ~ blocks^{p:.2f} (fit over >= 1000 blocks)")
    if args.generator_only:
        g = generator_only(args.generator_only)
        print(f"generator alone: {g['blocks']} blocks, {g['interfaces']} interfaces in "
              f"{g['generate']:.2f} s")


if __name__ == "__main__":
    main()
