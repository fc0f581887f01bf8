"""From a finite-element mechanism to its failing body and collapse ground velocity.

One-degree-of-freedom generalisation of eqs 4–7. The FE mechanism is a shape φ(x) = v(x)/ω
(unit rotation rate of the fitted block about O). With q the block's rotation angle and the
whole structure moving as q φ relative to the ground:
- kinetic energy ½ M q̇², generalised mass M = ∫ρ|φ|² dA (for a rigid body M = I_O);
- the impulse v_g (ground moving +x, the structure's inertia pushing −x) gives
  M q̇0 = v_g ∫ρ(−φ_x) dA  (eq. 4; for a rigid body ∫ρ(−φ_x) = m z_G);
- restoring work W(q): the body inside the 50 % participation line (the paper's crack, as
  ``fe_body``) rotates by q about O exactly, W_b = m_b g (x_G sin q + z_G cos q − z_G); every
  other moving element (the outer half of a fan, a smeared crack) is carried to first order,
  W_r = q g ∫_rest ρ φ_z (its dilatant lift);
- the mechanism tips over when the block's G passes over the vertical through O,
  q_m = atan(x_G/z_G), where W_b = m_b g (r_G − z_G) (eq. 18). (The linearised W_r never stops
  growing, so W itself has no peak: a fan's dilatant lift is bounded in real masonry by the
  block size, which the homogenised model does not see.)
- collapse when ½ M q̇0² >= W(q_m), whence (eq. 7)

      v̄_g = √(2 W(q_m) M) / ∫ρ(−φ_x) dA.

What this neglects: the fan's geometry change at finite rotation (its lift is linearised,
and its share of M and W is reported), any dissipation (none in the homogenised model), and
a change of mechanism during the motion. For a rigid mechanism (no deforming zone) it is eq. 7
with eq. 18 exactly. ``fe_body`` gives the other bracket: the rigid body bounded by the 50 %
participation line, fed to eq. 7 + eq. 18 (fan mass split at its mid-line, fan lift ignored).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from skfem import Basis, ElementTriP2

from ..errors import ParameterError, check_range
from ..impulse import RigidBody
from .rigidfit import p2_energy

__all__ = ["p2_nodes", "ray_conforming_mesh", "GeneralisedImpulse", "generalised_impulse",
           "fe_body"]


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

    w = case.wall
    b, L, H = w.b, w.L, w.H
    z0 = check_range("z0", z0, 0.0, H, hi_open=True, unit="m")
    z_hinge = check_range("z_hinge", z_hinge, z0, H, hi_open=True, unit="m")
    h = check_range("h", h, 0.0, H - z0, lo_open=True, unit="m")
    h_hinge = h / 4 if h_hinge is None else check_range("h_hinge", h_hinge, 0.0, h,
                                                         lo_open=True, unit="m")
    x_apex = check_range("x_apex", x_apex, 0.0, b, unit="m")
    rays = []
    for T in (check_range("slope", T, 0.0, lo_open=True) for T in slopes):
        z_end = min(H, z_hinge + (b + L - x_apex) / T)
        rays.append(((x_apex, z_hinge), (x_apex + T * (z_end - z_hinge), z_end)))
    return to_skfem(tsection(H, b, L, size=h, z0=z0, embed_lines=rays + list(extra_lines),
                             refine_points=[(x_apex, z_hinge, h_hinge, 1.0)]))


def _p2_integral(elements, area, density, F):
    """∫ρ F dA of a P2 scalar field per element (vertex functions integrate to 0, edge ones to
    A/3)."""
    Fe = np.asarray(F, float)[np.asarray(elements, int)]
    return np.asarray(density, float) * area * Fe[:, 3:].sum(axis=1) / 3.0


@dataclass(frozen=True)
class GeneralisedImpulse:
    """The one-degree-of-freedom impulse criterion of a mechanism shape φ (module docstring).

    M [kg m²], Pi = ∫ρ(−φ_x) [kg m], W_m [J] restoring work at the tipping angle q_m [rad],
    vg [m/s];
    block: the RigidBody inside the 50 % line; M_rest_share, W_rest_share: the linearised
    rest's shares of M and of W(q_m).
    """

    M: float
    Pi: float
    W_m: float
    q_m: float
    vg: float
    block: RigidBody | None
    M_rest_share: float
    W_rest_share: float


def generalised_impulse(X, V, elements, density, mm, g: float = 9.81,
                        block: np.ndarray | None = None) -> GeneralisedImpulse:
    """v̄_g of the P2 mechanism (X, V, elements, density) with its fit ``mm`` (eqs 4–7
    generalised; see the module docstring). ``block``: element mask of the part whose
    restoring work is taken at finite rotation (default: the moving elements of mean
    participation >= 1/2, the body bounded by the 50 % line, as ``fe_body``)."""
    g = check_range("g", g, 0.0, lo_open=True, unit="m/s^2")
    el = np.asarray(elements, int)
    phi = np.asarray(V, float) / mm.fit.omega
    rho = np.broadcast_to(np.asarray(density, float), (len(el),))
    e1, e2 = X[el[:, 1]] - X[el[:, 0]], X[el[:, 2]] - X[el[:, 0]]
    area = 0.5 * np.abs(e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0])
    blk = _body_mask(mm) if block is None else np.asarray(block, bool)
    e = p2_energy(el, area, rho, phi)
    M = float(e.sum())
    Pi = float(_p2_integral(el, area, rho, -phi[:, 0]).sum())
    rest = ~blk & (mm.label != 0)
    lift_rest = g * float(_p2_integral(el[rest], area[rest], rho[rest], phi[:, 1]).sum())
    body = None
    if blk.any():
        body = RigidBody.from_triangles(X, el[blk, :3], rho[blk], O=mm.fit.O)

    if body is None or body.x_G <= 0:
        raise ParameterError("block = None is out of range: the mechanism has no rigid block "
                             "with a restoring lever (x_G > 0), allowed a block about O")
    # the block tips over when G passes over the vertical through O (eq. 18)
    q_m = math.atan2(body.x_G, body.z_G)
    W_b = body.m * g * (body.r_G - body.z_G)
    W_m = W_b + q_m * lift_rest
    vg = math.sqrt(2.0 * W_m * M) / Pi
    return GeneralisedImpulse(M, Pi, W_m, q_m, vg, body, float(e[rest].sum()) / M,
                              q_m * lift_rest / W_m)


def _body_mask(mm, level: float = 0.5) -> np.ndarray:
    """Moving elements of mean participation >= level (elements at O belong to the body)."""
    return (np.nan_to_num(mm.participation, nan=1.0) >= level) & (mm.label != 0)


def fe_body(X, elements, density, mm, level: float = 0.5) -> RigidBody:
    """The rigid body bounded by the ``level`` participation line: the triangles whose mean
    participation is at least ``level``, about the fitted O, integrated exactly."""
    el = np.asarray(elements, int)
    sel = _body_mask(mm, level)
    rho = np.broadcast_to(np.asarray(density, float), (len(el),))
    return RigidBody.from_triangles(X, el[sel, :3], rho[sel], O=mm.fit.O)
