"""Rigid-block geometry: the T-section generator and the interface finder (homlimit.blocks)."""

import numpy as np
import pytest

from homlimit.blocks.geometry import (
    FACADE,
    SUPPORT,
    TOOTHING,
    WALL,
    find_interfaces,
    from_rectangles,
    polygon_moments,
    running_bond_panel,
    stack,
    t_section_blocks,
)
from homlimit.errors import ParameterError
from homlimit.impulse.body import triangle_moments
from homlimit.params import Case, Masonry, Wall

B1 = Case(Wall(H=9, L=6, s=0.5, b=0.5, l=6), Masonry(a=0.3, c=0.2, f=0.6), name="B1")
# H not a multiple of a, L not a multiple of 2c or of c
ODD = Case(Wall(H=2.95, L=2.3, s=0.4, b=0.45, l=2.0), Masonry(a=0.3, c=0.2, f=0.7), name="odd")


def _on_boundary(poly, p, tol=1e-9):
    """Is point p on the boundary of the polygon (within tol)?"""
    a, b = poly, np.roll(poly, -1, axis=0)
    d = b - a
    t = np.clip(np.einsum("ij,ij->i", p - a, d) / np.einsum("ij,ij->i", d, d), 0, 1)
    return np.min(np.linalg.norm(a + t[:, None] * d - p, axis=1)) < tol


@pytest.mark.parametrize("case", [B1, ODD], ids=["B1", "odd"])
@pytest.mark.parametrize("facade", ["through", "running-bond"])
def test_areas_and_masses_add_up_to_the_wall(case, facade):
    A = t_section_blocks(case, facade=facade)
    w = case.wall
    area = polygon_moments(A.vertices, A.offsets)[0]
    blocks = A.kind != SUPPORT
    assert area[blocks].sum() == pytest.approx(w.H * (w.b + w.L), rel=1e-13)
    gs = w.gamma * w.s
    assert A.mass.sum() == pytest.approx(case.rho * gs * w.b * w.H + gs * w.L * w.H, rel=1e-13)
    # centre of gravity of the whole, by hand: façade strip and wall rectangle
    mf, mw = case.rho * gs * w.b * w.H, gs * w.L * w.H
    xg = (mf * w.b / 2 + mw * (w.b + w.L / 2)) / (mf + mw)
    assert (A.mass @ A.centroid[:, 0]) / A.mass.sum() == pytest.approx(xg, rel=1e-12)
    assert (A.mass @ A.centroid[:, 1]) / A.mass.sum() == pytest.approx(w.H / 2, rel=1e-12)


@pytest.mark.parametrize("case", [B1, ODD], ids=["B1", "odd"])
def test_interfaces_are_shared_edges(case):
    A = t_section_blocks(case)
    jt = A.interfaces
    for k in range(jt.count):
        for e in (0, 1):
            assert _on_boundary(A.polygon(jt.a[k]), jt.p[k, e])
            assert _on_boundary(A.polygon(jt.b[k]), jt.p[k, e])
        # n points from a into b: a's centroid lies behind the joint, b's in front
        mid = jt.p[k].mean(axis=0)
        assert (A.centroid[jt.a[k]] - mid) @ jt.n[k] < 0 < (A.centroid[jt.b[k]] - mid) @ jt.n[k]
    # total joint length by hand: every course boundary and the base span b + L; each course
    # has (blocks − 1) head joints of its height
    w = case.wall
    heights = np.array([A.bounds()[A.course == k][0, 3] - A.bounds()[A.course == k][0, 1]
                        for k in range(A.meta["n_courses"])])
    counts = np.bincount(A.course[A.course >= 0])
    expected = A.meta["n_courses"] * (w.b + w.L) + np.sum((counts - 1) * heights)
    assert jt.length.sum() == pytest.approx(expected, rel=1e-12)
    # no interface twice: (a, b, position) unique
    key = np.c_[jt.a, jt.b, np.round(jt.p.reshape(len(jt.a), -1), 9)]
    assert len(np.unique(key, axis=0)) == jt.count


