"""``homlimit verify``: known-answer problems through the adaptive bracket, against their exact
values (issue 26, point 5).

    name          exact λ                                              singular points (fans)
    prandtl       2 + π (Prandtl 1920)                                 footing edge (1, 0)
    vertical_cut  3.7752 … 3.7776 (Kammoun, Pastor, Smaoui & Pastor    toe (0, 0), crest (0, 1)
                  2010: best published lower and upper bounds)
    tsection      the homogenised façade's hinge + fan, exact in       none: gap-driven sizes
                  closed form (``closed_form.fan.optimise_fan``),      on gmsh-strip (the
                  0.15216 for B1 (ρ = 12, a = 0.3 m); fan edges        strip's columns graded
                  T1 = min(f, c/a), T2 = max(f, c/a), √(T1 T2) = √(cf/a)  from 1 cm at the outer
                                                                       face); λ⁺ also searched
                                                                       over ray-conforming
                                                                       meshes (``conform``)
    free_block    b/h (rigid-block statics): one rigid block on a      none
                  frictional bed joint

Each runs ``fe.adapt.adapt`` from a gmsh mesh, the static bound with quadratic stresses
(``STRESS_DEGREE``; linear on the free block, whose rigid body and joint take no other); a
bracket "holds" when λ⁻ <= exact_hi and exact_lo <= λ⁺ up to the solver's relative tolerance
``TOL``. On the T-section the first cycle's mechanism with a hinge on the outer face also
starts a search over meshes conforming to a hinge + fan (``mechanism.conform.conform_hook``,
once): its λ⁺ are kinematic bounds like the others, and the crack is read off the best
one's field.
"""

from __future__ import annotations

import dataclasses
import math
import time
from collections.abc import Callable
from dataclasses import dataclass, field

from ..closed_form.fan import optimise_fan
from ..errors import ParameterError
from ..fe import geometry, problems
from ..fe.adapt import AdaptOptions, adapt, fan_rays
from ..fe.mesh import to_skfem
from ..fe.solver import SolverOptions
from ..mechanism.adaptive import hinge_fan, tsection_remesher
from ..mechanism.conform import conform_hook
from ..mechanism.crack import fan_ray
from ..params import Case
from .budget import estimate_triangles

__all__ = ["FIRST_TRIANGLES", "Known", "KNOWN", "TOL", "check_first_meshes", "check_name",
           "first_triangles", "known_problem", "verify_records"]

# the static bound's stresses: quadratic where the problem allows (docs/adaptive.md: on the
# T-section it reaches in 4 meshes what the linear field did not in 8)
STRESS_DEGREE = 2
TOL = 1e-6  # relative: both bounds are solved to Clarabel's 1e-9 (LP) or 1e-7 (SOC)


@dataclass(frozen=True)
class Known:
    """A problem with a known multiplier: exact = (lo, hi), lo == hi where exact."""

    name: str
    problem: problems.Problem
    remesh: Callable
    exact: tuple[float, float]
    source: str
    extra: dict = field(default_factory=dict)
    improve_upper: Callable | None = None     # ``fe.adapt.adapt``'s hook


def _polygon_remesher(regions, boundaries, size, rays, refine_points=()):
    def remesh(size_map, last=None):
        return to_skfem(geometry.polygon_mesh(regions, boundaries, size=size,
                                              embed_lines=rays, refine_points=refine_points,
                                              size_map=size_map))
    return remesh


def _prandtl(size: float = 0.5, n_fan: int = 24) -> Known:
    W, D = 4.5, 3.0
    regions = {"soil": [(0, -D), (W, -D), (W, 0), (0, 0)]}
    lines = {"footing": [((0, 0), (1, 0))], "symmetry": [((0, -D), (0, 0))],
             "bottom": [((0, -D), (W, -D))], "far": [((W, -D), (W, 0))]}
    remesh = _polygon_remesher(regions, lines, size, fan_rays((1.0, 0.0), -180, 0, n_fan, 1.0),
                               [(1.0, 0.0, size / 8, 0.5)])
    pr = dataclasses.replace(problems.prandtl(width=W, depth=D), mesh=remesh(None))
    return Known("prandtl", pr, remesh, (problems.PRANDTL,) * 2, "Prandtl 1920: 2 + π")


