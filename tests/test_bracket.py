"""Both bounds on the same problems: the brackets of issue 8, against published values.

Every case computed here is listed in ``CASES``; ``test_lower_never_exceeds_upper`` asserts
λ⁻ <= λ⁺ on each of them (the static and kinematic theorems together).
"""

from __future__ import annotations

import dataclasses
import functools

import numpy as np
import pytest

from homlimit.fe import problems, strength
from homlimit.fe.bracket import bracket, prandtl_fan
from homlimit.params import Case, Masonry, Wall

PRANDTL = 2.0 + np.pi


def _block(eps):
    b, h = 0.5, 3.0
    prob = problems.free_block(b=b, h=h, n_b=2)
    xs = problems.graded(0, b, eps, b / 2, foci=(0,), growth=1.6)
    zs = problems.graded(0, h, eps, b / 2, foci=(0,), growth=1.6)
    m = problems.crossed_mesh(xs, zs).with_boundaries(
        {"base": lambda x: np.abs(x[1]) < 1e-9}).with_subdomains({"facade": lambda x: x[0] > -1})
    return dataclasses.replace(prob, mesh=m)


def _cohesive_block():
    prob = problems.free_block(b=0.5, h=3.0, f=0.6, n_b=2)
    return dataclasses.replace(prob, interfaces={"base": strength.BedJoints(0.6, 1500.0, 2000.0)})


def _bedjoint_block_rigid_top():
    """The bed-joint block with its upper half rigid (above the mechanism's deforming zone)."""
    prob = problems.free_block(b=0.5, h=3.0, n_b=2, interior="bedjoints")
    m = prob.mesh.with_subdomains({"low": lambda x: x[1] < 1.5, "top": lambda x: x[1] > 1.5})
    w = prob.dead_body["facade"][1]
    return dataclasses.replace(prob, mesh=m, domains={"low": strength.BedJoints(0.6),
                                                      "top": strength.Rigid()},
                               live_body={"low": (w, 0.0), "top": (w, 0.0)},
                               dead_body={"low": (0.0, w), "top": (0.0, w)})


def _tsection(name, h, n_b):
    row = {r["test"]: r for r in _table1()}[name]
    case = Case(Wall(H=row["H"], L=row["L"], s=row["s"], b=row["b"], l=row["rho"] * row["s"]),
                Masonry(a=row["a"], c=row["c"], f=row["f"]), name=name)
    return problems.t_section(case, h=h, n_b=n_b, growth=1.3)


@functools.cache
def _table1():
    import csv
    from importlib.resources import files

    text = files("homlimit").joinpath("data/table1_dem.csv").read_text()
    rows = [r for r in csv.DictReader(line for line in text.splitlines()
                                      if not line.startswith("#"))]
    return [{k: (v if k == "test" else float(v)) for k, v in r.items()} for r in rows]


CASES = {
    "prandtl_crossed": lambda: problems.prandtl(h_min=0.05, h_max=0.5, growth=1.3),
    "prandtl_fan": lambda: prandtl_fan(size=0.3, h_min=0.03, radius=0.5, n_fan=12),
    "mohr_coulomb_crossed": lambda: problems.mohr_coulomb_footing(h_min=0.1, h_max=1.0,
                                                                  growth=1.3),
    "vertical_cut_coarse": lambda: problems.vertical_cut(h_min=0.1, h_max=0.25),
    "vertical_cut_fine": lambda: problems.vertical_cut(h_min=0.05, h_max=0.25),
    "rigid_block": lambda: problems.free_block(b=0.5, h=3.0, n_b=2),
    "rigid_block_eps0.01": lambda: _block(0.01),
    "rigid_block_squat": lambda: problems.free_block(b=0.5, h=0.5, f=0.6, n_b=2),
    "rigid_block_cohesive": _cohesive_block,
    "prandtl_rigid_footing": lambda: prandtl_fan(size=0.3, h_min=0.03, radius=0.5, n_fan=12,
                                                 footing=0.25),
    "bedjoint_block": lambda: problems.free_block(b=0.5, h=3.0, n_b=2, interior="bedjoints"),
    "bedjoint_block_rigid_top": _bedjoint_block_rigid_top,
}
TABLE1 = ("B1", "B2", "B3", "B4", "B5", "B6", "C1", "C2", "C3", "C4", "C5", "C6")
for _t in TABLE1:  # every Table 1 geometry at two nested refinements
    CASES[f"tsection_{_t}_h1"] = functools.partial(_tsection, _t, 1.0, 1)
    CASES[f"tsection_{_t}_h0.5"] = functools.partial(_tsection, _t, 0.5, 2)


