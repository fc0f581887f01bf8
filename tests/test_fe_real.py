"""Issue 30, FE both bounds: compression cap, ties and floors against hand values.

The references are derived here, not taken from the package: the stress-block multiplier of a
rigid block on a base joint capped at f_c (statics about the block's resultant, and again by
minimising the kinematic balance over the hinge position), a rigid block overturning about its
toe with a tie or a floor load, and the support function of a capped domain by maximising σ·d
over eq. 15 ∩ {σ + f_c I ⪰ 0} typed in from the paper.
"""

from __future__ import annotations

import math

import cvxpy as cp
import numpy as np
import pytest
from scipy.optimize import linprog, minimize_scalar

from homlimit.fe import strength
from homlimit.fe.kinematic import solve_kinematic
from homlimit.fe.problems import Problem, _ties_and_floors, crossed_mesh, t_section
from homlimit.fe.static import solve_static
from homlimit.params import Case, Floor, Masonry, Tie, Wall

from cases import b1

A_, C_, F_ = 0.3, 0.2, 0.6
TOL = 1e-7  # the interior-point solver's relative accuracy on these small programs


def eq15_rows(a, c, f):
    k = a / c
    return np.array([[0, f, 1], [0, f, -1], [k, f, f * k + 1], [k, f, -(f * k + 1)]])


# ----------------------------------------------------------------------- the capped domains

def test_capped_support_is_the_support_of_the_intersection():
    """π of eq. 15 ∩ {principal stress >= −fc}, from the domain's kinematic cone (the split
    d = d1 + d2, d2 ⪯ 0), equals max σ·d over the intersection (a direct SOCP)."""
    fc = 2.0
    dom = strength.Capped(strength.Homogenised(A_, C_, F_), fc)
    rng = np.random.default_rng(3)
    d = rng.normal(size=(8, 3))
    pi = dom.support(d)
    N = eq15_rows(A_, C_, F_)
    for k in range(len(d)):
        s = cp.Variable(3)
        cons = [N @ s <= 0, cp.SOC(s[0] + s[1] + 2 * fc, cp.hstack([s[0] - s[1], 2 * s[2]]))]
        ref = cp.Problem(cp.Maximize(d[k] @ s), cons).solve(solver="CLARABEL")
        assert pi[k] == pytest.approx(ref, rel=1e-6, abs=1e-6)
    # the static cone: admissible exactly when both conditions hold
    sig = rng.normal(size=(200, 3)) * 2
    low = 0.5 * (sig[:, 0] + sig[:, 1]) - np.hypot(0.5 * (sig[:, 0] - sig[:, 1]), sig[:, 2])
    inside = np.all(sig @ N.T <= 0, axis=1) & (low >= -fc)
    assert np.array_equal(dom.is_admissible(sig), inside)
    blk = dom.static_cone()
    r = sig @ blk.A.T + blk.e
    soc_ok = r[:, -3] >= np.hypot(r[:, -2], r[:, -1])
    assert np.array_equal(np.all(r[:, :4] >= 0, axis=1) & soc_ok, inside)


def test_capped_bed_joint_support_by_lp():
    """BedJoints(f, fc): |τ| + fσ_z <= 0, σ_z >= −fc; π by HiGHS over (σ_z, τ) for d_xx = 0."""
    fc, f = 3.0, 0.6
    dom = strength.BedJoints(f, fc=fc)
    rng = np.random.default_rng(4)
    d = rng.normal(size=(20, 3))
    d[:, 0] = 0.0
    A = np.array([[f, 1.0], [f, -1.0], [-1.0, 0.0]])
    b = np.array([0.0, 0.0, fc])
    for dk, pk in zip(d, dom.support(d)):
        res = linprog(-dk[1:], A_ub=A, b_ub=b, bounds=[(None, None)] * 2, method="highs")
        assert pk == pytest.approx(-res.fun, rel=1e-12, abs=1e-12)
    assert np.isinf(dom.support(np.array([1e-3, 1.0, 0.0])))   # σ_x is free: d_xx = 0


# ----------------------------------------------------------------------- rigid blocks

B, H, WG = 0.5, 2.0, 2.0e4          # block width, height [m], unit weight [N/m³]


