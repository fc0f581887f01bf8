"""Kinematic (upper-bound) limit analysis as one conic program, solved by Clarabel via cvxpy.

    λ⁺ = min_u  D(u) − P_dead(u)   s.t.  P_live(u) = 1,  d_p = B_p u ∈ dom π at every point p,

with u the free P2 velocity DOFs (supports eliminated, not constrained), d_p the strain rate at
the three vertices of every triangle and D(u) = Σ_p (area/3) π(d_p). Each region's strength
domain supplies its conic form π(d) = min_y cx·d + cy·y s.t. A d + D y + e ∈ K (a
``strength.ConicBlock``); over all points of a region it becomes one sparse matrix per cone
kind: kron(I, A) B u + kron(I, D) y + 1 ⊗ e ∈ K (no per-point Python objects). Joints to a
fixed ground (``Problem.interfaces``) add the same blocks on the jump at the Bernstein control
points of every facet (``operators.boundary_jump_operator``).

Because π is convex and positively homogeneous and d is linear on a triangle, the cone at the
vertices holds everywhere and the vertex rule overestimates ∫π: every feasible u gives a strict
upper bound of the collapse multiplier of the continuum (for the chosen loads and supports).
"""

from __future__ import annotations

import time
import warnings
from dataclasses import dataclass, field

import cvxpy as cp
import numpy as np
import scipy.sparse as sp

from ..errors import ParameterError, SolverError, check_range
from . import operators as ops
from .problems import Problem
from .solution import KinematicSolution

__all__ = ["SolverOptions", "Discretisation", "discretise", "solve_kinematic"]

SOLVERS = ("CLARABEL", "HIGHS")
# LPs with more free unknowns than this keep Clarabel's iterative refinement: without it the
# 131k-unknown T-section stalled at primal residual 7e-9 (the 60k one did not)
REFINE_ABOVE = 100_000
DIRECT_METHODS = ("qdldl", "faer", "auto")


@dataclass(frozen=True)
class SolverOptions:
    """Settings of the conic solve (defaults measured in benchmarks/, see docs/kinematic.md).

    solver               "CLARABEL" (default; LP and SOC) or "HIGHS" (interior point; LP only)
    tol                  Clarabel's tol_gap_abs = tol_gap_rel = tol_feas; None: 1e-9 for a linear
                         program, 1e-7 with second-order cones (tighter stalls on the
                         Mohr–Coulomb footing: degenerate duals at the apex)
    direct_solve_method  Clarabel's KKT factorisation: "qdldl" (default), "faer" or "auto"
    max_iter             interior-point iteration limit
    equilibrate          Clarabel's Ruiz equilibration
    scale_rows           scale each point's cone rows by its triangle's size (makes B = O(1))
    iterative_refinement Clarabel's iterative refinement of each KKT solve; None: off for a
                         linear program of up to REFINE_ABOVE free unknowns (1.75x faster on
                         the 15k-triangle T-section, same λ to 1e-7), solved again with it if
                         that run stalls; on for larger LPs (the 33k-triangle T-section stalls
                         without it) and with second-order cones (without it the Mohr–Coulomb
                         footing stalls and the vertical cut ends 8e-4 higher)
    verbose              print the solver log
    """

    solver: str = "CLARABEL"
    tol: float | None = None
    direct_solve_method: str = "qdldl"
    max_iter: int = 400
    equilibrate: bool = True
    scale_rows: bool = True
    iterative_refinement: bool | None = None
    verbose: bool = False

    def __post_init__(self):
        if self.solver not in SOLVERS:
            raise ParameterError(f"solver = {self.solver!r} is out of range: allowed {SOLVERS}")
        if self.direct_solve_method not in DIRECT_METHODS:
            raise ParameterError(f"direct_solve_method = {self.direct_solve_method!r} is out of "
                                 f"range: allowed {DIRECT_METHODS}")
        if self.tol is not None:
            check_range("tol", self.tol, 0.0, 1e-2, lo_open=True)
        check_range("max_iter", self.max_iter, 1)

    @property
    def cvxpy_solver(self) -> str:
        return cp.HIGHS if self.solver == "HIGHS" else cp.CLARABEL

    def solver_opts(self, conic: bool = False, n_free: int = 0) -> dict:
        """Options handed to the solver through cvxpy (``conic``: the program has SOCs;
        ``n_free``: number of free velocity unknowns)."""
        if self.solver == "HIGHS":
            return {"highs_options": {"solver": "ipm", "run_crossover": "off"}}
        tol = self.tol if self.tol is not None else (1e-7 if conic else 1e-9)
        refine = (self.iterative_refinement if self.iterative_refinement is not None
                  else conic or n_free > REFINE_ABOVE)
        return dict(tol_gap_abs=tol, tol_gap_rel=tol, tol_feas=tol,
                    iterative_refinement_enable=bool(refine),
                    max_iter=int(self.max_iter), direct_solve_method=self.direct_solve_method,
                    equilibrate_enable=self.equilibrate)