def _vertical_cut(size: float = 0.25, n_fan: int = 12) -> Known:
    regions = {"soil": [(-1.5, -1), (2.5, -1), (2.5, 1), (0, 1), (0, 0), (-1.5, 0)]}
    lines = {"bottom": [((-1.5, -1), (2.5, -1))],
             "sides": [((-1.5, -1), (-1.5, 0)), ((2.5, -1), (2.5, 1))]}
    rays = fan_rays((0.0, 0.0), -180, 90, n_fan, 0.5) + fan_rays((0.0, 1.0), -90, 0, n_fan, 0.5)
    remesh = _polygon_remesher(regions, lines, size, rays,
                               [(0.0, 0.0, size / 8, 0.3), (0.0, 1.0, size / 8, 0.3)])
    pr = dataclasses.replace(problems.vertical_cut(), mesh=remesh(None))
    return Known("vertical_cut", pr, remesh, (problems.VERTICAL_CUT_LB, problems.VERTICAL_CUT_UB),
                 "Kammoun, Pastor, Smaoui & Pastor 2010: 3.7752 <= γH/k <= 3.7776")


TSECTION_SIZE, TSECTION_OUTER = 0.25, 0.01   # the T-section's first mesh: size, outer column [m]


def _tsection(size: float = TSECTION_SIZE, case: Case = Case(),
              h_outer: float = TSECTION_OUTER) -> Known:
    fan = optimise_fan(case)
    remesh = tsection_remesher(case, size=size, strip=True, h_outer=h_outer)
    pr = dataclasses.replace(problems.t_section(case, facade="homogenised", h=size,
                                                mesher="gmsh-strip", h_outer=h_outer),
                             mesh=remesh(None))
    m = case.masonry
    conformed = []                    # the search (run once), for the record
    return Known("tsection", pr, remesh, (fan.lam, fan.lam),
                 f"hinge + fan in closed form (closed_form.fan), {case.name}, façade homogenised",
                 {"case": case, "z0": fan.z0, "T1": fan.T1, "T2": fan.T2,
                  "f": m.f, "c_over_a": m.c / m.a, "sqrt_cf_a": math.sqrt(m.c * m.f / m.a),
                  "conformed": conformed},
                 conform_hook(case, "homogenised", SolverOptions(stress_degree=1), conformed))


def _free_block(b: float = 0.5, h: float = 3.0, f: float = 0.6) -> Known:
    regions = {"facade": [(0, 0), (b, 0), (b, h), (0, h)]}
    remesh = _polygon_remesher(regions, {"base": [((0, 0), (b, 0))]}, b / 2, [])
    pr = problems.free_block(b=b, h=h, f=f)
    pr = dataclasses.replace(pr, mesh=remesh(None))
    return Known("free_block", pr, remesh, (pr.reference,) * 2, "rigid-block statics: b/h")


KNOWN = {"prandtl": _prandtl, "vertical_cut": _vertical_cut, "tsection": _tsection,
         "free_block": _free_block}


# triangles of each problem's first mesh, known before meshing (``check_first_meshes``): the
# polygons' fixed meshes as gmsh 4.15 makes them (tests/test_adapt.py checks them), the
# T-section's estimated as a run's (``budget.estimate_triangles``, gmsh-strip)
FIRST_TRIANGLES = {"prandtl": 1261, "vertical_cut": 1760, "free_block": 54}


def first_triangles(name: str) -> float:
    """The triangles of the first mesh of the known-answer problem ``name``, without meshing."""
    if name == "tsection":
        w = Case().wall
        return estimate_triangles(w.H, w.b, w.L, TSECTION_SIZE, "gmsh-strip",
                                  h_outer=TSECTION_OUTER)
    return FIRST_TRIANGLES[check_name(name)]


