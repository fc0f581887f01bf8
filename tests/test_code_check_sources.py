"""The code check against the one public example with printed digits that the searches found
(docs/code-check.md, "A second source"): the tests of an unreviewed open-source masonry
package, dancarloni/RD2229, tests/test_cinematica_muratura.py (its linear kinematic analysis
in src/methods/muratura/cinematica.py, citing Circolare 2019 §C8A.4.1). It is not a guideline
or a textbook; its printed numbers are few and simple, and they are reproduced here to their
printed digits, with the package's own formulas (not RD2229's code).

Its wall: h = 300 cm, t = 30 cm, L = 400 cm, γ = 0.0018 kg/cm³ (1800 kg/m³), turning about its
base (the simple overturning), its sites given by a_g/g, S, q, FC. Printed: α₀ = t/h = 0.1;
a₀* = 0.1/(0.75 × 1.35) "≈ 0.0988" g at FC = 1.35 and "≈ 0.133" g at FC = 1.0 (e* = 0.75,
"per distribuzione lineare"); the ground demand a_g S/q = 0.05 × 1.0/2.0 = 0.025 g. With a
load N_s on the top (500 kg/m over L = 400 cm: 2000 kg at mid-thickness) its α₀ pushes the
load horizontally, (W t/2 + N_s t/2)/(W h/2 + N_s h): the floors' Q_k reading here, not the
package's own."""

from __future__ import annotations

import dataclasses

import pytest

from homlimit.check import Site, linear_kinematic, nonlinear_kinematic
from homlimit.closed_form import real
from homlimit.params import Case, Floor, Masonry, Wall

G = 9.81
WALL = Case(wall=Wall(H=3.0, L=4.0, s=0.3, b=0.3, l=4.0, gamma=1800.0, g=G),
            masonry=Masonry(a=0.3, c=0.2, f=0.6), name="RD2229 parete_tipo")


def _check(case, FC, ag_g=0.05):
    sm = real.real_mechanism(case, "overturning").static_mechanism
    site = Site(ag=ag_g * G, F0=2.5, Tc_star=0.3, soil="A", topography="T1", q=2.0, FC=FC,
                g=G)
    return sm, linear_kinematic("overturning", sm, site, case.wall.H)


def test_rd2229_wall_to_its_printed_digits():
    for FC, printed in ((1.35, 0.0988), (1.0, 0.133)):
        sm, c = _check(WALL, FC)
        assert c.alpha0 == pytest.approx(0.1, rel=1e-9)               # "= 0.1"
        assert c.e_star == pytest.approx(0.75, rel=1e-12)
        assert c.Z == pytest.approx(0.0, abs=1e-9)                     # "a terra"
        assert round(c.a0_star / G, 3 if FC == 1.0 else 4) == printed
        assert c.demand / G == pytest.approx(0.025, rel=1e-12)          # "= 0.025"
        assert c.passes                                                 # "verificata"


def test_rd2229_top_load_is_the_floors_reading():
    """The package's floor at the top, q = 500 kgf/m = 4905 N/m at e = t/2: its own α₀ keeps
    the load vertical, (W t/2 + N t/2)/(W h/2) = 0.130864; the floors' reading pushes it too,
    (W t/2 + N t/2)/(W h/2 + N h) = 0.0809160, RD2229's formula (its test prints the formula;
    these digits are the hand evaluation here, with W = 6480 kgf, N = 2000 kgf)."""
    case = dataclasses.replace(WALL, floors=(Floor(z=3.0, load=500 * G, eccentricity=0.15),))
    W, N = 300 * 30 * 400 * 0.0018, 500 * 400 / 100
    own = (W * 15 + N * 15) / (W * 150)
    pushed = (W * 15 + N * 15) / (W * 150 + N * 300)
    assert (own, pushed) == pytest.approx((0.130864, 0.0809160), rel=1e-5)
    sm, c = _check(case, 1.35)
    assert sm.alpha0 == pytest.approx(own, rel=1e-9)
    assert sm.floor_reading.alpha0 == pytest.approx(pushed, rel=1e-9)
    # RD2229 keeps e* = 0.75 with the load; the transcription's C8.7.1.5 sums it:
    # e* = (m h/2 + n h)²/((m + n)(m h²/3 + n h²)), m = 6480, n = 2000 kg
    cq = linear_kinematic("overturning", sm.floor_reading, Site(ag=0.05 * G, F0=2.5,
                                                                Tc_star=0.3, g=G), 3.0)
    e_q = (W * 1.5 + N * 3.0) ** 2 / ((W + N) * (W * 3.0 + N * 9.0))
    assert cq.e_star == pytest.approx(e_q, rel=1e-9)
    assert e_q == pytest.approx(247118400 / 317491200, rel=1e-12)     # 0.778348


def test_rd2229_nonlinear_d0_star_of_the_simple_overturning():
    """RD2229 takes d₀* = 2t/3 for every mechanism; for the simple overturning of a uniform
    block it is exact (G's displacement t/2 at θ₀ = atan(t/h), times J_z/(m z_G²) = 4/3). Its
    tests print d₀* = 30 × 2/3 = 20 cm (t = 30 cm) and "d*_u = 0.4 × 60 × 2/3 = 16 cm" (t =
    60 cm). (Its T_s = 2π √(d₀*/a₀*) and its demand are its own: not compared.)"""
    for t, d0, du in ((0.3, 0.20, None), (0.6, None, 0.16)):
        case = dataclasses.replace(WALL, wall=dataclasses.replace(WALL.wall, b=t))
        sm, c = _check(case, 1.35)
        nl = nonlinear_kinematic(c, sm, Site(ag=0.05 * G, F0=2.5, Tc_star=0.3, g=G))
        if d0 is not None:
            assert round(nl.d0_star, 2) == d0 and nl.d0_star == pytest.approx(2 * t / 3)
        if du is not None:
            assert round(nl.du_star, 2) == du
