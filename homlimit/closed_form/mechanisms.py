"""Closed-form collapse mechanisms I and II of the paper, vectorised over (λ, ρ, α, β).

Normalised forms (eq. 11: λ = h/b, ρ = l/s, α = √(cf/a), β = c/b) work on numpy arrays that
broadcast together, so Figure 2's family of curves is one call. The object forms
``mechanism_I(case)`` and ``mechanism_II(case)`` return a MechanismResult in SI units.

Mechanism I (detachment): the façade strip of height h rotates about its outer toe; the
restoring work is eq. 10 (linearised gravity + friction at the abutment, both branches of eq. 9).
Normalised by g γ s b³ and written as w(θ)/24 it reads, for θ >= β/λ (u(h) >= c),

    24 W / (g γ s b³) = 12ρλθ − 6ρλ²θ² + 6α²βλ² − 4α²β²λ/θ + α²β³/θ²          (eq. 12, corrected)

(the printed eq. 12 has a factor 24 instead of 1/24 and β² instead of β³; eq. 13 has a wrong
sign: see analytic/NOTES.md). θ_m is the exact maximiser of W; eq. 14 is kept as an
approximation for comparison.

Mechanism II (diagonal crack): the façade strip and a wedge of the transversal wall cut by a
straight crack of slope tan ψ from the vertical (default √(cf/a), eq. 16) rotate about the
façade's outer toe; eqs 17, 20 give G and i, eq. 19 the collapse velocity. The wedge must stay
inside the transversal wall: λ tan ψ <= L/b.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..check.ntc import StaticMechanism
from ..errors import ParameterError, check_range
from ..impulse import RigidBody, hinge_impulse_ratio
from ..params import Case

__all__ = [
    "work_I",
    "theta_m_I",
    "theta_m_I_eq14",
    "vnorm_I",
    "critical_I",
    "geometry_II",
    "vnorm_II",
    "critical_II",
    "lam_max_II",
    "MechanismResult",
    "mechanism_I",
    "mechanism_II",
    "mechanisms_I",
    "mechanisms_II",
    "wall_arrays",
    "multiplier_I",
    "multiplier_II",
    "static_critical_I",
    "static_critical_II",
    "minimise",
]


def _bcast(*xs):
    arrs = [np.asarray(x, dtype=float) for x in xs]
    shape = arrs[0].shape
    if all(a.shape == shape for a in arrs):   # one wall's scalars: nothing to broadcast
        return arrs
    return np.broadcast_arrays(*arrs)


# --------------------------------------------------------------------------- mechanism I
def work_I(theta, lam, rho, alpha, beta):
    """Restoring work of mechanism I, W(θ) / (g γ s b³) (eqs 9–10, normalised as eq. 12).

    Both branches of eq. 9: θ < β/λ (every abutment joint still overlapping, u(h) < c) and
    θ >= β/λ. Gravity enters linearised, as in eq. 10.
    """
    theta, lam, rho, alpha, beta = _bcast(theta, lam, rho, alpha, beta)
    a2 = alpha ** 2
    gravity = 12 * rho * lam * theta - 6 * rho * lam ** 2 * theta ** 2
    with np.errstate(divide="ignore", invalid="ignore"):
        right = 6 * a2 * beta * lam ** 2 - 4 * a2 * beta ** 2 * lam / theta \
            + a2 * beta ** 3 / theta ** 2
        left = a2 * lam ** 3 * theta * (4 * beta - lam * theta) / beta
    friction = np.where(lam * theta < beta, left, right)
    return (gravity + friction) / 24.0


def _quartic_I(lam, rho, a2, beta):
    """Coefficients p3, p1, p0 of θ_m's quartic θ⁴ + p3 θ³ + p1 θ + p0 = 0 (corrected eq. 13)."""
    return -1.0 / lam, -a2 * beta ** 2 / (3 * rho * lam), a2 * beta ** 3 / (6 * rho * lam ** 2)


