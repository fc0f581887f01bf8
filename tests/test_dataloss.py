"""Nothing lost: a command replaces only the result set it wrote, in a folder that belongs to
one command and one source (issue 27).

- ``run`` → ``sweep`` → ``run`` keeps the sweep stored under the case's folder whole, byte for
  byte (records, Parquet, CSV, sweep.json, its report), through the command line and the API;
- a folder holding another source's or another command's set is refused with exit 2 and a
  one-line message with an ``--out`` hint, before any work: nothing deleted, nothing written;
- the same-name collisions of the issue (demo and examples/b1, table1 and table1 -t B1) have
  their own folders, and are refused when pointed at the same one;
- a second sweep interrupted over a finished one leaves the first one's set whole (never
  sweep.json of one sweep beside results.csv of the other), and resumes.

Closed-form cases only (C4, fe = false), but for the interrupted sweep (three tiny FE cases).
"""

from __future__ import annotations

import json
import os
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest
from typer.testing import CliRunner

import homlimit
from homlimit import _io
from homlimit.app.cli import app
from homlimit.app.config import load_case
from homlimit.app.engine import Engine
from homlimit.app.pipeline import output_dir
from homlimit.app.sweep import sweep
from homlimit.errors import ParameterError

ROOT = Path(__file__).resolve().parents[1]
C4 = ROOT / "examples" / "c4-closed-form" / "case.toml"
BIN = Path(sys.executable).parent


def invoke(*args):
    return CliRunner().invoke(app, [str(a) for a in args])


def tree(folder: Path) -> dict[str, bytes]:
    """Every file under ``folder``, by relative path, with its bytes."""
    return {str(p.relative_to(folder)): p.read_bytes() for p in sorted(folder.rglob("*"))
            if p.is_file()}


@pytest.fixture(scope="module")
def engine():
    with Engine(workers=1, progress=False) as eng:
        yield eng


