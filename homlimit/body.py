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

from .errors import ParameterError, check_range

__all__ = ["RigidBody"]


@dataclass(frozen=True)
class RigidBody:
    """A rigid body per unit out-of-plane thickness (or with its actual mass), rotating about O.

    m   : mass [kg] (per unit thickness: kg/m)
    x_G : horizontal distance of G from O, measured towards the restoring side [m] (x_G > 0:
          gravity opposes the overturning, the paper's x_G of eq. 17)
    z_G : height of G above O [m] (> 0)
    I_O : polar moment of inertia about O [kg m²] (same thickness convention as m)
    """

    m: float
    x_G: float
    z_G: float
    I_O: float

    def __post_init__(self):
        for name in ("m", "z_G", "I_O"):
            object.__setattr__(self, name, check_range(name, getattr(self, name), 0.0,
                                                       lo_open=True))
        object.__setattr__(self, "x_G", check_range("x_G", self.x_G))
        i_min = self.m * (self.x_G ** 2 + self.z_G ** 2)
        if self.I_O < i_min * (1 - 1e-12):
            raise ParameterError(f"I_O = {self.I_O!r} is out of range: the polar inertia about O "
                                 f"must be at least m r_G² = {i_min:g} (parallel-axis theorem)")

    @property
    def r_G(self) -> float:
        """|OG|."""
        return math.hypot(self.x_G, self.z_G)

    @property
    def i(self) -> float:
        """i = I_O / m (eq. 4) [m²]."""
        return self.I_O / self.m
