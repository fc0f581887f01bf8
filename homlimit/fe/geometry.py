"""Plane meshes of the wall section (x–z) with gmsh, returned as meshio.Mesh with named parts.

gmsh holds global state, so every use goes through ``gmsh_session()``, which always finalises
and reports gmsh failures as MeshError. Geometry builders validate their input before gmsh
starts (ParameterError naming the parameter).

- ``polygon_mesh``: polygonal regions with named (boundary or interior) segments, unnamed
  embedded lines the mesh must conform to, and local refinement around points and segments;
  the generic builder behind the classical benchmarks (strip footing, vertical cut, block).
- ``tsection``: the façade strip 0 <= x <= b and the transversal wall b <= x <= b + L,
  z0 <= z <= H, conforming along the junction x = b (paper, Figure 1); the outline and its
  names come from ``homlimit.geometry.TSection``. The strip may be a structured crossed grid
  (``strip="structured"``) inside the unstructured mesh.

The output mesh is the only mesh currency before scikit-fem (see ``homlimit.fe.mesh``):
points (n, 3) with z-coordinate 0 (the plane is x–z, stored as the first two columns);
one cell block per physical group ("triangle" for regions, "line" for named segments);
``cell_sets`` {name: [indices per block]}, ``cell_data["gmsh:physical"]`` and
``cell_data["gmsh:geometrical"]``, and ``field_data`` {name: [tag, dim]}.
"""

from __future__ import annotations

import math
import signal
import threading
from collections.abc import Iterator, Mapping, Sequence
from contextlib import contextmanager

import meshio
import numpy as np

from ..errors import MeshError, ParameterError, check_choice, check_range
from ..geometry import BOUNDARIES, REGIONS, TSection

__all__ = ["OUTER_GROWTH", "graded_columns", "gmsh_session", "polygon_mesh", "tsection",
           "TSECTION_REGIONS", "TSECTION_BOUNDARIES", "STRIPS"]

Point = tuple[float, float]
Segment = tuple[Point, Point]

TSECTION_REGIONS = REGIONS            # the names of homlimit.geometry.TSection
TSECTION_BOUNDARIES = BOUNDARIES
STRIPS = ("free", "structured")       # tsection's meshes of the façade strip


#: gmsh holds global state: one session at a time in this process, whichever thread opens it
_GMSH_LOCK = threading.RLock()
#: the signals whose handlers ``gmsh.initialize`` resets to the default (measured: SIGHUP,
#: SIGFPE, SIGPIPE and SIGTERM), put back by ``gmsh_session``
_SIGNALS = ("SIGHUP", "SIGTERM", "SIGPIPE", "SIGFPE")


@contextmanager
def gmsh_session(name: str = "homlimit", verbosity: int = 0) -> Iterator:
    """Open a gmsh session (yields the ``gmsh`` module); always finalised on exit.

    Errors raised by gmsh itself are re-raised as MeshError. One session at a time: a session
    opened in another thread waits for this one to close; a nested one raises MeshError.
    ``gmsh.initialize`` resets the process's handlers of SIGTERM, SIGHUP and SIGPIPE, which
    would let SIGTERM kill a run before its clean-up: opened in the main thread, the session
    puts Python's handlers back (only the main thread may). Mesh in the main thread.
    """
    import gmsh

    with _GMSH_LOCK:
        if gmsh.isInitialized():
            raise MeshError("a gmsh session is already open: gmsh holds global state, "
                            "nest no sessions")
        gmsh.initialize(readConfigFiles=False, interruptible=False)
        _put_back_signals()
        try:
            gmsh.option.setNumber("General.Terminal", 1 if verbosity > 0 else 0)
            gmsh.option.setNumber("General.Verbosity", int(verbosity))
            gmsh.option.setNumber("General.NumThreads", 1)     # reproducible meshes
            gmsh.model.add(name)
            yield gmsh
        except Exception as exc:
            if type(exc) is Exception:                        # gmsh's own error type
                raise MeshError(f"gmsh failed while meshing {name!r}: {exc}") from exc
            raise
        finally:
            gmsh.finalize()


