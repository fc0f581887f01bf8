"""The finite-element path of one wall, from a T-section problem to typed results.

``analyse`` solves one kinematic problem and measures what the mechanism is: the rigid fit
(``rigidfit``), the crack's mid-line and fan edges (``crack``), its kind, the failing body and
the collapse ground velocity (``fe_impulse``, eqs 4–7). ``h_scan`` repeats it over the heights
of the failing part (the part above z0 = H − h, base fixed at z0); ``fe_result`` runs the scan
over the heights the masonry admits and, optionally, the whole wall's static lower bound on
the same mesh. The critical FE mechanism is the scan's lowest v̄_g (eq. 7 minimised over h).

The block is the internal length. The homogenised continuum has none: a corner chip cut from
an outer-face hinge opens without dissipation and eq. 7 gives v̄_g ∝ √(size), so an unbounded
scan runs to ever smaller parts. In the wall no failing part is lower than one course, so the
scan spans a <= h <= H; with the default bed-joint façade (its blocks run through the
thickness) no crack cuts the façade diagonally. The scan starts from ``heights`` heights spaced
geometrically over that range and bisects around its minimum until the neighbouring heights
are one ``step`` (default a) apart, or two steps apart and within ``rtol`` (0.5 %) of the
minimum (``scan_midpoints``); the result says
whether the minimum is interior or sits at a bound (one course, or the whole wall).

With a joint cohesion (``fe_impulse.bond_reason``) no height has a v̄_g: both bounds, the
mechanism, its crack and the body inside its 50 % line (the code check's) are computed with
the cohesion and the tension, the scan runs its starting heights only (there is no minimum
to bisect around) and the whole wall stands for the FE mechanism, its v̄_g "not available"
with the reason, as the rigid blocks' (docs/real-walls.md "FE impulse").
"""

from __future__ import annotations

import dataclasses
import functools
import logging
import math
from dataclasses import dataclass

import numpy as np

from .. import _threads
from ..check.ntc import StaticMechanism
from ..errors import ParameterError, check_choice, check_range
from ..fe.problems import Problem, t_section
from ..impulse import RigidBody, collapse_velocity, hinge_impulse_ratio
from ..params import FACADE_DEFAULT, FACADE_MODELS, MESHER_DEFAULT, MESHERS, PART_DIVISIONS, Case
from .crack import FanEdges, fan_edges, mechanism_type
from .fe_impulse import (
    GeneralisedImpulse,
    body_loads,
    bond_reason,
    contour_body,
    contour_pieces,
    generalised_impulse,
    p2_nodes,
)
from .rigidfit import MechanismMeasures, measure_mechanism

__all__ = ["FEMechanism", "FEResult", "analyse", "densities", "fe_result", "first_heights",
           "h_scan", "part_problem", "scan_midpoints"]

# Clarabel's tolerance for the scan's parts: the linear programs' default 1e-9 stalls on most
# fine part meshes and is met only at the ladder's 1e-7 rung after two stalled runs (B2, part
# 2.5 m at h/40: 35 s, against 8.8 s at 1e-7 directly, v̄_g equal to 1e-6; docs/fe-impulse.md)
PART_TOL = 1e-7

log = logging.getLogger(__name__)

def densities(case: Case) -> dict[str, float]:
    """Mass per unit area of each T-section region in the section plane, times the
    transversal wall's thickness s [kg/m²]: façade ρ·γ·s (the paper's 2D reduction), wall γ·s;
    a façade opening band's region (``problems._facade_bands``) (1 − fraction) ρ·γ·s, after
    the façade's (``p2_nodes`` sets them in order)."""
    w = case.wall
    out = {"facade": case.rho * w.gamma * w.s, "wall": w.gamma * w.s}
    for k, op in enumerate(case.facade_openings):
        out[f"facade_open{k}"] = (1 - op.fraction) * case.rho * w.gamma * w.s
    for k in range(len(case.wall_openings)):    # the lintels are the wall's masonry
        out[f"lintel{k}"] = w.gamma * w.s
    return out