def check_first_meshes(names, max_triangles: int, option: str = "max_triangles"):
    """ParameterError when the first mesh of a problem of ``names`` (None: all) has more
    triangles than ``max_triangles`` allows: the adaptive loop solves its first mesh whatever
    the budget (``fe.adapt``), so such a budget is refused before any meshing."""
    need = {n: first_triangles(n) for n in (KNOWN if names is None else names)}
    worst = max(need, key=need.get, default=None)
    if worst is not None and need[worst] > max_triangles:
        n = math.ceil(need[worst])
        raise ParameterError(
            f"{option} = {max_triangles!r} is out of range: the first mesh of problem {worst} "
            f"has about {n:,} triangles (known before meshing): allowed {option} >= {n:,}, "
            f"or leave {worst} out")


def check_name(name: str, option: str = "problem") -> str:
    if name not in KNOWN:
        raise ParameterError(f"{option} = {name!r} is not a known-answer problem: allowed "
                             f"{', '.join(map(repr, KNOWN))}")
    return name


def known_problem(name: str) -> Known:
    """The known-answer problem ``name`` (a key of ``KNOWN``), meshed."""
    return KNOWN[check_name(name)]()


def verify_records(names=None, options: AdaptOptions = AdaptOptions(target_gap=0.005),
                   progress: Callable[[str, object], None] | None = None,
                   stress_degree: int = STRESS_DEGREE) -> list[dict]:
    """Run every known-answer problem (or ``names``) through ``fe.adapt.adapt``; one record
    per problem with both bounds, the exact value, whether the bracket holds, and for the
    T-section the hinge and fan edges beside z0, f, c/a and √(cf/a).

    stress_degree : of the static bound's stresses (``SolverOptions.stress_degree``); a
        problem with rigid bodies or joints (the free block) takes 1, and its record says so.
    """
    names = list(KNOWN) if names is None else list(names)
    for n in names:                       # every name checked before any work
        check_name(n)
    SolverOptions(stress_degree=stress_degree)
    check_first_meshes(names, options.max_triangles)
    out = []
    for n in names:
        t0 = time.perf_counter()
        k = known_problem(n)
        deg = stress_degree if stress_degree in k.problem.stress_degrees else 1
        res = adapt(k.problem, k.remesh, options, solver=SolverOptions(stress_degree=deg),
                    first_mesh=k.problem.mesh, improve_upper=k.improve_upper,
                    progress=None if progress is None else (lambda c, n=n: progress(n, c)))
        br, lo, hi = res.bracket, *k.exact
        rec = {"problem": n, "source": k.source, "exact_lo": lo, "exact_hi": hi,
               "lower": br.lower, "upper": br.upper, "rel_gap": br.rel_gap,
               "holds": br.lower <= hi * (1 + TOL) and br.upper >= lo * (1 - TOL),
               "lower_err": br.lower / lo - 1, "upper_err": br.upper / hi - 1,
               "triangles": res.cycles[-1].triangles, "cycles": len(res.cycles),
               "stop": res.stop, "seconds": time.perf_counter() - t0, "stress_degree": deg,
               "adapt": [c.as_dict() for c in res.cycles]}
        if n == "tsection":
            ex = k.extra
            hf = hinge_fan(ex["case"], br.kinematic)
            rec |= {"z0_exact": ex["z0"], "T1_exact": ex["T1"], "T2_exact": ex["T2"],
                    "T_mid_exact": float(fan_ray(0.5, ex["T1"], ex["T2"])),
                    "f": ex["f"], "c_over_a": ex["c_over_a"], "sqrt_cf_a": ex["sqrt_cf_a"],
                    "z0": None if hf is None else hf.z, "T1": None if hf is None else hf.T1,
                    "T2": None if hf is None else hf.T2,
                    "T_mid": None if hf is None else hf.T_mid,
                    "conform": ex["conformed"][0].as_dict() if ex["conformed"] else None}
        out.append(rec)
    return out
