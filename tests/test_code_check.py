"""The code check (NTC 2018 / Circolare 2019 §C8.7.1.2, docs/code-check.md) against hand
computations written here: the elastic spectrum at its corners, the soil and topography
tables, the participating mass of a rigid block, α₀ of a block, and B1's mechanism I at a
chosen site. Closed forms only: no FE solve."""

from __future__ import annotations

import dataclasses
import json
import math
import tomllib

import numpy as np
import pytest
from typer.testing import CliRunner

from homlimit.app import pipeline, registry
from homlimit.app.cli import app
from homlimit.app.code_check import code_check
from homlimit.app.config import load_case
from homlimit.app.pipeline import Result, compute
from homlimit.check import Site, StaticMechanism, linear_kinematic, participation, soil_factors
from homlimit.closed_form import real
from homlimit.closed_form.mechanisms import mechanism_I, mechanism_II
from homlimit.errors import ParameterError
from homlimit.impulse import RigidBody
from homlimit.params import Floor, Tie

G = 9.81
B1_TEXT = """name = "B1-site"
[wall]
H = 9.0
L = 6.0
s = 0.5
b = 0.5
l = 6.0
[masonry]
a = 0.3
c = 0.2
f = 0.6
[analysis]
fe = false
hinge_check = false
[output]
png = false
vtu = false
"""
SITE = "[site]\nag = 1.962\nF0 = 2.5\nTc_star = 0.3\n"


# ----------------------------------------------------------------------------- the spectrum
def test_elastic_spectrum_at_its_corners_by_hand():
    """a_g = 0.25 g, F0 = 2.4, Tc* = 0.35 s, soil B, topography T2, by hand (NTC 2018
    Tab. 3.2.IV, 3.2.V, eq. 3.2.2 with η = 1)."""
    ag = 0.25 * G
    s = Site(ag=ag, F0=2.4, Tc_star=0.35, soil="B", topography="T2", g=G)
    S_S = 1.40 - 0.40 * 2.4 * 0.25            # 1.16, inside [1.00, 1.20]
    C_C = 1.10 * 0.35 ** -0.20
    S = S_S * 1.2
    T_C = C_C * 0.35
    T_B, T_D = T_C / 3, 4.0 * 0.25 + 1.6
    assert s.S_S == pytest.approx(1.16, rel=1e-14) and s.S == pytest.approx(S, rel=1e-14)
    assert s.periods == pytest.approx((T_B, T_C, T_D), rel=1e-14)
    assert T_C == pytest.approx(0.474946, rel=1e-5)      # 1.1 × 1.233630 × 0.35
    plateau = ag * S * 2.4
    cases = {0.0: ag * S,                                 # the PGA at T = 0
             T_B / 2: ag * S * (0.5 * 2.4 + 0.5),         # halfway up the first branch
             T_B: plateau, (T_B + T_C) / 2: plateau, T_C: plateau,
             1.0: plateau * T_C / 1.0, T_D: plateau * T_C / T_D,
             3.0: plateau * T_C * T_D / 9.0}
    for T, want in cases.items():
        assert s.Se(T) == pytest.approx(want, rel=1e-13), T
    assert np.allclose(s.Se(list(cases)), list(cases.values()), rtol=1e-13, atol=0)
    assert plateau == pytest.approx(8.193312, rel=1e-6)   # 2.4525 × 1.392 × 2.4
    # the impulse view's PGV, NTC 2018 §3.2.3.3: v_g = 0.16 a_g S T_C
    assert s.pgv() == pytest.approx(0.16 * ag * S * T_C, rel=1e-14)
    assert s.pgv() == pytest.approx(0.259427, rel=1e-5)   # 0.16 × 2.4525 × 1.392 × 0.474949


