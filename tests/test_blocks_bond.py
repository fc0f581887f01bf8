"""The rigid-block LA with the joints' cohesion C and tension T (issue 30 item 4): a block on a
base joint and a two-block stack against hand statics (written out here, not the package's
code), C = T = 0 bit for bit, and the inputs refused. docs/real-walls.md, "Rigid blocks".

The stack is statically determinate: the part above joint j puts (N, V, M) on it by
equilibrium alone, and the joint's domain, σ >= −T_h, |τ| <= f σ + C with T_h = min(T, C/f),
decouples into |V| <= f N + C A and the resultant's position, so λ is the least over the
joints of the sliding λ = f + C A/(M g) and the overturning about the outer toe with the
whole joint in tension T_h (its moment T_h d L²/2)."""

import math

import numpy as np
import pytest

from homlimit.blocks import block_impulse, equilibrium_residual, solve_blocks, stack
from homlimit.blocks.impulse import rigid_body_of
from homlimit.blocks.real import RealActions
from homlimit.errors import ParameterError

RHO, G, F = 1000.0, 9.81, 0.6                  # kg/m² per slab of depth 1 m, m/s²


def solve(widths, heights, f=F, **real):
    A = stack(widths, heights, density=RHO,
              meta={"f": f, "g": G, "b": max(widths), "H": sum(heights),
                    "real": RealActions(**real) if real else None})
    return A, solve_blocks(A)


def balanced(A, r):
    return np.abs(equilibrium_residual(A, r)).max() < 1e-6 * A.mass.sum() * G


@pytest.mark.parametrize("C, T", [(500.0, 0.0), (500.0, 300.0), (500.0, 1e6)])
def test_squat_block_slides_with_cohesion(C, T):
    # b = 1 m, h = 0.5 m: sliding governs, λ m g = f m g + C A (A = b × 1 m); the tension
    # does not enter sliding (associative: δ_n = f δ_t, the tension's power T_h δ_n and the
    # cohesion's reduced part (C − f T_h) |δ_t| add up to C |δ_t|)
    b, h = 1.0, 0.5
    m = RHO * b * h
    A, r = solve([b], [h], cohesion=C, tension=T)
    assert r.multiplier == pytest.approx(F + C * b / (m * G), rel=1e-6)
    assert r.n_sliding == 1
    assert r.actions["bond_rate"][0] == pytest.approx(C * b, rel=1e-6)  # C A |δ_t|, |u| = 1
    assert balanced(A, r)
    V = r.shear[0].sum()                            # the base's shear on the ground's side
    assert abs(V) == pytest.approx(F * m * G + C * b, rel=1e-6)


@pytest.mark.parametrize("C, T", [(5e3, 2e3), (5e3, 2e4), (2e3, 1e3)])
def test_tall_block_overturns_with_the_tension_block_at_the_heel(C, T):
    # b = 0.5, h = 2 m: the block turns about its toe with the whole base in tension T_h =
    # min(T, C/f): λ = (m g b/2 + T_h b²/2)/(m g h/2); at T = 2e4 > C/f the apex caps it
    b, h = 0.5, 2.0
    m = RHO * b * h
    th = min(T, C / F)
    A, r = solve([b], [h], cohesion=C, tension=T)
    lam = (m * G * b / 2 + th * b * b / 2) / (m * G * h / 2)
    assert lam < F + C * b / (m * G)                # overturning governs
    assert r.multiplier == pytest.approx(lam, rel=1e-6)
    assert r.fit.O[0] == pytest.approx(0.0, abs=1e-6)
    assert r.actions["tension_effective"] == th
    # the static dual: the heel's end force is the uniform tension's −T_h b/2
    heel = int(np.argmax(A.interfaces.p[0, :, 0]))
    assert r.normal[0, heel] == pytest.approx(-th * b / 2, rel=1e-6)
    assert r.actions["bond_rate"][0] == pytest.approx(th * b * b / 2 * abs(r.velocity[1, 2]),
                                                      rel=1e-6)
    assert balanced(A, r)


@pytest.mark.parametrize("fc", [1e5, 3e5])
def test_tension_with_a_compression_cap(fc):
    # f_c and T_h together: σ in [−T_h, f_c] (a clean domain: the stress block shifted by the
    # uniform tension). The compressed zone w at the toe balances the weight and the tension
    # over the rest, f_c w − T_h (b − w) = m g; moments about the toe:
    # λ m g h/2 = m g b/2 − f_c w²/2 + T_h (b² − w²)/2
    b, h, C, T = 0.5, 2.0, 5e3, 2e3
    m = RHO * b * h
    w = (m * G + T * b) / (fc + T)
    lam = (m * G * b / 2 - fc * w * w / 2 + T * (b * b - w * w) / 2) / (m * G * h / 2)
    A, r = solve([b], [h], cohesion=C, tension=T, fc=fc)
    assert 0 < w < b
    assert r.multiplier == pytest.approx(lam, rel=1e-6)
    assert balanced(A, r)


