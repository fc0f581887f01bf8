"""From a finite-element mechanism to its failing body and collapse ground velocity.

The failing body is bounded by the 50 % line of the block's participation p (``rigidfit``):
every P2 triangle is cut into its four linear sub-triangles, each clipped by the level line
of its linear interpolant, and the pieces are integrated exactly (``contour_body``), so the
body converges with the mesh (an element mask carries the band's half elements: +4.7 % mass
at 0.24 m elements on B1).

One-degree-of-freedom generalisation of eqs 4–7. The FE mechanism is a shape φ(x) = v(x)/ω
(unit rotation rate of the fitted block about O). With q the block's rotation angle and the
whole structure moving as q φ relative to the ground:
- kinetic energy ½ M q̇², generalised mass M = ∫ρ|φ|² dA (for a rigid body M = I_O);
- the impulse v_g (ground moving +x, the structure's inertia pushing −x) gives
  M q̇0 = v_g ∫ρ(−φ_x) dA  (eq. 4; for a rigid body ∫ρ(−φ_x) = m z_G);
- restoring work W(q): the body inside the 50 % contour rotates by q about O exactly,
  W_b = m_b g (x_G sin q + z_G cos q − z_G); the rest of the moving material (the outer half
  of a fan, a smeared crack) is carried to first order, W_r = L q with
  L = g (∫_moving ρ φ_z − m_b x_G) (its dilatant lift; the body's share taken rigid);
- W(q) = W_b + W_r peaks where dW/dq = 0 (``impulse.peak_work``): after the block's tipping
  angle atan(x_G/z_G) when L > 0, exactly there (eq. 18) for a rigid mechanism;
- collapse when ½ M q̇0² >= W(q_m), whence (eq. 7)

      v̄_g = √(2 W(q_m) M) / ∫ρ(−φ_x) dA.

What this neglects: the fan's geometry change at finite rotation (its lift is linearised,
and its share of M and W is reported), any dissipation (none in the homogenised model), and
a change of mechanism during the motion. For a rigid mechanism (no deforming zone) it is eq. 7
with eq. 18 exactly.

A real wall's ties and floors (issue 30, ``BodyLoads``, docs/real-walls.md "FE impulse"): W(q)
gains, as separate terms, the floors' restoring work and the work done against the ties
yielding, as the closed forms (``closed_form.real``) and the blocks (``blocks.impulse``) take
them: a floor load Q at a point of the body turns with it exactly, Q ((x − x_O) sin q +
(z − z_O)(cos q − 1)); at a point of the rest, to first order, Q φ_z q; a tie at the outer face
(0, z_T) of the body opens by max(0, (z_T − z_O) sin q) (the closed forms' rule), on the rest
by max(0, −φ_x) q, and its work is the closed forms' tie law (``impulse.loads.tie_work``:
rigid-plastic T_y δ, or elastic–plastic, up to the ductility limit). These terms and their
derivative dW/dq live in ``impulse.LoadWork`` (``GeneralisedImpulse.load_work``), which the
FE body's rocker (``dynamics.GeneralisedRocker``) takes too. W is then maximised over
0 <= q <= π/2 (``impulse.peak_with_loads``: a grid, then bounded Brent, as the blocks). A
restraining floor is a support v_x = 0 of the FE problem; the body must not carry the
restrained point away from its hinge (checked: a ParameterError otherwise).

Not with a joint cohesion (and the tension it carries; ``bond_reason``): both FE bounds take
them as rigid-plastic strengths (``fe.problems.t_section``), but their dissipation at finite
rotation is not rigid-plastic (a joint's bond softens and is lost once it has opened or slid a
little, while θ D/|ω| would count it over the whole rotation), so W(q) would hang on a
softening rule the case file does not state: v̄_g is then "not available", as the rigid
blocks' (``blocks.impulse.no_bond``; docs/real-walls.md "FE impulse"). A tension without a
cohesion does not act (``fe.strength``: beyond the Coulomb apex C/f it is cut off), so v̄_g is
the dry wall's.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from skfem import Basis, ElementTriP2

from ..errors import ParameterError, check_range
from ..geometry import TSection
from ..impulse import LoadWork, RigidBody, no_bond_reason, peak_with_loads, peak_work
from .crack import p2_subtriangles

__all__ = ["p2_nodes", "ray_conforming_mesh", "BodyLoads", "GeneralisedImpulse",
           "body_loads", "bond_reason", "generalised_impulse", "contour_body", "contour_pieces"]


def p2_nodes(solution, densities: dict | None = None):
    """P2 nodes of a KinematicSolution: positions X (n, 2), velocities V (n, 2), triangles
    (n_el, 6) in scikit-fem's P2 order, and per-triangle densities (from ``densities``:
    region → mass per unit area, default 1)."""
    mesh = solution.mesh
    sb = Basis(mesh, ElementTriP2())
    X = sb.doflocs.T.copy()
    V = np.asarray(solution.u, float).reshape(-1, 2)  # vector P2 DOFs interleave (x, z)
    rho = np.ones(mesh.t.shape[1])
    for name, idx in (densities or {}).items():     # in order: a later region overrides
        if name in solution.regions:
            rho[solution.regions[name]] = idx
    return X, V, sb.element_dofs.T.copy(), rho


def ray_conforming_mesh(case, z_hinge: float, slopes, h: float, z0: float = 0.0,
                        h_hinge: float | None = None, x_apex: float = 0.0,
                        extra_lines=()):
    """A gmsh T-section mesh (``geometry.tsection``, the regions and boundaries of
    ``problems.t_section``) whose edges contain the rays x − x_apex = T (z − z_hinge) from
    (x_apex, z_hinge), one per slope T (default apex: the hinge on the façade's outer face;
    x_apex = b: mechanism II's crack from the inner corner), and the segments ``extra_lines``
    ((x0, z0), (x1, z1)), e.g. mechanism II's bed-joint crack under the façade. Element size h,
    refined to h_hinge (default h/4) within 1 m of the apex. Returns a scikit-fem MeshTri."""
    from ..fe.geometry import tsection
    from ..fe.mesh import to_skfem

    z0 = check_range("z0", z0, 0.0, case.wall.H, hi_open=True, unit="m")
    geo = TSection.from_case(case, z0)
    b, H = geo.b, geo.H
    z_hinge = check_range("z_hinge", z_hinge, z0, H, hi_open=True, unit="m")
    h = check_range("h", h, 0.0, H - z0, lo_open=True, unit="m")
    h_hinge = h / 4 if h_hinge is None else check_range("h_hinge", h_hinge, 0.0, h,
                                                         lo_open=True, unit="m")
    x_apex = check_range("x_apex", x_apex, 0.0, b, unit="m")
    rays = []
    for T in (check_range("slope", T, 0.0, lo_open=True) for T in slopes):
        z_end = min(H, z_hinge + (geo.x_end - x_apex) / T)
        rays.append(((x_apex, z_hinge), (x_apex + T * (z_end - z_hinge), z_end)))
    return to_skfem(tsection(H, b, geo.L, size=h, z0=z0, embed_lines=rays + list(extra_lines),
                             refine_points=[(x_apex, z_hinge, h_hinge, 1.0)],
                             holes=geo.holes, lintels=geo.lintels))


@dataclass(frozen=True)
class BodyLoads:
    """The ties, floors and restraints acting on a FE mechanism, in the impulse's units: per
    bay of façade (a value per metre of façade × l), as the FE masses (``analysis.densities``).

    floors      rows (Q [N], x [m], z [m]): a vertical dead load Q at (x, z)
    ties        rows (z [m], T_y [N], k [N/m], δ_u [m]): a tie at the outer face (0, z), yield
                force T_y, stiffness k (0: rigid-plastic), ductility limit δ_u (inf: none)
    restraints  heights z [m] of the restraining floors (v_x = 0 at the outer face)
    band        half-height [m] of a restraint's band (the FE support spans z ± band)
    """

    floors: tuple = ()
    ties: tuple = ()
    restraints: tuple = ()
    band: float = 0.0

    def __post_init__(self):
        fl = _rows("floors", self.floors, 3)
        ti = _rows("ties", self.ties, 4)
        zr = np.asarray(self.restraints, float).ravel()
        if not (np.all(np.isfinite(fl)) and np.all(fl[:, 0] >= 0)):
            raise ParameterError(f"floors = {self.floors!r} is out of range: allowed finite "
                                 "(Q >= 0, x, z)")
        if not (np.all(np.isfinite(ti[:, :3])) and np.all(ti[:, 1:3] >= 0)
                and np.all(ti[:, 3] > 0)):
            raise ParameterError(f"ties = {self.ties!r} is out of range: allowed finite z, "
                                 "T_y >= 0, k >= 0 and δ_u > 0 (inf: none)")
        if not np.all(np.isfinite(zr)):
            raise ParameterError(f"restraints = {self.restraints!r} is out of range: allowed "
                                 "finite heights")
        check_range("band", self.band, 0.0, unit="m")

    def __bool__(self) -> bool:
        return bool(self.floors or self.ties)


def _rows(name: str, rows, width: int) -> np.ndarray:
    """``rows`` as an (n, width) float array (n = 0 for none), or a ParameterError."""
    a = np.asarray(rows, float)
    if a.size == 0:
        return np.zeros((0, width))
    if a.ndim != 2 or a.shape[1] != width:
        raise ParameterError(f"{name} has shape {a.shape}: allowed rows of {width} numbers")
    return a


def body_loads(case, problem) -> BodyLoads:
    """The ``BodyLoads`` of a ``problems.t_section`` problem of ``case``: the ties and floors
    it places on its part (``problem.meta["real_wall"]``, those above its base), each at the
    resultant of its FE load (the tie's band centre ``z_used``, the floor's ``e_used``,
    ``z_used``), times the bay's length l."""
    placed = problem.meta.get("real_wall") or {}
    length = case.wall.l
    floors = tuple((case.floors[f["index"]].load * length, f["e_used"], f["z_used"])
                   for f in placed.get("floors", ()))
    ties = []
    for t in placed.get("ties", ()):
        tie = case.ties[t["index"]]
        ties.append((t["z_used"], tie.yield_force * length, tie.stiffness * length,
                     tie.ductility or math.inf))
    held = tuple(f["z"] for f in placed.get("floors", ()) if f["restrains"])
    return BodyLoads(floors, tuple(ties), held, case.masonry.a / 2)


def bond_reason(case) -> str:
    """Why the FE mechanism of ``case`` has no v̄_g: "" when its joints have no cohesion (a
    tension acts only with one: ``fe.strength``), else the reason (module docstring), worded
    as the rigid blocks' (``impulse.no_bond_reason``)."""
    m = case.masonry
    if not m.cohesion > 0:
        return ""
    return no_bond_reason(m.cohesion, m.tension, "the FE mechanism",
                          "both FE bounds and the mechanism take them")


@dataclass(frozen=True)
class GeneralisedImpulse:
    """The one-degree-of-freedom impulse criterion of a mechanism shape φ (module docstring).

    M [kg m²], Pi = ∫ρ(−φ_x) [kg m], W_m [J] restoring work at its peak q_m [rad], vg [m/s];
    block: the RigidBody inside the 50 % contour; lift_rest: L [N m], the rest's linearised
    work per radian; M_rest_share, W_rest_share: the rest's shares of M and of W(q_m);
    W_floors, W_ties [J]: the floors' and ties' parts of W(q_m) (``BodyLoads``; 0 without);
    load_work: their W(q) and dW/dq (``LoadWork``; None without), for the FE body's rocker.
    """

    M: float
    Pi: float
    W_m: float
    q_m: float
    vg: float
    block: RigidBody
    lift_rest: float
    M_rest_share: float
    W_rest_share: float
    W_floors: float = 0.0
    W_ties: float = 0.0
    load_work: LoadWork | None = None


def generalised_impulse(X, V, elements, density, mm, g: float = 9.81,
                        loads: BodyLoads | None = None) -> GeneralisedImpulse:
    """v̄_g of the P2 mechanism (X, V, elements, density) with its fit ``mm`` (eqs 4–7
    generalised; see the module docstring): the body bounded by the 50 % participation line
    (``contour_body``) at finite rotation, the material outside it carried linearly — its
    share of M, Π and the lift L integrated over the clipped pieces (φ linear on each).
    ``loads``: the ties and floors on the mechanism (``body_loads``), their work in W(q)."""
    g = check_range("g", g, 0.0, lo_open=True, unit="m/s^2")
    phi = np.asarray(V, float) / mm.fit.omega
    inside, outside = _clip_level(X, elements, density, mm, 0.5)
    body = _pieces_body(inside, mm.fit.O)
    if body.x_G <= 0 and not loads:
        raise ParameterError("block = body about O is out of range: the mechanism has no "
                             "rigid block with a restoring lever (x_G > 0)")
    pts, rho, bary, sub = outside
    f = np.einsum("kvb,kbc->kvc", bary, phi[sub])                    # φ at the pieces' vertices
    area = rho * _areas(pts)
    M_out = float(area @ ((f ** 2).sum(axis=(1, 2)) + (f[:, 0] * f[:, 1] + f[:, 1] * f[:, 2]
                                                         + f[:, 2] * f[:, 0]).sum(axis=1)) / 6)
    Pi_out = float(area @ -f[:, :, 0].mean(axis=1))
    lift = max(g * float(area @ f[:, :, 1].mean(axis=1)), 0.0)
    M, Pi = body.I_O + M_out, body.m * body.z_G + Pi_out
    W_f = W_t = 0.0
    lw = None
    if loads:
        lw = _load_work(loads, X, elements, phi, inside, mm.fit.O)
        q_m, W_m = peak_with_loads(body, lift, lw, g)
        W_f, W_t = (float(v) for v in lw.parts(q_m))
    else:
        q_m, W_m = peak_work(body, lift, g)
    vg = math.sqrt(2.0 * W_m * M) / Pi
    return GeneralisedImpulse(M, Pi, W_m, q_m, vg, body, lift, M_out / M, lift * q_m / W_m,
                              W_f, W_t, lw)


def _locate(points, tri):
    """Per point (n, 2), the first triangle of ``tri`` (k, 3, 2) holding it (−1: none) and its
    barycentric coordinates there (n, 3); points on an edge belong to either side."""
    P = np.asarray(points, float).reshape(-1, 2)
    if not len(tri) or not len(P):
        return np.full(len(P), -1), np.zeros((len(P), 3))
    a, e1, e2 = tri[:, 0], tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]
    det = e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0]
    d = P[:, None, :] - a[None]
    with np.errstate(divide="ignore", invalid="ignore"):
        s = (d[..., 0] * e2[:, 1] - d[..., 1] * e2[:, 0]) / det
        t = (e1[:, 0] * d[..., 1] - e1[:, 1] * d[..., 0]) / det
    lam = np.stack([1 - s - t, s, t], axis=-1)                     # (n, k, 3)
    ok = np.all(lam >= -1e-9, axis=-1) & (np.abs(det) > 0)
    idx = np.where(ok.any(axis=1), np.argmax(ok, axis=1), -1)
    return idx, lam[np.arange(len(P)), np.maximum(idx, 0)]


