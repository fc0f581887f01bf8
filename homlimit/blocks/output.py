"""Files of a rigid-block analysis: VTU of the blocks and of the contacts, the contact forces as
records, and a PNG of the mechanism with its open and sliding joints.

Every file is written whole or not at all (``homlimit._io``, ``fe.mesh.write``). The contact
records become blocks_contacts.csv through the one writer of result tables (the front door's
``app.report.write``: headers with units, schema sidecar), not here. matplotlib is imported
lazily with the Agg backend.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from ..fe.mesh import write
from .geometry import KIND_NAMES, Assembly
from .limit import STATE_NAMES, BlockLimitResult, check_result

__all__ = ["blocks_mesh", "contacts_mesh", "write_blocks_vtu", "write_contacts_vtu",
           "contact_records", "plot_blocks_mechanism"]


def blocks_mesh(assembly: Assembly, result: BlockLimitResult, body_mask=None):
    """meshio.Mesh with one polygon cell per block (cell blocks grouped by vertex count, in
    block order within each group). Point data "velocity" (each block has its own vertices,
    so the rigid-block field is discontinuous across joints, as it is). Cell data: "block"
    (index), "u", "w", "omega" [m/s, m/s, 1/s], "speed" (fastest vertex), "moving", "body"
    (the failing rigid body, if ``body_mask`` is given), "fixed", "kind" (``KIND_NAMES``),
    "course", "mass" [kg]."""
    import meshio

    check_result(assembly, result)
    vv = result.vertex_velocity(assembly)
    counts = np.diff(assembly.offsets)
    speed = result.speed(assembly)
    body = np.zeros(assembly.n_blocks, bool) if body_mask is None else np.asarray(body_mask)
    pts = np.c_[assembly.vertices, np.zeros(len(assembly.vertices))]
    cells, data = [], {k: [] for k in ("block", "u", "w", "omega", "speed", "moving", "body",
                                       "fixed", "kind", "course", "mass")}
    for k in np.unique(counts):
        idx = np.flatnonzero(counts == k)
        conn = assembly.offsets[idx][:, None] + np.arange(k)
        cells.append(("polygon", conn))
        q = result.velocity[idx]
        for name, val in (("block", idx), ("u", q[:, 0]), ("w", q[:, 1]), ("omega", q[:, 2]),
                          ("speed", speed[idx]), ("moving", result.moving[idx].astype(np.int8)),
                          ("body", body[idx].astype(np.int8)),
                          ("fixed", assembly.fixed[idx].astype(np.int8)),
                          ("kind", assembly.kind[idx]), ("course", assembly.course[idx]),
                          ("mass", assembly.mass[idx])):
            data[name].append(np.asarray(val))
    return meshio.Mesh(pts, cells, point_data={"velocity": np.c_[vv, np.zeros(len(vv))]},
                       cell_data=data,
                       field_data={"multiplier": np.array([result.multiplier])})


def contacts_mesh(assembly: Assembly, result: BlockLimitResult):
    """meshio.Mesh of the active interfaces as line cells (two points each). Point data at the
    end points: "normal_force" N and "shear_force" T [N per slab], "opening" δ_n and "slip"
    δ_t [m/s], "force" (the vector N n + T t on block b). Cell data: "state" (0 closed,
    1 open, 2 sliding), "block_a", "block_b"."""
    import meshio

    check_result(assembly, result)
    jt = assembly.interfaces
    act = np.flatnonzero(result.active)
    p = jt.p[act].reshape(-1, 2)
    F = (result.normal[act][..., None] * jt.n[act][:, None, :]
         + result.shear[act][..., None] * jt.t[act][:, None, :]).reshape(-1, 2)
    z = np.zeros(len(p))
    return meshio.Mesh(
        np.c_[p, z], [("line", np.arange(2 * act.size).reshape(-1, 2))],
        point_data={"normal_force": result.normal[act].ravel(),
                    "shear_force": result.shear[act].ravel(),
                    "opening": result.opening[act].ravel(), "slip": result.slip[act].ravel(),
                    "force": np.c_[F, z]},
        cell_data={"state": [result.state[act]], "block_a": [jt.a[act]],
                   "block_b": [jt.b[act]]})


def write_blocks_vtu(path, assembly: Assembly, result: BlockLimitResult, body_mask=None) -> Path:
    """``blocks_mesh`` as a .vtu file (ParaView: colour by "speed" or "velocity"), through
    the one mesh writer (``fe.mesh.write``)."""
    return write(blocks_mesh(assembly, result, body_mask), path)


def write_contacts_vtu(path, assembly: Assembly, result: BlockLimitResult) -> Path:
    """``contacts_mesh`` as a .vtu file (``fe.mesh.write``)."""
    return write(contacts_mesh(assembly, result), path)


def contact_records(assembly: Assembly, result: BlockLimitResult) -> list[dict]:
    """One record per end point of every active interface: interface, end, block_a, block_b,
    x, z [m], n_x, n_z, N, T [N per slab; force of a on b = N n + T t], opening, slip [m/s],
    state ("closed", "open", "sliding"): the rows of blocks_contacts.csv
    (``studies.BlocksAnalysis.files``)."""
    check_result(assembly, result)
    jt = assembly.interfaces
    act = np.flatnonzero(result.active)
    k = np.repeat(act, 2)
    e = np.tile([0, 1], act.size)
    p = jt.p[k, e]
    cols = {"interface": k, "end": e, "block_a": jt.a[k], "block_b": jt.b[k], "x": p[:, 0],
            "z": p[:, 1], "n_x": jt.n[k, 0], "n_z": jt.n[k, 1], "N": result.normal[k, e],
            "T": result.shear[k, e], "opening": result.opening[k, e],
            "slip": result.slip[k, e]}
    state = [STATE_NAMES[int(s)] for s in result.state[k]]
    return [{**{c: v[i].item() for c, v in cols.items()}, "state": state[i]}
            for i in range(k.size)]


def plot_blocks_mechanism(path, assembly: Assembly, result: BlockLimitResult, body_mask=None,
                          O=None, title: str | None = None, scale: float | None = None,  # noqa: E741
                          zmin: float | None = None, rays=()) -> Path:
    """PNG of the mechanism: blocks in the displaced configuration (displacement = ``scale`` ×
    velocity, default: the fastest vertex moves by 4 % of the drawing's height), coloured by
    speed (fixed blocks grey; block edges drawn up to 3000 blocks); open joints red, sliding
    joints blue; the failing body outlined and the rotation centre O marked, if given.
    zmin: lower edge of the view; rays: lines x − x0 = T (z − z0) from (x0, z0) to the top,
    given as (x0, z0, T, label), e.g. the edges of a hinge + fan (``fan.optimise_fan``)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.collections import LineCollection, PolyCollection

    from .._io import write_figure

    check_result(assembly, result)
    vv = result.vertex_velocity(assembly)
    vmax = float(np.hypot(vv[:, 0], vv[:, 1]).max()) or 1.0
    bb = assembly.bounds()
    real = ~assembly.fixed | (assembly.kind != 0)
    height = float(bb[real, 3].max() - max(bb[real, 1].min(), 0.0))
    s = (0.04 * height / vmax) if scale is None else float(scale)
    X = assembly.vertices + s * vv
    speed = result.speed(assembly) / vmax
    show = assembly.kind != 0
    polys = [X[assembly.offsets[i]:assembly.offsets[i + 1]] for i in np.flatnonzero(show)]
    fig, ax = plt.subplots(figsize=(7.5, 7.5 * min(2.0, max(0.6, height / max(
        float(np.ptp(bb[show][:, [0, 2]])), 1e-9)))))
    try:
        cmap = matplotlib.colormaps["viridis"].with_extremes(bad="0.85")
        # above 3000 blocks the edges take their block's colour (no hairline gaps, no moiré)
        few = len(polys) <= 3000
        col = PolyCollection(polys, cmap=cmap, edgecolors="0.35" if few else "face",
                             linewidths=0.25 if few else 0.3)
        col.set_array(np.where(assembly.fixed[show], np.nan, speed[show]))
        col.set_clim(0.0, 1.0)
        ax.add_collection(col)
        fig.colorbar(col, ax=ax, shrink=0.7, label="block speed / max (fastest vertex)")
        jt = assembly.interfaces
        for state, colour, lw, label in ((1, "tab:red", 1.4, "open joint"),
                                         (2, "tab:blue", 1.8, "sliding joint")):
            sel = np.flatnonzero((result.state == state) & result.active)
            if sel.size:
                seg = jt.p[sel]          # drawn in the initial position of the joint
                ax.add_collection(LineCollection(seg, colors=colour, linewidths=lw,
                                                 label=f"{label} ({sel.size})"))
        if body_mask is not None and np.any(body_mask):
            bm = np.flatnonzero(body_mask)
            ax.add_collection(PolyCollection(
                [X[assembly.offsets[i]:assembly.offsets[i + 1]] for i in bm],
                facecolors="none", edgecolors="white", linewidths=0.6))
        ztop = float(bb[show][:, 3].max())
        for (x0, z0, T, label), ls in zip(rays, ("--", ":", "-.", (0, (5, 1)))):
            ax.plot([x0, x0 + T * (ztop - z0)], [z0, ztop], color="tab:orange", ls=ls, lw=1.3,
                    label=label)
        if O is not None and all(math.isfinite(v) for v in O):
            ax.plot([O[0]], [O[1]], marker="o", color="tab:orange", ms=7, mec="k",
                    label=f"rotation centre O ({O[0]:.2f}, {O[1]:.2f}) m", ls="none")
        lo = bb[show]
        ax.set_xlim(lo[:, 0].min() - 0.03 * height, lo[:, 2].max() + 0.03 * height)
        z0 = lo[:, 1].min() if zmin is None else zmin
        ax.set_ylim(z0 - 0.03 * height, lo[:, 3].max() + 0.06 * height)
        ax.set_aspect("equal")
        ax.set_xlabel("x [m] (from the façade's outer face into the building)")
        ax.set_ylabel("z [m]")
        ax.set_title(title or f"{assembly.meta.get('name', 'blocks')}: λ = "
                     f"{result.multiplier:.4f} ({result.friction}), displacement = "
                     f"{s:.3g} s × velocity")
        ax.legend(loc="upper right", fontsize=8, framealpha=0.85)
        return write_figure(path, lambda tmp: fig.savefig(tmp, dpi=120, format="png"))
    finally:
        plt.close(fig)


_ = KIND_NAMES  # re-exported in the VTU field "kind"
