"""The DEM's doors (issue 29): the [dem] case section, ``[analysis] dem = true`` in ``run``,
``homlimit table1 --dem`` on the Dask engine, and the ParaView series and snapshots.

Every DEM run here is cheap: a small stack or a short, coarse setting; never a full Table 1
wall's threshold (that is benchmarks/dem_table1.py's, minutes per wall).
"""

from __future__ import annotations

import dataclasses

import pytest
from typer.testing import CliRunner

from homlimit.app.cli import app
from homlimit.app.config import SCHEMA, ConfigError, DemConfig, load_case
from homlimit.app.dem_stage import dem_params
from homlimit.dem import DEMParams

B1 = {"wall": {"H": 9.0, "L": 6.0, "s": 0.5, "b": 0.5, "l": 6.0},
      "masonry": {"a": 0.3, "c": 0.2, "f": 0.6}}


# ----------------------------------------------------------------------------- [dem] section
def test_dem_section_defaults_are_the_models_defaults():
    cfg = load_case(B1)
    assert cfg.dem == DemConfig()
    assert cfg.analysis.dem is False                    # off by default
    for name, key in SCHEMA["dem"].items():
        assert getattr(cfg.dem, name) == key.default, name
    # every parameter of DEMParams is a [dem] key, with the same default ("rho" is 0)
    assert dem_params(cfg.dem) == DEMParams()
    assert {f.name for f in dataclasses.fields(DEMParams)} <= set(SCHEMA["dem"])
    p = dem_params(dataclasses.replace(cfg.dem, facade_stiffness=3.0, base_joint="tied"))
    assert p.facade_stiffness == 3.0 and p.base_joint == "tied"


def test_bad_dem_values_are_reported_at_once_with_key_value_and_range():
    with pytest.raises(ConfigError) as e:
        load_case({**B1, "dem": {"kn": -1.0, "dt_fraction": 0.9, "loading": "sine",
                                 "base_joint": "glued", "frame": 1}})
    text = str(e.value)
    assert "[dem] kn = -1.0 Pa/m is out of range: allowed 100000 <= kn <= 1e+13 Pa/m" in text
    assert "[dem] dt_fraction = 0.9 is out of range: allowed 0 < dt_fraction <= 0.5" in text
    assert "[dem] loading = 'sine' is not allowed: allowed one of 'impulse'" in text
    assert "[dem] base_joint = 'glued' is not allowed" in text
    assert "[dem] unknown key 'frame'" in text
    assert len(e.value.problems) == 5


def test_dem_refuses_an_assembly_over_max_blocks():
    with pytest.raises(ConfigError, match=r"\[analysis\] dem = true needs about 480 blocks .* "
                                          r"\[dem\] max_blocks = 100"):
        load_case({**B1, "analysis": {"dem": True}, "dem": {"max_blocks": 100}})
    load_case({**B1, "dem": {"max_blocks": 100}})       # only when the DEM runs


def test_cli_bad_dem_value_exits_2_before_any_work(tmp_path):
    out = tmp_path / "o"
    res = CliRunner().invoke(app, ["run", "--set", "analysis.dem=true", "--set",
                                   "dem.rel_tol=0", "--out", str(out)])
    assert res.exit_code == 2, res.output
    assert "[dem] rel_tol = 0 is out of range: allowed 0 < rel_tol <= 0.5" in res.output
    assert "Traceback" not in res.output
    assert not out.exists()