def _largest_root_I(p3, p1, p0, max_iter=100):
    """Largest real root of θ⁴ + p3 θ³ + p1 θ + p0 (p3, p1 < 0 < p0), NaN if there is none.

    q' = 4θ³ + 3p3θ² + p1 is negative on (0, −p3/2] and increasing after, so q falls then rises
    on θ > 0: it has no positive root or two, and on [largest root, ∞) it is convex and
    increasing. Newton from a point above every root therefore decreases monotonically onto
    the largest one; θ0 = −p3 + min(|p1|/p3², ∛|p1|) is such a point (there θ0²(θ0 + p3) >=
    −p1, so q >= p0 > 0). An element stops when its step no longer decreases θ: converged, or
    NaN if q' <= 0 there (it went past q's minimum: no root). Each element follows its own
    iteration, so an array gives every element the bits it gets alone. An element still
    moving after ``max_iter`` steps (a near-double root) takes the largest real eigenvalue of
    its companion matrix.
    """
    x = -p3 + np.minimum(-p1 / p3 ** 2, np.cbrt(-p1))
    idx = np.arange(x.size)
    for _ in range(max_iter):
        xi, a3, a1, a0 = x[idx], p3[idx], p1[idx], p0[idx]
        q = ((xi + a3) * xi * xi + a1) * xi + a0
        dq = (4 * xi + 3 * a3) * xi * xi + a1
        with np.errstate(divide="ignore", invalid="ignore"):
            xn = xi - q / dq
        moving = (dq > 0) & (xn < xi)
        x[idx[~moving]] = np.where(dq[~moving] > 0, xi[~moving], np.nan)
        x[idx[moving]] = xn[moving]
        idx = idx[moving]
        if idx.size == 0:
            return x
    comp = np.zeros((idx.size, 4, 4))
    comp[:, 0, :] = -np.stack([p3[idx], np.zeros(idx.size), p1[idx], p0[idx]], axis=1)
    comp[:, 1, 0] = comp[:, 2, 1] = comp[:, 3, 2] = 1.0
    roots = np.linalg.eigvals(comp)
    real = np.abs(roots.imag) <= 1e-9 * np.maximum(1.0, np.abs(roots.real))
    x[idx] = np.max(np.where(real, roots.real, -np.inf), axis=1)
    x[idx] = np.where(x[idx] > 0, x[idx], np.nan)
    return x


def theta_m_I(lam, rho, alpha, beta):
    """Exact maximiser θ_m of W(θ) for mechanism I (corrected eq. 13, both branches).

    On the right branch (θ >= β/λ) W'(θ) has the sign of −q(θ), q = θ⁴ − θ³/λ − α²β²θ/(3ρλ)
    + α²β³/(6ρλ²): W rises where q < 0, so its local maxima there are the largest real root
    of q (``_largest_root_I``, Newton) if it is >= β/λ, and the branch point θ = β/λ. With the
    stationary point of the left branch (θ < β/λ) these are the candidates; the one of largest
    W wins.
    """
    lam, rho, alpha, beta = _bcast(lam, rho, alpha, beta)
    shape = lam.shape
    lam, rho, alpha, beta = (x.ravel() for x in (lam, rho, alpha, beta))
    a2 = alpha ** 2
    theta_c = beta / lam
    r = _largest_root_I(*_quartic_I(lam, rho, a2, beta))
    r = np.where(r >= theta_c, r, np.nan)
    # left branch: 24w = 12ρλθ − 6ρλ²θ² + α²λ³θ(4β − λθ)/β, stationary where derivative vanishes
    left = (12 * rho * lam + 4 * a2 * lam ** 3) / (12 * rho * lam ** 2 + 2 * a2 * lam ** 4 / beta)
    left = np.where(left < theta_c, left, np.nan)
    cand = np.column_stack([r, left, theta_c])
    W = work_I(cand, lam[:, None], rho[:, None], alpha[:, None], beta[:, None])
    W = np.where(np.isnan(cand), -np.inf, W)
    best = cand[np.arange(lam.size), np.argmax(W, axis=1)]
    return best.reshape(shape)