@dataclass
class Discretisation:
    """The assembled operators of a problem, in global P2 DOFs (``operators.p2_basis``)."""

    basis: object
    B: sp.csr_matrix                 # strain rates at vertex points, (9 nel, N)
    w: np.ndarray                    # vertex-rule weights area/3, (3 nel,)
    free: np.ndarray                 # DOFs not fixed by a support
    F_live: np.ndarray               # P_live = F_live·u
    F_dead: np.ndarray               # P_dead = F_dead·u
    jumps: dict = field(default_factory=dict)   # boundary → (J, w) of interface jumps


def discretise(problem: Problem) -> Discretisation:
    """Assemble strain-rate, jump and load operators and find the free DOFs."""
    basis = ops.p2_basis(problem.mesh)
    B, w = ops.strain_rate_operator(basis)
    N = basis.N
    F_live, F_dead = np.zeros(N), np.zeros(N)
    for reg, force in problem.live_body.items():
        F_live += ops.body_force_power(basis, reg, force)
    for bnd, trac in problem.live_traction.items():
        F_live += ops.traction_power(basis, bnd, trac)
    for reg, force in problem.dead_body.items():
        F_dead += ops.body_force_power(basis, reg, force)
    for bnd, trac in problem.dead_traction.items():
        F_dead += ops.traction_power(basis, bnd, trac)
    fixed = np.zeros(N, bool)
    for bnd, comp in problem.supports.items():
        fixed[ops.support_dofs(basis, bnd, comp)] = True
    jumps = {bnd: ops.boundary_jump_operator(basis, bnd) for bnd in problem.interfaces}
    return Discretisation(basis, B, w, np.flatnonzero(~fixed), F_live, F_dead, jumps)


@dataclass
class _Stack:
    """One region's (or interface's) cone constraints over its points, and how to read duals."""

    block: object
    points: np.ndarray               # indices into the operator's points
    weights: np.ndarray              # integration weight per point
    scale: np.ndarray                # row scale per point
    y: cp.Variable | None
    cons: list                       # [(kind, constraint, row index within block)]


def _stack_block(block, Bp: sp.csr_matrix, x: cp.Variable, weights: np.ndarray,
                 scale: np.ndarray):
    """Constraints s_p (A d_p + D y_p + e) ∈ K for all points, d = Bp x (rows point-major).

    Returns (_Stack without points, objective vector on x, objective term in y).
    """
    n, m = weights.size, block.n_rows
    S = sp.diags(np.repeat(scale, m))
    MA = (S @ sp.kron(sp.identity(n, format="csr"), sp.csr_matrix(block.A)) @ Bp).tocsr()
    y = cp.Variable(n * block.n_aux) if block.n_aux else None
    MD = (S @ sp.kron(sp.identity(n, format="csr"), sp.csr_matrix(block.D))).tocsr() \
        if y is not None else None
    e = np.kron(scale, block.e)

    def rows(r):                      # rows r (array) of every point, point-major within r
        idx = (np.arange(n)[None, :] * m + np.asarray(r)[:, None]).ravel()
        expr = MA[idx] @ x
        if y is not None:
            expr = expr + MD[idx] @ y
        if np.any(e[idx]):
            expr = expr + e[idx]
        return expr

    cons = []
    r = 0
    if block.n_eq:
        cons.append(("eq", rows(np.arange(r, r + block.n_eq)) == 0, np.arange(r, r + block.n_eq)))
        r += block.n_eq
    if block.n_lin:
        cons.append(("lin", rows(np.arange(r, r + block.n_lin)) >= 0,
                     np.arange(r, r + block.n_lin)))
        r += block.n_lin
    for q in block.soc:
        t = rows([r])
        X = cp.reshape(rows(np.arange(r + 1, r + q)), (n, q - 1), order="F")
        cons.append(("soc", cp.SOC(t, X, axis=1), np.arange(r, r + q)))
        r += q
    c_x = (np.kron(weights, block.cx) @ Bp) if np.any(block.cx) else None
    c_y = np.kron(weights, block.cy) @ y if (y is not None and np.any(block.cy)) else 0
    return _Stack(block, np.arange(n), weights, scale, y, cons), c_x, c_y


def _point_duals(st: _Stack) -> np.ndarray:
    """Duals z_p of the unscaled rows A d_p + D y_p + e ∈ K, shape (n, m); L = obj − Σ z·row."""
    n, m = st.weights.size, st.block.n_rows
    Z = np.zeros((n, m))
    for kind, con, r in st.cons:
        if kind == "soc":
            dt, dX = con.dual_value
            Z[:, r[0]] = np.asarray(dt).ravel()
            Z[:, r[1:]] = np.asarray(dX).reshape(n, len(r) - 1)
        else:
            dv = np.asarray(con.dual_value).reshape(len(r), n).T
            Z[:, r] = -dv if kind == "eq" else dv   # cvxpy: L = obj + ν·(expr) for expr == 0
    return Z * st.scale[:, None]


