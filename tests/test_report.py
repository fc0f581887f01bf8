"""Result files: atomic writers, JSON/CSV round trips, PNGs re-opened and inspected."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from homlimit import _io
from homlimit.app import report


def assert_png(path, size_px=None):
    """The file is a PNG of the expected size (w, h) in pixels and is not blank."""
    import matplotlib.image as mpimg

    assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    img = mpimg.imread(path)
    h, w = img.shape[:2]
    if size_px is not None:
        assert (w, h) == size_px
    rgb = img[..., :3].reshape(-1, 3)
    colours = np.unique(np.round(rgb * 255).astype(int), axis=0)
    assert len(colours) > 50, f"{path} looks blank ({len(colours)} colours)"
    assert rgb.std() > 0.05


def test_json_round_trip_with_numpy_and_non_finite(tmp_path):
    data = {"a": np.float64(1.5), "n": np.int64(3), "v": np.arange(3.0), "bad": math.inf,
            "nan": float("nan"), "flag": np.bool_(True), "nested": [{"x": (1, 2)}]}
    p = report.write(tmp_path / "sub" / "r.json", data)
    back = json.loads(p.read_text())
    head = {k: back.pop(k) for k in ("schema_version", "homlimit_version", "units")}
    assert back == {"a": 1.5, "n": 3, "v": [0.0, 1.0, 2.0], "bad": None, "nan": None,
                    "flag": True, "nested": [{"x": [1, 2]}]}
    assert head["schema_version"] == _io.SCHEMA_VERSION == 1
    assert head["homlimit_version"] == _io.package_version()
    assert head["units"] == {**dict.fromkeys(["a", "bad", "flag", "n", "nan", "v"]),  # none
                             "x": "m"}


def test_every_output_carries_units_schema_and_15_digits(tmp_path):
    """JSON: schema_version and homlimit_version first, units last; CSV: a plain table with
    units in its headers and the sidecar NAME.csv.json (schema, units by header); Parquet:
    the same in its schema metadata; floats in text to 15 significant digits."""
    import pyarrow as pa
    import pyarrow.parquet as pq

    noisy = 0.1 * 6                               # 0.6000000000000001
    assert repr(noisy) == "0.6000000000000001"
    back = json.loads(report.write(tmp_path / "t.json", {"alpha2": noisy, "rows": [
        {"h": 1 / 3, "vg": -2e-310}]}).read_text())
    assert list(back) == ["schema_version", "homlimit_version", "alpha2", "rows", "units"]
    assert back["alpha2"] == 0.6 and back["rows"] == [{"h": 0.333333333333333, "vg": -2e-310}]
    assert back["units"] == {"alpha2": "-", "h": "m", "vg": "m/s"}
    rows = json.loads(report.write(tmp_path / "r.json", [{"lam": noisy}]).read_text())
    assert rows["rows"] == [{"lam": 0.6}] and rows["units"] == {"lam": "-"}

    report.write(tmp_path / "t.csv", [{"alpha2": noisy, "vg": 0.5, "mechanism": "I"}])
    assert (tmp_path / "t.csv").read_text() == "alpha2 [-],vg [m/s],mechanism\n0.6,0.5,I\n"
    side = json.loads((tmp_path / "t.csv.json").read_text())
    assert side == {"schema_version": 1, "homlimit_version": _io.package_version(),
                    "file": "t.csv", "columns": ["alpha2 [-]", "vg [m/s]", "mechanism"],
                    "units": {"alpha2 [-]": "-", "vg [m/s]": "m/s", "mechanism": ""}}

    table = pa.table({"derived.alpha2": [noisy, None], "case": ["a", "b"]})
    _io.write_output(tmp_path / "t.parquet", table, units={"derived.alpha2": "-"})
    back = pq.read_table(tmp_path / "t.parquet")
    meta = back.schema.metadata
    assert meta[b"schema_version"] == b"1" and json.loads(meta[b"units"]) == {
        "derived.alpha2": "-"}
    assert back.column("derived.alpha2").to_pylist() == [noisy, None]     # binary: exact
    _io.write_output(tmp_path / "t2.csv", table, units={"derived.alpha2": "-", "case": ""})
    assert (tmp_path / "t2.csv").read_text().splitlines()[1:] == ['0.6,"a"', ',"b"']
    assert json.loads((tmp_path / "t2.csv.json").read_text())["units"] == {
        "derived.alpha2": "-", "case": ""}


def test_writes_are_whole_or_absent(tmp_path):
    p = tmp_path / "r.json"
    report.write(p, {"ok": 1})
    before = p.read_text()
    with pytest.raises(TypeError):
        report.write(p, {"bad": object()})   # fails while serialising
    assert p.read_text() == before and json.loads(before)["ok"] == 1  # the previous file kept

    def crash(tmp):
        tmp.write_bytes(b"half a picture")
        raise RuntimeError("renderer died")

    with pytest.raises(RuntimeError):
        _io.write_figure(tmp_path / "x.png", crash)
    assert not (tmp_path / "x.png").exists()
    assert sorted(f.name for f in tmp_path.iterdir()) == ["r.json"]  # no temporary left


def test_unknown_suffix_is_a_parameter_error(tmp_path):
    from homlimit.errors import ParameterError

    with pytest.raises(ParameterError, match="file suffix = '.docx' is out of range"):
        report.write(tmp_path / "r.docx", {"ok": 1})
    assert not list(tmp_path.iterdir())


def test_csv_round_trip(tmp_path):
    import csv

    recs = [{"c_over_a": 0.5, "f": 0.3, "tanpsi": None}, {"c_over_a": 1.0, "f": 0.6,
                                                          "tanpsi": 0.77}]
    p = report.write(tmp_path / "s.csv", recs)
    rows = list(csv.DictReader(p.open()))
    assert rows == [{"c_over_a [-]": "0.5", "f [-]": "0.3", "tanpsi [-]": ""},
                    {"c_over_a [-]": "1.0", "f [-]": "0.6", "tanpsi [-]": "0.77"}]
    back = report.read_csv(p)                              # units dropped, numbers parsed
    assert back[1] == {"c_over_a": 1.0, "f": 0.6, "tanpsi": 0.77}
    assert math.isnan(back[0]["tanpsi"])                   # an empty cell: NaN


def test_csv_headers_carry_units(tmp_path):
    """Every column a command writes to CSV has its unit (fe_scan, table1, crack study,
    spectra); a column without one is refused rather than written bare."""
    from homlimit.app.studies import CRACK_COLUMNS
    from homlimit.closed_form.paper import table1_rows
    from homlimit.dynamics.spectra import SPECTRUM_COLUMNS
    from homlimit.errors import ParameterError

    scan = ["h_part", "h", "lam", "vg", "vnorm", "vg_body", "multiplier", "mechanism",
            "tanpsi", "hinge_ratio", "status", "retries", "solver_tol",
            "vg_method"]                                                   # FEMechanism.record
    fe_cols = ["lam_fe", "vnorm_fe", "vg_fe", "tanpsi_fe", "tanpsi_fe_edges", "mechanism_fe",
               "multiplier_fe", "critical_at_fe", "hinge_ratio_fe"]
    for col in scan + list(table1_rows()[0]) + fe_cols + CRACK_COLUMNS + SPECTRUM_COLUMNS:
        report.csv_header(col)
    assert report.csv_header("vg") == "vg [m/s]" and report.csv_header("lam") == "lam [-]"
    assert report.csv_header("pga") == "pga [m/s^2]" and report.csv_header("test") == "test"
    with pytest.raises(ParameterError, match="column = 'speed' is out of range"):
        report.csv_header("speed")
    # a run still writes a column someone forgot to give a unit, flagged (and logged)
    report.write(tmp_path / "x.csv", [{"speed": 1.0, "vg": 2.0}])
    assert (tmp_path / "x.csv").read_text().splitlines()[0] == "speed [?],vg [m/s]"


def test_vtu_round_trip(tmp_path):
    import meshio

    pts = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]], float)
    m = meshio.Mesh(pts, [("triangle", np.array([[0, 1, 2], [1, 3, 2]]))],
                    point_data={"velocity": pts[:, :2] * 2},
                    cell_data={"region": [np.array([1, 2])]})
    p = report.write(tmp_path / "m.vtu", m)
    back = meshio.read(p)
    np.testing.assert_array_equal(back.points, pts)
    np.testing.assert_array_equal(back.point_data["velocity"], pts[:, :2] * 2)
    np.testing.assert_array_equal(back.cell_data["region"][0], [1, 2])


def test_vtu_keeps_named_sets_and_region_tags(tmp_path):
    from homlimit.fe.mesh import read

    pts = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]], float)
    cells = [("line", np.array([[0, 1]])), ("triangle", np.array([[0, 1, 2], [1, 3, 2]]))]
    sets = {"base": [np.array([0]), np.array([], int)],
            "facade": [np.array([], int), np.array([1])],
            "wall": [np.array([], int), np.array([0])]}
    import meshio

    m = meshio.Mesh(pts, cells, point_data={"speed": np.arange(4.0)}, cell_sets=sets)
    p = report.write(tmp_path / "m.vtu", m)
    assert set(m.cell_sets) == set(sets) and not m.cell_data      # the input is untouched
    raw = meshio.read(p)
    np.testing.assert_array_equal(raw.cell_data["region"][1], [2, 1])   # wall = 2, facade = 1
    np.testing.assert_array_equal(raw.point_data["speed"], np.arange(4.0))
    back = read(p)                                      # homlimit.fe.mesh restores the sets
    assert {k: [list(i) for i in v] for k, v in back.cell_sets.items()} == \
        {k: [list(i) for i in v] for k, v in sets.items()}


def test_format_table_aligns_columns():
    t = report.format_table(["name", "x"], [["I", 0.36968996], ["II", None]], title="T")
    lines = t.splitlines()
    assert lines[0] == "T"
    assert lines[3].split() == ["I", "0.3697"]
    assert lines[4].split() == ["II", "–"]
    assert len({len(line) for line in lines[1:]}) == 1


@pytest.mark.slow
def test_mesh_and_mechanism_pictures(tmp_path):
    """plot_mesh and plot_mechanism on a small hand-made two-region mesh."""
    import meshio

    from homlimit.app import plots
    from homlimit.params import Case

    x, z = np.meshgrid(np.linspace(0, 1.5, 7), np.linspace(0, 3, 9))
    pts = np.column_stack([x.ravel(), z.ravel(), 0 * x.ravel()])
    k = np.arange(6 * 8).reshape(8, 6) + np.arange(8)[:, None]
    tri = np.concatenate([np.column_stack([k.ravel(), k.ravel() + 1, k.ravel() + 7]),
                          np.column_stack([k.ravel() + 1, k.ravel() + 8, k.ravel() + 7])])
    cx = pts[tri, 0].mean(axis=1)
    mesh = meshio.Mesh(pts, [("triangle", tri), ("line", np.array([[0, 1], [1, 2]]))],
                       cell_sets={"facade": [np.flatnonzero(cx < 0.5), np.array([], int)],
                                  "wall": [np.flatnonzero(cx >= 0.5), np.array([], int)],
                                  "base": [np.array([], int), np.array([0, 1])]})
    pts_, tri_, region, names = plots.triangle_regions(mesh)
    assert names == ["facade", "wall"] and len(tri_) == len(tri)
    assert np.count_nonzero(region == 0) == np.count_nonzero(cx < 0.5)
    p = plots.plot_mesh(tmp_path / "mesh.png", mesh, title="case T")
    assert_png(p, (9 * plots.DPI, int(7.5 * plots.DPI)))
    vel = np.column_stack([-(pts[:, 1]), pts[:, 0]]) * (pts[:, 1] > 1)[:, None]
    case = Case()
    p = plots.plot_mechanism(tmp_path / "mech.png", {
        "points": pts, "triangles": tri, "velocity": vel, "hinge": (0.0, 1.0),
        "crack": np.array([[0.5, 1.0], [1.5, 2.5]]),
        "crack_edges": [np.array([[0.5, 1.0], [1.0, 2.8]])]}, case, title="case T")
    assert_png(p, (int(7.5 * plots.DPI), 8 * plots.DPI))


@pytest.mark.slow
def test_crack_study_picture(tmp_path):
    from homlimit.app import plots

    recs = [{"c_over_a": ca, "f": f, "tanpsi_fe": math.sqrt(ca * f) * 1.05, "facade": fac}
            for ca in (0.5, 1.0, 2.0) for f in (0.3, 0.6, 0.9)
            for fac in ("homogenised", "bed-joints")]
    p = plots.plot_crack_study(tmp_path / "study.png", recs)
    assert_png(p, (7 * plots.DPI, 6 * plots.DPI))


def test_vectorised_rounding_gives_the_doubles_of_the_15_digit_format():
    """``_io.round_array`` (the sweep's CSV columns) equals float(f"{x:.15g}") one by one, on
    every magnitude, halves near the 15th digit, signed zeros, subnormals and non-finite."""
    rng = np.random.default_rng(7)
    x = rng.random(20000) * 10.0 ** rng.integers(-320, 308, 20000)
    x = np.r_[x, -x[:5000], 0.1 * 6, 1 / 3, 123456789012345.5, 999999999999999.5, 1e15 - 0.4,
              0.0, -0.0, 5e-324, 1.7e308, math.nan, math.inf, -math.inf]
    exact = [float(f"{v:.15g}") if math.isfinite(v) else v for v in x.tolist()]
    got = _io.round_array(x)
    assert all(a == b or (math.isnan(a) and math.isnan(b)) for a, b in zip(got.tolist(), exact))
    assert np.array_equal(np.signbit(got), np.signbit(np.array(exact)))
