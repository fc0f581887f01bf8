"""Stage "mechanisms": every mechanism a run reports checked to be finite
(``check_results``), then each one's hinge under the ideal impulse (``hinge_checks``):
``conclude`` is the last step of every evaluated case, ``run``'s and a sweep's batch alike."""

from __future__ import annotations

from ..dynamics import holding_pulse
from ..errors import ResultError
from . import registry, report
from .models import finite, stage
from .result import Result

__all__ = ["check_results", "conclude", "hinge_checks"]


def check_results(result: Result):
    """Every result a run reports is a finite number: ResultError naming the mechanism and
    the quantity otherwise (never a summary with ``null`` where a number belongs). Quantities
    that do not apply (mechanism I's tan ψ, the crack of a distributed mechanism, a scan
    height without a block, whose ``vg_method`` says why; v̄_g of a mechanism whose
    ``vg_unavailable`` says why, as the rigid blocks with a joint cohesion or tension) are
    exempt; a run whose only mechanisms say why they have no v̄_g has no governing one."""
    for name, m in result.mechanisms.items():
        entry = registry.mechanism(name)
        exempt = ("vg", "vnorm") if getattr(m, "vg_unavailable", "") else ()
        for q in entry.checked:
            if q not in exempt and not finite(getattr(m, q)):
                raise ResultError(f"mechanism {name}: {q} = {getattr(m, q)!r} is not a finite "
                                  f"number for this case ({_what(q)}); nothing written")
        for q in entry.body_checked:
            if not finite(getattr(m.body, q)):
                raise ResultError(f"mechanism {name}: body {q} = {getattr(m.body, q)!r} is not "
                                  "a finite number for this case; nothing written")
    for model in registry.models():
        if model.check is not None:
            model.check(result)
    if result.critical() is None and not any(getattr(m, "vg_unavailable", "")
                                             for m in result.mechanisms.values()):
        raise ResultError("no mechanism gave a collapse velocity vg; nothing written")


def _what(q: str) -> str:
    unit = report.UNITS.get(q, "")
    return {"lam": "critical slenderness λ = h/b", "h": "height of the failing part",
            "vg": "collapse ground velocity v̄_g", "vnorm": "v̄_g/√(gb)",
            "theta_m": "rotation at the peak of the restoring work",
            "W_m": "peak restoring work"}[q] + (f" [{unit}]" if unit not in ("", "-") else "")


def conclude(result: Result) -> Result:
    """The last step of every evaluated case, ``run``'s and a sweep's batch alike: every
    result checked to be a finite number (``check_results``: ResultError naming the
    mechanism and the quantity), then, with ``[analysis] hinge_check``, the hinge check of
    each mechanism (``hinge_checks``). Returns ``result``, its ``hinges`` filled in."""
    check_results(result)
    if result.mechanisms and result.config.analysis.hinge_check:
        with stage(result.timings, "hinge check", "the shortest pulse the hinge holds"):
            result.hinges = hinge_checks(result)
    return result


def hinge_checks(result: Result) -> dict:
    """Per mechanism with a rocker (``registry``), the shortest rectangular pulse of a_g = f g
    (the most the bed joint under the hinge holds) that still overturns it
    (``dynamics.holding_pulse``): the ideal impulse needs |P_x/P_z| (``hinge_ratio``), more
    than f for the Table 1 walls."""
    case, out = result.case, {}
    for name, m in result.mechanisms.items():
        rocker = registry.mechanism(name).rocker
        if rocker is not None:
            out[name] = holding_pulse(rocker(case, m), case.masonry.f)
    return out