def test_the_spectrum_has_eurocode_8s_shape_at_F0_2_5():
    """A second form: EN 1998-1 §3.2.2.2 (eqs 3.2–3.5) writes the same spectrum as
    a_g S [1 + T/T_B (2.5 η − 1)], a_g S 2.5 η, ... T_C/T, ... T_C T_D/T²; with F₀ = 2.5 the
    two agree on every branch (soil C, a_g = 0.3 g: S = 1.25, its own T_B, T_C, T_D)."""
    s = Site(ag=0.3 * G, F0=2.5, Tc_star=0.4, soil="C", g=G)
    T_B, T_C, T_D = s.periods
    ag, S = 0.3 * G, 1.70 - 0.60 * 2.5 * 0.3

    def ec8(T):
        if T < T_B:
            return ag * S * (1 + T / T_B * (2.5 - 1))
        if T < T_C:
            return ag * S * 2.5
        return ag * S * 2.5 * (T_C / T if T < T_D else T_C * T_D / T ** 2)

    for T in np.linspace(0.0, 4.0, 81):
        assert s.Se(T) == pytest.approx(ec8(T), rel=1e-13), T


@pytest.mark.parametrize("soil, ag_g, F0, Tc, S_S, C_C", [
    ("A", 0.30, 2.5, 0.30, 1.0, 1.0),
    ("B", 0.05, 2.5, 0.30, 1.20, 1.10 * 0.30 ** -0.20),     # 1.35 clipped to 1.20
    ("C", 0.40, 3.0, 0.50, 1.00, 1.05 * 0.50 ** -0.33),     # 0.98 clipped to 1.00
    ("C", 0.20, 2.5, 0.30, 1.40, 1.05 * 0.30 ** -0.33),
    ("D", 0.35, 2.5, 0.40, 1.0875, 1.25 * 0.40 ** -0.50),
    ("D", 0.05, 2.5, 0.40, 1.80, 1.25 * 0.40 ** -0.50),     # 2.2125 clipped to 1.80
    ("D", 0.50, 2.5, 0.40, 0.90, 1.25 * 0.40 ** -0.50),     # 0.525 clipped to 0.90
    ("E", 0.20, 2.5, 0.30, 1.45, 1.15 * 0.30 ** -0.40),
])
def test_soil_factors_from_the_table(soil, ag_g, F0, Tc, S_S, C_C):
    got = soil_factors(soil, ag_g, F0, Tc)
    assert got == pytest.approx((S_S, C_C), rel=1e-12)


def test_topography_factors():
    got = [Site(ag=1.0, F0=2.5, Tc_star=0.3, topography=t).S_T for t in ("T1", "T2", "T3", "T4")]
    assert got == [1.0, 1.2, 1.2, 1.4]


def test_first_period_and_the_demand_at_height_by_hand():
    s = Site(ag=2.0, F0=2.5, Tc_star=0.3, soil="A", storeys=3, building_height=12.0, g=G)
    T1 = 0.05 * 12 ** 0.75                    # 0.32237 s: past T_C = 0.3 s (soil A)
    assert s.first_period(9.0) == pytest.approx(T1, rel=1e-14)
    d, Se, psi, gam = s.demand_height(6.0, 9.0)
    Se_hand = 2.0 * 2.5 * 0.3 / T1            # 4.65302 m/s², the 1/T branch
    assert (Se, psi, gam) == pytest.approx((Se_hand, 0.5, 9 / 7), rel=1e-14)
    assert Se == pytest.approx(4.65302, rel=1e-6)
    assert d == pytest.approx(Se_hand * 0.5 * 9 / 7 / 2.0, rel=1e-14)
    assert Site(ag=2.0, F0=2.5, Tc_star=0.3, T1=1.2, g=G).first_period(9.0) == 1.2
    with pytest.raises(ParameterError, match=r"Z = 13.0 m is out of range: allowed 0 <= Z"):
        s.demand_height(13.0, 9.0)


# ----------------------------------------------------------------------------- the mechanism
def _rectangle(b, h, z0=0.0):
    pts = np.array([[0, z0], [b, z0], [b, z0 + h], [0, z0 + h]], float)
    return pts, np.array([[0, 1, 2], [0, 2, 3]])


def test_participating_mass_of_a_rigid_block_about_its_toe():
    """δx ∝ z: M* = (∫z dm)²/∫z² dm = m (h/2)²/(h²/3) = 3m/4, e* = 0.75, for any b, h."""
    for b, h, rho in ((0.5, 9.0, 2000.0), (1.3, 2.1, 1800.0), (2.0, 0.7, 1.0)):
        pts, tri = _rectangle(b, h, z0=4.0)
        body = RigidBody.from_triangles(pts, tri, rho, O=(0.0, 4.0))
        m = rho * b * h
        assert body.J_z == pytest.approx(m * h * h / 3, rel=1e-13)
        M, e = participation(body)
        assert M == pytest.approx(0.75 * m, rel=1e-13) and e == pytest.approx(0.75, rel=1e-13)