def theta_m_I_eq14(lam, rho, alpha, beta, corrected=False):
    """The paper's approximation of θ_m (eq. 14): the quartic expanded to second order about 1/λ.

    As printed, eq. 14 carries the sign error of the printed eq. 13 (the term 30 + 18β); the
    expansion of the corrected quartic has 30 − 18β (``corrected=True``); see analytic/NOTES.md.
    """
    lam, rho, alpha, beta = _bcast(lam, rho, alpha, beta)
    k = (alpha * beta * lam) ** 2
    sign = -1.0 if corrected else 1.0
    return (5 / 6 + k / (18 * rho)
            + np.sqrt(9 * rho ** 2 + k * rho * (30 + sign * 18 * beta) + k ** 2) / (18 * rho)) / lam


def vnorm_I(lam, rho, alpha, beta, theta_m=None):
    """Normalised collapse velocity v̄_g / √(g b) of mechanism I (eqs 7, 10).

    With m = γ s b² ρλ, I_O = m b²(λ² + 1)/3 and z_G = λb/2 (the façade strip about its toe),
    eq. 7 gives (v̄_g)² / (g b) = 24 W(θ_m)/(g γ s b³) · (λ² + 1) / (9 ρ λ³).
    """
    lam, rho, alpha, beta = _bcast(lam, rho, alpha, beta)
    th = theta_m_I(lam, rho, alpha, beta) if theta_m is None else np.asarray(theta_m, float)
    w24 = 24 * work_I(th, lam, rho, alpha, beta)
    return np.sqrt(w24 * (lam ** 2 + 1) / (9 * rho * lam ** 3))


# --------------------------------------------------------------------------- mechanism II
def geometry_II(lam, rho, tanpsi):
    """x_G/b, z_G/b (eq. 17) and i/b² (eq. 20) of façade strip + wedge about the outer toe.

    The eqs are written with α = tan ψ; here tan ψ is free (eq. 16 sets √(cf/a)).
    """
    lam, rho, t = _bcast(lam, rho, tanpsi)
    den = 2 * rho + lam * t
    xg = (3 * rho + lam ** 2 * t ** 2 + 3 * t * lam) / (3 * den)
    zg = lam * (3 * rho + 2 * lam * t) / (3 * den)
    i = ((3 * t + t ** 3) * lam ** 3 + 4 * (rho + t ** 2) * lam ** 2 + 6 * lam * t
         + 4 * rho) / (6 * den)
    return xg, zg, i


def vnorm_II(lam, rho, tanpsi):
    """Normalised collapse velocity v̄_g / √(g b) of mechanism II (eq. 19 with eqs 17, 20)."""
    xg, zg, i = geometry_II(lam, rho, tanpsi)
    rg = np.hypot(xg, zg)
    return np.sqrt(2 * i / zg * (rg / zg - 1))


def lam_max_II(H_over_b, L_over_b, tanpsi):
    """Largest λ of mechanism II: the failing part fits the wall (λ <= H/b) and the wedge the
    transversal wall (λ tan ψ <= L/b)."""
    H_over_b, L_over_b, t = _bcast(H_over_b, L_over_b, tanpsi)
    with np.errstate(divide="ignore"):
        return np.minimum(H_over_b, np.where(t > 0, L_over_b / t, np.inf))


# --------------------------------------------------------------------------- collapse acceleration
def multiplier_I(lam, rho, alpha):
    """Collapse acceleration over g of mechanism I at rest (the kinematic check of a static
    horizontal load): the façade strip rotating about its toe against its weight and the full
    abutment friction of eq. 8 at u = 0, whose power is eq. 9 at θ = 0,

        a/g = (m g b/2 + g γ s f c h³/(6a)) / (m g h/2) = 1/λ + α² λ/(3ρ),   m = γ l b h.
    """
    lam, rho, alpha = _bcast(lam, rho, alpha)
    return 1.0 / lam + alpha ** 2 * lam / (3 * rho)


