"""Small-angle closed forms for a free-standing rigid block: the references the integrator is
checked against (Housner 1963; Makris & Roussos 2000; Zhang & Makris 2001).

A slender block (slenderness α, frequency parameter p = √(3g/(4R)), R the half-diagonal)
rocking on either toe obeys, linearised in α and θ,

    θ̈ = p² (θ − α sgn θ) + p² a_g(t)/g                                             (L)

(a_g > 0 pushes θ > 0; the papers write −a_g because their ground moves the other way). It
starts to rock when |a_g| > g α. For a pulse a_g = a_p sin(ω t + φ₀) on 0 <= t <= T
(one-sine: φ₀ = 0, ω = 2π/T; one-cosine: φ₀ = π/2; rectangular: ω = 0, φ₀ = π/2) every phase
on the side σ = sgn θ, started at (t_s, θ_s, θ̇_s), is

    θ(t) = σα + K sin(ωt + φ₀) + C₁ cosh p(t − t_s) + C₂ sinh p(t − t_s),
    K = −(a_p/g) / (1 + ω²/p²),  C₁ = θ_s − σα − K sin(ωt_s + φ₀),
    C₂ = (θ̇_s − Kω cos(ωt_s + φ₀)) / p,

with K = 0 after the pulse. At an impact (θ = 0) θ̇ → e θ̇ and σ changes. After the pulse
J = θ̇²/p² − (θ − σα)² is conserved between impacts, so the block overturns iff, moving
outwards, J >= 0 (or it is past ±α), and moving inwards below α, the next impact leaves
J' = e²(J + α²) − α² >= 0.

Closed forms that follow:
- rectangular pulse (Housner 1963): overturning iff a_p / (g α) >= 1 / (1 − e^{−p t_d});
- one-sine pulse, overturning without impact: with u = ω t_u (uplift at a_p sin u = g α) and
  ψ = ω/p, the block just overturns when (cos u − ψ sin u) e^{(2π − u)/ψ} = 1 (the
  end-of-pulse state on the separatrix, J = 0); then a_p / (g α) = 1 / sin u.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq

from ..errors import ParameterError, check_range
from ..params import G_STANDARD

__all__ = ["housner_rectangular", "one_sine_no_impact", "LinearOutcome",
           "linear_block_response", "linear_min_overturning"]

_PHASE = {"rectangular": math.pi / 2, "one-sine": 0.0, "one-cosine": math.pi / 2}


def housner_rectangular(alpha: float, p: float, duration: float, g: float = G_STANDARD) -> float:
    """Smallest rectangular-pulse acceleration that overturns a slender block (small angles):
    a_p = g α / (1 − e^{−p t_d}) [m/s²] (Housner 1963). Derivation: during the pulse
    θ − α + a_p/g = (a_p/g − α) cosh pt; after it the block reaches θ = α iff
    (θ − α) + θ̇/p >= 0 at t_d, i.e. (a_p/g − α) e^{p t_d} >= a_p/g."""
    alpha = check_range("alpha", alpha, 0.0, math.pi / 2, lo_open=True, unit="rad")
    p = check_range("p", p, 0.0, lo_open=True, unit="rad/s")
    duration = check_range("duration", duration, 0.0, lo_open=True, unit="s")
    return g * alpha / -math.expm1(-p * duration)


def one_sine_no_impact(alpha: float, p: float, T_p: float, g: float = G_STANDARD) -> float:
    """Smallest one-sine acceleration amplitude that overturns a slender block without impact
    (small angles, Zhang & Makris 2001): a_p = g α / sin u*, u* the root in
    (0, atan(p/ω)) of (cos u − ψ sin u) e^{(2π − u)/ψ} = 1, ψ = ω/p = 2π/(p T_p) (module
    docstring). Only meaningful where the block does not return to θ = 0 during the pulse
    at that amplitude (``linear_block_response`` with max_impacts=0 checks it)."""
    alpha = check_range("alpha", alpha, 0.0, math.pi / 2, lo_open=True, unit="rad")
    p = check_range("p", p, 0.0, lo_open=True, unit="rad/s")
    T_p = check_range("T_p", T_p, 0.0, lo_open=True, unit="s")
    psi = 2 * math.pi / (p * T_p)

    def f(u):  # written as log to stay finite for short pulses (large ψ) and long ones
        c = math.cos(u) - psi * math.sin(u)
        return math.log(c) + (2 * math.pi - u) / psi if c > 0 else -math.inf

    u_hi = math.atan(1 / psi)
    u = brentq(lambda x: f(x) if f(x) > -1e300 else -1e300, 1e-15, u_hi * (1 - 1e-15),
               xtol=1e-15, rtol=1e-15)
    return g * alpha / math.sin(u)


@dataclass(frozen=True)
class LinearOutcome:
    """Outcome of the linearised rocking (L): overturned, n_impacts, the impact times [s],
    margin (J/α² at the decision, > 0 overturned), reason."""

    overturned: bool
    n_impacts: int
    t_impacts: tuple[float, ...]
    margin: float
    reason: str


def linear_block_response(alpha: float, p: float, kind: str, a_p: float, T_p: float,
                          e: float, g: float = G_STANDARD, polarity: int = 1,
                          max_impacts: int | None = None, n_grid: int = 4000) -> LinearOutcome:
    """Piecewise closed-form response of (L) to a rectangular (T_p = duration), one-sine or
    one-cosine pulse of amplitude a_p [m/s²]; e: coefficient of restitution. Impact times are
    the first sign change of the closed-form θ(t) on n_grid samples per phase, refined by
    brentq. max_impacts: stop as not overturned after that many impacts."""
    if kind not in _PHASE:
        raise ParameterError(f"kind = {kind!r} is out of range: allowed {', '.join(_PHASE)}")
    alpha = check_range("alpha", alpha, 0.0, math.pi / 2, lo_open=True, unit="rad")
    a_p = polarity * check_range("a_p", a_p, 0.0, lo_open=True, unit="m/s^2")
    e = check_range("e", e, 0.0, 1.0)
    w = 0.0 if kind == "rectangular" else 2 * math.pi / T_p
    ph0 = _PHASE[kind]
    K = -(a_p / g) / (1 + (w / p) ** 2)

    def ag(t):
        return a_p * np.sin(w * np.asarray(t) + ph0)

    def phase(ts, th, thd, sig, k):
        c1 = th - sig * alpha - k * math.sin(w * ts + ph0)
        c2 = (thd - k * w * math.cos(w * ts + ph0)) / p

        def theta(t):
            x = p * (np.asarray(t) - ts)
            return sig * alpha + k * np.sin(w * np.asarray(t) + ph0) + c1 * np.cosh(x) \
                + c2 * np.sinh(x)

        def theta_dot(t):
            x = p * (t - ts)
            return k * w * math.cos(w * t + ph0) + p * (c1 * math.sinh(x) + c2 * math.cosh(x))
        return theta, theta_dot

    def first_root(f, t0, t1):
        """First return to θ = 0 after t0 (where θ = 0): f = σθ > 0 just after t0."""
        grid = np.linspace(t0, t1, n_grid)
        val = f(grid)
        bad = np.flatnonzero(val[1:] <= 0) + 1
        if bad.size == 0:
            return None
        k = int(bad[0])
        lo = grid[k - 1]
        if k == 1:  # an excursion shorter than one sample: bracket it away from t0
            for frac in (1e-12, 1e-9, 1e-6, 1e-3):
                lo = t0 + frac * (grid[1] - t0)
                if float(f(lo)) > 0:
                    break
            else:
                return t0  # below resolution: the block is back at once
        return brentq(lambda t: float(f(t)), lo, grid[k], xtol=1e-14 * T_p, rtol=1e-15)

    t, th, thd, sig = 0.0, 0.0, 0.0, 0
    impacts = []
    while True:
        if sig == 0:  # at rest: next uplift during the pulse
            grid = np.linspace(t, T_p, n_grid)
            hit = np.flatnonzero(np.abs(ag(grid)) > g * alpha)
            if hit.size == 0:
                return LinearOutcome(False, len(impacts), tuple(impacts), -1.0,
                                     "at rest after the pulse")
            k = int(hit[0])
            if k > 0:
                t = brentq(lambda x: abs(float(ag(x))) - g * alpha, grid[k - 1], grid[k],
                           xtol=1e-15 * T_p, rtol=1e-15)
            else:
                t = grid[0]
            sig = 1 if float(ag(t)) > 0 else -1
            th, thd = 0.0, 0.0
        theta, theta_dot = phase(t, th, thd, sig, K)
        t_imp = first_root(lambda x: sig * theta(x), t, T_p)
        if t_imp is None:  # the pulse ends on this side: decide by J
            th, thd = float(theta(T_p)), theta_dot(T_p)
            break
        v = theta_dot(t_imp) if t_imp > t else 0.0
        impacts.append(t_imp)
        if max_impacts is not None and len(impacts) > max_impacts:
            return LinearOutcome(False, len(impacts), tuple(impacts), -1.0, "impact limit")
        t, th, thd, sig = t_imp, 0.0, e * v, -sig
        if abs(thd) < 1e-12 * p * alpha:
            sig = 0
    # after the pulse: the linear invariant on side sig
    psi_ = th - sig * alpha
    J = (thd / p) ** 2 - psi_ ** 2
    outward = sig * thd >= 0
    if outward and (sig * th >= alpha or J >= 0):
        return LinearOutcome(True, len(impacts), tuple(impacts), max(J / alpha ** 2, 1e-12),
                             "overturns after the pulse")
    if not outward and sig * th > alpha and J <= 0:
        return LinearOutcome(True, len(impacts), tuple(impacts), 1e-12,
                             "turns back beyond alpha after the pulse")
    if outward:
        return LinearOutcome(False, len(impacts), tuple(impacts), J / alpha ** 2,
                             "returns after the pulse")
    # moving inwards: next impact, then J' on the other side
    if max_impacts is not None and len(impacts) + 1 > max_impacts:
        return LinearOutcome(False, len(impacts) + 1, tuple(impacts), -1.0, "impact limit")
    Jp = e ** 2 * (J + alpha ** 2) - alpha ** 2
    return LinearOutcome(Jp >= 0, len(impacts) + 1, tuple(impacts), Jp / alpha ** 2,
                         "after one more impact past the pulse")


def linear_min_overturning(alpha: float, p: float, kind: str, T_p: float, e: float,
                           g: float = G_STANDARD, scan_ratio: float = 1.01,
                           rtol: float = 1e-10, max_impacts: int | None = None) -> float:
    """Smallest a_p [m/s²] overturning the linearised block (L): scan up from g α by
    ``scan_ratio``, then brentq on the margin within the first overturning step."""
    a = g * alpha * (1 + 1e-12)

    def margin(x):
        return linear_block_response(alpha, p, kind, x, T_p, e, g,
                                     max_impacts=max_impacts).margin

    for _ in range(5000):
        if margin(a * scan_ratio) > 0:
            return brentq(margin, a, a * scan_ratio, xtol=1e-14 * a, rtol=rtol)
        a *= scan_ratio
    raise ParameterError(f"no overturning amplitude below {a:.4g} m/s^2")
