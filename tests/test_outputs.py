"""What a user opens: mechanism.vtu's fields, units and notes; the FE cache of `pulse`."""

from __future__ import annotations

import dataclasses
import json

import numpy as np
import pytest

from cases import b1, toml

# a demo-like wall (Table 1's B1) on a coarse mesh: a few seconds
TINY = b1("tiny", mesh={"size": 1.0, "part_divisions": 4, "outer_ratio": 0.0},  # one mesh:
          adapt={"max_cycles": 1},                          # vtu stress (not adaptive)
          analysis={"heights": 2, "facade": "homogenised", "hinge_check": False},
          output={"png": False})


@pytest.fixture
def cache(tmp_path, monkeypatch):
    """A fresh FE and mesh cache folder ($HOMLIMIT_MESH_CACHE)."""
    folder = tmp_path / "cache"
    monkeypatch.setenv("HOMLIMIT_MESH_CACHE", str(folder))
    return folder


def _text(field) -> str:
    """A text field of a .vtu (its UTF-8 bytes as a UInt8 array, fe.mesh.write)."""
    return bytes(np.asarray(field, np.uint8)).decode("utf-8")


def test_mechanism_vtu_stress_tensor_units_and_velocity_scale(tmp_path, cache):
    """The .vtu read back with meshio: stress a symmetric 3x3 tensor in Pa with out-of-plane
    components 0 whose plane part lies in eq. 15's domain; velocity normalised to max |v| = 1
    with velocity_scale [m/s] beside it; a unit for every field; no all-zero dissipation field
    (cohesionless masonry dissipates nothing) but a note saying why."""
    import meshio

    import homlimit
    from homlimit.fe.strength import Homogenised

    res = homlimit.run(TINY, out=tmp_path / "o")
    m = meshio.read(res.files["mechanism_vtu"])
    tri = next(k for k, c in enumerate(m.cells) if c.type == "triangle")
    n = len(m.cells[tri].data)
    assert n == res.fe.whole.n_triangles
    stress = m.cell_data["stress"][tri]
    assert stress.shape == (n, 9)
    t = stress.reshape(n, 3, 3)
    assert np.array_equal(t[:, 0, 1], t[:, 1, 0])                 # σ_xz = σ_zx
    assert not np.any(t[:, 2, :]) and not np.any(t[:, :, 2])      # out of plane: 0
    assert np.abs(t[:, 0, 1]).max() > 0                           # a shear stress is there
    sig = np.c_[t[:, 0, 0], t[:, 1, 1], t[:, 0, 1]]               # (σ_x, σ_z, τ_xz) [Pa]
    assert np.all(Homogenised(0.3, 0.2, 0.6).is_admissible(sig / np.abs(sig).max(), tol=1e-6))
    units = json.loads(_text(m.field_data["units"]))
    assert units["stress"] == "Pa" and units["velocity"] == "-"
    assert units["velocity_scale"] == "m/s" and units["density"] == "kg/m^2"
    fields = set(m.point_data) | set(m.cell_data) | {"velocity_scale"}
    assert set(units) == fields and None not in units.values()
    (scale,) = m.field_data["velocity_scale"]
    assert 0 < scale < 1e-3                            # the solver's amplitude, ~1e-6 m/s
    v = m.point_data["velocity"][np.unique(m.cells[tri].data)]
    assert np.linalg.norm(v, axis=1).max() == pytest.approx(1.0, rel=1e-12)
    notes = json.loads(_text(m.field_data["notes"]))
    assert "dissipation" not in m.cell_data
    assert notes["dissipation"].startswith("not written") and "eq. 15" in notes["dissipation"]
    assert "static_sigma_x" in m.cell_data and units["static_compression_angle"] == "rad"
    # the other outputs of the set: units and schema version
    summary = json.loads((tmp_path / "o" / "summary.json").read_text())
    assert summary["schema_version"] == 1 and summary["units"]["results"]["vg"] == "m/s"
    side = json.loads((tmp_path / "o" / "fe_scan.csv.json").read_text())
    assert side["file"] == "fe_scan.csv" and side["units"]["vg [m/s]"] == "m/s"


