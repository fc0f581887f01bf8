"""The sympy derivations in analytic/ against the paper and against homlimit's numerics."""

import numpy as np
import pytest

from analytic import mechanism_I as A1
from analytic import mechanism_II as A2
from homlimit.closed_form.mechanisms import geometry_II, theta_m_I, theta_m_I_eq14, vnorm_II, work_I


@pytest.mark.slow
def test_identities_and_misprints():
    ok = A1.checks() | A2.checks()
    printed_wrong = {"eq. 12 as printed", "eq. 13 as printed"}
    for name, holds in ok.items():
        assert holds == (name not in printed_wrong), name


@pytest.fixture(scope="module")
def points():
    rng = np.random.default_rng(20261123)
    n = 200
    lam = rng.uniform(1.0, 30.0, n)
    rho = rng.uniform(1.0, 40.0, n)
    alpha = rng.uniform(0.2, 1.5, n)
    beta = rng.uniform(0.05, 0.95, n)
    return lam, rho, alpha, beta, rng


def rel(a, b):
    return np.max(np.abs(np.asarray(a) / np.asarray(b) - 1))


def test_work_both_branches_agree_to_1e10(points):
    lam, rho, alpha, beta, rng = points
    th_r = beta / lam * rng.uniform(1.0, 5.0, lam.size)
    th_l = beta / lam * rng.uniform(0.05, 0.999, lam.size)
    args = (lam, rho, alpha, beta)
    assert rel(work_I(th_r, *args), A1.work_right(th_r, *args)) < 1e-10
    assert rel(work_I(th_l, *args), A1.work_left(th_l, *args)) < 1e-10


def test_theta_m_is_a_root_of_the_symbolic_quartic(points):
    lam, rho, alpha, beta, _ = points
    th = theta_m_I(lam, rho, alpha, beta)
    right = th >= beta / lam
    assert right.mean() > 0.9
    coeffs = np.array(A1.quartic_coeffs(lam, rho, alpha, beta), dtype=object)
    q = sum(np.asarray(c, float) * th ** (4 - k) for k, c in enumerate(coeffs))
    scale = th ** 4
    assert np.max(np.abs(q[right] / scale[right])) < 1e-10


def test_eq14_forms_agree_to_1e10(points):
    lam, rho, alpha, beta, _ = points
    assert rel(theta_m_I_eq14(lam, rho, alpha, beta), A1.theta14(lam, rho, alpha, beta)) < 1e-10
    assert rel(theta_m_I_eq14(lam, rho, alpha, beta, corrected=True),
               A1.theta14_corrected(lam, rho, alpha, beta)) < 1e-10


def test_mechanism_II_agrees_to_1e10(points):
    lam, rho, alpha, _, _ = points
    xg, zg, i = geometry_II(lam, rho, alpha)
    assert rel(xg, A2.xg(lam, rho, alpha)) < 1e-10
    assert rel(zg, A2.zg(lam, rho, alpha)) < 1e-10
    assert rel(i, A2.ig(lam, rho, alpha)) < 1e-10
    assert rel(vnorm_II(lam, rho, alpha), A2.vnorm_fn(lam, rho, alpha)) < 1e-10
