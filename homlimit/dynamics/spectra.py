"""Overturning spectra: the critical peak ground velocity (and acceleration) of a pulse
against its period, per mechanism.

For every rocker, pulse kind and period T_p the threshold search (``threshold``) gives the
smallest overturning pulse; the spectrum reports its pgv, pga, pgv/√(g b) and its ratio to
eq. 7's v̄_g (the ideal impulse, the short-period asymptote of the rectangular pulse: pgv =
a_p Δt → v̄_g as Δt → 0). The records are typed (``SpectrumPoint``); the application layer
prints, writes and draws them (``app.report.format_spectra``, ``app.plots.plot_spectra``).

Entry point for a case: ``case_spectra(case, ...)`` builds the rockers of mechanisms I and II
(at the critical λ of eq. 7) and of an optional FE body, and returns every point.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import asdict, dataclass

import numpy as np

from ..closed_form.mechanisms import mechanism_II
from ..errors import ParameterError, check_range
from ..impulse.body import RigidBody
from ..params import Case
from .integrate import IntegrationOptions
from .pulses import PULSE_KINDS, make_pulse
from .real_rocker import RealWallRocker
from .rocking import GeneralisedRocker, MechanismIRocker, RigidRocker, Rocker
from .threshold import critical_pulse

__all__ = ["SpectrumPoint", "DEFAULT_PERIODS", "overturning_spectrum", "case_rockers",
           "case_spectra", "record_thresholds", "SPECTRUM_COLUMNS", "PLAUSIBLE_PGA_G",
           "PLAUSIBLE_PGV", "implausible"]

DEFAULT_PERIODS = (0.02, 0.05, 0.1, 0.2, 0.5, 1.0, 2.0)  # s


@dataclass(frozen=True)
class SpectrumPoint:
    """One point of an overturning spectrum (SI units).

    mechanism, pulse (kind), period T_p [s] (rectangular: duration), polarity;
    pga [m/s²], pga_g = pga/g, pgv [m/s], vnorm = pgv/√(g b): the critical pulse;
    vg_eq7 [m/s], vnorm_eq7: eq. 7 (ideal impulse) for the same rocker; ratio = pgv/vg_eq7;
    p [rad/s]: the rocker's frequency parameter, pT = p·T_p; a_uplift [m/s²];
    n_impacts: impacts in the critical history; hinge_ratio: max |P_x|/P_z at the pivot
    during the critical pulse (rigid bodies; NaN for mechanism I, whose abutment forces also
    act, and for one-DOF shapes); rtol: threshold tolerance (relative, on pga);
    ivp_rtol, ivp_method: the time integration's tolerance and method;
    implausible: the critical pulse lies beyond any recorded ground motion (pga > 3 g or
    pgv > 3 m/s, ``PLAUSIBLE_PGA_G``, ``PLAUSIBLE_PGV``): a valid result, but no pulse of this
    shape and period that real ground motion reaches overturns the body.
    """

    mechanism: str
    pulse: str
    period: float
    polarity: int
    pga: float
    pga_g: float
    pgv: float
    vnorm: float
    vg_eq7: float
    vnorm_eq7: float
    ratio: float
    p: float
    pT: float
    a_uplift: float
    n_impacts: int
    hinge_ratio: float
    rtol: float
    ivp_rtol: float
    ivp_method: str
    implausible: bool = False

    def as_dict(self) -> dict:
        return asdict(self)


PLAUSIBLE_PGA_G = 3.0  # largest plausible peak ground acceleration [g]
PLAUSIBLE_PGV = 3.0    # largest plausible peak ground velocity [m/s]


def implausible(pga_g: float, pgv: float) -> bool:
    """Is a pulse of peak acceleration pga_g [g] and velocity pgv [m/s] beyond any recorded
    ground motion (pga > 3 g or pgv > 3 m/s)?"""
    return bool(pga_g > PLAUSIBLE_PGA_G or pgv > PLAUSIBLE_PGV)


SPECTRUM_COLUMNS = [f for f in SpectrumPoint.__dataclass_fields__]


def overturning_spectrum(rockers: Mapping[str, Rocker], kind: str, periods: Iterable[float],
                         *, b: float, g: float = 9.81, polarities: Sequence[int] = (1,),
                         rtol: float = 1e-6, scan_ratio: float = 1.05,
                         pulse_options: Mapping | None = None,
                         options: IntegrationOptions | None = None) -> list[SpectrumPoint]:
    """Critical pulses of ``kind`` (a key of PULSE_KINDS) at each period [s] for every rocker
    (name → Rocker) and polarity; b [m]: the façade thickness of the normalisation
    pgv/√(g b). A polarity whose pulse never pushes an attached body outwards (a rectangular
    pulse of polarity −1) gives no points."""
    if kind not in PULSE_KINDS:
        raise ParameterError(f"pulse kind = {kind!r} is out of range: allowed "
                             f"{', '.join(PULSE_KINDS)}")
    b = check_range("b", b, 0.0, lo_open=True, unit="m")
    g = check_range("g", g, 0.0, lo_open=True, unit="m/s^2")
    periods = [check_range("period", T, 0.0, lo_open=True, unit="s") for T in periods]
    if not periods:
        raise ParameterError("periods = [] is out of range: allowed at least one period")
    if not rockers:
        raise ParameterError("rockers = {} is out of range: allowed at least one mechanism")
    pts = []
    for name, rk in rockers.items():
        for pol in polarities:
            for T in periods:
                pulse = make_pulse(kind, T, 1.0, pol, **dict(pulse_options or {}))
                if not rk.two_sided and pulse.a_extremes[1] <= 0:
                    break  # this polarity never pushes the body outwards: no point
                pts.append(_point(name, rk, pulse, b, g, rtol, scan_ratio, options))
    return pts


def record_thresholds(rockers: Mapping[str, Rocker], pulse, *, b: float, g: float = 9.81,
                      rtol: float = 1e-6, scan_ratio: float = 1.05,
                      options: IntegrationOptions | None = None) -> list[SpectrumPoint]:
    """The critical scale of one pulse shape (e.g. a ``RecordPulse``) for every rocker, as
    spectrum points (period: the pulse's length)."""
    return [_point(name, rk, pulse, b, g, rtol, scan_ratio, options)
            for name, rk in rockers.items()]


def _point(name, rk, pulse, b, g, rtol, scan_ratio, options) -> SpectrumPoint:
    """The critical pulse of shape ``pulse`` for rocker ``rk`` as a SpectrumPoint."""
    th = critical_pulse(rk, pulse, rtol=rtol, scan_ratio=scan_ratio, options=options,
                        record=isinstance(rk, RigidRocker))
    ivp, T, sq = th.response.options, pulse.period, math.sqrt(g * b)
    return SpectrumPoint(name, pulse.kind, T, pulse.polarity, th.pga, th.pga / g, th.pgv,
                         th.pgv / sq, th.vg_impulse, th.vg_impulse / sq, th.ratio, rk.p,
                         rk.p * T, th.a_uplift, th.response.n_impacts, _hinge_ratio_of(rk, th),
                         rtol, ivp.rtol, ivp.method, implausible(th.pga / g, th.pgv))


def _hinge_ratio_of(rocker: Rocker, th) -> float:
    """max |P_x|/P_z at the pivot during the critical pulse, rigid rockers only."""
    if not isinstance(rocker, RigidRocker) or th.response.history is None:
        return math.nan
    h = th.response.history
    on = h["t"] <= th.pulse.t_end
    t, phi, phid, side = h["t"][on], h["phi"][on], h["phi_dot"][on], h["side"][on]
    ag = side * th.pulse.a(t)
    Pi, R = rocker.excitation(phi), rocker.restoring(phi)
    phidd = (Pi * ag - R) / rocker.inertia
    moving = h["moving"][on]
    if not np.any(moving):
        return math.nan
    Px, Pz = rocker.hinge_force(phi[moving], phid[moving], phidd[moving], ag[moving])
    if np.any(Pz <= 0):
        return math.inf
    return float(np.max(np.abs(Px) / Pz))


#: the closed-form mechanisms' rockers: (case, gravity_I, restitution) → Rocker
#: (a real wall's, ``case.real``: ``RealWallRocker`` of ``closed_form.real``)
_CLOSED_FORM_ROCKERS = {
    "I": lambda case, gravity_I, restitution: RealWallRocker(
        case, "detachment", geometry=gravity_I, restitution=restitution, name="I")
    if case.real else MechanismIRocker(case, gravity=gravity_I, restitution=restitution),
    "II": lambda case, gravity_I, restitution: RealWallRocker(
        case, "crack", restitution=restitution, name="II") if case.real else RigidRocker(
        mechanism_II(case).body, g=case.wall.g, restitution=restitution, name="II")}


def case_rockers(case: Case, mechanisms: Sequence[str] = ("I", "II"),
                 fe_body=None, gravity_I: str = "linearised",
                 restitution: float = 0.0) -> dict[str, Rocker]:
    """Rockers of a case: "I" (``MechanismIRocker`` at the critical λ, gravity per
    ``gravity_I``), "II" (the rigid body of ``mechanism_II`` at its critical λ, exact
    geometry), and "FE" if ``fe_body`` is given: a RigidBody (exact geometry), or an FE
    mechanism (``mechanism.analysis.FEMechanism``) as its v̄_g is computed: its one-DOF
    shape (the body inside the 50 % line turning exactly, the rest linearised)."""
    if not isinstance(case, Case):
        raise ParameterError(f"case = {case!r} is not a homlimit.params.Case")
    out = {}
    for m in mechanisms:
        if m not in _CLOSED_FORM_ROCKERS:
            raise ParameterError(f"mechanism = {m!r} is out of range: allowed "
                                 + ", ".join(map(repr, _CLOSED_FORM_ROCKERS))
                                 + " (the FE body comes as fe_body)")
        out[m] = _CLOSED_FORM_ROCKERS[m](case, gravity_I, restitution)
    if isinstance(fe_body, RigidBody):
        out["FE"] = RigidRocker(fe_body, g=case.wall.g, restitution=restitution, name="FE")
    elif fe_body is not None:
        out["FE"] = GeneralisedRocker.from_impulse(fe_body.impulse, g=case.wall.g,
                                                   restitution=restitution, name="FE")
    return out


def case_spectra(case: Case, kinds: Sequence[str] = ("rectangular", "one-sine"),
                 periods: Iterable[float] = DEFAULT_PERIODS, *,
                 mechanisms: Sequence[str] = ("I", "II"), fe_body: RigidBody | None = None,
                 gravity_I: str = "linearised", restitution: float = 0.0,
                 polarities: Sequence[int] = (1,), rtol: float = 1e-6,
                 scan_ratio: float = 1.05, pulse_options: Mapping | None = None,
                 options: IntegrationOptions | None = None) -> list[SpectrumPoint]:
    """Overturning spectra of a case: every pulse kind × mechanism × polarity × period."""
    rockers = case_rockers(case, mechanisms, fe_body, gravity_I, restitution)
    periods = list(periods)
    pts = []
    for kind in kinds:
        opts = (pulse_options or {}) if kind == "mp" else {}
        pts += overturning_spectrum(rockers, kind, periods, b=case.wall.b, g=case.wall.g,
                                    polarities=polarities, rtol=rtol, scan_ratio=scan_ratio,
                                    pulse_options=opts, options=options)
    return pts
