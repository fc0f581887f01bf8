"""Analyses of the T-section as rigid blocks: the h-scan, the front-door entry point, the
homogenisation study and Table 1 with the discrete column. Records are plain dicts.

Collapse height: as the FE path (``fe_impulse.h_scan``), one limit analysis of the part above
z0 per course boundary z0 (the blocks below are held fixed), each turned into v̄_g by
``impulse.block_impulse``; the critical record has the lowest v̄_g, and its h is the height
of the failing part above its own rotation centre, h = H − z_O (the hinge may float above z0).
The whole-wall analysis (z0 = 0, the mechanism chooses its own hinge) is kept beside it.
"""

from __future__ import annotations

import logging
import math
import time
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

from ..check.ntc import StaticMechanism
from ..errors import ParameterError, check_range
from ..fe.solver import SolverOptions
from ..impulse import hinge_impulse_ratio
from ..params import Case, Masonry
from .geometry import Assembly, t_section_blocks
from .impulse import BlockImpulse, block_impulse
from .limit import BlockLimitResult, solve_blocks

log = logging.getLogger(__name__)

__all__ = ["scan_record", "h_scan_blocks", "BlocksAnalysis", "analyse_blocks",
           "homogenisation_study", "table1_blocks", "DEM_RATIOS"]

#: the choices of a real wall in the blocks (docs/real-walls.md, "Rigid blocks")
REAL_CHOICES = {
    "per_metre": "ties and floors per metre of façade; the section (per bay) carries value × l",
    "floor_mass": "only the floor's vertical load bears on the block under it; its mass moves "
                  "with the building",
    "compression": "every contact 0 <= sigma <= fc over its length and out-of-plane depth (l in "
                   "the façade, s in the wall): the rectangular stress block, exact in (N, M)",
    "tie_law": "LA: 0 <= F <= T_y at the outer face of the façade block at its height; "
               "impulse: force min(k delta, T_y) until the ductility limit, delta = d sin theta "
               "on the body (the closed forms' rule)",
    "impulse": "W(theta) maximised over 0..pi/2 with the ties' work, the floors' loads "
               "turning with their blocks and the crushing work (rate of the mechanism) x theta",
    "bond": "cohesion C and tension T per contact over its area (depth as fc): "
            "sigma >= -T_h, |tau| <= f sigma + C, T_h = min(T, C/f) (the Coulomb apex); "
            "associative; v_g not available with them (their dissipation at finite rotation "
            "needs a softening rule), the critical record is the whole wall's (lowest lambda)",
}

DEM_RATIOS = {"B4/B1": 0.564 / 0.377, "B5/B2": 0.720 / 0.443, "B6/B3": 0.846 / 0.509}


def scan_record(assembly: Assembly, result: BlockLimitResult, z0: float) -> tuple[dict,
                                                                                 BlockImpulse]:
    """One record of the h-scan: λ, the mechanism and its impulse (NaN if the mechanism is
    a translation, which eq. 7 does not cover)."""
    from ..impulse import collapse_velocity

    H, b, g = assembly.meta["H"], assembly.meta["b"], assembly.meta["g"]
    rec = {"z0": z0, "h_part": H - z0, "multiplier": result.multiplier,
           "friction": result.friction, "n_moving": int(result.moving.sum()),
           "n_open": result.n_open, "n_sliding": result.n_sliding,
           "z_base": result.z_base, "solve_time": result.times.get("total", math.nan)}
    act = result.actions    # a real wall: the ties' total force at collapse, the dissipation
    real = {} if not act else {k: float(np.sum(act[k])) for k in ("tie_force", "crushing_rate",
                                                                   "bond_rate")}
    try:
        bi = block_impulse(assembly, result)
    except ParameterError as exc:
        rec.update({"vg": math.nan, "vnorm": math.nan, "vg_rigid": math.nan,
                    "vnorm_rigid": math.nan, "h": math.nan, "lam": math.nan,
                    "method": f"not available: {exc}", **real})
        return rec, None
    v_rigid = collapse_velocity(bi.body, g=g)
    rec.update({"vg": bi.vg, "vnorm": bi.vnorm, "vg_rigid": v_rigid,
                "vnorm_rigid": v_rigid / math.sqrt(g * b), "h": bi.h, "lam": bi.h / b,
                "x_O": bi.O[0], "z_O": bi.O[1], "method": bi.method, "n_body": bi.n_body,
                "m_body": bi.body.m, "theta_m": bi.theta_m,
                "W_rest_share": bi.W_rest / bi.W_m, "W_friction_share": bi.W_friction / bi.W_m,
                "M_rest_share": bi.M_rest_share, **bi.W_real, **real})
    return rec, bi


