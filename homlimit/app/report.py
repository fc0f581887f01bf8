"""What a run shows: the terminal summary and the plain-text tables (``format_table``,
``format_spectra``, ``summary_text``).

What it writes lives beside: ``app.writers`` (``write``: the registry of output files and one
writer per format, whole or nothing), ``app.units`` (``UNITS``: every quantity's SI unit,
once; the unit tables of JSON files and CSV sidecars) and ``app.result_mesh``
(mechanism.vtu's mesh). Their public names are importable from here too (``report.write``,
``report.UNITS``, ...). CSV headers carry the unit as ``name [unit]`` (``vg [m/s]``,
``lam [-]``; text columns plain, ``mechanism``), the way the terminal tables do; floats are
written to 15 significant digits.
"""


from __future__ import annotations

import math

import numpy as np

from . import registry
from .result_mesh import mechanism_mesh, static_mesh
from .units import UNITS, column_unit, csv_header, input_units, units_table
from .writers import OUTPUT_NAMES, OUTPUTS, WRITERS, read_csv, write

__all__ = ["OUTPUTS", "OUTPUT_NAMES", "UNITS", "WRITERS", "column_unit", "csv_header",
           "format_spectra", "format_table", "input_units", "mechanism_mesh", "read_csv",
           "static_mesh", "summary_text", "units_table", "write"]


def _fmt(x) -> str:
    if x is None:
        return "–"
    if isinstance(x, bool):
        return "yes" if x else "no"
    if isinstance(x, (int, np.integer)):
        return str(int(x))
    if isinstance(x, (float, np.floating)):
        x = float(x)
        if not math.isfinite(x):
            return "–"
        return f"{x:.4g}" if (x == 0 or 1e-3 <= abs(x) < 1e5) else f"{x:.3e}"
    return str(x)


def format_table(header: list[str], rows: list[list], title: str | None = None) -> str:
    """A plain-text table with aligned columns (numbers to 4 significant digits)."""
    cells = [[_fmt(c) for c in r] for r in rows]
    widths = [max([len(h)] + [len(r[i]) for r in cells]) for i, h in enumerate(header)]
    line = "  ".join("-" * w for w in widths)
    out = [] if title is None else [title]
    out += ["  ".join(h.ljust(w) for h, w in zip(header, widths)), line]
    out += ["  ".join(c.rjust(w) if i else c.ljust(w) for i, (c, w) in
                      enumerate(zip(r, widths))) for r in cells]
    return "\n".join(out)


def format_spectra(points, title: str | None = None) -> str:
    """The overturning spectra (``dynamics.SpectrumPoint``) as a text table: pulse, mechanism,
    polarity, T_p, critical pga/g, pgv, pgv/√(gb), pgv over eq. 7's v̄_g, impacts, and the flag
    "implausible" (pga > 3 g or pgv > 3 m/s)."""
    rows = [[p.pulse, p.mechanism, p.polarity, p.period, p.pga_g, p.pgv, p.vnorm, p.ratio,
             p.n_impacts, "implausible" if p.implausible else ""] for p in points]
    return format_table(["pulse", "mech", "pol", "T_p [s]", "pga/g", "pgv [m/s]",
                         "pgv/sqrt(gb)", "pgv/vg(eq.7)", "impacts", "flag"], rows, title)


