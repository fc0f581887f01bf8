"""The crack of a finite-element mechanism: level sets of the block's participation.

Given a P2 velocity field and its rigid fit (``rigidfit``: block rotating at ω about
O), the participation p = v·v_R/|v_R|² is 1 on the block and 0 on the fixed part. A sharp crack
is a jump of p smeared over about one element; a hinge + fan (``closed_form.fan``) spreads it over
a wedge of rays from the hinge, p(t) = (1 + T1 t)(T2 − t) / ((T2 − T1)(1 + t²)) along the ray
x − x_O = t (z − z_O).

``crack_line`` extracts the level set p = level inside the transversal wall as a point cloud
ordered by z (marching triangles on the P2 field, each P2 triangle split into its four linear
sub-triangles), its local angle ψ(z) from the vertical, and a straight-line fit x = x_0 + T z
over a stated part of it with an uncertainty from the element size:

    δT = √(se² + (h_e / ℓ_z)²),

se the fit's standard error, h_e the mean size of the elements the line crosses, ℓ_z the fitted
part's height: a level set of a field resolved at scale h_e is located to about ±h_e/2 at each
end. ``fan_edges`` fits the fan model to the slopes of the levels 0.1…0.9 to read the two edges
T1 (block side) and T2 (fixed side); the 50 % line is the mid-line (the prototype's finding: it
lies close to √(cf/a) = √(T1 T2) when T1 = f, T2 = c/a).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from scipy.optimize import least_squares

from ..errors import ParameterError, check_range
from .rigidfit import MechanismMeasures

__all__ = ["CrackLine", "FanEdges", "crack_line", "fan_edges", "p2_subtriangles",
           "level_crossings", "fan_ray", "mechanism_type", "LEVELS"]

LEVELS = tuple(np.round(np.arange(0.1, 0.91, 0.1), 10))

# the four linear sub-triangles of a P2 triangle (v1, v2, v3, e12, e23, e13)
_SUB = np.array([[0, 3, 5], [3, 1, 4], [5, 4, 2], [3, 4, 5]])


def p2_subtriangles(elements: np.ndarray) -> np.ndarray:
    """(4 n_el, 3) node indices of the linear sub-triangles of P2 triangles; sub-triangle 4k+j
    belongs to element k."""
    el = np.asarray(elements, int)
    return el[:, _SUB].reshape(-1, 3)


def level_crossings(X: np.ndarray, tri: np.ndarray, q: np.ndarray, level: float):
    """Points where the piecewise-linear field q crosses ``level`` on the triangles ``tri``.

    Returns (points (n, 2), triangle index (n,)): two points per crossed triangle (marching
    triangles), one segment each. Triangles with a NaN value are skipped.
    """
    Q = q[tri] - level
    ok = np.all(np.isfinite(Q), axis=1)
    pts, owner = [], []
    for i, j in ((0, 1), (1, 2), (2, 0)):
        a, b = Q[:, i], Q[:, j]
        cut = ok & (a * b < 0)
        s = a[cut] / (a[cut] - b[cut])
        xa, xb = X[tri[cut, i]], X[tri[cut, j]]
        pts.append(xa + s[:, None] * (xb - xa))
        owner.append(np.flatnonzero(cut))
    return np.concatenate(pts), np.concatenate(owner)


@dataclass(frozen=True)
class CrackLine:
    """A level set of the participation: the crack (or one line of a fan) in the wall.

    level: participation value; points (n, 2) ordered by z [m]; z_local, x_local, psi_local:
    the line binned in z (bins of 2 h_e, a polyline) and its local angle from the vertical
    ψ(z) [rad];
    T: fitted tan ψ over z ∈ fit_range [m]; dT: its uncertainty; h_e: element size [m].
    """

    level: float
    points: np.ndarray
    z_local: np.ndarray
    x_local: np.ndarray
    psi_local: np.ndarray
    T: float
    dT: float
    fit_range: tuple[float, float]
    h_e: float
    x0: float = math.nan

    @property
    def psi_deg(self) -> float:
        return math.degrees(math.atan(self.T))

    @property
    def polyline(self) -> np.ndarray:
        """(k, 2) vertices (x, z) of the binned line, bottom to top."""
        return np.c_[self.x_local, self.z_local]


@dataclass(frozen=True)
class FanEdges:
    """Edges of the deforming zone from the level-set slopes.

    T1, T2: block-side and fixed-side edges (tan ψ), from the fan model fitted to the slopes
    of ``levels``; T_mid: the 50 % line; dT: the 50 % line's uncertainty; lines: the level
    sets; sharp: T2 − T1 within 2 dT (a crack smeared over the mesh, not a resolved fan).
    """

    T1: float
    T2: float
    T_mid: float
    dT: float
    sharp: bool
    lines: dict = field(default_factory=dict)

    @property
    def edges(self) -> tuple[float, float]:
        return (self.T1, self.T2)


def _wall_mask(X, sub, b, hinge, r_min):
    """Sub-triangles in the transversal wall, above O and farther than r_min from it."""
    c = X[sub].mean(axis=1)
    r = np.hypot(c[:, 0] - hinge[0], c[:, 1] - hinge[1])
    return (c[:, 0] > b) & (c[:, 1] > hinge[1]) & (r > r_min)


def crack_line(X: np.ndarray, elements: np.ndarray, mm: MechanismMeasures, b: float,
               level: float = 0.5, fit_part: tuple[float, float] = (0.1, 0.9),
               r_min: float | None = None, z_top: float | None = None,
               resolution: float | None = None) -> CrackLine | None:
    """The level set p = level of the block's participation inside the wall x > b.

    X, elements: P2 nodes (n, 2) and triangles (n_el, 6) as given to ``measure_mechanism``;
    b: façade thickness [m] (the wall starts at x = b); fit_part: the fitted part as fractions
    of the line's height range in the wall (default: the middle 80 %, away from the façade
    junction and the top); r_min: points closer to O are ignored (default 2 h_e);
    z_top: ignore points within 2 h_e of this height (the free top); resolution: the slope
    uncertainty of the field itself, replacing h_e/ℓ_z in δT where the mesh conforms to the
    field's kinks (there a level set of the P2 field is exact, and what is uncertain is where
    the search put the kinks: ``conform``). Returns None if the level is not crossed (no block,
    or no crack in the wall).
    """
    level = check_range("level", level, 0.0, 1.0, lo_open=True, hi_open=True)
    lo, hi = (check_range("fit_part", v, 0.0, 1.0) for v in fit_part)
    if not hi > lo:
        raise ParameterError(f"fit_part = {fit_part!r} is out of range: allowed 0 <= lo < hi <= 1")
    X = np.asarray(X, float)
    sub = p2_subtriangles(elements)
    p = mm.node_participation
    e1, e2 = X[sub[:, 1]] - X[sub[:, 0]], X[sub[:, 2]] - X[sub[:, 0]]
    h_sub = np.sqrt(np.abs(e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0]))  # √(2 area)
    hinge = mm.fit.O
    r0 = 4.0 * float(np.median(h_sub)) if r_min is None else float(r_min)
    keep = _wall_mask(X, sub, b, hinge, r0)
    pts, own = level_crossings(X, sub[keep], p, level)
    if len(pts) < 4:
        return None
    h_e = 2.0 * float(np.mean(h_sub[keep][own]))  # P2 element ≈ 2 × sub-triangle size
    if z_top is not None:
        sel = pts[:, 1] < z_top - 2 * h_e
        pts = pts[sel]
        if len(pts) < 4:
            return None
    pts = pts[np.argsort(pts[:, 1])]
    z, x = pts[:, 1], pts[:, 0]
    # local angle: the line binned in z (bins of 2 h_e), centred differences
    nb = max(2, int((z[-1] - z[0]) / (2 * h_e)))
    edges = np.linspace(z[0], z[-1], nb + 1)
    k = np.clip(np.searchsorted(edges, z, side="right") - 1, 0, nb - 1)
    cnt = np.bincount(k, minlength=nb)
    good = cnt > 0
    zb = np.bincount(k, z, nb)[good] / cnt[good]
    xb = np.bincount(k, x, nb)[good] / cnt[good]
    psi = np.arctan(np.gradient(xb, zb)) if len(zb) > 1 else np.array([np.nan])
    za, zc = z[0] + lo * (z[-1] - z[0]), z[0] + hi * (z[-1] - z[0])
    sel = (z >= za) & (z <= zc)
    if sel.sum() < 4:
        return None
    A = np.c_[np.ones(sel.sum()), z[sel]]
    coef, res, *_ = np.linalg.lstsq(A, x[sel], rcond=None)
    r = x[sel] - A @ coef
    dof = max(sel.sum() - 2, 1)
    cov = np.linalg.inv(A.T @ A) * (r @ r) / dof
    se = math.sqrt(max(cov[1, 1], 0.0))
    dT = math.hypot(se, h_e / (zc - za) if resolution is None else resolution)
    return CrackLine(level, pts, zb, xb, psi, float(coef[1]), dT, (float(za), float(zc)), h_e,
                     float(coef[0]))


def fan_ray(p, T1, T2):
    """Ray slope t where the fan's participation equals p (root of a quadratic in t):
    (p (T2 − T1) + T1) t² + (1 − T1 T2) t + p (T2 − T1) − T2 = 0."""
    w = p * (T2 - T1)
    A, B, C = w + T1, 1.0 - T1 * T2, w - T2
    disc = np.sqrt(np.maximum(B * B - 4 * A * C, 0.0))
    return (-B + disc) / (2 * A)


def fan_edges(X: np.ndarray, elements: np.ndarray, mm: MechanismMeasures, b: float,
              levels=LEVELS, **kw) -> FanEdges | None:
    """Both edges and the mid-line of the deforming zone beside the block.

    The slopes T(p) of the level sets p ∈ ``levels`` are fitted with the fan model
    t(p; T1, T2) (rays from the hinge, ``homlimit.closed_form.fan.fan_participation``); T_mid is the
    50 % line's own fitted slope. Keyword arguments go to ``crack_line``.
    """
    lines = {lv: crack_line(X, elements, mm, b, level=lv, **kw) for lv in levels}
    lines = {lv: ln for lv, ln in lines.items() if ln is not None}
    if 0.5 not in lines or len(lines) < 3:
        return None
    ps = np.array(sorted(lines))
    Ts = np.array([lines[p].T for p in ps])
    w = 1.0 / np.array([lines[p].dT for p in ps])
    t_lo, t_hi = float(Ts.min()), float(Ts.max())

    def resid(q):
        T1, T2 = q[0], q[0] + math.exp(q[1])
        return w * (fan_ray(ps, T1, T2) - Ts)

    width = max(t_hi - t_lo, 1e-3)
    sol = least_squares(resid, [t_lo - 0.1 * width, math.log(1.2 * width)])
    T1, T2 = float(sol.x[0]), float(sol.x[0] + math.exp(sol.x[1]))
    mid = lines[0.5]
    return FanEdges(T1, T2, mid.T, mid.dT, (T2 - T1) <= 2 * mid.dT, lines)


def mechanism_type(mm: MechanismMeasures, edges: FanEdges | None) -> str:
    """"distributed" (no rigid block carries half the energy), "rigid" (a block behind one
    crack: no fan edges resolved apart, T2 − T1 <= 2 δT) or "hinge+fan" (edges resolved)."""
    if mm.kind == "distributed":
        return "distributed"
    return "rigid" if edges is None or edges.sharp else "hinge+fan"
