"""Parameter sweeps and building stocks: many cases, each evaluated as ``run`` evaluates one.

A sweep is a base case (a case file or dict; ``config.load_case``) and a list of overrides
(any case-file key, e.g. ``masonry.a``, ``wall.l`` for ρ = l/s; docs/case-file.md): a grid
(``{"wall.l": [3, 6, 9], "masonry.a": [0.15, 0.3]}``, every combination), a table (a CSV of
one case per row, one column per key), or a table times a grid. Every case

- is validated first (an invalid case is recorded as failed, with its error, and not run);
- gets a key: a hash of its resolved inputs (every case-file value except ``name`` and
  ``[output]``) and the package version (``engine.record_key``);
- is evaluated on the Dask ``engine``: a case with the FE analysis is one task, ``run(config,
  write=False)``; closed-form-only cases (``analysis.fe = false``) go in vectorised batches
  (their critical λ for thousands of walls at once, ``closed_form.mechanisms.critical_I/II``;
  then ``mechanisms_I/II`` at that λ, as ``run`` does), a few tasks in all;
- leaves its record (``Result.to_dict()``, the summary.json layout, plus ``status`` and, for
  a failed case, ``error``) in ``OUT/records/`` as soon as it finishes, atomically; a rerun
  with ``resume`` skips every case already recorded.

At the end the records become one table, one row per case in sweep order, columns named by
their path in summary.json (``inputs.masonry.a``, ``mechanisms.I.vg``, ``critical.vnorm``,
``fe.multiplier``...), as ``results.parquet`` (pyarrow) and ``results.csv``; ``sweep.json``
describes the sweep. ``sweep_report.report`` draws the standard plots.

Modules: the inputs and the cases in ``sweep_cases``, the tasks the workers run in
``sweep_tasks``, the table in ``sweep_table``; here the planning and the sweep itself (their
public names re-exported).
"""

from __future__ import annotations

import contextlib
import itertools
import logging
import math
import time
from dataclasses import dataclass, field
from pathlib import Path

from .._io import sidecar
from .config import ConfigError, load_case_inputs
from .engine import Engine, RecordStore, check_scheduler, cpu_count, record_key
from .pipeline import folder_name, package_version, result_folder, source_of
from .report import input_units
from .sweep_cases import (
    MAX_CASES,
    MAX_DIGITS,
    MAX_PROBLEMS,
    MAX_TABLE_BYTES,
    SweepCase,
    invalid_error,
    no_gc,
    parse_grid,
    read_table,
    sweep_inputs,
)
from .sweep_table import META, flatten, record_row, table_rows, write_table
from .sweep_tasks import BatchText, batch_closed_form, evaluate_item, failed_record, run_case
from .writers import write

__all__ = ["MAX_CASES", "MAX_DIGITS", "MAX_PROBLEMS", "MAX_TABLE_BYTES", "META", "SweepCase",
           "SweepResult", "batch_closed_form", "flatten", "parse_grid", "plan_sweep",
           "read_table", "record_row", "run_case", "sweep", "sweep_inputs", "write_table"]

log = logging.getLogger(__name__)

#: the files a sweep folder holds beside its records/ and report/ (nested sets)
SWEEP_NAMES = ("sweep.json", "results.parquet", "results.csv", sidecar("results.csv").name)

#: closed-form cases per vectorised task at most
BATCH = 2500


@dataclass
class SweepResult:
    """What ``sweep`` produced: the table rows (sweep order), counts and files."""

    folder: Path
    rows: list[dict]
    swept: list[str]
    n_ok: int
    n_failed: int
    n_resumed: int
    elapsed: float
    files: dict[str, Path] = field(default_factory=dict)

    def failed(self) -> list[dict]:
        return [r for r in self.rows if r["status"] != "ok"]


def plan_sweep(base=None, grid=None, table=None,
               max_cases: int = MAX_CASES) -> tuple[list[SweepCase], dict, str]:
    """The cases of a sweep (table rows × grid points, in that order), each validated and
    keyed. Returns (cases, base data, source). Raises ConfigError (a ParameterError) for a
    malformed grid, table or base, listing every problem (``sweep_inputs``), ParameterError
    for more than ``max_cases`` cases, and the first case's ConfigError when no case at all
    is valid."""
    data, source, grid, rows = sweep_inputs(base, grid, table, max_cases)
    errors: list[ConfigError] = []
    with no_gc():
        cases = list(_plan(data, source, grid, rows, errors))
    _check_some_valid(cases, errors)
    return cases, data, source


