"""Case files: the embedded default, round trips, and every class of bad input reported at once."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import pytest

from homlimit.app import models, models_rigid, pipeline
from homlimit.app.config import (
    SCHEMA,
    CaseConfig,
    ConfigError,
    default_case,
    load_case,
    schema_markdown,
)
from homlimit.errors import ParameterError

from cases import B1

ROOT = Path(__file__).resolve().parents[1]


def _write(tmp_path, text, name="case.toml"):
    p = tmp_path / name
    p.write_text(text, encoding="utf-8")
    return p


def test_default_case_is_table1_B1():
    cfg = default_case()
    w, m = cfg.case.wall, cfg.case.masonry
    # Table 1, test B1: H=9, L=6, s=0.5, b=0.5, l=6 (rho=12), a=0.3, c=0.2, f=0.6
    assert (w.H, w.L, w.s, w.b, w.l, w.gamma, w.g) == (9.0, 6.0, 0.5, 0.5, 6.0, 2000.0, 9.81)
    assert (m.a, m.c, m.f) == (0.3, 0.2, 0.6)
    assert cfg.name == "B1"
    # eq. 11 with the paper's Table 1 columns: rho = 12, beta = 0.4, alpha^2 = 0.4
    assert cfg.case.rho == pytest.approx(12.0, rel=1e-15)
    assert cfg.case.beta == pytest.approx(0.4, rel=1e-15)
    assert cfg.case.alpha ** 2 == pytest.approx(0.4, rel=1e-15)
    assert load_case(None) == cfg


def test_minimal_dict_gets_documented_defaults():
    cfg = load_case(B1)
    assert cfg.case.wall.gamma == 2000.0 and cfg.case.wall.g == 9.81
    for sec in ("mesh", "analysis", "output"):
        for name, key in SCHEMA[sec].items():
            assert getattr(getattr(cfg, sec), name) == key.default, (sec, name)
    assert cfg.name == "case" and cfg.source == "<dict>"


def test_as_dict_round_trips():
    cfg = load_case(ROOT / "examples" / "b1" / "case.toml")
    again = load_case(cfg.as_dict())
    assert dataclasses.replace(again, source=cfg.source) == cfg


def test_toml_file_name_defaults_to_stem(tmp_path):
    text = "[wall]\nH = 9\nL = 6\ns = 0.5\nb = 0.5\nl = 6\n[masonry]\na = 0.3\nc = 0.2\nf = 0.6\n"
    cfg = load_case(_write(tmp_path, text, "my_wall.toml"))
    assert cfg.name == "my_wall"
    assert isinstance(cfg.case.wall.H, float) and cfg.case.wall.H == 9.0  # ints accepted


BROKEN = """
name = "broken"
colour = "red"

[wall]
H = 9.0
L = "six"
s = -0.5
b = 0.5
thickness = 3

[masonry]
a = 0.3
c = 0.2
f = true

[mesh]
size = 0.0

[analysis]
facade = "concrete"
heights = 2.5

