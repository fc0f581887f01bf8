"""The one-DOF rocker of a real wall's rigid mechanism (I, II or the simple overturning of
``closed_form.real``): gravity, floor loads, tie-rods and the hinge retreat under f_c in
eq. 1 of the paper (``rocking`` module docstring), consistent with the closed forms' W(θ).

Sign convention: φ > 0 is the outward (overturning) rotation about the pivot O, which is the
outer toe moved inwards by the hinge retreat t = N/(2 f_c l) (``closed_form.real``); x is
measured inwards from O, z upwards. W(φ) is the work done against the restraints from rest:
the potential of gravity and of the floor loads plus the work stored or dissipated in the
ties; the restoring moment is its derivative, R(φ) = dW/dφ, so that I φ̈ = Π a_g − R − sgn(φ̇) F.

Exact geometry (II, the overturning; I with ``geometry="exact"``), eq. 18's kinematics:

    W = m g (x_G sin φ + z_G (cos φ − 1)) + Σ Q (x_F sin φ + z_F (cos φ − 1)) + Σ ∫₀^δ N dδ',
    R = m g (x_G cos φ − z_G sin φ)      + Σ Q (x_F cos φ − z_F sin φ)      + Σ N(δ) d cos φ,

with a floor load Q = q l at (x_F, z_F) = (e − t, z_F − z0) from O (its vertical lift is
x_F sin φ + z_F (cos φ − 1)), a tie at d = z_T − z0 above the hinge stretched by
δ = d sin φ, N(δ) its force (``impulse.loads.tie_force``, whose integral is ``tie_work``).
Linearised (mechanism I, eq. 10, the closed forms' default): sin φ → φ, cos φ → 1 − φ²/2,
δ = d φ, so R = m g (x_G − z_G φ) + Σ Q (x_F − z_F φ) + Σ N(d φ) d and Π = m z_G; mechanism
I's abutment friction F(φ) (eq. 9, ``rocking.friction_moment_I``) is dissipative, as in
``MechanismIRocker``.

The tie is memoryless: its force is N(δ) of the current elongation, so it pulls the body back
on the return and starts from δ = 0 again on the next outward excursion. This is exact for
the first outward excursion, which is what the impulse criterion and a pulse that overturns
the body in one excursion (the rectangular pulse of the hinge check) measure; a yielded tie
would really be slack on the return and on a later excursion until δ passed its last maximum
(docs/pulses.md). A rigid-plastic tie (stiffness 0) resists with T_y from φ = 0, so the lift-off
acceleration R(0)/Π(0) is the static multiplier of the closed forms at the same λ.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..closed_form import real
from ..errors import ParameterError
from ..fields import set_fields
from ..impulse import RigidBody, peak_of
from ..impulse.loads import tie_force, tie_work
from ..params import Case
from .rocking import RESTITUTION, BodyRocker, friction_moment_I

__all__ = ["RealWallRocker"]


@dataclass(frozen=True)
class RealWallRocker(BodyRocker):
    """Mechanism ``kind`` ("detachment" I, "crack" II, "overturning") of a real wall at
    slenderness ``lam`` (default: its critical λ, ``closed_form.real.real_mechanism``)
    rocking about its retreated hinge, with the floors and ties it carries (module
    docstring). geometry: "linearised" (I's default, the closed forms' eq. 10) or "exact"
    (II's and the overturning's, which take only that); the closed forms' W(θ), θ_m and v̄_g
    are this rocker's ``work``, ``theta_m`` and ``vg_impulse`` in their own geometry."""

    case: Case
    kind: str = "overturning"
    lam: float | None = None
    tanpsi: float | None = None
    geometry: str | None = None
    restitution: float = 0.0
    name: str = ""
    two_sided: bool = field(default=False, init=False)
    body: RigidBody = field(init=False, repr=False, compare=False)
    _loads: tuple = field(init=False, repr=False, compare=False)
    _theta_m: float = field(init=False, repr=False, compare=False)

    def __post_init__(self):
        if not isinstance(self.case, Case):
            raise ParameterError(f"case = {self.case!r} is not a homlimit.params.Case")
        joint = [f"[masonry] {k} = {getattr(self.case.masonry, k)!r} Pa"
                 for k in ("cohesion", "tension") if getattr(self.case.masonry, k)]
        if joint:
            raise ParameterError(f"{', '.join(joint)}: the rockers do not take a joint "
                                 "cohesion or tension; allowed 0 Pa (docs/real-walls.md)")
        if self.kind not in real.KINDS:
            raise ParameterError(f"kind = {self.kind!r} is out of range: allowed one of "
                                 f"{real.KINDS}")
        geo = self.geometry or ("linearised" if self.kind == "detachment" else "exact")
        if geo not in ("linearised", "exact") or (geo == "linearised"
                                                   and self.kind != "detachment"):
            raise ParameterError(f"geometry = {self.geometry!r} is out of range: allowed "
                                 "'linearised' or 'exact' for mechanism I, 'exact' for II and "
                                 "the overturning")
        set_fields(self, geometry=geo)
        set_fields(self, restitution=RESTITUTION.check("restitution", self.restitution))
        lam = self.lam
        if lam is None:
            lam = real.real_mechanism(self.case, self.kind, self.tanpsi).lam
        st = real.mechanism_state(self.case, self.kind, [float(lam)], self.tanpsi)
        t = float(st["t"][0])
        if not math.isfinite(t):
            raise ParameterError(f"[masonry] fc = {self.case.masonry.fc!r} Pa: mechanism "
                                 f"{self.kind} at λ = {lam:.4g} crushes at its hinge; allowed "
                                 "a larger fc")
        m, xg = float(st["m"][0]), float(st["xg"][0])
        body = RigidBody(m=m, x_G=xg - t, z_G=float(st["zg"][0]),
                         I_O=float(st["I_O"][0]) + m * (t * t - 2 * xg * t),
                         J_z=float(st["Jz"][0]))
        if body.x_G <= 0:
            raise ParameterError(f"x_G = {body.x_G!r} m is out of range: the hinge retreat "
                                 "leaves the body no restoring lever, allowed 0 < x_G")
        on_f = st["Q"][0] > 0
        floors = tuple(zip(st["Q"][0][on_f], st["e"][0][on_f] - t, st["zq"][0][on_f]))
        on_t = st["d"][0] > 0
        ties = tuple(zip(*(st[k][0][on_t] for k in ("T", "k", "du", "d"))))
        set_fields(self, lam=float(lam))
        set_fields(self, tanpsi=float(st["t_psi"]) if self.kind == "crack" else None)
        set_fields(self, body=body)
        set_fields(self, _loads=(tuple(tuple(map(float, f)) for f in floors),
                             tuple(tuple(map(np.float64, x)) for x in ties)))
        set_fields(self, name=self.name or real.NAMES[self.kind])
        if self.kind == "detachment" and geo == "exact":
            theta_m = peak_of(self.work)
        else:                             # the closed forms' own peak search
            theta_m = float(real.theta_m_real(self.case, self.kind, [self.lam],
                                              self.tanpsi)[0][0])
        set_fields(self, _theta_m=theta_m)

    # -- parameters
    @property
    def g(self):
        return self.case.wall.g

    @property
    def floors(self) -> tuple:
        """(Q [N], x_F [m], z_F [m]) of each floor load on the body, from the pivot."""
        return self._loads[0]

    @property
    def ties(self) -> tuple:
        """(T_y [N], k [N/m], δ_u [m], d [m]) of each tie in the body."""
        return self._loads[1]

    @property
    def exact(self) -> bool:
        return self.geometry == "exact"

    @property
    def has_friction(self):
        return self.kind == "detachment"

    def _delta(self, phi, d):
        return d * (np.sin(phi) if self.exact else phi)

    # -- eq. 1 terms (vectorised over φ; Π(φ) is the body's: BodyRocker.excitation)
    def restoring(self, phi):
        phi = np.asarray(phi, dtype=float)
        b, g = self.body, self.g
        if self.exact:
            c, s = np.cos(phi), np.sin(phi)
            R = b.m * g * (b.x_G * c - b.z_G * s)
            for Q, x, z in self.floors:
                R = R + Q * (x * c - z * s)
        else:
            c = 1.0
            R = b.m * g * (b.x_G - b.z_G * phi)
            for Q, x, z in self.floors:
                R = R + Q * (x - z * phi)
        for T, k, du, d in self.ties:
            R = R + tie_force(self._delta(phi, d), T, k, du) * d * c
        return R

    def friction(self, phi):
        if self.kind != "detachment":
            return np.zeros_like(np.asarray(phi, dtype=float))
        w, mas = self.case.wall, self.case.masonry
        return friction_moment_I(phi, self.lam * w.b, mas.c, mas.a, mas.f, w.s, w.gamma, w.g)

    def friction_work(self, phi):
        """D(φ) = ∫₀^φ F dφ' [J]: mechanism I's abutment friction (eq. 9 integrated)."""
        phi = np.asarray(phi, dtype=float)
        if self.kind != "detachment":
            return np.zeros_like(phi)
        return real.friction_work_I(self.case, self.lam, phi)

    def work(self, phi):
        phi = np.asarray(phi, dtype=float)
        b, g = self.body, self.g
        if self.exact:
            s, c1 = np.sin(phi), np.cos(phi) - 1.0
        else:
            s, c1 = phi, -0.5 * phi ** 2
        W = b.m * g * (b.x_G * s + b.z_G * c1)
        for Q, x, z in self.floors:
            W = W + Q * (x * s + z * c1)
        for T, k, du, d in self.ties:
            W = W + tie_work(np.maximum(self._delta(phi, d), 0.0), T, k, du)
        return W + self.friction_work(phi)

    def terms(self, phi):
        return (float(self.excitation(phi)), float(self.restoring(phi)),
                float(self.friction(phi)))

    def describe(self) -> dict:
        return {**super().describe(), "kind": self.kind, "lam": self.lam,
                "geometry": self.geometry, "floors": [list(f) for f in self.floors],
                "ties": [list(x) for x in self.ties]}

