"""Adaptive meshing driven by the bound gap: remesh where λ⁺ − λ⁻ lives, until the bounds meet.

One cycle: both bounds on one mesh (``bracket.bracket``), the per-triangle share of the gap
(``bracket.gap_contributions``, Ciria, Peraire & Bonet 2008) marked by Dörfler's rule (the
fewest triangles that carry ``theta`` of the gap), the marked triangles' size halved (never
below ``min_size``), the others kept, and that piecewise-constant size map handed to gmsh as a
background field for the next mesh (``geometry.polygon_mesh(size_map=...)``). The loop stops
when the relative gap (λ⁺ − λ⁻)/mean is at most ``target_gap``, after ``max_cycles`` meshes,
or before a remesh whose estimated triangle count exceeds ``max_triangles``.

After the bracket, ``refine_mechanism`` may split the best kinematic mesh where its mechanism
lives (nested: ``mesh.refined_nested``), the kinematic bound alone, until the figures it
measures (e.g. the crack's edges) move by less than a tolerance from one mesh to the next.

Singular points (corners where the exact static field has a centred fan of discontinuities,
the ``prandtl_fan`` lesson) are given to the mesher once, as fans of embedded rays
(``fan_rays``): an adaptive size field alone offers a static field too few edge directions there.
"""

from __future__ import annotations

import dataclasses
import math
import time
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from ..errors import ParameterError, check_range
from .bracket import Bracket, bracket
from .kinematic import solve_kinematic
from .mesh import element_areas, refined_nested
from .solver import SolverOptions

__all__ = ["AdaptOptions", "Cycle", "AdaptResult", "adapt", "refine_sizes", "fan_rays",
           "estimate_triangles", "refine_mechanism", "settled", "resume_rung"]

# triangles per unit of Σ area/size²: near-equilateral triangles of side h have area √3/4 h²
TRIANGLES_PER_AREA = 4.0 / math.sqrt(3.0)


@dataclass(frozen=True)
class AdaptOptions:
    """Settings of the adaptive loop ([adapt] in a case file).

    target_gap     stop when (λ⁺ − λ⁻)/mean <= target_gap (relative, e.g. 0.01 = 1 %)
    max_cycles     at most this many meshes (each one bracket)
    min_size       no element is asked to be smaller than this [m]
    theta          Dörfler fraction: refine the fewest triangles carrying this share of the gap
    max_triangles  refuse a remesh whose estimated size exceeds this (the run's budget)
    """

    target_gap: float = 0.01
    max_cycles: int = 6
    min_size: float = 0.01
    theta: float = 0.5
    max_triangles: int = 60_000

    def __post_init__(self):
        check_range("adapt.target_gap", self.target_gap, 0.0, 1.0, lo_open=True)
        check_range("adapt.max_cycles", self.max_cycles, 1, 50)
        if int(self.max_cycles) != self.max_cycles:
            raise ParameterError(f"adapt.max_cycles = {self.max_cycles!r} is not an integer")
        check_range("adapt.min_size", self.min_size, 0.0, lo_open=True, unit="m")
        check_range("adapt.theta", self.theta, 0.0, 1.0, lo_open=True)
        check_range("mesh.max_triangles", self.max_triangles, 1)


@dataclass(frozen=True)
class Cycle:
    """One mesh of the loop: its size, both bounds on it, the best bounds of all meshes so far
    (``best_lower`` = max λ⁻, ``best_upper`` = min λ⁺: each mesh's bounds are rigorous, so the
    tightest pair brackets λ), the best pair's relative gap and the seconds spent. ``kind``:
    "bracket" (both bounds solved) or "mechanism" (``refine_mechanism``: λ⁺ only, ``lower``
    NaN)."""

    cycle: int
    triangles: int
    lower: float
    upper: float
    best_lower: float
    best_upper: float
    rel_gap: float
    seconds: float
    mesh_seconds: float
    conformed: float | None = None    # λ⁺ of this cycle's ``improve_upper`` search (if any)
    measures: dict = field(default_factory=dict)    # ``adapt``'s ``measure`` of the best λ⁺
    kind: str = "bracket"

    def as_dict(self) -> dict:
        """The cycle's figures, its ``measures`` as columns of their own."""
        d = dataclasses.asdict(self)
        return d | d.pop("measures")


