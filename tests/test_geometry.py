"""Meshes of the T-section and of generic polygons: areas, regions, named lines, conformity,
size control, and failures (bad input before gmsh starts; gmsh errors; session finalised)."""

from __future__ import annotations

import math

import gmsh
import numpy as np
import pytest

from homlimit.errors import MeshError, ParameterError
from homlimit.fe import geometry
from homlimit.fe.geometry import gmsh_session, polygon_mesh, tsection
from homlimit.fe.mesh import element_areas, to_skfem

H, B, L = 9.0, 0.5, 6.0           # Table 1, B1


def facet_lengths(m, ix):
    a, b = m.p[:, m.facets[0, ix]], m.p[:, m.facets[1, ix]]
    return np.hypot(*(b - a))


def covered_length(m, p, q, tol=1e-9):
    """Total length of mesh edges lying on the segment pq (both ends within tol of it)."""
    p, q = np.asarray(p, float), np.asarray(q, float)
    u = (q - p) / np.linalg.norm(q - p)
    ends = [m.p[:, m.facets[i]].T - p for i in range(2)]
    on = np.ones(m.facets.shape[1], bool)
    for e in ends:
        s = e @ u
        on &= (np.abs(e[:, 0] * u[1] - e[:, 1] * u[0]) < tol) & (s > -tol) \
            & (s < np.linalg.norm(q - p) + tol)
    return facet_lengths(m, np.flatnonzero(on)).sum()


@pytest.fixture(scope="module")
def b1():
    return to_skfem(tsection(H, B, L, 0.6, size_junction=0.2, size_top=0.2))


def test_tsection_area_and_regions(b1):
    area = element_areas(b1)
    assert np.all(area > 0)
    assert area.sum() == pytest.approx(H * (B + L), rel=1e-12)
    sub = b1.subdomains
    assert set(sub) == {"facade", "wall"}
    every = np.concatenate([sub["facade"], sub["wall"]])
    np.testing.assert_array_equal(np.sort(every), np.arange(b1.t.shape[1]))   # exactly one
    assert area[sub["facade"]].sum() == pytest.approx(H * B, rel=1e-12)
    assert area[sub["wall"]].sum() == pytest.approx(H * L, rel=1e-12)
    x = b1.p[0, b1.t].mean(0)
    assert np.all(x[sub["facade"]] < B) and np.all(x[sub["wall"]] > B)


def test_tsection_named_lines(b1):
    bnd = b1.boundaries
    assert set(bnd) == {"base", "outer", "top", "end", "junction"}
    xz = {k: b1.p[:, b1.facets[:, ix]] for k, ix in bnd.items()}
    np.testing.assert_allclose(xz["base"][1], 0.0, atol=1e-12)
    np.testing.assert_allclose(xz["top"][1], H, atol=1e-12)
    np.testing.assert_allclose(xz["outer"][0], 0.0, atol=1e-12)
    np.testing.assert_allclose(xz["end"][0], B + L, atol=1e-12)
    np.testing.assert_allclose(xz["junction"][0], B, atol=1e-12)
    for k, want in (("base", B + L), ("top", B + L), ("outer", H), ("end", H), ("junction", H)):
        assert facet_lengths(b1, bnd[k]).sum() == pytest.approx(want, rel=1e-12), k
    # the four outer parts are exactly the mesh boundary; the junction is interior
    outer = np.concatenate([bnd[k] for k in ("base", "outer", "top", "end")])
    np.testing.assert_array_equal(np.sort(outer), np.sort(b1.boundary_facets()))


def test_junction_shared_by_both_regions(b1):
    f2t = b1.f2t[:, b1.boundaries["junction"]]
    assert np.all(f2t >= 0)                              # two neighbours each
    fac, wall = set(b1.subdomains["facade"]), set(b1.subdomains["wall"])
    for e1, e2 in f2t.T:
        assert {e1 in fac, e2 in fac} == {True, False}
        assert (e1 in wall) != (e2 in wall)


def test_restricted_height_z0():
    m = to_skfem(tsection(H, B, L, 0.75, z0=3.0))
    assert element_areas(m).sum() == pytest.approx((H - 3.0) * (B + L), rel=1e-12)
    np.testing.assert_allclose(m.p[1, m.facets[:, m.boundaries["base"]]], 3.0, atol=1e-12)
    assert m.p[1].min() == pytest.approx(3.0)


