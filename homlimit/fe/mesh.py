"""meshio.Mesh <-> scikit-fem MeshTri with named subdomains and boundaries; files; cache.

- ``to_skfem(m)``: a skfem.MeshTri whose ``subdomains`` {name: element indices} come from the
  triangle cell sets and ``boundaries`` {name: facet indices} from the line cell sets,
  interior lines (the "junction") included.
- ``from_skfem(mesh)``: back to meshio (for writing results on the mesh).
- ``read(path)`` / ``write(mesh, path)``: any format meshio knows; the named sets survive
  .msh (gmsh 2.2: physical groups), .vtu and .xdmf (one 0/1 cell array "set:<name>" per set).
  Files are written whole or not at all (temporary file + os.replace); .xdmf is written with
  inline XML data so that it is a single file.
- ``refined_nested(mesh, marked)``: the marked triangles split (with their conforming
  closure), every old triangle a union of new ones, the named sets kept.
- ``cached(builder, **params)``: a mesh from ``homlimit.fe.geometry`` generated once per set of
  parameters and kept under ``meshes/cache/`` (or $HOMLIMIT_MESH_CACHE).
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
import os
from pathlib import Path

import meshio
import numpy as np

from .._io import atomic_path
from ..errors import HomlimitError, MeshError, ParameterError

__all__ = ["to_skfem", "from_skfem", "read", "write", "cached", "cache_dir", "element_areas",
           "quality", "region_tags", "refined_nested"]

_SET = "set:"


# ---------------------------------------------------------------------------------- sets

def _sets(m: meshio.Mesh) -> dict[str, list[np.ndarray]]:
    """Named cell sets {name: [indices per cell block]}, from whichever encoding is present:
    meshio cell_sets, our "set:<name>" 0/1 cell data, or gmsh physical tags + field_data."""
    if m.cell_sets and any(sum(np.size(i) for i in v) for v in m.cell_sets.values()):
        return {k: [np.asarray(i, int).ravel() for i in v] for k, v in m.cell_sets.items()}
    out = {k[len(_SET):]: [np.flatnonzero(np.asarray(a).ravel()) for a in v]
           for k, v in m.cell_data.items() if k.startswith(_SET)}
    if out:
        return out
    phys = m.cell_data.get("gmsh:physical")
    if phys is not None and m.field_data:
        for k, (tag, dim) in ((k, np.asarray(v).ravel()[:2]) for k, v in m.field_data.items()):
            want = "triangle" if dim == 2 else "line" if dim == 1 else None
            out[k] = [np.flatnonzero(np.asarray(p).ravel() == tag) if c.type == want
                      else np.zeros(0, int) for c, p in zip(m.cells, phys)]
    return out


# ---------------------------------------------------------------------------------- skfem

def to_skfem(m: meshio.Mesh):
    """skfem.MeshTri of the triangles of ``m``, with ``subdomains`` and ``boundaries`` set from
    its named sets (``skfem.io.meshio.from_meshio``; boundary facets sorted).

    Boundaries may be interior lines; every named line must be a mesh edge (else MeshError).
    """
    from skfem import MeshTri
    from skfem.io.meshio import from_meshio

    pts = np.asarray(m.points, float)
    if pts.ndim != 2 or pts.shape[1] not in (2, 3):
        raise MeshError(f"points of shape {pts.shape}: expected (n, 2) or (n, 3)")
    if pts.shape[1] == 3 and np.any(np.abs(pts[:, 2]) > 1e-12 * (1 + np.abs(pts).max())):
        raise MeshError("the mesh is not plane: the third coordinate is not zero")
    tri = np.concatenate([c.data for c in m.cells if c.type == "triangle"] or [np.zeros((0, 3))])
    if len(tri) == 0:
        raise MeshError("the mesh has no triangles")
    if len(np.unique(np.sort(tri, axis=1), axis=0)) != len(tri):
        raise MeshError("the mesh repeats a triangle")
    sets = {k: v for k, v in _sets(m).items() if not k.startswith("gmsh:")}
    cells = [meshio.CellBlock(c.type, np.asarray(c.data, np.int64)) for c in m.cells]
    mesh = from_meshio(meshio.Mesh(pts, cells, cell_sets=sets), ignore_orientation=True)
    lines = {k: sum(len(i) for c, i in zip(m.cells, v) if c.type == "line")
             for k, v in sets.items()}
    bnd = {k: np.unique(v) for k, v in (mesh.boundaries or {}).items()}
    missing = sum(n - len(bnd.get(k, ())) for k, n in lines.items() if n)
    if missing:
        raise MeshError(f"{missing} named line(s) are not edges of the mesh")
    subs = {k: np.asarray(v, np.int64) for k, v in (mesh.subdomains or {}).items()}
    return MeshTri(mesh.p, mesh.t, _boundaries=bnd or None, _subdomains=subs or None)


def from_skfem(mesh) -> meshio.Mesh:
    """meshio.Mesh of a skfem MeshTri: one triangle block and one line block per boundary."""
    pts = np.column_stack([mesh.p.T, np.zeros(mesh.p.shape[1])])
    cells = [meshio.CellBlock("triangle", mesh.t.T.astype(np.int64))]
    bnd = mesh.boundaries or {}
    cells += [meshio.CellBlock("line", mesh.facets[:, np.asarray(ix)].T.astype(np.int64))
              for ix in bnd.values()]
    sets = {}
    for k, ix in (mesh.subdomains or {}).items():
        sets[k] = [np.asarray(ix, int)] + [np.zeros(0, int)] * len(bnd)
    for j, k in enumerate(bnd):
        sets[k] = [np.zeros(0, int) if i != j + 1 else np.arange(len(cells[j + 1].data))
                   for i in range(len(cells))]
    return meshio.Mesh(pts, cells, cell_sets=sets)


# ---------------------------------------------------------------------------------- files

def region_tags(mesh) -> tuple[list[np.ndarray], list[str]]:
    """Per cell block, the 1-based index of the named triangle set holding each cell (0: none),
    and the names of those sets in that order (for a T-section: 1 = facade, 2 = wall)."""
    tags = [np.zeros(len(c.data), np.int32) for c in mesh.cells]
    names = []
    for name, idx in _sets(mesh).items():
        hits = [(j, np.asarray(i, int)) for j, i in enumerate(idx)
                if j < len(mesh.cells) and mesh.cells[j].type == "triangle" and np.size(i)]
        if hits and not name.startswith("gmsh:"):
            names.append(name)
            for j, i in hits:
                tags[j][i] = len(names)
    return tags, names


def write(m: meshio.Mesh, path: str | os.PathLike) -> Path:
    """Write ``m`` to ``path`` (format from the suffix) whole or not at all, without modifying
    ``m``. Point and cell data are kept; named sets become gmsh physical groups (.msh) or 0/1
    cell data "set:<name>" plus an integer cell field "region" (``region_tags``; .vtu, .xdmf).
    A .vtu gets ``m.field_data`` as VTK field data (``_vtu_field_data``: numbers, and text as
    its UTF-8 bytes), which meshio's VTU writer would drop; .xdmf keeps its numeric entries."""
    path = Path(path)
    suffix = path.suffix.lower()
    sets = _sets(m)
    if suffix == ".msh":
        out, kw = _with_physical(m, sets), {"file_format": "gmsh22", "binary": False}
    else:
        data = {k: list(v) for k, v in m.cell_data.items() if not k.startswith(_SET)}
        sets = {k: v for k, v in sets.items() if not k.startswith("gmsh:")}
        if sets:
            data["region"] = region_tags(m)[0]
        for name, idx in sets.items():
            cols = []
            for c, i in zip(m.cells, idx):
                a = np.zeros(len(c.data), np.int32)
                a[np.asarray(i, int)] = 1
                cols.append(a)
            data[_SET + name] = cols
        numeric = {k: np.asarray(v) for k, v in m.field_data.items() if not isinstance(v, str)}
        out = meshio.Mesh(m.points, m.cells, point_data=dict(m.point_data), cell_data=data,
                          field_data={} if suffix == ".vtu" else numeric)
        kw = {"data_format": "XML"} if suffix == ".xdmf" else {}
    try:
        with atomic_path(path) as tmp:
            meshio.write(tmp, out, **kw)
            if suffix == ".vtu" and m.field_data:
                _vtu_field_data(tmp, m.field_data)
    except Exception as exc:
        if isinstance(exc, HomlimitError):  # MeshError, or OutputError (disk full, EFBIG)
            raise
        raise MeshError(f"could not write mesh to {path}: {exc}") from exc
    return path


