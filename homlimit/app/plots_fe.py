"""Pictures of the FE model: the mesh (mesh.png), the whole wall's mechanism
(mechanism.png), the static bound's stress field (stress.png) and the adaptive bracket's
cycles (adapt.png). Frame: x from the façade's outer face into the building, z up."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..fe.static.solution import peak_compression
from .plot_base import pyplot, save_png

__all__ = ["STRESS_GAMMA", "plot_adapt", "plot_mechanism", "plot_mesh", "plot_stress",
           "triangle_regions"]

STRESS_GAMMA = 0.4  # stress.png: colour ∝ (−σ₂)^0.4, so the wall's weak compression shows


def triangle_regions(mesh) -> tuple[np.ndarray, np.ndarray, np.ndarray, list[str]]:
    """(points (n, 2), triangles (m, 3), region index per triangle (m,), region names).

    Regions are the named sets that hold triangles (``fe.mesh.region_tags``); triangles in none
    form a region "other" (a mesh without named sets is one region "all").
    """
    from ..fe.mesh import region_tags

    tags, names = region_tags(mesh)
    blocks = [k for k, c in enumerate(mesh.cells) if c.type == "triangle"]
    tri = np.concatenate([mesh.cells[k].data for k in blocks])
    region = np.concatenate([tags[k] for k in blocks]).astype(int) - 1
    if not names or np.any(region < 0):
        names.append("other" if names else "all")
        region[region < 0] = len(names) - 1
    return np.asarray(mesh.points)[:, :2], tri, region, names


def _boundary_lines(mesh) -> dict[str, np.ndarray]:
    """name → line segments (k, 2, 2) of the named boundary parts (meshio line cell sets)."""
    pts = np.asarray(mesh.points)[:, :2]
    out = {}
    for name, sets in getattr(mesh, "cell_sets", {}).items():
        segs = [c.data[np.asarray(sets[k])] for k, c in enumerate(mesh.cells)
                if c.type == "line" and k < len(sets) and sets[k] is not None and len(sets[k])]
        if segs and not name.startswith("gmsh:"):
            out[name] = pts[np.concatenate(segs)]
    return out


def plot_mesh(path: str | Path, mesh, title: str = "") -> Path:
    """The triangulation coloured by region, with the named boundary parts drawn over it."""
    plt = pyplot()
    from matplotlib.collections import LineCollection

    pts, tri, region, names = triangle_regions(mesh)
    fig, ax = plt.subplots(figsize=(9, 7.5))
    colours = plt.get_cmap("Pastel1")
    ax.tripcolor(pts[:, 0], pts[:, 1], tri, facecolors=region.astype(float),
                 cmap=colours, vmin=0, vmax=8, edgecolors="0.35", linewidth=0.2)
    handles = [plt.Rectangle((0, 0), 1, 1, color=colours(k)) for k in range(len(names))]
    labels = [f"region {n} ({np.count_nonzero(region == k)} triangles)"
              for k, n in enumerate(names)]
    line_colours = plt.get_cmap("tab10")
    for k, (name, segs) in enumerate(_boundary_lines(mesh).items()):
        lc = LineCollection(segs, colors=[line_colours(k)], linewidths=2.5)
        ax.add_collection(lc)
        handles.append(plt.Line2D([], [], color=line_colours(k), lw=2.5))
        labels.append(f"boundary {name}")
    ax.legend(handles, labels, loc="upper left", bbox_to_anchor=(1.02, 1.0), fontsize=8)
    ax.set_aspect("equal")
    ax.set_xlabel("x [m] (from the façade's outer face into the building)")
    ax.set_ylabel("z [m]")
    ax.set_title(f"{title}: mesh, {len(tri)} triangles, {len(pts)} nodes".lstrip(": "))
    fig.tight_layout()
    return save_png(fig, path)




def plot_mechanism(path: str | Path, data: dict, case, title: str = "") -> Path:
    """The FE collapse mechanism: velocity magnitude and directions, the detected crack, and
    the lines of slope tan ψ = √(cf/a) (eq. 16), f and c/a from the hinge.

    ``data``: points (n, 2), triangles (m, 3), velocity (n, 2) at the points; optional
    ``crack`` (k, 2) polyline, ``crack_edges`` list of polylines, ``hinge`` (x, z).
    """
    plt = pyplot()
    pts = np.asarray(data["points"])[:, :2]
    tri = np.asarray(data["triangles"])
    v = np.asarray(data["velocity"])[:, :2]
    speed = np.hypot(v[:, 0], v[:, 1])
    vmax = float(speed.max()) or 1.0
    fig, ax = plt.subplots(figsize=(7.5, 8))
    tpc = ax.tripcolor(pts[:, 0], pts[:, 1], tri, speed / vmax, shading="gouraud",
                       cmap="viridis", vmin=0.0, vmax=1.0)
    fig.colorbar(tpc, ax=ax, shrink=0.7, label="velocity magnitude |u| / max |u| [-]")
    # velocity directions on a coarse grid of nodes
    span = float(max(np.ptp(pts[:, 0]), np.ptp(pts[:, 1])))
    cell = np.floor(pts / (span / 18)).astype(int)
    _, pick = np.unique(cell, axis=0, return_index=True)
    pick = pick[speed[pick] > 0.05 * vmax]
    ax.quiver(pts[pick, 0], pts[pick, 1], v[pick, 0], v[pick, 1], color="w", alpha=0.8,
              angles="xy", scale_units="xy", scale=vmax / (span / 18), width=0.003)
    from ..geometry import TSection

    geo = TSection.from_case(case)
    hinge = data.get("hinge")
    x0, z0 = ((geo.x_junction, geo.z0) if hinge is None
              else (float(hinge[0]), float(hinge[1])))
    if hinge is not None:
        ax.plot([x0], [z0], "o", color="r", ms=9, mec="k", label="hinge (rotation centre)")
    for k, poly in enumerate(data.get("crack_edges") or []):
        poly = np.asarray(poly)
        ax.plot(poly[:, 0], poly[:, 1], ":", color="orange", lw=2,
                label="10 % and 90 % participation lines" if k == 0 else None)
    if data.get("crack") is not None:
        c = np.asarray(data["crack"])
        ax.plot(c[:, 0], c[:, 1], "-", color="r", lw=2.5, label="detected crack (mid-line)")
    top = geo.H - z0
    c_a = case.masonry.c / case.masonry.a
    for slope, style, lab in ((case.alpha, "--", f"tan ψ = √(cf/a) = {case.alpha:.3f} (eq. 16)"),
                              (case.masonry.f, "-.", f"tan ψ = f = {case.masonry.f:.3f}"),
                              (c_a, ":", f"tan ψ = c/a = {c_a:.3f}")):
        t = np.array([0.0, top])
        ax.plot(x0 + slope * t, z0 + t, style, color="w", lw=1.8, label=lab)
    ax.set_xlim(float(pts[:, 0].min()), float(pts[:, 0].max()))
    ax.set_ylim(float(pts[:, 1].min()), float(pts[:, 1].max()))
    ax.set_aspect("equal")
    ax.legend(fontsize=8, loc="lower right", framealpha=0.9)
    ax.set_xlabel("x [m] (from the façade's outer face into the building)")
    ax.set_ylabel("z [m]")
    ax.set_title(f"{title}: collapse mechanism".lstrip(": "))
    return save_png(fig, path)




def plot_stress(path: str | Path, static, title: str = "", n_ticks: int = 1500,
                fc: float | None = None, rho: float = 1.0) -> Path:
    """The lower-bound stress field: the most compressive principal stress σ₂ per triangle
    (colour, kPa or MPa by its size) and its direction (short lines, length ∝ |σ₂|): the
    compression paths.

    ``static`` is a ``homlimit.fe.static.StaticSolution``; at most ``n_ticks`` direction lines are
    drawn (the most compressed triangles first); rigid bodies (no stress field) are grey. The
    colour scale is a power law, colour ∝ (−σ₂)^STRESS_GAMMA (said on the colour bar), so that
    the wall's weak compression shows beside the peak at the façade's toe. ``fc`` (Pa; 0 for
    infinite) adds a line to the title: f_c and the peak compression of the masonry
    (``peak_compression``: the façade strip's section stresses over ``rho`` = l/s; the
    colours are the section's stresses), which the static program keeps <= f_c.
    """
    plt = pyplot()
    m = static.mesh
    _, s2, theta = static.principal()
    # constrained layout keeps the title, the axes and the colour bar apart
    fig, ax = plt.subplots(figsize=(7.0, 6.0), layout="constrained")
    from matplotlib.colors import PowerNorm

    rigid = np.isnan(s2)  # rigid bodies carry no stress field: drawn grey
    comp = np.where(rigid, 0.0, np.maximum(-s2, 0.0))
    # the colour bar in kPa or MPa with plain tick labels: matplotlib's "1e7" offset label
    # would sit over the title
    unit, per = ("MPa", 1e6) if comp.max() >= 1e6 else ("kPa", 1e3)
    shown = comp / per
    # a power-law colour scale so that the wall's weak compression shows beside the façade's
    tpc = ax.tripcolor(m.p[0], m.p[1], m.t.T[~rigid], facecolors=shown[~rigid], cmap="magma_r",
                       norm=PowerNorm(STRESS_GAMMA, vmin=0.0, vmax=max(shown.max(), 1e-30)),
                       edgecolors="none")
    if rigid.any():
        ax.tripcolor(m.p[0], m.p[1], m.t.T[rigid], facecolors=np.zeros(rigid.sum()),
                     cmap="Greys", vmin=-1.0, vmax=3.0, edgecolors="none")
    bar = fig.colorbar(tpc, ax=ax, label=f"compression −σ₂ (most compressive principal "
                                         f"stress) [{unit}]\nnon-linear colour scale: colour ∝ "
                                         f"(−σ₂)^{STRESS_GAMMA:g}")
    bar.ax.ticklabel_format(useOffset=False, style="plain")
    c = m.p[:, m.t].mean(axis=1)
    if comp.max() > 0:
        pick = np.argsort(-comp)[:n_ticks]
        ell = 0.6 * np.sqrt(np.median(np.abs(static.element_areas())))
        half = ell * (0.25 + 0.75 * (comp[pick] / comp.max()) ** 0.4)
        dx, dz = half * np.cos(theta[pick]), half * np.sin(theta[pick])
        segs = np.stack([np.c_[c[0, pick] - dx, c[1, pick] - dz],
                         np.c_[c[0, pick] + dx, c[1, pick] + dz]], axis=1)
        from matplotlib.collections import LineCollection

        ax.add_collection(LineCollection(segs, colors="tab:cyan", linewidths=0.8))
    ax.set_aspect("equal")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("z [m]")
    title = title or f"lower-bound stress field, λ⁻ = {static.multiplier:.4g}"
    if fc is not None:
        peak = peak_compression(static, rho)
        what = "peak compression" + (f" (façade: section stress / ρ, ρ = {rho:.4g})"
                                     if rho != 1.0 else "")
        title += (f"\nf_c = {fc / 1e6:.4g} MPa: {what} {peak / 1e6:.4g} MPa <= f_c"
                  if fc > 0 else f"\nf_c infinite ([masonry] fc = 0): {what} "
                  f"{peak / 1e6:.4g} MPa")
    ax.set_title(title)
    return save_png(fig, path)




def plot_adapt(path: str | Path, cycles: list[dict], title: str = "",
               exact: float | None = None) -> Path:
    """adapt.png: both bounds of the adaptive bracket against the triangles of each cycle
    (``fe.adapt``): each mesh's and the best so far, and the best pair's relative gap; the
    crack's splits (``fe.adapt.refine_mechanism``) have λ⁺ only."""
    plt = pyplot()
    n = [c["triangles"] for c in cycles]
    fig, (ax, ag) = plt.subplots(1, 2, figsize=(10, 4), layout="constrained")
    ax.plot(n, [c["upper"] for c in cycles], "v", color="C0", alpha=0.5,
            label="kinematic λ⁺ on each mesh")
    ax.plot(n, [c["lower"] for c in cycles], "^", color="C1", alpha=0.5,
            label="static λ⁻ on each mesh")     # NaN (not drawn) on the crack's splits
    ax.plot(n, [c["best_upper"] for c in cycles], "-", color="C0", label="best λ⁺ so far")
    ax.plot(n, [c["best_lower"] for c in cycles], "-", color="C1", label="best λ⁻ so far")
    if exact is not None:
        ax.axhline(exact, color="k", lw=0.8, ls="--", label="exact")
    ax.set_xscale("log")
    ax.set_xlabel("triangles")
    ax.set_ylabel("collapse multiplier (acceleration / g)")
    ax.legend()
    ag.loglog(n, [100 * c["rel_gap"] for c in cycles], "o-")
    ag.set_xlabel("triangles")
    ag.set_ylabel("relative gap of the best bounds [%]")
    fig.suptitle(f"{title}: adaptive bracket" if title else "adaptive bracket")
    return save_png(fig, path)
