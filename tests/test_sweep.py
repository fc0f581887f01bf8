"""The sweep engine (issue 18): same numbers as single runs, a real Dask cluster, interruption.

References: ``run`` of each case alone (the sweep must reproduce it bit for bit: both records go
through JSON, whose float text round-trips exactly), the serial ``table1_records`` and
``crack_angle_study``, and a sweep left to finish uninterrupted.
"""

from __future__ import annotations

import json
import os
import signal
import socket
import subprocess
import sys
import time
from pathlib import Path

import pytest

from homlimit._io import MANIFEST, to_jsonable
from homlimit.app.config import ConfigError
from homlimit.app.engine import Engine, RecordStore, record_key
from homlimit.app.pipeline import run
from homlimit.app.sweep import batch_closed_form, flatten, parse_grid, plan_sweep, read_table, sweep
from homlimit.errors import ParameterError

ROOT = Path(__file__).resolve().parents[1]
BIN = Path(sys.executable).parent
C4 = ROOT / "examples" / "c4-closed-form" / "case.toml"
# a tiny FE case: B1 on a 0.8 m mesh with one course of 1 m (the scan's shortest part is
# 1 m tall, meshed at 1/3 m), no static bound: about 1 s
TINY_FE = {"mesh.size": 0.8, "mesh.part_divisions": 3, "masonry.a": 1.0,
           "analysis.heights": 2, "analysis.static": False}


def _single(base, overrides) -> dict:
    """The reference: ``run`` of one case alone, as its JSON record."""
    d = run(base, overrides=overrides, write=False).to_dict()
    d.pop("files")
    return json.loads(json.dumps(to_jsonable(d)))


def _strip(rec: dict) -> dict:
    return {k: v for k, v in rec.items() if k not in ("timings_s", "status")}


@pytest.fixture(scope="module")
def engine():
    with Engine(workers=2, progress=False) as eng:
        yield eng


# ----------------------------------------------------------------------------- no Dask
def test_grid_and_table_parsing(tmp_path):
    assert parse_grid(["wall.l=3,6,9", "masonry.a=0.15, 0.3", "analysis.facade=bedjoints"]) \
        == {"wall.l": [3, 6, 9], "masonry.a": [0.15, 0.3], "analysis.facade": ["bedjoints"]}
    with pytest.raises(ParameterError, match="--grid: key = 'wall.height' is out of range"):
        parse_grid(["wall.height=3"])
    with pytest.raises(ParameterError, match="--grid: 'wall.l' is out of range"):
        parse_grid(["wall.l"])
    csv = tmp_path / "t.csv"
    csv.write_text("# a comment\nname,wall.H,masonry.f\nF1,9,0.6\nF2,,0.5\n")
    assert read_table(csv) == [{"name": "F1", "wall.H": 9, "masonry.f": 0.6},
                               {"name": "F2", "masonry.f": 0.5}]
    csv.write_text("wall.Hx\n9\n")
    with pytest.raises(ParameterError, match="wall.Hx"):
        read_table(csv)


def test_plan_keys_and_invalid_cases():
    cases, _, source = plan_sweep(C4, {"wall.l": [2.5, 5.0], "masonry.c": [0.2, 4.0]})
    assert source == str(C4) and len(cases) == 4
    ok = [c for c in cases if c.config is not None]
    bad = [c for c in cases if c.config is None]
    # 2c = 8 m > L = 6 m: invalid, recorded with its error, not run
    assert len(ok) == 2 and len(bad) == 2 and "2c <= L" in bad[0].error
    assert len({c.key for c in cases}) == 4
    # the key: resolved inputs without name and [output]; same inputs, same key
    again, _, _ = plan_sweep(C4, {"wall.l": [2.5], "output.png": [False], "name": ["x"]})
    assert again[0].key == ok[0].key
    with pytest.raises(ConfigError):     # no valid case at all: bad input, before any work
        plan_sweep(C4, {"masonry.c": [4.0]})
    assert record_key("case", {"a": 1}, "1") != record_key("case", {"a": 1}, "2")


def test_closed_form_batch_equals_single_runs_bit_for_bit():
    """The vectorised path (critical λ of all cases at once) gives run()'s record exactly."""
    grid = {"wall.l": [2.5, 7.0], "masonry.f": [0.45], "wall.b": [0.25, 0.6],
            "analysis.tanpsi": [0.0, 0.5]}
    cases, _, _ = plan_sweep(C4, grid)
    recs = json.loads(json.dumps(to_jsonable(batch_closed_form([c.config for c in cases]))))
    assert len(recs) == 8
    for c, rec in zip(cases, recs):
        assert rec["status"] == "ok"
        assert _strip(rec) == _strip(_single(C4, c.overrides)), c.overrides


