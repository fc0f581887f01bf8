"""Rigid bodies rotating about a point O: mass, centre of gravity and polar inertia about O.

The one type shared by the closed-form mechanisms and the finite-element mechanisms, so that
the impulse criterion (``homlimit.impulse``) does not care where a body comes from.
Coordinates of G are relative to O, in the section frame (x into the building, z up); the
façade overturns towards -x, so a body about to overturn has x_G > 0 measured from O... see
``RigidBody`` for the sign convention used by eqs 4–7.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import ParameterError, check_range
from ..fields import check_fields, ranged, set_fields

__all__ = ["RigidBody", "triangle_moments"]


@dataclass(frozen=True)
class RigidBody:
    """A rigid body per unit out-of-plane thickness (or with its actual mass), rotating about O.

    m   : mass [kg] (per unit thickness: kg/m)
    x_G : horizontal distance of G from O, measured towards the restoring side [m] (x_G > 0:
          gravity opposes the overturning, the paper's x_G of eq. 17)
    z_G : height of G above O [m] (> 0)
    I_O : polar moment of inertia about O [kg m²] (same thickness convention as m)
    J_z : ∫(z − z_O)² dm, the second moment of the mass in height about O [kg m²]; NaN: not
          known. With ∫dm = m and ∫(z − z_O) dm = m z_G these are the participation integrals
          of a rotation about O, whose virtual horizontal displacement is δx ∝ z − z_O: the
          code check's participating mass M* = (m z_G)²/J_z (``homlimit.check.ntc``).
    """

    m: float = ranged(0.0, lo_open=True)
    x_G: float = ranged()           # any finite number
    z_G: float = ranged(0.0, lo_open=True)
    I_O: float = ranged(0.0, lo_open=True)
    J_z: float = math.nan

    def __post_init__(self):
        check_fields(self)
        i_min = self.m * (self.x_G ** 2 + self.z_G ** 2)
        if self.I_O < i_min * (1 - 1e-12):
            raise ParameterError(f"I_O = {self.I_O!r} is out of range: the polar inertia about O "
                                 f"must be at least m r_G² = {i_min:g} (parallel-axis theorem)")
        if not math.isnan(self.J_z):
            # Cauchy–Schwarz: (∫z dm)² <= m ∫z² dm; and ∫z² dm = I_O − ∫x² dm <= I_O − m x_G²
            lo, hi = self.m * self.z_G ** 2, self.I_O - self.m * self.x_G ** 2
            tol = 1e-12 * self.I_O
            if not (math.isfinite(self.J_z) and lo - tol <= self.J_z <= hi + tol):
                raise ParameterError(f"J_z = {self.J_z!r} kg m^2 is out of range: allowed "
                                     f"m z_G² = {lo:g} <= J_z <= I_O − m x_G² = {hi:g}")
            set_fields(self, J_z=float(self.J_z))

    @property
    def r_G(self) -> float:
        """|OG|."""
        return math.hypot(self.x_G, self.z_G)

    @property
    def i(self) -> float:
        """i = I_O / m (eq. 4) [m²]."""
        return self.I_O / self.m

    @classmethod
    def from_triangles(cls, points, triangles, density,
                       O=(0.0, 0.0)) -> RigidBody:  # noqa: E741 (the paper's O)
        """The rigid body made of linear triangles with per-triangle densities, rotating about O.

        points (n_points, 2) in the section frame [m]; triangles (n_tri, 3) vertex indices;
        density: scalar or (n_tri,) mass per unit area [kg/m² per unit thickness, i.e. γ·s];
        O: rotation centre (x, z) [m]. Mass, G and I_O are integrated exactly (linear geometry).
        """
        points = np.asarray(points, float)
        triangles = np.asarray(triangles, int)
        if points.ndim != 2 or points.shape[1] != 2:
            raise ParameterError(f"points has shape {points.shape}: allowed (n_points, 2)")
        if triangles.ndim != 2 or triangles.shape[1] != 3 or len(triangles) == 0:
            raise ParameterError(f"triangles has shape {triangles.shape}: "
                                 "allowed (n_tri >= 1, 3)")
        if triangles.min() < 0 or triangles.max() >= len(points):
            raise ParameterError(f"triangles index range [{triangles.min()}, {triangles.max()}] is "
                                 f"out of range: allowed 0 <= index < {len(points)}")
        rho = np.broadcast_to(np.asarray(density, float), (len(triangles),))
        if not np.all(np.isfinite(rho)) or np.any(rho < 0):
            raise ParameterError(f"density min = {rho.min()!r} is out of range: "
                                 "allowed 0 <= density")
        A, Sx, Sz, J, Jz = triangle_moments(points, triangles, O, z2=True)
        m = float(rho @ A)
        check_range("mass of the triangles", m, 0.0, lo_open=True, unit="kg")
        return cls(m=m, x_G=float(rho @ Sx) / m, z_G=float(rho @ Sz) / m, I_O=float(rho @ J),
                   J_z=float(rho @ Jz))


def triangle_moments(points: np.ndarray, triangles: np.ndarray,
                     O=(0.0, 0.0), z2: bool = False):  # noqa: E741 (the paper's O)
    """Exact area, first and polar second moments about O of linear triangles (vectorised).

    For a triangle of area A with vertices p_1, p_2, p_3 (relative to O):
    ∫ dA = A,  ∫ x dA = A x_c,  ∫ x² dA = (A/6)(Σ_i x_i² + Σ_{i<j} x_i x_j), same for z.
    Returns (A, Sx, Sz, J) arrays of shape (n_triangles,), with J = ∫ (x² + z²) dA, and
    with ``z2`` also Jz = ∫ z² dA (the participation integral of ``RigidBody.J_z``).
    """
    p = np.asarray(points, float)[np.asarray(triangles, int)] - np.asarray(O, float)
    x, z = p[..., 0], p[..., 1]  # (n, 3)
    A = 0.5 * np.abs((x[:, 1] - x[:, 0]) * (z[:, 2] - z[:, 0])
                     - (x[:, 2] - x[:, 0]) * (z[:, 1] - z[:, 0]))

    def second(u):
        return (A / 6.0) * (np.sum(u * u, axis=1) + u[:, 0] * u[:, 1] + u[:, 1] * u[:, 2]
                            + u[:, 2] * u[:, 0])

    Jz = second(z)
    out = (A, A * x.mean(axis=1), A * z.mean(axis=1), second(x) + Jz)
    return (*out, Jz) if z2 else out