def h_scan_blocks(case: Case, step: int = 1, facade: str = "through",
                  friction: str = "associative", options: SolverOptions = SolverOptions(),
                  min_courses: int = 2, toothed_first: bool = True, assembly=None,
                  **solve_kw) -> list[dict]:
    """``scan_record`` for the part above every ``step``-th course boundary z0 (from the base;
    at least ``min_courses`` courses above). Returns the records (module docstring)."""
    step = int(check_range("step", step, 1))
    min_courses = int(check_range("min_courses", min_courses, 1))
    A0 = t_section_blocks(case, toothed_first, facade) if assembly is None else assembly
    a = case.masonry.a
    n_c = A0.meta["n_courses"]
    recs = []
    for k in range(0, max(n_c - min_courses, 0) + 1, step):
        z0 = k * a
        A = A0.fix_below(z0) if k else A0
        r = solve_blocks(A, friction=friction, options=options, **solve_kw)
        rec, _ = scan_record(A, r, z0)
        recs.append(rec)
    return recs


@dataclass
class BlocksAnalysis:
    """The rigid-block analysis of one case (``analyse_blocks``).

    case; assembly (whole wall); whole: the whole-wall result (the mechanism chooses its
    hinge) and whole_record; scan: the h-scan records; critical: the record of lowest v̄_g,
    with critical_assembly, critical_result and critical_impulse (for the files);
    non_associative: the Gilbert et al. (2006) check at the critical height (record or None);
    times [s].
    """

    case: Case
    assembly: Assembly
    whole: BlockLimitResult
    whole_record: dict
    scan: list
    critical: dict
    critical_assembly: Assembly
    critical_result: BlockLimitResult
    critical_impulse: BlockImpulse | None
    non_associative: dict | None = None
    settings: dict = field(default_factory=dict)
    times: dict = field(default_factory=dict)

    # the mechanism protocol of pipeline.Result.mechanisms (label, lam, h, vg, vnorm, ...)
    name = "blocks"

    @property
    def label(self) -> str:
        return f"rigid blocks, façade {self.settings.get('facade')} (eq. 7)"

    @property
    def lam(self) -> float:
        return self.critical["lam"]

    @property
    def h(self) -> float:
        return self.critical["h"]

    @property
    def vg(self) -> float:
        return self.critical["vg"]

    @property
    def vnorm(self) -> float:
        return self.critical["vnorm"]

    @property
    def vg_unavailable(self) -> str:
        """Why v̄_g is not available ("" when it is): a joint cohesion or tension
        (``impulse.no_bond``); ``app.checks`` exempts v̄_g then."""
        if self.critical_impulse is not None:
            return ""
        return (f"{self.critical.get('method', 'not available')} (the whole wall's collapse "
                f"multiplier a/g = {self.whole.multiplier:.4g} takes them)")

    @property
    def hinge_ratio(self) -> float:
        """|P_x/P_z| of the ideal impulse at the critical body's hinge (``impulse``); NaN
        without an impulse (a joint cohesion or tension)."""
        if self.critical_impulse is None:
            return math.nan
        return hinge_impulse_ratio(self.critical_impulse.body)

    @property
    def static_mechanism(self) -> StaticMechanism:
        """The code check's α₀ and body: the whole wall's multiplier (the mechanism that
        activates first: it chooses its hinge) and the body of its blocks of participation
        >= 1/2 about that hinge; the critical height's if the whole wall's mechanism has no
        such body (``block_impulse`` refuses it)."""
        from .impulse import rigid_body_of

        if self.critical_impulse is None:       # a bond: no impulse, the whole wall's body
            try:
                body, O = rigid_body_of(self.assembly, self.whole)  # noqa: E741
            except ParameterError:
                return None
            return StaticMechanism(self.whole.multiplier, body, float(O[1]),
                                   "multiplier of the whole wall, its body of p >= 1/2")
        try:
            bi, r, what = block_impulse(self.assembly, self.whole), self.whole, "whole wall"
        except ParameterError:
            bi, r, what = self.critical_impulse, self.critical_result, "critical height"
        return StaticMechanism(r.multiplier, bi.body, float(bi.O[1]),
                               f"multiplier of the {what}, its body of p >= 1/2")

    def as_dict(self) -> dict:
        return {"name": self.name, **self.critical, "hinge_ratio": self.hinge_ratio}

    def files(self) -> dict:
        """File name → what is written there (a meshio mesh, records, or a function drawing
        to a path), for the one writer of result files (``app.report.write``, by suffix; a run
        with ``[analysis] blocks`` writes them): blocks.vtu (critical mechanism, polygons
        coloured by velocity), blocks_contacts.vtu and blocks_contacts.csv (its contact
        forces, the static dual), blocks_mechanism.png (critical height), blocks_whole.png
        (whole wall), blocks_scan.csv (the h-scan)."""
        from .output import blocks_mesh, contact_records, contacts_mesh

        A, r, bi = self.critical_assembly, self.critical_result, self.critical_impulse
        return {"blocks.vtu": blocks_mesh(A, r, None if bi is None else bi.body_mask),
                "blocks_contacts.vtu": contacts_mesh(A, r),
                "blocks_contacts.csv": contact_records(A, r),
                "blocks_mechanism.png": lambda path: _mechanism_pngs(self, path, "critical"),
                "blocks_whole.png": lambda path: _mechanism_pngs(self, path, "whole"),
                "blocks_scan.csv": self.scan}

    def summary(self) -> dict:
        """Plain data for JSON: settings, whole-wall and critical records, the non-associative
        check, and the scan."""
        return {"case": self.case.as_dict(), "settings": self.settings,
                "blocks": self.assembly.n_blocks - int(self.assembly.fixed.sum()),
                "interfaces": self.assembly.interfaces.count,
                "whole": self.whole_record, "critical": self.critical,
                "non_associative": self.non_associative, "scan": self.scan,
                "times": self.times}


