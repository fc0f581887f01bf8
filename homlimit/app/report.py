"""What a run shows and writes: the terminal summary, plain-text tables, the result meshes and
one writer per file format.

``write(path, data)`` picks the writer from the file's suffix (``WRITERS``): JSON data, CSV
records, a meshio mesh (.vtu, .xdmf, .msh) or a picture (a function that draws to a path).
Every writer is whole-or-nothing (``homlimit._io``).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from pathlib import Path

import numpy as np

from .._io import write_csv, write_json
from ..errors import ParameterError
from ..fe import mesh as fe_mesh

__all__ = ["WRITERS", "format_spectra", "format_table", "mechanism_mesh", "summary_text",
           "write"]

WRITERS: dict[str, Callable] = {
    ".json": write_json, ".csv": write_csv, ".png": lambda path, draw: draw(path),
    **dict.fromkeys((".vtu", ".xdmf", ".msh"), lambda path, mesh: fe_mesh.write(mesh, path))}


def write(path: str | Path, data) -> Path:
    """Write ``data`` to ``path`` with the writer of its suffix (``WRITERS``)."""
    path = Path(path)
    writer = WRITERS.get(path.suffix.lower())
    if writer is None:
        raise ParameterError(f"file suffix = {path.suffix!r} is out of range: allowed one of "
                             + ", ".join(WRITERS))
    writer(path, data)
    return path


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


def format_spectra(points, title: str | None = None) -> str:
    """The overturning spectra (``dynamics.SpectrumPoint``) as a text table: pulse, mechanism,
    polarity, T_p, critical pga/g, pgv, pgv/√(gb), pgv over eq. 7's v̄_g, impacts."""
    rows = [[p.pulse, p.mechanism, p.polarity, p.period, p.pga_g, p.pgv, p.vnorm, p.ratio,
             p.n_impacts] for p in points]
    return format_table(["pulse", "mech", "pol", "T_p [s]", "pga/g", "pgv [m/s]",
                         "pgv/sqrt(gb)", "pgv/vg(eq.7)", "impacts"], rows, title)


# ----------------------------------------------------------------------------- the summary
def summary_text(result) -> str:
    """A readable terminal table of a ``pipeline.Result``: each mechanism's λ, h, v̄_g and
    v̄_g/√(gb) beside the paper's DEM value, the FE details, the governing mechanism, files."""
    c = result.case
    rows = [[m.label, m.lam, m.h, m.vg, m.vnorm] for m in result.mechanisms.values()]
    if result.dem:
        d = result.dem
        rows.append(["DEM, paper's Table 1", d.lam_v, d.h_v, d.vg, d.vg_norm])
    head = (f"case {result.name}: H={c.wall.H:g} m, L={c.wall.L:g} m, s={c.wall.s:g} m, "
            f"b={c.wall.b:g} m, l={c.wall.l:g} m; a={c.masonry.a:g} m, c={c.masonry.c:g} m, "
            f"f={c.masonry.f:g}\n"
            f"  rho=l/s={c.rho:.4g}  alpha^2=cf/a={c.alpha ** 2:.4g}  beta=c/b={c.beta:.4g}"
            f"  (eq. 11)")
    out = [head, "", format_table(["mechanism", "lambda=h/b", "h [m]", "vg [m/s]",
                                   "vg/sqrt(gb)"], rows)]
    statics = [f"{k} {m.multiplier:.4g} at h = {m.lam_multiplier * c.wall.b:.2f} m"
               for k, m in result.mechanisms.items() if k in ("I", "II")]
    if statics:
        out += ["", "collapse acceleration a/g of a static check (smallest over h): "
                + "; ".join(statics)]
    if result.fe:
        out += ["", _fe_lines(result.fe, c)]
    if result.hinges:
        out += ["", _hinge_lines(result, c.masonry.f)]
    crit = result.critical()
    if crit:
        out += ["", f"governing: {crit['mechanism']}, collapse ground velocity "
                    f"vg = {crit['vg']:.3f} m/s (vg/sqrt(gb) = {crit['vnorm']:.3f})"]
    if result.files:
        out += ["", "files:"] + [f"  {v}" for v in result.files.values()]
    return "\n".join(out)


def _num(x, fmt=".3f") -> str:
    return "–" if x is None or not math.isfinite(x) else format(x, fmt)


