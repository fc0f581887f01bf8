"""The collapse ground velocity of a discrete mechanism (paper eqs 4–7, 18, generalised).

The mechanism of ``limit.solve_blocks`` gives every block a velocity (u_i, w_i, ω_i) about its
centroid. Its *body* is found as the FE path finds it (``homlimit.fe_impulse``): a rotation ω
about a centre O is fitted to the fastest blocks (mass-weighted least squares), each moving
block gets its participation p_i = ⟨q_i, q_R,i⟩ / ⟨q_R,i, q_R,i⟩ in the block's kinetic-energy
inner product (m |v_G|² + I_G ω²; q_R,i the fitted rotation's velocity of block i), the body is
the blocks with p_i >= 1/2, and the fit is repeated on the body until it no longer changes.

With the shape φ = q/ω (unit rotation rate of the body) and one degree of freedom, the body's
rotation angle θ (``fe_impulse``'s one-DOF generalisation, for rigid blocks):
- generalised mass M = Σ_i m_i |φ_Gi|² + I_Gi φ_ωi²  (= I_O for one rigid body);
- impulse M θ̇0 = v_g Π, Π = Σ_i m_i (−φ_ui)  (= m z_G, eq. 4);
- restoring work W(θ) = W_body + W_rest + W_friction:
  * W_body = m g (x_G sin θ + z_G cos θ − z_G): the body's exact rotation about O, with its
    exact mass properties (``RigidBody.from_triangles`` on the blocks' parts);
  * W_rest = θ g Σ_rest m_i φ_wi: the other moving blocks (a discrete fan), to first order;
  * W_friction: the friction dissipated at the sliding contacts of a non-associative
    mechanism (an associative one dissipates nothing: its dilatant lift is in W_body and
    W_rest). The counterpart of eqs 8–10 for the real bond: at sliding interface k the
    dissipation rate of the mechanism, D_k = Σ_ends |T| |φ_t| with the contact forces T of the
    static dual at collapse, falls linearly as the slip s_k = θ |φ_t,k| consumes the contact
    length ℓ_k (eq. 8's (c − u)), so W_friction = Σ_k D_k θ (1 − s_k / (2 ℓ_k)) while
    s_k < ℓ_k, and D_k ℓ_k / (2 |φ_t,k|) after;
- the body tips over when its G passes over the vertical through O, θ_m = atan(x_G / z_G)
  (eq. 18), and v̄_g = √(2 W(θ_m) M) / Π  (eq. 7). For one rigid body restrained by gravity
  only this is eq. 19 exactly.

A real wall (ties, floors, f_c: ``blocks.real``, docs/real-walls.md "Rigid blocks"): W(θ) =
W_body + W_rest + W_crushing + W_floors + W_ties is maximised over 0 <= θ <= π/2 instead (the
closed forms' rule), with W_crushing = θ D/|ω| (the mechanism's crushing dissipation rate D:
a rigid-plastic stress block keeps its depth), a floor's load turning with its block (exactly
on the body, to first order on the rest) and the tie law (``impulse.loads.
tie_work``) on the elongation (z_T − z_O) sin θ (body) or −φ_u θ (rest).

Not with a joint cohesion or tension (``blocks.real``): the limit analysis takes them as
rigid-plastic strengths, but their dissipation at finite rotation is not rigid-plastic (a
joint's bond softens and is lost once it has opened or slid a little, while θ D/|ω| would
count it over the whole rotation), so W(θ) would hang on a softening rule the case file does
not state. ``block_impulse`` refuses such an assembly (a ParameterError: the h-scan reports
v̄_g "not available" with the reason), as the FE path's impulse does (docs/real-walls.md
"FE impulse").

Approximations (stated, not hidden): the mechanism is followed with a fixed shape (no
geometry update of the contacts, no change of mechanism during the motion); the rest's lift
is linear in θ; the friction forces are those at collapse, reduced only by the lost overlap.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..errors import ParameterError, check_range
from ..impulse import RigidBody, no_bond_reason, peak_of
from .geometry import Assembly
from .limit import BlockLimitResult, check_result, fit_rotation
from .real import real_of

__all__ = ["BlockImpulse", "failing_body", "block_impulse", "participation", "no_bond",
           "rigid_body_of"]


@dataclass(frozen=True)
class BlockImpulse:
    """The impulse criterion of one discrete mechanism (module docstring).

    vg [m/s], vnorm = vg/√(g b); method: "rigid body (eqs 7, 18)" when the moving blocks are
    one rigid body, else "one-DOF (eqs 4-7 generalised)"; O (x_O, z_O) [m]; h = z_top − z_O
    [m]; body: the ``RigidBody`` of the blocks of participation >= 1/2 about O; n_body and
    n_moving blocks; M [kg m²], Pi [kg m], theta_m [rad]; W_m = W(θ_m) [J] and its parts
    W_body, W_rest, W_friction; M_rest_share: the share of M outside the body; multiplier λ.
    """

    vg: float
    vnorm: float
    method: str
    O: tuple  # noqa: E741 (the paper's O)
    h: float
    body: RigidBody
    n_body: int
    n_moving: int
    M: float
    Pi: float
    theta_m: float
    W_m: float
    W_body: float
    W_rest: float
    W_friction: float
    M_rest_share: float
    multiplier: float
    body_mask: np.ndarray = field(repr=False, default=None)
    W_real: dict = field(default_factory=dict)

    def as_dict(self) -> dict:
        return {"vg": self.vg, "vnorm": self.vnorm, "method": self.method,
                "x_O": self.O[0], "z_O": self.O[1], "h": self.h, "n_body": self.n_body,
                "n_moving": self.n_moving, "m_body": self.body.m, "x_G": self.body.x_G,
                "z_G": self.body.z_G, "I_O": self.body.I_O, "M": self.M, "Pi": self.Pi,
                "theta_m": self.theta_m, "W_m": self.W_m, "W_body": self.W_body,
                "W_rest": self.W_rest, "W_friction": self.W_friction,
                "M_rest_share": self.M_rest_share, "multiplier": self.multiplier,
                **self.W_real}


def _energy_inner(assembly: Assembly, q1: np.ndarray, q2: np.ndarray) -> np.ndarray:
    """Per block m (u1 u2 + w1 w2) + I_G ω1 ω2."""
    return (assembly.mass * (q1[:, 0] * q2[:, 0] + q1[:, 1] * q2[:, 1])
            + assembly.inertia * q1[:, 2] * q2[:, 2])


def _rotation(assembly: Assembly, O, omega: float) -> np.ndarray:  # noqa: E741 (the paper's O)
    """Block velocities (u, w, ω) of a rigid rotation ω about O."""
    G = assembly.centroid
    return np.c_[-omega * (G[:, 1] - O[1]), omega * (G[:, 0] - O[0]),
                 np.full(G.shape[0], omega)]


def participation(assembly: Assembly, q: np.ndarray, O, omega: float) -> np.ndarray:  # noqa: E741
    """Per block, p_i = ⟨q_i, q_R,i⟩ / ⟨q_R,i, q_R,i⟩ in the kinetic-energy inner product, q_R
    the rotation ω about O (module docstring); 0 where q_R vanishes."""
    qR = _rotation(assembly, O, omega)
    den = _energy_inner(assembly, qR, qR)
    return np.where(den > 0, _energy_inner(assembly, q, qR) / np.maximum(den, 1e-300), 0.0)


def failing_body(assembly: Assembly, result: BlockLimitResult, level: float = 0.5,
                 max_iter: int = 20):
    """(body mask, O, ω): the blocks of participation >= ``level`` in the rotation fitted to
    them (module docstring), found by fixed-point iteration from the blocks moving at more
    than half the top speed."""
    level = check_range("level", level, 0.0, 1.0, lo_open=True, hi_open=True)
    q = result.velocity
    moving = result.moving
    if not np.any(moving):
        raise ParameterError("result has 0 moving blocks: allowed a mechanism")
    speed = result.speed(assembly)
    body = moving & (speed >= 0.5 * speed[moving].max())
    for _ in range(max_iter):
        fit = fit_rotation(assembly, q, body, at_rest=~moving)
        O, omega = fit.O, fit.omega  # noqa: E741 (the paper's O)
        if not math.isfinite(O[0]):
            raise ParameterError("the mechanism's fastest blocks do not rotate (ω = 0): a "
                                 "translation has no tipping angle, allowed a rotating body")
        p = participation(assembly, q, O, omega)
        new = moving & (p >= level)
        if not np.any(new) or np.array_equal(new, body):
            break
        body = new
    size = float(np.ptp(assembly.vertices, axis=0).max())
    G = assembly.centroid[body].mean(axis=0)
    if math.hypot(O[0] - G[0], O[1] - G[1]) > 10.0 * size:
        raise ParameterError(f"rotation centre at {math.hypot(O[0] - G[0], O[1] - G[1]):.3g} m "
                             f"from the body is out of range: allowed within 10 × the "
                             f"assembly's size ({size:.3g} m); the mechanism is a translation "
                             "(sliding), which has no tipping angle for eq. 7")
    return body, O, omega


def block_impulse(assembly: Assembly, result: BlockLimitResult, g: float | None = None
                  ) -> BlockImpulse:
    """v̄_g of the discrete mechanism ``result`` of ``assembly`` (module docstring)."""
    check_result(assembly, result)
    no_bond(assembly)
    g = check_range("g", assembly.meta.get("g", 9.81) if g is None else g, 0.0, lo_open=True,
                    unit="m/s^2")
    body_mask, O, omega = failing_body(assembly, result)  # noqa: E741 (the paper's O)
    body_mask = body_mask & ~assembly.fixed
    phi = result.velocity / omega
    moving = ~assembly.fixed          # the whole mode: slow blocks count too
    e = _energy_inner(assembly, phi, phi)
    M = float(e[moving].sum())
    Pi = float((assembly.mass * -phi[:, 0])[moving].sum())
    rest = moving & ~body_mask
    pts, tri, dens, _ = assembly.triangles(body_mask)
    body = RigidBody.from_triangles(pts, tri, dens, O=O)
    real = real_of(assembly) if result.actions else None
    if (body.x_G <= 0 and real is None) or Pi <= 0:     # a real wall: W(θ_m) > 0 below
        raise ParameterError(f"x_G = {body.x_G:.4g} m, Pi = {Pi:.4g} kg m are out of range: "
                             "the body must have a restoring lever (x_G > 0) and be driven "
                             "by the impulse (Pi > 0)")
    W_real = None
    if real is not None:                          # a real wall: W(θ) maximised (its parts)
        theta_m, W_body, W_rest, W_real = _real_peak(assembly, result, real, body, body_mask,
                                                     rest, phi, O, omega, g)
        W_fric = 0.0
    else:
        theta_m = math.atan2(body.x_G, body.z_G)
        W_body = body.m * g * (body.r_G - body.z_G)                # eq. 18 at θ_m
        W_rest = theta_m * g * float((assembly.mass * phi[:, 1])[rest].sum())
        W_fric = 0.0
    if result.friction == "non-associative":
        jt = assembly.interfaces
        slip = np.abs(result.slip) / abs(omega)                # |φ_t| per end point
        D = (np.abs(result.shear) * slip).sum(axis=1)          # dissipation rate per interface
        sk = theta_m * slip.mean(axis=1)
        ell = jt.length
        with np.errstate(divide="ignore", invalid="ignore"):
            w_in = D * theta_m * (1.0 - sk / (2.0 * ell))
            w_out = D * ell / (2.0 * np.maximum(slip.mean(axis=1), 1e-300))
        W_fric = float(np.where(D > 0, np.where(sk < ell, w_in, w_out), 0.0).sum())
    W_m = W_body + W_rest + W_fric + (sum(W_real.values()) if W_real else 0.0)
    if not W_m > 0:
        raise ParameterError(f"W(theta_m) = {W_m!r} J is out of range: the mechanism must be "
                             "restrained, allowed > 0 J")
    vg = math.sqrt(2.0 * W_m * M) / Pi
    b = float(assembly.meta.get("b", 1.0))
    rigid = float(e[rest].sum()) <= 1e-9 * M
    z_top = float(assembly.meta.get("H", assembly.bounds()[:, 3].max()))
    return BlockImpulse(vg=vg, vnorm=vg / math.sqrt(g * b),
                        method="rigid body (eqs 7, 18)" if rigid else
                        "one-DOF (eqs 4-7 generalised)",
                        O=(float(O[0]), float(O[1])), h=z_top - float(O[1]), body=body,
                        n_body=int(body_mask.sum()), n_moving=int(result.moving.sum()), M=M,
                        Pi=Pi,
                        theta_m=theta_m, W_m=W_m, W_body=W_body, W_rest=W_rest,
                        W_friction=W_fric, M_rest_share=float(e[rest].sum()) / M,
                        multiplier=result.multiplier, body_mask=body_mask,
                        W_real=W_real or {})


def no_bond(assembly: Assembly) -> None:
    """A ParameterError naming [masonry] cohesion and tension if ``assembly``'s joints have a
    bond (module docstring: W(θ) would need a softening rule)."""
    real = real_of(assembly)
    if real is not None and real.bond:
        raise ParameterError(no_bond_reason(real.cohesion, real.tension, "the blocks",
                                            "the blocks' multiplier takes them"))


def rigid_body_of(assembly: Assembly, result: BlockLimitResult) -> tuple:
    """(RigidBody, O) of the blocks of participation >= 1/2 in ``result``'s mechanism about
    its fitted centre O (``failing_body``), without the impulse: the static check's body."""
    check_result(assembly, result)
    mask, O, _ = failing_body(assembly, result)  # noqa: E741 (the paper's O)
    pts, tri, dens, _ = assembly.triangles(mask & ~assembly.fixed)
    return RigidBody.from_triangles(pts, tri, dens, O=O), O


