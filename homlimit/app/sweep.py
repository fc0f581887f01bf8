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
"""

from __future__ import annotations

import contextlib
import csv
import gc
import itertools
import logging
import math
import time
import tomllib
import traceback
import unicodedata
from dataclasses import dataclass, field
from pathlib import Path
from sys import intern

import numpy as np

from .._io import sidecar, write_output
from ..errors import ParameterError, check_range
from . import registry
from .config import (
    SCHEMA,
    TOP_LEVEL,
    CaseConfig,
    ConfigError,
    array_key,
    case_data,
    check_base,
    load_case_inputs,
    read_text,
    shown,
)
from .engine import (
    Engine,
    RecordStore,
    batch_json,
    check_scheduler,
    cpu_count,
    record_key,
)

__all__ = ["MAX_CASES", "SweepCase", "SweepResult", "batch_closed_form", "flatten",
           "parse_grid", "plan_sweep", "read_table", "run_case", "sweep", "sweep_inputs",
           "write_table"]

log = logging.getLogger(__name__)

#: the files a sweep folder holds beside its records/ and report/ (nested sets)
SWEEP_NAMES = ("sweep.json", "results.parquet", "results.csv", sidecar("results.csv").name)

#: closed-form cases per vectorised task at most
BATCH = 2500
#: columns that come first in the table, before the swept inputs and the rest
META = ["case_index", "key", "status", "error", "case"]


@dataclass(frozen=True)
class SweepCase:
    """One case of a sweep: its position, overrides, key, and validated config (None: the
    case is invalid, ``error`` says why)."""

    index: int
    overrides: dict
    key: str
    config: CaseConfig | None = None
    error: str | None = None

    @property
    def closed_form_only(self) -> bool:
        """Evaluated in a vectorised batch (``batch_closed_form``): every model the case asks
        for is a batched one (``registry.Model.batched``: the closed forms)."""
        if self.config is None:
            return False
        on = [m for m in registry.models() if m.enabled(self.config)]
        # ties, floors, fc: the batch's arrays do not take them (one case at a time)
        return bool(on) and all(m.batched for m in on) and not self.config.case.real


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


# ----------------------------------------------------------------------------- the cases
#: cases a sweep may have (``--max-cases``), checked from the grid's and table's sizes before
#: any case is planned (planning keeps every case in memory, about 1 kB each)
MAX_CASES = 100_000
#: bytes of a table (a building stock of 100 000 walls is about 5 MB)
MAX_TABLE_BYTES = 256 << 20
#: problems of a table or grid listed at most (a binary file would give one per line)
MAX_PROBLEMS = 20
#: digits of an integer at most (Python's own limit of int(text))
MAX_DIGITS = 4300


def _value(text: str):
    """A grid or table value in TOML syntax (3, 0.15, true, "x"); a bare word is a string.
    ValueError (its reason) for what cannot be a value: an integer of more than 4300 digits,
    arrays nested too deeply."""
    text = text.strip()
    digits = text.lstrip("+-")
    if len(digits) > MAX_DIGITS and digits.isdigit():
        raise ValueError(f"an integer of {len(digits)} digits: allowed at most {MAX_DIGITS}")
    for number in (int, float):   # the common case, 20x faster than the TOML parser
        try:
            return number(text)
        except ValueError:
            pass
    try:
        return tomllib.loads(f"v = {text}")["v"]
    except tomllib.TOMLDecodeError:
        return text
    except ValueError as e:        # an integer of more than 4300 digits inside an array
        raise ValueError(f"not a value: {e}") from None
    except RecursionError:
        raise ValueError("not a value: arrays nested too deeply") from None


def _key_problem(key: str) -> str | None:
    """None for a case-file key (``name`` or ``section.key``), else the problem's text."""
    sec, dot, name = key.partition(".")
    if (not dot and key in TOP_LEVEL) or (dot and name in SCHEMA.get(sec, {})) \
            or array_key(key):
        return None
    return (f"key = {shown(key)} is out of range: allowed name or section.key of a case "
            "file, e.g. wall.l, masonry.a, mesh.size (docs/case-file.md)")


def _cap(problems: list[str]) -> list[str]:
    if len(problems) <= MAX_PROBLEMS:
        return problems
    return problems[:MAX_PROBLEMS] + [f"... and {len(problems) - MAX_PROBLEMS} more problems"]


