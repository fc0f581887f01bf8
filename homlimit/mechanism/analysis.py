"""The finite-element path of one wall, from a T-section problem to typed results.

``analyse`` solves one kinematic problem and measures what the mechanism is: the rigid fit
(``rigidfit``), the crack's mid-line and fan edges (``crack``), its kind, the failing body and
the collapse ground velocity (``fe_impulse``, eqs 4–7). ``h_scan`` repeats it over collapse
heights (the part above z0 = H − h, base fixed at z0); ``fe_result`` adds the whole wall and,
optionally, its static lower bound on the same mesh. The critical FE mechanism is the scan's
lowest v̄_g (eq. 7 minimised over λ = h/b).
"""

from __future__ import annotations

import dataclasses
import functools
import logging
import math
from dataclasses import dataclass

import numpy as np

from ..errors import ParameterError, check_choice, check_range
from ..fe.problems import Problem, t_section
from ..impulse import RigidBody, collapse_velocity
from ..params import FACADE_MODELS, Case
from .crack import FanEdges, fan_edges, mechanism_type
from .fe_impulse import GeneralisedImpulse, fe_body, generalised_impulse, p2_nodes
from .rigidfit import MechanismMeasures, measure_mechanism

__all__ = ["FEMechanism", "FEResult", "LAM_MIN", "analyse", "densities", "fe_result",
           "h_scan", "part_problem", "scan_lams"]

log = logging.getLogger(__name__)

LAM_MIN = 2.0  # the smallest slenderness λ = h/b of the FE impulse scan (a part of height 2b)


def scan_lams(case: Case, heights: int) -> np.ndarray:
    """Slenderness values of the FE impulse scan: ``heights`` values spaced geometrically from
    λ = LAM_MIN to H/b (one value: the whole wall)."""
    lam_max = case.wall.lam_max
    if heights <= 1:
        return np.array([lam_max])
    return np.geomspace(min(LAM_MIN, lam_max), lam_max, int(heights))


def densities(case: Case) -> dict[str, float]:
    """Mass per unit area of each T-section region in the section plane, times the
    transversal wall's thickness s [kg/m²]: façade ρ·γ·s (the paper's 2D reduction), wall γ·s."""
    w = case.wall
    return {"facade": case.rho * w.gamma * w.s, "wall": w.gamma * w.s}


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
    def label(self) -> str:
        return f"FE body, {self.kind} (eq. 7)"

    def record(self) -> dict:
        """The flat record of one analysed height (fe_scan.csv)."""
        return {"h_part": self.h_part, "h": self.h, "lam": self.lam, "vg": self.vg,
                "vnorm": self.vnorm, "multiplier": self.multiplier, "mechanism": self.kind,
                "tanpsi": self.tanpsi, "vg_method": self.vg_method}

    def as_dict(self) -> dict:
        """The mechanism's row of summary.json (as the closed forms' ``as_dict``)."""
        return {"name": self.name, **self.record()}

    def drawing(self) -> dict:
        """What ``plots.plot_mechanism`` draws: points, triangles and velocity at the mesh
        vertices, the hinge, the 50 % line ``crack`` and the 10 % and 90 % ``crack_edges``."""
        sol = self.solution
        lines = self.edges.lines if self.edges is not None else {}
        return {"points": sol.mesh.p.T.copy(), "triangles": sol.mesh.t.T.copy(),
                "velocity": sol.velocity, "hinge": self.O,
                "crack": lines[0.5].polyline if 0.5 in lines else None,
                "crack_edges": [lines[lv].polyline for lv in (0.1, 0.9) if lv in lines]}


def part_problem(case: Case, h_part: float, facade: str, mesh_size: float) -> Problem:
    """The T-section of the top part of height ``h_part`` (``problems.t_section`` with its base
    at z0 = H − h_part), element size min(mesh_size, h_part/10) so that short parts stay
    resolved."""
    prob = t_section(case, z0=max(0.0, case.wall.H - h_part), facade=facade,
                     h=min(mesh_size, h_part / 10))
    return dataclasses.replace(prob, meta={**prob.meta, "h_part": h_part})


def analyse(case: Case, problem: Problem, options=None) -> FEMechanism:
    """Solve ``problem`` (a ``t_section`` of ``case``, base fixed at its z0) and measure its
    mechanism: rigid fit, crack, kind, body and v̄_g.

    A sharp crack (``kind == "rigid"``) gets eq. 7 + eq. 18 of the body inside its 50 % line
    (the limit of the one-DOF value as the smeared band thins); a fan or a distributed
    mechanism the one-DOF generalisation of eqs 4–7, fan included (``fe_impulse``).
    """
    from ..fe.kinematic import solve_kinematic
    from ..fe.solver import SolverOptions

    w = case.wall
    sol = solve_kinematic(problem, options or SolverOptions())
    X, V, el, rho = p2_nodes(sol, densities(case))
    mm = measure_mechanism(X, V, el, rho)
    edges = fan_edges(X, el, mm, w.b, z_top=w.H) if mm.kind != "distributed" else None
    kind = mechanism_type(mm, edges)
    meta = problem.meta
    common = dict(case=case, problem=problem, solution=sol, measures=mm, edges=edges,
                  kind=kind, facade=meta.get("facade", ""), z0=float(meta.get("z0", 0.0)),
                  mesh_size=float(meta.get("h", math.nan)))
    try:
        gi = generalised_impulse(X, V, el, rho, mm, g=w.g)
        body = fe_body(X, el, rho, mm)
    except ParameterError as exc:
        return FEMechanism(**common, body=None, impulse=None, vg=math.nan,
                           vg_method=f"not available: {exc}")
    if kind == "rigid":
        vg, how = (collapse_velocity(body, g=w.g),
                   "eq. 7 + eq. 18, body inside the 50 % participation line")
    else:
        vg, how = gi.vg, ("one-DOF generalisation of eqs 4-7 (fe_impulse docstring): body "
                          "inside the 50 % line at finite rotation, the rest linearised")
    return FEMechanism(**common, body=body, impulse=gi, vg=vg, vg_method=how)


