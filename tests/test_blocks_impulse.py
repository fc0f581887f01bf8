"""Collapse ground velocity of discrete mechanisms (homlimit.blocks.impulse) against eq. 19 and
a hand-summed one-DOF generalisation."""

import math

import numpy as np
import pytest

from homlimit.blocks.geometry import stack, t_section_blocks
from homlimit.blocks.impulse import block_impulse, failing_body
from homlimit.blocks.limit import solve_blocks
from homlimit.errors import ParameterError
from homlimit.params import Case, Masonry, Wall

G = 9.81


def _eq19_rectangle(b, h, g=G):
    """Eq. 19 for a rectangle b × h rocking about its toe: i = (b² + h²)/3, G = (b/2, h/2)."""
    i = (b * b + h * h) / 3.0
    zg, rg = h / 2.0, math.hypot(b / 2.0, h / 2.0)
    return math.sqrt(2.0 * g * i / zg * (rg / zg - 1.0))


def test_single_rocking_block_is_eq19():
    A = stack([0.6], [2.4], x_left=[1.0], density=2000.0, meta={"g": G, "b": 0.6, "H": 2.4})
    r = solve_blocks(A, f=0.7)
    bi = block_impulse(A, r)
    assert bi.method.startswith("rigid")
    assert bi.O == pytest.approx((1.0, 0.0), abs=1e-7)
    assert bi.vg == pytest.approx(_eq19_rectangle(0.6, 2.4), rel=1e-7)
    assert bi.theta_m == pytest.approx(math.atan(0.6 / 2.4), rel=1e-7)
    assert bi.M == pytest.approx(bi.body.I_O, rel=1e-7)
    assert bi.W_rest == 0 and bi.W_friction == 0


def test_stack_rocking_as_one_body_has_its_exact_mass_properties():
    """Two equal blocks 1 × 1 rocking together: one rectangle 1 × 2 (eq. 19)."""
    A = stack([1.0, 1.0], [1.0, 1.0], density=1500.0, meta={"g": G, "b": 1.0, "H": 2.0})
    r = solve_blocks(A, f=0.9)
    bi = block_impulse(A, r)
    assert bi.n_body == 2 and bi.method.startswith("rigid")
    assert bi.body.m == pytest.approx(3000.0, rel=1e-12)
    assert bi.body.I_O == pytest.approx(3000.0 * (1 + 4) / 3, rel=1e-7)
    assert bi.vg == pytest.approx(_eq19_rectangle(1.0, 2.0), rel=1e-7)


def test_top_block_alone_about_its_own_toe():
    A = stack([1.0, 0.2], [1.0, 1.0], meta={"g": G, "b": 0.2, "H": 2.0})
    r = solve_blocks(A, f=0.6)
    bi = block_impulse(A, r)
    assert bi.O == pytest.approx((0.0, 1.0), abs=1e-7)
    assert bi.h == pytest.approx(1.0, rel=1e-7)
    assert bi.vg == pytest.approx(_eq19_rectangle(0.2, 1.0), rel=1e-7)


def test_one_dof_generalisation_summed_by_hand():
    """A T-section part whose mechanism is a body plus slower blocks: M, Π and W(θ_m) summed
    here block by block from the rigid-block kinematics (m |v_G|² + I_G ω², m(−u), the
    body's rotation about O at finite θ, the rest's lift to first order), independently of
    the module's vectorised sums; v̄_g = √(2 W M)/Π."""
    case = Case(Wall(H=4.2, L=2.4, s=0.5, b=0.5, l=6.0), Masonry(a=0.3, c=0.2, f=0.6))
    A = t_section_blocks(case)
    r = solve_blocks(A)
    bi = block_impulse(A, r)
    body, O, omega = failing_body(A, r)  # noqa: E741 (the paper's O)
    assert bi.method.startswith("one-DOF") and 0 < bi.M_rest_share < 0.2
    M = Pi = lift_rest = 0.0
    m_b = sx = sz = 0.0
    for i in range(A.n_blocks):
        if A.fixed[i]:
            continue
        u, w, om = r.velocity[i] / omega
        M += A.mass[i] * (u * u + w * w) + A.inertia[i] * om * om
        Pi += -A.mass[i] * u
        if body[i]:
            m_b += A.mass[i]
            sx += A.mass[i] * (A.centroid[i, 0] - O[0])
            sz += A.mass[i] * (A.centroid[i, 1] - O[1])
        else:
            lift_rest += A.mass[i] * w
    xg, zg = sx / m_b, sz / m_b
    th = math.atan2(xg, zg)
    W = m_b * G * (math.hypot(xg, zg) - zg) + th * G * lift_rest
    assert bi.M == pytest.approx(M, rel=1e-12)
    assert bi.Pi == pytest.approx(Pi, rel=1e-12)
    assert bi.theta_m == pytest.approx(th, rel=1e-12)
    assert bi.W_m == pytest.approx(W, rel=1e-12)
    assert bi.vg == pytest.approx(math.sqrt(2 * W * M) / Pi, rel=1e-12)
    assert bi.vnorm == pytest.approx(bi.vg / math.sqrt(G * 0.5), rel=1e-14)


def test_friction_work_of_a_non_associative_mechanism():
    """Non-associative mechanisms dissipate: W_friction > 0, bounded by the eq. 8 rule
    (friction falling with the lost overlap): at most D_k θ_m per sliding interface."""
    case = Case(Wall(H=4.2, L=2.4, s=0.5, b=0.5, l=6.0), Masonry(a=0.3, c=0.2, f=0.6))
    A = t_section_blocks(case)
    r = solve_blocks(A, friction="non-associative", max_iter=40)
    bi = block_impulse(A, r)
    _, _, omega = failing_body(A, r)
    D = (np.abs(r.shear) * np.abs(r.slip) / abs(omega)).sum()
    assert 0 < bi.W_friction <= D * bi.theta_m * (1 + 1e-12)


def test_a_sliding_mechanism_has_no_tipping_angle():
    A = stack([1.0], [0.5], meta={"g": G, "b": 1.0, "H": 0.5})
    r = solve_blocks(A, f=0.6)
    with pytest.raises(ParameterError, match="translation"):
        block_impulse(A, r)


def test_bad_input():
    A = stack([1.0], [2.0])
    r = solve_blocks(A, f=0.6)
    with pytest.raises(ParameterError, match="assembly, result"):
        block_impulse(A, "r")
    with pytest.raises(ParameterError, match="result has 2 blocks and assembly 3"):
        block_impulse(stack([1.0, 1.0], [1.0, 1.0]), r)
    with pytest.raises(ParameterError, match="g = -1"):
        block_impulse(A, r, g=-1)