@pytest.mark.parametrize("heights, f, C, T, joint, mode", [
    ([1.0, 1.0], 0.6, 2e3, 2e3, 0, "overturning"),
    ([0.4, 1.0], 0.3, 300.0, 0.0, 1, "sliding"),
    ([1.0, 1.0], 0.3, 300.0, 0.0, 0, "sliding"),
])
def test_two_block_stack(heights, f, C, T, joint, mode):
    # a base block 1 m wide, a top block 0.5 m wide on its outer edge (x = 0): per joint j
    # (length L_j, the part above of mass M_j with the moment arm Σ m z_G about the joint)
    widths = [1.0, 0.5]
    th = min(T, C / f)
    m = RHO * np.array(widths) * np.array(heights)
    xg = np.array(widths) / 2
    zg = np.cumsum(heights) - np.array(heights) / 2
    z_joint = np.r_[0.0, heights[0]]
    lam = {}
    for j in (0, 1):
        above = np.arange(2) >= j
        M = m[above].sum()
        L = widths[j]
        lam[j, "sliding"] = f + C * L / (M * G)
        lam[j, "overturning"] = ((G * (m * xg)[above].sum() + th * L * L / 2)
                                 / (G * (m * (zg - z_joint[j]))[above].sum()))
    ref = min(lam.values())
    assert lam[joint, mode] == ref
    A, r = solve(widths, heights, f=f, cohesion=C, tension=T)
    assert r.multiplier == pytest.approx(ref, rel=1e-6)
    assert r.z_base == pytest.approx(z_joint[joint], abs=1e-9)
    assert balanced(A, r)


def test_no_bond_is_the_same_program_bit_for_bit():
    # C = 0 (with or without a tension, which needs a cohesion to act) adds nothing: the same
    # LP as without them, to the last bit; so with f_c
    ref = solve([0.5] * 3, [0.9] * 3)[1]
    for real in ({"cohesion": 0.0, "tension": 0.0}, {"tension": 1e4}):
        r = solve([0.5] * 3, [0.9] * 3, **real)[1]
        assert r.multiplier == ref.multiplier
        assert np.array_equal(r.normal, ref.normal) and np.array_equal(r.velocity,
                                                                      ref.velocity)
    cap = solve([0.5] * 3, [0.9] * 3, fc=2e5)[1]
    r = solve([0.5] * 3, [0.9] * 3, fc=2e5, tension=1e4)[1]
    assert r.multiplier == cap.multiplier and np.array_equal(r.normal, cap.normal)


@pytest.mark.parametrize("key, value", [("cohesion", -1.0), ("tension", -5.0),
                                        ("cohesion", math.nan), ("tension", math.inf)])
def test_bad_bond_refused(key, value):
    with pytest.raises(ParameterError, match=key):
        RealActions(**{key: value})


def test_non_associative_refuses_a_bond():
    A = stack([0.5], [2.0], density=RHO,
              meta={"f": F, "g": G, "b": 0.5, "H": 2.0, "real": RealActions(cohesion=1e3)})
    with pytest.raises(ParameterError, match="cohesion or tension"):
        solve_blocks(A, friction="non-associative")


def test_impulse_is_not_available_with_a_bond():
    # v̄_g would hang on a softening rule the case does not state: refused, never a number;
    # the static check's body is still the mechanism's (the block about its toe)
    A, r = solve([0.5], [2.0], cohesion=5e3, tension=2e3)
    with pytest.raises(ParameterError, match=r"cohesion = 5000.0 Pa, tension = 2000.0 Pa: "
                                             r"v̄_g \(eq. 7\) of the blocks does not take"):
        block_impulse(A, r)
    body, _ = rigid_body_of(A, r)
    assert body.m == pytest.approx(RHO * 0.5 * 2.0, rel=1e-12)
    assert (body.x_G, body.z_G) == pytest.approx((0.25, 1.0), abs=1e-6)
    # a tension without a cohesion does not act (T_h = 0): the impulse is the paper's, to
    # the last bit (the paper's path: θ_m in closed form)
    A, r = solve([0.5], [2.0], tension=2e3)
    A0, r0 = solve([0.5], [2.0])
    assert block_impulse(A, r).vg == block_impulse(A0, r0).vg
