"""The static bound's own mesh with the façade's columns graded to the outer face.

An overturning façade bears on its outer face; a linear stress field can put its compression
resultant no nearer to that face than about a third of the outermost column, so the static
bound loses a lever arm of the order of that column's width (docs/static.md, "The outer face").
Reference: the homogenised façade's exact hinge + fan multiplier (closed_form.fan), which no
lower bound may exceed.
"""

import numpy as np
import pytest

from homlimit.app.budget import estimate_triangles
from homlimit.closed_form.fan import optimise_fan
from homlimit.errors import ParameterError
from homlimit.fe.adapt import AdaptOptions
from homlimit.fe.geometry import graded_columns, tsection
from homlimit.fe.problems import OUTER_GROWTH, t_section
from homlimit.fe.solver import SolverOptions
from homlimit.fe.static import solve_static
from homlimit.mechanism.adaptive import adaptive_bracket
from homlimit.params import Case


def _columns(prob, b):
    """The column lines of the façade: the grid's x on the base (cell centres lie above it)."""
    P = prob.mesh.p
    xs = np.unique(np.round(P[0, P[1] == P[1].min()], 12))
    return xs[xs <= b + 1e-12]


def test_columns_grade_from_h_outer_at_the_outer_face():
    case = Case()
    b = case.wall.b
    p = t_section(case, facade="bedjoints", h=0.5, mesher="crossed", h_outer=0.01)
    w = np.diff(_columns(p, b))
    assert w[0] == pytest.approx(0.01)
    assert np.all(w[1:-1] <= w[:-2] * OUTER_GROWTH * (1 + 1e-9))  # growing at most 1.5×
    assert w.max() <= 1.5 * b / 4 and w.sum() == pytest.approx(b)   # graded(): last < 1.5 h
    # the default (None) keeps the 4 equal columns of the kinematic bound's mesh
    w0 = np.diff(_columns(t_section(case, facade="bedjoints", h=0.5, mesher="crossed"), b))
    assert w0 == pytest.approx(np.full(4, b / 4))


def test_h_outer_is_refused_out_of_range_and_on_unstructured_gmsh():
    case = Case()
    with pytest.raises(ParameterError, match="h_outer = 0.2"):
        t_section(case, h=0.5, mesher="crossed", h_outer=0.2)       # > b/n_b = 0.125
    with pytest.raises(ParameterError, match="mesher = 'gmsh'"):
        t_section(case, h=0.5, mesher="gmsh", h_outer=0.01)


def test_graded_columns_bring_the_static_bound_within_0_6_percent_of_the_exact_fan():
    """B1, homogenised façade, crossed grid 0.25 m: uniform columns 0.14721 (n_b 8, 5328
    triangles); graded to 1 cm at the outer face 0.15139 (4896), 0.51 % below the exact
    0.152160."""
    case = Case()
    exact = optimise_fan(case).lam
    p = t_section(case, facade="homogenised", h=0.25, mesher="crossed", h_outer=0.01)
    lam = solve_static(p).multiplier
    assert lam <= exact * (1 + 1e-7)
    assert lam >= exact * (1 - 0.006)
    uniform = solve_static(t_section(case, facade="homogenised", h=0.25, n_b=8,
                                     mesher="crossed")).multiplier
    assert lam > uniform + 0.003


@pytest.mark.slow
def test_run_brackets_on_the_graded_static_mesh(tmp_path):
    """`run` (crossed mesher, default outer_ratio 25): the static bound on its own mesh, more
    triangles than the mechanism's, below the exact fan and above the same-mesh bound;
    mechanism.vtu says where its stress field is instead of carrying it."""
    import json

    import meshio

    from homlimit.app import pipeline

    # the scan's parts play no part here (3 elements per part height: the whole wall's
    # bounds and meshes are unchanged)
    over = {"mesh.size": 0.6, "mesh.part_divisions": 3, "analysis.heights": 2,
            "mesh.mesher": "crossed",
            "analysis.facade": "homogenised", "analysis.hinge_check": False}
    exact = optimise_fan(Case()).lam
    graded = pipeline.run(None, out=tmp_path / "g", overrides=over).to_dict()["fe"]
    same = pipeline.run(None, out=tmp_path / "s",
                        overrides=over | {"mesh.outer_ratio": 0.0}).to_dict()["fe"]
    assert same["static_triangles"] == same["n_triangles"]
    assert graded["static_triangles"] > graded["n_triangles"] == same["n_triangles"]
    assert graded["multiplier"] == same["multiplier"]          # the kinematic side unchanged
    assert same["lower_bound"] < graded["lower_bound"] <= exact * (1 + 1e-7)
    mech = meshio.read(tmp_path / "g" / "mechanism.vtu")
    assert "static_sigma_x" not in mech.cell_data
    notes = bytes(np.asarray(mech.field_data["notes"], np.uint8)).decode("utf-8")  # UTF-8 bytes
    assert "another mesh" in json.loads(notes)["static"]


# ------------------------------------------------------------------ gmsh-strip: graded columns
def test_graded_columns_are_a_geometric_progression_filling_b():
    for b, h0, n_b in ((0.5, 0.01, 4), (0.25, 0.004, 4), (0.5, 0.02, 8)):
        n, r = graded_columns(b, h0, n_b, OUTER_GROWTH)
        assert n >= n_b and 1.0 < r <= OUTER_GROWTH
        assert h0 * (r ** n - 1) / (r - 1) == pytest.approx(b, rel=1e-12)
        if n > n_b:                                   # the fewest columns that reach b
            assert h0 * (OUTER_GROWTH ** (n - 1) - 1) / (OUTER_GROWTH - 1) < b
    assert graded_columns(0.5, 0.125, 4) == (4, 1.0)                     # equal columns


def test_gmsh_strip_columns_grade_from_h_outer():
    case = Case()
    b = case.wall.b
    p = t_section(case, facade="bedjoints", h=0.5, mesher="gmsh-strip", h_outer=0.01)
    w = np.diff(_columns(p, b))
    n, r = graded_columns(b, 0.01, 4, OUTER_GROWTH)
    assert w.size == n and w[0] == pytest.approx(0.01, rel=1e-6)
    assert w[1:] / w[:-1] == pytest.approx(np.full(n - 1, r), rel=1e-6)
    n_tri = p.n_triangles
    assert estimate_triangles(9.0, b, 6.0, 0.5, "gmsh-strip", h_outer=0.01) == \
        pytest.approx(n_tri, rel=0.15)


def test_rows_and_h_outer_need_the_structured_strip():
    with pytest.raises(ParameterError, match="h_outer = 0.01 with strip = 'free'"):
        tsection(9.0, 0.5, 6.0, 0.5, h_outer=0.01)
    with pytest.raises(ParameterError, match="rows = 0.1 with strip = 'free'"):
        tsection(9.0, 0.5, 6.0, 0.5, rows=0.1)


def test_gmsh_strip_graded_bracket_holds_the_exact_fan():
    """B1's homogenised façade, rows of 0.5 m, columns from 2 cm (1604 triangles), one cycle of
    the adaptive chain: 0.15105 <= 0.152160 <= 0.15442 (measured)."""
    case = Case()
    exact = optimise_fan(case).lam
    res = adaptive_bracket(case, "homogenised", 0.5, AdaptOptions(max_cycles=1),
                           SolverOptions(stress_degree=2), mesher="gmsh-strip", h_outer=0.02)
    br = res.bracket
    assert br.lower <= exact * (1 + 1e-7) and br.upper >= exact * (1 - 1e-7)
    assert br.lower >= exact * (1 - 0.008)
    assert res.cycles[0].triangles == res.problem.n_triangles
