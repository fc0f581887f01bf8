"""The rigid-block LA and impulse of a real wall (issue 30): ties, floors and f_c on a stack of
blocks, against hand computations of the overturning of the part above each joint (written
out here, not the package's closed forms). docs/real-walls.md, "Rigid blocks"."""

import math

import numpy as np
import pytest
from scipy.optimize import minimize_scalar

from homlimit.blocks import block_impulse, equilibrium_residual, solve_blocks, stack
from homlimit.blocks.real import RealActions
from homlimit.errors import ParameterError

from cases import b1, run_cli

RHO, B, G, H, N_BLK = 1000.0, 0.5, 9.81, 9.0, 10     # kg/m² per slab of depth 1 m, m, m/s², m
Z_J = np.arange(N_BLK) * H / N_BLK                   # the joints (the base first)


def column(real, f=0.6):
    A = stack(np.full(N_BLK, B), np.full(N_BLK, H / N_BLK), density=RHO,
              meta={"f": f, "g": G, "b": B, "H": H, "real": real})
    return A, solve_blocks(A)


def overturning(T=0.0, z_t=H, Q=0.0, z_q=H, e=0.0, fc=0.0, depth=1.0, above=-1.0):
    """λ of the part above each joint z_j overturning about its (retreated) toe: moments about
    the resultant of the joint's stress block, at t = w/2 = N/(2 fc d) from the outer face
    (N the weight above plus the floor load if it bears on the part, z_q > z_j); a tie at
    z_t > z_j pulls T inwards, lever z_t − z_j. Joints at or below ``above`` are held."""
    m = RHO * B * (H - Z_J)
    Qj = np.where(z_q > Z_J + 1e-9, Q, 0.0)
    N = m * G + Qj
    t = N / (2 * fc * depth) if fc else 0.0 * N
    Tm = np.where(z_t > Z_J + 1e-9, T * (z_t - Z_J), 0.0)
    lam = (m * G * (B / 2 - t) + Qj * (e - t) + Tm) / (m * G * (H - Z_J) / 2)
    return np.where(Z_J >= above - 1e-9, lam, np.inf)


@pytest.mark.parametrize("T", [100.0, 500.0, 1000.0])
def test_top_tie_matches_simple_overturning(T):
    # a tie at the top at three yield forces: λ = min over the joints of the overturning with
    # the tie's moment T (H − z_j); it yields (F = T_y) and the column turns about its toe
    A, r = column(RealActions(ties=[(H, T, 0.0, 0.0)]))
    ref = overturning(T=T)
    assert r.multiplier == pytest.approx(ref.min(), rel=1e-6)
    assert int(ref.argmin()) == 0 and r.z_base == pytest.approx(0.0, abs=1e-9)
    assert r.actions["tie_force"][0] == pytest.approx(T, rel=1e-6)
    scale = RHO * B * H * G
    assert np.abs(equilibrium_residual(A, r)).max() < 1e-6 * scale


def test_stronger_top_tie_finds_a_lower_mechanism():
    # at T = 2 kN the top block rocks backwards on the one below (the tie no longer yields):
    # the LA is below the single overturning (an upper bound), as it must be
    A, r = column(RealActions(ties=[(H, 2000.0, 0.0, 0.0)]))
    assert r.multiplier < overturning(T=2000.0).min() * (1 - 1e-3)
    assert r.actions["tie_force"][0] < 2000.0


