"""Strength domains: π(d) against brute-force maximisation of σ·d, conic forms against π and G.

References are independent of homlimit.fe.strength: eq. 15 is typed in from the paper, the cone
closed form from the mechanics note, the cohesive extension is rebuilt from its micro stress
field, and maxima come from HiGHS (scipy.optimize.linprog) or from sampling the boundary.
"""

from __future__ import annotations

import cvxpy as cp
import numpy as np
import pytest
from scipy.optimize import linprog

from homlimit.errors import ParameterError
from homlimit.fe.strength import (
    BedJoints,
    ConicBlock,
    Homogenised,
    MohrCoulomb,
    Tresca,
    jump_strain,
)

A_, C_, F_ = 0.3, 0.2, 0.6  # Table 1, B1 (c/a = 0.667 >= f)


def eq15_rows(a, c, f):
    """Eq. 15 as printed: ±τ + fσ_z <= 0, (a/c)σ_x ± (fa/c + 1)τ + fσ_z <= 0."""
    k = a / c
    return np.array([[0, f, 1], [0, f, -1], [k, f, f * k + 1], [k, f, -(f * k + 1)]])


def lp_max(d, A_ub, b_ub, box=None, n_extra=0, A_eq=None, b_eq=None):
    """max σ·d over {A_ub z <= b_ub} with z = (σ, extra); returns +inf if HiGHS says unbounded."""
    cost = -np.concatenate([d, np.zeros(n_extra)])
    bounds = [(None, None)] * (3 + n_extra) if box is None else [(-box, box)] * (3 + n_extra)
    res = linprog(cost, A_ub=A_ub, b_ub=b_ub, A_eq=A_eq, b_eq=b_eq, bounds=bounds,
                  method="highs")
    if res.status == 3:
        return np.inf
    assert res.status == 0, res.message
    return -res.fun


def random_d(rng, n):
    return rng.normal(size=(n, 3))