def test_halving_size_quadruples_elements():
    """Observed: 584 -> 2188 triangles from size 0.5 to 0.25 m (ratio 3.75; boundary layers make
    it a little below 4 on coarse meshes, 4.04 from 0.25 to 0.125)."""
    n1 = to_skfem(tsection(H, B, L, 0.5)).t.shape[1]
    n2 = to_skfem(tsection(H, B, L, 0.25)).t.shape[1]
    assert 3.5 < n2 / n1 < 4.5, (n1, n2)


def test_local_refinement(b1):
    p, t = b1.p, b1.t
    edge = np.max([np.hypot(*(p[:, t[i]] - p[:, t[(i + 1) % 3]])) for i in range(3)], axis=0)
    c = p[:, t].mean(1)
    near_j = np.abs(c[0] - B) < 0.2
    near_top = (c[1] > H - 0.2) & (c[0] < B)
    far = (np.abs(c[0] - B) > 2.0) & (c[1] < H - 2.0)
    assert edge[near_j].max() < 0.2 * 1.6 and edge[near_top].max() < 0.2 * 1.6
    assert np.median(edge[far]) > 0.6 * 0.8
    coarse = to_skfem(tsection(H, B, L, 0.6))
    assert b1.t.shape[1] > 1.5 * coarse.t.shape[1]


def test_embedded_rays_from_a_hinge_on_the_outer_face():
    zh = 3.0
    rays = [((0.0, zh), (B + 2.0, H)),          # ends on the top boundary, crosses the junction
            ((0.0, zh), (B + L, zh + 1.0)),     # ends on the far end
            ((0.0, zh), (3.0, zh + 2.5)),       # ends inside the wall
            ((0.0, zh), (B + L + 2.0, zh + 0.5))]   # leaves the domain: clipped at x = b + L
    m = to_skfem(tsection(H, B, L, 0.6, embed_lines=rays))
    for (p, q) in rays[:3]:
        assert covered_length(m, p, q) == pytest.approx(math.dist(p, q), rel=1e-9)
    p, q = rays[3]
    zq = p[1] + (q[1] - p[1]) * (B + L) / q[0]
    assert covered_length(m, p, q) == pytest.approx(math.dist(p, (B + L, zq)), rel=1e-9)
    assert element_areas(m).sum() == pytest.approx(H * (B + L), rel=1e-12)
    # the hinge splits the outer face: still all of it, and a mesh node sits at (0, z_h)
    assert facet_lengths(m, m.boundaries["outer"]).sum() == pytest.approx(H, rel=1e-12)
    assert np.min(np.hypot(m.p[0], m.p[1] - zh)) < 1e-12


@pytest.mark.parametrize("rays", [
    [((0.0, 0.0), (B + L, H))],                                # toe to the far top corner
    [((0.0, 0.0), (B + 3.0, H)), ((0.0, 0.0), (B + L, 4.0))],   # a fan from the toe
    [((B, 2.0), (B, 5.0))],                                    # on the junction itself
    [((0.0, 1.0), (0.0, 4.0))],                                # on the outer face
    [((0.0, 2.0), (4.0, H)), ((0.0, 6.0), (B + L, 3.0))]])     # two rays crossing
def test_embedded_lines_on_corners_boundaries_and_crossings(rays):
    m = to_skfem(tsection(H, B, L, 0.5, embed_lines=rays, refine_points=[(0.0, 0.0, 0.1, 0.3)]))
    for p, q in rays:
        assert covered_length(m, p, q) == pytest.approx(math.dist(p, q), rel=1e-9)
    assert element_areas(m).sum() == pytest.approx(H * (B + L), rel=1e-12)
    assert set(m.boundaries) == {"base", "outer", "top", "end", "junction"}
    assert facet_lengths(m, m.boundaries["junction"]).sum() == pytest.approx(H, rel=1e-12)


