"""The DEM's model of an assembly and its time histories: settling under gravity, then the
ideal impulse or a base acceleration, with the collapse criterion checked as it runs.

Frame: the ground's. The ground (the assembly's fixed blocks) stays put; a ground
acceleration a_g(t) (> 0 towards +x, into the building) loads every free block with the
inertia force −m a_g x̂; the ideal impulse v_g (eq. 3's limit, the ground's velocity jumping
by v_g towards +x) gives every free block the velocity −v_g x̂ relative to the ground at
t = 0, after settling.

Collapse criterion (``Outcome.collapsed``): a watched block (the façade's and toothing blocks
of a T-section, every free block otherwise) has moved outwards (−x) by more than
``disp_limit`` (default: H/4 for a T-section; the widest block otherwise) or turned by more
than ``rot_limit`` (default: none for a T-section; otherwise atan(w/h) of the watched blocks'
narrowest width w and total height h, the static overturning angle of a block rocking on its
toe: beyond it, it falls without further input). Displacements are measured from the
settled state, relative to the ground, so they include sliding. For a T-section the
criterion is a stated convention, not a proof. A displacement of b (the free strip's
overturning point) is not enough: B4 (b = 0.25 m) under 0.52, 0.6 and 0.75 m/s moved its
top out by 0.25, 0.35 and 0.62 m and stopped there (the abutment's friction and the sliding
of the upper courses), while under 0.9 m/s it passed 2 m by t = 2.25 s and kept falling.
The run stops there; otherwise it is safe at ``t_max``.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np

from .. import _threads
from ..blocks.geometry import FACADE, TOOTHING, Assembly
from ..errors import ParameterError, check_range
from ..params import G_STANDARD
from . import kernels
from .params import DEMParams

__all__ = ["DEMModel", "DEMState", "ENERGY", "Outcome", "build_model", "kicked", "pulse_function",
           "settle", "run", "t_section_model"]


@dataclass
class DEMState:
    """Positions (n, 2) [m], rotations (n,) [rad], velocities (n, 2) [m/s], angular
    velocities (n,) [rad/s] of the block centroids, and the contact list."""

    pos: np.ndarray
    th: np.ndarray
    vel: np.ndarray
    om: np.ndarray
    contacts: tuple
    build_pos: np.ndarray
    build_th: np.ndarray
    tstate: np.ndarray = field(default_factory=lambda: np.zeros((0, 2)))

    def copy(self) -> DEMState:
        return DEMState(self.pos.copy(), self.th.copy(), self.vel.copy(), self.om.copy(),
                        tuple(a.copy() for a in self.contacts), self.build_pos.copy(),
                        self.build_th.copy(), self.tstate.copy())


@dataclass
class DEMModel:
    """An assembly prepared for the DEM: vertex offsets from the centroids, inverse masses,
    the widened ground, the stiffness rule and the time step. ``offsets``: the DEM's polygons
    (rel[offsets[i]:offsets[i+1]]; the assembly's, plus the joint points when its bottom edges
    are split); ``crush``: (f_c [Pa] (0: infinite), depth in the façade, depth elsewhere [m],
    x of the façade's inner face [m]) of the contacts' caps; ``flat``: per vertex, whether its
    two edges are collinear (a joint point); ``xref``: per vertex, its x before any motion
    (which side of the façade's inner face ``fac_x`` a new contact's tributary lies on)."""

    assembly: Assembly
    params: DEMParams
    f: float
    g: float
    thickness: float
    rel: np.ndarray
    nxt: np.ndarray
    prv: np.ndarray
    owner: np.ndarray
    inv_m: np.ndarray
    inv_I: np.ndarray
    mass: np.ndarray
    radius: np.ndarray
    fac_x: float
    fac_f: float
    watch: np.ndarray
    dt: float
    k_max: float
    m_min: float
    disp_limit: float
    rot_limit: float
    coinc: float
    info: dict = field(default_factory=dict)
    loads: np.ndarray = field(default_factory=lambda: np.zeros((0, 5)))
    ties: np.ndarray = field(default_factory=lambda: np.zeros((0, 8)))
    offsets: np.ndarray | None = None
    crush: tuple = (0.0, 1.0, 1.0, math.inf)
    flat: np.ndarray | None = None
    xref: np.ndarray | None = None

    def __post_init__(self):
        if self.offsets is None:
            self.offsets = self.assembly.offsets
        if self.flat is None:
            self.flat = np.zeros(self.rel.shape[0], np.bool_)
        if self.xref is None:
            self.xref = self.assembly.centroid[self.owner, 0] + self.rel[:, 0]

    @property
    def n_blocks(self) -> int:
        return self.assembly.n_blocks

    def initial_state(self) -> DEMState:
        a = self.assembly
        n = a.n_blocks
        pos = a.centroid.astype(float).copy()
        th = np.zeros(n)
        X = np.empty_like(self.rel)
        kernels.world_vertices(pos, th, self.rel, self.owner, X)
        p = self.params
        empty = (np.empty(0, np.int64), np.empty(0), np.empty(0), np.empty(0),
                 np.empty(0, np.bool_), np.empty(0), np.empty(0), np.empty(0))
        c = kernels.build_candidates(
            X, self.offsets, self.nxt, self.prv, self.flat, self.owner, a.fixed,
            p.verlet_margin,
            self.coinc, p.cone_tolerance + 0.1, *empty, 0, p.kn, p.ks_over_kn,
            self.thickness, self.fac_x, self.fac_f, self.xref, p.trib_floor,
            p.base_joint == "tied",
            *self.crush)
        return DEMState(pos, th, np.zeros((n, 2)), np.zeros(n), c, pos.copy(), th.copy(),
                        np.zeros((len(self.ties), 2)))


def _widen_ground(a: Assembly, margin: float) -> np.ndarray:
    """The outline with every fixed block's leftmost and rightmost vertices moved out by
    ``margin`` (the assembly's ground ends flush with the façade's toe)."""
    v = a.vertices.astype(float).copy()
    for i in np.flatnonzero(a.fixed):          # the supports: one or two blocks
        sl = slice(a.offsets[i], a.offsets[i + 1])
        x = v[sl, 0]
        lo, hi = x.min(), x.max()
        x[np.isclose(x, lo)] -= margin
        x[np.isclose(x, hi)] += margin
        v[sl, 0] = x
    return v


def build_model(assembly: Assembly, params: DEMParams | None = None, *, f: float | None = None,
                thickness: float | None = None, disp_limit: float | None = None,
                rot_limit: float | None = None) -> DEMModel:
    """Prepare ``assembly`` (``homlimit.blocks.geometry``) for the DEM.

    f: friction coefficient (default the assembly's meta "f"); thickness: the slab thickness
    s [m] multiplying the joint stiffness (default meta "s", else 1 m); disp_limit,
    rot_limit: the collapse criterion (module docstring)."""
    if not isinstance(assembly, Assembly):
        raise ParameterError(f"assembly = {assembly!r} is not a homlimit.blocks Assembly")
    p = params or DEMParams()
    if not isinstance(p, DEMParams):
        raise ParameterError(f"params = {p!r} is not a DEMParams")
    meta = assembly.meta
    if meta.get("toothing", p.toothing) != p.toothing:
        raise ParameterError(f"toothing = {p.toothing!r} is out of range: the assembly's "
                             f"toothing blocks are {meta['toothing']!r}; allowed the same "
                             "(build both with t_section_model)")
    real = meta.get("real")
    fc = float(real.fc) if real is not None else 0.0
    f = meta.get("f") if f is None else f
    if f is None:
        raise ParameterError("f = None is out of range: the assembly has no friction "
                             "coefficient in its meta; allowed 0 < f")
    f = check_range("f", f, 0.0, lo_open=True)
    thickness = check_range("thickness", meta.get("s", 1.0) if thickness is None else thickness,
                            0.0, lo_open=True, unit="m")
    g = float(meta.get("g", G_STANDARD))
    a = assembly
    n = a.n_blocks
    if a.n_free == 0:
        raise ParameterError("assembly has no free block: allowed at least one")
    bb = a.bounds()
    size_min = np.minimum(bb[:, 2] - bb[:, 0], bb[:, 3] - bb[:, 1])
    thin = np.flatnonzero(~a.fixed & (size_min <= p.verlet_margin))
    if thin.size:       # the contact detection's assumption (docs/dem.md, "Openings")
        i = int(thin[np.argmin(size_min[thin])])
        raise ParameterError(
            f"block {i} of the assembly is {bb[i, 2] - bb[i, 0]:.4g} x {bb[i, 3] - bb[i, 1]:.4g} m:"
            f" out of range: allowed free blocks wider and taller than verlet_margin = "
            f"{p.verlet_margin:g} m (a thinner block falls through its neighbours' contacts)")
    verts = _widen_ground(a, p.ground_margin)
    # the longest edge before any split, for the stiffest contact below
    d0 = np.roll(verts, -1, axis=0) - verts
    last = a.offsets[1:] - 1
    d0[last] = verts[a.offsets[:-1]] - verts[last]
    owner0 = np.repeat(np.arange(n), np.diff(a.offsets))
    elen = np.hypot(d0[:, 0], d0[:, 1])
    longest = float(elen[~a.fixed[owner0]].max())
    verts, offsets = _split_bottoms(verts, a.offsets, a.fixed, p.segments(fc), p.verlet_margin)
    owner = np.repeat(np.arange(n), np.diff(offsets))
    # the ground's widened vertices move its centroid; the fixed blocks' centroids stay those
    # of the assembly (they never move, so only the offsets matter)
    rel = verts - a.centroid[owner]
    P = verts.shape[0]
    nxt = np.arange(1, P + 1)
    nxt[offsets[1:] - 1] = offsets[:-1]
    prv = np.arange(-1, P - 1)
    prv[offsets[:-1]] = offsets[1:] - 1
    # flat vertices (the joint points): collinear edges, a property of the rigid polygon
    d_in, d_out = verts - verts[prv], verts[nxt] - verts
    cross = d_in[:, 0] * d_out[:, 1] - d_in[:, 1] * d_out[:, 0]
    flat = (np.abs(cross) < 1e-9 * np.hypot(*d_in.T) * np.hypot(*d_out.T)) \
        & ((d_in * d_out).sum(1) > 0)
    free = ~a.fixed
    inv_m = np.where(free, 1.0 / np.where(free, a.mass, 1.0), 0.0)
    inv_I = np.where(free, 1.0 / np.where(free, np.maximum(a.inertia, 1e-300), 1.0), 0.0)
    radius = np.sqrt(np.maximum.reduceat((rel ** 2).sum(1), offsets[:-1]))
    radius[a.fixed] = 0.0
    # façade factor (T-sections): the paper's uniform lowering
    if "b" in meta and "rho" in meta:
        fac_x = float(meta["b"])
        fac_f = float(meta["rho"]) if p.facade_stiffness == "rho" else float(p.facade_stiffness)
        watch = np.isin(a.kind, (FACADE, TOOTHING)) & free
    else:
        fac_x, fac_f = -math.inf, 1.0
        watch = free.copy()
    # the stiffest contact that can form: half the longest free edge, with the façade factor
    # (a joint point's tributary, one segment, is at most half its edge), in its stiffer
    # direction (ks > kn is allowed)
    k_max = p.kn * max(p.ks_over_kn, 1.0) * thickness * max(fac_f, 1.0) * 0.5 * longest
    m_min = float(a.mass[free].min())
    dt = p.dt_fraction * math.sqrt(m_min / k_max)
    size = float(np.ptp(a.vertices[:, 0][free[owner0]])) or 1.0
    if disp_limit is None:
        disp_limit = 0.25 * float(meta["H"]) if "H" in meta and "b" in meta else \
            float((bb[free, 2] - bb[free, 0]).max())
    if rot_limit is None and "b" in meta:
        rot_limit = math.pi      # T-sections: the displacement criterion alone
    elif rot_limit is None:
        wb = bb[watch]
        width = float(np.min(wb[:, 2] - wb[:, 0]))
        height = float(wb[:, 3].max() - wb[:, 1].min())
        rot_limit = math.atan2(width, height)
    disp_limit = check_range("disp_limit", disp_limit, 0.0, lo_open=True, unit="m")
    rot_limit = check_range("rot_limit", rot_limit, 0.0, math.pi, lo_open=True, unit="rad")
    coinc = 1e-6 * size
    loads, ties = _real_actions(a, real, 0.5 * k_max)
    if ties.size and ties[:, 4].max() > k_max:             # a stiffer tie sets the step
        k_max = float(ties[:, 4].max())
        dt = p.dt_fraction * math.sqrt(m_min / k_max)
    crush = (fc, real.depth_facade, real.depth_wall, real.x_junction) if fc > 0 else \
        (0.0, 1.0, 1.0, math.inf)
    return DEMModel(a, p, f, g, thickness, rel, nxt, prv, owner, inv_m, inv_I,
                    a.mass.astype(float), radius, fac_x, fac_f, watch, dt, k_max, m_min,
                    disp_limit, rot_limit, coinc,
                    info={"n_blocks": n, "n_free": a.n_free, "dt": dt, "k_max": k_max,
                          "m_min": m_min, "ties": len(ties), "loads": len(loads), "fc": fc,
                          "joint_segments": p.segments(fc),
                          "joint_points": int(P - a.vertices.shape[0])},
                    loads=loads, ties=ties, offsets=offsets, crush=crush, flat=flat)


def t_section_model(case, params: DEMParams | None = None) -> DEMModel:
    """The DEM of ``case``'s T-section, the paper's UDEC model: its blocks with the façade
    "through" and the toothing blocks' density of ``params.toothing``
    (``blocks.geometry.t_section_blocks``)."""
    from ..blocks.geometry import t_section_blocks

    p = params or DEMParams()
    return build_model(t_section_blocks(case, facade="through", toothing=p.toothing), p)


def _split_bottoms(verts: np.ndarray, offsets: np.ndarray, fixed: np.ndarray, n_seg: int,
                   margin: float) -> tuple[np.ndarray, np.ndarray]:
    """The polygons with every free block's bottom edge (outward normal −z: running towards
    +x, counter-clockwise) split into ``n_seg`` equal segments by inserted vertices, leaving
    out a point within ``margin`` of another block's vertex (a corner contact already stands
    there; two coincident points would each count their tributary). Returns (vertices,
    offsets); unchanged for n_seg = 1."""
    if n_seg <= 1:
        return verts, offsets
    from scipy.spatial import cKDTree

    P = verts.shape[0]
    owner = np.repeat(np.arange(offsets.size - 1), np.diff(offsets))
    nxt = np.arange(1, P + 1)
    nxt[offsets[1:] - 1] = offsets[:-1]
    d = verts[nxt] - verts
    L = np.hypot(d[:, 0], d[:, 1])
    bottom = ~fixed[owner] & (d[:, 0] > 0) & (np.abs(d[:, 1]) < 1e-9 * L)
    e = np.flatnonzero(bottom)
    frac = np.arange(1, n_seg) / n_seg
    pts = (verts[e, None, :] + frac[None, :, None] * d[e, None, :]).reshape(-1, 2)
    edge = np.repeat(e, frac.size)
    dist, _ = cKDTree(verts).query(pts, distance_upper_bound=margin)
    keep = ~np.isfinite(dist)
    pts, edge, fr = pts[keep], edge[keep], np.tile(frac, e.size)[keep]
    # every vertex k, then the points of its edge k in order along it
    key_e = np.r_[np.arange(P), edge]
    key_f = np.r_[np.zeros(P), fr]
    order = np.lexsort((key_f, key_e))
    out = np.r_[verts, pts][order]
    counts = np.bincount(owner[key_e], minlength=offsets.size - 1)
    return out, np.r_[0, np.cumsum(counts)].astype(offsets.dtype)


def _real_actions(a: Assembly, real, k_rigid: float):
    """The kernel's ``loads`` (n_l, 5) and ``ties`` (n_t, 8) of a real wall (``kernels.
    advance``; ``blocks.real``: per bay, on the façade block whose outer face holds z): a
    floor's load Q at (e, z) as a dead force (0, −Q); a tie at the outer face (x = 0) as an
    elastic–plastic spring anchored where that point is built, stiffness k l (``k_rigid`` =
    half the stiffest contact for a rigid-plastic tie, k = 0), yield T_y l, breaking at the
    ductility δ_u; a restraining floor as a bilateral spring of stiffness ``k_rigid`` at
    (0, z) that never yields."""
    from ..blocks.real import anchor_blocks

    loads, ties = np.zeros((0, 5)), np.zeros((0, 8))
    if real is None:
        return loads, ties
    G = a.centroid
    fl, ti = real.floors, real.ties
    fb, tb = anchor_blocks(a, fl[:, 0]), anchor_blocks(a, ti[:, 0])
    on = fb >= 0
    b = fb[on]
    loads = np.c_[b, fl[on, 2] - G[b, 0], fl[on, 0] - G[b, 1], np.zeros(b.size), -fl[on, 1]]
    held = on & (fl[:, 3] > 0)
    bh = fb[held]
    rows = [np.c_[bh, -G[bh, 0], fl[held, 0] - G[bh, 1], np.zeros(bh.size),
                  np.full(bh.size, k_rigid), np.full(bh.size, np.inf),
                  np.full(bh.size, np.inf), np.ones(bh.size)]]
    on_t = tb >= 0
    bt = tb[on_t]
    k = np.where(ti[on_t, 2] > 0, ti[on_t, 2], k_rigid)
    du = np.where(ti[on_t, 3] > 0, ti[on_t, 3], np.inf)
    rows.append(np.c_[bt, -G[bt, 0], ti[on_t, 0] - G[bt, 1], np.zeros(bt.size), k,
                      ti[on_t, 1], du, np.zeros(bt.size)])
    ties = np.vstack(rows)
    return np.ascontiguousarray(loads, float), np.ascontiguousarray(ties, float)


#: the kernel's energy terms (``Outcome.work``) [J]: friction work with the ground (a fixed
#: block), in bed joints within the façade strip (x < b of a T-section) and beyond it, and in
#: the other joints (head joints, the façade's inner face), crushing work (f_c finite), and the
#: ground acceleration's work on the blocks
ENERGY = ("friction_base", "friction_bed_facade", "friction_bed", "friction_head", "crushing",
          "ground_work")


@dataclass
class Outcome:
    """One time history. collapsed: the criterion was met (module docstring), at
    t_collapse [s]; steps, t_end [s]; record: (rows, 8) t, kinetic, potential, elastic
    energy [J], x-displacement [m] and rotation [rad] of the first watched block, energy
    dissipated so far and the ground's work so far [J] (``ENERGY``); state: the final state;
    slip_base, slip_bed: per block, the largest plastic slip [m] of its contacts with the
    ground and of its bed joints (each contact's slip summed over time); work: the run's
    energy terms [J] named by ``ENERGY``; cpu [s] (the kernel's thread's: walls' bisections
    may run in threads at once); builds: Verlet list rebuilds.

    Energy per slab of thickness s: with no ties, loads or damping, kinetic + potential +
    elastic + dissipated − ground's work stays at its value at t = 0 (``energy_balance``)."""

    collapsed: bool
    t_collapse: float
    steps: int
    t_end: float
    record: np.ndarray
    state: DEMState
    slip_base: np.ndarray
    slip_bed: np.ndarray
    work: np.ndarray
    cpu: float
    builds: int

    @property
    def energy(self) -> dict[str, float]:
        """The run's energy terms [J], by name (``ENERGY``)."""
        return dict(zip(ENERGY, map(float, self.work)))

    def energy_balance(self) -> np.ndarray:
        """Per recorded row: kinetic + potential + elastic + dissipated − ground's work [J],
        constant up to the integration's error when no ties, loads or damping act."""
        r = self.record
        return r[:, 1] + r[:, 2] + r[:, 3] + r[:, 6] - r[:, 7]


def _advance(model: DEMModel, state: DEMState, nsteps: int, *, ag=None, t0: float = 0.0,
             damping: float = 0.0, ref: DEMState | None = None, check_every: int = 0,
             rec_every: int = 0, rec_rows: int = 0, slip=None, vel_tol: float = 0.0,
             z_ref=None):
    a = model.assembly
    p = model.params
    ref = ref or state
    ag = np.zeros(0) if ag is None else np.ascontiguousarray(ag, float)
    rec = np.zeros((max(rec_rows, 1), 8))
    work = np.zeros(len(ENERGY))
    slip_base, slip_bed = slip if slip is not None else (np.zeros(a.n_blocks),
                                                         np.zeros(a.n_blocks))
    z_ref = ref.pos[:, 1].copy() if z_ref is None else z_ref
    if nsteps <= 0:
        return 0, 0, rec[:0], slip_base, slip_bed, 0, work, 0.0
    # in a thread of its own (the kernel releases the GIL), so that a signal interrupts it
    out, cpu = _threads.call(
        _timed, kernels.advance,
        int(nsteps), model.dt, state.pos, state.th, state.vel, state.om, model.rel,
        model.offsets, model.nxt, model.prv, model.flat, model.owner, a.fixed, model.inv_m,
        model.inv_I, model.mass, model.radius, model.g, model.f, ag, t0, damping,
        *state.contacts,
        state.build_pos, state.build_th, p.verlet_margin, model.coinc, p.cone_tolerance + 0.1,
        p.cone_tolerance, model.coinc, p.kn, p.ks_over_kn, model.thickness, model.fac_x,
        model.fac_f, model.xref, p.trib_floor, *model.crush, model.watch, ref.pos, ref.th,
        model.disp_limit, model.rot_limit, int(check_every), slip_base, slip_bed,
        work, int(rec_every), rec, z_ref, vel_tol, model.loads, model.ties, state.tstate)
    steps, status, nrow = out[0], out[1], out[2]
    state.contacts = tuple(out[3:14])
    return steps, status, rec[:nrow], slip_base, slip_bed, out[14], work, cpu


def _timed(fn, *args):
    """(fn(*args), the CPU seconds of the thread that ran it)."""
    c0 = time.thread_time()
    out = fn(*args)
    return out, time.thread_time() - c0


def settle(model: DEMModel, state: DEMState | None = None, *, a_g: float = 0.0
           ) -> tuple[DEMState, dict]:
    """Settle under gravity with local damping (``DEMParams.settle_damping``) until every
    block is slower than settle_velocity or settle_time has passed; velocities are then
    zeroed (the contact forces stay). a_g [m/s²]: a constant ground acceleration held while
    settling (a lateral body force −m a_g x̂). Returns the state and {time, steps,
    converged}."""
    p = model.params
    a_g = check_range("a_g", a_g, unit="m/s^2")
    st = state or model.initial_state()
    nmax = int(math.ceil(p.settle_time / model.dt))
    check = max(1, int(round(0.01 / model.dt)))
    steps, status, *_ = _advance(model, st, nmax, ag=np.full(nmax, a_g),
                                 damping=p.settle_damping, check_every=check,
                                 vel_tol=p.settle_velocity)
    st.vel[:] = 0.0
    st.om[:] = 0.0
    return st, {"time": steps * model.dt, "steps": int(steps), "converged": status == 2}


def kicked(model: DEMModel, settled: DEMState, *, v_g: float = 0.0,
           velocity=None) -> DEMState:
    """A copy of the settled state with the loads of ``run`` at t = 0: ``velocity`` (n, 3)
    (u, w, ω) given to the free blocks, then −v_g x̂ added to them (the ideal impulse)."""
    v_g = check_range("v_g", v_g, unit="m/s")
    st = settled.copy()
    free = ~model.assembly.fixed
    if velocity is not None:
        q = np.asarray(velocity, float)
        if q.shape != (model.n_blocks, 3):
            raise ParameterError(f"velocity has shape {q.shape}: allowed ({model.n_blocks}, 3)")
        st.vel[free] = q[free, :2]
        st.om[free] = q[free, 2]
    st.vel[free, 0] -= v_g
    return st


def pulse_function(pulse, t_max: float):
    """(a_g(t), t_end) of a base acceleration: anything with a vectorised ``a(t)`` [m/s²]
    (``homlimit.dynamics.pulses``; its ``t_end`` if it has one, else t_max) or a callable
    a_g(t)."""
    fun = pulse.a if hasattr(pulse, "a") else pulse
    if not callable(fun):
        raise ParameterError(f"pulse = {pulse!r} is out of range: allowed a pulse with "
                             "a(t) or a callable a_g(t)")
    return fun, getattr(pulse, "t_end", t_max)


def run(model: DEMModel, settled: DEMState, *, v_g: float = 0.0, velocity=None,
        pulse=None, t_max: float = 3.0, record_every: int = 0,
        stop_on_collapse: bool = True) -> Outcome:
    """A time history from the settled state (copied, so one settling serves many runs).

    v_g [m/s]: the ideal impulse, every free block given −v_g x̂ relative to the ground at
    t = 0. velocity: (n, 3) (u, w, ω) of the centroids instead, the exact post-impulse field
    of a chosen mechanism (e.g. a block rotating about its toe with θ̇0 of eq. 4). pulse: a
    base acceleration, anything with ``a(t)`` vectorised [m/s²] (``homlimit.dynamics.pulses``)
    or a callable a_g(t). t_max [s]: the end of the run if nothing collapses."""
    t_max = check_range("t_max", t_max, 0.0, lo_open=True, unit="s")
    st = kicked(model, settled, v_g=v_g, velocity=velocity)
    nsteps = int(math.ceil(t_max / model.dt))
    ag = None
    if pulse is not None:
        fun, t_end = pulse_function(pulse, t_max)
        k = min(nsteps, int(math.ceil(t_end / model.dt)) + 1)
        ag = np.asarray(fun(np.arange(k) * model.dt), float)
    ref = settled
    check = max(1, int(round(0.002 / model.dt))) if stop_on_collapse else 0
    rows = (nsteps // record_every + 1) if record_every else 0
    steps, status, rec, sb, sd, builds, work, cpu = _advance(
        model, st, nsteps, ag=ag, ref=ref, check_every=check, rec_every=record_every,
        rec_rows=rows)
    collapsed = status == 1
    return Outcome(collapsed, steps * model.dt if collapsed else math.nan, int(steps),
                   steps * model.dt, rec, st, sb, sd, work, cpu, int(builds))
