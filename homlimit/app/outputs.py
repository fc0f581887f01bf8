"""Stage "outputs": where a case's result set goes (``output_dir``, ``folder_name``), its
source as the manifest records it (``source_of``), the result set itself
(``result_folder``: whole or nothing) and the files of a run (``write_result``: each model's
files, the DEM's, summary.json last)."""

from __future__ import annotations

import hashlib
import os
import unicodedata
from contextlib import contextmanager
from pathlib import Path

from .. import _io
from .._version import package_version
from . import registry, report, report_html
from .config import CaseConfig
from .dem_stage import write_files as write_dem_files
from .models import stage
from .result import Result

__all__ = ["MAX_FOLDER_NAME", "folder_name", "output_dir", "outputs_of", "result_folder",
           "source_of", "write_result"]

MAX_FOLDER_NAME = 80  # bytes of a folder name made from a case name


def folder_name(name: str) -> str:
    """A case name made safe as one folder name: letters, digits and ``-_.+`` kept, anything
    else (separators, control characters, spaces) replaced by ``_``, no leading dots (no
    hidden folder, no ``..``), at most MAX_FOLDER_NAME bytes; when anything was changed, a
    short hash of the original name is appended so that different names stay apart."""
    keep = "".join(ch if (ch.isalnum() or ch in "-_.+") and unicodedata.category(ch)[0] != "C"
                   else "_" for ch in unicodedata.normalize("NFC", name))
    keep = keep.lstrip(".") or "case"
    while len(keep.encode()) > MAX_FOLDER_NAME - 9:
        keep = keep[:-1]
    if keep != name:
        keep += "-" + hashlib.sha256(name.encode("utf-8", "surrogatepass")).hexdigest()[:8]
    return keep


def output_dir(config: CaseConfig, out: str | Path | None = None) -> Path:
    """--out, else [output] dir (both taken as given), else homlimit-out/NAME/ (relative to the
    working folder) with NAME the case name made safe (``folder_name``); a case changed by
    ``--set`` has a hash of its inputs in its name (``config.load_case``)."""
    if out:
        return Path(out)
    if config.output.dir:
        return Path(config.output.dir)
    return Path("homlimit-out") / folder_name(config.name)


def source_of(where) -> dict:
    """A result set's source, as its manifest records it: ``{"source": absolute path,
    "source_sha256": hash of the file's bytes}`` for a case file, ``{"source":
    "embedded:B1"}`` for the embedded default case (``None``, or a CaseConfig read from it),
    ``{"source": "<dict>", "source_sha256": hash of its JSON}`` for a dict given in Python.
    ``where``: a path, None, a dict or a CaseConfig (its ``source``)."""
    if isinstance(where, CaseConfig):
        if where.source.startswith("<default"):
            return {"source": "embedded:B1"}
        if where.source.startswith("<"):
            return {"source": where.source, "source_sha256": hashlib.sha256(
                _io.json_bytes(where.as_dict(), sort_keys=True)).hexdigest()}
        where = Path(where.source)
    if where is None:
        return {"source": "embedded:B1"}
    if isinstance(where, dict):
        return {"source": "<dict>", "source_sha256": hashlib.sha256(
            _io.json_bytes(where, sort_keys=True)).hexdigest()}
    path = Path(os.path.abspath(where))
    try:
        digest = hashlib.sha256(path.read_bytes()).hexdigest() if path.is_file() else None
    except OSError:
        digest = None
    return {"source": str(path), "source_sha256": digest}


@contextmanager
def result_folder(out: str | Path, command: str, **info):
    """Write one command's result set into ``out`` (``_io.result_set``): checks the folder and
    creates the staging folder now, before any work; yields the staging folder, where the
    caller writes its files under their final names; on success the set (with its manifest:
    version, ``command``, ``info``, files) replaces ``out`` whole, on failure or interrupt
    ``out`` is left as it was. The reusable door for every command that writes files.
    ``info``'s ``source`` (``source_of``; default ``embedded:<command>``) and ``command``
    must match the set already in ``out``, if any: another command's or another source's set
    is refused before any work (exit 2 with an ``--out`` hint, ``_io.check_owner``), and
    what that set did not write (nested sets, a user's files) is kept."""
    info = {"source": f"embedded:{command}", **info}
    with _io.result_set(out, info={"homlimit_version": package_version(), "command": command,
                                   **info}, names=report.OUTPUT_NAMES) as staging:
        yield staging


def outputs_of(result: Result) -> dict[str, tuple[str, object]]:
    """Key → (file name, what ``report.write`` writes there) for the files the case asks for:
    each model's (``registry.Model.files``), in the registry's order."""
    out: dict[str, tuple[str, object]] = {}
    for model in registry.models():
        if model.files is not None:
            out.update(model.files(result))
    return out


def write_result(result: Result, staging: Path, out: Path) -> dict[str, Path]:
    """Write every output of ``result`` into ``staging`` (a ``result_folder``), under the names
    they will have in ``out``; summary.json last, listing them all. Returns key → final path."""
    files = {}
    with stage(result.timings, "writing files"):
        for key, (name, data) in outputs_of(result).items():
            report.write(staging / name, data)
            files[key] = out / name
        if result.dem_run is not None:
            files.update(write_dem_files(result.dem_run, result.config.output, staging, out,
                                     f"case {result.name}"))
        if result.config.output.report:       # after the pictures it embeds
            report.write(staging / "report.html", report_html.page(result, staging))
            files["report_html"] = out / "report.html"
        if result.config.output.json:
            files["summary_json"] = out / "summary.json"
            result.files = files
            report.write(staging / "summary.json", result.to_dict())
    return files
