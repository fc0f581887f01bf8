"""The adaptive bracket (fe.adapt) and ``homlimit verify`` on known answers."""

from __future__ import annotations

import json
import math
import subprocess
import sys

import numpy as np
import pytest
from skfem import MeshTri

from homlimit.errors import ParameterError
from homlimit.fe import geometry
from homlimit.fe.adapt import (
    AdaptOptions,
    adapt,
    element_sizes,
    estimate_triangles,
    fan_rays,
    refine_sizes,
)
from homlimit.fe.mesh import to_skfem

SQUARE = {"plate": [(0, 0), (1, 0), (1, 1), (0, 1)]}


def test_doerfler_marks_the_fewest_triangles_carrying_theta():
    m = MeshTri.init_sqsymmetric().refined(1)              # 32 equal triangles
    h = element_sizes(m)
    assert np.allclose(h, h[0])
    eta = np.zeros(m.t.shape[1])
    eta[[3, 7, 11]] = [4.0, 3.0, 2.0]                      # total 9; 4 + 3 >= 0.5 · 9 > 4
    eta[12] = -1.0                                         # negative shares are ignored
    new = refine_sizes(m, eta, theta=0.5, min_size=1e-6)
    assert np.flatnonzero(new < h).tolist() == [3, 7]
    assert np.allclose(new[[3, 7]], h[0] / 2)
    # never below min_size (but never coarser than the element either)
    new = refine_sizes(m, eta, theta=1.0, min_size=0.9 * h[0])
    assert np.allclose(new[[3, 7, 11]], 0.9 * h[0])


def test_element_size_is_the_equilateral_side_of_the_same_area():
    p = np.array([[0.0, 1.0, 0.5], [0.0, 0.0, math.sqrt(3) / 2]])
    m = MeshTri(p, np.array([[0], [1], [2]]))
    assert element_sizes(m)[0] == pytest.approx(1.0, rel=1e-12)


def test_size_map_refines_where_it_asks_and_the_estimate_follows_gmsh():
    coarse = to_skfem(geometry.polygon_mesh(SQUARE, size=0.1))
    est = estimate_triangles(coarse, element_sizes(coarse))
    assert 0.8 < est / coarse.t.shape[1] < 1.25
    # ask for size 0.025 on the left half only
    c = coarse.p[:, coarse.t].mean(axis=1)
    sizes = np.where(c[0] < 0.5, 0.025, 0.1)
    fine = to_skfem(geometry.polygon_mesh(SQUARE, size=0.1,
                                          size_map=(coarse.p, coarse.t, sizes)))
    cf = fine.p[:, fine.t].mean(axis=1)
    n_left, n_right = np.sum(cf[0] < 0.45), np.sum(cf[0] > 0.55)
    assert n_left > 8 * n_right      # (0.1/0.025)² = 16 times the density
    est = estimate_triangles(coarse, sizes)
    assert 0.7 < est / fine.t.shape[1] < 1.3


def test_bad_adapt_options_name_the_key():
    with pytest.raises(ParameterError, match="adapt.target_gap"):
        AdaptOptions(target_gap=0.0)
    with pytest.raises(ParameterError, match="adapt.max_cycles"):
        AdaptOptions(max_cycles=0)
    with pytest.raises(ParameterError, match="adapt.max_cycles"):
        AdaptOptions(max_cycles=2.5)
    with pytest.raises(ParameterError, match="adapt.min_size"):
        AdaptOptions(min_size=-1)
    with pytest.raises(ParameterError, match="size_map"):
        geometry.polygon_mesh(SQUARE, size=0.5, size_map=(np.zeros((2, 3)), np.zeros((3, 1)),
                                                         np.array([-1.0])))


def test_fan_rays_leave_the_point_at_equal_angles():
    rays = fan_rays((1.0, 0.0), -180, 0, 3, 2.0)
    ang = [math.degrees(math.atan2(q[1] - p[1], q[0] - p[0])) for p, q in rays]
    assert ang == pytest.approx([-135.0, -90.0, -45.0])
    assert all(math.dist(p, q) == pytest.approx(2.0) for p, q in rays)


def test_free_block_is_exact_on_the_first_mesh():
    from homlimit.app.verify import known_problem

    k = known_problem("free_block")
    res = adapt(k.problem, k.remesh, AdaptOptions(target_gap=1e-6), first_mesh=k.problem.mesh)
    assert res.stop == "target" and len(res.cycles) == 1
    assert res.bracket.lower == pytest.approx(0.5 / 3.0, rel=1e-7)    # b/h
    assert res.bracket.upper == pytest.approx(0.5 / 3.0, rel=1e-7)


