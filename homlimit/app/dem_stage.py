"""The DEM's doors (issue 29): ``[analysis] dem = true`` in ``homlimit run`` and
``homlimit table1 --dem``, over the explicit rigid-block DEM of ``homlimit.dem``.

A case's [dem] section (``config.DemConfig``, validated with the rest of the case) gives the
DEM's parameters (``dem_params``) and the load: the ideal impulse (the threshold is v̄_g), a
base-acceleration pulse of duration/period ``pulse_period`` (the threshold is its amplitude
a_g; ``dynamics.pulses.make_pulse``) or the accelerogram ``[dem] record`` (the threshold is
its scale, as its pga; ``dynamics.RecordPulse``). The model is the case's T-section as blocks
with the façade "through" (``blocks.geometry.t_section_blocks``, the paper's UDEC model). The
threshold is ``dem.threshold.collapse_threshold``; its trials are logged on stderr as they end.

The first trial (``[dem] guess``, 0: automatic) only sets where the bracket search starts
(steps of ×1.5); the threshold does not depend on it beyond the bisection's tolerance. The
automatic guess of the ideal impulse is the paper's v̄_g rounded to 0.1 m/s for a Table 1
wall (what benchmarks/dem_table1.py used for docs/dem.md, so the doors reproduce that table
trial for trial), mechanism I's closed-form v̄_g rounded so otherwise; of a pulse, the larger
of mechanism I's static collapse acceleration (multiplier × g) and the a_g whose pgv is that
velocity guess (as benchmarks/dem_sensitivity.py).

Given a ``map`` (``engine.Engine.stored_map``; ``homlimit run`` passes one when the case asks
for the DEM), every trial is a task (``trial_task``; issue 29: one trial per task): the
bisection (``threshold_by_trials``) runs here, its trials depend on each other, and it waits
for each trial's task. Each trial's record is stored as it ends and read back on a rerun, so
an interrupted run resumes at the trial where it stopped. A worker builds and settles a wall
once, at its first trial of it, and keeps it for the next (settling is deterministic, so every
worker's settled state is the same and the trials are those of a run here); the files' trial
is re-run here from a state settled here. Table 1's column is ``app.dem_table1``.
"""

from __future__ import annotations

import dataclasses
import logging
import math
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from .._io import json_bytes
from ..dem.params import DEMParams
from .config import CaseConfig, DemConfig, resolved_inputs, wall_inputs

__all__ = ["DemRun", "dem_params", "dem_threshold", "table1_row", "threshold_by_trials",
           "trial_amplitude", "trial_task", "write_files"]

log = logging.getLogger(__name__)


def dem_params(dem: DemConfig) -> DEMParams:
    """The ``dem.DEMParams`` of a [dem] section (facade_stiffness 0: "rho")."""
    names = {f.name for f in dataclasses.fields(DEMParams)}
    kw = {k: v for k, v in dataclasses.asdict(dem).items() if k in names}
    kw["facade_stiffness"] = "rho" if dem.facade_stiffness == 0 else dem.facade_stiffness
    return DEMParams(**kw)


def _pulse(dem: DemConfig, amplitude: float, record=None):
    """The base acceleration of amplitude a_g [m/s²]: [dem] loading's pulse, or the
    accelerogram ``record`` (``dynamics.RecordPulse``) scaled to that pga."""
    if dem.loading == "record":
        return dataclasses.replace(record.with_pga(amplitude), polarity=dem.polarity)
    from ..dynamics.pulses import make_pulse

    return make_pulse(dem.loading, dem.pulse_period, amplitude, dem.polarity)


def _record(config: CaseConfig):
    """[dem] record read (``accelerogram.read_record``) with loading "record", else None."""
    if config.dem.loading != "record":
        return None
    from .accelerogram import read_record

    return read_record(config.source, config.dem.record, "[dem] record")


def _record_item(record) -> dict:
    """A record as a trial task carries it (its samples: a worker need not read the file)."""
    return {"t": record.t.tolist(), "a_g": record.a_g.tolist(), "name": record.name}


def _guess(case, dem: DemConfig, record=None) -> float:
    """The first trial (module docstring)."""
    if dem.guess > 0:
        return dem.guess
    from ..closed_form.mechanisms import mechanism_I
    from ..closed_form.paper import dem_row

    row = dem_row(case)
    v = row.vg if row is not None else mechanism_I(case).vg
    v = round(v, 1) or v
    if dem.loading == "impulse":
        return v
    # a pulse below the static collapse acceleration cannot start the rocking, and one whose
    # pgv is below the impulse's v̄_g rarely overturns (the impulse is the short-pulse limit)
    return max(mechanism_I(case).multiplier * case.wall.g, v / _pulse(dem, 1.0, record).pgv)