def _put_back_signals() -> None:
    """Python's handler of each of ``_SIGNALS``, installed again (main thread only)."""
    if threading.current_thread() is not threading.main_thread():
        return
    for name in _SIGNALS:
        sig = getattr(signal, name, None)
        handler = None if sig is None else signal.getsignal(sig)
        if handler is not None:
            signal.signal(sig, handler)


# ---------------------------------------------------------------------------------- checks

def _point(name: str, p) -> Point:
    try:
        x, z = p
    except (TypeError, ValueError):
        raise ParameterError(f"{name} = {p!r} is not a point (x, z)") from None
    return check_range(f"{name}.x", x, unit="m"), check_range(f"{name}.z", z, unit="m")


def _segment(name: str, s) -> Segment:
    try:
        p, q = s
    except (TypeError, ValueError):
        raise ParameterError(f"{name} = {s!r} is not a segment ((x1, z1), (x2, z2))") from None
    p, q = _point(f"{name}[0]", p), _point(f"{name}[1]", q)
    if math.dist(p, q) == 0.0:
        raise ParameterError(f"{name} = {s!r} has zero length: allowed two distinct points")
    return p, q


def _name(kind: str, n) -> str:
    if not isinstance(n, str) or not n.strip():
        raise ParameterError(f"{kind} name {n!r} is not a non-empty string")
    return n


def _polygon(name: str, pts) -> np.ndarray:
    pts = [_point(f"{name}[{i}]", p) for i, p in enumerate(pts)]
    P = np.array(pts, float)
    if len(P) < 3:
        raise ParameterError(f"{name} has {len(P)} vertices: allowed at least 3")
    x, z = P[:, 0], P[:, 1]
    area = 0.5 * np.sum(x * np.roll(z, -1) - np.roll(x, -1) * z)
    if not abs(area) > 0.0:
        raise ParameterError(f"{name} has zero area: allowed a simple polygon of positive area")
    if np.any(np.hypot(*(P - np.roll(P, -1, axis=0)).T) == 0.0):
        raise ParameterError(f"{name} repeats a vertex: allowed distinct consecutive vertices")
    return P


def _refinement(name: str, r, segment: bool):
    """(point or segment, size, radius) from (x, z, size, radius) or (p, q, size, radius)."""
    try:
        geo, size, radius = r[0:2], r[2], r[3]
    except (TypeError, IndexError, KeyError):
        kind = "((x1, z1), (x2, z2), size, radius)" if segment else "(x, z, size, radius)"
        raise ParameterError(f"{name} = {r!r} is not {kind}") from None
    geo = _segment(name, geo) if segment else _point(name, geo)
    return (geo, check_range(f"{name}.size", size, 0.0, lo_open=True, unit="m"),
            check_range(f"{name}.radius", radius, 0.0, lo_open=True, unit="m"))


# ---------------------------------------------------------------------------------- builder