@functools.cache
def run(name):
    return bracket(CASES[name]())


@pytest.mark.parametrize("name", sorted(CASES))
@pytest.mark.slow
def test_lower_never_exceeds_upper(name):
    br = run(name)
    assert br.lower <= br.upper * (1 + 1e-7), f"{name}: {br.lower} > {br.upper}"


@pytest.mark.slow
def test_prandtl_brackets_2_plus_pi_with_gap_under_3_percent():
    """Fan mesh of ~2 000 triangles: λ⁻ <= 2 + π <= λ⁺ and (λ⁺ − λ⁻)/mean < 3 %."""
    br = run("prandtl_fan")
    assert br.static.mesh.t.shape[1] <= 20_000
    assert br.lower <= PRANDTL <= br.upper
    assert br.rel_gap < 0.03, f"gap {br.rel_gap:.4f} ({br.lower:.4f}, {br.upper:.4f})"


@pytest.mark.slow
def test_prandtl_crossed_mesh_still_brackets():
    """The structured crossed mesh is poor for the static bound (no fan) but still a bracket."""
    br = run("prandtl_crossed")
    assert br.lower <= PRANDTL <= br.upper


@pytest.mark.slow
def test_mohr_coulomb_footing_brackets_nc():
    """Prandtl–Reissner N_c(30°) = 30.14 lies in the bracket (crossed mesh: a weak λ⁻)."""
    br = run("mohr_coulomb_crossed")
    assert br.lower <= problems.mohr_coulomb_nc(30.0) <= br.upper


@pytest.mark.slow
def test_vertical_cut_brackets_published_bounds():
    """Kammoun et al. 2010: 3.7752 <= γH/k <= 3.7776; gap < 5 % on the finer CI mesh."""
    gaps = []
    for name in ("vertical_cut_coarse", "vertical_cut_fine"):
        br = run(name)
        assert br.lower <= problems.VERTICAL_CUT_LB, name
        assert br.upper >= problems.VERTICAL_CUT_UB, name
        gaps.append(br.rel_gap)
    assert gaps[1] < gaps[0]
    assert gaps[1] < 0.05, f"gap {gaps[1]:.4f}"


def test_rigid_block_both_bounds_b_over_h():
    """Free-standing rigid block on a dry bed joint: both bounds b/h to solver precision, on a
    coarse mesh and on one graded to the toe (b = 0.5 m, h = 3 m); a squat one slides at f."""
    b, h = 0.5, 3.0
    for name in ("rigid_block", "rigid_block_eps0.01"):
        br = run(name)
        assert br.lower == pytest.approx(b / h, rel=1e-7), name
        assert br.upper == pytest.approx(b / h, rel=1e-7), name
        assert br.rel_gap < 1e-7, name
    br = run("rigid_block_squat")
    assert br.lower == pytest.approx(0.6, rel=1e-7) and br.upper == pytest.approx(0.6, rel=1e-7)


def test_rigid_block_on_cohesive_joint_both_bounds_exact():
    """Tensile strength T_h = 2000 Pa on the joint: λ = (W b + T_h b²)/(W h), W = γ b h."""
    b, h, t_h = 0.5, 3.0, 2000.0
    W = 2000.0 * 9.81 * b * h
    exact = (W * b + t_h * b * b) / (W * h)
    br = run("rigid_block_cohesive")
    assert br.lower == pytest.approx(exact, rel=1e-7)
    assert br.upper == pytest.approx(exact, rel=1e-7)


