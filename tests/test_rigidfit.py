"""Rigid fit of velocity fields: exact recovery of rigid rotations, non-rigid fields recognised."""

import numpy as np
import pytest
import skfem as fem

from homlimit.closed_form.fan import fan_strain_rate, fan_velocity
from homlimit.errors import ParameterError
from homlimit.mechanism.rigidfit import fit_rigid, measure_mechanism, p2_energy


def _p2_mesh(nx=24, nz=32, W=3.0, H=4.0):
    m = fem.MeshTri.init_tensor(np.linspace(0, W, nx + 1), np.linspace(0, H, nz + 1))
    b = fem.Basis(m, fem.ElementTriP2())
    return b.doflocs.T.copy(), b.element_dofs.T.copy(), m


def _area(X, el):
    a, b = X[el[:, 1]] - X[el[:, 0]], X[el[:, 2]] - X[el[:, 0]]
    return 0.5 * np.abs(a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0])


def _rot(X, centre, om):
    return om * np.stack([-(X[:, 1] - centre[1]), X[:, 0] - centre[0]], axis=1)


def test_prescribed_rigid_rotation_is_recovered_to_solver_precision():
    rng = np.random.default_rng(0)
    X = rng.uniform(-2, 5, size=(300, 2))
    centre, om = (0.3, 2.0), 0.7
    fit = fit_rigid(X, _rot(X, centre, om))
    assert fit.omega == pytest.approx(om, rel=1e-12)
    np.testing.assert_allclose(fit.O, centre, rtol=0, atol=1e-11)
    assert fit.rms < 1e-12
    assert fit.block.sum() == np.sum(np.linalg.norm(_rot(X, centre, om), axis=1)
                                     > 0.02 * fit.vmax)


def test_block_behind_a_crack_and_fixed_part():
    X, el, _ = _p2_mesh()
    hinge = (0.0, 1.0)
    moving = X[:, 0] < 0.6 * (X[:, 1] - hinge[1])  # block left of a ray from the hinge
    V = np.where(moving[:, None], _rot(X, hinge, 1.0), 0.0)
    mm = measure_mechanism(X, V, el)
    np.testing.assert_allclose(mm.fit.O, hinge, atol=1e-12)
    assert mm.fit.omega == pytest.approx(1.0, rel=1e-12)
    assert mm.kind == "rigid"
    assert mm.block_share > 0.5
    assert np.all(mm.spin[mm.label == 1] == pytest.approx(1.0))
    assert np.all(mm.strain[mm.label == 1] < 1e-10)
    assert np.all(mm.spin[mm.label == 0] == 0.0)


def test_two_zone_field_is_not_rigid():
    X, el, _ = _p2_mesh()
    left = X[:, 0] < 1.5
    V = np.where(left[:, None], _rot(X, (0.0, 0.0), 1.0), _rot(X, (3.0, 0.0), -1.0))
    mm = measure_mechanism(X, V, el)
    assert mm.kind != "rigid"
    assert mm.explained < 0.7
    assert mm.block_share < 0.7


def test_fan_field_spin_strain_and_unexplained_energy():
    """Closed-form hinge + fan field: spin/ω = 1/2 and |d| = |(1, T1T2, −(T1+T2))|/(T2−T1) in
    the fan (P2 reproduces the affine field exactly), and the energy the rigid fit does not
    explain is at least that of the elements wholly inside the fan."""
    X, el, _ = _p2_mesh(36, 48)
    z0, T1, T2 = 0.5, 0.4, 1.2
    V = fan_velocity(X[:, 0], X[:, 1], z0, T1, T2)
    mm = measure_mechanism(X, V, el)
    np.testing.assert_allclose(mm.fit.O, (0.0, z0), atol=1e-12)
    zeta = X[el, 1] - z0
    inside = np.all((X[el, 0] >= T1 * zeta) & (X[el, 0] <= T2 * zeta) & (zeta > 0), axis=1)
    assert inside.sum() > 50
    np.testing.assert_allclose(mm.spin[inside], 0.5, rtol=1e-10)
    np.testing.assert_allclose(mm.strain[inside], np.linalg.norm(fan_strain_rate(T1, T2)),
                               rtol=1e-10)
    assert np.all(mm.label[inside] == 2)
    area = _area(X, el)
    e = p2_energy(el, area, 1.0, V)
    assert 1 - mm.explained >= e[inside].sum() / e.sum() - 1e-12
    assert mm.kind == "deforming"


def test_p2_energy_is_exact_for_quadratic_fields():
    X, el, m = _p2_mesh(5, 7)
    V = np.stack([X[:, 0] ** 2 - X[:, 1], X[:, 0] * X[:, 1]], axis=1)
    area = _area(X, el)
    # ∫∫ (x² − z)² + x² z² over [0,3]×[0,4], by hand
    ref = (3 ** 5 / 5 * 4 - 2 * 3 ** 3 / 3 * 8 + 3 * 64 / 3) + 9 * 64 / 3
    assert p2_energy(el, area, 1.0, V).sum() == pytest.approx(ref, rel=1e-12)


def test_bad_input():
    with pytest.raises(ParameterError, match="max"):
        fit_rigid(np.zeros((4, 2)), np.zeros((4, 2)))
    with pytest.raises(ParameterError, match="X, V"):
        fit_rigid(np.zeros((4, 2)), np.zeros((3, 2)))
    with pytest.raises(ParameterError, match="rtol"):
        fit_rigid(np.ones((4, 2)), np.ones((4, 2)), rtol=2.0)