def _vtu_field_data(path: Path, field_data: dict):
    """Put ``field_data`` into the .vtu at ``path`` as the grid's FieldData (VTK XML, ascii
    arrays, which ParaView shows under "Field Data" and ``meshio.read`` returns as
    ``field_data``). Numbers become Float64 or Int64 arrays; a string becomes a UInt8 array of
    its UTF-8 bytes (read it back with ``bytes(a).decode()``: meshio reads no VTK String
    arrays), repeated as plain text in an XML comment for a reader of the file itself."""
    arrays, notes = [], []
    for name, value in field_data.items():
        if isinstance(value, str):
            raw = np.frombuffer(value.encode("utf-8"), np.uint8)
            kind, text = "UInt8", " ".join(map(str, raw.tolist()))
            notes.append(f"{name}: {value}".replace("--", "- -"))
        else:
            a = np.asarray(value).ravel()
            kind = "Float64" if a.dtype.kind == "f" else "Int64"
            text = " ".join(repr(float(x)) if kind == "Float64" else str(int(x)) for x in a)
            raw = a
        arrays.append(f'<DataArray type="{kind}" Name="{_xml_attr(name)}" '
                      f'NumberOfTuples="{len(raw)}" format="ascii">{text}</DataArray>')
    comment = "".join(f"\n<!-- {n} -->" for n in notes)
    block = f"\n<FieldData>{comment}\n" + "\n".join(arrays) + "\n</FieldData>"
    body = path.read_bytes()
    tag = b"<UnstructuredGrid>"
    if body.count(tag) != 1:  # pragma: no cover - meshio's layout changed
        raise MeshError(f"cannot add field data to {path.name}: no single {tag.decode()}")
    path.write_bytes(body.replace(tag, tag + block.encode("utf-8"), 1))