# ----------------------------------------------------------------------------- the summary
def summary_text(result) -> str:
    """A readable terminal table of a ``pipeline.Result``: each mechanism's λ, h, v̄_g and
    v̄_g/√(gb) beside the paper's DEM value, the FE details, the governing mechanism, files."""
    c = result.case
    rows = [[m.label, m.lam, m.h, m.vg, m.vnorm] for m in result.mechanisms.values()]
    if result.dem:
        d = result.dem
        rows.append(["DEM, paper's Table 1", d.lam_v, d.h_v, d.vg, d.vg_norm])
    run = getattr(result, "dem_run", None)
    if run is not None:
        d = run.as_dict()
        rows.append([run.label(), d["lam"], d["h"], d["pgv"], d["vnorm"]])
    head = (f"case {result.name}: H={c.wall.H:g} m, L={c.wall.L:g} m, s={c.wall.s:g} m, "
            f"b={c.wall.b:g} m, l={c.wall.l:g} m; a={c.masonry.a:g} m, c={c.masonry.c:g} m, "
            f"f={c.masonry.f:g}\n"
            f"  rho=l/s={c.rho:.4g}  alpha^2=cf/a={c.alpha ** 2:.4g}  beta=c/b={c.beta:.4g}"
            f"  (eq. 11)")
    cfg = result.config
    if cfg.modified:
        head += f"\n  modified by --set: {cfg.describe_changes()}"
    head += "".join(f"\n  warning: {w}" for w in cfg.warnings)
    out = [head, "", format_table(["mechanism", "lambda=h/b", "h [m]", "vg [m/s]",
                                   "vg/sqrt(gb)"], rows)]
    statics = [f"{k} {m.multiplier:.4g} at h = {m.lam_multiplier * c.wall.b:.2f} m"
               for k, m in result.mechanisms.items() if registry.mechanism(k).static]
    if statics:
        out += ["", "collapse acceleration a/g of a static check (smallest over h): "
                + "; ".join(statics)]
    if run is not None:
        out += ["", run.lines()]
    if result.fe:
        out += ["", _fe_lines(result.fe, c)]
    if result.hinges:
        out += ["", _hinge_lines(result, c.masonry.f)]
    out += [""] + _code_check_lines(result)
    crit = result.critical()
    if crit:
        out += ["", f"governing: {crit['mechanism']}, collapse ground velocity "
                    f"vg = {crit['vg']:.3f} m/s (vg/sqrt(gb) = {crit['vnorm']:.3f})"]
    out += [f"  {k}: vg {m.vg_unavailable}" for k, m in result.mechanisms.items()
            if getattr(m, "vg_unavailable", "")]
    if result.files:
        out += ["", "files:"] + [f"  {v}" for v in result.files.values()]
    return "\n".join(out)


def _num(x, fmt=".3f") -> str:
    return "–" if x is None or not math.isfinite(x) else format(x, fmt)


def _fe_lines(fe, case) -> str:
    """The FE block of the summary: the whole wall, its bracket, hinge, crack and scan."""
    full, crit = fe.whole, fe.critical
    e1, e2 = full.tanpsi_edges
    lines = [f"FE, whole wall: {full.n_triangles} triangles, façade {full.facade}, "
             f"collapse multiplier {_num(full.multiplier, '.4g')} (acceleration / g)"]
    if fe.static is not None:
        ns = fe.static.mesh.t.shape[1]
        how = ("same mesh" if ns == full.n_triangles else
               f"static on its own mesh, {ns} triangles, façade columns graded to the "
               f"outer face") if fe.adapt is None else (
            f"adaptive {full.problem.meta.get('mesher', 'gmsh')} mesh, "
            + _adapt_cycles(fe.adapt))
        lines.append(f"  bracket: static {_num(fe.lower_bound, '.4g')} <= multiplier <= "
                     f"kinematic {_num(full.multiplier, '.4g')} (gap "
                     f"{100 * fe.bracket_rel_gap:.1f} %, {how})")
    lines += [f"  {full.kind} mechanism, hinge at x = {_num(full.O[0], '.2f')} m, "
              f"z = {_num(full.O[1], '.2f')} m",
              f"  crack: tan psi = {_num(full.tanpsi)} ± {_num(full.tanpsi_uncertainty)} "
              f"(50 % line), edges {_num(e1)} .. {_num(e2)}",
              f"         sqrt(cf/a) = {case.alpha:.3f} (eq. 16), f = {case.masonry.f:.3f}, "
              f"c/a = {case.masonry.c / case.masonry.a:.3f}", _crack_change_line(fe)]
    if crit is None and getattr(fe, "vg_unavailable", ""):
        lines += [f"  impulse: vg not available at any of {len(fe.scan)} heights of the "
                  f"failing part ({fe.h_min:g} m, one course, to H); the FE mechanism is "
                  f"{fe.critical_at}", f"         ({fe.vg_unavailable})"]
    if crit is not None:
        lines += [f"  impulse: lowest vg over {len(fe.scan)} heights of the failing part "
                  f"({fe.h_min:g} m, one course, to H) at h = {_num(crit.h, '.2f')} m: "
                  f"{fe.critical_at}", f"         ({crit.vg_method})"]
    return "\n".join(lines)


