"""The hinge + fan family of the T-section in closed form, beside mechanism II's rigid wedge.

Frame: x from the façade's outer face into the building, z up; façade 0 <= x <= b (density
ρ·γ, the paper's 2D reduction), transversal wall b <= x <= b + L (density γ); the analysed part
spans z_base <= z <= H with its base fixed. A horizontal body force λ g (per unit mass) pushes
towards −x; eq. 15's cone makes every admissible field dissipation-free (no cohesion), so the
kinematic multiplier is the ratio of the powers of gravity and of the horizontal force,

    λ = ∫ ρ v_z dA / ∫ ρ (−v_x) dA.

Hinge + fan (unit rotation rate, hinge at (0, z0) on the façade's outer face, ζ = z − z0):
- block  x <= T1 ζ:            v = (−ζ, x)        (rigid rotation about the hinge)
- fan    T1 ζ <= x <= T2 ζ:    v = (−1, T1) (T2 ζ − x)/(T2 − T1)   (affine)
- fixed  x >= T2 ζ or ζ <= 0:  v = 0.
The fan's uniform strain rate is d = (1, T1 T2, −(T1 + T2))/(T2 − T1) (d_xx, d_zz, γ_xz), and
the cone of eq. 15 (d_xx >= 0, d_zz >= f(c/a) d_xx, |γ_xz| <= d_zz/f + f d_xx) admits it iff

    T1 T2 >= cf/a   and   (T1 − f)(T2 − f) >= 0.

T1 = T2 = T is a sharp crack from the hinge, admissible iff T² >= cf/a (eq. 16). For given T1
the narrowest admissible fan is T2*(T1) = max(T1, cf/(a T1)); it exists for
T1 >= min(f, c/a). The narrowest fan with the steepest block edge is T1 = min(f, c/a),
T2 = max(f, c/a): the geometric mean of its edges is √(cf/a), the paper's tan ψ.

Mechanism II (rigid wedge): the façade above z0 and the wedge x − b <= T (z − z0) of the
transversal wall rotate about the outer toe (0, z0). The horizontal bed-joint crack under the
façade opens in pure extension (admissible in both façade models); the straight crack from the
inner corner at tan ψ = T is admissible iff T² >= cf/a and, near the corner, T >= f (its jump
strain fails |γ| <= d_zz/f + f d_xx there when T < f).

A bed-joints-only façade admits no horizontal extension (d_xx = 0), so no fan may cross it:
the hinge + fan family is inadmissible for that façade model.

All integrals are exact: every region is a convex polygon (the wall rectangles clipped by the
rays), and the integrand is affine on it (area × value at the centroid).
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass

import numpy as np
from scipy.optimize import minimize

from ..errors import ParameterError, check_choice, check_range
from ..geometry import TSection
from ..params import FACADE_MODELS, Case

__all__ = [
    "FanResult",
    "fan_admissible",
    "fan_strain_rate",
    "fan_velocity",
    "fan_participation",
    "fan_multiplier",
    "optimise_fan",
    "narrowest_T2",
    "wedge_admissible",
    "wedge_multiplier",
    "optimise_wedge",
]



# --------------------------------------------------------------------------- kinematics
def fan_strain_rate(T1: float, T2: float) -> np.ndarray:
    """Uniform strain rate of the fan, d = (1, T1 T2, −(T1 + T2)) / (T2 − T1)."""
    if not T2 > T1:
        raise ParameterError(f"T2 = {T2!r} is out of range: allowed T2 > T1 = {T1!r}")
    return np.array([1.0, T1 * T2, -(T1 + T2)]) / (T2 - T1)


def fan_admissible(T1: float, T2: float, a: float, c: float, f: float, tol: float = 1e-12) -> bool:
    """Does eq. 15's cone admit the fan (or, for T1 = T2, the sharp crack)?"""
    if T1 < 0 or T2 < T1:
        return False
    return bool(T1 * T2 >= c * f / a - tol and (T1 - f) * (T2 - f) >= -tol)


def narrowest_T2(T1, a: float, c: float, f: float):
    """Narrowest admissible fan edge T2*(T1) = max(T1, cf/(a T1)), for T1 >= min(f, c/a)."""
    T1 = np.asarray(T1, float)
    return np.maximum(T1, c * f / (a * T1))


