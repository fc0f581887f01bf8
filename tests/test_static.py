"""Static (lower-bound) program: exact closed forms, independent admissibility checks, errors.

References are independent of the code: uniaxial strength 2k of a Tresca block, the statics of
rigid blocks on no-tension frictional and on cohesive joints (hand equilibrium), and a
checker that recomputes equilibrium and traction continuity of the returned stress field from
the mesh alone.
"""

from __future__ import annotations

import dataclasses

import meshio
import numpy as np
import pytest
from skfem import MeshTri

from homlimit.errors import ParameterError, SolverError
from homlimit.fe import problems, strength
from homlimit.fe.mesh import write
from homlimit.fe.problems import Problem
from homlimit.fe.solver import SolverOptions
from homlimit.fe.static import solve_static


def _block_mesh(nx=4, nz=8, b=1.0, h=2.0):
    m = problems.crossed_mesh(np.linspace(0, b, nx + 1), np.linspace(0, h, nz + 1))
    return m.with_boundaries({"top": lambda x: np.isclose(x[1], h),
                              "base": lambda x: np.isclose(x[1], 0.0),
                              "left": lambda x: np.isclose(x[0], 0.0)}) \
        .with_subdomains({"soil": lambda x: x[0] > -1})


def test_uniaxial_compression_tresca_is_2k():
    """A Tresca block pressed on top, smooth base and symmetry side: q = 2k (all points yield)."""
    k = 3.0e4
    m = _block_mesh()
    sol = solve_static(Problem("block", m, {"soil": strength.Tresca(k)},
                               live_traction={"top": (0.0, -k)},
                               supports={"base": "z", "left": "x"}))
    assert sol.multiplier == pytest.approx(2.0, rel=1e-7)
    # the limit field is uniaxial σ_z = −2k, on the Tresca circle at every vertex
    s = sol.stress.reshape(-1, 3)
    assert np.allclose(s[:, 1], -2 * k, rtol=1e-5)
    assert np.allclose(s[:, [0, 2]], 0.0, atol=1e-5 * k)
    assert np.all(sol.active == 0)


def test_one_diagonal_mesh_either_orientation():
    """skfem's init_tensor triangles are clockwise: the gradients must not care."""
    m = MeshTri.init_tensor(np.linspace(0, 1, 4), np.linspace(0, 2, 7)).with_boundaries(
        {"top": lambda x: np.isclose(x[1], 2), "base": lambda x: np.isclose(x[1], 0)}) \
        .with_subdomains({"soil": lambda x: x[0] > -1})
    sol = solve_static(Problem("block", m, {"soil": strength.Tresca(1.0)},
                               live_traction={"top": (0.0, -1.0)}, supports={"base": "fixed"}))
    # fixed base: the block is stronger than uniaxially (confinement), but only the base may help
    assert sol.multiplier >= 2.0 - 1e-7