def test_J_z_out_of_range_and_missing():
    with pytest.raises(ParameterError, match=r"J_z = 1.0 kg m\^2 is out of range"):
        RigidBody(m=1.0, x_G=0.5, z_G=2.0, I_O=6.0, J_z=1.0)     # < m z_G² = 4
    with pytest.raises(ParameterError, match=r"J_z = nan is out of range"):
        participation(RigidBody(m=1.0, x_G=0.5, z_G=2.0, I_O=6.0))


def test_alpha0_of_a_rigid_block_is_b_over_h(b1):
    """The simple overturning of B1 (no ties, floors, f_c): the whole façade, a/g = b/H."""
    m = real.real_mechanism(b1, "overturning")
    sm = m.static_mechanism
    assert sm.alpha0 == pytest.approx(0.5 / 9.0, rel=1e-9)
    assert sm.z_hinge == pytest.approx(0.0, abs=1e-9)
    assert sm.body.m == pytest.approx(2000 * 6 * 0.5 * 9, rel=1e-12)
    assert participation(sm.body)[1] == pytest.approx(0.75, rel=1e-12)


def test_mechanism_II_participation_integrals_against_a_triangulation(b1):
    """Strip (b × h, γ l) + wedge (width z tan ψ at height z, γ s) integrated by
    ``from_triangles``: the closed forms' m, z_G, I_O and J_z of II's two bodies."""
    m2 = mechanism_II(b1)
    t, b = m2.tanpsi, 0.5
    for body, h in ((m2.body, m2.h), (m2.static_body, m2.lam_multiplier * b)):
        strip, tri = _rectangle(b, h)
        wedge = np.array([[b, 0.0], [b, h], [b + t * h, h]])
        ref = RigidBody.from_triangles(np.vstack([strip, wedge]),
                                       np.vstack([tri, [[4, 5, 6]]]),
                                       [2000 * 6.0, 2000 * 6.0, 2000 * 0.5])
        for k in ("m", "x_G", "z_G", "I_O", "J_z"):
            assert getattr(body, k) == pytest.approx(getattr(ref, k), rel=1e-12), k
    assert m2.static_z0 == pytest.approx(9.0 - m2.lam_multiplier * b, rel=1e-14)


def test_B1_mechanism_I_worked_example_by_hand(b1):
    """B1 (ρ = 12, α² = cf/a = 0.4), a_g = 0.2 g, F0 = 2.5, Tc* = 0.3 s, soil A, T1, q = 2,
    FC = 1.35, a one-storey building of the wall's height 9 m, base on the ground.

    Mechanism I's a/g = 1/λ + α²λ/(3ρ) is smallest at λ = √(3ρ)/α = 6/√0.4 = 9.4868, where
    α₀ = 2α/√(3ρ) = 0.210819; the strip b × h turns about its toe: e* = 3/4. Its hinge is at
    Z = 9 − 0.5 λ = 4.25658 m. T1 = 0.05 × 9^0.75 = 0.2598 s lies on the plateau
    (T_B = 0.1, T_C = 0.3 s): S_e = a_g F0 = 4.905 m/s²; ψ = Z/9, γ = 3/3 = 1.
    a₀* = 0.210819 × 9.81/(0.75 × 1.35) = 2.04260 m/s²; at height 4.905 × 0.472954/2 =
    1.15992 m/s² > a_g/q = 0.981: ratio 1.76098 (e* = 1: 1.53195/1.15992 = 1.32074).
    """
    alpha0 = 2 * math.sqrt(0.4) / 6
    lam = 6 / math.sqrt(0.4)
    Z = 9 - 0.5 * lam
    a0 = alpha0 * G / (0.75 * 1.35)                      # 2.04260 m/s²
    ground = 0.2 * G / 2                                 # 0.981 m/s²
    height = 0.2 * G * 2.5 * (Z / 9) * 1 / 2             # 1.15994 m/s²
    site = Site(ag=0.2 * G, F0=2.5, Tc_star=0.3, g=G)
    c = linear_kinematic("I", mechanism_I(b1).static_mechanism, site, 9.0)
    assert c.alpha0 == pytest.approx(alpha0, rel=1e-9)
    assert c.e_star == pytest.approx(0.75, rel=1e-12)
    assert c.M_star == pytest.approx(0.75 * 2000 * 6 * 0.5 * 0.5 * lam, rel=1e-6)
    assert c.Z == pytest.approx(Z, rel=1e-6)
    assert c.a0_star == pytest.approx(a0, rel=1e-9)
    assert c.demand_ground == pytest.approx(ground, rel=1e-14)
    assert c.demand_height == pytest.approx(height, rel=1e-6)
    assert c.demand == c.demand_height
    assert c.ratio == pytest.approx(a0 / height, rel=1e-6)
    assert c.ratio == pytest.approx(1.76098, rel=1e-5)
    assert c.a0_star_lumped == pytest.approx(alpha0 * G / 1.35, rel=1e-9)
    assert c.ratio_lumped == pytest.approx(1.32074, rel=1e-5)


