"""What a user looks at of a DEM run: a ParaView time series (.pvd + .vtu frames), snapshot
PNGs and a GIF animation.

``record_frames`` runs one time history (``model.run``) in chunks of ``interval`` and keeps the
state after each; a run continued from a state is the same run (the kernel carries the
contacts, their stiffness, shear force and slip in the state), so the last frame is what one
uninterrupted ``run`` of that length ends with (tests/test_dem_doors.py). ``write_series``
writes the frames: per frame, the blocks (one polygon cell per block) and the acting contact
points (vertex cells with their forces), and the .pvd collection listing them last, every file
through the package's whole-or-nothing writers (``fe.mesh.write``, ``_io.write_text``,
``_io.write_figure``); the series as a whole is written or not at all (``write_series``). In
``homlimit run`` it is part of the run's result set (``_io.result_set``).
"""

from __future__ import annotations

import math
import os
import secrets
import shutil
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .._io import write_figure, write_text
from ..blocks.geometry import FACADE
from ..errors import OutputError, ParameterError, check_range
from .kernels import FLAT_CONE
from .model import DEMModel, DEMState, kicked, pulse_function, run

__all__ = ["Frame", "record_frames", "contact_forces", "blocks_mesh", "contacts_mesh",
           "write_series", "plot_snapshots", "plot_animation"]


@dataclass
class Frame:
    """The state at time t [s] after the load began (t = 0: just after the impulse)."""

    t: float
    state: DEMState


class _Shifted:
    """A base acceleration seen from time t0 on: a(t) = pulse.a(t0 + t)."""

    def __init__(self, fun, t0: float, t_end: float):
        self.fun, self.t0, self.t_end = fun, t0, max(t_end - t0, 0.0)

    def a(self, t):
        return self.fun(self.t0 + np.asarray(t, float))


def record_frames(model: DEMModel, settled: DEMState, *, v_g: float = 0.0, velocity=None,
                  pulse=None, t_max: float = 3.0, interval: float = 0.05,
                  stop_on_collapse: bool = True) -> list[Frame]:
    """The frames of one time history (the loads of ``model.run``), every ``interval`` s
    (rounded to whole time steps) up to the multiple of it nearest t_max; with
    ``stop_on_collapse``, the series ends with the first frame past the collapse criterion
    (``model``: a watched block outwards by more than disp_limit or turned by more than
    rot_limit, from the settled state)."""
    t_max = check_range("t_max", t_max, 0.0, lo_open=True, unit="s")
    interval = check_range("interval", interval, 0.0, lo_open=True, unit="s")
    k = max(1, int(round(interval / model.dt)))
    chunk = (k - 0.5) * model.dt          # run() takes ceil(t_max/dt) = k steps
    fun, t_end = (None, math.inf) if pulse is None else pulse_function(pulse, t_max)
    frames = [Frame(0.0, kicked(model, settled, v_g=v_g, velocity=velocity))]
    state, steps = settled, 0
    w = model.watch
    while steps * model.dt < t_max - 0.5 * k * model.dt:     # frames at multiples of k dt
        t0 = steps * model.dt
        load = {"v_g": v_g, "velocity": velocity} if steps == 0 else {}
        if fun is not None:
            load["pulse"] = _Shifted(fun, t0, t_end)
        out = run(model, state, t_max=chunk, stop_on_collapse=False, **load)
        state, steps = out.state, steps + out.steps
        frames.append(Frame(steps * model.dt, state.copy()))
        if stop_on_collapse and np.any(
                (settled.pos[w, 0] - state.pos[w, 0] > model.disp_limit)
                | (np.abs(state.th[w] - settled.th[w]) > model.rot_limit)):
            break
    return frames


def _vertices(model: DEMModel, state: DEMState) -> np.ndarray:
    """World coordinates (P, 2) of every vertex (the ground widened as in the model)."""
    c, s = np.cos(state.th)[model.owner], np.sin(state.th)[model.owner]
    r = model.rel
    return state.pos[model.owner] + np.c_[c * r[:, 0] - s * r[:, 1], s * r[:, 0] + c * r[:, 1]]


