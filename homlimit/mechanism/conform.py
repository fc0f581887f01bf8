"""The kinematic bound on meshes that conform to the mechanism's fan: the crack resolved.

A P2 velocity field carries a hinge + fan exactly when the mesh has edges along the fan's two
rays: the block's rigid rotation and the fan's affine field are polynomials of degree 1 in
each triangle, and the field only kinks across the rays (docs/crack-angle.md). On such a mesh
the kinematic bound of B1's homogenised T-section equals the closed form's 0.152160 to 5e-7
whatever the element size (0.25 to 1 m); on an unaligned mesh the fan is smeared over
elements, λ⁺ stays 0.5–1 % high and its edges are not resolved. Refinement cannot cure this
cheaply: λ is flat in the fan's edges (a sharp crack at the edges' geometric mean costs
+0.05 %, an edge 0.01 off f costs +0.025 %), so reading the edges to 2 % needs a bound
accurate to ~2e-4.

Here the mesh's geometry is an unknown too (r-adaptivity): the hinge height z_h on the
façade's outer face and the slopes T1 < T2 (tan ψ from the vertical) of two rays from it are
chosen by Nelder–Mead (in the rays' centre and width, restarted until it stops moving) to
minimise λ⁺, starting from the hinge and edges read off an unconstrained solution
(``adaptive.hinge_fan``). B1 from edges 0.610 .. 0.626: 30 solves reach edges 0.600 .. 0.667
(λ⁺ +1e-4), 60 solves λ⁺ +7e-6 (docs/adaptive.md). Every trial is a strict upper bound (a
kinematically admissible field on a valid mesh), so the smallest is the tightest; the field is
free on every mesh, and the rays only let it kink where it prefers. Nothing of the closed form
enters: the edges reported are read off the optimal field (``crack.fan_edges``), and they
coincide with the rays only if the field puts its kinks there.
"""

from __future__ import annotations

import dataclasses
import math
import time
from dataclasses import dataclass

import numpy as np
from scipy.optimize import minimize

from ..errors import ParameterError, SolverError, check_range
from ..fe.kinematic import solve_kinematic
from ..fe.problems import t_section, t_section_on_mesh
from ..fe.solver import SolverOptions
from ..params import Case
from .adaptive import HingeFan, hinge_fan
from .fe_impulse import ray_conforming_mesh

__all__ = ["ConformedFan", "conform_fan", "conform_hook"]

ROUND = 20        # solves per Nelder–Mead round before it restarts from the best field


@dataclass(frozen=True)
class ConformedFan:
    """The best ray-conforming kinematic solution (module docstring).

    kinematic: its KinematicSolution (λ⁺ = kinematic.multiplier); problem: the problem on its
    mesh; z_h [m], T1, T2: the
    trial mesh's hinge and ray slopes; fan: the hinge and edges read off its field
    (``HingeFan``; None if the field has no hinge on the outer face); start: where the search
    began; trials: (z_h, T1, T2, λ⁺) of every solved trial in order (λ⁺ NaN: the solver
    failed on that mesh); seconds: wall time of the search; change: the largest change of the
    field's edges (or mid-line) over the search's last improving round (over the first: from
    the start), at least ``xatol``: the crack's resolution, kept in the problem's meta as
    ``crack_resolution`` for ``analysis.analyse``.
    """

    kinematic: object
    problem: object
    z_h: float
    T1: float
    T2: float
    fan: HingeFan | None
    start: HingeFan
    trials: tuple[tuple[float, float, float, float], ...]
    seconds: float
    change: float = math.nan

    @property
    def lam(self) -> float:
        return float(self.kinematic.multiplier)

    def as_dict(self) -> dict:
        f = self.fan
        return {"lam": self.lam, "z_h": self.z_h, "T1_rays": self.T1, "T2_rays": self.T2,
                "hinge_z": None if f is None else f.z,
                "T1": None if f is None else f.T1, "T2": None if f is None else f.T2,
                "T_mid": None if f is None else f.T_mid,
                "start": dataclasses.asdict(self.start), "trials": len(self.trials),
                "seconds": self.seconds, "change": self.change}