def _load(dem: DemConfig, record=None):
    """amplitude -> keyword arguments of ``dem.run``."""
    if dem.loading == "impulse":
        return lambda v: {"v_g": v}
    return lambda a: {"pulse": _pulse(dem, a, record)}


def amplitude(dem: DemConfig, plot: bool = False) -> tuple[str, str]:
    """The name and unit of a threshold's amplitude: ("vg", "m/s") under the ideal impulse,
    ("a_g", "m/s^2") under a pulse or a record ("m/s²" on plots)."""
    if dem.loading == "impulse":
        return "vg", "m/s"
    return "a_g", "m/s²" if plot else "m/s^2"


@dataclass
class DemRun:
    """One case's DEM threshold: loading ("impulse" or a pulse kind), the threshold
    (``dem.threshold.Threshold``: v = the amplitude, v̄_g [m/s] or a_g [m/s²]), the model and
    its settled state (for the files; None until ``write_files`` settles it when the trials
    were tasks), b and g of the case, wall-clock seconds, the accelerogram (loading
    "record")."""

    dem: DemConfig
    threshold: Any
    model: Any
    settled: Any
    b: float
    g: float
    seconds: float
    record: Any = None

    @property
    def impulse(self) -> bool:
        return self.dem.loading == "impulse"

    @property
    def pgv(self) -> float:
        """v̄_g (ideal impulse), or the peak ground velocity of the threshold pulse [m/s]."""
        if self.impulse:
            return self.threshold.v
        return _pulse(self.dem, self.threshold.v, self.record).pgv

    def as_dict(self) -> dict:
        """summary.json's "dem": the threshold and its bracket (vg or pga), h, λ = h/b, the
        failing part's base z0, the slide flags and largest slips, trials, CPU, wall time.
        Each trial keeps its amplitude with every digit as text ("exact": the file's numbers
        carry 15 digits, and a trial near the threshold can turn on the 16th; docs/dem.md
        section 3)."""
        th = self.threshold
        k = "vg" if self.impulse else "pga"
        d = {"loading": self.dem.loading}
        if self.record is not None:
            d.update(record=self.dem.record, polarity=self.dem.polarity)
        elif not self.impulse:
            d.update(pulse_period=self.dem.pulse_period, polarity=self.dem.polarity)
        d.update({k: th.v, f"{k}_lo": th.lo, f"{k}_hi": th.hi, "pgv": self.pgv,
                  "vnorm": self.pgv / math.sqrt(self.g * self.b), "rel_tol": th.rel_tol,
                  "h": th.h, "lam": th.h / self.b, "z0": th.z0, "base_slid": th.base_slid,
                  "hinge_slid": th.hinge_slid, "base_slip": th.base_slip,
                  "hinge_slip": th.hinge_slip, "n_trials": len(th.trials),
                  "trials": [{k: v, "exact": repr(v), "collapsed": c, "t_end": t}
                             for v, c, t in th.trials],
                  "cpu": th.cpu, "seconds": self.seconds, "dt": th.dt,
                  "n_blocks": self.model.n_blocks,
                  "fc": self.model.info.get("fc", 0.0),
                  "joint_segments": self.model.info.get("joint_segments", 1),
                  "joint_points": self.model.info.get("joint_points", 0),
                  "settle_time": th.settle.get("time"),
                  "settle_converged": th.settle.get("converged")})
        return d

    def label(self) -> str:
        if self.impulse:
            return "DEM (homlimit.dem), ideal impulse"
        if self.record is not None:
            return f"DEM (homlimit.dem), record {self.record.name}: its pgv"
        return (f"DEM (homlimit.dem), {self.dem.loading} pulse {self.dem.pulse_period:g} s: "
                "its pgv")

    def lines(self) -> str:
        """The summary's DEM lines: threshold bracket, slides, trials, time."""
        th = self.threshold
        what, unit = amplitude(self.dem)
        yn = {True: "yes", False: "no"}
        return (f"DEM: {what} = {th.v:.4g} {unit} (safe {th.lo:.4g}, collapsed {th.hi:.4g}, "
                f"±{100 * th.rel_tol:g} %); failing height h = {th.h:.2f} m from z = "
                f"{th.z0:.2f} m; base slid {yn[th.base_slid]} ({1e3 * th.base_slip:.0f} mm), "
                f"hinge slid {yn[th.hinge_slid]} ({1e3 * th.hinge_slip:.0f} mm); "
                f"{len(th.trials)} trials, {th.cpu:.3g} s CPU, {self.seconds:.3g} s"
                + self._joints())

    def _joints(self) -> str:
        """With points along the joints, what they change (docs/dem.md section 10)."""
        info = self.model.info
        if info.get("joint_segments", 1) <= 1:
            return ""
        fc = info.get("fc", 0.0)
        return (f"; contacts on {info['joint_segments']} points per bed joint"
                + (f" (f_c = {fc / 1e6:.4g} MPa caps each)" if fc else "")
                + ": the joints' rotational stiffness drops with them (B1 at f_c infinite: "
                  "0.753 m/s on 8 points, 0.88-0.90 on the corners; docs/dem.md section 10)")


