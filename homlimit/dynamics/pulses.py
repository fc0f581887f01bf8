"""Ground-motion pulses a_g(t) [m/s²] for the time-history check of the impulse criterion.

Every pulse is a small frozen dataclass with validated parameters and
- ``a(t)``: the ground acceleration, vectorised over t [s]; positive a_g accelerates the
  ground towards +x (into the building), so its inertia pushes the façade outwards (the
  overturning direction of eq. 1); zero outside the closed support [0, t_end];
- ``v(t)``: the ground velocity ∫₀ᵗ a_g dt [m/s];
- ``pga`` [m/s²], ``pgv`` [m/s]: peak |a_g| and peak |v|;
- ``period`` [s]: the pulse period T_p (rectangular pulse: its duration Δt; record: its
  length), the abscissa of an overturning spectrum;
- ``t_end`` [s]: the end of the support (the pulse starts at t = 0);
- ``with_pga(a)``: the same pulse scaled to peak ground acceleration ``a``.

``polarity`` = +1 (default) puts the first or main acceleration lobe outwards; −1 flips the
pulse. Kinds (``make_pulse`` names):

- ``rectangular``: a_g = a_p on [0, Δt]; v_g = a_p Δt is the paper's impulse (eq. 3) for
  Δt → 0;
- ``one-sine``: a_g = a_p sin(2πt/T_p) on [0, T_p] (Makris & Roussos 2000, type-A: a forward
  velocity pulse, pgv = a_p T_p/π);
- ``one-cosine``: a_g = a_p cos(2πt/T_p) on [0, T_p] (type-B: a full velocity cycle,
  pgv = a_p T_p/(2π));
- ``ricker``: a_g = a_p (1 − 2π²τ²/T_p²) exp(−π²τ²/T_p²), τ = t − t0, truncated to
  |τ| <= t0 = 1.5 T_p (the cut-off acceleration is below 1e-8 a_p); T_p = 1/f_p, f_p the
  frequency where its Fourier amplitude peaks;
- ``mp``: the Mavroeidis & Papageorgiou (2003) near-fault velocity pulse
  v = (v_p/2)[1 + cos(2πf_p τ/γ)] cos(2πf_p τ + ν) for |τ| <= γ/(2f_p), τ = t − γ/(2f_p),
  f_p = 1/T_p, and its derivative as a_g;
- ``RecordPulse``: a user record, two-column CSV t [s], a_g [m/s²], linear between samples.
"""

from __future__ import annotations

import csv
import dataclasses
import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from scipy.integrate import cumulative_trapezoid
from scipy.optimize import minimize_scalar

from ..errors import ParameterError, check_range
from ..fields import Range, check_fields, ranged, set_fields

__all__ = ["Pulse", "RectangularPulse", "OneSinePulse", "OneCosinePulse", "RickerPulse",
           "MavroeidisPapageorgiouPulse", "RecordPulse", "PULSE_KINDS", "make_pulse",
           "RECORD_MIN_SAMPLES", "RECORD_MAX_STEP", "RECORD_MAX_DURATION"]

RICKER_CUT = 1.5  # Ricker support |t − t0| <= RICKER_CUT · T_p
RECORD_MIN_SAMPLES = 16    # fewer samples cannot describe a ground motion
RECORD_MAX_STEP = 0.05     # s: a longer sample step gets a warning (peaks between samples lost)
RECORD_MAX_DURATION = 600.0  # s: a longer record gets a warning (no earthquake lasts that long)
_N_PEAK = 20001  # samples for numerically found peaks (smooth pulses: error ~ (T/N)²)


_AMPLITUDE = Range(0.0, lo_open=True, unit="m/s^2")    # a_p of a pulse
_PERIOD = Range(0.0, lo_open=True, unit="s")            # T_p of a pulse


def _polarity(value) -> int:
    if value not in (1, -1):
        raise ParameterError(f"polarity = {value!r} is out of range: allowed +1 or -1")
    return int(value)