def polygon_mesh(regions: Mapping[str, Sequence[Point]],
                 boundaries: Mapping[str, Sequence[Segment]] | None = None,
                 *, size: float,
                 refine_points: Sequence = (),
                 refine_segments: Sequence = (),
                 embed_lines: Sequence[Segment] = (),
                 structured: Mapping[str, tuple] | None = None,
                 size_map=None,
                 holes: Sequence[Sequence[Point]] = (),
                 inserts: Sequence[str] = (),
                 name: str = "polygon",
                 verbosity: int = 0) -> meshio.Mesh:
    """Triangulate polygonal regions, conforming across shared edges.

    regions:        {name: [(x, z), ...]} simple polygons (either orientation), not overlapping.
    boundaries:     {name: [segment, ...]} named straight segments ((x1, z1), (x2, z2)); the
                    mesh edges lying on them, on the outer boundary or inside (e.g. the
                    junction between two regions), form the line group ``name``. Endpoints
                    need not be polygon vertices: the boundary is split there ("footing" as
                    part of a top edge). Parts outside every region are dropped.
    size:           global element size [m].
    refine_points:  [(x, z, size, radius)]: element size ``size`` within ``radius`` of the
                    point, growing linearly to the global size over a further ``radius``.
    refine_segments:[((x1, z1), (x2, z2), size, radius)], the same around a segment.
    embed_lines:    unnamed segments the mesh must conform to (e.g. rays of a fan from a hinge
                    on the boundary); they may end on, or cross, boundaries and each other.
    structured:     {region: (nx, nz)}: an axis-aligned rectangular region meshed as a
                    structured grid of nx × nz equal cells (gmsh transfinite, recombined into
                    quadrangles), each cell cut by its two diagonals into four triangles at its
                    centre (the "crossed" cells of ``problems.crossed_mesh``, whose edges are
                    aligned with x and z); the other regions stay unstructured and conform to
                    its edge nodes. No embedded line may cross it. (nx, nz, r): the columns
                    grow geometrically by r (> 0) from the region's left side (x min).
    size_map:       (points (2, n), triangles (3, nt), sizes (nt,)): a background mesh whose
                    element sizes [m] also bound the size (``homlimit.fe.adapt``).
    holes:          [[(x, z), ...]]: polygons cut out of every region (gmsh OCC boolean
                    difference), e.g. the openings of a transversal wall; none may meet a
                    structured region.
    inserts:        names of regions cut out of the other regions (which they may overlap),
                    e.g. a lintel inside the wall; an insert must not meet a structured
                    region nor another insert.
    Returns a meshio.Mesh (see the module docstring).
    """
    boundaries = {} if boundaries is None else boundaries
    size = check_range("size", size, 0.0, lo_open=True, unit="m")
    if not isinstance(regions, Mapping) or not regions:
        raise ParameterError(f"regions = {regions!r}: allowed a non-empty mapping name -> polygon")
    polys = {_name("region", k): _polygon(f"regions[{k!r}]", v) for k, v in regions.items()}
    segs = {}
    for k, v in boundaries.items():
        _name("boundary", k)
        if k in polys:
            raise ParameterError(f"boundary name {k!r} is also a region name: allowed "
                                 "distinct names")
        v = [v] if len(v) == 2 and np.ndim(v[0]) == 1 else v
        segs[k] = [_segment(f"boundaries[{k!r}][{i}]", s) for i, s in enumerate(v)]
        if not segs[k]:
            raise ParameterError(f"boundaries[{k!r}] is empty: allowed at least one segment")
    rpts = [_refinement(f"refine_points[{i}]", r, False) for i, r in enumerate(refine_points)]
    rsegs = [_refinement(f"refine_segments[{i}]", r, True) for i, r in enumerate(refine_segments)]
    lines = [_segment(f"embed_lines[{i}]", s) for i, s in enumerate(embed_lines)]
    grid = {}
    for k, v in (structured or {}).items():
        if k not in polys:
            raise ParameterError(f"structured region {k!r} is out of range: allowed one of "
                                 f"{sorted(polys)}")
        P = polys[k]
        if len(P) != 4 or not all(P[i, 0] == P[(i + 1) % 4, 0] or P[i, 1] == P[(i + 1) % 4, 1]
                                  for i in range(4)):
            raise ParameterError(f"structured region {k!r} is not an axis-aligned rectangle: "
                                 "allowed four vertices joined by horizontal and vertical edges")
        try:
            nx, nz, *r = v
            (r,) = r or (1.0,)
        except (TypeError, ValueError):
            raise ParameterError(f"structured[{k!r}] = {v!r} is not (nx, nz) or "
                                 "(nx, nz, r)") from None
        grid[k] = (int(check_range(f"structured[{k!r}].nx", nx, 1, 10 ** 5)),
                   int(check_range(f"structured[{k!r}].nz", nz, 1, 10 ** 5)),
                   check_range(f"structured[{k!r}].r", r, 0.0, lo_open=True))
    cuts = [_polygon(f"holes[{i}]", v) for i, v in enumerate(holes)]
    inserts = [_name("insert", k) for k in inserts]
    for k in inserts:
        if k not in polys:
            raise ParameterError(f"insert {k!r} is out of range: allowed one of {sorted(polys)}")
    for k in grid:                       # a structured grid cannot take a hole
        lo, hi = polys[k].min(0), polys[k].max(0)
        if any(np.all(P.max(0) > lo) and np.all(P.min(0) < hi)
               for P in cuts + [polys[j] for j in inserts]):
            raise ParameterError(f"holes meet the structured region {k!r}: allowed holes "
                                 "clear of it")
    allp = np.vstack(list(polys.values()))
    extent = float(np.max(allp.max(0) - allp.min(0)))
    check_range("size", size, 0.0, extent, lo_open=True, unit="m")
    tol = 1e-9 * extent

    with gmsh_session(name, verbosity) as gmsh:
        occ = gmsh.model.occ
        def plane(P):
            pt = [occ.addPoint(x, z, 0.0) for x, z in P]
            cv = [occ.addLine(pt[i], pt[(i + 1) % len(pt)]) for i in range(len(pt))]
            return occ.addPlaneSurface([occ.addCurveLoop(cv)])

        surf = [plane(P) for P in polys.values()]
        if cuts or inserts:              # each region less the holes (and the inserts)
            holes_ = [(2, plane(P)) for P in cuts]
            ins = [(2, plane(polys[k])) for k in inserts]
            def cut(k, s):
                tools = holes_ + (ins if k not in inserts else [])
                if not tools:
                    return [s]
                return [t for d, t in occ.cut([(2, s)], tools, removeObject=True,
                                              removeTool=False)[0] if d == 2]

            groups = [cut(k, s) for k, s in zip(polys, surf)]
            occ.remove(holes_ + ins, recursive=True)
        else:
            groups = [[s] for s in surf]
        surf = [t for g in groups for t in g]
        named = [(k, occ.addLine(occ.addPoint(*p, 0.0), occ.addPoint(*q, 0.0)))
                 for k, ss in segs.items() for p, q in ss]
        free = [occ.addLine(occ.addPoint(*p, 0.0), occ.addPoint(*q, 0.0)) for p, q in lines]
        tools = [(1, c) for _, c in named] + [(1, c) for c in free]
        if len(surf) > 1 or tools:
            _, out_map = occ.fragment([(2, s) for s in surf], tools, removeObject=True,
                                      removeTool=True)
        else:                            # one region, nothing to cut it: fragment maps nothing
            out_map = [[(2, surf[0])]]
        occ.synchronize()

        # which new surfaces came from which region; every triangle must belong to one region
        first = np.cumsum([0] + [len(g) for g in groups])
        reg_surf = {k: sorted({t for m in out_map[first[i]:first[i + 1]] for d, t in m
                               if d == 2}) for i, k in enumerate(polys)}
        owners = [t for ts in reg_surf.values() for t in ts]
        if len(owners) != len(set(owners)):
            raise MeshError(f"regions {list(polys)} overlap: allowed disjoint polygons")
        inside = _curves_in_surfaces(gmsh, owners)
        outside = [(1, c) for d, c in gmsh.model.getEntities(1) if c not in inside]
        if outside:                      # parts of named/embedded segments outside the domain
            occ.remove(outside, recursive=True)
            occ.synchronize()
        bnd_curves = {}
        for (k, _), m in zip(named, out_map[len(surf):len(surf) + len(named)]):
            bnd_curves.setdefault(k, set()).update(t for d, t in m if d == 1 and t in inside)
        for k, cs in bnd_curves.items():
            if not cs:
                raise MeshError(f"boundary {k!r}: none of its segments lies in or on the "
                                f"regions {list(polys)}")

        for k, ts in reg_surf.items():
            gmsh.model.addPhysicalGroup(2, ts, name=k)
        for k, cs in bnd_curves.items():
            gmsh.model.addPhysicalGroup(1, sorted(cs), name=k)

        for k, (nx, nz, r) in grid.items():
            _transfinite(gmsh, k, reg_surf[k], nx, nz, r)
        _size_field(gmsh, size, rpts, rsegs, _size_map(size_map))
        gmsh.model.mesh.generate(2)
        return _to_meshio(gmsh, tol)