@dataclass(frozen=True)
class FEMechanism:
    """One FE collapse mechanism and what is measured on it.

    problem, solution   the analysed part (base fixed at z0) and its KinematicSolution
    measures            rigid fit (hinge O, rotation rate ω) and per-element participation
    edges               the crack's level lines, mid-line and fan edges (None: no crack found)
    kind                "rigid", "hinge+fan" or "distributed" (``crack.mechanism_type``)
    body                the rigid body inside the 50 % participation line (None: no block)
    impulse             the one-degree-of-freedom criterion of the whole mechanism
    vg, vg_method       the collapse ground velocity [m/s] and how it was obtained (NaN and
                        the reason when the mechanism has no block with a restoring lever)
    vg_unavailable      why eq. 7 has no v̄_g for this case at all ("" when it has one): a
                        joint cohesion (``fe_impulse.bond_reason``); the body is then kept
                        for the code check, and ``app.checks`` exempts v̄_g
    """

    case: Case
    problem: Problem
    solution: object
    measures: MechanismMeasures
    edges: FanEdges | None
    kind: str
    body: RigidBody | None
    impulse: GeneralisedImpulse | None
    vg: float
    vg_method: str
    facade: str
    mesh_size: float
    z0: float = 0.0
    vg_unavailable: str = ""
    name = "FE"

    @property
    def multiplier(self) -> float:
        """λ⁺ of the analysed part: the collapse acceleration over g (an upper bound)."""
        return self.solution.multiplier

    @property
    def n_triangles(self) -> int:
        return self.problem.n_triangles

    @property
    def O(self) -> tuple[float, float]:  # noqa: E743 (the paper's rotation centre)
        return tuple(self.measures.fit.O)

    @property
    def h_part(self) -> float:
        """Height of the analysed part, H − z0 [m]."""
        return float(self.problem.meta.get("h_part", self.case.wall.H - self.z0))

    @property
    def h(self) -> float:
        """Height of the failing part above the hinge, H − z_O [m]."""
        return self.case.wall.H - self.measures.fit.O[1]

    @property
    def lam(self) -> float:
        """λ = h/b (eq. 11) of the failing part."""
        return self.h / self.case.wall.b

    @property
    def vnorm(self) -> float:
        """v̄_g/√(g b)."""
        w = self.case.wall
        return self.vg / math.sqrt(w.g * w.b)

    @property
    def static_mechanism(self) -> StaticMechanism | None:
        """The code check's α₀ and body: λ⁺ of the analysed part and the body inside its
        50 % participation line, about the fitted hinge (None without a body)."""
        if self.body is None or not math.isfinite(self.multiplier):
            return None
        what = "whole wall" if self.z0 == 0 else f"part above z = {self.z0:.3g} m"
        return StaticMechanism(self.multiplier, self.body, float(self.measures.fit.O[1]),
                               f"λ⁺ of the {what}, its body inside the 50 % line")

    @property
    def tanpsi(self) -> float:
        """Slope tan ψ of the crack's mid-line (the 50 % participation line)."""
        return self.edges.T_mid if self.edges else math.nan

    @property
    def tanpsi_uncertainty(self) -> float:
        return self.edges.dT if self.edges else math.nan

    @property
    def tanpsi_edges(self) -> tuple[float, float]:
        """Block-side and fixed-side fan edges (a sharp crack: the mid-line twice)."""
        if self.edges is None:
            return (math.nan, math.nan)
        return (self.edges.T_mid, self.edges.T_mid) if self.edges.sharp else self.edges.edges

    @property
    def vg_body(self) -> float:
        """Eq. 7 + eq. 18 of the body inside the 50 % line alone [m/s] (NaN without one, or
        without a v̄_g: ``vg_unavailable``)."""
        if self.body is None or self.vg_unavailable:
            return math.nan
        return collapse_velocity(self.body, g=self.case.wall.g)

    @property
    def hinge_ratio(self) -> float:
        """|P_x/P_z| the hinge must transmit under the ideal impulse (``impulse``), for the
        body inside the 50 % line (NaN without a body, or without a v̄_g)."""
        if self.body is None or self.vg_unavailable:
            return math.nan
        return hinge_impulse_ratio(self.body)

    @property
    def label(self) -> str:
        if self.vg_unavailable:             # a cohesion: the whole wall's λ⁺ and body only
            return f"FE whole wall, {self.kind} (vg not available)"
        return f"FE body, {self.kind} (one-DOF eqs 4-7)"

    def record(self) -> dict:
        """The flat record of one analysed height (fe_scan.csv)."""
        return {"h_part": self.h_part, "h": self.h, "lam": self.lam, "vg": self.vg,
                "vnorm": self.vnorm, "vg_body": self.vg_body, "multiplier": self.multiplier,
                "mechanism": self.kind,
                "tanpsi": self.tanpsi, "hinge_ratio": self.hinge_ratio,
                "status": self.solution.status,
                "retries": len(self.solution.sizes.get("attempts", [0])) - 1,
                "solver_tol": self.solution.sizes.get("tol"), "vg_method": self.vg_method
                } | self._real_record()

    def _real_record(self) -> dict:
        """With ties or floors (issue 30): W(q_m) and its floors' and ties' parts [J] (NaN
        without a body); nothing for the paper's wall."""
        if not (self.case.ties or self.case.floors):
            return {}
        gi = self.impulse
        return {k: math.nan if gi is None else getattr(gi, k)
                for k in ("W_m", "W_floors", "W_ties")}

    def as_dict(self) -> dict:
        """The mechanism's row of summary.json (as the closed forms' ``as_dict``)."""
        return {"name": self.name, **self.record()}

    def body_pieces(self):
        """The failing body as triangles (points (k, 3, 2), density (k,) [kg/m²]): the
        pieces inside the 50 % participation line (``fe_impulse.contour_pieces``)."""
        X, _, el, rho = p2_nodes(self.solution, densities(self.case))
        return contour_pieces(X, el, rho, self.measures)

    def drawing(self) -> dict:
        """What ``plots.plot_mechanism`` draws: points, triangles and velocity at the mesh
        vertices, the hinge, the 50 % line ``crack`` and the 10 % and 90 % ``crack_edges``."""
        sol = self.solution
        lines = self.edges.lines if self.edges is not None else {}
        return {"points": sol.mesh.p.T.copy(), "triangles": sol.mesh.t.T.copy(),
                "velocity": sol.velocity, "hinge": self.O,
                "crack": lines[0.5].polyline if 0.5 in lines else None,
                "crack_edges": [lines[lv].polyline for lv in (0.1, 0.9) if lv in lines]}


