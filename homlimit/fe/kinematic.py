"""Kinematic (upper-bound) limit analysis as one conic program, solved by Clarabel via cvxpy.

    λ⁺ = min_u  D(u) − P_dead(u)   s.t.  P_live(u) = 1,  d_p = B_p u ∈ dom π at every point p,

with u the free P2 velocity DOFs (supports eliminated, not constrained), d_p the strain rate at
the three vertices of every triangle and D(u) = Σ_p (area/3) π(d_p). Each region's strength
domain supplies its conic form π(d) = min_y cx·d + cy·y s.t. A d + D y + e ∈ K (a
``strength.ConicBlock``); over all points of a region it becomes one sparse matrix per cone
kind: kron(I, A) B u + kron(I, D) y + 1 ⊗ e ∈ K (no per-point Python objects). Joints to a
fixed ground (``Problem.interfaces``) add the same blocks on the jump at the Bernstein control
points of every facet (``operators.boundary_jump_operator``). A tie (``Problem.ties``: a
traction ν t, 0 <= ν <= 1) dissipates max(0, −P_t(u)), P_t(u) = ∫ t·v ds its power at yield:
one auxiliary s >= 0, s >= −P_t(u), cost s (the dual of the static program's free ν).

Because π is convex and positively homogeneous and d is linear on a triangle, the cone at the
vertices holds everywhere and the vertex rule overestimates ∫π: every feasible u gives a strict
upper bound of the collapse multiplier of the continuum (for the chosen loads and supports).
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field

import cvxpy as cp
import numpy as np
import scipy.sparse as sp

from . import operators as ops
from .conic import Stack, stack
from .problems import Problem
from .solution import KinematicSolution
from .solver import SolverOptions, check_inputs, solve_cvxpy

__all__ = ["Discretisation", "discretise", "solve_kinematic"]

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
    F_ties: dict = field(default_factory=dict)  # boundary → power of its tie at yield


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
    F_ties = {bnd: ops.traction_power(basis, bnd, trac) for bnd, trac in problem.ties.items()}
    return Discretisation(basis, B, w, np.flatnonzero(~fixed), F_live, F_dead, jumps, F_ties)


@dataclass
class _Cones:
    """One region's (or interface's) cone rows as cvxpy constraints, and how to read duals."""

    rows: Stack
    weights: np.ndarray              # integration weight per point
    scale: np.ndarray                # row scale per point
    y: cp.Variable | None
    cons: list                       # [(kind, constraint)]
    points: np.ndarray | None = None  # indices into the operator's points (regions)


def _cones(block, Bp: sp.csr_matrix, x: cp.Variable, weights: np.ndarray, scale: np.ndarray):
    """Constraints s_p (A d_p + D y_p + e) ∈ K for all points, d = Bp x (``conic.stack``, rows
    in row order: one batched constraint per kind, one ``cp.SOC(axis=1)`` per cone of the
    block). Returns (_Cones, objective vector on x or None, objective term in y)."""
    st = stack(block, Bp, scale, order="row")
    n = st.n
    y = cp.Variable(n * block.n_aux) if block.n_aux else None

    def expr(rows, sl=slice(None)):
        out = rows.M[sl] @ x
        if y is not None:
            out = out + rows.D[sl] @ y
        return out + rows.e[sl] if np.any(rows.e[sl]) else out

    cons = [(kind, expr(st.kinds[kind]) == 0 if kind == "eq" else expr(st.kinds[kind]) >= 0)
            for kind in ("eq", "lin") if kind in st.kinds]
    o = 0
    for q in block.soc:
        t = expr(st.kinds["soc"], slice(o * n, (o + 1) * n))
        X = expr(st.kinds["soc"], slice((o + 1) * n, (o + q) * n))
        cons.append(("soc", cp.SOC(t, cp.reshape(X, (n, q - 1), order="F"), axis=1)))
        o += q
    c_x, c_y = st.cost(Bp, weights)
    return _Cones(st, weights, scale, y, cons), c_x, (c_y @ y if c_y is not None else 0)


def _point_duals(c: _Cones) -> np.ndarray:
    """Duals z_p of the unscaled rows A d_p + D y_p + e ∈ K, shape (n, m); L = obj − Σ z·row."""
    vals = {}
    for kind, con in c.cons:
        if kind == "soc":
            dt, dX = con.dual_value
            n = c.rows.n
            vals.setdefault("soc", []).extend(
                [np.asarray(dt).ravel(), np.asarray(dX).reshape(n, -1).ravel(order="F")])
        else:                                        # cvxpy: L = obj + ν·(expr) for expr == 0
            dv = np.asarray(con.dual_value).ravel()
            vals[kind] = [-dv if kind == "eq" else dv]
    Z = c.rows.per_point({k: np.concatenate(v) for k, v in vals.items()})
    return Z * c.scale[:, None]


def solve_kinematic(problem: Problem, options: SolverOptions = SolverOptions()
                    ) -> KinematicSolution:
    """Collapse multiplier λ⁺ (strict upper bound) and mechanism of ``problem``."""
    check_inputs(problem, options)
    blocks = {reg: dom.kinematic_cone() for reg, dom in problem.domains.items()}
    jblocks = {bnd: dom.kinematic_cone() for bnd, dom in problem.interfaces.items()}
    conic = any(b.soc for b in [*blocks.values(), *jblocks.values()])
    options.check_program(conic)
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
    x = cp.Variable(free.size)
    c_u = -disc.F_dead[free] / kappa
    cost_y = 0
    size = np.sqrt(3.0 * disc.w)                       # ~ triangle size, per point
    parts = []                                         # (key, block, d = X x, w, scale, points)
    for reg, block in blocks.items():
        elems = np.asarray(mesh.subdomains[reg])
        pts = (3 * elems[:, None] + np.arange(3)).ravel()
        rows = (3 * pts[:, None] + np.arange(3)).ravel()
        scale = size[pts] if options.scale_rows else np.ones(pts.size)
        parts.append((("region", reg), block, Bf[rows], disc.w[pts], scale, pts))
    for bnd, block in jblocks.items():
        J, wj = disc.jumps[bnd]
        scale = np.sqrt(3.0 * wj) if options.scale_rows else np.ones(wj.size)
        parts.append((("interface", bnd), block, J[:, free].tocsr(), wj, scale, None))
    cons, stacks = [], {}
    for key, block, X, w, scale, pts in parts:
        st, c_x, c_y = _cones(block, X, x, w / kappa, scale)
        st.points = pts
        stacks[key] = st
        cons += [c for _, c in st.cons]
        if c_x is not None:
            c_u = c_u + c_x
        cost_y = cost_y + c_y
    if disc.F_ties:                                    # ties: s_k >= max(0, −P_k(u)/κ)
        F_t = np.stack([F[free] for F in disc.F_ties.values()]) / kappa
        s_tie = cp.Variable(F_t.shape[0], nonneg=True)
        cons.append(s_tie + F_t @ x >= 0)
        cost_y = cost_y + cp.sum(s_tie)
    normalise = (disc.F_live[free] / kappa) @ x == 1.0
    prob = cp.Problem(cp.Minimize(c_u @ x + cost_y), [normalise, *cons])
    # compiled once, solved down the ladder: without iterative refinement the LP can stall on
    # large meshes, and is solved again with it (solver.SolverOptions.ladder)
    run = solve_cvxpy(prob, options, "kinematic", free.size, conic)
    times["build"] = time.perf_counter() - t0 - run.times["solve"] - run.times["wrap"]
    times["solve"] = run.times["solve"]
    times["wrap"] = run.times["wrap"]                  # cvxpy's hand-over
    stats, data, attempts = prob.solver_stats, run.data, run.attempts

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
        blk = st.rows.block
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
    solve = run.report(dual=dual_obj)          # Clarabel's own objectives where it has them
    primal, dual_obj = solve["primal_objective"], solve["dual_objective"]
    times["unpack"] = time.perf_counter() - t0
    times["total"] = sum(times[k] for k in ("mesh", "assembly", "build", "solve", "unpack"))
    sizes = {"triangles": int(nel), "dofs": int(disc.basis.N), "free": int(free.size),
             "variables": int(data["A"].shape[1]), "rows": int(data["A"].shape[0]),
             "nnz": int(data["A"].nnz), "iterations": int(stats.num_iters or 0),
             "retried": int(len(attempts) > 1), "attempts": attempts,
             "tol": run.settings.get("tol_gap_rel")}
    return KinematicSolution(
        multiplier=primal, u=u, velocity=u[disc.basis.nodal_dofs].T.copy(),
        dissipation=dissip_pt.reshape(nel, 3).sum(axis=1), interface_dissipation=idis,
        strain_rate=d, intensity=intensity, stress=stress,
        live_power=float(disc.F_live @ u), dead_power=float(disc.F_dead @ u),
        gap=primal - dual_obj, **solve, times=times, sizes=sizes, mesh=mesh,
        regions={k: np.asarray(v) for k, v in (mesh.subdomains or {}).items()})