def fan_velocity(x, z, z0: float, T1: float, T2: float) -> np.ndarray:
    """Velocity (v_x, v_z) of the hinge + fan field at points (x, z), unit rotation rate."""
    x, z = np.broadcast_arrays(np.asarray(x, float), np.asarray(z, float))
    zeta = z - z0
    v = np.zeros(x.shape + (2,))
    block = (zeta > 0) & (x <= T1 * zeta)
    fan = (zeta > 0) & (x > T1 * zeta) & (x < T2 * zeta)
    v[block] = np.stack([-zeta[block], x[block]], axis=-1)
    if T2 > T1:
        s = (T2 * zeta[fan] - x[fan]) / (T2 - T1)
        v[fan] = np.stack([-s, T1 * s], axis=-1)
    return v


def fan_participation(t, T1: float, T2: float):
    """Participation p = v·v_R/|v_R|² of the fan field along the ray x = t ζ from the hinge,
    v_R = (−ζ, x) the block's rotation: 1 on the block edge t = T1, 0 on the fixed edge T2.

        p(t) = (1 + T1 t)(T2 − t) / ((T2 − T1)(1 + t²))   for T1 <= t <= T2.
    """
    t = np.asarray(t, float)
    p = (1 + T1 * t) * (T2 - t) / ((T2 - T1) * (1 + t * t))
    return np.where(t <= T1, 1.0, np.where(t >= T2, 0.0, p))


# --------------------------------------------------------------------------- exact integrals
def _clip(poly: np.ndarray, n: np.ndarray, d: float) -> np.ndarray:
    """Sutherland–Hodgman: the part of a convex polygon with n·p <= d."""
    if len(poly) == 0:
        return poly
    s = poly @ n - d
    out = []
    for k in range(len(poly)):
        p, q, sp, sq = poly[k], poly[(k + 1) % len(poly)], s[k], s[(k + 1) % len(poly)]
        if sp <= 0:
            out.append(p)
        if sp * sq < 0:
            out.append(p + (q - p) * (sp / (sp - sq)))
    return np.array(out).reshape(-1, 2)


def _area_centroid(poly: np.ndarray):
    """Area and centroid of a simple polygon (shoelace)."""
    if len(poly) < 3:
        return 0.0, np.zeros(2)
    x, z = poly[:, 0], poly[:, 1]
    xn, zn = np.roll(x, -1), np.roll(z, -1)
    cr = x * zn - xn * z
    A = 0.5 * cr.sum()
    if abs(A) < 1e-300:
        return 0.0, np.zeros(2)
    return abs(A), np.array([((x + xn) * cr).sum(), ((z + zn) * cr).sum()]) / (6 * A)


@dataclass(frozen=True)
class _Section:
    """The analysed T-section (``homlimit.geometry.TSection`` over z_base <= z <= H) with the
    façade's density ratio ρ."""

    geo: TSection
    rho: float

    @property
    def b(self) -> float:
        return self.geo.b

    @property
    def H(self) -> float:
        return self.geo.H

    @property
    def z_base(self) -> float:
        return self.geo.z0

    def parts(self):
        """(density relative to the wall's, polygon) of the façade and the wall."""
        reg = self.geo.regions
        yield self.rho, np.array(reg["facade"], float)
        yield 1.0, np.array(reg["wall"], float)


def _section(case: Case, z_base: float) -> _Section:
    w = case.wall
    z_base = check_range("z_base", z_base, 0.0, w.H, hi_open=True, unit="m")
    return _Section(TSection.from_case(case, z_base), case.rho)


def _ray(T: float, z0: float, side: int):
    """Half-plane side·(x − T (z − z0)) <= 0 as (n, d) for _clip."""
    n = side * np.array([1.0, -T])
    return n, side * (-T * z0)


