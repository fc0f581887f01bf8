"""The ``homlimit`` command line: a thin typer layer over the Python API.

    homlimit run [CASE.toml]      the full pipeline for one wall (no case: the embedded B1 wall)
    homlimit demo                 the embedded default case (Table 1's B1)
    homlimit table1 [--fe|--dem]  the paper's Table 1 beside the closed forms (and the FE body,
                                  or this package's rigid-block DEM)
    homlimit figure2              the paper's Figure 2 as a PNG
    homlimit crack-study          the crack-angle study over a grid of c/a and f
    homlimit pulse [CASE.toml]    overturning spectra of real pulses (rocking time histories)
    homlimit mesh CASE.toml       the T-section mesh only, for inspection

Every computing command takes ``--json`` (machine-readable on stdout, nothing else there),
``--out DIR`` (default homlimit-out/NAME/), ``-v`` (solver logs) and ``-q`` (no progress);
progress, warnings and logs go to stderr through ``logging``. Each command writes one result
set: its folder is checked before any work (a set of another command or another case source
there is refused, exit 2) and the previous set replaced at the end, what that set did not write
kept (``_io.result_set``).
Exit codes: 0 success, 2 bad input (ParameterError, invalid case file, unusable output folder,
usage), 3 a failure of the computation or of the disk (SolverError, MeshError, ResultError,
OutputError, out of memory), with a one-line reason on stderr and no traceback; an interrupt
(SIGINT, SIGTERM, SIGHUP) exits 128 + the signal's number after removing what it had begun,
leaving the previous result set as it was.
"""

from __future__ import annotations

import functools
import json
import logging
import os
import signal
import sys
from contextlib import contextmanager
from pathlib import Path
from typing import Annotated

import typer

from .._version import package_version
from ..errors import (
    HomlimitError,
    MeshError,
    OutputError,
    ParameterError,
    ResultError,
    SolverError,
)
from ..params import MESHER_DEFAULT
from .budget import DEFAULT_MAX_TRIANGLES

MAX_CASES = 100_000         # sweep.MAX_CASES (sweep imports numpy: kept off the start-up)

__all__ = ["app", "main"]

EXIT_BAD_INPUT = 2
EXIT_SOLVER = 3

# plain help (click's formatter), as wide as the terminal up to 120 columns: typer's Rich
# markup would eat bracketed words such as the case file's "[pulse]" and "[m]", and its Rich
# panels show a "<bool>" value after each flag
app = typer.Typer(add_completion=False, no_args_is_help=True, pretty_exceptions_enable=False,
                  rich_markup_mode=None, context_settings={"max_content_width": 120},
                  help="Out-of-plane collapse of masonry façades bonded to transversal walls: "
                       "closed-form mechanisms, homogenised FE limit analysis, impulse "
                       "criterion.")

JsonOpt = Annotated[bool, typer.Option("--json", help="Print the results as JSON on stdout "
                                                      "(nothing else there); no progress.")]


def _out(default: str):
    """The --out option of a command whose result set goes to ``default`` without it."""
    return Annotated[Path | None, typer.Option(
        "--out", "-o", show_default=False,
        help=f"Output folder: the new result set replaces the one there, if it is this "
             f"command's on this case [default: {default}].")]


_NAME = ("NAME the case name, with a hash of its inputs when --set changed them")
OutOpt = _out(f"homlimit-out/NAME/, {_NAME}")
VerboseOpt = Annotated[bool, typer.Option("--verbose", "-v", help="Show solver logs "
                                                               "(debug level) on stderr.")]
QuietOpt = Annotated[bool, typer.Option("--quiet", "-q", help="Only warnings and errors on "
                                                             "stderr (no progress).")]
SetOpt = Annotated[list[str] | None, typer.Option(
    "--set", "-s", help="Override a case key before validation, e.g. --set mesh.size=0.5 "
                        "--set analysis.fe=false (repeatable).")]
CaseArg = Annotated[Path | None, typer.Argument(help="Case file (TOML); see docs/case-file.md. "
                                                "Omitted: the embedded default case (B1).",
                                                show_default=False)]
MaxTriOpt = Annotated[int, typer.Option(
    help="Problem-size budget: the most triangles one FE mesh may have (estimated before "
         "meshing; the default fits a 2-core, 24 GiB machine).")]
MesherOpt = Annotated[str, typer.Option(
    help="FE mesh: crossed, gmsh or gmsh-strip (the case file's [mesh] mesher).")]


_HANDLER: logging.Handler | None = None
_LOG = logging.getLogger("homlimit")