def _xml_attr(text: str) -> str:
    from xml.sax.saxutils import escape

    return escape(text, {'"': "&quot;"})


def _with_physical(m: meshio.Mesh, sets) -> meshio.Mesh:
    """A copy in which every named set is its own cell block tagged by a physical group."""
    if "gmsh:physical" in m.cell_data and m.field_data:
        return m
    cells, phys, fdata = [], [], {}
    for tag, (name, idx) in enumerate(sets.items(), start=1):
        for c, i in zip(m.cells, idx):
            if len(i):
                cells.append(meshio.CellBlock(c.type, c.data[np.asarray(i, int)]))
                phys.append(np.full(len(i), tag))
                fdata[name] = np.array([tag, 2 if c.type == "triangle" else 1])
    return meshio.Mesh(m.points, cells, cell_data={"gmsh:physical": phys,
                                                   "gmsh:geometrical": phys},
                       field_data=fdata)


def read(path: str | os.PathLike) -> meshio.Mesh:
    """Read a mesh; its named sets are restored as ``cell_sets`` whatever the format."""
    path = Path(path)
    if not path.is_file():
        raise ParameterError(f"path = {str(path)!r} is not an existing mesh file")
    try:
        m = meshio.read(path)
    except Exception as exc:
        raise MeshError(f"could not read mesh {path}: {exc}") from exc
    sets = _sets(m)
    data = {k: v for k, v in m.cell_data.items() if not k.startswith(_SET)}
    return meshio.Mesh(m.points, m.cells, cell_data=data, field_data=m.field_data,
                       cell_sets=sets)


# ---------------------------------------------------------------------------------- cache

def cache_dir() -> Path:
    """$HOMLIMIT_MESH_CACHE, else meshes/cache/ of the source tree the package runs from (a
    checkout: homlimit/ beside meshes/ and pyproject.toml), else ~/.cache/homlimit/meshes."""
    env = os.environ.get("HOMLIMIT_MESH_CACHE")
    if env:
        return Path(env)
    repo = Path(__file__).resolve().parents[2]          # homlimit/fe/mesh.py → the tree
    if (repo / "meshes").is_dir() and (repo / "pyproject.toml").is_file():
        return repo / "meshes" / "cache"
    return Path.home() / ".cache" / "homlimit" / "meshes"


def cached(builder: str = "tsection", directory: str | os.PathLike | None = None,
           **params) -> meshio.Mesh:
    """The mesh ``homlimit.fe.geometry.<builder>(**params)``, generated once and read afterwards.

    The file name is a hash of the builder name, its parameters and the gmsh version.
    """
    from . import geometry

    build = getattr(geometry, builder, None)
    if builder not in ("tsection", "polygon_mesh") or build is None:
        raise ParameterError(f"builder = {builder!r} is not a mesh builder: allowed "
                             "'tsection', 'polygon_mesh'")
    import gmsh

    key = json.dumps({"builder": builder, "params": params, "gmsh": gmsh.__version__},
                     sort_keys=True, default=_jsonable)
    digest = hashlib.sha256(key.encode()).hexdigest()[:20]
    path = Path(directory) if directory is not None else cache_dir()
    path = path / f"{builder}-{digest}.msh"
    if path.is_file():
        return read(path)
    m = build(**params)
    write(m, path)
    return read(path)