def test_polygon_prandtl_footing_and_point_refinement():
    W, D, Bf = 5.0, 5.0, 1.0
    m = to_skfem(polygon_mesh(
        {"soil": [(-W, -D), (W, -D), (W, 0.0), (-W, 0.0)]},
        {"footing": ((-Bf / 2, 0.0), (Bf / 2, 0.0)), "top": ((-W, 0.0), (W, 0.0)),
         "bottom": ((-W, -D), (W, -D)), "sides": [((-W, -D), (-W, 0.0)), ((W, -D), (W, 0.0))]},
        size=1.0, refine_points=[(Bf / 2, 0.0, 0.05, 0.3), (-Bf / 2, 0.0, 0.05, 0.3)]))
    bnd = m.boundaries
    assert facet_lengths(m, bnd["footing"]).sum() == pytest.approx(Bf, rel=1e-12)
    assert set(bnd["footing"]) <= set(bnd["top"])
    assert facet_lengths(m, bnd["top"]).sum() == pytest.approx(2 * W, rel=1e-12)
    assert facet_lengths(m, bnd["sides"]).sum() == pytest.approx(2 * D, rel=1e-12)
    assert element_areas(m).sum() == pytest.approx(2 * W * D, rel=1e-12)
    d = np.hypot(m.p[0] - Bf / 2, m.p[1])
    fl = facet_lengths(m, np.arange(m.facets.shape[1]))
    near = np.min(d[m.facets], axis=0) < 0.1
    assert fl[near].max() < 0.05 * 2.5


def test_polygon_vertical_cut_step_and_block():
    # step-shaped soil: a vertical cut of height 1 at x = 0
    step = [(-3.0, -2.0), (3.0, -2.0), (3.0, 1.0), (0.0, 1.0), (0.0, 0.0), (-3.0, 0.0)]
    m = to_skfem(polygon_mesh({"soil": step}, {"face": ((0.0, 0.0), (0.0, 1.0))}, size=0.4))
    assert element_areas(m).sum() == pytest.approx(6 * 2 + 3 * 1, rel=1e-12)
    assert facet_lengths(m, m.boundaries["face"]).sum() == pytest.approx(1.0, rel=1e-12)
    # free-standing block of width 0.5 and height 2 on its base
    blk = to_skfem(polygon_mesh({"block": [(0, 0), (0.5, 0), (0.5, 2.0), (0, 2.0)]},
                                {"base": ((0, 0), (0.5, 0))}, size=0.25))
    assert element_areas(blk).sum() == pytest.approx(1.0, rel=1e-12)


def test_regions_conform_along_partly_shared_edges():
    """A region whose edge covers only part of its neighbour's edge: no crack in the mesh
    (the mesh boundary is the perimeter of the union)."""
    m = to_skfem(polygon_mesh({"low": [(0, 0), (2, 0), (2, 1), (0, 1)],
                               "up": [(0.5, 1), (1.3, 1), (1.3, 2), (0.5, 2)]},
                              {"shared": ((0.5, 1), (1.3, 1))}, size=0.3))
    assert facet_lengths(m, m.boundary_facets()).sum() == pytest.approx(6 + 2, rel=1e-12)
    assert np.all(m.f2t[:, m.boundaries["shared"]] >= 0)


@pytest.mark.parametrize("kwargs,name", [
    ({"H": -9.0}, "H"), ({"b": 0.0}, "b"), ({"L": float("nan")}, "L"), ({"size": 0.0}, "size"),
    ({"size": 20.0}, "size"), ({"z0": 9.0}, "z0"), ({"z0": -1.0}, "z0"),
    ({"size_junction": -0.1}, "size_junction"), ({"size_top": 5.0}, "size_top"),
    ({"radius_top": 0.0}, "radius_top"),
    ({"embed_lines": [((0, 1), (0, 1))]}, r"embed_lines\[0\]"),
    ({"embed_lines": [((0, 1), (float("inf"), 1))]}, r"embed_lines\[0\]\[1\].x")])
def test_invalid_tsection_input_fails_before_gmsh(monkeypatch, kwargs, name):
    def no_gmsh(*a, **k):
        raise AssertionError("gmsh must not start on invalid input")
    monkeypatch.setattr(gmsh, "initialize", no_gmsh)
    args = dict(H=H, b=B, L=L, size=0.5) | kwargs
    with pytest.raises(ParameterError, match=rf"^{name} = "):
        tsection(**args)


