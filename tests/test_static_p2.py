"""Quadratic (Bernstein) stresses in the static program (``SolverOptions(stress_degree=2)``).

The checks are independent of the assembly: the solved field is evaluated at random points and
tested for the three conditions of the static theorem (σ ∈ G, div σ + λ b + b⁰ = 0 by finite
differences, σ n continuous across edges); the linear fields are a subset of the quadratic ones
(a linear σ is the quadratic whose edge coefficients are the mean of the ends, inside a convex
G), so on one mesh λ⁻(2) >= λ⁻(1); and the gap splits over the elements exactly (virtual
power with the kinematic field on the same mesh).
"""

import dataclasses

import numpy as np
import pytest

from homlimit.errors import ParameterError
from homlimit.fe.bracket import bernstein2, bracket
from homlimit.fe.problems import free_block, t_section, vertical_cut
from homlimit.fe.solver import SolverOptions
from homlimit.fe.static import solve_static
from homlimit.params import Case

P2 = SolverOptions(stress_degree=2)


@pytest.fixture(scope="module")
def cut():
    prob = vertical_cut(h_min=0.05, h_max=0.25)
    return prob, solve_static(prob), solve_static(prob, P2)


@pytest.fixture(scope="module")
def tsec():
    prob = t_section(Case(), facade="homogenised", h=1.0, n_b=2, mesher="crossed")
    return prob, bracket(prob, options=P2)


def _at(prob, sol, lam):
    """σ (q, nt, 3) at barycentric points lam (q, 3) and their physical coordinates."""
    p, t = prob.mesh.p, prob.mesh.t
    X = np.einsum("qi,die->qed", lam, p[:, t])
    return bernstein2(sol.control, lam), X


def _body(prob, lam_):
    """λ b + b⁰ per element (nt, 2)."""
    nt = prob.mesh.t.shape[1]
    b = np.zeros((nt, 2))
    for loads, scale in ((prob.live_body, lam_), (prob.dead_body, 1.0)):
        for reg, val in loads.items():
            b[prob.mesh.subdomains[reg]] += scale * np.asarray(val, float)
    return b


@pytest.mark.parametrize("which", ["cut", "tsec"])
def test_quadratic_field_is_admissible_everywhere(which, cut, tsec):
    prob, sol = (cut[0], cut[2]) if which == "cut" else (tsec[0], tsec[1].static)
    rng = np.random.default_rng(0)
    lam = rng.dirichlet(np.ones(3), size=40)
    sig, _ = _at(prob, sol, lam)
    scale = np.abs(sol.control).max()
    for reg, dom in prob.domains.items():
        els = prob.mesh.subdomains[reg]
        # is_admissible's tolerance is relative to |σ|: a relative solver tolerance 1e-8
        assert dom.is_admissible(sig[:, els] / scale, tol=1e-7).all(), reg


@pytest.mark.parametrize("which", ["cut", "tsec"])
def test_quadratic_field_in_equilibrium_by_finite_differences(which, cut, tsec):
    prob, sol = (cut[0], cut[2]) if which == "cut" else (tsec[0], tsec[1].static)
    p, t = prob.mesh.p, prob.mesh.t
    rng = np.random.default_rng(1)
    lam = rng.dirichlet(4 * np.ones(3), size=5)            # interior points
    X = np.einsum("qi,die->qed", lam, p[:, t])
    # barycentric coordinates of a physical point in each triangle
    T = np.stack([p[:, t[1]] - p[:, t[0]], p[:, t[2]] - p[:, t[0]]], axis=-1)  # (2, nt, 2)
    Tinv = np.linalg.inv(np.moveaxis(T, 0, 1))                                 # (nt, 2, 2)

    def sigma(Y):  # Y (q, nt, 2) → σ (q, nt, 3)
        r = np.einsum("eij,qej->qei", Tinv, Y - p[:, t[0]].T[None])
        lb = np.concatenate([1 - r.sum(-1, keepdims=True), r], axis=-1)   # (q, nt, 3)
        l0, l1, l2 = np.moveaxis(lb, -1, 0)
        B = np.stack([l0 * l0, l1 * l1, l2 * l2, 2 * l0 * l1, 2 * l1 * l2, 2 * l2 * l0], -1)
        return np.einsum("qek,ekm->qem", B, sol.control)

    size = np.sqrt(sol.element_areas())[None, :, None]
    h = 1e-4 * size
    dx = (sigma(X + h * [1, 0]) - sigma(X - h * [1, 0])) / (2 * h)
    dz = (sigma(X + h * [0, 1]) - sigma(X - h * [0, 1])) / (2 * h)
    div = np.stack([dx[..., 0] + dz[..., 2], dx[..., 2] + dz[..., 1]], axis=-1)
    resid = div + _body(prob, sol.multiplier)[None]
    ref = np.abs(_body(prob, sol.multiplier)).max()
    assert np.abs(resid).max() <= 1e-6 * ref