def contact_forces(model: DEMModel, state: DEMState) -> dict:
    """The contacts acting in ``state``, by the kernel's test (``kernels.advance``): gap < −δ_p
    (δ_p the contact's plastic closure, 0 unless it crushed), the vertex within its edge's
    span and the edge's inward normal in the vertex's cone, or tied; of two acting twins, the
    one whose vertex belongs to the lower block. Returns point (m, 2) [m], normal n and
    tangent t (m, 2) of the edge, fn (the normal spring's force at these positions,
    min(kn (−gap − δ_p), cap)) and fs (the shear force the last step carried) [N per slab],
    the force on the vertex's block fn n + fs t, block (the vertex's) and other (the edge's),
    slip [m], closure δ_p [m]."""
    X = _vertices(model, state)
    key, cv, ce, kn_c, ks_c, fs_c, tied, sl_c, twin, cap_c, dp_c = state.contacts
    A, B = X[ce], X[model.nxt[ce]]
    d = B - A
    L = np.hypot(d[:, 0], d[:, 1])
    t = d / L[:, None]
    n = np.c_[t[:, 1], -t[:, 0]]
    r = X[cv] - A
    s = (r * t).sum(1)
    gap = (r * n).sum(1)
    tol = model.coinc
    # the vertex's normal cone (between the normals of its two edges), widened by the
    # tolerance, must hold the edge's inward normal -n
    d1 = X[cv] - X[model.prv[cv]]
    n1 = np.c_[d1[:, 1], -d1[:, 0]] / np.hypot(d1[:, 0], d1[:, 1])[:, None]
    d2 = X[model.nxt[cv]] - X[cv]
    n2 = np.c_[d2[:, 1], -d2[:, 0]] / np.hypot(d2[:, 0], d2[:, 1])[:, None]
    m = -n
    st = math.sin(model.params.cone_tolerance)
    cone = ((n1[:, 0] * m[:, 1] - n1[:, 1] * m[:, 0] >= -st)
            & (m[:, 0] * n2[:, 1] - m[:, 1] * n2[:, 0] >= -st))
    # a flat vertex (a joint point): within max(tolerance, FLAT_CONE) of its normal
    wide = math.cos(max(model.params.cone_tolerance, FLAT_CONE))
    cone = np.where(model.flat[cv], (m * n2).sum(1) >= wide, cone)
    valid = tied | ((gap < -dp_c) & (s >= -tol) & (s <= L + tol) & cone)
    own = model.owner[cv]
    tw = np.where(twin >= 0, twin, 0)
    shadowed = (twin >= 0) & valid[tw] & (model.owner[cv[tw]] < own)
    act = np.flatnonzero(valid & ~shadowed)
    fn = np.minimum(kn_c[act] * (-gap[act] - dp_c[act]), cap_c[act])
    fs = fs_c[act]
    return {"point": X[cv[act]], "n": n[act], "t": t[act], "fn": fn, "fs": fs,
            "force": fn[:, None] * n[act] + fs[:, None] * t[act], "block": own[act],
            "other": model.owner[ce[act]], "slip": sl_c[act], "closure": dp_c[act]}


