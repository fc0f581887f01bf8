"""Collapse threshold: the smallest pulse amplitude that overturns a rocker.

For a pulse shape (any ``Pulse``, scaled by its peak ground acceleration), the search
1. starts at the amplitude below which the body never leaves its seat,
   a_lo = a_uplift / max(a_g / pga) (``Rocker.a_uplift``; both signs for a two-sided block);
2. steps up geometrically by ``scan_ratio`` until a time history overturns (a_hi);
3. scans again, by the finer ``sub_ratio``, the last ``sub_steps`` coarse steps below a_hi
   (down to the first coarse step, or to the uplift amplitude if a_hi is the first step) and
   keeps the first overturning amplitude found:
   rocking blocks have safe islands above their minimum overturning amplitude (Zhang &
   Makris 2001), so the first coarse hit may lie past the first overturning window. On free
   blocks under one-cosine pulses the ×1.05 scan alone returned windows up to 3.3 % above the
   minimum, the first window lying one or two coarse steps below the first hit
   (tests/test_dynamics_block.py checks the minima against an independent integration). A
   window narrower than one fine step, or lying more than ``sub_steps`` coarse steps below
   a_hi, is still missed;
4. refines the fine bracket with ``scipy.optimize.brentq`` on ``Response.margin``
   (continuous where the outcome is decided by energy after the pulse) to the relative
   tolerance ``rtol``;
5. confirms the threshold: pga·(1 − 2 rtol) is safe and pga·(1 + 2 rtol) overturns; otherwise
   SolverError.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from scipy.optimize import brentq

from ..errors import ParameterError, SolverError, check_range
from .integrate import IntegrationOptions, Response, simulate
from .pulses import Pulse, RectangularPulse
from .rocking import Rocker

__all__ = ["HoldingPulse", "Threshold", "critical_pulse", "holding_pulse"]


@dataclass(frozen=True)
class Threshold:
    """The critical pulse of one rocker (SI units).

    rocker: its name; pulse: the critical pulse (scaled to the threshold); pga [m/s²],
    pgv [m/s]: its peak ground acceleration and velocity; vg_impulse [m/s]: eq. 7 for the
    same rocker (the ideal impulse); a_uplift [m/s²]; response: the overturning time history
    just above the threshold (pga·(1 + 2 rtol)); below: the safe one just below;
    n_simulations: time histories run; rtol, scan_ratio: the search's tolerances.
    """

    rocker: str
    pulse: Pulse
    pga: float
    pgv: float
    vg_impulse: float
    a_uplift: float
    response: Response
    below: Response
    n_simulations: int
    rtol: float
    scan_ratio: float

    @property
    def ratio(self) -> float:
        """pgv / v̄_g(eq. 7): how much more ground velocity the finite pulse needs."""
        return self.pgv / self.vg_impulse

    def as_dict(self) -> dict:
        return {"rocker": self.rocker, **{f"pulse_{k}": v for k, v in
                                          self.pulse.describe().items()},
                "pga": self.pga, "pgv": self.pgv, "vg_impulse": self.vg_impulse,
                "ratio": self.ratio, "a_uplift": self.a_uplift,
                "n_impacts": self.response.n_impacts, "reason": self.response.reason,
                "n_simulations": self.n_simulations, "rtol": self.rtol,
                "scan_ratio": self.scan_ratio, "ivp_rtol": self.response.options.rtol,
                "ivp_method": self.response.options.method}


def critical_pulse(rocker: Rocker, pulse: Pulse, *, rtol: float = 1e-6,
                   scan_ratio: float = 1.05, max_scan: int = 1000,
                   sub_ratio: float = 1.002, sub_steps: int = 3,
                   options: IntegrationOptions | None = None,
                   max_impacts: int | None = None, record: bool = False) -> Threshold:
    """The smallest peak ground acceleration of the shape ``pulse`` that overturns ``rocker``
    (module docstring), to the relative tolerance rtol. scan_ratio: the coarse scan's step;
    sub_ratio, sub_steps: the fine re-scan of the last sub_steps coarse steps (sub_steps = 0:
    none). max_impacts = 0 looks for overturning without impact only. record: keep the
    critical time history (``Threshold.response``)."""
    if not isinstance(rocker, Rocker):
        raise ParameterError(f"rocker = {rocker!r} is not a homlimit.dynamics Rocker")
    if not isinstance(pulse, Pulse):
        raise ParameterError(f"pulse = {pulse!r} is not a homlimit.dynamics Pulse")
    rtol = check_range("rtol", rtol, 1e-13, 1e-2)
    scan_ratio = check_range("scan_ratio", scan_ratio, 1.0, 10.0, lo_open=True)
    max_scan = int(check_range("max_scan", max_scan, 1))
    # a fine step no longer than the coarse one
    sub_ratio = min(check_range("sub_ratio", sub_ratio, 1.0, 10.0, lo_open=True), scan_ratio)
    sub_steps = int(check_range("sub_steps", sub_steps, 0, 100))
    lo_a, hi_a = pulse.with_pga(1.0).a_extremes
    peak = max(hi_a, -lo_a) if rocker.two_sided else hi_a
    if peak <= 0:
        raise ParameterError(f"pulse {pulse.kind!r} with polarity {pulse.polarity} never "
                             f"pushes {rocker.name!r} outwards (max a_g <= 0): allowed a pulse "
                             "with an outward lobe (try the other polarity)")
    n = 0

    def run(a, rec=False):
        nonlocal n
        n += 1
        return simulate(rocker, pulse.with_pga(a), options=options, record=rec,
                        max_impacts=max_impacts)

    a_lo = a_up = rocker.a_uplift / peak
    r_lo = run(a_lo)
    if r_lo.overturned:  # cannot happen: at a_lo the body barely lifts
        raise SolverError(f"{rocker.name}: overturned at the uplift amplitude {a_lo:.6g} m/s^2",
                          status="bracket")
    a_hi = a_lo
    for _ in range(max_scan):
        a_lo, a_hi = a_hi, a_hi * scan_ratio
        if run(a_hi).margin > 0:
            break
    else:
        raise SolverError(f"{rocker.name}: no overturning found up to pga = {a_hi:.6g} m/s^2 "
                          f"({max_scan} steps of x{scan_ratio:g} from the uplift amplitude)",
                          status="no bracket")
    # the first overturning window may lie below a_hi: re-scan the last coarse steps finely
    # (from the first coarse step up, unless that one overturned: just above the uplift
    # amplitude a free block chatters through hundreds of impacts, 0.5 s a history, and gains
    # little energy)
    if sub_steps:
        a = a_up if a_hi <= a_up * scan_ratio * (1 + 1e-12) else max(
            a_up * scan_ratio, a_hi / scan_ratio ** sub_steps)
        while a * sub_ratio < a_hi * (1 - 1e-12):
            if run(a * sub_ratio).margin > 0:
                a_lo, a_hi = a, a * sub_ratio
                break
            a *= sub_ratio
        else:
            a_lo = max(a_lo, a)
    xtol = 1e-15 * a_hi
    a_c = brentq(lambda a: run(a).margin, a_lo, a_hi, xtol=xtol, rtol=rtol)
    up = run(a_c * (1 + 2 * rtol), record)
    down = run(a_c * (1 - 2 * rtol), record)
    if not up.overturned or down.overturned:
        raise SolverError(f"{rocker.name}: threshold at pga = {a_c:.8g} m/s^2 not confirmed "
                          f"(x(1+2rtol): {up.reason}; x(1-2rtol): {down.reason})",
                          status="not confirmed")
    crit = pulse.with_pga(a_c)
    return Threshold(rocker.name, crit, a_c, crit.pgv, rocker.vg_impulse, rocker.a_uplift, up,
                     down, n, rtol, scan_ratio)




@dataclass(frozen=True)
class HoldingPulse:
    """The shortest rectangular pulse whose acceleration the hinge can hold (a_g = f g, no
    sliding) and that still overturns the rocker: duration [s], pgv = f g·duration [m/s] and
    its ratio to eq. 7's ideal impulse; duration = NaN (and ``reason``) when no such pulse
    exists (f g below the lift-off acceleration: the hinge slides before the body lifts)."""

    f: float
    duration: float
    pgv: float
    ratio: float
    reason: str = ""


def holding_pulse(rocker: Rocker, f: float, *, rtol: float = 1e-4,
                  options: IntegrationOptions | None = None) -> HoldingPulse:
    """Bisect the duration of a rectangular pulse of amplitude f g (the most a hinge of
    friction f holds) between eq. 7's ideal impulse v̄_g/(f g), which a finite pulse never
    reaches, and the first doubling that overturns."""
    f = check_range("f", f, 0.0, lo_open=True)
    rtol = check_range("rtol", rtol, 1e-10, 1e-2)
    a = f * rocker.g
    v7 = rocker.vg_impulse
    if a <= rocker.a_uplift:
        return HoldingPulse(f, math.nan, math.nan, math.nan,
                            f"f g = {a:.3g} m/s² does not lift the body (lift-off at "
                            f"{rocker.a_uplift:.3g} m/s²): the hinge slides first")

    def overturns(dt):
        return simulate(rocker, RectangularPulse(a, dt), options=options).overturned

    lo, hi = v7 / a, 2 * v7 / a      # a finite pulse needs more than the ideal impulse
    while not overturns(hi):
        lo, hi = hi, 2.0 * hi
        if hi > 1e3 * v7 / a:
            raise SolverError(f"no rectangular pulse of {a:.3g} m/s² shorter than "
                              f"{hi:.3g} s overturns {rocker.name}", status="no bracket")
    while hi - lo > rtol * hi:
        mid = 0.5 * (lo + hi)
        lo, hi = (lo, mid) if overturns(mid) else (mid, hi)
    return HoldingPulse(f, hi, a * hi, a * hi / v7)