@dataclass
class AdaptResult:
    """The best bracket over all meshes, every cycle's figures and why the loop stopped.

    bracket: λ⁻ of the best static mesh and λ⁺ of the best kinematic mesh (with their
    solutions; ``element_gap`` only when both come from one mesh); problem: the problem on
    the best kinematic mesh (its mechanism is the one reported);
    stop: "target" (gap reached), "cycles" (max_cycles meshes), "budget" (the next mesh would
    exceed max_triangles) or "min_size" (nothing left to refine); mechanism_stop: why
    ``refine_mechanism`` stopped ("" if it did not run): "settled" (the measured figures moved
    by at most its tolerance over the last mesh), "cycles", "budget" or "unmarked" (nothing to
    refine, e.g. no crack).
    """

    bracket: Bracket
    problem: object
    cycles: list[Cycle] = field(default_factory=list)
    stop: str = ""
    mechanism_stop: str = ""

    @property
    def converged(self) -> bool:
        return self.stop == "target"

    def as_dict(self) -> dict:
        return {"stop": self.stop, "converged": self.converged,
                "mechanism_stop": self.mechanism_stop,
                "cycles": [c.as_dict() for c in self.cycles]}


def element_sizes(mesh) -> np.ndarray:
    """Size of every triangle [m]: the side of the equilateral triangle of the same area."""
    return np.sqrt(4.0 * element_areas(mesh) / math.sqrt(3.0))


def refine_sizes(mesh, indicator: np.ndarray, theta: float, min_size: float) -> np.ndarray:
    """New size per triangle: halved on the fewest triangles that carry ``theta`` of the
    (non-negative part of the) indicator (Dörfler marking), kept elsewhere, never below
    ``min_size``. Returns the sizes (nt,) [m]."""
    eta = np.maximum(np.asarray(indicator, float), 0.0)
    h = element_sizes(mesh)
    if eta.shape != h.shape:
        raise ParameterError(f"indicator has shape {eta.shape}: expected ({h.size},)")
    new = h.copy()
    total = eta.sum()
    if total > 0:
        order = np.argsort(eta)[::-1]
        n = int(np.searchsorted(np.cumsum(eta[order]), theta * total)) + 1
        new[order[:n]] *= 0.5
    return np.maximum(new, np.minimum(min_size, h))


def estimate_triangles(mesh, sizes: np.ndarray) -> int:
    """Triangles gmsh will make for a size map: Σ area/(√3/4 size²)."""
    return int(math.ceil(TRIANGLES_PER_AREA * np.sum(element_areas(mesh) / sizes ** 2)))


def fan_rays(point, angle_from: float, angle_to: float, n: int, length: float
             ) -> list[tuple]:
    """``n`` straight segments of ``length`` from ``point`` at equal angles strictly between
    ``angle_from`` and ``angle_to`` [deg, counter-clockwise from +x]: the edge directions a
    static field needs at a singular point."""
    x0, z0 = point
    a = np.radians(np.linspace(angle_from, angle_to, n + 2)[1:-1])
    return [((x0, z0), (x0 + length * math.cos(t), z0 + length * math.sin(t))) for t in a]


