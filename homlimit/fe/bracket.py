"""Bracket a collapse multiplier between the static (lower) and kinematic (upper) bounds.

    λ⁻ (static, ``homlimit.fe.static``)  <=  λ  <=  λ⁺ (kinematic, ``homlimit.fe.kinematic``)

Both programs consume the same ``problems.Problem``. On one mesh, the gap splits exactly over
the elements: for the kinematic field u (continuous P2, u = 0 on supports, P_live(u) = 1) and the
static field σ (in equilibrium with λ⁻ times the live loads plus the dead loads, tractions
continuous, prescribed on free boundaries), virtual power gives
∫ σ : D(u) dΩ + Σ_joints ∫ (σ n)·u dΓ = λ⁻ + P_dead(u), so

    λ⁺ − λ⁻ = Σ_e [ D_e(u) − ∫_e σ : D(u) dΩ ] + Σ_joint edges [ D_j(u) − ∫_j (σ n)·u dΓ ],

every term non-negative (σ ∈ G and D_e is at least ∫ π(D(u)) ≥ ∫ σ : D(u)). The element terms
are the local error indicators of mesh adaptivity (Ciria, Peraire & Bonet 2008). σ : D(u) is
quadratic on a triangle and integrated exactly by the three-edge-midpoint rule.
"""

from __future__ import annotations

import dataclasses
import time
from dataclasses import dataclass, field

import numpy as np

from .. import _threads
from ..errors import ParameterError, check_range
from .kinematic import solve_kinematic
from .mesh import element_areas
from .solver import SolverOptions
from .static import StaticSolution, solve_static

__all__ = ["Bracket", "bracket", "gap_contributions", "prandtl_fan", "same_mesh"]


def same_mesh(a, b) -> bool:
    """Whether two skfem meshes are one: same triangles, same points."""
    return a is b or (a.t.shape == b.t.shape and np.array_equal(a.t, b.t)
                      and np.allclose(a.p, b.p))


def gap_contributions(static: StaticSolution, kinematic) -> np.ndarray:
    """Per-triangle share of λ⁺ − λ⁻ on a common mesh, shape (nt,) [same unit as λ].

    D_e(u) − ∫_e σ : D(u) with D(u) linear (vertex values ``kinematic.strain_rate``) and σ linear
    on the triangle: the product is quadratic, integrated exactly at the edge midpoints with
    weights area/3; σ quadratic (``static.degree`` 2): cubic, integrated exactly by a
    degree-4 rule. Joint (interface) dissipation is not included (see ``Bracket.joint_gap``);
    rigid elements (``strength.Rigid``: no stress, D(u) = 0) contribute 0.
    """
    m = static.mesh
    if kinematic.mesh is not None and (kinematic.mesh.t.shape != m.t.shape
                                       or not np.array_equal(kinematic.mesh.t, m.t)):
        raise ParameterError("gap_contributions needs both bounds on the same mesh; got "
                             f"{kinematic.mesh.t.shape[1]} and {m.t.shape[1]} triangles")
    area = element_areas(m)
    d = kinematic.strain_rate  # (nt, vertex, comp)
    if static.degree == 1:
        s = np.where(np.isnan(static.stress), 0.0, static.stress)  # rigid: no stress, D = 0
        mids = ((0, 1), (1, 2), (2, 0))
        work = sum(np.einsum("ec,ec->e", 0.5 * (s[:, i] + s[:, j]), 0.5 * (d[:, i] + d[:, j]))
                   for i, j in mids) * area / 3.0
    else:  # σ quadratic × D linear: cubic, Strang–Fix's 6-point rule is exact to degree 4
        lam, w = _TRI_RULE
        work = np.einsum("q,qec,qec->e", w, bernstein2(static.control, lam),
                         np.einsum("qi,eic->qec", lam, d)) * area
    return kinematic.dissipation - work


def bernstein2(control: np.ndarray, lam: np.ndarray) -> np.ndarray:
    """A quadratic in Bernstein form (control (nt, 6, m): vertices 0–2, edges 01, 12, 20) at
    barycentric points lam (q, 3): (q, nt, m)."""
    l0, l1, l2 = lam.T
    B = np.stack([l0 * l0, l1 * l1, l2 * l2, 2 * l0 * l1, 2 * l1 * l2, 2 * l2 * l0], axis=1)
    return np.einsum("qk,ekm->qem", B, control)


def _strang_fix_6():
    """Barycentric points (6, 3) and weights (sum 1) of the 6-point degree-4 triangle rule."""
    a, b = 0.816847572980459, 0.091576213509771
    c, d = 0.108103018168070, 0.445948490915965
    wa, wc = 0.109951743655322, 0.223381589678011
    pts = [(a, b, b), (b, a, b), (b, b, a), (c, d, d), (d, c, d), (d, d, c)]
    return np.array(pts), np.array([wa] * 3 + [wc] * 3)


_TRI_RULE = _strang_fix_6()


