"""Overturning spectra: the critical peak ground velocity (and acceleration) of a pulse
against its period, per mechanism.

For every rocker, pulse kind and period T_p the threshold search (``threshold``) gives the
smallest overturning pulse; the spectrum reports its pgv, pga, pgv/√(g b) and its ratio to
eq. 7's v̄_g (the ideal impulse, the short-period asymptote of the rectangular pulse: pgv =
a_p Δt → v̄_g as Δt → 0). The records are typed (``SpectrumPoint``); ``write_spectra_csv``
and ``plot_spectra`` write them, ``format_spectra`` prints them.

Entry point for a case: ``case_spectra(case, ...)`` builds the rockers of mechanisms I and II
(at the critical λ of eq. 7) and of an optional FE body, and returns every point.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import asdict, dataclass
from pathlib import Path

import numpy as np

from ..body import RigidBody
from ..errors import ParameterError, check_range
from ..mechanisms import mechanism_II
from ..params import Case
from ..report import format_table, write_csv, write_figure
from .integrate import IntegrationOptions
from .pulses import PULSE_KINDS, make_pulse
from .rocking import MechanismIRocker, RigidRocker, Rocker
from .threshold import critical_pulse

__all__ = ["SpectrumPoint", "DEFAULT_PERIODS", "overturning_spectrum", "case_rockers",
           "case_spectra", "format_spectra", "write_spectra_csv", "plot_spectra",
           "SPECTRUM_COLUMNS"]

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
    ivp_rtol, ivp_method: the time integration's tolerance and method.
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

    def as_dict(self) -> dict:
        return asdict(self)


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
                th = critical_pulse(rk, pulse, rtol=rtol, scan_ratio=scan_ratio,
                                    options=options, record=isinstance(rk, RigidRocker))
                hr = _hinge_ratio_of(rk, th)
                ivp = th.response.options
                pts.append(SpectrumPoint(
                    name, kind, T, pol, th.pga, th.pga / g, th.pgv, th.pgv / math.sqrt(g * b),
                    th.vg_impulse, th.vg_impulse / math.sqrt(g * b), th.ratio, rk.p, rk.p * T,
                    th.a_uplift, th.response.n_impacts, hr, rtol, ivp.rtol, ivp.method))
    return pts


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


def case_rockers(case: Case, mechanisms: Sequence[str] = ("I", "II"),
                 fe_body: RigidBody | None = None, gravity_I: str = "linearised",
                 restitution: float = 0.0) -> dict[str, Rocker]:
    """Rockers of a case: "I" (``MechanismIRocker`` at the critical λ, gravity per
    ``gravity_I``), "II" (the rigid body of ``mechanism_II`` at its critical λ, exact
    geometry), and "FE" (``fe_body``, exact geometry) if given."""
    if not isinstance(case, Case):
        raise ParameterError(f"case = {case!r} is not a homlimit.params.Case")
    out = {}
    for m in mechanisms:
        if m == "I":
            out["I"] = MechanismIRocker(case, gravity=gravity_I, restitution=restitution)
        elif m == "II":
            out["II"] = RigidRocker(mechanism_II(case).body, g=case.wall.g,
                                    restitution=restitution, name="II")
        else:
            raise ParameterError(f"mechanism = {m!r} is out of range: allowed 'I', 'II' "
                                 "(the FE body comes as fe_body)")
    if fe_body is not None:
        out["FE"] = RigidRocker(fe_body, g=case.wall.g, restitution=restitution, name="FE")
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


def format_spectra(points: Sequence[SpectrumPoint], title: str | None = None) -> str:
    """A text table: pulse, mechanism, T_p, critical pga/g, pgv, pgv/√(gb), pgv/v̄_g(eq. 7)."""
    rows = [[p.pulse, p.mechanism, p.polarity, p.period, p.pga_g, p.pgv, p.vnorm, p.ratio,
             p.n_impacts] for p in points]
    return format_table(["pulse", "mech", "pol", "T_p [s]", "pga/g", "pgv [m/s]",
                         "pgv/sqrt(gb)", "pgv/vg(eq.7)", "impacts"], rows, title)


def write_spectra_csv(points: Sequence[SpectrumPoint], path: str | Path) -> Path:
    """Write the spectrum points as CSV (columns SPECTRUM_COLUMNS), atomically."""
    return write_csv(path, [p.as_dict() for p in points], SPECTRUM_COLUMNS)


def plot_spectra(points: Sequence[SpectrumPoint], path: str | Path, *,
                 dem_vnorm: float | None = None, title: str | None = None) -> Path:
    """Critical pgv/√(g b) against pulse period, one panel per pulse kind, one line per
    mechanism (and polarity), eq. 7 (the ideal impulse) as a dashed line of the same colour
    (the short-period asymptote of the rectangular pulse), the DEM value of Table 1 when given.
    Saved atomically as PNG."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    if not points:
        raise ParameterError("points = [] is out of range: nothing to plot")
    kinds = list(dict.fromkeys(p.pulse for p in points))
    mechs = list(dict.fromkeys(p.mechanism for p in points))
    colours = dict(zip(mechs, plt.rcParams["axes.prop_cycle"].by_key()["color"]))
    fig, axes = plt.subplots(1, len(kinds), figsize=(5.2 * len(kinds), 4.8), squeeze=False,
                             sharey=True, layout="constrained")
    for ax, kind in zip(axes[0], kinds):
        for m in mechs:
            for pol in sorted({p.polarity for p in points}, reverse=True):
                sel = sorted((p for p in points if p.pulse == kind and p.mechanism == m
                              and p.polarity == pol), key=lambda p: p.period)
                if not sel:
                    continue
                lab = m if pol > 0 else f"{m} (polarity -1)"
                ax.plot([p.period for p in sel], [p.vnorm for p in sel], "o-" if pol > 0
                        else "s:", color=colours[m], label=lab, ms=4)
            eq7 = next((p.vnorm_eq7 for p in points if p.mechanism == m), None)
            if eq7 is not None:
                ax.axhline(eq7, color=colours[m], ls="--", lw=1,
                           label=f"{m}: eq. 7 (ideal impulse)")
        if dem_vnorm is not None:
            ax.axhline(dem_vnorm, color="k", ls="-.", lw=1, label="DEM (Table 1)")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("pulse period T_p [s]" if kind != "rectangular"
                      else "pulse duration Δt [s]")
        ax.set_title(kind)
        ax.grid(True, which="both", alpha=0.3)
    axes[0][0].set_ylabel("critical pgv / √(g b)")
    handles, labels = axes[0][0].get_legend_handles_labels()
    for ax in axes[0][1:]:
        for hd, lb in zip(*ax.get_legend_handles_labels()):
            if lb not in labels:
                handles.append(hd)
                labels.append(lb)
    fig.legend(handles, labels, fontsize=7, loc="outside lower center",
               ncol=min(len(labels), 4))
    if title:
        fig.suptitle(title)

    def draw(tmp: Path):
        fig.savefig(tmp, dpi=130, format="png")

    try:
        return write_figure(path, draw)
    finally:
        plt.close(fig)
