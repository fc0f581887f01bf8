"""The one solve chain of homlimit's conic programs: settings, retry ladder, solve, status.

Three programs go through it: the FE kinematic (upper-bound) program and the rigid-block
program (``blocks.limit``), both kinematic linear or conic programs compiled by cvxpy and solved
by Clarabel or HiGHS (``solve_cvxpy``), and the FE static (lower-bound) program, handed to
Clarabel directly (``solve_clarabel``) or through cvxpy. One ``SolverOptions`` configures all
three; ``SolverOptions.ladder`` lists the settings tried in turn, ``run_ladder`` tries them
until a solve does not stall, and ``check_status`` turns a final status into a ``SolverError``
naming its likely cause from one table (``_CAUSES``); ``Solved.report`` unpacks what the solver
says (status, objectives, iterations) into the fields of ``SolveRecord``, which the three
programs' results (``KinematicSolution``, ``StaticSolution``, ``blocks.BlockLimitResult``) share.
Statuses keep their solver's names: cvxpy's ("optimal", "optimal_inaccurate", ...) through
cvxpy, Clarabel's ("Solved", "AlmostSolved", ...) for the direct static solve (the static
program reports Clarabel's names through cvxpy too, ``CLARABEL_NAMES``).
"""

from __future__ import annotations

import time
import warnings
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field

import numpy as np

from .. import _threads
from ..errors import ParameterError, SolverError, check_choice, check_range
from .problems import Problem

__all__ = ["SolverOptions", "Solved", "SolveRecord", "solve_cvxpy", "solve_clarabel", "run_ladder",
           "check_status", "check_inputs", "solver_failed", "PROGRAMS", "FAER_ABOVE",
           "REFINE_ABOVE", "STATIC_RETRIES"]

SOLVERS = ("CLARABEL", "HIGHS")
DIRECT_METHODS = ("qdldl", "faer", "auto")
STRESS_DEGREES = (1, 2)
BACKENDS = ("direct", "cvxpy")
#: the programs of the chain: what names them in a message, their interior-point iteration
#: limit, whether an unset factorisation becomes faer on one thread above FAER_ABOVE
#: unknowns (not for the FE kinematic LP: "auto" → faer cost 6x the CPU of qdldl there,
#: docs/kinematic.md), the remedy a stalled solve suggests, and whether the program is the
#: static one (a maximum over stress fields, whose infeasibility is the kinematic program's
#: unboundedness)
PROGRAMS = {
    "kinematic": {"title": "kinematic limit analysis", "max_iter": 400, "faer": False,
                  "remedy": "scale_rows=True", "static": False},
    "blocks": {"title": "rigid-block limit analysis", "max_iter": 400, "faer": True,
               "remedy": "", "static": False},
    "static": {"title": "static limit analysis", "max_iter": 300, "faer": True,
               "remedy": "another stress_scale or mesh", "static": True},
}
# kinematic LPs with more free unknowns than this keep Clarabel's iterative refinement: without
# it the 131k-unknown T-section stalled at primal residual 7e-9 (the 60k one did not)
REFINE_ABOVE = 100_000
STATIC_REG = 1e-6  # the kinematic LP's last rung: Clarabel's static_regularization_constant
                   # (default 1e-8; docs/kinematic.md, "Very low friction")
# static and rigid-block programs with more unknowns than this factor with faer on one thread
# (two threads are slower on a 2-core machine). One value serves both: CPU seconds of the
# solve, qdldl / faer, measured on a loaded 2-core machine (docs/static.md, docs/blocks.md):
#   static, Prandtl fan:  31 285 unknowns 11.0 / 9.3,  37 693: 18.3 / 12.3,
#                         45 136: 24.4 / 16.0,         63 820: 51.5 / 29.4;
#   blocks, T-section B1: 28 980 unknowns 21.7 / 22.7, 34 200: 31.8 / 29.3,
#                         42 840: 46.1 / 36.4 (the blocks' former 45 000 lost 20 % there).
# Not for the FE kinematic LP ("auto" → faer cost it 6x the CPU, docs/kinematic.md).
FAER_ABOVE = 30_000
# the static program's rungs: its equilibrium programs are degenerate (many optimal stress
# fields away from the mechanism), so a static regularisation 1e-7 comes first (Clarabel's
# default 1e-8 stalled on most Prandtl meshes), then 1e-6, the other factorisation, and
# Clarabel's defaults
STATIC_RETRIES = ({"static_regularization_constant": 1e-7},
                  {"static_regularization_constant": 1e-6}, "other factorisation", {})