def cone_points(rng, n, rows_generators):
    """Random d inside cone(N): Σ μ_k N_k with μ >= 0 (half of them on a face: some μ_k = 0)."""
    mu = rng.exponential(size=(n, len(rows_generators)))
    mu[: n // 2, 0] = 0.0
    return mu @ rows_generators


# ----------------------------------------------------------------- homogenised, dry (eq. 15)

def test_homogenised_normals_are_eq15():
    h = Homogenised(A_, C_, F_)
    np.testing.assert_allclose(h.normals, eq15_rows(A_, C_, F_))
    np.testing.assert_array_equal(h.rhs, 0.0)


@pytest.mark.slow
def test_homogenised_support_matches_linprog_dry():
    rng = np.random.default_rng(1)
    h = Homogenised(A_, C_, F_)
    N = eq15_rows(A_, C_, F_)
    d = np.vstack([random_d(rng, 150), cone_points(rng, 150, N)])
    pi = h.support(d)
    ref = np.array([lp_max(di, N, np.zeros(4)) for di in d])
    assert np.isinf(pi).sum() > 50 and np.isfinite(pi).sum() >= 150
    np.testing.assert_array_equal(np.isinf(pi), np.isinf(ref))
    np.testing.assert_allclose(pi[np.isfinite(pi)], 0.0, atol=1e-9)
    # unbounded: over a box |σ_i| <= M the maximum grows linearly with M
    for di in d[np.isinf(pi)][:10]:
        m1, m2 = lp_max(di, N, np.zeros(4), box=1e3), lp_max(di, N, np.zeros(4), box=1e6)
        assert m1 > 0 and m2 == pytest.approx(1e3 * m1, rel=1e-6)


def test_homogenised_cone_equals_closed_form():
    """d ∈ cone(N_k) ⇔ d_xx >= 0, d_zz >= f(c/a) d_xx, |γ| <= d_zz/f + f d_xx (mechanics.md)."""
    rng = np.random.default_rng(2)
    for a, c, f in [(A_, C_, F_), (0.15, 0.2, 0.6), (0.3, 0.1, 0.9), (0.2, 0.3, 0.3)]:
        h = Homogenised(a, c, f)
        d = np.vstack([random_d(rng, 300), cone_points(rng, 200, eq15_rows(a, c, f))])
        closed = ((d[:, 0] >= 0) & (d[:, 1] >= f * c / a * d[:, 0])
                  & (np.abs(d[:, 2]) <= d[:, 1] / f + f * d[:, 0]))
        # the generated points lie on faces: compare with a relative tolerance on those
        margin = np.min(np.column_stack([d[:, 0], d[:, 1] - f * c / a * d[:, 0],
                                         d[:, 1] / f + f * d[:, 0] - np.abs(d[:, 2])]), axis=1)
        clear = np.abs(margin) > 1e-9 * (1 + np.linalg.norm(d, axis=1))
        inside_facets = np.all(d @ h.facets.T >= -1e-12, axis=1)
        assert closed[clear].sum() > 150 and (~closed[clear]).sum() > 150
        np.testing.assert_array_equal(inside_facets[clear], closed[clear])
        np.testing.assert_array_equal(np.isfinite(h.support(d)), closed | ~clear)


def test_homogenised_jump_test():
    """A vertical crack opening horizontally (mechanism I) is not admissible; a jump whose
    normal opening is f times its sliding across a bed joint is (mechanics.md)."""
    h = Homogenised(A_, C_, F_)
    assert np.isinf(h.support_jump(np.array([1.0, 0.0]), np.array([1.0, 0.0])))
    assert h.support_jump(np.array([1.0, F_]), np.array([0.0, 1.0])) == 0.0
    np.testing.assert_allclose(jump_strain([2.0, 3.0], [0.6, 0.8]), [1.2, 2.4, 2 * 0.8 + 3 * 0.6])


# ----------------------------------------------------------------- homogenised, cohesive

def micro_field_lp(a, c, f, C, T):
    """Brute-force description of the cohesive domain: σ = σ1 + σ2 with σ2 in the eq. 15 cone
    and σ1 carried by piecewise-constant joint stresses of a running-bond cell.

    Variables z = (σ (3), σ2 (3), σ_h, τ_h, τ_A, τ_B, σ_A, σ_B). Cell statics (blocks 2c × a):
    σ1_x = σ_h − (c/a)(τ_A − τ_B)/2, τ1 = (τ_A + τ_B)/2, σ1_z = (σ_A + σ_B)/2 and block moment
    τ_h = τ1 − (c/(2a))(σ_B − σ_A). Joints: |τ_j| + fσ_j <= C, σ_j <= T.
    Returns (A_ub, b_ub, A_eq, b_eq) over the 12 variables (σ first)."""
    k = c / a
    names = ("SX", "SZ", "TU", "S2X", "S2Z", "T2", "SH", "TH", "TA", "TB", "SA", "SB")

    def row(**coef):
        r = np.zeros(len(names))
        for key, v in coef.items():
            r[names.index(key)] += v
        return r
    rows, rhs = [], []
    for t, sg in (("TA", "SA"), ("TB", "SB"), ("TH", "SH")):
        rows += [row(**{t: 1, sg: f}), row(**{t: -1, sg: f}), row(**{sg: 1})]
        rhs += [C, C, T]
    for N in eq15_rows(a, c, f):                   # σ2 in the eq. 15 cone
        rows.append(row(S2X=N[0], S2Z=N[1], T2=N[2]))
        rhs.append(0.0)
    eqs = [row(SX=1, S2X=-1, SH=-1, TA=k / 2, TB=-k / 2),      # σ1_x
           row(TU=1, T2=-1, TA=-0.5, TB=-0.5),                  # τ1
           row(SZ=1, S2Z=-1, SA=-0.5, SB=-0.5),                 # σ1_z
           row(TH=1, TU=-1, T2=1, SB=k / 2, SA=-k / 2)]         # moment of a block
    return np.array(rows), np.array(rhs, float), np.array(eqs), np.zeros(len(eqs))


@pytest.mark.parametrize("a,c,f,C,T", [
    (A_, C_, F_, 1e4, 0.0), (A_, C_, F_, 1e4, 5e3), (A_, C_, F_, 1e4, 1e6), (A_, C_, F_, 0.0, 5e3),
    (0.3, 0.1, 0.9, 1e4, 1e6), (0.3, 0.1, 0.9, 1e4, 2e3)])
@pytest.mark.slow
def test_homogenised_cohesive_support_matches_micro_field(a, c, f, C, T):
    rng = np.random.default_rng(3)
    h = Homogenised(a, c, f, cohesion=C, tension=T)
    A_ub, b_ub, A_eq, b_eq = micro_field_lp(a, c, f, C, T)
    d = np.vstack([random_d(rng, 50), cone_points(rng, 50, eq15_rows(a, c, f))])
    pi = h.support(d)
    ref = np.array([lp_max(di, A_ub, b_ub, n_extra=9, A_eq=A_eq, b_eq=b_eq) for di in d])
    np.testing.assert_array_equal(np.isinf(pi), np.isinf(ref))
    fin = np.isfinite(ref)
    assert fin.sum() >= 50
    np.testing.assert_allclose(pi[fin], ref[fin], rtol=1e-7, atol=1e-6 * max(C, 1.0))


def test_homogenised_cohesive_closed_form():
    """T >= C/f: ±τ + fσ_z <= C, (a/c)σ_x + fσ_z ± (1 + fa/c)τ <= C + (a/c)(C/f)."""
    C = 2e4
    h = Homogenised(A_, C_, F_, cohesion=C, tension=1e9)
    np.testing.assert_allclose(h.normals, eq15_rows(A_, C_, F_))
    np.testing.assert_allclose(h.rhs, [C, C, C + A_ / C_ * C / F_, C + A_ / C_ * C / F_])
    assert not h.dry and Homogenised(A_, C_, F_, tension=5.0).dry
    # i.e. eq. 15 moved to the apex σ* = (C/f, C/f, 0): π(d) = σ*·d on the cone (any c/a)
    rng = np.random.default_rng(11)
    for a, c, f in [(A_, C_, F_), (0.3, 0.1, 0.9)]:
        d = cone_points(rng, 100, eq15_rows(a, c, f))
        hc = Homogenised(a, c, f, cohesion=C, tension=1e9)
        np.testing.assert_allclose(hc.support(d), C / f * (d[:, 0] + d[:, 1]), rtol=1e-9)


# ----------------------------------------------------------------- bed joints

@pytest.mark.parametrize("C,T", [(0.0, 0.0), (2e4, 0.0), (2e4, 1e4), (2e4, 1e9)])
@pytest.mark.slow
def test_bedjoints_support_matches_linprog(C, T):
    rng = np.random.default_rng(4)
    f = 0.6
    bj = BedJoints(f, cohesion=C, tension=T)
    # reference domain typed in: |τ| + fσ_z <= C, σ_z <= T (σ_x free)
    A_ub = np.array([[0, f, 1], [0, f, -1], [0, 1, 0]], float)
    b_ub = np.array([C, C, T])
    d = random_d(rng, 150)
    d_fin = cone_points(rng, 150, np.array([[0, f, 1], [0, f, -1]]))   # d_xx = 0 exactly
    d = np.vstack([d, d_fin])
    pi = bj.support(d)
    ref = np.array([lp_max(di, A_ub, b_ub) for di in d])
    np.testing.assert_array_equal(np.isinf(pi), np.isinf(ref))
    assert np.isfinite(pi).sum() >= 150 and np.isinf(pi).sum() >= 150
    np.testing.assert_allclose(pi[np.isfinite(pi)], ref[np.isfinite(ref)], rtol=1e-9, atol=1e-6)


# ----------------------------------------------------------------- smooth domains by sampling

def sampled_max(d, k_of_p, p_lo, p_hi, n_p=401, n_t=2001):
    """max σ·d over σ = (p + q cosθ, p − q cosθ, q sinθ), q = k_of_p(p), on a fine grid."""
    p = np.linspace(p_lo, p_hi, n_p)[:, None]
    t = np.linspace(0, 2 * np.pi, n_t)[None, :]
    q = k_of_p(p)
    s = np.stack([p + q * np.cos(t), p - q * np.cos(t), q * np.sin(t)], -1)
    return (s @ d).max()


def test_tresca_support_matches_sampling():
    rng = np.random.default_rng(5)
    k = 3.0
    tr = Tresca(k)
    d_inf = random_d(rng, 100)
    d_fin = random_d(rng, 100)
    d_fin[:, 1] = -d_fin[:, 0]                   # isochoric
    for di in d_fin:
        ref = sampled_max(di, lambda p: k + 0 * p, 0.0, 0.0, n_p=1)
        # the grid max is below the true max by at most a factor cos(Δθ/2), Δθ = 2π/2000
        pi = tr.support(di)
        assert ref <= pi * (1 + 1e-12) and ref >= pi * np.cos(np.pi / 2000)
    pi = tr.support(d_inf)
    assert np.all(np.isinf(pi))
    for di in d_inf[:20]:                        # grows with the box of p
        m1 = sampled_max(di, lambda p: k + 0 * p, -1e2, 1e2, n_p=3, n_t=64)
        m2 = sampled_max(di, lambda p: k + 0 * p, -1e4, 1e4, n_p=3, n_t=64)
        # σ·d = p (d_xx + d_zz) + bounded: the box maximum grows by (1e4 − 1e2)|tr d|
        assert m2 - m1 == pytest.approx((1e4 - 1e2) * abs(di[0] + di[1]), rel=1e-9)


@pytest.mark.slow
def test_mohr_coulomb_support_matches_sampling():
    rng = np.random.default_rng(6)
    c, phi = 2.0, 30.0
    mc = MohrCoulomb(c, phi)
    s, co = np.sin(np.radians(phi)), np.cos(np.radians(phi))
    apex = c * co / s
    d = random_d(rng, 300)
    e = np.hypot(d[:, 0] - d[:, 1], d[:, 2])
    fin = d[:, 0] + d[:, 1] >= s * e
    assert 50 < fin.sum() < 250
    pi = mc.support(d)
    np.testing.assert_array_equal(np.isfinite(pi), fin)
    R = lambda p: np.maximum(c * co - p * s, 0.0)     # noqa: E731
    for di, pii in zip(d[fin][:60], pi[fin][:60]):
        ref = sampled_max(di, R, -200.0, apex, n_p=2001, n_t=721)
        assert pii == pytest.approx(ref, rel=1e-9, abs=1e-9)
    for di in d[~fin][:20]:                      # grows as p → −∞
        m1 = sampled_max(di, R, -1e2, apex, n_p=201, n_t=721)
        m2 = sampled_max(di, R, -1e4, apex, n_p=201, n_t=721)
        assert m2 > 10 * max(m1, 1e-3)


# ----------------------------------------------------------------- conic forms

def in_cone(block: ConicBlock, z: np.ndarray, tol: float = 0.0) -> np.ndarray:
    """Rows z (n, m) of A x + D y + e lie in K = {0}^n_eq × R₊^n_lin × SOC(q)...? (numpy)."""
    z = np.atleast_2d(z)
    scale = tol * (1.0 + np.linalg.norm(z, axis=1))
    r = block.n_eq
    ok = np.all(np.abs(z[:, :r]) <= scale[:, None], axis=1)
    ok &= np.all(z[:, r:r + block.n_lin] >= -scale[:, None], axis=1)
    r += block.n_lin
    for q in block.soc:
        ok &= z[:, r] >= np.linalg.norm(z[:, r + 1:r + q], axis=1) - scale
        r += q
    return ok


def block_value(block: ConicBlock, x: np.ndarray):
    """min cx·x + cy·y s.t. A x + D y + e ∈ K for one fixed x (+inf if infeasible): evaluated
    directly without auxiliary variables, otherwise solved by cvxpy/Clarabel."""
    if block.n_aux == 0:
        ok = in_cone(block, block.A @ x + block.e, tol=1e-12)[0]
        return float(block.cx @ x) if ok else np.inf
    y = cp.Variable(block.n_aux)
    z = block.A @ x + block.e + block.D @ y
    ne, nl = block.n_eq, block.n_lin
    cons = [z[:ne] == 0] if ne else []
    if nl:
        cons.append(z[ne:ne + nl] >= 0)
    r = ne + nl
    for q in block.soc:
        cons.append(cp.SOC(z[r], z[r + 1:r + q]))
        r += q
    prob = cp.Problem(cp.Minimize(block.cy @ y), cons)
    prob.solve(solver=cp.CLARABEL)
    if prob.status in ("infeasible", "infeasible_inaccurate"):
        return np.inf
    assert prob.status == "optimal", prob.status
    return float(block.cx @ x) + float(block.cy @ y.value)


DOMAINS = [Homogenised(A_, C_, F_), Homogenised(A_, C_, F_, cohesion=1.0, tension=0.0),
           Homogenised(A_, C_, F_, cohesion=1.0, tension=0.5), BedJoints(F_),
           BedJoints(F_, cohesion=1.0, tension=0.3), Tresca(1.5), MohrCoulomb(1.0, 30.0)]


def near_boundary_points(dom, rng, n):
    """Half random, half made finite for the domain (projected onto where π < ∞)."""
    d = random_d(rng, n)
    if isinstance(dom, Homogenised):
        d[: n // 2] = cone_points(rng, n // 2, eq15_rows(A_, C_, F_))
    elif isinstance(dom, BedJoints):
        d[: n // 2] = cone_points(rng, n // 2, np.array([[0, F_, 1], [0, F_, -1]]))
    elif isinstance(dom, Tresca):
        d[: n // 2, 1] = -d[: n // 2, 0]
    else:
        d[: n // 2, 1] = np.abs(d[: n // 2, 1]) + 3 * np.abs(d[: n // 2, 0]) + 2 * np.abs(
            d[: n // 2, 2])
    return d


@pytest.mark.parametrize("dom", DOMAINS, ids=lambda d: type(d).__name__)
def test_kinematic_cone_reproduces_support(dom):
    rng = np.random.default_rng(7)
    d = near_boundary_points(dom, rng, 24)
    block = dom.kinematic_cone()
    pi = dom.support(d)
    assert np.isfinite(pi).sum() >= 12 and np.isinf(pi).sum() >= 6
    got = np.array([block_value(block, di) for di in d])
    np.testing.assert_array_equal(np.isinf(got), np.isinf(pi))
    np.testing.assert_allclose(got[np.isfinite(pi)], pi[np.isfinite(pi)], rtol=1e-6, atol=1e-6)


@pytest.mark.parametrize("dom", DOMAINS, ids=lambda d: type(d).__name__)
def test_static_cone_reproduces_admissibility(dom):
    rng = np.random.default_rng(8)
    sig = rng.normal(size=(400, 3)) * 2.0
    block = dom.static_cone()
    assert block.n_aux == 0
    ok = in_cone(block, sig @ block.A.T + block.e)
    adm = dom.is_admissible(sig, tol=0.0)
    assert adm.sum() >= 20 and (~adm).sum() >= 20
    np.testing.assert_array_equal(ok, adm)


def test_static_and_kinematic_are_dual_on_samples():
    """σ·d <= π(d) for every admissible σ (the support function bounds the power)."""
    rng = np.random.default_rng(9)
    for dom in DOMAINS:
        sig = rng.normal(size=(500, 3))
        sig = sig[dom.is_admissible(sig)]
        d = near_boundary_points(dom, rng, 50)
        pi = dom.support(d)
        assert np.all(sig @ d.T <= pi[None, :] + 1e-9)


def test_active_facet():
    h = Homogenised(A_, C_, F_, cohesion=1e4, tension=1e9)   # four facets
    # on bed-joint facet 1: τ + fσ_z = C with σ_x very compressive (facets 3, 4 slack)
    assert h.active_facet(np.array([-1e6, 0.0, 1e4])) == 0
    assert h.active_facet(np.array([-1e6, 0.0, -1e4])) == 1
    assert h.active_facet(np.array([-1e6, -1e5, 0.0])) == -1
    # on facet 3 (the head-joint mechanism): pick σ with N_3·σ = r_3, others slack
    s = np.array([0.0, -1e4, 0.0])
    s[0] = (h.rhs[2] - h.normals[2, 1:] @ s[1:]) / h.normals[2, 0]
    assert h.active_facet(s) == 2
    out = h.active_facet(np.stack([s, np.array([-1e6, -1e5, 0.0])]))
    np.testing.assert_array_equal(out, [2, -1])


@pytest.mark.parametrize("make,name", [
    (lambda: Homogenised(-0.3, 0.2, 0.6), "a"), (lambda: Homogenised(0.3, 0.0, 0.6), "c"),
    (lambda: Homogenised(0.3, 0.2, float("nan")), "f"),
    (lambda: Homogenised(0.3, 0.2, 0.6, cohesion=-1), "cohesion"),
    (lambda: BedJoints(0.6, tension=-2), "tension"), (lambda: Tresca(0), "k"),
    (lambda: MohrCoulomb(1.0, 90.0), "phi_deg"), (lambda: MohrCoulomb(0.0, 30), "cohesion")])
def test_invalid_parameters_named(make, name):
    with pytest.raises(ParameterError, match=rf"^{name} = "):
        make()
