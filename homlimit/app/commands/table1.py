"""``homlimit table1``: the paper's Table 1, with the FE body's, the rigid blocks' or the
DEM's column."""

from __future__ import annotations

from dataclasses import asdict
from pathlib import Path

from ...blocks.geometry import FACADE_BONDS
from ...errors import check_choice
from .. import pipeline, plots, report
from ..dem_table1 import dem_section, table1_dem_records, table1_dem_walls
from ..door import (
    check_verbosity,
    interruptible,
    open_engine,
    setup_logging,
    show,
    stdout_quiet,
    stored_tasks,
)
from ..engine import RecordStore
from ..problems import Problems
from ..tables import table1_checks

# the column flags (one at a time: each its own computation and result set) and the options
# that only one or some of them use
COLUMNS = ("fe", "blocks", "dem")
USED_BY = {"mesh_size": ("fe",), "heights": ("fe",), "facade": ("fe",),
           "max_triangles": ("fe",), "mesher": ("fe",), "part_divisions": ("fe",),
           "blocks_facade": ("blocks",), "overrides": ("dem",), "resume": ("dem",),
           "workers": ("fe", "dem"), "scheduler": ("fe", "dem")}
NONE_DEFAULT = ("overrides", "workers", "scheduler")    # given wherever they are not None
FLAGS = {"fe": "--fe", "blocks": "--blocks", "dem": "--dem", "mesh_size": "--mesh-size",
         "heights": "--heights", "facade": "--facade", "max_triangles": "--max-triangles",
         "mesher": "--mesher", "part_divisions": "--part-divisions", "test": "--test",
         "blocks_facade": "--blocks-facade", "overrides": "--set", "resume": "--resume",
         "workers": "--workers", "scheduler": "--scheduler"}


def check_options(options: dict, given: set[str] = frozenset()):
    """Every problem of table1's options at once (ConfigError, exit 2), before any work: two
    column flags together; an option given without the column that uses it (``USED_BY``;
    ``given``: the options given, ``given_options``); any value out of its range, whatever
    the flags."""
    o = options
    problems = Problems("table1")
    problems.check(check_verbosity, o["verbose"], o["quiet"])
    on = [c for c in COLUMNS if o[c]]
    if len(on) > 1:
        problems.add(f"{' and '.join(FLAGS[c] for c in on)} cannot be combined: allowed one "
                     "of --fe, --blocks, --dem (each its own column, computation and result "
                     "set); run table1 once per column")
    for key, users in USED_BY.items():
        if (key in given or key in NONE_DEFAULT and o[key]) and not any(o[c] for c in users):
            shown = (f"--set {o[key][0]!r}" if key == "overrides" else
                     "--resume" if o[key] is True else "--no-resume" if o[key] is False
                     else f"{FLAGS[key]} {o[key]!r}")
            problems.add(f"{shown} is out of range without "
                         f"{' or '.join(FLAGS[c] for c in users)}: allowed only with "
                         + " or ".join(f"table1 {FLAGS[c]}" for c in users)
                         + (" (its [dem] keys)" if key == "overrides" else ""))
    table1_checks(problems, fe=o["fe"] and not (o["blocks"] or o["dem"]),
                  mesh_size=o["mesh_size"], heights=o["heights"], tests=o["test"],
                  facade=o["facade"], max_triangles=o["max_triangles"], mesher=o["mesher"],
                  part_divisions=o["part_divisions"], names=FLAGS)
    problems.check(check_choice, "--blocks-facade", o["blocks_facade"], FACADE_BONDS)
    if o["dem"]:                  # the [dem] keys of --set, and the loading Table 1 needs
        section = problems.check(dem_section, o["overrides"])
        if section is not None:
            problems.check(table1_dem_walls, [], section)
    problems.raise_any()


def given_options(ctx) -> set[str]:
    """The parameters whose options were given on the command line (not left at their
    default) in the click context ``ctx`` (none without one: called from Python)."""
    if ctx is None:
        return set()
    return {name for name in ctx.params
            if getattr(ctx.get_parameter_source(name), "name", "DEFAULT")
            not in ("DEFAULT", "DEFAULT_MAP")}