def parse_grid(specs) -> dict[str, list]:
    """A grid from ``["wall.l=3,6,9", "masonry.a=0.15,0.3"]`` (the CLI's ``--grid``) or a
    dict {key: values}; values in TOML syntax. Every key is checked against the schema; every
    problem is reported at once (ConfigError, source "--grid" or "grid")."""
    source = "grid" if isinstance(specs, dict) else "--grid"
    problems: list[str] = []
    items = []
    if isinstance(specs, dict):
        items = [(str(k), list(v) if isinstance(v, list | tuple) else [v])
                 for k, v in specs.items()]
    else:
        for spec in specs or ():
            key, sep, values = str(spec).partition("=")
            if not sep or not values.strip():
                problems.append(f"{shown(str(spec))} is out of range: allowed "
                                "section.key=v1,v2,... e.g. wall.l=3,6,9")
                continue
            vals = []
            for v in values.split(","):
                try:
                    vals.append(_value(v))
                except ValueError as e:
                    problems.append(f"{key.strip()} = {shown(v.strip())}: {e}")
            items.append((key.strip(), vals))
    grid: dict[str, list] = {}
    for key, values in items:
        bad = _key_problem(key)
        if bad:
            problems.append(bad)
        elif key in grid:
            problems.append(f"key = {key!r} is given twice: allowed once, with all its values "
                            f"(e.g. {key}=v1,v2,v3)")
        elif not values:
            problems.append(f"key = {key!r} has no values: allowed at least one")
        else:
            grid[key] = values
    if problems:
        raise ConfigError(source, _cap(problems), "the grid")
    return grid


def read_table(path: str | Path) -> list[dict]:
    """The cases of a CSV table: a header of case keys (``wall.H``, ``masonry.a``, ``name``,
    ...), one case per row, values in TOML syntax; an empty cell leaves the base's value;
    blank lines and ``#`` lines are skipped. The file is read as a case file is
    (``config.read_text``: a regular UTF-8 file, a spreadsheet's byte-order mark allowed);
    every problem (unknown or repeated column, a row of another length than the header, a
    value that cannot be one) is reported at once, with its line (ConfigError)."""
    path = Path(path)
    source = f"table {path}"

    def fail(msg: str):
        raise ConfigError(source, [msg], "the table")

    text = read_text(path, "table", MAX_TABLE_BYTES, fail,
                     size_hint="100 000 cases are about 5 MB", bom=True)
    kept = [(n, ln) for n, ln in enumerate(text.splitlines(), 1)
            if ln.strip() and not ln.lstrip().startswith("#")]
    reader = csv.reader(ln for _, ln in kept)
    try:
        cells = list(reader)
    except csv.Error as e:       # a NUL byte, say
        fail(f"line {kept[reader.line_num - 1][0]} is not CSV: {e}")
    if not cells:
        fail("no header and no case: allowed a CSV with a header of case keys and at least "
             "one case")
    header = [k.strip() for k in cells[0]]
    problems = []
    for k in header:
        bad = _key_problem(k)
        if bad:
            problems.append(f"line {kept[0][0]}: column {bad}")
    for k in sorted({k for k in header if header.count(k) > 1}):
        problems.append(f"line {kept[0][0]}: column key = {k!r} is given twice: allowed once")
    rows = []
    for (n, _), row in zip(kept[1:], cells[1:]):
        if len(row) != len(header):
            problems.append(f"line {n} has {len(row)} cells, the header {len(header)}: allowed "
                            "one cell per column (an empty cell keeps the base's value)")
            continue
        case = {}
        for k, v in zip(header, row):
            if not v.strip():
                continue
            if any(unicodedata.category(ch) == "Cc" for ch in v):
                problems.append(f"line {n}, column {k}: {shown(v)} contains control "
                                "characters (a NUL byte, an escape, ...): allowed printable "
                                "text; a binary file?")
                continue
            try:
                case[k] = v if k == "name" else _value(v)
            except ValueError as e:
                problems.append(f"line {n}, column {k}: {shown(v.strip())}: {e}")
        rows.append(case)
    if problems:
        err = ConfigError(source, _cap(problems), "the table")
        err.columns = header        # the keys the table gives (sweep_inputs' base check)
        raise err
    if not rows:
        fail("no case: allowed a CSV with a header and at least one case")
    return rows


def plan_sweep(base=None, grid=None, table=None,
               max_cases: int = MAX_CASES) -> tuple[list[SweepCase], dict, str]:
    """The cases of a sweep (table rows × grid points, in that order), each validated and
    keyed. Returns (cases, base data, source). Raises ConfigError (a ParameterError) for a
    malformed grid, table or base, listing every problem (``sweep_inputs``), ParameterError
    for more than ``max_cases`` cases, and the first case's ConfigError when no case at all
    is valid."""
    data, source, grid, rows = sweep_inputs(base, grid, table, max_cases)
    errors: list[ConfigError] = []
    with _no_gc():
        cases = list(_plan(data, source, grid, rows, errors))
    _check_some_valid(cases, errors)
    return cases, data, source