def test_rigid_region_above_the_mechanism():
    """Bed-joint block, upper half made rigid. A rigid region is stronger: it admits more stress
    fields (λ⁻ can only rise) and fewer mechanisms (λ⁺ can only rise). The mechanism deforms
    near the base, so both move little (measured: +1.8e-6 and +2e-10 relative)."""
    a, b = run("bedjoint_block"), run("bedjoint_block_rigid_top")
    assert b.static.sizes["rigid_bodies"] == 1
    assert a.lower * (1 - 1e-9) <= b.lower <= a.lower * (1 + 1e-4)
    assert a.upper * (1 - 1e-9) <= b.upper <= a.upper * (1 + 1e-4)
    assert b.joint_gap >= -1e-6 * b.upper


@pytest.mark.slow
def test_rigid_footing_brackets_prandtl():
    """Rough rigid footing (a Rigid region bonded to the soil) on weightless Tresca: 2 + π."""
    br = run("prandtl_rigid_footing")
    assert br.static.sizes["rigid_bodies"] == 1
    assert br.lower <= PRANDTL <= br.upper
    assert br.rel_gap < 0.05, f"gap {br.rel_gap:.4f}"
    # virtual power splits the gap over the soil's elements; the body's elements contribute 0
    assert br.element_gap.sum() == pytest.approx(br.gap, abs=1e-6 * br.upper)
    assert np.all(br.element_gap[br.static.rigid] == 0.0)


def test_gap_splits_over_elements_by_virtual_power():
    """Σ_e [D_e(u) − ∫_e σ:D(u)] = λ⁺ − λ⁻ and every element term is >= 0 (σ ∈ G)."""
    for name in ("prandtl_crossed", "vertical_cut_coarse", "tsection_B1_h1"):
        br = run(name)
        eg = br.element_gap
        assert eg is not None and eg.shape == (br.static.mesh.t.shape[1],)
        assert eg.sum() == pytest.approx(br.gap, abs=1e-6 * abs(br.upper)), name
        assert eg.min() >= -1e-6 * abs(br.upper), name


def test_gap_with_bed_joint_interface_includes_joint_share():
    """With a joint to the ground the element terms miss the joint's share, which is >= 0."""
    br = run("bedjoint_block")
    assert br.joint_gap >= -1e-6 * br.upper


@pytest.mark.parametrize("test", TABLE1)
@pytest.mark.slow
def test_tsection_gap_shrinks_under_refinement(test):
    """Halving the element size shrinks the gap (B1: 42 % → 17 %, docs/static.md)."""
    coarse, fine = run(f"tsection_{test}_h1"), run(f"tsection_{test}_h0.5")
    assert 0 < coarse.lower and fine.rel_gap < 0.6 * coarse.rel_gap
    # both brackets hold the same exact multiplier: they must overlap
    assert coarse.lower <= fine.upper and fine.lower <= coarse.upper


@pytest.mark.slow
def test_different_meshes_for_each_bound():
    pr = problems.prandtl(h_min=0.1, h_max=0.5, growth=1.3)
    fan = prandtl_fan(size=0.5, h_min=0.08, radius=0.5, n_fan=6)
    br = bracket(pr, static_mesh=fan.mesh)
    assert br.element_gap is None
    assert br.lower <= PRANDTL <= br.upper
    d = br.as_dict()
    assert d["triangles_static"] == fan.mesh.t.shape[1] != d["triangles_kinematic"]


def test_static_field_attached_to_the_mechanism_vtu(tmp_path):
    """The lower-bound stresses ride along the mechanism's .vtu as cell data."""
    import meshio

    from homlimit.fe.static import attach_cell_fields

    br = run("vertical_cut_coarse")
    m = attach_cell_fields(br.kinematic.to_meshio(), br.static)
    path = tmp_path / "mechanism.vtu"
    meshio.write(path, m)
    back = meshio.read(path)
    assert "velocity" in back.point_data
    s = back.cell_data["static_sigma_z"][0]
    assert np.allclose(s, br.static.element_mean()[:, 1])
    assert set(np.unique(back.cell_data["static_active_facet"][0])) <= {-1.0, 0.0}