def block_problem(interface, nb=10, nz=8, extra=None, walls=None):
    """A rigid block 0 <= x <= B, 0 <= z <= H on a base joint, overturned by λ × its weight."""
    xs, zs = np.linspace(0.0, B, nb + 1), np.linspace(0.0, H, nz + 1)
    m = crossed_mesh(xs, zs).with_boundaries({
        "base": lambda x: np.abs(x[1]) < 1e-9, "outer": lambda x: np.abs(x[0]) < 1e-9,
    }).with_subdomains({"facade": lambda x: x[0] > -1.0})
    fields = {"ties": {}, "dead_body": {}, "supports": {}}
    if walls is not None:
        m, fields, _ = _ties_and_floors(m, walls, 0.0)
    return Problem("block", m, {"facade": strength.Rigid()}, interfaces={"base": interface},
                   supports=fields["supports"], ties=fields["ties"],
                   live_body={"facade": (-WG * (extra or 1.0), 0.0)},
                   dead_body={"facade": (0.0, -WG * (extra or 1.0))} | fields["dead_body"])


def bracket(p):
    return solve_static(p).multiplier, solve_kinematic(p).multiplier


def test_rigid_block_on_capped_joint_brackets_the_stress_block():
    """Exact: N = W on a rectangular block of depth w = W/fc at the toe; moments about its
    resultant (w/2): λ W h/2 = W (b − w)/2, λ = (b − w)/h. The kinematic balance about a hinge
    at x_c, λ W h/2 = W (b/2 − x_c) + fc x_c²/2, is least at x_c = w and gives the same λ.
    The hinge depth w = 0.12 m lies inside an element (columns of 0.025 m): a real gap,
    which closes like the column width squared (measured: 1.1 %, 0.18 %, 0.069 % at 10, 20,
    40 columns)."""
    W = WG * B * H
    w = 0.12
    fc = W / w
    exact = (B - w) / H
    kin = minimize_scalar(lambda xc: (W * (B / 2 - xc) + fc * xc ** 2 / 2) / (W * H / 2),
                          bounds=(0.0, B), method="bounded", options={"xatol": 1e-12})
    assert kin.fun == pytest.approx(exact, rel=1e-9) and kin.x == pytest.approx(w, rel=1e-6)
    lo, up = bracket(block_problem(strength.BedJoints(F_, fc=fc), nb=20))
    assert lo <= exact * (1 + TOL) and up >= exact * (1 - TOL)
    assert (up - lo) / exact < 0.003, (lo, up, exact)
    assert exact < B / H                          # the cap lowers the rigid block's b/h


def test_rigid_block_with_a_top_tie():
    """The tie at the top pulls the façade towards the wall over the top course's band: its
    outer-face facets within a/2 of z = H, here [H − a/2, H] (facets of a/2), resultant at
    z_t = H − a/4. About the toe: λ W h/2 = W b/2 + ρ T_y z_t (per unit section thickness the
    tie carries ρ = l/s times its force per metre of façade, like the façade's weight)."""
    a, T = 0.5, 2000.0
    wall = Wall(H=H, b=B, L=2.0, s=0.5, l=6.0)
    case = Case(wall, Masonry(a=a, c=0.2, f=F_), ties=(Tie(H, T),))
    rho = wall.l / wall.s
    W = WG * rho * B * H
    z_t = H - a / 4
    exact = (W * B / 2 + rho * T * z_t) / (W * H / 2)
    assert exact < F_                                # it tilts, it does not slide
    lo, up = bracket(block_problem(strength.BedJoints(F_), extra=rho, walls=case))
    assert lo <= exact * (1 + TOL) and up >= exact * (1 - TOL)
    assert (up - lo) / exact < 1e-6, (lo, up, exact)


@pytest.mark.parametrize("e", [0.1, 0.4])
def test_rigid_block_with_a_floor_load(e):
    """A floor's vertical load Q (per metre of façade) at eccentricity e: λ W h/2 = W b/2 +
    ρ Q e about the toe, whatever its height (a vertical force's moment about the toe)."""
    Q = 30000.0
    wall = Wall(H=H, b=B, L=2.0, s=0.5, l=6.0)
    case = Case(wall, Masonry(a=0.5, c=0.2, f=F_), floors=(Floor(1.0, Q, e),))
    rho = wall.l / wall.s
    W = WG * rho * B * H
    exact = (W * B / 2 + rho * Q * e) / (W * H / 2)
    lo, up = bracket(block_problem(strength.BedJoints(F_), extra=rho, walls=case))
    assert lo <= exact * (1 + TOL) and up >= exact * (1 - TOL)
    assert (up - lo) / exact < 1e-6, (lo, up, exact)


# ----------------------------------------------------------------------- the T-section