def _check_static_admissibility(sol, prob):
    """Recompute div σ per triangle and traction jumps per interior edge from the mesh alone."""
    m = prob.mesh
    p, t = m.p, m.t
    x, z = p[0, t], p[1, t]
    # least-squares plane through the three vertex values of each component (exact: linear)
    ones = np.ones_like(x)
    M = np.stack([ones, x, z], axis=-1).transpose(1, 0, 2)          # (nt, 3 vertices, 3)
    coef = np.linalg.solve(M, sol.stress)                           # (nt, 3 [1,x,z], 3 comp)
    sx_x, sz_z = coef[:, 1, 0], coef[:, 2, 1]
    t_x, t_z = coef[:, 1, 2], coef[:, 2, 2]
    lam = sol.multiplier
    b = np.zeros((t.shape[1], 2))
    for reg, f in prob.live_body.items():
        b[m.subdomains[reg]] += lam * np.asarray(f)
    for reg, f in prob.dead_body.items():
        b[m.subdomains[reg]] += np.asarray(f)
    scale = np.abs(sol.stress).max() / np.sqrt(sol.element_areas().min())
    assert np.abs(sx_x + t_z + b[:, 0]).max() < 1e-6 * scale
    assert np.abs(t_x + sz_z + b[:, 1]).max() < 1e-6 * scale
    # traction continuity at both ends of every interior edge
    f2t = m.f2t
    inner = np.flatnonzero(f2t[1] >= 0)
    a, c = m.facets[:, inner]
    tang = p[:, c] - p[:, a]
    n = np.stack([tang[1], -tang[0]]) / np.hypot(*tang)
    for node in (a, c):
        pts = p[:, node]
        sig = []
        for side in (0, 1):
            e = f2t[side, inner]
            s = np.einsum("ek,eki->ei", np.stack([np.ones_like(pts[0]), pts[0], pts[1]], 1),
                          coef[e])
            sig.append(np.stack([s[:, 0] * n[0] + s[:, 2] * n[1],
                                 s[:, 2] * n[0] + s[:, 1] * n[1]]))
        assert np.abs(sig[0] - sig[1]).max() < 1e-6 * np.abs(sol.stress).max()


def test_vertical_cut_field_is_statically_admissible():
    """The returned field satisfies equilibrium, continuity and the Tresca condition."""
    prob = problems.vertical_cut(h_min=0.1, h_max=0.3)
    sol = solve_static(prob)
    _check_static_admissibility(sol, prob)
    assert np.all(strength.Tresca(1.0).is_admissible(sol.stress, tol=1e-6))
    assert sol.multiplier <= problems.VERTICAL_CUT_LB


# ------------------------------------------------------------- rigid bodies (strength.Rigid)
# A rigid block on a joint to the ground: hand statics of one body (3 equations) and the
# joint's traction set. Tilting about the toe needs a concentrated contact force there, which
# the program represents (end forces in the recession cone of the joint's domain).

B, H, F, UNIT_WEIGHT = 0.5, 3.0, 0.6, 2000.0 * 9.81


def _graded_block(eps, b=B, h=H):
    xs = problems.graded(0, b, eps, b / 2, foci=(0,), growth=1.6)
    zs = problems.graded(0, h, eps, b / 2, foci=(0,), growth=1.6)
    return problems.crossed_mesh(xs, zs).with_boundaries(
        {"base": lambda x: np.abs(x[1]) < 1e-9}).with_subdomains({"facade": lambda x: x[0] > -1})


@pytest.mark.parametrize("b, h, n_b", [(0.5, 3.0, 1), (0.5, 3.0, 2), (0.4, 5.0, 3)])
def test_rigid_block_tilts_at_b_over_h(b, h, n_b):
    """Dry bed joint, horizontal load λ × weight: moment about the toe W b/2 = λ W h/2."""
    sol = solve_static(problems.free_block(b=b, h=h, f=F, n_b=n_b))
    assert sol.multiplier == pytest.approx(b / h, rel=1e-7)
    assert sol.sizes["rigid_bodies"] == 1 and sol.rigid.all()
    assert np.isnan(sol.stress).all()


def test_rigid_block_on_a_graded_mesh_is_still_b_over_h():
    """The mesh does not matter for one rigid body (a continuum block would give
    (b − 2ε/3)/h: linear contact pressure on the toe edge ε puts the resultant ε/3 inside)."""
    prob = dataclasses.replace(problems.free_block(b=B, h=H, f=F), mesh=_graded_block(0.01))
    sol = solve_static(prob)
    assert sol.multiplier == pytest.approx(B / H, rel=1e-7)


def test_squat_rigid_block_slides_at_f():
    """b = h: tilting needs λ = 1 > f, so the block slides at λ = f (|V| <= f N, N = W)."""
    sol = solve_static(problems.free_block(b=0.5, h=0.5, f=F))
    assert sol.multiplier == pytest.approx(F, rel=1e-7)