def adapt(problem, remesh: Callable[[tuple | None, Bracket | None], object],
          options: AdaptOptions = AdaptOptions(),
          solver: SolverOptions = SolverOptions(),
          progress: Callable[[Cycle], None] | None = None,
          first_mesh=None, on_mesh: Callable[[object], object] | None = None,
          improve_upper: Callable | None = None,
          measure: Callable[[object], dict] | None = None) -> AdaptResult:
    """Bracket ``problem`` on a sequence of meshes refined where the gap is.

    remesh(size_map, last) returns a skfem mesh with the problem's region and boundary names;
    ``size_map`` is None for the first mesh, then (points, triangles, sizes) of the previous
    mesh, and ``last`` the previous cycle's ``Bracket`` (None at first), from which a remesher
    may read the mechanism (e.g. a fan of rays at its hinge). ``first_mesh``: start from this
    mesh instead of ``remesh(None, None)``. ``progress`` is
    called with every finished ``Cycle``. ``on_mesh(mesh)``: the problem on a new mesh
    (default: ``problem`` with its mesh replaced; ``problems.t_section_on_mesh`` places a
    T-section's ties and floors anew). ``improve_upper(bracket, problem)``: after each
    cycle's bracket, a search for a lower λ⁺ started from its mechanism (e.g.
    ``mechanism.conform.conform_hook``), returning (KinematicSolution, problem) or None; a
    lower λ⁺ it finds is a kinematic bound like any other (its mesh is another valid mesh).
    ``measure(kinematic)``: figures of the best kinematic solution so far, recorded in each
    cycle's ``measures`` (e.g. the mechanism's hinge and crack, so that a report can say how
    they moved over the last cycle); each solution is measured once.
    """
    if not isinstance(options, AdaptOptions):
        raise ParameterError(f"options = {options!r} is not an AdaptOptions")
    cycles: list[Cycle] = []
    t0 = time.perf_counter()
    mesh = remesh(None, None) if first_mesh is None else first_mesh
    mesh_s = time.perf_counter() - t0
    stop = "cycles"
    lo = up = None                    # (bracket, problem) of the best static / kinematic mesh
    measured: dict[int, tuple] = {}   # id(kinematic) → (kinematic, measure(kinematic))
    for k in range(int(options.max_cycles)):
        t0 = time.perf_counter()
        prob = (dataclasses.replace(problem, mesh=mesh) if on_mesh is None
                else on_mesh(mesh))
        br = bracket(prob, options=solver)
        if lo is None or br.lower > lo[0].lower:
            lo = (br, prob)
        if up is None or br.upper < up[0].upper:
            up = (br, prob)
        better = None if improve_upper is None else improve_upper(br, prob)
        if better is not None and better[0].multiplier < up[0].upper:
            kin, kprob = better
            up = (Bracket(name=br.name, lower=br.lower, upper=float(kin.multiplier),
                          static=br.static, kinematic=kin,
                          times={"kinematic": float(kin.times.get("total", math.nan)),
                                 "static": br.times.get("static", math.nan)}), kprob)
        best = _best(lo[0], up[0])
        seconds = time.perf_counter() - t0 + mesh_s        # the measuring not counted
        if measure is not None and id(best.kinematic) not in measured:
            measured[id(best.kinematic)] = (best.kinematic, dict(measure(best.kinematic)))
        cyc = Cycle(k, prob.n_triangles, br.lower, br.upper, best.lower, best.upper,
                    best.rel_gap, seconds, mesh_s,
                    None if better is None else float(better[0].multiplier),
                    measured[id(best.kinematic)][1] if measure is not None else {})
        cycles.append(cyc)
        if progress is not None:
            progress(cyc)
        if best.rel_gap <= options.target_gap:
            stop = "target"
            break
        if k + 1 == options.max_cycles:
            break
        sizes = refine_sizes(mesh, br.element_gap, options.theta, options.min_size)
        if np.array_equal(sizes, element_sizes(mesh)):
            stop = "min_size"
            break
        if estimate_triangles(mesh, sizes) > options.max_triangles:
            stop = "budget"
            break
        t0 = time.perf_counter()
        mesh = remesh((mesh.p, mesh.t, sizes), br)
        mesh_s = time.perf_counter() - t0
    return AdaptResult(best, up[1], cycles, stop)


def settled(before: dict, after: dict, keys, tol: float) -> bool:
    """Every figure ``keys`` of two measures moved by at most ``tol`` relative to its last
    value (False where either lacks one)."""
    for k in keys:
        a, b = before.get(k), after.get(k)
        if a is None or b is None or not (math.isfinite(a) and math.isfinite(b)):
            return False
        if abs(b - a) > tol * abs(a):
            return False
    return True