def _logging(verbose: bool = False, quiet: bool = False, as_json: bool = False):
    """Progress and logs of the library on stderr: stages at INFO (the default), solver logs
    at DEBUG (-v); only warnings with -q or --json (stdout carries the JSON document)."""
    global _HANDLER
    logger = logging.getLogger("homlimit")
    if _HANDLER is not None:
        logger.removeHandler(_HANDLER)
    _HANDLER = logging.StreamHandler(sys.stderr)
    _HANDLER.setFormatter(logging.Formatter("[homlimit] %(message)s"))
    logger.addHandler(_HANDLER)
    logger.propagate = False
    logger.setLevel(logging.DEBUG if verbose else
                    logging.WARNING if (quiet or as_json) else logging.INFO)


def _version(value: bool):
    if value:
        print(f"homlimit {package_version()}")
        raise typer.Exit()


@app.callback()
def _main(version: Annotated[bool | None, typer.Option(
        "--version", callback=_version, is_eager=True,
        help="Print the installed version and exit.")] = None):
    """Out-of-plane collapse of masonry façades bonded to transversal walls."""


def _fail(code: int, message: str):
    print(f"homlimit: error: {message}", file=sys.stderr)
    raise typer.Exit(code)


class _Interrupted(KeyboardInterrupt):
    """SIGTERM or SIGHUP, raised like Ctrl-C so that every clean-up on the way runs."""

    def __init__(self, signum: int):
        super().__init__(signal.Signals(signum).name)
        self.signum = signum


def _raise_interrupt(signum, frame):
    raise _Interrupted(signum)


@contextmanager
def _signals():
    """SIGTERM and SIGHUP raise like SIGINT (the result set's clean-up runs); SIGXFSZ is
    ignored, so that a write over ``ulimit -f`` fails with EFBIG (an OutputError) instead of
    killing the process. The previous handlers are put back on exit."""
    wanted = {"SIGTERM": _raise_interrupt, "SIGHUP": _raise_interrupt, "SIGXFSZ": signal.SIG_IGN}
    saved = {}
    try:
        for name, handler in wanted.items():
            if hasattr(signal, name):
                saved[name] = signal.signal(getattr(signal, name), handler)
    except ValueError:  # not the main thread: leave the signals alone
        pass
    try:
        yield
    finally:
        for name, handler in saved.items():
            signal.signal(getattr(signal, name), handler)


def _guarded(fn):
    """Map expected failures to exit codes 2 (bad input) and 3 (computation or disk), and
    interrupts to 128 + the signal number; one line on stderr, no traceback."""

    @functools.wraps(fn)
    def wrapper(*args, **kwargs):
        from .config import ConfigError

        try:
            with _signals():
                return fn(*args, **kwargs)
        except ConfigError as e:
            print(f"homlimit: error: {e.problems[0] if len(e.problems) == 1 else e}",
                  file=sys.stderr)
            raise typer.Exit(EXIT_BAD_INPUT) from None
        except ParameterError as e:
            _fail(EXIT_BAD_INPUT, str(e))
        except SolverError as e:
            hint = " [a looser tolerance: --set analysis.tol=1e-7]" if \
                e.status == "optimal_inaccurate" else ""
            _fail(EXIT_SOLVER, f"solver failed ({e.status or 'no status'}): {e}{hint}")
        except MeshError as e:
            _fail(EXIT_SOLVER, f"meshing failed: {e}")
        except OutputError as e:
            _fail(EXIT_SOLVER, f"{e}; the previous result set, if any, is kept")
        except ResultError as e:
            _fail(EXIT_SOLVER, f"no result: {e}")
        except HomlimitError as e:  # any other expected failure
            _fail(EXIT_SOLVER, str(e))
        except MemoryError:
            _fail(EXIT_SOLVER, "out of memory: a coarser [mesh] size, or a lower [mesh] "
                               "max_triangles so that such cases stop before they start")
        except KeyboardInterrupt as e:
            signum = getattr(e, "signum", signal.SIGINT)
            print(f"homlimit: interrupted ({signal.Signals(signum).name}): the result set "
                  "being written was removed, the previous one is kept", file=sys.stderr)
            raise typer.Exit(128 + signum) from None

    return wrapper