def blocks_mesh(model: DEMModel, state: DEMState, settled: DEMState):
    """meshio.Mesh of the blocks in ``state``: one polygon cell per block (grouped by vertex
    count). Point data "velocity" [m/s] (each block has its own vertices). Cell data "block",
    "fixed", "kind", "course", "u", "w" [m/s], "omega" [1/s], "rotation" θ [rad] (from the
    assembly's initial layout, as ``DEMState.th``), "ux", "uz" [m] (displacement from the
    settled state, relative to the ground), "watched"."""
    import meshio

    a = model.assembly
    X = _vertices(model, state)
    r = X - state.pos[model.owner]
    om = state.om[model.owner]
    vv = state.vel[model.owner] + np.c_[-om * r[:, 1], om * r[:, 0]]
    counts = np.diff(model.offsets)
    du = state.pos - settled.pos
    cells, data = [], {k: [] for k in ("block", "fixed", "kind", "course", "u", "w", "omega",
                                       "rotation", "ux", "uz", "watched")}
    for k in np.unique(counts):
        idx = np.flatnonzero(counts == k)
        cells.append(("polygon", model.offsets[idx][:, None] + np.arange(k)))
        for name, val in (("block", idx), ("fixed", a.fixed[idx].astype(np.int8)),
                          ("kind", a.kind[idx]), ("course", a.course[idx]),
                          ("u", state.vel[idx, 0]), ("w", state.vel[idx, 1]),
                          ("omega", state.om[idx]), ("rotation", state.th[idx]),
                          ("ux", du[idx, 0]), ("uz", du[idx, 1]),
                          ("watched", model.watch[idx].astype(np.int8))):
            data[name].append(np.asarray(val))
    z = np.zeros(len(X))
    return meshio.Mesh(np.c_[X, z], cells, point_data={"velocity": np.c_[vv, z]},
                       cell_data=data)


def contacts_mesh(model: DEMModel, state: DEMState):
    """meshio.Mesh of the acting contact points (``contact_forces``) as vertex cells. Point
    data "force" (on the vertex's block) [N per slab], "normal" (the edge's outward normal),
    "normal_force", "shear_force" [N per slab], "slip" [m] (plastic, summed over time),
    "closure" [m] (plastic normal closure: crushing under a finite f_c), "block", "other"."""
    import meshio

    c = contact_forces(model, state)
    m = len(c["fn"])
    z = np.zeros(m)
    return meshio.Mesh(np.c_[c["point"], z], [("vertex", np.arange(m)[:, None])],
                       point_data={"force": np.c_[c["force"], z], "normal": np.c_[c["n"], z],
                                   "normal_force": c["fn"], "shear_force": c["fs"],
                                   "slip": c["slip"], "closure": c["closure"],
                                   "block": c["block"],
                                   "other": c["other"]})


def write_series(folder, model: DEMModel, settled: DEMState, frames: list[Frame],
                 name: str = "dem") -> Path:
    """Write ``frames`` as a ParaView time series into ``folder``: NAME/blocks_NNNN.vtu and
    NAME/contacts_NNNN.vtu per frame (``blocks_mesh``, ``contacts_mesh``; the collection's
    parts 0 and 1), then NAME.pvd listing them with their times. Whole or not at all: the
    frames go into a hidden folder first (every file through ``fe.mesh.write``), which takes
    NAME/'s place once complete; the .pvd (``_io.write_text``) comes last, and an earlier
    NAME.pvd is removed before its frames are replaced, so a .pvd never lists a missing or a
    foreign frame. On a failure nothing new is left (OutputError for the disk's). Returns the
    .pvd's path."""
    from ..fe.mesh import write

    if not frames:
        raise ParameterError("frames = [] is out of range: allowed at least one frame")
    folder = Path(folder)
    pvd, final = folder / f"{name}.pvd", folder / name
    tmp = folder / f".{name}-{secrets.token_hex(4)}"
    old = None
    try:
        rows = []
        width = max(4, len(str(len(frames) - 1)))
        for k, fr in enumerate(frames):
            for part, what, mesh in ((0, "blocks", blocks_mesh(model, fr.state, settled)),
                                     (1, "contacts", contacts_mesh(model, fr.state))):
                base = f"{what}_{k:0{width}d}.vtu"
                write(mesh, tmp / base)
                rows.append(f'    <DataSet timestep="{fr.t:.9g}" group="" part="{part}" '
                            f'file="{name}/{base}"/>')
        text = ('<?xml version="1.0"?>\n<VTKFile type="Collection" version="0.1" '
                'byte_order="LittleEndian">\n  <Collection>\n' + "\n".join(rows)
                + "\n  </Collection>\n</VTKFile>\n")
        if pvd.exists():
            pvd.unlink()
        if final.exists():
            old = folder / f".{name}-old-{secrets.token_hex(4)}"
            os.rename(final, old)
        os.rename(tmp, final)
        write_text(pvd, text)
    except BaseException as exc:
        shutil.rmtree(tmp, ignore_errors=True)
        if isinstance(exc, OSError) and not isinstance(exc, OutputError):
            raise OutputError(f"cannot write the series {pvd}: {exc.strerror or exc}") from exc
        raise
    finally:
        if old is not None:
            shutil.rmtree(old, ignore_errors=True)
    return pvd


