"""Mechanism I's abutment friction (eqs 8–10) in the equation of motion: consistent with eq. 10,
dissipative in both directions, and able to hold the façade where it stopped."""

import math

import numpy as np
import pytest
from scipy.integrate import quad

from homlimit.closed_form.mechanisms import mechanism_I, work_I
from homlimit.dynamics import MechanismIRocker, OneSinePulse, RectangularPulse, simulate
from homlimit.dynamics.rocking import friction_moment_I


def eq10_friction(case, lam, theta):
    """The friction term of eq. 10, g γ s f c² (6h²θ² + c² − 4chθ) / (24 a θ²) (θ >= c/h),
    written out from the paper."""
    w, m = case.wall, case.masonry
    h, c, a, f = lam * w.b, m.c, m.a, m.f
    return w.g * w.gamma * w.s * f * c ** 2 * (6 * h ** 2 * theta ** 2 + c ** 2
                                               - 4 * c * h * theta) / (24 * a * theta ** 2)


@pytest.mark.parametrize("lam", [4.0, 9.923])
def test_friction_moment_integrates_to_eq10(b1, lam):
    rk = MechanismIRocker(b1, lam=lam)
    w, m = b1.wall, b1.masonry
    theta_c = m.c / rk.h
    for theta in (0.5 * theta_c, theta_c, 2 * theta_c, 5 * theta_c):
        D = quad(lambda t: float(friction_moment_I(t, rk.h, m.c, m.a, m.f, w.s, w.gamma)),
                 0, theta, points=[theta_c] if theta > theta_c else None, epsabs=0,
                 epsrel=1e-12)[0]
        assert float(rk.friction_work(theta)) == pytest.approx(D, rel=1e-10)
        if theta >= theta_c:
            assert D == pytest.approx(eq10_friction(b1, lam, theta), rel=1e-10)
    # eq. 9 at θ = 0: every abutment joint overlaps by c, F = g γ s f h³ c / (6 a)
    assert float(rk.friction(0.0)) == pytest.approx(
        w.g * w.gamma * w.s * m.f * rk.h ** 3 * m.c / (6 * m.a), rel=1e-14)


def test_rocker_work_is_eq10_and_peaks_at_theta_m(b1):
    rk = MechanismIRocker(b1)
    res = mechanism_I(b1)
    w = b1.wall
    th = np.linspace(1e-3, 0.3, 1001)
    ref = work_I(th, res.lam, b1.rho, b1.alpha, b1.beta) * w.g * w.gamma * w.s * w.b ** 3
    assert np.allclose(rk.work(th), ref, rtol=1e-12, atol=1e-12 * rk.W_m)
    assert rk.theta_m == pytest.approx(res.theta_m, rel=1e-14)
    assert rk.W_m == pytest.approx(res.W_m, rel=1e-12)
    # R + F is the slope of W (eq. 9 against eq. 10)
    for t in (0.01, 0.05, 0.2):
        dW = (float(rk.work(t + 1e-7)) - float(rk.work(t - 1e-7))) / 2e-7
        assert float(rk.restoring(t) + rk.friction(t)) == pytest.approx(dW, rel=1e-6)


def test_friction_work_is_not_returned_when_the_motion_reverses(b1):
    """A short part (λ = 4, h = 2 m) thrown outwards at θ̇0 = 0.3 rad/s: gravity's restoring
    moment beats the friction (R(0) = 29.4 kN m > F(0) = 5.2 kN m), so the façade turns at
    θ_max < θ_m and falls back onto its seat. Along the way out and back friction dissipates
    2 D(θ_max) (D: eq. 10's friction term), not zero as it would if eq. 10's W were a
    potential: the façade returns with ½ I θ̇0² − 2 D(θ_max) instead of ½ I θ̇0²."""
    rk = MechanismIRocker(b1, lam=4.0)
    assert float(rk.restoring(0.0)) > float(rk.friction(0.0))
    w0 = 0.3
    K0 = 0.5 * rk.inertia * w0 ** 2
    r = simulate(rk, None, theta_dot0=w0, duration=5.0)
    assert r.theta_max < rk.theta_m
    # out: the kinetic energy is spent on eq. 10's restoring work
    assert float(rk.work(r.theta_max)) == pytest.approx(K0, rel=1e-9)
    D = float(rk.friction_work(r.theta_max))
    assert r.W_friction == pytest.approx(2 * D, rel=1e-9)
    assert r.n_impacts == 1
    K_back = r.impacts[0].K_before
    assert K_back == pytest.approx(K0 - 2 * D, rel=1e-9)
    assert K0 - K_back > 0.1 * K0  # a visible loss: 2D/K0 = 0.30 here
    assert abs(r.energy_residual) <= 1e-9 * K0
    assert r.reason == "at rest on the seat after the pulse"


def test_friction_dissipates_under_a_pulse(b1):
    """Sub-critical one-sine pulse: the body rocks out and back; the energy balance closes
    with the friction work accumulated along the path, which exceeds the friction work of
    the outward path alone."""
    rk = MechanismIRocker(b1, lam=4.0)
    r = simulate(rk, OneSinePulse(0.6 * 9.81, 0.5), duration=4.0)
    assert not r.overturned and r.theta_max > 0
    assert r.W_friction > float(rk.friction_work(r.theta_max)) * 1.5
    assert abs(r.energy_residual) <= 1e-8 * r.W_ground


def test_friction_holds_the_facade_where_it_stopped(b1):
    """At B1's critical λ the abutment friction exceeds gravity's restoring moment for
    θ < 0.026 rad (F(0) = 79.9 kN m > R(0) = 73.0 kN m) and again for θ > 0.080 rad: a
    sub-critical impulse of 0.6 v̄_g turns the façade to 0.019 rad, where it stops and stays,
    held by friction (0.9 v̄_g reaches 0.057 rad, where gravity wins: it falls back)."""
    rk = MechanismIRocker(b1)
    assert float(rk.friction(0.0)) > float(rk.restoring(0.0))
    v = 0.6 * rk.vg_impulse
    r = simulate(rk, RectangularPulse(v / 0.002, 0.002), duration=10.0, record=True)
    assert not r.overturned
    assert r.reason == "stuck by friction after the pulse"
    th = r.history["phi"][-1]
    assert 0 < th < rk.theta_m
    assert abs(float(rk.restoring(th))) <= float(rk.friction(th))
    assert r.n_impacts == 0
    assert math.isclose(r.theta_max, th, rel_tol=1e-12)