def _jsonable(x):
    if isinstance(x, np.ndarray | np.generic):
        return x.tolist()
    raise TypeError(f"mesh parameter {x!r} is not JSON-serialisable")


# ---------------------------------------------------------------------------- refinement

def refined_nested(mesh, marked) -> object:
    """``mesh`` with the triangles ``marked`` (indices) split by scikit-fem's adaptive
    refinement (red–green–blue, with the closure that keeps the mesh conforming), named
    subdomains and boundaries kept. The new mesh is nested in the old: its vertices start with
    the old ones, every old triangle is a union of new ones and every old named facet is a new
    facet or the two halves of it, so a P2 space on it contains the old one."""
    marked = np.asarray(marked, int)
    if marked.size == 0:
        return mesh
    if marked.min() < 0 or marked.max() >= mesh.t.shape[1]:
        raise ParameterError(f"marked triangles {marked.min()}..{marked.max()} are out of "
                             f"range: allowed 0..{mesh.t.shape[1] - 1}")
    # skfem drops the named facets (and logs it); they are put back below
    new = dataclasses.replace(mesh, _boundaries=None).refined(marked)
    n_old = mesh.p.shape[1]
    if not np.array_equal(new.p[:, :n_old], mesh.p):
        raise MeshError("refined_nested: the refined mesh does not keep the old vertices first")
    if not mesh.boundaries:
        return new
    nv = new.p.shape[1]
    keys = np.sort(new.facets, axis=0)
    keys = keys[0] * nv + keys[1]
    order = np.argsort(keys)

    def facet_of(a, b):   # new facet index of the vertex pairs (a, b), −1 where none
        k = np.minimum(a, b) * nv + np.maximum(a, b)
        i = np.minimum(np.searchsorted(keys, k, sorter=order), keys.size - 1)
        return np.where(keys[order[i]] == k, order[i], -1)

    from scipy.spatial import cKDTree
    tree = cKDTree(new.p[:, n_old:].T) if nv > n_old else None
    named = {}
    for name, facets in mesh.boundaries.items():
        a, b = mesh.facets[:, facets]
        same = facet_of(a, b)
        split = same < 0
        if split.any():
            mid = 0.5 * (mesh.p[:, a[split]] + mesh.p[:, b[split]])
            dist, m = tree.query(mid.T)
            m = m + n_old
            halves = np.concatenate([facet_of(a[split], m), facet_of(m, b[split])])
            if np.any(dist > 1e-9 * (1.0 + np.abs(mid).max())) or np.any(halves < 0):
                raise MeshError(f"refined_nested: boundary {name!r} not recovered")
            named[name] = np.sort(np.concatenate([same[~split], halves]))
        else:
            named[name] = np.sort(same)
    return new.with_boundaries(named)


# ---------------------------------------------------------------------------------- measures

def element_areas(mesh) -> np.ndarray:
    """Areas of the triangles of a skfem MeshTri (which sorts each element's node indices, so
    their orientation is not kept)."""
    p, t = mesh.p, mesh.t
    a, b, c = p[:, t[0]], p[:, t[1]], p[:, t[2]]
    return 0.5 * np.abs((b - a)[0] * (c - a)[1] - (b - a)[1] * (c - a)[0])


def quality(mesh) -> dict:
    """Element count, total area, smallest and largest angle [deg], edge-length range [m]."""
    p, t = mesh.p, mesh.t
    e = [p[:, t[(i + 2) % 3]] - p[:, t[(i + 1) % 3]] for i in range(3)]   # edge opposite i
    ln = np.array([np.hypot(*v) for v in e])
    cosang = np.array([-(e[(i + 1) % 3] * e[(i + 2) % 3]).sum(0)
                       / (ln[(i + 1) % 3] * ln[(i + 2) % 3]) for i in range(3)])
    ang = np.degrees(np.arccos(np.clip(cosang, -1, 1)))
    return {"n_elements": int(t.shape[1]), "area": float(element_areas(mesh).sum()),
            "min_angle_deg": float(ang.min()), "max_angle_deg": float(ang.max()),
            "h_min": float(ln.min()), "h_max": float(ln.max())}