@pytest.mark.parametrize("fc", [2e5, 5e5, 2e6])
def test_crushing_cap_is_the_rectangular_stress_block(fc):
    # the hinge retreats to the stress block's resultant, t = w/2, w = N/fc (per metre):
    # λ = (b/2 − w/2)/z_G; the mechanism turns about the block's inner edge x = w (the
    # kinematic optimum of the crushing work fc w²/2 θ̇ against the lost lever)
    A, r = column(RealActions(fc=fc))
    ref = overturning(fc=fc)
    assert r.multiplier == pytest.approx(ref.min(), rel=1e-6)
    w = RHO * B * H * G / fc
    # λ is quadratic in the rotation centre near its optimum: a solver tolerance ε on λ
    # leaves the centre to ~√ε (measured 1e-5 to 3e-5 relative)
    assert r.fit.O[0] == pytest.approx(w, rel=1e-3)
    assert r.fit.O[1] == pytest.approx(0.0, abs=1e-6)
    # the static dual at the base: the resultant N at w/2 from the toe, N = the weight
    jt = A.interfaces
    base = np.flatnonzero((A.fixed[jt.a] | A.fixed[jt.b]) & (jt.p[:, :, 1].max(axis=1) < 1e-9))
    Nb = r.normal[base].sum()
    xr = (r.normal[base] * jt.p[base, :, 0]).sum() / Nb
    assert Nb == pytest.approx(RHO * B * H * G, rel=1e-6)
    assert xr == pytest.approx(w / 2, rel=1e-5)
    # the crushing dissipation rate fc ∫ (−δ_n)⁺ = fc x_O² ω / 2 at the base (rotation about
    # x_O: the toe sinks at ω (x_O − x)), nowhere else
    omega = abs(r.velocity[1, 2])
    x_o = r.fit.O[0]
    assert r.actions["crushing_rate"].sum() == pytest.approx(fc * x_o ** 2 * omega / 2,
                                                             rel=1e-6)


def test_infinite_fc_and_no_actions_keep_the_paper_program():
    A0, r0 = column(None)
    A1, r1 = column(RealActions())               # nothing active: the paper's program
    assert r1.multiplier == r0.multiplier and r1.actions == {}
    assert r0.multiplier == pytest.approx((B / 2) / (H / 2), rel=1e-6)


@pytest.mark.parametrize("e", [0.1, 0.4])
def test_floor_load_at_mid_height(e):
    # a 5 kN floor at z = 4.5 m (a joint: it bears on the block below): the parts above the
    # joints below it carry Q (e from the outer face) in their resisting moment
    A, r = column(RealActions(floors=[(4.5, 5000.0, e, 0.0)]))
    ref = overturning(Q=5000.0, z_q=4.5, e=e)
    assert r.multiplier == pytest.approx(ref.min(), rel=1e-6)
    assert np.abs(equilibrium_residual(A, r)).max() < 1e-6 * RHO * B * H * G


def test_restraining_floor_holds_the_part_below():
    # restraining at 4.5 m: the failing part lies above it, λ = min over z_j >= 4.5 m; the
    # reaction balances the part below's share of the horizontal load
    A, r = column(RealActions(floors=[(4.5, 5000.0, 0.4, 1.0)]))
    ref = overturning(Q=5000.0, z_q=4.5, e=0.4, above=4.5)
    assert r.multiplier == pytest.approx(ref.min(), rel=1e-6)
    assert r.z_base == pytest.approx(4.5, abs=1e-9)
    assert np.abs(equilibrium_residual(A, r)).max() < 1e-6 * RHO * B * H * G


def test_floor_and_crushing_together():
    A, r = column(RealActions(fc=5e5, floors=[(4.5, 5000.0, 0.4, 0.0)]))
    ref = overturning(Q=5000.0, z_q=4.5, e=0.4, fc=5e5)
    assert r.multiplier == pytest.approx(ref.min(), rel=1e-6)


def _peak(W):
    o = minimize_scalar(lambda t: -W(t), bounds=(0.0, math.pi / 2), method="bounded",
                        options={"xatol": 1e-12})
    return o.x, W(o.x)


@pytest.mark.parametrize("T", [100.0, 1000.0])
def test_impulse_with_a_top_tie(T):
    # eq. 7 about the toe, the tie's work T_y H sin θ (rigid-plastic, the closed forms' rule)
    A, r = column(RealActions(ties=[(H, T, 0.0, 0.0)]))
    bi = block_impulse(A, r)
    m, zg = RHO * B * H, H / 2
    I_O = m * (H ** 2 + B ** 2) / 3
    th, Wm = _peak(lambda t: m * G * (B / 2 * math.sin(t) + zg * (math.cos(t) - 1))
                   + T * H * math.sin(t))
    assert bi.theta_m == pytest.approx(th, rel=1e-6)
    assert bi.vg == pytest.approx(math.sqrt(2 * Wm * I_O) / (m * zg), rel=1e-6)
    assert bi.W_real["W_ties"] == pytest.approx(T * H * math.sin(th), rel=1e-6)