def test_B1_mechanism_I_with_a_tie_by_hand(b1):
    """B1 with a tie at the top, T_y = 2 kN/m (a bay of l = 6 m: 12 kN), rigid-plastic: the
    resisting moment gains T_y l h, so a/g = 1/λ + α²λ/(3ρ) + T_y l h/(m g h/2) with
    m = γ l b h (docs/real-walls.md); e* stays 3/4 (the tie adds no mass)."""
    case = dataclasses.replace(b1, ties=(Tie(z=9.0, yield_force=2000.0),))
    m = real.real_mechanism(case, "detachment")
    sm = m.static_mechanism

    def hand(lam):
        h = 0.5 * lam
        mass = 2000 * 6 * 0.5 * h
        return 1 / lam + 0.4 * lam / 36 + 2000 * 6 * h / (mass * G * h / 2)

    lam = m.lam_multiplier
    assert sm.alpha0 == pytest.approx(hand(lam), rel=1e-12)
    assert hand(lam) <= min(hand(lam * 0.99), hand(min(lam * 1.01, 18.0))) * (1 + 1e-12)
    assert participation(sm.body)[1] == pytest.approx(0.75, rel=1e-12)
    assert sm.z_hinge == pytest.approx(9 - 0.5 * lam, rel=1e-12)


# ----------------------------------------------------------------------------- the door
def test_run_prints_the_code_check_and_writes_it(tmp_path):
    case = tmp_path / "b1.toml"
    case.write_text(B1_TEXT + SITE)
    res = CliRunner().invoke(app, ["run", str(case), "--out", str(tmp_path / "o")])
    assert res.exit_code == 0, res.output
    assert "code check, linear kinematic analysis" in res.stdout
    d = json.loads((tmp_path / "o" / "summary.json").read_text())
    cc = d["code_check"]
    assert set(cc["mechanisms"]) == {"I", "II"}
    assert cc["mechanisms"]["I"]["ratio"] == pytest.approx(1.76098, rel=1e-5)
    assert d["inputs"]["site"]["ag"] == 1.962 and d["units"]["results"]["a0_star"] == "m/s^2"
    assert cc["governing"] in ("I", "II") and cc["not_checked"] == []
    assert None not in d["units"]["results"].values()
    # the impulse view: soil A, T1: S = 1, T_C = T_C* = 0.3 s, PGV = 0.16 × 1.962 × 0.3
    pgv = 0.16 * 1.962 * 1.0 * 0.3
    assert cc["site"]["pgv"] == pytest.approx(pgv, rel=1e-14)
    for k in ("I", "II"):
        vg = d["mechanisms"][k]["vg"]
        assert cc["impulse"][k] == {"vg": vg, "vg_over_pgv": pytest.approx(vg / pgv, rel=1e-14)}
    assert "impulse view: site PGV = 0.16 a_g S T_C = 0.09418 m/s" in res.stdout


def test_run_without_site_says_so(tmp_path):
    cfg = load_case(tomllib.loads(B1_TEXT))
    assert cfg.site is None and "site" not in cfg.as_dict()
    result = compute(cfg)
    assert result.code_check is None
    assert "none, the case has no [site] section" in result.summary()
    assert result.to_dict()["code_check"] is None