def multiplier_II(lam, rho, tanpsi):
    """Collapse acceleration over g of mechanism II at rest: the weight of façade strip + wedge
    against the same horizontal acceleration about the outer toe, a/g = x_G/z_G (eq. 17)."""
    xg, zg, _ = geometry_II(lam, rho, tanpsi)
    return xg / zg


def static_critical_I(rho, alpha, lam_max):
    """The smallest a/g of mechanism I over 0 < λ <= lam_max and its λ: d(a/g)/dλ = 0 at
    λ = √(3ρ)/α (a/g = 2α/√(3ρ)), or λ = lam_max when that is lower."""
    rho, alpha, lam_max = _bcast(rho, alpha, lam_max)
    lam = np.minimum(np.sqrt(3 * rho) / alpha, lam_max)
    return lam, multiplier_I(lam, rho, alpha)


def static_critical_II(rho, tanpsi, lam_max):
    """The smallest a/g of mechanism II over 0 < λ <= lam_max (see lam_max_II) and its λ."""
    rho, t, lam_max = _bcast(rho, tanpsi, lam_max)
    r, tt = rho.ravel(), t.ravel()
    lam, v = _minimise(lambda x, ix: multiplier_II(x, r[ix], tt[ix]), lam_max.ravel())
    return lam.reshape(rho.shape), v.reshape(rho.shape)


# --------------------------------------------------------------------------- minimisation
def _minimise(fun, lam_max, lam_min=0.5, n_grid=160, n_golden=45):
    """Vectorised minimisation of fun(λ) over [lam_min, lam_max] for arrays of problems.

    A log-spaced grid locates the best cell, then golden-section search refines it (one new
    evaluation per step: the other interior point is the previous step's). Returns
    (λ*, fun(λ*)). If the minimum sits on lam_max the constraint λ <= H/b is active.
    A NaN value is no candidate (a real wall's part that crushes, ``real``): the search keeps
    to the finite values; a problem with no finite value on the grid gets (λ, NaN).
    """
    lam_max = np.asarray(lam_max, float)
    shape = lam_max.shape
    lm = lam_max.ravel()
    s = np.linspace(0.0, 1.0, n_grid)
    grid = lam_min * (lm[:, None] / lam_min) ** s[None, :]

    def fin(v):                 # NaN: no candidate, above any value
        return np.where(np.isnan(v), np.inf, v)

    raw = fun(grid, (slice(None), None))
    vals = fin(raw)
    k = np.argmin(vals, axis=1)
    idx = np.arange(lm.size)
    lo = grid[idx, np.maximum(k - 1, 0)]
    hi = grid[idx, np.minimum(k + 1, n_grid - 1)]
    gr = (math.sqrt(5) - 1) / 2
    x1, x2 = hi - gr * (hi - lo), lo + gr * (hi - lo)
    f1, f2 = fin(fun(x1, slice(None))), fin(fun(x2, slice(None)))
    for _ in range(n_golden - 1):
        left = f1 < f2          # the minimum is in [lo, x2]: x1 becomes the new x2
        hi, lo = np.where(left, x2, hi), np.where(left, lo, x1)
        x_new = np.where(left, hi - gr * (hi - lo), lo + gr * (hi - lo))
        f_new = fin(fun(x_new, slice(None)))
        x1, x2 = np.where(left, x_new, x2), np.where(left, x1, x_new)
        f1, f2 = np.where(left, f_new, f2), np.where(left, f1, f_new)
    left = f1 < f2
    hi, lo = np.where(left, x2, hi), np.where(left, lo, x1)
    lam = 0.5 * (lo + hi)
    f_lam = fun(lam, slice(None))
    # a midpoint past a crushing limit (NaN): the better inner point of the last bracket
    if np.isnan(f_lam).any():
        inner = np.where(f1 < f2, x1, x2)
        lam = np.where(np.isnan(f_lam), inner, lam)
        f_lam = np.where(np.isnan(f_lam), fun(inner, slice(None)), f_lam)
    # keep the grid's point if it beats the interior refinement (the minimum on an end point)
    grid_wins = vals[idx, k] < fin(f_lam)
    lam = np.where(grid_wins, grid[idx, k], lam)
    f_lam = np.where(grid_wins, raw[idx, k], f_lam)
    return lam.reshape(shape), f_lam.reshape(shape)