def _curves_in_surfaces(gmsh, surfaces) -> set[int]:
    """Curves bounding or embedded in the given surfaces."""
    cs = set()
    for s in surfaces:
        cs.update(abs(t) for d, t in gmsh.model.getBoundary([(2, s)], oriented=False) if d == 1)
        cs.update(t for d, t in gmsh.model.mesh.getEmbedded(2, s) if d == 1)
    return cs


def _transfinite(gmsh, region, surfaces, nx, nz, r=1.0):
    """Make the rectangle ``region`` a transfinite surface of nx × nz quadrangles, the
    columns growing by ``r`` from its left side."""
    if len(surfaces) != 1:
        raise MeshError(f"structured region {region!r} is cut into {len(surfaces)} surfaces "
                        "by embedded or named lines: allowed none crossing it")
    s = surfaces[0]
    curves = [abs(t) for d, t in gmsh.model.getBoundary([(2, s)], oriented=False) if d == 1]
    if len(curves) != 4:
        raise MeshError(f"structured region {region!r} has {len(curves)} boundary curves "
                        "after the named lines split it: allowed 4 (a segment ends on a side)")
    for c in curves:
        x0, z0, _, x1, z1, _ = gmsh.model.getBoundingBox(1, c)
        # OCC pads bounding boxes (~1e-7): a side is horizontal if wider than tall
        if x1 - x0 > z1 - z0:
            start = gmsh.model.getBoundary([(1, c)], oriented=True)[0][1]
            xs = gmsh.model.getValue(0, abs(start), [])[0]
            coef = r if abs(xs - x0) < abs(xs - x1) else 1.0 / r
            gmsh.model.mesh.setTransfiniteCurve(c, nx + 1, "Progression", coef)
        else:
            gmsh.model.mesh.setTransfiniteCurve(c, nz + 1)
    gmsh.model.mesh.setTransfiniteSurface(s)
    gmsh.model.mesh.setRecombine(2, s)


