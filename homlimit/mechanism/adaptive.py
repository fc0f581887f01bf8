"""The adaptive bracket of the T-section, with meshes that follow the last mechanism.

``fe.adapt.adapt`` refines where the bound gap is. On the T-section that alone converges
slowly on the static side: the block rotating about its hinge (0, z0) on the façade's outer
face bears on the fixed part at that point, so the exact stress field concentrates there (a
centred fan of compression struts, σ ~ 1/r), and the fan's two edge rays are lines of stress
discontinuity. After every cycle the remesher reads the hinge and the fan's edges off the
kinematic field (``rigidfit.measure_mechanism``, ``crack.fan_edges``) and gives gmsh
- a fan of rays at the hinge and a geometric grading towards it (``hinge_refinement``);
- the two edge rays (block side T1, fixed side T2) up to the top, as embedded lines;
- fans at the fixed singular corners (outer toe, the façade's top corners).
Nothing here assumes the answer: a mechanism without a hinge on the outer face (a
distributed one) gets the corner fans and the gap-driven sizes only.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from ..fe import adapt as fe_adapt
from ..fe import geometry
from ..fe.mesh import to_skfem
from ..params import Case
from .analysis import densities
from .crack import fan_edges
from .fe_impulse import p2_nodes
from .rigidfit import measure_mechanism

__all__ = ["HingeFan", "hinge_fan", "hinge_refinement", "tsection_remesher"]


@dataclass(frozen=True)
class HingeFan:
    """The hinge (x, z) and fan edges (T1, T2, mid-line; None where not measured) of a
    kinematic field, as read for remeshing."""

    x: float
    z: float
    T1: float | None
    T2: float | None
    T_mid: float | None


def hinge_fan(case: Case, kinematic) -> HingeFan | None:
    """Hinge and fan edges of a T-section's kinematic solution, or None if its mechanism has
    no rigid block about a point of the façade's outer face."""
    w = case.wall
    X, V, el, rho = p2_nodes(kinematic, densities(case))
    mm = measure_mechanism(X, V, el, rho)
    if mm.kind == "distributed":
        return None
    x0, z0 = (float(v) for v in mm.fit.O)
    if not (abs(x0) <= 0.25 * w.b and kinematic.mesh.p[1].min() <= z0 < w.H):
        return None
    ed = fan_edges(X, el, mm, w.b, z_top=w.H)
    if ed is None:
        return HingeFan(0.0, z0, None, None, None)
    return HingeFan(0.0, z0, float(ed.T1), float(ed.T2), float(ed.T_mid))


def hinge_refinement(point, h_min: float, size: float, ratio: float = 5.0) -> list[tuple]:
    """Nested ``refine_points`` (x, z, size, radius) grading geometrically from ``h_min`` at
    ``point`` to ``size``: element size ≈ r/ratio·… at distance r (σ ~ 1/r needs it)."""
    out, h = [], h_min
    while h < size:
        out.append((point[0], point[1], h, ratio * h))
        h *= ratio
    return out


def tsection_remesher(case: Case, *, size: float, z0: float = 0.0, n_b: int = 4,
                      n_fan: int = 16, h_hinge: float = 0.002, corners: bool = True):
    """``remesh(size_map, last)`` for ``fe.adapt.adapt`` on the T-section (gmsh, element size
    ``size``, b/n_b at the junction): corner fans always; after a cycle, the last mechanism's
    hinge fan, grading to ``h_hinge`` [m] and edge rays (module docstring)."""
    w = case.wall
    fans = [(0.0, z0, 0, 90), (0.0, w.H, -90, 0), (w.b, w.H, -180, 0)] if corners else []
    base = [r for x, z, a0, a1 in fans for r in fe_adapt.fan_rays((x, z), a0, a1, 6, w.b)]

    def remesh(size_map, last=None):
        rays, points = list(base), []
        hf = hinge_fan(case, last.kinematic) if last is not None else None
        if hf is not None and hf.z > z0 + 1e-9:
            rays += fe_adapt.fan_rays((hf.x, hf.z), -90, 90, n_fan, w.b)
            points += hinge_refinement((hf.x, hf.z), h_hinge, size)
            for T in (hf.T1, hf.T2):
                if T is not None and math.isfinite(T) and T > 0:
                    rays.append(((hf.x, hf.z), (hf.x + T * (w.H - hf.z), w.H)))
        return to_skfem(geometry.tsection(w.H, w.b, w.L, size=size, z0=z0,
                                          size_junction=min(size, w.b / n_b),
                                          embed_lines=rays, refine_points=points,
                                          size_map=size_map))
    return remesh
