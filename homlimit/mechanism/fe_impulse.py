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
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from skfem import Basis, ElementTriP2

from ..errors import ParameterError, check_range
from ..geometry import TSection
from ..impulse import RigidBody, peak_work
from .crack import p2_subtriangles

__all__ = ["p2_nodes", "ray_conforming_mesh", "GeneralisedImpulse", "generalised_impulse",
           "contour_body", "contour_pieces"]


def p2_nodes(solution, densities: dict | None = None):
    """P2 nodes of a KinematicSolution: positions X (n, 2), velocities V (n, 2), triangles
    (n_el, 6) in scikit-fem's P2 order, and per-triangle densities (from ``densities``:
    region → mass per unit area, default 1)."""
    mesh = solution.mesh
    sb = Basis(mesh, ElementTriP2())
    X = sb.doflocs.T.copy()
    V = np.asarray(solution.u, float).reshape(-1, 2)  # vector P2 DOFs interleave (x, z)
    rho = np.ones(mesh.t.shape[1])
    for name, idx in (densities or {}).items():
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
                             refine_points=[(x_apex, z_hinge, h_hinge, 1.0)]))


@dataclass(frozen=True)
class GeneralisedImpulse:
    """The one-degree-of-freedom impulse criterion of a mechanism shape φ (module docstring).

    M [kg m²], Pi = ∫ρ(−φ_x) [kg m], W_m [J] restoring work at its peak q_m [rad], vg [m/s];
    block: the RigidBody inside the 50 % contour; lift_rest: L [N m], the rest's linearised
    work per radian; M_rest_share, W_rest_share: the rest's shares of M and of W(q_m).
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


def generalised_impulse(X, V, elements, density, mm, g: float = 9.81) -> GeneralisedImpulse:
    """v̄_g of the P2 mechanism (X, V, elements, density) with its fit ``mm`` (eqs 4–7
    generalised; see the module docstring): the body bounded by the 50 % participation line
    (``contour_body``) at finite rotation, the material outside it carried linearly — its
    share of M, Π and the lift L integrated over the clipped pieces (φ linear on each)."""
    g = check_range("g", g, 0.0, lo_open=True, unit="m/s^2")
    phi = np.asarray(V, float) / mm.fit.omega
    inside, outside = _clip_level(X, elements, density, mm, 0.5)
    body = _pieces_body(inside, mm.fit.O)
    if body.x_G <= 0:
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
    q_m, W_m = peak_work(body, lift, g)
    vg = math.sqrt(2.0 * W_m * M) / Pi
    return GeneralisedImpulse(M, Pi, W_m, q_m, vg, body, lift, M_out / M, lift * q_m / W_m)


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
