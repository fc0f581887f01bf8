"""Convergence of the kinematic bound on the classical benchmarks, with fitted rates.

For each benchmark, a sequence of graded crossed meshes (every size halved by a factor r):
triangles, the multiplier, its relative error to the exact/best value and the solve time;
then the fitted rate p of error ∝ triangles^(−p) (and ∝ h^(−2p) in a mesh size h).

    python benchmarks/bench_classical.py [prandtl] [cut] [mc]
"""

from __future__ import annotations

import sys
import time

import numpy as np

from homlimit.fe.kinematic import solve_kinematic
from homlimit.fe.problems import (
    PRANDTL,
    VERTICAL_CUT_UB,
    mohr_coulomb_footing,
    mohr_coulomb_nc,
    prandtl,
    vertical_cut,
)

SEQUENCES = {
    "prandtl": (lambda r: prandtl(h_min=0.04 * r, h_max=0.4 * r), PRANDTL,
                [2.0, 1.0, 0.5, 0.35, 0.25]),
    "cut": (lambda r: vertical_cut(h_min=0.02 * r, h_max=0.1 * r), VERTICAL_CUT_UB,
            [2.0, 1.0, 0.6, 0.4]),
    "mc": (lambda r: mohr_coulomb_footing(30.0, h_min=0.05 * r, h_max=0.5 * r),
           mohr_coulomb_nc(30.0), [1.5, 1.0, 0.6, 0.45]),
}


def run(name: str):
    make, ref, rs = SEQUENCES[name]
    print(f"{name}: reference {ref:.5f}")
    print(f"{'r':>5s} {'tri':>7s} {'lambda':>10s} {'error':>9s} {'solve s':>8s} {'it':>3s}")
    tri, err = [], []
    for r in rs:
        prob = make(r)
        t0 = time.perf_counter()
        sol = solve_kinematic(prob)
        e = sol.multiplier / ref - 1
        tri.append(prob.n_triangles)
        err.append(e)
        print(f"{r:5.2f} {prob.n_triangles:7d} {sol.multiplier:10.5f} {e:9.2e} "
              f"{time.perf_counter() - t0:8.1f} {sol.sizes['iterations']:3d}", flush=True)
    ok = np.array(err) > 0
    if ok.sum() >= 2:
        p = -np.polyfit(np.log(np.array(tri)[ok]), np.log(np.array(err)[ok]), 1)[0]
        print(f"{name}: error ~ triangles^-{p:.2f} (~ h^{2 * p:.2f})")


if __name__ == "__main__":
    for name in sys.argv[1:] or list(SEQUENCES):
        run(name)
