"""Where the demo's kinematic time goes: the solver ladder on the demo's mesh, and the two
cures measured and not adopted (docs/kinematic.md, "Where the demo's kinematic time goes").

B1, bed-joint façade, gmsh-strip, size 0.25 m, outer column 1 cm (the demo's first mesh):
the kinematic bound solved
- as the package does (the ladder: 1e-9, 1e-9 with iterative refinement, then 1e-7);
- from Clarabel's 1e-7 directly (``SolverOptions(tol=1e-7)``);
- one attempt at 1e-9 whose AlmostSolved is accepted at reduced tolerances of 1e-7 (a
  status check turned off here only, to read that attempt's λ⁺).
Prints λ⁺, the seconds and the ladder's attempts (status, iterations) of each.

    python benchmarks/bench_ladder.py
"""

from __future__ import annotations

import os
import time

import homlimit.fe.kinematic as kinematic
import homlimit.fe.solver as solver
from homlimit.fe.problems import t_section
from homlimit.fe.solver import SolverOptions
from homlimit.params import Case

REDUCED = {"reduced_tol_gap_abs": 1e-7, "reduced_tol_gap_rel": 1e-7, "reduced_tol_feas": 1e-7}


def solve(problem, options, label):
    t0 = time.perf_counter()
    k = kinematic.solve_kinematic(problem, options)
    sec = time.perf_counter() - t0
    att = [(a[1], a[2]) for a in k.sizes["attempts"]]
    print(f"{label:<44s} lambda+ {k.multiplier:.7f}  {sec:6.1f} s  {att}", flush=True)


def main() -> None:
    print(f"load average before the runs: {os.getloadavg()[0]:.2f} on {os.cpu_count()} cores")
    p = t_section(Case(), facade="bedjoints", h=0.25, mesher="gmsh-strip", h_outer=0.01)
    print(f"demo's mesh: {p.mesh.t.shape[1]} triangles")
    solve(p, SolverOptions(), "the ladder (default)")
    solve(p, SolverOptions(tol=1e-7), "from 1e-7")
    keep = solver.check_status
    solver.check_status = lambda *a, **k: None
    try:
        solve(p, SolverOptions(settings=REDUCED, retries=False),
              "first attempt, AlmostSolved at 1e-7 accepted")
    finally:
        solver.check_status = keep


if __name__ == "__main__":
    main()
