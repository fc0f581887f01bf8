"""Rigid-block assemblies in the section plane x–z: the T-section in running bond, small test
assemblies, and the interfaces found from the block outlines.

Frame (as ``homlimit.params``): x from the façade's outer face into the building, z up. The
façade strip 0 <= x <= b and the transversal wall b <= x <= b + L stand on a fixed ground at
z = 0.

The T-section (``t_section_blocks``), per course of height a:
- the transversal wall is laid in running bond of blocks 2c × a, staggered by c from course to
  course; where a course ends at x = b + L, the last block is what is left (a half block c × a
  when L is a multiple of 2c);
- the façade is one block across its thickness b in every course (the paper's blocks have the
  depth of the wall, so a section through the façade shows bed joints only);
- in alternate courses the façade block runs into the wall by c (a *toothing* block
  [0, b + c]), so that every bed joint at the abutment x = b overlaps by c (the assumption of
  eq. 8);
- masses per slab of thickness s (the paper's 2D reduction): façade at ρ·γ·s, wall at γ·s
  [kg/m²]; a toothing block carries both parts.

Blocks are simple polygons with counter-clockwise vertices, stored ragged (``vertices``,
``offsets``). Interfaces are the shared segments of block edges: two edges lying on one line
with opposite outward normals, overlapping over a positive length (``find_interfaces``, one
vectorised sort and search, no loop over blocks). Each interface is a segment with two end
points, a unit normal n pointing from block ``a`` to block ``b`` and the tangent t = (−n_z, n_x).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import numpy as np

from ..errors import ParameterError, check_range
from ..geometry import TSection
from ..params import Case
from .real import from_case

__all__ = ["Assembly", "Interfaces", "KIND_NAMES", "polygon_moments", "find_interfaces",
           "from_rectangles", "t_section_blocks", "FACADE_BONDS", "TOOTHINGS",
           "vertex_velocity", "block_speed", "stack", "running_bond_panel", "course_blocks"]

# block kinds
SUPPORT, FACADE, TOOTHING, WALL, OTHER = 0, 1, 2, 3, 4
KIND_NAMES = {SUPPORT: "support", FACADE: "facade", TOOTHING: "toothing", WALL: "wall",
              OTHER: "block"}


# --------------------------------------------------------------------------- polygons
def _next_vertex(offsets: np.ndarray) -> np.ndarray:
    """Index of the next vertex around each ragged polygon (wrapping at its end)."""
    P = int(offsets[-1])
    nxt = np.arange(1, P + 1)
    nxt[offsets[1:] - 1] = offsets[:-1]
    return nxt


def polygon_moments(vertices: np.ndarray, offsets: np.ndarray):
    """Exact area, first moments and second moments of ragged simple polygons (vectorised).

    With cross_i = x_i z_{i+1} − x_{i+1} z_i over the counter-clockwise edges:
    A = ½ Σ cross,  ∫x dA = (1/6) Σ (x_i + x_{i+1}) cross,  ∫x² dA = (1/12) Σ (x_i² + x_i
    x_{i+1} + x_{i+1}²) cross, and the same in z. Returns (A, Sx, Sz, Jxx, Jzz) with
    Jxx = ∫x² dA and Jzz = ∫z² dA about the origin, each of shape (n_polygons,).
    """
    v = np.asarray(vertices, float)
    nxt = _next_vertex(offsets)
    x, z = v[:, 0], v[:, 1]
    xn, zn = x[nxt], z[nxt]
    cr = x * zn - xn * z
    start = offsets[:-1]

    def total(a):
        return np.add.reduceat(a, start)

    A = 0.5 * total(cr)
    Sx = total((x + xn) * cr) / 6.0
    Sz = total((z + zn) * cr) / 6.0
    Jxx = total((x * x + x * xn + xn * xn) * cr) / 12.0
    Jzz = total((z * z + z * zn + zn * zn) * cr) / 12.0
    return A, Sx, Sz, Jxx, Jzz


def _rectangles(x0, x1, z0, z1):
    """Counter-clockwise ragged polygons of axis-aligned rectangles."""
    x0, x1, z0, z1 = (np.asarray(t, float) for t in (x0, x1, z0, z1))
    v = np.stack([np.c_[x0, z0], np.c_[x1, z0], np.c_[x1, z1], np.c_[x0, z1]], axis=1)
    return v.reshape(-1, 2), 4 * np.arange(len(x0) + 1)


# --------------------------------------------------------------------------- interfaces
@dataclass(frozen=True)
class Interfaces:
    """Contact segments between blocks.

    a, b    block indices (k,); the unit normal n points from block a into block b
    p       end points (k, 2, 2) [m]: p[:, 0] and p[:, 1], ordered along t
    n, t    unit normal (k, 2) and tangent t = (−n_z, n_x)
    length  segment lengths (k,) [m]
    """

    a: np.ndarray
    b: np.ndarray
    p: np.ndarray
    n: np.ndarray

    @property
    def t(self) -> np.ndarray:
        return np.c_[-self.n[:, 1], self.n[:, 0]]

    @property
    def length(self) -> np.ndarray:
        return np.linalg.norm(self.p[:, 1] - self.p[:, 0], axis=1)

    @property
    def count(self) -> int:
        return int(self.a.size)

    @property
    def horizontal(self) -> np.ndarray:
        """Bed joints: normal within 1e-9 of ±z."""
        return np.abs(self.n[:, 0]) < 1e-9

    def take(self, mask) -> Interfaces:
        idx = np.flatnonzero(np.asarray(mask, bool)) if np.asarray(mask).dtype == bool else mask
        return Interfaces(self.a[idx], self.b[idx], self.p[idx], self.n[idx])


def find_interfaces(vertices: np.ndarray, offsets: np.ndarray, tol: float | None = None
                    ) -> Interfaces:
    """Shared edge segments of ragged counter-clockwise polygons (vectorised).

    Every edge gets its outward normal n and the canonical normal of its supporting line
    (n or −n, whichever points to +x, or to +z on a horizontal line). Edges are grouped by
    line (sorted by normal angle and offset, split where either jumps by more than ``tol``).
    On each line, an edge whose outward normal is canonical ("+", block a) faces the edges of
    opposite normal ("−", block b); "+" edges on one line do not overlap each other (the
    polygons do not overlap), so for each "−" edge the "+" edges it overlaps form one run of
    the "+" edges sorted by (line, position), found by ``np.searchsorted`` on complex keys
    line + i·position (numpy orders complex numbers lexicographically).
    ``tol`` defaults to 1e-9 × the size of the assembly [m].
    """
    v = np.asarray(vertices, float)
    offsets = np.asarray(offsets, int)
    size = float(np.ptp(v, axis=0).max()) or 1.0
    tol = 1e-9 * size if tol is None else check_range("tol", tol, 0.0, lo_open=True, unit="m")
    nxt = _next_vertex(offsets)
    owner = np.repeat(np.arange(offsets.size - 1), np.diff(offsets))
    s, e = v, v[nxt]
    d = e - s
    ln = np.hypot(d[:, 0], d[:, 1])
    keep = ln > tol
    s, e, d, ln, owner = s[keep], e[keep], d[keep], ln[keep], owner[keep]
    d = d / ln[:, None]
    n_out = np.c_[d[:, 1], -d[:, 0]]
    canon = (n_out[:, 0] > 1e-12) | ((np.abs(n_out[:, 0]) <= 1e-12) & (n_out[:, 1] > 0))
    nc = np.where(canon[:, None], n_out, -n_out)
    tc = np.c_[-nc[:, 1], nc[:, 0]]
    ang = np.arctan2(nc[:, 1], nc[:, 0])
    off = np.einsum("ij,ij->i", nc, s)
    sa, sb = np.einsum("ij,ij->i", tc, s), np.einsum("ij,ij->i", tc, e)
    lo, hi = np.minimum(sa, sb), np.maximum(sa, sb)
    # group the edges by supporting line
    order = np.lexsort((off, ang))
    brk = np.r_[True, (np.diff(ang[order]) > 1e-9) | (np.diff(off[order]) > tol)]
    line = np.empty(order.size, int)
    line[order] = np.cumsum(brk) - 1
    plus, minus = np.flatnonzero(canon), np.flatnonzero(~canon)
    plus = plus[np.lexsort((lo[plus], line[plus]))]
    key_lo = line[plus] + 1j * lo[plus]
    key_hi = line[plus] + 1j * hi[plus]
    # "+" edges overlapping minus edge m: hi+ > lo− + tol and lo+ < hi− − tol
    first = np.searchsorted(key_hi, line[minus] + 1j * (lo[minus] + tol), side="right")
    last = np.searchsorted(key_lo, line[minus] + 1j * (hi[minus] - tol), side="left")
    count = np.maximum(last - first, 0)
    m_idx = np.repeat(minus, count)
    p_idx = plus[np.repeat(first, count) + (np.arange(count.sum())
                                            - np.repeat(np.cumsum(count) - count, count))]
    s0 = np.maximum(lo[p_idx], lo[m_idx])
    s1 = np.minimum(hi[p_idx], hi[m_idx])
    ok = s1 - s0 > tol
    p_idx, m_idx, s0, s1 = p_idx[ok], m_idx[ok], s0[ok], s1[ok]
    n = nc[p_idx]
    t = tc[p_idx]
    o = off[p_idx]
    p = np.stack([o[:, None] * n + s0[:, None] * t, o[:, None] * n + s1[:, None] * t], axis=1)
    a, b = owner[p_idx], owner[m_idx]
    srt = np.lexsort((p[:, 0, 0], p[:, 0, 1], b, a))
    return Interfaces(a[srt], b[srt], p[srt], n[srt])


# --------------------------------------------------------------------------- assembly
def vertex_velocity(assembly, q: np.ndarray) -> np.ndarray:
    """Velocity (P, 2) of every outline vertex under block velocities q (n, 3) = (u, w, ω)
    about the centroids: v = (u − ω (z − z_G), w + ω (x − x_G))."""
    owner = np.repeat(np.arange(assembly.n_blocks), np.diff(assembly.offsets))
    r = assembly.vertices - assembly.centroid[owner]
    qo = np.asarray(q, float)[owner]
    return np.c_[qo[:, 0] - qo[:, 2] * r[:, 1], qo[:, 1] + qo[:, 2] * r[:, 0]]


def block_speed(assembly, q: np.ndarray) -> np.ndarray:
    """Per block, the speed of its fastest vertex under q (the speed is convex in position,
    so its maximum over a polygon is at a vertex)."""
    v = vertex_velocity(assembly, q)
    return np.maximum.reduceat(np.hypot(v[:, 0], v[:, 1]), assembly.offsets[:-1])



@dataclass(frozen=True)
class Assembly:
    """Rigid blocks in the x–z plane with their masses and interfaces (SI, per slab thickness).

    vertices, offsets   block outlines: ragged counter-clockwise polygons (block i has vertices
                        vertices[offsets[i]:offsets[i+1]]) [m]
    mass                (n,) [kg]; centroid (n, 2) [m]; inertia (n,) about the centroid [kg m²]
    fixed               (n,) True for supports (the ground, or blocks held fixed)
    kind                (n,) 0 support, 1 façade, 2 toothing, 3 wall, 4 other (``KIND_NAMES``)
    course              (n,) course index (−1 for the ground)
    parts               (part_vertices, part_offsets, part_block, part_density): the material
                        parts of each block (a toothing block has a façade and a wall part)
    interfaces          ``Interfaces`` found from the outlines
    meta                the geometry it was built from (H, L, b, a, c, rho, gamma, s, g, ...)
    """

    vertices: np.ndarray
    offsets: np.ndarray
    mass: np.ndarray
    centroid: np.ndarray
    inertia: np.ndarray
    fixed: np.ndarray
    kind: np.ndarray
    course: np.ndarray
    parts: tuple
    interfaces: Interfaces
    meta: dict = field(default_factory=dict)

    @property
    def n_blocks(self) -> int:
        return int(self.mass.size)

    @property
    def n_free(self) -> int:
        return int(np.count_nonzero(~self.fixed))

    def polygon(self, i: int) -> np.ndarray:
        return self.vertices[self.offsets[i]:self.offsets[i + 1]]

    def bounds(self) -> np.ndarray:
        """Per block (x_min, z_min, x_max, z_max)."""
        start = self.offsets[:-1]
        v = self.vertices
        return np.c_[np.minimum.reduceat(v[:, 0], start), np.minimum.reduceat(v[:, 1], start),
                     np.maximum.reduceat(v[:, 0], start), np.maximum.reduceat(v[:, 1], start)]

    def fix_below(self, z0: float) -> Assembly:
        """A copy with every block lying at or below z0 held fixed (the base of an analysed
        upper part, as the FE h-scan does). z0 must not cut a block."""
        z0 = check_range("z0", z0, unit="m")
        bb = self.bounds()
        tol = 1e-9 * max(1.0, float(np.ptp(self.vertices[:, 1])))
        cut = (bb[:, 1] < z0 - tol) & (bb[:, 3] > z0 + tol)
        if np.any(cut):
            levels = np.unique(np.round(bb[~self.fixed, 1], 12))
            raise ParameterError(f"z0 = {z0!r} m is out of range: it cuts {int(cut.sum())} "
                                 f"block(s); allowed a course boundary, e.g. "
                                 f"{', '.join(f'{z:g}' for z in levels[:6])}, ...")
        fixed = self.fixed | (bb[:, 3] <= z0 + tol)
        return replace(self, fixed=fixed, meta={**self.meta, "z_fixed": z0})

    def triangles(self, mask=None, density: bool = True):
        """Fan triangulation of the material parts of the blocks in ``mask`` (default all):
        (points (P, 2), triangles (T, 3), density per triangle, block per triangle). Exact
        for convex parts (all parts built here are rectangles)."""
        pv, po, pb, pd = self.parts
        sel = np.ones(self.n_blocks, bool) if mask is None else np.asarray(mask, bool)
        take = np.flatnonzero(sel[pb])
        counts = np.diff(po)[take]
        tri_counts = counts - 2
        first = po[:-1][take]
        k = np.arange(tri_counts.sum()) - np.repeat(np.cumsum(tri_counts) - tri_counts,
                                                    tri_counts)
        f0 = np.repeat(first, tri_counts)
        tris = np.c_[f0, f0 + k + 1, f0 + k + 2]
        return (pv, tris, np.repeat(pd[take], tri_counts), np.repeat(pb[take], tri_counts))


def _mass_properties(n, parts, outline_v, outline_o):
    """Mass, centroid and inertia about the centroid of each block from its parts (exact)."""
    pv, po, pb, pd = parts
    A, Sx, Sz, Jxx, Jzz = polygon_moments(pv, po)
    m = np.bincount(pb, pd * A, minlength=n)
    mx = np.bincount(pb, pd * Sx, minlength=n)
    mz = np.bincount(pb, pd * Sz, minlength=n)
    J = np.bincount(pb, pd * (Jxx + Jzz), minlength=n)
    Ao, Sxo, Szo, _, _ = polygon_moments(outline_v, outline_o)
    with np.errstate(invalid="ignore", divide="ignore"):
        G = np.where(m[:, None] > 0, np.c_[mx, mz] / m[:, None], np.c_[Sxo, Szo] / Ao[:, None])
    inertia = J - m * (G[:, 0] ** 2 + G[:, 1] ** 2)
    return m, G, np.maximum(inertia, 0.0)


def _assemble(outline, parts, fixed, kind, course, meta) -> Assembly:
    v, o = outline
    n = o.size - 1
    m, G, inertia = _mass_properties(n, parts, v, o)
    A = polygon_moments(v, o)[0]
    if np.any(A <= 0):
        bad = int(np.flatnonzero(A <= 0)[0])
        raise ParameterError(f"block {bad} has area {A[bad]!r} m^2: allowed a counter-clockwise "
                             f"polygon of positive area")
    inter = find_interfaces(v, o)
    both_fixed = fixed[inter.a] & fixed[inter.b]
    inter = inter.take(~both_fixed)
    return Assembly(v, o, m, G, inertia, np.asarray(fixed, bool), np.asarray(kind, np.int8),
                    np.asarray(course, int), parts, inter, meta)


def from_rectangles(x0, x1, z0, z1, density, fixed=None, kind=None, course=None,
                    meta: dict | None = None) -> Assembly:
    """An assembly of axis-aligned rectangular blocks [x0, x1] × [z0, z1], each of one
    material of ``density`` [kg/m² per slab]; ``fixed`` marks supports (mass ignored)."""
    x0, x1, z0, z1 = (np.atleast_1d(np.asarray(t, float)) for t in (x0, x1, z0, z1))
    n = x0.size
    if not (x1.size == z0.size == z1.size == n):
        raise ParameterError(f"x0, x1, z0, z1 have sizes {x0.size}, {x1.size}, {z0.size}, "
                             f"{z1.size}: allowed equal sizes")
    if np.any(x1 <= x0) or np.any(z1 <= z0):
        raise ParameterError("rectangles with x1 <= x0 or z1 <= z0 are out of range: allowed "
                             "x0 < x1 and z0 < z1")
    dens = np.broadcast_to(np.asarray(density, float), (n,)).copy()
    if np.any(~np.isfinite(dens)) or np.any(dens < 0):
        raise ParameterError(f"density min = {float(dens.min())!r} is out of range: allowed "
                             "0 <= density (kg/m^2)")
    fixed = np.zeros(n, bool) if fixed is None else np.broadcast_to(fixed, (n,)).copy()
    dens[fixed] = 0.0
    outline = _rectangles(x0, x1, z0, z1)
    parts = (*outline, np.arange(n), dens)
    kind = np.full(n, OTHER) if kind is None else kind
    kind = np.where(fixed, SUPPORT, kind)
    course = np.zeros(n, int) if course is None else course
    return _assemble(outline, parts, fixed, kind, course, dict(meta or {}))


def stack(widths, heights, x_left=None, density: float = 1.0, ground: bool = True,
          meta: dict | None = None) -> Assembly:
    """A column of rectangular blocks on a fixed ground at z = 0: block k spans
    [x_left_k, x_left_k + widths_k] × [Σ_{j<k} heights_j, Σ_{j<=k} heights_j]. ``meta``: facts
    for the analyses (f, g, b, H, ...)."""
    w = np.atleast_1d(np.asarray(widths, float))
    h = np.atleast_1d(np.asarray(heights, float))
    if w.size != h.size:
        raise ParameterError(f"widths has {w.size} entries and heights {h.size}: allowed equal "
                             "sizes")
    for name, arr in (("widths", w), ("heights", h)):
        if np.any(~(arr > 0)):
            raise ParameterError(f"{name} min = {float(arr.min())!r} m is out of range: allowed "
                                 "> 0 m")
    xl = np.zeros_like(w) if x_left is None else np.atleast_1d(np.asarray(x_left, float))
    zt = np.cumsum(h)
    x0, x1, z0, z1 = xl, xl + w, zt - h, zt
    fixed = np.zeros(w.size, bool)
    course = np.arange(w.size)
    if ground:
        lo, hi = float(x0.min()), float(x1.max())
        x0, x1 = np.r_[lo - 1.0, x0], np.r_[hi + 1.0, x1]
        z0, z1 = np.r_[-1.0, z0], np.r_[0.0, z1]
        fixed = np.r_[True, fixed]
        course = np.r_[-1, course]
    return from_rectangles(x0, x1, z0, z1, np.where(fixed, 0.0, density), fixed=fixed,
                           course=course, meta=meta)


def running_bond_panel(n_blocks: int, n_courses: int, a: float, c: float,
                       density: float = 1.0, shift_first: bool = False) -> Assembly:
    """A panel of width 2c·n_blocks in running bond on a fixed ground: courses of blocks
    2c × a, every other course shifted by c with half blocks c × a at both ends (the first
    course is shifted if ``shift_first``)."""
    n_blocks = int(check_range("n_blocks", n_blocks, 1))
    n_courses = int(check_range("n_courses", n_courses, 1))
    a = check_range("a", a, 0.0, lo_open=True, unit="m")
    c = check_range("c", c, 0.0, lo_open=True, unit="m")
    W = 2 * c * n_blocks
    rows = []
    for k in range(n_courses):                      # loop over courses (a handful), not blocks
        shifted = (k % 2 == 0) == shift_first
        xs = np.r_[0.0, c + 2 * c * np.arange(n_blocks), W] if shifted else \
            2 * c * np.arange(n_blocks + 1)
        rows.append(np.c_[xs[:-1], xs[1:], np.full(xs.size - 1, k * a),
                          np.full(xs.size - 1, (k + 1) * a), np.full(xs.size - 1, k)])
    r = np.vstack(rows)
    x0, x1, z0, z1, course = r.T
    x0, x1 = np.r_[-1.0, x0], np.r_[W + 1.0, x1]
    z0, z1 = np.r_[-a, z0], np.r_[0.0, z1]
    fixed = np.r_[True, np.zeros(course.size, bool)]
    return from_rectangles(x0, x1, z0, z1, np.where(fixed, 0.0, density), fixed=fixed,
                           course=np.r_[-1, course.astype(int)],
                           meta={"a": a, "c": c, "width": W, "n_courses": n_courses})


FACADE_BONDS = ("through", "running-bond")
TOOTHINGS = ("split", "block")     # a toothing block's density (t_section_blocks)


def _course_breaks(geo: TSection, c: float, toothed: bool, facade: str, tol: float
                   ) -> np.ndarray:
    """x breaks of one course. Wall: blocks of 2c from x = b (x = b + c if ``toothed``), the
    last one whatever is left up to b + L. Façade "through": one block [0, b] (or [0, b + c]
    if toothed); "running-bond": the wall's bond continued to x = 0 (the first block is what
    is left), so that a block straddles x = b in toothed courses."""
    b, x_end = geo.x_junction, geo.x_end
    start = b + c if toothed else b
    k_max = int(math.ceil(x_end / (2 * c))) + 2
    j = np.arange(-k_max, k_max + 1)
    xs = start + 2 * c * j
    lo = b + tol if facade == "through" else tol
    xs = xs[(xs > lo) & (xs < x_end - tol)]
    if facade == "through" and not toothed:
        xs = np.r_[b, xs]
    return np.unique(np.r_[0.0, xs, x_end])


def course_levels(H: float, a: float, tol: float | None = None) -> np.ndarray:
    """The course boundaries 0, a, 2a, ..., H of ``t_section_blocks`` (a top course shorter
    than a kept when it is taller than ``tol``, default 1e-9 H)."""
    tol = 1e-9 * H if tol is None else tol
    zs = a * np.arange(int(math.floor(H / a + 1e-9)) + 1)
    if H - zs[-1] > tol:
        zs = np.r_[zs, H]
    zs[-1] = H
    return zs


def open_courses(zs: np.ndarray, hole, k: int = 0):
    """(opened, top): the courses (boundaries ``zs``) a wall opening (x0, x1, z0, z1) opens,
    those whose mid-height lies in [z0, z1] (or, if none, the one holding its mid-height), and
    the course of its lintel, the one above them. ParameterError naming [[wall_opening]] k if
    there is none."""
    _, _, hz0, hz1 = hole
    n_c = zs.size - 1
    mid = (zs[:-1] + zs[1:]) / 2
    opened = (mid >= hz0) & (mid <= hz1)
    if not opened.any():
        opened[min(int(np.searchsorted(zs, (hz0 + hz1) / 2)) - 1, n_c - 1)] = True
    top = int(np.flatnonzero(opened).max()) + 1
    if top >= n_c:
        raise ParameterError(f"[[wall_opening]] {k} z + height = {hz1!r} m leaves no course "
                             f"above it for its lintel in the blocks: allowed an opening "
                             f"whose courses end below the top course ({zs[-2]:g} m)")
    return opened, top


def _open_courses(x0, x1, course, zs, hole, k: int, tol: float):
    """The blocks (x0, x1, course) with the wall opening ``hole`` = (x0, x1, z0, z1) cut out
    (docs/real-walls.md "Openings"): the courses whose mid-height lies in [z0, z1] (or, if
    none, the one holding the opening's mid-height) lose what lies between x0 and x1, a block
    across a jamb cut there; in the course above the last one opened, the blocks over the
    opening become one block, the lintel, from the first one's start to the last one's end.
    ParameterError if no course is left above the opening. Returns (x0, x1, course, the
    narrowest piece the jambs leave [m], inf if they cut no block)."""
    hx0, hx1, hz0, hz1 = hole
    opened, top = open_courses(zs, hole, k)
    hit = opened[course] & (x0 < hx1 - tol) & (x1 > hx0 + tol)
    left, right = hit & (x0 < hx0 - tol), hit & (x1 > hx1 + tol)
    narrow = float(np.r_[hx0 - x0[left], x1[right] - hx1, np.inf].min())
    x0, x1, course = (np.r_[x0[~hit], x0[left], np.full(right.sum(), hx1)],
                      np.r_[x1[~hit], np.full(left.sum(), hx0), x1[right]],
                      np.r_[course[~hit], course[left], course[right]])
    over = (course == top) & (x0 < hx1 - tol) & (x1 > hx0 + tol)
    x0, x1, course = (np.r_[x0[~over], x0[over].min()], np.r_[x1[~over], x1[over].max()],
                      np.r_[course[~over], top])
    order = np.lexsort((x0, course))
    return x0[order], x1[order], course[order], narrow


def _band_parts(rects, on_facade, z_lo: float, z_hi: float, scale: float):
    """Rectangular parts (x0, x1, z0, z1, block, density) with the façade's (``on_facade``)
    cut at z_lo and z_hi: a part crossing the band [z_lo, z_hi] becomes its pieces below, in
    and above it, the piece in it at ``scale`` × its density (docs/real-walls.md "Openings":
    the façade's mass over an opening band times 1 − fraction). Returns the new arrays and
    their façade flags."""
    x0, x1, z0, z1, pb, pd = (np.asarray(a) for a in rects)
    hit = on_facade & (z0 < z_hi) & (z1 > z_lo)
    keep = ~hit
    lo, hi = np.maximum(z0, z_lo), np.minimum(z1, z_hi)
    pieces = [(z0, lo, 1.0), (lo, hi, scale), (hi, z1, 1.0)]   # below, in, above the band
    out = [[a[keep]] for a in (x0, x1, z0, z1, pb, pd, on_facade)]
    for a, b, f in pieces:
        sel = hit & (b > a)
        for lst, v in zip(out, (x0[sel], x1[sel], a[sel], b[sel], pb[sel], pd[sel] * f,
                                on_facade[sel])):
            lst.append(v)
    return tuple(np.concatenate(lst) for lst in out)


def course_blocks(geo: TSection, a: float, c: float, toothed_first: bool = True,
                  facade: str = "through"):
    """The blocks of ``t_section_blocks`` as (x0, x1, course) arrays, the course boundaries
    ``zs``, and per wall opening of ``geo.holes`` the narrowest piece its jambs leave of a
    block they cut [m] (inf if they cut none; ``_open_courses``). ParameterError as there."""
    if facade not in FACADE_BONDS:
        raise ParameterError(f"facade = {facade!r} is out of range: allowed {FACADE_BONDS}")
    tol = 1e-9 * geo.extent
    zs = course_levels(geo.H, a, tol)
    n_c = zs.size - 1
    toothed = (np.arange(n_c) % 2 == 0) == bool(toothed_first)
    xt = _course_breaks(geo, c, True, facade, tol)
    xp = _course_breaks(geo, c, False, facade, tol)
    counts = np.where(toothed, xt.size - 1, xp.size - 1)
    course = np.repeat(np.arange(n_c), counts)
    j = np.arange(counts.sum()) - np.repeat(np.cumsum(counts) - counts, counts)
    tt = toothed[course]
    jt, jp = np.minimum(j, xt.size - 2), np.minimum(j, xp.size - 2)
    x0 = np.where(tt, xt[jt], xp[jp])
    x1 = np.where(tt, xt[jt + 1], xp[jp + 1])
    narrow = []
    for k, hole in enumerate(geo.holes):    # the wall's openings, each under a lintel block
        x0, x1, course, n = _open_courses(x0, x1, course, zs, hole, k, tol)
        narrow.append(n)
    return x0, x1, course, zs, tuple(narrow)


def t_section_blocks(case: Case, toothed_first: bool = True, facade: str = "through",
                     toothing: str = "split") -> Assembly:
    """The paper's T-section as rigid blocks (module docstring): façade strip [0, b], transversal
    wall [b, b + L] in running bond 2c × a, toothed at the abutment with overlap c, on a fixed
    ground; any H, L, b, a, c of ``case``. The bottom course is toothed if ``toothed_first``.
    A top course shorter than a (H not a multiple of a) is kept with its own height.
    The wall's openings (``case.wall_openings``) are cut out of the courses they hold, each
    under one lintel block (``_open_courses``).
    Masses per slab of thickness s: façade ρ·γ·s (times 1 − fraction over an opening band:
    the façade parts cut at its edges), wall γ·s; a block straddling x = b has a
    façade part and a wall part.

    toothing: "split" (default: a block straddling x = b is ρ·γ·s over [x0, b] and γ·s over
    [b, x1]) or "block" (one density per block, as a DEM gives each block one material: the
    straddling blocks of the façade "through", whose centroids lie in the façade, at ρ·γ·s
    over their whole area; docs/dem.md sections 16-17).
    facade: "through" (default, the paper's: one block across the façade's thickness per
    course, so the façade shows bed joints only) or "running-bond" (the wall's bond continued
    through the façade: the discrete counterpart of the homogenised façade of eq. 15).
    """
    if toothing not in TOOTHINGS or (toothing == "block" and facade != "through"):
        raise ParameterError(f"toothing = {toothing!r} is out of range with facade = "
                             f"{facade!r}: allowed {TOOTHINGS} ('block' with the façade "
                             "'through' only)")
    geo = TSection.from_case(case)
    w, mas = case.wall, case.masonry
    H, L, b, a, c = geo.H, geo.L, geo.x_junction, mas.a, mas.c
    tol = 1e-9 * geo.extent
    x0, x1, course, zs, _ = course_blocks(geo, a, c, toothed_first, facade)
    n_c = zs.size - 1
    z0, z1 = zs[course], zs[course + 1]
    kind = np.where(x1 <= b + tol, FACADE, np.where(x0 >= b - tol, WALL, TOOTHING))
    gs = w.gamma * w.s
    # ground (index 0), then the blocks
    X0, X1 = np.r_[0.0, x0], np.r_[geo.x_end, x1]
    Z0, Z1 = np.r_[-a, z0], np.r_[0.0, z1]
    n = X0.size
    fixed = np.r_[True, np.zeros(n - 1, bool)]
    kind = np.r_[SUPPORT, kind]
    course = np.r_[-1, course]
    outline = _rectangles(X0, X1, Z0, Z1)
    # parts: every block is one part, except with toothing "split" the blocks straddling
    # x = b: façade [x0, b] + wall [b, x1]
    split = (kind == TOOTHING) & (toothing == "split")
    last = np.where(split, b, X1)
    dens = np.where(kind == SUPPORT, 0.0, np.where(kind == WALL, gs, case.rho * gs))
    tooth = np.flatnonzero(split)
    px0 = np.r_[X0, np.full(tooth.size, b)]
    px1 = np.r_[last, X1[tooth]]
    pz0, pz1 = np.r_[Z0, Z0[tooth]], np.r_[Z1, Z1[tooth]]
    pb, pd = np.r_[np.arange(n), tooth], np.r_[dens, np.full(tooth.size, gs)]
    on_facade = np.r_[(kind == FACADE) | (kind == TOOTHING), np.zeros(tooth.size, bool)]
    for op in case.facade_openings:     # the façade parts cut at the band, its part lighter
        px0, px1, pz0, pz1, pb, pd, on_facade = _band_parts(
            (px0, px1, pz0, pz1, pb, pd), on_facade, op.z_bottom, op.z_top, 1 - op.fraction)
    pv, po = _rectangles(px0, px1, pz0, pz1)
    parts = (pv, po, pb, pd)
    meta = {"H": H, "L": L, "b": b, "a": a, "c": c, "f": mas.f, "rho": case.rho,
            "gamma": w.gamma, "s": w.s, "g": w.g, "n_courses": n_c,
            "toothed_first": bool(toothed_first), "facade": facade, "toothing": toothing,
            "name": case.name}
    real = from_case(case)              # ties, floors, fc per bay (blocks.real); None: paper's
    if real is not None:
        meta["real"] = real
    return _assemble(outline, parts, fixed, kind, course, meta)
