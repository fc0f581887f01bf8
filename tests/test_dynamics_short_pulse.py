"""Short-pulse limit: the rectangular-pulse threshold a_g·Δt of the time history tends to eq. 7's
v̄_g as Δt → 0, at first order, with the coefficient derived by hand.

Hand derivation (one rocker, eq. 1, from rest, pulse a_g = A on 0 <= t <= Δt): to first order
in Δt, I φ̇(Δt) = Π₀ v − R₀ Δt + Π'₀ Π₀ v² Δt / (6 I) and φ(Δt) = Π₀ v Δt / (2 I), v = A Δt
(R₀ = R(0) + F(0), Π₀ = Π(0), Π'₀ = dΠ/dφ at 0). After the pulse the body overturns iff
½ I φ̇² + W(φ) >= W_m = ½ (Π₀ v̄)² / I, with W(φ) = R₀ φ + O(φ²). Hence

    v / v̄ − 1 = c₁ Δt + O(Δt²),   c₁ = a_up / (2 v̄) − Π'₀ v̄ / (6 I),   a_up = R₀ / Π₀.

For a slender rigid body c₁ ≈ p/2 (mechanics.md); mechanism I's abutment friction raises a_up.
The durations are p·Δt = 0.0025 ... 0.04; thresholds to rtol = 1e-10. The scan ratio 1.2 is
enough here: for a rectangular pulse the overturning amplitudes form one interval.
"""

import math

import numpy as np
import pytest

from homlimit.closed_form.mechanisms import mechanism_I, mechanism_II, work_I
from homlimit.dynamics import (
    GeneralisedRocker,
    MechanismIRocker,
    RectangularPulse,
    RigidRocker,
    critical_pulse,
)
from homlimit.impulse import collapse_velocity
from homlimit.impulse.body import RigidBody
from homlimit.mechanism.fe_impulse import GeneralisedImpulse
from homlimit.params import Case

P_DT = np.array([0.0025, 0.005, 0.01, 0.02, 0.04])


def fe_like_body(case: Case, h: float = 2.3, T: float | None = None) -> RigidBody:
    """The body an FE mechanism of B1 identifies (docs/fe-impulse.md): a hinge on the façade's
    outer face at z0 = H − h, a straight crack x = T (z − z0) (T = √(cf/a)) through façade
    (density ρ γ s) and transversal wall (γ s); three triangles, integrated exactly."""
    w = case.wall
    T = case.alpha if T is None else T
    z0 = w.H - h
    pts = np.array([[0, z0], [w.b, z0 + w.b / T], [w.b, w.H], [0, w.H], [T * h, w.H]])
    tri = np.array([[0, 1, 2], [0, 2, 3], [1, 4, 2]])
    dens = np.array([case.rho * w.gamma * w.s] * 2 + [w.gamma * w.s])
    return RigidBody.from_triangles(pts, tri, dens, O=(0.0, z0))


def convergence(rocker, v_ref):
    dts = P_DT / rocker.p
    ex = np.array([critical_pulse(rocker, RectangularPulse(1.0, dt), rtol=1e-10,
                                  scan_ratio=1.2).pgv / v_ref - 1 for dt in dts])
    slope = np.polyfit(np.log(dts), np.log(ex), 1)[0]
    c1 = (4 * ex[0] - ex[1]) / (2 * dts[0])  # Richardson: removes the O(Δt²) term
    return dts, ex, slope, c1


def hand_c1(rocker, v_ref, dPi):
    return rocker.a_uplift / (2 * v_ref) - dPi * v_ref / (6 * rocker.inertia)


@pytest.mark.slow
def test_mechanism_I_converges_to_eq7_at_first_order(b1):
    """Linearised gravity (eq. 10) and the abutment friction of eq. 9: the limit is the
    closed form mechanism_I(case).vg; Π = m z_G is constant (Π'₀ = 0)."""
    rk = MechanismIRocker(b1)
    v7 = mechanism_I(b1).vg
    dts, ex, slope, c1 = convergence(rk, v7)
    assert np.all(ex > 0)
    assert ex[0] < 0.005  # within 0.5 % at the shortest duration (measured 0.18 %)
    assert slope == pytest.approx(1.0, abs=0.02)  # measured 1.003
    assert c1 == pytest.approx(hand_c1(rk, v7, 0.0), rel=1e-4)  # measured 1.2642 1/s