def _peak(fun, grid, sign: float) -> float:
    """max (sign = 1) or min (sign = -1) of a smooth fun over the grid's span: the best grid
    point, refined by a bounded scalar minimisation between its neighbours."""
    y = sign * fun(grid)
    k = int(np.argmax(y))
    lo, hi = grid[max(k - 1, 0)], grid[min(k + 1, len(grid) - 1)]
    res = minimize_scalar(lambda t: -sign * float(fun(t)), bounds=(lo, hi), method="bounded",
                          options={"xatol": 1e-14 * max(1.0, hi)})
    return sign * max(float(y[k]), -float(res.fun))


def _support(t, t_end):
    t = np.asarray(t, dtype=float)
    return t, (t >= 0.0) & (t <= t_end)


class Pulse:
    """Common behaviour of the pulses (see the module docstring)."""

    kind = "pulse"

    @property
    def t_end(self) -> float:  # pragma: no cover - every pulse defines it
        raise NotImplementedError

    @property
    def period(self) -> float:  # pragma: no cover
        raise NotImplementedError

    @property
    def pga(self) -> float:
        """Peak |a_g| [m/s²] (found numerically unless a subclass knows it)."""
        return max(-self.a_extremes[0], self.a_extremes[1])

    @property
    def pgv(self) -> float:
        """Peak |v_g| [m/s] (found numerically unless a subclass knows it)."""
        return max(-_peak(self.v, self._grid(), -1.0), _peak(self.v, self._grid(), 1.0))

    @property
    def a_extremes(self) -> tuple[float, float]:
        """(min a_g, max a_g) [m/s²] over the support (found numerically unless a subclass
        knows them)."""
        grid = self._grid()
        return _peak(self.a, grid, -1.0), _peak(self.a, grid, 1.0)

    def _grid(self):
        return np.linspace(0.0, self.t_end, _N_PEAK)

    def at(self, t: float) -> float:
        """a_g at one time t [s] as a float (the integrator's hot path)."""
        return float(self.a(t))

    @property
    def step_hint(self) -> float:
        """Largest integration step that still sees every lobe [s]: T_p/10."""
        return self.period / 10

    def with_pga(self, pga: float) -> Pulse:  # pragma: no cover
        raise NotImplementedError

    def describe(self) -> dict:
        """Plain record of the pulse: kind, its parameters, pga, pgv, period."""
        d = {"kind": self.kind}
        for f in dataclasses.fields(self):
            v = getattr(self, f.name)
            if not isinstance(v, np.ndarray):
                d[f.name] = v
        d.update(pga=self.pga, pgv=self.pgv, period=self.period)
        return d


@dataclass(frozen=True)
class RectangularPulse(Pulse):
    """a_g = polarity · a_p on 0 <= t <= duration (a_p [m/s²], duration [s])."""

    a_p: float = ranged(_AMPLITUDE)
    duration: float = ranged(0.0, lo_open=True, unit="s")
    polarity: int = 1
    kind = "rectangular"

    def __post_init__(self):
        check_fields(self)
        set_fields(self, polarity=_polarity(self.polarity))

    @property
    def t_end(self):
        return self.duration

    @property
    def period(self):
        return self.duration

    def a(self, t):
        t, on = _support(t, self.duration)
        return np.where(on, self.polarity * self.a_p, 0.0)

    def at(self, t):
        return self.polarity * self.a_p if 0.0 <= t <= self.duration else 0.0

    def v(self, t):
        t = np.asarray(t, dtype=float)
        return self.polarity * self.a_p * np.clip(t, 0.0, self.duration)

    @property
    def pga(self):
        return self.a_p

    @property
    def pgv(self):
        return self.a_p * self.duration

    @property
    def a_extremes(self):
        return (min(0.0, self.polarity * self.a_p), max(0.0, self.polarity * self.a_p))

    def with_pga(self, pga):
        return dataclasses.replace(self, a_p=pga)


