"""A mechanism's ties and floors in its one-degree-of-freedom restoring work (issue 30).

``LoadWork`` holds the floors' and ties' parts of W(q) and of the moment dW/dq of a mechanism
shape turning by q (the FE mechanism's, ``mechanism.fe_impulse``: a block turning exactly,
the rest carried to first order). It is the one home of these expressions: the FE impulse
criterion's W(q) (``fe_impulse.generalised_impulse``) and the FE body's rocker
(``dynamics.GeneralisedRocker``) both evaluate them, so that the rocker's θ_m, W_m and v̄_g
are the criterion's. A tie's work and force are the closed forms' (``closed_form.real``
``tie_work`` and its derivative ``tie_force``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import ParameterError
from .body import RigidBody
from .criterion import peak_of

__all__ = ["LoadWork", "N_THETA", "peak_with_loads", "work_with_loads"]

N_THETA = 2049          # the q grid of W's peak with ties or floors, then bounded Brent


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

    A tie's work is ``closed_form.real.tie_work`` (δ), its force ``tie_force`` = its
    derivative, so moment(q) = d(parts(q))/dq exactly (the tie's contribution N(δ) dδ/dq).
    The tie is memoryless, as the closed forms' rockers' (``dynamics.real_rocker``).
    """

    floors_body: tuple = ()
    floors_rest: tuple = ()
    ties_body: tuple = ()
    ties_rest: tuple = ()

    def __bool__(self) -> bool:
        return bool(self.floors_body or self.floors_rest or self.ties_body or self.ties_rest)

    def _arrays(self):
        return [np.asarray(r, float).reshape(-1, n) for r, n in (
            (self.floors_body, 3), (self.floors_rest, 2), (self.ties_body, 4),
            (self.ties_rest, 4))]

    def parts(self, q):
        """(W_floors, W_ties) [J] at q (vectorised: arrays of q's shape)."""
        from ..closed_form.real import tie_work

        fb, fr, tb, tr = self._arrays()
        q = np.asarray(q, float)[..., None]
        s, c1 = np.sin(q), np.cos(q) - 1.0
        W_f = (np.sum(fb[:, 0] * (fb[:, 1] * s + fb[:, 2] * c1), axis=-1)
               + np.sum(fr[:, 0] * fr[:, 1] * q, axis=-1))
        W_t = (np.sum(tie_work(np.maximum(tb[:, 0] * s, 0.0), tb[:, 1], tb[:, 2], tb[:, 3]),
                      axis=-1)
               + np.sum(tie_work(tr[:, 0] * q, tr[:, 1], tr[:, 2], tr[:, 3]), axis=-1))
        return W_f, W_t

    def work(self, q):
        """W_floors + W_ties [J] at q (vectorised)."""
        W_f, W_t = self.parts(q)
        return W_f + W_t

    def moment(self, q):
        """dW/dq [N m] of the floors and ties at q >= 0 (vectorised): Q ((x − x_O) cos q −
        (z − z_O) sin q) and Q φ_z for the floors, N(δ) dδ/dq for the ties (d cos q on the
        body where d > 0, else 0; a on the rest), N = ``tie_force`` (a rigid-plastic tie
        pulls with T_y from q = 0, so the moment at rest includes T_y d)."""
        from ..closed_form.real import tie_force

        fb, fr, tb, tr = self._arrays()
        q = np.asarray(q, float)[..., None]
        c, s = np.cos(q), np.sin(q)
        R = (np.sum(fb[:, 0] * (fb[:, 1] * c - fb[:, 2] * s), axis=-1)
             + np.sum(fr[:, 0] * fr[:, 1] + 0.0 * q, axis=-1))
        d = tb[:, 0]
        R = R + np.sum(tie_force(np.maximum(d * s, 0.0), tb[:, 1], tb[:, 2], tb[:, 3])
                       * np.where(d > 0, d * c, 0.0), axis=-1)
        return R + np.sum(tie_force(tr[:, 0] * q, tr[:, 1], tr[:, 2], tr[:, 3]) * tr[:, 0],
                          axis=-1)

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
