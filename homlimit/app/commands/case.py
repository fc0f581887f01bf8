"""The commands of one case: ``homlimit run``, ``demo``, ``pulse`` and ``mesh``."""

from __future__ import annotations

from contextlib import ExitStack
from pathlib import Path

from ...closed_form.paper import dem_row
from ...errors import ParameterError
from .. import pipeline, plots, report
from ..config import load_case
from ..door import (
    emit_json,
    interruptible,
    setup_logging,
    stdout_quiet,
    stored_tasks,
)
from ..engine import RecordStore


def pulse(case, as_json, out, verbose, quiet, overrides):
    """``homlimit pulse``'s work: see ``cli.pulse``."""
    setup_logging(verbose, quiet, as_json)
    with stdout_quiet(as_json or verbose) as stdout:
        config = load_case(case, overrides)
        pipeline.announce(config)
        out = out or pipeline.output_dir(config) / "pulse"
        with pipeline.result_folder(out, "pulse", case=config.name,
                                    **pipeline.source_of(config)) as staging:
            points, fe = pipeline.pulse_records(config)
            dem = dem_row(config.case)
            report.write(staging / "spectra.csv", [p.as_dict() for p in points])
            plots.plot_spectra(staging / "spectra.png", points,
                               dem_vnorm=None if dem is None else dem.vg_norm,
                               title=f"case {config.name}: critical pulses")
    files = [out / "spectra.csv", out / "spectra.png"]
    cache = None if fe is None else {"path": fe.cache, "read": fe.from_cache}
    if as_json:
        emit_json(stdout, {"points": [p.as_dict() for p in points], "files": files,
                           "fe_cache": cache})
        return
    print(report.format_spectra(points, title=f"case {config.name}: overturning spectra "
                                              "(pgv/vg(eq.7): over the ideal impulse)"))
    if fe is not None and fe.cache is not None:
        print(f"\nFE result {'read from' if fe.from_cache else 'written to'} cache {fe.cache}")
    print("\nfiles: " + ", ".join(map(str, files)))


def mesh(case, as_json, out, overrides):
    """``homlimit mesh``'s work: see ``cli.mesh``."""
    setup_logging(False, False, as_json)
    with stdout_quiet(as_json) as stdout:
        config = load_case(case, overrides)
        pipeline.announce(config)
        info = pipeline.mesh_case(config, out or pipeline.output_dir(config) / "mesh")
    if as_json:
        emit_json(stdout, info)
    else:
        print(f"case {config.name}: {info['n_triangles']} triangles, {info['n_nodes']} nodes; "
              + ", ".join(f"{k} {v}" for k, v in info["regions"].items()))
        print("files: " + ", ".join(info["files"].values()))


def run_case(case: Path | None, as_json: bool, out: Path | None, verbose: bool,
             quiet: bool, overrides: list[str] | None, command: str = "run",
             workers: int | None = None, scheduler: str | None = None, resume: bool = True):
    """``homlimit run``'s (and ``demo``'s) work: see ``cli.run_cmd``. With ``[analysis] dem``
    the DEM's trials are tasks of a Dask engine, their records kept in OUT/records/ as they end
    and read back by the same run again (``--no-resume``: cleared first)."""
    setup_logging(verbose, quiet, as_json)
    with stdout_quiet(as_json or verbose) as stdout, ExitStack() as stack:
        config = load_case(case, overrides)
        if not config.analysis.dem:
            _no_engine_without_dem({f"--workers {workers}": workers is not None,
                                    f"--scheduler {scheduler}": scheduler is not None,
                                    "--no-resume": not resume})

        def tasks(target: Path):
            # the output folder is checked by now: its records may be read or cleared
            store = RecordStore(target / "records")
            stack.enter_context(interruptible(store.folder))
            return stack.enter_context(stored_tasks(
                store, "run-dem", "DEM trial", resume=resume, workers=workers,
                scheduler=scheduler, quiet=quiet or as_json, show=False))

        result = pipeline.run(config, out=out, write=True, command=command,
                              tasks=tasks if config.analysis.dem else None)
    if as_json:
        emit_json(stdout, result.to_dict())
    else:
        print(result.summary())


def _no_engine_without_dem(given: dict):
    """ParameterError for the first engine option given (``given``: flag → whether it was) of
    ``run`` on a case that does not ask for the DEM: its trials are the engine's only tasks."""
    flag = next((f for f, on in given.items() if on), None)
    if flag is not None:
        raise ParameterError(f"{flag} is out of range without [analysis] dem = true: allowed "
                             "only when the case runs the DEM (its trials are the engine's "
                             "tasks)")
