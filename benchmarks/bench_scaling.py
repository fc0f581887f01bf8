"""Scaling of the kinematic T-section program: stages, memory, Clarabel beside HiGHS (IPM).

Every mesh size runs in a fresh subprocess (so the peak resident memory is that run's own).
Printed per size: triangles, free unknowns, cone rows, seconds in each stage (mesh, assembly,
cvxpy build, solve; solve also as CPU seconds, robust to other jobs on the machine),
interior-point iterations, peak memory and the multiplier; then the same LP solved by HiGHS's
interior point (crossover off) for the sizes up to --highs-max triangles. Mesh: t_section with
spacing h and max(4, b/h) columns across the façade (so the façade cells stay square). At the
end: the fitted exponent p of solve time ∝ triangles^p and the three targets of issue 5
(build <= solve/4, p <= 1.6, Clarabel >= 3x faster than HiGHS).

    python benchmarks/bench_scaling.py [--h 0.6 0.35 0.25 0.125 0.085] [--highs-max 5000]
"""

from __future__ import annotations

import argparse
import json
import resource
import subprocess
import sys
import time

import numpy as np

CASE = dict(H=9.0, L=6.0, s=0.5, b=0.5, l=6.0, a=0.3, c=0.2, f=0.6)   # Table 1, B1


def one(h: float, solver: str, method: str) -> dict:
    from homlimit.fe.kinematic import solve_kinematic
    from homlimit.fe.problems import t_section
    from homlimit.fe.solver import SolverOptions
    from homlimit.params import Case, Masonry, Wall

    k = CASE
    case = Case(wall=Wall(H=k["H"], L=k["L"], s=k["s"], b=k["b"], l=k["l"]),
                masonry=Masonry(k["a"], k["c"], k["f"]), name="B1")
    prob = t_section(case, h=h, n_b=max(4, round(case.wall.b / h)))   # cells ~ square in the façade
    c0 = time.process_time()
    sol = solve_kinematic(prob, SolverOptions(solver=solver, direct_solve_method=method))
    cpu = time.process_time() - c0
    t = sol.times
    return {"h": h, "solver": solver, "method": method, "triangles": prob.n_triangles,
            "free": sol.sizes["free"], "rows": sol.sizes["rows"], "nnz": sol.sizes["nnz"],
            "iters": sol.sizes["iterations"], "mesh": t["mesh"], "assembly": t["assembly"],
            "build": t["build"], "solve": t["solve"],
            "solve_cpu": cpu - (t["assembly"] + t["build"] + t["unpack"]),
            "mem_MiB": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024,
            "lam": sol.multiplier}


def run_child(h: float, solver: str, method: str) -> dict:
    out = subprocess.run([sys.executable, __file__, "--one", str(h), solver, method],
                         capture_output=True, text=True, check=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--h", type=float, nargs="+", default=[0.6, 0.35, 0.25, 0.125, 0.085])
    ap.add_argument("--highs-max", type=int, default=5000)
    ap.add_argument("--method", default="qdldl")
    ap.add_argument("--one", nargs=3)
    args = ap.parse_args()
    if args.one:
        print(json.dumps(one(float(args.one[0]), args.one[1], args.one[2])))
        return
    print("T-section B1 (Homogenised eq. 15 in wall and façade), Clarabel "
          f"direct_solve_method={args.method!r} vs HiGHS IPM")
    head = (f"{'tri':>6s} {'free':>6s} {'rows':>7s} {'mesh':>6s} {'asm':>6s} {'build':>6s} "
            f"{'solve':>7s} {'cpu':>7s} {'it':>3s} {'MiB':>6s} {'lambda':>10s} | "
            f"{'HiGHS':>7s} {'lambda':>10s} {'ratio':>6s}")
    print(head)
    rows = []
    for h in args.h:
        r = run_child(h, "CLARABEL", args.method)
        line = (f"{r['triangles']:6d} {r['free']:6d} {r['rows']:7d} {r['mesh']:6.2f} "
                f"{r['assembly']:6.2f} {r['build']:6.2f} {r['solve']:7.2f} "
                f"{r['solve_cpu']:7.2f} {r['iters']:3d} {r['mem_MiB']:6.0f} {r['lam']:10.6f} |")
        if r["triangles"] <= args.highs_max:
            g = run_child(h, "HIGHS", args.method)
            r["highs"] = g["solve"]
            line += f" {g['solve']:7.2f} {g['lam']:10.6f} {g['solve'] / r['solve']:6.1f}"
        print(line, flush=True)
        rows.append(r)
    tri = np.array([r["triangles"] for r in rows], float)
    solve = np.array([r["solve"] for r in rows])
    cpu = np.array([r["solve_cpu"] for r in rows])
    p = np.polyfit(np.log(tri), np.log(solve), 1)[0]
    pc = np.polyfit(np.log(tri), np.log(cpu), 1)[0]
    ratio = max((r["assembly"] + r["build"]) / r["solve"] for r in rows)
    print(f"solve time ~ triangles^{p:.2f} (wall), ^{pc:.2f} (cpu)  [target <= 1.6]")
    print(f"max (assembly + build)/solve = {ratio:.3f}  [target <= 0.25]")
    hs = [r["highs"] / r["solve"] for r in rows if "highs" in r]
    if hs:
        print(f"HiGHS IPM / Clarabel solve time: min {min(hs):.1f}x  [target >= 3]")


if __name__ == "__main__":
    main()