def analyse_blocks(case: Case, facade: str = "through", friction: str = "associative",
                   step: int = 1, non_associative_check: bool = False,
                   options: SolverOptions = SolverOptions(), toothed_first: bool = True,
                   max_iter: int = 30, relax: float = 0.5) -> BlocksAnalysis:
    """The front-door entry point: the T-section of ``case`` as rigid blocks.

    Whole-wall limit analysis (λ, mechanism, contact forces), h-scan every ``step`` courses
    (friction model ``friction``), the critical height of lowest v̄_g with its mechanism and
    impulse, and optionally the non-associative check (Gilbert et al. 2006, ``max_iter``,
    ``relax``) at the critical height."""
    if not isinstance(case, Case):
        raise ParameterError(f"case = {type(case).__name__} is out of range: allowed a "
                             "homlimit.params.Case")
    t0 = time.perf_counter()
    A = t_section_blocks(case, toothed_first, facade)
    kw = {"max_iter": max_iter, "relax": relax} if friction == "non-associative" else {}
    whole = solve_blocks(A, friction=friction, options=options, **kw)
    whole_rec, _ = scan_record(A, whole, 0.0)
    t_whole = time.perf_counter() - t0
    scan = [whole_rec] + h_scan_blocks(case, step, friction=friction, options=options,
                                       assembly=A, **kw)[1:]
    ok = [r for r in scan if np.isfinite(r["vg"])]
    real = A.meta.get("real")
    bond = real is not None and real.bond
    if bond:                    # no v̄_g (impulse.no_bond): the whole wall, of lowest λ
        crit = dict(whole_rec, h=whole.h, lam=whole.h / case.wall.b,
                    critical_at="the whole wall (lowest multiplier): v̄_g not available "
                                "with a joint cohesion or tension")
        Ac, rc, bi = A, whole, None
    elif not ok:
        raise ParameterError("no analysed height gave an overturning mechanism (all slide): "
                             "eq. 7 needs a rotation")
    else:
        crit = dict(min(ok, key=lambda r: r["vg"]))
        z0 = crit["z0"]
        Ac = A.fix_below(z0) if z0 > 0 else A
        rc = whole if z0 == 0 else solve_blocks(Ac, friction=friction, options=options, **kw)
        bi = block_impulse(Ac, rc)
    na = None
    if non_associative_check and friction == "associative" and not bond:
        rn = solve_blocks(Ac, friction="non-associative", options=options, max_iter=max_iter,
                          relax=relax)
        na, _ = scan_record(Ac, rn, z0)
        hist = np.asarray(rn.history)
        na.update({"converged": rn.converged, "iterations": len(hist) - 1,
                   "band_last5": float(np.ptp(hist[-5:])), "history": hist.tolist(),
                   "coulomb_violation": rn.sizes.get("coulomb_violation")})
    times = {"whole": t_whole, "total": time.perf_counter() - t0}
    settings = {"facade": facade, "friction": friction, "step": step,
                "toothed_first": toothed_first, "collapse_height": "h-scan over course "
                "boundaries, lowest v_g (h = H - z_O)"}
    if real is not None:            # ties, floors, fc per bay and the choices made
        settings["real"] = {**real.as_dict(), "choices": dict(REAL_CHOICES)}
        settings["real"]["tension_effective"] = real.tension_effective(A.meta["f"])
    return BlocksAnalysis(case, A, whole, whole_rec, scan, crit, Ac, rc, bi, na, settings,
                          times)


