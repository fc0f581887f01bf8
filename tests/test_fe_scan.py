"""The FE collapse velocity is set by the masonry (issue 13): the scan's range starts at one
course, its minimum is interior for the paper's bed-joint façade and sits on the bound for the
homogenised one, and the hinge's impulse ratio and holding pulse are those of eq. 4."""

import math

import pytest

from homlimit import mechanism_I, mechanism_II
from homlimit.dynamics import MechanismIRocker, RectangularPulse, RigidRocker, holding_pulse
from homlimit.dynamics.integrate import simulate
from homlimit.impulse import hinge_impulse_ratio
from homlimit.mechanism.analysis import (
    PART_TOL,
    analyse,
    fe_result,
    h_scan,
    part_problem,
    scan_midpoints,
)


@pytest.mark.slow
def test_scan_below_one_course_does_not_lower_the_bed_joint_minimum(table1_case):
    """B1, bed-joint façade: the minimum over heights is interior, and parts lower than one
    course (a/2, a/4: smaller than any block) give no lower v̄_g — the reported minimum is the
    mechanics', not the scan's bound. Such a part cannot rock on a bed joint inside it: its
    kinematic bound is Coulomb sliding on its base, λ⁺ = f (measured 0.600005 and 0.600004),
    four times the critical part's, and it has no rocking body, so no v̄_g."""
    case = table1_case("B1")
    res = fe_result(case, mesh_size=0.5, facade="bedjoints", heights=4)
    assert res.critical_at == "interior"
    a = case.masonry.a
    below = h_scan(case, [a / 2, a / 4], mesh_size=0.5, facade="bedjoints")
    for m in below:
        assert m.multiplier == pytest.approx(case.masonry.f, rel=1e-4), m.h_part
        assert m.multiplier > 3 * res.critical.multiplier
        assert m.kind == "distributed" and math.isnan(m.vg)


@pytest.mark.slow
def test_homogenised_facade_minimum_sits_on_the_one_course_bound(table1_case):
    """B1 with the homogenised façade (a crack may cut it diagonally: no internal length):
    the smallest part is critical, and the result says the bound sets it."""
    case = table1_case("B1")
    res = fe_result(case, mesh_size=0.5, facade="homogenised", heights=4)
    assert res.critical_at == "bound: one course"
    assert res.critical.h_part == pytest.approx(case.masonry.a)


def test_hinge_impulse_ratio_of_the_closed_forms_of_B1(table1_case):
    """|P_x/P_z| = (i − z_G²)/(x_G z_G) (eq. 4's hinge impulse) for B1: 3.44 (mechanism I)
    and 1.78 (II), as an independent prototype found (shared/design/mechanics.md), both above
    f = 0.6; for a free block b × h about its toe, i = (b² + h²)/3 and G = (b/2, h/2)."""
    case = table1_case("B1")
    assert hinge_impulse_ratio(mechanism_I(case).body) == pytest.approx(3.44, abs=0.005)
    assert hinge_impulse_ratio(mechanism_II(case).body) == pytest.approx(1.78, abs=0.005)
    from homlimit.impulse import RigidBody

    b, h, m = 0.5, 3.0, 1.0
    block = RigidBody(m=m, x_G=b / 2, z_G=h / 2, I_O=m * (b * b + h * h) / 3)
    i = (b * b + h * h) / 3
    assert hinge_impulse_ratio(block) == pytest.approx((i - h * h / 4) / (b * h / 4), rel=1e-14)


@pytest.mark.parametrize("mech", ["I", "II"])
def test_holding_pulse_is_the_shortest_overturning_pulse_at_f_g(table1_case, mech):
    """The shortest rectangular pulse of a_g = f g that overturns: just shorter is safe, it
    overturns, and it needs more than eq. 7's ideal impulse (a finite pulse always does)."""
    case = table1_case("B1")
    rk = (MechanismIRocker(case) if mech == "I"
          else RigidRocker(mechanism_II(case).body, g=case.wall.g))
    f, g = case.masonry.f, case.wall.g
    hp = holding_pulse(rk, f, rtol=1e-5)
    assert hp.pgv == pytest.approx(f * g * hp.duration, rel=1e-12)
    assert simulate(rk, RectangularPulse(f * g, hp.duration)).overturned
    assert not simulate(rk, RectangularPulse(f * g, hp.duration * (1 - 3e-5))).overturned
    assert 1.0 < hp.ratio < 1.5 and hp.ratio == pytest.approx(hp.pgv / rk.vg_impulse)