def _adapt_cycles(adapt) -> str:
    """"1 cycle, target reached" and, after ``fe.adapt.refine_mechanism``, "; the crack's band
    split 2 times, settled"."""
    n = sum(c.kind == "bracket" for c in adapt.cycles)
    k = len(adapt.cycles) - n
    out = (f"{n} cycle{'s' if n != 1 else ''}, "
           + ("target reached" if adapt.converged else f"stopped: {adapt.stop}"))
    if adapt.mechanism_stop == "unmarked" and k == 0:
        out += "; no crack to split"
    elif adapt.mechanism_stop:
        out += (f"; the crack's band split {k} time{'s' if k != 1 else ''}, "
                + ("settled" if adapt.mechanism_stop == "settled"
                   else f"stopped: {adapt.mechanism_stop}"))
    return out


def _crack_change_line(fe) -> str:
    """How far the hinge and crack moved before the run stopped (``FEResult.crack_change``)."""
    ch = fe.crack_change
    if "resolution" in ch:
        return (f"         changed by at most {ch['resolution']:.4f} (edges, mid-line) over "
                f"{ch['over']}")
    if ch:
        rel = (ch["T_mid"] / fe.whole.tanpsi if ch["T_mid"] is not None and fe.whole.tanpsi
               else None)
        return (f"         change over {ch['over']}: hinge z {_num(ch['hinge_z'])} m, edges "
                f"{_num(ch['T1'], '.4f')} / {_num(ch['T2'], '.4f')}, mid-line "
                f"{_num(ch['T_mid'], '.4f')} ({_num(None if rel is None else 100 * rel, '.1f')} %)")
    return ("         change over the last cycle: not measured (one mesh"
            + (": the bracket met its target on its first)" if fe.adapt is not None
               and fe.adapt.converged else ")"))


def _code_check_lines(result) -> list[str]:
    """The terminal's code-check block (or the line saying there is none)."""
    cc = getattr(result, "code_check", None)
    if cc is None:
        return ["code check (NTC 2018 / Circolare 2019 §C8.7.1.2): none, the case has no "
                "[site] section (docs/code-check.md)"]
    s, H = cc.site, cc.wall_H
    T_B, T_C, T_D = s.periods
    T1 = s.first_period(H)
    head = ["code check, linear kinematic analysis (NTC 2018 / Circolare 2019 §C8.7.1.2; "
            "docs/code-check.md)",
            f"  site: a_g = {s.ag:.4g} m/s² ({s.ag_over_g:.4g} g), F0 = {s.F0:g}, "
            f"Tc* = {s.Tc_star:g} s, soil {s.soil} (S_S = {s.S_S:.4g}, C_C = {s.C_C:.4g}), "
            f"{s.topography} (S_T = {s.S_T:g}): S = {s.S:.4g}; T_B, T_C, T_D = {T_B:.3f}, "
            f"{T_C:.3f}, {T_D:.3f} s; q = {s.q:g}, FC = {s.FC:g}",
            f"  building: H = {s.height(H):.4g} m, N = {s.storeys}, T1 = {T1:.3f} s"
            f"{'' if s.T1 else ' (0.05 H^0.75)'}, S_e(T1) = {s.Se(T1):.4g} m/s², "
            f"gamma = {3 * s.storeys / (2 * s.storeys + 1):.4g}; wall base at {s.z_base:g} m; "
            f"ground demand a_g S/q = {s.demand_ground():.4g} m/s²"]
    rows = [[c.name, c.alpha0, c.e_star, c.a0_star, c.Z, c.demand_height, c.demand, c.ratio,
             c.a0_star_lumped, c.ratio_lumped, "yes" if c.passes else "NO"]
            for c in cc.checks.values()]
    out = head + [format_table(["mechanism", "alpha0", "e*", "a0* [m/s2]", "Z [m]",
                                "height [m/s2]", "demand [m/s2]", "ratio", "a0*(e*=1)",
                                "ratio(e*=1)", "met"], rows)]
    out.append("  ratio = a0*/demand (used: e* by integration over the body); beside it "
               "e* = 1 (weights lumped at G); demand = max(ground, at height where Z > 0)")
    out += [f"  {k}: not checked ({why})" for k, why in cc.skipped.items()]
    if cc.vg:
        pgv = s.pgv()
        out.append(f"  impulse view: site PGV = 0.16 a_g S T_C = {pgv:.4g} m/s (NTC 2018 "
                   "§3.2.3.3); vg/PGV " + ", ".join(f"{k} {v / pgv:.3g}"
                                                   for k, v in cc.vg.items())
                   + " (>= 1: the mechanism's collapse velocity exceeds the site's PGV)")
    gov = cc.governing
    if gov is not None:
        out.append(f"  governing in the code check: {gov.name}, ratio {gov.ratio:.3f} "
                   f"({'met' if gov.passes else 'NOT met'})")
    return out + _floors_lines(cc, result.case.floors) + _nonlinear_lines(cc)


