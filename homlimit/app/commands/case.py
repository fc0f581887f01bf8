"""The commands of one case: ``homlimit run``, ``demo``, ``pulse`` and ``mesh``."""

from __future__ import annotations

from pathlib import Path

from ...closed_form.paper import dem_row
from .. import pipeline, plots, report
from ..config import load_case
from ..door import (
    emit_json,
    setup_logging,
    stdout_quiet,
)


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
             quiet: bool, overrides: list[str] | None, command: str = "run"):
    setup_logging(verbose, quiet, as_json)
    with stdout_quiet(as_json or verbose) as stdout:
        result = pipeline.run(case, out=out, write=True, overrides=overrides, command=command)
    if as_json:
        emit_json(stdout, result.to_dict())
    else:
        print(result.summary())
