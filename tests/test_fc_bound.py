"""A finite [masonry] fc too low for the wall (docs/real-walls.md "a part that would crush"):
refused before any work, naming fc, its value and the wall's bound N(λ = 0.5)/(b l); above
the bound the closed forms keep to the parts that do not crush (``mechanisms._minimise``)."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

import homlimit
from homlimit.app import pipeline
from homlimit.app.config import ConfigError, load_case
from homlimit.closed_form import mechanisms as M
from homlimit.closed_form import real
from homlimit.errors import ParameterError

from cases import run_cli

# Table 1's C4 (b = 0.25 m, l = 2.5 m, γ = 2000 kg/m³): mechanism I's bound γ g b/2
C4 = {"wall": {"H": 9.0, "L": 6.0, "s": 0.5, "b": 0.25, "l": 2.5},
      "masonry": {"a": 0.3, "c": 0.2, "f": 0.6}, "analysis": {"fe": False}}
FC_I = 2000 * 9.81 * 0.25 / 2                  # 2452.5 Pa


def c4(fc: float) -> dict:
    return {**C4, "masonry": {**C4["masonry"], "fc": fc}}


def test_the_bound_is_the_smallest_parts_block_filling_b():
    case = load_case(c4(1e6)).case
    low, n = real.fc_min(case, "detachment")
    assert low == pytest.approx(FC_I, rel=1e-12)
    assert n == pytest.approx(2000 * 9.81 * 2.5 * 0.25 * 0.125, rel=1e-12)
    assert real.fc_min(case, "overturning")[0] == pytest.approx(FC_I, rel=1e-12)
    # mechanism II's wedge adds γ s tan ψ h²/2 to the smallest part's mass
    t = math.sqrt(0.2 * 0.6 / 0.3)
    wedge = 2000 * 9.81 * 0.5 * t * 0.125 ** 2 / 2
    assert real.fc_min(case, "crack")[0] == pytest.approx(FC_I + wedge / (0.25 * 2.5),
                                                            rel=1e-12)


@pytest.mark.parametrize("fc", [1.0, 1000.0, 2530.0])
def test_load_case_refuses_a_crushing_fc(fc):
    with pytest.raises(ConfigError) as e:
        load_case(c4(fc))
    msg = str(e.value)
    assert f"[masonry] fc = {fc!r} Pa is too low for this wall" in msg
    assert "allowed fc = 0 (infinite) or fc >= 2531 Pa (a bound of this wall" in msg


def test_the_rounded_bound_is_admissible():
    res = homlimit.run(c4(2531.0), write=False)
    assert all(math.isfinite(m.vg) for m in res.mechanisms.values())


def test_api_raises_parameter_error_before_any_work(monkeypatch):
    monkeypatch.setattr(pipeline, "compute", lambda *a, **k: pytest.fail("computed"))
    with pytest.raises(ParameterError, match=r"\[masonry\] fc = 1000.0 Pa is too low"):
        homlimit.run(c4(1000.0), write=False)


def test_real_mechanism_raises_parameter_error():
    case = load_case(c4(1e6)).case
    case = dataclasses.replace(case, masonry=dataclasses.replace(case.masonry, fc=100.0))
    for kind in real.KINDS:
        with pytest.raises(ParameterError, match=r"\[masonry\] fc = 100.0 Pa is too low"):
            real.real_mechanism(case, kind)


@pytest.mark.parametrize("fc", [1e4, 3e4])
def test_parts_that_do_not_crush_are_searched(fc):
    # only the short parts fit their stress block (λ <= about fc/(γ g b)): the critical part
    # is one of them, not "every part crushes" (the golden section once ran into the NaNs)
    res = homlimit.run(c4(fc), write=False)
    for m in res.mechanisms.values():
        assert math.isfinite(m.vg) and m.vg > 0
        assert 2 * m.hinge_retreat <= 0.25
        grid = np.linspace(0.5, m.lam_max, 4000)
        v = real.vnorm_real(res.config.case, m.kind, grid, m.tanpsi)
        assert m.vnorm <= np.nanmin(v) * (1 + 1e-6)


def test_minimise_keeps_to_finite_values():
    def fun(lam, ix):                 # decreasing, NaN (crushed) beyond λ = 2
        return np.where(lam <= 2.0, 1.0 / lam, np.nan) + 0 * lam

    lam, v = M.minimise(fun, np.array([36.0, 1.5]))
    assert lam[0] == pytest.approx(2.0, rel=1e-6) and v[0] == pytest.approx(0.5, rel=1e-6)
    assert lam[1] == pytest.approx(1.5, rel=1e-9)
    lam, v = M.minimise(lambda x, ix: np.full_like(x, np.nan), np.array([10.0]))
    assert np.isnan(v[0])             # none finite: NaN, not numpy's All-NaN ValueError


def test_cli_exit_2_names_fc_and_writes_nothing(tmp_path):
    res = run_cli(tmp_path, c4(1000.0), "run")
    assert res.returncode == 2, res.stderr
    assert "Traceback" not in res.stderr
    assert "[masonry] fc = 1000.0 Pa is too low for this wall" in res.stderr
    assert "fc >= 2531 Pa" in res.stderr
    assert not (tmp_path / "out").exists()