N_THETA = 2049          # the θ grid of W's peak (a real wall), then bounded refinement


def _real_peak(assembly, result, real, body, body_mask, rest, phi, O, omega, g):  # noqa: E741
    """θ_m and the parts of W(θ_m) of a real wall's mechanism (module docstring, "A real
    wall"): (θ_m, W_body, W_rest, {"W_crushing", "W_floors", "W_ties"}), W maximised over
    0 <= θ <= π/2 on a grid, then refined (bounded Brent)."""
    from ..impulse.loads import tie_work

    act = result.actions
    G = assembly.centroid
    rest_rate = g * float((assembly.mass * phi[:, 1])[rest].sum())
    crush_rate = float(np.sum(act["crushing_rate"])) / abs(omega)
    fl, ti = real.floors, real.ties

    def split(blocks):
        ok = blocks >= 0
        b = np.maximum(blocks, 0)
        return ok & body_mask[b], ok & rest[b], b

    fb, fr, fblk = split(act["floor_block"])
    tb, tr, tblk = split(act["tie_block"])
    # a load on the body turns with it exactly; on the rest, first order (φ_w at its point)
    Q = fl[:, 1]
    phi_w = phi[fblk, 1] + phi[fblk, 2] * (fl[:, 2] - G[fblk, 0])
    phi_u = phi[tblk, 0] - phi[tblk, 2] * (ti[:, 0] - G[tblk, 1])
    d_t = ti[:, 0] - O[1]

    def parts(th):
        th = np.asarray(th, float)[..., None]
        s, c1 = np.sin(th), np.cos(th) - 1.0
        W_body = body.m * g * (body.x_G * s[..., 0] + body.z_G * c1[..., 0])
        W_f = np.sum(np.where(fb, Q * ((fl[:, 2] - O[0]) * s + (fl[:, 0] - O[1]) * c1), 0.0)
                     + np.where(fr, Q * phi_w * th, 0.0), axis=-1)
        # tie elongation: d sin θ on the body (the closed forms' rule), −φ_u θ on the rest
        delta = np.where(tb, d_t * s, np.where(tr, np.maximum(-phi_u, 0.0) * th, 0.0))
        W_t = np.sum(tie_work(delta, ti[:, 1], ti[:, 2],
                              np.where(ti[:, 3] > 0, ti[:, 3], np.inf)), axis=-1)
        return W_body, rest_rate * th[..., 0], crush_rate * th[..., 0], W_f, W_t

    def total(th):
        return sum(parts(th))

    th = peak_of(total, N_THETA)
    W_body, W_rest, W_c, W_f, W_t = (float(v) for v in parts(th))
    return th, W_body, W_rest, {"W_crushing": W_c, "W_floors": W_f, "W_ties": W_t}
