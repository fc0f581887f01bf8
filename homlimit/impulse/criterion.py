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

import numpy as np

from ..errors import ParameterError, check_range
from ..params import G_STANDARD
from .body import RigidBody

__all__ = ["theta_dot0", "peak_work", "peak_of", "rigid_restoring_work", "collapse_velocity",
           "hinge_impulse_ratio", "no_bond_reason"]

N_PEAK = 2049           # the grid of ``peak_of``, then bounded Brent


def no_bond_reason(cohesion: float, tension: float, model: str, takes: str) -> str:
    """Why eq. 7 gives ``model`` no v̄_g with a joint cohesion or tension (the rigid blocks'
    ``blocks.impulse.no_bond``, the FE path's ``mechanism.fe_impulse.no_bond``): their
    dissipation at finite rotation is not rigid-plastic (a bond softens once it has opened or
    slid a little), so W(θ) would hang on a softening rule the case file does not state.
    ``takes``: what of ``model`` does take them (docs/real-walls.md "FE impulse")."""
    return (f"[masonry] cohesion = {cohesion!r} Pa, tension = {tension!r} Pa: v̄_g (eq. 7) of "
            f"{model} does not take a joint cohesion or tension: their dissipation at finite "
            f"rotation needs a softening rule the case file does not state ({takes}; "
            "docs/real-walls.md \"FE impulse\"); allowed 0 Pa for v̄_g")


def theta_dot0(body: RigidBody, v_g: float) -> float:
    """Angular velocity right after the impulse, θ̇0 = m z_G v_g / I_O [rad/s] (eq. 4)."""
    return body.m * body.z_G * float(v_g) / body.I_O


def peak_work(body: RigidBody, lift: float = 0.0, g: float = G_STANDARD
              ) -> tuple[float, float]:
    """The peak (θ_m, W(θ_m)) of the restoring work of the body turning about O by θ, plus a
    work ``lift``·θ done by material carried linearly (a fan's dilatant lift, [N m]):

        W(θ) = m g (x_G sin θ + z_G cos θ − z_G) + lift θ,
        dW/dθ = m g r_G cos(θ + φ_G) + lift = 0,  φ_G = atan2(z_G, x_G),
        θ_m = arccos(−lift / (m g r_G)) − φ_G.

    For lift = 0, θ_m = atan(x_G/z_G): G over the vertical through O, W = m g (r_G − z_G)
    (eq. 18). W never peaks if lift >= m g r_G (ParameterError); θ_m = 0 and W = 0 if the body
    has no restoring lever.
    """
    g = check_range("g", g, 0.0, lo_open=True, unit="m/s^2")
    lift = check_range("lift", lift, 0.0, unit="N m")
    mgr = body.m * g * body.r_G
    if lift >= mgr:
        raise ParameterError(f"lift = {lift:g} N m is out of range: the restoring work has no "
                             f"peak unless lift < m g r_G = {mgr:g} N m")
    theta = math.acos(-lift / mgr) - math.atan2(body.z_G, body.x_G)
    if theta <= 0.0:
        return 0.0, 0.0
    W = body.m * g * (body.x_G * math.sin(theta) + body.z_G * (math.cos(theta) - 1.0))
    return theta, W + lift * theta


def peak_of(total, n: int = N_PEAK) -> float:
    """The θ of the largest restoring work ``total(θ)`` (vectorised over θ) over 0 <= θ <= π/2:
    the best of a grid of ``n`` points, refined by bounded Brent between its neighbours (for a
    W with ties, floors or dissipation, which has no closed-form peak: the blocks' and the FE
    impulse's real-wall rule)."""
    from scipy.optimize import minimize_scalar

    n = int(check_range("n", n, 3, 10 ** 7))
    grid = np.linspace(0.0, math.pi / 2, n)
    k = int(np.argmax(total(grid)))
    lo, hi = grid[max(k - 1, 0)], grid[min(k + 1, n - 1)]
    opt = minimize_scalar(lambda t: -float(total(t)), bounds=(lo, hi), method="bounded",
                          options={"xatol": 1e-12})
    return float(opt.x) if -opt.fun >= total(grid[k]) else float(grid[k])


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


def hinge_impulse_ratio(body: RigidBody) -> float:
    """|P_x/P_z| of the impulse the hinge O must transmit when an ideal impulse v_g sets the
    body rotating (eq. 4): P_x = m v_g (i − z_G²)/i, P_z = m v_g x_G z_G/i, so
    |P_x/P_z| = (i − z_G²)/(x_G z_G). Above the friction coefficient f of the bed joint under O
    the hinge slides instead (the ideal impulse is not attainable without sliding)."""
    if body.x_G <= 0:
        return math.inf
    return (body.i - body.z_G ** 2) / (body.x_G * body.z_G)
