"""The rigid-body models of ``app.models``' registry: the closed forms (mechanisms I,
eqs 8–14, and II, eqs 16–20, and the real-wall closed forms of ``closed_form.real``) with
their v̄_g(λ) curves, the rigid blocks (``blocks.analyse_blocks``), the DEM
(``app.dem_stage``), and the rockers of rigid mechanisms (pulse spectra, hinge check)."""

from __future__ import annotations

import math

import numpy as np

from ..blocks import analyse_blocks
from ..closed_form import mechanisms as mech
from ..closed_form import real
from ..dynamics import MechanismIRocker, RealWallRocker, RigidRocker
from ..errors import ParameterError
from . import plots
from .stages import solver_options, stage

__all__ = ["blocks_files", "closed_form_alone", "closed_form_files", "closed_forms",
           "no_joint_strength", "no_real_wall", "real_closed_forms", "real_rocker",
           "rigid_rocker", "rocker_I", "run_blocks", "run_closed_forms", "run_dem"]


# ----------------------------------------------------------------------------- closed forms
def closed_forms(config) -> tuple[dict, dict]:
    """Mechanisms I and II at their critical λ, and their curves name → (λ, v̄_g(λ), label)
    over 0 < λ <= H/b (II: up to its wedge's limit)."""
    case, an = config.case, config.analysis
    if case.real:                     # ties, floors, finite fc: docs/real-walls.md
        return real_closed_forms(config, ("detachment", "crack"))
    m1 = mech.mechanism_I(case)
    m2 = mech.mechanism_II(case, tanpsi=an.tanpsi or None)  # 0: eq. 16's √(cf/a)
    w = case.wall
    lam = np.linspace(w.lam_max / an.lam_points, w.lam_max, an.lam_points)
    scale = math.sqrt(w.g * w.b)
    lam2 = lam[lam <= m2.lam_max * (1 + 1e-12)]
    curves = {m1.name: (lam, mech.vnorm_I(lam, case.rho, case.alpha, case.beta) * scale,
                        "mechanism I (detachment)"),
              m2.name: (lam2, mech.vnorm_II(lam2, case.rho, m2.tanpsi) * scale,
                        f"mechanism II (diagonal crack, tan ψ = {m2.tanpsi:.3f})")}
    return {m1.name: m1, m2.name: m2}, curves


def real_closed_forms(config, kinds) -> tuple[dict, dict]:
    """``closed_forms`` of a real wall (``closed_form.real``): the mechanisms ``kinds`` at
    their critical λ and their curves over 0.5 <= λ <= their largest λ."""
    case, an = config.case, config.analysis
    tanpsi = an.tanpsi or None
    out, curves = {}, {}
    scale = math.sqrt(case.wall.g * case.wall.b)
    for kind in kinds:
        m = real.real_mechanism(case, kind, tanpsi=tanpsi)
        lam = np.linspace(m.lam_max / an.lam_points, m.lam_max, an.lam_points)
        lam = lam[lam >= real.LAM_MIN]
        out[m.name] = m
        curves[m.name] = (lam, real.vnorm_real(case, kind, lam, tanpsi) * scale, m.label)
    return out, curves



def run_closed_forms(config, result) -> None:
    with stage(result.timings, "closed-form mechanisms I and II"):
        mechanisms, result.curves = closed_forms(config)
        result.mechanisms.update(mechanisms)


def closed_form_files(result) -> dict:
    """vg_lambda.png: the curves v̄_g(λ), every mechanism's critical point, the FE scan and
    the paper's DEM value."""
    if not (result.config.output.png and result.curves):
        return {}
    return {"vg_lambda_png": ("vg_lambda.png", lambda p: plots.plot_vg_lambda(
        p, result.curves, result.mechanisms, fe=result.fe, dem=result.dem,
        title=f"case {result.name}", b=result.case.wall.b))}

def run_blocks(config, result) -> None:
    b = config.blocks
    with stage(result.timings, "rigid blocks", f"façade {b.facade}, {b.friction}"):
        result.blocks = analyse_blocks(config.case, b.facade, b.friction, b.step,
                                       b.non_associative_check,
                                       solver_options(config.analysis.tol))
    result.mechanisms[result.blocks.name] = result.blocks


