"""A mechanism's ties and floors in its one-degree-of-freedom restoring work (issue 30).

``LoadWork`` holds the floors' and ties' parts of W(q) and of the moment dW/dq of a mechanism
shape turning by q (the FE mechanism's, ``mechanism.fe_impulse``: a block turning exactly,
the rest carried to first order). It is the one home of these expressions: the FE impulse
criterion's W(q) (``fe_impulse.generalised_impulse``) and the FE body's rocker
(``dynamics.GeneralisedRocker``) both evaluate them, so that the rocker's θ_m, W_m and v̄_g
are the criterion's. The tie law is here too, ``tie_work`` and its derivative ``tie_force``:
the closed forms, the rockers and the blocks' impulse read it from here.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numpy as np

from ..errors import ParameterError
from .body import RigidBody
from .criterion import peak_of

__all__ = ["LoadWork", "N_THETA", "peak_with_loads", "tie_force", "tie_work", "work_with_loads"]

N_THETA = 2049          # the q grid of W's peak with ties or floors, then bounded Brent


def tie_work(delta, T, k, du):
    """∫ min(kδ, T_y) dδ up to min(δ, δ_u) (k = 0: T_y δ), elementwise."""
    x = np.minimum(delta, du)
    with np.errstate(divide="ignore", invalid="ignore"):
        dy = np.where(k > 0, T / k, 0.0)
        elastic = np.where(x <= dy, 0.5 * k * x ** 2, T * (x - 0.5 * dy))
    return np.where(k > 0, elastic, T * x)


def tie_force(delta, T, k, du):
    """The tie's force N(δ) = d(``tie_work``)/dδ [N], elementwise: min(kδ, T_y) (k = 0: T_y
    from δ = 0, rigid-plastic) while 0 <= δ < δ_u, zero beyond the ductility limit and for
    δ < 0 (a tie does not push)."""
    delta = np.asarray(delta, float)
    on = (delta >= 0) & (delta < du)
    return np.where(on, np.where(k > 0, np.minimum(k * delta, T), T), 0.0)


@dataclass(frozen=True)
class LoadWork:
    """The floors' and ties' parts of a mechanism shape's W(q) and of its moment dW/dq, per
    bay (``fe_impulse.BodyLoads``' units), as functions of the block's rotation q (module
    docstring; ``fe_impulse._load_work`` builds it from a mechanism):

    floors_body  rows (Q [N], x − x_O [m], z − z_O [m]): a floor load on the body, turning
                 with it exactly, W = Q ((x − x_O) sin q + (z − z_O)(cos q − 1))
    floors_rest  rows (Q [N], φ_z [m/rad]): a floor load on the rest, W = Q φ_z q
    ties_body    rows (d = z_T − z_O [m], T_y [N], k [N/m], δ_u [m]): a tie on the body,
                 δ = max(0, d sin q)
    ties_rest    rows (a = max(0, −φ_x) [m/rad], T_y, k, δ_u): a tie on the rest, δ = a q

    A tie's work is ``tie_work`` (δ), its force ``tie_force`` = its
    derivative, so moment(q) = d(parts(q))/dq exactly (the tie's contribution N(δ) dδ/dq).
    The tie is memoryless, as the closed forms' rockers' (``dynamics.real_rocker``).
    """

    floors_body: tuple = ()
    floors_rest: tuple = ()
    ties_body: tuple = ()
    ties_rest: tuple = ()

    def __bool__(self) -> bool:
        return bool(self.floors_body or self.floors_rest or self.ties_body or self.ties_rest)

    @functools.cached_property
    def _pre(self):
        """The rows as arrays, once: the body's floors (Q, x, z), the rest's floors' constant
        moment Σ Q φ_z, and the ties' (D_body, max(D_body, 0), D_rest, (T_y, k, δ_u)) with
        D_body = d on the body (0 on the rest), D_rest = a on the rest (0 on the body), so
        that δ = max(D_body sin q, 0) + D_rest q and dδ/dq = max(D_body, 0) cos q + D_rest."""
        fb = np.asarray(self.floors_body, float).reshape(-1, 3)
        fr = np.asarray(self.floors_rest, float).reshape(-1, 2)
        ties = np.asarray(self.ties_body + self.ties_rest, float).reshape(-1, 4)
        body = np.arange(len(ties)) < len(self.ties_body)
        d_body, d_rest = np.where(body, ties[:, 0], 0.0), np.where(body, 0.0, ties[:, 0])
        return (fb.T, float(fr[:, 0] @ fr[:, 1]),
                (d_body, np.maximum(d_body, 0.0), d_rest, ties[:, 1:].T))

    def parts(self, q):
        """(W_floors, W_ties) [J] at q (vectorised: arrays of q's shape)."""

        (Q, x, z), C_rest, (d_body, _, d_rest, law) = self._pre
        q = np.asarray(q, float)[..., None]
        s, c = np.sin(q), np.cos(q)
        W_f = np.sum(Q * (x * s + z * (c - 1.0)), axis=-1) + C_rest * q[..., 0]
        delta = np.maximum(d_body * s, 0.0) + d_rest * q
        return W_f, np.sum(tie_work(delta, *law), axis=-1)

    def work(self, q):
        """W_floors + W_ties [J] at q (vectorised)."""
        W_f, W_t = self.parts(q)
        return W_f + W_t

    def moment(self, q):
        """dW/dq [N m] of the floors and ties at q >= 0 (vectorised; a float for a scalar q,
        the rockers' hot path): Q ((x − x_O) cos q − (z − z_O) sin q) and Q φ_z for the
        floors, N(δ) dδ/dq for the ties (d cos q on the body where d > 0, else 0; a on the
        rest), N = ``tie_force`` (a rigid-plastic tie pulls with T_y from q = 0, so the
        moment at rest includes T_y d)."""

        (Q, x, z), C_rest, (d_body, d_pos, d_rest, law) = self._pre
        if np.ndim(q) == 0:
            q = float(q)
            s, c = math.sin(q), math.cos(q)
            R = C_rest + float(Q @ (x * c - z * s)) if len(Q) else C_rest
            if len(d_rest):
                N = tie_force(np.maximum(d_body * s, 0.0) + d_rest * q, *law)
                R += float(N @ (d_pos * c + d_rest))
            return R
        q = np.asarray(q, float)[..., None]
        s, c = np.sin(q), np.cos(q)
        N = tie_force(np.maximum(d_body * s, 0.0) + d_rest * q, *law)
        return (np.sum(Q * (x * c - z * s), axis=-1) + C_rest
                + np.sum(N * (d_pos * c + d_rest), axis=-1))

    def as_dict(self) -> dict:
        """Plain data for the FE cache (an infinite δ_u as None)."""
        inf = lambda rows: [[None if math.isinf(v) else v for v in r] for r in rows]  # noqa
        return {"floors_body": [list(r) for r in self.floors_body],
                "floors_rest": [list(r) for r in self.floors_rest],
                "ties_body": inf(self.ties_body), "ties_rest": inf(self.ties_rest)}

    @classmethod
    def from_dict(cls, d: dict) -> LoadWork:
        """The inverse of ``as_dict`` (None: an infinite δ_u)."""
        rows = lambda k: tuple(tuple(math.inf if v is None else float(v) for v in r)  # noqa
                               for r in d.get(k, ()))
        return cls(*(rows(k) for k in ("floors_body", "floors_rest", "ties_body",
                                       "ties_rest")))


def work_with_loads(body: RigidBody, lift: float, lw: LoadWork, g: float, q):
    """W(q) [J] of the one-DOF shape with its ties and floors (module docstring), vectorised:
    the body turning exactly, the rest's lift L q, and ``lw``'s floors' and ties' parts."""
    q = np.asarray(q, float)
    return (body.m * g * (body.x_G * np.sin(q) + body.z_G * (np.cos(q) - 1.0)) + lift * q
            + lw.work(q))


def peak_with_loads(body: RigidBody, lift: float, lw: LoadWork, g: float
                    ) -> tuple[float, float]:
    """(q_m, W(q_m)) of ``work_with_loads`` over 0 <= q <= π/2 (``impulse.peak_of`` on
    N_THETA points, then bounded Brent); a ParameterError unless W(q_m) > 0."""
    q_m = peak_of(lambda q: work_with_loads(body, lift, lw, g, q), N_THETA)
    W_m = float(work_with_loads(body, lift, lw, g, q_m))
    if not W_m > 0:
        raise ParameterError(f"W(q_m) = {W_m!r} J is out of range: the mechanism must be "
                             "restrained, allowed > 0 J")
    return q_m, W_m
