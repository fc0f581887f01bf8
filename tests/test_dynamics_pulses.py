"""Ground-motion pulses: accelerations, velocities and peaks against closed forms and numerical
integration; the user record from CSV."""

import math

import numpy as np
import pytest
from scipy.integrate import cumulative_trapezoid

from homlimit import ParameterError
from homlimit.dynamics import (
    PULSE_KINDS,
    MavroeidisPapageorgiouPulse,
    OneCosinePulse,
    OneSinePulse,
    RecordPulse,
    RectangularPulse,
    RickerPulse,
    make_pulse,
)


@pytest.mark.parametrize("kind", list(PULSE_KINDS))
def test_velocity_is_the_integral_of_acceleration(kind):
    p = make_pulse(kind, 0.4, 3.0)
    t = np.linspace(0, p.t_end, 400001)
    v_num = cumulative_trapezoid(p.a(t), t, initial=0.0)
    assert np.max(np.abs(v_num - p.v(t))) <= 1e-8 * p.pgv
    assert p.pga == pytest.approx(3.0, rel=1e-12)
    assert p.pga == pytest.approx(np.max(np.abs(p.a(t))), rel=1e-8)
    assert p.pgv == pytest.approx(np.max(np.abs(v_num)), rel=1e-8)
    # outside the support nothing moves; the scalar path agrees with the vectorised one
    assert p.at(-1e-9) == 0.0 and p.at(p.t_end + 1e-9) == 0.0
    ts = np.linspace(-0.1, p.t_end + 0.1, 301)
    assert np.allclose(np.array([p.at(x) for x in ts]), p.a(ts), rtol=0, atol=1e-13 * p.pga)


def test_peaks_by_hand():
    assert RectangularPulse(2.0, 0.3).pgv == pytest.approx(0.6, rel=1e-15)
    assert OneSinePulse(2.0, 0.5).pgv == pytest.approx(2.0 * 0.5 / math.pi, rel=1e-15)
    assert OneCosinePulse(2.0, 0.5).pgv == pytest.approx(2.0 * 0.5 / (2 * math.pi), rel=1e-15)
    # Ricker: v = a_p τ exp(−π²τ²/T²) peaks at τ = T/(π√2): a_p T e^{-1/2}/(π√2)
    r = RickerPulse(1.0, 1.0)
    assert r.pgv == pytest.approx(math.exp(-0.5) / (math.pi * math.sqrt(2)), rel=1e-15)
    lo, hi = r.a_extremes
    assert (lo, hi) == (pytest.approx(-2 * math.exp(-1.5)), 1.0)
    # Ricker truncated at ±1.5 T: the cut-off acceleration is negligible
    assert abs(r.at(0.0)) < 1e-8
    # one-sine velocity returns to zero at the end, one-cosine too; the rectangular does not
    assert OneSinePulse(1.0, 1.0).v(1.0) == pytest.approx(0.0, abs=1e-16)
    assert RectangularPulse(1.0, 1.0).v(5.0) == 1.0


def test_mavroeidis_papageorgiou_pulse():
    """v(t) = (v_p/2)[1 + cos(2πf_p τ/γ)] cos(2πf_p τ + ν): zero at both ends, peak v_p at
    the centre for ν = 0; a_g is its derivative (checked by central differences)."""
    p = MavroeidisPapageorgiouPulse(0.8, 0.6, gamma=2.5, nu=0.4)
    assert p.t_end == pytest.approx(1.5)
    assert p.v(0.0) == pytest.approx(0.0, abs=1e-15)
    assert p.v(p.t_end) == pytest.approx(0.0, abs=1e-15)
    assert p.a(0.0) == pytest.approx(0.0, abs=1e-14) and abs(p.a(p.t_end)) < 1e-14
    t = np.linspace(0.01, 1.49, 77)
    h = 1e-6
    assert np.allclose(p.a(t), (p.v(t + h) - p.v(t - h)) / (2 * h), rtol=1e-6, atol=1e-6)
    centre = MavroeidisPapageorgiouPulse(0.8, 0.6, gamma=2.5, nu=0.0)
    assert centre.pgv == pytest.approx(0.8, rel=1e-12)
    scaled = p.with_pga(5.0)
    assert scaled.pga == pytest.approx(5.0, rel=1e-12)
    assert scaled.v_p / p.v_p == pytest.approx(5.0 / p.pga, rel=1e-14)


def test_polarity_and_scaling():
    for kind in PULSE_KINDS:
        p = make_pulse(kind, 0.3, 2.0)
        q = make_pulse(kind, 0.3, 2.0, polarity=-1)
        t = np.linspace(0, p.t_end, 1001)
        assert np.allclose(q.a(t), -p.a(t), rtol=0, atol=1e-14)
        assert p.with_pga(7.0).pga == pytest.approx(7.0, rel=1e-12)
        d = p.describe()
        assert d["kind"] == kind and d["pga"] == pytest.approx(2.0) and d["period"] == 0.3


