"""Stage "code check": the linear kinematic analysis of NTC 2018 / Circolare 2019 §C8.7.1.2
(``check.ntc``) of every mechanism a run found that offers ``static_mechanism`` (its static
multiplier α₀ and the body it moves; or its registry entry's ``static_of``: the FE path's
whole wall), against the case's [site]. A case without [site] gets
none, and the terminal says so (``report.summary_text``). docs/code-check.md: what is
computed and the readings."""

from __future__ import annotations

import math
from dataclasses import dataclass

from ..check import LinearKinematic, Site, linear_kinematic, nonlinear_kinematic
from . import plots, registry

__all__ = ["READING", "CodeCheck", "code_check", "code_check_files"]

#: the readings taken, as summary.json records them
READING = {
    "e_star_reading":
        "continuous integration over the body, M* = (∫z dm)²/∫z² dm about the hinge "
              "(the 2009 form; 0.75 for a uniform rectangular block): used for a0_star and "
              "ratio; e_star_lumped = 1 (each body's weight lumped at its G) beside it",
    "demand_reading":
        "ground a_g S/q; where Z > 0 also S_e(T1) psi(Z) gamma/q at height, psi = Z/H, "
              "gamma = 3N/(2N+1); the larger governs",
    "alpha0_reading":
        "the mechanism's static multiplier (ties, floors, fc as its model takes them); "
              "the weights pushed horizontally are its body's (floor loads bear, their mass "
              "moves with the building: docs/real-walls.md)",
    "source_reading":
        "NTC 2018 §3.2.3.2.1 and Circolare 2019 §C8.7.1.2 as known to the authors, "
              "cross-checked against an unreviewed public transcription of the Circolare "
              "(a0*, e* agree; its floor masses Q_k differ: floors_Qk computes that reading) "
              "and an open-source code, RD2229 (docs/code-check.md)",
    "floors_Qk_reading":
        "floors_Qk beside the used check: the floors' weights Q_k (load x l) pushed "
              "horizontally in alpha0 and summed in M*, e* (the Circolare 2019 transcription's "
              "C8.7.1.1, C8.7.1.5), at the height of that reading's smallest multiplier; "
              "equal to the used check without floors",
    "nonlinear_reading":
        "where the capacity curve is clean (the simple overturning under gravity "
              "alone) and at the ground: alpha falls linearly to 0 at dk0 (G's displacement at "
              "theta0 = atan(x_G/z_G)); d* = d_k J_z/(m z_G^2); used: the 2009 form du* = "
              "0.4 d0*, Ts = 2 pi sqrt(ds*/as*), ds* = 0.4 du*, du* >= S_De(Ts) at 5 %; beside "
              "it the 2019 transcription's d_SLV = 0.4 d0*, T_SLV = 1.68 pi sqrt(d_SLV/a(d_SLV)),"
              " S_De(T_SLV) at 8 %",
    "impulse_reading":
        "beside the code check: the site's PGV 0.16 a_g S T_C (NTC 2018 §3.2.3.3) against "
              "each mechanism's collapse ground velocity vg (eq. 7): vg_over_pgv >= 1 holds",
}


