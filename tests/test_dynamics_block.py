"""Free-standing rigid block (no transversal wall): the nonlinear time history against the
small-angle closed forms of Housner (1963), Makris & Roussos (2000) and Zhang & Makris (2001),
derived in ``homlimit.dynamics.housner`` (the linearised rocking θ̈ = p²(θ − α sgn θ) + p² a_g/g
solved piecewise in closed form). Slender block α = 0.1 (b/h = tan α, h = 5 m), Housner's
e = 1 − 1.5 sin²α = 0.98505, p = 1.7112 rad/s.

Tabulated points (a_p/(g α), small-angle closed form; nonlinear within 1 %):
- rectangular, p t_d = 0.1, 0.5, 1, 2, 5: 10.5083, 2.54149, 1.58198, 1.15652, 1.00678
  (Housner: 1/(1 − e^{−p t_d})); measured deviations +0.32 ... +0.44 %;
- one-sine, ω_p/p = 1, 2, 3, 4, without impact (transcendental equation, brentq):
  1.41832, 2.34990, 3.63115, 5.23896; deviations +0.33 ... +0.59 %;
- one-sine minimum (with impact allowed): 1.09574 (3 impacts), 1.21541, 1.37182, 1.66459
  (1 impact); deviations +0.33 ... +0.40 %;
- one-cosine minimum at ω_p/p = 2, 3: 1.25169, 1.76864 (+0.34, +0.43 %), without impact at
  ω_p/p = 1, 2: 2.00374, 5.22583 (+0.33, +0.20 %).
The deviation is the linearisation error, O(α²) (≈ α²/3 = tan α/α − 1 at low ω_p/p); at
α = 0.05 it is four times smaller.
"""

import math

import numpy as np
import pytest

from homlimit.dynamics import (
    OneCosinePulse,
    OneSinePulse,
    RectangularPulse,
    critical_pulse,
    free_block,
    simulate,
)
from homlimit.dynamics.housner import (
    housner_rectangular,
    linear_block_response,
    linear_min_overturning,
    one_sine_no_impact,
)
from homlimit.dynamics.integrate import _potential

G = 9.81
ALPHA = 0.1
BLOCK = free_block(5.0 * math.tan(ALPHA), 5.0)
P, E = BLOCK.p, BLOCK.restitution


def test_block_constants_by_hand():
    R = 0.5 * math.hypot(5.0 * math.tan(ALPHA), 5.0)
    assert P == pytest.approx(math.sqrt(3 * G / (4 * R)), rel=1e-12)
    assert E == pytest.approx(1 - 1.5 * math.sin(ALPHA) ** 2, rel=1e-12)
    assert BLOCK.theta_m == pytest.approx(ALPHA, rel=1e-12)
    assert BLOCK.a_uplift == pytest.approx(G * math.tan(ALPHA), rel=1e-12)


@pytest.mark.parametrize("p_td, ref", [(0.1, 10.508332), (0.5, 2.541494), (1.0, 1.581977),
                                       (2.0, 1.156518), (5.0, 1.006784)])
@pytest.mark.slow
def test_housner_rectangular_pulse(p_td, ref):
    td = p_td / P
    closed = housner_rectangular(ALPHA, P, td)
    assert closed / (G * ALPHA) == pytest.approx(ref, rel=1e-6)
    assert closed / (G * ALPHA) == pytest.approx(1 / (1 - math.exp(-p_td)), rel=1e-12)
    # the piecewise closed form finds the same threshold independently
    lin = linear_min_overturning(ALPHA, P, "rectangular", td, E)
    assert lin == pytest.approx(closed, rel=1e-8)
    nl = critical_pulse(BLOCK, RectangularPulse(1.0, td), rtol=1e-8)
    assert nl.pga == pytest.approx(closed, rel=0.01)
    assert nl.response.n_impacts == 0


@pytest.mark.parametrize("wp, ref", [(1.0, 1.41832), (2.0, 2.34990), (3.0, 3.63115),
                                     (4.0, 5.23896)])
@pytest.mark.slow
def test_one_sine_overturning_without_impact(wp, ref):
    T = 2 * math.pi / (wp * P)
    closed = one_sine_no_impact(ALPHA, P, T)
    assert closed / (G * ALPHA) == pytest.approx(ref, rel=1e-5)
    # the transcendental equation agrees with the piecewise solution forbidden to impact,
    # and at that amplitude the block indeed stays on one side during the pulse
    lin = linear_min_overturning(ALPHA, P, "one-sine", T, E, max_impacts=0)
    assert lin == pytest.approx(closed, rel=1e-7)
    out = linear_block_response(ALPHA, P, "one-sine", closed * (1 + 1e-6), T, E)
    assert out.overturned and out.n_impacts == 0
    nl = critical_pulse(BLOCK, OneSinePulse(1.0, T), rtol=1e-7, max_impacts=0)
    assert nl.pga == pytest.approx(closed, rel=0.01)
    assert nl.response.n_impacts == 0