def _size_map(sm):
    """Checked (p, t, sizes) of a background size map, or None."""
    if sm is None:
        return None
    try:
        p, t, s = (np.asarray(a) for a in sm)
    except (TypeError, ValueError):
        raise ParameterError("size_map is not (points, triangles, sizes)") from None
    if p.ndim != 2 or p.shape[0] != 2 or t.ndim != 2 or t.shape[0] != 3 or s.shape != t.shape[1:]:
        raise ParameterError(f"size_map has shapes {p.shape}, {t.shape}, {s.shape}: allowed "
                             "(2, n), (3, nt), (nt,)")
    if not np.all(np.isfinite(s)) or np.any(s <= 0):
        raise ParameterError("size_map sizes must be finite and > 0 [m]")
    return p.astype(float), t.astype(int), s.astype(float)


def _size_field(gmsh, size, rpts, rsegs, size_map=None):
    """Background size: min(global, Threshold(distance) for every refinement).

    Distances are MathEval expressions (gmsh's parser has abs and sqrt but no min/max, so
    max(u, 0) is written (u + |u|)/2, and the clamp of t to [0, 1] as t⁺ − (t − 1)⁺).
    """
    fld = gmsh.model.mesh.field
    parts = []

    def threshold(expr, local, radius):
        d = fld.add("MathEval")
        fld.setString(d, "F", expr)
        t = fld.add("Threshold")
        fld.setNumber(t, "InField", d)
        fld.setNumber(t, "SizeMin", min(local, size))
        fld.setNumber(t, "SizeMax", size)
        fld.setNumber(t, "DistMin", radius)
        fld.setNumber(t, "DistMax", 2.0 * radius)
        parts.append(t)

    pos = "((({u}) + abs({u}))/2)"
    for (x0, z0), local, radius in rpts:
        threshold(f"sqrt((x - ({x0!r}))^2 + (y - ({z0!r}))^2)", local, radius)
    for ((x1, z1), (x2, z2)), local, radius in rsegs:
        dx, dz = x2 - x1, z2 - z1
        t = f"((x - ({x1!r}))*({dx!r}) + (y - ({z1!r}))*({dz!r}))/({dx * dx + dz * dz!r})"
        tc = f"({pos.format(u=t)} - {pos.format(u=t + ' - 1')})"
        ex, ez = f"(x - ({x1!r}) - {tc}*({dx!r}))", f"(y - ({z1!r}) - {tc}*({dz!r}))"
        threshold(f"sqrt({ex}^2 + {ez}^2)", local, radius)
    if size_map is not None:       # piecewise-constant sizes on a background triangulation
        p, t, s = size_map
        xyz = np.zeros((9, t.shape[1]))
        xyz[0:3], xyz[3:6] = p[0, t], p[1, t]
        data = np.vstack([xyz, np.repeat(s[None, :], 3, axis=0)]).T.ravel()
        view = gmsh.view.add("size_map")
        gmsh.view.addListData(view, "ST", t.shape[1], data.tolist())
        pv = fld.add("PostView")
        fld.setNumber(pv, "ViewTag", view)
        parts.append(pv)
    const = fld.add("MathEval")
    fld.setString(const, "F", repr(float(size)))
    m = fld.add("Min")
    fld.setNumbers(m, "FieldsList", parts + [const])
    fld.setAsBackgroundMesh(m)
    opt = gmsh.option
    opt.setNumber("Mesh.MeshSizeFromPoints", 0)
    opt.setNumber("Mesh.MeshSizeFromCurvature", 0)
    opt.setNumber("Mesh.MeshSizeExtendFromBoundary", 0)
    opt.setNumber("Mesh.MeshSizeMax", size)
    opt.setNumber("Mesh.Algorithm", 6)         # Frontal-Delaunay: well-shaped triangles


