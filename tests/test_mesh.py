"""meshio <-> scikit-fem with named sets; round trips through files; cache; reference meshes."""

from __future__ import annotations

from pathlib import Path

import meshio
import numpy as np
import pytest

from homlimit.errors import MeshError, ParameterError
from homlimit.fe import geometry
from homlimit.fe import mesh as hm
from homlimit.fe.geometry import tsection

MESHES = Path(__file__).resolve().parent.parent / "meshes"


@pytest.fixture(scope="module")
def tm():
    return tsection(9.0, 0.5, 6.0, 1.0, size_junction=0.3)


def same_skfem(a, b):
    np.testing.assert_array_equal(a.p, b.p)
    np.testing.assert_array_equal(a.t, b.t)
    assert set(a.subdomains) == set(b.subdomains) and set(a.boundaries) == set(b.boundaries)
    for k in a.subdomains:
        np.testing.assert_array_equal(np.sort(a.subdomains[k]), np.sort(b.subdomains[k]))
    for k in a.boundaries:
        np.testing.assert_array_equal(np.sort(a.boundaries[k]), np.sort(b.boundaries[k]))


@pytest.mark.parametrize("suffix", [".msh", ".vtu", ".xdmf"])
def test_write_read_round_trip(tm, tmp_path, suffix):
    ref = hm.to_skfem(tm)
    path = hm.write(tm, tmp_path / f"t{suffix}")
    assert sorted(p.name for p in tmp_path.iterdir()) == [f"t{suffix}"]   # one whole file
    back = hm.read(path)
    same_skfem(ref, hm.to_skfem(back))
    # and once more through the file just read (merged blocks, re-encoded sets)
    same_skfem(ref, hm.to_skfem(hm.read(hm.write(back, tmp_path / f"u{suffix}"))))


def test_skfem_round_trip(tm, tmp_path):
    ref = hm.to_skfem(tm)
    same_skfem(ref, hm.to_skfem(hm.from_skfem(ref)))
    same_skfem(ref, hm.to_skfem(hm.read(hm.write(hm.from_skfem(ref), tmp_path / "s.msh"))))


def test_boundaries_are_facets_on_their_lines(tm):
    m = hm.to_skfem(tm)
    xz = m.p[:, m.facets[:, m.boundaries["junction"]]]
    np.testing.assert_allclose(xz[0], 0.5, atol=1e-12)
    # the skfem facet index of a named line joins exactly its two nodes
    lines = np.vstack([c.data for c, s in zip(tm.cells, tm.cell_sets["base"]) if len(s)])
    got = np.sort(m.facets[:, m.boundaries["base"]].T, axis=1)
    np.testing.assert_array_equal(np.unique(np.sort(lines, axis=1), axis=0),
                                  np.unique(got, axis=0))


def test_bad_meshes_raise(tm, tmp_path):
    pts = tm.points.copy()
    pts[0, 2] = 1.0
    with pytest.raises(MeshError, match="not plane"):
        hm.to_skfem(meshio.Mesh(pts, tm.cells, cell_sets=tm.cell_sets))
    tri = [c for c in tm.cells if c.type == "triangle"][0].data
    bogus = meshio.Mesh(tm.points, [("triangle", tri), ("line", np.array([tri[0, [0, 0]]]))],
                        cell_sets={"x": [np.zeros(0, int), np.array([0])]})
    with pytest.raises(MeshError, match="not edges"):
        hm.to_skfem(bogus)
    with pytest.raises(ParameterError, match="path = "):
        hm.read(tmp_path / "missing.msh")


def test_failed_write_leaves_old_file_untouched(tm, tmp_path, monkeypatch):
    path = tmp_path / "keep.vtu"
    path.write_text("old")

    def half_write(filename, mesh, **kw):          # a writer dying half-way through
        Path(filename).write_text("partial")
        raise OSError("disk full")
    monkeypatch.setattr(meshio, "write", half_write)
    from homlimit.errors import OutputError

    with pytest.raises(OutputError, match="cannot write .*keep.vtu: disk full"):  # a disk
        hm.write(tm, path)                   # failure, not a meshing one (exit 3 either way)
    assert path.read_text() == "old"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["keep.vtu"]


def test_cache_generates_once(tmp_path, monkeypatch):
    kw = dict(H=4.0, b=0.5, L=2.0, size=0.8)
    first = hm.cached("tsection", directory=tmp_path, **kw)
    files = list(tmp_path.iterdir())
    assert len(files) == 1 and files[0].suffix == ".msh"
    monkeypatch.setattr(geometry, "tsection", lambda **k: pytest.fail("regenerated"))
    again = hm.cached("tsection", directory=tmp_path, **kw)
    same_skfem(hm.to_skfem(first), hm.to_skfem(again))
    monkeypatch.undo()
    hm.cached("tsection", directory=tmp_path, **(kw | {"size": 0.7}))
    assert len(list(tmp_path.iterdir())) == 2
    with pytest.raises(ParameterError, match="builder = "):
        hm.cached("nonsense", directory=tmp_path)


def test_cache_folder_of_a_checkout_and_of_an_install(tmp_path, monkeypatch):
    """docs/cli.md: $HOMLIMIT_MESH_CACHE, else meshes/cache/ of a source checkout, else
    ~/.cache/homlimit/meshes. The module lies at homlimit/fe/mesh.py in both layouts."""
    monkeypatch.delenv("HOMLIMIT_MESH_CACHE", raising=False)
    monkeypatch.setenv("HOME", str(tmp_path / "home"))
    tree = tmp_path / "checkout"
    (tree / "homlimit" / "fe").mkdir(parents=True)
    (tree / "meshes").mkdir()
    (tree / "pyproject.toml").write_text("")
    monkeypatch.setattr(hm, "__file__", str(tree / "homlimit" / "fe" / "mesh.py"))
    assert hm.cache_dir() == tree / "meshes" / "cache"
    site = tmp_path / "lib" / "python3.11" / "site-packages"
    (site / "homlimit" / "fe").mkdir(parents=True)
    monkeypatch.setattr(hm, "__file__", str(site / "homlimit" / "fe" / "mesh.py"))
    assert hm.cache_dir() == tmp_path / "home" / ".cache" / "homlimit" / "meshes"
    monkeypatch.setenv("HOMLIMIT_MESH_CACHE", str(tmp_path / "mine"))
    assert hm.cache_dir() == tmp_path / "mine"


@pytest.mark.parametrize("name,b", [("tsection_B1_coarse", 0.5), ("tsection_B4_coarse", 0.25)])
def test_reference_meshes(name, b):
    m = hm.to_skfem(hm.read(MESHES / f"{name}.msh"))
    H, L = 9.0, 6.0
    area = hm.element_areas(m)
    assert area.sum() == pytest.approx(H * (b + L), rel=1e-12)
    assert area[m.subdomains["facade"]].sum() == pytest.approx(H * b, rel=1e-12)
    assert set(m.boundaries) == {"base", "outer", "top", "end", "junction"}
    assert np.all(m.f2t[:, m.boundaries["junction"]] >= 0)
    q = hm.quality(m)
    assert q["min_angle_deg"] > 20 and 300 < q["n_elements"] < 3000
