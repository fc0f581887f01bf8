"""The one-page report (``[output] report = true``, app/report_html.py): report.html is one
self-contained file of the result set, with the inputs' values and units as the case file gives
them, the code check's ratios as summary.json has them, the package version, and the run's
PNG pictures embedded byte for byte. A cheap case: closed forms only, a floor and a [site].
The multi-storey example's case file loads (its full run takes minutes: not run here)."""

from __future__ import annotations

import base64
import json
import re
from pathlib import Path

import pytest

import homlimit
from homlimit._version import package_version
from homlimit.app.config import load_case

ROOT = Path(__file__).resolve().parents[1]

CASE = {"name": "report-case",
        "wall": {"H": 9.0, "L": 6.0, "s": 0.5, "b": 0.5, "l": 6.0},
        "masonry": {"a": 0.3, "c": 0.2, "f": 0.6},
        "analysis": {"fe": False, "overturning": True, "hinge_check": False},
        "floor": [{"z": 4.5, "load": 12500.0, "eccentricity": 0.35}],
        "site": {"ag": 2.56, "F0": 2.36, "Tc_star": 0.35, "soil": "B", "storeys": 2},
        "output": {"report": True}}

CELL = re.compile(r'data-key="([^"]+)" data-value="([^"]+)">[^<]*</td>(?:<td>([^<]*)</td>)?')


def _run(tmp_path, **output) -> Path:
    case = {**CASE, "output": {**CASE["output"], **output}}
    homlimit.run(case, out=tmp_path / "out")
    return tmp_path / "out"


def _cells(text: str) -> dict[str, tuple[float, str | None]]:
    """data-key → (data-value, the next cell's text: an input's unit)."""
    return {m[1]: (float(m[2]), m[3]) for m in CELL.finditer(text)}


def test_report_is_one_self_contained_file_with_inputs_ratios_version_pictures(tmp_path):
    out = _run(tmp_path)
    html = out / "report.html"
    assert html.is_file()
    assert [p.name for p in out.glob("*.html")] == ["report.html"]
    assert "report.html" in json.loads((out / ".homlimit-set.json").read_text())["files"]
    text = html.read_text(encoding="utf-8")
    summary = json.loads((out / "summary.json").read_text(encoding="utf-8"))
    assert summary["files"]["report_html"] == str(out / "report.html")
    cells = _cells(text)
    # the inputs as the case file gives them, each with its unit
    for key, value, unit in [("wall.H", 9.0, "m"), ("wall.gamma", 2000.0, "kg/m³"),
                             ("masonry.f", 0.6, "–"), ("site.ag", 2.56, "m/s²"),
                             ("site.Tc_star", 0.35, "s"), ("site.FC", 1.35, "–")]:
        assert cells[key] == (value, unit), key
    assert cells["floor.0.load"][0] == 12500.0 and "load [N/m]" in text
    assert "eccentricity [m]" in text and cells["floor.0.eccentricity"][0] == 0.35
    # the code check's ratios, both e* readings, are summary.json's
    cc = summary["code_check"]["mechanisms"]
    assert set(cc) == {"I", "II", "overturning"}
    for name, c in cc.items():
        for q in ("ratio", "ratio_lumped", "a0_star", "e_star", "alpha0"):
            assert cells[f"code_check.{name}.{q}"][0] == pytest.approx(c[q], rel=1e-14)
    for name, m in summary["mechanisms"].items():
        assert cells[f"{name}.vg"][0] == pytest.approx(m["vg"], rel=1e-14)
    assert f'<span id="version">{package_version()}</span>' in text
    # self-contained: no link, no script; the run's pictures embedded as they were written
    assert not re.search(r"<script|<link|src=\"(?!data:)|href=", text)
    images = re.findall(r'src="data:image/png;base64,([A-Za-z0-9+/=]+)"', text)
    pngs = sorted(out.glob("*.png"))
    assert [p.name for p in pngs] == ["code_check.png", "vg_lambda.png"]
    assert sorted(base64.b64decode(i) for i in images) == sorted(p.read_bytes() for p in pngs)


def test_report_without_pictures_says_so(tmp_path):
    out = _run(tmp_path, png=False)
    text = (out / "report.html").read_text(encoding="utf-8")
    assert not list(out.glob("*.png")) and "data:image" not in text
    assert "none ([output] png = false)" in text


def test_no_report_by_default(tmp_path):
    case = {**CASE, "output": {}}
    homlimit.run(case, out=tmp_path / "out")
    assert not (tmp_path / "out" / "report.html").exists()
    assert (tmp_path / "out" / "summary.json").is_file()


def test_report_without_site_has_no_code_check(tmp_path):
    case = {k: v for k, v in CASE.items() if k != "site"}
    homlimit.run({**case, "output": {"report": True, "png": False}}, out=tmp_path / "out")
    text = (tmp_path / "out" / "report.html").read_text(encoding="utf-8")
    assert "none: the case has no [site] section" in text and "code_check." not in text


def test_the_multistorey_example_loads():
    """examples/multistorey: three storeys, a window band and a floor in each, the roof's
    floor, a top tie, a [site]; every model and the report asked for."""
    cfg = load_case(ROOT / "examples" / "multistorey" / "case.toml")
    c = cfg.case
    assert c.wall.H == 10.5
    assert [f.z for f in c.floors] == [3.5, 7.0, 10.5]
    assert [(o.z_bottom, o.z_top, o.fraction) for o in c.facade_openings] == [
        (0.9, 2.4, 0.3), (4.4, 5.9, 0.3), (7.9, 9.4, 0.3)]
    assert [(t.z, t.yield_force) for t in c.ties] == [(10.5, 9400.0)]
    an = cfg.analysis
    assert an.closed_form and an.overturning and an.fe and an.static and an.blocks and an.dem
    assert cfg.site is not None and cfg.site.storeys == 3 and cfg.output.report


def test_a_failing_report_leaves_no_result_set(tmp_path, monkeypatch):
    """The report is written inside the run's result set: if building it fails, nothing of
    the run is left (whole or nothing), and an earlier set in the folder is kept."""
    from homlimit.app import report_html

    out = _run(tmp_path)
    before = sorted(p.name for p in out.iterdir())
    old = (out / "report.html").read_bytes()

    def broken(result, folder):
        raise RuntimeError("report failed")

    monkeypatch.setattr(report_html, "page", broken)
    with pytest.raises(RuntimeError, match="report failed"):
        homlimit.run({**CASE, "wall": {**CASE["wall"], "H": 8.0}}, out=out)
    assert sorted(p.name for p in out.iterdir()) == before
    assert (out / "report.html").read_bytes() == old
    fresh = tmp_path / "fresh"
    with pytest.raises(RuntimeError, match="report failed"):
        homlimit.run(CASE, out=fresh)
    assert not fresh.exists() or not any(fresh.iterdir())