@pytest.fixture
def sandbox(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    shutil.copy(C4, tmp_path / "c4.toml")
    return tmp_path


def _assert_sweep_kept(out: Path, before: dict[str, bytes]):
    assert tree(out / "sweep") == before
    assert _io.check_result_set(out) == [] and _io.check_result_set(out / "sweep") == []
    assert json.loads((out / _io.MANIFEST).read_text())["kept"] == ["sweep"]


def test_run_sweep_run_keeps_the_sweep_cli(sandbox, engine):
    out = sandbox / "homlimit-out" / "C4"
    assert invoke("run", "c4.toml", "-q").exit_code == 0
    res = invoke("sweep", "c4.toml", "--grid", "wall.l=2.5,5", "--scheduler",
                 engine.client.scheduler.address, "-q")
    assert res.exit_code == 0, res.output
    assert invoke("sweep", "report", out / "sweep").exit_code == 0
    before = tree(out / "sweep")
    names = {n.split("/")[0] for n in before}
    assert {"records", "report", "results.parquet", "results.csv", "sweep.json"} <= names
    res = invoke("run", "c4.toml", "-q")
    assert res.exit_code == 0, res.output
    assert (out / "summary.json").is_file()
    _assert_sweep_kept(out, before)


def test_run_sweep_run_keeps_the_sweep_api(sandbox, engine):
    out = sandbox / "homlimit-out" / "C4"
    homlimit.run("c4.toml")
    res = sweep("c4.toml", ["masonry.f=0.5,0.6"], engine=engine, progress=False)
    assert res.folder == Path("homlimit-out/C4/sweep") and res.n_ok == 2
    before = tree(out / "sweep")
    homlimit.run("c4.toml")
    _assert_sweep_kept(out, before)


def test_another_source_is_refused_nothing_deleted_nothing_written(sandbox):
    """C4 edited into another file of the same name: its default folder is the first one's."""
    assert invoke("run", "c4.toml", "-q").exit_code == 0
    (sandbox / "other").mkdir()
    (sandbox / "other" / "c4.toml").write_text(C4.read_text().replace("f = 0.6", "f = 0.5"))
    before, listing = tree(sandbox), sorted(p.name for p in sandbox.iterdir())
    res = invoke("run", "other/c4.toml", "-q")
    assert res.exit_code == 2 and res.stdout == ""
    line = res.stderr.strip()
    assert "\n" not in line and "Traceback" not in line
    assert line.startswith("homlimit: error: output folder = 'homlimit-out/C4' holds the "
                           "result set of 'homlimit run' on ") and "--out DIR" in line
    assert str(sandbox / "other" / "c4.toml") in line
    for cmd in (["pulse", "c4.toml", "--out", "homlimit-out/C4"],      # another command
                ["mesh", "c4.toml", "--out", "homlimit-out/C4"],
                ["demo", "--out", "homlimit-out/C4"]):
        res = invoke(*cmd)
        assert res.exit_code == 2 and "--out DIR" in res.stderr, (cmd, res.output)
    with pytest.raises(ParameterError, match="holds the result set of 'homlimit run'"):
        homlimit.run(sandbox / "other" / "c4.toml")
    with pytest.raises(ParameterError, match="holds the result set of 'homlimit run'"):
        sweep("other/c4.toml", ["wall.l=2.5,5"], out="homlimit-out/C4", progress=False)
    assert tree(sandbox) == before and sorted(p.name for p in sandbox.iterdir()) == listing
    # the same file edited since: the normal workflow, replaced
    (sandbox / "c4.toml").write_text(C4.read_text().replace("f = 0.6", "f = 0.7"))
    assert invoke("run", "c4.toml", "-q").exit_code == 0
    s = json.loads((sandbox / "homlimit-out" / "C4" / "summary.json").read_text())
    assert s["inputs"]["masonry"]["f"] == 0.7


def test_demo_and_examples_b1_keep_their_own_sets(sandbox):
    """The demo's folder stays homlimit-out/B1/; examples/b1 (the README's Python snippet)
    writes homlimit-out/B1-example/; pointed at one folder, the second is refused."""
    assert output_dir(load_case(None)) == Path("homlimit-out/B1")
    example = ROOT / "examples" / "b1" / "case.toml"
    assert output_dir(load_case(example)) == Path("homlimit-out/B1-example")
    fast = ["--set", "analysis.fe=false", "--set", "output.png=false"]
    assert invoke("demo", *fast, "--out", "o").exit_code == 0
    before = tree(sandbox / "o")
    for cmd in (["run", example], ["run"]):          # another source; another command
        res = invoke(*cmd, *fast, "--out", "o")
        assert res.exit_code == 2 and "--out DIR" in res.stderr, res.output
        assert "'homlimit demo' on embedded:B1" in res.stderr
    assert tree(sandbox / "o") == before
    assert invoke("demo", *fast, "--out", "o").exit_code == 0          # re-running: fine


def test_table1_selection_has_its_own_folder(sandbox):
    assert invoke("table1", "-t", "B1", "-q").exit_code == 0
    assert invoke("table1", "-q").exit_code == 0
    one, full = sandbox / "homlimit-out" / "table1-B1", sandbox / "homlimit-out" / "table1"
    assert len(json.loads((one / "table1.json").read_text())["rows"]) == 1
    assert len(json.loads((full / "table1.json").read_text())["rows"]) == 12
    before = tree(full)
    res = invoke("table1", "-t", "B1", "--out", full)
    assert res.exit_code == 2 and "embedded:table1:B1" in res.stderr and "--out DIR" in \
        res.stderr
    assert tree(full) == before


# ----------------------------------------------------------------------------- interrupted
def _default_sigint():
    signal.signal(signal.SIGINT, signal.SIG_DFL)


def _sweep(base: Path, out: Path, *spec) -> list:
    return [BIN / "homlimit", "sweep", base, *spec, "--workers", "1", "--out", out, "-q"]


@pytest.mark.slow
def test_a_second_sweep_interrupted_over_a_finished_one_never_mixes(tmp_path):
    """Sweep 1 (closed forms, two cases) finishes; sweep 2 of the same base (three tiny FE
    cases, ~1 s each) is stopped after its first record: the folder still holds sweep 1's
    sweep.json, results.parquet and results.csv, byte for byte; sweep 2 then resumes."""
    base = tmp_path / "b1.toml"
    base.write_text((ROOT / "homlimit" / "data" / "default.toml").read_text()
                    .replace("fe = true ", "fe = false"))    # B1, closed forms
    assert load_case(base).analysis.fe is False
    out = tmp_path / "sweep"
    r = subprocess.run(_sweep(base, out, "--grid", "masonry.f=0.5,0.6"), capture_output=True,
                       text=True, timeout=600)
    assert r.returncode == 0, r.stderr
    first = {k: v for k, v in tree(out).items() if not k.startswith("records/")}
    assert set(first) == {_io.MANIFEST, "sweep.json", "results.parquet", "results.csv",
                          "results.csv.json"}
    n_first = len(list((out / "records").glob("[!.]*.json")))
    (tmp_path / "cases.csv").write_text(
        "analysis.fe,mesh.size,mesh.part_divisions,masonry.a,analysis.heights,"
        "analysis.static,masonry.f\n"
        + "".join(f"true,0.8,3,1.0,2,false,{f}\n" for f in (0.45, 0.6, 0.75)))
    second = _sweep(base, out, "--table", tmp_path / "cases.csv")
    p = subprocess.Popen(second, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                         preexec_fn=_default_sigint)
    t0 = time.monotonic()
    while len(list((out / "records").glob("[!.]*.json"))) <= n_first:   # complete records
        assert p.poll() is None, p.communicate()
        assert time.monotonic() - t0 < 300, "no record of the second sweep after 300 s"
        time.sleep(0.05)
    os.kill(p.pid, signal.SIGINT)           # Ctrl-C (SIGTERM: tests/test_sweep.py)
    _, err = p.communicate(timeout=120)
    assert p.returncode == 128 + signal.SIGINT, err
    assert "Traceback" not in err.split("homlimit: interrupted")[-1]
    now = tree(out)
    assert {k: v for k, v in now.items() if not k.startswith("records/")} == first
    assert _io.check_result_set(out) == []
    assert not [p for p in tmp_path.iterdir() if p.name.startswith(".homlimit-")]
    r = subprocess.run(second + ["--json"], capture_output=True, text=True, timeout=600)
    assert r.returncode == 0, r.stderr
    info = json.loads(r.stdout)
    assert info["ok"] == 3 and info["resumed"] >= 1
    meta = json.loads((out / "sweep.json").read_text())
    assert meta["n_cases"] == 3 and meta["table"] == str(tmp_path / "cases.csv")
    assert _io.check_result_set(out) == []
