"""The built-in models and their mechanisms, registered in ``app.registry``.

- the closed forms (``closed_form.mechanisms``): mechanisms I (eqs 8–14) and II (eqs 16–20) at
  their critical slenderness, and their v̄_g(λ) curves;
- the finite-element path (``mechanism.analysis.fe_result``): the impulse scan over collapse
  heights, the whole wall's mechanism and crack, its static lower bound (on the same mesh, or
  the adaptive bracket's), and mechanism "FE", its critical body; the FE cache keeps that
  body's one-DOF impulse for ``homlimit pulse``;
- the rigid blocks (``blocks.analyse_blocks``): mechanism "blocks".

Each model runs when the case asks for it (``[analysis] closed_form``, ``fe``, ``blocks``) and
fills the ``pipeline.Result``. The closed forms, the rigid blocks, the DEM and the rigid
rockers live in ``app.models_rigid``, the FE path here and its cache in ``app.fe_cache``;
every model registers here.
``stage`` and ``solver_options`` (``app.stages``) serve every command.
"""

from __future__ import annotations

import functools
import logging

from .. import _threads
from ..dynamics import GeneralisedRocker
from ..errors import ParameterError, ResultError
from ..fe.mesh import from_skfem
from ..mechanism.analysis import fe_result, first_heights, h_scan
from . import plots, registry, report
from .code_check import code_check_files
from .config import CaseConfig
from .fe_cache import FERocker, fe_cache_inputs, fe_cache_path, read_fe_cache, write_fe_cache
from .models_rigid import (
    blocks_files,
    closed_form_alone,
    closed_form_files,
    closed_forms,
    no_joint_strength,
    real_closed_forms,
    rigid_rocker,
    rocker_I,
    run_blocks,
    run_closed_forms,
    run_dem,
)
from .registry import Mechanism, Model
from .stages import finite, solver_options, stage

__all__ = ["FERocker", "adaptive", "adaptive_bracket_of", "closed_forms", "fe_cache_inputs",
           "fe_cache_path", "fe_rocker", "finite", "read_fe_cache", "real_closed_forms",
           "rigid_rocker", "solver_options", "stage", "whole_problem", "write_fe_cache"]

log = logging.getLogger(__name__)


# ----------------------------------------------------------------------------- the FE path
def adaptive(config: CaseConfig) -> bool:
    """The whole wall's bracket is adaptive on gmsh meshes (``[mesh] mesher = "gmsh"`` or
    "gmsh-strip") with the static bound on and more than one cycle allowed."""
    return (config.mesh.mesher in ("gmsh", "gmsh-strip") and config.analysis.static
            and config.adapt.max_cycles > 1)


def outer_width(config: CaseConfig) -> float | None:
    """Width [m] of the façade's outermost column on a graded mesh (crossed or gmsh-strip with
    ``[mesh] outer_ratio`` > 0): size/outer_ratio, at most b/4; else None."""
    me = config.mesh
    if me.mesher not in ("crossed", "gmsh-strip") or me.outer_ratio <= 0:
        return None
    return min(me.size / me.outer_ratio, config.case.wall.b / 4)