def part_problem(case: Case, h_part: float, facade: str, mesh_size: float,
                 divisions: int = PART_DIVISIONS, mesher: str = MESHER_DEFAULT) -> Problem:
    """The T-section of the top part of height ``h_part`` (``problems.t_section`` with its base
    at z0 = H − h_part), element size min(mesh_size, h_part/divisions) so that short parts stay
    resolved; ``mesher``: ``problems.MESHERS``."""
    prob = t_section(case, z0=max(0.0, case.wall.H - h_part), facade=facade,
                     h=min(mesh_size, h_part / divisions), mesher=mesher)
    return dataclasses.replace(prob, meta={**prob.meta, "h_part": h_part})


def analyse(case: Case, problem: Problem, options=None, solution=None) -> FEMechanism:
    """Solve ``problem`` (a ``t_section`` of ``case``, base fixed at its z0) and measure its
    mechanism: rigid fit, crack, kind, body and v̄_g.

    v̄_g is the one-DOF generalisation of eqs 4–7 for every kind (``fe_impulse``): for a sharp
    crack (``kind == "rigid"``) it tends to eq. 7 + eq. 18 of the body inside the 50 % line as
    the smeared band thins (that value is kept as ``vg_body``), and one rule for all kinds keeps
    v̄_g continuous when refining the mesh turns a smeared crack into a resolved fan.
    """
    from ..fe.kinematic import solve_kinematic
    from ..fe.solver import SolverOptions

    w = case.wall
    sol = solution if solution is not None else solve_kinematic(problem,
                                                                options or SolverOptions())
    X, V, el, rho = p2_nodes(sol, densities(case))
    mm = measure_mechanism(X, V, el, rho)
    # a mesh conforming to the field's kinks (mechanism.conform) states its own resolution
    res = problem.meta.get("crack_resolution")
    edges = (fan_edges(X, el, mm, w.b, z_top=w.H, resolution=res)
             if mm.kind != "distributed" else None)
    kind = mechanism_type(mm, edges)
    meta = problem.meta
    common = dict(case=case, problem=problem, solution=sol, measures=mm, edges=edges,
                  kind=kind, facade=meta.get("facade", ""), z0=float(meta.get("z0", 0.0)),
                  mesh_size=float(meta.get("h", math.nan)))
    reason = bond_reason(case)
    if reason:      # a cohesion: no W(q) (fe_impulse.bond_reason); the body for the code check
        try:
            body = contour_body(X, el, rho, mm)
        except ParameterError:
            body = None
        why = f"not available: {reason}"
        return FEMechanism(**common, body=body, impulse=None, vg=math.nan, vg_method=why,
                           vg_unavailable=why)
    loads = body_loads(case, problem)
    try:
        gi = generalised_impulse(X, V, el, rho, mm, g=w.g, loads=loads)
    except ParameterError as exc:
        return FEMechanism(**common, body=None, impulse=None, vg=math.nan,
                           vg_method=f"not available: {exc}")
    return FEMechanism(**common, body=gi.block, impulse=gi, vg=gi.vg, vg_method=(
        "one-DOF generalisation of eqs 4-7 (fe_impulse docstring): body inside the 50 % line "
        "at finite rotation, the rest linearised, W at its peak"
        + (", with the ties' and floors' work" if loads else "")))


