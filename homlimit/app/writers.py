"""One writer per file format: ``write(path, data)`` picks it from the file's suffix
(``WRITERS``): JSON data, CSV records, a meshio mesh (.vtu, .xdmf, .msh) or a picture (a
function that draws to a path). Every writer is whole-or-nothing (``homlimit._io``): JSON and
CSV go through ``_io.write_output`` with their units (``app.units``). ``read_csv`` reads such
a CSV back into plain keys and numbers.
"""

from __future__ import annotations

import csv
import math
import re
from collections.abc import Callable, Iterable, Mapping
from pathlib import Path

from .._io import write_output
from ..errors import ParameterError
from ..fe import mesh as fe_mesh
from .units import UNITS, csv_header, units_of, unknown_units

__all__ = ["WRITERS", "read_csv", "write"]


def _write_csv(path: Path, records: Iterable[Mapping], columns: list[str] | None = None):
    records = [dict(r) for r in records]
    if columns is None:
        columns = list(dict.fromkeys(k for r in records for k in r))
    unknown_units(columns)
    head = {k: csv_header(k) if k in UNITS else f"{k} [?]" for k in columns}
    return write_output(path, [{head[k]: v for k, v in r.items()} for r in records],
                        units={head[k]: UNITS.get(k) for k in columns},
                        columns=[head[k] for k in columns])


def _write_json(path: Path, data) -> Path:
    """JSON data with its units: the ``units`` table ``data`` carries (summary.json's, by
    section), else the unit of every key it holds (``units_of``)."""
    units = data["units"] if isinstance(data, Mapping) and "units" in data else units_of(data)
    return write_output(path, data, units=units)


_UNIT_SUFFIX = re.compile(r"^(.*?) \[[^\]]*\]$")


def read_csv(path: str | Path) -> list[dict]:
    """Read a CSV written by ``write``: plain keys (the unit suffix dropped), numbers as floats
    (ints where integral text), empty cells as NaN, other text as is."""
    def value(text: str):
        if text == "":
            return math.nan
        for conv in (int, float):
            try:
                return conv(text)
            except ValueError:
                pass
        return text

    with open(path, newline="", encoding="utf-8") as fh:
        rows = list(csv.DictReader(fh))
    return [{(_UNIT_SUFFIX.match(k).group(1) if _UNIT_SUFFIX.match(k) else k): value(v)
             for k, v in r.items()} for r in rows]



WRITERS: dict[str, Callable] = {
    ".json": _write_json, ".csv": _write_csv, ".png": lambda path, draw: draw(path),
    **dict.fromkeys((".vtu", ".xdmf", ".msh"), lambda path, mesh: fe_mesh.write(mesh, path))}


def write(path: str | Path, data) -> Path:
    """Write ``data`` to ``path`` with the writer of its suffix (``WRITERS``)."""
    path = Path(path)
    writer = WRITERS.get(path.suffix.lower())
    if writer is None:
        raise ParameterError(f"file suffix = {path.suffix!r} is out of range: allowed one of "
                             + ", ".join(WRITERS))
    writer(path, data)
    return path