@contextmanager
def _stdout_quiet(enabled: bool):
    """Under --json or -v, send everything written to stdout during the computation to stderr
    (Python or native libraries: gmsh, and Clarabel's log, which its Rust core prints to file
    descriptor 1), so that stdout carries the JSON document or the result table only. Yields
    the real stdout."""
    real = sys.stdout
    if not enabled:
        yield real
        return
    saved_fd = None
    try:
        fd = real.fileno()
    except (AttributeError, OSError, ValueError):  # e.g. typer's CliRunner
        fd = None
    real.flush()
    if fd is not None:
        saved_fd = os.dup(fd)
        os.dup2(sys.stderr.fileno(), fd)
    sys.stdout = sys.stderr
    try:
        yield real
    finally:
        sys.stdout.flush()
        real.flush()  # what a library wrote to the real stream meanwhile goes to stderr too
        sys.stdout = real
        if saved_fd is not None:
            os.dup2(saved_fd, fd)
            os.close(saved_fd)


def _emit_json(stream, data):
    from .._io import rounded  # floats to 15 digits, as in the files (_io.write_output)

    stream.write(json.dumps(rounded(data), indent=2, ensure_ascii=False) + "\n")
    stream.flush()


def _show(stdout, as_json: bool, data, records: list[dict], cols: list[str], title: str,
          files):
    """--json: ``data`` on stdout; otherwise the ``cols`` of ``records`` as a table, then the
    files written."""
    if as_json:
        _emit_json(stdout, data)
        return
    from .report import format_table

    print(format_table(cols, [[r.get(k) for k in cols] for r in records], title=title))
    print("\nfiles: " + ", ".join(map(str, files)))


def _run_case(case: Path | None, as_json: bool, out: Path | None, verbose: bool,
              quiet: bool, overrides: list[str] | None, command: str = "run"):
    from .pipeline import run

    _logging(verbose, quiet, as_json)
    with _stdout_quiet(as_json or verbose) as stdout:
        result = run(case, out=out, write=True, overrides=overrides, command=command)
    if as_json:
        _emit_json(stdout, result.to_dict())
    else:
        print(result.summary())


@app.command("run")
@_guarded
def run_cmd(case: CaseArg = None, as_json: JsonOpt = False, out: OutOpt = None,
            verbose: VerboseOpt = False, quiet: QuietOpt = False, overrides: SetOpt = None):
    """Run the full pipeline for one wall (no CASE: the embedded default, B1).

    Closed-form mechanisms I and II, the FE mechanism and its crack, the impulse criterion;
    prints a summary and writes summary.json, .vtu and PNG files."""
    _run_case(case, as_json, out, verbose, quiet, overrides)


@app.command()
@_guarded
def demo(as_json: JsonOpt = False, out: OutOpt = None, verbose: VerboseOpt = False,
         quiet: QuietOpt = False, overrides: SetOpt = None):
    """Run the embedded default case: the paper's Table 1 wall B1 (H=9 m, b=0.5 m, ρ=12)."""
    _run_case(None, as_json, out, verbose, quiet, overrides, command="demo")