def test_t_section_places_ties_and_floors_with_their_resultants():
    """B1 with a tie at 6 m and a floor at 4.5 m: the tie's traction integrates to ρ T_y, the
    floor's body forces to ρ Q with moment ρ Q e about the outer face; a restraining floor is a
    support v_x = 0 on the outer face at its height; no tie or floor: no extra tags."""
    T, Q, e = 5000.0, 20000.0, 0.1
    case = Case(ties=(Tie(6.0, T),), floors=(Floor(4.5, Q, e, restrains=True),))
    rho = case.rho
    p = t_section(case, h=0.5)
    m = p.mesh
    f = np.asarray(m.boundaries["tie0"])
    ends = m.p[:, m.facets[:, f]]
    assert np.allclose(ends[0], 0.0)                                     # on the outer face
    length = np.abs(ends[1, 1] - ends[1, 0]).sum()
    assert p.ties["tie0"][0] * length == pytest.approx(rho * T, rel=1e-12)
    assert abs(ends[1].mean() - 6.0) <= 0.25 + 1e-9                      # within one row
    force = moment = 0.0
    x, z = m.p[0, m.t], m.p[1, m.t]
    area = 0.5 * np.abs((x[1] - x[0]) * (z[2] - z[0]) - (x[2] - x[0]) * (z[1] - z[0]))
    for name, (fx, fz) in p.dead_body.items():
        if name.startswith("floor0"):
            els = m.subdomains[name]
            assert fx == 0 and np.all(x[:, els] <= case.wall.b + 1e-12)
            force += fz * area[els].sum()
            moment += fz * (area[els] * x[:, els].mean(axis=0)).sum()
    assert force == pytest.approx(-rho * Q, rel=1e-12)
    assert moment / force == pytest.approx(e, rel=1e-12)
    assert p.supports["floor0_held"] == "x"
    held = m.p[:, m.facets[:, m.boundaries["floor0_held"]]]
    assert np.allclose(held[0], 0.0) and np.all(np.abs(held[1] - 4.5) <= 0.5 + 1e-9)
    plain = t_section(Case(), h=0.5)
    assert set(plain.mesh.boundaries) == {"base", "outer", "top", "end"} and not plain.ties


@pytest.mark.parametrize("facade", ["homogenised", "bedjoints"])
def test_t_section_bracket_holds_with_cap_tie_floor(facade):
    """The whole B1 T-section on a coarse mesh with f_c = 2 MPa, a top tie and a floor: both
    programs take the same problem, so λ⁻ <= λ⁺; the cap weakens the wall, the tie
    strengthens it; the static field keeps every principal stress >= −fc (the façade strip's
    >= −ρ fc)."""
    base = Case()
    fc = 2e6
    capped = Case(masonry=Masonry(fc=fc))
    real = Case(masonry=Masonry(fc=fc), ties=(Tie(9.0, 10000.0),),
                floors=(Floor(4.5, 20000.0, 0.1),))
    out = {}
    for name, case in (("base", base), ("capped", capped), ("real", real)):
        p = t_section(case, facade=facade, h=1.0)
        s, k = solve_static(p), solve_kinematic(p)
        assert s.multiplier <= k.multiplier * (1 + TOL), name
        out[name] = (s, k)
        if case.masonry.fc:   # the façade strip's stresses are ρ times the façade's
            for reg, cap in (("facade", case.rho * fc), ("wall", fc)):
                sig = s.stress[p.mesh.subdomains[reg]].reshape(-1, 3)
                low = 0.5 * (sig[:, 0] + sig[:, 1]) - np.hypot(0.5 * (sig[:, 0] - sig[:, 1]),
                                                                sig[:, 2])
                assert low.min() >= -cap * (1 + 1e-6), reg
    assert out["capped"][1].multiplier < out["base"][1].multiplier
    assert out["real"][0].multiplier > out["capped"][0].multiplier


def test_fc_zero_builds_the_paper_domains():
    """fc = 0 (infinite) keeps the paper's domains themselves, not a capped copy."""
    p = t_section(Case(), facade="bedjoints", h=1.0)
    assert type(p.domains["facade"]) is strength.BedJoints
    assert type(p.domains["wall"]) is strength.Homogenised
    q = t_section(Case(masonry=Masonry(fc=1e6)), h=1.0)
    assert isinstance(q.domains["wall"], strength.Capped) and q.domains["wall"].fc == 1e6
    assert q.domains["facade"].fc == 12e6              # ρ fc: the strip stands for l/s of it
    assert math.isinf(strength.capped(strength.Tresca(1.0), 0.0).support(
        np.array([1.0, 0.0, 0.0])))