@pytest.mark.parametrize("tension, cohesion", [(2000.0, 1500.0), (5000.0, 4000.0)])
def test_rigid_block_on_cohesive_joint(tension, cohesion):
    """Joint with tensile strength T_h = min(T, C/f): tension T_h over the base plus a
    concentrated compression at the toe, λ W h/2 = W b/2 + T_h b²/2."""
    W = UNIT_WEIGHT * B * H
    t_h = min(tension, cohesion / F)
    exact = (W * B + t_h * B * B) / (W * H)
    prob = dataclasses.replace(problems.free_block(b=B, h=H, f=F),
                               interfaces={"base": strength.BedJoints(F, cohesion, tension)})
    sol = solve_static(prob)
    assert sol.multiplier == pytest.approx(exact, rel=1e-7)


def test_two_rigid_blocks_are_two_bodies():
    """Two rigid regions not sharing an edge are two bodies, each in its own equilibrium: the
    slender one (0.5 × 3) tilts at b/h = 1/6, the squat one (0.5 × 1) would hold up to 0.5."""
    from homlimit.fe import geometry
    from homlimit.fe import mesh as hmesh

    mm = geometry.polygon_mesh(
        {"left": [(0, 0), (0.5, 0), (0.5, 3), (0, 3)], "right": [(1, 0), (1.5, 0), (1.5, 1),
                                                                   (1, 1)]},
        {"base": [((0, 0), (1.5, 0))]}, size=0.5)
    m = hmesh.to_skfem(mm)
    w = (-UNIT_WEIGHT, 0.0), (0.0, -UNIT_WEIGHT)
    sol = solve_static(Problem("blocks", m, {"left": strength.Rigid(), "right": strength.Rigid()},
                               live_body={"left": w[0], "right": w[0]},
                               dead_body={"left": w[1], "right": w[1]},
                               interfaces={"base": strength.BedJoints(F)}))
    assert sol.sizes["rigid_bodies"] == 2
    assert sol.multiplier == pytest.approx(0.5 / 3.0, rel=1e-7)


def test_rigid_footing_on_tresca_soil_is_a_lower_bound():
    """A rigid rough footing loaded on top, bonded to weightless Tresca soil: the body takes the
    soil's tractions across its boundary; q/k = 2 + π for a rough footing too."""
    from homlimit.fe.bracket import prandtl_fan

    prob = prandtl_fan(size=0.5, h_min=0.08, n_fan=6, footing=0.25)
    sol = solve_static(prob)
    assert sol.sizes["rigid_bodies"] == 1
    assert 4.5 < sol.multiplier <= problems.PRANDTL
    soil = ~sol.rigid
    assert np.all(strength.Tresca(1.0).is_admissible(sol.stress[soil], tol=1e-6))


def test_unsupported_rigid_body_is_reported():
    """A rigid block with no support and no joint cannot carry its weight: Infeasible."""
    m = _block_mesh(1, 2)
    with pytest.raises(SolverError) as exc:
        solve_static(Problem("block", m, {"soil": strength.Rigid()},
                             live_body={"soil": (-1.0, 0.0)}, dead_body={"soil": (0.0, -1.0)}),
                     SolverOptions(retries=False))
    assert "Infeasible" in exc.value.status


def test_homogenised_field_is_admissible_and_compressive(b1):
    """T-section lower-bound field: eq. 15 holds at every vertex (no tension anywhere)."""
    prob = problems.t_section(b1, h=1.0, n_b=1, growth=1.3)
    sol = solve_static(prob)
    dom = strength.Homogenised(0.3, 0.2, 0.6)
    scale = np.abs(sol.stress).max()
    # eq. 15 facets N_k·σ <= 0 with a tolerance relative to the stress scale
    N = np.array([[0, 0.6, 1], [0, 0.6, -1], [1.5, 0.6, 1 + 0.6 / 1.5],
                  [1.5, 0.6, -(1 + 0.6 / 1.5)]])
    assert (sol.stress.reshape(-1, 3) @ N.T).max() <= 1e-6 * scale
    assert np.all(dom.is_admissible(sol.stress / scale, tol=1e-6))
    _check_static_admissibility(sol, prob)
    assert np.all(sol.stress[..., 1] <= 1e-6 * scale)       # σ_z <= 0: no tension