@app.command()
@_guarded
def table1(as_json: JsonOpt = False, out: _out(
               "homlimit-out/table1/; with --fe, --blocks or -t: table1-fe/, table1-blocks/, "
               "table1-B1/...") = None,
           verbose: VerboseOpt = False, quiet: QuietOpt = False,
           fe: Annotated[bool, typer.Option("--fe", help="Add the finite-element body's "
                                            "columns (slow: one scan over h per wall).")]
           = False,
           mesh_size: Annotated[float, typer.Option(help="FE mesh size [m] (with --fe).")]
           = 0.25,
           heights: Annotated[int, typer.Option(help="Starting heights of the FE scan, from "
                                                "one course to H, refined around its "
                                                "minimum (with --fe).")] = 6,
           facade: Annotated[str, typer.Option(help="Façade model of the FE scan: bedjoints "
                                               "or homogenised (with --fe).")] = "bedjoints",
           test: Annotated[list[str] | None, typer.Option(
               "--test", "-t", show_default=False,
               help="Only this Table 1 test, e.g. B1 (repeatable) [default: all 12].")]
           = None,
           max_triangles: MaxTriOpt = DEFAULT_MAX_TRIANGLES,
           mesher: MesherOpt = MESHER_DEFAULT,
           workers: WorkersOpt = None, scheduler: SchedulerOpt = None,
           blocks: Annotated[bool, typer.Option("--blocks", help="Instead: the rigid-block "
                                                "model's column (slow: one scan per wall).")]
           = False,
           blocks_facade: Annotated[str, typer.Option(help="Façade of the block model: "
                                                      "through or running-bond (with "
                                                      "--blocks).")] = "through",
           dem: Annotated[bool, typer.Option("--dem", help="Instead: this package's "
                                             "rigid-block DEM (homlimit.dem) beside UDEC, "
                                             "every wall a Dask task (slow: minutes of CPU "
                                             "per wall; docs/dem.md).")] = False,
           overrides: Annotated[list[str] | None, typer.Option(
               "--set", "-s", help="With --dem: a [dem] key for every wall, e.g. --set "
                                   "dem.kn=3e9 (repeatable; docs/case-file.md).")] = None,
           resume: Annotated[bool, typer.Option(
               "--resume/--no-resume", help="With --dem: keep the walls recorded in "
                                            "OUT/records/ by an earlier run.")] = True):
    """The paper's Table 1: critical λ and v̄_g/√(gb) of mechanisms I and II beside the DEM."""
    from . import plots, report
    from .pipeline import result_folder, table1_blocks_records, table1_records

    if overrides and not dem:
        raise ParameterError(f"--set {overrides[0]!r} is out of range without --dem: allowed "
                             "only with table1 --dem (its [dem] keys)")
    variant = "--dem" if dem else "--blocks" if blocks else "--fe" if fe else ""
    tests = sorted(set(test or ()))
    out = out or _table1_folder(variant, tests)
    owner = dict(command=f"table1 {variant}".strip(),
                 source="embedded:table1" + (f":{','.join(tests)}" if tests else ""))
    _logging(verbose, quiet, as_json)
    if dem:   # validated before any work, then every wall a Dask task, its record kept
        from dataclasses import asdict

        from .dem_stage import dem_section, table1_dem_records
        from .engine import RecordStore

        section = dem_section(overrides)
        table1_dem_records(tests, section, map=lambda fn, walls: [])
        store = RecordStore(out / "records")
        with _stdout_quiet(as_json or verbose) as stdout, _interruptible(store.folder), \
                result_folder(out, **owner) as staging:
            if not resume:
                store.clear()
            with _engine(workers, scheduler, quiet or as_json) as engine:
                rows, ratios = table1_dem_records(tests, section, map=engine.stored_map(
                    store, "table1-dem", "DEM walls"))
            report.write(staging / "table1_dem.csv", rows)
            report.write(staging / "table1_dem_ratios.json", {
                "ratios": ratios, "dem": asdict(section),
                "units": {"ratios": "-", "dem": report.input_units()["dem"]}})
        files = [out / "table1_dem.csv", out / "table1_dem_ratios.json"]
        cols = ["test", "vg", "vg_udec", "dem_over_udec", "h", "h_udec", "vnorm",
                "vnorm_udec", "base_slid", "hinge_slid", "n_trials", "cpu"]
        _show(stdout, as_json, {"rows": rows, "ratios": ratios}, rows, cols,
              "Table 1 with this package's DEM (ideal impulse) beside UDEC: vg [m/s], h [m], "
              "vnorm = vg/sqrt(gb); block-size ratios of vnorm: "
              + ", ".join(f"{k} {v['vnorm']:.2f} (UDEC {v['vnorm_udec']:.2f})"
                          for k, v in ratios.items()), files)
        return
    if blocks:
        with _stdout_quiet(as_json or verbose) as stdout, \
                result_folder(out, **owner) as staging:
            rows, ratios = table1_blocks_records(test, facade=blocks_facade)
            report.write(staging / "table1_blocks.csv", rows)
            report.write(staging / "table1_blocks_ratios.json", ratios)
        cols = ["test", "blocks", "lam_blocks", "h_blocks", "vnorm_blocks", "lam_I",
                "vnorm_I", "vnorm_II", "lam_dem", "vnorm_dem", "ratio_blocks_dem"]
        _show(stdout, as_json, {"rows": rows, "ratios": ratios}, rows, cols,
              "Table 1 with the rigid-block model: vnorm = vg/sqrt(gb); ratios "
              + ", ".join(f"{k} blocks {v['vnorm_blocks']:.2f} (DEM {v['vnorm_dem']:.2f})"
                          for k, v in ratios.items()),
              [out / "table1_blocks.csv", out / "table1_blocks_ratios.json"])
        return
    kw = dict(fe=fe, mesh_size=mesh_size, heights=heights, tests=test, facade=facade,
              max_triangles=max_triangles, mesher=mesher)
    with _stdout_quiet(as_json or verbose) as stdout, \
            result_folder(out, **owner) as staging:
        if fe:  # validated before any work, then every height of every wall a Dask task
            table1_records(**kw, fe_results=lambda *args: [])
            with _engine(workers, scheduler, not (quiet or as_json)) as engine:
                rows = table1_records(**kw, fe_results=engine.fe_results)
        else:
            rows = table1_records(**kw)
        report.write(staging / "table1.csv", rows)
        report.write(staging / "table1.json", rows)
        plots.plot_table1(staging / "table1.png", rows)
    cols = ["test", "lam_I", "vnorm_I", "lam_II", "vnorm_II", "lam_dem", "vnorm_dem",
            "ratio_I", "ratio_II"] + (["lam_fe", "vnorm_fe", "mechanism_fe", "critical_at_fe"]
                                      if fe else [])
    _show(stdout, as_json, rows, rows, cols, "Table 1: closed forms (I, II) beside the DEM; "
          "vnorm = vg/sqrt(gb), ratio = closed form / DEM",
          [out / "table1.csv", out / "table1.json", out / "table1.png"])


