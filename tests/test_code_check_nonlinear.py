"""The nonlinear kinematic analysis at the ground (docs/code-check.md), for the simple
overturning under gravity alone, against hand computations written here.

A uniform block b × h about its toe, G at (b/2, h/2): α(θ) falls to zero at θ₀ = atan(b/h),
where G stands over the toe, so G's horizontal displacement is d_k,0 = b/2. With δx ∝ z,
d* = d_k ∫z² dm/(z_G ∫z dm) = d_k (h²/3)/(h/2)² = 4 d_k/3: d₀* = 2b/3. The 2009 form:
d_u* = 0.4 d₀*, d_s* = 0.4 d_u*, a_s* = a₀*(1 − d_s*/d₀*) = 0.84 a₀*, T_s = 2π √(d_s*/a_s*),
demand S_De(T_s) = S_e(T_s) T_s²/4π² at 5 %. The 2019 transcription's: d_SLV = 0.4 d₀*,
T_SLV = 1.68π √(d_SLV/(0.6 a₀*)), S_De at ξ = 8 %, η = √(10/13)."""

from __future__ import annotations

import dataclasses
import math
import tomllib

import pytest

from homlimit.app import pipeline
from homlimit.app.config import load_case
from homlimit.check import Site, linear_kinematic, nonlinear_kinematic
from homlimit.closed_form import real
from homlimit.errors import ParameterError
from homlimit.params import Floor, Masonry

from cases import b1 as b1_dict
from cases import toml

G = 9.81
SITE = Site(ag=0.2 * G, F0=2.5, Tc_star=0.3, g=G)      # soil A, T1: S = 1, T_C = 0.3 s


def test_B1_overturning_nonlinear_by_hand(b1):
    """B1's whole façade (b = 0.5, H = 9 m): α₀ = b/H, a₀* = α₀ g/(0.75 × 1.35) = 0.538272
    m/s², d₀* = 1/3 m, d_u* = 0.133333 m, T_s = 2π √(0.053333/0.452148) = 2.15794 s, on the
    1/T branch (T_C = 0.3 < T_s < T_D = 4 × 0.2 + 1.6 = 2.4 s): S_e = a_g F₀ T_C/T_s,
    S_De = 0.0804339 m, ratio 1.65767. 2019: T_SLV = 1.68π √(0.133333/0.322963) = 3.39119 s
    > T_D: S_e = a_g η F₀ T_C T_D/T², S_De = a_g η F₀ T_C T_D/4π² = 0.0784585 m."""
    sm = real.real_mechanism(b1, "overturning").static_mechanism
    c = nonlinear_kinematic(linear_kinematic("overturning", sm, SITE, 9.0), sm, SITE)
    b, H, ag = 0.5, 9.0, 0.2 * G
    a0 = (b / H) * G / (0.75 * 1.35)
    d0 = 2 * b / 3
    du, ds = 0.4 * d0, 0.16 * d0
    Ts = 2 * math.pi * math.sqrt(ds / (0.84 * a0))
    SDe = ag * 2.5 * 0.3 / Ts * Ts ** 2 / (4 * math.pi ** 2)
    assert 0.3 < Ts < 2.4
    assert c.theta0 == pytest.approx(math.atan(b / H), rel=1e-9)
    assert c.dk0 == pytest.approx(b / 2, rel=1e-9)
    assert c.d0_star == pytest.approx(d0, rel=1e-9) and c.du_star == pytest.approx(du, rel=1e-9)
    assert c.as_star == pytest.approx(0.84 * a0, rel=1e-9)
    assert c.Ts == pytest.approx(Ts, rel=1e-9)
    assert c.SDe_Ts == pytest.approx(SDe, rel=1e-9)
    assert c.ratio == pytest.approx(du / SDe, rel=1e-9) and c.passes
    assert (a0, Ts, SDe, du / SDe) == pytest.approx((0.538272, 2.15794, 0.0804339, 1.65767),
                                                    rel=1e-5)
    eta = math.sqrt(10 / 13)
    T_slv = 1.68 * math.pi * math.sqrt(0.4 * d0 / (0.6 * a0))
    SDe_slv = ag * eta * 2.5 * 0.3 * 2.4 / (4 * math.pi ** 2)
    assert T_slv > 2.4
    assert c.T_SLV == pytest.approx(T_slv, rel=1e-9)
    assert c.SDe_SLV == pytest.approx(SDe_slv, rel=1e-9)
    assert c.ratio_SLV == pytest.approx(0.4 * d0 / SDe_slv, rel=1e-9)
    assert (T_slv, SDe_slv) == pytest.approx((3.39119, 0.0784585), rel=1e-5)


