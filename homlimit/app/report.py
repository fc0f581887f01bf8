"""Result files and the terminal summary.

Every writer is atomic: it writes a temporary file in the destination folder and renames it over
the target with ``os.replace``, so a file is either whole or absent (a crash or an error while
writing leaves the previous file, or nothing). JSON summaries are plain data: numpy scalars and
arrays become numbers and lists, non-finite floats become ``null``.
"""

from __future__ import annotations

import csv
import io
import json
import math
from collections.abc import Callable, Iterable, Mapping
from pathlib import Path

import numpy as np

from .._io import atomic_path

__all__ = ["atomic_path", "format_table", "to_jsonable", "write_csv", "write_json",
           "region_tags", "write_figure", "write_text",
           "write_vtu"]


def write_text(path: str | Path, text: str) -> Path:
    """Write ``text`` (UTF-8) to ``path`` atomically."""
    with atomic_path(path) as tmp:
        tmp.write_text(text, encoding="utf-8")
    return Path(path)


def to_jsonable(obj):
    """Plain JSON data from dataclass-free nested containers of numbers, numpy values, paths."""
    if isinstance(obj, Mapping):
        return {str(k): to_jsonable(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [to_jsonable(v) for v in obj]
    if isinstance(obj, np.ndarray):
        return to_jsonable(obj.tolist())
    if isinstance(obj, (bool, np.bool_)):
        return bool(obj)
    if isinstance(obj, (int, np.integer)):
        return int(obj)
    if isinstance(obj, (float, np.floating)):
        x = float(obj)
        return x if math.isfinite(x) else None
    if isinstance(obj, Path):
        return str(obj)
    if obj is None or isinstance(obj, str):
        return obj
    raise TypeError(f"cannot write {type(obj).__name__} to JSON: {obj!r}")


def write_json(path: str | Path, data) -> Path:
    """Write ``data`` as indented JSON, atomically."""
    return write_text(path, json.dumps(to_jsonable(data), indent=2, ensure_ascii=False) + "\n")


def write_csv(path: str | Path, records: Iterable[Mapping], columns: list[str] | None = None
              ) -> Path:
    """Write a list of flat records as CSV with a header row, atomically."""
    records = [to_jsonable(r) for r in records]
    if columns is None:
        columns = list(dict.fromkeys(k for r in records for k in r))
    buf = io.StringIO()
    w = csv.DictWriter(buf, fieldnames=columns, extrasaction="raise", lineterminator="\n")
    w.writeheader()
    for r in records:
        w.writerow({k: ("" if r.get(k) is None else r.get(k)) for k in columns})
    return write_text(path, buf.getvalue())


def region_tags(mesh) -> list[np.ndarray]:
    """Per cell block, the 1-based index of the named triangle set holding each cell (0: none).

    The order of the sets is that of ``mesh.cell_sets`` restricted to sets holding triangles
    (for a T-section: 1 = facade, 2 = wall)."""
    sets = {k: v for k, v in (mesh.cell_sets or {}).items() if not k.startswith("gmsh:")}
    tags = [np.zeros(len(c.data), np.int32) for c in mesh.cells]
    k = 0
    for name, idx in sets.items():
        hits = [(j, np.asarray(i, int)) for j, i in enumerate(idx)
                if j < len(mesh.cells) and mesh.cells[j].type == "triangle" and np.size(i)]
        if hits:
            k += 1
            for j, i in hits:
                tags[j][i] = k
    return tags


def write_vtu(path: str | Path, mesh) -> Path:
    """Write a meshio.Mesh as VTU for ParaView, atomically, without modifying ``mesh``.

    Point and cell data are kept; named sets become 0/1 cell data "set:<name>" (the encoding
    ``homlimit.fe.mesh.read`` restores as cell_sets) and an integer cell field "region"
    (see ``region_tags``)."""
    import meshio

    data = {k: list(v) for k, v in mesh.cell_data.items()}
    sets = {k: v for k, v in (mesh.cell_sets or {}).items() if not k.startswith("gmsh:")}
    if sets:
        data["region"] = region_tags(mesh)
        for name, idx in sets.items():
            cols = [np.zeros(len(c.data), np.int32) for c in mesh.cells]
            for j, i in enumerate(idx[:len(cols)]):
                cols[j][np.asarray(i, int)] = 1
            data[f"set:{name}"] = cols
    copy = meshio.Mesh(mesh.points, mesh.cells, point_data=dict(mesh.point_data),
                       cell_data=data, field_data=dict(mesh.field_data))
    with atomic_path(path) as tmp:
        meshio.write(tmp, copy, file_format="vtu")
    return Path(path)


def write_figure(path: str | Path, draw: Callable[[Path], None]) -> Path:
    """Run ``draw(tmp_path)`` (which saves a picture there), then rename onto ``path``."""
    with atomic_path(path) as tmp:
        draw(tmp)
    return Path(path)


def _fmt(x) -> str:
    if x is None:
        return "–"
    if isinstance(x, bool):
        return "yes" if x else "no"
    if isinstance(x, (int, np.integer)):
        return str(int(x))
    if isinstance(x, (float, np.floating)):
        x = float(x)
        if not math.isfinite(x):
            return "–"
        return f"{x:.4g}" if (x == 0 or 1e-3 <= abs(x) < 1e5) else f"{x:.3e}"
    return str(x)


def format_table(header: list[str], rows: list[list], title: str | None = None) -> str:
    """A plain-text table with aligned columns (numbers to 4 significant digits)."""
    cells = [[_fmt(c) for c in r] for r in rows]
    widths = [max([len(h)] + [len(r[i]) for r in cells]) for i, h in enumerate(header)]
    line = "  ".join("-" * w for w in widths)
    out = [] if title is None else [title]
    out += ["  ".join(h.ljust(w) for h, w in zip(header, widths)), line]
    out += ["  ".join(c.rjust(w) if i else c.ljust(w) for i, (c, w) in
                      enumerate(zip(r, widths))) for r in cells]
    return "\n".join(out)