def test_the_loop_stops_before_the_budget():
    from homlimit.app.verify import known_problem

    k = known_problem("prandtl")
    n0 = k.problem.n_triangles
    res = adapt(k.problem, k.remesh, AdaptOptions(target_gap=1e-4, max_triangles=n0 + 1),
                first_mesh=k.problem.mesh)
    assert res.stop == "budget" and len(res.cycles) == 1
    # one bracket on the first mesh already holds 2 + π
    assert res.bracket.lower <= 2 + math.pi <= res.bracket.upper


@pytest.mark.slow
def test_verify_prandtl_brackets_2_plus_pi_within_1_percent(tmp_path):
    out = subprocess.run([sys.executable, "-m", "homlimit", "verify", "-p", "prandtl",
                          "-p", "free_block", "--target-gap", "0.01", "--json",
                          "--out", str(tmp_path / "v")], capture_output=True, text=True,
                         timeout=900)
    assert out.returncode == 0, out.stderr
    recs = {r["problem"]: r for r in json.loads(out.stdout)["problems"]}
    pr = recs["prandtl"]
    assert pr["lower"] <= 2 + math.pi <= pr["upper"]
    assert pr["rel_gap"] <= 0.01
    assert recs["free_block"]["holds"]
    # quadratic stresses where the problem takes them; the free block's body and joint take 1
    assert pr["stress_degree"] == 2 and recs["free_block"]["stress_degree"] == 1
    assert (tmp_path / "v" / "verify.json").is_file() and (tmp_path / "v" / "verify.csv").is_file()


@pytest.mark.slow
def test_run_with_gmsh_brackets_adaptively_around_the_exact_fan(tmp_path):
    """`run` on B1's homogenised façade with ``[mesh] mesher = "gmsh"``: the whole wall's
    bracket is adaptive, logged per cycle in summary.json and fe_adapt.csv, drawn in adapt.png,
    and holds the exact hinge + fan multiplier (closed_form.fan, 0.15216)."""
    from homlimit.app import pipeline
    from homlimit.closed_form.fan import optimise_fan
    from homlimit.params import Case

    over = {"mesh.size": 1.0, "mesh.mesher": "gmsh", "mesh.part_divisions": 3,
            "analysis.heights": 2, "analysis.facade": "homogenised",
            "analysis.hinge_check": False, "analysis.closed_form": False,
            "adapt.max_cycles": 2, "adapt.target_gap": 0.001,
            "adapt.conform": False}       # the gap-driven chain alone (test_conform: the search)
    res = pipeline.run(None, out=tmp_path / "o", overrides=over)
    fe = res.to_dict()["fe"]
    cycles = fe["adapt"]["cycles"]
    assert len(cycles) == 2 and fe["adapt"]["stop"] == "cycles"
    exact = optimise_fan(Case()).lam
    for c in cycles:
        assert c["lower"] <= exact * (1 + 1e-6) and c["upper"] >= exact * (1 - 1e-6)
    # the best bounds of all meshes: max λ⁻ and min λ⁺, the mechanism of the best λ⁺
    assert fe["lower_bound"] == cycles[-1]["best_lower"] == max(c["lower"] for c in cycles)
    assert fe["multiplier"] == cycles[-1]["best_upper"] == min(c["upper"] for c in cycles)
    best = min(cycles, key=lambda c: c["upper"])
    assert fe["n_triangles"] == best["triangles"]
    # each cycle's hinge and crack are those of its best field: the last one's are the
    # reported mechanism's, and the summary's change is theirs over the last cycle
    assert cycles[-1]["hinge_z"] == pytest.approx(fe["hinge"][1], abs=1e-9)
    assert cycles[-1]["T_mid"] == pytest.approx(fe["tanpsi"], abs=1e-9)
    ch = fe["crack_change"]
    assert ch["over"] == "the last cycle"
    assert ch["hinge_z"] == pytest.approx(abs(cycles[1]["hinge_z"] - cycles[0]["hinge_z"]))
    assert ch["T_mid"] == pytest.approx(abs(cycles[1]["T_mid"] - cycles[0]["T_mid"]))
    assert "change over the last cycle: hinge z" in res.summary()
    assert (tmp_path / "o" / "fe_adapt.csv").is_file() and (tmp_path / "o" / "adapt.png").is_file()


