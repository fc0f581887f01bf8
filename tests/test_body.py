"""RigidBody.from_triangles: exact integration over triangles vs hand formulas and eqs 17, 20."""

import numpy as np
import pytest
from scipy.spatial import Delaunay

from homlimit.errors import ParameterError
from homlimit.impulse.body import RigidBody, triangle_moments


def _triangulate_convex(corners, n_inner, rng):
    """Delaunay triangulation of a convex polygon with random interior points."""
    corners = np.asarray(corners, float)
    w = rng.dirichlet(np.ones(len(corners)), size=n_inner)
    pts = np.vstack([corners, w @ corners])
    tri = Delaunay(pts).simplices
    return pts, tri


def test_rectangle_about_its_corner():
    w, h, rho = 0.7, 3.2, 1900.0
    rng = np.random.default_rng(0)
    pts, tri = _triangulate_convex([(0, 0), (w, 0), (w, h), (0, h)], 40, rng)
    body = RigidBody.from_triangles(pts, tri, rho, O=(0.0, 0.0))
    m = rho * w * h
    assert body.m == pytest.approx(m, rel=1e-12)
    assert body.x_G == pytest.approx(w / 2, rel=1e-12)
    assert body.z_G == pytest.approx(h / 2, rel=1e-12)
    assert body.I_O == pytest.approx(m * (w ** 2 + h ** 2) / 3, rel=1e-12)


def test_right_triangle_about_its_right_angle_and_shifted_origin():
    w, h = 1.5, 2.5
    pts = np.array([[2.0, 1.0], [2.0 + w, 1.0], [2.0, 1.0 + h]])
    tri = np.array([[0, 1, 2]])
    body = RigidBody.from_triangles(pts, tri, 2.0, O=(2.0, 1.0))
    m = 2.0 * w * h / 2
    assert body.m == pytest.approx(m, rel=1e-14)
    assert (body.x_G, body.z_G) == pytest.approx((w / 3, h / 3), rel=1e-14)
    assert body.I_O == pytest.approx(m * (w ** 2 + h ** 2) / 6, rel=1e-14)


def test_moments_do_not_depend_on_vertex_order():
    rng = np.random.default_rng(3)
    pts = rng.normal(size=(3, 2))
    a = triangle_moments(pts, [[0, 1, 2]], O=(0.3, -0.2))
    b = triangle_moments(pts, [[2, 1, 0]], O=(0.3, -0.2))
    np.testing.assert_allclose(a, b, rtol=1e-14)


@pytest.mark.parametrize("rho, lam, alpha", [(12.0, 13.8, np.sqrt(0.4)), (5.0, 5.4, np.sqrt(0.8)),
                                             (2.0, 3.0, 1.3)])
def test_mechanism_II_body_matches_eqs_17_and_20(rho, lam, alpha):
    """Façade strip (density ρ) + wedge behind a straight crack from the inner corner at
    tan ψ = α, about the façade's outer toe: x_G, z_G (eq. 17) and i (eq. 20)."""
    b = 0.5
    h = lam * b
    rng = np.random.default_rng(1)
    p1, t1 = _triangulate_convex([(0, 0), (b, 0), (b, h), (0, h)], 30, rng)
    p2, t2 = _triangulate_convex([(b, 0), (b + alpha * h, h), (b, h)], 30, rng)
    pts = np.vstack([p1, p2])
    tri = np.vstack([t1, t2 + len(p1)])
    dens = np.r_[np.full(len(t1), rho), np.ones(len(t2))]
    body = RigidBody.from_triangles(pts, tri, dens, O=(0.0, 0.0))
    x_G = b / 3 * (3 * rho + lam ** 2 * alpha ** 2 + 3 * alpha * lam) / (2 * rho + lam * alpha)
    z_G = b / 3 * lam * (3 * rho + 2 * lam * alpha) / (2 * rho + lam * alpha)
    i = b ** 2 / 6 * ((3 * alpha + alpha ** 3) * lam ** 3 + 4 * (rho + alpha ** 2) * lam ** 2
                      + 6 * lam * alpha + 4 * rho) / (2 * rho + lam * alpha)
    assert body.x_G == pytest.approx(x_G, rel=1e-6)
    assert body.z_G == pytest.approx(z_G, rel=1e-6)
    assert body.i == pytest.approx(i, rel=1e-6)


def test_bad_input_names_the_parameter():
    pts = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]])
    with pytest.raises(ParameterError, match="density"):
        RigidBody.from_triangles(pts, [[0, 1, 2]], -1.0)
    with pytest.raises(ParameterError, match="triangles"):
        RigidBody.from_triangles(pts, [[0, 1, 5]], 1.0)
    with pytest.raises(ParameterError, match="points"):
        RigidBody.from_triangles(np.zeros((3, 3)), [[0, 1, 2]], 1.0)
