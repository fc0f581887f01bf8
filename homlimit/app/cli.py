"""The ``homlimit`` command line: a thin typer layer over the Python API. This module declares
the commands and their options; each command's work is a plain function of those options in
``app.commands`` (called with the command's ``locals()``: its options, nothing else), what
they share in ``app.door`` (exit codes, logging, signals, JSON and table output).

    homlimit run [CASE.toml]      the full pipeline for one wall (no case: the embedded B1 wall)
    homlimit demo                 the embedded default case (Table 1's B1)
    homlimit table1 [--fe|--dem]  the paper's Table 1 beside the closed forms (and the FE body,
                                  or this package's rigid-block DEM)
    homlimit figure2              the paper's Figure 2 as a PNG
    homlimit crack-study          the crack-angle study over a grid of c/a and f
    homlimit pulse [CASE.toml]    overturning spectra of real pulses (rocking time histories)
    homlimit mesh CASE.toml       the T-section mesh only, for inspection

Every computing command takes ``--json`` (machine-readable on stdout, nothing else there),
``--out DIR`` (default homlimit-out/NAME/), and all but figure2, mesh and sweep report ``-v``
(solver logs) and ``-q`` (no progress; not both); a command's bad options are listed at once;
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

import signal
import sys
from pathlib import Path
from typing import Annotated

import typer

from ..params import MESHER_DEFAULT, PART_DIVISIONS
from .budget import DEFAULT_MAX_TRIANGLES
from .commands import case as case_cmds
from .commands import studies as study_cmds
from .commands import sweep as sweep_cmds
from .commands import table1 as table1_cmds
from .door import EXIT_BAD_INPUT, EXIT_SOLVER, guarded, leave, print_version

MAX_CASES = 100_000         # sweep.MAX_CASES (sweep imports numpy: kept off the start-up)

__all__ = ["EXIT_BAD_INPUT", "EXIT_SOLVER", "app", "main"]

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
WorkersOpt = Annotated[int | None, typer.Option(
    "--workers", "-w", help="Embedded Dask worker processes, one thread each [default: one "
                            "per core].")]
SchedulerOpt = Annotated[str | None, typer.Option(
    "--scheduler", help="Address of a running Dask scheduler (e.g. tcp://127.0.0.1:8786) to "
                        "use instead of embedded workers; exit 2 if none answers within 5 s.")]

ResumeOpt = Annotated[bool, typer.Option(
    "--resume/--no-resume", help="With [analysis] dem: keep the DEM trials recorded in "
                                 "OUT/records/ by an earlier run of this case.")]


@app.callback()
def _main(version: Annotated[bool | None, typer.Option(
        "--version", callback=print_version, is_eager=True,
        help="Print the installed version and exit.")] = None):
    """Out-of-plane collapse of masonry façades bonded to transversal walls."""


@app.command("run")
@guarded
def run_cmd(case: CaseArg = None, as_json: JsonOpt = False, out: OutOpt = None,
            verbose: VerboseOpt = False, quiet: QuietOpt = False, overrides: SetOpt = None,
            workers: WorkersOpt = None, scheduler: SchedulerOpt = None,
            resume: ResumeOpt = True):
    """Run the full pipeline for one wall (no CASE: the embedded default, B1).

    Closed-form mechanisms I and II, the FE mechanism and its crack, the impulse criterion;
    prints a summary and writes summary.json, .vtu and PNG files. With [analysis] dem, every
    DEM trial is a Dask task (--workers, --scheduler) whose record is kept as it ends, so an
    interrupted run resumes at the trial where it stopped."""
    case_cmds.run_case(case, as_json, out, verbose, quiet, overrides, workers=workers,
                       scheduler=scheduler, resume=resume)


@app.command()
@guarded
def demo(as_json: JsonOpt = False, out: OutOpt = None, verbose: VerboseOpt = False,
         quiet: QuietOpt = False, overrides: SetOpt = None, workers: WorkersOpt = None,
         scheduler: SchedulerOpt = None, resume: ResumeOpt = True):
    """Run the embedded default case: the paper's Table 1 wall B1 (H=9 m, b=0.5 m, ρ=12).

    The same as run with no case (--workers, --scheduler, --resume: with --set
    analysis.dem=true)."""
    case_cmds.run_case(None, as_json, out, verbose, quiet, overrides, command="demo",
                       workers=workers, scheduler=scheduler, resume=resume)


@app.command()
@guarded
def table1(ctx: typer.Context, as_json: JsonOpt = False, out: _out(
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
           part_divisions: Annotated[int, typer.Option(
               help="Elements per part height of the FE scan's parts (with --fe; the case "
                    "file's [mesh] part_divisions).")] = PART_DIVISIONS,
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
    table1_cmds.table1(**locals())


@app.command()
@guarded
def figure2(as_json: JsonOpt = False, out: _out("homlimit-out/figure2/") = None):
    """The paper's Figure 2: critical λ and v̄_g/√(gb) against ρ, both mechanisms, DEM points.

    Writes figure2.png and figure2.json (the curves); --json prints the curves."""
    study_cmds.figure2(**locals())


@app.command()
@guarded
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
    study_cmds.verify(**locals())


@app.command("crack-study")
@guarded
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
                conform: Annotated[bool, typer.Option(
                    "--conform/--no-conform", help="On the homogenised façade, also search "
                    "λ⁺ over meshes conforming to a hinge + fan (docs/crack-angle.md): the "
                    "crack's edges resolved.")] = True,
                workers: WorkersOpt = None, scheduler: SchedulerOpt = None,
                resume: Annotated[bool, typer.Option(
                    "--resume/--no-resume", help="Keep the points recorded in OUT/records/ "
                                                 "by an earlier run.")] = True):
    """The crack-angle study: the FE crack slope over a grid of c/a and f, beside √(cf/a)."""
    study_cmds.crack_study(**locals())


@app.command()
@guarded
def pulse(case: CaseArg = None, as_json: JsonOpt = False,
          out: _out(f"homlimit-out/NAME/pulse/, {_NAME}") = None,
          verbose: VerboseOpt = False, quiet: QuietOpt = False, overrides: SetOpt = None):
    """Overturning spectra: the critical pulse per mechanism against pulse period ([pulse]);
    default folder homlimit-out/NAME/pulse/."""
    case_cmds.pulse(**locals())


@app.command()
@guarded
def mesh(case: CaseArg = None, as_json: JsonOpt = False,
         out: _out(f"homlimit-out/NAME/mesh/, {_NAME}") = None,
         overrides: SetOpt = None):
    """Mesh the T-section of a case only; write mesh.vtu and mesh.png for inspection
    (default folder homlimit-out/NAME/mesh/)."""
    case_cmds.mesh(**locals())


# ----------------------------------------------------------------------------- sweeps (Dask)
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
@guarded
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
    sweep_cmds.sweep_run(**locals())


@sweep_app.command("report")
@guarded
def sweep_report_cmd(
        results: Annotated[Path, typer.Argument(help="A sweep folder, or its results.parquet "
                                                     "/ results.csv.")],
        out: Annotated[Path | None, typer.Option("--out", "-o", help="Folder of the "
                                                 "plots [default: RESULTS/report/].")] = None,
        as_json: JsonOpt = False):
    """Draw a sweep's standard plots: vg/sqrt(gb) against each swept key, the critical
    mechanism map, measured against predicted tan psi, the histogram of vg."""
    sweep_cmds.sweep_report(**locals())


def main():
    """Console-script entry point (``homlimit``, ``python -m homlimit``). Ctrl-C outside a
    command's own handling (while modules are still importing, say) exits 130 with one line,
    as an interrupted command does, never a traceback. The exit itself: ``door.leave``."""
    try:
        try:
            app(prog_name="homlimit")
        except KeyboardInterrupt:
            interrupted()
    except SystemExit as e:
        leave(e.code)
        raise


def interrupted():
    """Exit 130 with a one-line note: Ctrl-C before any command had begun its work."""
    print("homlimit: interrupted (SIGINT): nothing was written", file=sys.stderr)
    raise SystemExit(128 + signal.SIGINT)


if __name__ == "__main__":  # pragma: no cover
    main()