def test_impulse_with_an_elastic_brittle_tie():
    # k = 20 kN/m per m, T_y = 1 kN, breaks at 0.2 m: W_tie = T (δ_u − T/2k) past θ_u
    T, k, du = 1000.0, 2e4, 0.2
    A, r = column(RealActions(ties=[(H, T, k, du)]))
    bi = block_impulse(A, r)
    m, zg = RHO * B * H, H / 2
    I_O = m * (H ** 2 + B ** 2) / 3

    def W(t):
        d = min(H * math.sin(t), du)
        wt = 0.5 * k * d ** 2 if d <= T / k else T * (d - T / (2 * k))
        return m * G * (B / 2 * math.sin(t) + zg * (math.cos(t) - 1)) + wt

    grid = np.linspace(0, math.pi / 2, 20001)
    j = int(np.argmax([W(t) for t in grid]))
    o = minimize_scalar(lambda t: -W(t), bounds=(grid[max(j - 1, 0)], grid[j + 1]),
                        method="bounded", options={"xatol": 1e-12})
    assert bi.vg == pytest.approx(math.sqrt(2 * W(o.x) * I_O) / (m * zg), rel=1e-6)


def test_impulse_with_crushing():
    # the mechanism turns about x = w with the crushing work N (w/2) θ (first order): eq. 7
    # about (w, 0); the closed forms' rotation about w/2 without crushing work differs at
    # second order in w (0.02 % here)
    fc = 2e5
    A, r = column(RealActions(fc=fc))
    bi = block_impulse(A, r)
    m, zg = RHO * B * H, H / 2
    N = m * G
    w = N / fc
    I_w = m * (H ** 2 + B ** 2) / 3 + m * (w ** 2 - B * w)
    th, Wm = _peak(lambda t: N * ((B / 2 - w) * math.sin(t) + zg * (math.cos(t) - 1))
                   + N * w / 2 * t)
    assert bi.vg == pytest.approx(math.sqrt(2 * Wm * I_w) / (m * zg), rel=1e-5)
    t = w / 2
    I_t = m * (H ** 2 + B ** 2) / 3 + m * (t ** 2 - B * t)
    _, W_t = _peak(lambda s: N * ((B / 2 - t) * math.sin(s) + zg * (math.cos(s) - 1)))
    assert bi.vg == pytest.approx(math.sqrt(2 * W_t * I_t) / (m * zg), rel=1e-3)


def test_impulse_with_a_floor():
    # the floor's load turns with the body exactly: Q ((e) sin θ + z_Q (cos θ − 1)) (the
    # whole column fails: the floor at 4.5 m on it, e = 0.4)
    Q, e, zq = 5000.0, 0.4, 4.5
    A, r = column(RealActions(floors=[(zq, Q, e, 0.0)]))
    bi = block_impulse(A, r)
    assert r.z_base == pytest.approx(0.0, abs=1e-9)
    m, zg = RHO * B * H, H / 2
    I_O = m * (H ** 2 + B ** 2) / 3
    th, Wm = _peak(lambda t: m * G * (B / 2 * math.sin(t) + zg * (math.cos(t) - 1))
                   + Q * (e * math.sin(t) + zq * (math.cos(t) - 1)))
    assert bi.vg == pytest.approx(math.sqrt(2 * Wm * I_O) / (m * zg), rel=1e-6)


def test_non_associative_refused_with_real_actions():
    A = stack(np.full(3, B), np.full(3, 1.0), density=RHO,
              meta={"f": 0.6, "g": G, "real": RealActions(fc=1e6)})
    with pytest.raises(ParameterError, match="friction = 'non-associative'"):
        solve_blocks(A, friction="non-associative")


