"""Energy-based impulse criterion for a body rotating about O (paper eqs 1–7, 18–19).

An impulse of peak ground velocity v_g (eq. 3) gives the failing body the angular velocity
θ̇0 = m z_G v_g / I_O (eq. 4). It overturns when its kinetic energy ½ I_O θ̇0² exceeds the peak
W(θ_m) of the restoring work along the motion (eqs 5–6), whence the collapse ground velocity

    v̄_g = (i / z_G) √(2 W(θ_m) / I_O),    i = I_O / m            (eq. 7).

For a rigid body restrained by gravity only, W(θ_m) = m g (r_G − z_G) (eq. 18), which gives
v̄_g = √((2 g i / z_G)(r_G / z_G − 1)) (eq. 19).
"""

from __future__ import annotations

import math

from ..errors import check_range
from ..params import G_STANDARD
from .body import RigidBody

__all__ = ["theta_dot0", "rigid_restoring_work", "collapse_velocity"]


def theta_dot0(body: RigidBody, v_g: float) -> float:
    """Angular velocity right after the impulse, θ̇0 = m z_G v_g / I_O [rad/s] (eq. 4)."""
    return body.m * body.z_G * float(v_g) / body.I_O


def rigid_restoring_work(body: RigidBody, g: float = G_STANDARD) -> float:
    """Peak restoring work of gravity, W(θ_m) = m g (r_G − z_G) [J] (eq. 18).

    Reached when G passes over the vertical through O; zero if x_G <= 0 (no restoring lever).
    """
    g = check_range("g", g, 0.0, lo_open=True, unit="m/s^2")
    if body.x_G <= 0.0:
        return 0.0
    return body.m * g * (body.r_G - body.z_G)


def collapse_velocity(body: RigidBody, W: float | None = None, g: float = G_STANDARD) -> float:
    """Collapse peak ground velocity v̄_g = (i / z_G) √(2 W(θ_m) / I_O) [m/s] (eq. 7).

    ``W`` is the peak restoring work W(θ_m) [J]; by default the rigid-body value of eq. 18.
    """
    if W is None:
        W = rigid_restoring_work(body, g)
    W = check_range("W", W, 0.0, unit="J")
    return body.i / body.z_G * math.sqrt(2.0 * W / body.I_O)