def solve_kinematic(problem: Problem, options: SolverOptions = SolverOptions()
                    ) -> KinematicSolution:
    """Collapse multiplier λ⁺ (strict upper bound) and mechanism of ``problem``."""
    if not isinstance(problem, Problem):
        raise ParameterError(f"problem = {type(problem).__name__} is out of range: allowed a "
                             f"homlimit.fe.problems.Problem")
    if not isinstance(options, SolverOptions):
        raise ParameterError(f"options = {type(options).__name__} is out of range: allowed a "
                             f"homlimit.fe.kinematic.SolverOptions")
    blocks = {reg: dom.kinematic_cone() for reg, dom in problem.domains.items()}
    jblocks = {bnd: dom.kinematic_cone() for bnd, dom in problem.interfaces.items()}
    conic = any(b.soc for b in [*blocks.values(), *jblocks.values()])
    if options.solver == "HIGHS" and conic:
        raise ParameterError("solver = 'HIGHS' is out of range: HiGHS solves linear programs "
                             "only, and this problem has second-order cones; use 'CLARABEL'")
    times = {"mesh": float(problem.meta.get("mesh_time", 0.0))}

    t0 = time.perf_counter()
    disc = discretise(problem)
    mesh = problem.mesh
    nel = mesh.t.shape[1]
    free = disc.free
    Bf = disc.B[:, free].tocsr()
    times["assembly"] = time.perf_counter() - t0

    t0 = time.perf_counter()
    # unknowns x = κ u: with κ = Σ|F_live| a unit-power field has velocities of order 1 and
    # the objective (D − P_dead)/κ stays the multiplier (D is positively homogeneous)
    kappa = float(np.abs(disc.F_live).sum())
    if kappa == 0.0:
        raise ParameterError("live loads = 0 is out of range: the live loads must do work")
    x = cp.Variable(free.size)
    cons, stacks = [], {}
    c_u = -disc.F_dead[free] / kappa
    cost_y = 0
    size = np.sqrt(3.0 * disc.w)                       # ~ triangle size, per point
    for reg, block in blocks.items():
        elems = np.asarray(mesh.subdomains[reg])
        pts = (3 * elems[:, None] + np.arange(3)).ravel()
        rows = (3 * pts[:, None] + np.arange(3)).ravel()
        scale = size[pts] if options.scale_rows else np.ones(pts.size)
        st, c_x, c_y = _stack_block(block, Bf[rows], x, disc.w[pts] / kappa, scale)
        st.points = pts
        stacks[("region", reg)] = st
        cons += [c for _, c, _ in st.cons]
        if c_x is not None:
            c_u = c_u + c_x
        cost_y = cost_y + c_y
    for bnd, block in jblocks.items():
        J, wj = disc.jumps[bnd]
        scale = np.sqrt(3.0 * wj) if options.scale_rows else np.ones(wj.size)
        st, c_x, c_y = _stack_block(block, J[:, free].tocsr(), x, wj / kappa, scale)
        stacks[("interface", bnd)] = st
        cons += [c for _, c, _ in st.cons]
        if c_x is not None:
            c_u = c_u + c_x
        cost_y = cost_y + c_y
    normalise = (disc.F_live[free] / kappa) @ x == 1.0
    prob = cp.Problem(cp.Minimize(c_u @ x + cost_y), [normalise, *cons])
    data, chain, inv = prob.get_problem_data(options.cvxpy_solver)
    times["build"] = time.perf_counter() - t0

    t0 = time.perf_counter()
    opts = options.solver_opts(conic, free.size)
    raw = _solve(prob, data, chain, inv, opts, options)
    t_solve = time.perf_counter() - t0
    stats = prob.solver_stats
    times["solve"] = float(stats.solve_time) if stats.solve_time else t_solve
    retried = False
    if (prob.status == cp.OPTIMAL_INACCURATE and options.solver == "CLARABEL"
            and options.iterative_refinement is None and not opts["iterative_refinement_enable"]):
        # without refinement the LP can stall on large meshes: solve again with it
        retried = True
        t1 = time.perf_counter()
        raw = _solve(prob, data, chain, inv, {**opts, "iterative_refinement_enable": True},
                     options)
        t_solve += time.perf_counter() - t1
        times["solve"] += float(prob.solver_stats.solve_time or 0.0)
    stats = prob.solver_stats
    times["wrap"] = t_solve - times["solve"]         # cvxpy's hand-over to and from the solver
    _check_status(prob.status, options.solver)

    t0 = time.perf_counter()
    u = np.zeros(disc.basis.N)
    u[free] = x.value / kappa
    d = (disc.B @ u).reshape(nel, 3, 3)
    # stress estimate σ_p = cx − Aᵀ z_p / w_p, and dissipation per point cx·d + cy·y
    stress = np.zeros((nel, 3, 3))
    dissip_pt = np.zeros(3 * nel)
    dual_obj = float(-normalise.dual_value)
    idis = {}
    for (kind, name), st in stacks.items():
        blk = st.block
        Z = _point_duals(st)
        dual_obj -= float(np.sum(Z @ blk.e))
        yv = st.y.value.reshape(-1, blk.n_aux) / kappa if st.y is not None else None
        w_true = st.weights * kappa
        if kind == "region":
            dp = d.reshape(-1, 3)[st.points]
            # σ_p = cx − Aᵀ z_p / (w_p/κ): stationarity of the scaled program in x
            stress.reshape(-1, 3)[st.points] = blk.cx - (Z @ blk.A) / st.weights[:, None]
            val = dp @ blk.cx + (yv @ blk.cy if yv is not None else 0.0)
            dissip_pt[st.points] = w_true * val
        else:
            dj = (disc.jumps[name][0] @ u).reshape(-1, 3)
            val = dj @ blk.cx + (yv @ blk.cy if yv is not None else 0.0)
            idis[name] = (w_true * val).reshape(-1, 3).sum(axis=1)
    intensity = np.sqrt(d[..., 0] ** 2 + d[..., 1] ** 2 + 0.5 * d[..., 2] ** 2).mean(axis=1)
    primal = float(prob.value)
    if hasattr(raw, "obj_val_dual"):                 # Clarabel reports both objectives
        primal, dual_obj = float(raw.obj_val), float(raw.obj_val_dual)
    times["unpack"] = time.perf_counter() - t0
    times["total"] = sum(times[k] for k in ("mesh", "assembly", "build", "solve", "unpack"))
    sizes = {"triangles": int(nel), "dofs": int(disc.basis.N), "free": int(free.size),
             "variables": int(data["A"].shape[1]), "rows": int(data["A"].shape[0]),
             "nnz": int(data["A"].nnz), "iterations": int(stats.num_iters or 0),
             "retried": int(retried)}
    return KinematicSolution(
        multiplier=primal, u=u, velocity=u[disc.basis.nodal_dofs].T.copy(),
        dissipation=dissip_pt.reshape(nel, 3).sum(axis=1), interface_dissipation=idis,
        strain_rate=d, intensity=intensity, stress=stress,
        live_power=float(disc.F_live @ u), dead_power=float(disc.F_dead @ u),
        primal_objective=primal, dual_objective=dual_obj, gap=primal - dual_obj,
        status=prob.status, solver=options.solver, times=times, sizes=sizes, mesh=mesh,
        regions={k: np.asarray(v) for k, v in (mesh.subdomains or {}).items()})