def _plan(data: dict, source: str, grid: dict, rows: list[dict], errors: list):
    """The cases one by one (``plan_sweep``), the grid's points made as they are needed;
    each invalid case's ConfigError is appended to ``errors``."""
    version = package_version()
    keys = list(grid)
    combos = itertools.product(rows, itertools.product(*grid.values()))
    for k, (row, vals) in enumerate(combos):
        ov = {**row, **dict(zip(keys, vals))}
        try:
            config, inputs = load_case_inputs(data, ov, source)
        except ConfigError as e:
            errors.append(e)
            yield SweepCase(k, ov, record_key("invalid", {"base": data, "set": ov}),
                            error=invalid_error(e))
            continue
        yield SweepCase(k, ov, record_key("case", inputs, version), config)


def _check_some_valid(cases: list[SweepCase], errors: list):
    if cases and all(c.config is None for c in cases):
        raise errors[0]


# ----------------------------------------------------------------------------- the sweep
def _chunk_size(n_cases: int, workers: int) -> int:
    """Closed-form cases per batch: about four batches per worker (the first can start while
    the next are planned), at most BATCH."""
    return max(1, min(BATCH, math.ceil(n_cases / (4 * max(workers, 1)))))


def sweep(base=None, grid=None, table=None, out: str | Path | None = None, *,
          workers: int | None = None, scheduler: str | None = None, resume: bool = True,
          retry_failed: bool = False, progress: bool = True,
          engine: Engine | None = None, max_cases: int = MAX_CASES) -> SweepResult:
    """Run a sweep (see the module docstring) and write its records and table to ``out``
    (default homlimit-out/<base name>/sweep/).

    base: a case file, a dict or None (the embedded B1); grid: ``parse_grid`` input; table: a
    CSV path or a list of override dicts; workers / scheduler: the Dask engine (an embedded
    LocalCluster of ``workers`` processes, or an existing scheduler's address), or ``engine``
    already open; resume: keep the records of an earlier run and run only the missing cases
    (off: start from nothing); retry_failed: run recorded failures again; max_cases: the most
    cases the sweep may have (checked from the grid's and table's sizes before any planning).
    The base, grid and table are checked before anything else (``sweep_inputs``).

    The cases are planned (validated and keyed) in chunks: when the first chunk has work, the
    engine starts and each chunk's batch runs while the next is planned; otherwise (a resumed
    or an invalid sweep) every case is planned before anything starts.
    """
    t0 = time.perf_counter()
    if scheduler is not None and engine is None:
        check_scheduler(scheduler)          # a malformed address: before any work
    data, source, grid_d, rows_in = sweep_inputs(base, grid, table, max_cases)
    name = str(data.get("name") or "sweep")
    folder = Path(out) if out else Path("homlimit-out") / folder_name(name) / "sweep"
    # one result set: sweep.json and the table staged, replacing the previous sweep's together
    # at the end (records/ and report/, nested sets, are kept); checked before any work
    with result_folder(folder, "sweep", **source_of(base), base_name=name) as staging:
        return _sweep_into(staging, folder, t0, data, source, grid_d, rows_in, table,
                           workers=workers, scheduler=scheduler, resume=resume,
                           retry_failed=retry_failed, progress=progress, engine=engine)


