"""Stage "impulse/pulses": the overturning spectra of ``[pulse]`` (``homlimit.dynamics``) for
the mechanisms the case chooses, each from the registry (``registry.Mechanism.alone`` and
its rocker)."""

from __future__ import annotations

import logging

from ..dynamics import overturning_spectrum
from ..dynamics.spectra import PLAUSIBLE_PGA_G, PLAUSIBLE_PGV, record_thresholds
from ..errors import ParameterError
from . import registry
from .accelerogram import MAX_RECORD_BYTES, read_record
from .config import CaseConfig, ConfigError
from .models import FERocker, stage
from .models_rigid import no_joint_strength
from .result import Result

__all__ = ["MAX_RECORD_BYTES", "pulse_records"]

log = logging.getLogger("homlimit.app.pipeline")

def pulse_records(config: CaseConfig) -> tuple[list, FERocker | None]:
    """The overturning spectra of ``[pulse]`` (``homlimit.dynamics``): every pulse kind ×
    mechanism × polarity × period, and the critical scale of ``[pulse] record`` if given.
    Each chosen mechanism (in the registry's order) comes from its ``alone`` (``registry``):
    the FE body from the FE cache, or the FE path (as ``run``, without the static bound),
    which is then cached (``models.fe_rocker``). Returns the spectrum points and the FE
    rocker (None unless chosen), which says whether it came from the cache."""
    case, pc = config.case, config.pulse
    w = case.wall
    # refused before any work (the FE path): what the chosen rockers do not take
    # (every rocker takes fc, ties and floors: the FE body's with the FE impulse's LoadWork)
    no_joint_strength(case, "the pulse spectra's rocker of every mechanism")
    record = _record(config) if pc.record else None
    chosen = {e.name: _alone(e, config) for e in registry.mechanisms()
              if e.name in pc.mechanisms}
    rockers = {name: registry.mechanism(name).rocker(case, m, gravity_I=pc.gravity_I,
                                                     restitution=pc.restitution)
               for name, m in chosen.items()}
    kw = dict(b=w.b, g=w.g, rtol=pc.rtol, scan_ratio=pc.scan_ratio)
    points = []
    for kind in pc.kinds:
        with stage({}, "overturning spectrum", f"{kind}, {len(rockers)} mechanisms"):
            points += overturning_spectrum(
                rockers, kind, pc.periods, polarities=pc.polarities,
                pulse_options={"gamma": pc.gamma, "nu": pc.nu} if kind == "mp" else None, **kw)
    if record is not None:
        with stage({}, "critical scale of the record", pc.record):
            points += record_thresholds(rockers, record, **kw)
    _warn_implausible(points)
    return points, next((m for m in chosen.values() if isinstance(m, FERocker)), None)


def _record(config: CaseConfig):
    """[pulse] record read (``read_record``); a problem with it is the case's, ConfigError
    naming the case file as [dem] record's (``accelerogram.record_problems``)."""
    try:
        return read_record(config.source, config.pulse.record, "[pulse] record")
    except ParameterError as e:
        raise ConfigError(config.source, [str(e)]) from None


def _alone(entry: registry.Mechanism, config: CaseConfig):
    """The mechanism ``entry`` of the case for the pulse spectra: its ``alone`` (the FE
    path's through the FE cache), else what its model gives on the case."""
    if entry.alone is not None:
        return entry.alone(config)
    result = Result(config=config)
    registry.model(entry.model).run(config, result)
    return result.mechanisms[entry.name]


def _warn_implausible(points) -> None:
    """One warning for the critical pulses beyond any recorded ground motion (kept in the
    results, marked ``implausible``)."""
    bad = [p for p in points if p.implausible]
    if not bad:
        return
    shown = "; ".join(f"{p.pulse} {p.polarity:+d} T_p = {p.period:g} s, {p.mechanism}: "
                      f"pga {p.pga_g:.3g} g, pgv {p.pgv:.3g} m/s" for p in bad[:3])
    more = f"; and {len(bad) - 3} more" if len(bad) > 3 else ""
    log.warning("warning: %d of %d critical pulses need pga > %g g or pgv > %g m/s, beyond "
                "recorded ground motion (kept, column implausible = true): %s%s", len(bad),
                len(points), PLAUSIBLE_PGA_G, PLAUSIBLE_PGV, shown, more)