#: the vectorised minimiser of the critical λ, for the other closed forms (``real``)
minimise = _minimise


def critical_I(rho, alpha, beta, lam_max):
    """Critical slenderness λ and v̄_g/√(gb) of mechanism I: min over 0 < λ <= lam_max (= H/b)."""
    rho, alpha, beta, lam_max = _bcast(rho, alpha, beta, lam_max)
    r, a, b = rho.ravel(), alpha.ravel(), beta.ravel()

    def fun(lam, ix):
        return vnorm_I(lam, r[ix], a[ix], b[ix])

    lam, v = _minimise(fun, lam_max.ravel())
    return lam.reshape(rho.shape), v.reshape(rho.shape)


def critical_II(rho, tanpsi, lam_max):
    """Critical λ and v̄_g/√(gb) of mechanism II: min over 0 < λ <= lam_max (see lam_max_II)."""
    rho, t, lam_max = _bcast(rho, tanpsi, lam_max)
    r, tt = rho.ravel(), t.ravel()

    def fun(lam, ix):
        return vnorm_II(lam, r[ix], tt[ix])

    lam, v = _minimise(fun, lam_max.ravel())
    return lam.reshape(rho.shape), v.reshape(rho.shape)


# --------------------------------------------------------------------------- SI objects
@dataclass(frozen=True)
class MechanismResult:
    """A closed-form mechanism at its critical height.

    lam = h/b, h [m], vnorm = v̄_g/√(gb), vg = v̄_g [m/s], theta_m [rad] (peak of W), W_m [J],
    body: the failing body about O (3D masses: façade of length l, wedge of thickness s).
    """

    name: str
    lam: float
    h: float
    vnorm: float
    vg: float
    theta_m: float
    W_m: float
    body: RigidBody
    tanpsi: float | None = None
    theta_m_eq14: float | None = None
    lam_max: float = math.inf
    multiplier: float = math.nan       # smallest collapse acceleration a/g (static check)
    lam_multiplier: float = math.nan   # λ = h/b of that smallest a/g
    static_body: RigidBody | None = None   # the body of that smallest a/g, about its hinge
    static_z0: float = math.nan        # its hinge's height above the wall's base [m]
    floor_static: StaticMechanism | None = None   # the floors' reading (``check.ntc``)
    static_theta0: float | None = None  # rotation where a/g falls to 0 (nonlinear check)

    @property
    def static_mechanism(self) -> StaticMechanism | None:
        """The static check's body and multiplier (the code check's α₀ and M*)."""
        if self.static_body is None:
            return None
        return StaticMechanism(self.multiplier, self.static_body, self.static_z0,
                               "the body of the smallest a/g over h",
                               floor_reading=self.floor_static, theta0=self.static_theta0)

    @property
    def hinge_ratio(self) -> float:
        """|P_x/P_z| the hinge must transmit under the ideal impulse (``impulse``)."""
        return hinge_impulse_ratio(self.body)

    @property
    def label(self) -> str:
        """The row label of the summary table."""
        if self.tanpsi is None:        # mechanism I: no crack
            return "I  detachment (eqs 10, 7)"
        return f"II diagonal crack tan psi={self.tanpsi:.3f} (eqs 17-20)"

    def as_dict(self) -> dict:
        d = {k: getattr(self, k) for k in ("name", "lam", "h", "vnorm", "vg", "theta_m", "W_m",
                                           "tanpsi", "theta_m_eq14", "lam_max", "multiplier",
                                           "lam_multiplier", "hinge_ratio")}
        d["body"] = {k: getattr(self.body, k) for k in ("m", "x_G", "z_G", "I_O", "J_z")}
        return d


