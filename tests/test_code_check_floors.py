"""The code check's floors' Q_k reading beside the package's own (docs/code-check.md, reading
3): the public transcription of the Circolare 2019 (C8.7.1.1, C8.7.1.5) pushes the floors'
weights Q_k horizontally in α₀ and sums them in M* and e*,

    α₀ = (Σ P_k δy_k − Σ F_k δ_F,k + L_i) / Σ (P_k + Q_k) δx_k,
    e* = [Σ (P_k + Q_k) δx_k]² / ([Σ (P_k + Q_k)] [Σ (P_k + Q_k) δx_k²]),

while the package's floor bears vertically only. B1 (H = 9, b = 0.5, l = 6 m, γ = 2000
kg/m³, α² = cf/a = 0.4, ρ = l/s = 12) with a floor at mid-height z_F = 4.5 m, q = 20 kN/m
(Q = q l = 120 kN), at two eccentricities e from the outer face. Every expected number is
written out here by hand; the package is only asked for its answer. Closed forms only."""

from __future__ import annotations

import dataclasses
import json
import math
import tomllib

import numpy as np
import pytest
from scipy.optimize import brentq
from typer.testing import CliRunner

from homlimit.app import pipeline
from homlimit.app.cli import app
from homlimit.app.config import load_case
from homlimit.check import Site, linear_kinematic
from homlimit.closed_form import real
from homlimit.params import Floor

from cases import b1 as b1_dict
from cases import toml

G = 9.81
GAMMA, L, B, H, S = 2000.0, 6.0, 0.5, 9.0, 0.5          # kg/m³, m
F_FRICTION, C, A = 0.6, 0.2, 0.3                          # f, c, a of the masonry
ZF, QL = 4.5, 20000.0 * 6.0                               # floor height [m], Q = q l [N]
QM = QL / G                                               # its mass [kg]
SITE = Site(ag=0.2 * G, F0=2.5, Tc_star=0.3, g=G)        # soil A, T1, q = 2, FC = 1.35


def _b1_floor(b1, e):
    return dataclasses.replace(b1, floors=(Floor(z=ZF, load=20000.0, eccentricity=e),))


# ----------------------------------------------------------------------------- overturning
@pytest.mark.parametrize("e", [0.1, 0.4])
def test_overturning_floors_reading_by_hand(b1, e):
    """The whole façade (W = γ l b H g = 529.74 kN) about its toe. Package: α₀ = (W b/2 +
    Q e)/(W H/2). Floors' reading: α₀ = (W b/2 + Q e)/(W H/2 + Q z_F), both smallest at
    h = H (checked on a grid of the hand formula below); M* = (m H/2 + q z_F)²/(m H²/3 +
    q z_F²) with q = Q/g, e* = M*/(m + q); lumped at G (= z_F = H/2) e* = 1 exactly."""
    m = GAMMA * L * B * H
    W = m * G
    alpha_own = (W * B / 2 + QL * e) / (W * H / 2)
    alpha_q = (W * B / 2 + QL * e) / (W * H / 2 + QL * ZF)
    # the hand multipliers over the top part of height h (floor on it where h > H − z_F)
    hs = np.linspace(0.25, H, 3601)
    wh = GAMMA * L * B * hs * G
    on = hs > H - ZF
    own = (wh * B / 2 + on * QL * e) / (wh * hs / 2)
    pushed = (wh * B / 2 + on * QL * e) / (wh * hs / 2 + on * QL * (hs - (H - ZF)))
    assert own.argmin() == pushed.argmin() == hs.size - 1       # both at h = H
    M_q = (m * H / 2 + QM * ZF) ** 2 / (m * H ** 2 / 3 + QM * ZF ** 2)
    e_q = M_q / (m + QM)
    if e == 0.1:       # the printed digits of the hand computation
        assert (alpha_own, alpha_q, e_q) == pytest.approx((0.0605895, 0.0493992, 0.786306),
                                                          rel=1e-5)

    sm = real.real_mechanism(_b1_floor(b1, e), "overturning").static_mechanism
    own_c = linear_kinematic("overturning", sm, SITE, H)
    q_c = linear_kinematic("overturning", sm.floor_reading, SITE, H)
    assert own_c.alpha0 == pytest.approx(alpha_own, rel=1e-9)
    assert own_c.e_star == pytest.approx(0.75, rel=1e-9) and own_c.m_floors == 0.0
    assert q_c.alpha0 == pytest.approx(alpha_q, rel=1e-9)
    assert q_c.Z == pytest.approx(0.0, abs=1e-9)
    assert q_c.m == pytest.approx(m + QM, rel=1e-9) and q_c.m_floors == pytest.approx(QM)
    assert q_c.M_star == pytest.approx(M_q, rel=1e-9)
    assert q_c.e_star == pytest.approx(e_q, rel=1e-9)
    assert q_c.e_star_lumped == pytest.approx(1.0, rel=1e-12)
    a0 = alpha_q * G / (e_q * 1.35)
    demand = 0.2 * G / 2.0                     # ground: a_g S/q, S = 1
    assert q_c.a0_star == pytest.approx(a0, rel=1e-9)
    assert q_c.demand == pytest.approx(demand, rel=1e-14) and q_c.demand_height is None
    assert q_c.ratio == pytest.approx(a0 / demand, rel=1e-9)
    assert own_c.ratio == pytest.approx(alpha_own * G / (0.75 * 1.35) / demand, rel=1e-9)


