"""FE mechanism → body → impulse: exact body integration on a crack-conforming mesh (eqs 17, 20),
the one-DOF impulse reducing to eq. 19 for a rigid body, and one FE analysis end to end."""

import math

import numpy as np
import pytest
import skfem as fem

from homlimit.closed_form.fan import optimise_fan
from homlimit.closed_form.mechanisms import geometry_II
from homlimit.fe.problems import t_section
from homlimit.impulse.body import RigidBody
from homlimit.mechanism.analysis import analyse, fe_result
from homlimit.mechanism.fe_impulse import generalised_impulse, ray_conforming_mesh
from homlimit.mechanism.rigidfit import measure_mechanism


def test_crack_conforming_mesh_body_matches_mechanism_II(table1_case):
    """A gmsh mesh containing the straight crack tan ψ = α from the inner corner (b, z_h) and
    the bed joint under the façade at z_h; the
    triangles behind it (façade above z_h + wedge), about the outer toe (0, z_h), integrated
    exactly: x_G, z_G (eq. 17) and i (eq. 20) to 1e-6."""
    case = table1_case("B2")
    w, alpha, z_h = case.wall, case.alpha, 5.0
    m = ray_conforming_mesh(case, z_h, [alpha], h=0.4, x_apex=w.b,
                            extra_lines=[((0.0, z_h), (w.b, z_h))])
    c = m.p[:, m.t].mean(axis=1)
    behind = (c[1] > z_h) & (c[0] - w.b < alpha * (c[1] - z_h))
    rho = np.where(c[0] < w.b, case.rho, 1.0)
    body = RigidBody.from_triangles(m.p.T, m.t.T[behind], rho[behind], O=(0.0, z_h))
    lam = (w.H - z_h) / w.b
    xg, zg, i = (float(v) for v in geometry_II(lam, case.rho, alpha))
    assert body.x_G == pytest.approx(xg * w.b, rel=1e-6)
    assert body.z_G == pytest.approx(zg * w.b, rel=1e-6)
    assert body.i == pytest.approx(i * w.b ** 2, rel=1e-6)


def test_generalised_impulse_of_a_rigid_block_is_eq_19():
    """Free rectangle b × h rocking about its toe: the one-DOF criterion reduces to eq. 19,
    v̄_g = √((2 g i / z_G)(r_G / z_G − 1)) with i = (b² + h²)/3, z_G = h/2, r_G = ½√(b² + h²)."""
    b, h, g = 0.5, 3.0, 9.81
    mesh = fem.MeshTri.init_tensor(np.linspace(0, b, 5), np.linspace(0, h, 13))
    sb = fem.Basis(mesh, fem.ElementTriP2())
    X, el = sb.doflocs.T.copy(), sb.element_dofs.T.copy()
    V = 0.3 * np.stack([-X[:, 1], X[:, 0]], axis=1)
    mm = measure_mechanism(X, V, el, 1800.0)
    gi = generalised_impulse(X, V, el, 1800.0, mm, g=g)
    i, zg, rg = (b * b + h * h) / 3, h / 2, 0.5 * math.hypot(b, h)
    assert gi.vg == pytest.approx(math.sqrt(2 * g * i / zg * (rg / zg - 1)), rel=1e-12)
    assert gi.M_rest_share == pytest.approx(0.0, abs=1e-12)


@pytest.mark.slow
def test_fe_analysis_end_to_end_on_a_coarse_mesh(table1_case):
    """The part above z0 = 3 m of wall B2 on a coarse crossed mesh: a hinge + fan whose hinge
    and mid-line agree with the closed form within the element-size uncertainty, and a v̄_g
    bracketed by the two body models."""
    case = table1_case("B2")
    r = analyse(case, t_section(case, z0=3.0, h=0.5))
    opt = optimise_fan(case, z_base=3.0)
    assert r.kind == "hinge+fan"
    assert r.multiplier >= opt.lam
    assert abs(r.O[1] - opt.z0) < 0.5
    assert abs(r.tanpsi - case.alpha) <= r.tanpsi_uncertainty
    assert r.lam == pytest.approx((case.wall.H - r.O[1]) / case.wall.b)
    assert r.vnorm == pytest.approx(r.vg / math.sqrt(9.81 * 0.5))
    assert 0.2 < r.vnorm < 1.0


@pytest.mark.slow
def test_fe_result_critical_is_the_minimum_of_the_scan(table1_case):
    """The Table 1 columns: the scan's minimum of v̄_g, with λ = h/b from the hinge height."""
    case = table1_case("B2")
    res = fe_result(case, [4.0, 8.0, case.wall.lam_max], mesh_size=0.5)
    r = res.critical
    assert [round(m.h_part, 9) for m in res.scan] == [2.0, 4.0, 9.0]
    assert r.vnorm == pytest.approx(min(m.vnorm for m in res.scan))
    assert r.kind in ("rigid", "hinge+fan", "distributed")
    assert len(r.tanpsi_edges) == 2
    assert r.lam == pytest.approx(r.h / 0.5)
    assert res.as_dict()["vnorm"] == r.vnorm and len(res.as_dict()["scan"]) == 3


def test_prescribed_mechanism_II_field_through_the_fe_pipeline(table1_case):
    """Mechanism II's field (rotation about the outer toe behind the crack from the inner
    corner, rest at rest) on the P2 nodes of a crack-conforming mesh: the rigid fit finds the
    toe, and the body inside the 50 % line reproduces eqs 17 and 20 to 1e-6."""
    from homlimit.mechanism.fe_impulse import fe_body

    case = table1_case("B2")
    w, alpha, z_h = case.wall, case.alpha, 5.0
    m = ray_conforming_mesh(case, z_h, [alpha], h=0.4, x_apex=w.b,
                            extra_lines=[((0.0, z_h), (w.b, z_h))])
    sb = fem.Basis(m, fem.ElementTriP2())
    X, el = sb.doflocs.T.copy(), sb.element_dofs.T.copy()
    tol = 1e-9
    behind = (X[:, 1] >= z_h - tol) & (X[:, 0] - w.b <= alpha * (X[:, 1] - z_h) + tol)
    V = np.where(behind[:, None], np.stack([-(X[:, 1] - z_h), X[:, 0]], axis=1), 0.0)
    c = m.p[:, m.t].mean(axis=1)
    rho = np.where(c[0] < w.b, case.rho, 1.0)
    mm = measure_mechanism(X, V, el, rho)
    np.testing.assert_allclose(mm.fit.O, (0.0, z_h), atol=1e-10)
    body = fe_body(X, el, rho, mm)
    lam = (w.H - z_h) / w.b
    xg, zg, i = (float(v) for v in geometry_II(lam, case.rho, alpha))
    assert body.x_G == pytest.approx(xg * w.b, rel=1e-6)
    assert body.z_G == pytest.approx(zg * w.b, rel=1e-6)
    assert body.i == pytest.approx(i * w.b ** 2, rel=1e-6)