CASE = b1(masonry={"fc": 2e6},
          analysis={"fe": False, "hinge_check": False, "closed_form": False,
                    "overturning": True, "blocks": True},
          blocks={"step": 10}, tie=[{"z": 9.0, "yield_force": 2000.0}])


def test_cli_blocks_take_ties_and_fc(tmp_path):
    import json

    r = run_cli(tmp_path, CASE, "run", "-q")
    assert r.returncode == 0, r.stderr
    assert "no unit registered" not in r.stderr
    s = json.loads((tmp_path / "out" / "summary.json").read_text())
    blk = s["mechanisms"]["blocks"]
    # the tie at the top yields at 2 kN/m × l = 12 kN in the critical mechanism
    assert blk["tie_force"] == pytest.approx(12000.0, rel=1e-6)
    assert blk["W_ties"] > 0 and blk["W_crushing"] > 0
    real = s["blocks"]["settings"]["real"]
    assert real["fc"] == 2e6 and real["ties"][0]["yield_force_N"] == 12000.0
    # cohesion: the closed forms (the overturning) refuse it, the blocks alone take it
    bond = {**CASE, "masonry": {**CASE["masonry"], "cohesion": 1e4}}
    r = run_cli(tmp_path, bond, "run", out="bad")
    assert r.returncode == 2 and "[masonry] cohesion = 10000.0 Pa: the closed forms" in r.stderr
    assert not (tmp_path / "bad").exists() and "Traceback" not in r.stderr
    r = run_cli(tmp_path, {**bond, "blocks": {"step": 10, "friction": "non-associative"},
                           "analysis": {**CASE["analysis"], "overturning": False}},
                "run", out="bad")
    assert r.returncode == 2 and "the non-associative scheme does not take them" in r.stderr
    assert not (tmp_path / "bad").exists() and "Traceback" not in r.stderr


@pytest.mark.slow
def test_cli_blocks_take_cohesion_and_tension(tmp_path):
    # the blocks' λ takes them (its hand checks: tests/test_blocks_bond.py); v̄_g is not
    # available (no softening rule), said in the summary and the terminal, and the run writes
    import json

    case = {**CASE, "masonry": {**CASE["masonry"], "cohesion": 1e4, "tension": 5e3},
            "analysis": {**CASE["analysis"], "overturning": False}}
    r = run_cli(tmp_path, case, "run", "-q")
    assert r.returncode == 0, r.stderr
    assert "no unit registered" not in r.stderr
    s = json.loads((tmp_path / "out" / "summary.json").read_text())
    blk = s["mechanisms"]["blocks"]
    assert blk["vg"] is None and blk["method"].startswith("not available: [masonry] cohesion")
    assert "softening rule" in blk["method"] and s["critical"] is None
    assert blk["multiplier"] > 0 and blk["bond_rate"] > 0
    real = s["blocks"]["settings"]["real"]
    assert (real["cohesion"], real["tension"], real["tension_effective"]) == (1e4, 5e3, 5e3)
    assert all(rec["vg"] is None for rec in s["blocks"]["scan"])
    # the LA is the whole wall's: its multiplier is the least of the scan's
    assert blk["multiplier"] == min(rec["multiplier"] for rec in s["blocks"]["scan"])


def test_dem_takes_a_finite_fc_as_caps_along_the_joints():
    # (the cap's checks against hand results: tests/test_dem_crush.py)
    from homlimit.dem.model import build_model

    A = stack(np.full(3, B), np.full(3, 1.0), density=RHO,
              meta={"f": 0.6, "g": G, "real": RealActions(fc=1e6)})
    model = build_model(A)
    assert model.info["fc"] == 1e6 and model.info["joint_points"] == 3 * 7


def _dem_column(real):
    from homlimit.dem.model import build_model, settle

    A = stack(np.full(N_BLK, B), np.full(N_BLK, H / N_BLK), density=RHO,
              meta={"f": 0.6, "g": G, "real": real})
    model = build_model(A)
    return model, settle(model)[0]


