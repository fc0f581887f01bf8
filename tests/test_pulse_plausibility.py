"""`homlimit pulse` on doubtful input (issue 27): records that cannot be a ground motion are
refused (exit 2, one line naming the key [pulse] record and the problem, nothing written);
valid but doubtful records and critical pulses beyond recorded ground motion are kept, flagged
and warned about (exit 0)."""

from __future__ import annotations

import csv
import json

import pytest
from typer.testing import CliRunner

from homlimit.app.cli import app

CHEAP = ("--set", 'pulse.kinds=["rectangular"]', "--set", "pulse.periods=[0.5]",
         "--set", 'pulse.mechanisms=["I"]', "--set", "pulse.polarities=[1]")


def invoke(*args):
    res = CliRunner().invoke(app, [str(a) for a in args])
    assert res.exit_code in (0, 2, 3), (res.exit_code, res.output, res.exception)
    assert "Traceback" not in res.stderr
    return res


@pytest.fixture
def sandbox(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    return tmp_path


@pytest.mark.parametrize("rows, reason", [
    # the record: 3 samples over 1e9 s (it gave pgv 3e9 m/s)
    ([(0, 0), (5e8, 6), (1e9, 0)], "has 3 times and 3 accelerations: allowed two equal "
                                   "columns of at least 16 rows"),
    ([(0.01 * k, 1.0) for k in range(15)], "has 15 times"),
    ([(0.01 * k, 1.0) for k in range(8)] + [(0.05, 1.0)]
     + [(0.1 + 0.01 * k, 1.0) for k in range(8)], "record time t[8] = 0.05 s is out of range"),
    ([(0.01 * k, 1.0) for k in range(8)] + [(0.07, 1.0)]
     + [(0.1 + 0.01 * k, 1.0) for k in range(8)], "record time t[8] = 0.07 s is out of range"),
    ([(0.01 * k, float("nan") if k == 3 else 1.0) for k in range(20)], "non-finite"),
    ([(float("inf") if k == 19 else 0.01 * k, 1.0) for k in range(20)], "non-finite"),
])
def test_a_record_that_is_no_ground_motion_exits_2(sandbox, rows, reason):
    with open(sandbox / "rec.csv", "w", newline="") as fh:
        csv.writer(fh).writerows(rows)
    res = invoke("pulse", "--set", "pulse.record=rec.csv", *CHEAP)
    assert res.exit_code == 2
    (line,) = [ln for ln in res.stderr.splitlines() if "error" in ln]
    assert line.startswith("homlimit: error: <default: B1>: [pulse] record = 'rec.csv': ")
    assert reason in line
    assert not (sandbox / "homlimit-out").exists()


def test_a_coarse_record_is_kept_with_a_warning(sandbox):
    """16 samples, one step of 0.16 s: valid, computed, and warned about (the key, the
    step and where it is)."""
    rows = [(0.01 * k, 4.0 if 0 < k < 14 else 0.0) for k in range(15)] + [(0.3, 0.0)]
    with open(sandbox / "rec.csv", "w", newline="") as fh:
        csv.writer(fh).writerows(rows)
    res = invoke("pulse", "--set", "pulse.record=rec.csv", "--json", *CHEAP)
    assert res.exit_code == 0, res.stderr
    assert ("[pulse] record = 'rec.csv': record 'rec' has a time step of 0.16 s (from t = 0.14 s): "
            "over 0.05 s") in res.stderr
    points = json.loads(res.stdout)["points"]
    assert [p["pulse"] for p in points] == ["rectangular", "record"]


def test_implausible_critical_pulses_are_kept_flagged_and_warned(sandbox):
    """Mechanism I of B1 under a one-sine of 0.02 s (+1) needs pga > 3 g: exit 0, the row is
    in spectra.csv and the JSON with implausible = true, the text table says so, stderr
    warns; the 0.5 s pulse (pga about 0.7 g) is not flagged."""
    args = ("pulse", "--set", 'pulse.kinds=["one-sine"]', "--set", "pulse.periods=[0.02, 0.5]",
            "--set", 'pulse.mechanisms=["I"]', "--set", "pulse.polarities=[1]")
    res = invoke(*args, "--json", "--out", sandbox / "out")
    assert res.exit_code == 0, res.stderr
    short, long_ = json.loads(res.stdout)["points"]
    assert short["pga_g"] > 3 and short["implausible"] is True
    assert long_["pga_g"] < 3 and long_["pgv"] < 3 and long_["implausible"] is False
    assert ("warning: 1 of 2 critical pulses need pga > 3 g or pgv > 3 m/s, beyond recorded "
            "ground motion (kept, column implausible = true): one-sine +1 T_p = 0.02 s, I: "
            f"pga {short['pga_g']:.3g} g") in res.stderr
    with open(sandbox / "out" / "spectra.csv", newline="") as fh:
        rows = list(csv.DictReader(fh))
    assert [r["implausible"] for r in rows] == ["True", "False"]
    text = invoke(*args, "--out", sandbox / "again")
    assert text.exit_code == 0
    rows = [ln.split() for ln in text.stdout.splitlines() if ln.startswith("one-sine")]
    assert [(r[3], r[-1]) for r in rows] == [("0.02", "implausible"), ("0.5", "0")]