def test_flatten_names_columns_by_summary_paths():
    row = flatten({"a": {"b": 1, "c": [1.0, 2.0], "scan": [{"x": 1}]}, "traceback": "t"})
    assert row == {"a.b": 1, "a.c.0": 1.0, "a.c.1": 2.0}


# ----------------------------------------------------------------------------- embedded Dask
@pytest.mark.slow
def test_sweep_records_equal_single_runs(tmp_path, engine):
    """Three cases (two with the FE path, one closed-form only) through the engine: each
    record is the single-case run's, bit for bit; a rerun resumes everything."""
    table = [{**TINY_FE, "masonry.f": 0.5}, {**TINY_FE, "masonry.f": 0.7},
             {"analysis.fe": False, "masonry.f": 0.7}]
    res = sweep(None, table=table, out=tmp_path, engine=engine, progress=False)
    assert (res.n_ok, res.n_failed, res.n_resumed) == (3, 0, 0)
    stored = RecordStore(tmp_path / "records").load()
    plan, _, _ = plan_sweep(None, table=table)
    for c, ov in zip(plan, table):
        assert _strip(stored[c.key]) == _strip(_single(None, ov)), ov
    assert stored[plan[0].key]["fe"]["scan"][0]["mechanism"]
    # the table: one row per case, columns named by summary.json paths
    import pyarrow.parquet as pq

    rows = pq.read_table(tmp_path / "results.parquet").to_pylist()
    assert [r["inputs.masonry.f"] for r in rows] == [0.5, 0.7, 0.7]
    assert rows[0]["fe.multiplier"] == stored[plan[0].key]["fe"]["multiplier"]
    assert rows[2]["fe.multiplier"] is None
    assert rows[1]["critical.vg"] == stored[plan[1].key]["critical"]["vg"]
    again = sweep(None, table=table, out=tmp_path, engine=engine, progress=False)
    assert again.n_resumed == 3 and again.rows == res.rows


@pytest.mark.slow
def test_failed_cases_are_recorded_and_the_sweep_goes_on(tmp_path):
    """An invalid case and a case whose FE path fails are rows with their error; the others
    finish; the command exits 3."""
    r = subprocess.run([BIN / "homlimit", "sweep", C4, "--grid", "masonry.c=0.2,4.0",
                        "--grid", "wall.l=2.5", "--workers", "1", "--out", tmp_path / "s",
                        "--json"], capture_output=True, text=True, timeout=300)
    assert r.returncode == 3, r.stderr
    info = json.loads(r.stdout)
    assert (info["ok"], info["failed"]) == (1, 1)
    assert "2c <= L" in info["failures"][0]["error"]
    import pyarrow.parquet as pq

    rows = pq.read_table(tmp_path / "s" / "results.parquet").to_pylist()
    assert [r["status"] for r in rows] == ["ok", "failed"]


@pytest.mark.slow
def test_table1_fe_and_crack_study_through_the_engine_are_unchanged(tmp_path, engine):
    """table1 --fe (every height a task) and the crack study (every point a task) give the
    serial functions' numbers bit for bit."""
    from homlimit.app.pipeline import crack_study_records, table1_records

    kw = dict(fe=True, mesh_size=0.5, heights=2, tests=["B1"], part_divisions=3)
    assert table1_records(**kw, fe_results=engine.fe_results) == table1_records(**kw)
    grid = dict(mesh_size=0.8, finer=None, c_over_a=[1.0, 2.0], frictions=[0.6],
                facades=["homogenised"])
    serial = crack_study_records(**grid)
    store = RecordStore(tmp_path / "records")
    para = crack_study_records(**grid, map=engine.stored_map(store, "crack-study"))

    def strip(rs):  # NaN compares by its text
        return json.dumps([{k: v for k, v in r.items() if k != "solve_time"} for r in rs])

    assert strip(para) == strip(serial) and len(serial) == 2
    assert len(store.load()) == 2
    # a rerun reads the records back (nothing computed: no task would see a new key)
    again = crack_study_records(**grid, map=engine.stored_map(store, "crack-study"))
    assert json.dumps(again) == json.dumps(para)


# ----------------------------------------------------------------------------- a real cluster
def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