def conform_fan(case: Case, start: HingeFan, *, facade: str = "homogenised", size: float = 0.5,
                spread: float = 0.03, xatol: float = 1e-3, max_trials: int = 60,
                options: SolverOptions = SolverOptions()) -> ConformedFan:
    """Minimise λ⁺ over ray-conforming meshes (module docstring) from ``start`` (a hinge on
    the outer face; its edges, or its mid-line ± ``spread`` where the edges were not read).

    size [m]: element size away from the rays (λ⁺ on conforming meshes barely depends on it);
    xatol: Nelder–Mead's tolerance on z_h [m] and the slopes; max_trials: its budget of
    kinematic solves. A trial whose solve fails is skipped (λ⁺ = +inf to the search) and
    listed in ``trials`` with NaN; if every trial fails, SolverError.
    """
    w = case.wall
    size = check_range("size", size, 0.0, w.H, lo_open=True, unit="m")
    spread = check_range("spread", spread, 0.0, 1.0, lo_open=True)
    xatol = check_range("xatol", xatol, 0.0, 1.0, lo_open=True)
    max_trials = int(check_range("max_trials", max_trials, 4, 10_000))
    z_lo, z_hi = 0.0, w.H - size        # a hinge may sit at the toe (cf/a >= 1.2)
    check_range("start.z", start.z, 0.0, w.H, unit="m")

    def simplex_start(hf: HingeFan) -> np.ndarray:
        """(z_h, centre, width) of the rays from a hinge and its edges (or mid-line)."""
        if hf.T1 is not None and hf.T2 is not None and hf.T2 - hf.T1 > spread / 2:
            T1, T2 = hf.T1, hf.T2
        else:
            mid = hf.T_mid if hf.T_mid is not None else (hf.T1 or hf.T2)
            if mid is None or not math.isfinite(mid) or mid <= 0:
                raise ParameterError(f"start = {hf!r} is out of range: the hinge has no edge "
                                     f"or mid-line slope (> 0) to start the fan's search from")
            T1, T2 = mid - spread, mid + spread
        return np.array([min(max(hf.z, z_lo), z_hi), (T1 + T2) / 2, T2 - T1])

    x = simplex_start(start)
    fans = [start]                           # the best field's hinge and edges, per round
    read = {}                                # id(solution) → its hinge_fan, read once

    def fan_of(k):
        if id(k) not in read:
            read[id(k)] = (k, hinge_fan(case, k))    # k kept: its id stays its own
        return read[id(k)][1]

    problem0 = t_section(case, facade=facade, h=size)
    trials, best = [], {}
    t0 = time.perf_counter()

    def lam(p):
        z_h, mid, width = (float(v) for v in p)
        T1, T2 = mid - abs(width) / 2, mid + abs(width) / 2
        slopes = [T1] if T2 - T1 < 1e-6 else [T1, T2]
        mesh = ray_conforming_mesh(case, z_h, slopes, h=size)
        prob = t_section_on_mesh(problem0, case, mesh)     # ties and floors placed anew
        try:
            k = solve_kinematic(prob, options)
        except SolverError:
            trials.append((z_h, T1, T2, math.nan))
            return math.inf
        trials.append((z_h, T1, T2, float(k.multiplier)))
        if not best or k.multiplier < best["k"].multiplier:
            best.update(k=k, prob=prob, p=(z_h, T1, T2))
        return float(k.multiplier)

    # the rays' centre and width: the search's valley (λ⁺ is flat along a family of fans
    # of one centre) runs along an axis, where Nelder–Mead's simplex need not turn. Rays far
    # from where the field wants to kink are ignored by it (λ⁺ flat in them): each round
    # restarts from the hinge and edges of the best field so far, until a round gains nothing
    while len(trials) < max_trials:
        n0, lam0 = len(trials), best["k"].multiplier if best else math.inf
        simplex = np.array([x, x + [size / 2, 0, 0], x + [0, spread / 2, 0],
                            x + [0, 0, spread]])
        minimize(lam, x, method="Nelder-Mead",
                 bounds=[(z_lo, z_hi), (0.05, 5.0), (0.0, 5.0)],
                 options=dict(initial_simplex=simplex, xatol=xatol, fatol=1e-9,
                              maxfev=min(max_trials - n0, ROUND)))
        if not best or best["k"].multiplier >= lam0 * (1 - 1e-7):
            break
        hf = fan_of(best["k"])
        fans.append(hf)
        try:
            nxt = simplex_start(hf) if hf is not None else None
        except ParameterError:
            nxt = None
        if nxt is None:
            z_h, T1, T2 = best["p"]
            nxt = np.array([z_h, (T1 + T2) / 2, T2 - T1])
        if np.all(np.abs(nxt - x) <= xatol):
            break
        x = nxt
    if not best:
        raise SolverError(f"every one of the {len(trials)} ray-conforming meshes failed to solve")
    k = best["k"]
    z_h, T1, T2 = best["p"]
    fan = fan_of(k)
    change = max(xatol, _change(fans[-2] if len(fans) > 1 else start, fan))
    prob = dataclasses.replace(best["prob"], meta={**best["prob"].meta,
                                                   "crack_resolution": change})
    return ConformedFan(k, prob, z_h, T1, T2, fan, start, tuple(trials),
                        time.perf_counter() - t0, change)


def _change(a: HingeFan | None, b: HingeFan | None) -> float:
    """The largest change of the edges (or, where one has none, the mid-lines) from a to b."""
    if a is None or b is None:
        return math.inf
    pairs = [(a.T1, b.T1), (a.T2, b.T2)] if None not in (a.T1, a.T2, b.T1, b.T2) else \
        [(a.T_mid if a.T_mid is not None else a.T1, b.T_mid)]
    d = [abs(u - v) for u, v in pairs if u is not None and v is not None]
    return max(d) if d else math.inf


def conform_hook(case: Case, facade: str = "homogenised",
                 options: SolverOptions = SolverOptions(), found: list | None = None):
    """``fe.adapt.adapt``'s ``improve_upper``: the search (``conform_fan``) from the first
    cycle's mechanism that has a hinge on the façade's outer face, once (the conforming meshes
    do not depend on the cycle's mesh, only on where the search starts); its ``ConformedFan``
    is appended to ``found`` (if given)."""
    found = [] if found is None else found

    def improve(br, problem):
        start = None if found else hinge_fan(case, br.kinematic)
        if start is None:
            return None
        c = conform_fan(case, start, facade=facade, options=options)
        found.append(c)
        return c.kinematic, c.problem
    return improve
