"""A sweep's inputs and cases: the grid (``parse_grid``), the table (``read_table``), the base
and every key checked at once before any case is planned (``sweep_inputs``), one planned
case (``SweepCase``)."""

from __future__ import annotations

import contextlib
import csv
import gc
import math
import tomllib
import unicodedata
from dataclasses import dataclass
from pathlib import Path

from ..errors import ParameterError, check_range
from . import registry
from .case_checks import toml_float
from .config import (
    SCHEMA,
    TOP_LEVEL,
    CaseConfig,
    ConfigError,
    array_key,
    case_data,
    check_base,
    read_text,
    shown,
)

__all__ = ["MAX_CASES", "MAX_DIGITS", "MAX_PROBLEMS", "MAX_TABLE_BYTES", "SweepCase",
           "invalid_error", "key_problem", "no_gc", "parse_grid", "read_table", "sweep_inputs"]


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
    for number in (int, toml_float):   # the common case, 20x faster than the TOML parser
        try:
            return number(text)
        except ValueError:
            pass
    try:
        return tomllib.loads(f"v = {text}", parse_float=toml_float)["v"]
    except tomllib.TOMLDecodeError:
        return text
    except ValueError as e:        # an integer of more than 4300 digits inside an array
        raise ValueError(f"not a value: {e}") from None
    except RecursionError:
        raise ValueError("not a value: arrays nested too deeply") from None


def key_problem(key: str) -> str | None:
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
        bad = key_problem(key)
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
        bad = key_problem(k)
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
        bad = sorted({p for r in rows for k in r for p in [key_problem(str(k))] if p})
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


def invalid_error(e: ConfigError) -> str:
    """An invalid case's error, one line: every problem, each naming its key."""
    cut = len(e.source) + 2
    return "invalid case: " + "; ".join(p[cut:] if p.startswith(e.source + ": ") else p
                                        for p in e.problems)



@contextlib.contextmanager
def no_gc():
    """Python's cyclic garbage collector paused: planning and batches make tens of thousands
    of objects without cycles, and collecting that heap again and again costs 10 %."""
    was = gc.isenabled()
    gc.disable()
    try:
        yield
    finally:
        if was:
            gc.enable()
