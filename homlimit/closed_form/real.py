"""Mechanisms I, II and the simple overturning of a real wall: finite compressive strength,
tie-rods and floors (issue 30; the choices and their sources: docs/real-walls.md).

The failing body is the façade's top part of height h = λb (hinge at z0 = H − h on the outer
face, the paper's frame), as in mechanisms I (eqs 8–14) and II (eqs 16–20); the simple
overturning is mechanism I without the abutment friction (the façade not bonded to the
transversal walls). Everything is per bay of façade length l (as the paper's m = γ l b h):
a tie or a floor given per metre of façade carries its value × l.

- Finite f_c: the hinge joint's compressed zone is a rectangular stress block of depth
  w = N/(f_c l) (N: the body's weight and the floor loads on it); the body turns about the
  block's resultant, the hinge retreating inwards by t = w/2 = N/(2 f_c l). A part whose block
  would not fit the thickness (w > b) crushes: it is no candidate (NaN).
- A tie at z_T > z0 stretches by δ = d θ (mechanism I, linearised like eq. 10) or d sin θ (II
  and the overturning, exact like eq. 18), d = z_T − z0; its force is min(kδ, T_y) (k = 0:
  rigid-plastic, T_y from the start) until δ reaches the ductility limit, zero after. The work
  done against it, ∫F dδ, is restoring work in W(θ) (eq. 7); the static multiplier takes T_y d
  (limit analysis: the tie yields).
- A floor at z_F > z0 is a dead load Q = q l at (e, z_F − z0) from the hinge: its vertical
  displacement's work adds to W(θ) (linearised for I) and Q (e − t) to the resisting moment;
  its mass moves with the building (not in I_O, not in the horizontal load). A restraining
  floor bounds the body: z0 >= z_F. Beside it, the code check's floors' reading
  (``multiplier_real(..., floor_mass=True)``, docs/code-check.md) also pushes Q horizontally.

W(θ_m) is the largest W over 0 <= θ <= θ_hi (a grid, then golden-section refinement); v̄_g
from eq. 7 about the retreated hinge. A case without ties, floors and f_c never comes here
(``mechanisms`` keeps the paper's forms bit for bit).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..check.ntc import StaticMechanism
from ..errors import ParameterError
from ..impulse import RigidBody
from ..impulse.loads import tie_work
from ..params import Case
from .mechanisms import MechanismResult, geometry_II, lam_max_II, minimise, wedge_Jz

__all__ = ["KINDS", "RealMechanismResult", "real_mechanism", "vnorm_real", "multiplier_real",
           "friction_work_I", "mechanism_state", "fc_min", "fc_problem",
           "work_real", "theta_m_real", "lam_bounds"]

KINDS = ("detachment", "crack", "overturning")     # mechanisms I, II and the overturning
#: the mechanism (registry) name of each kind
NAMES = {"detachment": "I", "crack": "II", "overturning": "overturning"}
LAM_MIN = 0.5           # the closed forms' smallest λ (``mechanisms._minimise``'s lam_min)
N_THETA = 1025          # the θ grid of W's peak, then golden-section refinement
N_GOLDEN = 60


def _tanpsi(case: Case, kind: str, tanpsi: float | None) -> float:
    return (tanpsi or case.alpha) if kind == "crack" else 0.0


def _body(case: Case, kind: str, lam, t_psi: float):
    """Mass m [kg], x_G, z_G [m] from the outer toe, I_O and J_z = ∫z² dm [kg m²] of the
    failing body (arrays over λ): the façade strip (I, overturning) or strip + wedge (II,
    eqs 17, 20), less what the openings remove (``_removed``: the real body integrated)."""
    w = case.wall
    b, h = w.b, lam * w.b
    if kind == "crack":
        xg, zg, i = geometry_II(lam, w.rho, t_psi)
        m = w.gamma * (w.l * b * h + w.s * t_psi * h ** 2 / 2)
        full = m, xg * b, zg * b, m * i * b ** 2, wedge_Jz(w.gamma, w.l, w.s, b, h, t_psi)
    else:
        m = w.gamma * w.l * b * h
        full = m, np.full_like(h, b / 2), h / 2, m * (h ** 2 + b ** 2) / 3, m * h ** 2 / 3
    if not (case.facade_openings or (kind == "crack" and case.wall_openings)):
        return full
    m, xg, zg, I_O, Jz = full
    mr, sx, sz, io, jz = _removed(case, kind, h, t_psi)
    mn = m - mr
    return mn, (m * xg - sx) / mn, (m * zg - sz) / mn, I_O - io, Jz - jz


def _rect_moments(x0, x1, z0, z1):
    """∫1, ∫x, ∫z, ∫(x² + z²), ∫z² over [x0, x1] × [z0, z1] (zero where empty), elementwise."""
    dx, dz = np.maximum(x1 - x0, 0.0), np.maximum(z1 - z0, 0.0)
    A = dx * dz
    x1, z1 = np.maximum(x1, x0), np.maximum(z1, z0)
    ix2 = (x1 ** 3 - x0 ** 3) / 3 * dz
    iz2 = (z1 ** 3 - z0 ** 3) / 3 * dx
    return A, A * (x0 + x1) / 2, A * (z0 + z1) / 2, ix2 + iz2, iz2


_GL_X, _GL_W = np.polynomial.legendre.leggauss(4)     # exact to degree 7 (here <= 5)


def _wedge_hole_moments(x0, x1, z0, z1, b, t):
    """∫1, ∫x, ∫z, ∫(x² + z²), ∫z² over the rectangle [x0, x1] × [z0, z1] (b < x0, z from
    the hinge) cut by the wedge's crack x <= b + t z (mechanism II's wedge: its part of a
    wall opening), elementwise: over x the column runs from max(z0, (x − b)/t) to z1, a
    polynomial of degree <= 5 in x on each of two pieces, integrated exactly by 4-point
    Gauss–Legendre."""
    with np.errstate(divide="ignore", invalid="ignore"):
        xa, xb = b + t * z0, b + t * z1            # the crack crosses z0 and z1 here
    out = [0.0] * 5
    for lo_x, hi_x, cut in ((x0, np.minimum(x1, xa), False),
                            (np.maximum(x0, xa), np.minimum(x1, xb), True)):
        width = np.maximum(hi_x - lo_x, 0.0)
        for xi, wi in zip(_GL_X, _GL_W):
            x = lo_x + (xi + 1) / 2 * width
            lo = np.maximum((x - b) / t, z0) if cut else z0
            hi = np.maximum(z1, lo)
            c0, c1, c2 = hi - lo, (hi ** 2 - lo ** 2) / 2, (hi ** 3 - lo ** 3) / 3
            wt = wi * width / 2
            for k, v in enumerate((c0, x * c0, c1, x * x * c0 + c2, c2)):
                out[k] = out[k] + wt * v
    return tuple(np.where(z1 > z0, v, 0.0) for v in out)


def _removed(case: Case, kind: str, h, t_psi: float):
    """What the openings take from the failing body of height h (arrays over λ), about the
    outer toe (0, H − h): mass, ∫x dm, ∫z dm, ∫(x² + z²) dm, ∫z² dm [SI]. A façade band
    removes ``fraction`` of the strip's mass over its part of the body (density γ l,
    x in [0, b]); mechanism II also loses the part of each wall opening inside its wedge
    (density γ s). Mechanism I and the overturning take the façade only: a wall opening
    does not change them (docs/real-walls.md "Openings")."""
    w = case.wall
    z_hinge = w.H - h
    tot = [np.zeros_like(h) for _ in range(5)]
    for op in case.facade_openings:
        lo = np.clip(op.z_bottom - z_hinge, 0.0, h)
        hi = np.clip(op.z_top - z_hinge, 0.0, h)
        mom = _rect_moments(0.0, w.b, lo, hi)
        for k in range(5):
            tot[k] = tot[k] + op.fraction * w.gamma * w.l * mom[k]
    if kind == "crack" and t_psi > 0:
        for op in case.wall_openings:
            x0, x1, z0, z1 = op.box
            lo = np.clip(z0 - z_hinge, 0.0, h)
            hi = np.clip(z1 - z_hinge, 0.0, h)
            mom = _wedge_hole_moments(x0, x1, lo, hi, w.b, t_psi)
            for k in range(5):
                tot[k] = tot[k] + w.gamma * w.s * mom[k]
    return tuple(tot)


def _loads(case: Case, lam):
    """Per λ: the floors bearing on the body (Q [N], e [m], z above the hinge [m]) and the
    ties in it (T_y [N], k [N/m], δ_u [m], d [m]), each an (n_λ, n) array, zero where the
    floor or tie lies at or below the hinge."""
    w = case.wall
    z0 = w.H - np.asarray(lam, float) * w.b
    fl, ti = case.floors, case.ties
    zf = np.array([f.z for f in fl], float)
    on_f = zf[None, :] > z0[..., None]
    Q = np.where(on_f, np.array([f.load for f in fl], float) * w.l, 0.0)
    e = np.broadcast_to(np.array([f.eccentricity for f in fl], float), Q.shape)
    zq = np.where(on_f, zf[None, :] - z0[..., None], 0.0)
    zt = np.array([t.z for t in ti], float)
    on_t = zt[None, :] > z0[..., None]
    d = np.where(on_t, zt[None, :] - z0[..., None], 0.0)
    T = np.where(on_t, np.array([t.yield_force for t in ti], float) * w.l, 0.0)
    k = np.broadcast_to(np.array([t.stiffness for t in ti], float) * w.l, d.shape)
    du = np.broadcast_to(np.array([t.ductility or math.inf for t in ti], float), d.shape)
    return Q, e, zq, T, k, du, d


def _state(case: Case, kind: str, lam, tanpsi=None):
    lam = np.atleast_1d(np.asarray(lam, float))
    t_psi = _tanpsi(case, kind, tanpsi)
    m, xg, zg, I_O, Jz = _body(case, kind, lam, t_psi)
    Q, e, zq, T, k, du, d = _loads(case, lam)
    g, fc, b, length = case.wall.g, case.masonry.fc, case.wall.b, case.wall.l
    N = m * g + Q.sum(axis=-1)
    t = N / (2 * fc * length) if fc > 0 else np.zeros_like(N)
    t = np.where(2 * t <= b, t, np.nan)        # the stress block must fit the thickness
    return dict(lam=lam, m=m, xg=xg, zg=zg, I_O=I_O, Jz=Jz, Q=Q, e=e, zq=zq, T=T, k=k, du=du, d=d,
                N=N, t=t, g=g, t_psi=t_psi)


def fc_min(case: Case, kind: str, tanpsi: float | None = None) -> tuple[float, float]:
    """(fc_min [Pa], N [N]): the smallest f_c at which some part of mechanism ``kind`` is a
    candidate, and the normal force N on the hinge that sets it. A part crushes when its
    stress block w = N/(f_c l) is deeper than b, i.e. f_c < N/(b l); N (the body's weight and
    the floor loads on it, all >= 0) only grows with λ, so the smallest part, λ = LAM_MIN,
    sets the bound: fc_min = N(LAM_MIN)/(b l) (a plain wall's mechanism I: γ g b/2)."""
    n = float(_state(case, kind, [LAM_MIN], tanpsi)["N"][0])
    return n / (case.wall.b * case.wall.l), n


def fc_problem(case: Case, kinds=KINDS, tanpsi: float | None = None) -> str | None:
    """The problem line of a finite ``[masonry] fc`` under which every part of one of the
    mechanisms ``kinds`` crushes at its hinge (none: None). The bound depends on the wall
    (``fc_min``), and the message says so."""
    fc = case.masonry.fc
    if not fc:
        return None
    bounds = {kind: fc_min(case, kind, tanpsi) for kind in kinds}
    kind = max(bounds, key=lambda k: bounds[k][0])
    low, n = bounds[kind]
    if fc >= low:
        return None
    w = case.wall
    step = 10.0 ** (math.floor(math.log10(low)) - 3)
    up = math.ceil(low / step) * step           # 4 digits, rounded up: an admissible value
    return (f"[masonry] fc = {fc!r} Pa is too low for this wall: every part of mechanism "
            f"{NAMES[kind]} ({kind}) crushes at its hinge; allowed fc = 0 (infinite) or "
            f"fc >= {up:.4g} Pa (a bound of this wall: its smallest part, h = {LAM_MIN:g} b "
            f"= {LAM_MIN * w.b:.4g} m, presses N = {n:.4g} N (its weight and the floor loads "
            f"on it) on its hinge, whose stress block N/(fc l) must fit the thickness "
            f"b = {w.b:g} m: fc >= N/(b l); docs/real-walls.md)")


def mechanism_state(case: Case, kind: str, lam, tanpsi: float | None = None) -> dict:
    """Per λ (arrays): the failing body (m, x_G, z_G from the outer toe, I_O, Jz), the hinge
    retreat t and normal force N, the floors on it (Q, e, zq: height above the hinge) and the
    ties in it (T, k, du, d), each (n_λ, n); t_psi, g. What the rockers build on."""
    return _state(case, kind, lam, tanpsi)


def friction_work_I(case: Case, lam, theta):
    """Mechanism I's abutment friction work at λ up to θ [J] (eq. 9 integrated)."""
    return _friction_I(case, lam, theta)


def _friction_I(case: Case, lam, theta):
    """The abutment friction's work of mechanism I, eq. 9 integrated (both branches) [J]."""
    w, ms = case.wall, case.masonry
    h, c = lam * w.b, ms.c
    scale = w.g * w.gamma * w.s * ms.f / ms.a
    with np.errstate(divide="ignore", invalid="ignore"):
        left = h ** 3 * theta * (4 * c - h * theta) / 24
        right = c ** 2 * (6 * h ** 2 * theta ** 2 + c ** 2 - 4 * c * h * theta) / (24 * theta ** 2)
    return scale * np.where(h * theta < c, left, right)


def _work(case: Case, kind: str, st: dict, theta):
    """W(θ) [J] for θ of shape (n_λ, n_θ) (or (n_λ,)), the state ``st`` of ``_state``."""
    th = np.asarray(theta, float)
    ex = (lambda a: a[:, None]) if th.ndim == 2 else (lambda a: a)
    m, g, xg, zg, t = ex(st["m"]), st["g"], ex(st["xg"]), ex(st["zg"]), ex(st["t"])
    Q, e, zq = st["Q"], st["e"], st["zq"]
    T, k, du, d = st["T"], st["k"], st["du"], st["d"]
    if th.ndim == 2:
        Q, e, zq, T, k, du, d = (a[:, None, :] for a in (Q, e, zq, T, k, du, d))
    ths = th[..., None]
    if kind == "detachment":                     # linearised as eq. 10
        W = m * g * ((xg - t) * th - zg * th ** 2 / 2)
        W = W + np.sum(Q * ((e - t[..., None]) * ths - zq * ths ** 2 / 2), axis=-1)
        W = W + _friction_I(case, ex(st["lam"]), th)
        delta = d * ths
    else:                               # exact rigid rotation, as eq. 18
        W = m * g * ((xg - t) * np.sin(th) + zg * (np.cos(th) - 1))
        W = W + np.sum(Q * ((e - t[..., None]) * np.sin(ths) + zq * (np.cos(ths) - 1)), axis=-1)
        delta = d * np.sin(ths)
    return W + np.sum(tie_work(delta, T, k, du), axis=-1)


def _moment0(case: Case, kind: str, st: dict):
    """The resisting moment about the hinge at rest [N m]: gravity and floors about the
    retreated hinge, the ties at yield, mechanism I's abutment friction (eq. 9 at θ = 0)."""
    M = st["m"] * st["g"] * (st["xg"] - st["t"])
    M = M + np.sum(st["Q"] * (st["e"] - st["t"][:, None]), axis=-1)
    M = M + np.sum(st["T"] * st["d"], axis=-1)
    if kind == "detachment":
        w, ms = case.wall, case.masonry
        h = st["lam"] * w.b
        M = M + w.g * w.gamma * w.s * ms.f * ms.c * h ** 3 / (6 * ms.a)
    return M


def _theta_hi(case: Case, kind: str, st: dict):
    """An upper end of the search for θ_m: mechanism I's W'(θ) <= M0 − K θ (the friction's and
    the ties' rates never grow), K = m g z_G + Σ Q z_Q; the exact forms stop at π/2."""
    if kind != "detachment":
        return np.full_like(st["lam"], math.pi / 2)
    K = st["m"] * st["g"] * st["zg"] + np.sum(st["Q"] * st["zq"], axis=-1)
    return np.maximum(_moment0(case, kind, st) / K, 1e-9) * 1.001


def _peak(case: Case, kind: str, st: dict):
    """θ_m and W(θ_m) per λ: the best of a θ grid on [0, θ_hi], refined by golden section."""
    hi = _theta_hi(case, kind, st)
    hi = np.where(np.isfinite(hi), hi, math.pi / 2)
    s = np.linspace(0.0, 1.0, N_THETA)
    grid = hi[:, None] * s[None, :]
    W = _work(case, kind, st, grid)
    W[:, 0] = 0.0
    k = np.nanargmax(np.where(np.isnan(W), -np.inf, W), axis=1)
    idx = np.arange(len(hi))
    lo, up = grid[idx, np.maximum(k - 1, 0)], grid[idx, np.minimum(k + 1, N_THETA - 1)]
    gr = (math.sqrt(5) - 1) / 2
    x1, x2 = up - gr * (up - lo), lo + gr * (up - lo)
    f1, f2 = _work(case, kind, st, x1), _work(case, kind, st, x2)
    for _ in range(N_GOLDEN):
        left = f1 > f2                          # the maximum is in [lo, x2]
        up, lo = np.where(left, x2, up), np.where(left, lo, x1)
        xn = np.where(left, up - gr * (up - lo), lo + gr * (up - lo))
        fn = _work(case, kind, st, xn)
        x1, x2 = np.where(left, xn, x2), np.where(left, x1, xn)
        f1, f2 = np.where(left, fn, f2), np.where(left, f1, fn)
    th = 0.5 * (lo + up)
    Wm = _work(case, kind, st, th)
    grid_wins = W[idx, k] > Wm
    th, Wm = np.where(grid_wins, grid[idx, k], th), np.where(grid_wins, W[idx, k], Wm)
    bad = np.isnan(st["t"])
    return np.where(bad, np.nan, th), np.where(bad, np.nan, np.maximum(Wm, 0.0))


def lam_bounds(case: Case, kind: str, tanpsi: float | None = None) -> float:
    """The largest λ of the mechanism: the wall (H/b), II's wedge in the transversal wall
    (``lam_max_II``), and a restraining floor at z_F (the body above it: λ <= (H − z_F)/b)."""
    w = case.wall
    lam = w.H / w.b
    if kind == "crack":
        lam = float(lam_max_II(w.H / w.b, w.L / w.b, _tanpsi(case, kind, tanpsi)))
    zr = [f.z for f in case.floors if f.restrains]
    if zr:
        lam = min(lam, (w.H - max(zr)) / w.b)
    return lam


def work_real(case: Case, kind: str, lam: float, theta, tanpsi: float | None = None):
    """W(θ) [J] of the mechanism at one λ, θ an array (the restoring work of eq. 7)."""
    st = _state(case, kind, [lam], tanpsi)
    return _work(case, kind, st, np.atleast_1d(np.asarray(theta, float))[None, :])[0]


def theta_m_real(case: Case, kind: str, lam, tanpsi: float | None = None):
    """(θ_m, W(θ_m) [J]) per λ."""
    return _peak(case, kind, _state(case, kind, lam, tanpsi))


def _velocity(case: Case, kind: str, st: dict):
    """(v̄_g [m/s], θ_m, W_m, I about the retreated hinge) per λ (eq. 7:
    v̄_g = (i/z_G)√(2W/I) = √(2 W I)/(m z_G))."""
    th, Wm = _peak(case, kind, st)
    m, xg, t = st["m"], st["xg"], st["t"]
    I_h = st["I_O"] + m * (t ** 2 - 2 * xg * t)       # parallel axes: O → (t, 0)
    return np.sqrt(2 * Wm * I_h) / (m * st["zg"]), th, Wm, I_h


def vnorm_real(case: Case, kind: str, lam, tanpsi: float | None = None):
    """v̄_g/√(g b) per λ (NaN where the part would crush: w > b)."""
    st = _state(case, kind, lam, tanpsi)
    return _velocity(case, kind, st)[0] / math.sqrt(case.wall.g * case.wall.b)


def multiplier_real(case: Case, kind: str, lam, tanpsi: float | None = None,
                    floor_mass: bool = False):
    """The collapse acceleration a/g at rest per λ: the resisting moment (``_moment0``) over
    the overturning moment of the body's weight pushed horizontally, m g z_G. With
    ``floor_mass`` (the floors' reading of the Circolare 2019 transcription's C8.7.1.1,
    docs/code-check.md) the floors' weights Q on the body are pushed too: + Σ Q z_Q."""
    st = _state(case, kind, lam, tanpsi)
    push = st["m"] * st["g"] * st["zg"]
    if floor_mass:
        push = push + np.sum(st["Q"] * st["zq"], axis=-1)
    return _moment0(case, kind, st) / push


def _static(case: Case, kind: str, lam_max: float, tanpsi, floor_mass: bool):
    """The static check at the smallest a/g over λ <= lam_max: (a/g, λ, the body about its
    retreated hinge or None where it crushes, the floors on it as (Q/g [kg], z_Q [m]))."""
    lam_a, a_g = minimise(lambda x, ix: multiplier_real(case, kind, np.ravel(x), tanpsi,
                                                        floor_mass).reshape(np.shape(x)),
                          np.array([lam_max]))
    lam_a = float(lam_a[0])
    sa = _state(case, kind, [lam_a], tanpsi)
    ma, xa, ta = float(sa["m"][0]), float(sa["xg"][0]), float(sa["t"][0])
    body = None if not math.isfinite(ta) else RigidBody(   # NaN: it crushes
        m=ma, x_G=xa - ta, z_G=float(sa["zg"][0]),
        I_O=float(sa["I_O"][0]) + ma * (ta ** 2 - 2 * xa * ta), J_z=float(sa["Jz"][0]))
    floors = tuple((float(q) / sa["g"], float(z)) for q, z in zip(sa["Q"][0], sa["zq"][0])
                   if q > 0)
    return float(a_g[0]), lam_a, body, floors


@dataclass(frozen=True)
class RealMechanismResult(MechanismResult):
    """A mechanism of a real wall at its critical height (``MechanismResult`` and what the
    real wall adds: hinge_retreat t [m], the normal force N [N] on the hinge joint, the
    tie elongations at θ_m [m], the choices made)."""

    kind: str = "detachment"
    hinge_retreat: float = 0.0
    normal_force: float = math.nan
    tie_elongation: tuple = ()
    fc: float = 0.0
    choices: dict = field(default_factory=dict)

    @property
    def label(self) -> str:
        fc = "fc infinite" if not self.fc else f"fc = {self.fc / 1e6:g} MPa"
        what = {"detachment": "I  detachment",
                "crack": f"II diagonal crack tan psi={self.tanpsi or 0:.3f}",
                "overturning": "simple overturning"}[self.kind]
        return f"{what} (real wall: {fc}, docs/real-walls.md)"

    def as_dict(self) -> dict:
        d = super().as_dict()
        d.update(kind=self.kind, hinge_retreat=self.hinge_retreat,
                 normal_force=self.normal_force, tie_elongation=list(self.tie_elongation),
                 fc=self.fc, fc_infinite=not self.fc, choices=dict(self.choices))
        return d


CHOICES = {
    "per_metre": "ties and floors per metre of façade (N/m); a bay of length l carries value × l",
    "floor_mass": "only the floor's vertical load bears on the façade; its mass moves with "
                  "the building (not in I_O, not in the horizontal load)",
    "hinge_rule": "rectangular stress block of depth w = N/(fc l); rotation about its "
                     "resultant, t = w/2",
    "tie_law": "force min(k δ, T_y) until the ductility limit (0: none), then 0; the work done "
           "against it is restoring work; the static multiplier takes T_y",
    "abutment_friction_I": "the paper's eq. 9 as corrected here (analytic/NOTES.md)",
}


def _theta0(case: Case, kind: str, body) -> float | None:
    """The rotation where the simple overturning's a/g falls to zero, atan(x_G/z_G) about the
    (retreated) hinge, where its capacity curve is clean (gravity alone: no ties, no floors);
    None elsewhere (the code check's nonlinear analysis, docs/code-check.md)."""
    if kind != "overturning" or case.ties or case.floors or body is None:
        return None
    return math.atan2(body.x_G, body.z_G)


def real_mechanism(case: Case, kind: str, tanpsi: float | None = None,
                   lam: float | None = None) -> RealMechanismResult:
    """Mechanism ``kind`` (detachment I, crack II or overturning) of a real wall at its
    critical λ (the smallest v̄_g over LAM_MIN <= λ <= ``lam_bounds``), or at a given λ."""
    if kind not in KINDS:
        raise ParameterError(f"kind = {kind!r} is out of range: allowed one of {KINDS}")
    w = case.wall
    lam_max = lam_bounds(case, kind, tanpsi)
    if lam_max < LAM_MIN:
        raise ParameterError(
            f"[[floor]] restrains = true at z = {max(f.z for f in case.floors if f.restrains):g}"
            f" m leaves mechanism {kind} a body of λ <= {lam_max:.4g}: out of range: allowed "
            f"λ_max >= {LAM_MIN:g} (the body above the restraining floor)")

    def fun(x, ix):
        return vnorm_real(case, kind, np.ravel(x), tanpsi).reshape(np.shape(x))

    bad = fc_problem(case, (kind,), tanpsi)
    if bad:                          # every part crushes: nothing to minimise
        raise ParameterError(bad)
    if lam is None:
        lam, _ = minimise(fun, np.array([lam_max]))    # the parts that crush are no candidates
        lam = float(lam[0])
    st = _state(case, kind, [lam], tanpsi)
    v, th, Wm, I_h = (float(a[0]) for a in _velocity(case, kind, st))
    if not math.isfinite(v):
        need = float(st["N"][0]) / (w.b * w.l)
        raise ParameterError(f"[masonry] fc = {case.masonry.fc!r} Pa: mechanism {kind} at "
                             f"λ = {lam:.4g} crushes at its hinge (its stress block N/(fc l) "
                             f"is deeper than b); allowed fc = 0 (infinite) or fc >= N/(b l) "
                             f"= {need:.4g} Pa at this λ")
    t = float(st["t"][0])
    m, zg, xg = float(st["m"][0]), float(st["zg"][0]), float(st["xg"][0])
    body = RigidBody(m=m, x_G=xg - t, z_G=zg, I_O=I_h, J_z=float(st["Jz"][0]))
    a_g, lam_a, static_body, _ = _static(case, kind, lam_max, tanpsi, False)
    floor_static = None
    if case.floors:         # the floors' reading: their weights pushed too (docs/code-check.md)
        a_q, lam_q, body_q, floors_q = _static(case, kind, lam_max, tanpsi, True)
        if body_q is not None:
            floor_static = StaticMechanism(
                a_q, body_q, w.H - lam_q * w.b, "the body of the smallest a/g over h, the "
                "floors' weights pushed horizontally", floor_masses=floors_q)
    d = st["d"][0]
    delta = d * th if kind == "detachment" else d * math.sin(th)
    return RealMechanismResult(
        NAMES[kind], lam, lam * w.b, v / math.sqrt(w.g * w.b), v, th, Wm, body,
        tanpsi=st["t_psi"] if kind == "crack" else None, lam_max=lam_max,
        multiplier=a_g, lam_multiplier=lam_a, static_body=static_body,
        static_z0=w.H - lam_a * w.b, floor_static=floor_static, kind=kind,
        static_theta0=_theta0(case, kind, static_body),
        hinge_retreat=t, normal_force=float(st["N"][0]),
        tie_elongation=tuple(float(x) for x in delta), fc=case.masonry.fc,
        choices=dict(CHOICES))
