"""The wall's geometry home (homlimit.geometry.TSection) against hand values for B1
(Table 1: H = 9 m, b = 0.5 m, L = 6 m), and the meshes and blocks that read it."""

from __future__ import annotations

import numpy as np
import pytest

from homlimit.errors import ParameterError
from homlimit.geometry import BOUNDARIES, REGIONS, TSection
from homlimit.params import Case, Wall


def test_b1_areas_segments_and_box():
    g = TSection(9.0, 0.5, 6.0)
    assert g == TSection.from_case(Case())                       # Case() is B1's wall
    assert (g.x_junction, g.x_end, g.height) == (0.5, 6.5, 9.0)
    assert g.bbox == (0.0, 0.0, 6.5, 9.0)
    assert g.area("facade") == 4.5 and g.area("wall") == 54.0 and g.area() == 58.5
    assert tuple(g.regions) == REGIONS and tuple(g.boundaries) == BOUNDARIES
    assert g.boundaries == {"base": ((0.0, 0.0), (6.5, 0.0)), "outer": ((0.0, 0.0), (0.0, 9.0)),
                            "top": ((0.0, 9.0), (6.5, 9.0)), "end": ((6.5, 0.0), (6.5, 9.0)),
                            "junction": ((0.5, 0.0), (0.5, 9.0))}
    assert g.regions["facade"] == ((0.0, 0.0), (0.5, 0.0), (0.5, 9.0), (0.0, 9.0))


def test_failing_part_above_z0():
    p = TSection(9.0, 0.5, 6.0).part(3.0)
    assert (p.z0, p.height, p.span) == (3.0, 6.0, 6.0)
    assert p.area("facade") == 3.0 and p.area("wall") == 36.0
    assert p.boundaries["base"] == ((0.0, 3.0), (6.5, 3.0))
    assert p.boundaries["junction"] == ((0.5, 3.0), (0.5, 9.0))
    assert TSection.from_case(Case(Wall(H=4.0, L=2.0)), 1.0).bbox == (0.0, 1.0, 2.5, 4.0)


def test_membership_tests():
    g = TSection(9.0, 0.5, 6.0, 3.0)
    x = np.array([[0.0, 0.25, 0.5, 6.5, 3.0, 3.0], [5.0, 3.0, 4.0, 8.0, 9.0, 2.0]])
    np.testing.assert_array_equal(g.on_boundary("outer", x), [1, 0, 0, 0, 0, 0])
    np.testing.assert_array_equal(g.on_boundary("base", x), [0, 1, 0, 0, 0, 0])
    np.testing.assert_array_equal(g.on_boundary("junction", x), [0, 0, 1, 0, 0, 0])
    np.testing.assert_array_equal(g.on_boundary("end", x), [0, 0, 0, 1, 0, 0])
    np.testing.assert_array_equal(g.on_boundary("top", x), [0, 0, 0, 0, 1, 0])
    c = np.array([[0.25, 0.75, 3.0], [6.0, 6.0, 2.0]])
    np.testing.assert_array_equal(g.in_region("facade", c), [1, 0, 0])
    np.testing.assert_array_equal(g.in_region("wall", c), [0, 1, 0])       # z = 2 < z0


@pytest.mark.parametrize("kwargs, name", [(dict(H=0.0), "H"), (dict(b=-1.0), "b"),
                                          (dict(L=float("nan")), "L"), (dict(z0=9.0), "z0")])
def test_bad_geometry_names_the_parameter(kwargs, name):
    args = dict(H=9.0, b=0.5, L=6.0, z0=0.0) | kwargs
    with pytest.raises(ParameterError, match=rf"\b{name}\b"):
        TSection(**args)
    with pytest.raises(ParameterError, match="region"):
        TSection(9.0, 0.5, 6.0).area("roof")


def test_meshes_and_blocks_cover_the_geometry():
    from homlimit.blocks.geometry import polygon_moments, t_section_blocks
    from homlimit.fe.mesh import element_areas
    from homlimit.fe.problems import t_section

    g = TSection(9.0, 0.5, 6.0, 4.5)
    m = t_section(Case(), z0=4.5, h=0.75).mesh
    a = element_areas(m)
    for r in REGIONS:
        assert a[m.subdomains[r]].sum() == pytest.approx(g.area(r), rel=1e-12)
    A = t_section_blocks(Case())
    areas = polygon_moments(A.vertices, A.offsets)[0][~A.fixed]
    assert areas.sum() == pytest.approx(TSection(9.0, 0.5, 6.0).area(), rel=1e-12)


# ----------------------------------------------------------------------------- the gmsh strip
def test_structured_strip_is_a_crossed_grid_conforming_to_the_wall():
    """tsection(strip="structured"): the façade is n_b × ⌈h/size⌉ crossed cells (4 triangles
    each, every cell side along x or z), the wall conforms to its nodes on x = b."""
    from homlimit.fe.geometry import tsection
    from homlimit.fe.mesh import element_areas, to_skfem

    g = TSection(9.0, 0.5, 6.0, 3.0)
    m = to_skfem(tsection(g.H, g.b, g.L, 0.5, z0=g.z0, strip="structured", n_b=4))
    f, w = m.subdomains["facade"], m.subdomains["wall"]
    assert len(f) == 4 * 4 * 12                                    # 6 m / 0.5 m rows
    a = element_areas(m)
    assert a[f] == pytest.approx(np.full(len(f), 0.125 * 0.5 / 4), rel=1e-9)
    assert a[w].sum() == pytest.approx(g.area("wall"), rel=1e-12)
    # façade nodes: the grid x ∈ {0, 1/8, .., 1/2} × z ∈ {3, 3.5, .., 9} and the cell centres
    P = m.p[:, np.unique(m.t[:, f])]
    corner = np.isclose(P[0] * 8, np.round(P[0] * 8)) & np.isclose(P[1] * 2, np.round(P[1] * 2))
    centre = np.isclose(P[0] * 8 % 1, 0.5) & np.isclose(P[1] * 2 % 1, 0.5)
    assert np.all(corner | centre) and corner.sum() == 5 * 13 and centre.sum() == 4 * 12
    # the wall's triangles on the junction use exactly the strip's 13 nodes there
    Pw = m.p[:, np.unique(m.t[:, w])]
    on = np.isclose(Pw[0], 0.5)
    np.testing.assert_allclose(np.sort(Pw[1, on]), 3.0 + 0.5 * np.arange(13), atol=1e-12)
    assert {"base", "outer", "top", "end", "junction"} == set(m.boundaries)


def test_structured_strip_refuses_embedded_lines():
    from homlimit.fe.geometry import tsection

    with pytest.raises(ParameterError, match="embed_lines"):
        tsection(9.0, 0.5, 6.0, 0.5, strip="structured", embed_lines=[((0, 1), (3, 3))])
    with pytest.raises(ParameterError, match="strip"):
        tsection(9.0, 0.5, 6.0, 0.5, strip="mapped")