@dataclass(frozen=True)
class CodeCheck:
    """The code check of one run: the site, the checks per mechanism (name →
    ``LinearKinematic``), the mechanisms without one (name → why)."""

    site: Site
    wall_H: float
    checks: dict
    skipped: dict
    vg: dict            # name → the mechanism's v̄_g [m/s] (the impulse view), where it has one
    floors: dict = None          # name → ``LinearKinematic`` in the floors' Q_k reading
    floors_skipped: dict = None  # name → why that reading is not computed
    nonlinear: dict = None       # name → ``NonlinearKinematic`` (at the ground, clean curves)
    nonlinear_skipped: dict = None   # name → why it has none

    @property
    def governing(self) -> LinearKinematic | None:
        return min(self.checks.values(), key=lambda c: c.ratio, default=None)

    def as_dict(self) -> dict:
        s = self.site
        gov = self.governing
        return {"reading": dict(READING),
                "site": {**s.as_dict(), "H_building": s.height(self.wall_H),
                         "first_period": s.first_period(self.wall_H),
                         "Se_T1": s.Se(s.first_period(self.wall_H))},
                "mechanisms": {k: c.as_dict() for k, c in self.checks.items()},
                "not_checked": [{"mechanism": k, "reason": why}
                                for k, why in self.skipped.items()],
                "impulse": {k: {"vg": v, "vg_over_pgv": v / s.pgv()}
                            for k, v in self.vg.items()},
                "governing": None if gov is None else gov.name,
                "ratio": None if gov is None else gov.ratio,
                "floors_Qk": self._floors_dict(),
                "nonlinear": {"mechanisms": {k: c.as_dict()
                                             for k, c in (self.nonlinear or {}).items()},
                              "not_computed": [{"mechanism": k, "reason": why} for k, why
                                               in (self.nonlinear_skipped or {}).items()]}}

    def _floors_dict(self) -> dict:
        fl = self.floors or {}
        gov = min(fl.values(), key=lambda c: c.ratio, default=None)
        return {"mechanisms": {k: c.as_dict() for k, c in fl.items()},
                "not_computed": [{"mechanism": k, "reason": why}
                                 for k, why in (self.floors_skipped or {}).items()],
                "governing": None if gov is None else gov.name,
                "ratio": None if gov is None else gov.ratio}


def code_check(result) -> CodeCheck | None:
    """The code check of ``result``'s mechanisms against its case's [site] (None without)."""
    site = result.config.site
    if site is None:
        return None
    H = result.case.wall.H
    checks, skipped, vg, floors, floors_skipped = {}, {}, {}, {}, {}
    nonlin, nonlin_skipped = {}, {}
    for name, m in result.mechanisms.items():
        v = getattr(m, "vg", None)
        if isinstance(v, (int, float)) and math.isfinite(v) and v > 0:
            vg[name] = float(v)
        entry = next((e for e in registry.mechanisms() if e.name == name), None)
        sm = (entry.static_of(result) if entry is not None and entry.static_of is not None
              else getattr(m, "static_mechanism", None))
        if sm is None:
            skipped[name] = "no static multiplier with a rigid body"
            continue
        checks[name] = linear_kinematic(name, sm, site, H)
        if not result.case.floors:      # no floors: the two readings are one
            floors[name] = checks[name]
        elif sm.floor_reading is not None:
            floors[name] = linear_kinematic(name, sm.floor_reading, site, H)
        else:
            floors_skipped[name] = ("its model pushes only the wall's own weight; the floors' "
                                    "weights would need a new limit analysis")
        if sm.theta0 is None:
            nonlin_skipped[name] = ("no clean capacity curve (only the simple overturning "
                                    "under gravity alone: no ties, no floors)")
        elif checks[name].Z > 1e-9:
            nonlin_skipped[name] = (f"its base is at Z = {checks[name].Z:.4g} m: the check at "
                                    "height is not computed")
        else:
            nonlin[name] = nonlinear_kinematic(checks[name], sm, site)
    return CodeCheck(site, H, checks, skipped, vg, floors, floors_skipped, nonlin,
                     nonlin_skipped)


def code_check_files(result) -> dict:
    """code_check.png (with [output] png and a [site]): ``plots.plot_code_check``."""
    cc = result.code_check
    if cc is None or not result.config.output.png or not (cc.checks or cc.vg):
        return {}
    pgv = cc.site.pgv()
    return {"code_check_png": ("code_check.png", lambda p: plots.plot_code_check(
        p, cc.checks, {k: v / pgv for k, v in cc.vg.items()}, title=f"case {result.name}",
        floors=cc.floors if result.case.floors else None))}