BAD_SITE = {
    "ag negative": ("ag = -1.0\nF0 = 2.5\nTc_star = 0.3\n",
                    "[site] ag = -1.0 m/s² is out of range: allowed 0 < ag <= 20 m/s²"),
    "F0 small": ("ag = 1.0\nF0 = 1.5\nTc_star = 0.3\n",
                 "[site] F0 = 1.5 is out of range: allowed 2.2 <= F0 <= 5"),
    "soil": ("ag = 1.0\nF0 = 2.5\nTc_star = 0.3\nsoil = \"F\"\n",
             "[site] soil = 'F' is not allowed: allowed one of 'A', 'B', 'C', 'D', 'E'"),
    "topography": ("ag = 1.0\nF0 = 2.5\nTc_star = 0.3\ntopography = \"T5\"\n",
                   "[site] topography = 'T5' is not allowed: allowed one of 'T1', 'T2', "
                   "'T3', 'T4'"),
    "q": ("ag = 1.0\nF0 = 2.5\nTc_star = 0.3\nq = 0.5\n",
          "[site] q = 0.5 is out of range: allowed 1 <= q <= 4"),
    "FC": ("ag = 1.0\nF0 = 2.5\nTc_star = 0.3\nFC = 0.9\n",
           "[site] FC = 0.9 is out of range: allowed 1 <= FC <= 2"),
    "storeys": ("ag = 1.0\nF0 = 2.5\nTc_star = 0.3\nstoreys = 0\n",
                "[site] storeys = 0 is out of range: allowed 1 <= storeys <= 200"),
    "missing ag": ("F0 = 2.5\nTc_star = 0.3\n", "[site] ag is missing"),
    "building too low": ("ag = 1.0\nF0 = 2.5\nTc_star = 0.3\nz_base = 3.0\n"
                         "building_height = 10.0\n",
                         "[site] building_height = 10.0 m is out of range: allowed 0 (the "
                         "wall's top) or building_height >= z_base + H = 12 m"),
}


@pytest.mark.parametrize("kind", sorted(BAD_SITE))
def test_bad_site_exits_2_with_the_message(tmp_path, kind):
    text, message = BAD_SITE[kind]
    case = tmp_path / "bad.toml"
    case.write_text(B1_TEXT + "[site]\n" + text)
    res = CliRunner().invoke(app, ["run", str(case), "--out", str(tmp_path / "o")])
    assert res.exit_code == 2, res.output
    assert message in res.stderr, res.stderr
    assert "Traceback" not in res.stderr
    assert not (tmp_path / "o").exists()


def test_the_stage_takes_the_registry_entry_or_the_mechanism_or_skips(tmp_path):
    """A registered mechanism's ``static_of`` wins (the FE path's whole wall); else the
    object's ``static_mechanism``; a mechanism with neither is listed as not checked."""
    cfg = load_case(tomllib.loads(B1_TEXT + SITE))
    block = RigidBody(m=3.0, x_G=0.25, z_G=1.0, I_O=3 * (0.5 ** 2 + 2 ** 2) / 3,
                      J_z=3 * 2 ** 2 / 3)               # a 0.5 × 2 block about its toe
    sm = StaticMechanism(0.25, block, 1.0, "toy")

    class Own:
        static_mechanism = StaticMechanism(0.5, block, 0.0, "own")

    with registry.registered(registry.Mechanism("toy", model="toy", static_of=lambda r: sm)):
        res = Result(config=cfg, mechanisms={"toy": Own(), "other": Own(), "none": object()})
        cc = code_check(res)
    assert cc.checks["toy"].alpha0 == 0.25 and cc.checks["toy"].Z == 1.0
    assert cc.checks["other"].alpha0 == 0.5 and cc.checks["other"].Z == 0.0
    assert cc.checks["toy"].e_star == pytest.approx(0.75, rel=1e-14)
    assert list(cc.skipped) == ["none"]
    assert cc.governing.name == "toy"          # α₀ = 0.25 at Z = 1 m: the smaller ratio


