"""The FE bounds of B1 with a real wall's inputs (issue 30; docs/real-walls.md "FE bounds").

Prints, per case (f_c, a top tie, a floor), the façade model, the triangles, λ⁻ (static,
linear stresses), λ⁺ (kinematic) and their relative gap, and the seconds of both solves, on
one modest mesh of the T-section, both bounds on it: crossed, rows of h = 0.25 m, the
façade's columns graded from h/25 at the outer face (``t_section(h_outer=)``, the static
mesh of a run with ``[mesh] outer_ratio = 25``): a crushing zone of a few centimetres needs
columns that fine (on 4 equal columns of 0.125 m neither bound sees f_c = 2 MPa).

    python benchmarks/bench_fe_real.py [--quick] [--bedjoints]
    (--quick: rows of 0.5 m; --bedjoints: the bed-joint façade too)
"""

from __future__ import annotations

import sys
import time

from homlimit.fe.kinematic import solve_kinematic
from homlimit.fe.problems import t_section
from homlimit.fe.static import solve_static
from homlimit.params import Case, Floor, Masonry, Tie

CASES = [("none (the paper's B1)", Case()),
         ("fc = 1 MPa", Case(masonry=Masonry(fc=1e6))),
         ("fc = 2 MPa", Case(masonry=Masonry(fc=2e6))),
         ("fc = 5 MPa", Case(masonry=Masonry(fc=5e6))),
         ("tie at 9 m, 10 kN/m", Case(ties=(Tie(9.0, 1e4),))),
         ("tie at 9 m, 10 kN/m, fc = 2 MPa", Case(masonry=Masonry(fc=2e6), ties=(Tie(9.0, 1e4),))),
         ("floor at 4.5 m, 20 kN/m, e = 0.1 m", Case(floors=(Floor(4.5, 2e4, 0.1),))),
         ("the same floor, restraining", Case(floors=(Floor(4.5, 2e4, 0.1, True),)))]


def main(quick: bool = False, bedjoints: bool = False) -> None:
    h = 0.5 if quick else 0.25
    print(f"B1 T-section, crossed mesh, rows of {h} m, façade columns graded from {h / 25} m "
          "at the outer face; both bounds on it")
    print("| inputs | façade | triangles | λ⁻ | λ⁺ | gap | s |")
    print("|---|---|---|---|---|---|---|")
    for facade in ("homogenised", "bedjoints") if bedjoints else ("homogenised",):
        for name, case in CASES:
            t0 = time.perf_counter()
            p = t_section(case, facade=facade, h=h, h_outer=h / 25)
            lo, up = solve_static(p).multiplier, solve_kinematic(p).multiplier
            print(f"| {name} | {facade} | {p.n_triangles} | {lo:.4f} | {up:.4f} | "
                  f"{100 * (up - lo) / (0.5 * (up + lo)):.1f} % | "
                  f"{time.perf_counter() - t0:.0f} |", flush=True)


if __name__ == "__main__":
    main("--quick" in sys.argv[1:], "--bedjoints" in sys.argv[1:])
