"""Hostile input to the sweep (issue 27): every door of ``homlimit sweep`` and ``homlimit sweep
report`` refuses what it cannot use before any work, with exit 2 and a one-line reason naming
the key (or file, line and column), no traceback, and nothing written (outside the output
folder or in it); the scheduler fails fast; Ctrl-C, at start-up or mid-sweep, prints no
traceback, exits 130 and leaves a sweep that resumes with no case lost or repeated.

The sweeps here are closed-form only (C4), so each costs a second or less; the subprocess
tests (a real Ctrl-C, a killed worker) are marked slow. Every message quoted with ``doc(...)``
is in docs/sweep.md's error table (checked at the end).
"""

from __future__ import annotations

import json
import os
import signal
import socket
import subprocess
import sys
import time
import warnings
from pathlib import Path

import pytest
from typer.testing import CliRunner

from homlimit.app import cli
from homlimit.app import sweep as sweep_mod
from homlimit.app.cli import app
from homlimit.app.config import ConfigError
from homlimit.app.engine import Engine, check_scheduler
from homlimit.app.sweep import MAX_CASES, parse_grid, plan_sweep, read_table, sweep
from homlimit.errors import ParameterError

ROOT = Path(__file__).resolve().parents[1]
C4 = ROOT / "examples" / "c4-closed-form" / "case.toml"
DOCUMENTED: set[str] = set()


def doc(fragment: str) -> str:
    DOCUMENTED.add(fragment)
    return fragment


def invoke(*args) -> object:
    """The command line in this process: exit 0, 2 or 3, never a traceback."""
    res = CliRunner().invoke(app, [str(a) for a in args])
    assert res.exit_code in (0, 2, 3), (res.exit_code, res.output, res.exception)
    assert "Traceback" not in res.stderr
    return res


def refused(*args, message: str):
    """Exit 2 with ``message`` in one ``homlimit: error:`` report and nothing written."""
    res = invoke(*args)
    assert res.exit_code == 2, res.output
    err = res.stderr[res.stderr.find("homlimit: error: "):]    # after any progress line
    assert "homlimit: error: " in res.stderr and message in err, res.stderr
    return res


def files_under(root: Path) -> set[str]:
    return {str(p.relative_to(root)) for p in root.rglob("*") if p.is_file()}


@pytest.fixture
def no_planning(monkeypatch):
    """Planning a case fails the test: for checks that must come before it."""
    def boom(*a, **k):  # pragma: no cover - must never run
        raise AssertionError("planning started")

    monkeypatch.setattr(sweep_mod, "_plan", boom)


@pytest.fixture
def alarm():
    """A test that would hang (a read from a named pipe) fails after 20 s instead."""
    def ring(signum, frame):  # pragma: no cover - only on a hang
        raise AssertionError("hung for 20 s")

    old = signal.signal(signal.SIGALRM, ring)
    signal.alarm(20)
    yield
    signal.alarm(0)
    signal.signal(signal.SIGALRM, old)


def _only_inputs(sandbox: Path, *extra: str):
    """Nothing but the test's own input files under the sandbox's root."""
    assert files_under(sandbox.parents[2]) == {f"a/b/c/{name}" for name in extra}


# ----------------------------------------------------------------------------- the base
B1_LONG_INT = "[wall]\nH = 9\nL = 6\ns = 0.5\nb = 0.5\nl = 1" + "0" * 5000 + "\n"


@pytest.mark.parametrize("raw, message", [
    (bytes(range(256)) * 3, doc("base.toml: the case file is not UTF-8 text: byte 0x80 at "
                                "offset 128")),
    (b"\x00\x01\x02binary", "base.toml: not valid TOML"),
    (b"garbage = = [", "base.toml: not valid TOML: Invalid value (at line 1, column 11)"),
    (B1_LONG_INT.encode(), doc("l = 10000000...(5001 digits) at line 6: an integer of more "
                               "than 4300 digits")),
    (b"\xef\xbb\xbf" + C4.read_bytes(), "starts with a UTF-8 byte-order mark (BOM)"),
])
def test_a_bad_base_file_is_one_line_exit_2(sandbox, no_planning, raw, message):
    (sandbox / "base.toml").write_bytes(raw)
    res = refused("sweep", "base.toml", "--grid", "wall.l=3", message=message)
    assert len(res.stderr.splitlines()) == 1
    _only_inputs(sandbox, "base.toml")


