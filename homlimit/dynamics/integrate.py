"""Time history of a rocker under a ground pulse: ``scipy.integrate.solve_ivp`` between events.

The motion of eq. 1 (``rocking`` module docstring) is a sequence of phases:
- **at rest** on the seat (φ = 0) or stuck by friction (φ̇ = 0, |Π a_g − R| <= F): the next
  time the ground moves the body is found on the pulse's samples and refined by brentq;
- **moving** one way (φ̇ of one sign, so the friction term is smooth): integrated by
  ``solve_ivp`` with terminal events
  - *turning*: φ̇ = 0 (the body stops; it sticks or moves back),
  - *impact*: φ = 0 with φ̇ < 0 (seat or pivot change; φ̇⁺ = −e φ̇⁻ in the local
    coordinate; below ``rest_velocity`` the body stays seated),
  - *fall*: φ = π/2 (the body lies on the ground: overturned),
  - *top*: φ = θ_m (after the pulse, to decide again).

State y = (φ, φ̇, W_ground, W_friction): the last two accumulate the work of the ground's
inertia load ∫Π a_g φ̇ dt and the friction work ∫F|φ̇| dt, so the energy balance
½Iφ̇² + V(φ) = E₀ + W_ground − W_friction − E_impact (V = W − friction work) can be checked.

**After the pulse** nothing feeds energy in, so Φ = ½Iφ̇² + W(φ) can only decrease
(``Rocker.energy``): the body overturns when it moves outward below θ_m with Φ >= W_m, or is
past θ_m moving outward; it is safe once Φ < W_m. The decision is taken as soon as it is
certain, so the time to creep over the unstable equilibrium near the threshold never has to be
integrated. ``Response.margin`` = (Φ − W_m)/W_m at the decision (> 0: overturned) is
continuous in the pulse amplitude wherever the decision is by energy, which lets brentq
converge fast on the threshold.

Default tolerances: DOP853, rtol = 1e-10, atol = 1e-12 × (θ_m, p θ_m, W_m, W_m).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

from ..errors import ParameterError, SolverError, check_range
from .pulses import Pulse
from .rocking import Rocker

__all__ = ["IntegrationOptions", "Impact", "Response", "simulate"]

_METHODS = ("DOP853", "RK45", "Radau", "LSODA", "BDF")
_TINY = 1e-300


@dataclass(frozen=True)
class IntegrationOptions:
    """Tolerances and limits of one time history.

    method: a ``solve_ivp`` method; rtol: relative tolerance; atol: absolute tolerance as a
    fraction of the state scales (θ_m [rad], p θ_m [rad/s], W_m [J], W_m [J]);
    max_rhs: right-hand-side evaluations allowed per history (the step budget);
    max_phases: phases (between turning points, impacts, stick/slip) allowed per history;
    rest_velocity: an impact leaving |φ̇| < rest_velocity · p θ_m leaves the body at rest;
    scan_points: samples of the pulse to find when a body at rest starts moving;
    horizon: free motion integrated after the pulse before giving up, in units of 1/p.
    """

    method: str = "DOP853"
    rtol: float = 1e-10
    atol: float = 1e-12
    max_rhs: int = 400_000
    max_phases: int = 5_000
    rest_velocity: float = 1e-9
    scan_points: int = 4000
    horizon: float = 200.0

    def __post_init__(self):
        if self.method not in _METHODS:
            raise ParameterError(f"method = {self.method!r} is out of range: allowed "
                                 f"{', '.join(_METHODS)}")
        check_range("rtol", self.rtol, 1e-14, 1e-2)
        check_range("atol", self.atol, 1e-16, 1e-2)
        check_range("max_rhs", self.max_rhs, 100)
        check_range("max_phases", self.max_phases, 1)
        check_range("rest_velocity", self.rest_velocity, 0.0, 1e-2)
        check_range("scan_points", self.scan_points, 10)
        check_range("horizon", self.horizon, 1.0)


@dataclass(frozen=True)
class Impact:
    """One impact at φ = 0: time [s], angular velocities before/after [rad/s] (global sign),
    kinetic energies before/after [J]."""

    t: float
    theta_dot_before: float
    theta_dot_after: float
    K_before: float
    K_after: float


@dataclass(frozen=True)
class Response:
    """Outcome of one time history (SI units; rotations global: θ > 0 outwards).

    overturned, reason: the outcome and why; margin: (Φ − W_m)/W_m at the decision (> 0
    overturned; +1 for a fall during the pulse; −1 if the body never moved);
    t_decision [s]; uplifted, t_uplift [s]; theta_max [rad] (largest |θ|); impacts;
    W_ground, W_friction, E_impact [J] (work of the ground, friction work, energy lost in
    impacts), E0, E_final [J] (½Iθ̇² + V at the start and at the decision);
    history: dict of arrays t, theta, theta_dot (global), phi, phi_dot (local), side and
    phase (index of the phase each point belongs to), moving (False while at rest), or None;
    n_rhs: right-hand-side evaluations; options: the tolerances used.
    """

    overturned: bool
    reason: str
    margin: float
    t_decision: float
    uplifted: bool
    t_uplift: float
    theta_max: float
    impacts: tuple[Impact, ...]
    W_ground: float
    W_friction: float
    E_impact: float
    E0: float
    E_final: float
    n_rhs: int
    options: IntegrationOptions
    history: dict | None = field(default=None, repr=False)

    @property
    def n_impacts(self) -> int:
        return len(self.impacts)

    @property
    def energy_residual(self) -> float:
        """E_final − (E0 + W_ground − W_friction − E_impact) [J]: zero up to the tolerances."""
        return self.E_final - (self.E0 + self.W_ground - self.W_friction - self.E_impact)


class _Budget:
    def __init__(self, limit):
        self.n, self.limit = 0, limit

    def tick(self):
        self.n += 1
        if self.n > self.limit:
            raise SolverError(f"the time history needed more than max_rhs = {self.limit} "
                              "right-hand-side evaluations (stiff or chattering motion)",
                              status="max_rhs")


def _event(fun, direction, name):
    fun.terminal, fun.direction, fun.name = True, direction, name
    return fun


def _potential(rocker: Rocker, phi):
    """V(φ) = W(φ) − friction work: gravity (and, for a shape, the rest's lift)."""
    fw = getattr(rocker, "friction_work", None)
    return float(rocker.work(phi)) - (float(fw(phi)) if fw is not None else 0.0)


def _first_time(g, t0, t1, n, tol, knots=None):
    """First t in [t0, t1] where g(t) > 0 (g vectorised), or None. Sampled on n points (and on
    the pulse's own sample times ``knots``, if any), then refined by brentq; the returned time
    has g > 0."""
    grid = np.linspace(t0, t1, n)
    if knots is not None:
        grid = np.union1d(grid, knots[(knots > t0) & (knots < t1)])
    val = g(grid)
    hit = np.flatnonzero(val > 0)
    if hit.size == 0:
        return None
    k = int(hit[0])
    if k == 0:
        return t0
    lo, hi = grid[k - 1], grid[k]
    try:
        root = brentq(lambda t: float(g(np.array([t]))[0]), lo, hi, xtol=tol, rtol=1e-15)
    except ValueError:  # a jump rather than a crossing
        return hi
    for t in (root, root + tol, root + 10 * tol):
        if t <= hi and float(g(np.array([t]))[0]) > 0:
            return t
    return hi


def simulate(rocker: Rocker, pulse: Pulse | None = None, *, theta0: float = 0.0,
             theta_dot0: float = 0.0, options: IntegrationOptions | None = None,
             record: bool = False, max_impacts: int | None = None,
             duration: float | None = None) -> Response:
    """Integrate eq. 1 for ``rocker`` under ``pulse`` (None: free motion) from θ(0) = theta0
    [rad], θ̇(0) = theta_dot0 [rad/s] (default at rest on the seat) until the outcome is
    certain (module docstring). max_impacts: stop as "safe (impact limit)" at the impact after
    that many (0: count only overturning without impact). duration [s]: integrate the whole
    time history up to t = duration instead (for plots and energy checks; the outcome is then
    decided at that time). Raises SolverError when the motion cannot be integrated (solver
    failure, step budget, missed event, no decision)."""
    if not isinstance(rocker, Rocker):
        raise ParameterError(f"rocker = {rocker!r} is not a homlimit.dynamics Rocker")
    if pulse is not None and not isinstance(pulse, Pulse):
        raise ParameterError(f"pulse = {pulse!r} is not a homlimit.dynamics Pulse")
    opt = options or IntegrationOptions()
    theta0 = check_range("theta0", theta0, -rocker.theta_fall, rocker.theta_fall, unit="rad")
    theta_dot0 = check_range("theta_dot0", theta_dot0, unit="rad/s")
    if max_impacts is not None:
        max_impacts = int(check_range("max_impacts", max_impacts, 0))
    if not rocker.two_sided and (theta0 < 0 or (theta0 == 0 and theta_dot0 < 0)):
        raise ParameterError(f"theta0 = {theta0!r} rad, theta_dot0 = {theta_dot0!r} rad/s are "
                             "out of range: an attached mechanism rocks outwards only, allowed "
                             "theta0 > 0, or theta0 = 0 and theta_dot0 >= 0")
    if duration is not None:
        duration = check_range("duration", duration, 0.0, lo_open=True, unit="s")
    return _History(rocker, pulse, opt, record, max_impacts, duration).run(theta0, theta_dot0)


class _History:
    """The phase loop of ``simulate`` (one object per time history)."""

    def __init__(self, rocker, pulse, opt, record, max_impacts, t_stop=None):
        self.r, self.pulse, self.opt, self.t_stop = rocker, pulse, opt, t_stop
        self.record, self.max_impacts = record, max_impacts
        self.t_end = pulse.t_end if pulse is not None else 0.0
        self.I = rocker.inertia
        self.theta_m, self.W_m = rocker.theta_m, rocker.W_m
        self.p = rocker.p
        self.scale = np.array([self.theta_m, self.p * self.theta_m, self.W_m, self.W_m])
        self.atol = opt.atol * self.scale
        self.budget = _Budget(opt.max_rhs)
        self.impacts = []
        self.hist = ({k: [] for k in ("t", "phi", "phi_dot", "side", "phase", "moving")} if record
                     else None)
        self.theta_max = 0.0
        self.t_uplift = math.nan

    # -- helpers
    def a_g(self, t):
        """Ground acceleration (arrays), zero after the pulse."""
        if self.pulse is None:
            return np.zeros_like(np.asarray(t, dtype=float))
        return self.pulse.a(t)

    def _log(self, t, phi, phid, side, moving=False):
        if self.hist is not None:
            t = np.atleast_1d(np.asarray(t, dtype=float))
            self.hist["t"].append(t)
            self.hist["phi"].append(np.broadcast_to(phi, t.shape).astype(float))
            self.hist["phi_dot"].append(np.broadcast_to(phid, t.shape).astype(float))
            self.hist["side"].append(np.full(t.shape, side))
            self.hist["phase"].append(np.full(t.shape, len(self.hist["phase"])))
            self.hist["moving"].append(np.full(t.shape, moving))

    def _respond(self, overturned, reason, margin, t, phi, phid, y_work):
        hist = None
        if self.hist is not None:
            hist = {k: np.concatenate(v) if v else np.zeros(0) for k, v in self.hist.items()}
            hist["theta"] = hist["side"] * hist["phi"]
            hist["theta_dot"] = hist["side"] * hist["phi_dot"]
        E_final = 0.5 * self.I * phid ** 2 + _potential(self.r, phi)
        return Response(bool(overturned), reason, float(margin), float(t),
                        not math.isnan(self.t_uplift), self.t_uplift, self.theta_max,
                        tuple(self.impacts), y_work[0], y_work[1], y_work[2], self.E0, E_final,
                        self.budget.n, self.opt, hist)

    def _segment(self, t0, t1, phi, phid, side, s, post):
        """Integrate one phase moving in direction s (±1) from t0 towards t1."""
        r, I_ = self.r, self.I
        pulse_on = not post and self.pulse is not None
        a_at = self.pulse.at if pulse_on else None
        terms = r.terms
        budget = self.budget

        def rhs(t, y):
            budget.tick()
            ph, phd = y[0], y[1]
            ag = side * a_at(t) if pulse_on else 0.0
            Pi, R, F = terms(ph)
            return [phd, (Pi * ag - R - s * F) / I_, Pi * ag * phd, s * F * phd]

        # a phase may start on its own event surface (φ̇ = 0 or φ = 0); there the event
        # functions take the sign of the motion that follows, so that a step spanning a whole
        # excursion finds the event inside it rather than at its start
        events = [_event(lambda t, y: y[1] if t > t0 else s * _TINY, -s, "turning"),
                  _event(lambda t, y: y[0] if t > t0 else _TINY, -1, "impact"),
                  _event(lambda t, y: y[0] - r.theta_fall, 1, "fall")]
        if post and self.t_stop is None and abs(phi - self.theta_m) > 1e-12 * self.theta_m:
            events.append(_event(lambda t, y: y[0] - self.theta_m, 0, "top"))
        # steps short enough to see every lobe of the pulse and every excursion
        max_step = 0.1 / self.p
        if pulse_on:
            max_step = min(max_step, self.pulse.step_hint)
        sol = solve_ivp(rhs, (t0, t1), [phi, phid, 0.0, 0.0], method=self.opt.method,
                        rtol=self.opt.rtol, atol=self.atol, events=events,
                        max_step=max_step)
        if sol.status == -1:
            raise SolverError(f"solve_ivp ({self.opt.method}) failed at t = {sol.t[-1]:.6g} s: "
                              f"{sol.message}", status="solve_ivp")
        self.theta_max = max(self.theta_max, float(np.max(sol.y[0])))
        self._log(sol.t, sol.y[0], sol.y[1], side, True)
        hit = None
        for name in ("fall", "impact", "turning", "top"):
            for ev, te, ye in zip(events, sol.t_events, sol.y_events):
                if ev.name == name and te.size:
                    hit = (name, float(te[0]), ye[0])
                    break
            if hit:
                break
        if hit is None:
            y_end = sol.y[:, -1]
            # an event passed between steps unnoticed would leave the state inconsistent
            if y_end[0] < -1e-8 * self.theta_m or s * y_end[1] < -1e-8 * self.p * self.theta_m:
                raise SolverError(f"event missed between t = {t0:.6g} and {sol.t[-1]:.6g} s "
                                  f"(phi = {y_end[0]:.3g} rad, phi_dot = {y_end[1]:.3g} rad/s)",
                                  status="event missed")
            return "end", float(sol.t[-1]), y_end
        return hit

    def _start_from_rest(self, t, phi, side, rest_seated):
        """Next time in [t, t_end] the ground moves the body at rest; (t, side, s) or None."""
        r = self.r
        tol = 1e-13 * max(self.t_end, 1e-9)
        if rest_seated:
            Pi0 = float(r.excitation(0.0))
            hold = float(r.restoring(0.0) + r.friction(0.0))
            if r.two_sided:
                def g(tt):
                    return np.abs(self.a_g(tt)) * Pi0 - hold
            else:
                def g(tt):
                    return self.a_g(tt) * Pi0 - hold
        else:
            Pi, R, F = (float(f(phi)) for f in (r.excitation, r.restoring, r.friction))

            def g(tt):
                return np.abs(side * self.a_g(tt) * Pi - R) - F
        t_s = _first_time(g, t, self.t_end, self.opt.scan_points, tol,
                          getattr(self.pulse, "t", None))
        if t_s is None:
            return None
        ag = float(self.a_g(t_s))
        if rest_seated:
            new_side = 1 if (ag > 0 or not r.two_sided) else -1
            return t_s, new_side, 1
        N = side * ag * float(r.excitation(phi)) - float(r.restoring(phi))
        return t_s, side, (1 if N > 0 else -1)

    def _at_time_limit(self, t, phi, phid, work):
        """The outcome when the history is cut at ``duration``: by the energy rule if the pulse
        is over and the rule is certain, else not overturned ("undecided")."""
        r = self.r
        m = (float(r.energy(phi, phid)) - self.W_m) / self.W_m
        if t >= self.t_end:
            if phi < self.theta_m and m < 0:
                return self._respond(False, "time limit: energy below W_m", m, t, phi, phid,
                                     work)
            if phid >= 0 and (phi >= self.theta_m or m >= 0):
                return self._respond(True, "time limit: overturning", max(m, 0.0) + 1e-12, t,
                                     phi, phid, work)
        return self._respond(False, "time limit: undecided", m, t, phi, phid, work)

    # -- the phase loop
    def run(self, theta0, theta_dot0):
        r, opt = self.r, self.opt
        side = -1 if (theta0 < 0 or (theta0 == 0 and theta_dot0 < 0)) else 1
        phi, phid = abs(theta0), side * theta_dot0
        self.E0 = 0.5 * self.I * phid ** 2 + _potential(r, phi)
        moving = phi > 0 or phid != 0
        if moving:
            self.t_uplift = 0.0
        work = np.zeros(3)  # W_ground, W_friction, E_impact
        t, s, n_stall = 0.0, 1, 0
        seated = not moving and phi == 0
        for _ in range(opt.max_phases):
            post = t >= self.t_end
            if self.t_stop is not None and t >= self.t_stop:
                return self._at_time_limit(t, phi, phid if moving else 0.0, work)
            if not moving:
                if post:
                    if seated or abs(float(r.restoring(phi))) <= float(r.friction(phi)):
                        Phi = float(r.work(phi))
                        margin = (-1.0 if math.isnan(self.t_uplift)
                                  else (Phi - self.W_m) / self.W_m)
                        why = ("never moved" if math.isnan(self.t_uplift) else
                               "at rest on the seat after the pulse" if seated else
                               "stuck by friction after the pulse")
                        return self._respond(False, why, margin, t, phi, 0.0, work)
                    moving, s = True, (1 if float(r.restoring(phi)) < 0 else -1)
                    phid = 0.0
                else:
                    start = self._start_from_rest(t, phi, side, seated)
                    if start is None:
                        self._log(np.array([t, self.t_end]), phi, 0.0, side)
                        t = self.t_end
                        continue
                    t_s, side, s = start
                    self._log(np.array([t, t_s]), phi, 0.0, side)
                    t, moving, seated, phid = t_s, True, False, 0.0
                    if math.isnan(self.t_uplift):
                        self.t_uplift = t
                    continue
            # moving
            if post and self.t_stop is None:
                Phi = float(r.energy(phi, phid))
                m = (Phi - self.W_m) / self.W_m
                if phi < self.theta_m:
                    if m < 0:
                        return self._respond(False, "energy below W_m after the pulse", m, t,
                                             phi, phid, work)
                    if phid >= 0:
                        return self._respond(True, "energy above W_m after the pulse, moving "
                                             "outwards", m, t, phi, phid, work)
                elif phid >= 0:
                    return self._respond(True, "past theta_m moving outwards after the pulse",
                                         max(m, 0.0) + 1e-12, t, phi, phid, work)
            if phid != 0:
                s = 1 if phid > 0 else -1
            if not post:
                t1 = self.t_end if self.t_stop is None else min(self.t_end, self.t_stop)
            else:
                t1 = t + opt.horizon / self.p if self.t_stop is None else self.t_stop
            t_prev = t
            name, t_ev, y = self._segment(t, t1, phi, phid, side, s, post)
            work[:2] += y[2:4]
            t, phi, phid = t_ev, max(float(y[0]), 0.0), float(y[1])
            if name == "end":
                if self.t_stop is not None and t >= self.t_stop:
                    return self._at_time_limit(t, phi, phid, work)
                if post:
                    raise SolverError(f"no decision within {opt.horizon:g}/p = "
                                      f"{opt.horizon / self.p:.4g} s of free motion after the "
                                      "pulse", status="no decision")
                continue
            if name == "fall":
                return self._respond(True, "fell (rotation reached 90 degrees)", 1.0, t,
                                     r.theta_fall, phid, work)
            if name == "impact":
                phi = 0.0
                K_b = 0.5 * self.I * phid ** 2
                phid_new = -r.restitution * phid
                new_side = -side if r.two_sided else side
                if phid_new < opt.rest_velocity * self.p * self.theta_m:
                    phid_new = 0.0
                K_a = 0.5 * self.I * phid_new ** 2
                self.impacts.append(Impact(t, side * phid, new_side * phid_new, K_b, K_a))
                work[2] += K_b - K_a
                side, phid = new_side, phid_new
                if self.max_impacts is not None and len(self.impacts) > self.max_impacts:
                    return self._respond(False, "impact limit", -1.0, t, phi, phid, work)
                if phid == 0.0:
                    moving, seated = False, True
                continue
            if name == "turning":
                # a turning point reached with no progress: the net moment vanished with the
                # velocity (grazing); leave it the other way
                stalled = t_ev - t_prev <= 1e-13 * max(t_ev, 1.0)
                phid = 0.0
                ag = side * float(self.a_g(t)) if not post else 0.0
                N = ag * float(r.excitation(phi)) - float(r.restoring(phi))
                if phi <= 1e-12 * self.theta_m and N <= 0:
                    phi, moving, seated = 0.0, False, True  # back on the seat at rest
                elif abs(N) <= float(r.friction(phi)) and not stalled:
                    moving, seated = False, False  # stuck by friction
                elif stalled:
                    n_stall += 1
                    if n_stall > 2:
                        raise SolverError(f"the motion cannot leave the turning point at "
                                          f"t = {t:.9g} s, phi = {phi:.6g} rad",
                                          status="stalled")
                    s = -s
                else:
                    s = 1 if N > 0 else -1
                if not stalled:
                    n_stall = 0
                continue
            # "top": decide again at the loop head
        raise SolverError(f"more than max_phases = {opt.max_phases} phases (impacts, turning "
                          "points, stick-slip) in one time history", status="max_phases")
