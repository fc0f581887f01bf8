"""The fast closed-form numerics (Newton root of θ_m's quartic, golden section reusing its
interior point) against slow independent references on random walls: θ_m from W's
derivative (eq. 12 differentiated by hand, roots by scipy's brentq at xtol 1e-15), the
critical λ by scipy's bounded minimize_scalar at xatol 1e-13 on a fine-grid bracket.

The minimum v̄_g(λ*) is asserted to 1e-12. λ* itself is fixed by v only to about √(ε v/v'')
~ 1e-8 relative (v is flat at its minimum: a relative change δ in λ changes v by ~δ²), so
for λ* the test asserts that v there is the reference minimum to 1e-13 and λ* within 1e-6.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.optimize import brentq, minimize_scalar

from homlimit.closed_form.mechanisms import (
    _largest_root_I,
    _quartic_I,
    critical_I,
    critical_II,
    static_critical_II,
    theta_m_I,
    vnorm_II,
)


def _random_walls(n, seed, beta_max=1.2):
    """ρ, α, β and λ (or λ_max) of n random walls."""
    rng = np.random.default_rng(seed)
    return (rng.uniform(2.0, 40.0, n), np.sqrt(rng.uniform(0.05, 2.0, n)),
            rng.uniform(0.05, beta_max, n), rng.uniform(1.0, 40.0, n))


# ------------------------------------------------------------------- θ_m, written from eq. 12
def _w24(t, lam, rho, a2, beta):
    """24 W/(g γ s b³), eq. 12 corrected (right branch) and eq. 9's left branch."""
    g = 12 * rho * lam * t - 6 * rho * lam ** 2 * t ** 2
    if lam * t < beta:
        return g + a2 * lam ** 3 * t * (4 * beta - lam * t) / beta
    return g + 6 * a2 * beta * lam ** 2 - 4 * a2 * beta ** 2 * lam / t + a2 * beta ** 3 / t ** 2


def _dw24(t, lam, rho, a2, beta):
    """d(24 W)/dθ on either branch (θ scalar or array)."""
    g = 12 * rho * lam - 12 * rho * lam ** 2 * t
    left = g + a2 * lam ** 3 * (4 * beta - 2 * lam * t) / beta
    right = g + 4 * a2 * beta ** 2 * lam / t ** 2 - 2 * a2 * beta ** 3 / t ** 3
    return np.where(lam * t < beta, left, right)


def _theta_m_ref(lam, rho, alpha, beta):
    """The largest W over its stationary points (brentq on W') and the branch point β/λ."""
    a2 = alpha ** 2
    tc = beta / lam
    cand = [tc]
    for lo_, hi_ in ((1e-9 * tc, tc * (1 - 1e-15)), (tc, 10.0 / lam + 10.0)):
        t = np.geomspace(lo_, hi_, 3000)
        d = _dw24(t, lam, rho, a2, beta)
        for k in np.flatnonzero(np.sign(d[:-1]) * np.sign(d[1:]) < 0):
            cand.append(brentq(lambda x: float(_dw24(x, lam, rho, a2, beta)), t[k], t[k + 1],
                               xtol=1e-15, rtol=1e-15))
    return max(cand, key=lambda x: _w24(x, lam, rho, a2, beta))


def test_theta_m_is_the_maximiser_of_eq12_found_by_brentq():
    rho, alpha, beta, lam = _random_walls(80, 1, beta_max=2.5)
    got = theta_m_I(lam, rho, alpha, beta)
    ref = np.array([_theta_m_ref(*x) for x in zip(lam, rho, alpha, beta)])
    assert np.max(np.abs(got / ref - 1)) < 1e-12
    # both kinds of maximiser occur: a root of the quartic (right branch, θ > β/λ) and the
    # stationary point of the left branch (large β)
    assert np.sum(got > beta / lam) > 10 and np.sum(got < beta / lam) > 10


def test_newton_gives_the_largest_real_root_of_the_quartic():
    rho, alpha, beta, lam = _random_walls(400, 2)
    p3, p1, p0 = _quartic_I(lam, rho, alpha ** 2, beta)
    got = _largest_root_I(p3, p1, p0)
    for x, c3, c1, c0 in zip(got, p3, p1, p0):
        r = np.roots([1.0, c3, 0.0, c1, c0])
        real = r.real[np.abs(r.imag) <= 1e-9 * np.abs(r)]
        if real.size == 0:
            assert np.isnan(x)
        else:
            assert x == pytest.approx(real.max(), rel=1e-12)
    assert np.isfinite(got).mean() > 0.5
    # the companion-matrix fallback (a Newton iteration cut short) gives the same roots
    short = _largest_root_I(p3, p1, p0, max_iter=2)
    np.testing.assert_allclose(short, got, rtol=1e-12)


# ------------------------------------------------------------------- the critical λ
def _min_ref(v, lam_max, lam_min=0.5):
    """min of v over [lam_min, lam_max]: a 500-point grid, then bounded Brent at 1e-13."""
    grid = np.geomspace(lam_min, lam_max, 500)
    vals = np.array([v(x) for x in grid])
    k = int(np.argmin(vals))
    lo, hi = grid[max(k - 1, 0)], grid[min(k + 1, grid.size - 1)]
    res = minimize_scalar(v, bounds=(lo, hi), method="bounded",
                          options={"xatol": 1e-13 * hi})
    return (res.x, res.fun) if res.fun < vals[k] else (grid[k], vals[k])


def _check_minimum(lam, v, fun, lam_max):
    lam_ref, v_ref = _min_ref(fun, lam_max)
    assert v == pytest.approx(v_ref, rel=1e-12)
    assert fun(lam) <= v_ref * (1 + 1e-13)         # as low as the reference's minimum
    assert lam == pytest.approx(lam_ref, rel=1e-6)  # λ* as far as v fixes it


@pytest.mark.parametrize("k", range(12))
def test_critical_I_is_the_minimum_found_by_brent(k):
    rho, alpha, beta, lam_max = (x[k] for x in _random_walls(12, 3))
    lam, v = critical_I(rho, alpha, beta, lam_max)

    def fun(x):
        th = _theta_m_ref(x, rho, alpha, beta)
        w24 = _w24(th, x, rho, alpha ** 2, beta)
        return np.sqrt(w24 * (x ** 2 + 1) / (9 * rho * x ** 3))   # eq. 7 as vnorm_I

    _check_minimum(float(lam), float(v), fun, lam_max)


def test_critical_II_and_its_static_check_are_the_minima_found_by_brent():
    from homlimit.closed_form.mechanisms import multiplier_II

    rho, t, _, lam_max = _random_walls(25, 4)
    lam, v = critical_II(rho, t, lam_max)
    lam_s, a_g = static_critical_II(rho, t, lam_max)
    for j in range(rho.size):
        _check_minimum(lam[j], v[j], lambda x: float(vnorm_II(x, rho[j], t[j])), lam_max[j])
        _check_minimum(lam_s[j], a_g[j], lambda x: float(multiplier_II(x, rho[j], t[j])),
                       lam_max[j])