def _column(cases, get) -> np.ndarray:
    return np.array([get(c) for c in cases], float)


def wall_arrays(cases) -> dict[str, np.ndarray]:
    """The wall fields H, b, l, s, L, γ, g and ρ, α, β of ``cases`` as arrays (for
    ``mechanisms_I/II`` and the critical λ of many walls)."""
    ws = [c.wall for c in cases]
    cols = {k: _column(ws, lambda w, k=k: getattr(w, k)) for k in "H b l s L gamma g".split()}
    cols.update(rho=cols["l"] / cols["s"], alpha=_column(cases, lambda c: c.alpha),
                beta=_column(cases, lambda c: c.beta))
    return cols


def mechanisms_I(cases, lam, theta_m=None, walls=None) -> list[MechanismResult]:
    """``mechanism_I`` of many walls at once: ``lam`` (and θ_m, if known) one per case, the
    arithmetic on arrays, element by element the same as for one wall; ``walls``: their
    ``wall_arrays`` if already made."""
    w = wall_arrays(cases) if walls is None else walls
    rho, alpha, beta, b = w["rho"], w["alpha"], w["beta"], w["b"]
    lam = np.asarray(lam, float)
    th = theta_m_I(lam, rho, alpha, beta) if theta_m is None else np.asarray(theta_m, float)
    v = vnorm_I(lam, rho, alpha, beta, th)
    h = lam * b
    m = w["gamma"] * h * b * w["l"]
    I_O = m * (h ** 2 + b ** 2) / 3
    W_m = work_I(th, lam, rho, alpha, beta) * w["g"] * w["gamma"] * w["s"] * b ** 3
    lam_max = w["H"] / b
    lam_a, a_g = static_critical_I(rho, alpha, lam_max)
    eq14 = theta_m_I_eq14(lam, rho, alpha, beta)
    vg = v * np.sqrt(w["g"] * b)
    h_a = lam_a * b
    m_a = w["gamma"] * h_a * b * w["l"]
    return [MechanismResult("I", *x[:3], x[3], x[4], x[5],
                            RigidBody(m=x[6], x_G=x[7] / 2, z_G=x[1] / 2, I_O=x[8],
                                      J_z=x[6] * x[1] ** 2 / 3),
                            theta_m_eq14=x[9], lam_max=x[10], multiplier=x[11],
                            lam_multiplier=x[12],
                            static_body=_strip(x[13], x[7], x[14]), static_z0=x[15] - x[14])
            for x in zip(*(a.tolist() for a in (lam, h, v, vg, th, W_m, m, b, I_O, eq14,
                                                 lam_max, a_g, lam_a, m_a, h_a, w["H"])))]


def _strip(m: float, b: float, h: float) -> RigidBody:
    """The façade strip b × h of mass m about its outer toe (uniform: J_z = m h²/3)."""
    return RigidBody(m=m, x_G=b / 2, z_G=h / 2, I_O=m * (h * h + b * b) / 3, J_z=m * h * h / 3)


def mechanism_I(case: Case, lam: float | None = None,
                theta_m: float | None = None) -> MechanismResult:
    """Mechanism I (detachment of the façade) at its critical λ, or at a given λ <= H/b;
    ``theta_m``: θ_m at that λ if already known."""
    lam_max = case.wall.H / case.wall.b
    if lam is None:
        lam, _ = critical_I(case.rho, case.alpha, case.beta, lam_max)
    lam = check_range("lam", lam, 0.0, lam_max, lo_open=True)
    return mechanisms_I([case], [lam], None if theta_m is None else [theta_m])[0]


