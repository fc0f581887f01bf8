"""Parameter studies that return plain records (lists of flat dicts, ready for CSV/JSON).

``crack_angle_study``: the crack of the FE mechanism of the whole T-section (base fixed at
z = 0) over a grid of block proportions c/a and joint frictions f, for both façade models and
two mesh sizes, beside the closed forms: the hinge + fan optimum (``closed_form.fan``; edges
min/max(f, c/a) where admissible) and mechanism II's rigid wedge at tan ψ = √(cf/a). With
``conform``, the homogenised façade's points also search λ⁺ over meshes conforming to a
hinge + fan started from the FE mechanism (``mechanism.conform``): the conform_* columns.
The wall is Table 1's B2 (H = 9 m, L = 6 m, b = 0.5 m, ρ = 12) with a = 0.2 m and c = (c/a) a.
"""

from __future__ import annotations

import dataclasses
import functools
import logging
import math
import time

import numpy as np

from ..closed_form.fan import optimise_fan, optimise_wedge
from ..errors import ParameterError, SolverError, check_choice, check_range
from ..fe.problems import t_section
from ..fe.solver import SolverOptions
from ..mechanism.adaptive import hinge_fan_of
from ..mechanism.analysis import analyse
from ..mechanism.conform import conform_fan
from ..params import FACADE_MODELS, MESHER_DEFAULT, MESHERS, Case, Masonry, Wall

__all__ = ["crack_angle_study", "crack_point", "C_OVER_A", "FRICTIONS", "STUDY_WALL",
           "CRACK_COLUMNS"]

log = logging.getLogger(__name__)

C_OVER_A = (0.5, 0.75, 1.0, 1.5, 2.0, 3.0)
FRICTIONS = (0.3, 0.6, 0.9)
STUDY_WALL = Wall(H=9.0, L=6.0, s=0.5, b=0.5, l=6.0)
FINER = 0.25        # the second, finer mesh of the study [m] (crack-study --finer's default)
_A = 0.2  # block height [m] of the study; c = (c/a) a

CRACK_COLUMNS = [
    "c_over_a", "f", "facade", "mesh_size", "n_triangles", "mechanism_fe", "hinge_z",
    "tanpsi_fe", "dtanpsi_fe", "tanpsi_block", "tanpsi_fixed", "tan_alpha", "tan_f",
    "tan_c_over_a", "psi_fe_deg", "psi_alpha_deg", "psi_f_deg", "psi_c_over_a_deg",
    "multiplier_fe", "multiplier_fan", "fan_z0", "fan_T1", "fan_T2", "fan_admissible",
    "multiplier_wedge", "wedge_z0", "wedge_admissible", "explained", "block_share",
    "interior_share", "vnorm_fe", "conform_multiplier", "conform_hinge_z", "conform_T1",
    "conform_T2", "conform_T_mid", "conform_trials", "conform_seconds", "solve_time",
]
_CONFORM = {k: math.nan for k in CRACK_COLUMNS if k.startswith("conform_")}


def _nan(v) -> float:
    return math.nan if v is None else float(v)


def _deg(t: float) -> float:
    return math.degrees(math.atan(t)) if np.isfinite(t) else math.nan


def check_finer(mesh_size: float | None, finer: float | None, name: str = "finer",
                size_name: str = "mesh_size") -> float | None:
    """The study's second mesh size (None: none, for None or 0), below ``mesh_size`` (None:
    not known, a bad one), else ParameterError naming ``name`` (0 <= finer < mesh_size, 0:
    none) or, when finer is its default, ``size_name``, the size the user lowered below it.
    ``name``, ``size_name``: the arguments' names in the messages (the flags)."""
    if finer is None or finer == 0:
        return None
    if mesh_size is not None and finer == FINER and finer >= mesh_size:
        raise ParameterError(
            f"{size_name} = {mesh_size!r} m is not above {name} = {finer!r} m (the default "
            f"of {name}, the study's second, finer mesh): out of range: allowed {name} < "
            f"{size_name}; give {name} below {mesh_size!r} m, or {name} 0 (none)")
    return check_range(name, finer, 0.0, mesh_size, hi_open=True, unit="m",
                       note=f"below {size_name}; 0: none")