@pytest.fixture
def dask_cluster(tmp_path):
    """`dask scheduler` and two `dask worker` processes on 127.0.0.1, killed at the end."""
    port = _free_port()
    addr = f"tcp://127.0.0.1:{port}"
    procs = []
    logs = [open(tmp_path / f"dask{k}.log", "w") for k in range(3)]

    def stop():
        # the workers first, each gone before the next, the scheduler last: terminated
        # together, the workers lose the scheduler while closing and take 8 s (0.6 s this way)
        for p in procs[::-1]:
            if p.poll() is None:
                p.terminate()
            try:
                p.wait(timeout=20)
            except subprocess.TimeoutExpired:
                p.kill()
                p.wait()
        for f in logs:
            f.close()

    try:
        procs.append(subprocess.Popen(
            [BIN / "dask", "scheduler", "--host", "127.0.0.1", "--port", str(port),
             "--no-dashboard"], stdout=logs[0], stderr=subprocess.STDOUT))
        for k in (1, 2):
            procs.append(subprocess.Popen(
                [BIN / "dask", "worker", addr, "--host", "127.0.0.1", "--nthreads", "1",
                 "--nworkers", "1", "--no-dashboard", "--name", f"w{k}"],
                stdout=logs[k], stderr=subprocess.STDOUT))
        from distributed import Client

        with Client(addr, timeout="60s") as c:
            c.wait_for_workers(2, timeout=120)
        yield addr
    finally:
        stop()


