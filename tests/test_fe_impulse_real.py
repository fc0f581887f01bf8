"""Issue 30, the FE path's impulse with ties and floors (``fe_impulse.BodyLoads``) against
hand computations that do not reuse the package's code.

The reference: a rigid body of mass m turning outwards about O by q, with G at (x_G, z_G)
from O, a floor load Q at (x_F, z_F) from O on the body and a rigid-plastic tie T_y at the
outer face, d above O, restores

    W(q) = A sin q − B (1 − cos q),   A = m g x_G + Q x_F + T_y d,   B = m g z_G + Q z_F,

(the tie's work T_y d sin q: the closed forms' elongation d sin θ), whose peak is at
tan q_m = A/B with W_m = √(A² + B²) − B; eq. 7 gives v̄_g = √(2 W_m I_O)/(m z_G).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import skfem as fem

from homlimit.errors import ParameterError
from homlimit.fe import strength
from homlimit.fe.kinematic import solve_kinematic
from homlimit.fe.problems import Problem, _ties_and_floors, crossed_mesh
from homlimit.mechanism.fe_impulse import BodyLoads, body_loads, generalised_impulse, p2_nodes
from homlimit.mechanism.rigidfit import measure_mechanism
from homlimit.params import Case, Floor, Masonry, Tie, Wall

G = 9.81


def hand(m, xg, zg, I_O, floors=(), ties=()):
    """(q_m, W_m, v̄_g) of the reference (module docstring); floors (Q, x_F, z_F), ties
    (T_y, d), all from O."""
    A = m * G * xg + sum(Q * x for Q, x, _ in floors) + sum(T * d for T, d in ties)
    B = m * G * zg + sum(Q * z for Q, _, z in floors)
    W = math.hypot(A, B) - B
    return math.atan2(A, B), W, math.sqrt(2 * W * I_O) / (m * zg)


def rocking_field(b, h, z_hinge=0.0, nx=4, ny=24, omega=0.3):
    """P2 nodes of a b × h rectangle whose part above z_hinge turns about (0, z_hinge) at
    rate ω, the part below at rest (a mesh line at z_hinge)."""
    mesh = fem.MeshTri.init_tensor(np.linspace(0, b, nx + 1), np.linspace(0, h, ny + 1))
    sb = fem.Basis(mesh, fem.ElementTriP2())
    X, el = sb.doflocs.T.copy(), sb.element_dofs.T.copy()
    up = X[:, 1] >= z_hinge - 1e-12
    V = omega * np.stack([-(X[:, 1] - z_hinge), X[:, 0]], axis=1) * up[:, None]
    return X, V, el


def test_rigid_block_with_a_tie_and_a_floor_is_the_hand_formula():
    """A free block b × h rocking about its toe, a top tie (d = h) and a floor load at (e, z):
    v̄_g, q_m and the floors' and ties' parts of W(q_m) as by hand."""
    b, h, rho = 0.5, 3.0, 1800.0
    X, V, el = rocking_field(b, h)
    m, I_O = rho * b * h, rho * b * h * (b * b + h * h) / 3
    Q, e, zf, T = 4000.0, 0.4, 1.5, 1500.0
    loads = BodyLoads(floors=((Q, e, zf),), ties=((h, T, 0.0, math.inf),))
    gi = generalised_impulse(X, V, el, rho, measure_mechanism(X, V, el, rho), g=G, loads=loads)
    q, W, vg = hand(m, b / 2, h / 2, I_O, floors=[(Q, e, zf)], ties=[(T, h)])
    assert gi.q_m == pytest.approx(q, rel=1e-7)
    assert gi.W_m == pytest.approx(W, rel=1e-12)
    assert gi.vg == pytest.approx(vg, rel=1e-12)
    assert gi.W_ties == pytest.approx(T * h * math.sin(q), rel=1e-7)
    assert gi.W_floors == pytest.approx(Q * (e * math.sin(q) + zf * (math.cos(q) - 1)),
                                        rel=1e-6)
    bare = hand(m, b / 2, h / 2, I_O)[2]
    assert vg > 1.3 * bare                        # the tie and floor matter here


def hand_tie(delta, T, k=0.0, du=math.inf):
    """A tie's (work, force) at elongation δ >= 0, written out: rigid-plastic (k = 0) T δ and
    T; elastic-plastic ½ k δ² and k δ up to δ_y = T/k, then T (δ − δ_y/2) and T; beyond the
    ductility limit δ_u the work stays at its value there and the force is 0."""
    x = min(delta, du)
    if k == 0:
        work = T * x
    else:
        dy = T / k
        work = 0.5 * k * x * x if x <= dy else T * (x - 0.5 * dy)
    force = 0.0 if delta >= du else (T if k == 0 else min(k * delta, T))
    return work, force


def test_fe_rocker_with_a_tie_and_a_floor_is_the_rigid_block_by_hand():
    """The FE body's rocker (``GeneralisedRocker.from_impulse``) of a free block b × h rocking
    about its toe (the FE generalisation reduces to the rigid block: M = I_O, Π = m z_G, no
    rest), with a floor on it and a tie at its top, is the rigid block's rocker by hand:

        W(q) = m g (x_G sin q + z_G (cos q − 1)) + Q (e sin q + z_F (cos q − 1)) + W_T(h sin q),
        R(q) = m g (x_G cos q − z_G sin q)      + Q (e cos q − z_F sin q)      + N(h sin q) h cos q

    (the closed forms' rocker, ``dynamics.real_rocker``), for a rigid-plastic and an
    elastic–plastic tie with a ductility limit (``hand_tie``); its θ_m, W_m and v̄_g are the
    FE impulse criterion's, and with the rigid-plastic tie the hand formula's (module
    docstring); its static threshold R(0)/Π(0) = (m g x_G + Q e + T_y h)/(m z_G)."""
    from homlimit.dynamics import GeneralisedRocker

    b, h, rho = 0.5, 3.0, 1800.0
    X, V, el = rocking_field(b, h)
    m, I_O = rho * b * h, rho * b * h * (b * b + h * h) / 3
    Q, e, zf, T = 4000.0, 0.4, 1.5, 1500.0
    mm = measure_mechanism(X, V, el, rho)
    q = np.array([0.0, 0.003, 0.02, 0.1, 0.25, 0.6])
    for k, du in ((0.0, math.inf), (2.0e5, 0.5)):       # δ_y = 7.5 mm, δ_u = 0.5 m
        loads = BodyLoads(floors=((Q, e, zf),), ties=((h, T, k, du),))
        gi = generalised_impulse(X, V, el, rho, mm, g=G, loads=loads)
        rk = GeneralisedRocker.from_impulse(gi, g=G)
        assert rk.inertia == pytest.approx(I_O, rel=1e-12)
        assert rk.excitation(0.0) == pytest.approx(m * h / 2, rel=1e-12)
        W_hand = [m * G * (b / 2 * math.sin(t) + h / 2 * (math.cos(t) - 1))
                  + Q * (e * math.sin(t) + zf * (math.cos(t) - 1))
                  + hand_tie(h * math.sin(t), T, k, du)[0] for t in q]
        R_hand = [m * G * (b / 2 * math.cos(t) - h / 2 * math.sin(t))
                  + Q * (e * math.cos(t) - zf * math.sin(t))
                  + hand_tie(h * math.sin(t), T, k, du)[1] * h * math.cos(t) for t in q]
        np.testing.assert_allclose(rk.work(q), W_hand, rtol=1e-9, atol=1e-9 * m * G * h)
        np.testing.assert_allclose(rk.restoring(q), R_hand, rtol=1e-9)
        assert [rk.terms(t)[1] for t in q] == pytest.approx(R_hand, rel=1e-9)
        assert rk.theta_m == gi.q_m and rk.W_m == pytest.approx(gi.W_m, rel=1e-12)
        assert rk.vg_impulse == pytest.approx(gi.vg, rel=1e-12)
        assert rk.restoring(rk.theta_m) == pytest.approx(0.0, abs=1e-6 * m * G * b)
    # the rigid-plastic tie: the hand peak, and the static threshold with the tie's T_y h
    rp = GeneralisedRocker.from_impulse(generalised_impulse(
        X, V, el, rho, mm, g=G, loads=BodyLoads(floors=((Q, e, zf),),
                                                ties=((h, T, 0.0, math.inf),))), g=G)
    q_m, W_m, vg = hand(m, b / 2, h / 2, I_O, floors=[(Q, e, zf)], ties=[(T, h)])
    assert rp.theta_m == pytest.approx(q_m, rel=1e-7)
    assert rp.W_m == pytest.approx(W_m, rel=1e-12) and rp.vg_impulse == pytest.approx(vg,
                                                                                     rel=1e-12)
    assert rp.a_uplift == pytest.approx((m * G * b / 2 + Q * e + T * h) / (m * h / 2),
                                        rel=1e-12)


def test_fe_rocker_restoring_is_the_derivative_of_its_work():
    """R(q) = dW/dq by central differences (h = 1e-6) for a shape with a rest (M > I_O,
    Π ≠ m z_G, lift L) and every kind of load: a floor on the body and one on the rest, an
    elastic–plastic tie with a ductility limit on the body, a rigid-plastic one below the
    hinge (no work) and one on the rest (δ = a q), away from the ties' kinks."""
    from homlimit.dynamics import GeneralisedRocker
    from homlimit.impulse import LoadWork, RigidBody

    body = RigidBody(m=2000.0, x_G=0.25, z_G=1.5, I_O=6000.0)
    lw = LoadWork(floors_body=((3000.0, 0.4, 1.0),), floors_rest=((1500.0, 0.05),),
                  ties_body=((3.0, 2000.0, 1.0e5, 0.6), (-0.5, 900.0, 0.0, math.inf)),
                  ties_rest=((0.8, 700.0, 0.0, math.inf),))
    rk = GeneralisedRocker(6500.0, 3200.0, body, 1200.0, g=G, load_work=lw)
    # kinks: δ_y = 0.02 m at q = asin(0.02/3) = 0.00667, δ_u at asin(0.2) = 0.2014
    q = np.array([0.003, 0.05, 0.15, 0.3, 0.9, 1.4])
    dW = (rk.work(q + 1e-6) - rk.work(q - 1e-6)) / 2e-6
    np.testing.assert_allclose(rk.restoring(q), dW, rtol=1e-7)
    W_f, W_t = lw.parts(0.3)                          # the parts by hand at q = 0.3
    s, c1 = math.sin(0.3), math.cos(0.3) - 1
    assert W_f == pytest.approx(3000.0 * (0.4 * s + 1.0 * c1) + 1500.0 * 0.05 * 0.3, rel=1e-12)
    assert W_t == pytest.approx(hand_tie(3.0 * s, 2000.0, 1.0e5, 0.6)[0] + 700.0 * 0.8 * 0.3,
                                rel=1e-12)
    # the static threshold: R(0) = m g x_G + L + Q e + Q_r φ_z + N(0) (tie on the body:
    # elastic, N = 0; on the rest: rigid-plastic, 700 × 0.8) over Π(0)
    R0 = 2000.0 * G * 0.25 + 1200.0 + 3000.0 * 0.4 + 1500.0 * 0.05 + 700.0 * 0.8
    assert rk.a_uplift == pytest.approx(R0 / 3200.0, rel=1e-12)
    assert rk.restoring(rk.theta_m) == pytest.approx(0.0, abs=1e-6 * R0)
    assert LoadWork.from_dict(lw.as_dict()) == lw       # the FE cache's round trip


def test_fe_rocker_with_a_tie_stands_below_its_vg_and_overturns_above():
    """Under the ideal impulse of its own v̄_g (eq. 7 with the tie's and floor's work) ∓ 1 %,
    the FE body's rocker of the tied block stands / overturns: the time history's energy
    balance agrees with the FE impulse criterion."""
    from homlimit.dynamics import GeneralisedRocker, simulate

    X, V, el = rocking_field(0.5, 3.0)
    mm = measure_mechanism(X, V, el, 1800.0)
    gi = generalised_impulse(X, V, el, 1800.0, mm, g=G, loads=BodyLoads(
        floors=((4000.0, 0.4, 1.5),), ties=((3.0, 1500.0, 2.0e5, 0.5),)))
    rk = GeneralisedRocker.from_impulse(gi, g=G)
    w0 = gi.vg * rk.excitation(0.0) / rk.inertia
    assert not simulate(rk, theta_dot0=0.99 * w0, duration=5.0).overturned
    assert simulate(rk, theta_dot0=1.01 * w0, duration=5.0).overturned


def test_a_tie_below_the_hinge_adds_nothing():
    """Hinge at z = 1 m, the part below at rest: a tie at 0.5 m does not open (W_ties = 0)
    and leaves v̄_g as without it (``peak_work``'s closed form, eq. 19 generalised)."""
    X, V, el = rocking_field(0.5, 4.0, z_hinge=1.0)
    mm = measure_mechanism(X, V, el, 1800.0)
    bare = generalised_impulse(X, V, el, 1800.0, mm, g=G)
    low = generalised_impulse(X, V, el, 1800.0, mm, g=G,
                              loads=BodyLoads(ties=((0.5, 5000.0, 0.0, math.inf),)))
    assert low.W_ties == 0.0 and low.W_floors == 0.0
    assert low.vg == pytest.approx(bare.vg, rel=1e-12)
    assert low.q_m == pytest.approx(bare.q_m, rel=1e-7)


def test_a_floor_over_the_hinge():
    """A block b × h rocking about its toe: a floor on the hinge's vertical (x = 0) does no
    first-order work, only Q z_F (cos q − 1) < 0 (v̄_g lower, by hand); a floor at the hinge
    itself does none."""
    b, h, rho = 0.5, 3.0, 1800.0
    X, V, el = rocking_field(b, h)
    mm = measure_mechanism(X, V, el, rho)
    m, I_O = rho * b * h, rho * b * h * (b * b + h * h) / 3

    def run(**kw):
        return generalised_impulse(X, V, el, rho, mm, g=G, loads=BodyLoads(**kw))

    bare = hand(m, b / 2, h / 2, I_O)
    Q, zf = 5000.0, 2.0
    on_line = run(floors=((Q, 0.0, zf),))
    q, W, vg = hand(m, b / 2, h / 2, I_O, floors=[(Q, 0.0, zf)])
    assert on_line.vg == pytest.approx(vg, rel=1e-12) and vg < bare[2]
    assert on_line.W_floors == pytest.approx(Q * zf * (math.cos(q) - 1), rel=1e-6)
    at_hinge = run(floors=((Q, 0.0, 0.0),))
    assert at_hinge.W_floors == pytest.approx(0.0, abs=1e-12 * bare[1])
    assert at_hinge.vg == pytest.approx(bare[2], rel=1e-12)


def test_a_restraint_inside_the_body_is_refused():
    """A restraining floor at 3 m while the body turns about (0, 1): the rotation would carry
    the restrained point away (ParameterError); at the hinge's height it is consistent."""
    X, V, el = rocking_field(0.5, 4.0, z_hinge=1.0)
    mm = measure_mechanism(X, V, el, 1800.0)
    floor = ((1000.0, 0.1, 3.0),)
    with pytest.raises(ParameterError, match="restrains = true at z = 3"):
        generalised_impulse(X, V, el, 1800.0, mm, loads=BodyLoads(floor, (), (3.0,), 0.15))
    ok = generalised_impulse(X, V, el, 1800.0, mm, loads=BodyLoads(floor, (), (1.1,), 0.15))
    assert ok.vg > 0


def test_fe_block_with_a_top_tie_and_a_floor_by_hand():
    """The FE kinematic mechanism of a rigid block (b = 0.5, h = 2 m, 20 kN/m³ per unit
    thickness × ρ = l/s) on a no-tension base joint, with a tie at the top (T_y = 2 kN/m)
    and a floor (30 kN/m at z = 1 m, e = 0.1 m), placed by ``t_section``'s rule: the tie over
    the top course's band, resultant at H − a/4; the floor's patch symmetric about z = 1 with
    its resultant at e. The mechanism turns about the toe; its v̄_g (per bay of length l: the
    loads × l, the mass γ l b h) is the hand formula's."""
    B, H, WG, a = 0.5, 2.0, 2.0e4, 0.5
    T, Q, e = 2000.0, 30000.0, 0.1
    wall = Wall(H=H, b=B, L=2.0, s=0.5, l=6.0)
    case = Case(wall, Masonry(a=a, c=0.2, f=0.6), ties=(Tie(H, T),),
                floors=(Floor(1.0, Q, e),))
    rho = wall.l / wall.s
    m = crossed_mesh(np.linspace(0, B, 11), np.linspace(0, H, 9)).with_boundaries({
        "base": lambda x: np.abs(x[1]) < 1e-9, "outer": lambda x: np.abs(x[0]) < 1e-9,
    }).with_subdomains({"facade": lambda x: x[0] > -1.0})
    m, fields, placed = _ties_and_floors(m, case, 0.0)
    prob = Problem("block", m, {"facade": strength.Rigid()},
                   interfaces={"base": strength.BedJoints(0.6)}, ties=fields["ties"],
                   live_body={"facade": (-WG * rho, 0.0)},
                   dead_body={"facade": (0.0, -WG * rho)} | fields["dead_body"],
                   meta={"real_wall": placed})
    sol = solve_kinematic(prob)
    z_t = H - a / 4
    lam = (WG * rho * B * H * B / 2 + rho * T * z_t + rho * Q * e) / (WG * rho * B * H * H / 2)
    assert sol.multiplier == pytest.approx(lam, rel=1e-6)
    dens = WG * rho * wall.s / G                        # kg per m² of section, per bay
    X, Vel, el, rho_el = p2_nodes(sol, {"facade": dens})
    mm = measure_mechanism(X, Vel, el, rho_el)
    assert np.allclose(mm.fit.O, 0.0, atol=1e-6)
    loads = body_loads(case, prob)
    assert loads.ties[0][0] == pytest.approx(z_t) and loads.floors[0][1:] == \
        pytest.approx((e, 1.0))
    gi = generalised_impulse(X, Vel, el, rho_el, mm, g=G, loads=loads)
    mass = dens * B * H
    q, W, vg = hand(mass, B / 2, H / 2, mass * (B * B + H * H) / 3,
                    floors=[(Q * wall.l, e, 1.0)], ties=[(T * wall.l, z_t)])
    assert gi.vg == pytest.approx(vg, rel=1e-6)
    assert gi.W_m == pytest.approx(W, rel=1e-6)


def test_t_section_on_mesh_places_ties_and_floors_anew():
    """An adaptive remesh of a T-section with a tie and a restraining floor: the problem on
    the new mesh carries them as ``t_section`` built on that mesh does (same bands, loads,
    support and placement), none of the old mesh's tags."""
    from homlimit.fe.problems import t_section, t_section_on_mesh

    case = Case(ties=(Tie(9.0, 5000.0),), floors=(Floor(4.5, 2e4, 0.1, restrains=True),))
    coarse = t_section(case, h=1.0)
    direct = t_section(case, h=0.5)
    moved = t_section_on_mesh(coarse, case, t_section(Case(), h=0.5).mesh)
    assert moved.ties == direct.ties
    assert moved.supports == direct.supports
    assert set(moved.dead_body) == set(direct.dead_body)
    for k, v in direct.dead_body.items():
        assert moved.dead_body[k] == pytest.approx(v)
    for k in ("tie0", "floor0_held"):
        assert np.array_equal(moved.mesh.boundaries[k], direct.mesh.boundaries[k])
    assert moved.meta["real_wall"] == direct.meta["real_wall"]
    assert moved.meta["real_wall"]["floors"][0]["z_used"] == pytest.approx(4.5)
    bare = t_section(Case(), h=1.0)
    assert t_section_on_mesh(bare, Case(), direct.mesh).mesh is direct.mesh


def test_a_part_of_b1_with_a_top_tie():
    """B1's top 2 m on a coarse crossed mesh, with and without a top tie of 5 kN/m: the FE
    path's ``analyse`` puts the tie in both the multiplier and W(q_m) (W_ties > 0, reported
    in the record), and v̄_g rises."""
    from homlimit.fe.problems import t_section
    from homlimit.mechanism.analysis import analyse

    tied = Case(ties=(Tie(9.0, 5000.0),))
    runs = [analyse(c, t_section(c, z0=7.0, facade="bedjoints", h=0.5))
            for c in (Case(), tied)]
    bare, tie = runs
    assert math.isfinite(bare.vg) and math.isfinite(tie.vg)
    assert tie.impulse.W_ties > 0 and bare.impulse.W_ties == 0
    assert tie.vg > 1.2 * bare.vg and tie.multiplier > 1.2 * bare.multiplier
    rec = tie.record()
    assert rec["W_ties"] == tie.impulse.W_ties and rec["W_m"] == tie.impulse.W_m
    assert "W_ties" not in bare.record()


@pytest.mark.slow
def test_adaptive_bracket_keeps_the_tie_on_every_mesh():
    """The adaptive bracket of B1 with a top tie on gmsh-strip meshes: every cycle's problem
    carries the tie (the remesh places it anew), and the best kinematic mesh's problem too."""
    from homlimit.fe.adapt import AdaptOptions
    from homlimit.fe.solver import SolverOptions
    from homlimit.mechanism.adaptive import adaptive_bracket

    tied = Case(ties=(Tie(9.0, 5000.0),))
    res = adaptive_bracket(tied, "bedjoints", 1.0, AdaptOptions(target_gap=1e-6, max_cycles=2),
                           SolverOptions(), mesher="gmsh-strip")
    assert len(res.cycles) == 2
    assert list(res.problem.ties) == ["tie0"]
    assert res.problem.meta["real_wall"]["ties"][0]["yield_force"] == 5000.0
    bare = adaptive_bracket(Case(), "bedjoints", 1.0, AdaptOptions(max_cycles=1),
                            SolverOptions(), mesher="gmsh-strip")
    assert res.cycles[0].upper > 1.2 * bare.cycles[0].upper      # the tie holds the wall


@pytest.mark.parametrize("kw, message", [
    (dict(floors=((1.0, 0.1),)), "floors has shape"),
    (dict(floors=((-1.0, 0.1, 2.0),)), "floors = "),
    (dict(ties=((9.0, math.nan, 0.0, math.inf),)), "ties = "),
    (dict(ties=((9.0, 1.0, 0.0, 0.0),)), "ties = "),
    (dict(restraints=(math.inf,)), "restraints = "),
    (dict(band=-0.1), "band = -0.1 m is out of range"),
])
def test_bad_body_loads_are_named(kw, message):
    with pytest.raises(ParameterError, match=message):
        BodyLoads(**kw)


def test_a_run_with_a_tie_on_the_fe_path(tmp_path, monkeypatch):
    """`homlimit run` on a coarse B1 with a top tie and a floor and [analysis] fe = true:
    it runs (the refusal is lifted), fe_scan.csv and summary.json carry W_m, W_floors and
    W_ties, the FE mechanism's row its multiplier; the FE cache entry keeps the ties' and
    floors' work (``LoadWork``), and the FE body's rocker read from it has the run's v̄_g and
    the static threshold (m g x_G + L + T_y l d)/Π of its numbers by hand; the hinge check
    runs on the FE body's rocker too."""
    import csv
    import json

    import homlimit
    from homlimit.app.config import load_case
    from homlimit.app.models import fe_cache_path, read_fe_cache, rocker_fe

    monkeypatch.setenv("HOMLIMIT_MESH_CACHE", str(tmp_path / "cache"))
    cfg = load_case(None, ["mesh.size=1.0", "mesh.part_divisions=4", "analysis.heights=2",
                           "analysis.static=false", "analysis.hinge_check=true",
                           "output.png=false", "output.vtu=false", "tie.0.z=9",
                           "tie.0.yield_force=2000", "floor.0.z=4.5", "floor.0.load=20000",
                           "floor.0.eccentricity=0.1"])
    homlimit.run(cfg, out=tmp_path / "o")
    s = json.loads((tmp_path / "o" / "summary.json").read_text())
    fe = s["fe"]
    assert 0 < fe["W_ties"] < fe["W_m"] and "loads_rule" in fe     # (11 of 21 kJ here)
    assert s["units"]["results"]["W_ties"] == "J"
    rows = list(csv.DictReader(open(tmp_path / "o" / "fe_scan.csv", encoding="utf-8")))
    crit = min((r for r in rows if r["vg [m/s]"]), key=lambda r: float(r["vg [m/s]"]))
    assert float(crit["W_ties [J]"]) == pytest.approx(fe["W_ties"], rel=1e-12)
    assert float(crit["W_floors [J]"]) == pytest.approx(fe["W_floors"], rel=1e-12)
    assert s["mechanisms"]["FE"]["vg"] == fe["vg"]
    cached = read_fe_cache(cfg)
    assert cached is not None and cached.cache == fe_cache_path(cfg)
    gi = cached.impulse
    assert gi.W_ties == pytest.approx(fe["W_ties"], rel=1e-12) and gi.load_work
    rk = rocker_fe(cfg.case, cached)
    assert rk.vg_impulse == pytest.approx(fe["vg"], rel=1e-9)
    assert rk.W_m == pytest.approx(fe["W_m"], rel=1e-9)
    (d, T, k, du), = gi.load_work.ties_body                # the top tie on the body
    assert (T, k, du) == (2000.0 * cfg.case.wall.l, 0.0, math.inf) and d > 0
    b = gi.block
    assert rk.a_uplift == pytest.approx((b.m * G * b.x_G + gi.lift_rest + T * d
                                         + sum(Q * x for Q, x, _ in gi.load_work.floors_body)
                                         + sum(Q * f for Q, f in gi.load_work.floors_rest))
                                        / gi.Pi, rel=1e-12)
    hinge = s["hinges"]["FE"]               # f g = 5.9 m/s² lifts it (a_uplift ~ 2.6 m/s²)
    assert rk.a_uplift < 0.6 * G and hinge["pgv"] > fe["vg"]
    assert hinge["ratio"] == pytest.approx(hinge["pgv"] / fe["vg"], rel=1e-9)


def test_cli_pulse_with_the_fe_body_takes_a_tie(tmp_path, monkeypatch):
    """`homlimit pulse` with [pulse] mechanisms = ["FE"] on a coarse B1 with a top tie of
    2 kN/m (refused before issue 30's item 5) exits 0; the tie raises the FE rocker's static
    threshold, its eq. 7 v̄_g and the rectangular pulse's threshold over the bare wall's, and
    the rocker's v̄_g is the FE impulse criterion's (the FE cache entry the command wrote)."""
    import csv
    import json

    from cases import b1, run_cli

    monkeypatch.setenv("HOMLIMIT_MESH_CACHE", str(tmp_path / "cache"))
    base = dict(mesh={"size": 1.0, "part_divisions": 4},
                analysis={"heights": 2, "static": False, "hinge_check": False},
                output={"png": False, "vtu": False},
                pulse={"mechanisms": ["FE"], "kinds": ["rectangular"], "periods": [0.5],
                       "polarities": [1]})
    rows = {}
    for name, extra in (("bare", {}), ("tied", {"tie": [{"z": 9.0, "yield_force": 2000.0}]})):
        r = run_cli(tmp_path, b1(name, **base, **extra), "pulse", out=name)
        assert r.returncode == 0, r.stderr
        rows[name], = csv.DictReader(open(tmp_path / name / "spectra.csv", encoding="utf-8"))
    bare, tied = ({k: float(v) for k, v in rows[n].items() if k.endswith("]") and v}
                  for n in ("bare", "tied"))
    assert tied["a_uplift [m/s^2]"] > 1.05 * bare["a_uplift [m/s^2]"]
    assert tied["vg_eq7 [m/s]"] > 1.2 * bare["vg_eq7 [m/s]"]
    assert tied["pgv [m/s]"] > 1.2 * bare["pgv [m/s]"]
    entries = [json.loads(p.read_text()) for p in (tmp_path / "cache").glob("fe-*.json")]
    tied_entry, = (e for e in entries if e["inputs"].get("tie"))
    assert tied["vg_eq7 [m/s]"] == pytest.approx(tied_entry["vg"], rel=1e-9)
    assert tied_entry["impulse"]["load_work"]["ties_body"]