@pytest.mark.parametrize("wp, ref, impacts", [(1.0, 1.09574, 3), (2.0, 1.21541, 1),
                                              (3.0, 1.37182, 1), (4.0, 1.66459, 1)])
@pytest.mark.slow
def test_one_sine_minimum_overturning_with_impact(wp, ref, impacts):
    T = 2 * math.pi / (wp * P)
    lin = linear_min_overturning(ALPHA, P, "one-sine", T, E)
    assert lin / (G * ALPHA) == pytest.approx(ref, rel=1e-5)
    assert lin < one_sine_no_impact(ALPHA, P, T)  # overturning after impact needs less
    nl = critical_pulse(BLOCK, OneSinePulse(1.0, T), rtol=1e-7)
    assert nl.pga == pytest.approx(lin, rel=0.01)
    assert nl.response.n_impacts == impacts
    assert linear_block_response(ALPHA, P, "one-sine", lin * (1 + 1e-6), T, E).n_impacts \
        == impacts


@pytest.mark.parametrize("wp, ref, no_impact", [(2.0, 1.25169, False), (3.0, 1.76864, False),
                                                (1.0, 2.00374, True), (2.0, 5.22583, True)])
@pytest.mark.slow
def test_one_cosine_minimum_overturning(wp, ref, no_impact):
    T = 2 * math.pi / (wp * P)
    mi = 0 if no_impact else None
    lin = linear_min_overturning(ALPHA, P, "one-cosine", T, E, max_impacts=mi)
    assert lin / (G * ALPHA) == pytest.approx(ref, rel=1e-5)
    nl = critical_pulse(BLOCK, OneCosinePulse(1.0, T), rtol=1e-7, max_impacts=mi)
    assert nl.pga == pytest.approx(lin, rel=0.01)


@pytest.mark.slow
def test_linearisation_error_is_second_order_in_alpha():
    """Halving α divides the nonlinear/small-angle deviation by about four."""
    devs = []
    for alpha in (0.1, 0.05):
        blk = free_block(5.0 * math.tan(alpha), 5.0)
        T = 2 * math.pi / (2.0 * blk.p)
        lin = linear_min_overturning(alpha, blk.p, "one-sine", T, blk.restitution)
        nl = critical_pulse(blk, OneSinePulse(1.0, T), rtol=1e-8).pga
        devs.append(nl / lin - 1)
    assert devs[0] / devs[1] == pytest.approx(4.0, rel=0.1)


def test_energy_conserved_between_impacts_and_restitution_at_each_impact():
    """Free rocking from θ0 = 0.9 α: ½ I θ̇² + V constant on every phase to 1e-8 (measured
    ~1e-13), each impact multiplies θ̇ by Housner's e exactly, and the energy lost is the
    kinetic energy's (1 − e²) share."""
    r = simulate(BLOCK, None, theta0=0.9 * ALPHA, duration=30.0, record=True)
    assert r.n_impacts >= 10
    H = r.history
    En = 0.5 * BLOCK.inertia * H["phi_dot"] ** 2 + np.array([_potential(BLOCK, x)
                                                              for x in H["phi"]])
    for k in np.unique(H["phase"]):
        assert np.ptp(En[H["phase"] == k]) <= 1e-8 * r.E0
    for im in r.impacts:
        assert im.theta_dot_after / im.theta_dot_before == pytest.approx(E, rel=1e-12)
        assert im.K_after == pytest.approx(E ** 2 * im.K_before, rel=1e-12)
        # the sign of θ̇ is kept: the block rocks on to the other toe
        assert np.sign(im.theta_dot_after) == np.sign(im.theta_dot_before)
    assert abs(r.energy_residual) <= 1e-9 * r.E0
    assert not r.overturned


@pytest.mark.slow
def test_energy_balance_under_a_pulse():
    """E_final = E0 + work of the ground − impact losses, through impacts under a pulse."""
    T = 2 * math.pi / (2.0 * P)
    r = simulate(BLOCK, OneSinePulse(1.15 * G * ALPHA, T), duration=20.0)
    assert r.n_impacts >= 1
    assert abs(r.energy_residual) <= 1e-8 * max(r.W_ground, 1.0)