def _solve(prob, data, chain, inv, opts: dict, options: SolverOptions):
    """Run the solver on the compiled data and unpack into ``prob``; returns the raw solution."""
    if hasattr(inv[-1], "solver_options"):
        inv[-1].solver_options = dict(opts)          # what prob.solve() would have recorded
    try:
        raw = chain.solve_via_data(prob, data, warm_start=False, verbose=options.verbose,
                                   solver_opts=dict(opts))
        with warnings.catch_warnings():     # an inaccurate status raises in _check_status
            warnings.simplefilter("ignore", UserWarning)
            prob.unpack_results(raw, chain, inv)
    except cp.error.SolverError as exc:
        raise SolverError(f"{options.solver} failed: {exc} (numerical trouble: try "
                          f"scale_rows=True, a looser tol or another direct_solve_method)",
                          status="solver_error") from exc
    return raw


_CAUSES = {
    "infeasible": "no kinematically admissible mechanism has unit live-load power: the supports "
                  "and strength domains lock the body, or the live load does no work",
    "unbounded": "the dead loads do unbounded work on an admissible mechanism: the body is "
                 "unstable under its dead loads alone (a support or a strength condition is "
                 "missing)",
    "infeasible_inaccurate": "probably no admissible mechanism (inaccurate certificate)",
    "unbounded_inaccurate": "probably unstable under dead loads alone (inaccurate certificate)",
    "optimal_inaccurate": "numerical trouble: the solver stalled before the requested accuracy "
                          "(try a looser tol, scale_rows=True or another direct_solve_method)",
}


def _check_status(status: str, solver: str) -> None:
    if status != cp.OPTIMAL:
        cause = _CAUSES.get(status, "numerical trouble or iteration limit")
        raise SolverError(f"{solver} ended with status {status!r}: {cause}", status=status)
