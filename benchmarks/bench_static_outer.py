"""The static bound of B1's T-section against the façade's outermost column (docs/static.md,
"The outer face" and "Quadratic stresses").

Prints, per mesh: the façade model, the row height, the columns (equal, or graded from h_outer
at the outer face by ``problems.OUTER_GROWTH``), triangles, λ⁻ with linear and, where asked,
quadratic stresses, and the seconds of each solve. Reference: the homogenised façade's exact
hinge + fan multiplier (``closed_form.fan``), which no lower bound may exceed.

    python benchmarks/bench_static_outer.py [--quick]   (--quick: the rows at ratio 25 only)
"""

from __future__ import annotations

import sys
import time

from homlimit.closed_form.fan import optimise_fan
from homlimit.fe.problems import t_section
from homlimit.fe.solver import SolverOptions
from homlimit.fe.static import solve_static
from homlimit.params import Case

# (façade, row height h [m], n_b, h_outer [m] or None, quadratic too)
ROWS = [("bedjoints", 0.25, 4, None, False), ("bedjoints", 0.5, 16, None, False),
        ("bedjoints", 0.5, 32, None, False), ("bedjoints", 0.25, 4, 0.01, True),
        ("bedjoints", 0.125, 4, 0.005, False), ("bedjoints", 0.25, 4, 0.005, True),
        ("bedjoints", 0.25, 4, 0.002, False), ("bedjoints", 0.25, 4, 0.001, False),
        ("homogenised", 0.25, 4, None, False), ("homogenised", 0.25, 8, None, False),
        ("homogenised", 0.25, 4, 0.01, True), ("homogenised", 0.25, 4, 0.005, True),
        ("homogenised", 0.25, 4, 0.002, True)]


def main(quick: bool) -> None:
    case = Case()
    print(f"B1; homogenised façade exact (hinge + fan): {optimise_fan(case).lam:.6f}")
    print(f"{'façade':<12s} {'h':>6s} {'columns':>18s} {'tri':>6s} {'linear':>9s} {'s':>6s} "
          f"{'quadratic':>9s} {'s':>6s}", flush=True)
    for facade, h, n_b, h_outer, quad in ROWS:
        if quick and (h_outer is None or abs(h / h_outer - 25) > 1e-9):
            continue
        p = t_section(case, facade=facade, h=h, n_b=n_b, mesher="crossed", h_outer=h_outer)
        cols = f"{n_b} equal" if h_outer is None else f"graded from {1000 * h_outer:g} mm"
        out = []
        for deg in (1, 2) if quad else (1,):
            t0 = time.perf_counter()
            lam = solve_static(p, SolverOptions(stress_degree=deg)).multiplier
            out.append(f"{lam:>9.5f} {time.perf_counter() - t0:>6.1f}")
        print(f"{facade:<12s} {h:>6g} {cols:>18s} {p.n_triangles:>6d} {' '.join(out)}",
              flush=True)


if __name__ == "__main__":
    main("--quick" in sys.argv[1:])