def _model(case, dem: DemConfig):
    from ..dem import t_section_model

    return t_section_model(case, dem_params(dem))


def trial_amplitude(v: float) -> str:
    """A trial's amplitude for the log: four digits, and every digit where those are not the
    value (a trial near the threshold is chaotic: one unit in the last place moves its
    collapse time by a second, docs/dem.md section 3), so a trial can be re-run from the log."""
    short = f"{v:.4g}"
    return short if float(short) == v else f"{short} ({v!r})"


def _logger(what: str, unit: str):
    def progress(v, collapsed, t_end, trials):
        safe = [a for a, c, _ in trials if not c]
        fell = [a for a, c, _ in trials if c]
        br = (f"{max(safe):.4g} .. {min(fell):.4g} {unit}" if safe and fell else "open")
        log.info("DEM trial %d: %s = %s %s %s at %.2f s; bracket %s", len(trials), what,
                 trial_amplitude(float(v)), unit, "collapsed" if collapsed else "stood", t_end,
                 br)
    return progress


def dem_threshold(config: CaseConfig, map=None) -> DemRun:
    """The DEM threshold of a validated case (its [dem] section; module docstring): every
    trial here, or with ``map`` every trial a task (``threshold_by_trials``); then the model is
    settled here only if its files are written (``write_files``)."""
    from ..dem import settle
    from ..dem.threshold import collapse_threshold

    dem, case = config.dem, config.case
    t0 = time.perf_counter()
    record = _record(config)
    model = _model(case, dem)
    what, unit = amplitude(dem)
    if map is not None:
        log.info("DEM: %d blocks, dt = %.3g s; every trial a task", model.n_blocks, model.dt)
        item = {"wall": wall_inputs(resolved_inputs(config)), "dem": dataclasses.asdict(dem)}
        if record is not None:
            item["record"] = _record_item(record)
        th, _ = threshold_by_trials(item, case, dem, map, what)
        return DemRun(dem, th, model, None, case.wall.b, case.wall.g, time.perf_counter() - t0,
                      record)
    log.info("DEM: %d blocks, dt = %.3g s; settling under gravity", model.n_blocks, model.dt)
    settled, info = settle(model)
    log.info("DEM: settled in %.2f s of simulated time (%s)", info["time"],
             "converged" if info["converged"] else "not converged: settle_time reached")
    th = collapse_threshold(model, settled, guess=_guess(case, dem, record), rel_tol=dem.rel_tol,
                            t_max=dem.t_max, load=_load(dem, record),
                            progress=_logger(what, unit))
    th = dataclasses.replace(th, settle=info)
    return DemRun(dem, th, model, settled, case.wall.b, case.wall.g, time.perf_counter() - t0,
                  record)


