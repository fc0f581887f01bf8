"""Table 1's DEM column (issue 29): ``homlimit table1 --dem``, the 12 walls (or some) with one
[dem] parameter set, beside UDEC.

``table1_dem_records`` runs the walls' thresholds. Given a ``map``
(``engine.Engine.stored_map``), every trial is a task (``dem_stage.trial_task``; issue 29: one
trial per task): a client thread per wall runs its bisection (``dem_stage.threshold_by_trials``),
whose trials depend on each other, and waits for each trial's task; the walls' threads run at
once, so the workers hold one trial of each wall in flight. Each trial's record is stored as it
ends and read back on a rerun, so an interrupted table resumes at the trial where it stopped
(the command line's ``table1 --dem`` holds them in a result set).
"""

from __future__ import annotations

import dataclasses
import math

from .. import _threads
from ..errors import ParameterError, check_choice
from .config import CaseConfig, DemConfig
from .dem_stage import dem_threshold, table1_row, threshold_by_trials

__all__ = ["DEM_PAIRS", "dem_section", "table1_dem_records", "table1_dem_walls",
           "wall_record"]

#: the block-size ratios of v̄_g/√(gb): same wall and façade, smaller blocks over larger
DEM_PAIRS = ("B4/B1", "B5/B2", "B6/B3", "C4/C1", "C5/C2", "C6/C3")


def _wall_row(row, th, n_blocks: int, seconds: float) -> dict:
    """A row of table1_dem.csv from a wall's ``Threshold``."""
    g, b = row.case.wall.g, row.case.wall.b
    return {"test": row.test, "vg_udec": row.vg, "h_udec": row.h_v,
            "vnorm_udec": row.vg_norm, "vg": th.v, "vg_lo": th.lo, "vg_hi": th.hi,
            "h": th.h, "vnorm": th.v / math.sqrt(g * b), "dem_over_udec": th.v / row.vg,
            "base_slid": th.base_slid, "hinge_slid": th.hinge_slid,
            "base_slip": th.base_slip, "hinge_slip": th.hinge_slip,
            "n_trials": len(th.trials), "n_blocks": n_blocks, "cpu": th.cpu,
            "seconds": seconds}


def wall_record(item: dict) -> dict:
    """One Table 1 wall's DEM threshold, every trial here (``item`` = {"test": name, "dem":
    the [dem] section as a dict}): the record of a row of table1_dem.csv."""
    row = table1_row(item["test"])
    r = dem_threshold(CaseConfig(case=row.case, dem=DemConfig(**item["dem"])))
    return _wall_row(row, r.threshold, r.model.n_blocks, r.seconds)


def _wall_by_trials(item: dict, map) -> dict:
    """``wall_record`` with every trial a task of ``map`` (module docstring); its seconds
    are those of its trials' tasks, summed (a resumed table reads them from the records)."""
    row = table1_row(item["test"])
    th, recs = threshold_by_trials(item, row.case, DemConfig(**item["dem"]), map,
                                   f"{row.test} vg")
    return _wall_row(row, th, recs[0]["n_blocks"], sum(r["seconds"] for r in recs))


def table1_dem_walls(tests: list[str] | None = None, dem: DemConfig | None = None
                     ) -> list[str]:
    """The walls ``table1_dem_records`` runs, the costliest first, after checking the tests'
    names and the loading (ParameterError, before any work)."""
    from ..closed_form.paper import table1

    dem = dem or DemConfig()
    if dem.loading != "impulse":
        raise ParameterError(f"[dem] loading = {dem.loading!r} is out of range for table1 "
                             "--dem: allowed 'impulse' (Table 1 is the ideal impulse's)")
    walls = {t.test: t for t in table1()}
    for t in tests or ():
        check_choice("test", t, tuple(walls))
    names = [t for t in walls if not tests or t in tests]
    # the costliest first (blocks × steps per second ~ 1/a), so two workers end together
    names.sort(key=lambda t: -(walls[t].case.wall.H / walls[t].case.masonry.a) ** 2
               * walls[t].case.wall.L / walls[t].case.masonry.c)
    return names


def table1_dem_records(tests: list[str] | None = None, dem: DemConfig | None = None,
                       map=None) -> tuple[list[dict], dict]:
    """Table 1's DEM column: one row per wall (``wall_record``) and the block-size ratios
    (``DEM_PAIRS``) of v̄_g/√(gb), this DEM's and UDEC's. One parameter set (``dem``, default
    [dem]'s defaults) for every wall; ideal impulse only. ``map(fn, items)``: every trial a
    task, the walls' bisections at once (module docstring); default: the walls one after the
    other, every trial here."""
    from ..closed_form.paper import table1

    dem = dem or DemConfig()
    names = table1_dem_walls(tests, dem)
    walls = {t.test: t for t in table1()}
    items = [{"test": t, "dem": dataclasses.asdict(dem)} for t in names]
    if map is None:
        recs = [wall_record(x) for x in items]
    elif items:
        # daemon threads: an interrupt leaves at once, not after the walls' bisections
        recs = _threads.map_threads(lambda x: _wall_by_trials(x, map), items, len(items))
    else:
        recs = []
    by = {r["test"]: r for r in recs}
    rows = [by[t] for t in walls if t in by]
    ratios = {}
    for pair in DEM_PAIRS:
        hi, lo = pair.split("/")
        if hi in by and lo in by:
            ratios[pair] = {"vnorm": by[hi]["vnorm"] / by[lo]["vnorm"],
                            "vnorm_udec": by[hi]["vnorm_udec"] / by[lo]["vnorm_udec"]}
    return rows, ratios


def dem_section(overrides: list[str] | None) -> DemConfig:
    """The [dem] section that "dem.key=value" overrides make of the defaults, checked like a
    case file's (ConfigError naming key, value and range); another section is refused."""
    from .config import case_data, load_case

    bad = [o for o in overrides or () if not str(o).strip().startswith("dem.")]
    if bad:
        raise ParameterError(f"--set {bad[0]!r} is out of range for table1 --dem: allowed "
                             "dem.KEY=VALUE (the [dem] section; the walls are Table 1's)")
    return load_case(case_data(None)[0], list(overrides or ()), source="table1 --dem").dem
