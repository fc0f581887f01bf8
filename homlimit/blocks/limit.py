"""Rigid-block kinematic limit analysis as one sparse linear (conic) program, Clarabel via cvxpy.

Unknowns: the velocity of every free block about its centroid G_i, q_i = (u_i, w_i, ω_i)
(ω counter-clockwise in the x–z view, so ω > 0 tips the top towards −x, the façade's outward
side). A point p of block i moves with v_i(p) = (u_i − ω_i (p_z − G_iz), w_i + ω_i (p_x − G_ix)).
At each end point p of each interface (normal n from block a to block b, tangent t) the
relative velocity [v] = v_b(p) − v_a(p) has the opening δ_n = [v]·n and the slip δ_t = [v]·t.
Relative velocities are linear along a rigid interface, so the conditions at the two end
points hold on the whole segment.

Associative Coulomb joints (the flow rule eq. 15 is derived from, de Buhan & de Felice
1997): δ_n >= f |δ_t|, i.e. δ_n − f δ_t >= 0 and δ_n + f δ_t >= 0, and no dissipation
without cohesion or tension (with them: below). Loads: self-weight dead, a horizontal body
force λ g per unit mass towards −x live. The kinematic theorem gives

    λ = min_q  −P_dead(q) / κ   s.t.  P_live(q) / κ = 1,   C q >= 0,

with κ = g × (mass of the free blocks), so that the mass-weighted mean of −u is 1. C is one
sparse matrix (two rows per contact point, six non-zeros per row) assembled in one vectorised
pass; the fixed blocks (the ground, or the part below an analysed height) have no unknowns.

The static dual: the multipliers y⁻, y⁺ >= 0 of the rows δ_n ∓ f δ_t give, at each contact
point, the force F = N n + T t exerted by block a on block b,
N = κ (y⁻ + y⁺) >= 0 (compression) and T = κ f (y⁺ − y⁻) (so |T| <= f N): stationarity of the
Lagrangian is the virtual-power statement P_dead + λ P_live + Σ_p (N δ_n + T δ_t) = 0 for
every q, i.e. equilibrium of every block (``equilibrium_residual`` checks it block by block).

Cohesion C and tension T (a real wall, ``blocks.real``; the end-point-force formulation of
rigid-block limit analysis: Livesley 1978, Int. J. Numer. Meth. Eng. 12:1853–1871). Pointwise
a contact carries σ >= −T_h, |τ| <= f σ + C, with T_h = min(T, C/f) (beyond the Coulomb apex
C/f a tension cannot act: the FE's ``BedJoints`` rule). Over its area A = d L (d: l in the
façade, s in the transversal wall, as the f_c cap) the end-point forces take exactly

    N_e >= −T_h A/2  (e = 0, 1; the tension cut-off),    |V| <= f N + C A  (V = T_0 + T_1),

both linear; equivalently N_e = N'_e − t_e, |T_e| <= f N'_e + r_e with N'_e >= 0, t_e =
T_h A/2, r_e = (C − f T_h) A/2 >= 0 (the domain is the cone of the rows above, shifted by the
uniform tension and widened by r_e). The kinematic program keeps the rows δ_n ∓ f δ_t >= 0
(associative: a cohesive joint dilates as a dry one) and gains the dissipation

    D = Σ_e t_e δ_n,e + r_e |δ_t,e| = d [C L |δ_t| + T_h ∫₀ᴸ (δ_n(s) − f |δ_t|) ds],

(|δ_t| is uniform along a contact): the cohesion's C A |slip| and the tension's T_h × the
opening beyond the dilatancy. Pure sliding (δ_n = f |δ_t|) costs C A |δ_t|, a block rocking
about its toe T_h d L² θ̇/2. Its static dual adds −t_e to N_e and the
multipliers of σ_e >= ±δ_t,e to T_e. With f_c as well the pointwise domain is
−T_h <= σ <= f_c, |τ| <= f σ + C, which is clean: the stress block of ``_RealTerms`` for
σ + T_h in [0, f_c + T_h] (C' = (f_c + T_h) d L) shifted by t_e, its support function
C |δ_t| + f_c (f|δ_t| − δ_n)⁺ + T_h (δ_n − f|δ_t|)⁺ per unit area.

Non-associative friction (``friction="non-associative"``): the iterative scheme of Gilbert,
Casapulla & Ahmed (2006, Computers & Structures 84:873–887), in this variant. Each iteration
solves the same LP with the Coulomb cone at every contact point replaced by a surface of zero
dilatancy whose shear capacity is fixed by the normal force of the previous iteration,
|T| <= f N_prev (kinematically: δ_n >= 0 and a dissipation f N_prev |δ_t|). It starts from the
associative forces and relaxes them, N_prev ← r N + (1 − r) N_prev (r = ``relax``). It stops
when λ changed by less than ``tol`` over the last three iterations and the last force field
meets Coulomb with its own normal forces. A converged iterate is a mechanism and a force field
with |T| <= f N at the same λ, sliding without dilatancy. Such a state need not exist, be
unique, or be the lowest one. Measured (docs/blocks.md): single blocks and stacks converge in
3 iterations; a running-bond panel converges to a state above its lowest non-associative
load; on the T-section λ settles into a narrow band while the normal forces keep moving. The
record keeps λ per iteration (``history``) and the flag ``converged``.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import cvxpy as cp
import numpy as np
import scipy.sparse as sp

from ..errors import ParameterError, check_range
from ..fe.solver import SolveRecord, SolverOptions, solve_cvxpy
from ..mechanism.rigidfit import RigidFit
from .geometry import FACADE, TOOTHING, Assembly, block_speed, vertex_velocity
from .real import anchor_blocks, real_of

__all__ = ["contact_operator", "loads", "BlockLimitResult", "fit_rotation", "solve_blocks",
           "equilibrium_residual", "check_result", "FRICTION_MODELS"]

FRICTION_MODELS = ("associative", "non-associative")
_CLOSED, _OPEN, _SLIDING = 0, 1, 2
STATE_NAMES = {_CLOSED: "closed", _OPEN: "open", _SLIDING: "sliding"}


def _scale(assembly: Assembly) -> np.ndarray:
    """Length ℓ_i per block (√area of its outline) scaling ω into a velocity ℓ ω."""
    from .geometry import polygon_moments

    A = polygon_moments(assembly.vertices, assembly.offsets)[0]
    return np.sqrt(np.abs(A))


def contact_operator(assembly: Assembly, scaled: bool = True):
    """Sparse (2K, 3n) operators Dn, Dt with [δ_n; δ_t] at the contact points 2k + e (interface
    k, end e) as Dn @ q, Dt @ q, for q = (u_0, w_0, ℓ_0 ω_0, u_1, ...) (``scaled``) or
    (u_0, w_0, ω_0, ...). Six non-zeros per row; built without a loop over blocks."""
    jt = assembly.interfaces
    G = assembly.centroid
    ell = _scale(assembly) if scaled else np.ones(assembly.n_blocks)
    K = jt.count
    p = jt.p.reshape(-1, 2)                               # (2K, 2): point 2k + e
    n = np.repeat(jt.n, 2, axis=0)
    t = np.c_[-n[:, 1], n[:, 0]]
    rows = np.arange(2 * K)
    mats = []
    for vec in (n, t):
        data, cols, rr = [], [], []
        for blk, sign in ((np.repeat(jt.b, 2), 1.0), (np.repeat(jt.a, 2), -1.0)):
            r = p - G[blk]
            rot = (r[:, 0] * vec[:, 1] - r[:, 1] * vec[:, 0]) / ell[blk]
            data += [sign * vec[:, 0], sign * vec[:, 1], sign * rot]
            cols += [3 * blk, 3 * blk + 1, 3 * blk + 2]
            rr += [rows] * 3
        mats.append(sp.csr_matrix((np.concatenate(data), (np.concatenate(rr),
                                                          np.concatenate(cols))),
                                  shape=(2 * K, 3 * assembly.n_blocks)))
    return mats[0], mats[1]


def loads(assembly: Assembly):
    """(live, dead) power vectors on q (scaled ω): P_live = live·q for a unit multiplier (the
    horizontal force −m g per block), P_dead = dead·q (the weight −m g vertical)."""
    g = float(assembly.meta.get("g", 9.81))
    n = assembly.n_blocks
    live, dead = np.zeros(3 * n), np.zeros(3 * n)
    live[0::3] = -assembly.mass * g
    dead[1::3] = -assembly.mass * g
    return live, dead


@dataclass(frozen=True)
class BlockLimitResult(SolveRecord):
    """The collapse multiplier and mechanism of a rigid-block assembly, with its static dual.

    multiplier      λ (horizontal acceleration / g at collapse)
    velocity        (n, 3) block velocities (u, w, ω) about the centroids [m/s, m/s, 1/s],
                    normalised so that the mass-weighted mean of −u over the free blocks is 1
    opening, slip   (K, 2) δ_n, δ_t at the two end points of each interface [m/s]
    normal, shear   (K, 2) contact forces N (compression >= 0) and T at the end points [N per
                    slab of thickness s]: the force of block a on block b is N n + T t
    state           (K,) 0 closed, 1 open (no slip), 2 sliding (``STATE_NAMES``)
    active          (K,) interfaces with a free block on at least one side
    moving          (n,) the failing set: blocks whose fastest vertex moves faster than
                    tol_motion (default 1 %) × the fastest vertex of the mechanism (optimal
                    mechanisms of the T-section move the rest of the wall at 0.1–1 %: the
                    body pushes it aside below the hinge; a simplex vertex shows the same)
    h               height of the failing part: top of the wall minus the lowest base of a
                    moving façade block (or of any moving block, if no façade block moves) [m]
    z_base          that lowest base [m]
    fit             the rotation fitted to the moving blocks (``fit_rotation``, a
                    ``mechanism.rigidfit.RigidFit``); rigid: the failing set moves as one body
                    (the fit's rms misfit below 1e-3 × the blocks' rms speed)
    friction        "associative" or "non-associative"; f the friction coefficient
    status, solver, primal_objective, dual_objective (the last LP's), iterations (summed over
                    the LPs), times [s], sizes: the solve's (``fe.solver.SolveRecord``)
    history         non-associative loop: λ per iteration (associative start first)
    actions         a real wall's ties, floors and crushing (``_RealTerms.record``; empty for
                    the paper's wall): per tie its block, force [N] and elongation rate
                    [m/s], per floor its block, load and reaction of a restraint [N], per
                    interface the crushing dissipation rate [W]
    """

    multiplier: float
    velocity: np.ndarray
    opening: np.ndarray
    slip: np.ndarray
    normal: np.ndarray
    shear: np.ndarray
    state: np.ndarray
    active: np.ndarray
    moving: np.ndarray
    h: float
    z_base: float
    fit: RigidFit
    rigid: bool
    friction: str
    f: float
    history: tuple = ()
    converged: bool = True
    actions: dict = field(default_factory=dict)

    @property
    def n_open(self) -> int:
        return int(np.count_nonzero(self.state == _OPEN))

    @property
    def n_sliding(self) -> int:
        return int(np.count_nonzero(self.state == _SLIDING))

    def vertex_velocity(self, assembly: Assembly) -> np.ndarray:
        """Velocity (P, 2) of every outline vertex of ``assembly`` under this mechanism."""
        return vertex_velocity(assembly, self.velocity)

    def speed(self, assembly: Assembly) -> np.ndarray:
        """Per block, the speed of its fastest vertex [m/s]."""
        return block_speed(assembly, self.velocity)


def check_result(assembly: Assembly, result: BlockLimitResult):
    """ParameterError unless ``result`` is a BlockLimitResult of ``assembly``."""
    if not isinstance(assembly, Assembly) or not isinstance(result, BlockLimitResult):
        raise ParameterError("assembly, result are out of range: allowed a "
                             "homlimit.blocks.Assembly and its BlockLimitResult")
    if result.velocity.shape[0] != assembly.n_blocks:
        raise ParameterError(f"result has {result.velocity.shape[0]} blocks and assembly "
                             f"{assembly.n_blocks}: allowed the result of this assembly")


def _solve(prob: cp.Problem, options: SolverOptions, n_free: int):
    """``prob`` through the one solve chain (``fe.solver.solve_cvxpy``, program "blocks": the
    kinematic LP's settings and ladder, faer on one thread above ``fe.solver.FAER_ABOVE``
    unknowns); returns (the chain's ``Solved``, times: "build" cvxpy's compilation, "solve"
    the solves down the ladder with their unpacking)."""
    run = solve_cvxpy(prob, options, "blocks", n_free, conic=False)
    return run, {"build": run.times["compile"], "solve": run.times["solve"] + run.times["wrap"]}


def fit_rotation(assembly: Assembly, q: np.ndarray, sel: np.ndarray,
                 at_rest: np.ndarray | None = None) -> RigidFit:
    """The rotation ω about O that best fits the block velocities q (n, 3) = (u, w, ω) on the
    blocks ``sel``: u_i = −ω (z_Gi − z_O), w_i = ω (x_Gi − x_O), ω_i = ω, least squares in the
    blocks' kinetic-energy norm (m |Δv_G|² + I_G Δω²), unknowns (ω, ω x_O, ω z_O).

    Returns the FE path's record (``mechanism.rigidfit.RigidFit``) with blocks for nodes:
    block = ``sel``, fixed = ``at_rest`` (default: the blocks not in ``sel``), rms the misfit
    √(Σ m|Δv_G|² + I_G Δω²) / Σ m) [m/s], vmax the fastest vertex of ``sel``, n_iter 1.
    O = (NaN, NaN) when ``sel`` is empty or ω vanishes (a translation)."""
    sel = np.asarray(sel, bool)
    fixed = ~sel if at_rest is None else np.asarray(at_rest, bool)
    nan = (float("nan"), float("nan"))
    if not np.any(sel):
        return RigidFit(nan, 0.0, sel, fixed, float("nan"), 0.0, 0)
    G = assembly.centroid[sel]
    m = assembly.mass[sel]
    ell = np.sqrt(np.maximum(assembly.inertia[sel] / np.maximum(m, 1e-300), 0.0))  # gyration
    u, w, om = q[sel, 0], q[sel, 1], q[sel, 2]
    k = m.size
    # unknowns (ω, a = ω z_O, b = ω x_O): u = −ω z_G + a, w = ω x_G − b, ℓ ω_i = ℓ ω
    M = np.zeros((3 * k, 3))
    M[:k, 0], M[:k, 1] = -G[:, 1], 1.0
    M[k:2 * k, 0], M[k:2 * k, 2] = G[:, 0], -1.0
    M[2 * k:, 0] = ell
    rhs = np.r_[u, w, ell * om]
    wt = np.sqrt(np.r_[m, m, m])
    sol, *_ = np.linalg.lstsq(M * wt[:, None], rhs * wt, rcond=None)
    omega, a, b = sol
    rms = float(np.linalg.norm((M @ sol - rhs) * wt) / math.sqrt(m.sum()))
    vmax = float(block_speed(assembly, q)[sel].max())
    O = nan if abs(omega) < 1e-12 * max(np.abs(rhs).max(), 1e-300) else (  # noqa: E741
        float(b / omega), float(a / omega))
    return RigidFit(O, float(omega), sel, fixed, rms, vmax, 1)


def _full(x, free, n):
    """The scaled unknowns of all blocks (zero on the fixed ones)."""
    xs = np.zeros(3 * n)
    xs[free] = x
    return xs


def _finish(assembly, free, x, ell, Dn, Dt, N, T, lam, run, iters, times, friction, f,
            tol_motion, history=(), converged=True, sizes=None, actions=None
            ) -> BlockLimitResult:
    """The result record: block velocities from the scaled unknowns, relative velocities at
    the contact points, the joint states, the failing set and its height, the rigid fit."""
    n = assembly.n_blocks
    xs = np.zeros(3 * n)
    xs[free] = x
    q = xs.reshape(n, 3).copy()
    q[:, 2] /= ell
    dn = (Dn @ xs).reshape(-1, 2)
    dt = (Dt @ xs).reshape(-1, 2)
    speed = block_speed(assembly, q)
    thr = tol_motion * (float(speed.max()) if speed.size else 0.0)
    moving = (speed > thr) & ~assembly.fixed
    jt = assembly.interfaces
    active = ~(assembly.fixed[jt.a] & assembly.fixed[jt.b])
    state = np.where(np.abs(dt).max(axis=1) > thr, _SLIDING,
                     np.where(dn.max(axis=1) > thr, _OPEN, _CLOSED)).astype(np.int8)
    state[~active] = _CLOSED
    bb = assembly.bounds()
    fac = moving & np.isin(assembly.kind, (FACADE, TOOTHING))
    base_set = fac if np.any(fac) else moving
    z_top = float(assembly.meta.get("H", bb[:, 3].max()))
    z_base = float(bb[base_set, 1].min()) if np.any(base_set) else float("nan")
    fit = fit_rotation(assembly, q, moving, at_rest=~moving)
    e = assembly.mass * (q[:, 0] ** 2 + q[:, 1] ** 2) + assembly.inertia * q[:, 2] ** 2
    rms_speed = math.sqrt(e[moving].sum() / assembly.mass[moving].sum()) if fit.n_iter else 0.0
    return BlockLimitResult(
        multiplier=lam, velocity=q, opening=dn, slip=dt, normal=N, shear=T, state=state,
        active=active, moving=moving, h=z_top - z_base, z_base=z_base, fit=fit,
        rigid=bool(fit.rms < 1e-3 * rms_speed), friction=friction, f=f,
        **run.report() | {"iterations": iters}, times=times, sizes=sizes or {},
        history=tuple(history), converged=converged, actions=actions or {})


def solve_blocks(assembly: Assembly, f: float | None = None, friction: str = "associative",
                 options: SolverOptions = SolverOptions(), tol_motion: float = 1e-2,
                 max_iter: int = 50, relax: float = 0.5, tol: float = 1e-6
                 ) -> BlockLimitResult:
    """Collapse multiplier λ, mechanism and contact forces of ``assembly`` (module docstring).

    f: friction coefficient of every joint (default ``assembly.meta["f"]``); friction:
    "associative" (one LP, exact for the associative model: primal = dual) or
    "non-associative" (Gilbert, Casapulla & Ahmed 2006: at most ``max_iter`` LPs, relaxation
    ``relax`` of the normal forces, converged when λ changed by less than ``tol`` relative over
    the last three iterations and the last force field meets Coulomb with its own normal
    forces); tol_motion: a block moves if its fastest vertex exceeds tol_motion × the
    fastest vertex of the mechanism (also the threshold for open and sliding joints).
    """
    if not isinstance(assembly, Assembly):
        raise ParameterError(f"assembly = {type(assembly).__name__} is out of range: allowed a "
                             "homlimit.blocks.Assembly")
    if friction not in FRICTION_MODELS:
        raise ParameterError(f"friction = {friction!r} is out of range: allowed "
                             f"{FRICTION_MODELS}")
    if not isinstance(options, SolverOptions) or options.solver != "CLARABEL":
        raise ParameterError(f"options = {options!r} is out of range: allowed a "
                             "homlimit.fe.solver.SolverOptions with solver='CLARABEL'")
    if f is None:
        if "f" not in assembly.meta:
            raise ParameterError("f = None is out of range: give the friction coefficient "
                                 "(the assembly carries none), allowed 0 < f")
        f = assembly.meta["f"]
    f = check_range("f", f, 0.0, lo_open=True)
    tol_motion = check_range("tol_motion", tol_motion, 0.0, 1.0, lo_open=True, hi_open=True)
    max_iter = int(check_range("max_iter", max_iter, 1))
    relax = check_range("relax", relax, 0.0, 1.0, lo_open=True)
    tol = check_range("tol", tol, 0.0, lo_open=True)
    if assembly.n_free == 0:
        raise ParameterError("assembly has 0 free blocks: allowed at least one block that is "
                             "not fixed")

    t0 = time.perf_counter()
    ell = _scale(assembly)
    Dn, Dt = contact_operator(assembly)
    live, dead = loads(assembly)
    free_blk = ~assembly.fixed
    free = np.flatnonzero(np.repeat(free_blk, 3))
    jt = assembly.interfaces
    act_pts = np.repeat(free_blk[jt.a] | free_blk[jt.b], 2)
    rows = np.flatnonzero(act_pts)
    Dnf, Dtf = Dn[rows][:, free].tocsr(), Dt[rows][:, free].tocsr()
    kappa = float(-live[free].sum())                     # g × free mass
    if not kappa > 0:
        raise ParameterError("mass of the free blocks = 0 kg is out of range: the live load "
                             "must do work, allowed > 0 kg")
    c_obj = -dead[free] / kappa
    l_vec = live[free] / kappa
    t_asm = time.perf_counter() - t0

    x = cp.Variable(free.size)
    C = sp.vstack([Dnf - f * Dtf, Dnf + f * Dtf]).tocsr()
    real = real_of(assembly)
    if real is not None and friction != "associative":
        raise ParameterError(f"friction = {friction!r} with ties, floors, fc, cohesion or "
                             "tension is out of range: allowed 'associative' "
                             "(docs/real-walls.md)")
    if real is None:                                     # the paper's program, unchanged
        cone = C @ x >= 0
        norm = l_vec @ x == 1.0
        prob = cp.Problem(cp.Minimize(c_obj @ x), [norm, cone])
        extra = None
    else:
        extra = _RealTerms(assembly, real, x, free, ell, kappa, rows, C, c_obj, f, Dnf, Dtf)
        cone, norm = extra.cone, l_vec @ x == 1.0
        prob = cp.Problem(cp.Minimize(extra.objective), [norm, cone, *extra.constraints])
    run, times = _solve(prob, options, free.size)
    iters = run.iterations
    times["assembly"] = t_asm
    lam = float(prob.value)
    P = rows.size
    y = np.asarray(cone.dual_value, float).ravel()
    ym, yp = y[:P], y[P:]
    Np = np.zeros(2 * jt.count)
    Tp = np.zeros(2 * jt.count)
    Np[rows] = kappa * (ym + yp)
    Tp[rows] = kappa * f * (yp - ym)
    if extra is not None and extra.bond:      # the shifted domain's forces (_RealTerms)
        dN, dT = extra.bond_forces(kappa)
        Np[rows] += dN
        Tp[rows] += dT
    sizes = {"blocks": assembly.n_blocks, "free_blocks": int(free_blk.sum()),
             "interfaces": jt.count, "contact_points": int(P), "unknowns": int(free.size),
             "rows": int(C.shape[0]), "nnz": int(C.nnz),
             "factorisation": run.settings["direct_solve_method"], "attempts": run.attempts}
    xv = np.asarray(x.value, float)
    actions = {} if extra is None else extra.record(
        xv, kappa, f, *((D @ _full(xv, free, ell.size)).reshape(-1, 2) for D in (Dn, Dt)))
    history = [lam]
    converged = True
    if friction == "non-associative":
        xv, lam, Np, Tp, history, converged, run, iters2, t_na, viol = _non_associative(
            Dnf, Dtf, rows, c_obj, l_vec, kappa, f, Np, options, free.size, max_iter, relax,
            tol, history, jt.count)
        iters += iters2
        times["non_associative"] = t_na
        sizes["coulomb_violation"] = viol[-1]
        sizes["non_associative_iterations"] = len(viol)
    times["total"] = sum(v for k, v in times.items() if k != "total")
    return _finish(assembly, free, xv, ell, Dn, Dt, Np.reshape(-1, 2), Tp.reshape(-1, 2), lam,
                   run, iters, times, friction, f, tol_motion, history, converged, sizes,
                   actions)


class _RealTerms:
    """The terms a real wall adds to the kinematic program (``blocks.real``; docs/real-walls.md
    "Rigid blocks"), on the scaled unknowns x of the free blocks:

    - a floor load Q at (e, z) on block i: dead power −Q w_i(e, z), so the objective gains
      (Q/κ) w_i(e, z); a restraining floor: u_i(z) = 0 (u_i(z) = u_i − ω_i (z − z_Gi), the
      horizontal velocity of the block's points at height z), its multiplier the reaction;
    - a tie T_y at height z on block i: its dissipation T_y max(−u_i(z), 0) (it yields as the
      façade moves outwards, −x, and goes slack inwards), an elongation rate s >= 0,
      s >= −u_i(z), cost (T_y/κ) s; the multiplier of s + u_i(z) >= 0 is the tie force / κ;
    - f_c: the dissipation of the stresses 0 <= σ <= f_c, |τ| <= f σ on a contact, the support
      function of N_e >= (N_0 + N_1)²/(2C) (C = f_c d L) per end e, by conic duality:
      min Σ_e C (w_e − v_e) over (w_e, u_e, v_e) in the second-order cone, with the closing
      velocity ξ_e = −(w_e + v_e + √2 (u_0 + u_1)) added to the Coulomb rows
      (δ_n ∓ f δ_t + ξ >= 0). As f_c → ∞ the cost forces ξ → 0: the paper's rows. Its value
      is f_c d ∫ (f |δ_t| − δ_n(s))⁺ ds over the contact (``crushing_rate``);
    - cohesion C and tension T_h = min(T, C/f) (``blocks.real``): the domain shifted by the
      uniform tension, N_e = N'_e − t_e with t_e = T_h A/2 per end (A = d L), |T_e| <= f N'_e
      + r_e with r_e = (C − f T_h) A/2, and (with f_c) N' in the stress block of
      C' = (f_c + T_h) d L. Its support function adds t_e δ_n,e + r_e |δ_t,e| per end
      (an auxiliary σ_e >= ±δ_t,e, cost r_e σ_e) to the rows above, which keep their form."""

    def __init__(self, assembly, real, x, free, ell, kappa, rows, C, c_obj, f, Dnf, Dtf):
        n = assembly.n_blocks
        self.assembly, self.real = assembly, real
        col = np.full(3 * n, -1)
        col[free] = np.arange(free.size)
        self.col, self.ell = col, ell
        obj = c_obj @ x
        cons = []
        fl, ti = real.floors, real.ties
        self.floor_block = anchor_blocks(assembly, fl[:, 0])
        self.tie_block = anchor_blocks(assembly, ti[:, 0])
        on = self.floor_block >= 0
        if np.any(on):
            Wr = self._rows(self.floor_block[on], fl[on, 0], fl[on, 2], vertical=True,
                            n_free=free.size)
            obj = obj + (fl[on, 1] / kappa) @ (Wr @ x)
        held = on & (fl[:, 3] > 0)
        self.restraint = None
        if np.any(held):
            Ur = self._rows(self.floor_block[held], fl[held, 0], None, False, free.size)
            self.restraint = Ur @ x == 0
            cons.append(self.restraint)
        self.held = held
        on_t = self.tie_block >= 0
        self.tie_con, self.tie_s = None, None
        if np.any(on_t):
            Ut = self._rows(self.tie_block[on_t], ti[on_t, 0], None, False, free.size)
            s = cp.Variable(int(on_t.sum()), nonneg=True)
            self.tie_con = s + Ut @ x >= 0
            cons.append(self.tie_con)
            obj = obj + (ti[on_t, 1] / kappa) @ s
            self.tie_s = s
        self.on_t = on_t
        jt = assembly.interfaces
        P = rows.size
        k = rows // 2
        x_mid = 0.5 * (jt.p[k, 0, 0] + jt.p[k, 1, 0])
        area = real.depth(x_mid) * jt.length[k]                     # A = d L per point [m²]
        self.bond = real.bond
        self.t_h = real.tension_effective(f) if real.bond else 0.0
        if real.bond:                   # the uniform tension t_e and the cohesion's r_e [N]
            self.t_pt = self.t_h * area / 2.0
            r_pt = (real.cohesion - f * self.t_h) * area / 2.0
            sig = cp.Variable(P, nonneg=True)
            self.slip_m, self.slip_p = sig - Dtf @ x >= 0, sig + Dtf @ x >= 0
            cons += [self.slip_m, self.slip_p]
            obj = obj + (self.t_pt / kappa) @ (Dnf @ x) + (r_pt / kappa) @ sig
        if real.fc > 0:
            cap = (real.fc + self.t_h) * real.depth(x_mid) * jt.length[k]  # C' per point [N]
            w, u, v = cp.Variable(P), cp.Variable(P), cp.Variable(P)
            pair = sp.kron(sp.identity(P // 2), np.ones((2, 2))).tocsr()  # u_0 + u_1 per end
            xi = -(w + v + math.sqrt(2.0) * (pair @ u))
            self.cone = C @ x + cp.hstack([xi, xi]) >= 0
            cons.append(cp.SOC(w, cp.vstack([u, v]), axis=0))
            obj = obj + (cap / kappa) @ (w - v)
        else:
            self.cone = C @ x >= 0
        self.objective, self.constraints = obj, cons

    def bond_forces(self, kappa):
        """(ΔN, ΔT) per contact point [N] to add to the Coulomb rows' forces: the uniform
        tension −t_e and the cohesion's shear κ (z₊ − z₋) (the duals of σ ± δ_t >= 0)."""
        zm = np.asarray(self.slip_m.dual_value, float).ravel()
        zp = np.asarray(self.slip_p.dual_value, float).ravel()
        return -self.t_pt, kappa * (zp - zm)

    def _rows(self, blocks, z, xe, vertical: bool, n_free: int):
        """Sparse rows on x: u_i(z) = u_i − ω_i (z − z_Gi) or, ``vertical``, the vertical
        velocity w_i + ω_i (x_e − x_Gi) of the point (x_e, z) of block i."""
        G = self.assembly.centroid[blocks]
        ell = self.ell[blocks]
        r = np.arange(blocks.size)
        if vertical:
            c0, val0 = self.col[3 * blocks + 1], np.ones(blocks.size)
            val2 = (xe - G[:, 0]) / ell
        else:
            c0, val0 = self.col[3 * blocks], np.ones(blocks.size)
            val2 = -(z - G[:, 1]) / ell
        return sp.csr_matrix((np.r_[val0, val2], (np.r_[r, r], np.r_[c0, self.col[3 * blocks
                                                                              + 2]])),
                             shape=(blocks.size, n_free))

    def record(self, xv, kappa, f, opening, slip) -> dict:
        """The actions at collapse: ties (block, force F [N], elongation rate [m/s]), floors
        (block, load, restraint reaction R [N] on the block, +x), the crushing dissipation
        rate per interface [W] (0 for f_c infinite)."""
        real = self.real
        ti, fl = real.ties, real.floors
        n = self.assembly.n_blocks
        q = np.zeros(3 * n)
        q[self.col >= 0] = xv
        q = q.reshape(n, 3)
        q[:, 2] /= self.ell
        G = self.assembly.centroid

        def u_at(blocks, z):
            ok = blocks >= 0
            b = np.maximum(blocks, 0)
            return np.where(ok, q[b, 0] - q[b, 2] * (z - G[b, 1]), 0.0)

        F = np.zeros(len(ti))
        if self.tie_con is not None:
            F[self.on_t] = kappa * np.asarray(self.tie_con.dual_value, float).ravel()
        R = np.zeros(len(fl))
        if self.restraint is not None:
            R[self.held] = -kappa * np.asarray(self.restraint.dual_value, float).ravel()
        return {"tie_block": self.tie_block, "tie_force": F,
                "tie_rate": np.maximum(-u_at(self.tie_block, ti[:, 0]), 0.0),
                "floor_block": self.floor_block, "floor_load": fl[:, 1].copy(),
                "restraint_force": R, "fc": real.fc, "cohesion": real.cohesion,
                "tension_effective": self.t_h,
                "crushing_rate": crushing_rate(self.assembly, real, f, opening, slip),
                "bond_rate": bond_rate(self.assembly, real, f, opening, slip)}


def crushing_rate(assembly, real, f, opening, slip) -> np.ndarray:
    """Per interface, f_c d ∫₀ᴸ (f |δ_t| − δ_n(s))⁺ ds [W] for the end-point opening and slip
    rates (K, 2) (δ_n linear along the contact): the dissipation of 0 <= σ <= f_c, |τ| <= f σ
    (zero for f_c infinite or a contact that does not close)."""
    jt = assembly.interfaces
    if not real.fc:
        return np.zeros(jt.count)
    x_mid = 0.5 * (jt.p[:, 0, 0] + jt.p[:, 1, 0])
    return real.fc * real.depth(x_mid) * _positive_integral(f * np.abs(slip) - opening,
                                                             jt.length)


def bond_rate(assembly, real, f, opening, slip) -> np.ndarray:
    """Per interface, d [C L |δ_t| + T_h ∫₀ᴸ (δ_n(s) − f |δ_t|)⁺ ds] [W]: the dissipation of
    the cohesion and the tension (pointwise max of −σ δ_n + τ δ_t over σ >= −T_h, |τ| <= f σ
    + C, less the crushing part; zero without cohesion). δ_t is uniform along a contact."""
    jt = assembly.interfaces
    if not real.bond:
        return np.zeros(jt.count)
    th = real.tension_effective(f)
    x_mid = 0.5 * (jt.p[:, 0, 0] + jt.p[:, 1, 0])
    L = jt.length
    return real.depth(x_mid) * (real.cohesion * L * np.abs(slip).mean(axis=1)
                                + th * _positive_integral(opening - f * np.abs(slip), L))


def _positive_integral(a, L) -> np.ndarray:
    """∫₀ᴸ a(s)⁺ ds for a linear between its end values a (K, 2)."""
    lo, hi = a.min(axis=1), a.max(axis=1)
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(lo >= 0, 0.5 * L * (lo + hi),
                        np.where(hi <= 0, 0.0, 0.5 * L * hi ** 2 / (hi - lo)))


def _non_associative(Dnf, Dtf, rows, c_obj, l_vec, kappa, f, N0, options, n_free, max_iter,
                     relax, tol, history, K):
    """Gilbert, Casapulla & Ahmed (2006): LPs with |T| <= f N_prev, zero dilatancy.

    Converged when λ changed by less than ``tol`` (relative) over the last three iterations
    and the force field of the last one meets Coulomb with its own normal forces,
    max(|T| − f N)⁺ <= tol_c · max N with tol_c = max(tol, 1e-4)."""
    t0 = time.perf_counter()
    P = rows.size
    x = cp.Variable(n_free)
    tau = cp.Variable(P)
    cap = cp.Parameter(P, nonneg=True)
    c_open = Dnf @ x >= 0
    c_m = tau - Dtf @ x >= 0
    c_p = tau + Dtf @ x >= 0
    norm = l_vec @ x == 1.0
    prob = cp.Problem(cp.Minimize(c_obj @ x + cap @ tau), [norm, c_open, c_m, c_p])
    N_prev = N0[rows].copy()
    converged = False
    iters = 0
    violation = []
    Np, Tp = np.zeros(2 * K), np.zeros(2 * K)
    for _ in range(max_iter):
        cap.value = f * N_prev / kappa
        run, _ = _solve(prob, options, n_free)
        iters += run.iterations
        lam = float(prob.value)
        N = kappa * np.asarray(c_open.dual_value, float).ravel()
        T = kappa * (np.asarray(c_p.dual_value, float).ravel()
                     - np.asarray(c_m.dual_value, float).ravel())
        history.append(lam)
        viol = float(np.maximum(np.abs(T) - f * N, 0.0).max()) / max(float(N.max()), 1e-300)
        violation.append(viol)
        N_prev = relax * N + (1.0 - relax) * N_prev
        recent = np.asarray(history[-4:])
        if (len(history) >= 4 and np.ptp(recent) <= tol * abs(recent[-1])
                and viol <= max(tol, 1e-4)):
            converged = True
            break
    Np[rows], Tp[rows] = N, T
    return (np.asarray(x.value, float), lam, Np, Tp, history, converged, run, iters,
            time.perf_counter() - t0, violation)


def equilibrium_residual(assembly: Assembly, result: BlockLimitResult) -> np.ndarray:
    """Per free block, the out-of-balance (R_x, R_z [N], M [N m] about the centroid) of the
    contact forces, the weight and the live load λ m g towards −x; (n_free, 3). Zero (to the
    solver tolerance) when the contact forces are the static dual of the mechanism."""
    jt = assembly.interfaces
    g = float(assembly.meta.get("g", 9.81))
    n = assembly.n_blocks
    F = (result.normal[..., None] * jt.n[:, None, :]
         + result.shear[..., None] * jt.t[:, None, :])           # (K, 2, 2) force on b
    R = np.zeros((n, 3))
    for blk, sign in ((jt.b, 1.0), (jt.a, -1.0)):
        for e in (0, 1):
            r = jt.p[:, e] - assembly.centroid[blk]
            Fe = sign * F[:, e]
            np.add.at(R, blk, np.c_[Fe, r[:, 0] * Fe[:, 1] - r[:, 1] * Fe[:, 0]])
    R[:, 0] -= result.multiplier * assembly.mass * g
    R[:, 1] -= assembly.mass * g
    act = result.actions
    if act:                 # a real wall: floor loads, tie forces, restraint reactions
        real = assembly.meta["real"]
        G = assembly.centroid
        for blk, z, x, Fx, Fz in (
                (act["floor_block"], real.floors[:, 0], real.floors[:, 2], act[
                    "restraint_force"], -act["floor_load"]),
                (act["tie_block"], real.ties[:, 0], np.zeros(len(real.ties)), act["tie_force"],
                 np.zeros(len(real.ties)))):
            ok = blk >= 0
            b = blk[ok]
            mom = (x[ok] - G[b, 0]) * Fz[ok] - (z[ok] - G[b, 1]) * Fx[ok]
            np.add.at(R, b, np.c_[Fx[ok], Fz[ok], mom])
    return R[~assembly.fixed]