def test_quadratic_tractions_continuous_along_edges(tsec):
    prob, br = tsec
    sol, m = br.static, prob.mesh
    f = np.flatnonzero(m.f2t[1] >= 0)
    ends = m.p[:, m.facets[:, f]]                             # (2, 2, nf)
    tang = ends[:, 1] - ends[:, 0]
    n = np.stack([tang[1], -tang[0]]) / np.hypot(*tang)
    for s in (0.21, 0.5, 0.83):
        x = ends[:, 0] + s * tang                              # (2, nf)
        tr = []
        for side in (0, 1):
            e = m.f2t[side, f]
            P = m.p[:, m.t[:, e]]                              # (2, 3, nf)
            A = np.stack([P[:, 1] - P[:, 0], P[:, 2] - P[:, 0]], -1)   # (2, nf, 2)
            r = np.linalg.solve(np.moveaxis(A, 0, 1), (x - P[:, 0]).T[..., None])[..., 0]
            lb = np.c_[1 - r.sum(1), r]
            l0, l1, l2 = lb.T
            B = np.stack([l0 * l0, l1 * l1, l2 * l2, 2 * l0 * l1, 2 * l1 * l2, 2 * l2 * l0], 1)
            sg = np.einsum("ek,ekm->em", B, sol.control[e])
            tr.append(np.stack([sg[:, 0] * n[0] + sg[:, 2] * n[1],
                                sg[:, 2] * n[0] + sg[:, 1] * n[1]]))
        assert np.abs(tr[0] - tr[1]).max() <= 1e-7 * np.abs(sol.control).max()


def test_quadratic_bound_is_above_the_linear_on_one_mesh_and_below_the_exact(cut):
    prob, lin, quad = cut
    lb, ub = prob.bounds                                       # Kammoun et al. 2010
    assert quad.multiplier >= lin.multiplier * (1 - 1e-7)
    assert quad.multiplier <= ub
    assert quad.multiplier > lin.multiplier + 0.01             # measured: 3.7351 → 3.7536


def test_quadratic_gap_splits_exactly_over_the_elements(tsec):
    _, br = tsec
    assert br.lower <= 0.152160 <= br.upper       # the exact hinge + fan (closed_form.fan)
    assert br.element_gap.min() >= -1e-6 * br.gap
    assert br.element_gap.sum() == pytest.approx(br.gap, rel=1e-5)


def test_quadratic_stresses_refuse_rigid_bodies_and_joints():
    prob = free_block()
    with pytest.raises(ParameterError, match="stress_degree = 2"):
        solve_static(prob, P2)
    with pytest.raises(ParameterError, match="stress_degree"):
        SolverOptions(stress_degree=3)
    assert dataclasses.replace(P2, stress_degree=1).stress_degree == 1


def test_run_takes_the_stress_degree_from_the_case(tmp_path):
    """`[analysis] stress_degree = 2`: the run's static bound is the quadratic field's, on the
    same mesh at least the linear one's (a superset of stress fields) and still below the
    kinematic bound; 3 is refused before any work, naming the key and its range."""
    from homlimit.app import pipeline
    from homlimit.app.config import ConfigError

    over = {"mesh.size": 1.0, "mesh.part_divisions": 3, "analysis.heights": 2,
            "analysis.facade": "homogenised", "analysis.hinge_check": False,
            "adapt.max_cycles": 1, "mesh.outer_ratio": 0.0}
    fe = {d: pipeline.run(None, write=False, overrides=over | {"analysis.stress_degree": d})
          .to_dict()["fe"] for d in (1, 2)}
    assert fe[1]["static_triangles"] == fe[2]["static_triangles"] == fe[1]["n_triangles"]
    assert fe[1]["lower_bound"] <= fe[2]["lower_bound"] * (1 + 1e-6)
    assert fe[2]["lower_bound"] <= fe[2]["multiplier"]
    with pytest.raises(ConfigError, match=r"\[analysis\] stress_degree = 3 is out of range: "
                                          r"allowed 1 <= stress_degree <= 2"):
        pipeline.run(None, write=False, overrides=over | {"analysis.stress_degree": 3})