def _outlines(model: DEMModel, state: DEMState) -> list[np.ndarray]:
    """Every block's polygon (its vertices, (k, 2)) in ``state``."""
    o, X = model.offsets, _vertices(model, state)
    return [X[o[i]:o[i + 1]] for i in range(model.n_blocks)]


def _rotation(model: DEMModel, settled: DEMState, state: DEMState) -> np.ndarray:
    """Each block's rotation from the settled state [rad]; NaN on the fixed ground (grey)."""
    return np.where(model.assembly.fixed, np.nan, state.th - settled.th)


def _rotation_scale(model: DEMModel, settled: DEMState, frames) -> float:
    """The colour scale's half-range [rad]: the largest rotation of the façade's blocks (of
    every free block if there is no façade) over ``frames``. A T-section's loose toothing
    blocks may tumble by radians; beyond the façade's rotation the colours saturate."""
    a = model.assembly
    real = ~a.fixed
    scale = real & (a.kind == FACADE) if np.any(real & (a.kind == FACADE)) else real
    return max(float(max(np.abs(f.state.th[scale] - settled.th[scale]).max()
                         for f in frames)), 1e-9)


def _block_panel(ax, model: DEMModel, outlines, colour, vmax: float):
    """One panel of the DEM pictures: the blocks coloured by ``colour`` on ±vmax (coolwarm,
    the ground grey), the view from the free blocks' bounds; returns the PolyCollection."""
    import matplotlib.pyplot as plt
    from matplotlib.collections import PolyCollection

    a = model.assembly
    real = ~a.fixed
    bb = a.bounds()
    x0, x1 = bb[real, 0].min(), bb[real, 2].max()
    z1 = bb[real, 3].max()
    pc = PolyCollection(outlines, array=colour,
                        cmap=plt.get_cmap("coolwarm").with_extremes(bad="0.7"),
                        edgecolors="k", linewidths=0.1 if a.n_blocks > 200 else 0.4)
    pc.set_clim(-vmax, vmax)
    ax.add_collection(pc)
    ax.set_xlim(x0 - 0.35 * (z1 + x1 - x0), x1 + 0.05 * (x1 - x0))
    ax.set_ylim(-0.05 * z1, 1.05 * z1)
    ax.set_aspect("equal")
    ax.set_xlabel("x [m]")
    return pc