def test_a_named_pipe_as_base_or_table_is_refused_not_read(sandbox, no_planning, alarm):
    os.mkfifo(sandbox / "base.toml")
    refused("sweep", "base.toml", "--grid", "wall.l=3",
            message=doc("base.toml: cannot read the case file: not a regular file"))
    os.mkfifo(sandbox / "cases.csv")
    refused("sweep", C4, "--table", "cases.csv",
            message=doc("table cases.csv: cannot read the table: not a regular file"))
    assert not (sandbox / "homlimit-out").exists()


def test_the_base_grid_and_table_problems_come_at_once(sandbox, no_planning):
    """One report for all three inputs: the base's own keys (those no grid key or table
    column replaces) checked as run checks a case, the grid's keys, the table's columns."""
    (sandbox / "base.toml").write_text("[wall]\nH = 9\nHx = 3\nl = -1\n[masonry]\na = 'x'\n"
                                       "c = 0.2\nf = 0.6\n")
    (sandbox / "cases.csv").write_text("wall.L,wall.s,wall.b,wall.q\n6,0.5,0.5,1\n")
    res = refused("sweep", "base.toml", "--grid", "wall.l=3,6", "--grid", "wall.zz=1",
                  "--table", "cases.csv", message="4 problems in the sweep's inputs")
    lines = res.stderr.splitlines()[1:]
    assert lines == [
        "  - base.toml: [wall] unknown key 'Hx': allowed H, L, s, b, l, gamma, g",
        "  - base.toml: [masonry] a = 'x' has the wrong type: expected a number",
        "  - --grid: key = 'wall.zz' is out of range: allowed name or section.key of a case "
        "file, e.g. wall.l, masonry.a, mesh.size (docs/case-file.md)",
        "  - table cases.csv: line 1: column key = 'wall.q' is out of range: allowed name or "
        "section.key of a case file, e.g. wall.l, masonry.a, mesh.size (docs/case-file.md)"]
    # wall.l = -1 is replaced by the grid and L, s, b come from the table: not problems
    assert "[wall] l" not in res.stderr and "is missing" not in res.stderr


def test_a_key_given_nowhere_is_named(sandbox, no_planning):
    (sandbox / "base.toml").write_text("[wall]\nH = 9\nL = 6\ns = 0.5\nb = 0.5\n"
                                       "[masonry]\na = 0.3\nc = 0.2\nf = 0.6\n")
    refused("sweep", "base.toml", "--grid", "masonry.f=0.4,0.6",
            message=doc("base.toml: [wall] l is missing"))


# ----------------------------------------------------------------------------- the table
@pytest.mark.parametrize("raw, message", [
    (b"wall.l,masonry.f\n3,0.5\n4\n5,0.6,7\n",
     doc("table cases.csv: 2 problems in the table")),
    (b"wall.l,masonry.f\n3,0.5\n4\n", doc("line 3 has 1 cells, the header 2: allowed one cell "
                                         "per column")),
    (b"wall.l\n3\n\x81\x82\n", doc("table cases.csv: the table is not UTF-8 text: byte 0x81 "
                                   "at offset 9 (line 3)")),
    (b"wall.l,masonry.f\n3,0.5\n4,0\x00.6\n", doc("line 3, column masonry.f: '0\\x00.6' "
                                                  "contains control characters")),
    (b"wall.l,wall.l\n3,4\n", doc("column key = 'wall.l' is given twice")),
    (b"wall.l\n1" + b"0" * 5000 + b"\n", "line 2, column wall.l: '1000000000"),
    (b"# only a comment\n", "no header and no case"),
    (b"wall.l\n", "no case: allowed a CSV with a header and at least one case"),
])
def test_a_bad_table_is_exit_2_naming_line_and_column(sandbox, no_planning, raw, message):
    (sandbox / "cases.csv").write_bytes(raw)
    refused("sweep", C4, "--table", "cases.csv", message=message)
    _only_inputs(sandbox, "cases.csv")