def _fan_powers(sec: _Section, z0: float, T1: float, T2: float):
    """(∫ρ v_z, ∫ρ (−v_x)) of the hinge + fan field over the section (exact)."""
    Pz = Px = 0.0
    for rho, rect in sec.parts():
        blk = _clip(rect, *_ray(T1, z0, +1))
        A, (xc, zc) = _area_centroid(blk)
        Pz += rho * A * xc
        Px += rho * A * (zc - z0)
        if T2 > T1:
            fan = _clip(_clip(rect, *_ray(T1, z0, -1)), *_ray(T2, z0, +1))
            A, (xc, zc) = _area_centroid(fan)
            s = rho * A * (T2 * (zc - z0) - xc) / (T2 - T1)
            Px += s
            Pz += T1 * s
    return Pz, Px


def fan_multiplier(case: Case, z0: float, T1: float, T2: float | None = None,
                   z_base: float = 0.0) -> float:
    """Kinematic multiplier λ of the hinge + fan field (exact; T2 default: narrowest fan).

    Does not test admissibility: see ``fan_admissible``.
    """
    sec = _section(case, z_base)
    z0 = check_range("z0", z0, sec.z_base, sec.H, hi_open=True, unit="m")
    T1 = check_range("T1", T1, 0.0, lo_open=True)
    m = case.masonry
    T2 = float(narrowest_T2(T1, m.a, m.c, m.f)) if T2 is None else check_range("T2", T2, T1)
    Pz, Px = _fan_powers(sec, z0, T1, T2)
    return Pz / Px


def wedge_multiplier(case: Case, z0: float, T: float | None = None, z_base: float = 0.0,
                     apex: str = "inner") -> float:
    """Multiplier λ = x_G / z_G of mechanism II's rigid body: façade above z0 + the wedge
    behind a straight crack of slope T (default √(cf/a), eq. 16) from the inner corner
    (b, z0) (``apex="inner"``, the paper's) or from the hinge (0, z0) (``apex="outer"``),
    about the outer toe (0, z0). Exact for any L, H (the wedge is clipped by the wall)."""
    sec = _section(case, z_base)
    z0 = check_range("z0", z0, sec.z_base, sec.H, hi_open=True, unit="m")
    T = case.alpha if T is None else check_range("T", T, 0.0)
    check_choice("apex", apex, ("inner", "outer"))
    x0 = sec.b if apex == "inner" else 0.0
    Pz = Px = 0.0
    for rho, rect in sec.parts():
        poly = _clip(rect, np.array([0.0, -1.0]), -z0)  # z >= z0
        poly = _clip(poly, np.array([1.0, -T]), x0 - T * z0)  # x − x0 <= T (z − z0)
        A, (xc, zc) = _area_centroid(poly)
        Pz += rho * A * xc
        Px += rho * A * (zc - z0)
    return Pz / Px


def wedge_admissible(T: float, a: float, c: float, f: float, apex: str = "inner") -> bool:
    """Is the straight crack admissible under eq. 15? T² >= cf/a, and T >= f from the inner
    corner (the jump there combines opening of the bed joint and sliding)."""
    ok = T * T >= c * f / a * (1 - 1e-12)
    return bool(ok and (T >= f * (1 - 1e-12) if apex == "inner" else True))


# --------------------------------------------------------------------------- optimisation
@dataclass(frozen=True)
class FanResult:
    """Optimum of a closed-form family over its parameters.

    lam: multiplier; z0: hinge height [m]; T1, T2: block-side and fixed-side edge slopes
    (tan ψ from the vertical; T1 = T2 for a sharp crack); family: "hinge+fan", "crack"
    (sharp crack from the hinge) or "wedge" (mechanism II); admissible: the cone test holds.
    """

    lam: float
    z0: float
    T1: float
    T2: float
    family: str
    admissible: bool
    z_base: float = 0.0

    @property
    def T_mid(self) -> float:
        """Geometric mean of the edges, √(T1 T2) (= √(cf/a) on the narrowest fan)."""
        return math.sqrt(self.T1 * self.T2)

    def as_dict(self) -> dict:
        d = asdict(self)
        d["T_mid"] = self.T_mid
        return d


def _check_facade(facade: str):
    check_choice("facade", facade, FACADE_MODELS)


