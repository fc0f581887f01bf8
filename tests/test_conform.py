"""The kinematic bound searched over ray-conforming meshes (``mechanism.conform``) against the
homogenised façade's hinge + fan in closed form (``closed_form.fan``, an independent
integration of the same mechanism family)."""

import math

import pytest

from homlimit.closed_form.fan import optimise_fan
from homlimit.errors import ParameterError
from homlimit.mechanism.adaptive import HingeFan
from homlimit.mechanism.conform import conform_fan
from homlimit.params import Case, Masonry, Wall

# a shorter wall than B1 (cheaper solves) whose optimal hinge still lies above the toe
CASE = Case(Wall(H=6.0, L=4.0, s=0.5, b=0.5, l=6.0), Masonry(a=0.3, c=0.2, f=0.6))


@pytest.mark.slow
def test_search_from_a_wrong_fan_finds_the_edges_f_and_c_over_a():
    """From edges 7 % off and a hinge 0.2 m low, 30 solves find λ⁺ within 0.05 % of the closed
    form and fan edges (read off the field) within 2 % of f and c/a; every trial is an upper
    bound of the exact multiplier."""
    opt = optimise_fan(CASE)
    assert opt.family == "hinge+fan" and opt.z0 > 0.1
    c = conform_fan(CASE, HingeFan(0.0, opt.z0 - 0.2, 0.56, 0.62, None), size=0.5,
                    max_trials=30)
    assert len(c.trials) <= 31
    assert all(t[3] >= opt.lam * (1 - 1e-6) for t in c.trials)
    assert c.lam == pytest.approx(opt.lam, rel=5e-4) and c.lam >= opt.lam * (1 - 1e-6)
    f, ca = CASE.masonry.f, CASE.masonry.c / CASE.masonry.a
    assert c.fan.T1 == pytest.approx(f, rel=0.02)
    assert c.fan.T2 == pytest.approx(ca, rel=0.02)
    assert math.sqrt(c.fan.T1 * c.fan.T2) == pytest.approx(math.sqrt(f * ca), rel=0.01)


def test_a_start_without_slopes_is_refused_before_any_solve():
    with pytest.raises(ParameterError, match="start"):
        conform_fan(CASE, HingeFan(0.0, 1.0, None, None, None))
    with pytest.raises(ParameterError, match="max_trials"):
        conform_fan(CASE, HingeFan(0.0, 1.0, 0.6, 0.7, 0.65), max_trials=2)


def test_a_run_on_the_homogenised_facade_takes_the_searched_bound(monkeypatch):
    """`run` with the homogenised façade and the adaptive chain: the first cycle's mechanism
    starts the search ([adapt] conform, the default), whose λ⁺ (below the cycle's own, above
    the closed form) becomes the run's kinematic bound and mechanism. The search is replaced
    here by one solve on the mesh conforming to the closed-form fan (its accuracy: the test
    above and docs/adaptive.md); [adapt] conform = false never calls it."""
    import dataclasses

    from homlimit.app import pipeline
    from homlimit.fe.kinematic import solve_kinematic
    from homlimit.fe.problems import t_section
    from homlimit.mechanism import conform
    from homlimit.mechanism.fe_impulse import ray_conforming_mesh

    opt = optimise_fan(CASE)
    calls = []

    def one_solve(case, start, **kw):
        calls.append(start)
        p = dataclasses.replace(t_section(case, facade="homogenised", h=0.5),
                                mesh=ray_conforming_mesh(case, opt.z0, [opt.T1, opt.T2], h=0.5))
        k = solve_kinematic(p)
        return conform.ConformedFan(k, p, opt.z0, opt.T1, opt.T2, None, start, (), 0.0)

    monkeypatch.setattr(conform, "conform_fan", one_solve)
    w, m = CASE.wall, CASE.masonry
    case = {"wall": {"H": w.H, "L": w.L, "s": w.s, "b": w.b, "l": w.l},
            "masonry": {"a": m.a, "c": m.c, "f": m.f}}
    over = {"mesh.size": 1.0, "mesh.part_divisions": 3, "analysis.heights": 2,
            "analysis.facade": "homogenised", "analysis.hinge_check": False,
            "analysis.closed_form": False, "adapt.max_cycles": 2, "adapt.target_gap": 0.9}
    fe = pipeline.run(case, write=False, overrides=over).to_dict()["fe"]
    (cyc,) = fe["adapt"]["cycles"]                   # the 90 % target: one cycle
    assert len(calls) == 1 and calls[0].x == 0.0      # started from a hinge on the outer face
    assert opt.lam * (1 - 1e-6) <= cyc["conformed"] < cyc["upper"]
    assert cyc["conformed"] == pytest.approx(opt.lam, rel=1e-5)
    assert fe["multiplier"] == cyc["conformed"] == cyc["best_upper"]
    assert fe["hinge"][1] == pytest.approx(opt.z0, abs=0.05)   # the mechanism: the searched one
    pipeline.run(case, write=False, overrides=over | {"adapt.conform": False})
    assert len(calls) == 1


def test_hinge_fan_of_an_analysed_mechanism_is_hinge_fan_of_its_solution():
    """The crack study's start (``hinge_fan_of``: the hinge and edges ``analyse`` measured)
    is what ``hinge_fan`` reads off the same solution."""
    from homlimit.fe.problems import t_section
    from homlimit.mechanism.adaptive import hinge_fan, hinge_fan_of
    from homlimit.mechanism.analysis import analyse

    fe = analyse(CASE, t_section(CASE, facade="homogenised", h=0.5))
    assert hinge_fan_of(fe) == hinge_fan(CASE, fe.solution)
    assert hinge_fan_of(fe) is not None