def adaptive_bracket_of(config: CaseConfig, timings: dict, beside=None):
    """``mechanism.adaptive.adaptive_bracket`` of the whole wall, each cycle logged, then the
    crack's splits (``refine_crack``). ``beside()``: work for this thread while the splits,
    kinematic solves one after another on one core, run in a thread of their own; it should
    wait interruptibly (``_threads``). Returns (the AdaptResult, beside's result), or None
    for the latter where it did not run: no splits, one core, or a Dask worker."""
    from ..fe.adapt import AdaptOptions
    from ..mechanism.adaptive import adaptive_bracket, refine_crack
    from ..mechanism.conform import conform_hook

    ad = config.adapt
    opts = AdaptOptions(target_gap=ad.target_gap, max_cycles=ad.max_cycles,
                        min_size=ad.min_size, max_triangles=config.mesh.max_triangles)

    def progress(c):
        log.info("  adaptive bracket, cycle %d: %d triangles, %.5g <= multiplier <= %.5g; "
                 "best %.5g .. %.5g (gap %.2f %%), %.1f s", c.cycle, c.triangles, c.lower,
                 c.upper, c.best_lower, c.best_upper, 100 * c.rel_gap, c.seconds)

    solver = solver_options(config.analysis.tol, config.analysis.stress_degree)
    # the bed-joint façade locks on the conforming meshes' unaligned triangles: no search
    conform = ad.conform and config.analysis.facade == "homogenised"
    with stage(timings, "adaptive bracket", f"target gap {100 * ad.target_gap:g} %, at most "
                f"{ad.max_cycles} meshes" + (", λ⁺ searched over fan-conforming meshes"
                                             if conform else "")):
        res = adaptive_bracket(config.case, config.analysis.facade, config.mesh.size, opts,
                               solver, progress, mesher=config.mesh.mesher,
                               h_outer=outer_width(config),
                               improve_upper=conform_hook(config.case, "homogenised", solver)
                               if conform else None)
    if not res.converged:
        log.warning("warning: the adaptive bracket stopped (%s) at a gap of %.2f %%, above "
                    "its target %g %%", res.stop, 100 * res.cycles[-1].rel_gap,
                    100 * ad.target_gap)
    if conform or ad.crack_cycles == 0:      # the fan search resolves the crack itself
        return res, None

    def crack_progress(c):
        m = c.measures
        log.info("  crack cycle %d: %d triangles, multiplier <= %.5g (gap %.2f %%), crack "
                 "edges %s .. %s, mid-line %s, %.1f s", c.cycle, c.triangles, c.upper,
                 100 * c.rel_gap, *(("-" if m.get(k) is None else f"{m[k]:.4f}")
                                    for k in ("T1", "T2", "T_mid")), c.seconds)

    alongside = beside is not None and _threads.threads_here(2) > 1
    with stage(timings, "crack refinement" + (" beside the scan's first parts" if alongside
                                              else ""),
               f"the crack's band split until its edges and mid-line move <= "
               f"{100 * ad.crack_tol:g} %, at most {ad.crack_cycles} times"):
        split = functools.partial(refine_crack, config.case, res, ad.crack_tol,
                                  ad.crack_cycles, config.mesh.max_triangles, solver,
                                  crack_progress)
        if alongside:       # the splits use no gmsh: they may leave this thread to beside()
            future = _threads.background(split)
            done = beside()
            res = future.result()
        else:
            res, done = split(), None
    if res.mechanism_stop == "unmarked":
        log.info("  no crack to split: the mechanism has no block turning about the façade's "
                 "outer face")
    elif res.mechanism_stop != "settled":
        log.warning("warning: the crack refinement stopped (%s) before the crack settled to "
                    "%g %%", res.mechanism_stop, 100 * ad.crack_tol)
    return res, done


def whole_problem(config: CaseConfig):
    """The whole wall's T-section problem (``problems.t_section``, base at z = 0)."""
    from ..fe.problems import t_section  # here: tests replace it to forbid meshing

    return t_section(config.case, facade=config.analysis.facade, h=config.mesh.size,
                     mesher=config.mesh.mesher)


def static_problem(config: CaseConfig):
    """The whole wall on the static bound's own mesh: with ``[mesh] outer_ratio`` > 0 on the
    crossed grid or gmsh-strip, the façade's columns graded to width size/outer_ratio at the
    outer face (``t_section(h_outer=)``, docs/static.md "The outer face"); else None (the
    static bound on the kinematic bound's mesh)."""
    from ..fe.problems import t_section

    me = config.mesh
    h_outer = outer_width(config)
    if not config.analysis.static or h_outer is None:
        return None
    return t_section(config.case, facade=config.analysis.facade, h=me.size,
                     mesher=me.mesher, h_outer=h_outer)