def _load_work(loads: BodyLoads, X, elements, phi, inside, O) -> LoadWork:  # noqa: E741
    """The ``LoadWork`` of ``loads`` on the mechanism (module docstring): each load point on
    the body (``inside``, the pieces of the 50 % contour) turns with it exactly, elsewhere it
    moves with φ to first order. A restraining floor inside the body away from its hinge is
    refused (ParameterError)."""
    X = np.asarray(X, float)
    sub = p2_subtriangles(elements)
    xO, zO = (float(v) for v in O)
    fl = np.asarray(loads.floors, float).reshape(-1, 3)
    ti = np.asarray(loads.ties, float).reshape(-1, 4)
    pts = np.r_[fl[:, 1:3], np.c_[np.zeros(len(ti)), ti[:, 0]],
                np.c_[np.zeros(len(loads.restraints)), loads.restraints]]
    on_body = _locate(pts, inside[0])[0] >= 0
    k, lam = _locate(pts, X[sub])
    f_at = np.where((k >= 0)[:, None], np.einsum("nb,nbc->nc", lam, phi[sub[np.maximum(k, 0)]]),
                    0.0)                                          # φ at the points (0 outside)
    nf, nt = len(fl), len(ti)
    fb, tb = on_body[:nf], on_body[nf:nf + nt]
    for z_r in np.compress(on_body[nf + nt:], loads.restraints):
        if abs(z_r - zO) > loads.band * (1 + 1e-9):
            raise ParameterError(
                f"[[floor]] restrains = true at z = {z_r:g} m lies inside the failing body, "
                f"{abs(z_r - zO):.3g} m from its hinge (z_O = {zO:.4g} m): out of range: the "
                "body's rotation would carry the restrained point away; allowed a body "
                "bounded by the floor (its hinge within the floor's band)")
    rest_f = np.c_[fl[:, 0], f_at[:nf, 1]]
    body_t = np.c_[ti[:, 0] - zO, ti[:, 1:]]
    rest_t = np.c_[np.maximum(-f_at[nf:nf + nt, 0], 0.0), ti[:, 1:]]
    rows = lambda a: tuple(tuple(map(float, r)) for r in a)  # noqa: E731
    return LoadWork(rows(np.c_[fl[:, 0], fl[:, 1] - xO, fl[:, 2] - zO][fb]), rows(rest_f[~fb]),
                    rows(body_t[tb]), rows(rest_t[~tb]))