def _fe_lines(fe, case) -> str:
    """The FE block of the summary: the whole wall, its bracket, hinge, crack and scan."""
    full, crit = fe.whole, fe.critical
    e1, e2 = full.tanpsi_edges
    lines = [f"FE, whole wall: {full.n_triangles} triangles, façade {full.facade}, "
             f"collapse multiplier {_num(full.multiplier, '.4g')} (acceleration / g)"]
    if fe.static is not None:
        lines.append(f"  bracket: static {_num(fe.lower_bound, '.4g')} <= multiplier <= "
                     f"kinematic {_num(full.multiplier, '.4g')} (gap "
                     f"{100 * fe.bracket_rel_gap:.1f} %, same mesh)")
    lines += [f"  {full.kind} mechanism, hinge at x = {_num(full.O[0], '.2f')} m, "
              f"z = {_num(full.O[1], '.2f')} m",
              f"  crack: tan psi = {_num(full.tanpsi)} ± {_num(full.tanpsi_uncertainty)} "
              f"(50 % line), edges {_num(e1)} .. {_num(e2)}",
              f"         sqrt(cf/a) = {case.alpha:.3f} (eq. 16), f = {case.masonry.f:.3f}, "
              f"c/a = {case.masonry.c / case.masonry.a:.3f}"]
    if crit is not None:
        lines += [f"  impulse: lowest vg over {len(fe.scan)} heights of the failing part "
                  f"({fe.h_min:g} m, one course, to H) at h = {_num(crit.h, '.2f')} m: "
                  f"{fe.critical_at}", f"         ({crit.vg_method})"]
    return "\n".join(lines)


def _hinge_lines(result, f: float) -> str:
    """The hinge under the ideal impulse: |P_x/P_z| against f, and the shortest rectangular
    pulse of a_g = f g that still overturns each mechanism."""
    rows = [[k, result.mechanisms[k].hinge_ratio, "yes" if result.mechanisms[k].hinge_ratio > f
             else "no", h.duration, h.pgv, h.ratio] for k, h in result.hinges.items()]
    out = [format_table(["mechanism", "|Px/Pz|", "slides", "holding pulse [s]", "pgv [m/s]",
                         "pgv/vg"], rows,
                        title=f"hinge under the ideal impulse (it slides where |Px/Pz| > "
                              f"f = {f:g}) and the shortest rectangular pulse of a_g = f g "
                              "that still overturns")]
    slid = [k for k, r in zip(result.hinges, rows) if r[2] == "yes"]
    if slid:
        out.append(f"  the ideal-impulse vg of {', '.join(slid)} is not attainable without the "
                   "hinge sliding: a pulse the hinge holds needs the pgv above")
    out += [f"  {k}: {h.reason}" for k, h in result.hinges.items() if h.reason]
    return "\n".join(out)


# ----------------------------------------------------------------------------- result meshes
def mechanism_mesh(fe):
    """The whole wall's mechanism as a meshio mesh for ParaView: the solution's fields
    (velocity, dissipation, intensity, region, stress estimate), the block participation and
    label per triangle, the detected crack (the 50 % line) as a line block, the failing body
    (inside the 50 % line) as a triangle block of its own (cell fields ``body`` = 1 and its
    ``density`` [kg/m²]) and, with the static bound, its stress field (``static_*``) and each
    triangle's share of the bracket's gap."""
    import meshio

    from ..fe.bracket import gap_contributions
    from ..fe.static import attach_cell_fields

    full = fe.whole
    m = full.solution.to_meshio()
    crack = full.drawing()["crack"]
    cells = [meshio.CellBlock("triangle", m.cells[0].data)]
    data = {k: [np.asarray(v[0], float)] for k, v in m.cell_data.items()}
    data["participation"] = [np.asarray(full.measures.participation, float)]
    data["label"] = [np.asarray(full.measures.label, float)]
    pts = m.points
    if crack is not None and len(crack) > 1:
        k0 = len(pts)
        pts = np.vstack([pts, np.c_[crack, np.zeros(len(crack))]])
        cells.append(meshio.CellBlock("line", np.c_[np.arange(len(crack) - 1),
                                                    np.arange(1, len(crack))] + k0))
        for v in data.values():
            v.append(np.full((len(crack) - 1,) + v[0].shape[1:], np.nan))
        data["crack"] = [np.zeros(len(cells[0].data)), np.ones(len(crack) - 1)]
    body, rho = full.body_pieces()                # the failing body: its own triangle block
    k0, nb = len(pts), len(body)
    pts = np.vstack([pts, np.c_[body.reshape(-1, 2), np.zeros(3 * nb)]])
    cells.append(meshio.CellBlock("triangle", k0 + np.arange(3 * nb).reshape(-1, 3)))
    for v in data.values():
        v.append(np.full((nb,) + v[0].shape[1:], np.nan))
    data["body"] = [np.zeros(len(c.data)) for c in cells[:-1]] + [np.ones(nb)]
    data["density"] = [np.full(len(c.data), np.nan) for c in cells[:-1]] + [rho]
    pdata = {k: np.vstack([v, np.zeros((len(pts) - len(v),) + v.shape[1:])])
             for k, v in m.point_data.items()}
    out = meshio.Mesh(pts, cells, point_data=pdata, cell_data=data)
    if fe.static is not None:
        out = attach_cell_fields(out, fe.static)
        gap = gap_contributions(fe.static, full.solution)  # share of λ⁺ − λ⁻ (virtual power)
        out.cell_data["bracket_gap"] = [gap] + [np.full(len(b.data), np.nan)
                                                for b in out.cells[1:]]
    return out
