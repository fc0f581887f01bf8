"""A sweep's table: its records as rows (``flatten``, ``record_row``, ``table_rows``) and the
rows as results.parquet and results.csv with their units (``write_table``)."""

from __future__ import annotations

from pathlib import Path
from sys import intern

from .report import column_unit
from .sweep_cases import SweepCase
from .writers import write

__all__ = ["META", "flatten", "record_row", "table_rows", "write_table"]

#: columns that come first in the table, before the swept inputs and the rest
META = ["case_index", "key", "status", "error", "case"]


def flatten(record: dict, prefix: str = "") -> dict:
    """A record as one table row: nested keys joined with "." (their summary.json paths),
    lists of numbers as ``path.0``, ``path.1``...; the inputs' [[tie]] and [[floor]] entries as
    ``inputs.tie.0.z``...; other lists of records (the FE scan, kept in the JSON record) and
    the traceback are left out; NaN and ±inf as None (null, as the stored JSON record has
    them)."""
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


def table_rows(cases: list[SweepCase], records: dict[str, dict],
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
    metadata and in the CSV's sidecar results.csv.json (``writers.write``)."""
    import pyarrow as pa

    seen: dict = {}
    for r in rows:          # every row's keys in first-seen order (dict.update keeps it)
        seen.update(r)
    cols = list(dict.fromkeys(META + swept + list(seen)))
    table = pa.table({c: _column([r.get(c) for r in rows]) for c in cols})
    units = {c: column_unit(c) for c in cols if c not in META}
    files = {"parquet": folder / "results.parquet", "csv": folder / "results.csv"}
    for path in files.values():       # units and schema version: metadata, CSV's sidecar
        write(path, table, units=units)
    return files