def _nonlinear_lines(cc) -> list[str]:
    """The nonlinear kinematic check at the ground, where it is computed."""
    nl = cc.nonlinear or {}
    rows = [[c.name, c.d0_star, c.du_star, c.Ts, c.SDe_Ts, c.ratio, "yes" if c.passes else "NO",
             c.T_SLV, c.SDe_SLV, c.ratio_SLV] for c in nl.values()]
    out = []
    if rows:
        out.append(format_table(
            ["mechanism", "d0* [m]", "du* [m]", "Ts [s]", "S_De(Ts) [m]", "ratio", "met",
             "T_SLV [s]", "S_De(T_SLV,8%) [m]", "ratio(2019)"], rows,
            title="nonlinear kinematic analysis at the ground (2009 C8A.4.2 form: du* = 0.4 "
                  "d0* >= S_De(Ts); beside it the 2019 transcription's d_SLV = 0.4 d0*, "
                  "T_SLV = 1.68 pi sqrt(d/a), 8 %)"))
    out += [f"  {k}: no nonlinear check: {why}" for k, why in (cc.nonlinear_skipped or {}).items()]
    return out


def _floors_lines(cc, floors) -> list[str]:
    """The floors' Q_k reading beside the used check (docs/code-check.md, reading 3)."""
    if not floors:
        return ["  floors' Q_k reading (Circolare 2019 transcription, C8.7.1.1/.5): the case has "
                "no floors, the same as above"]
    rows = [[c.name, c.alpha0, c.m_floors, c.e_star, c.a0_star, c.Z, c.demand, c.ratio,
             cc.checks[c.name].ratio, "yes" if c.passes else "NO"]
            for c in (cc.floors or {}).values()]
    out = [format_table(["mechanism", "alpha0", "floors [kg]", "e*", "a0* [m/s2]", "Z [m]",
                         "demand [m/s2]", "ratio", "ratio used", "met"], rows,
                        title="beside it, the floors' Q_k reading (Circolare 2019 "
                              "transcription, C8.7.1.1/.5): the floors' weights pushed "
                              "horizontally in alpha0 and summed in M*, e*")]
    out += [f"  {k}: floors' reading not computed ({why})"
            for k, why in (cc.floors_skipped or {}).items()]
    if rows:
        gov = min(cc.floors.values(), key=lambda c: c.ratio)
        out.append(f"  governing in the floors' reading: {gov.name}, ratio {gov.ratio:.3f} "
                   f"({'met' if gov.passes else 'NOT met'}); its own smallest a/g over h "
                   "(the body, Z may differ from the used check's)")
    return out


def _hinge_lines(result, f: float) -> str:
    """The hinge under the ideal impulse: |P_x/P_z| against f, and the shortest rectangular
    pulse of a_g = f g that still overturns each mechanism."""
    rows = [[k, result.mechanisms[k].hinge_ratio, "yes" if result.mechanisms[k].hinge_ratio > f
             else "no", h.duration, h.pgv, h.ratio] for k, h in result.hinges.items()]
    out = [format_table(["mechanism", "|Px/Pz|", "slides", "holding pulse [s]", "pgv [m/s]",
                         "pgv/vg"], rows,
                        title=f"hinge under the ideal impulse (it slides where |Px/Pz| > "
                              f"f = {f:g}) and the shortest rectangular pulse of a_g = f g "
                              "that still overturns")]
    slid = [k for k, r in zip(result.hinges, rows) if r[2] == "yes"]
    if slid:
        out.append(f"  the ideal-impulse vg of {', '.join(slid)} is not attainable without the "
                   "hinge sliding: a pulse the hinge holds needs the pgv above")
    out += [f"  {k}: {h.reason}" for k, h in result.hinges.items() if h.reason]
    return "\n".join(out)


# ----------------------------------------------------------------------------- result meshes
