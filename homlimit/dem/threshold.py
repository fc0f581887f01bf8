"""The collapse threshold by bisection, with the failing height and the slide flags.

A trial is one ``model.run`` from one settled state; it collapses by the criterion of
``homlimit.dem.model`` (a watched block outwards by more than disp_limit, or turned by more
than rot_limit, before t_max). The bracket [lo, hi] (lo safe, hi collapsed) is found by
steps of ×``step`` (default 1.5) from ``guess`` and halved until (hi − lo)/(hi + lo) <=
rel_tol; the threshold is (lo + hi)/2, ± rel_tol.

Failing height h: at the collapse of the lowest collapsing trial, the watched blocks turned by
more than half the largest watched rotation form the failing part; h is the top of the
watched blocks minus the lowest bottom of the failing part. Slides: the base slid if a block's
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

__all__ = ["Threshold", "collapse_threshold", "failing_part"]


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
    turned = w & (rot > 0.5 * rot[w].max())
    z0 = float(bb[turned, 1].min())
    h = float(bb[w, 3].max()) - z0
    base_slip = float(out.slip_base.max())
    low = turned & np.isclose(bb[:, 1], z0)
    below = (~a.fixed) & np.isclose(bb[:, 3], z0) & (bb[:, 0] < float(bb[low, 2].max()))
    hinge_slip = float(out.slip_bed[low | below].max()) if np.any(low | below) else 0.0
    return h, z0, base_slip > slide_tol, hinge_slip > slide_tol, base_slip, hinge_slip


def collapse_threshold(model: DEMModel, settled: DEMState | None = None, *, guess: float = 0.5,
                       rel_tol: float = 0.01, t_max: float = 5.0, load=None,
                       slide_tol: float = 1e-3, max_trials: int = 40,
                       progress=None, step: float = 1.5) -> Threshold:
    """The smallest collapsing amplitude by bisection (module docstring).

    load: amplitude -> keyword arguments of ``run`` (default: the ideal impulse,
    {"v_g": amplitude}); e.g. ``lambda v: {"velocity": field(v)}`` or
    ``lambda a: {"pulse": pulse.with_pga(a)}``. settled: a settled state (default: settle
    here). progress(amplitude, collapsed, t_end, trials): called after each trial (e.g. a
    line on stderr); it changes nothing. step: the bracket search's factor (> 1; a guess
    known to lie near the threshold saves trials with a small one, e.g. 1.1)."""
    guess = check_range("guess", guess, 0.0, lo_open=True)
    step = check_range("step", step, 1.0, 10.0, lo_open=True)
    rel_tol = check_range("rel_tol", rel_tol, 0.0, 0.5, lo_open=True)
    settle_info = {}
    if settled is None:
        settled, settle_info = settle(model)
    load = load or (lambda v: {"v_g": v})
    trials = []
    cpu = 0.0
    outs = {}

    def trial(v):
        nonlocal cpu
        if len(trials) >= max_trials:
            raise ResultError(f"DEM threshold: no bracket or no convergence in {max_trials} "
                              f"trials (last amplitude {v:g})")
        o = run(model, settled, t_max=t_max, **load(v))
        trials.append((v, o.collapsed, o.t_end))
        cpu += o.cpu
        outs[v] = o
        if progress is not None:
            progress(v, o.collapsed, o.t_end, tuple(trials))
        return o.collapsed

    lo, hi = None, None
    v = guess
    if trial(v):
        hi = v
        while lo is None:
            v /= step
            if trial(v):
                hi = v
            else:
                lo = v
    else:
        lo = v
        while hi is None:
            v *= step
            if trial(v):
                hi = v
            else:
                lo = v
    while (hi - lo) / (hi + lo) > rel_tol:
        mid = 0.5 * (lo + hi)
        if trial(mid):
            hi = mid
        else:
            lo = mid
    if not math.isfinite(hi):  # pragma: no cover - guarded by the loop
        raise ParameterError("no collapse found")
    h, z0, bs, hs, bsl, hsl = failing_part(model, settled, outs[hi], slide_tol)
    return Threshold(0.5 * (lo + hi), lo, hi, rel_tol, h, z0, bs, hs, bsl, hsl, tuple(trials),
                     cpu, model.dt, settle_info)