def _analyse_height(case: Case, mesh_size: float, facade: str, options, divisions: int,
                    h_part: float, mesher: str = MESHER_DEFAULT) -> FEMechanism:
    """One height of the scan: ``analyse`` on the top part of height ``h_part`` (the whole
    wall, meshed at ``mesh_size``, when h_part >= H). A module function, so that an executor
    can run it as a task (``h_scan``'s ``map``)."""
    return analyse(case, *_height_problem(case, mesh_size, facade, options, divisions, h_part,
                                          mesher))


def _height_problem(case: Case, mesh_size: float, facade: str, options, divisions: int,
                    h_part: float, mesher: str = MESHER_DEFAULT) -> tuple[Problem, object]:
    """The problem of one height of the scan and its solver options: a part is solved to
    ``PART_TOL`` unless ``options`` sets a tolerance."""
    if h_part >= case.wall.H:
        log.info("FE mechanism of the whole wall")
        return t_section(case, facade=facade, h=mesh_size, mesher=mesher), options
    from ..fe.solver import SolverOptions

    log.info("FE analysis: part of height %.3f m", h_part)
    options = options or SolverOptions()
    if options.tol is None:
        options = dataclasses.replace(options, tol=PART_TOL)
    return part_problem(case, h_part, facade, mesh_size, divisions, mesher), options


def h_scan(case: Case, h_parts, mesh_size: float = 0.25, facade: str = FACADE_DEFAULT,
           options=None, map=None, divisions: int = PART_DIVISIONS,
           mesher: str = MESHER_DEFAULT, at_once: int | None = None) -> list[FEMechanism]:
    """``analyse`` on the top part of height h_part for every h_part in ``h_parts`` [m] (the
    whole wall for h_part = H). The hinge may float above the base of the analysed part: each
    mechanism's own h = H − z_O. ``map(fn, h_parts)``: how the heights are evaluated, results
    in order (``app.engine.Engine.map`` makes each height a Dask task; the builtin ``map``:
    one after another here). The default, None: here, every part meshed in this thread (gmsh
    holds global state and resets the signal handlers, which only the main thread may put
    back: ``fe.geometry.gmsh_session``), then solved as many at a time as there are cores, one
    after another on a Dask worker (``_threads.map_here``; on the demo's B1 scan the mechanisms
    of the one-after-another run, bit for bit). ``divisions``: elements per part height
    (``part_problem``); ``mesher``: ``problems.MESHERS``; ``at_once``: with ``map`` None, how
    many parts to solve at a time (default: ``_threads.map_here``'s)."""
    w = case.wall
    check_choice("mesher", mesher, MESHERS)
    h_parts = [check_range("h_part", hp, 0.0, w.H, lo_open=True, unit="m") for hp in h_parts]
    divisions = int(check_range("divisions", divisions, 1, 1000))
    log.info("FE scan: %d collapse heights", len(h_parts))
    if map is None:
        jobs = [_height_problem(case, mesh_size, facade, options, divisions, hp, mesher)
                for hp in h_parts]
        if at_once is not None:
            return _threads.map_threads(lambda job: analyse(case, *job), jobs, at_once)
        return _threads.map_here(lambda job: analyse(case, *job), jobs)
    return list(map(functools.partial(_analyse_height, case, mesh_size, facade, options,
                                      divisions, mesher=mesher), h_parts))