def sweep_inputs(base, grid, table, max_cases: int = MAX_CASES
                 ) -> tuple[dict, str, dict, list[dict]]:
    """The base case's data and source, the parsed grid and the table's override rows,
    checked before any case is planned: the base read as ``run`` reads a case file
    (``config.case_data``) and its keys that no grid key or table column replaces checked as
    ``run`` checks them (``config.check_base``), every problem of the base, grid and table at
    once (one ConfigError); then the number of cases (table rows × grid points, counted, not
    built) against ``max_cases`` (ParameterError)."""
    max_cases = int(check_range("max_cases", max_cases, 1, 1e9))
    errors: list[ConfigError] = []
    data, source, grid_d, rows = None, "<dict>", {}, [{}]
    given = set(grid) if isinstance(grid, dict) else \
        {str(spec).partition("=")[0].strip() for spec in grid or ()}   # keys the base needn't give
    try:
        data, source, stem = case_data(base)
        data = dict(data) if isinstance(data, dict) else data
        if base is not None and not isinstance(base, dict):
            data.setdefault("name", stem)       # as load_case names a file's case
    except ConfigError as e:
        errors.append(e)
    if grid:
        try:
            grid_d = parse_grid(grid)
        except ConfigError as e:
            errors.append(e)
    if isinstance(table, list):
        rows = [dict(r) for r in table]
        bad = sorted({p for r in rows for k in r for p in [_key_problem(str(k))] if p})
        if bad:
            errors.append(ConfigError("table", bad, "the table"))
    elif table is not None:
        try:
            rows = read_table(table)
        except ConfigError as e:
            errors.append(e)
            given |= set(getattr(e, "columns", ()))
    if data is not None:
        try:
            check_base(data, source, given | {k for r in rows for k in r})
        except ConfigError as e:
            errors.insert(0, e)
    if errors:
        raise ConfigError.merged(errors, "the sweep's inputs")
    n = len(rows) * math.prod(len(v) for v in grid_d.values())
    if n > max_cases:
        parts = ([f"{len(rows):,} table rows"] if table is not None else []) + \
            [f"{len(v):,} {k}" for k, v in grid_d.items()]
        raise ParameterError(f"the sweep has {n:,} cases ({' x '.join(parts)}): out of range: "
                             f"allowed at most max_cases (--max-cases) = {max_cases:,}; "
                             "raise it, or split the sweep")
    return data, source, grid_d, rows


def _invalid(e: ConfigError) -> str:
    """An invalid case's error, one line: every problem, each naming its key."""
    cut = len(e.source) + 2
    return "invalid case: " + "; ".join(p[cut:] if p.startswith(e.source + ": ") else p
                                        for p in e.problems)


def _plan(data: dict, source: str, grid: dict, rows: list[dict], errors: list):
    """The cases one by one (``plan_sweep``), the grid's points made as they are needed;
    each invalid case's ConfigError is appended to ``errors``."""
    from .pipeline import package_version

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
                            error=_invalid(e))
            continue
        yield SweepCase(k, ov, record_key("case", inputs, version), config)


def _check_some_valid(cases: list[SweepCase], errors: list):
    if cases and all(c.config is None for c in cases):
        raise errors[0]


@contextlib.contextmanager
def _no_gc():
    """Python's cyclic garbage collector paused: planning and batches make tens of thousands
    of objects without cycles, and collecting that heap again and again costs 10 %."""
    was = gc.isenabled()
    gc.disable()
    try:
        yield
    finally:
        if was:
            gc.enable()


# ----------------------------------------------------------------------------- the tasks
def _failed(config: CaseConfig | None, exc: BaseException, t0: float) -> dict:
    from .pipeline import package_version

    return {"homlimit_version": package_version(),
            "case": None if config is None else config.name,
            "source": None if config is None else config.source,
            "inputs": None if config is None else config.as_dict(),
            "status": "failed", "error": f"{type(exc).__name__}: {exc}",
            "traceback": "".join(traceback.format_exception(exc)),
            "timings_s": {"total": time.perf_counter() - t0}}


def run_case(config: CaseConfig) -> dict:
    """One case's record: ``run(config, write=False).to_dict()`` and status "ok", or the
    error of a case that failed (status "failed", error, traceback). Runs on a worker."""
    from .pipeline import run

    t0 = time.perf_counter()
    try:
        rec = run(config, write=False).to_dict()
    except Exception as exc:  # a failed case never stops the sweep: it is recorded
        return _failed(config, exc, t0)
    rec.pop("files", None)
    return {**rec, "status": "ok"}