# a solve that stopped short, in Clarabel's names and cvxpy's (cvxpy reports Clarabel's
# MaxIterations as "user_limit"): tried again down the ladder
STALLED = ("optimal_inaccurate", "AlmostSolved", "NumericalError", "InsufficientProgress",
           "MaxIterations", "user_limit")
# cvxpy's statuses that pass ``check_status`` in Clarabel's names (``Solved.report``)
CLARABEL_NAMES = {"optimal": "Solved", "optimal_inaccurate": "AlmostSolved"}


@dataclass(frozen=True)
class SolverOptions:
    """Settings of the conic solve of every program of ``PROGRAMS`` (defaults measured in
    benchmarks/, see docs/kinematic.md, docs/static.md and docs/blocks.md).

    solver               "CLARABEL" (default; LP and SOC) or "HIGHS" (LP only, through cvxpy:
                         interior point without crossover for the kinematic bound, HiGHS's
                         default (simplex: a vertex solution) for the static bound)
    tol                  Clarabel's tol_gap_abs = tol_gap_rel = tol_feas; None: 1e-9 for a linear
                         program, 1e-7 with second-order cones (tighter stalls on the
                         Mohr–Coulomb footing: degenerate duals at the apex)
    direct_solve_method  Clarabel's KKT factorisation "qdldl", "faer" or "auto"; None: "qdldl"
                         ("auto" picks faer on large kinematic LPs at 6x the CPU of qdldl),
                         except static and rigid-block programs above FAER_ABOVE unknowns:
                         faer on one thread
    max_iter             interior-point iteration limit; None: 400 (kinematic, blocks), 300
                         (static)
    equilibrate          Clarabel's Ruiz equilibration (indispensable for the kinematic LP)
    scale_rows           FE kinematic bound: scale each point's cone rows by its triangle's size
                         (makes B = O(1))
    iterative_refinement Clarabel's iterative refinement of each KKT solve; None: Clarabel's
                         default (on) for the static bound; for the kinematic and rigid-block
                         programs off for a linear program of up to REFINE_ABOVE free unknowns
                         (1.75x faster on the 15k-triangle T-section, same λ to 1e-7), solved
                         again with it if that run stalls; on for larger LPs (the 33k-triangle
                         T-section stalls without it) and with second-order cones (without it
                         the Mohr–Coulomb footing stalls and the vertical cut ends 8e-4 higher)
    verbose              print the solver log
    retries              a stalled solve is tried again down ``ladder``
    settings             raw solver settings applied last to every attempt (Clarabel settings,
                         e.g. {"max_threads": 1}; cvxpy solve options for HiGHS)
    backend              static bound: "direct" (the assembled matrices handed to Clarabel) or
                         "cvxpy" (the same matrices as a cvxpy problem, the kinematic bound's
                         path; 4x slower); HiGHS always runs through cvxpy
    stress_scale         static bound: reference stress [Pa] of the scaled unknowns; None: the
                         largest of the strengths, body force × domain size and tractions
    stress_degree        static bound: 1 (linear stresses, three vertex values per triangle) or
                         2 (quadratic, six Bernstein coefficients; the strength condition on
                         every coefficient keeps the bound rigorous: docs/static.md)
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
    stress_degree: int = 1

    def __post_init__(self):
        check_choice("solver", self.solver, SOLVERS)
        check_choice("direct_solve_method", self.direct_solve_method, (None, *DIRECT_METHODS))
        check_choice("backend", self.backend, BACKENDS)
        if self.tol is not None:
            check_range("tol", self.tol, 0.0, 1e-2, lo_open=True)
        if self.max_iter is not None:
            check_range("max_iter", self.max_iter, 1)
        check_choice("stress_degree", self.stress_degree, STRESS_DEGREES)
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

    def ladder(self, program: str, n_unknowns: int, conic: bool) -> list[tuple[dict, dict]]:
        """The solver settings tried in turn, as [(rung, settings)], ``rung`` being what sets the
        attempt apart; ``program`` one of ``PROGRAMS``. Kinematic and blocks: one run, then, if
        it stalls with iterative refinement off by default, the same with it on; an LP at the
        default tolerance then at 1e-7; an LP last with the static regularisation STATIC_REG
        (the previous rung's tolerance kept). Static: the rungs of ``STATIC_RETRIES``. HiGHS:
        one run.
        Without ``retries`` only the first; ``settings`` is applied last to every rung.
        """
        check_choice("program", program, tuple(PROGRAMS))
        prog = PROGRAMS[program]
        raw = dict(self.settings or {})
        if self.solver == "HIGHS":
            ipm = {"highs_options": {"solver": "ipm", "run_crossover": "off"}}
            return [({}, {**(ipm if not prog["static"] else {}), **raw})]
        tol = self.tol if self.tol is not None else (1e-7 if conic else 1e-9)
        first = {"tol_gap_abs": tol, "tol_gap_rel": tol, "tol_feas": tol,
                 "max_iter": int(self.max_iter or prog["max_iter"])}
        method = self.direct_solve_method or (
            "faer" if prog["faer"] and n_unknowns > FAER_ABOVE else "qdldl")
        first["direct_solve_method"] = method
        if self.direct_solve_method is None and method == "faer":
            first["max_threads"] = 1
        if not prog["static"]:
            refine = (self.iterative_refinement if self.iterative_refinement is not None
                      else conic or n_unknowns > REFINE_ABOVE)
            first.update(iterative_refinement_enable=bool(refine),
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


@dataclass(frozen=True, kw_only=True)
class SolveRecord:
    """What the result of every program of ``PROGRAMS`` keeps of its solve (the kinematic,
    static and rigid-block results derive from it; ``Solved.report`` fills the first five).

    status               the last attempt's status, in its solver's names (``Solved.report``)
    solver               "CLARABEL" or "HIGHS"
    primal_objective, dual_objective   the objectives at the optimum as the solver reports them
                         (``Solved.report``: Clarabel's own pair, else cvxpy's value and the
                         program's own dual objective or NaN)
    iterations           interior-point iterations
    times                [s] per stage of the program
    sizes                the program's sizes and the ladder's attempts
    """

    status: str
    solver: str
    primal_objective: float
    dual_objective: float
    iterations: int
    times: dict = field(default_factory=dict)
    sizes: dict = field(default_factory=dict)


@dataclass
class Solved:
    """The end of a solve down the ladder (its status checked: optimal).

    status       the last attempt's status (the solver's own name)
    attempts     [(rung, status, iterations)] as from ``run_ladder``
    settings     the last attempt's solver settings
    raw          the solver's raw solution of the last attempt (cvxpy: unpacked into the
                 problem; direct Clarabel: its ``DefaultSolution``)
    iterations   interior-point iterations of the last attempt
    times        [s] "compile" (cvxpy's problem data), "solve" (the solver's own time, summed
                 over the attempts), "wrap" (the rest: hand-over and unpacking)
    data         cvxpy's problem data (None for direct Clarabel)
    value        cvxpy's optimal value of the problem (None for direct Clarabel)
    solver       the solver's name ("CLARABEL", "HIGHS")
    """

    status: str
    attempts: list
    settings: dict
    raw: object
    iterations: int
    times: dict = field(default_factory=dict)
    data: dict | None = None
    value: float | None = None
    solver: str = "CLARABEL"

    def report(self, *, dual: float = float("nan"), negate: bool = False,
               clarabel_names: bool = False) -> dict:
        """The solve's fields of a ``SolveRecord`` (status, solver, primal_objective,
        dual_objective, iterations), to pass to a result as keywords. The objectives are
        Clarabel's own pair where it reports one (through cvxpy or directly), else cvxpy's
        value and ``dual`` (the program's own dual objective, or NaN); ``negate``: the
        program is a maximum posed as the minimum of its negative (the static one), so both
        change sign; ``clarabel_names``: the status in Clarabel's names (``CLARABEL_NAMES``)."""
        if hasattr(self.raw, "obj_val_dual"):             # Clarabel reports both objectives
            primal, dual = float(self.raw.obj_val), float(self.raw.obj_val_dual)
        else:
            primal = float(self.value)
        sign = -1.0 if negate else 1.0
        status = CLARABEL_NAMES.get(self.status, self.status) if clarabel_names else self.status
        return {"status": status, "solver": self.solver, "primal_objective": sign * primal,
                "dual_objective": sign * dual, "iterations": self.iterations}


def _down_ladder(attempt, raws: list, times: dict, options: SolverOptions, program: str,
                 n_unknowns: int, conic: bool, **extra) -> Solved:
    """``run_ladder`` over ``options.ladder(...)``, ``check_status`` of the last attempt, and
    its ``Solved`` (``raws``: the raw solution of every attempt, appended by ``attempt``)."""
    t0 = time.perf_counter()
    ladder = options.ladder(program, n_unknowns, conic)
    status, attempts = run_ladder(attempt, ladder)
    times["wrap"] = time.perf_counter() - t0 - times["solve"]
    check_status(program, status, options.solver, attempts)
    return Solved(status=status, attempts=attempts, settings=ladder[len(attempts) - 1][1],
                  raw=raws[-1], iterations=attempts[-1][2], times=times,
                  solver=options.solver, **extra)


def solve_cvxpy(prob, options: SolverOptions, program: str, n_unknowns: int,
                conic: bool) -> Solved:
    """Compile the cvxpy problem ``prob`` once for ``options.solver``, solve it down
    ``options.ladder(program, n_unknowns, conic)``, unpack every attempt into ``prob`` (its
    variables and duals hold the last one) and ``check_status`` the last: a SolverError
    naming the likely cause unless it is optimal."""
    import cvxpy as cp

    t0 = time.perf_counter()
    data, chain, inv = prob.get_problem_data(options.solver)
    times = {"compile": time.perf_counter() - t0, "solve": 0.0}
    raws = []

    def attempt(opts):
        if hasattr(inv[-1], "solver_options"):
            inv[-1].solver_options = dict(opts)      # what prob.solve() would have recorded
        t1 = time.perf_counter()
        try:
            raw = _threads.call(chain.solve_via_data, prob, data, warm_start=False,
                                verbose=options.verbose, solver_opts=dict(opts))
            with warnings.catch_warnings():    # an inaccurate status raises in check_status
                warnings.simplefilter("ignore", UserWarning)
                prob.unpack_results(raw, chain, inv)
        except cp.error.SolverError as exc:
            raise solver_failed(program, options.solver, exc) from exc
        times["solve"] += float(prob.solver_stats.solve_time or time.perf_counter() - t1)
        raws.append(raw)
        return prob.status, prob.solver_stats.num_iters or 0

    run = _down_ladder(attempt, raws, times, options, program, n_unknowns, conic, data=data)
    run.value = prob.value
    return run


def solve_clarabel(q: np.ndarray, A, b: np.ndarray, cones: list, options: SolverOptions,
                   program: str, conic: bool) -> Solved:
    """Clarabel directly on min qᵀx s.t. A x + s = b, s ∈ ``cones`` (Clarabel cone objects),
    down ``options.ladder(program, q.size, conic)``; ``check_status`` as ``solve_cvxpy``."""
    import clarabel
    import scipy.sparse as sp

    P = sp.csc_matrix((q.size, q.size))
    sols = []
    times = {"compile": 0.0, "solve": 0.0}

    def attempt(opts):
        settings = clarabel.DefaultSettings()
        settings.verbose = bool(options.verbose)
        for key, val in opts.items():
            setattr(settings, key, val)
        sol = _threads.call(lambda: clarabel.DefaultSolver(P, q, A, b, cones, settings).solve())
        times["solve"] += float(sol.solve_time)
        sols.append(sol)
        return str(sol.status).split(".")[-1], sol.iterations

    return _down_ladder(attempt, sols, times, options, program, q.size, conic)


_NO_MECHANISM = ("no admissible mechanism has unit live-load power, so λ is unbounded: the "
                 "supports, strength domains or contacts lock the body, or the live load does "
                 "no work (check the supports and the live load's direction)")
_DEAD_LOADS = ("the dead loads alone drive an admissible mechanism, so no admissible stress field "
               "carries them: a support, a strength condition or a contact is missing (without "
               "tension a load needs a compressive path to a support)")
# what a status says in either solver's names: the program (as posed, a minimum) has no
# feasible point ("infeasible") or no lower bound ("unbounded"), with an accurate certificate
# or not
_VERDICT = {"infeasible": ("infeasible", True), "PrimalInfeasible": ("infeasible", True),
            "unbounded": ("unbounded", True), "DualInfeasible": ("unbounded", True),
            "infeasible_inaccurate": ("infeasible", False),
            "AlmostPrimalInfeasible": ("infeasible", False),
            "unbounded_inaccurate": ("unbounded", False),
            "AlmostDualInfeasible": ("unbounded", False)}
# the one table of causes, by (static program?, verdict): the kinematic program is the dual of
# the static one, its infeasibility is the static program's unboundedness and vice versa
_CAUSES = {(False, "infeasible"): _NO_MECHANISM, (True, "unbounded"): _NO_MECHANISM,
           (False, "unbounded"): _DEAD_LOADS, (True, "infeasible"): _DEAD_LOADS}


def _remedy(program: str) -> str:
    extra = PROGRAMS[program]["remedy"]
    return "try a looser tol or another direct_solve_method" + (f", {extra}" if extra else "")


def check_status(program: str, status: str, solver: str, attempts=()) -> None:
    """Raise a SolverError naming the likely cause unless ``status`` is optimal ("optimal",
    "Solved"); ``program`` one of ``PROGRAMS``, ``attempts`` as from ``run_ladder``."""
    if status in ("optimal", "Solved"):
        return
    if status in _VERDICT:
        verdict, accurate = _VERDICT[status]
        cause = _CAUSES[PROGRAMS[program]["static"], verdict]
        if not accurate:
            cause = f"probably: {cause} (inaccurate certificate)"
    else:
        tried = (f" after {len(attempts)} attempt(s) {[a[1] for a in attempts]}"
                 if attempts else "")
        cause = (f"numerical trouble or the iteration limit: the solver stopped before the "
                 f"requested accuracy{tried} ({_remedy(program)})")
    raise SolverError(f"{PROGRAMS[program]['title']} ended with {solver} status {status!r}: "
                      f"{cause}", status=status)


def solver_failed(program: str, solver: str, exc: Exception) -> SolverError:
    """The SolverError for a solver that raised (cvxpy's SolverError) instead of ending."""
    return SolverError(f"{PROGRAMS[program]['title']}: {solver} failed: {exc} (numerical "
                       f"trouble: {_remedy(program)})", status="solver_error")


def check_inputs(problem, options) -> None:
    """Both bounds take a ``problems.Problem`` and a ``SolverOptions`` it can take (checked
    before any work: the static stress degree)."""
    if not isinstance(problem, Problem):
        raise ParameterError(f"problem = {type(problem).__name__} is out of range: allowed a "
                             f"homlimit.fe.problems.Problem")
    if not isinstance(options, SolverOptions):
        raise ParameterError(f"options = {type(options).__name__} is out of range: allowed a "
                             f"homlimit.fe.solver.SolverOptions")
    if options.stress_degree not in problem.stress_degrees:
        raise ParameterError(f"stress_degree = {options.stress_degree} is out of range for "
                             f"problem {problem.name!r}, which has rigid regions or joints: "
                             f"allowed {problem.stress_degrees} (quadratic stresses on bodies and "
                             f"joints are not built)")
