"""Kinematic FE multiplier and rotation centre of the T-section for every Table 1 geometry.

Prints, per test of homlimit/data/table1_dem.csv: the FE upper bound λ⁺ (Homogenised eq. 15 in
wall and façade), the rotation centre O of a rigid rotation fitted (mechanism.rigidfit) to the
moving nodes, and beside them the closed-form hinge + fan optimum (closed_form.fan) with its hinge
height z0 and fan edges T1, T2. Optional: --facade bedjoints, --h 0.125.

    python benchmarks/table1_kinematic.py [--h 0.15] [--facade homogenised]
"""

from __future__ import annotations

import argparse
import csv
import time
from importlib.resources import files

from homlimit.closed_form.fan import optimise_fan
from homlimit.fe.kinematic import solve_kinematic
from homlimit.fe.problems import t_section
from homlimit.fe.solver import SolverOptions
from homlimit.mechanism.rigidfit import fit_rigid
from homlimit.params import Case, Masonry, Wall


def table1_cases():
    text = files("homlimit").joinpath("data/table1_dem.csv").read_text()
    rows = [r for r in csv.DictReader(line for line in text.splitlines()
                                      if not line.startswith("#"))]
    for r in rows:
        H, L, s, b = (float(r[k]) for k in ("H", "L", "s", "b"))
        a, c, f, rho = (float(r[k]) for k in ("a", "c", "f", "rho"))
        yield Case(wall=Wall(H=H, L=L, s=s, b=b, l=rho * s), masonry=Masonry(a=a, c=c, f=f),
                   name=r["test"])


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--h", type=float, default=0.15)
    ap.add_argument("--facade", default="homogenised")
    args = ap.parse_args()
    print(f"T-section, facade={args.facade}, h={args.h} m (4 columns across the façade)")
    print(f"{'test':5s} {'tri':>6s} {'lam_FE':>9s} {'O_x':>7s} {'O_z':>6s} {'lam_fan':>9s} "
          f"{'FE/fan-1':>9s} {'z0_fan':>6s} {'T1':>5s} {'T2':>5s} {'t_solve':>7s}")
    for case in table1_cases():
        prob = t_section(case, facade=args.facade, h=args.h)
        sol = solve_kinematic(prob, SolverOptions())
        X = prob.mesh.p.T
        fit = fit_rigid(X, sol.velocity)
        fan = optimise_fan(case)
        t = sol.times["solve"]
        print(f"{case.name:5s} {prob.n_triangles:6d} {sol.multiplier:9.5f} {fit.O[0]:7.3f} "
              f"{fit.O[1]:6.2f} {fan.lam:9.5f} {sol.multiplier / fan.lam - 1:9.2e} "
              f"{fan.z0:6.2f} {fan.T1:5.2f} {fan.T2:5.2f} {t:7.1f}", flush=True)


if __name__ == "__main__":
    t0 = time.perf_counter()
    main()
    print(f"total {time.perf_counter() - t0:.0f} s")