def crack_angle_study(mesh_size: float = 0.5, finer: float | None = FINER, quick: bool = False,
                      c_over_a=C_OVER_A, frictions=FRICTIONS, facades=FACADE_MODELS,
                      wall: Wall = STUDY_WALL, options=None, map=map,
                      mesher: str = MESHER_DEFAULT, conform: bool = False) -> list[dict]:
    """Crack-angle records, one per (c/a, f, façade, mesh size); keys ``CRACK_COLUMNS``.

    mesh_size: the default mesh (``problems.t_section``'s h) [m]; finer: a second, finer mesh
    (None: skip); quick: c/a ∈ {0.5, 1, 3}, f ∈ {0.3, 0.9} and the default mesh only;
    options: ``SolverOptions`` of the kinematic solves; map(fn, points): how the grid points
    are evaluated, records in order (default: one after another here; ``app.engine.Engine``'s
    ``stored_map`` makes each point a Dask task whose record is kept); mesher: the mesh of
    every point (``problems.MESHERS``); conform: on the homogenised façade, the ray-conforming
    search from each point's mechanism (``mechanism.conform``; NaN columns elsewhere).
    """
    check_choice("mesher", mesher, MESHERS)
    mesh_size = check_range("mesh_size", mesh_size, 0.0, lo_open=True, unit="m")
    sizes = [mesh_size]
    finer = None if quick else check_finer(mesh_size, finer)
    if finer is not None:
        sizes.append(finer)
    if quick:
        c_over_a, frictions = (0.5, 1.0, 3.0), (0.3, 0.9)
    grid = [(check_range("c_over_a", ca, 0.0, lo_open=True), f, fac, h)
            for ca in c_over_a for f in frictions for fac in facades for h in sizes]
    fn = functools.partial(crack_point, wall=wall, options=options or SolverOptions(),
                           mesher=mesher, conform=conform)
    return list(map(fn, grid))


def crack_point(point: tuple, wall: Wall = STUDY_WALL, options=None,
                mesher: str = MESHER_DEFAULT, conform: bool = False) -> dict:
    """The crack-angle record of one grid point (c/a, f, façade, mesh size) [-, -, -, m] on
    the ``mesher``'s mesh (``conform``: see ``crack_angle_study``)."""
    ca, f, fac, h = point
    options = options or SolverOptions()
    case = Case(dataclasses.replace(wall), Masonry(a=_A, c=ca * _A, f=f),
                name=f"c/a={ca:g},f={f:g}")
    t0 = time.perf_counter()
    problem = t_section(case, facade=fac, h=h, mesher=mesher)
    try:                      # the solver's own ladder retries a stall (fe.solver)
        fe = analyse(case, problem, options)
    except SolverError as exc:
        return {"c_over_a": ca, "f": f, "facade": fac, "mesh_size": h,
                "mechanism_fe": f"solver failed: {exc.status}"}
    opt = optimise_fan(case, facade=fac)
    wed = optimise_wedge(case)
    alpha = case.alpha
    e1, e2 = fe.tanpsi_edges
    mm = fe.measures
    r = {"c_over_a": ca, "f": f, "facade": fac, "mesh_size": h,
         "n_triangles": fe.n_triangles, "mechanism_fe": fe.kind,
         "hinge_z": fe.O[1], "tanpsi_fe": fe.tanpsi,
         "dtanpsi_fe": fe.tanpsi_uncertainty, "tanpsi_block": e1, "tanpsi_fixed": e2,
         "tan_alpha": alpha, "tan_f": f, "tan_c_over_a": ca,
         "psi_fe_deg": _deg(fe.tanpsi), "psi_alpha_deg": _deg(alpha),
         "psi_f_deg": _deg(f), "psi_c_over_a_deg": _deg(ca),
         "multiplier_fe": fe.multiplier, "multiplier_fan": opt.lam,
         "fan_z0": opt.z0, "fan_T1": opt.T1, "fan_T2": opt.T2,
         "fan_admissible": opt.admissible, "multiplier_wedge": wed.lam,
         "wedge_z0": wed.z0, "wedge_admissible": wed.admissible,
         "explained": mm.explained, "block_share": mm.block_share,
         "interior_share": mm.interior_share, "vnorm_fe": fe.vnorm, **_CONFORM}
    hf = hinge_fan_of(fe) if conform and fac == "homogenised" else None
    if hf is not None:
        try:
            c = conform_fan(case, hf, options=options)
        except SolverError as exc:
            log.warning("crack study: c/a=%g f=%g: the conforming search failed (%s)", ca, f,
                        exc)
        else:
            cf = c.fan
            r |= {"conform_multiplier": c.lam, "conform_trials": len(c.trials),
                  "conform_seconds": c.seconds}
            if cf is not None:
                r |= {"conform_hinge_z": cf.z, "conform_T1": _nan(cf.T1),
                      "conform_T2": _nan(cf.T2), "conform_T_mid": _nan(cf.T_mid)}
    r["solve_time"] = time.perf_counter() - t0
    log.info("crack study: c/a=%g f=%g %s h=%g %s z_O=%.2f T1=%.3f T_mid=%.3f "
             "T2=%.3f (±%.3f) | √(cf/a)=%.3f | λ_FE=%.4f λ_fan=%.4f λ_wedge=%.4f %.1fs",
             ca, f, fac, h, r["mechanism_fe"], r["hinge_z"], e1,
             r["tanpsi_fe"], e2, r["dtanpsi_fe"], alpha, r["multiplier_fe"], opt.lam,
             wed.lam, r["solve_time"])
    return r