def test_a_spreadsheet_table_with_a_byte_order_mark_reads(tmp_path):
    (tmp_path / "t.csv").write_bytes(b"\xef\xbb\xbfwall.l,masonry.f\r\n3,0.5\r\n")
    assert read_table(tmp_path / "t.csv") == [{"wall.l": 3, "masonry.f": 0.5}]


def test_a_table_of_dicts_is_checked_too():
    with pytest.raises(ConfigError, match="table: key = 'wall.q' is out of range"):
        plan_sweep(C4, table=[{"wall.q": 1}])


# ----------------------------------------------------------------------------- the grid
@pytest.mark.parametrize("args, message", [
    (["--grid", "wall.l"], doc("--grid: 'wall.l' is out of range: allowed section.key=v1,v2,...")),
    (["--grid", "wall.l=3", "--grid", "wall.l=4"], doc("--grid: key = 'wall.l' is given twice")),
    (["--grid", "wall.l=1" + "0" * 5000], doc("an integer of 5001 digits: allowed at most "
                                              "4300")),
    (["--grid", "wall.l=[" + "[" * 2000 + "]" * 2001], "nested too deeply"),
])
def test_a_bad_grid_is_exit_2_naming_the_key(sandbox, no_planning, args, message):
    refused("sweep", C4, *args, message=message)
    assert not (sandbox / "homlimit-out").exists()


def test_grid_problems_come_at_once():
    with pytest.raises(ConfigError) as e:
        parse_grid(["wall.zz=1", "masonry.q=2", "wall.l"])
    assert len(e.value.problems) == 3


# ----------------------------------------------------------------------------- invalid points
def test_an_invalid_point_names_its_key_and_reason(sandbox):
    res = invoke("sweep", C4, "--grid", "masonry.c=0.2,4", "--grid", "wall.l=2.5",
                 "--workers", "1", "-q", "--out", "s")
    assert res.exit_code == 3, res.output
    msg = doc("failed case 1: invalid case: [masonry] c = 4.0 m is out of range: a block must "
              "fit the transversal wall, allowed 0.001 <= 2c <= L = 6 m")
    assert msg in res.stdout
    import pyarrow.parquet as pq

    rows = pq.read_table(sandbox / "s" / "results.parquet").to_pylist()
    assert [r["status"] for r in rows] == ["ok", "failed"]
    assert rows[1]["error"] == msg.removeprefix("failed case 1: ")


@pytest.mark.parametrize("value, message", [
    ("5000", doc("[mesh] part_divisions = 5000 is out of range: allowed 2 <= part_divisions "
                 "<= 1000")),
    ("1", "[mesh] part_divisions = 1 is out of range"),
    ("1" + "0" * 400, "[mesh] part_divisions = 10000000...(401 digits) is out of range"),
])
def test_extreme_part_divisions_is_named_with_its_range(sandbox, value, message):
    refused("sweep", C4, "--grid", f"mesh.part_divisions={value}", "--workers", "1",
            message=message)
    refused("run", C4, "--set", f"mesh.part_divisions={value}", message=message)
    assert not (sandbox / "homlimit-out").exists()


def test_part_divisions_over_the_budget_is_named(sandbox):
    """The whole wall fits the triangle budget; the scan's shortest part at a/1000 does not:
    the message names part_divisions, not the mesh size."""
    msg = doc("[mesh] part_divisions = 1000 gives about 3.96e+06 triangles in the shortest "
              "part of the FE impulse scan")
    refused("run", "--set", "mesh.part_divisions=1000", message=msg)
    refused("sweep", "--grid", "mesh.part_divisions=1000", "--workers", "1", message=msg)
    assert not (sandbox / "homlimit-out").exists()