def first_heights(case: Case, heights: int = 6) -> list[float]:
    """The scan's first round of part heights below the whole wall [m]: ``heights`` − 1 of
    them, geometric from one course (a) up, the whole wall (H) being the last of the round."""
    heights = int(check_range("heights", heights, 2, 200))
    return list(np.geomspace(case.masonry.a, case.wall.H, heights)[:-1])


@dataclass(frozen=True)
class FEResult:
    """The FE path of one wall: the impulse scan over the heights of the failing part, sorted
    by height (the whole wall last), and the whole wall's static lower bound on the same mesh
    (None if not run). ``h_min``: the smallest part the masonry admits (one course, a)."""

    scan: tuple[FEMechanism, ...]
    static: object = None
    h_min: float = 0.0
    adapt: object = None            # the whole wall's fe.adapt.AdaptResult, if adaptive

    @property
    def whole(self) -> FEMechanism:
        return self.scan[-1]

    @property
    def vg_unavailable(self) -> str:
        """Why no height has a v̄_g ("" when they may): a joint cohesion
        (``FEMechanism.vg_unavailable``)."""
        return self.whole.vg_unavailable

    @property
    def critical_at(self) -> str:
        """Where the scan's minimum lies: "interior", "bound: one course" or "bound: whole
        wall" (a minimum at a bound is set by that bound, not by the mechanics); with a
        joint cohesion, the whole wall (no v̄_g to minimise)."""
        if self.vg_unavailable:
            return ("the whole wall (no v̄_g to minimise: not available with a joint "
                    "cohesion or tension)")
        crit = self.critical
        if crit is None or len(self.scan) < 2:
            return "interior" if crit is not None else "none"
        if crit is self.scan[0] and math.isclose(crit.h_part, self.h_min, rel_tol=1e-9):
            return "bound: one course"
        return "bound: whole wall" if crit is self.scan[-1] else "interior"

    @property
    def critical(self) -> FEMechanism | None:
        """The scan's lowest finite v̄_g (None if no height gave one)."""
        ok = [m for m in self.scan if np.isfinite(m.vg)]
        return min(ok, key=lambda m: m.vg) if ok else None

    @property
    def crack_change(self) -> dict:
        """How far the reported hinge and crack moved before the run stopped: over the fan
        search's last improving round ("over", "resolution": its ``crack_resolution``, the
        largest change of the edges or mid-line), or over the adaptive chain's last cycle
        ("over", and the absolute changes of hinge_z [m], T1, T2, T_mid between the last two
        cycles' best kinematic fields, None where either had none); {} where neither was
        measured (one mesh)."""
        res = self.whole.problem.meta.get("crack_resolution")
        if res is not None:
            return {"over": "the fan search's last improving round", "resolution": float(res)}
        ms = [] if self.adapt is None else [c.measures for c in self.adapt.cycles if c.measures]
        if len(ms) < 2:
            return {}
        a, b = ms[-2], ms[-1]
        return {"over": "the last cycle"} | {
            k: None if a.get(k) is None or b.get(k) is None else abs(b[k] - a[k])
            for k in ("hinge_z", "T1", "T2", "T_mid")}

    @property
    def lower_bound(self) -> float | None:
        return None if self.static is None else self.static.multiplier

    @property
    def bracket_rel_gap(self) -> float | None:
        """(λ⁺ − λ⁻)/mean of the whole wall's bracket on one mesh."""
        if self.static is None:
            return None
        up, lo = self.whole.multiplier, self.static.multiplier
        return (up - lo) / (0.5 * (up + lo))

    def as_dict(self) -> dict:
        """The summary's "fe" section: the whole wall, its bracket, the critical height and
        every height of the scan."""
        full, crit, case = self.whole, self.critical, self.whole.case
        at = full if self.vg_unavailable else crit    # with a cohesion: the whole wall
        return {
            "multiplier": full.multiplier, "n_triangles": full.n_triangles,
            "facade": full.facade, "mesh_size": full.mesh_size,
            "mesher": full.problem.meta.get("mesher", ""), "hinge": list(full.O),
            "omega": full.measures.fit.omega, "mechanism": full.kind,
            "explained": full.measures.explained, "block_share": full.measures.block_share,
            "tanpsi": full.tanpsi, "tanpsi_uncertainty": full.tanpsi_uncertainty,
            "tanpsi_edges": list(full.tanpsi_edges), "sqrt_cf_a": case.alpha,
            "f": case.masonry.f, "c_over_a": case.masonry.c / case.masonry.a,
            "lower_bound": self.lower_bound, "bracket_rel_gap": self.bracket_rel_gap,
            "static_triangles": None if self.static is None
            else int(self.static.mesh.t.shape[1]),
            "adapt": None if self.adapt is None else self.adapt.as_dict(),
            "crack_change": self.crack_change,
            "vg": None if crit is None else crit.vg,
            "vnorm": None if crit is None else crit.vnorm,
            "lam": None if at is None else at.lam,
            "h": None if at is None else at.h,
            "critical_mechanism": None if at is None else at.kind,
            "critical_multiplier": None if at is None else at.multiplier,
            "vg_method": None if at is None else at.vg_method,
            "critical_at": self.critical_at, "h_min": self.h_min,
            "scan": [m.record() for m in self.scan]} | self._fc_dict() | self._loads_dict() \
            | self._bond_dict()

    def _bond_dict(self) -> dict:
        """With a joint cohesion or tension (issue 30): both, the tension that acts and how
        they enter, and why v̄_g is not available; nothing for the dry wall."""
        m = self.whole.case.masonry
        if not (m.cohesion or m.tension):
            return {}
        return {"cohesion": m.cohesion, "tension": m.tension,
                "tension_effective": min(m.tension, m.cohesion / m.f),
                "bond_rule": "both bounds, the mechanism and its crack: the domains' "
                             "cohesive forms (bed joints |tau| <= C + f p, p the compression; "
                             "eq. 15 with cohesion C), a tension up to T_h = min(T, C/f) (none "
                             "without a cohesion), the facade strip's times rho = l/s "
                             "(fe.strength); v_g not available with a cohesion (no softening "
                             "rule for W(theta))",
                "vg_unavailable": self.vg_unavailable or None}

    def _loads_dict(self) -> dict:
        """With ties or floors (issue 30): the critical mechanism's W(q_m) and its floors'
        and ties' parts, and how they enter it; nothing for the paper's wall."""
        case, crit = self.whole.case, self.critical
        if not (case.ties or case.floors):
            return {}
        gi = None if crit is None else crit.impulse
        return {k: None if gi is None else getattr(gi, k)
                for k in ("W_m", "W_floors", "W_ties")} | {
            "loads_rule": "per bay (value per metre x l), at the FE loads' resultants; on the "
                          "body: floor Q ((x - x_O) sin q + (z - z_O)(cos q - 1)), tie "
                          "tie_work((z_T - z_O) sin q); on the rest to first order; W "
                          "maximised over 0 <= q <= pi/2 (mechanism.fe_impulse)"}

    def _fc_dict(self) -> dict:
        """With a finite fc (issue 30): fc, the cap's rule and the static field's peak
        compression of the masonry (``peak_compression``); nothing for fc = 0."""
        case = self.whole.case
        fc = case.masonry.fc
        if not fc:
            return {}
        from ..fe.static.solution import peak_compression

        return {"fc": fc, "fc_infinite": False,
                "fc_rule": "both bounds: principal compressive stress >= -fc (the facade "
                           "strip's section stresses >= -rho fc, rho = l/s); static: at "
                           "every control point of the stress field",
                "peak_compression": None if self.static is None
                else peak_compression(self.static, case.rho)}


