"""Known-answer problems on gmsh meshes, each with its ``adapt`` remesher and its exact value.

    name          exact λ (reference)                                   singular points (fans)
    prandtl       2 + π (Prandtl 1920)                                  footing edge (1, 0)
    vertical_cut  3.7752 … 3.7776 (Kammoun, Pastor, Smaoui & Pastor     toe (0, 0), crest (0, H)
                  2010: best lower and upper bounds)
    tsection      hinge + fan of the homogenised façade, exact in       outer toe, top corners
                  closed form (``closed_form.fan.optimise_fan``):
                  0.15216 for B1 (ρ = 12, a = 0.3 m)
    free_block    b/h (rigid-block statics), one rigid block on a       none
                  frictional bed joint

Each factory returns a ``Known``: the problem (its first mesh), the ``remesh(size_map)`` the
adaptive loop calls, and the exact value or bracket.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable
from dataclasses import dataclass

from ..closed_form.fan import optimise_fan
from ..params import Case
from . import geometry, problems
from .adapt import fan_rays
from .mesh import to_skfem

__all__ = ["Known", "KNOWN", "known_prandtl", "known_vertical_cut", "known_tsection",
           "known_free_block"]


@dataclass(frozen=True)
class Known:
    """A problem with an exactly known multiplier (or a published bracket ``exact``)."""

    name: str
    problem: problems.Problem
    remesh: Callable
    exact: tuple[float, float]          # (lo, hi); lo == hi where the value is exact
    source: str
    extra: dict = dataclasses.field(default_factory=dict)


def _polygon_remesher(regions, boundaries, size, rays, refine_points=()):
    def remesh(size_map, last=None):
        return to_skfem(geometry.polygon_mesh(regions, boundaries, size=size,
                                              embed_lines=rays, refine_points=refine_points,
                                              size_map=size_map))
    return remesh


def known_prandtl(size: float = 0.5, n_fan: int = 12, width: float = 4.5,
                  depth: float = 3.0) -> Known:
    """``problems.prandtl`` (Tresca, half-domain) on gmsh with a fan of rays at (1, 0)."""
    W, D = width, depth
    regions = {"soil": [(0, -D), (W, -D), (W, 0), (0, 0)]}
    lines = {"footing": [((0, 0), (1, 0))], "symmetry": [((0, -D), (0, 0))],
             "bottom": [((0, -D), (W, -D))], "far": [((W, -D), (W, 0))]}
    remesh = _polygon_remesher(regions, lines, size, fan_rays((1.0, 0.0), -180, 0, n_fan, 1.0),
                               [(1.0, 0.0, size / 8, 0.5)])
    pr = dataclasses.replace(problems.prandtl(width=W, depth=D), mesh=remesh(None, None))
    return Known("prandtl", pr, remesh, (problems.PRANDTL, problems.PRANDTL),
                 "Prandtl 1920: q_u/k = 2 + π")


def known_vertical_cut(size: float = 0.25, n_fan: int = 8) -> Known:
    """``problems.vertical_cut`` (H = 1) on gmsh with fans at the toe and the crest."""
    regions = {"soil": [(-1.5, -1), (2.5, -1), (2.5, 1), (0, 1), (0, 0), (-1.5, 0)]}
    lines = {"bottom": [((-1.5, -1), (2.5, -1))],
             "sides": [((-1.5, -1), (-1.5, 0)), ((2.5, -1), (2.5, 1))]}
    rays = fan_rays((0.0, 0.0), -180, 90, n_fan, 0.5) + fan_rays((0.0, 1.0), -90, 0, n_fan, 0.5)
    remesh = _polygon_remesher(regions, lines, size, rays,
                               [(0.0, 0.0, size / 8, 0.3), (0.0, 1.0, size / 8, 0.3)])
    pr = dataclasses.replace(problems.vertical_cut(), mesh=remesh(None, None))
    return Known("vertical_cut", pr, remesh,
                 (problems.VERTICAL_CUT_LB, problems.VERTICAL_CUT_UB),
                 "Kammoun, Pastor, Smaoui & Pastor 2010: 3.7752 <= γH/k <= 3.7776")


def known_tsection(case: Case = Case(), size: float = 0.5, n_b: int = 4, n_fan: int = 6) -> Known:
    """The T-section with the homogenised façade (eq. 15 everywhere), on gmsh, fans at the
    outer toe and the façade's top corners; exact: the hinge + fan optimum in closed form
    (``closed_form.fan``), whose edges T1 = min(f, c/a), T2 = max(f, c/a)."""
    w = case.wall
    fan = optimise_fan(case)
    rays = (fan_rays((0.0, 0.0), 0, 90, n_fan, w.b) + fan_rays((0.0, w.H), -90, 0, n_fan, w.b)
            + fan_rays((w.b, w.H), -180, 0, n_fan, w.b))

    def remesh(size_map, last=None):
        return to_skfem(geometry.tsection(w.H, w.b, w.L, size=size,
                                          size_junction=min(size, w.b / n_b), embed_lines=rays,
                                          size_map=size_map))
    pr = dataclasses.replace(problems.t_section(case, facade="homogenised", h=size, n_b=n_b),
                             mesh=remesh(None, None))
    return Known("tsection", pr, remesh, (fan.lam, fan.lam),
                 f"hinge + fan in closed form (closed_form.fan), case {case.name}",
                 extra={"z0": fan.z0, "T1": fan.T1, "T2": fan.T2, "case": case})


def known_free_block(b: float = 0.5, h: float = 3.0, f: float = 0.6, size: float = 0.25
                     ) -> Known:
    """``problems.free_block`` (one rigid block on a frictional bed joint) on gmsh: λ = b/h."""
    regions = {"facade": [(0, 0), (b, 0), (b, h), (0, h)]}
    lines = {"base": [((0, 0), (b, 0))]}
    remesh = _polygon_remesher(regions, lines, min(size, b / 2), [])
    pr = problems.free_block(b=b, h=h, f=f)
    pr = dataclasses.replace(pr, mesh=remesh(None, None))
    return Known("free_block", pr, remesh, (pr.reference, pr.reference),
                 "rigid-block statics: λ = b/h (b/h < f)")


KNOWN = {"prandtl": known_prandtl, "vertical_cut": known_vertical_cut,
         "tsection": known_tsection, "free_block": known_free_block}