def _mechanism_pngs(analysis: BlocksAnalysis, path: Path, which: str) -> Path:
    """The PNG of the critical mechanism (``which`` = "critical") or of the whole wall."""
    from .output import plot_blocks_mechanism

    name = analysis.case.name
    if which == "critical":
        A, r, bi = (analysis.critical_assembly, analysis.critical_result,
                    analysis.critical_impulse)
        if bi is None:                  # a bond: no impulse (the whole wall, its fitted O)
            return plot_blocks_mechanism(
                path, A, r, None, r.fit.O,
                title=f"{name}: blocks, whole wall, λ = {r.multiplier:.4f} (cohesion/tension; "
                      "v_g not available)")
        return plot_blocks_mechanism(
            path, A, r, bi.body_mask, bi.O,
            title=f"{name}: blocks, critical height h = {bi.h:.2f} m, λ = {r.multiplier:.4f}, "
                  f"v_g/√(gb) = {bi.vnorm:.3f}")
    w = analysis.whole_record
    return plot_blocks_mechanism(
        path, analysis.assembly, analysis.whole, None,
        (w.get("x_O", math.nan), w.get("z_O", math.nan)),
        title=f"{name}: blocks, whole wall, λ = {analysis.whole.multiplier:.4f}, "
              f"h = {w.get('h', math.nan):.2f} m")


