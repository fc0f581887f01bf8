"""Static (lower-bound) solve time by Clarabel factorisation: qdldl, faer on one thread, faer
on all threads. The figures behind ``solver.FAER_ABOVE`` (docs/static.md, "Solver settings").

Prints per problem: triangles, unknowns, then λ⁻, iterations and solve seconds per setting.

    python benchmarks/bench_static_factorisation.py [--large]   (--large adds 11 051 triangles)
"""

from __future__ import annotations

import sys

from homlimit.fe import problems
from homlimit.fe.bracket import prandtl_fan
from homlimit.fe.solver import FAER_ABOVE, SolverOptions
from homlimit.fe.static import solve_static
from homlimit.params import Case

SETTINGS = {"qdldl": {"direct_solve_method": "qdldl"},
            "faer 1 thread": {"direct_solve_method": "faer", "max_threads": 1},
            "faer all threads": {"direct_solve_method": "faer", "max_threads": 0}}


def cases(large: bool):
    yield "Prandtl fan 0.3/0.03/12", prandtl_fan(size=0.3, h_min=0.03, n_fan=12)
    yield "Prandtl fan 0.2/0.02/16", prandtl_fan(size=0.2, h_min=0.02, n_fan=16)
    yield "Prandtl fan 0.15/0.015/20", prandtl_fan(size=0.15, h_min=0.015, n_fan=20)
    if large:
        yield "Prandtl fan 0.12/0.012/24", prandtl_fan(size=0.12, h_min=0.012, n_fan=24)
    yield "T-section B1 crossed h=0.25", problems.t_section(Case(), h=0.25)
    yield "vertical cut h_min=0.02", problems.vertical_cut(h_min=0.02, h_max=0.25)


if __name__ == "__main__":
    print(f"default: faer on one thread above FAER_ABOVE = {FAER_ABOVE} unknowns")
    print(f"{'problem':<30s} {'tri':>6s} {'unknowns':>9s}  " +
          "  ".join(f"{k:>26s}" for k in SETTINGS))
    for name, pr in cases("--large" in sys.argv[1:]):
        cells, n = [], 0
        for opts in SETTINGS.values():
            s = solve_static(pr, SolverOptions(settings=opts, retries=False))
            n = s.sizes["variables"]
            cells.append(f"{s.multiplier:.7f} {s.iterations:>3d} it {s.times['solve']:>6.1f} s")
        print(f"{name:<30s} {pr.n_triangles:>6d} {n:>9d}  " + "  ".join(f"{c:>26s}" for c in cells),
              flush=True)