def _sweep_into(staging: Path, folder: Path, t0: float, data: dict, source: str, grid_d: dict,
                rows_in: list[dict], table, *, workers, scheduler, resume, retry_failed,
                progress, engine) -> SweepResult:
    """The body of ``sweep``: records in ``folder``/records/, sweep.json and the table written
    into ``staging`` (the result set that replaces ``folder``)."""
    store = RecordStore(folder / "records")
    if not resume:
        store.clear()
    records = store.load()
    if retry_failed:
        records = {k: r for k, r in records.items() if r.get("status") == "ok"}
    n_cases = len(rows_in) * math.prod(len(v) for v in grid_d.values())
    size = _chunk_size(n_cases, engine.n_workers if engine and engine.client
                       else workers or cpu_count())
    errors: list[ConfigError] = []
    planner = _plan(data, source, grid_d, rows_in, errors)
    with no_gc():
        cases = list(itertools.islice(planner, size))
    stream = any(c.config is not None and c.key not in records for c in cases)
    if not stream:                       # nothing to do in the first chunk: plan every case
        with no_gc():
            cases += list(planner)
        _check_some_valid(cases, errors)

    def write_meta():                    # sweep.json, once every case is planned
        swept = list(dict.fromkeys(
            [f"inputs.{k}" if "." in k else "case" for k in grid_d]
            + [f"inputs.{k}" if "." in k else "case" for c in cases for k in c.overrides]))
        write(staging / "sweep.json", {
            "homlimit_version": package_version(), "base": source, "base_case": data,
            "grid": grid_d, "table": None if table is None or isinstance(table, list)
            else str(table), "swept": swept, "n_cases": len(cases),
            "cases": [{"index": c.index, "key": c.key, "overrides": c.overrides,
                       "valid": c.config is not None} for c in cases]},
            units={"inputs": input_units()})
        return swept

    recorded = set(records)
    flat: dict[str, dict] = {}     # table rows of the batches' records, made on the workers
    work = _Work(records, size)
    swept = None
    if stream or any(work.todo(c) for c in cases):
        n_failed = sum(1 for r in records.values() if r.get("status", "ok") != "ok")
        total = n_cases if stream else len({c.key for c in cases if c.config is not None})
        done = 0 if stream else len({c.key for c in cases if c.key in records})

        def planned():
            yield from list(cases)
            for c in planner:
                cases.append(c)
                yield c

        def items():
            nonlocal swept
            with no_gc():
                yield from work.batches(planned())
            swept = write_meta()
            yield from work.singles()

        with Engine(workers, scheduler, progress) if engine is None \
                else contextlib.nullcontext(engine) as eng:
            _evaluate(eng, store, records, flat, work.owners, items(), total,
                      (done, n_failed if not stream else 0))
    if swept is None:
        swept = write_meta()
    n_resumed = len({c.key for c in cases if c.config is not None} & recorded)
    if n_resumed:
        log.info("resumed: %d distinct cases were already recorded in %s", n_resumed,
                 store.folder)
    rows = table_rows(cases, records, flat)
    files = {k: folder / p.name for k, p in write_table(staging, rows, swept).items()}
    files.update({"sweep_json": folder / "sweep.json", "records": store.folder})
    n_failed = sum(1 for r in rows if r["status"] != "ok")
    return SweepResult(folder, rows, swept, len(rows) - n_failed, n_failed, n_resumed,
                       time.perf_counter() - t0, files)


class _Work:
    """The work items of the cases not recorded yet, one task per distinct key: closed-form
    cases in batches of ``size`` as they come, the others (``singles``) after them;
    ``owners[k]``: the cases of item k."""

    def __init__(self, records: dict, size: int):
        self.seen = set(records)
        self.size = size
        self.owners: list[list[SweepCase]] = []
        self._single: list[SweepCase] = []

    def todo(self, c: SweepCase) -> bool:
        return c.config is not None and c.key not in self.seen

    def batches(self, cases):
        batch = []
        for c in cases:
            if not self.todo(c):
                continue
            self.seen.add(c.key)
            if not c.closed_form_only:
                self._single.append(c)
                continue
            batch.append(c)
            if len(batch) == self.size:
                yield self._item(batch)
                batch = []
        if batch:
            yield self._item(batch)

    def _item(self, batch):
        self.owners.append(batch)
        return "batch", ([c.config for c in batch], [c.key for c in batch])

    def singles(self):
        for c in self._single:
            self.owners.append([c])
            yield "case", c.config


def _evaluate(eng: Engine, store: RecordStore, records: dict, flat: dict,
              owners: list[list[SweepCase]], items, total: int, already: tuple[int, int]):
    """Run the work ``items`` on ``eng`` (closed-form batches, one task per other case;
    ``owners[k]``: the cases of item k, filled in as ``items`` is consumed): every record is
    stored the moment it arrives (a batch as one file, its text and its table rows made on the
    worker: ``flat``; other records in ``records``)."""

    def save(k, res):
        if isinstance(res, BatchText):
            store.put_batch_json(res.keys, res.text)
            flat.update(zip(res.keys, res.rows))
        else:
            store.put(owners[k][0].key, res)
            records[owners[k][0].key] = res

    def lost(item, exc):  # a task that raised (worker lost): not stored, so a rerun retries
        kind, payload = item
        recs = [failed_record(c, exc, time.perf_counter())
                for c in (payload[0] if kind == "batch" else [payload])]
        return recs if kind == "batch" else recs[0]

    def weight(res):
        if isinstance(res, BatchText):
            return len(res.keys), res.n_failed
        recs = res if isinstance(res, list) else [res]
        return len(recs), sum(1 for r in recs if r.get("status") != "ok")

    results = eng.run(evaluate_item, items, on_result=save, failed=lost, weight=weight,
                      total=total, already=already, description="sweep")
    for k, res in enumerate(results):   # lost tasks: failed in the table, not in the store
        if not isinstance(res, BatchText):
            for c, rec in zip(owners[k], res if isinstance(res, list) else [res]):
                records.setdefault(c.key, rec)


_rows = table_rows      # the name the table's rows had here (tests/test_sweep.py)