def homogenisation_study(case: Case, factors=(1, 2, 4, 8), facades=("through", "running-bond"),
                         options: SolverOptions = SolverOptions(), figures_dir=None) -> list[dict]:
    """The whole-wall multiplier of ``case`` with its blocks shrunk, (a, c) → (a, c)/k for k in
    ``factors`` at fixed c/a, for each façade bond, beside the homogenised hinge + fan
    (``fan.optimise_fan``). Records: facade, k, a, c, blocks, interfaces, multiplier,
    fan_multiplier, diff (relative), hinge (x_O, z_O) and the mechanism's staircase slope,
    build/solve times. ``figures_dir``: write a PNG of each mechanism there."""
    from ..closed_form.fan import optimise_fan

    fan = optimise_fan(case)
    m = case.masonry
    recs = []
    for facade in facades:
        for k in factors:
            k = check_range("factor", k, 1.0)
            ck = replace(case, masonry=Masonry(a=m.a / k, c=m.c / k, f=m.f))
            A = t_section_blocks(ck, facade=facade)
            t0 = time.perf_counter()
            r = solve_blocks(A, options=options)
            wall = time.perf_counter() - t0
            rec = {"facade": facade, "k": k, "a": ck.masonry.a, "c": ck.masonry.c,
                   "blocks": A.n_free, "interfaces": A.interfaces.count,
                   "multiplier": r.multiplier, "fan_multiplier": fan.lam,
                   "diff": r.multiplier / fan.lam - 1.0, "fan_z0": fan.z0, "fan_T1": fan.T1,
                   "fan_T2": fan.T2, "iterations": r.iterations,
                   "build_time": r.times.get("build", math.nan),
                   "solve_time": r.times.get("solve", math.nan), "wall_time": wall}
            rec.update(_mechanism_geometry(A, r))
            recs.append(rec)
            if figures_dir is not None:
                from .output import plot_blocks_mechanism

                rays = [(0.0, fan.z0, fan.T1, f"hinge + fan edge tan ψ = {fan.T1:.3f}"),
                        (0.0, fan.z0, fan.T2, f"hinge + fan edge tan ψ = {fan.T2:.3f}")]
                plot_blocks_mechanism(
                    Path(figures_dir) / f"blocks_homogenisation_{facade}_k{int(k)}.png", A, r,
                    O=(rec["x_hinge"], rec["z_hinge"]), rays=rays,
                    title=f"{case.name} blocks/{int(k)} ({facade} façade): λ = "
                          f"{r.multiplier:.4f}, hinge + fan {fan.lam:.4f}")
            log.info("  %-12s k = %g: %d blocks, λ = %.5f (fan %.5f, %+.2f %%), %.1f s",
                     facade, k, A.n_free, r.multiplier, fan.lam, 100 * rec["diff"], wall)
    return recs


def _mechanism_geometry(A: Assembly, r: BlockLimitResult) -> dict:
    """Where the mechanism sits, to set beside the hinge + fan: the rotation centre O of its
    body (``impulse.failing_body``) and the slopes x/(z − z_O) from O of the lines where the
    participation p (module ``impulse``) falls to 0.9, 0.5 and 0.1: per course above O, the
    right edge of the farthest block with p >= level, at mid-course height; the median over
    the courses in the upper three quarters of the part above O."""
    from .impulse import failing_body, participation

    try:
        body, O, omega = failing_body(A, r)  # noqa: E741 (the paper's O)
    except ParameterError:
        return {"x_hinge": math.nan, "z_hinge": math.nan, "slope_90": math.nan,
                "slope_50": math.nan, "slope_10": math.nan}
    p = participation(A, r.velocity, O, omega)
    bb = A.bounds()
    zc = 0.5 * (bb[:, 1] + bb[:, 3])
    H = float(A.meta.get("H", bb[:, 3].max()))
    out = {"x_hinge": float(O[0]), "z_hinge": float(O[1])}
    for lv in (0.9, 0.5, 0.1):
        sel = (p >= lv) & ~A.fixed & (zc > O[1] + 0.25 * (H - O[1]))
        if not np.any(sel):
            out[f"slope_{int(100 * lv)}"] = math.nan
            continue
        course = A.course[sel]
        order = np.argsort(course, kind="stable")
        uc, first = np.unique(course[order], return_index=True)
        xmax = np.maximum.reduceat(bb[sel, 2][order], first)
        zmid = np.maximum.reduceat(zc[sel][order], first)
        out[f"slope_{int(100 * lv)}"] = float(np.median((xmax - O[0]) / (zmid - O[1])))
    return out


