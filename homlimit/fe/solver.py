"""Solver settings of both bounds, their retry ladder, and the cause of a failed solve.

The kinematic (upper-bound) program is compiled by cvxpy and solved by Clarabel or HiGHS; the
static (lower-bound) program goes to Clarabel directly (or through cvxpy). One ``SolverOptions``
configures both; ``SolverOptions.ladder`` lists the settings tried in turn, ``run_ladder`` tries
them until a solve does not stall, and ``check_status`` turns a final status into a
``SolverError`` naming its likely cause. Statuses keep their solver's names: cvxpy's
("optimal", "optimal_inaccurate", ...) for the kinematic bound, Clarabel's ("Solved",
"AlmostSolved", ...) for the static one.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass

from ..errors import ParameterError, SolverError, check_choice, check_range
from .problems import Problem

__all__ = ["SolverOptions", "run_ladder", "check_status", "check_inputs", "solver_failed",
           "FAER_ABOVE", "REFINE_ABOVE", "STATIC_RETRIES"]

SOLVERS = ("CLARABEL", "HIGHS")
DIRECT_METHODS = ("qdldl", "faer", "auto")
BACKENDS = ("direct", "cvxpy")
MAX_ITER = {"kinematic": 400, "static": 300}
# kinematic LPs with more free unknowns than this keep Clarabel's iterative refinement: without
# it the 131k-unknown T-section stalled at primal residual 7e-9 (the 60k one did not)
REFINE_ABOVE = 100_000
STATIC_REG = 1e-6  # the kinematic LP's last rung: Clarabel's static_regularization_constant
                   # (default 1e-8; docs/kinematic.md, "Very low friction")
# static programs with more unknowns than this factor with faer on one thread (docs/static.md:
# 7091 triangles 26 s against 45 s with qdldl; a tie near 4 000 triangles; two threads are
# slower on a 2-core machine)
FAER_ABOVE = 30_000
# the static program's rungs: its equilibrium programs are degenerate (many optimal stress
# fields away from the mechanism), so a static regularisation 1e-7 comes first (Clarabel's
# default 1e-8 stalled on most Prandtl meshes), then 1e-6, the other factorisation, and
# Clarabel's defaults
STATIC_RETRIES = ({"static_regularization_constant": 1e-7},
                  {"static_regularization_constant": 1e-6}, "other factorisation", {})
STALLED = ("optimal_inaccurate", "AlmostSolved", "NumericalError", "InsufficientProgress",
           "MaxIterations")


@dataclass(frozen=True)
class SolverOptions:
    """Settings of the conic solve of either bound (defaults measured in benchmarks/, see
    docs/kinematic.md and docs/static.md).

    solver               "CLARABEL" (default; LP and SOC) or "HIGHS" (LP only, through cvxpy:
                         interior point without crossover for the kinematic bound, HiGHS's
                         default (simplex: a vertex solution) for the static bound)
    tol                  Clarabel's tol_gap_abs = tol_gap_rel = tol_feas; None: 1e-9 for a linear
                         program, 1e-7 with second-order cones (tighter stalls on the
                         Mohr–Coulomb footing: degenerate duals at the apex)
    direct_solve_method  Clarabel's KKT factorisation "qdldl", "faer" or "auto"; None: "qdldl"
                         ("auto" picks faer on large kinematic LPs at 6x the CPU of qdldl),
                         except static programs above FAER_ABOVE unknowns: faer on one thread
    max_iter             interior-point iteration limit; None: 400 (kinematic), 300 (static)
    equilibrate          Clarabel's Ruiz equilibration (indispensable for the kinematic LP)
    scale_rows           kinematic bound: scale each point's cone rows by its triangle's size
                         (makes B = O(1))
    iterative_refinement Clarabel's iterative refinement of each KKT solve; None: Clarabel's
                         default (on) for the static bound; for the kinematic bound off for a
                         linear program of up to REFINE_ABOVE free unknowns (1.75x faster on the
                         15k-triangle T-section, same λ to 1e-7), solved again with it if that
                         run stalls; on for larger LPs (the 33k-triangle T-section stalls
                         without it) and with second-order cones (without it the Mohr–Coulomb
                         footing stalls and the vertical cut ends 8e-4 higher)
    verbose              print the solver log
    retries              a stalled solve is tried again down ``ladder``
    settings             raw solver settings applied last to every attempt (Clarabel settings,
                         e.g. {"max_threads": 1}; cvxpy solve options for HiGHS)
    backend              static bound: "direct" (the assembled matrices handed to Clarabel) or
                         "cvxpy" (the same matrices as a cvxpy problem, the kinematic bound's
                         path; 4x slower); HiGHS always runs through cvxpy
    stress_scale         static bound: reference stress [Pa] of the scaled unknowns; None: the
                         largest of the strengths, body force × domain size and tractions
    """

    solver: str = "CLARABEL"
    tol: float | None = None
    direct_solve_method: str | None = None
    max_iter: int | None = None
    equilibrate: bool = True
    scale_rows: bool = True
    iterative_refinement: bool | None = None
    verbose: bool = False
    retries: bool = True
    settings: Mapping | None = None
    backend: str = "direct"
    stress_scale: float | None = None

    def __post_init__(self):
        check_choice("solver", self.solver, SOLVERS)
        check_choice("direct_solve_method", self.direct_solve_method, (None, *DIRECT_METHODS))
        check_choice("backend", self.backend, BACKENDS)
        if self.tol is not None:
            check_range("tol", self.tol, 0.0, 1e-2, lo_open=True)
        if self.max_iter is not None:
            check_range("max_iter", self.max_iter, 1)
        if self.stress_scale is not None:
            check_range("stress_scale", self.stress_scale, 0.0, lo_open=True, unit="Pa")
        if not isinstance(self.settings, Mapping | None):
            raise ParameterError(f"settings = {self.settings!r} is out of range: allowed a "
                                 f"mapping of solver settings or None")
        if self.solver == "HIGHS":
            import cvxpy as cp

            if "HIGHS" not in cp.installed_solvers():
                raise ParameterError(f"solver = 'HIGHS' is out of range: not installed; "
                                     f"installed cvxpy solvers {sorted(cp.installed_solvers())}")

    def check_program(self, conic: bool) -> None:
        """Raise before any work if the solver cannot take the program (HiGHS: LPs only)."""
        if conic and self.solver == "HIGHS":
            raise ParameterError("solver = 'HIGHS' is out of range: HiGHS solves linear programs "
                                 "only, and this problem has second-order cones; use 'CLARABEL'")

    def ladder(self, bound: str, n_unknowns: int, conic: bool) -> list[tuple[dict, dict]]:
        """The solver settings tried in turn, as [(rung, settings)], ``rung`` being what sets the
        attempt apart. Kinematic: one run, then, if it stalls with iterative refinement off by
        default, the same with it on; an LP at the default tolerance then at 1e-7; an LP last
        with the static regularisation STATIC_REG (the previous rung's tolerance kept). Static: the
        rungs of ``STATIC_RETRIES``. HiGHS: one run.
        Without ``retries`` only the first; ``settings`` is applied last to every rung.
        """
        raw = dict(self.settings or {})
        if self.solver == "HIGHS":
            ipm = {"highs_options": {"solver": "ipm", "run_crossover": "off"}}
            return [({}, {**(ipm if bound == "kinematic" else {}), **raw})]
        tol = self.tol if self.tol is not None else (1e-7 if conic else 1e-9)
        first = {"tol_gap_abs": tol, "tol_gap_rel": tol, "tol_feas": tol,
                 "max_iter": int(self.max_iter or MAX_ITER[bound])}
        if bound == "kinematic":
            refine = (self.iterative_refinement if self.iterative_refinement is not None
                      else conic or n_unknowns > REFINE_ABOVE)
            first.update(iterative_refinement_enable=bool(refine),
                         direct_solve_method=self.direct_solve_method or "qdldl",
                         equilibrate_enable=self.equilibrate)
            rungs = [{}] + ([{"iterative_refinement_enable": True}]
                            if self.iterative_refinement is None and not refine else [])
            if self.tol is None and not conic:   # last resort: 1e-7 (docs/kinematic.md)
                rungs.append({"iterative_refinement_enable": True, "tol_gap_abs": 1e-7,
                              "tol_gap_rel": 1e-7, "tol_feas": 1e-7})
            if not conic:   # a stiffer KKT regularisation, same tolerance: B1 at f = 0.001
                rungs.append({**rungs[-1], "iterative_refinement_enable": True,
                              "static_regularization_constant": STATIC_REG})
        else:
            method = self.direct_solve_method or ("faer" if n_unknowns > FAER_ABOVE else "qdldl")
            first["direct_solve_method"] = method
            if self.direct_solve_method is None and method == "faer":
                first["max_threads"] = 1
            if not self.equilibrate:
                first["equilibrate_enable"] = False
            if self.iterative_refinement is not None:
                first["iterative_refinement_enable"] = self.iterative_refinement
            other = {"direct_solve_method": "qdldl" if method == "faer" else "faer",
                     "max_threads": 1}
            rungs = [other if r == "other factorisation" else r for r in STATIC_RETRIES]
        rungs = rungs if self.retries else rungs[:1]
        return [(rung, {**first, **rung, **raw}) for rung in rungs]


def run_ladder(attempt: Callable[[dict], tuple[str, int]], ladder) -> tuple[str, list]:
    """Call ``attempt(settings) -> (status, iterations)`` down ``ladder`` until a status is not
    a stall; returns the last status and the attempts [(rung, status, iterations)]."""
    attempts = []
    for rung, settings in ladder:
        status, iterations = attempt(settings)
        attempts.append((rung, status, int(iterations)))
        if status not in STALLED:
            break
    return status, attempts


_NO_MECHANISM = ("no admissible mechanism has unit live-load power, so λ is unbounded: the "
                 "supports and strength domains lock the body, or the live load does no work "
                 "(check the supports and the live load's direction)")
_DEAD_LOADS = ("the dead loads alone drive an admissible mechanism, so no admissible stress field "
               "carries them: a support or a strength condition is missing (without tension a "
               "load needs a compressive path to a support)")
# the kinematic program is the dual of the static one: its infeasibility is the static
# program's unboundedness and vice versa
_CAUSES = {"infeasible": _NO_MECHANISM, "DualInfeasible": _NO_MECHANISM,
           "unbounded": _DEAD_LOADS, "PrimalInfeasible": _DEAD_LOADS}
_CAUSES.update({k: f"probably: {_CAUSES[v]} (inaccurate certificate)" for k, v in (
    ("infeasible_inaccurate", "infeasible"), ("AlmostDualInfeasible", "DualInfeasible"),
    ("unbounded_inaccurate", "unbounded"), ("AlmostPrimalInfeasible", "PrimalInfeasible"))})


def _remedy(bound: str) -> str:
    extra = "scale_rows=True" if bound == "kinematic" else "another stress_scale or mesh"
    return f"try a looser tol, another direct_solve_method, {extra}"


def check_status(bound: str, status: str, solver: str, attempts=()) -> None:
    """Raise a SolverError naming the likely cause unless ``status`` is optimal ("optimal",
    "Solved"); ``bound`` is "kinematic" or "static", ``attempts`` as from ``run_ladder``."""
    if status in ("optimal", "Solved"):
        return
    cause = _CAUSES.get(status)
    if cause is None:
        tried = (f" after {len(attempts)} attempt(s) {[a[1] for a in attempts]}"
                 if attempts else "")
        cause = (f"numerical trouble or the iteration limit: the solver stopped before the "
                 f"requested accuracy{tried} ({_remedy(bound)})")
    raise SolverError(f"{bound} limit analysis ended with {solver} status {status!r}: {cause}",
                      status=status)


def solver_failed(bound: str, solver: str, exc: Exception) -> SolverError:
    """The SolverError for a solver that raised (cvxpy's SolverError) instead of ending."""
    return SolverError(f"{bound} limit analysis: {solver} failed: {exc} (numerical trouble: "
                       f"{_remedy(bound)})", status="solver_error")


def check_inputs(problem, options) -> None:
    """Both bounds take a ``problems.Problem`` and a ``SolverOptions``."""
    if not isinstance(problem, Problem):
        raise ParameterError(f"problem = {type(problem).__name__} is out of range: allowed a "
                             f"homlimit.fe.problems.Problem")
    if not isinstance(options, SolverOptions):
        raise ParameterError(f"options = {type(options).__name__} is out of range: allowed a "
                             f"homlimit.fe.solver.SolverOptions")