# ----------------------------------------------------------------------------- mechanism I
def _I_terms():
    """a/g(h) = N(h)/D(h) of mechanism I over a top part of height h carrying the floor
    (h > H − z_F), floors' reading: N = A h + C h³ + Q e, D = Bq h² + Q (h − (H − z_F)),
    A = γ l b g b/2 (gravity about the toe), C = g γ s f c/(6a) (eq. 9's friction moment
    at θ = 0: g γ s f c h³/(6a)), Bq = γ l b g/2."""
    return GAMMA * L * B * G * B / 2, G * GAMMA * S * F_FRICTION * C / (6 * A), \
        GAMMA * L * B * G / 2


def _I_hand(e):
    """The floors' reading's smallest a/g of mechanism I by hand: the stationary point of
    N/D above the floor (N'D − N D' = 0, by brentq to 1e-15), against the part just below
    the floor (no floor on it: 1/λ + α²λ/(3ρ) at λ = 9, = 0.211111). Returns (α₀, h)."""
    Ac, Cc, Bc = _I_terms()
    z1 = H - ZF

    def N(h):
        return Ac * h + Cc * h ** 3 + QL * e

    def D(h):
        return Bc * h * h + QL * (h - z1)

    def dfd(h):
        return (Ac + 3 * Cc * h * h) * D(h) - N(h) * (2 * Bc * h + QL)

    below = 1 / 9 + 0.4 * 9 / 36            # h = 4.5: λ = 9, the floor at the hinge
    if dfd(z1 + 1e-9) < 0 < dfd(H):
        h = brentq(dfd, z1 + 1e-9, H, xtol=1e-15, rtol=1e-15)
        if N(h) / D(h) < below:
            return N(h) / D(h), h
    return below, z1


def test_mechanism_I_floors_reading_moves_the_body_by_hand(b1):
    """e = 0.1 m: the floors' reading's a/g has its minimum above the floor, at h = 6.47954 m
    (α₀ = 0.193640, against the package's 0.211111 at h = 4.5 m just below the floor): the
    body λ = h/b carries the floor at z_Q = h − 4.5 above its hinge, with
    M* = (m h/2 + q z_Q)²/(m h²/3 + q z_Q²), m = γ l b h, q = Q/g, e* = M*/(m + q),
    lumped e* = (m h/2 + q z_Q)²/((m (h/2)² + q z_Q²)(m + q)). The hinge at Z = H − h."""
    alpha_q, h = _I_hand(0.1)
    assert (alpha_q, h) == pytest.approx((0.1936402, 6.479539), rel=1e-6)
    sm = real.real_mechanism(_b1_floor(b1, 0.1), "detachment").static_mechanism
    assert sm.alpha0 == pytest.approx(1 / 9 + 0.1, rel=1e-9)          # own: h = 4.5
    c = linear_kinematic("I", sm.floor_reading, SITE, H)
    assert c.alpha0 == pytest.approx(alpha_q, rel=1e-9)
    h_pkg = H - c.Z
    assert h_pkg == pytest.approx(h, rel=1e-8)      # golden search on a flat minimum

    def hand(hh):
        m, zq = GAMMA * L * B * hh, hh - (H - ZF)
        M = (m * hh / 2 + QM * zq) ** 2 / (m * hh ** 2 / 3 + QM * zq ** 2)
        lump = (m * hh / 2 + QM * zq) ** 2 / (m * hh ** 2 / 4 + QM * zq ** 2) / (m + QM)
        return M, M / (m + QM), lump

    M, e, lump = hand(h_pkg)
    assert (c.M_star, c.e_star, c.e_star_lumped) == pytest.approx((M, e, lump), rel=1e-12)
    assert (c.M_star, c.e_star) == pytest.approx(hand(h)[:2], rel=1e-8)
    assert e == pytest.approx(0.7453, rel=1e-3)
    Z = H - h_pkg
    T1 = 0.05 * H ** 0.75                             # 0.2598 s: on the plateau
    height = 0.2 * G * 2.5 * (Z / H) * 1.0 / 2.0      # S_e ψ γ / q, γ = 1
    assert c.first_period == pytest.approx(T1, rel=1e-14)
    assert c.demand == pytest.approx(max(height, 0.2 * G / 2), rel=1e-12)
    assert c.ratio == pytest.approx(alpha_q * G / (e * 1.35) / c.demand, rel=1e-9)