def test_verify_refuses_bad_input_before_any_work(tmp_path):
    from typer.testing import CliRunner

    from homlimit.app.cli import app

    for args, message in ((["-p", "nope"], "problem = 'nope' is not a known-answer problem"),
                          (["--target-gap", "0"], "adapt.target_gap = 0"),
                          (["--max-cycles", "0"], "adapt.max_cycles = 0"),
                          (["--stress-degree", "3"], "stress_degree = 3")):
        res = CliRunner().invoke(app, ["verify", *args, "--out", str(tmp_path / "v")])
        assert res.exit_code == 2, res.output
        assert message in res.stderr and "Traceback" not in res.stderr
        assert not (tmp_path / "v").exists()


def test_strip_rows_halve_only_when_the_gap_marks_the_facade():
    """gmsh-strip's adaptive remesher: a transfinite strip takes no size field, so its rows
    halve when Dörfler's marking asks any façade triangle (centroid x < b) to shrink."""
    from homlimit.mechanism.adaptive import strip_rows

    p = np.array([[0.0, 0.5, 0.5, 1.0, 1.0], [0.0, 0.0, 1.0, 0.0, 1.0]])
    t = np.array([[0, 1, 1], [1, 3, 4], [2, 4, 2]])      # one façade triangle, two wall ones
    h = np.sqrt(4 * np.array([0.25, 0.25, 0.25]) / np.sqrt(3))
    assert strip_rows((p, t, h), 0.5, 0.4) == 0.4                      # nothing marked
    assert strip_rows((p, t, h * [1, 0.5, 1]), 0.5, 0.4) == 0.4        # the wall only
    assert strip_rows((p, t, h * [0.5, 1, 1]), 0.5, 0.4) == 0.2        # the façade


def test_each_cycle_records_the_measure_of_its_best_upper_bound():
    """``adapt(measure=)``: every cycle carries the figures of the best kinematic solution so
    far, each solution measured once, and ``as_dict`` gives them columns of their own."""
    from homlimit.app.verify import known_problem

    k = known_problem("free_block")
    seen = []

    def measure(kin):
        seen.append(kin)
        return {"lam": float(kin.multiplier)}

    res = adapt(k.problem, k.remesh, AdaptOptions(target_gap=1e-6), first_mesh=k.problem.mesh,
                measure=measure)
    (cyc,) = res.cycles
    assert len(seen) == 1 and seen[0] is res.bracket.kinematic
    assert cyc.measures == {"lam": pytest.approx(0.5 / 3.0, rel=1e-7)}     # b/h
    row = cyc.as_dict()
    assert row["lam"] == cyc.measures["lam"] and "measures" not in row


def test_crack_change_is_the_last_cycles_move_or_the_searchs_resolution():
    """``FEResult.crack_change`` and the summary's line under the crack: the absolute change
    of the hinge and crack between the last two cycles (hand differences), the fan search's
    resolution where the mechanism came from it, nothing measured on one mesh."""
    from types import SimpleNamespace

    from homlimit.app.report import _crack_change_line
    from homlimit.mechanism.analysis import FEResult

    def result(measures, meta=None, converged=False):
        whole = SimpleNamespace(problem=SimpleNamespace(meta=meta or {}), tanpsi=0.584)
        cycles = [SimpleNamespace(measures=m) for m in measures]
        return FEResult((whole,), adapt=SimpleNamespace(cycles=cycles, converged=converged))

    a = {"hinge_z": 2.62, "T1": 0.570, "T2": 0.607, "T_mid": 0.586}
    b = {"hinge_z": 2.70, "T1": 0.562, "T2": 0.608, "T_mid": 0.584}
    ch = result([a, b]).crack_change
    assert ch["over"] == "the last cycle"
    for key, d in (("hinge_z", 0.08), ("T1", 0.008), ("T2", 0.001), ("T_mid", 0.002)):
        assert ch[key] == pytest.approx(d, abs=1e-12)
    line = _crack_change_line(result([a, b]))
    assert "hinge z 0.080 m, edges 0.0080 / 0.0010, mid-line 0.0020 (0.3 %)" in line
    assert result([a, {**b, "T1": None}]).crack_change["T1"] is None
    searched = result([a], meta={"crack_resolution": 0.0031})
    assert searched.crack_change == {"over": "the fan search's last improving round",
                                     "resolution": 0.0031}
    assert "at most 0.0031 (edges, mid-line)" in _crack_change_line(searched)
    assert result([a], converged=True).crack_change == {}
    assert "not measured (one mesh: the bracket met its target on its first)" in \
        _crack_change_line(result([a], converged=True))
