"""The wall's geometry in the section plane x–z: the one place that knows the T-section's outline.

Frame (as ``homlimit.params``): x from the façade's outer face into the building, z up.
The façade strip 0 <= x <= b and the transversal wall b <= x <= b + L meet along the junction
x = b (paper, Figure 1); the analysed part runs from its base z0 to the top H (the failing part
of height h = H − z0 when z0 > 0, the whole wall when z0 = 0).

``TSection`` gives the region polygons ("facade", "wall"), the named boundary segments
("base", "outer", "top", "end", "junction"), the failing part above a base, the bounding box
and the membership tests that structured meshes use to name their cells and facets. Every
mesher (``fe.geometry.tsection``, ``fe.problems.t_section``), the block assembly
(``blocks.geometry.t_section_blocks``), the closed-form fan (``closed_form.fan``) and the
pictures read it; later features (openings) extend it here.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .errors import ParameterError, check_range
from .fields import check_fields, ranged, set_fields
from .params import Case

__all__ = ["TSection", "REGIONS", "BOUNDARIES", "lintel_boxes"]

REGIONS = ("facade", "wall")
BOUNDARIES = ("base", "outer", "top", "end", "junction")

Point = tuple[float, float]


@dataclass(frozen=True)
class TSection:
    """Façade strip [0, b] and transversal wall [b, b + L] over z0 <= z <= H [m].

    ``holes``: the transversal wall's openings, rectangles (x0, x1, z0, z1) strictly inside
    it (``params.WallOpening.box``); ``lintels``: the wall's rectangles over them that the FE
    makes rigid (``from_case``: one course above each, a half block beyond either side).
    Validated on construction (ParameterError naming the parameter): 0 < H, 0 < b, 0 < L,
    0 <= z0 < H, the holes inside the wall, holes and lintels not overlapping.
    """

    H: float = ranged(0.0, lo_open=True, unit="m")
    b: float = ranged(0.0, lo_open=True, unit="m")
    L: float = ranged(0.0, lo_open=True, unit="m")
    z0: float = 0.0
    holes: tuple = ()
    lintels: tuple = ()

    def __post_init__(self):
        check_fields(self)
        # the upper bound is a field's: checked here
        set_fields(self, z0=check_range("z0", self.z0, 0.0, self.H, hi_open=True, unit="m"),
                   holes=tuple(tuple(float(v) for v in box) for box in self.holes),
                   lintels=tuple(tuple(float(v) for v in box) for box in self.lintels))
        boxes = [("holes", k, box) for k, box in enumerate(self.holes)]
        boxes += [("lintels", k, box) for k, box in enumerate(self.lintels)]
        for i, (n1, k1, (a0, a1, c0, c1)) in enumerate(boxes):
            for n2, k2, (d0, d1, e0, e1) in boxes[i + 1:]:
                if a0 < d1 and d0 < a1 and c0 < e1 and e0 < c1:
                    raise ParameterError(f"{n1}[{k1}] = {(a0, a1, c0, c1)!r} m overlaps {n2}"
                                         f"[{k2}] = {(d0, d1, e0, e1)!r} m: allowed openings "
                                         "whose lintels (one course above each, a half block "
                                         "beyond each side) clear the other openings")
        for k, (x0, x1, z0, z1) in enumerate(self.holes):
            if not (self.b < x0 < x1 < self.b + self.L and 0 < z0 < z1 < self.H):
                raise ParameterError(f"holes[{k}] = {(x0, x1, z0, z1)!r} is out of range: "
                                     f"allowed b = {self.b:g} < x0 < x1 < b + L = "
                                     f"{self.b + self.L:g}, 0 < z0 < z1 < H = {self.H:g} m")

    @classmethod
    def from_case(cls, case: Case, z0: float = 0.0) -> TSection:
        """The section of ``case``'s wall (H, b, L), analysed from z0 up."""
        if not isinstance(case, Case):
            raise ParameterError(f"case = {type(case).__name__} is out of range: allowed a "
                                 "homlimit.params.Case")
        w, m = case.wall, case.masonry
        holes = tuple(o.box for o in case.wall_openings)
        return cls(w.H, w.b, w.L, z0, holes=holes,
                   lintels=lintel_boxes(holes, w.H, w.b, w.L, m.a, m.c))

    # ------------------------------------------------------------------ lengths
    @property
    def x_junction(self) -> float:
        """x of the junction between façade and wall: b."""
        return self.b

    @property
    def x_end(self) -> float:
        """x of the wall's free end: b + L."""
        return self.b + self.L

    @property
    def height(self) -> float:
        """Height of the analysed part, h = H − z0."""
        return self.H - self.z0

    @property
    def bbox(self) -> tuple[float, float, float, float]:
        """(x_min, z_min, x_max, z_max) = (0, z0, b + L, H)."""
        return 0.0, self.z0, self.x_end, self.H

    @property
    def extent(self) -> float:
        """The larger side of the bounding box [m] (the scale of geometric tolerances)."""
        return max(self.x_end, self.height)

    @property
    def span(self) -> float:
        """The smaller side of the bounding box, min(H − z0, b + L): the largest mesh size."""
        return min(self.height, self.x_end)

    def part(self, z0: float) -> TSection:
        """The failing part above the base z0 (0 <= z0 < H), same walls."""
        return TSection(self.H, self.b, self.L, z0, self.holes, self.lintels)

    @property
    def part_holes(self) -> tuple[tuple[float, float, float, float], ...]:
        """The wall's openings (x0, x1, z0, z1) in the part z >= z0, clipped to it (a hole
        the base cuts is a notch in it)."""
        t = 1e-6 * self.H              # no sliver of wall between the base and a hole
        return tuple((x0, x1, self.z0 if z0 < self.z0 + t else z0, z1)
                     for x0, x1, z0, z1 in self.holes if z1 > self.z0 + t)

    @property
    def part_lintels(self) -> dict[str, tuple[Point, ...]]:
        """The openings' lintels in the part z >= z0, clipped to it: "lintel<k>" → its
        counter-clockwise polygon (regions of the wall, ``fe.problems.t_section``)."""
        t = 1e-6 * self.H
        z = [self.z0 if z0 < self.z0 + t else z0 for _, _, z0, _ in self.lintels]
        return {f"lintel{k}": ((x0, zk), (x1, zk), (x1, z1), (x0, z1))
                for k, ((x0, x1, _, z1), zk) in enumerate(zip(self.lintels, z))
                if z1 > self.z0 + t}

    @property
    def hole_polygons(self) -> tuple[tuple[Point, ...], ...]:
        """``part_holes`` as counter-clockwise polygons."""
        return tuple(((x0, z0), (x1, z0), (x1, z1), (x0, z1))
                     for x0, x1, z0, z1 in self.part_holes)

    # ------------------------------------------------------------------ regions and segments
    @property
    def regions(self) -> dict[str, tuple[Point, ...]]:
        """{"facade", "wall"}: counter-clockwise polygons."""
        z0, H, b, x1 = self.z0, self.H, self.b, self.x_end
        return {"facade": ((0.0, z0), (b, z0), (b, H), (0.0, H)),
                "wall": ((b, z0), (x1, z0), (x1, H), (b, H))}

    @property
    def boundaries(self) -> dict[str, tuple[Point, Point]]:
        """Named segments: "base" (z = z0), "outer" (x = 0), "top" (z = H), "end" (x = b + L)
        and the interior "junction" (x = b), shared by both regions."""
        z0, H, b, x1 = self.z0, self.H, self.b, self.x_end
        return {"base": ((0.0, z0), (x1, z0)), "outer": ((0.0, z0), (0.0, H)),
                "top": ((0.0, H), (x1, H)), "end": ((x1, z0), (x1, H)),
                "junction": ((b, z0), (b, H))}

    def area(self, region: str | None = None) -> float:
        """Area of one region, or of the whole section [m²] (shoelace formula)."""
        polys = self.regions
        if region is not None and region not in polys:
            raise ParameterError(f"region = {region!r} is out of range: allowed one of "
                                 f"{sorted(polys)}")
        names = polys if region is None else (region,)
        holes = sum((x1 - x0) * (z1 - z0) for x0, x1, z0, z1 in self.part_holes)
        return float(sum(_shoelace(np.asarray(polys[n], float)) for n in names)
                     - (holes if region in (None, "wall") else 0.0))

    # ------------------------------------------------------------------ membership
    def tol(self) -> float:
        """Geometric tolerance of the membership tests: 1e-9 × H."""
        return 1e-9 * self.H

    def on_boundary(self, name: str, x, tol: float | None = None) -> np.ndarray:
        """Points x (2, n) within ``tol`` (default ``tol()``) of the segment ``name``."""
        segs = self.boundaries
        if name not in segs:
            raise ParameterError(f"boundary = {name!r} is out of range: allowed one of "
                                 f"{sorted(segs)}")
        tol = self.tol() if tol is None else tol
        (px, pz), (qx, qz) = segs[name]
        x = np.asarray(x, float)
        # the segments are axis-aligned: distance to the line, then within its extent
        if px == qx:
            return (np.abs(x[0] - px) < tol) & (x[1] > min(pz, qz) - tol) \
                & (x[1] < max(pz, qz) + tol)
        return (np.abs(x[1] - pz) < tol) & (x[0] > min(px, qx) - tol) \
            & (x[0] < max(px, qx) + tol)

    def in_region(self, name: str, x) -> np.ndarray:
        """Points x (2, n) strictly inside region ``name`` (cell centres)."""
        polys = self.regions
        if name not in polys:
            raise ParameterError(f"region = {name!r} is out of range: allowed one of "
                                 f"{sorted(polys)}")
        (x0, z0), _, (x1, z1), _ = polys[name]
        x = np.asarray(x, float)
        inside = (x[0] > x0) & (x[0] < x1) & (x[1] > z0) & (x[1] < z1)
        for a0, a1, c0, c1 in self.part_holes:        # the wall's openings are no region's
            inside &= ~((x[0] > a0) & (x[0] < a1) & (x[1] > c0) & (x[1] < c1))
        return inside


def lintel_boxes(holes, H: float, b: float, L: float, a: float, c: float) -> tuple:
    """The lintel (x0, x1, z0, z1) of each wall opening (x0, x1, z0, z1) of ``holes``: one
    course of height a above it, bearing a half block c beyond either side, within the wall
    (b <= x <= b + L, z <= H)."""
    return tuple((max(b, x0 - c), min(b + L, x1 + c), z1, min(H, z1 + a))
                 for x0, x1, _, z1 in holes)


def _shoelace(P: np.ndarray) -> float:
    x, z = P[:, 0], P[:, 1]
    return abs(0.5 * float(np.sum(x * np.roll(z, -1) - np.roll(x, -1) * z)))