def _analyse_height(case: Case, mesh_size: float, facade: str, options, lam: float
                    ) -> FEMechanism:
    """One height of ``h_scan``: ``analyse`` on the part above z0 = H − λ b."""
    hp = lam * case.wall.b
    log.info("FE analysis: part of height %.2f m (lam = %.3g)", hp, lam)
    return analyse(case, part_problem(case, hp, facade, mesh_size), options)


def h_scan(case: Case, lams, mesh_size: float = 0.25, facade: str = "homogenised",
           options=None, map=map) -> list[FEMechanism]:
    """``analyse`` on the part above z0 = H − λ b for every λ in ``lams``. The hinge may float
    above the base of the analysed part: each mechanism's own h = H − z_O.

    ``map(fn, lams)``: how the heights are evaluated, results in order (default: one after
    another here; ``app.engine.Engine.map`` makes each height a Dask task)."""
    w = case.wall
    lams = [check_range("lam", lam, 0.0, w.lam_max, lo_open=True) for lam in lams]
    log.info("FE scan: %d collapse heights", len(lams))
    return list(map(functools.partial(_analyse_height, case, mesh_size, facade, options), lams))


@dataclass(frozen=True)
class FEResult:
    """The FE path of one wall: the impulse scan over collapse heights (the whole wall last)
    and the whole wall's static lower bound on the same mesh (None if not run)."""

    scan: tuple[FEMechanism, ...]
    static: object = None

    @property
    def whole(self) -> FEMechanism:
        return self.scan[-1]

    @property
    def critical(self) -> FEMechanism | None:
        """The scan's lowest finite v̄_g (None if no height gave one)."""
        ok = [m for m in self.scan if np.isfinite(m.vg)]
        return min(ok, key=lambda m: m.vg) if ok else None

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
        return {
            "multiplier": full.multiplier, "n_triangles": full.n_triangles,
            "facade": full.facade, "mesh_size": full.mesh_size, "hinge": list(full.O),
            "omega": full.measures.fit.omega, "mechanism": full.kind,
            "explained": full.measures.explained, "block_share": full.measures.block_share,
            "tanpsi": full.tanpsi, "tanpsi_uncertainty": full.tanpsi_uncertainty,
            "tanpsi_edges": list(full.tanpsi_edges), "sqrt_cf_a": case.alpha,
            "f": case.masonry.f, "c_over_a": case.masonry.c / case.masonry.a,
            "lower_bound": self.lower_bound, "bracket_rel_gap": self.bracket_rel_gap,
            "vg": None if crit is None else crit.vg,
            "vnorm": None if crit is None else crit.vnorm,
            "lam": None if crit is None else crit.lam,
            "h": None if crit is None else crit.h,
            "critical_mechanism": None if crit is None else crit.kind,
            "critical_multiplier": None if crit is None else crit.multiplier,
            "vg_method": None if crit is None else crit.vg_method,
            "scan": [m.record() for m in self.scan]}


def fe_result(case: Case, lams, mesh_size: float = 0.25, facade: str = "homogenised",
              options=None, whole: Problem | None = None, static: bool = False,
              map=map) -> FEResult:
    """The scan over ``lams`` (the last value must be H/b: the whole wall) and, with
    ``static``, the whole wall's lower bound on the same mesh. ``whole``: the whole wall's
    problem if already built (``t_section(case, facade=facade, h=mesh_size)``); ``map``: the
    scan's heights (``h_scan``)."""
    check_choice("facade", facade, FACADE_MODELS)
    lams = np.asarray(lams, float)
    if not lams.size or not math.isclose(lams[-1], case.wall.lam_max, rel_tol=1e-12):
        raise ParameterError(f"lams = {lams.tolist()!r} is out of range: the last value must "
                             f"be H/b = {case.wall.lam_max:g} (the whole wall)")
    scan = h_scan(case, lams[:-1], mesh_size, facade, options, map=map)
    whole = whole or t_section(case, facade=facade, h=mesh_size)
    log.info("FE mechanism of the whole wall: %d triangles, P2", whole.n_triangles)
    scan.append(analyse(case, whole, options))
    sta = None
    if static:
        from ..fe.solver import SolverOptions
        from ..fe.static import solve_static

        log.info("static lower bound of the whole wall: %d triangles", whole.n_triangles)
        sta = solve_static(whole, options or SolverOptions())
    return FEResult(tuple(scan), sta)