[extras]
x = 1
"""


def test_every_problem_is_reported_at_once(tmp_path):
    path = _write(tmp_path, BROKEN)
    with pytest.raises(ConfigError) as info:
        load_case(path)
    e = info.value
    assert isinstance(e, ParameterError)
    assert len(e.problems) == 10, e.problems
    text = str(e)
    expected = [
        "unknown key 'colour'",                                     # unknown top-level key
        "unknown section 'extras'",                                 # unknown section
        "[wall] L = 'six' has the wrong type: expected a number",   # wrong type
        "[wall] s = -0.5 m is out of range: allowed 0.001 <= s <= 1000 m",  # range, unit
        "[wall] unknown key 'thickness'",                           # unknown key in a section
        "[wall] l is missing",                                      # missing required
        "[masonry] f = True has the wrong type",                    # bool is not a number
        "[mesh] size = 0.0 m is out of range: allowed 0 < size <= 10000 m",
        "[analysis] facade = 'concrete' is not allowed: allowed one of 'homogenised', "
        "'bedjoints'",
        "[analysis] heights = 2.5 has the wrong type: expected an integer",
    ]
    for piece in expected:
        assert piece in text, piece
    for p in e.problems:  # every line names the file
        assert p.startswith(f"{path}: ")


def test_missing_required_section_and_cross_checks(tmp_path):
    with pytest.raises(ConfigError) as info:
        load_case({"wall": B1["wall"]})
    assert len(info.value.problems) == 1
    assert "[masonry] section is missing: required keys a, c, f" in str(info.value)
    # a block taller than the wall, and a mesh size larger than the wall (params.Case checks)
    with pytest.raises(ConfigError) as info:
        load_case({"wall": B1["wall"], "masonry": {"a": 10.0, "c": 0.2, "f": 0.6}})
    assert "a = 10.0 m is out of range" in str(info.value)
    assert "a <= H = 9 m" in str(info.value)
    with pytest.raises(ConfigError) as info:
        load_case({**B1, "mesh": {"size": 20.0}})
    assert "size = 20.0 m is out of range: allowed 0 < size <= min(H, b + L) = 6.5 m" \
        in str(info.value)
    # the FE scan meshes each part at min(size, h_part/10): a coarse size is valid
    thin = {"wall": {**B1["wall"], "b": 0.25}, "masonry": B1["masonry"]}
    assert load_case({**thin, "mesh": {"size": 0.6}}).mesh.size == 0.6
    with pytest.raises(ConfigError) as info:
        load_case({**B1, "analysis": {"heights": 1, "tol": 0.5}})
    assert "[analysis] heights = 1 is out of range: allowed 2 <= heights <= 200" \
        in str(info.value)
    assert "[analysis] tol = 0.5 is out of range: allowed 0 <= tol <= 0.01" in str(info.value)


def test_unreadable_and_malformed_files(tmp_path):
    with pytest.raises(ConfigError, match="cannot read the case file"):
        load_case(tmp_path / "nowhere.toml")
    with pytest.raises(ConfigError, match="not valid TOML"):
        load_case(_write(tmp_path, "[wall\nH = 9\n"))
    with pytest.raises(ConfigError, match=r"\[wall\] must be a section"):
        load_case({"wall": 3, "masonry": B1["masonry"]})


def test_nothing_is_computed_before_validation(monkeypatch):
    def boom(*a, **k):  # pragma: no cover - must never run
        raise AssertionError("computation started on an invalid case")

    monkeypatch.setattr(models_rigid, "closed_forms", boom)
    monkeypatch.setattr(models, "fe_result", boom)
    with pytest.raises(ConfigError):
        pipeline.run({**B1, "wall": {**B1["wall"], "H": float("nan")}}, write=False)


def test_docs_list_every_key_with_default_unit_and_range():
    doc = (ROOT / "docs" / "case-file.md").read_text(encoding="utf-8")
    assert schema_markdown() in doc, ("docs/case-file.md is out of date: run "
                                      "homlimit.app.schema_doc.update_case_file_doc")
    for sec, keys in SCHEMA.items():
        for name in keys:
            assert f"| `{name}` |" in doc, (sec, name)


def test_case_config_is_immutable():
    cfg = default_case()
    assert isinstance(cfg, CaseConfig)
    with pytest.raises(dataclasses.FrozenInstanceError):
        cfg.mesh.size = 1.0


def test_overrides_apply_before_validation():
    cfg = load_case(None, ["mesh.size=0.5", "analysis.facade=bedjoints", "name='B1x'",
                           "analysis.fe=false"])
    assert (cfg.mesh.size, cfg.analysis.facade, cfg.analysis.fe) == (0.5, "bedjoints", False)
    assert cfg.base_name == "B1x" and cfg.name.startswith("B1x-")   # inputs changed: hashed
    assert load_case(B1, {"wall.H": 8}).case.wall.H == 8.0
    with pytest.raises(ConfigError) as info:
        load_case(B1, ["walls.H=3", "masonry.f=0"])
    text = str(info.value)
    assert "unknown section 'walls'" in text and "[masonry] f = 0 is out of range" in text