def test_no_holding_pulse_when_f_g_does_not_lift_the_body(table1_case):
    case = table1_case("B1")
    rk = RigidRocker(mechanism_II(case).body, g=case.wall.g)
    hp = holding_pulse(rk, 0.5 * rk.a_uplift / case.wall.g)
    assert math.isnan(hp.duration) and "slides first" in hp.reason


def test_scan_splits_a_wide_gap_whose_far_end_is_near_the_minimum():
    """The halved B2 scan (h_part [m], v̄_g/√(gb)): the old rule left the 1.12 m gap between
    1.96 and 3.08 m because 0.4722 is within 0.5 % of 0.4702, yet v̄_g is 0.4638 at 2.5 m.
    A gap is closed only when it is at most one step wide, or at most two and near."""
    hs = [1.440, 1.963, 3.083, 3.153]
    vg = [0.50661, 0.47220, 0.47015, 0.47172]
    assert scan_midpoints(hs, vg, step=0.07, rtol=0.005) == [pytest.approx(2.523)]
    # two steps wide and within rtol: closed; one step wide: closed whatever the values
    assert scan_midpoints([1.0, 1.2, 1.3], [0.471, 0.470, 0.60], step=0.1, rtol=0.005) == []
    assert scan_midpoints([1.0, 1.2, 1.3], [0.480, 0.470, 0.60], step=0.1, rtol=0.005) == \
        [pytest.approx(1.1)]
    # non-finite values are never the minimum; a minimum at the last height has one gap
    assert scan_midpoints([1.0, 2.0, 4.0], [math.nan, 0.5, 0.4], step=0.1, rtol=0.005) == \
        [pytest.approx(3.0)]


@pytest.mark.slow
def test_parts_solved_at_part_tol_give_the_ladders_v_g(table1_case):
    """The scan solves its parts at Clarabel tolerance PART_TOL = 1e-7 instead of the ladder
    (1e-9, which stalls on fine part meshes): v̄_g and the multiplier are those of the
    ladder's solve to 1e-4 (B2, the part of 2.5 m at h/20: a hinge + fan)."""
    case = table1_case("B2")
    ladder = analyse(case, part_problem(case, 2.5, "bedjoints", 0.25, 20))
    (part,) = h_scan(case, [2.5], mesh_size=0.25, divisions=20)
    assert PART_TOL == 1e-7 and part.kind == ladder.kind == "hinge+fan"
    assert part.record()["solver_tol"] == PART_TOL            # recorded in fe_scan.csv
    assert ladder.record()["solver_tol"] in (1e-9, 1e-7)      # the ladder's first or last rung
    assert part.vg == pytest.approx(ladder.vg, rel=1e-4)
    assert part.multiplier == pytest.approx(ladder.multiplier, rel=1e-4)


def test_scan_heights_in_threads_equal_one_after_another(table1_case):
    """h_scan's default (every part meshed here, then solved in threads,
    ``_threads.map_here``) gives the builtin map's mechanisms bit for bit, in order."""
    import builtins

    case = table1_case("B1")
    hs = [0.6, 1.5, 3.0]
    kw = dict(mesh_size=0.5, facade="bedjoints", divisions=3)
    threads = h_scan(case, hs, **kw)
    serial = h_scan(case, hs, map=builtins.map, **kw)
    assert [m.h_part for m in threads] == hs
    for x, y in zip(threads, serial):
        assert x.n_triangles == y.n_triangles
        assert x.multiplier == y.multiplier and x.h == y.h
        assert x.vg == y.vg or (math.isnan(x.vg) and math.isnan(y.vg))