def mechanisms_II(cases, tanpsi, lam, static=None,
                  walls=None) -> list[MechanismResult | ParameterError]:
    """``mechanism_II`` of many walls at once: tan ψ and λ one per case (``static``: the
    arrays (λ, a/g) of ``static_critical_II`` if known), the arithmetic on arrays, element by
    element the same as for one wall. A case whose λ does not fit its wall gets the
    ParameterError ``mechanism_II`` would raise, in place of its result. ``walls``: their
    ``wall_arrays`` if already made."""
    w = wall_arrays(cases) if walls is None else walls
    rho, b = w["rho"], w["b"]
    t, lam = np.asarray(tanpsi, float), np.asarray(lam, float)
    lam_max = lam_max_II(w["H"] / b, w["L"] / b, t)
    xg, zg, i = geometry_II(lam, rho, t)
    v = vnorm_II(lam, rho, t)
    h = lam * b
    m = w["gamma"] * (w["l"] * b * h + w["s"] * t * h ** 2 / 2)
    lam_a, a_g = static_critical_II(rho, t, lam_max) if static is None else static
    vg = v * np.sqrt(w["g"] * b)
    Jz = wedge_Jz(w["gamma"], w["l"], w["s"], b, h, t)
    lam_a = np.asarray(lam_a, float)
    h_a = lam_a * b
    xa, za, ia = geometry_II(lam_a, rho, t)
    m_a = w["gamma"] * (w["l"] * b * h_a + w["s"] * t * h_a ** 2 / 2)
    Jz_a = wedge_Jz(w["gamma"], w["l"], w["s"], b, h_a, t)
    out = []
    for x, y in zip(zip(*(np.asarray(a, float).tolist() for a in (
            lam, h, v, vg, m, xg * b, zg * b, m * i * b ** 2, t, lam_max, a_g, lam_a, xg, zg,
            w["g"], Jz))), zip(*(np.broadcast_to(np.asarray(a, float), lam_a.shape).tolist()
                                 for a in (m_a, xa * b, za * b, m_a * ia * b ** 2, Jz_a,
                                           w["H"] - h_a)))):
        if not 0.0 < x[0] <= x[9] * (1 + 1e-12):
            out.append(ParameterError(
                f"lam = {x[0]!r} is out of range: allowed 0 < lam <= {x[9]:g} (the part must "
                "fit the wall and the wedge the transversal wall)"))
            continue
        body = RigidBody(m=x[4], x_G=x[5], z_G=x[6], I_O=x[7], J_z=x[15])
        W_m = x[4] * x[14] * (body.r_G - body.z_G)
        out.append(MechanismResult("II", x[0], x[1], x[2], x[3],
                                   math.atan2(x[12], x[13]),  # G over O (eq. 18)
                                   W_m, body, tanpsi=x[8], lam_max=x[9], multiplier=x[10],
                                   lam_multiplier=x[11],
                                   static_body=RigidBody(m=y[0], x_G=y[1], z_G=y[2], I_O=y[3],
                                                         J_z=y[4]), static_z0=y[5]))
    return out


def wedge_Jz(gamma, l, s, b, h, tanpsi):  # noqa: E741 (the paper's l)
    """∫z² dm about the toe of façade strip + wedge (eqs 17, 20's body): the strip's
    γ l b h³/3 and the wedge's γ s tan ψ h⁴/4 (its width at height z is z tan ψ)."""
    return gamma * (l * b * h ** 3 / 3 + s * tanpsi * h ** 4 / 4)


def mechanism_II(case: Case, tanpsi: float | None = None, lam: float | None = None,
                 static: tuple[float, float] | None = None) -> MechanismResult:
    """Mechanism II (diagonal crack, tan ψ default √(cf/a), eq. 16) at its critical λ;
    ``static``: (λ, a/g) of ``static_critical_II`` if already known."""
    w = case.wall
    t = case.alpha if tanpsi is None else check_range("tanpsi", tanpsi, 0.0)
    if lam is None:
        lam, _ = critical_II(case.rho, t, float(lam_max_II(w.H / w.b, w.L / w.b, t)))
    res = mechanisms_II([case], [t], [float(lam)],
                        None if static is None else ([static[0]], [static[1]]))[0]
    if isinstance(res, ParameterError):
        raise res
    return res