def batch_closed_form(configs: list[CaseConfig]) -> list[dict]:
    """Records of closed-form-only cases, as ``run_case`` gives them: the critical λ of
    mechanisms I and II of every case at once (``critical_I``, ``critical_II`` on arrays, the
    same arithmetic element by element as one case) and mechanism I's θ_m there, then
    ``mechanisms_I/II`` at that λ (arrays again) and ``Result.to_dict()`` per case.
    ``timings_s`` holds each case's share of the batch."""
    with _no_gc():
        return _batch_closed_form(configs)


def _batch_closed_form(configs: list[CaseConfig]) -> list[dict]:
    from ..closed_form import mechanisms as mech
    from ..closed_form.paper import dem_row
    from .pipeline import Result, conclude

    t0 = time.perf_counter()
    cases = [c.case for c in configs]
    walls = mech.wall_arrays(cases)
    rho, alpha, beta = walls["rho"], walls["alpha"], walls["beta"]
    H_b, L_b = walls["H"] / walls["b"], walls["L"] / walls["b"]
    tanpsi = np.array([cf.analysis.tanpsi or c.alpha for cf, c in zip(configs, cases)])
    lam_I, _ = mech.critical_I(rho, alpha, beta, H_b)
    theta_I = mech.theta_m_I(lam_I, rho, alpha, beta)
    lam_max_II = mech.lam_max_II(H_b, L_b, tanpsi)
    lam_II, _ = mech.critical_II(rho, tanpsi, lam_max_II)
    static_II = mech.static_critical_II(rho, tanpsi, lam_max_II)
    res_I = mech.mechanisms_I(cases, lam_I, theta_I, walls)
    res_II = mech.mechanisms_II(cases, tanpsi, lam_II, static_II, walls)
    out = []
    for config, m1, m2 in zip(configs, res_I, res_II):
        t1 = time.perf_counter()
        try:
            if isinstance(m2, Exception):
                raise m2
            res = Result(config=config, dem=dem_row(config.case),
                         mechanisms={m1.name: m1, m2.name: m2})
            conclude(res)          # as compute(): results checked, then the hinge check
            rec = {**res.to_dict(), "status": "ok"}
            rec.pop("files", None)
        except Exception as exc:  # recorded, as run_case records it
            rec = _failed(config, exc, t1)
        out.append(rec)
    share = (time.perf_counter() - t0) / max(len(configs), 1)
    for rec in out:
        if rec["status"] == "ok":
            rec["timings_s"] = {"closed-form mechanisms I and II (batch share)": share}
    return out


# ----------------------------------------------------------------------------- the table
def flatten(record: dict, prefix: str = "") -> dict:
    """A record as one table row: nested keys joined with "." (their summary.json paths),
    lists of numbers as ``path.0``, ``path.1``...; the inputs' [[tie]] and [[floor]] entries as
    ``inputs.tie.0.z``...; other lists of records (the FE scan, kept in the JSON record) and
    the traceback are left out; NaN and ±inf as None (null, as the stored
    JSON record has them)."""
    row: dict = {}
    _flatten_into(row, record, prefix)
    return row


def _flatten_into(row: dict, record: dict, prefix: str):
    for k, v in record.items():
        if k == "traceback":
            continue
        path = intern(f"{prefix}{k}")     # one key object per column: small pickles
        kind = type(v)
        if kind is float:
            row[path] = v if v - v == 0.0 else None    # NaN, ±inf: null
        elif kind is str or kind is int or v is None or kind is bool:
            row[path] = v          # the plain values first: most of a record
        elif isinstance(v, dict):
            _flatten_into(row, v, path + ".")
        elif isinstance(v, list | tuple):
            if all(not isinstance(x, dict | list | tuple) for x in v):
                row.update({f"{path}.{j}": None if type(x) is float and x - x != 0.0 else x
                            for j, x in enumerate(v)})
            elif path.startswith("inputs.") and all(isinstance(x, dict) for x in v):
                for j, x in enumerate(v):    # [[tie]], [[floor]]: inputs.tie.0.yield_force
                    _flatten_into(row, x, f"{path}.{j}.")
        else:
            row[path] = v


def record_row(record: dict) -> dict:
    """A record's part of its table row: status, error, then ``flatten`` of the rest but its
    ``units`` table (the same for every case: the table's metadata, ``write_table``)."""
    return {"status": record.get("status"), "error": record.get("error"),
            **flatten({k: v for k, v in record.items()
                       if k not in ("status", "error", "units")})}