# ----------------------------------------------------------------------------- max-cases
def test_a_grid_of_1e8_points_is_refused_at_once(sandbox, no_planning):
    # ``no_planning`` fails the test if a single case is planned: refused on the count alone
    values = ",".join(str(2.0 + k * 1e-4) for k in range(10_000))
    refused("sweep", C4, "--grid", f"wall.l={values}", "--grid", f"wall.H={values}",
            message=doc("the sweep has 100,000,000 cases (10,000 wall.l x 10,000 wall.H): out "
                        "of range: allowed at most max_cases (--max-cases) = 100,000"))
    assert not (sandbox / "homlimit-out").exists()


def test_max_cases_counts_table_rows_times_grid(tmp_path, no_planning):
    (tmp_path / "t.csv").write_text("masonry.f\n0.4\n0.5\n0.6\n")
    with pytest.raises(ParameterError, match=r"has 6 cases \(3 table rows x 2 wall.l\)"):
        plan_sweep(C4, {"wall.l": [3, 4]}, tmp_path / "t.csv", max_cases=5)
    with pytest.raises(ParameterError, match="max_cases = 0 is out of range"):
        plan_sweep(C4, {"wall.l": [3]}, max_cases=0)
    assert cli.MAX_CASES == MAX_CASES == 100_000


def test_max_cases_can_be_raised(sandbox):
    res = invoke("sweep", C4, "--grid", "wall.l=2.5,3,4", "--max-cases", "2", "-q")
    assert res.exit_code == 2 and "--max-cases) = 2" in res.stderr
    res = invoke("sweep", C4, "--grid", "wall.l=2.5,3,4", "--max-cases", "3", "-q",
                 "--workers", "1", "--json")
    assert res.exit_code == 0 and json.loads(res.stdout)["ok"] == 3


# ----------------------------------------------------------------------------- sweep report
@pytest.fixture(scope="module")
def finished(tmp_path_factory):
    """A finished closed-form sweep of two cases (one worker)."""
    out = tmp_path_factory.mktemp("report") / "s"
    sweep(C4, {"wall.l": [2.5, 5.0]}, out=out, workers=1, progress=False)
    return out


def _garbled(finished: Path, tmp_path: Path, name: str, cut: int | None = None,
             raw: bytes | None = None) -> Path:
    folder = tmp_path / "r"
    folder.mkdir()
    for f in ("results.parquet", "results.csv", "sweep.json"):
        data = (finished / f).read_bytes()
        if f == name:
            data = raw if raw is not None else data[:cut]
        (folder / f).write_bytes(data)
    return folder


@pytest.mark.parametrize("name, cut, raw, message", [
    ("results.parquet", 100, None, doc("results.parquet' cannot be read as Parquet")),
    ("results.parquet", None, bytes(range(256)) * 8, "cannot be read as Parquet"),
    ("sweep.json", 50, None, doc("sweep.json' is not valid JSON")),
    ("sweep.json", None, b'{"swept": 3}', doc("has no list of swept columns")),
    ("sweep.json", None, b"\xff\xfe\x00", "is not valid JSON"),
])
def test_sweep_report_refuses_a_garbled_file(finished, tmp_path, name, cut, raw, message):
    folder = _garbled(finished, tmp_path, name, cut, raw)
    res = refused("sweep", "report", folder, message=message)
    assert len(res.stderr.splitlines()) == 1
    assert not (folder / "report").exists()


@pytest.mark.parametrize("raw, message", [
    (bytes(range(256)) * 8, doc("results.csv' cannot be read as CSV")),
    (b"a,b\n1\n1,2,3\n", "Expected 2 columns, got 1"),
    (b"status,critical.vg,inputs.wall.l\nok,fast,3\nok,slow,4\n",
     doc("results column 'critical.vg' holds values that are not numbers")),
])
def test_sweep_report_refuses_a_garbled_csv(tmp_path, raw, message):
    (tmp_path / "results.csv").write_bytes(raw)
    res = refused("sweep", "report", tmp_path / "results.csv", message=message)
    assert len(res.stderr.splitlines()) == 1
    assert "\x00" not in res.stderr and not (tmp_path / "report").exists()


