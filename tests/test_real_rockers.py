"""The rockers of a real wall's mechanisms (issue 30 item 5, ``dynamics.RealWallRocker``):
their equation of motion against W(θ) of the closed forms, the static threshold against hand
computations of the multiplier, the ideal impulse at v̄_g ± 1 % integrated in time, and the
hinge check and ``homlimit pulse`` taking fc, ties and floors."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from scipy.optimize import minimize_scalar

from homlimit.closed_form import real
from homlimit.dynamics import RealWallRocker, RectangularPulse, simulate
from homlimit.errors import ParameterError
from homlimit.params import Case, Floor, Masonry, Tie, Wall

from cases import b1

WALL = dict(H=9.0, L=6.0, s=0.5, b=0.5, l=6.0, gamma=2000.0, g=9.81)
B1 = Case(Wall(**WALL), Masonry(a=0.3, c=0.2, f=0.6), name="B1")
TIE, FLOOR = Tie(9.0, 2000.0), Floor(4.5, 20000.0, 0.3)
REAL = dataclasses.replace(B1, ties=(TIE,), floors=(FLOOR,),
                           masonry=dataclasses.replace(B1.masonry, fc=2e6))
G = WALL["g"]


def _strip(h, fc, Q):
    """The façade strip of height h (per bay l): mass, hinge retreat t = N/(2 fc l), I about
    the retreated toe (I_G + m |OG|²), by hand."""
    b, bay = WALL["b"], WALL["l"]
    m = WALL["gamma"] * bay * b * h
    t = (m * G + Q) / (2 * fc * bay)
    x, z = b / 2 - t, h / 2
    return m, t, x, z, m * (b * b + h * h) / 12 + m * (x * x + z * z)


@pytest.mark.parametrize("kind", real.KINDS)
def test_restoring_moment_is_dW(kind):
    # R + F = dW/dφ (central differences) and W is the closed forms' W(θ); also with an
    # elastic-plastic tie that breaks at its ductility limit (its kink avoided by the points)
    case = dataclasses.replace(REAL, ties=(TIE, Tie(6.0, 3000.0, 2e5, 0.05)))
    r = RealWallRocker(case, kind, lam=14.0)
    phi = np.array([0.003, 0.01, 0.02, 0.05, 0.09, 0.15])
    h = 1e-6
    dW = (r.work(phi + h) - r.work(phi - h)) / (2 * h)
    np.testing.assert_allclose(r.restoring(phi) + r.friction(phi), dW, rtol=1e-7)
    np.testing.assert_allclose(r.work(phi), real.work_real(case, kind, 14.0, phi), rtol=1e-12)


@pytest.mark.parametrize("kind", ["overturning", "detachment"])
def test_static_threshold_is_the_multiplier_by_hand(kind):
    # the multiplier of the strip at λ = 18 (the whole height) by hand: the resisting moment
    # about the retreated toe (gravity, the floor at e − t, the tie at yield T_y d, I's
    # abutment friction g γ s f c h³/(6a), eq. 9 at θ = 0) over m g z_G
    b, bay, H = WALL["b"], WALL["l"], WALL["H"]
    h = H
    Q = FLOOR.load * bay
    m, t, x, z, _ = _strip(h, 2e6, Q)
    M = m * G * x + Q * (FLOOR.eccentricity - t) + TIE.yield_force * bay * TIE.z
    if kind == "detachment":
        M += G * WALL["gamma"] * WALL["s"] * 0.6 * 0.2 * h ** 3 / (6 * 0.3)
    a_hand = M / (m * G * z)
    r = RealWallRocker(REAL, kind, lam=h / b)
    assert r.a_uplift / G == pytest.approx(a_hand, rel=1e-12)
    assert float(real.multiplier_real(REAL, kind, [h / b])[0]) == pytest.approx(a_hand,
                                                                                rel=1e-12)
    # a constant ground acceleration 1 % below does not lift it; 1 % above tips it over
    long = RectangularPulse(0.99 * a_hand * G, 30.0)
    assert not simulate(r, long).overturned
    assert simulate(r, RectangularPulse(1.01 * a_hand * G, 30.0)).overturned


def test_static_threshold_of_II_is_its_multiplier():
    m = real.real_mechanism(REAL, "crack")
    r = RealWallRocker(REAL, "crack", lam=m.lam_multiplier)
    assert r.a_uplift / G == pytest.approx(m.multiplier, rel=1e-12)
    a = m.multiplier * G
    assert not simulate(r, RectangularPulse(0.99 * a, 30.0)).overturned
    assert simulate(r, RectangularPulse(1.01 * a, 30.0)).overturned


def test_ideal_impulse_of_the_overturning_by_hand():
    # W(θ) of the tied, loaded strip on its retreated toe written out here, its peak by a
    # bounded search, and v̄_g = I ω0/(m z_G) with ½ I ω0² = W_m
    b, bay, H = WALL["b"], WALL["l"], WALL["H"]
    h = H
    Q = FLOOR.load * bay
    m, t, x, z, inertia = _strip(h, 2e6, Q)
    xF, zF, T, d = FLOOR.eccentricity - t, FLOOR.z, TIE.yield_force * bay, TIE.z

    def W(th):
        return (m * G * (x * math.sin(th) + z * (math.cos(th) - 1))
                + Q * (xF * math.sin(th) + zF * (math.cos(th) - 1)) + T * d * math.sin(th))

    opt = minimize_scalar(lambda th: -W(th), bounds=(0.0, 0.5), method="bounded",
                          options={"xatol": 1e-12})
    W_m = -opt.fun
    w0 = math.sqrt(2 * W_m / inertia)
    vg = inertia * w0 / (m * z)
    r = RealWallRocker(REAL, "overturning", lam=h / b)
    assert r.inertia == pytest.approx(inertia, rel=1e-12)
    assert r.W_m == pytest.approx(W_m, rel=1e-10)
    assert r.vg_impulse == pytest.approx(vg, rel=1e-10)
    st = real._state(REAL, "overturning", [h / b])
    assert float(real._velocity(REAL, "overturning", st)[0][0]) == pytest.approx(vg, rel=1e-10)
    # the time history from θ̇0 = (1 ± 1 %) ω0, integrated for 5 s
    low = simulate(r, theta_dot0=0.99 * w0, duration=5.0)
    assert not low.overturned and low.theta_max < opt.x
    assert simulate(r, theta_dot0=1.01 * w0, duration=5.0).overturned


@pytest.mark.parametrize("kind", real.KINDS)
def test_ideal_impulse_at_the_closed_forms_vg(kind):
    # each mechanism at its critical λ, an elastic-plastic tie with a ductility limit too:
    # the impulse m z_G v̄_g (1 ± 1 %) of the closed forms' v̄_g stands / overturns
    case = dataclasses.replace(REAL, ties=(TIE, Tie(6.0, 3000.0, 2e5, 0.05)))
    mech = real.real_mechanism(case, kind)
    r = RealWallRocker(case, kind)
    assert r.lam == mech.lam and r.vg_impulse == pytest.approx(mech.vg, rel=1e-12)
    w0 = mech.vg * r.excitation(0.0) / r.inertia
    low = simulate(r, theta_dot0=0.99 * w0, duration=5.0)
    assert not low.overturned and low.theta_max < mech.theta_m
    assert simulate(r, theta_dot0=1.01 * w0, duration=5.0).overturned


def test_joint_strength_and_bad_geometry_are_refused():
    coh = dataclasses.replace(REAL, masonry=dataclasses.replace(REAL.masonry, cohesion=1e4))
    with pytest.raises(ParameterError, match=r"\[masonry\] cohesion = 10000.0 Pa"):
        RealWallRocker(coh, "crack")
    with pytest.raises(ParameterError, match="geometry = 'linearised'"):
        RealWallRocker(REAL, "crack", geometry="linearised")
    with pytest.raises(ParameterError, match="kind = 'II'"):
        RealWallRocker(REAL, "II")


def test_hinge_check_takes_a_tie():
    # B1 with a 2 kN/m top tie, closed forms only: the hinge check's holding pulse of each
    # closed-form mechanism (the numbers of docs/real-walls.md)
    from homlimit.app.pipeline import run

    res = run(b1(analysis={"fe": False, "overturning": True},
                 tie=[{"z": 9.0, "yield_force": 2000.0}]), write=False)
    assert set(res.hinges) == {"I", "II", "overturning"}
    for name, hp in res.hinges.items():
        m = res.mechanisms[name]
        assert math.isfinite(hp.duration) and hp.ratio > 1, (name, hp)
        assert hp.pgv == pytest.approx(0.6 * G * hp.duration)
        assert hp.pgv / hp.ratio == pytest.approx(m.vg, rel=1e-9)   # eq. 7's v̄_g


def test_pulse_spectra_take_a_tie():
    # `homlimit pulse`'s spectra of a tied B1: I and the overturning (not enabled in
    # [analysis]: its `alone` computes it) on RealWallRocker at the closed forms' λ and v̄_g;
    # a rectangular pulse of finite duration needs more pgv than the ideal impulse
    from homlimit.app.config import load_case
    from homlimit.app.pulses import pulse_records

    config = load_case(b1(analysis={"fe": False}, tie=[{"z": 9.0, "yield_force": 2000.0}],
                          pulse={"mechanisms": ["I", "overturning"], "kinds": ["rectangular"],
                                 "periods": [0.2], "polarities": [1]}))
    points, fe = pulse_records(config)
    assert fe is None and {p.mechanism for p in points} == {"I", "overturning"}
    for p in points:
        mech = real.real_mechanism(config.case, {"I": "detachment"}.get(p.mechanism,
                                                                         p.mechanism))
        assert p.vg_eq7 == pytest.approx(mech.vg, rel=1e-12)
        assert 1 < p.ratio < 3 and p.pga > p.a_uplift >= mech.multiplier * G


def test_hinge_check_refusals_lifted_where_the_rockers_take_the_inputs():
    # fc, ties and floors on every rocker (the FE body's too, with the FE impulse's LoadWork:
    # test_fe_impulse_real.py); any rocker with cohesion stays refused (test_real_walls.py)
    from homlimit.app.config import load_case

    assert load_case(b1(masonry={"fc": 2e6})).analysis.hinge_check       # fe = true default
    fe_tied = load_case(b1(tie=[{"z": 9.0, "yield_force": 2000.0}]))
    assert fe_tied.analysis.fe and fe_tied.analysis.hinge_check and fe_tied.case.ties
    tied = load_case(b1(analysis={"fe": False}, floor=[{"z": 4.5, "load": 2e4,
                                                        "eccentricity": 0.1}],
                        tie=[{"z": 9.0, "yield_force": 2000.0}]))
    assert tied.analysis.hinge_check and tied.case.ties and tied.case.floors


def test_mechanism_I_exact_gravity():
    # [pulse] gravity_I = "exact": gravity, floors and ties at finite rotation (δ = d sin φ),
    # the friction linearised as eq. 8; R + F = dW/dφ, θ_m where R + F changes sign, and the
    # impulse of its own v̄_g (1 ∓ 1 %) stands / overturns
    r = RealWallRocker(REAL, "detachment", geometry="exact")
    phi = np.array([0.01, 0.05, 0.12])
    dW = (r.work(phi + 1e-6) - r.work(phi - 1e-6)) / 2e-6
    np.testing.assert_allclose(r.restoring(phi) + r.friction(phi), dW, rtol=1e-7)
    th = r.theta_m
    assert r.restoring(th * 0.999) + r.friction(th * 0.999) > 0
    assert r.restoring(th * 1.001) + r.friction(th * 1.001) < 0
    w0 = r.vg_impulse * r.excitation(0.0) / r.inertia
    assert not simulate(r, theta_dot0=0.99 * w0, duration=5.0).overturned
    assert simulate(r, theta_dot0=1.01 * w0, duration=5.0).overturned
