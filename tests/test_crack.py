"""Crack angle of finite-element mechanisms: level sets of the participation vs the hinge + fan.

Synthetic fields pin the measurement itself; finite-element fields pin what the study found:
on a mesh conforming to the closed-form rays the FE multiplier is the hinge + fan value and the
measured edges are f and c/a; on unaligned (crossed) meshes they approach them within a
tolerance derived from the element size, which shrinks under refinement.
"""

import dataclasses
import math

import numpy as np
import pytest
import skfem as fem

from homlimit.closed_form.fan import fan_participation, fan_velocity, optimise_fan
from homlimit.fe.kinematic import solve_kinematic
from homlimit.fe.problems import t_section
from homlimit.fe.solver import SolverOptions
from homlimit.mechanism.crack import crack_line, fan_edges, mechanism_type
from homlimit.mechanism.fe_impulse import p2_nodes, ray_conforming_mesh
from homlimit.mechanism.rigidfit import measure_mechanism
from homlimit.params import Case, Masonry, Wall


def _p2_mesh(nx, nz, W=6.5, H=9.0):
    m = fem.MeshTri.init_tensor(np.linspace(0, W, nx + 1), np.linspace(0, H, nz + 1))
    b = fem.Basis(m, fem.ElementTriP2())
    return b.doflocs.T.copy(), b.element_dofs.T.copy()


def _t_of_p(p, T1, T2):
    """Brute force: the ray slope where the fan's participation is p (bisection)."""
    lo, hi = T1, T2
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if fan_participation(mid, T1, T2) > p else (lo, mid)
    return 0.5 * (lo + hi)


def test_synthetic_fan_levels_and_edges():
    X, el = _p2_mesh(52, 72)
    z0, T1, T2 = 2.0, 0.6, 1.0
    mm = measure_mechanism(X, fan_velocity(X[:, 0], X[:, 1], z0, T1, T2), el)
    fe = fan_edges(X, el, mm, b=0.5, z_top=9.0)
    for p, line in fe.lines.items():
        assert abs(line.T - _t_of_p(p, T1, T2)) <= line.dT
    assert abs(fe.T1 - T1) <= fe.dT and abs(fe.T2 - T2) <= fe.dT
    assert not fe.sharp
    assert mechanism_type(mm, fe) == "hinge+fan"


def test_synthetic_sharp_crack_is_sharp_and_local_angle_is_constant():
    X, el = _p2_mesh(52, 72)
    T = 0.8
    V = fan_velocity(X[:, 0], X[:, 1], 1.0, T, T)
    mm = measure_mechanism(X, V, el)
    line = crack_line(X, el, mm, b=0.5, z_top=9.0)
    assert abs(line.T - T) <= line.dT
    inner = slice(2, -2)
    assert np.all(np.abs(np.tan(line.psi_local[inner]) - T) <= 3 * line.dT)
    assert fan_edges(X, el, mm, b=0.5, z_top=9.0).sharp
    assert mechanism_type(mm, fan_edges(X, el, mm, b=0.5, z_top=9.0)) == "rigid"


def _fe(case, mesh=None, h=0.5):
    prob = t_section(case, h=h)
    if mesh is not None:
        prob = dataclasses.replace(prob, mesh=mesh)
    sol = solve_kinematic(prob, SolverOptions(tol=1e-9))
    X, V, el, rho = p2_nodes(sol, {"facade": case.rho, "wall": 1.0})
    mm = measure_mechanism(X, V, el, rho)
    return sol, mm, fan_edges(X, el, mm, case.wall.b, z_top=case.wall.H)


@pytest.mark.parametrize("a, c, f", [(0.2, 0.2, 0.6), (0.4, 0.2, 0.9)])
@pytest.mark.slow
def test_conforming_mesh_reproduces_the_hinge_and_fan(a, c, f):
    """Mesh containing the rays tan ψ = f and c/a from the optimal hinge: FE multiplier = the
    closed form to 1e-4 and the measured edges are f and c/a (c/a > f and c/a < f)."""
    case = Case(Wall(b=0.5, l=6.0), Masonry(a=a, c=c, f=f))
    opt = optimise_fan(case)
    mesh = ray_conforming_mesh(case, opt.z0, [opt.T1, opt.T2], h=0.3)
    sol, mm, fe = _fe(case, mesh)
    assert sol.multiplier == pytest.approx(opt.lam, rel=1e-4)
    np.testing.assert_allclose(mm.fit.O, (0.0, opt.z0), atol=1e-3)
    # the FE field is the exact fan here: only the linear interpolation of p between P2 nodes
    # remains, well inside a tenth of the element-size uncertainty
    assert abs(fe.T1 - min(f, c / a)) <= 0.1 * fe.dT
    assert abs(fe.T2 - max(f, c / a)) <= 0.1 * fe.dT
    assert mm.kind == "deforming" and not fe.sharp


@pytest.mark.slow
def test_unaligned_meshes_approach_the_fan_under_refinement(table1_case):
    """Crossed meshes not aligned with the rays: λ decreases towards the hinge + fan value from
    above, the measured edges lie within 2 δT of f and c/a and the mid-line within δT of
    √(cf/a), δT the element-size uncertainty, and both errors shrink from h = 0.5 to 0.25 m."""
    case = table1_case("B2")
    opt = optimise_fan(case)
    alpha = math.sqrt(0.6)
    errs, mids, lams = [], [], []
    for h in (0.5, 0.25):
        sol, mm, fe = _fe(case, h=h)
        assert abs(fe.T1 - 0.6) <= 2 * fe.dT and abs(fe.T2 - 1.0) <= 2 * fe.dT
        assert abs(fe.T_mid - alpha) <= fe.dT
        errs.append(abs(fe.T1 - 0.6) + abs(fe.T2 - 1.0))
        mids.append(abs(fe.T_mid - alpha))
        lams.append(sol.multiplier)
    assert errs[1] < errs[0] and mids[1] < mids[0]
    assert opt.lam < lams[1] < lams[0] < 1.02 * opt.lam