def _table1_folder(variant: str, tests: list[str]) -> Path:
    """table1's default folder: homlimit-out/table1/ for the whole closed-form table; a
    variant (--fe, --blocks) or a selection of tests (-t B1) has its own (table1-fe-B1/), so
    that it never replaces another's set."""
    from .pipeline import folder_name

    parts = ["table1", variant.lstrip("-"), *tests]
    return Path("homlimit-out") / folder_name("-".join(p for p in parts if p))


@app.command()
@_guarded
def figure2(as_json: JsonOpt = False, out: _out("homlimit-out/figure2/") = None):
    """The paper's Figure 2: critical λ and v̄_g/√(gb) against ρ, both mechanisms, DEM points.

    Writes figure2.png and figure2.json (the curves); --json prints the curves."""
    from . import plots, report
    from .pipeline import figure2_curves, result_folder

    out = out or Path("homlimit-out") / "figure2"
    with _stdout_quiet(as_json) as stdout, result_folder(out, "figure2") as staging:
        curves = figure2_curves()
        plots.figure2(staging / "figure2.png", curves)
        report.write(staging / "figure2.json", curves)
    files = {"figure2_png": str(out / "figure2.png"), "figure2_json": str(out / "figure2.json")}
    if as_json:
        _emit_json(stdout, {"curves": curves, "files": files})
    else:
        print(f"Figure 2 written to {files['figure2_png']} (curves: {files['figure2_json']})")


@app.command()
@_guarded
def verify(as_json: JsonOpt = False, out: _out("homlimit-out/verify/") = None,
           verbose: VerboseOpt = False, quiet: QuietOpt = False,
           problem: Annotated[list[str] | None, typer.Option(
               "--problem", "-p", show_default=False,
               help="Only this known-answer problem: prandtl, vertical_cut, tsection or "
                    "free_block (repeatable) [default: all].")] = None,
           target_gap: Annotated[float, typer.Option(
               help="Stop refining at this relative gap (lambda+ - lambda-)/mean.")] = 0.005,
           max_cycles: Annotated[int, typer.Option(help="At most this many meshes.")] = 6,
           min_size: Annotated[float, typer.Option(help="Smallest element size [m].")] = 1e-3,
           max_triangles: MaxTriOpt = DEFAULT_MAX_TRIANGLES,
           stress_degree: Annotated[int, typer.Option(
               help="Static bound's stresses: 1 linear, 2 quadratic (Bernstein; the free "
                    "block takes 1).")] = 2):
    """Known-answer problems through the adaptive bracket (gmsh, both bounds refined where
    their gap is), each against its exact value: Prandtl 2 + pi, the vertical cut
    3.7752-3.7776, the homogenised B1 T-section's hinge + fan (0.15216, fan edges f and c/a),
    a free block b/h. Writes verify.json and verify.csv (every cycle)."""
    from ..fe.adapt import AdaptOptions
    from ..fe.solver import SolverOptions
    from . import report
    from .pipeline import result_folder
    from .verify import verify_records

    out = out or Path("homlimit-out") / "verify"
    _logging(verbose, quiet, as_json)
    opts = AdaptOptions(target_gap=target_gap, max_cycles=max_cycles, min_size=min_size,
                        max_triangles=max_triangles)
    SolverOptions(stress_degree=stress_degree)   # checked before any work
    with _stdout_quiet(as_json or verbose) as stdout, result_folder(out, "verify") as staging:
        records = verify_records(problem, opts, stress_degree=stress_degree,
                                 progress=lambda n, c: _LOG.info(
            "verify %s: cycle %d, %d triangles, %.6g <= lambda <= %.6g; best %.6g .. %.6g "
            "(gap %.3g %%), %.1f s", n, c.cycle, c.triangles, c.lower, c.upper, c.best_lower,
            c.best_upper, 100 * c.rel_gap, c.seconds))
        cycles = [{"problem": r["problem"], **c} for r in records for c in r["adapt"]]
        report.write(staging / "verify.json", {"problems": records})
        report.write(staging / "verify.csv", cycles)
    files = [out / "verify.json", out / "verify.csv"]
    cols = ["problem", "triangles", "cycles", "lower", "upper", "rel_gap", "exact_lo",
            "exact_hi", "holds"]
    _show(stdout, as_json, {"problems": records, "files": list(map(str, files))}, records,
          cols, "known-answer problems, adaptive bracket", files)
    if not as_json:
        for r in records:
            if r["problem"] == "tsection" and r.get("T1") is not None:
                print(f"tsection crack: hinge z = {r['z0']:.3f} m (exact {r['z0_exact']:.3f}), "
                      f"fan edges {r['T1']:.3f} .. {r['T2']:.3f} (f = {r['f']:.3f}, "
                      f"c/a = {r['c_over_a']:.3f}), sqrt(T1 T2) = "
                      f"{(r['T1'] * r['T2']) ** 0.5:.3f} against sqrt(cf/a) = "
                      f"{r['sqrt_cf_a']:.3f}, mid-line {r['T_mid']:.3f}")