def test_B1_overturning_with_a_floor_and_a_tie_by_hand(b1):
    """B1's simple overturning with a floor on the top (q = 20 kN/m at e = 0.1 m from the
    outer face) and a rigid-plastic tie at the top (T_y = 2 kN/m), a bay of l = 6 m: about
    the toe, a/g(h) = [m g b/2 + Q e + T_y l h]/(m g h/2), m = γ l b h, falls with h, so the
    whole façade (h = H = 9 m) activates first:
    α₀ = b/H + 2 Q e/(m g H) + 2 T_y l/(m g) = 0.055556 + 0.005034 + 0.045305 = 0.105895."""
    case = dataclasses.replace(b1, ties=(Tie(z=9.0, yield_force=2000.0),),
                               floors=(Floor(z=9.0, load=20000.0, eccentricity=0.1),))
    m = 2000 * 6 * 0.5 * 9
    alpha0 = 0.5 / 9 + 2 * 20000 * 6 * 0.1 / (m * G * 9) + 2 * 2000 * 6 / (m * G)
    assert alpha0 == pytest.approx(0.105895, rel=1e-5)
    sm = real.real_mechanism(case, "overturning").static_mechanism
    assert sm.alpha0 == pytest.approx(alpha0, rel=1e-9)
    assert sm.body.m == pytest.approx(m, rel=1e-9)       # the floor's mass is not the body's
    site = Site(ag=0.15 * G, F0=2.5, Tc_star=0.3, FC=1.2, g=G)
    c = linear_kinematic("overturning", sm, site, 9.0)
    assert c.e_star == pytest.approx(0.75, rel=1e-9)
    assert c.a0_star == pytest.approx(alpha0 * G / (0.75 * 1.2), rel=1e-9)
    assert c.demand_height is None and c.demand == pytest.approx(0.15 * G / 2, rel=1e-14)
    assert c.ratio == pytest.approx(alpha0 / (0.75 * 1.2) / 0.075, rel=1e-9)   # 1.56881


def test_B1_mechanism_I_with_a_floor_by_hand(b1):
    """B1's mechanism I with a floor at mid-height (q = 20 kN/m, e = 0.1 m): where the body
    holds it (h > 4.5 m) a/g = 1/λ + α²λ/(3ρ) + Q e/(m g h/2); e* stays 3/4."""
    case = dataclasses.replace(b1, floors=(Floor(z=4.5, load=20000.0, eccentricity=0.1),))
    m = real.real_mechanism(case, "detachment")

    def hand(lam):
        h = 0.5 * lam
        mass = 2000 * 6 * 0.5 * h
        floor = 20000 * 6 * 0.1 / (mass * G * h / 2) if h > 4.5 else 0.0
        return 1 / lam + 0.4 * lam / 36 + floor

    lam = m.lam_multiplier
    sm = m.static_mechanism
    assert sm.alpha0 == pytest.approx(hand(lam), rel=1e-12)
    assert hand(lam) <= min(hand(lam * 0.99), hand(min(lam * 1.01, 18.0))) * (1 + 1e-12)
    c = linear_kinematic("I", sm, Site(ag=1.0, F0=2.5, Tc_star=0.3, g=G), 9.0)
    assert c.e_star == pytest.approx(0.75, rel=1e-12)
    assert c.a0_star == pytest.approx(hand(lam) * G / (0.75 * 1.35), rel=1e-12)


def test_code_check_png_sets_both_views_side_by_side(tmp_path):
    """With [site] and [output] png, code_check.png: a₀*/demand and v̄_g/PGV per mechanism (the
    overturning of B1 fails the acceleration check, 0.549, and passes the velocity one)."""
    d = tomllib.loads(B1_TEXT + SITE)
    d["analysis"]["overturning"] = True
    d["output"]["png"] = True
    res = pipeline.run(d, out=tmp_path / "o")
    png = tmp_path / "o" / "code_check.png"
    assert res.files["code_check_png"] == png and png.stat().st_size > 1000
    cc = res.to_dict()["code_check"]
    over = cc["mechanisms"]["overturning"]["ratio"], cc["impulse"]["overturning"]["vg_over_pgv"]
    assert over[0] < 1 < over[1]
    d["output"]["png"] = False
    assert "code_check_png" not in pipeline.run(d, out=tmp_path / "p").files