def test_sweep_report_refuses_a_pipe(tmp_path, alarm):
    os.mkfifo(tmp_path / "results.csv")
    refused("sweep", "report", tmp_path / "results.csv", message="is out of range")
    (tmp_path / "d").mkdir()
    (tmp_path / "d" / "results.csv").write_text("status\nok\n")
    os.mkfifo(tmp_path / "d" / "sweep.json")
    refused("sweep", "report", tmp_path / "d", message="sweep.json' is not a regular file")


# ----------------------------------------------------------------------------- the scheduler
@pytest.mark.parametrize("address, message", [
    ("not an address", doc("scheduler (--scheduler) = 'not an address' is not a scheduler "
                           "address")),
    ("http://127.0.0.1:8786", "unknown scheme 'http'"),
    ("tcp://127.0.0.1", "no port number"),
    ("tcp://127.0.0.1:99999", "no port number"),
    ("", "it is empty"),
])
def test_a_malformed_scheduler_address_is_refused_before_any_work(sandbox, no_planning,
                                                                   address, message):
    refused("sweep", C4, "--grid", "wall.l=3", "--scheduler", address, message=message)
    assert not (sandbox / "homlimit-out").exists()


def _closed_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def test_no_scheduler_at_the_address_fails_fast(sandbox):
    # a refused port is found by one TCP connection: the error is the refusal, not a timeout
    port = _closed_port()
    res = refused("sweep", C4, "--grid", "wall.l=3", "--scheduler", f"tcp://127.0.0.1:{port}",
                  message=f"scheduler (--scheduler) = 'tcp://127.0.0.1:{port}': "
                          + doc("no Dask scheduler answers there (Connection refused"))
    assert len(res.stderr.splitlines()) == 2        # "connecting to ...", the error
    assert not (sandbox / "homlimit-out").exists()
    with pytest.raises(ParameterError, match=r"answers there \(Connection refused"):
        with Engine(scheduler="tcp://127.0.0.1:1"):
            pass


def test_a_silent_server_is_given_up_within_the_timeout(monkeypatch):
    """A port that accepts connections but never speaks Dask: the handshake times out, after
    the engine's timeout (here 1 s, so the test does not wait the default's)."""
    import homlimit.app.engine as engine

    monkeypatch.setattr(engine, "SCHEDULER_TIMEOUT", 1.0)
    with socket.socket() as srv:
        srv.bind(("127.0.0.1", 0))
        srv.listen()
        with pytest.raises(ParameterError, match=r"no Dask scheduler answers there \(.*"
                                                 r"waited at most 1 s\)"):
            with Engine(scheduler=f"tcp://127.0.0.1:{srv.getsockname()[1]}"):
                pass


def test_scheduler_addresses():
    assert check_scheduler("127.0.0.1:8786") == ("tcp://127.0.0.1:8786", "127.0.0.1", 8786)
    assert check_scheduler("tls://[::1]:8786")[1:] == ("::1", 8786)
    assert check_scheduler("inproc://10.0.0.1/1/2")[1:] == (None, None)


# ----------------------------------------------------------------------------- the dashboard
def test_an_embedded_engine_serves_no_dashboard_and_leaves_8787_alone():
    """No dashboard; the scheduler's HTTP endpoint on a free port, so no warning when 8787 is
    taken (it is taken here when it was free)."""
    holder = socket.socket()
    try:
        holder.bind(("127.0.0.1", 8787))
        holder.listen()
    except OSError:          # taken already: the case under test all the same
        pass
    try:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            with Engine(workers=1, progress=False) as eng:
                services = eng.client.scheduler_info()["services"]
                assert eng.map(abs, [-1, -2]) == [1, 2]
    finally:
        holder.close()
    assert not [w for w in caught if "8787" in str(w.message)], [str(w.message) for w in caught]
    assert services.get("dashboard") != 8787