def write_files(run: DemRun, output, staging: Path, out: Path, title: str = "") -> dict:
    """The files of a DEM run into ``staging`` (a result set's), under the names they will
    have in ``out``: with [output] vtu, the ParaView series dem.pvd + dem/*.vtu of the lowest
    collapsing trial; with png, dem_snapshots.png of it and, with [dem] animation,
    dem_animation.gif of it beside the highest standing trial (re-run for t_max). Returns
    key → final path."""
    from ..dem.output import plot_animation, plot_snapshots, record_frames, write_series

    if not (output.vtu or output.png):
        return {}
    if run.settled is None:            # its trials were tasks: settle here as they did
        from ..dem import settle

        log.info("DEM: settling the model here for its files")
        run.settled = settle(run.model)[0]
    th = run.threshold
    log.info("DEM: recording the lowest collapsing trial (%.4g) every %g s", th.hi,
             run.dem.frame_interval)
    frames = record_frames(run.model, run.settled, t_max=run.dem.t_max,
                           interval=run.dem.frame_interval, **_load(run.dem, run.record)(th.hi))
    files = {}
    what, unit = amplitude(run.dem, plot=True)
    if output.vtu:
        write_series(staging, run.model, run.settled, frames, name="dem")
        files["dem_pvd"] = out / "dem.pvd"
    if output.png:
        plot_snapshots(staging / "dem_snapshots.png", run.model, run.settled, frames,
                       title=f"{title}: DEM at {th.hi:.4g} {unit} (lowest collapsing trial)")
        files["dem_snapshots_png"] = out / "dem_snapshots.png"
    if output.png and run.dem.animation:
        log.info("DEM: recording the highest standing trial (%.4g) for the animation", th.lo)
        standing = record_frames(run.model, run.settled, t_max=run.dem.t_max,
                                 interval=run.dem.frame_interval,
                                 **_load(run.dem, run.record)(th.lo))
        plot_animation(staging / "dem_animation.gif", run.model, run.settled,
                       [(f"{what} = {th.hi:.4g} {unit}: collapsed", frames),
                        (f"{what} = {th.lo:.4g} {unit}: stood", standing)],
                       title=f"{title}: DEM at the threshold and just below")
        files["dem_animation_gif"] = out / "dem_animation.gif"
    return files


# ----------------------------------------------------------------------------- trial tasks
def table1_row(name: str):
    """Table 1's row of the wall ``name`` (``closed_form.paper.table1``)."""
    from ..closed_form.paper import table1

    return {t.test: t for t in table1()}[name]


def _wall_of(item: dict):
    """The ``Case`` of a trial task's item: a Table 1 wall's, or a case's from its wall
    inputs (``config.wall_inputs``)."""
    if "test" in item:
        return table1_row(item["test"]).case
    from .config import load_case

    return load_case(item["wall"], source="DEM trial").case


#: per worker process: (model, settled state, settling report) of each wall and [dem] section
#: a trial task has met (``trial_task``)
_SETTLED: dict = {}


def trial_task(item: dict) -> dict:
    """One trial of a bisection, a task: ``item`` = {"test": a Table 1 wall's name, or "wall":
    a case's wall inputs (``config.wall_inputs``), "dem": the [dem] section as a dict,
    "amplitude": v̄_g [m/s] or a pulse's a_g [m/s²], and with loading "record" "record": its
    samples (``_record_item``)}. The wall is built and settled at this
    worker's first trial of it and kept (module docstring). Returns
    ``dem.threshold.trial_record`` with dt [s], n_blocks, settle (the settling's report),
    settle_cpu [s] (the settling's CPU in this task, 0 when it was kept) and seconds (the
    task's wall clock)."""
    from ..dem import run, settle
    from ..dem.threshold import trial_record

    key = json_bytes({k: v for k, v in item.items() if k != "amplitude"}, sort_keys=True)
    dem = DemConfig(**item["dem"])
    wall = time.perf_counter()
    t0 = time.thread_time()
    if key not in _SETTLED:
        model = _model(_wall_of(item), dem)
        _SETTLED[key] = (model, *settle(model))
    model, settled, info = _SETTLED[key]
    settle_cpu = time.thread_time() - t0
    amp = float(item["amplitude"])
    out = run(model, settled, t_max=dem.t_max, **_load(dem, _record_of(item))(amp))
    return {**trial_record(model, settled, out, amp), "dt": model.dt,
            "n_blocks": model.n_blocks, "settle": info, "settle_cpu": settle_cpu,
            "seconds": time.perf_counter() - wall}


def _record_of(item: dict):
    """The accelerogram a trial task carries (``_record_item``), or None."""
    if "record" not in item:
        return None
    from ..dynamics import RecordPulse

    r = item["record"]
    return RecordPulse(r["t"], r["a_g"], name=r["name"])


def threshold_by_trials(item: dict, case, dem: DemConfig, map, label: str):
    """The threshold of ``case`` with every trial a task of ``map`` (``trial_task`` on
    ``item`` with the trial's amplitude): (``dem.threshold.Threshold``, the trials' records).
    The bisection runs here and waits for each task; ``label`` names the trials in the log."""
    from ..dem.threshold import bisect, threshold_of

    def trial(v):
        return map(trial_task, [{**item, "amplitude": v}])[0]

    lo, hi, recs = bisect(trial, guess=_guess(case, dem, _record_of(item)), rel_tol=dem.rel_tol,
                          progress=_logger(label, amplitude(dem)[1]))
    return threshold_of(lo, hi, recs, dem.rel_tol, recs[0]["dt"], recs[0]["settle"]), recs