def fe_rocker(config: CaseConfig) -> FERocker:
    """The FE path's critical mechanism for the pulse spectra: read from the FE cache (which
    ``run`` fills) when the entry is sound, else computed (``fe_result``, as ``run`` without
    the static bound) and written to the cache."""
    no_joint_strength(config.case, "the FE body's rocker (pulse spectra)")   # before any work
    cached = read_fe_cache(config)
    if cached is not None:
        log.info("FE result read from cache %s", cached.cache)
        return cached
    case, an = config.case, config.analysis
    with stage({}, "FE path for the FE rocker"):
        fe = fe_result(case, config.mesh.size, an.facade,
                       solver_options(an.tol, an.stress_degree),
                       heights=an.heights, divisions=config.mesh.part_divisions,
                       mesher=config.mesh.mesher)
    if fe.critical is None:
        raise ParameterError("[pulse] mechanisms = 'FE': the FE scan found no mechanism "
                             "with a v̄_g (see fe_scan's vg_method)")
    path = write_fe_cache(config, fe)
    if path is not None:
        log.info("FE result written to cache %s", path)
    return FERocker(fe.critical.impulse, fe.critical.h, fe.critical.vg, path, False)


# ----------------------------------------------------------------------------- the models

def run_fe(config, result) -> None:
    """The FE path (``fe_result``): on the adaptive bracket's mesh (``adaptive``) or the
    case's; its critical body becomes mechanism "FE" when the scan found one."""
    an = config.analysis
    case = config.case
    first = first_heights(case, an.heights)

    def first_parts():       # the scan's first round below H does not need the whole wall:
        # meshed here (gmsh), solved one at a time in a thread while this one waits
        return dict(zip(first, h_scan(case, first, config.mesh.size, an.facade,
                                      solver_options(an.tol, an.stress_degree), None,
                                      config.mesh.part_divisions, config.mesh.mesher,
                                      at_once=1)))

    adapted, parts = (adaptive_bracket_of(config, result.timings, beside=first_parts)
                      if adaptive(config) else (None, None))
    whole = whole_problem(config) if adapted is None else adapted.problem
    with stage(result.timings, "FE analyses",
               f"scan from one course to H, whole wall {whole.n_triangles} triangles"
               f"{', static bound' if an.static else ''}"):
        result.fe = fe_result(config.case, config.mesh.size, an.facade,
                              solver_options(an.tol, an.stress_degree), whole=whole,
                              static=an.static,
                              heights=an.heights, divisions=config.mesh.part_divisions,
                              mesher=config.mesh.mesher, adapted=adapted,
                              static_problem=None if adapted else static_problem(config),
                              parts=parts)
    if result.fe.critical is not None:
        result.mechanisms[result.fe.critical.name] = result.fe.critical
    elif getattr(result.fe, "vg_unavailable", ""):   # a cohesion: the whole wall, no v̄_g
        result.mechanisms[result.fe.whole.name] = result.fe.whole


def check_fe(result) -> None:
    """The FE path's multiplier and static bound are finite, and its scan found a body."""
    fe = result.fe
    if fe is None:
        return
    if not finite(fe.whole.multiplier):
        raise ResultError(f"mechanism FE: the whole wall's multiplier = "
                          f"{fe.whole.multiplier!r} is not a finite number; nothing written")
    if fe.static is not None and not finite(fe.lower_bound):
        raise ResultError(f"mechanism FE: the static lower bound = {fe.lower_bound!r} is "
                          "not a finite number; nothing written")
    if fe.critical is None and not getattr(fe, "vg_unavailable", ""):
        raise ResultError("mechanism FE: no collapse height of the scan gave a collapse "
                          f"velocity vg (whole wall: {fe.whole.vg_method}); nothing "
                          "written ([analysis] fe = false skips the FE path)")