def test_stress_fields_and_vtu_round_trip(tmp_path):
    m = _block_mesh(2, 4)
    sol = solve_static(Problem("block", m, {"soil": strength.Tresca(1.0)},
                               live_traction={"top": (0.0, -1.0)},
                               supports={"base": "z", "left": "x"}))
    f = sol.fields()
    assert set(f) == {"sigma_x", "sigma_z", "tau_xz", "active_facet"}
    assert f["sigma_z"].shape == (m.t.shape[1], 3)
    path = tmp_path / "stress.vtu"
    write(sol.to_meshio(), path)               # the one mesh writer, homlimit.fe.mesh
    back = meshio.read(path)
    assert back.points.shape[0] == 3 * m.t.shape[1]
    assert np.allclose(back.point_data["sigma_z"], -2.0, rtol=1e-5)
    assert np.allclose(back.cell_data["sigma_z"][0], -2.0, rtol=1e-5)
    assert not list(tmp_path.glob("*.tmp*"))


def test_plot_stress(tmp_path):
    from homlimit.app.plots import plot_stress

    m = _block_mesh(2, 4)
    sol = solve_static(Problem("block", m, {"soil": strength.Tresca(1.0)},
                               live_traction={"top": (0.0, -1.0)},
                               supports={"base": "z", "left": "x"}))
    out = plot_stress(tmp_path / "s.png", sol, title="block")
    import matplotlib.image as mpimg

    img = mpimg.imread(out)
    assert img.shape[0] > 300 and img.shape[1] > 300
    assert img[..., :3].std() > 0.05                         # not blank


# ------------------------------------------------------------------------------- bad input


def test_bad_input_raises_parameter_error_naming_the_value():
    """Names, supports, load vectors and live loads are checked by the Problem (once, for both
    bounds), active_tol by solve_static."""
    m = _block_mesh(1, 2)
    tr = {"soil": strength.Tresca(1.0)}
    with pytest.raises(ParameterError, match="supports\\['base'\\] = 'clamped'"):
        Problem("p", m, tr, live_traction={"top": (0, -1)}, supports={"base": "clamped"})
    with pytest.raises(ParameterError, match="boundary = 'roof'"):
        Problem("p", m, tr, live_traction={"roof": (0, -1)}, supports={"base": "z"})
    with pytest.raises(ParameterError, match="region = 'wall'"):
        Problem("p", m, {"wall": tr["soil"]}, live_traction={"top": (0, -1)})
    with pytest.raises(ParameterError, match="domains\\['soil'\\] = 'tresca'"):
        Problem("p", m, {"soil": "tresca"}, live_traction={"top": (0, -1)})
    with pytest.raises(ParameterError, match="live loads"):
        Problem("p", m, tr, dead_traction={"top": (0, -1)}, supports={"base": "z"})
    with pytest.raises(ParameterError, match="live loads"):
        Problem("p", m, tr, live_traction={"top": (0, 0)}, supports={"base": "z"})
    with pytest.raises(ParameterError, match="shape"):
        Problem("p", m, tr, live_traction={"top": (0, -1, 0)}, supports={"base": "z"})
    with pytest.raises(ParameterError, match="active_tol"):
        solve_static(Problem("p", m, tr, live_traction={"top": (0, -1)}), active_tol=-1.0)


def test_solver_error_names_the_status():
    """No support and a dead load: no stress field can carry it (primal infeasible)."""
    m = _block_mesh(1, 2)
    with pytest.raises(SolverError) as exc:
        solve_static(Problem("p", m, {"soil": strength.Tresca(1.0)},
                             live_traction={"top": (-1.0, 0)}, dead_traction={"top": (0, -1.0)}),
                     SolverOptions(retries=False))
    assert "Infeasible" in exc.value.status
    assert "Infeasible" in str(exc.value)


