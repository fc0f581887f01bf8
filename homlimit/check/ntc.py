"""The linear kinematic analysis of a local mechanism, NTC 2018 / Circolare 2019 §C8.7.1.2
(the 2009 Circolare's §C8A.4.2 in the same form), for one rigid body turning about its hinge.

- α₀: the collapse multiplier of the horizontal load α P by virtual work (the mechanism's
  static multiplier, with the ties, floors and f_c its model takes: docs/real-walls.md);
- the participating mass M* = (Σ P_i δx_i)² / (g Σ P_i δx_i²), δx_i the virtual horizontal
  displacement of weight P_i. For a body turning by δθ about O, δx = δθ (z − z_O), so with
  the body's participation integrals (``impulse.RigidBody``: ∫dm = m, ∫(z − z_O) dm = m z_G,
  ∫(z − z_O)² dm = J_z) the sum becomes the integral M* = (m z_G)²/J_z;
- e* = g M*/Σ P_i = M*/m, the participating fraction;
- a₀* = α₀ Σ P_i/(M* FC) = α₀ g/(e* FC), the spectral acceleration that activates the
  mechanism [m/s²].

Readings (docs/code-check.md): the ratio uses e* of the continuous integration above (the
2009 form, 3/4 for a uniform rectangular block about its toe); beside it the lumped reading,
each block's weight at its centre of gravity, gives e* = 1 for a single rigid body (a₀*
smaller by the factor e*: the conservative side). The demand is the larger of the ground
check a_g S/q and, where the mechanism's base is above the ground (Z > 0), the check at
height S_e(T₁) ψ(Z) γ/q (``site.Site``).

The floors' reading (docs/code-check.md, reading 3): a public transcription of the Circolare
2019 (C8.7.1.1, C8.7.1.5) adds the weights Q_k the blocks carry (the floors) to α₀'s
horizontal virtual work and to the sums of M* and e*. A ``StaticMechanism`` in that reading
carries those weights as point masses (``floor_masses``: m_k = Q_k/g at height z_k above the
hinge, δx_k = δθ z_k), and its α₀ counts them; ``participation`` then sums body and floors:
M* = (m z_G + Σ m_k z_k)²/(J_z + Σ m_k z_k²), e* = M*/(m + Σ m_k).
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np

from ..errors import ParameterError
from ..impulse import RigidBody
from .site import Site

__all__ = ["LinearKinematic", "NonlinearKinematic", "StaticMechanism", "linear_kinematic",
           "nonlinear_kinematic", "participation", "participation_lumped"]


@dataclass(frozen=True)
class StaticMechanism:
    """What the code check needs of a mechanism: its static multiplier α₀ = a/g, the body it
    moves (about its hinge, with J_z), the hinge's height above the wall's base [m], and a
    word on which body it is.

    floor_masses: rows (m_k [kg], z_k [m] above the hinge) of the weights Q_k = m_k g the
    body carries and pushes horizontally besides its own (the floors' reading of the
    transcription's C8.7.1.1/.5; empty in the package's own reading, where α₀ does not push
    them). floor_reading: the same mechanism in that reading (its own α₀, body and
    floor_masses: the height of its smallest multiplier may differ), where the model computes
    it; None where it does not."""

    alpha0: float
    body: RigidBody
    z_hinge: float
    what: str = ""
    floor_masses: tuple = ()
    floor_reading: StaticMechanism | None = None
    theta0: float | None = None


def participation(body: RigidBody, floor_masses=()) -> tuple[float, float]:
    """(M*, e*) of a rigid body turning about its hinge: M* = (∫z dm)²/∫z² dm = (m z_G)²/J_z
    (the mass's unit: kg, or kg/m for a body per unit thickness), e* = M*/m <= 1. With
    ``floor_masses`` (rows m_k, z_k above the hinge: the floors' reading) the point masses
    join the sums: M* = (m z_G + Σ m_k z_k)²/(J_z + Σ m_k z_k²), e* = M*/(m + Σ m_k)."""
    if not math.isfinite(body.J_z):
        raise ParameterError(f"J_z = {body.J_z!r} is out of range: the code check needs the "
                             "body's ∫z² dm about its hinge (a finite number)")
    mk, zk = _floor_rows(floor_masses)
    M = float((body.m * body.z_G + mk @ zk) ** 2 / (body.J_z + mk @ zk ** 2))
    return M, float(M / (body.m + mk.sum()))


def _floor_rows(floor_masses) -> tuple[np.ndarray, np.ndarray]:
    rows = np.asarray(floor_masses, float).reshape(-1, 2)
    if not (np.all(np.isfinite(rows)) and np.all(rows[:, 0] >= 0)):
        raise ParameterError(f"floor_masses = {floor_masses!r} is out of range: allowed rows "
                             "(m_k >= 0 kg, z_k m above the hinge), finite")
    return rows[:, 0], rows[:, 1]


def participation_lumped(body: RigidBody, floor_masses=()) -> tuple[float, float]:
    """(M*, e*) with the body's weight lumped at its G (one P_i per block; e* = 1 without
    floors), the floors as point masses: ``participation`` of the same body with J_z = m z_G²,
    M* = (m z_G + Σ m_k z_k)²/(m z_G² + Σ m_k z_k²)."""
    return participation(dataclasses.replace(body, J_z=body.m * body.z_G ** 2), floor_masses)


class _Verdict:
    """A check's verdict, capacity/demand ``ratio`` >= 1, and its fields as a dict."""

    @property
    def passes(self) -> bool:
        return self.ratio >= 1.0

    def as_dict(self) -> dict:
        d = {k: getattr(self, k) for k in self.__dataclass_fields__}
        d["passes"] = self.passes
        return d


@dataclass(frozen=True)
class LinearKinematic(_Verdict):
    """The linear kinematic check of one mechanism (``linear_kinematic``).

    alpha0 [-]; m [kg] (ΣP/g, the floors' masses included in the floors' reading);
    m_floors [kg] (Σ m_k: 0 in the package's own reading); M_star [kg]; e_star [-]
    (continuous integration, used); a0_star [m/s²]; e_star_lumped [-] (weights lumped at the
    body's G: 1 without floor masses) and
    a0_star_lumped [m/s²]; Z [m] the mechanism's base above the ground; demand_ground =
    a_g S/q, demand_height = S_e(T₁) ψ γ/q (None at Z = 0) with first_period T₁ [s],
    Se_T1 [m/s²], psi_Z = Z/H, gamma_N = 3N/(2N + 1); demand [m/s²] the larger; ratio =
    a0_star/demand (>= 1: the check is met) and
    ratio_lumped = a0_star_lumped/demand.
    """

    name: str
    what: str
    alpha0: float
    m: float
    m_floors: float
    M_star: float
    e_star: float
    a0_star: float
    e_star_lumped: float
    a0_star_lumped: float
    Z: float
    demand_ground: float
    demand_height: float | None
    first_period: float
    Se_T1: float
    psi_Z: float
    gamma_N: float
    demand: float
    ratio: float
    ratio_lumped: float


def linear_kinematic(name: str, sm: StaticMechanism, site: Site,
                     wall_H: float) -> LinearKinematic:
    """The §C8.7.1.2 check of mechanism ``name`` (its ``StaticMechanism``) at ``site``, on a
    wall of height ``wall_H`` [m] whose base is ``site.z_base`` above the ground."""
    if not (math.isfinite(sm.alpha0) and sm.alpha0 > 0):
        raise ParameterError(f"alpha0 = {sm.alpha0!r} of mechanism {name} is out of range: "
                             "allowed a finite 0 < alpha0")
    M, e = participation(sm.body, sm.floor_masses)
    e_lumped = participation_lumped(sm.body, sm.floor_masses)[1]
    m_floors = float(_floor_rows(sm.floor_masses)[0].sum())
    g = site.g
    a0 = sm.alpha0 * g / (e * site.FC)
    a0_lumped = sm.alpha0 * g / (e_lumped * site.FC)
    Z = site.z_base + sm.z_hinge
    ground = site.demand_ground()
    T1 = site.first_period(wall_H)
    height, Se, psi, gam = site.demand_height(Z, wall_H)
    at_height = height if Z > 0 else None
    demand = max(ground, height) if Z > 0 else ground
    return LinearKinematic(name, sm.what, sm.alpha0, sm.body.m + m_floors, m_floors, M, e, a0,
                           e_lumped, a0_lumped, Z,
                           ground, at_height, T1, Se, psi, gam, demand, a0 / demand,
                           a0_lumped / demand)


@dataclass(frozen=True)
class NonlinearKinematic(_Verdict):
    """The nonlinear kinematic check of one mechanism at the ground (``nonlinear_kinematic``).

    The 2009 form (C8A.4.2, used): theta0 [rad], dk0 [m] (G's horizontal displacement at
    theta0: the control point is the body's G), d0_star = dk0 J_z/(m z_G²) [m], du_star =
    0.4 d0_star, ds_star = 0.4 du_star, as_star = a0_star (1 − ds/d0) [m/s²], Ts = 2π
    √(ds/as) [s], SDe_Ts = S_De(T_s) at 5 % [m], ratio = du_star/SDe_Ts.
    Beside it the 2019 transcription's form (C8.7.1.2.1.6, .8): d_SLV = 0.4 d0_star, a_SLV =
    a0_star (1 − 0.4) [m/s²], T_SLV = 1.68π √(d_SLV/a_SLV) [s], SDe_SLV = S_De(T_SLV) at
    xi_SLV = 8 % [m], ratio_SLV = d_SLV/SDe_SLV."""

    name: str
    theta0: float
    dk0: float
    a0_star: float
    d0_star: float
    du_star: float
    ds_star: float
    as_star: float
    Ts: float
    SDe_Ts: float
    ratio: float
    d_SLV: float
    a_SLV: float
    T_SLV: float
    xi_SLV: float
    SDe_SLV: float
    ratio_SLV: float


def nonlinear_kinematic(lk: LinearKinematic, sm: StaticMechanism,
                        site: Site) -> NonlinearKinematic:
    """The nonlinear kinematic check at the ground of a mechanism whose capacity curve is
    clean (``sm.theta0``: a rigid body turning about its hinge under gravity alone), beside
    its linear check ``lk`` (its a₀*, e*). α(d_k) falls linearly from α₀ to zero at d_k,0, the
    control point G's horizontal displacement at θ₀ of the exact rigid rotation,
    x_G (1 − cos θ₀) + z_G sin θ₀; with δx ∝ z the SDOF displacement is
    d* = d_k Σ P δx²/(δx_k Σ P δx) = d_k J_z/(m z_G²) and a* = α g/(e* FC) (C8A.4.2 of 2009
    and the transcription's C8.7.1.3, .4). ParameterError where the mechanism has no θ₀ or its
    base is above the ground (the check at height is not computed)."""
    if sm.theta0 is None or not (math.isfinite(sm.theta0) and 0 < sm.theta0 < math.pi / 2):
        raise ParameterError(f"theta0 = {sm.theta0!r} of mechanism {lk.name} is out of range: "
                             "the nonlinear check needs a finite 0 < theta0 < π/2 rad")
    if lk.Z > 1e-9:
        raise ParameterError(f"Z = {lk.Z!r} m of mechanism {lk.name} is out of range: the "
                             "nonlinear check is computed at the ground only (Z = 0)")
    b, th = sm.body, sm.theta0
    dk0 = b.x_G * (1 - math.cos(th)) + b.z_G * math.sin(th)
    d0 = dk0 * b.J_z / (b.m * b.z_G ** 2)
    du, a0 = 0.4 * d0, lk.a0_star
    ds = 0.4 * du
    a_s = a0 * (1 - ds / d0)
    Ts = 2 * math.pi * math.sqrt(ds / a_s)
    dem = site.SDe(Ts)
    d_slv, a_slv, xi = 0.4 * d0, a0 * (1 - 0.4), 8.0
    T_slv = 1.68 * math.pi * math.sqrt(d_slv / a_slv)
    dem_slv = site.SDe(T_slv, xi)
    return NonlinearKinematic(lk.name, th, dk0, a0, d0, du, ds, a_s, Ts, dem, du / dem,
                              d_slv, a_slv, T_slv, xi, dem_slv, d_slv / dem_slv)