@app.command("crack-study")
@_guarded
def crack_study(as_json: JsonOpt = False, out: _out("homlimit-out/crack-study/") = None,
                verbose: VerboseOpt = False, quiet: QuietOpt = False,
                mesh_size: Annotated[float, typer.Option(help="FE mesh size [m].")] = 0.5,
                finer: Annotated[float, typer.Option(help="A second, finer mesh size [m] "
                                                     "(0: none).")] = 0.25,
                quick: Annotated[bool, typer.Option(help="A small grid (c/a 0.5, 1, 3; f 0.3, "
                                                    "0.9), one mesh.")] = False,
                c_over_a: Annotated[list[float] | None, typer.Option(
                    "--c-over-a", show_default=False,
                    help="Block proportion c/a [-] (repeat for several) [default: 0.5, "
                         "0.75, 1, 1.5, 2, 3].")] = None,
                friction: Annotated[list[float] | None, typer.Option(
                    "--friction", show_default=False,
                    help="Joint friction f [-] (repeat for several) [default: 0.3, 0.6, "
                         "0.9].")] = None,
                facade: Annotated[list[str] | None, typer.Option(
                    show_default=False, help="Façade model: homogenised or bedjoints (repeat "
                                             "for both) [default: both].")] = None,
                max_triangles: MaxTriOpt = DEFAULT_MAX_TRIANGLES,
                mesher: MesherOpt = MESHER_DEFAULT,
                workers: WorkersOpt = None, scheduler: SchedulerOpt = None,
                resume: Annotated[bool, typer.Option(
                    "--resume/--no-resume", help="Keep the points recorded in OUT/records/ "
                                                 "by an earlier run.")] = True):
    """The crack-angle study: the FE crack slope over a grid of c/a and f, beside √(cf/a)."""
    from . import plots, report
    from .engine import RecordStore
    from .pipeline import crack_study_records, result_folder

    out = out or Path("homlimit-out") / "crack-study"
    _logging(verbose, quiet, as_json)
    grid = dict(mesh_size=mesh_size, finer=finer or None, quick=quick, c_over_a=c_over_a,
                frictions=friction, facades=facade, max_triangles=max_triangles,
                mesher=mesher)
    store = RecordStore(out / "records")   # a nested set: kept when the set is replaced
    with _stdout_quiet(as_json or verbose) as stdout, _interruptible(store.folder), \
            result_folder(out, "crack-study") as staging:
        crack_study_records(**grid, map=lambda fn, points: [])   # validate before any work
        if not resume:
            store.clear()
        with _engine(workers, scheduler, not (quiet or as_json)) as engine:
            records = crack_study_records(**grid, map=engine.stored_map(
                store, "crack-study", "crack-study"))
        report.write(staging / "crack_study.csv", records)
        plots.plot_crack_study(staging / "crack_study.png", records,
                               title="crack-angle study: FE crack against √(cf/a), f and c/a")
    files = {"csv": out / "crack_study.csv", "png": out / "crack_study.png"}
    cols = ["facade", "mesh_size", "c_over_a", "f", "mechanism_fe", "tanpsi_fe", "dtanpsi_fe",
            "tan_alpha", "tanpsi_block", "tanpsi_fixed", "multiplier_fe", "multiplier_fan"]
    _show(stdout, as_json, {"records": records, "files": files}, records, cols,
          "crack-angle study: FE crack slope tan psi (50 % line, edges) beside tan_alpha = "
          "sqrt(cf/a)", files.values())


