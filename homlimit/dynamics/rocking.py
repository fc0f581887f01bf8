"""One-degree-of-freedom equations of motion of every mechanism kind the project produces.

A failing body (or a mechanism shape) turns by φ about its pivot O; φ > 0 is the outward,
overturning rotation (towards −x). With the ground accelerating at a_g(t) (positive: towards
+x, so the inertia pushes the body outwards) eq. 1 of the paper, at finite rotation and
without viscous damping, reads

    I φ̈ = Π(φ) a_g(t) − R(φ) − sgn(φ̇) F(φ)                                      (1)

- I [kg m²]: polar inertia about O (generalised mass M of a mechanism shape);
- Π(φ) [kg m]: excitation factor, the moment of the inertia force per unit a_g
  (m z_G at φ = 0, eq. 1);
- R(φ) [N m]: restoring moment of gravity, dV/dφ (conservative);
- F(φ) >= 0 [N m]: a friction moment that always opposes the motion (mechanism I's
  abutment, eqs 8–9); the body sticks while φ̇ = 0 and |Π a_g − R| <= F.

W(φ) = ∫₀^φ (R + F) dφ' is the restoring work of an outward motion from rest (eq. 10 for
mechanism I, eq. 18 for a rigid body); it peaks at θ_m, where R + F changes sign, and
W_m = W(θ_m). The short-pulse limit of (1) is eqs 2–7: v̄_g = √(2 W_m I) / Π(0).

Rockers (all frozen dataclasses, parameters validated):
- ``RigidRocker``: any ``homlimit.impulse.RigidBody`` (mechanism II, the FE body); exact
  geometry by default, or gravity and excitation linearised in φ (``geometry="linearised"``);
  ``two_sided=True`` with ``free_block`` for a free-standing block (no transversal wall)
  that rocks about both toes, with Housner's impact.
- ``MechanismIRocker``: the façade strip of mechanism I with the abutment friction of eq. 9;
  gravity linearised as in eq. 10 (default) or exact.
- ``GeneralisedRocker``: the one-DOF generalisation of ``homlimit.mechanism.fe_impulse``
  (``GeneralisedImpulse``): generalised mass M, excitation Π, the block inside the 50 % line
  at exact geometry, the rest's lift linearised.

Attached mechanisms (I, II, FE) rock on one side only: at φ = 0 the body hits its seat and
rebounds with φ̇⁺ = −e φ̇⁻, e = ``restitution`` (default 0: it re-seats and stays until the
ground lifts it again). A two-sided block changes pivot at φ = 0 and keeps turning with
angular velocity e φ̇⁻ (Housner 1963).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from scipy.optimize import brentq

from ..closed_form.mechanisms import mechanism_I, work_I
from ..errors import ParameterError, check_range
from ..fields import Range, check_fields, ranged, set_fields
from ..impulse import LoadWork, RigidBody, peak_with_loads, peak_work, work_with_loads
from ..params import G_STANDARD, Case

__all__ = ["Rocker", "BodyRocker", "RigidRocker", "MechanismIRocker", "GeneralisedRocker",
           "free_block", "housner_restitution", "friction_moment_I", "THETA_FALL"]

THETA_FALL = math.pi / 2  # rad: the body lies on the ground; overturned whatever follows


RESTITUTION = Range(0.0, 1.0)    # a coefficient of restitution


def _restitution(e) -> float:
    return RESTITUTION.check("restitution", e)


def _geometry(value) -> str:
    if value not in ("exact", "linearised"):
        raise ParameterError(f"geometry = {value!r} is out of range: allowed 'exact' or "
                             "'linearised'")
    return value


class Rocker:
    """Common behaviour of the one-degree-of-freedom rockers (module docstring, eq. 1).

    Subclasses provide: name, inertia I, theta_m, W_m, two_sided, restitution, g and the
    vectorised functions excitation Π(φ), restoring R(φ), friction F(φ), work W(φ), and p.
    """

    name: str
    inertia: float
    theta_m: float
    W_m: float
    two_sided: bool
    restitution: float
    g: float

    def excitation(self, phi):  # pragma: no cover - abstract
        raise NotImplementedError

    def restoring(self, phi):  # pragma: no cover
        raise NotImplementedError

    def friction(self, phi):
        """F(φ) >= 0 [N m]; no friction unless a subclass has it."""
        return np.zeros_like(np.asarray(phi, dtype=float))

    def work(self, phi):  # pragma: no cover
        raise NotImplementedError

    def terms(self, phi: float) -> tuple[float, float, float]:
        """(Π, R, F) at one rotation φ, as floats (the integrator's hot path)."""
        return (float(self.excitation(phi)), float(self.restoring(phi)),
                float(self.friction(phi)))

    @property
    def p(self) -> float:  # pragma: no cover
        raise NotImplementedError

    @property
    def has_friction(self) -> bool:
        return False

    @property
    def vg_impulse(self) -> float:
        """Eq. 7 with this rocker's I, Π(0) and W_m: v̄_g = √(2 W_m I) / Π(0) [m/s]."""
        return math.sqrt(2.0 * self.W_m * self.inertia) / float(self.excitation(0.0))

    @property
    def a_uplift(self) -> float:
        """Ground acceleration that starts the motion from rest: (R(0) + F(0)) / Π(0) [m/s²]."""
        return float((self.restoring(0.0) + self.friction(0.0)) / self.excitation(0.0))

    @property
    def theta_fall(self) -> float:
        return THETA_FALL

    def energy(self, phi, phi_dot):
        """Φ = ½ I φ̇² + W(φ) [J]: after the pulse it can only decrease (friction, impacts),
        so Φ < W_m means the body can no longer overturn, and Φ >= W_m while moving outward
        below θ_m means it will."""
        return 0.5 * self.inertia * np.asarray(phi_dot) ** 2 + self.work(phi)

    def describe(self) -> dict:
        return {"name": self.name, "inertia": self.inertia, "theta_m": self.theta_m,
                "W_m": self.W_m, "p": self.p, "vg_impulse": self.vg_impulse,
                "a_uplift": self.a_uplift, "two_sided": self.two_sided,
                "restitution": self.restitution}


# --------------------------------------------------------------------------- rigid bodies
class BodyRocker(Rocker):
    """A rigid ``body`` (m, x_G, z_G, I_O about its pivot) rocking on its pivot: its inertia,
    p, the excitation Π(φ) and gravity's moment and work, at finite rotation (``exact``) or
    linearised (eq. 10); θ_m, unless a subclass derives it, is kept as ``_theta_m``
    (RigidRocker, MechanismIRocker and the real walls' RealWallRocker)."""

    @property
    def inertia(self):
        return self.body.I_O

    @property
    def theta_m(self):
        return self._theta_m

    @property
    def W_m(self):
        return float(self.work(self._theta_m))

    @property
    def p(self):
        """Frequency parameter p = √(m g r_G / I_O) [rad/s] (Housner 1963)."""
        bd = self.body
        return math.sqrt(bd.m * self.g * bd.r_G / bd.I_O)

    def excitation(self, phi):
        b = self.body
        if self.exact:
            return b.m * (b.z_G * np.cos(phi) + b.x_G * np.sin(phi))
        return b.m * b.z_G + 0.0 * np.asarray(phi, dtype=float)

    def gravity_moment(self, phi):
        """R of gravity: m g (x_G cos φ − z_G sin φ), linearised m g (x_G − z_G φ) [N m]."""
        b = self.body
        if self.exact:
            return b.m * self.g * (b.x_G * np.cos(phi) - b.z_G * np.sin(phi))
        return b.m * self.g * (b.x_G - b.z_G * np.asarray(phi, dtype=float))

    def gravity_work(self, phi):
        """W of gravity: m g (x_G sin φ + z_G (cos φ − 1)), linearised m g (x_G φ − z_G φ²/2)
        [J]."""
        b = self.body
        phi = np.asarray(phi, dtype=float)
        if self.exact:
            return b.m * self.g * (b.x_G * np.sin(phi) + b.z_G * (np.cos(phi) - 1.0))
        return b.m * self.g * (b.x_G * phi - 0.5 * b.z_G * phi ** 2)


@dataclass(frozen=True)
class RigidRocker(BodyRocker):
    """A rigid body (m, x_G, z_G, I_O about its pivot O) rocking on O, restrained by gravity.

    geometry = "exact": Π = m (z_G cos φ + x_G sin φ), R = m g (x_G cos φ − z_G sin φ),
    W = m g (x_G sin φ + z_G cos φ − z_G), θ_m = atan(x_G/z_G), W_m = m g (r_G − z_G) (eq. 18).
    geometry = "linearised": Π = m z_G, R = m g (x_G − z_G φ), W = m g (x_G φ − z_G φ²/2),
    θ_m = x_G/z_G, W_m = m g x_G²/(2 z_G) (the gravity work of eq. 10).
    two_sided: the body rocks on both toes (a body symmetric about the vertical through G,
    e.g. ``free_block``); otherwise it is attached and rocks outwards only.
    """

    body: RigidBody
    g: float = ranged(0.0, lo_open=True, unit="m/s^2", default=G_STANDARD)
    geometry: str = "exact"
    restitution: float = ranged(RESTITUTION, default=0.0)
    two_sided: bool = False
    name: str = "rigid body"

    def __post_init__(self):
        if not isinstance(self.body, RigidBody):
            raise ParameterError(f"body = {self.body!r} is not a homlimit.impulse.RigidBody")
        if self.body.x_G <= 0:
            raise ParameterError(f"x_G = {self.body.x_G!r} m is out of range: a rocking body "
                                 "needs a restoring lever, allowed 0 < x_G")
        check_fields(self)
        set_fields(self, geometry=_geometry(self.geometry), two_sided=bool(self.two_sided))

    @property
    def exact(self) -> bool:
        return self.geometry == "exact"

    @property
    def theta_m(self):
        b = self.body
        return math.atan2(b.x_G, b.z_G) if self.exact else b.x_G / b.z_G

    @property
    def W_m(self):
        b = self.body
        if self.exact:
            return b.m * self.g * (b.r_G - b.z_G)
        return b.m * self.g * b.x_G ** 2 / (2 * b.z_G)

    def restoring(self, phi):
        return self.gravity_moment(phi)

    def work(self, phi):
        return self.gravity_work(phi)

    def terms(self, phi):
        b = self.body
        if self.exact:
            c, s = math.cos(phi), math.sin(phi)
            return (b.m * (b.z_G * c + b.x_G * s), b.m * self.g * (b.x_G * c - b.z_G * s), 0.0)
        return b.m * b.z_G, b.m * self.g * (b.x_G - b.z_G * phi), 0.0

    def hinge_force(self, phi, phi_dot, phi_ddot, a_g):
        """Pivot reaction on the body (P_x, P_z) [N] from Newton's law for G in the frame
        where O accelerates at a_g: P = m (a_G + a_g x̂) + m g ẑ, exact geometry. P_x < 0
        pushes the body outwards; the pivot holds without sliding while |P_x| <= f P_z
        (the joint's friction f)."""
        b = self.body
        c, s = np.cos(phi), np.sin(phi)
        xdd = -phi_ddot * (b.x_G * s + b.z_G * c) - phi_dot ** 2 * (b.x_G * c - b.z_G * s)
        zdd = phi_ddot * (b.x_G * c - b.z_G * s) - phi_dot ** 2 * (b.x_G * s + b.z_G * c)
        return b.m * (xdd + a_g), b.m * (zdd + self.g)


    def hinge_ratio_at_rest(self, a_g):
        """|P_x| / P_z at the pivot the instant a ground acceleration a_g [m/s²] lifts the body
        from rest (φ = φ̇ = 0): φ̈ = m (z_G a_g − g x_G) / I_O, P_x = m (a_g − z_G φ̈),
        P_z = m (g + x_G φ̈). For a_g → ∞ (the ideal impulse) it tends to
        (i − z_G²) / (x_G z_G), i = I_O/m (mechanics.md)."""
        b = self.body
        a_g = np.asarray(a_g, dtype=float)
        phidd = b.m * (b.z_G * a_g - self.g * b.x_G) / b.I_O
        return np.abs(a_g - b.z_G * phidd) / (self.g + b.x_G * phidd)


def housner_restitution(body: RigidBody) -> float:
    """Housner's coefficient of restitution e = φ̇⁺/φ̇⁻ = 1 − 2 m x_G² / I_O of a body
    symmetric about the vertical through G, from the angular momentum about the new pivot
    (at 2 x_G from the old) kept through the impact; for a rectangular block
    e = 1 − (3/2) sin² α."""
    return 1.0 - 2.0 * body.m * body.x_G ** 2 / body.I_O


def free_block(b: float, h: float, density: float = 2000.0, g: float = G_STANDARD,
               restitution: float | None = None, geometry: str = "exact") -> RigidRocker:
    """A free-standing rectangular block of width b and height h [m] (per unit thickness,
    ``density`` [kg/m³]) rocking about either bottom corner; slenderness α = atan(b/h),
    half-diagonal R = √(b² + h²)/2, p = √(3g / (4R)). restitution: default Housner's
    e = 1 − (3/2) sin² α."""
    b = check_range("b", b, 0.0, lo_open=True, unit="m")
    h = check_range("h", h, 0.0, lo_open=True, unit="m")
    density = check_range("density", density, 0.0, lo_open=True, unit="kg/m^3")
    m = density * b * h
    body = RigidBody(m=m, x_G=b / 2, z_G=h / 2, I_O=m * (b * b + h * h) / 3, J_z=m * h * h / 3)
    e = housner_restitution(body) if restitution is None else restitution
    return RigidRocker(body, g=g, geometry=geometry, restitution=e, two_sided=True,
                       name=f"free block {b:g} x {h:g} m")


# --------------------------------------------------------------------------- mechanism I
def friction_moment_I(phi, h, c, a, f, s, gamma, g=G_STANDARD):
    """Moment of the abutment friction of mechanism I about the toe, F(φ) [N m] (eq. 9):

        F = (g γ s f / a) ∫₀^{min(h, c/φ)} (h − z)(c − φ z) z dz
          = g γ s f h³ (2c − hφ) / (12 a)        for φ < c/h,
          = g γ s f c³ (2hφ − c) / (12 a φ³)     for φ >= c/h,

    with the paper's linearised kinematics u(z) = φ z (eq. 8: friction acts on the
    overlap c − u of the abutment joints; joints with u >= c have separated)."""
    phi = np.asarray(phi, dtype=float)
    k = g * gamma * s * f / (12.0 * a)
    with np.errstate(divide="ignore", invalid="ignore"):
        right = k * c ** 3 * (2 * h * phi - c) / phi ** 3
    return np.where(phi * h < c, k * h ** 3 * (2 * c - h * phi), right)


@dataclass(frozen=True)
class MechanismIRocker(BodyRocker):
    """Mechanism I (the façade strip of height h = λ b detaching from the transversal wall),
    rocking about its outer toe, restrained by gravity and by the abutment friction of eq. 9,
    which opposes the motion in both directions (dissipative).

    Linearised (the paper's, eq. 10; ``gravity="linearised"``): Π = m z_G, R = m g (b/2 − hφ/2),
    W = eq. 10, θ_m = ``mechanisms.theta_m_I`` (the exact maximiser of eq. 10), so the
    short-pulse limit is ``mechanism_I(case).vg``. Exact (``gravity="exact"``): the rigid
    strip's Π, R, V at finite rotation; θ_m the root of R + F. In both, the friction keeps the
    paper's linearised kinematics u(z) = φ z (``friction_moment_I``).

    lam: slenderness λ = h/b of the failing part (default: the critical λ of eq. 7).
    """

    case: Case
    lam: float | None = None
    gravity: str = "linearised"
    restitution: float = 0.0
    name: str = "I"
    two_sided: bool = field(default=False, init=False)
    _res: object = field(init=False, repr=False, compare=False)
    _theta_m: float = field(init=False, repr=False, compare=False)

    def __post_init__(self):
        if not isinstance(self.case, Case):
            raise ParameterError(f"case = {self.case!r} is not a homlimit.params.Case")
        set_fields(self, gravity=_geometry(self.gravity),
                   restitution=_restitution(self.restitution))
        res = mechanism_I(self.case, self.lam)
        set_fields(self, _res=res, lam=res.lam)
        set_fields(self, _theta_m=res.theta_m if self.gravity == "linearised"
                   else self._exact_theta_m())          # reads _res and lam

    # -- parameters
    @property
    def g(self):
        return self.case.wall.g

    @property
    def h(self):
        return self._res.h

    @property
    def body(self) -> RigidBody:
        return self._res.body

    @property
    def has_friction(self):
        return True

    @property
    def exact(self) -> bool:
        return self.gravity == "exact"

    # -- eq. 1 terms
    def restoring(self, phi):
        return self.gravity_moment(phi)

    def friction(self, phi):
        w, mas = self.case.wall, self.case.masonry
        return friction_moment_I(phi, self.h, mas.c, mas.a, mas.f, w.s, w.gamma, w.g)

    def terms(self, phi):
        bd, w, mas = self.body, self.case.wall, self.case.masonry
        if self.gravity == "exact":
            c, s = math.cos(phi), math.sin(phi)
            Pi, R = bd.m * (bd.z_G * c + bd.x_G * s), bd.m * self.g * (bd.x_G * c - bd.z_G * s)
        else:
            Pi, R = bd.m * bd.z_G, bd.m * self.g * (bd.x_G - bd.z_G * phi)
        h, cc = self.h, mas.c
        k = w.g * w.gamma * w.s * mas.f / (12.0 * mas.a)
        F = k * h ** 3 * (2 * cc - h * phi) if phi * h < cc else \
            k * cc ** 3 * (2 * h * phi - cc) / phi ** 3
        return Pi, R, F

    def friction_work(self, phi):
        """D(φ) = ∫₀^φ F dφ' [J]: the friction term of eq. 10 (``mechanisms.work_I`` less its
        linearised gravity)."""
        c = self.case
        w = c.wall
        phi = np.asarray(phi, dtype=float)
        total = work_I(phi, self.lam, c.rho, c.alpha, c.beta) * w.g * w.gamma * w.s * w.b ** 3
        bd = self.body
        return total - bd.m * self.g * (bd.x_G * phi - 0.5 * bd.z_G * phi ** 2)

    def work(self, phi):
        return self.gravity_work(phi) + self.friction_work(phi)

    def _exact_theta_m(self) -> float:
        """First sign change of R + F (the peak of W) on 0 < φ < π/2, refined by brentq."""
        grid = np.linspace(1e-9, THETA_FALL, 4001)
        dw = self.restoring(grid) + self.friction(grid)
        k = int(np.argmax(dw < 0))
        if dw[k] >= 0:
            raise ParameterError("gravity = 'exact': R + F has no sign change below pi/2")
        return brentq(lambda t: float(self.restoring(t) + self.friction(t)), grid[k - 1],
                      grid[k], xtol=1e-15, rtol=1e-14)


# --------------------------------------------------------------------------- one-DOF shape
@dataclass(frozen=True)
class GeneralisedRocker(Rocker):
    """The one-DOF generalisation of eqs 4–7 for a mechanism shape (``fe_impulse``): the
    block inside the 50 % participation line (``block``, about O) turns by q exactly; the rest
    of the moving material is carried linearly.

    I = M [kg m²] (generalised mass ∫ρ|φ|²), Π(q) = (Pi − m_b z_G) + m_b (z_G cos q + x_G sin q)
    (Pi = ∫ρ(−φ_x) [kg m] at q = 0; the rest's share stays linear),
    R(q) = m_b g (x_G cos q − z_G sin q) + L + R_loads(q),
    W(q) = m_b g (x_G sin q + z_G (cos q − 1)) + L q + W_loads(q),
    with L [N m] the rest's linearised lift and ``load_work`` (``impulse.LoadWork``, None
    without) a real wall's floors and ties (issue 30): W_loads their parts of W(q), R_loads =
    dW_loads/dq, the expressions of the FE impulse criterion (``fe_impulse``), so R = dW/dq.
    R vanishes at q_m, the peak of W over 0 <= q <= π/2 (``impulse.peak_work``; with loads
    ``impulse.peak_with_loads``, the criterion's own search), which makes W(q_m) the
    ``GeneralisedImpulse.W_m`` and ``vg_impulse`` its v̄_g. Ties are memoryless (their force
    follows the current opening, as ``real_rocker.RealWallRocker``'s): exact over the first
    outward excursion, which the impulse criterion and the hinge check's pulse measure.
    """

    M: float
    Pi: float = ranged(0.0, lo_open=True, unit="kg m")
    block: RigidBody
    lift_rest: float = ranged(0.0, unit="N m", default=0.0)
    g: float = ranged(0.0, lo_open=True, unit="m/s^2", default=G_STANDARD)
    restitution: float = ranged(RESTITUTION, default=0.0)
    name: str = "FE one-DOF"
    load_work: LoadWork | None = None
    two_sided: bool = field(default=False, init=False)
    _peak: tuple = field(init=False, repr=False, compare=False)

    def __post_init__(self):
        if not isinstance(self.block, RigidBody):
            raise ParameterError(f"block = {self.block!r} is not a homlimit.impulse.RigidBody")
        if self.load_work is not None and not isinstance(self.load_work, LoadWork):
            raise ParameterError(f"load_work = {self.load_work!r} is not a "
                                 "homlimit.impulse.LoadWork")
        if not self.load_work:
            set_fields(self, load_work=None)
        if self.block.x_G <= 0 and self.load_work is None:
            raise ParameterError(f"x_G = {self.block.x_G!r} m is out of range: the block needs "
                                 "a restoring lever, allowed 0 < x_G")
        set_fields(self, M=check_range("M", self.M, self.block.I_O * (1 - 1e-9), unit="kg m^2"))
        check_fields(self)       # Pi, lift_rest, g, restitution
        if self.load_work is None:
            peak = peak_work(self.block, self.lift_rest, self.g)
        else:                    # W(q_m) > 0, else a ParameterError
            peak = peak_with_loads(self.block, self.lift_rest, self.load_work, self.g)
        set_fields(self, _peak=peak)

    @classmethod
    def from_impulse(cls, gi, g: float = G_STANDARD, restitution: float = 0.0,
                     name: str = "FE one-DOF") -> GeneralisedRocker:
        """From a ``fe_impulse.GeneralisedImpulse`` (its block, lift L and, with ties or
        floors, their ``load_work``)."""
        return cls(gi.M, gi.Pi, gi.block, gi.lift_rest, g=g, restitution=restitution,
                   name=name, load_work=getattr(gi, "load_work", None))

    @property
    def inertia(self):
        return self.M

    @property
    def theta_m(self):
        return self._peak[0]

    @property
    def W_m(self):
        return float(self.work(self.theta_m))

    @property
    def p(self):
        """p = √(m_b g r_G / M) [rad/s]."""
        return math.sqrt(self.block.m * self.g * self.block.r_G / self.M)

    def excitation(self, phi):
        b = self.block
        return self.Pi - b.m * b.z_G + b.m * (b.z_G * np.cos(phi) + b.x_G * np.sin(phi))

    def terms(self, phi):
        b = self.block
        c, s = math.cos(phi), math.sin(phi)
        R = b.m * self.g * (b.x_G * c - b.z_G * s) + self.lift_rest
        if self.load_work is not None:
            R += float(self.load_work.moment(phi))
        return self.Pi - b.m * b.z_G + b.m * (b.z_G * c + b.x_G * s), R, 0.0

    def restoring(self, phi):
        b = self.block
        phi = np.asarray(phi, dtype=float)
        R = b.m * self.g * (b.x_G * np.cos(phi) - b.z_G * np.sin(phi)) + self.lift_rest
        return R if self.load_work is None else R + self.load_work.moment(phi)

    def work(self, phi):
        if self.load_work is not None:
            return work_with_loads(self.block, self.lift_rest, self.load_work, self.g, phi)
        b = self.block
        phi = np.asarray(phi, dtype=float)
        return (b.m * self.g * (b.x_G * np.sin(phi) + b.z_G * (np.cos(phi) - 1.0))
                + self.lift_rest * phi)