# ----------------------------------------------------------------------- the case file

def test_case_file_fe_takes_fc_ties_floors_and_joint_strengths():
    """[analysis] fe takes [masonry] fc, ties, floors, cohesion and tension (with a cohesion
    its v̄_g is not available: tests/test_fe_bond.py); the closed forms still refuse the
    joint strengths, naming the key and the model, and not the keys they take."""
    from homlimit.app.config import ConfigError, load_case

    base = b1(masonry={"fc": 2e6}, analysis={"fe": True, "hinge_check": False,
                                             "closed_form": False},
              tie=[{"z": 9.0, "yield_force": 5e3}],
              floor=[{"z": 4.5, "load": 1e4, "eccentricity": 0.1, "restrains": True}])
    c = load_case(base).case
    assert c.masonry.fc == 2e6 and c.ties[0].yield_force == 5e3 and c.floors[0].restrains
    for k in ("cohesion", "tension"):
        wet = {**base, "masonry": {**base["masonry"], k: 1e5}}
        assert getattr(load_case(wet).case.masonry, k) == 1e5
        with pytest.raises(ConfigError) as e:
            load_case({**wet, "analysis": {**wet["analysis"], "closed_form": True}})
        msg = str(e.value)
        assert f"[masonry] {k} = 100000.0 Pa: the closed forms" in msg, msg
        assert "[analysis] fe = true" not in msg and "[[tie]]" not in msg, msg


def test_stress_png_states_fc_and_the_peak(tmp_path):
    """stress.png's title: f_c and the masonry's peak compression (the façade strip's section
    stresses over ρ), which the capped static field keeps <= f_c."""
    from homlimit.app.plots import plot_stress
    from homlimit.fe.static.solution import peak_compression

    fc = 1e6
    case = Case(masonry=Masonry(fc=fc))
    s = solve_static(t_section(case, facade="bedjoints", h=1.0))
    peak = peak_compression(s, case.rho)
    fac = s.stress[s.mesh.subdomains["facade"]].reshape(-1, 3) / case.rho
    by_hand = -(0.5 * (fac[:, 0] + fac[:, 1]) - np.hypot(0.5 * (fac[:, 0] - fac[:, 1]),
                                                        fac[:, 2])).min()
    assert by_hand <= peak <= fc * (1 + 1e-6)
    assert peak > 0.9 * fc                     # the façade's toe reaches the cap at collapse
    out = plot_stress(tmp_path / "s.png", s, fc=fc, rho=case.rho)
    assert out.stat().st_size > 0


def test_t_section_takes_cohesion_and_tension():
    """Cohesion and tension from the case enter both bounds (the domains' cohesive forms, the
    façade strip's times ρ): the bracket holds and the wall is stronger than dry."""
    dry = t_section(Case(), facade="bedjoints", h=1.0)
    wet = t_section(Case(masonry=Masonry(cohesion=2e4, tension=1e4)), facade="bedjoints", h=1.0)
    assert wet.domains["facade"].cohesion == pytest.approx(12 * 2e4)
    assert wet.domains["wall"].cohesion == 2e4 and wet.domains["wall"].tension == 1e4
    lo, up = solve_static(wet).multiplier, solve_kinematic(wet).multiplier
    assert lo <= up * (1 + TOL)
    assert lo > solve_kinematic(dry).multiplier        # above the dry wall's upper bound


def test_quadratic_stresses_take_the_cap_on_every_control_coefficient():
    """stress_degree 2: the cap holds at all six Bernstein coefficients of every triangle
    (the stress is their convex combination, so it holds everywhere) and λ⁻ <= λ⁺."""
    from homlimit.fe.solver import SolverOptions

    fc = 1e6
    case = Case(masonry=Masonry(fc=fc))
    p = t_section(case, facade="homogenised", h=1.0)
    s = solve_static(p, SolverOptions(stress_degree=2))
    assert s.control.shape[1] == 6
    for reg, cap in (("facade", case.rho * fc), ("wall", fc)):
        c = s.control[p.mesh.subdomains[reg]].reshape(-1, 3)
        low = 0.5 * (c[:, 0] + c[:, 1]) - np.hypot(0.5 * (c[:, 0] - c[:, 1]), c[:, 2])
        assert low.min() >= -cap * (1 + 1e-6), reg
    assert s.multiplier <= solve_kinematic(p).multiplier * (1 + TOL)