@dataclass(frozen=True)
class _CyclePulse(Pulse):
    """One cycle a_g = polarity · a_p f(2πt/T_p) on 0 <= t <= T_p (cycloidal pulses)."""

    a_p: float = ranged(_AMPLITUDE)
    T_p: float = ranged(_PERIOD)
    polarity: int = 1

    def __post_init__(self):
        check_fields(self)
        set_fields(self, polarity=_polarity(self.polarity))

    @property
    def t_end(self):
        return self.T_p

    @property
    def period(self):
        return self.T_p

    @property
    def omega(self):
        """ω_p = 2π/T_p [rad/s]."""
        return 2 * math.pi / self.T_p

    def a(self, t):
        t, on = _support(t, self.T_p)
        return np.where(on, self.polarity * self.a_p * self._f(self.omega * t), 0.0)

    def at(self, t):
        if 0.0 <= t <= self.T_p:
            return self.polarity * self.a_p * self._f_scalar(2 * math.pi * t / self.T_p)
        return 0.0

    @property
    def pga(self):
        return self.a_p

    @property
    def a_extremes(self):
        return (-self.a_p, self.a_p)

    def with_pga(self, pga):
        return dataclasses.replace(self, a_p=pga)


@dataclass(frozen=True)
class OneSinePulse(_CyclePulse):
    """a_g = polarity · a_p sin(2πt/T_p) on 0 <= t <= T_p (type-A cycloidal pulse)."""

    kind = "one-sine"
    _f, _f_scalar = np.sin, math.sin

    def v(self, t):
        tc = np.clip(np.asarray(t, dtype=float), 0.0, self.T_p)
        return self.polarity * self.a_p / self.omega * (1.0 - np.cos(self.omega * tc))

    @property
    def pgv(self):
        return self.a_p * self.T_p / math.pi


@dataclass(frozen=True)
class OneCosinePulse(_CyclePulse):
    """a_g = polarity · a_p cos(2πt/T_p) on 0 <= t <= T_p (type-B cycloidal pulse)."""

    kind = "one-cosine"
    _f, _f_scalar = np.cos, math.cos

    def v(self, t):
        tc = np.clip(np.asarray(t, dtype=float), 0.0, self.T_p)
        return self.polarity * self.a_p / self.omega * np.sin(self.omega * tc)

    @property
    def pgv(self):
        return self.a_p * self.T_p / (2 * math.pi)


@dataclass(frozen=True)
class RickerPulse(Pulse):
    """Ricker wavelet a_g = polarity · a_p (1 − 2π²τ²/T_p²) exp(−π²τ²/T_p²), τ = t − t0,
    t0 = 1.5 T_p, support [0, 2 t0]. Its velocity is v = a_p τ exp(−π²τ²/T_p²), peak
    pgv = a_p T_p e^{-1/2} / (π√2) at τ = T_p/(π√2)."""

    a_p: float = ranged(_AMPLITUDE)
    T_p: float = ranged(_PERIOD)
    polarity: int = 1
    kind = "ricker"

    def __post_init__(self):
        check_fields(self)
        set_fields(self, polarity=_polarity(self.polarity))

    @property
    def t0(self):
        return RICKER_CUT * self.T_p

    @property
    def t_end(self):
        return 2 * self.t0

    @property
    def period(self):
        return self.T_p

    def a(self, t):
        t, on = _support(t, self.t_end)
        x = (math.pi * (t - self.t0) / self.T_p) ** 2
        return np.where(on, self.polarity * self.a_p * (1 - 2 * x) * np.exp(-x), 0.0)

    def at(self, t):
        if 0.0 <= t <= self.t_end:
            x = (math.pi * (t - self.t0) / self.T_p) ** 2
            return self.polarity * self.a_p * (1 - 2 * x) * math.exp(-x)
        return 0.0

    def v(self, t):
        tc = np.clip(np.asarray(t, dtype=float), 0.0, self.t_end)
        tau = tc - self.t0
        v0 = -self.t0 * math.exp(-(math.pi * self.t0 / self.T_p) ** 2)  # v at t = 0
        return self.polarity * self.a_p * (tau * np.exp(-(math.pi * tau / self.T_p) ** 2) - v0)

    @property
    def pga(self):
        return self.a_p

    @property
    def pgv(self):
        return self.a_p * self.T_p * math.exp(-0.5) / (math.pi * math.sqrt(2.0))

    @property
    def a_extremes(self):
        side = 2 * math.exp(-1.5) * self.a_p  # the side lobes, at π²τ²/T_p² = 3/2
        return (-self.a_p, side) if self.polarity < 0 else (-side, self.a_p)

    def with_pga(self, pga):
        return dataclasses.replace(self, a_p=pga)