def _to_meshio(gmsh, tol) -> meshio.Mesh:
    """Physical groups of the current model as a meshio.Mesh (unused nodes dropped)."""
    tags, xyz, _ = gmsh.model.mesh.getNodes()
    xyz = xyz.reshape(-1, 3)
    index = np.full(int(tags.max()) + 1, -1)
    index[tags.astype(int)] = np.arange(len(tags))
    blocks, names, centres = [], {}, []
    for dim, ptag in gmsh.model.getPhysicalGroups():
        pname = gmsh.model.getPhysicalName(dim, ptag)
        etype = 2 if dim == 2 else 1
        conn, geo = [], []
        for ent in gmsh.model.getEntitiesForPhysicalGroup(dim, ptag):
            _, ntags = gmsh.model.mesh.getElementsByType(etype, int(ent))
            c = index[ntags.astype(int)].reshape(-1, dim + 1)
            if dim == 2:                  # quadrangles of a structured region: crossed cells
                _, qtags = gmsh.model.mesh.getElementsByType(3, int(ent))
                if len(qtags):
                    q = index[qtags.astype(int)].reshape(-1, 4)
                    mid = len(xyz) + sum(len(m) for m in centres) + np.arange(len(q))
                    centres.append(xyz[q].mean(axis=1))
                    c = np.vstack([c, np.stack([np.stack([q[:, i], q[:, (i + 1) % 4], mid], 1)
                                                for i in range(4)], 1).reshape(-1, 3)])
            conn.append(c)
            geo.append(np.full(len(c), int(ent)))
        conn = np.vstack(conn) if conn else np.zeros((0, dim + 1), int)
        if len(conn) == 0:
            raise MeshError(f"physical group {pname!r} received no elements")
        blocks.append(("triangle" if dim == 2 else "line", conn, ptag, np.concatenate(geo)))
        names[pname] = (ptag, dim)
    if centres:
        xyz = np.vstack([xyz, *centres])
    # compact node numbering; counter-clockwise triangles
    used = np.unique(np.concatenate([c.ravel() for _, c, _, _ in blocks]))
    renum = np.full(len(xyz), -1)
    renum[used] = np.arange(len(used))
    pts = xyz[used].copy()
    pts[:, 2] = 0.0
    cells = []
    for kind, c, _, _ in blocks:
        c = renum[c]
        if kind == "triangle":
            a, b, d = pts[c[:, 0], :2], pts[c[:, 1], :2], pts[c[:, 2], :2]
            cross = (b - a)[:, 0] * (d - a)[:, 1] - (b - a)[:, 1] * (d - a)[:, 0]
            if np.any(np.abs(cross) <= tol * tol):
                raise MeshError("gmsh produced a degenerate triangle")
            c[cross < 0] = c[cross < 0][:, [0, 2, 1]]
        cells.append(meshio.CellBlock(kind, c))
    n = len(blocks)
    cell_sets = {}
    for i, (pname, (ptag, dim)) in enumerate(names.items()):
        cell_sets[pname] = [np.arange(len(cells[j].data)) if j == i else np.zeros(0, int)
                            for j in range(n)]
    return meshio.Mesh(
        pts, cells,
        cell_data={"gmsh:physical": [np.full(len(c.data), b[2]) for c, b in zip(cells, blocks)],
                   "gmsh:geometrical": [b[3] for b in blocks]},
        field_data={k: np.array([t, d]) for k, (t, d) in names.items()},
        cell_sets=cell_sets)