def _areas(pts):
    e1, e2 = pts[:, 1] - pts[:, 0], pts[:, 2] - pts[:, 0]
    return 0.5 * np.abs(e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0])


def _clip_level(X, elements, density, mm, level: float):
    """The P2 triangles' linear sub-triangles clipped by the level line of the nodal
    participation's linear interpolant: (inside p >= level, outside), each as (points
    (k, 3, 2), density (k,), barycentric coordinates of the piece's vertices in its
    sub-triangle (k, 3, 3), the sub-triangle's nodes (k, 3)). Where the participation is
    undefined (at O, where both v and the rigid velocity vanish) the node lies on the line."""
    X = np.asarray(X, float)
    sub = p2_subtriangles(elements)
    rho = np.repeat(np.broadcast_to(np.asarray(density, float), (len(elements),)), 4)
    pn = np.nan_to_num(mm.node_participation, nan=level)
    pn[np.hypot(*(X - np.asarray(mm.fit.O)).T) <= 1e-9 * np.ptp(X, axis=0).max()] = level
    p = pn[sub] - level
    eye = np.eye(3)
    sides = []
    for inside in (p >= 0, p < 0):
        n_in = inside.sum(axis=1)
        keep = [(np.flatnonzero(n_in == 3), np.broadcast_to(eye, (int((n_in == 3).sum()), 3, 3)))]
        for n, odd in ((1, inside), (2, ~inside)):
            sel = np.flatnonzero(n_in == n)
            k = np.argmax(odd[sel], axis=1)                          # the vertex on its own
            order = (k[:, None] + np.arange(3)) % 3
            q = p[sel[:, None], order]
            E = eye[order]                                           # (m, 3, 3) rows e_A, e_B, e_C
            sAB = (q[:, 0] / (q[:, 0] - q[:, 1]))[:, None]
            sAC = (q[:, 0] / (q[:, 0] - q[:, 2]))[:, None]
            AB = (1 - sAB) * E[:, 0] + sAB * E[:, 1]
            AC = (1 - sAC) * E[:, 0] + sAC * E[:, 2]
            if n == 1:                                               # the triangle A, AB, AC
                keep.append((sel, np.stack([E[:, 0], AB, AC], axis=1)))
            else:                                                    # the quad B, C, AC, AB
                keep += [(sel, np.stack([E[:, 1], E[:, 2], AC], axis=1)),
                         (sel, np.stack([E[:, 1], AC, AB], axis=1))]
        idx = np.concatenate([s for s, _ in keep])
        bary = np.concatenate([b for _, b in keep]).reshape(-1, 3, 3)
        sides.append((np.einsum("kvb,kbc->kvc", bary, X[sub[idx]]), rho[idx], bary, sub[idx]))
    return sides


def _pieces_body(pieces, origin) -> RigidBody:
    pts, rho = pieces[0], pieces[1]
    if not len(pts):
        raise ParameterError("level = 0.5 is out of range: no participation reaches it (no "
                             "block)")
    return RigidBody.from_triangles(pts.reshape(-1, 2), np.arange(3 * len(pts)).reshape(-1, 3),
                                    rho, O=origin)


def contour_pieces(X, elements, density, mm, level: float = 0.5):
    """The body bounded by the ``level`` line of the participation as triangles: the pieces of
    the P2 triangles' linear sub-triangles on the block's side of the line of the
    participation's linear interpolant (``_clip_level``): points (k, 3, 2), density (k,)."""
    level = check_range("level", level, 0.0, 1.0, lo_open=True, hi_open=True)
    return _clip_level(X, elements, density, mm, level)[0][:2]


def contour_body(X, elements, density, mm, level: float = 0.5) -> RigidBody:
    """The rigid body bounded by the ``level`` line of the participation, about the fitted O
    (``contour_pieces``, integrated exactly)."""
    return _pieces_body(contour_pieces(X, elements, density, mm, level), mm.fit.O)