@app.command()
@_guarded
def pulse(case: CaseArg = None, as_json: JsonOpt = False,
          out: _out(f"homlimit-out/NAME/pulse/, {_NAME}") = None,
          verbose: VerboseOpt = False, quiet: QuietOpt = False, overrides: SetOpt = None):
    """Overturning spectra: the critical pulse per mechanism against pulse period ([pulse]);
    default folder homlimit-out/NAME/pulse/."""
    from ..closed_form.paper import dem_row
    from . import plots, report
    from .config import load_case
    from .pipeline import announce, output_dir, pulse_records, result_folder, source_of

    _logging(verbose, quiet, as_json)
    with _stdout_quiet(as_json or verbose) as stdout:
        config = load_case(case, overrides)
        announce(config)
        out = out or output_dir(config) / "pulse"
        with result_folder(out, "pulse", case=config.name, **source_of(config)) as staging:
            points, fe = pulse_records(config)
            dem = dem_row(config.case)
            report.write(staging / "spectra.csv", [p.as_dict() for p in points])
            plots.plot_spectra(staging / "spectra.png", points,
                               dem_vnorm=None if dem is None else dem.vg_norm,
                               title=f"case {config.name}: critical pulses")
    files = [out / "spectra.csv", out / "spectra.png"]
    cache = None if fe is None else {"path": fe.cache, "read": fe.from_cache}
    if as_json:
        _emit_json(stdout, {"points": [p.as_dict() for p in points], "files": files,
                            "fe_cache": cache})
        return
    print(report.format_spectra(points, title=f"case {config.name}: overturning spectra "
                                              "(pgv/vg(eq.7): over the ideal impulse)"))
    if fe is not None and fe.cache is not None:
        print(f"\nFE result {'read from' if fe.from_cache else 'written to'} cache {fe.cache}")
    print("\nfiles: " + ", ".join(map(str, files)))


@app.command()
@_guarded
def mesh(case: CaseArg = None, as_json: JsonOpt = False,
         out: _out(f"homlimit-out/NAME/mesh/, {_NAME}") = None,
         overrides: SetOpt = None):
    """Mesh the T-section of a case only; write mesh.vtu and mesh.png for inspection
    (default folder homlimit-out/NAME/mesh/)."""
    from .config import load_case
    from .pipeline import announce, mesh_case, output_dir

    _logging(False, False, as_json)
    with _stdout_quiet(as_json) as stdout:
        config = load_case(case, overrides)
        announce(config)
        info = mesh_case(config, out or output_dir(config) / "mesh")
    if as_json:
        _emit_json(stdout, info)
    else:
        print(f"case {config.name}: {info['n_triangles']} triangles, {info['n_nodes']} nodes; "
              + ", ".join(f"{k} {v}" for k, v in info["regions"].items()))
        print("files: " + ", ".join(info["files"].values()))

# ----------------------------------------------------------------------------- sweeps (Dask)
WorkersOpt = Annotated[int | None, typer.Option(
    "--workers", "-w", help="Embedded Dask worker processes, one thread each [default: one "
                            "per core].")]
SchedulerOpt = Annotated[str | None, typer.Option(
    "--scheduler", help="Address of a running Dask scheduler (e.g. tcp://127.0.0.1:8786) to "
                        "use instead of embedded workers; exit 2 if none answers within 5 s.")]


@contextmanager
def _interruptible(where):
    """Ctrl-C / SIGTERM: what is recorded stays; exit 130 / 143 with a one-line note."""
    from .engine import Interrupted

    try:
        yield
    except KeyboardInterrupt as e:
        signum = e.signum if isinstance(e, Interrupted) else 2
        print(f"homlimit: interrupted; the finished records are kept in {where}: run the same "
              "command again to resume", file=sys.stderr)
        raise typer.Exit(128 + signum) from None


def _engine(workers: int | None, scheduler: str | None, quiet: bool):
    from .engine import Engine

    return Engine(workers=workers, scheduler=scheduler, progress=not quiet)


class _SweepGroup(typer.core.TyperGroup):
    """``homlimit sweep BASE.toml ...`` is ``homlimit sweep run BASE.toml ...``."""

    def parse_args(self, ctx, args):
        if args and args[0] not in self.commands and args[0] not in ("--help", "-h"):
            args = ["run", *args]
        return super().parse_args(ctx, args)


sweep_app = typer.Typer(cls=_SweepGroup, no_args_is_help=True, help=(
    "Parameter sweeps and building stocks on Dask: homlimit sweep BASE.toml --grid "
    "wall.l=3,6,9 [--table cases.csv]; homlimit sweep report RESULTS."))
app.add_typer(sweep_app, name="sweep")


