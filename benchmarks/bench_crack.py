"""Convergence of the FE crack measurement and multiplier for wall B2 (c/a = 1, f = 0.6).

Prints, per mesh size h, the FE multiplier against the hinge + fan closed form, the measured
fan edges (block side, fixed side) against f and c/a, the mid-line (50 % participation)
against √(cf/a) and the fan model's own 50 % ray, the uncertainty δT and the solve time:
first on crossed meshes not aligned with the rays (``problems.t_section``), then on meshes
conforming to the closed-form rays (``fe_impulse.ray_conforming_mesh``).

Usage: python benchmarks/bench_crack.py [h ...]   (default h = 0.5 0.35 0.25 0.18)
"""

from __future__ import annotations

import dataclasses
import math
import sys
import time

from homlimit.closed_form.fan import optimise_fan
from homlimit.fe.kinematic import solve_kinematic
from homlimit.fe.problems import t_section
from homlimit.fe.solver import SolverOptions
from homlimit.mechanism.crack import fan_edges, fan_ray
from homlimit.mechanism.fe_impulse import p2_nodes, ray_conforming_mesh
from homlimit.mechanism.rigidfit import measure_mechanism
from homlimit.params import Case, Masonry, Wall


def run(case, prob):
    t0 = time.perf_counter()
    sol = solve_kinematic(prob, SolverOptions())
    X, V, el, rho = p2_nodes(sol, {"facade": case.rho, "wall": 1.0})
    mm = measure_mechanism(X, V, el, rho)
    fe = fan_edges(X, el, mm, case.wall.b, z_top=case.wall.H)
    return sol, mm, fe, time.perf_counter() - t0


def main(sizes):
    case = Case(Wall(b=0.5, l=6.0), Masonry(a=0.2, c=0.2, f=0.6), name="B2")
    opt = optimise_fan(case)
    t50 = float(fan_ray(0.5, opt.T1, opt.T2))
    print(f"closed form: λ = {opt.lam:.6f}, hinge z0 = {opt.z0:.3f} m, edges T1 = {opt.T1:.4f}, "
          f"T2 = {opt.T2:.4f}, √(T1T2) = {opt.T_mid:.4f}, fan-model 50 % ray = {t50:.4f}")
    head = (f"{'mesh':<10}{'h':>6}{'tri':>7}{'λ_FE':>10}{'rel':>10}{'z_O':>7}{'T1':>8}{'T2':>8}"
            f"{'T_mid':>8}{'δT':>7}{'time':>7}")
    for kind in ("crossed", "conforming"):
        print(head)
        for h in sizes:
            if kind == "crossed":
                prob = t_section(case, h=h)
            else:
                m = ray_conforming_mesh(case, opt.z0, [opt.T1, opt.T2], h=h)
                prob = dataclasses.replace(t_section(case), mesh=m)
            sol, mm, fe, t = run(case, prob)
            print(f"{kind:<10}{h:>6.3g}{prob.n_triangles:>7d}{sol.multiplier:>10.6f}"
                  f"{sol.multiplier / opt.lam - 1:>10.2e}{mm.fit.O[1]:>7.3f}{fe.T1:>8.4f}"
                  f"{fe.T2:>8.4f}{fe.T_mid:>8.4f}{fe.dT:>7.3f}{t:>7.1f}", flush=True)
    print(f"(√(cf/a) = {math.sqrt(0.6):.4f})")


if __name__ == "__main__":
    main([float(a) for a in sys.argv[1:]] or [0.5, 0.35, 0.25, 0.18])