def test_overturning_with_fc_turns_about_the_retreated_hinge(b1):
    """f_c = 1 MPa: the stress block N/(f_c l) = m g/(f_c l) = 0.088290 m deep, the hinge
    retreats by t = 0.044145 m; the block turns about it, x_G = b/2 − t: θ₀ = atan(x_G/(H/2)),
    d_k,0 = x_G, d₀* = 4 x_G/3 (J_z and z_G about the retreated hinge are unchanged)."""
    case = dataclasses.replace(b1, masonry=Masonry(a=0.3, c=0.2, f=0.6, fc=1e6))
    sm = real.real_mechanism(case, "overturning").static_mechanism
    m = 2000 * 6 * 0.5 * 9
    t = m * G / (2 * 1e6 * 6)
    xg = 0.25 - t
    c = nonlinear_kinematic(linear_kinematic("overturning", sm, SITE, 9.0), sm, SITE)
    assert t == pytest.approx(0.044145, rel=1e-9)
    assert c.theta0 == pytest.approx(math.atan(xg / 4.5), rel=1e-9)
    assert c.dk0 == pytest.approx(xg, rel=1e-9)
    assert c.d0_star == pytest.approx(4 * xg / 3, rel=1e-9)


def test_no_nonlinear_check_where_the_curve_is_not_clean_or_the_base_is_raised(b1):
    with_floor = dataclasses.replace(b1, floors=(Floor(z=9.0, load=1000.0, eccentricity=0.1),))
    sm = real.real_mechanism(with_floor, "overturning").static_mechanism
    assert sm.theta0 is None
    with pytest.raises(ParameterError, match="theta0 = None of mechanism overturning is out "
                                             "of range"):
        nonlinear_kinematic(linear_kinematic("overturning", sm, SITE, 9.0), sm, SITE)
    assert real.real_mechanism(b1, "detachment").static_mechanism.theta0 is None
    sm = real.real_mechanism(b1, "overturning").static_mechanism
    raised = Site(ag=0.2 * G, F0=2.5, Tc_star=0.3, z_base=3.0, g=G)
    with pytest.raises(ParameterError, match=r"Z = 3.0 m of mechanism overturning is out of "
                                             r"range: the nonlinear check is computed at the "
                                             r"ground only"):
        nonlinear_kinematic(linear_kinematic("overturning", sm, raised, 9.0), sm, raised)


B1_RUN = toml(b1_dict("B1-nl", 
                       analysis={"fe": False, "hinge_check": False, "overturning": True},
                       output={"png": False, "vtu": False},
                       site={"ag": 1.962, "F0": 2.5, "Tc_star": 0.3}))


def test_the_run_prints_and_records_the_nonlinear_check():
    res = pipeline.compute(load_case(tomllib.loads(B1_RUN)))
    text = res.summary()
    assert "nonlinear kinematic analysis at the ground" in text
    assert "I: no nonlinear check: no clean capacity curve" in text
    nl = res.to_dict()["code_check"]["nonlinear"]
    assert set(nl["mechanisms"]) == {"overturning"}
    assert nl["mechanisms"]["overturning"]["ratio"] == pytest.approx(1.65767, rel=1e-5)
    assert {r["mechanism"] for r in nl["not_computed"]} == {"I", "II"}