# ---------------------------------------------------------------------------------- T-section

#: the façade columns' growth from the outer face (``graded_columns``, ``problems.t_section``'s
#: h_outer): measured on B1, docs/static.md "The outer face"
OUTER_GROWTH = 1.5


def graded_columns(b: float, h_outer: float, n_b: int = 4, growth: float = OUTER_GROWTH
                   ) -> tuple[int, float]:
    """(n, r): n columns across the width b growing geometrically by r from ``h_outer``
    (h_outer·(rⁿ − 1)/(r − 1) = b), the fewest with r <= ``growth`` and n >= n_b."""
    b = check_range("b", b, 0.0, lo_open=True, unit="m")
    h_outer = check_range("h_outer", h_outer, 0.0, b / max(int(n_b), 1), lo_open=True, unit="m")
    growth = check_range("growth", growth, 1.0, lo_open=True)
    n = max(int(n_b), int(math.ceil(math.log1p(b * (growth - 1.0) / h_outer)
                                    / math.log(growth) - 1e-9)))
    if abs(n * h_outer - b) <= 1e-12 * b:
        return n, 1.0
    lo, hi = 1.0 + 1e-12, growth            # Σ h_outer·r^k = b, increasing in r
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if h_outer * (mid ** n - 1.0) / (mid - 1.0) < b else (lo, mid)
    return n, 0.5 * (lo + hi)