@pytest.mark.slow
def test_mechanism_I_exact_gravity_converges_to_its_own_eq7(b1):
    """Exact gravity: the limit is eq. 7 with the peak of (exact gravity work + eq. 10's
    friction term), found here by brute force on a grid (independent of the rocker's root)."""
    rk = MechanismIRocker(b1, gravity="exact")
    res = mechanism_I(b1)
    w = b1.wall
    th = np.linspace(1e-4, 0.3, 300001)
    lin_grav = res.body.m * w.g * (res.body.x_G * th - 0.5 * res.body.z_G * th ** 2)
    friction = work_I(th, res.lam, b1.rho, b1.alpha, b1.beta) * w.g * w.gamma * w.s * w.b ** 3 \
        - lin_grav
    bd = res.body
    exact = bd.m * w.g * (bd.x_G * np.sin(th) + bd.z_G * (np.cos(th) - 1)) + friction
    v_ref = collapse_velocity(bd, W=float(exact.max()))
    assert rk.vg_impulse == pytest.approx(v_ref, rel=1e-9)
    dts, ex, slope, c1 = convergence(rk, v_ref)
    assert ex[0] < 0.005
    assert slope == pytest.approx(1.0, abs=0.02)
    assert c1 == pytest.approx(hand_c1(rk, v_ref, bd.m * bd.x_G), rel=1e-4)


@pytest.mark.slow
def test_mechanism_II_converges_to_eq19(b1):
    rk = RigidRocker(mechanism_II(b1).body, name="II")
    v19 = mechanism_II(b1).vg
    dts, ex, slope, c1 = convergence(rk, v19)
    assert ex[0] < 0.005  # measured 0.12 %
    assert slope == pytest.approx(1.0, abs=0.02)
    bd = rk.body
    assert c1 == pytest.approx(hand_c1(rk, v19, bd.m * bd.x_G), rel=1e-4)  # 1.0155 1/s
    assert c1 == pytest.approx(rk.p / 2, rel=0.05)  # mechanics.md: ≈ p Δt / 2 (p/2 = 1.040)


@pytest.mark.slow
def test_fe_like_body_of_B1_converges_to_eq7(b1):
    """A RigidBody from triangles (the lead replaces it with the FE body of B1 later)."""
    body = fe_like_body(b1)
    rk = RigidRocker(body, name="FE")
    v7 = collapse_velocity(body)
    dts, ex, slope, c1 = convergence(rk, v7)
    assert ex[0] < 0.005  # measured 0.12 %
    assert slope == pytest.approx(1.0, abs=0.02)
    assert c1 == pytest.approx(hand_c1(rk, v7, body.m * body.x_G), rel=1e-4)


@pytest.mark.slow
def test_generalised_one_dof_converges_to_its_vg(b1):
    """The one-DOF shape (fe_impulse): M > I_O, Π₀ = Pi, a linear rest lifting L q.
    Reference: v̄_g = √(2 W(q_m) M) / Pi, the formula of fe_impulse.generalised_impulse,
    with W(q) = m g (x_G sin q + z_G cos q − z_G) + L q written out here and its peak found
    by a bounded scalar search (the lift delays it past the block's tipping angle)."""
    from scipy.optimize import minimize_scalar

    body = fe_like_body(b1)
    g = b1.wall.g
    q_tip = math.atan2(body.x_G, body.z_G)
    W_b = body.m * g * (body.r_G - body.z_G)
    L = 0.12 * W_b / q_tip
    M, Pi = 1.08 * body.I_O, 1.05 * body.m * body.z_G

    def W(q):
        return body.m * g * (body.x_G * math.sin(q) + body.z_G * (math.cos(q) - 1)) + L * q

    r = minimize_scalar(lambda q: -W(q), bounds=(0.0, math.pi / 2), method="bounded",
                        options={"xatol": 1e-12})
    q_m, W_m = float(r.x), -float(r.fun)
    assert q_m > q_tip and W_m > W_b + q_tip * L
    vg = math.sqrt(2 * W_m * M) / Pi
    gi = GeneralisedImpulse(M, Pi, W_m, q_m, vg, body, L, 0.08, q_m * L / W_m)
    rk = GeneralisedRocker.from_impulse(gi, g=g)
    assert rk.theta_m == pytest.approx(q_m, abs=1e-6)
    assert rk.vg_impulse == pytest.approx(vg, rel=1e-9)
    assert rk.W_m == pytest.approx(W_m, rel=1e-12)
    dts, ex, slope, c1 = convergence(rk, vg)
    assert ex[0] < 0.005
    assert slope == pytest.approx(1.0, abs=0.02)
    assert c1 == pytest.approx(hand_c1(rk, vg, body.m * body.x_G), rel=1e-4)