@dataclass(frozen=True)
class MavroeidisPapageorgiouPulse(Pulse):
    """Near-fault velocity pulse of Mavroeidis & Papageorgiou (2003), started at t = 0:

        v(t) = polarity (v_p/2) [1 + cos(2π f_p τ/γ)] cos(2π f_p τ + ν),  |τ| <= γ/(2 f_p),
        τ = t − γ/(2 f_p),  f_p = 1/T_p,

    a_g = dv/dt. v_p [m/s] velocity amplitude, T_p [s] pulse period, γ (gamma) > 1 the number
    of half cycles' oscillatory character, ν (nu) [rad] phase. Both v and a_g vanish at the
    ends of the support [0, γ T_p]; pga and pgv are found numerically.
    """

    v_p: float = ranged(0.0, lo_open=True, unit="m/s")
    T_p: float = ranged(_PERIOD)
    gamma: float = ranged(1.0, 10.0, lo_open=True, default=2.0)
    nu: float = ranged(-2 * math.pi, 2 * math.pi, unit="rad", default=0.0)
    polarity: int = 1
    kind = "mp"

    def __post_init__(self):
        check_fields(self)
        set_fields(self, polarity=_polarity(self.polarity))

    @property
    def t_end(self):
        return self.gamma * self.T_p

    @property
    def period(self):
        return self.T_p

    def _tau(self, t):
        return t - 0.5 * self.gamma * self.T_p

    def v(self, t):
        t, on = _support(t, self.t_end)
        w, tau = 2 * math.pi / self.T_p, self._tau(t)
        v = 0.5 * self.v_p * (1 + np.cos(w * tau / self.gamma)) * np.cos(w * tau + self.nu)
        return np.where(on, self.polarity * v, 0.0)

    def a(self, t):
        t, on = _support(t, self.t_end)
        w, g, tau = 2 * math.pi / self.T_p, self.gamma, self._tau(t)
        a = -(self.v_p * w / (2 * g)) * (np.sin(w * tau / g) * np.cos(w * tau + self.nu)
                                        + g * np.sin(w * tau + self.nu)
                                        * (1 + np.cos(w * tau / g)))
        return np.where(on, self.polarity * a, 0.0)

    def at(self, t):
        if not 0.0 <= t <= self.t_end:
            return 0.0
        w, g, tau = 2 * math.pi / self.T_p, self.gamma, self._tau(t)
        return -self.polarity * (self.v_p * w / (2 * g)) * (
            math.sin(w * tau / g) * math.cos(w * tau + self.nu)
            + g * math.sin(w * tau + self.nu) * (1 + math.cos(w * tau / g)))

    def with_pga(self, pga):
        pga = check_range("pga", pga, 0.0, lo_open=True, unit="m/s^2")
        return dataclasses.replace(self, v_p=self.v_p * pga / self.pga)


