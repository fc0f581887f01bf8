"""The simple overturning of the façade about its toe (``closed_form.real``): mechanism I
without the abutment friction, with ties, floors and a finite f_c (docs/real-walls.md).

A model of its own (``[analysis] overturning``, off by default, so that the paper's runs and
the closed forms' batched sweeps are unchanged) with one mechanism, "overturning", registered
like I and II, with its rocker (``dynamics.RealWallRocker``, exact geometry) for the hinge
check and the pulse spectra.
"""

from __future__ import annotations

from . import registry
from .models import real_closed_forms, stage
from .models_rigid import closed_form_alone, real_rocker
from .registry import Mechanism, Model

__all__ = ["run_overturning"]


def run_overturning(config, result) -> None:
    """Mechanism "overturning" at its critical λ, and its curve v̄_g(λ)."""
    with stage(result.timings, "closed-form simple overturning"):
        mechanisms, curves = real_closed_forms(config, ("overturning",))
        result.mechanisms.update(mechanisms)
        result.curves.update(curves)


registry.register(
    Model("overturning", lambda config: config.analysis.overturning, run_overturning),
    Mechanism("overturning", model="overturning", rocker=real_rocker,
              alone=closed_form_alone("overturning"),
              checked=("lam", "h", "vg", "vnorm", "theta_m", "W_m"),
              body_checked=("m", "x_G", "z_G", "I_O", "J_z"), static=True, colour="tab:brown",
              marker="s", size=8))