@pytest.mark.parametrize("call,name", [
    (lambda: polygon_mesh({"r": [(0, 0), (1, 0)]}, size=0.1), r"regions\['r'\]"),
    (lambda: polygon_mesh({"r": [(0, 0), (1, 0), (2, 0)]}, size=0.1), r"regions\['r'\]"),
    (lambda: polygon_mesh({"r": [(0, 0), (1, 0), (0, 1)]}, size=-1), "size"),
    (lambda: polygon_mesh({"r": [(0, 0), (1, 0), (0, 1)]}, {"r": ((0, 0), (1, 0))}, size=0.1),
     "boundary name"),
    (lambda: polygon_mesh({"r": [(0, 0), (1, 0), (0, 1)]}, size=0.1,
                          refine_points=[(0, 0, 0.0, 0.1)]), r"refine_points\[0\].size"),
    (lambda: polygon_mesh({"r": [(0, 0), (1, 0), (0, 1)]}, size=0.1,
                          refine_segments=[((0, 0), (1, 0), 0.01, -1)]),
     r"refine_segments\[0\].radius")])
def test_invalid_polygon_input_fails_before_gmsh(monkeypatch, call, name):
    monkeypatch.setattr(gmsh, "initialize", lambda *a, **k: pytest.fail("gmsh started"))
    with pytest.raises(ParameterError, match=rf"^{name}"):
        call()


def test_gmsh_error_is_a_mesh_error_and_session_is_finalised():
    with pytest.raises(MeshError, match="gmsh failed"):
        with gmsh_session("broken") as g:
            g.model.occ.addLine(1001, 1002)             # no such points
            g.model.occ.synchronize()
    assert not gmsh.isInitialized()


def test_failure_during_meshing_finalises(monkeypatch):
    def boom(*a, **k):
        raise Exception("simulated gmsh failure")       # gmsh raises plain Exception
    monkeypatch.setattr(gmsh.model.mesh, "generate", boom)
    with pytest.raises(MeshError, match="simulated gmsh failure"):
        tsection(H, B, L, 1.0)
    assert not gmsh.isInitialized()


def test_gmsh_sessions_of_two_threads_wait_for_each_other():
    # gmsh holds global state: meshes made in two threads at once equal those made one after
    # the other (gmsh_session's lock), and no session is left open
    from concurrent.futures import ThreadPoolExecutor

    sizes = [0.5, 0.3, 0.4, 0.25]
    def mesh(size):
        return polygon_mesh({"a": [(0, 0), (2, 0), (2, 1), (0, 1)]}, size=size)
    serial = [mesh(h) for h in sizes]
    with ThreadPoolExecutor(2) as pool:
        threaded = list(pool.map(mesh, sizes))
    for x, y in zip(serial, threaded):
        np.testing.assert_array_equal(x.points, y.points)
        np.testing.assert_array_equal(x.cells_dict["triangle"], y.cells_dict["triangle"])
    assert not gmsh.isInitialized()


def test_a_gmsh_session_keeps_the_processs_sigterm_handler():
    # gmsh.initialize resets SIGTERM, SIGHUP and SIGPIPE to the default, so a SIGTERM after
    # meshing killed `homlimit run` before its clean-up; gmsh_session puts Python's back
    import subprocess
    import sys

    code = """
import os, signal, sys, time
signal.signal(signal.SIGTERM, lambda s, f: sys.exit(7))
from homlimit.fe.geometry import polygon_mesh
polygon_mesh({"a": [(0, 0), (2, 0), (2, 1), (0, 1)]}, size=0.5)
os.kill(os.getpid(), signal.SIGTERM)
time.sleep(5)
"""
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, timeout=120)
    assert proc.returncode == 7, (proc.returncode, proc.stderr[-500:])


def test_overlapping_regions_and_nested_sessions():
    with pytest.raises(MeshError, match="overlap"):
        polygon_mesh({"a": [(0, 0), (2, 0), (2, 1), (0, 1)],
                      "b": [(1, 0), (3, 0), (3, 1), (1, 1)]}, size=0.5)
    assert not gmsh.isInitialized()
    with gmsh_session():
        with pytest.raises(MeshError, match="already open"):
            with gmsh_session():
                pass
    assert not gmsh.isInitialized()


def test_public_names():
    assert geometry.TSECTION_REGIONS == ("facade", "wall")
    assert set(geometry.TSECTION_BOUNDARIES) == {"base", "outer", "top", "end", "junction"}