def _rows(cases: list[SweepCase], records: dict[str, dict],
          flat: dict[str, dict] | None = None) -> list[dict]:
    """The table rows in sweep order; ``flat``: rows ``record_row`` already made (on the
    workers, for the batches), by key."""
    rows, flat = [], flat or {}
    for c in cases:
        fr = flat.get(c.key)
        if fr is None:
            rec = records.get(c.key)
            if rec is None:  # invalid, or a task lost with its worker
                rec = {"status": "failed", "error": c.error or "no record (the task was lost)"}
            fr = record_row(rec)
        row = {"case_index": c.index, "key": c.key, **fr}
        if c.config is not None:  # a case's own name and source (records are shared by key)
            row.update({"case": c.config.name, "source": c.config.source})
        rows.append(row)
    return rows


def _column(values: list):
    """One table column for pyarrow (rows from ``record_row``: NaN already null, as a stored
    JSON record has it); a column that mixes kinds (numbers and text) as text."""
    import pyarrow as pa

    try:
        return pa.array(values)
    except (pa.ArrowInvalid, pa.ArrowTypeError):
        return pa.array([None if v is None else str(v) for v in values])


def write_table(folder: Path, rows: list[dict], swept: list[str]) -> dict[str, Path]:
    """results.parquet and results.csv: one row per case, META, the swept inputs, the rest;
    the unit of every column (``report.column_unit``) and the schema version as the Parquet
    metadata and in the CSV's sidecar results.csv.json (``_io.write_output``)."""
    import pyarrow as pa

    from .report import column_unit

    seen: dict = {}
    for r in rows:          # every row's keys in first-seen order (dict.update keeps it)
        seen.update(r)
    cols = list(dict.fromkeys(META + swept + list(seen)))
    table = pa.table({c: _column([r.get(c) for r in rows]) for c in cols})
    units = {c: column_unit(c) for c in cols if c not in META}
    files = {"parquet": folder / "results.parquet", "csv": folder / "results.csv"}
    for path in files.values():       # units and schema version: metadata, CSV's sidecar
        write_output(path, table, units=units)
    return files


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
    from .pipeline import folder_name, result_folder, source_of

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
    from .pipeline import package_version

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
    with _no_gc():
        cases = list(itertools.islice(planner, size))
    stream = any(c.config is not None and c.key not in records for c in cases)
    if not stream:                       # nothing to do in the first chunk: plan every case
        with _no_gc():
            cases += list(planner)
        _check_some_valid(cases, errors)

    def write_meta():                    # sweep.json, once every case is planned
        from .report import input_units

        swept = list(dict.fromkeys(
            [f"inputs.{k}" if "." in k else "case" for k in grid_d]
            + [f"inputs.{k}" if "." in k else "case" for c in cases for k in c.overrides]))
        write_output(staging / "sweep.json", {
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
            with _no_gc():
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
    rows = _rows(cases, records, flat)
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
        if isinstance(res, _BatchText):
            store.put_batch_json(res.keys, res.text)
            flat.update(zip(res.keys, res.rows))
        else:
            store.put(owners[k][0].key, res)
            records[owners[k][0].key] = res

    def lost(item, exc):  # a task that raised (worker lost): not stored, so a rerun retries
        kind, payload = item
        recs = [_failed(c, exc, time.perf_counter())
                for c in (payload[0] if kind == "batch" else [payload])]
        return recs if kind == "batch" else recs[0]

    def weight(res):
        if isinstance(res, _BatchText):
            return len(res.keys), res.n_failed
        recs = res if isinstance(res, list) else [res]
        return len(recs), sum(1 for r in recs if r.get("status") != "ok")

    results = eng.run(_evaluate_item, items, on_result=save, failed=lost, weight=weight,
                      total=total, already=already, description="sweep")
    for k, res in enumerate(results):   # lost tasks: failed in the table, not in the store
        if not isinstance(res, _BatchText):
            for c, rec in zip(owners[k], res if isinstance(res, list) else [res]):
                records.setdefault(c.key, rec)


@dataclass(frozen=True)
class _BatchText:
    """A batch's records as the text of its record file (``engine.batch_json``) and as table
    rows (``record_row``), both made on the worker: the client writes the text as it is."""

    keys: list[str]
    text: str
    rows: list[dict]
    n_failed: int


def _evaluate_item(item):
    kind, payload = item
    if kind == "case":
        return run_case(payload)
    configs, keys = payload
    recs = batch_closed_form(configs)
    return _BatchText(keys, batch_json(dict(zip(keys, recs))), [record_row(r) for r in recs],
                      sum(1 for r in recs if r["status"] != "ok"))