def fe_files(result) -> dict:
    """The FE path's files: mesh.png, mechanism.png, stress.png (static bound), fe_adapt.csv
    and adapt.png (adaptive bracket), fe_scan.csv, mechanism.vtu, and static.vtu where the
    static bound lives on another mesh than the mechanism's."""
    art, cfg, title = result.fe, result.config.output, f"case {result.name}"
    if art is None:
        return {}
    out = {}
    if cfg.png:
        out["mesh_png"] = ("mesh.png", lambda p: plots.plot_mesh(
            p, from_skfem(art.whole.problem.mesh), title=title))
        out["mechanism_png"] = ("mechanism.png", lambda p: plots.plot_mechanism(
            p, art.whole.drawing(), result.case, title=title))
        if art.static is not None:
            out["stress_png"] = ("stress.png", lambda p: plots.plot_stress(
                p, art.static, title=f"{title}: lower-bound stress field, λ⁻ = "
                                     f"{art.static.multiplier:.4g}",
                fc=result.case.masonry.fc, rho=result.case.rho))
    if art.adapt is not None:
        cycles = [c.as_dict() for c in art.adapt.cycles]
        out["fe_adapt_csv"] = ("fe_adapt.csv", cycles)
        if cfg.png:
            out["adapt_png"] = ("adapt.png", lambda p: plots.plot_adapt(p, cycles, title=title))
    out["fe_scan_csv"] = ("fe_scan.csv", [m.record() for m in art.scan])
    if cfg.vtu:
        out["mechanism_vtu"] = ("mechanism.vtu", report.mechanism_mesh(art))
        from ..fe.bracket import same_mesh
        if art.static is not None and not same_mesh(art.static.mesh, art.whole.solution.mesh):
            out["static_vtu"] = ("static.vtu", report.static_mesh(art.static))
    return out



def rocker_fe(case, mechanism, gravity_I="linearised", restitution=0.0):
    """The FE body's one-DOF rocker: the body inside the 50 % line turning exactly, the rest
    linearised (``mechanism`` an ``FEMechanism`` or an ``FERocker``: its ``impulse``), with
    the ties' and floors' work of the FE impulse criterion (``impulse.LoadWork``). It has no
    joint cohesion's or tension's work: a case with them is refused (ParameterError)."""
    no_joint_strength(case, "the FE body's rocker (pulse spectra, hinge check)")
    return GeneralisedRocker.from_impulse(mechanism.impulse, g=case.wall.g,
                                          restitution=restitution, name=mechanism.name)


CLOSED = dict(model="closed_forms", checked=("lam", "h", "vg", "vnorm", "theta_m", "W_m"),
              body_checked=("m", "x_G", "z_G", "I_O", "J_z"), static=True, marker="o",
              size=8)
registry.register(
    Model("closed_forms", lambda config: config.analysis.closed_form, run_closed_forms,
          batched=True, files=closed_form_files),
    Model("fe", lambda config: config.analysis.fe, run_fe, check_fe, files=fe_files),
    Model("blocks", lambda config: config.analysis.blocks, run_blocks, files=blocks_files),
    Model("dem", lambda config: config.analysis.dem, run_dem, tasks=True),
    # the check itself runs after the results' checks (pipeline.compute, and in a sweep's
    # closed-form batches); this entry adds its picture to a run's files
    Model("code_check", lambda config: config.site is not None, lambda config, result: None,
          batched=True, files=code_check_files),
    Mechanism("I", rocker=rocker_I, alone=closed_form_alone("detachment"),
              colour="tab:blue", **CLOSED),
    Mechanism("II", rocker=rigid_rocker, alone=closed_form_alone("crack"),
              colour="tab:orange", **CLOSED),
    Mechanism("FE", model="fe", rocker=rocker_fe, alone=fe_rocker, colour="tab:green",
              marker="*", size=16, needs_mesh=True,
              static_of=lambda result: result.fe.whole.static_mechanism),  # first to activate
    Mechanism("blocks", model="blocks"))