@sweep_app.command("run")
@_guarded
def sweep_run(
        base: CaseArg = None, as_json: JsonOpt = False, verbose: VerboseOpt = False,
        quiet: QuietOpt = False,
        out: Annotated[Path | None, typer.Option("--out", "-o", help="Sweep folder "
                                                 "[default: homlimit-out/NAME/sweep/].")] = None,
        grid: Annotated[list[str] | None, typer.Option(
            "--grid", "-g", help="A swept key and its values, e.g. --grid wall.l=3,6,9 "
                                 "(repeatable: every combination).")] = None,
        table: Annotated[Path | None, typer.Option(
            "--table", help="CSV of cases: one per row, one case key per column (times the "
                            "grid, if both).")] = None,
        workers: WorkersOpt = None, scheduler: SchedulerOpt = None,
        resume: Annotated[bool, typer.Option(
            "--resume/--no-resume", help="Keep the records of an earlier run of this sweep "
                                         "and run only the missing cases.")] = True,
        retry_failed: Annotated[bool, typer.Option(
            "--retry-failed", help="Run the cases recorded as failed again.")] = False,
        max_cases: Annotated[int, typer.Option(
            "--max-cases", help="The most cases the sweep may have (table rows × grid "
                                "points), checked before any planning.")] = MAX_CASES):
    """Run a sweep: every case of a grid and/or table of overrides on BASE, on Dask.

    Each case's record is written as soon as it finishes (OUT/records/); the table is
    OUT/results.parquet and OUT/results.csv. Exit 3 if any case failed."""
    from . import report
    from .sweep import sweep

    if not grid and table is None:
        raise ParameterError("--grid / --table = none is out of range: allowed at least one "
                             "--grid key=v1,v2 or a --table CSV")
    _logging(verbose, quiet, as_json)
    where = out or "the sweep folder"
    with _stdout_quiet(as_json) as stdout, _interruptible(where):
        res = sweep(base, grid, table, out, workers=workers, scheduler=scheduler,
                    resume=resume, retry_failed=retry_failed, progress=not (quiet or as_json),
                    max_cases=max_cases)
    info = {"folder": res.folder, "n_cases": len(res.rows), "ok": res.n_ok,
            "failed": res.n_failed, "resumed": res.n_resumed, "elapsed_s": res.elapsed,
            "swept": res.swept, "files": res.files,
            "failures": [{k: r.get(k) for k in ("case_index", "key", "error")}
                         for r in res.failed()]}
    if as_json:
        _emit_json(stdout, info)
    else:
        cols = [c for c in ["case_index", *res.swept, "status", "critical.mechanism",
                            "critical.vg", "critical.vnorm"]]
        shown = res.rows[:20]
        print(report.format_table(cols, [[r.get(c) for c in cols] for r in shown],
                                  title=f"sweep of {len(res.rows)} cases: {res.n_ok} ok, "
                                        f"{res.n_failed} failed, {res.n_resumed} resumed "
                                        f"({res.elapsed:.1f} s)"
                                        + ("; first 20 rows" if len(res.rows) > 20 else "")))
        for f in info["failures"][:10]:
            print(f"failed case {f['case_index']}: {f['error']}".splitlines()[0])
        print("\nfiles: " + ", ".join(str(v) for v in res.files.values()))
    if res.n_failed:
        raise typer.Exit(EXIT_SOLVER)


@sweep_app.command("report")
@_guarded
def sweep_report_cmd(
        results: Annotated[Path, typer.Argument(help="A sweep folder, or its results.parquet "
                                                     "/ results.csv.")],
        out: Annotated[Path | None, typer.Option("--out", "-o", help="Folder of the "
                                                 "plots [default: RESULTS/report/].")] = None,
        as_json: JsonOpt = False):
    """Draw a sweep's standard plots: vg/sqrt(gb) against each swept key, the critical
    mechanism map, measured against predicted tan psi, the histogram of vg."""
    from .sweep_report import report

    with _stdout_quiet(as_json) as stdout:
        files = report(results, out)
    if as_json:
        _emit_json(stdout, {"files": files})
    else:
        print("files: " + ", ".join(str(v) for v in files.values()))


def main():
    """Console-script entry point (``homlimit``, ``python -m homlimit``). Ctrl-C outside a
    command's own handling (while modules are still importing, say) exits 130 with one line,
    as an interrupted command does, never a traceback."""
    try:
        app(prog_name="homlimit")
    except KeyboardInterrupt:
        interrupted()


def interrupted():
    """Exit 130 with a one-line note: Ctrl-C before any command had begun its work."""
    print("homlimit: interrupted (SIGINT): nothing was written", file=sys.stderr)
    raise SystemExit(128 + signal.SIGINT)


if __name__ == "__main__":  # pragma: no cover
    main()