@dataclass(frozen=True, eq=False)
class RecordPulse(Pulse):
    """A recorded or user-made ground acceleration: samples t [s] (at least
    RECORD_MIN_SAMPLES = 16, finite, strictly increasing, t[0] >= 0) and a_g [m/s²], linear
    between samples, zero outside [t[0], t[-1]]; scaled by ``scale`` (> 0). ``period`` is its
    length t[-1] − t[0]. ``warnings``: valid but doubtful sampling (a step over 0.05 s, a
    length over 600 s)."""

    t: np.ndarray
    a_g: np.ndarray
    scale: float = ranged(0.0, lo_open=True, default=1.0)
    polarity: int = 1
    name: str = "record"
    _v: np.ndarray = field(init=False, repr=False)
    kind = "record"

    def __post_init__(self):
        t = np.asarray(self.t, dtype=float).ravel()
        a = np.asarray(self.a_g, dtype=float).ravel()
        if t.size < RECORD_MIN_SAMPLES or t.size != a.size:
            raise ParameterError(f"record {self.name!r} has {t.size} times and {a.size} "
                                 "accelerations: allowed two equal columns of at least "
                                 f"{RECORD_MIN_SAMPLES} rows")
        if not (np.all(np.isfinite(t)) and np.all(np.isfinite(a))):
            raise ParameterError(f"record {self.name!r} holds non-finite values: allowed "
                                 "finite t [s] and a_g [m/s^2]")
        check_range("t[0]", float(t[0]), 0.0, unit="s")
        dt = np.diff(t)
        if np.any(dt <= 0):
            k = int(np.argmax(dt <= 0))
            raise ParameterError(f"record time t[{k + 1}] = {float(t[k + 1])!r} s is out of "
                                 f"range: times must increase strictly, allowed "
                                 f"t > {float(t[k])!r} s")
        if not np.any(a != 0):
            raise ParameterError(f"record {self.name!r} is all zero: allowed a record with "
                                 "some a_g != 0")
        set_fields(self, t=t, a_g=a)
        check_fields(self)       # scale
        set_fields(self, polarity=_polarity(self.polarity),
                   _v=cumulative_trapezoid(a, t, initial=0.0))

    @property
    def warnings(self) -> list[str]:
        """Valid but doubtful sampling: a step over RECORD_MAX_STEP, a length over
        RECORD_MAX_DURATION (each a sentence naming the record)."""
        out = []
        dt = np.diff(self.t)
        k = int(np.argmax(dt))
        if dt[k] > RECORD_MAX_STEP:
            out.append(f"record {self.name!r} has a time step of {float(dt[k]):.4g} s (from "
                       f"t = {float(self.t[k]):.6g} s): over {RECORD_MAX_STEP:g} s, a_g is "
                       "linear between samples and the peaks between them are lost")
        if self.period > RECORD_MAX_DURATION:
            out.append(f"record {self.name!r} lasts {self.period:.4g} s: over "
                       f"{RECORD_MAX_DURATION:g} s, longer than any earthquake")
        return out

    @classmethod
    def from_csv(cls, path: str | Path, **kwargs) -> RecordPulse:
        """Read a two-column CSV: t [s], a_g [m/s²]; lines starting with '#' and one header
        line of non-numbers are skipped. Errors name the file and line."""
        path = Path(path)
        if not path.is_file():
            raise ParameterError(f"record = {str(path)!r} is not a file: allowed a two-column "
                                 "CSV t [s], a_g [m/s^2]")
        rows, header = [], False
        with path.open(newline="", encoding="utf-8") as fh:
            for k, row in enumerate(csv.reader(fh), start=1):
                cells = [c.strip() for c in row if c.strip()]
                if not cells or cells[0].startswith("#"):
                    continue
                try:
                    vals = [float(c) for c in cells]
                except ValueError:
                    if not rows and not header:
                        header = True
                        continue  # one header line before the data
                    raise ParameterError(f"{path}:{k}: {row!r} is not two numbers: allowed "
                                         "t [s], a_g [m/s^2]") from None
                if len(vals) != 2:
                    raise ParameterError(f"{path}:{k}: {len(vals)} columns: allowed two, "
                                         "t [s], a_g [m/s^2]")
                rows.append(vals)
        if not rows:
            raise ParameterError(f"record = {str(path)!r} holds no data rows")
        arr = np.asarray(rows)
        kwargs.setdefault("name", path.stem)
        return cls(arr[:, 0], arr[:, 1], **kwargs)

    @property
    def t_end(self):
        return float(self.t[-1])

    @property
    def period(self):
        return float(self.t[-1] - self.t[0])

    @property
    def sign(self) -> float:
        return self.polarity * self.scale

    def a(self, t):
        t = np.asarray(t, dtype=float)
        on = (t >= self.t[0]) & (t <= self.t[-1])
        return np.where(on, self.sign * np.interp(t, self.t, self.a_g), 0.0)

    def v(self, t):
        """∫ a_g dt, exact for the piecewise linear record (quadratic between samples)."""
        t = np.asarray(t, dtype=float)
        tc = np.clip(t, self.t[0], self.t[-1])
        k = np.clip(np.searchsorted(self.t, tc, side="right") - 1, 0, self.t.size - 2)
        dt = self.t[k + 1] - self.t[k]
        tau = tc - self.t[k]
        a0, a1 = self.a_g[k], self.a_g[k + 1]
        return self.sign * (self._v[k] + a0 * tau + (a1 - a0) * tau ** 2 / (2 * dt))

    def _grid(self):
        return self.t

    @property
    def step_hint(self):
        """The shortest sample interval [s]: no step jumps over a sample."""
        return float(np.min(np.diff(self.t)))

    @property
    def pga(self):
        return float(self.scale * np.max(np.abs(self.a_g)))

    @property
    def pgv(self):
        """Peak |v|: at the samples or where a_g crosses zero between them."""
        a0, a1 = self.a_g[:-1], self.a_g[1:]
        cross = (a0 * a1) < 0
        tz = self.t[:-1][cross] + (self.t[1:] - self.t[:-1])[cross] * a0[cross] / (
            a0[cross] - a1[cross])
        return float(np.max(np.abs(self.v(np.concatenate([self.t, tz])))))

    def with_pga(self, pga):
        pga = check_range("pga", pga, 0.0, lo_open=True, unit="m/s^2")
        return dataclasses.replace(self, scale=pga / float(np.max(np.abs(self.a_g))))

    def describe(self):
        return {"kind": self.kind, "name": self.name, "n_samples": int(self.t.size),
                "scale": self.scale, "polarity": self.polarity, "pga": self.pga,
                "pgv": self.pgv, "period": self.period}


PULSE_KINDS = {"rectangular": RectangularPulse, "one-sine": OneSinePulse,
               "one-cosine": OneCosinePulse, "ricker": RickerPulse,
               "mp": MavroeidisPapageorgiouPulse}


def make_pulse(kind: str, period: float, pga: float = 1.0, polarity: int = 1,
               **options) -> Pulse:
    """The pulse ``kind`` (a key of PULSE_KINDS) of period T_p [s] (rectangular: duration)
    and peak ground acceleration ``pga`` [m/s²]; ``options``: gamma, nu for ``mp``."""
    if kind not in PULSE_KINDS:
        raise ParameterError(f"pulse kind = {kind!r} is out of range: allowed "
                             f"{', '.join(PULSE_KINDS)}")
    extra = set(options) - ({"gamma", "nu"} if kind == "mp" else set())
    if extra:
        raise ParameterError(f"pulse option {sorted(extra)[0]!r} is not a parameter of "
                             f"kind {kind!r}")
    if kind == "rectangular":
        return RectangularPulse(pga, period, polarity)
    if kind == "mp":
        return MavroeidisPapageorgiouPulse(1.0, period, polarity=polarity,
                                           **options).with_pga(pga)
    return PULSE_KINDS[kind](pga, period, polarity)
