"""Impulse criterion (eqs 4-7, 18-19) against the classical rocking block worked by hand."""

import math

import pytest

from homlimit import ParameterError
from homlimit.impulse import collapse_velocity, rigid_restoring_work, theta_dot0
from homlimit.impulse.body import RigidBody

G = 9.81


def block(b, h, gamma=2000.0):
    m = gamma * b * h
    return RigidBody(m=m, x_G=b / 2, z_G=h / 2, I_O=m * (b * b + h * h) / 3)


def test_free_standing_block_threshold_by_hand():
    # b = 0.5 m, h = 5 m rocking about its toe: every number below is worked out by hand.
    b, h = 0.5, 5.0
    i = (b ** 2 + h ** 2) / 3                     # 8.416667 m²
    r_G, z_G = math.sqrt(b ** 2 + h ** 2) / 2, h / 2  # 2.512469, 2.5 m
    v_hand = i / z_G * math.sqrt(2 * G * (r_G - z_G) / i)
    assert v_hand == pytest.approx(0.57398, rel=1e-4)  # 3.36667 * sqrt(0.029066)
    assert collapse_velocity(block(b, h)) == pytest.approx(v_hand, rel=1e-12)
    # eq. 19 is the same number
    assert math.sqrt(2 * G * i / z_G * (r_G / z_G - 1)) == pytest.approx(v_hand, rel=1e-12)


def test_theta_dot0_balances_the_energy_at_threshold():
    body = block(0.4, 3.0)
    v = collapse_velocity(body)
    w0 = theta_dot0(body, v)
    assert 0.5 * body.I_O * w0 ** 2 == pytest.approx(rigid_restoring_work(body), rel=1e-12)


def test_supplied_work_scales_velocity_as_sqrt():
    body = block(0.5, 4.0)
    W = rigid_restoring_work(body)
    assert collapse_velocity(body, W=4 * W) == pytest.approx(2 * collapse_velocity(body))


def test_bad_input_is_named():
    with pytest.raises(ParameterError, match="W = -1"):
        collapse_velocity(block(0.5, 4.0), W=-1.0)
    with pytest.raises(ParameterError, match=r"I_O = 1\.0 .*parallel-axis"):
        RigidBody(m=1.0, x_G=1.0, z_G=1.0, I_O=1.0)
    with pytest.raises(ParameterError, match="z_G = 0"):
        RigidBody(m=1.0, x_G=1.0, z_G=0.0, I_O=5.0)