def tsection(H: float, b: float, L: float, size: float, *,
             size_junction: float | None = None, size_top: float | None = None,
             radius_junction: float | None = None, radius_top: float | None = None,
             z0: float = 0.0, embed_lines: Sequence[Segment] = (),
             refine_points: Sequence = (), refine_segments: Sequence = (),
             strip: str = "free", n_b: int = 4, rows: float | None = None,
             h_outer: float | None = None, growth: float = OUTER_GROWTH, size_map=None,
             holes: Sequence = (), lintels: Sequence = (),
             verbosity: int = 0) -> meshio.Mesh:
    """Mesh of the x–z section: façade 0 <= x <= b, transversal wall b <= x <= b + L,
    z0 <= z <= H (the failing part of height h = H − z0 when z0 > 0).

    Regions "facade", "wall"; lines "base" (z = z0), "outer" (x = 0), "top" (z = H),
    "end" (x = b + L) and the interior "junction" (x = b), shared by both regions.
    Element size ``size``, refined to ``size_junction`` within ``radius_junction`` (default b)
    of the junction and to ``size_top`` within ``radius_top`` (default b) of the façade's top
    edge, growing linearly to ``size`` over a further radius. ``embed_lines``: segments the
    mesh must conform to, e.g. rays from a hinge (0, z_h) on the outer face; ``refine_points``
    (x, z, size, radius) and ``refine_segments``: more local refinement (see ``polygon_mesh``).
    ``strip``: "free" (default: the façade strip meshed unstructured like the wall) or
    "structured": the strip is a grid of ``n_b`` columns across b and max(2, ⌈(H − z0)/rows⌉)
    equal rows (``rows`` [m], default ``size``), each cell cut by its diagonals into four
    triangles (the crossed cells of ``problems.crossed_mesh``, edges aligned with x), and the
    wall, unstructured, conforms to its nodes on the junction; no embedded line may cross the
    strip then. ``h_outer`` (with "structured"): the strip's columns grow geometrically from
    width ``h_outer`` at the outer face x = 0 (``graded_columns``: at least n_b columns,
    growth at most ``growth``), where an overturning façade bears (docs/static.md, "The
    outer face"). ``holes``: rectangles (x0, x1, z0, z1) cut out of the wall (its openings,
    ``TSection.holes``), clipped to the part z >= z0; ``lintels``: rectangles of the wall over
    them, regions "lintel<k>" (``TSection.part_lintels``).
    """
    geo = TSection(H, b, L, z0, holes=tuple(holes), lintels=tuple(lintels))
    H, b, z0 = geo.H, geo.b, geo.z0
    size = check_range("size", size, 0.0, geo.span, lo_open=True, unit="m")
    check_choice("strip", strip, STRIPS)
    structured = None
    if strip == "structured":
        n_b = int(check_range("n_b", n_b, 1, 10 ** 4))
        if embed_lines:
            raise ParameterError(f"embed_lines = {list(embed_lines)!r} with strip = "
                                 "'structured' is out of range: allowed none (the strip is a "
                                 "structured grid; use strip = 'free')")
        nx, r = (n_b, 1.0) if h_outer is None else graded_columns(b, h_outer, n_b, growth)
        rows = size if rows is None else check_range("rows", rows, 0.0, geo.height,
                                                     lo_open=True, unit="m")
        structured = {"facade": (nx, max(2, int(math.ceil(geo.height / rows))), r)}
    elif h_outer is not None or rows is not None:
        what = "h_outer" if h_outer is not None else "rows"
        raise ParameterError(f"{what} = {h_outer if h_outer is not None else rows} with strip = "
                             f"{strip!r} is out of range: allowed only with strip = 'structured'")
    refine = []
    seg = geo.boundaries
    for what, s, r, line in (("junction", size_junction, radius_junction, seg["junction"]),
                             ("top", size_top, radius_top, ((0.0, H), (b, H)))):
        if r is not None:
            r = check_range(f"radius_{what}", r, 0.0, lo_open=True, unit="m")
        if s is not None:
            s = check_range(f"size_{what}", s, 0.0, size, lo_open=True, unit="m")
            refine.append((*line, s, b if r is None else r))
    regions = {k: list(v) for k, v in geo.regions.items()}
    lint = geo.part_lintels
    regions |= {k: list(v) for k, v in lint.items()}
    boundaries = {k: [v] for k, v in seg.items()}
    return polygon_mesh(regions, boundaries, size=size,
                        refine_segments=refine + list(refine_segments),
                        refine_points=refine_points, embed_lines=embed_lines,
                        structured=structured, size_map=size_map, name="tsection",
                        holes=geo.hole_polygons, inserts=list(lint), verbosity=verbosity)
