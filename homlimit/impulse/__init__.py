"""The energy-based impulse criterion (paper eqs 1–7, 18–19) and the rigid body it acts on."""

from .body import RigidBody, triangle_moments
from .criterion import (
    collapse_velocity,
    hinge_impulse_ratio,
    no_bond_reason,
    peak_of,
    peak_work,
    rigid_restoring_work,
    theta_dot0,
)
from .loads import LoadWork, peak_with_loads, work_with_loads

__all__ = ["LoadWork", "RigidBody", "collapse_velocity", "hinge_impulse_ratio", "no_bond_reason",
           "peak_of", "peak_with_loads", "peak_work", "rigid_restoring_work", "theta_dot0",
           "triangle_moments", "work_with_loads"]