def optimise_fan(case: Case, z_base: float = 0.0, free_T2: bool = False, T_cap: float = 4.0,
                 n_z: int = 61, n_T: int = 41, facade: str = "homogenised") -> FanResult:
    """Minimise λ over the hinge height z0 ∈ [z_base, H) and the block edge T1 ∈
    [min(f, c/a), T_cap], with T2 the narrowest admissible fan edge T2*(T1) (T2 = T1 beyond
    √(cf/a): a sharp crack from the hinge). ``free_T2=True`` also frees T2 >= T2*(T1), to
    show that the narrowest fan is optimal. Grid search, then a bounded polish.

    A bed-joints-only façade admits no fan (see module docstring): ``admissible`` is False.
    """
    _check_facade(facade)
    sec = _section(case, z_base)
    m = case.masonry
    T_lo = min(m.f, m.c / m.a)
    T_cap = check_range("T_cap", T_cap, T_lo, lo_open=True)

    def lam_of(z0, T1, dT2=0.0):
        T2 = float(narrowest_T2(T1, m.a, m.c, m.f)) + dT2
        Pz, Px = _fan_powers(sec, z0, T1, T2)
        return Pz / Px

    zs = sec.z_base + (sec.H - sec.z_base) * np.linspace(0.0, 0.95, n_z)
    Ts = T_lo + (T_cap - T_lo) * np.linspace(0.0, 1.0, n_T) ** 2
    grid = np.array([[lam_of(z0, T1) for T1 in Ts] for z0 in zs])
    iz, it = np.unravel_index(np.argmin(grid), grid.shape)
    x0 = [zs[iz], Ts[it]]
    bounds = [(sec.z_base, sec.z_base + 0.99 * (sec.H - sec.z_base)), (T_lo, T_cap)]
    if free_T2:
        x0.append(0.0)
        bounds.append((0.0, 10.0))
    res = minimize(lambda p: lam_of(*p), x0, method="L-BFGS-B" if not free_T2 else "Powell",
                   bounds=bounds, options={"ftol": 1e-15, "xtol": 1e-12} if free_T2 else
                   {"ftol": 1e-15, "gtol": 1e-12})
    z0, T1 = float(res.x[0]), float(res.x[1])
    dT2 = float(res.x[2]) if free_T2 else 0.0
    lam = float(res.fun)
    if grid[iz, it] < lam:  # keep the grid point if the polish wandered off
        z0, T1, dT2, lam = float(zs[iz]), float(Ts[it]), 0.0, float(grid[iz, it])
    T2 = float(narrowest_T2(T1, m.a, m.c, m.f)) + dT2
    family = "hinge+fan" if T2 > T1 * (1 + 1e-9) else "crack"
    # a bed-joints façade admits neither a fan nor a crack through it (both need d_xx > 0)
    ok = fan_admissible(T1, T2, m.a, m.c, m.f, tol=1e-9) and facade == "homogenised"
    return FanResult(lam, z0, T1, T2, family, ok, sec.z_base)


def optimise_wedge(case: Case, z_base: float = 0.0, T: float | None = None,
                   apex: str = "inner", n_z: int = 200) -> FanResult:
    """Mechanism II's rigid wedge (default tan ψ = √(cf/a), eq. 16) at its best z0."""
    sec = _section(case, z_base)
    m = case.masonry
    T = case.alpha if T is None else check_range("T", T, 0.0)
    zs = sec.z_base + (sec.H - sec.z_base) * np.linspace(0.0, 0.97, n_z)
    lams = np.array([wedge_multiplier(case, z0, T, sec.z_base, apex) for z0 in zs])
    k = int(np.argmin(lams))
    lo, hi = zs[max(k - 1, 0)], zs[min(k + 1, n_z - 1)]
    from scipy.optimize import minimize_scalar

    r = minimize_scalar(lambda z0: wedge_multiplier(case, z0, T, sec.z_base, apex),
                        bounds=(lo, hi), method="bounded", options={"xatol": 1e-10})
    z0, lam = (float(r.x), float(r.fun)) if r.fun < lams[k] else (float(zs[k]), float(lams[k]))
    return FanResult(lam, z0, T, T, "wedge", wedge_admissible(T, m.a, m.c, m.f, apex), sec.z_base)
