"""``solve_static``: the static program assembled step by step, solved, and read back."""

from __future__ import annotations

import time

import numpy as np
import scipy.sparse as sp

from ...errors import SolverError, check_range
from ..solver import SolverOptions, check_inputs, solve_clarabel, solve_cvxpy
from .assembly import StaticProgram
from .solution import StaticSolution

__all__ = ["solve_static"]


def solve_static(problem, options: SolverOptions = SolverOptions(), *,
                 active_tol: float = 1e-6) -> StaticSolution:
    """Largest live multiplier λ⁻ (a lower bound) carried by a statically admissible linear
    (``options.stress_degree`` 1) or quadratic (2) stress field of ``problem``, a
    ``problems.Problem`` as for ``kinematic.solve_kinematic``.

    options : the ``solver.SolverOptions`` of both bounds. Static-only fields: ``backend``
        ("direct": Clarabel on the assembled matrices, the default; "cvxpy": the same matrices
        as a cvxpy problem, the kinematic bound's path) and
        ``stress_scale`` (reference stress [Pa], default from the data). A stalled solve is
        retried down ``options.ladder("static", ...)``; the attempts are in ``sizes``.
    active_tol : post-processing, not a solver setting (hence a keyword): a facet is active at
        a vertex when its normalised slack is at most this (relative to the reference stress).
    """
    check_inputs(problem, options)
    check_range("active_tol", active_tol, 0.0, lo_open=True)
    doms = (*problem.domains.values(), *problem.interfaces.values())
    options.check_program(any(dom.static_cone().soc for dom in doms))
    times = {}
    t0 = time.perf_counter()
    prog = StaticProgram(problem, options.stress_scale, options.stress_degree)
    prog.equilibrium()     # 1. div σ + λ b + b⁰ = 0 in every triangle
    prog.continuity()      # 2. σ n continuous across interior edges
    prog.boundary()        # 3. σ n = λ t + t⁰ on free boundaries
    prog.joints()          # 4. σ n = σ_j n on joints to the ground, forces on bodies
    prog.bodies()          # 4b. every rigid body in equilibrium
    prog.strength()        # 5. σ ∈ G at every vertex, σ_j ∈ G_j on the joints
    blocks, rhs, layout, where, (M_eq, e_eq) = prog.matrix()
    M_full = sp.vstack(blocks, format="csc")
    M_full.eliminate_zeros()
    e = np.concatenate(rhs)
    # the stress columns of rigid elements are unused: leave them out of the program
    live = np.ones(prog.n_var, bool)
    rb = np.flatnonzero(prog.rigid)
    live[prog.sig(rb[:, None, None], np.arange(prog.nloc)[:, None], np.arange(3)).ravel()] = False
    M = M_full[:, live]
    times["assembly"] = time.perf_counter() - t0

    t1 = time.perf_counter()
    q = np.zeros(prog.n_var)
    q[prog.lam] = -1.0
    direct = options.backend == "direct" and options.solver == "CLARABEL"
    # the one solve chain (fe.solver): the ladder, then a SolverError naming the cause
    x_live, run = (_solve_direct if direct else _solve_cvxpy)(M, e, q[live], layout, options)
    times["solve"] = time.perf_counter() - t1
    x = np.zeros(prog.n_var)
    x[live] = x_live
    # the dropped rows must hold too (they do unless prescribed tractions contradict at a node)
    resid = np.abs(M_eq @ x + e_eq).max(initial=0.0)
    resid /= max(1.0, np.abs(x[:prog.n_sig]).max(initial=0.0))
    if resid > 1e-5:
        raise SolverError(f"static limit analysis: relative equilibrium residual {resid:.3g} after "
                          f"dropping dependent traction rows; the prescribed tractions are "
                          f"inconsistent at some boundary node", status="Inconsistent")
    control = (x[:prog.n_sig] * prog.s_ref).reshape(prog.nt, prog.nloc, 3)
    control[prog.rigid] = np.nan  # a rigid body's inner stresses are not determined
    stress = control[:, :3].copy()  # the vertex values (a Bernstein vertex coefficient is one)
    active = _active_facets(prog, where, M_full @ x + e, active_tol)
    times["post"] = time.perf_counter() - t1 - times["solve"]
    sizes = {"triangles": prog.nt, "variables": int(live.sum()), "rows": M.shape[0],
             "nnz": M.nnz, "equilibrium_rows": prog.n_equilibrium, "soc_cones": len(layout[2]),
             "rigid_bodies": prog.n_body, "attempts": run.attempts}
    # the program is min −λ: its objectives change sign; statuses in Clarabel's names
    return StaticSolution(multiplier=float(x[prog.lam]), stress=stress, active=active,
                          mesh=problem.mesh, **run.report(negate=True, clarabel_names=True),
                          sizes=sizes, times=times, rigid=prog.rigid,
                          control=control if prog.degree == 2 else None)