def blocks_files(result) -> dict:
    """The rigid blocks' files (``BlocksAnalysis.files``), pictures and meshes as asked."""
    if result.blocks is None:
        return {}
    cfg = result.config.output
    return {name.replace(".", "_"): (name, data)
            for name, data in result.blocks.files().items()
            if (cfg.png or not name.endswith(".png")) and (cfg.vtu or not name.endswith(".vtu"))}


def run_dem(config, result, map=None) -> None:
    """The DEM's collapse threshold (``app.dem_stage``): a model that returns v̄_g, the failing
    height and the slide flags directly, not a mechanism; its series is written by
    ``dem_stage.write_files``. ``map``: every trial a task of it (``dem_threshold``)."""
    from .dem_stage import dem_threshold

    dem = config.dem
    with stage(result.timings, "DEM threshold", f"{dem.loading}, bisection to "
                                                f"±{100 * dem.rel_tol:g} %"):
        result.dem_run = dem_threshold(config, map)

# ----------------------------------------------------------------------------- the rockers
def no_real_wall(case, what: str) -> None:
    """A ParameterError naming the real-wall inputs (ties, floors, fc, ...) that ``what``
    does not take yet, if the case has any (docs/real-walls.md)."""
    if case.real:
        raise ParameterError(f"{', '.join(case.real_inputs())}: {what} does not take ties, "
                             "floors, fc, cohesion or tension yet; allowed a case without "
                             "them (docs/real-walls.md)")


def no_joint_strength(case, what: str) -> None:
    """A ParameterError naming [masonry] cohesion / tension if the case sets them: no rocker
    takes a joint strength (its work at finite rotation is not rigid-plastic)."""
    m = case.masonry
    keys = [f"[masonry] {k} = {getattr(m, k)!r} Pa" for k in ("cohesion", "tension")
            if getattr(m, k)]
    if keys:
        raise ParameterError(f"{', '.join(keys)}: {what} does not take a joint cohesion or "
                             "tension; allowed 0 Pa (docs/real-walls.md)")


def real_rocker(case, mechanism, gravity_I="linearised", restitution=0.0):
    """The rocker of a real wall's closed-form mechanism (``closed_form.real``: I, II or the
    overturning, fc, ties and floors; ``dynamics.RealWallRocker``) at the mechanism's λ;
    mechanism I's gravity per ``gravity_I``, II and the overturning exact."""
    what = f"the rocker of mechanism {mechanism.name} (pulse spectra, hinge check)"
    no_joint_strength(case, what)
    kind = getattr(mechanism, "kind", None)
    if kind not in real.KINDS:
        no_real_wall(case, what)            # not a closed form of closed_form.real
    geometry = gravity_I if kind == "detachment" else "exact"
    return RealWallRocker(case, kind, lam=mechanism.lam, tanpsi=mechanism.tanpsi,
                          geometry=geometry, restitution=restitution, name=mechanism.name)


def rigid_rocker(case, mechanism, gravity_I="linearised", restitution=0.0):
    """The rocker of a mechanism with a rigid ``body`` (exact geometry); a real wall's
    (``case.real``): ``real_rocker``."""
    if case.real:
        return real_rocker(case, mechanism, gravity_I, restitution)
    return RigidRocker(mechanism.body, g=case.wall.g, restitution=restitution,
                       name=mechanism.name)


def rocker_I(case, mechanism, gravity_I="linearised", restitution=0.0):
    """Mechanism I's rocker: the façade strip with the abutment friction of eq. 9, at the
    critical λ, its gravity linearised (eq. 10) or exact (``gravity_I``); a real wall's:
    ``real_rocker``."""
    if case.real:
        return real_rocker(case, mechanism, gravity_I, restitution)
    return MechanismIRocker(case, gravity=gravity_I, restitution=restitution)


def closed_form_alone(kind: str):
    """``registry.Mechanism.alone`` of closed-form mechanism ``kind`` (for ``homlimit
    pulse``): the paper's form, or ``closed_form.real``'s on a real wall."""
    def alone(config):
        case = config.case
        if case.real or kind == "overturning":
            return real_closed_forms(config, (kind,))[0][real.NAMES[kind]]
        return mech.mechanism_I(case) if kind == "detachment" else mech.mechanism_II(case)
    return alone