def _dem_step(model, settled, lam, t_max=2.0):
    from homlimit.dem.model import run

    return run(model, settled, pulse=lambda t: np.full_like(t, lam * G), t_max=t_max)


def test_dem_tie_holds_the_column_below_its_static_threshold():
    # a top tie of 1 kN: the static threshold (m g b/2 + T H)/(m g H/2) = 0.1009 (hand, as
    # the LA above) against b/H = 0.0556 without it; a constant ground acceleration of 0.09 g
    # topples the free column, not the tied one, whose tie ends at the static force
    # (0.09 m g H/2 − m g b/2)/H = 760 N (elastic, after a transient yield); 0.11 g topples it
    T = 1000.0
    mg = RHO * B * H * G
    lam_T = (mg * B / 2 + T * H) / (mg * H / 2)
    assert lam_T == pytest.approx(0.10086, rel=1e-4)
    model0, st0 = _dem_column(None)
    assert _dem_step(model0, st0, 0.09).collapsed
    model, st = _dem_column(RealActions(ties=[(H, T, 0.0, 0.0)]))
    safe = _dem_step(model, st, 0.09, t_max=3.0)
    assert not safe.collapsed
    tie = model.ties[0]
    b = int(tie[0])
    th = safe.state.th[b]
    x = safe.state.pos[b, 0] + math.cos(th) * tie[1] - math.sin(th) * tie[2]
    F = tie[4] * (tie[3] - x - safe.state.tstate[0, 0])
    assert F == pytest.approx((0.09 * mg * H / 2 - mg * B / 2) / H, rel=0.05)
    assert _dem_step(model, st, 0.11).collapsed


def test_dem_brittle_tie_breaks():
    # the same tie breaking at 1 mm: the onset's transient stretches it past that, it breaks
    # and the column falls at 0.09 g
    model, st = _dem_column(RealActions(ties=[(H, 1000.0, 0.0, 1e-3)]))
    out = _dem_step(model, st, 0.09)
    assert out.collapsed and out.state.tstate[0, 1] == 1.0


def test_dem_floor_load():
    # a 5 kN floor at 4.5 m, e = 0.4 m: threshold (m g b/2 + Q e)/(m g H/2) = 0.0656 (the
    # LA's, above): 0.06 g (which topples the bare column) is safe, 0.072 g topples it
    assert _dem_step(*_dem_column(None), 0.06).collapsed
    model, st = _dem_column(RealActions(floors=[(4.5, 5000.0, 0.4, 0.0)]))
    assert model.loads.shape == (1, 5) and model.loads[0, 4] == -5000.0
    assert not _dem_step(model, st, 0.06).collapsed
    assert _dem_step(model, st, 0.072).collapsed


def test_t_section_of_a_real_case_carries_its_actions_per_bay():
    import dataclasses

    from homlimit.blocks import t_section_blocks
    from homlimit.params import Case, Floor, Masonry, Tie

    case = Case(ties=(Tie(9.0, 2000.0, stiffness=1e5),), floors=(Floor(4.5, 2e4, 0.1, True),),
                masonry=Masonry(fc=2e6))
    real = t_section_blocks(case).meta["real"]
    l, s = case.wall.l, case.wall.s  # noqa: E741 (the paper's l)
    assert real.ties.tolist() == [[9.0, 2000.0 * l, 1e5 * l, 0.0]]
    assert real.floors.tolist() == [[4.5, 2e4 * l, 0.1, 1.0]]
    assert (real.fc, real.depth_facade, real.depth_wall) == (2e6, l, s)
    assert "real" not in t_section_blocks(Case()).meta
    # cohesion and tension are stresses: the contacts' depth (l, s) carries them, not × l
    bond = t_section_blocks(dataclasses.replace(case, masonry=Masonry(cohesion=1e3,
                                                                      tension=500.0)))
    assert (bond.meta["real"].cohesion, bond.meta["real"].tension) == (1e3, 500.0)
