"""The one-page report (``[output] report = true``, app/report_html.py): report.html is one
self-contained file of the result set, with the inputs' values and units as the case file gives
them, the code check's ratios as summary.json has them, the package version, and the run's
PNG pictures embedded byte for byte, the floors' Q_k reading and the nonlinear check as
summary.json has them. Cheap cases: closed forms only, a floor and a [site]; B1 (tests/cases.py)
with a [site], with and without a floor.
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

from cases import b1

ROOT = Path(__file__).resolve().parents[1]

CASE = {"name": "report-case",
        "wall": {"H": 9.0, "L": 6.0, "s": 0.5, "b": 0.5, "l": 6.0},
        "masonry": {"a": 0.3, "c": 0.2, "f": 0.6},
        "analysis": {"fe": False, "overturning": True, "hinge_check": False},
        "floor": [{"z": 4.5, "load": 12500.0, "eccentricity": 0.35}],
        "site": {"ag": 2.56, "F0": 2.36, "Tc_star": 0.35, "soil": "B", "storeys": 2},
        "output": {"report": True}}

#: B1 on the code check's tests' site (soil A, a_g = 0.2 g), closed forms and the overturning
SITE = {"ag": 0.2 * 9.81, "F0": 2.5, "Tc_star": 0.3}
CHEAP = {"fe": False, "overturning": True, "hinge_check": False}

CELL = re.compile(r'data-key="([^"]+)" data-value="([^"]+)">[^<]*</td>(?:<td>([^<]*)</td>)?')


def _run(tmp_path, **output) -> Path:
    case = {**CASE, "output": {**CASE["output"], **output}}
    homlimit.run(case, out=tmp_path / "out")
    return tmp_path / "out"


def _shown(text: str) -> dict[str, tuple[float, str]]:
    """data-key → (data-value, the cell's text as the table shows it)."""
    return {m[1]: (float(m[2]), m[3])
            for m in re.finditer(r'data-key="([^"]+)" data-value="([^"]+)">([^<]*)</td>', text)}


def _run_b1(tmp_path, **sections) -> tuple[str, dict]:
    """report.html's text and summary.json of B1 with a [site], the closed forms only."""
    case = b1("report-b1", analysis=CHEAP, site=SITE, output={"report": True, "png": False},
              **sections)
    homlimit.run(case, out=tmp_path / "out")
    summary = json.loads((tmp_path / "out" / "summary.json").read_text(encoding="utf-8"))
    return (tmp_path / "out" / "report.html").read_text(encoding="utf-8"), summary


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


def test_report_shows_the_floors_reading_beside_the_used_check(tmp_path):
    """B1 with a floor of 20 kN/m at mid-height (docs/code-check.md, reading 3): the floors'
    Q_k table shows summary.json's code_check.floors_Qk, each number to 4 significant digits
    (the floors' masses to 5) with its full value in data-value, the used ratio beside it."""
    text, summary = _run_b1(tmp_path, floor=[{"z": 4.5, "load": 20000.0,
                                              "eccentricity": 0.1}])
    cc = summary["code_check"]
    fq = cc["floors_Qk"]
    assert set(fq["mechanisms"]) == {"I", "II", "overturning"} and not fq["not_computed"]
    shown = _shown(text)
    for name, c in fq["mechanisms"].items():
        for q, digits in [("alpha0", 4), ("m_floors", 5), ("e_star", 4), ("a0_star", 4),
                          ("Z", 4), ("demand", 4), ("ratio", 4)]:
            value, cell = shown[f"code_check.floors_Qk.{name}.{q}"]
            assert value == pytest.approx(c[q], rel=1e-14), (name, q)
            assert cell == f"{c[q]:.{digits}g}", (name, q)
        assert f">{cc['mechanisms'][name]['ratio']:.4g}</td>" in text
    assert (f"governing in the floors' reading: {fq['governing']}, ratio {fq['ratio']:.4g}"
            in text)
    # docs/code-check.md's figures for this floor: the overturning's ratio 0.598 → 0.465
    assert (cc["ratio"], fq["ratio"]) == pytest.approx((0.598, 0.465), abs=6e-4)
    # the floor takes the clean capacity curve away: no nonlinear check, the reason once
    assert text.count("nonlinear check not computed for I, II, overturning: no clean "
                      "capacity curve") == 1
    assert "code_check.nonlinear." not in text


def test_report_shows_the_nonlinear_check_and_that_the_readings_coincide(tmp_path):
    """B1 without floors: one line says the floors' reading is the used one; the simple
    overturning's nonlinear check at the ground (tests/test_code_check_nonlinear.py's hand
    computation: d_u* = 0.133333 m, S_De(T_s) = 0.0804339 m, ratio 1.65767; 2019 form
    1.69941) as summary.json's code_check.nonlinear has it."""
    text, summary = _run_b1(tmp_path)
    assert ("the floors' Q_k reading (Circolare 2019 transcription, C8.7.1.1/.5): the case "
            "has no floors, the readings coincide") in text
    assert "code_check.floors_Qk." not in text
    nl = summary["code_check"]["nonlinear"]
    c = nl["mechanisms"]["overturning"]
    shown = _shown(text)
    for q in ("d0_star", "du_star", "Ts", "SDe_Ts", "ratio", "T_SLV", "SDe_SLV", "ratio_SLV"):
        value, cell = shown[f"code_check.nonlinear.overturning.{q}"]
        assert value == pytest.approx(c[q], rel=1e-14) and cell == f"{c[q]:.4g}", q
    assert (c["du_star"], c["SDe_Ts"], c["ratio"]) == pytest.approx(
        (0.133333, 0.0804339, 1.65767), rel=1e-5)
    assert c["ratio_SLV"] == pytest.approx(1.69941, rel=1e-5)
    assert shown["code_check.nonlinear.overturning.ratio"][1] == "1.658"
    assert [n["mechanism"] for n in nl["not_computed"]] == ["I", "II"]
    assert "nonlinear check not computed for I, II: no clean capacity curve" in text


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