def test_toothing_overlap_is_c_and_bond_staggered_by_c():
    A = t_section_blocks(B1)
    jt, bb = A.interfaces, A.bounds()
    b, c, a = 0.5, 0.2, 0.3
    tooth = np.flatnonzero(A.kind == TOOTHING)
    assert tooth.size == 15 and np.allclose(bb[tooth, 2], b + c)          # courses 0, 2, ..., 28
    assert np.array_equal(A.course[tooth], np.arange(0, 30, 2))
    for t in tooth:
        # bed joints of the tooth's wall part with the wall blocks above and below: [b, b + c]
        for other in (jt.b[jt.a == t], jt.a[jt.b == t]):
            wall = [o for o in other if A.kind[o] == WALL]
            for o in wall:
                k = np.flatnonzero((((jt.a == t) & (jt.b == o)) | ((jt.a == o) & (jt.b == t)))
                                   & jt.horizontal)
                if k.size == 0:         # the wall block beside the tooth (head joint)
                    continue
                assert k.size == 1
                xs = np.sort(jt.p[k[0], :, 0])
                assert xs == pytest.approx([b, b + c], abs=1e-12)
    # plain courses: façade block [0, b] with a head joint of height a at x = b
    plain = np.flatnonzero(A.kind == FACADE)
    assert plain.size == 15 and np.allclose(bb[plain, 2], b)
    head = ~jt.horizontal & np.isin(jt.a, plain)
    assert head.sum() == 15
    assert np.allclose(jt.p[head, :, 0], b) and np.allclose(jt.length[head], a)
    # running bond: wall head joints of consecutive courses are offset by c (mod 2c)
    vert = ~jt.horizontal & (A.kind[jt.a] == WALL) & (A.kind[jt.b] == WALL)
    for k in range(29):
        x0 = np.unique(np.round(jt.p[vert & (A.course[jt.a] == k), 0, 0], 9))
        x1 = np.unique(np.round(jt.p[vert & (A.course[jt.a] == k + 1), 0, 0], 9))
        assert np.allclose(np.mod(x0[:, None] - x1[None, :], 2 * c), c, atol=1e-9)
    # the wall ends with half blocks (L = 15 · 2c) in the toothed courses
    last = bb[(A.kind == WALL) & np.isin(A.course, A.course[tooth])]
    widths = last[:, 2] - last[:, 0]
    assert np.isclose(widths, c).sum() == 15 and np.isclose(widths, 2 * c).sum() == 15 * 14


def test_partial_top_course_and_last_block():
    A = t_section_blocks(ODD)
    bb = A.bounds()
    top = A.course == A.meta["n_courses"] - 1
    assert A.meta["n_courses"] == 10
    assert np.allclose(bb[top, 3] - bb[top, 1], 2.95 - 2.7)
    # each course ends at b + L with whatever is left of the 2c bond
    ends = [bb[A.course == k, 2].max() for k in range(10)]
    assert np.allclose(ends, 0.45 + 2.3)
    widths = bb[A.kind == WALL, 2] - bb[A.kind == WALL, 0]
    assert widths.max() == pytest.approx(0.4) and widths.min() > 0


def test_toothing_block_carries_both_densities():
    A = t_section_blocks(B1)
    t = np.flatnonzero(A.kind == TOOTHING)[0]
    gs = 2000 * 0.5
    m_hand = 12 * gs * 0.5 * 0.3 + gs * 0.2 * 0.3
    assert A.mass[t] == pytest.approx(m_hand, rel=1e-14)
    xg = (12 * gs * 0.5 * 0.3 * 0.25 + gs * 0.2 * 0.3 * 0.6) / m_hand
    assert A.centroid[t, 0] == pytest.approx(xg, rel=1e-14)
    # inertia about the centroid: two rectangles, parallel axes
    I_hand = sum(m * ((w ** 2 + 0.3 ** 2) / 12 + (x - xg) ** 2)
                 for m, w, x in ((12 * gs * 0.15, 0.5, 0.25), (gs * 0.06, 0.2, 0.6)))
    assert A.inertia[t] == pytest.approx(I_hand, rel=1e-12)