def test_record_from_csv(tmp_path):
    path = tmp_path / "rec.csv"
    # the piecewise-linear a_g through (0, 0), (0.1, 2), (0.3, -1), (0.4, 0), sampled every
    # 0.025 s (17 samples: a record needs 16)
    ts = np.linspace(0.0, 0.4, 17)
    ag = np.interp(ts, [0.0, 0.1, 0.3, 0.4], [0.0, 2.0, -1.0, 0.0])
    path.write_text("# a triangle\nt [s], a_g [m/s2]\n"
                    + "".join(f"{t!r}, {a!r}\n" for t, a in zip(ts.tolist(), ag.tolist())))
    r = RecordPulse.from_csv(path)
    assert r.name == "rec" and r.t_end == 0.4 and r.period == pytest.approx(0.4)
    assert r.a(0.05) == pytest.approx(1.0)
    assert r.a(0.5) == 0.0
    assert r.pga == 2.0
    # v peaks where a crosses zero (t = 1/6 + 0.1 ... by hand: 0.1 + 2/3 · 0.2 · ... )
    t = np.linspace(0, 0.4, 40001)
    assert r.pgv == pytest.approx(np.max(np.abs(cumulative_trapezoid(r.a(t), t))), rel=1e-6)
    # area of the positive part: 0.1·2/2 + (0.2·2/3)·2/2 = 0.1 + 0.1333
    assert r.pgv == pytest.approx(0.1 + 0.4 / 3, rel=1e-12)
    s = r.with_pga(4.0)
    assert s.pga == pytest.approx(4.0) and s.pgv == pytest.approx(2 * r.pgv)
    assert r.step_hint == pytest.approx(0.025)
    assert r.warnings == []


def _rows(a, t0=1.0, n=16):
    """n rows t = t0, t0 + 0.01, ... with a_g = a (padding that is itself valid)."""
    return "".join(f"{t0 + 0.01 * k:.2f},{a}\n" for k in range(n))


@pytest.mark.parametrize("text, match", [
    ("0,0\n0.1,1\n0.1,2\n" + _rows(1), r"t\[2\] = 0\.1 s is out of range"),
    ("0,0\n0.1,1,3\n", "3 columns"),
    ("t,a\n0,0\nx,1\n", r"rec\.csv:3"),
    ("0,0\n0.1,0\n" + _rows(0), "all zero"),
    ("0,1\n", "1 times and 1 accelerations: allowed .* at least 16 rows"),
    ("0,0\n" + _rows(1, n=14), "15 times .* at least 16 rows"),
    ("-0.1,1\n0.1,1\n" + _rows(1), r"t\[0\] = -0\.1"),
    ("0,1\n0.1,nan\n" + _rows(1), "non-finite"),
    ("0,1\n0.1,inf\n" + _rows(1), "non-finite"),
])
def test_record_errors_name_the_problem(tmp_path, text, match):
    path = tmp_path / "rec.csv"
    path.write_text(text)
    with pytest.raises(ParameterError, match=match):
        RecordPulse.from_csv(path)


def test_record_sampling_warnings():
    """A step over 0.05 s or a length over 600 s is valid but warned about, naming the
    record, the step and where it is."""
    t = np.concatenate([np.linspace(0.0, 0.15, 16), [0.25]])
    (w,) = RecordPulse(t, np.ones(17), name="coarse").warnings
    assert "record 'coarse' has a time step of 0.1 s (from t = 0.15 s): over 0.05 s" in w
    (w,) = RecordPulse(np.linspace(0.0, 700.0, 70001), np.ones(70001), name="long").warnings
    assert "record 'long' lasts 700 s: over 600 s" in w
    assert len(RecordPulse(np.linspace(0.0, 1e9, 16), np.ones(16)).warnings) == 2


def test_missing_record_file(tmp_path):
    with pytest.raises(ParameterError, match="record = .*nope.csv.* is not a file"):
        RecordPulse.from_csv(tmp_path / "nope.csv")


@pytest.mark.parametrize("make, match", [
    (lambda: RectangularPulse(0.0, 1.0), r"a_p = 0\.0 m/s\^2 is out of range"),
    (lambda: RectangularPulse(1.0, -1.0), r"duration = -1\.0 s is out of range"),
    (lambda: OneSinePulse(1.0, 0.0), r"T_p = 0\.0 s is out of range"),
    (lambda: OneCosinePulse(float("nan"), 1.0), "a_p = nan"),
    (lambda: RickerPulse(1.0, 1.0, polarity=2), "polarity = 2 is out of range"),
    (lambda: MavroeidisPapageorgiouPulse(1.0, 1.0, gamma=1.0), r"gamma = 1\.0 is out of range"),
    (lambda: MavroeidisPapageorgiouPulse(1.0, 1.0, nu=7.0), r"nu = 7\.0 rad is out of range"),
    (lambda: MavroeidisPapageorgiouPulse(-1.0, 1.0), r"v_p = -1\.0 m/s is out of range"),
    (lambda: RecordPulse(np.arange(16.0), np.ones(16), scale=0.0),
     r"scale = 0\.0 is out of range"),
    (lambda: make_pulse("triangle", 1.0), "pulse kind = 'triangle' is out of range"),
    (lambda: make_pulse("ricker", 1.0, gamma=2.0), "pulse option 'gamma'"),
])
def test_bad_parameters_are_named(make, match):
    with pytest.raises(ParameterError, match=match):
        make()