def test_invariant_under_units():
    """γH/k does not depend on the units: H = 1 m, k = 1 Pa vs H = 7 m, k = 40 kPa."""
    a = solve_static(problems.vertical_cut(h_min=0.1, h_max=0.3))
    b = solve_static(problems.vertical_cut(h_min=0.1, h_max=0.3, H=7.0, k=4.0e4))
    assert b.multiplier == pytest.approx(a.multiplier, rel=1e-6)


# ------------------------------------------------------------------ the cvxpy path, HiGHS


def test_cvxpy_backend_reproduces_the_direct_program():
    """The same matrices through cvxpy → Clarabel (the kinematic program's path): same λ⁻."""
    prob = problems.vertical_cut(h_min=0.1, h_max=0.3)                  # second-order cones
    a = solve_static(prob)
    b = solve_static(prob, SolverOptions(backend="cvxpy"))
    assert b.multiplier == pytest.approx(a.multiplier, rel=1e-7)
    assert np.allclose(b.stress, a.stress, atol=1e-4 * np.abs(a.stress).max())
    # one unpacking (fe.solver.Solved.report): Clarabel's objectives and Clarabel's status
    # names on both paths, the objectives of max λ as λ itself
    for s in (a, b):
        assert (s.status, s.solver) == ("Solved", "CLARABEL")
        assert s.primal_objective == pytest.approx(a.multiplier, rel=1e-7)
        assert s.dual_objective == pytest.approx(a.multiplier, rel=1e-6)


@pytest.mark.slow
def test_highs_simplex_confirms_the_linear_programs():
    """An independent LP solver (HiGHS through cvxpy) on eq. 15 and on the rigid block."""
    from homlimit.params import Case

    tsec = problems.t_section(Case(), h=1.0, n_b=1, growth=1.3)
    a = solve_static(tsec)
    h = solve_static(tsec, SolverOptions(solver="HIGHS"))
    assert h.multiplier == pytest.approx(a.multiplier, rel=1e-7)
    block = solve_static(problems.free_block(b=B, h=H, f=F), SolverOptions(solver="HIGHS"))
    assert block.multiplier == pytest.approx(B / H, rel=1e-12)          # a vertex solution


def test_backend_choices_are_checked():
    prob = problems.vertical_cut(h_min=0.2, h_max=0.3)
    with pytest.raises(ParameterError, match="backend = 'mosek'"):
        SolverOptions(backend="mosek")
    with pytest.raises(ParameterError, match="solver = 'NOSUCH'"):
        SolverOptions(backend="cvxpy", solver="NOSUCH")
    with pytest.raises(ParameterError, match="solver = 'HIGHS'"):                 # cones
        solve_static(prob, SolverOptions(backend="cvxpy", solver="HIGHS"))


@pytest.mark.slow
def test_faer_on_one_thread_gives_the_same_bound():
    """The factorisation chosen above solver.FAER_ABOVE unknowns (faer, one thread) against
    qdldl on a small program: the same λ⁻."""
    from homlimit.fe.solver import FAER_ABOVE

    def first(n):  # the settings of the first attempt on a static program of n unknowns
        return SolverOptions().ladder("static", n, conic=False)[0][1]

    assert first(FAER_ABOVE + 1)["direct_solve_method"] == "faer"
    assert first(FAER_ABOVE + 1)["max_threads"] == 1
    assert first(FAER_ABOVE)["direct_solve_method"] == "qdldl"
    prob = problems.vertical_cut(h_min=0.1, h_max=0.3)
    a = solve_static(prob)
    b = solve_static(prob, SolverOptions(settings={"direct_solve_method": "faer",
                                                   "max_threads": 1}))
    assert b.multiplier == pytest.approx(a.multiplier, rel=1e-7)