def test_mechanism_I_floors_reading_keeps_the_body_below_the_floor_by_hand(b1):
    """e = 0.4 m: the floor's larger restoring moment keeps the smallest a/g below it in both
    readings (h = 4.5 m, λ = 9, 1/λ + α²λ/(3ρ) = 0.211111): no floor on the body, e* = 3/4."""
    alpha_q, h = _I_hand(0.4)
    assert (alpha_q, h) == (pytest.approx(1 / 9 + 0.1, rel=1e-15), H - ZF)
    sm = real.real_mechanism(_b1_floor(b1, 0.4), "detachment").static_mechanism
    c = linear_kinematic("I", sm.floor_reading, SITE, H)
    assert c.alpha0 == pytest.approx(alpha_q, rel=1e-9)
    assert c.m_floors == 0.0 and c.e_star == pytest.approx(0.75, rel=1e-12)
    assert c.Z == pytest.approx(ZF, rel=1e-9)


# ----------------------------------------------------------------------------- the run
B1_FLOOR = toml(b1_dict("B1-floor", 
                       analysis={"fe": False, "hinge_check": False, "overturning": True},
                       output={"png": False, "vtu": False},
                       floor=[{"z": 4.5, "load": 20000.0, "eccentricity": 0.1}],
                       site={"ag": 1.962, "F0": 2.5, "Tc_star": 0.3}))


def test_run_prints_and_writes_the_floors_reading(tmp_path):
    case = tmp_path / "b1.toml"
    case.write_text(B1_FLOOR)
    res = CliRunner().invoke(app, ["run", str(case), "--out", str(tmp_path / "o")])
    assert res.exit_code == 0, res.output
    assert "beside it, the floors' Q_k reading" in res.stdout
    d = json.loads((tmp_path / "o" / "summary.json").read_text())
    fl = d["code_check"]["floors_Qk"]
    assert set(fl["mechanisms"]) == {"I", "II", "overturning"}
    m = GAMMA * L * B * H
    alpha_q = (m * G * B / 2 + QL * 0.1) / (m * G * H / 2 + QL * ZF)
    e_q = (m * H / 2 + QM * ZF) ** 2 / (m * H ** 2 / 3 + QM * ZF ** 2) / (m + QM)
    over = fl["mechanisms"]["overturning"]
    assert over["alpha0"] == pytest.approx(alpha_q, rel=1e-9)
    assert over["ratio"] == pytest.approx(alpha_q * G / (e_q * 1.35) / 0.981, rel=1e-9)
    assert fl["governing"] == "overturning" and fl["not_computed"] == []
    assert d["code_check"]["mechanisms"]["overturning"]["m_floors"] == 0.0
    assert d["units"]["results"]["m_floors"] == "kg"
    assert None not in d["units"]["results"].values()


def test_without_floors_the_readings_are_one_and_the_run_says_so():
    d = tomllib.loads(B1_FLOOR)
    del d["floor"]
    res = pipeline.compute(load_case(d))
    cc = res.code_check
    assert cc.floors == cc.checks
    assert "the case has no floors, the same as above" in res.summary()
    assert math.isfinite(res.to_dict()["code_check"]["floors_Qk"]["ratio"])