# ----------------------------------------------------------------------------- Ctrl-C
_IMPORT_INTERRUPT = r"""
import sys
import homlimit                                          # the package itself imports first


class Interrupt:                                         # Ctrl-C while cli's modules import
    def find_spec(self, name, path=None, target=None):
        if name == "homlimit.app.cli":
            raise KeyboardInterrupt
        return None


sys.meta_path.insert(0, Interrupt())
sys.argv = ["homlimit", "table1", "--help"]       # (--version alone never imports the cli)
from homlimit.__main__ import main
main()
"""


def test_ctrl_c_while_the_command_line_imports_exits_130_without_a_traceback():
    r = subprocess.run([sys.executable, "-c", _IMPORT_INTERRUPT], capture_output=True,
                       text=True, timeout=120)
    assert r.returncode == 130, r.stderr
    assert r.stderr == doc("homlimit: interrupted (SIGINT): nothing was written") + "\n"


def test_ctrl_c_in_cli_main_exits_130(monkeypatch, capsys):
    def interrupted(*a, **k):
        raise KeyboardInterrupt

    monkeypatch.setattr(cli, "app", interrupted)
    with pytest.raises(SystemExit) as e:
        cli.main()
    assert e.value.code == 130
    assert capsys.readouterr().err == "homlimit: interrupted (SIGINT): nothing was written\n"


def _group_sigint():
    """Ctrl-C at a terminal: SIGINT to the whole process group, Python's default handler."""
    os.setsid()
    signal.signal(signal.SIGINT, signal.SIG_DFL)


def _start(args: list, cwd: Path) -> subprocess.Popen:
    return subprocess.Popen([sys.executable, "-m", "homlimit", *map(str, args)], cwd=cwd,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            preexec_fn=_group_sigint)


def _records(folder: Path) -> list[Path]:
    return [f for f in (folder / "records").glob("*.json") if not f.name.startswith(".")] \
        if (folder / "records").is_dir() else []


def _wait(p: subprocess.Popen, ready, what: str, limit: float = 300):
    t0 = time.monotonic()
    while not ready():
        assert p.poll() is None, p.communicate()
        assert time.monotonic() - t0 < limit, f"no {what} after {limit} s"
        time.sleep(0.02)


def _each_key_once(folder: Path) -> dict:
    """Every record file's keys: no key stored twice (a batch or a case repeated)."""
    keys = []
    for f in _records(folder):
        data = json.loads(f.read_text())
        keys += list(data["records"]) if f.name.startswith("batch-") else [f.stem]
    assert len(keys) == len(set(keys)), "a case was recorded twice"
    return dict.fromkeys(keys)


# 40 closed-form façades with the hinge check (about 0.15 s each: 10 batches of 4 on one
# worker, a few seconds in all): a table times a grid
TABLE = "wall.H,masonry.f\n" + "".join(f"{9 + k * 0.25},{0.4 + 0.05 * (k % 5)}\n"
                                       for k in range(20))


@pytest.mark.slow
def test_ctrl_c_while_the_workers_start_prints_no_traceback(tmp_path):
    """SIGINT to the process group the moment the engine starts its workers (they are still
    importing): exit 130, one line, no worker's traceback, no Dask warning."""
    (tmp_path / "cases.csv").write_text(TABLE)
    p = _start(["sweep", C4, "--table", "cases.csv", "--grid", "wall.l=2.5,5", "--workers",
                "2", "--out", "s"], tmp_path)
    err = []

    def starting():
        line = p.stderr.readline()
        err.append(line)
        return "starting 2 local Dask workers" in line or not line

    _wait(p, starting, "engine start")
    os.killpg(p.pid, signal.SIGINT)
    out, rest = p.communicate(timeout=120)
    stderr = "".join(err) + rest
    assert p.returncode == 130, stderr
    assert "Traceback" not in stderr and "KeyboardInterrupt" not in stderr, stderr
    assert "Warning" not in stderr and "distributed" not in stderr, stderr
    assert stderr.splitlines()[-1].startswith("homlimit: interrupted"), stderr


