"""The output registry (issue 28): every result file has one entry (name → writer, where its
units are, schema version) and one writer; ``writers.write`` honours the entry."""

from __future__ import annotations

import json

from homlimit.app import writers
from homlimit.app.writers import FORMATS, OUTPUT_NAMES, OUTPUTS, Output, write


def test_every_registered_file_has_one_writer():
    for name, out in OUTPUTS.items():
        assert out.name == name
        if out.by == "app.writers.write":
            assert out.suffix in FORMATS or out.suffix == ".parquet", name
        assert out.units in ("columns", "keys", "sections", "metadata", "fields", "axes",
                             "inline", ""), name
    # the CSV files' sidecars are result files too
    assert "blocks_contacts.csv.json" in OUTPUT_NAMES and "summary.json" in OUTPUT_NAMES
    assert len(set(OUTPUT_NAMES)) == len(OUTPUT_NAMES)


def test_write_takes_the_schema_version_of_the_entry(tmp_path, monkeypatch):
    monkeypatch.setitem(OUTPUTS, "toy.json", Output("toy.json", "test", "keys", schema=7))
    monkeypatch.setitem(OUTPUTS, "toy.csv", Output("toy.csv", "test", "columns", schema=5))
    write(tmp_path / "toy.json", {"vg": 0.5})
    write(tmp_path / "toy.csv", [{"vg": 0.5, "h": 2.0}])
    write(tmp_path / "other.json", {"vg": 0.5})
    data = json.loads((tmp_path / "toy.json").read_text(encoding="utf-8"))
    assert data["schema_version"] == 7 and data["units"] == {"vg": "m/s"}
    side = json.loads((tmp_path / "toy.csv.json").read_text(encoding="utf-8"))
    assert side["schema_version"] == 5 and side["units"] == {"vg [m/s]": "m/s", "h [m]": "m"}
    assert (tmp_path / "toy.csv").read_text(encoding="utf-8").splitlines() == [
        "vg [m/s],h [m]", "0.5,2.0"]
    other = json.loads((tmp_path / "other.json").read_text(encoding="utf-8"))
    assert other["schema_version"] == writers.SCHEMA_VERSION == 1


def test_a_caller_unit_map_goes_to_the_file(tmp_path):
    write(tmp_path / "sweep.json", {"n_cases": 2}, units={"inputs": {"wall": {"H": "m"}}})
    data = json.loads((tmp_path / "sweep.json").read_text(encoding="utf-8"))
    assert data["units"] == {"inputs": {"wall": {"H": "m"}}} and data["n_cases"] == 2