def scan_midpoints(hs, vg, step: float, rtol: float) -> list[float]:
    """The next heights of the scan: the midpoints of the gaps beside the lowest finite v̄_g
    of the heights ``hs`` (sorted) that are still open. A gap is closed when it is at most
    ``step`` wide, or at most 2·``step`` wide with its far end within ``rtol`` of the minimum:
    the end values alone never close a wide gap, since v̄_g may dip inside it."""
    v = [x if math.isfinite(x) else math.inf for x in vg]
    k = int(np.argmin(v))
    tol = 1 + 1e-9
    new = []
    for j in (k - 1, k + 1):
        if not 0 <= j < len(hs):
            continue
        width = abs(hs[j] - hs[k])
        near = math.isfinite(v[k]) and abs(v[j] / v[k] - 1) <= rtol
        if width > step * tol and not (near and width <= 2 * step * tol):
            new.append(0.5 * (hs[j] + hs[k]))
    return new


def fe_result(case: Case, mesh_size: float = 0.25, facade: str = FACADE_DEFAULT, options=None,
              whole: Problem | None = None, static: bool = False, heights: int = 6,
              step: float | None = None, rtol: float = 0.005, map=None,
              divisions: int = PART_DIVISIONS, mesher: str = MESHER_DEFAULT,
              adapted=None, static_problem: Problem | None = None,
              parts: dict | None = None) -> FEResult:
    """The FE impulse scan over a <= h_part <= H (module docstring): ``heights`` starting
    heights, refined around the minimum down to ``step`` [m] (default a), or 2·step where
    the neighbour is within ``rtol`` of the minimum (``scan_midpoints``); with
    ``static``, the whole wall's lower bound on its mesh. ``whole``: the whole wall's problem if
    already built (``t_section(case, facade=facade, h=mesh_size)``). ``map``: how each round
    of heights is evaluated (``h_scan``; the whole wall too when ``whole`` is not given);
    ``divisions``: elements per part height (``part_problem``); ``mesher``: the mesh of the
    whole wall and of every part (``problems.MESHERS``). ``adapted``: the whole wall's
    ``fe.adapt.AdaptResult`` (``mechanism.adaptive.adaptive_bracket``): its last mesh is the
    whole wall's, and both its bounds are reused (no second solve). ``static_problem``: the
    whole wall on the static bound's own mesh (default: ``whole``'s), e.g. with the façade's
    columns graded to the outer face (``t_section(h_outer=)``). ``parts``: {h_part:
    FEMechanism} already analysed (``h_scan``, e.g. of ``first_heights`` while the whole wall
    was refined), not analysed again."""
    check_choice("facade", facade, FACADE_MODELS)
    check_choice("mesher", mesher, MESHERS)
    w, a = case.wall, case.masonry.a
    heights = int(check_range("heights", heights, 2, 200))
    step = a if step is None else check_range("step", step, 0.0, w.H, lo_open=True, unit="m")
    rtol = check_range("rtol", rtol, 0.0, 0.5, lo_open=True)
    if adapted is not None:
        whole = adapted.problem
    if static and whole is None:
        whole = t_section(case, facade=facade, h=mesh_size, mesher=mesher)
    done: dict[float, FEMechanism] = dict(parts or {})

    def run(hs):
        new = sorted(set(hs) - set(done))
        if whole is not None and w.H in new:
            log.info("FE mechanism of the whole wall: %d triangles, P2", whole.n_triangles)
            done[w.H] = analyse(case, whole, options, solution=None if adapted is None
                                else adapted.bracket.kinematic)
            new.remove(w.H)
        done.update(zip(new, h_scan(case, new, mesh_size, facade, options, map, divisions,
                                    mesher)))

    run(first_heights(case, heights) + [w.H])
    # with a cohesion no height has a v̄_g: no minimum to bisect around (module docstring)
    while not done[w.H].vg_unavailable and (new := scan_midpoints(
            sorted(done), [done[h].vg for h in sorted(done)], step, rtol)):
        run(new)
    sta = None if adapted is None else adapted.bracket.static
    if static and sta is None:
        from ..fe.solver import SolverOptions
        from ..fe.static import solve_static

        sp_ = whole if static_problem is None else static_problem
        log.info("static lower bound of the whole wall: %d triangles", sp_.n_triangles)
        sta = solve_static(sp_, options or SolverOptions())
    return FEResult(tuple(done[h] for h in sorted(done)), sta, a, adapted)