def _active_facets(prog: StaticProgram, where: list, slack: np.ndarray, active_tol: float):
    """Active facet (nt, 3) per vertex from the slacks of each domain's rows: each linear row,
    normalised by its |A| row, is one facet, each second-order cone (t − |u|) one; −1 where
    none is within ``active_tol``."""
    active = np.full((prog.nt, 3), -1)
    for (blk, els, st, _), rows in zip(prog.cones, where):
        if els is None or not (blk.n_lin or blk.soc):
            continue
        P = st.per_point({kind: slack[r] for kind, r in rows.items() if kind != "eq"})
        j = blk.n_eq + blk.n_lin
        norm = np.linalg.norm(blk.A[blk.n_eq:j], axis=1)
        cols = [P[:, blk.n_eq:j] / np.where(norm > 0, norm, 1.0)]
        for qd in blk.soc:
            cols.append((P[:, j] - np.linalg.norm(P[:, j + 1:j + qd], axis=1))[:, None])
            j += qd
        sl = np.hstack(cols)
        k = np.argmin(sl, axis=1)
        act = np.where(sl[np.arange(k.size), k] <= active_tol, k, -1)
        active[els] = act.reshape(els.size, prog.nloc)[:, :3]  # at the vertices
    return active


def _solve_direct(M, e, q, layout, options: SolverOptions):
    """Clarabel on min qᵀx s.t. M x + e ∈ K, i.e. A x + s = b, s ∈ K with A = −M, b = e;
    returns (x, the chain's ``Solved``)."""
    import clarabel

    n_zero, n_lin, socs = layout
    cones = ([clarabel.ZeroConeT(n_zero)] + ([clarabel.NonnegativeConeT(n_lin)] if n_lin else [])
             + [clarabel.SecondOrderConeT(d) for d in socs])
    run = solve_clarabel(q, -M, e, cones, options, "static", bool(socs))
    return np.asarray(run.raw.x), run


def _solve_cvxpy(M, e, q, layout, options: SolverOptions):
    """The same program through cvxpy: M x + e = 0 on the first n_zero rows, >= 0 on the next
    n_lin, then one second-order cone per entry of ``socs`` (cones of equal size batched)."""
    import cvxpy as cp

    n_zero, n_lin, socs = layout
    M = sp.csr_matrix(M)
    x = cp.Variable(q.size)
    cons = [M[:n_zero] @ x + e[:n_zero] == 0]
    if n_lin:
        cons.append(M[n_zero:n_zero + n_lin] @ x + e[n_zero:n_zero + n_lin] >= 0)
    dims = np.asarray(socs, int)
    start = n_zero + n_lin + np.r_[0, np.cumsum(dims)[:-1]].astype(int)
    for d in np.unique(dims):
        rows = start[dims == d][:, None] + np.arange(d)  # (cones, d)
        t = M[rows[:, 0]] @ x + e[rows[:, 0]]
        X = cp.vstack([M[rows[:, j]] @ x + e[rows[:, j]] for j in range(1, d)])
        cons.append(cp.SOC(t, X, axis=0))
    prob = cp.Problem(cp.Minimize(q @ x), cons)
    run = solve_cvxpy(prob, options, "static", q.size, bool(socs))
    return x.value, run
