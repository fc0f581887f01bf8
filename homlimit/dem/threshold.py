"""The collapse threshold by bisection, with the failing height and the slide flags.

A trial is one ``model.run`` from one settled state; it collapses by the criterion of
``homlimit.dem.model`` (a watched block outwards by more than disp_limit, or turned by more
than rot_limit, before t_max). The bracket [lo, hi] (lo safe, hi collapsed) is found by
steps of ×``step`` (default 1.5) from ``guess`` and halved until (hi − lo)/(hi + lo) <=
rel_tol; the threshold is (lo + hi)/2, ± rel_tol.

Failing height h: at the collapse of the lowest collapsing trial, the watched blocks turned by
more than half the rotation of the lead block form the failing part; h is the top of the
watched blocks minus the lowest bottom of the failing part. The lead block is the watched
block that met the criterion (furthest out among those past disp_limit, else the most turned),
not the most turned of all: a block that tumbles on its own (the multi-storey example's top
course, swung 3.1 rad about its tie once the courses under it had gone) would otherwise be
the failing part alone (examples/multistorey/README.md). Slides: the base slid if a block's
plastic slip against the ground exceeds ``slide_tol``; the hinge slid if a failing block of
the lowest failing course, or a block of the course below, slipped in its bed joints by more
than slide_tol.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import ParameterError, ResultError, check_range
from .model import DEMModel, DEMState, Outcome, run, settle

__all__ = ["Threshold", "bisect", "collapse_threshold", "failing_part", "threshold_of",
           "trial_record"]


@dataclass(frozen=True)
class Threshold:
    """v [m/s] (or the load's amplitude) = (lo + hi)/2; lo safe, hi collapsed; rel_tol;
    h [m] failing height, z0 [m] its base; base_slid, hinge_slid; base_slip, hinge_slip [m]
    (largest plastic slips); trials [(amplitude, collapsed, t_end)]; cpu [s] summed over the
    trials; dt [s]; settle (the settling's report)."""

    v: float
    lo: float
    hi: float
    rel_tol: float
    h: float
    z0: float
    base_slid: bool
    hinge_slid: bool
    base_slip: float
    hinge_slip: float
    trials: tuple
    cpu: float
    dt: float
    settle: dict

    def as_dict(self) -> dict:
        return {"v": self.v, "lo": self.lo, "hi": self.hi, "rel_tol": self.rel_tol,
                "h": self.h, "z0": self.z0, "base_slid": self.base_slid,
                "hinge_slid": self.hinge_slid, "base_slip": self.base_slip,
                "hinge_slip": self.hinge_slip, "n_trials": len(self.trials), "cpu": self.cpu,
                "dt": self.dt}


def failing_part(model: DEMModel, settled: DEMState, out: Outcome, slide_tol: float = 1e-3):
    """(h, z0, base_slid, hinge_slid, base_slip, hinge_slip) of a collapsed run (module
    docstring)."""
    a = model.assembly
    w = model.watch
    rot = np.abs(out.state.th - settled.th)
    bb = a.bounds()
    ux = np.where(w, settled.pos[:, 0] - out.state.pos[:, 0], -np.inf)  # outwards (−x)
    past = ux > model.disp_limit
    lead = int(np.argmax(ux)) if past.any() else int(np.argmax(np.where(w, rot, -np.inf)))
    turned = w & (rot > 0.5 * rot[lead])
    turned[lead] = True
    z0 = float(bb[turned, 1].min())
    h = float(bb[w, 3].max()) - z0
    base_slip = float(out.slip_base.max())
    low = turned & np.isclose(bb[:, 1], z0)
    below = (~a.fixed) & np.isclose(bb[:, 3], z0) & (bb[:, 0] < float(bb[low, 2].max()))
    hinge_slip = float(out.slip_bed[low | below].max()) if np.any(low | below) else 0.0
    return h, z0, base_slip > slide_tol, hinge_slip > slide_tol, base_slip, hinge_slip


def trial_record(model: DEMModel, settled: DEMState, out: Outcome, amplitude: float,
                 slide_tol: float = 1e-3) -> dict:
    """One trial as JSON-able data: amplitude, collapsed, t_end [s], cpu [s]; a collapsed
    trial also its failing part (``failing_part``: h, z0 [m], base_slid, hinge_slid,
    base_slip, hinge_slip [m])."""
    rec = {"amplitude": float(amplitude), "collapsed": bool(out.collapsed),
           "t_end": float(out.t_end), "cpu": float(out.cpu)}
    if out.collapsed:
        h, z0, bs, hs, bsl, hsl = failing_part(model, settled, out, slide_tol)
        rec.update(h=h, z0=z0, base_slid=bool(bs), hinge_slid=bool(hs), base_slip=bsl,
                   hinge_slip=hsl)
    return rec


def bisect(trial, *, guess: float = 0.5, rel_tol: float = 0.01, max_trials: int = 40,
           progress=None, step: float = 1.5) -> tuple[float, float, list[dict]]:
    """The bracket [lo, hi] (lo safe, hi collapsed) of ``trial(amplitude) -> record``
    (``trial_record``'s keys) by steps of ×step from guess, halved until (hi − lo)/(hi + lo)
    <= rel_tol (module docstring). Each trial depends on the ones before, so they run one
    after the other, wherever ``trial`` runs them (here, or a task each). Returns (lo, hi,
    records in trial order)."""
    guess = check_range("guess", guess, 0.0, lo_open=True)
    rel_tol = check_range("rel_tol", rel_tol, 0.0, 0.5, lo_open=True)
    step = check_range("step", step, 1.0, 10.0, lo_open=True)
    recs = []

    def collapses(v):
        if len(recs) >= max_trials:
            raise ResultError(f"DEM threshold: no bracket or no convergence in {max_trials} "
                              f"trials (last amplitude {v:g})")
        recs.append(trial(v))
        if progress is not None:
            progress(v, recs[-1]["collapsed"], recs[-1]["t_end"],
                     tuple((r["amplitude"], r["collapsed"], r["t_end"]) for r in recs))
        return recs[-1]["collapsed"]

    lo, hi = None, None
    v = guess
    if collapses(v):
        hi = v
        while lo is None:
            v /= step
            if collapses(v):
                hi = v
            else:
                lo = v
    else:
        lo = v
        while hi is None:
            v *= step
            if collapses(v):
                hi = v
            else:
                lo = v
    while (hi - lo) / (hi + lo) > rel_tol:
        mid = 0.5 * (lo + hi)
        if collapses(mid):
            hi = mid
        else:
            lo = mid
    if not math.isfinite(hi):  # pragma: no cover - guarded by the loop
        raise ParameterError("no collapse found")
    return lo, hi, recs


def threshold_of(lo: float, hi: float, recs: list[dict], rel_tol: float, dt: float,
                 settle_info: dict) -> Threshold:
    """The ``Threshold`` of a bisection's records (``bisect``): the failing part of the lowest
    collapsing trial, CPU summed over the trials."""
    top = next(r for r in recs if r["collapsed"] and r["amplitude"] == hi)
    return Threshold(0.5 * (lo + hi), lo, hi, rel_tol, top["h"], top["z0"], top["base_slid"],
                     top["hinge_slid"], top["base_slip"], top["hinge_slip"],
                     tuple((r["amplitude"], r["collapsed"], r["t_end"]) for r in recs),
                     sum(r["cpu"] for r in recs), dt, settle_info)


def collapse_threshold(model: DEMModel, settled: DEMState | None = None, *, guess: float = 0.5,
                       rel_tol: float = 0.01, t_max: float = 5.0, load=None,
                       slide_tol: float = 1e-3, max_trials: int = 40,
                       progress=None, step: float = 1.5) -> Threshold:
    """The smallest collapsing amplitude by bisection (module docstring), every trial run
    here (``bisect`` with ``trial_record`` of ``run``).

    load: amplitude -> keyword arguments of ``run`` (default: the ideal impulse,
    {"v_g": amplitude}); e.g. ``lambda v: {"velocity": field(v)}`` or
    ``lambda a: {"pulse": pulse.with_pga(a)}``. settled: a settled state (default: settle
    here). progress(amplitude, collapsed, t_end, trials): called after each trial (e.g. a
    line on stderr); it changes nothing. step: the bracket search's factor (> 1; a guess
    known to lie near the threshold saves trials with a small one, e.g. 1.1)."""
    check_range("guess", guess, 0.0, lo_open=True)
    check_range("rel_tol", rel_tol, 0.0, 0.5, lo_open=True)
    check_range("step", step, 1.0, 10.0, lo_open=True)
    settle_info = {}
    if settled is None:
        settled, settle_info = settle(model)
    load = load or (lambda v: {"v_g": v})

    def trial(v):
        return trial_record(model, settled, run(model, settled, t_max=t_max, **load(v)), v,
                            slide_tol)

    lo, hi, recs = bisect(trial, guess=guess, rel_tol=rel_tol, max_trials=max_trials,
                          progress=progress, step=step)
    return threshold_of(lo, hi, recs, rel_tol, model.dt, settle_info)
