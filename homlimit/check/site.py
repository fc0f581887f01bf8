"""The site's seismic action of NTC 2018 §3.2: the soil and topographic amplification and the
horizontal elastic response spectrum S_e(T) (eq. 3.2.2), and the building's first period.

Written from the NTC 2018 text as the package's authors know it (the text is not on this
machine; docs/code-check.md says so). Soil categories A–E give S_S and C_C by Tab. 3.2.IV
(Tab. 3.2.V of NTC 2008), topographic categories T1–T4 give S_T by Tab. 3.2.V (NTC 2008: Tab.
3.2.VI), at the top of the relief (the code lets S_T fall linearly to 1 at its base; not
taken here). Units SI: a_g in m/s², periods in s.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import ParameterError
from ..fields import check_fields, ranged

__all__ = ["C1_MASONRY", "SOILS", "Site", "TOPOGRAPHIES", "corner_periods", "elastic_spectrum",
           "soil_factors", "topography_factor"]

#: soil category → (S_S = clip(a − b F₀ a_g/g, lo, hi): a, b, lo, hi; C_C = c (T_C*)^k: c, k)
#: (NTC 2018 Tab. 3.2.IV)
SOILS = {"A": (1.00, 0.00, 1.00, 1.00, 1.00, 0.00),
         "B": (1.40, 0.40, 1.00, 1.20, 1.10, -0.20),
         "C": (1.70, 0.60, 1.00, 1.50, 1.05, -0.33),
         "D": (2.40, 1.50, 0.90, 1.80, 1.25, -0.50),
         "E": (2.00, 1.10, 1.00, 1.60, 1.15, -0.40)}
#: topographic category → S_T at the top of the relief (NTC 2018 Tab. 3.2.V)
TOPOGRAPHIES = {"T1": 1.0, "T2": 1.2, "T3": 1.2, "T4": 1.4}
#: T₁ = C₁ H^(3/4) for masonry buildings (NTC 2018 eq. 7.3.6 with C₁ = 0.050)
C1_MASONRY = 0.05


def soil_factors(soil: str, ag_over_g: float, F0: float, Tc_star: float) -> tuple[float, float]:
    """(S_S, C_C) of soil category ``soil`` (NTC 2018 Tab. 3.2.IV); ag_over_g = a_g/g."""
    if soil not in SOILS:
        raise ParameterError(f"soil = {soil!r} is not allowed: allowed one of "
                             + ", ".join(map(repr, SOILS)))
    a, b, lo, hi, c, k = SOILS[soil]
    return min(max(a - b * F0 * ag_over_g, lo), hi), c * Tc_star ** k


def topography_factor(topography: str) -> float:
    """S_T of topographic category ``topography`` (NTC 2018 Tab. 3.2.V, top of the relief)."""
    if topography not in TOPOGRAPHIES:
        raise ParameterError(f"topography = {topography!r} is not allowed: allowed one of "
                             + ", ".join(map(repr, TOPOGRAPHIES)))
    return TOPOGRAPHIES[topography]


def corner_periods(ag_over_g: float, Tc_star: float, C_C: float) -> tuple[float, float, float]:
    """(T_B, T_C, T_D) [s]: T_C = C_C T_C*, T_B = T_C/3, T_D = 4.0 a_g/g + 1.6 (NTC 2018
    eqs 3.2.3–3.2.5 as numbered in §3.2.3.2.1)."""
    T_C = C_C * Tc_star
    return T_C / 3.0, T_C, 4.0 * ag_over_g + 1.6


def elastic_spectrum(T, ag: float, S: float, F0: float, T_B: float, T_C: float, T_D: float,
                     eta: float = 1.0):
    """The horizontal elastic acceleration spectrum S_e(T) [m/s² when a_g is] of NTC 2018
    eq. 3.2.2 (η = 1: 5 % damping):

        0 <= T < T_B:   a_g S η F₀ [T/T_B + (1 − T/T_B)/(η F₀)]
        T_B <= T < T_C: a_g S η F₀
        T_C <= T < T_D: a_g S η F₀ T_C/T
        T_D <= T:       a_g S η F₀ T_C T_D/T²
    """
    T = np.asarray(T, float)
    if np.any(~np.isfinite(T)) or np.any(T < 0):
        raise ParameterError(f"T = {T!r} s is out of range: allowed 0 <= T")
    top = ag * S * eta * F0
    with np.errstate(divide="ignore", invalid="ignore"):
        out = np.where(T < T_B, ag * S * eta * F0 * (T / T_B + (1 - T / T_B) / (eta * F0)),
                       np.where(T < T_C, top, np.where(T < T_D, top * T_C / T,
                                                       top * T_C * T_D / T ** 2)))
    return float(out) if out.ndim == 0 else out


@dataclass(frozen=True)
class Site:
    """The seismic action at the building's site and what the check at height needs of the
    building (the case file's [site], docs/code-check.md).

    ag [m/s²]: the peak ground acceleration on rigid soil a_g (of the limit state checked);
    F0 [-], Tc_star [s]: F₀ and T_C* of the same hazard; soil: category A–E; topography:
    T1–T4; q [-]: the behaviour factor of the linear kinematic check (§C8.7.1.2: 2.0);
    FC [-]: the confidence factor; T1 [s]: the building's first period (0: C₁ H^(3/4) with
    C₁ = 0.05); building_height [m]: H of the building (0: the wall's top, z_base + the
    wall's H); storeys: N; z_base [m]: height of the wall's base above the ground (the
    mechanism's base is at Z = z_base + its hinge's height in the wall).
    """

    ag: float = ranged(0.0, 20.0, lo_open=True, unit="m/s^2")
    F0: float = ranged(2.2, 5.0)
    Tc_star: float = ranged(0.0, 2.0, lo_open=True, unit="s")
    soil: str = "A"
    topography: str = "T1"
    q: float = ranged(1.0, 4.0, default=2.0)
    FC: float = ranged(1.0, 2.0, default=1.35)
    T1: float = ranged(0.0, 10.0, unit="s", default=0.0)
    building_height: float = ranged(0.0, 1000.0, unit="m", default=0.0)
    storeys: int = 1
    z_base: float = ranged(0.0, 1000.0, unit="m", default=0.0)
    g: float = ranged(0.0, lo_open=True, unit="m/s^2", default=9.81)

    def __post_init__(self):
        check_fields(self)
        soil_factors(self.soil, 0.0, self.F0, self.Tc_star)
        topography_factor(self.topography)
        if not (isinstance(self.storeys, int) and 1 <= self.storeys <= 200):
            raise ParameterError(f"storeys = {self.storeys!r} is out of range: allowed an "
                                 "integer 1 <= storeys <= 200")

    @property
    def ag_over_g(self) -> float:
        return self.ag / self.g

    @property
    def S_S(self) -> float:
        return soil_factors(self.soil, self.ag_over_g, self.F0, self.Tc_star)[0]

    @property
    def C_C(self) -> float:
        return soil_factors(self.soil, self.ag_over_g, self.F0, self.Tc_star)[1]

    @property
    def S_T(self) -> float:
        return topography_factor(self.topography)

    @property
    def S(self) -> float:
        """S = S_S S_T (NTC 2018 eq. 3.2.3)."""
        return self.S_S * self.S_T

    @property
    def periods(self) -> tuple[float, float, float]:
        """(T_B, T_C, T_D) [s]."""
        return corner_periods(self.ag_over_g, self.Tc_star, self.C_C)

    def Se(self, T):
        """S_e(T) [m/s²], η = 1 (``elastic_spectrum``)."""
        return elastic_spectrum(T, self.ag, self.S, self.F0, *self.periods)

    def SDe(self, T, xi: float = 5.0):
        """The elastic displacement spectrum S_De(T) = S_e(T) T²/(4π²) [m] (NTC 2018
        §3.2.3.2.3) at viscous damping ``xi`` [%], η = max(√(10/(5 + ξ)), 0.55) (eq. 3.2.4,
        as the authors know it: the text is not here)."""
        if not (0.0 <= xi <= 100.0):
            raise ParameterError(f"xi = {xi!r} % is out of range: allowed 0 <= xi <= 100")
        eta = max(math.sqrt(10.0 / (5.0 + xi)), 0.55)
        T = np.asarray(T, float)
        out = elastic_spectrum(T, self.ag, self.S, self.F0, *self.periods, eta=eta) \
            * T ** 2 / (4 * math.pi ** 2)
        return float(out) if np.ndim(out) == 0 else out

    def height(self, wall_H: float) -> float:
        """The building's height H [m]: ``building_height``, or the wall's top."""
        return self.building_height or self.z_base + wall_H

    def first_period(self, wall_H: float) -> float:
        """T₁ [s]: ``T1``, or C₁ H^(3/4) with C₁ = 0.05 (masonry; NTC 2018 eq. 7.3.6)."""
        return self.T1 or C1_MASONRY * self.height(wall_H) ** 0.75

    def demand_ground(self) -> float:
        """The ground-level demand a_g S/q [m/s²] (§C8.7.1.2's check of a mechanism at the
        ground)."""
        return self.ag * self.S / self.q

    def demand_height(self, Z: float, wall_H: float) -> tuple[float, float, float, float]:
        """The demand at height Z [m] of the mechanism's base, S_e(T₁) ψ(Z) γ / q [m/s²],
        with ψ(Z) = Z/H and γ = 3N/(2N + 1); returns (demand, S_e(T₁), ψ, γ)."""
        H = self.height(wall_H)
        if not 0.0 <= Z <= H * (1 + 1e-12):
            raise ParameterError(f"Z = {Z!r} m is out of range: allowed 0 <= Z <= H = {H:g} m "
                                 "(the mechanism's base within the building)")
        N = self.storeys
        psi, gam = Z / H, 3 * N / (2 * N + 1)
        Se = self.Se(self.first_period(wall_H))
        return Se * psi * gam / self.q, Se, psi, gam

    def pgv(self) -> float:
        """The site's peak ground velocity v_g = 0.16 a_g S T_C [m/s] (NTC 2018 §3.2.3.3), the
        demand of the impulse view beside the code check (docs/code-check.md)."""
        return 0.16 * self.ag * self.S * self.periods[1]

    def as_dict(self) -> dict:
        T_B, T_C, T_D = self.periods
        return {"S_S": self.S_S, "C_C": self.C_C, "S_T": self.S_T, "S": self.S,
                "T_B": T_B, "T_C": T_C, "T_D": T_D, "demand_ground": self.demand_ground(),
                "pgv": self.pgv()}

