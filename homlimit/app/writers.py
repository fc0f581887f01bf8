"""The result files: one registry of every file a command writes (``OUTPUTS``: name → its
writer, where its units are, its schema version) and one writer per file format
(``FORMATS``: JSON data, CSV records, Parquet tables, a meshio mesh, a picture, a page).

``write(path, data)`` writes a file with its format's writer and the schema version its
entry gives; JSON, CSV and Parquet go through ``_io.write_output`` (whole or nothing, led by
``schema_version`` and ``homlimit_version``, with their units: CSV headers ``name [unit]`` and
the sidecar ``NAME.csv.json``, JSON's ``units`` map, Parquet's metadata), pictures through
``_io.write_figure``, meshes through ``fe.mesh.write``. ``read_csv`` reads such a CSV back
into plain keys and numbers. A new output file is one ``Output`` here (and its quantities'
units in ``app.units``).
"""

from __future__ import annotations

import csv
import math
import re
from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass
from pathlib import Path

from .._io import SCHEMA_VERSION, write_output, write_text
from ..errors import ParameterError
from ..fe import mesh as fe_mesh
from .units import UNITS, csv_header, units_of, unknown_units

__all__ = ["FORMATS", "OUTPUTS", "OUTPUT_NAMES", "WRITERS", "Output", "read_csv", "write"]


def _write_csv(path: Path, records: Iterable[Mapping], columns: list[str] | None = None,
               schema: int = SCHEMA_VERSION):
    records = [dict(r) for r in records]
    if columns is None:
        columns = list(dict.fromkeys(k for r in records for k in r))
    unknown_units(columns)
    head = {k: csv_header(k) if k in UNITS else f"{k} [?]" for k in columns}
    return write_output(path, [{head[k]: v for k, v in r.items()} for r in records],
                        units={head[k]: UNITS.get(k) for k in columns},
                        columns=[head[k] for k in columns], schema=schema)


def _write_json(path: Path, data, schema: int = SCHEMA_VERSION) -> Path:
    """JSON data with its units: the ``units`` table ``data`` carries (summary.json's, by
    section), else the unit of every key it holds (``units_of``)."""
    units = data["units"] if isinstance(data, Mapping) and "units" in data else units_of(data)
    return write_output(path, data, units=units, schema=schema)


def _write_mesh(path: Path, mesh, schema: int = SCHEMA_VERSION) -> Path:
    return fe_mesh.write(mesh, path)


def _write_picture(path: Path, draw: Callable[[Path], None], schema: int = SCHEMA_VERSION):
    return draw(path)


def _write_page(path: Path, text: str, schema: int = SCHEMA_VERSION) -> Path:
    """A text page (report.html: ``app.report_html.page``), whole or nothing."""
    return write_text(path, text)


#: suffix → the one writer of that format: writer(path, data, schema)
FORMATS: dict[str, Callable] = {
    ".json": _write_json, ".csv": _write_csv, ".png": _write_picture, ".html": _write_page,
    **dict.fromkeys((".vtu", ".xdmf", ".msh"), _write_mesh)}
WRITERS = FORMATS          # the name before the registry


@dataclass(frozen=True)
class Output:
    """One result file: its name, the command writing it, where its units are (``units``:
    "columns" a CSV's headers and sidecar, "keys" or "sections" a JSON file's ``units`` map,
    "metadata" Parquet's, "fields" a mesh's field data, "axes" a picture's labels, "inline"
    a page's table headers and text, "" none),
    the version of its layout (``schema``) and, for a file not written by ``write``, the one
    function that writes it (``by``)."""

    name: str
    command: str
    units: str
    schema: int = SCHEMA_VERSION
    by: str = "app.writers.write"

    @property
    def suffix(self) -> str:
        return Path(self.name).suffix.lower()


def _outputs(command: str, units: str, names: str, **kw) -> list[Output]:
    return [Output(n, command, units, **kw) for n in names.split()]


#: name → Output: every file a homlimit command writes (a file of these names that the set
#: in an output folder did not write is refused before any work, ``_io.check_output_folder``)
OUTPUTS: dict[str, Output] = {o.name: o for o in [
    *_outputs("run", "sections", "summary.json"),
    *_outputs("run", "axes", "vg_lambda.png mesh.png mechanism.png stress.png"),
    *_outputs("run", "columns", "fe_scan.csv"),
    *_outputs("run", "fields", "mechanism.vtu static.vtu"),
    *_outputs("mesh", "fields", "mesh.vtu"),
    *_outputs("table1", "columns", "table1.csv"),
    *_outputs("table1", "keys", "table1.json"),
    *_outputs("table1", "axes", "table1.png"),
    *_outputs("figure2", "axes", "figure2.png"),
    *_outputs("figure2", "keys", "figure2.json"),
    *_outputs("crack-study", "columns", "crack_study.csv"),
    *_outputs("crack-study", "axes", "crack_study.png"),
    *_outputs("pulse", "columns", "spectra.csv"),
    *_outputs("pulse", "axes", "spectra.png"),
    *_outputs("mesh", "keys", "mesh.json"),
    *_outputs("run", "fields", "blocks.vtu blocks_contacts.vtu"),
    *_outputs("run", "columns", "blocks_contacts.csv"),
    *_outputs("run", "axes", "blocks_mechanism.png blocks_whole.png"),
    *_outputs("run", "columns", "blocks_scan.csv"),
    *_outputs("table1", "columns", "table1_blocks.csv"),
    *_outputs("table1", "keys", "table1_blocks_ratios.json"),
    *_outputs("sweep", "keys", "sweep.json"),
    *_outputs("sweep", "metadata", "results.parquet"),
    *_outputs("sweep", "columns", "results.csv"),
    *_outputs("sweep", "axes", "vnorm_swept.png critical_map.png tanpsi.png "
                              "vg_histogram.png", by="app.sweep_report.report"),
    *_outputs("verify", "keys", "verify.json"),
    *_outputs("verify", "columns", "verify.csv"),
    *_outputs("run", "columns", "fe_adapt.csv"),
    *_outputs("run", "axes", "adapt.png code_check.png"),
    *_outputs("run", "", "dem.pvd", by="dem.output.write_series"),
    *_outputs("run", "axes", "dem_snapshots.png", by="dem.output.plot_snapshots"),
    *_outputs("table1", "columns", "table1_dem.csv"),
    *_outputs("table1", "keys", "table1_dem_ratios.json"),
    *_outputs("run", "inline", "report.html"),
]}
#: every file name a command writes, the CSV files' sidecars (NAME.csv.json) included
OUTPUT_NAMES = tuple(OUTPUTS) + tuple(n + ".json" for n in OUTPUTS if n.endswith(".csv"))


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


def write(path: str | Path, data, *, units: Mapping | None = None) -> Path:
    """Write ``data`` to ``path`` with the writer of its format (``FORMATS``) and the schema
    version of its ``OUTPUTS`` entry (a name not registered there: the current version).
    ``units``: a unit map made by the caller (by key or column: the sweep's tables, whose
    columns are summary.json paths), for JSON, CSV and Parquet, instead of ``app.units``'."""
    path = Path(path)
    entry = OUTPUTS.get(path.name)
    schema = entry.schema if entry is not None else SCHEMA_VERSION
    suffix = path.suffix.lower()
    if units is not None and suffix in (".json", ".csv", ".parquet"):
        write_output(path, data, units=units, schema=schema)
        return path
    writer = FORMATS.get(suffix)
    if writer is None:
        raise ParameterError(f"file suffix = {path.suffix!r} is out of range: allowed one of "
                             + ", ".join(FORMATS))
    writer(path, data, schema=schema)
    return path