def test_interface_dissipation_is_written_where_it_is_not_zero():
    """A rigid block on a base joint with tension strength T tips about its outer toe: the
    base opens by ω x and dissipates T ω b²/2; the .vtu's interface line cells carry it per
    facet (times velocity_scale), and the multiplier is b/h + T b/(γ g h²) (moments about
    the toe)."""
    from homlimit.app import result_mesh
    from homlimit.fe import problems, strength
    from homlimit.fe.kinematic import solve_kinematic

    b, h, T, w = 0.5, 3.0, 5e3, 2000.0 * 9.81
    prob = problems.free_block(b=b, h=h, f=0.8, n_b=2)
    prob = dataclasses.replace(prob, interfaces={
        "base": strength.BedJoints(0.8, cohesion=1e4, tension=T)})
    sol = solve_kinematic(prob)
    assert sol.multiplier == pytest.approx(b / h + T * b / (w * h * h), rel=1e-6)
    m = sol.to_meshio()
    v = m.point_data["velocity"]
    scale = np.linalg.norm(v, axis=1).max()
    notes: dict = {}
    out = result_mesh.interface_cells(m, prob, sol, scale, notes)
    assert [c.type for c in out.cells] == ["triangle", "line"] and not notes
    line = out.cells[1].data
    assert len(line) == 2 and np.all(out.points[line][..., 1] == 0.0)    # the base facets
    assert np.array_equal(out.cell_data["interface"][1], [1.0, 1.0])
    top = np.isclose(m.points[:, 1], h)
    omega = np.mean(-v[top, 0] / m.points[top, 1])          # rigid rotation about (0, 0)
    D = out.cell_data["interface_dissipation"][1].sum() * scale
    assert D == pytest.approx(T * omega * b * b / 2, rel=1e-5)
    # a dry joint dissipates nothing: no field, a note
    dry = dataclasses.replace(prob, interfaces={"base": strength.BedJoints(0.8)})
    notes = {}
    out = result_mesh.interface_cells(m, dry, sol, scale, notes)
    assert "interface_dissipation" not in out.cell_data
    assert notes["interface_dissipation"].startswith("not written")


def test_pulse_reads_the_fe_result_run_cached_and_never_trusts_a_corrupt_entry(tmp_path,
                                                                                cache):
    """`run` leaves the FE path's critical mechanism in the cache; `pulse` reads it from
    there, with the numbers the FE path gives when computed again; a tampered entry (its
    checksum fails) is not trusted, a corrupt one is computed again and rewritten; the CLI
    says where the FE result came from."""
    from typer.testing import CliRunner

    import homlimit
    from homlimit.app.cli import app
    from homlimit.app.config import load_case
    from homlimit.app.pipeline import fe_cache_path, pulse_records, read_fe_cache

    case_file = tmp_path / "tiny.toml"
    # TINY's mesh size and outputs, on the default mesher settings and adaptive chain
    case = b1("tiny", mesh={"size": 1.0, "part_divisions": 4}, output={"png": False},
              analysis={**TINY["analysis"], "static": False},
              pulse={"mechanisms": ["FE"], "kinds": ["rectangular"], "periods": [0.5],
                     "polarities": [1]})
    case_file.write_text(toml(case))
    cfg = load_case(case_file)
    path = fe_cache_path(cfg)
    assert path.parent == cache and not path.exists()
    homlimit.run(cfg, out=tmp_path / "o")
    assert path.is_file()
    pts, fe = pulse_records(cfg)                       # read: no FE solve
    assert fe.from_cache and fe.cache == path
    entry = json.loads(path.read_text())               # tampered: a valid JSON, a new number
    entry["impulse"]["M"] *= 1.01
    path.write_text(json.dumps(entry))
    assert read_fe_cache(cfg) is None                  # never trusted
    path.write_bytes(b"\x00garbage{")                  # corrupt: computed again, rewritten
    again, fresh = pulse_records(cfg)
    assert not fresh.from_cache and fresh.cache == path
    assert fresh.impulse == fe.impulse and (fresh.h, fresh.vg) == (fe.h, fe.vg)
    assert [p.as_dict() for p in again] == [p.as_dict() for p in pts]   # identical numbers
    assert read_fe_cache(cfg) == dataclasses.replace(fresh, from_cache=True)
    res = CliRunner().invoke(app, ["pulse", str(case_file), "--out", str(tmp_path / "p")])
    assert res.exit_code == 0, res.output
    assert f"FE result read from cache {path}" in res.stdout


def test_the_fe_cache_key_follows_the_adapt_section(tmp_path):
    """[adapt] sets the whole wall's meshes and the crack's splits, so an FE cache entry of
    one setting is never read for another; the same case gives the same entry."""
    from homlimit.app.config import load_case
    from homlimit.app.pipeline import fe_cache_path

    def path(name, **adapt):
        f = tmp_path / f"{name}.toml"
        f.write_text(toml(b1(name, adapt=adapt) if adapt else b1(name)))
        return fe_cache_path(load_case(f))

    assert path("a") == path("b")
    assert path("c", crack_cycles=0) != path("a")
    assert path("d", target_gap=0.005) != path("a")