def table1_blocks(step: int = 1, facade: str = "through", non_associative_check: bool = True,
                  options: SolverOptions = SolverOptions(), tests=None,
                  figures_dir=None, figures_for=()) -> tuple[list[dict], dict]:
    """Table 1 with the discrete column: for every wall (or ``tests``), the closed forms I and
    II, the paper's DEM, and the rigid-block model (whole-wall λ and hinge, critical height of
    the h-scan, v̄_g/√(gb) one-DOF and rigid body, the non-associative check). Returns (rows,
    ratios) with the ratios B4/B1, B5/B2, B6/B3 of v̄_g/√(gb) for the DEM, I, II and the
    blocks. ``figures_dir``: the critical and whole-wall mechanism PNGs of the walls ``figures_for``
    as blocks_table1_<test>_critical.png, blocks_table1_<test>_whole.png."""
    from ..closed_form.mechanisms import mechanism_I, mechanism_II
    from ..closed_form.paper import table1

    walls = table1()
    names = [t.test for t in walls]
    unknown = sorted(set(tests or ()) - set(names))
    if unknown:
        raise ParameterError(f"tests = {unknown!r} is out of range: allowed Table 1 walls "
                             f"{names}")
    rows = []
    for t in walls:
        if tests is not None and t.test not in tests:
            continue
        case = t.case
        an = analyse_blocks(case, facade=facade, step=step,
                            non_associative_check=non_associative_check, options=options)
        mI, mII = mechanism_I(case), mechanism_II(case)
        c, w = an.critical, an.whole_record
        row = {"test": t.test, "rho": case.rho, "alpha2": case.alpha ** 2, "beta": case.beta,
               "blocks": an.assembly.n_free,
               "lam_I": mI.lam, "vnorm_I": mI.vnorm, "lam_II": mII.lam, "vnorm_II": mII.vnorm,
               "lam_dem": t.lam_v, "h_dem": t.h_v, "vnorm_dem": t.vg_norm,
               "multiplier_whole": w["multiplier"], "h_whole": w["h"],
               "vnorm_whole": w["vnorm"],
               "multiplier_crit": c["multiplier"], "z0_crit": c["z0"], "h_blocks": c["h"],
               "lam_blocks": c["lam"], "vnorm_blocks": c["vnorm"],
               "vnorm_blocks_rigid": c["vnorm_rigid"], "method": c["method"],
               "W_rest_share": c.get("W_rest_share", math.nan),
               "M_rest_share": c.get("M_rest_share", math.nan),
               "ratio_blocks_dem": c["vnorm"] / t.vg_norm, "time": an.times["total"]}
        if an.non_associative is not None:
            na = an.non_associative
            row.update({"multiplier_na": na["multiplier"], "vnorm_na": na["vnorm"],
                        "h_na": na["h"], "na_converged": na["converged"],
                        "na_band": na["band_last5"],
                        "W_friction_share_na": na.get("W_friction_share", math.nan)})
        rows.append(row)
        if figures_dir is not None and t.test in figures_for:
            for which in ("critical", "whole"):
                _mechanism_pngs(an, Path(figures_dir) / f"blocks_table1_{t.test}_{which}.png",
                                which)
        log.info("  %s: λ_whole = %.4f, critical h = %.2f m, v/√(gb) = %.3f (rigid %.3f), "
                 "DEM %.3f, %.0f s", t.test, w["multiplier"], c["h"], c["vnorm"],
                 c["vnorm_rigid"], t.vg_norm, an.times["total"])
    by = {r["test"]: r for r in rows}
    ratios = {}
    for pair in DEM_RATIOS:
        hi, lo = pair.split("/")
        if hi in by and lo in by:
            ratios[pair] = {k: by[hi][k] / by[lo][k] for k in
                            ("vnorm_dem", "vnorm_I", "vnorm_II", "vnorm_blocks",
                             "vnorm_blocks_rigid") if k in by[hi]}
            if "vnorm_na" in by[hi] and "vnorm_na" in by[lo]:
                ratios[pair]["vnorm_na"] = by[hi]["vnorm_na"] / by[lo]["vnorm_na"]
    return rows, ratios