@dataclass
class Bracket:
    """Lower and upper bounds of one problem's collapse multiplier.

    lower, upper : λ⁻ (static) and λ⁺ (kinematic); mean = (λ⁻ + λ⁺)/2;
    rel_gap = (λ⁺ − λ⁻)/mean (the half-width of the bracket around the mean is rel_gap/2);
    element_gap : per-triangle share of λ⁺ − λ⁻ (None when the meshes differ);
    joint_gap : the rest of λ⁺ − λ⁻ (joints to the ground, solver tolerance), when available.
    """

    name: str
    lower: float
    upper: float
    static: StaticSolution
    kinematic: object
    element_gap: np.ndarray | None = None
    times: dict = field(default_factory=dict)

    @property
    def mean(self) -> float:
        return 0.5 * (self.lower + self.upper)

    @property
    def gap(self) -> float:
        return self.upper - self.lower

    @property
    def rel_gap(self) -> float:
        return self.gap / abs(self.mean) if self.mean else float("inf")

    @property
    def joint_gap(self) -> float | None:
        if self.element_gap is None:
            return None
        return self.gap - float(self.element_gap.sum())

    def as_dict(self) -> dict:
        return {"name": self.name, "lower": self.lower, "upper": self.upper, "mean": self.mean,
                "gap": self.gap, "rel_gap": self.rel_gap,
                "triangles_static": int(self.static.mesh.t.shape[1]),
                "triangles_kinematic": int(self.kinematic.mesh.t.shape[1])
                if getattr(self.kinematic, "mesh", None) is not None else None,
                "times": dict(self.times)}


def bracket(problem, *, static_mesh=None, kinematic_mesh=None,
            options: SolverOptions = SolverOptions()) -> Bracket:
    """Run both bounds on ``problem`` (on its mesh, or on meshes chosen for each).

    static_mesh, kinematic_mesh : optional skfem meshes with the same region and boundary
        names, replacing ``problem.mesh`` for one bound (per-element gaps need one mesh).
    options : the ``solver.SolverOptions`` of both bounds.

    The two conic programs are independent: they are solved at once, in two threads (Clarabel
    releases the GIL; measured on the demo's first B1 mesh, 3278 triangles: 8.4 s one after
    the other, 5.9 s at once, the same multipliers bit for bit; ``benchmarks/bench_bracket.py
    concurrent``), or one after the other on a Dask worker or on one core
    (``_threads.map_here``). ``times``: each bound's own wall seconds.
    """
    pk = problem if kinematic_mesh is None else dataclasses.replace(problem, mesh=kinematic_mesh)
    ps = problem if static_mesh is None else dataclasses.replace(problem, mesh=static_mesh)
    (sta, t_sta), (kin, t_kin) = _threads.map_here(
        lambda job: _timed(*job), [(solve_static, ps, options), (solve_kinematic, pk, options)])
    times = {"kinematic": t_kin, "static": t_sta}
    eg = gap_contributions(sta, kin) if same_mesh(ps.mesh, pk.mesh) else None
    return Bracket(name=problem.name, lower=sta.multiplier, upper=kin.multiplier, static=sta,
                   kinematic=kin, element_gap=eg, times=times)


def _timed(solve, problem, options):
    """(solve(problem, options), its wall seconds)."""
    t0 = time.perf_counter()
    return solve(problem, options), time.perf_counter() - t0


def prandtl_fan(size: float = 0.3, h_min: float = 0.03, radius: float = 0.5, n_fan: int = 12,
                width: float = 4.5, depth: float = 3.0, footing: float = 0.0):
    """``problems.prandtl`` on an unstructured gmsh mesh with a fan of rays at the footing edge.

    A lower bound needs stress discontinuities in many directions at the singular point (the
    exact field has a centred fan there); the crossed structured mesh offers four and stalls at
    2√5 ≈ 4.472. ``n_fan`` straight rays of length 1 leave (1, 0) at equal angles into the
    soil; the mesh is refined to ``h_min`` within ``radius`` of the edge, ``size`` elsewhere.
    ``footing`` > 0 [m]: the load q = λ k acts on the top of a rigid footing (``Rigid``) of that
    height, bonded to the soil (a rough footing; on weightless Tresca soil still 2 + π).
    """
    from . import geometry, problems, strength
    from . import mesh as hmesh

    footing = check_range("footing", footing, 0.0, unit="m")
    rays = [((1.0, 0.0), (1.0 + np.cos(a), -np.sin(a)))
            for a in np.linspace(0.0, np.pi, n_fan + 2)[1:-1]]
    W, D, F = width, depth, footing
    regions = {"soil": [(0, -D), (W, -D), (W, 0), (0, 0)]}
    lines = {"footing": [((0, F), (1, F))], "symmetry": [((0, -D), (0, F))],
             "bottom": [((0, -D), (W, -D))], "far": [((W, -D), (W, 0))]}
    if F > 0:
        regions["block"] = [(0, 0), (1, 0), (1, F), (0, F)]
    mm = geometry.polygon_mesh(regions, lines, size=size,
                               refine_points=[(1.0, 0.0, h_min, radius)], embed_lines=rays)
    pr = problems.prandtl(width=width, depth=depth)
    domains = dict(pr.domains)
    if F > 0:
        domains["block"] = strength.Rigid()
    return dataclasses.replace(pr, mesh=hmesh.to_skfem(mm), domains=domains,
                               name="prandtl_fan" + ("_rigid_footing" if F > 0 else ""))