def test_running_bond_facade_straddles_the_abutment():
    A = t_section_blocks(B1, facade="running-bond")
    bb = A.bounds()
    strad = np.flatnonzero(A.kind == TOOTHING)
    assert np.allclose(bb[strad, 0], 0.5 - 0.2) and np.allclose(bb[strad, 2], 0.5 + 0.2)
    assert np.all(A.kind[(bb[:, 2] <= 0.5 + 1e-12) & (A.kind != SUPPORT)] == FACADE)


def test_find_interfaces_general_polygons():
    # two triangles sharing the diagonal of the unit square, and a square beside them offset
    # by half its height: shared segments of non-axis-aligned and partly overlapping edges
    v = np.array([[0, 0], [1, 0], [1, 1],          # triangle a (ccw)
                  [0, 0], [1, 1], [0, 1],          # triangle b (ccw)
                  [1, 0.5], [2, 0.5], [2, 1.5], [1, 1.5]], float)
    o = np.array([0, 3, 6, 10])
    jt = find_interfaces(v, o)
    assert jt.count == 2
    diag = np.flatnonzero((jt.a == 0) & (jt.b == 1) | (jt.a == 1) & (jt.b == 0))[0]
    assert jt.length[diag] == pytest.approx(np.sqrt(2), rel=1e-14)
    n_ab = jt.n[diag] if jt.a[diag] == 0 else -jt.n[diag]
    assert n_ab == pytest.approx([-np.sqrt(0.5), np.sqrt(0.5)])
    side = 1 - diag
    assert {jt.a[side], jt.b[side]} == {0, 2}
    assert sorted(jt.p[side, :, 1]) == pytest.approx([0.5, 1.0])


def test_polygon_moments_match_triangle_moments():
    rng = np.random.default_rng(7)
    for _ in range(20):
        ang = np.sort(rng.uniform(0, 2 * np.pi, 7))
        poly = np.c_[np.cos(ang), np.sin(ang)] * rng.uniform(0.5, 2) + rng.normal(size=2)
        A, Sx, Sz, Jxx, Jzz = polygon_moments(poly, np.array([0, 7]))
        tri = np.c_[np.zeros(5, int), np.arange(1, 6), np.arange(2, 7)]
        At, Sxt, Szt, Jt = triangle_moments(poly, tri)
        assert A[0] == pytest.approx(At.sum(), rel=1e-12)
        assert Sx[0] == pytest.approx(Sxt.sum(), rel=1e-12)
        assert Sz[0] == pytest.approx(Szt.sum(), rel=1e-12)
        assert Jxx[0] + Jzz[0] == pytest.approx(Jt.sum(), rel=1e-12)


def test_fix_below_holds_the_lower_courses():
    A = t_section_blocks(B1).fix_below(3.0)
    bb = A.bounds()
    assert np.all(A.fixed == (bb[:, 3] <= 3.0 + 1e-9))
    assert A.n_free == 16 * 20


def test_bad_input_is_refused_with_the_parameter_named():
    with pytest.raises(ParameterError, match="case"):
        t_section_blocks("B1")
    with pytest.raises(ParameterError, match="facade = 'brick'"):
        t_section_blocks(B1, facade="brick")
    with pytest.raises(ParameterError, match=r"z0 = 0\.15 m .* cuts 16 block"):
        t_section_blocks(B1).fix_below(0.15)
    with pytest.raises(ParameterError, match="x0 < x1"):
        from_rectangles([0, 1], [1, 0.5], [0, 0], [1, 1], 1.0)
    with pytest.raises(ParameterError, match=r"widths min = -1\.0 m is out of range"):
        stack([1.0, -1.0], [1.0, 1.0])
    with pytest.raises(ParameterError, match="n_blocks = 0"):
        running_bond_panel(0, 2, 0.3, 0.2)
    with pytest.raises(ParameterError, match="density min"):
        from_rectangles([0], [1], [0], [1], -2.0)
