"""What Clarabel's settings and the formulation buy on the T-section LP (one mesh size).

Rows: the default (qdldl, tol 1e-9, equilibration, row scaling, no iterative refinement for an
LP, facet form of eq. 15), then one change at a time: faer / auto direct solver, tol 1e-8 /
1e-10, no equilibration, no row scaling, iterative refinement on, and the generator form
d = Σ μ_k N_k (μ >= 0) instead of the four facet inequalities.
Printed: multiplier, its deviation from the default, iterations, solve seconds (wall, CPU).

    python benchmarks/bench_settings.py [--h 0.25]
"""

from __future__ import annotations

import argparse
import dataclasses
import time

from homlimit.fe.kinematic import solve_kinematic
from homlimit.fe.problems import t_section
from homlimit.fe.solver import SolverOptions
from homlimit.fe.strength import Homogenised
from homlimit.params import Case, Masonry, Wall


class GeneratorForm(Homogenised):
    """Homogenised eq. 15 through its generators: d − Nᵀμ = 0, μ >= 0 (4 extra unknowns)."""

    def kinematic_cone(self):
        return self.generator_cone()


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--h", type=float, default=0.25)
    args = ap.parse_args()
    case = Case(wall=Wall(H=9.0, L=6.0, s=0.5, b=0.5, l=6.0), masonry=Masonry(0.3, 0.2, 0.6))
    prob = t_section(case, h=args.h)
    gen = dataclasses.replace(prob, domains={k: GeneratorForm(v.a, v.c, v.f)
                                             for k, v in prob.domains.items()})
    runs = [("default (qdldl, 1e-9)", prob, SolverOptions()),
            ("faer", prob, SolverOptions(direct_solve_method="faer")),
            ("auto", prob, SolverOptions(direct_solve_method="auto")),
            ("tol 1e-8", prob, SolverOptions(tol=1e-8)),
            ("tol 1e-10", prob, SolverOptions(tol=1e-10)),
            ("no equilibration", prob, SolverOptions(equilibrate=False)),
            ("no row scaling", prob, SolverOptions(scale_rows=False)),
            ("iterative refinement on", prob, SolverOptions(iterative_refinement=True)),
            ("generator form", gen, SolverOptions())]
    print(f"T-section B1, {prob.n_triangles} triangles")
    print(f"{'run':24s} {'lambda':>12s} {'dev':>9s} {'it':>3s} {'solve':>7s} {'cpu':>7s}")
    ref = None
    for name, p, opt in runs:
        c0 = time.process_time()
        try:
            sol = solve_kinematic(p, opt)
        except Exception as exc:                       # report and go on with the study
            print(f"{name:24s} failed: {exc}")
            continue
        cpu = time.process_time() - c0 - sol.times["assembly"] - sol.times["build"]
        ref = sol.multiplier if ref is None else ref
        print(f"{name:24s} {sol.multiplier:12.8f} {sol.multiplier / ref - 1:9.1e} "
              f"{sol.sizes['iterations']:3d} {sol.times['solve']:7.2f} {cpu:7.2f}", flush=True)


if __name__ == "__main__":
    main()