@pytest.mark.slow
def test_ctrl_c_mid_sweep_resumes_with_no_case_lost_or_repeated(tmp_path):
    """A table-driven sweep (table × grid) stopped by SIGINT to the whole process group once
    its first batch is recorded: exit 130, no traceback from the client or the workers; the
    records kept are complete, and the rerun resumes them and runs only the rest: every case
    ok, each recorded once, the table the uninterrupted sweep's."""
    (tmp_path / "cases.csv").write_text(TABLE)
    args = [C4, "--table", "cases.csv", "--grid", "wall.l=2.5,5", "--workers", "1", "-q"]
    p = _start(["sweep", *args, "--out", "stopped"], tmp_path)
    _wait(p, lambda: _records(tmp_path / "stopped"), "record")
    os.killpg(p.pid, signal.SIGINT)
    _, err = p.communicate(timeout=120)
    assert p.returncode == 130, err
    assert "Traceback" not in err and "KeyboardInterrupt" not in err, err
    kept = _each_key_once(tmp_path / "stopped")
    assert 1 <= len(kept) < 40
    r = subprocess.run([sys.executable, "-m", "homlimit", "sweep", *map(str, args), "--out",
                        "stopped", "--json"], cwd=tmp_path, capture_output=True, text=True,
                       timeout=300)
    assert r.returncode == 0, r.stderr
    info = json.loads(r.stdout)
    assert (info["ok"], info["resumed"]) == (40, len(kept))
    assert len(_each_key_once(tmp_path / "stopped")) == 40
    whole = sweep(C4, {"wall.l": [2.5, 5]}, tmp_path / "cases.csv", tmp_path / "whole",
                  workers=1, progress=False)
    import pyarrow.parquet as pq

    def table(folder):
        return [{k: v for k, v in row.items() if not k.startswith("timings_s.")}
                for row in pq.read_table(folder / "results.parquet").to_pylist()]

    assert table(tmp_path / "stopped") == table(whole.folder)


@pytest.mark.slow
def test_a_worker_killed_mid_sweep_loses_no_case(tmp_path):
    """A table-driven sweep whose worker process is killed (SIGKILL) once the first batch is
    recorded: Dask restarts the worker and runs its lost batch again; every case ok, each
    recorded once."""
    import psutil

    (tmp_path / "cases.csv").write_text(TABLE)
    p = _start(["sweep", C4, "--table", "cases.csv", "--grid", "wall.l=2.5,5", "--workers", "1",
                "-q", "--json", "--out", "s"], tmp_path)
    _wait(p, lambda: _records(tmp_path / "s"), "record")
    workers = [c for c in psutil.Process(p.pid).children(recursive=True)
               if "spawn_main" in " ".join(c.cmdline())]
    assert len(workers) == 1
    workers[0].kill()
    out, err = p.communicate(timeout=300)
    assert p.returncode == 0, err
    assert json.loads(out)["ok"] == 40
    assert len(_each_key_once(tmp_path / "s")) == 40
    assert "Traceback" not in err


# ----------------------------------------------------------------------------- the docs
def test_the_sweep_error_table_lists_every_message():
    """docs/sweep.md's error table quotes every message these tests check."""
    import ast

    quoted = {node.args[0].value for node in ast.walk(ast.parse(Path(__file__).read_text()))
              if isinstance(node, ast.Call) and getattr(node.func, "id", "") == "doc"
              and isinstance(node.args[0], ast.Constant)}
    text = (ROOT / "docs" / "sweep.md").read_text(encoding="utf-8")
    table = text[text.index("## When a sweep goes wrong"):]
    missing = sorted(f for f in quoted if f not in table)
    assert not missing, f"docs/sweep.md's error table lacks: {missing}"
