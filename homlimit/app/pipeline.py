"""The whole analysis of one wall, shared by the three doors.

``homlimit run CASE.toml``, ``python -m homlimit run CASE.toml`` and ``homlimit.run(CASE)`` all
call ``run`` below, which

1. validates the case (``config``), before any computation;
2. runs every registered model the case enables (``registry``, ``models``): the closed-form
   mechanisms I (eqs 8–14) and II (eqs 16–20) at their critical slenderness and their
   v̄_g(λ) curves; with ``[analysis] fe`` the finite-element path (the impulse scan over
   collapse heights, the whole wall's mechanism and crack, its static lower bound); with
   ``[analysis] blocks`` the rigid blocks;
3. checks that every result is a finite number (``ResultError`` naming the mechanism and the
   quantity otherwise);
4. writes the result files (``report.write``) as one result set (``result_folder``): into a
   staging folder that replaces the output folder in one rename at the end, so the folder holds
   the previous set or the new one, never a mix. The output folder is checked (and the staging
   folder created) before any computation.

Progress and warnings go to the ``logging`` module (the command line shows them). The
stages live in one module each (``case``, ``models``, ``checks``, ``pulses``, ``outputs``),
the other commands' work (``table1_records``, ``crack_study_records``, ``mesh_case``,
``figure2_curves``) in ``tables``; this module re-exports their public names.
"""

from __future__ import annotations

import logging
import os
from pathlib import Path

from .._version import package_version
from ..closed_form.paper import dem_row
from ..errors import check_type
from . import registry
from .case import announce, resolve_case
from .checks import check_results, conclude, hinge_checks
from .code_check import code_check
from .config import CaseConfig
from .models import FERocker, fe_cache_path, fe_rocker, read_fe_cache, write_fe_cache
from .outputs import (
    MAX_FOLDER_NAME,
    folder_name,
    output_dir,
    outputs_of,
    result_folder,
    source_of,
    write_result,
)
from .pulses import MAX_RECORD_BYTES, pulse_records
from .result import Result
from .tables import (
    crack_study_records,
    figure2_curves,
    mesh_case,
    table1_blocks_records,
    table1_records,
)

# the stages, one module each: case (``case``) → models (``registry``, ``models``; their
# product ``result.Result``) → mechanisms (``checks``) → impulse/pulses (``pulses``) →
# outputs (``outputs``); the other commands' work in ``tables``. Their public names are
# re-exported here, the door every command and ``homlimit.run`` go through.
__all__ = ["FERocker", "MAX_FOLDER_NAME", "MAX_RECORD_BYTES", "Result", "announce",
           "check_results", "compute", "conclude", "crack_study_records", "fe_cache_path",
           "fe_rocker", "figure2_curves", "folder_name", "hinge_checks", "mesh_case",
           "output_dir", "outputs_of", "package_version", "pulse_records", "read_fe_cache",
           "resolve_case", "result_folder", "run", "source_of", "table1_blocks_records",
           "table1_records", "write_fe_cache", "write_result"]

log = logging.getLogger(__name__)


def compute(config: CaseConfig, map=None) -> Result:
    """The models the case asks for (``registry.models``: the closed forms, the FE path, the
    rigid blocks, ...), in the registry's order, then ``conclude``; writes nothing. ``map``: a
    map hook (``engine.Engine.stored_map``) for the models that run their work as tasks
    (``registry.Model.tasks``); without it they run it here."""
    result = Result(config=config, dem=dem_row(config.case))
    for model in registry.models():
        if model.enabled(config):
            model.run(config, result, **({"map": map} if model.tasks and map is not None else {}))
    result = conclude(result)
    result.code_check = code_check(result)
    return result



def run(path_or_dict: str | Path | dict | CaseConfig | None = None, *,
        out: str | Path | None = None, write: bool = True,
        overrides: list[str] | dict | None = None, command: str = "run",
        tasks=None) -> Result:
    """Run the case: validate, closed forms, FE (if asked), write files to ``out``.

    ``path_or_dict``: a TOML case file, a dict of the same shape, a CaseConfig, or None for the
    embedded default (Table 1's B1); ``overrides``: "section.key=value" strings or a
    {"section.key": value} dict applied before validation. ``out`` defaults to [output] dir or
    homlimit-out/NAME/ (``output_dir``); the files are one result set (``result_folder``):
    the folder is checked before any computation and replaced whole at the end; a folder
    holding the set of another source or another command (``command``, recorded in the
    manifest: "run", or "demo" for the command line's demo) is refused. ``tasks(folder)``:
    the map hook of ``compute``, asked for once the output folder has been checked (its
    records may live there); None: every model's work here.
    Raises ConfigError/ParameterError for bad input (an argument of the wrong type too:
    ``write`` is a bool, ``out`` a path or None) and an unusable output folder (before any
    computation), SolverError when a conic program does not end optimal, ResultError when a
    result is not a finite number, OutputError when the files cannot be written (the previous
    set is then kept).
    """
    check_type("write", write, (bool,), "True or False")
    check_type("out", out, (str, os.PathLike, type(None)),
               "a folder's path (str or pathlib.Path), or None (the default folder)")
    check_type("overrides", overrides, (list, tuple, dict, type(None)),
               "a list of 'section.key=value' strings, a {'section.key': value} dict, or None")
    config = resolve_case(path_or_dict, overrides)
    announce(config)
    if not write:
        return compute(config)
    target = output_dir(config, out)
    with result_folder(target, command, case=config.name, **source_of(config)) as staging:
        result = compute(config, None if tasks is None else tasks(Path(target)))
        result.files = write_result(result, staging, target)
    if result.fe is not None:       # for `homlimit pulse` on this case (``fe_rocker``)
        write_fe_cache(config, result.fe)
    return result