def plot_snapshots(path, model: DEMModel, settled: DEMState, frames: list[Frame],
                   n: int = 4, title: str | None = None) -> Path:
    """PNG of ``n`` frames side by side (the first, the last and evenly between): the blocks
    coloured by their rotation from the settled state [rad] (the scale: the façade's largest,
    if there is a façade), the ground grey."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    if not frames:
        raise ParameterError("frames = [] is out of range: allowed at least one frame")
    pick = sorted(set(np.linspace(0, len(frames) - 1, min(n, len(frames))).round().astype(int)))
    vmax = _rotation_scale(model, settled, [frames[k] for k in pick])

    def draw(p):
        fig, axes = plt.subplots(1, len(pick), figsize=(3.2 * len(pick), 4.2), squeeze=False,
                                 sharey=True)
        for ax, k in zip(axes[0], pick):
            st = frames[k].state
            pc = _block_panel(ax, model, _outlines(model, st), _rotation(model, settled, st),
                              vmax)
            ax.set_title(f"t = {frames[k].t:.2f} s", fontsize=9)
        axes[0][0].set_ylabel("z [m]")
        fig.colorbar(pc, ax=list(axes[0]), shrink=0.8, extend="both",
                     label="rotation from settled [rad]")
        if title:
            fig.suptitle(title, fontsize=10)
        fig.savefig(p, dpi=110)
        plt.close(fig)

    return write_figure(path, draw)


def plot_animation(path, model: DEMModel, settled: DEMState, panels: list[tuple[str, list]],
                   fps: float | None = None, max_frames: int = 200,
                   title: str | None = None) -> Path:
    """GIF of time histories side by side (``panels``: (label, frames) each, e.g. the lowest
    collapsing trial and the highest standing one), played in step: panel j shows its frame
    at the animation's time, or its last one once it has ended (a collapsing trial's series
    ends past the collapse criterion). Blocks coloured by their rotation from the settled
    state as in ``plot_snapshots``. fps: frames per second of the GIF (default real time,
    1/interval rounded to whole centiseconds per frame, within 1..25); at most
    ``max_frames`` frames (every k-th frame of the longest panel). Written by matplotlib's
    PillowWriter through ``_io.write_figure``: the file is whole or absent."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.animation import FuncAnimation, PillowWriter

    if not panels or any(not fr for _, fr in panels):
        raise ParameterError("panels: allowed at least one panel, each with at least one "
                             "frame")
    max_frames = int(check_range("max_frames", max_frames, 2, 10_000))
    a = model.assembly
    times = [np.array([f.t for f in fr]) for _, fr in panels]
    longest = max(range(len(panels)), key=lambda j: times[j][-1])
    t_all = times[longest]
    step = max(1, math.ceil(len(t_all) / max_frames))
    t_show = t_all[::step]
    if fps is None:
        # a GIF stores whole centiseconds per frame (PillowWriter truncates 1000/fps ms)
        dtf = float(np.median(np.diff(t_show))) if len(t_show) > 1 else 1.0
        fps = 100.0 / min(100, max(4, round(100 * dtf)))
    fps = check_range("fps", fps, 0.0, 100.0, lo_open=True)
    vmax = _rotation_scale(model, settled, [f for _, fr in panels for f in fr])
    colour = np.where(a.fixed, np.nan, 0.0)

    def pick(j, t):
        """panel j's frame at time t: the last one not after it."""
        return panels[j][1][max(0, int(np.searchsorted(times[j], t + 1e-9, side="right")) - 1)]

    def draw(p):
        fig, axes = plt.subplots(1, len(panels), figsize=(3.4 * len(panels), 4.4),
                                 squeeze=False, sharey=True)
        cols, heads = [], []
        for ax, (label, fr) in zip(axes[0], panels):
            pc = _block_panel(ax, model, _outlines(model, fr[0].state), colour.copy(), vmax)
            cols.append(pc)
            heads.append(ax.set_title(label, fontsize=8))
        axes[0][0].set_ylabel("z [m]")
        fig.colorbar(cols[-1], ax=list(axes[0]), shrink=0.8, extend="both",
                     label="rotation from settled [rad]")
        if title:
            fig.suptitle(title, fontsize=9)

        def update(t):
            for j, (label, _) in enumerate(panels):
                f = pick(j, t)
                cols[j].set_verts(_outlines(model, f.state))
                cols[j].set_array(_rotation(model, settled, f.state))
                heads[j].set_text(f"{label}\nt = {f.t:.2f} s")
            return cols + heads

        anim = FuncAnimation(fig, update, frames=list(t_show), blit=False)
        anim.save(p, writer=PillowWriter(fps=fps), dpi=80)
        plt.close(fig)

    return write_figure(path, draw)