def table1(as_json, out, verbose, quiet, fe, mesh_size, heights, facade, test, max_triangles,
           mesher, part_divisions, workers, scheduler, blocks, blocks_facade, dem, overrides,
           resume, ctx=None):
    """``homlimit table1``'s work: see ``cli.table1``; ``ctx``: its click context."""
    check_options(locals(), given_options(ctx))
    variant = "--dem" if dem else "--blocks" if blocks else "--fe" if fe else ""
    tests = sorted(set(test or ()))
    out = out or table1_folder(variant, tests)
    owner = dict(command=f"table1 {variant}".strip(),
                 source="embedded:table1" + (f":{','.join(tests)}" if tests else ""))
    setup_logging(verbose, quiet, as_json)
    if dem:   # validated before any work, then every trial a Dask task, its record kept

        section = dem_section(overrides)
        table1_dem_walls(tests, section)
        store = RecordStore(out / "records")
        with stdout_quiet(as_json or verbose) as stdout, interruptible(store.folder), \
                pipeline.result_folder(out, **owner) as staging:
            # each trial logs its line; one bar per trial's map would be noise
            with stored_tasks(store, "table1-dem", "DEM trial", resume=resume,
                              workers=workers, scheduler=scheduler, quiet=quiet or as_json,
                              show=False) as map_:
                rows, ratios = table1_dem_records(tests, section, map=map_)
            report.write(staging / "table1_dem.csv", rows)
            report.write(staging / "table1_dem_ratios.json", {
                "ratios": ratios, "dem": asdict(section),
                "units": {"ratios": "-", "dem": report.input_units()["dem"]}})
        files = [out / "table1_dem.csv", out / "table1_dem_ratios.json"]
        cols = ["test", "vg", "vg_udec", "dem_over_udec", "h", "h_udec", "vnorm",
                "vnorm_udec", "base_slid", "hinge_slid", "n_trials", "cpu"]
        show(stdout, as_json, {"rows": rows, "ratios": ratios}, rows, cols,
             "Table 1 with this package's DEM (ideal impulse) beside UDEC: vg [m/s], h [m], "
             "vnorm = vg/sqrt(gb); block-size ratios of vnorm: "
             + ", ".join(f"{k} {v['vnorm']:.2f} (UDEC {v['vnorm_udec']:.2f})"
                         for k, v in ratios.items()), files)
        return
    if blocks:
        with stdout_quiet(as_json or verbose) as stdout, \
                pipeline.result_folder(out, **owner) as staging:
            rows, ratios = pipeline.table1_blocks_records(test, facade=blocks_facade)
            report.write(staging / "table1_blocks.csv", rows)
            report.write(staging / "table1_blocks_ratios.json", ratios)
        cols = ["test", "blocks", "lam_blocks", "h_blocks", "vnorm_blocks", "lam_I",
                "vnorm_I", "vnorm_II", "lam_dem", "vnorm_dem", "ratio_blocks_dem"]
        show(stdout, as_json, {"rows": rows, "ratios": ratios}, rows, cols,
             "Table 1 with the rigid-block model: vnorm = vg/sqrt(gb); ratios "
             + ", ".join(f"{k} blocks {v['vnorm_blocks']:.2f} (DEM {v['vnorm_dem']:.2f})"
                         for k, v in ratios.items()),
             [out / "table1_blocks.csv", out / "table1_blocks_ratios.json"])
        return
    kw = dict(fe=fe, mesh_size=mesh_size, heights=heights, tests=test, facade=facade,
              max_triangles=max_triangles, mesher=mesher, part_divisions=part_divisions)
    with stdout_quiet(as_json or verbose) as stdout, \
            pipeline.result_folder(out, **owner) as staging:
        if fe:  # validated before any work, then every height of every wall a Dask task
            pipeline.table1_records(**kw, fe_results=lambda *args: [])
            with open_engine(workers, scheduler, quiet or as_json) as engine:
                rows = pipeline.table1_records(**kw, fe_results=engine.fe_results)
        else:
            rows = pipeline.table1_records(**kw)
        report.write(staging / "table1.csv", rows)
        report.write(staging / "table1.json", rows)
        plots.plot_table1(staging / "table1.png", rows)
    cols = ["test", "lam_I", "vnorm_I", "lam_II", "vnorm_II", "lam_dem", "vnorm_dem",
            "ratio_I", "ratio_II"] + (["lam_fe", "vnorm_fe", "mechanism_fe", "critical_at_fe"]
                                      if fe else [])
    show(stdout, as_json, rows, rows, cols, "Table 1: closed forms (I, II) beside the DEM; "
         "vnorm = vg/sqrt(gb), ratio = closed form / DEM",
         [out / "table1.csv", out / "table1.json", out / "table1.png"])


def table1_folder(variant: str, tests: list[str]) -> Path:
    """table1's default folder: homlimit-out/table1/ for the whole closed-form table; a
    variant (--fe, --blocks) or a selection of tests (-t B1) has its own (table1-fe-B1/), so
    that it never replaces another's set."""
    parts = ["table1", variant.lstrip("-"), *tests]
    return Path("homlimit-out") / pipeline.folder_name("-".join(p for p in parts if p))