@pytest.mark.slow
def test_sweep_on_a_running_dask_scheduler(tmp_path, dask_cluster):
    """`homlimit sweep --scheduler` on a scheduler and two workers started with the dask CLI:
    the records are the single runs' and both workers did work."""
    r = subprocess.run([BIN / "homlimit", "sweep", C4, "--grid", "wall.l=2.5,5",
                        "--grid", "masonry.f=0.4,0.8", "--scheduler", dask_cluster,
                        "--out", tmp_path / "s", "--json"],
                       capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr
    assert json.loads(r.stdout)["ok"] == 4
    stored = RecordStore(tmp_path / "s" / "records").load()
    for c in plan_sweep(C4, {"wall.l": [2.5, 5], "masonry.f": [0.4, 0.8]})[0]:
        assert _strip(stored[c.key]) == _strip(_single(C4, c.overrides))
    # FE cases too, one task each, spread over the two workers
    from distributed import get_task_stream

    with Engine(scheduler=dask_cluster, progress=False) as eng:
        assert eng.n_workers == 2
        table = [{**TINY_FE, "masonry.f": f} for f in (0.5, 0.7)]
        with get_task_stream(eng.client) as ts:
            res = sweep(None, table=table, out=tmp_path / "fe", engine=eng, progress=False)
        assert res.n_ok == 2
    assert len({t["worker"] for t in ts.data}) == 2
    first = res.rows[0]
    assert first["critical.vg"] == _single(None, table[0])["critical"]["vg"]


# ----------------------------------------------------------------------------- interruption
def _default_sigint():
    """A child of a background job (nohup, CI runners) inherits SIGINT ignored; Ctrl-C at a
    terminal reaches Python's default handler, which is what is tested here."""
    signal.signal(signal.SIGINT, signal.SIG_DFL)


def _sweep_cmd(out: Path) -> list:
    return [BIN / "homlimit", "sweep", "--table", out.parent / "cases.csv", "--workers", "1",
            "--out", out, "-q"]


@pytest.fixture(scope="module")
def interrupt_cases(tmp_path_factory):
    """Three tiny FE cases (``TINY_FE``, about 1 s each on one worker: the sweep is still
    running when the first is recorded) and their uninterrupted table."""
    d = tmp_path_factory.mktemp("interrupt")
    rows = ["mesh.size,mesh.part_divisions,masonry.a,analysis.heights,analysis.static,"
            "masonry.f"] + [f"0.8,3,1.0,2,false,{f:.2f}" for f in (0.45, 0.6, 0.75)]
    (d / "cases.csv").write_text("\n".join(rows) + "\n")
    r = subprocess.run(_sweep_cmd(d / "whole"), capture_output=True, text=True, timeout=600)
    assert r.returncode == 0, r.stderr
    return d


def _table(folder: Path) -> list[dict]:
    import pyarrow.parquet as pq

    return [{k: v for k, v in row.items() if not k.startswith("timings_s.")}
            for row in pq.read_table(folder / "results.parquet").to_pylist()]


@pytest.mark.slow
@pytest.mark.parametrize("sig", [signal.SIGINT, signal.SIGTERM])
def test_interrupted_sweep_resumes_to_the_same_table(interrupt_cases, sig):
    d = interrupt_cases
    out = d / f"stopped-{sig.name}"
    p = subprocess.Popen(_sweep_cmd(out), stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                         preexec_fn=_default_sigint,
                         text=True)
    records = out / "records"
    t0 = time.monotonic()
    # complete records: hidden names are the manifest and temporary files still being written
    done = lambda: [f for f in records.glob("*.json") if not f.name.startswith(".")]  # noqa: E731
    while not (records.is_dir() and done()):
        assert p.poll() is None, p.communicate()
        assert time.monotonic() - t0 < 300, "no record after 300 s"
        time.sleep(0.05)
    os.kill(p.pid, sig)
    _, err = p.communicate(timeout=120)
    assert p.returncode == 128 + sig, err
    assert "interrupted" in err and "resume" in err
    assert (records / MANIFEST).is_file()                        # a nested set: kept on swap
    kept = [f for f in records.iterdir() if f.name != MANIFEST]
    assert all(not f.name.startswith(".") for f in kept)        # no partial file left
    recs = [json.loads(f.read_text()) for f in kept]             # each one complete
    assert 1 <= len(recs) < 3 and all(r["status"] == "ok" for r in recs)
    assert not (out / "results.parquet").exists()
    r = subprocess.run(_sweep_cmd(out) + ["--json"], capture_output=True, text=True,
                       timeout=600)
    assert r.returncode == 0, r.stderr
    info = json.loads(r.stdout)
    assert info["resumed"] == len(recs) and info["ok"] == 3
    assert _table(out) == _table(d / "whole")


def test_stock_example_is_200_valid_facades_as_drawn():
    """examples/stock/stock.csv is what make_stock.py draws, and every façade is a valid case
    of the stock's base (so the FE mesh fits every scan)."""
    import importlib.util

    stock = ROOT / "examples" / "stock"
    spec = importlib.util.spec_from_file_location("make_stock", stock / "make_stock.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    assert read_table(stock / "stock.csv") == mod.draw()
    cases, _, _ = plan_sweep(stock / "case.toml", table=stock / "stock.csv")
    assert len(cases) == 200 and all(c.config is not None for c in cases)
    assert len({c.key for c in cases}) == 200
    H = [c.config.case.wall.H for c in cases]
    assert 6.0 <= min(H) and max(H) <= 20.0


def test_cli_bad_sweep_input_exits_2_before_any_work(tmp_path):
    from typer.testing import CliRunner

    from homlimit.app.cli import app

    r = CliRunner().invoke(app, ["sweep", str(C4), "--grid", "wall.hh=3", "--out",
                                 str(tmp_path)])
    assert r.exit_code == 2 and "--grid: key = 'wall.hh' is out of range" in r.stderr
    r = CliRunner().invoke(app, ["sweep", str(C4), "--out", str(tmp_path)])
    assert r.exit_code == 2 and "at least one --grid" in r.stderr
    r = CliRunner().invoke(app, ["sweep", str(C4), "--grid", "masonry.c=4", "--out",
                                 str(tmp_path)])
    assert r.exit_code == 2 and "2c <= L" in r.stderr         # no valid case at all
    assert not (tmp_path / "records").exists()


@pytest.mark.slow
def test_report_draws_the_standard_plots(tmp_path):
    """The plots of a closed-form sweep's table (made here without Dask) and of a table with
    FE columns: one file per standard plot."""
    from test_report import assert_png

    from homlimit.app.sweep import _rows, write_table
    from homlimit.app.sweep_report import report

    cases, _, _ = plan_sweep(C4, {"wall.l": [2.5, 5.0], "masonry.f": [0.4, 0.8]})
    recs = batch_closed_form([c.config for c in cases])
    rows = _rows(cases, {c.key: r for c, r in zip(cases, recs)})
    write_table(tmp_path, rows, ["inputs.wall.l", "inputs.masonry.f"])
    files = report(tmp_path)
    assert sorted(files) == ["critical_map_png", "vg_histogram_png", "vnorm_swept_png"]
    for f in files.values():
        assert_png(f)
    for r in rows:  # as if the FE had run: the crack plot appears
        r.update({"fe.tanpsi": 0.6, "fe.sqrt_cf_a": 0.63, "mechanisms.FE.vnorm": 0.5})
    write_table(tmp_path, rows, ["inputs.wall.l", "inputs.masonry.f"])
    assert "tanpsi_png" in report(tmp_path, tmp_path / "r2")