def resume_rung(kinematic, solver: SolverOptions) -> SolverOptions:
    """``solver`` for a problem refined from ``kinematic``'s: started at the tolerance of the
    ladder's rung that solved the parent (docs/kinematic.md: on bed-joint meshes the first two
    rungs stall, and a nested refinement stalls where its parent did), else ``solver``."""
    attempts = (getattr(kinematic, "sizes", None) or {}).get("attempts") or []
    rung = attempts[-1][0] if attempts else {}
    if solver.tol is not None or not isinstance(rung, dict) or "tol_gap_abs" not in rung:
        return solver
    return dataclasses.replace(solver, tol=float(rung["tol_gap_abs"]), iterative_refinement=True)


def refine_mechanism(result: AdaptResult, mark: Callable[[object], np.ndarray],
                     on_mesh: Callable[[object], object], measure: Callable[[object], dict],
                     keys=("T1", "T2", "T_mid"), tol: float = 0.01, max_cycles: int = 3,
                     max_triangles: int = 60_000, solver: SolverOptions = SolverOptions(),
                     progress: Callable[[Cycle], None] | None = None) -> AdaptResult:
    """Split the best kinematic mesh of ``result`` where its mechanism lives, λ⁺ only, until its
    figures settle.

    Each cycle: ``mark(kinematic)`` → triangle indices (e.g. the crack's band), split with their
    closure (``mesh.refined_nested``: the new P2 space contains the last, so λ⁺ cannot rise
    beyond the solver's tolerance), the problem carried there (``on_mesh``), the kinematic
    bound solved (``resume_rung``) and ``measure``d. Stops when every figure ``keys`` moved by
    at most ``tol`` (relative) over the last mesh ("settled"), after ``max_cycles`` meshes,
    before a mesh of more than ``max_triangles``, or when nothing is marked. The static bound
    is not solved again: the bracket keeps the best λ⁻. Returns ``result`` with the new cycles
    (``kind`` "mechanism"), the last mesh's λ⁺ and problem (its mechanism is the one reported;
    nested, its λ⁺ is at most the last one's up to the solver's tolerance) and
    ``mechanism_stop``."""
    check_range("tol", tol, 0.0, 1.0, lo_open=True)
    check_range("max_cycles", max_cycles, 1, 50)
    br, problem = result.bracket, result.problem
    kin = br.kinematic
    before = dict(measure(kin))
    cycles = list(result.cycles)
    if cycles and not cycles[-1].measures:
        cycles[-1] = dataclasses.replace(cycles[-1], measures=before)
    stop = "cycles"
    for _ in range(int(max_cycles)):
        marked = np.asarray(mark(kin), int)
        if marked.size == 0:
            stop = "unmarked"
            break
        t0 = time.perf_counter()
        mesh = refined_nested(problem.mesh, marked)
        if mesh.t.shape[1] > max_triangles:
            stop = "budget"
            break
        mesh_s = time.perf_counter() - t0
        problem = on_mesh(mesh)
        solver = resume_rung(kin, solver)     # once resumed, kept for the finer meshes
        new = solve_kinematic(problem, solver)
        seconds = time.perf_counter() - t0
        after = dict(measure(new))
        upper = float(new.multiplier)      # the last mesh's: its mechanism is the one reported
        br = Bracket(name=br.name, lower=br.lower, upper=upper, static=br.static, kinematic=new,
                     times={"kinematic": float(new.times.get("total", math.nan)),
                            "static": br.times.get("static", math.nan)})
        cyc = Cycle(len(cycles), problem.n_triangles, math.nan, float(new.multiplier),
                    br.lower, upper, br.rel_gap, seconds, mesh_s, None, after, "mechanism")
        cycles.append(cyc)
        if progress is not None:
            progress(cyc)
        done = settled(before, after, keys, tol)
        kin, before = new, after
        if done:
            stop = "settled"
            break
    return dataclasses.replace(result, bracket=br, problem=problem, cycles=cycles,
                               mechanism_stop=stop)


def _best(lo: Bracket, up: Bracket) -> Bracket:
    """The bracket of the best static and the best kinematic bound (one mesh or two)."""
    if lo is up:
        return lo
    return Bracket(name=up.name, lower=lo.lower, upper=up.upper, static=lo.static,
                   kinematic=up.kinematic, element_gap=None,
                   times={"kinematic": up.times["kinematic"], "static": lo.times["static"]})
