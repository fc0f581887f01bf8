"""Signals at the command line's exit: an interrupt leaves a table's walls running in threads
at once (nothing joins them), and ends the process without finalising the interpreter while
a solve may still run in native code; a closed stdout (``| head``) exits 141 quietly.
The subprocess variants of interrupts while files are written: test_interrupts."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import threading
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
CASE = ROOT / "examples" / "c4-closed-form" / "case.toml"


@pytest.fixture
def blocked():
    """``make(first)``: a stub scan of a wall. The first wall in the table's order (``first``)
    is interrupted (raises KeyboardInterrupt, as a Ctrl-C delivered to its waiting caller
    would) once the other wall's stub runs; that one blocks until released (``release``),
    then marks ``finished``. Whatever waits for the walls must leave at once, not after the
    blocked one (an executor's ``with`` joined it: Ctrl-C and SIGTERM waited for the whole
    scan). No signal: which thread a test runs in (pytest-xdist) does not matter. Released
    at the end, so no thread outlives the test."""
    started, release, finished = threading.Event(), threading.Event(), threading.Event()

    def make(first: str):
        def stub(wall, *args, **kwargs):
            if (wall if isinstance(wall, str) else wall["test"]) == first:
                assert started.wait(60)
                raise KeyboardInterrupt
            started.set()
            try:
                release.wait(30)    # a safety net: before the fix the caller joined this
            finally:
                finished.set()
        return stub

    try:
        yield make, finished
    finally:
        release.set()
    assert finished.wait(60)


def test_an_interrupt_abandons_the_fe_scans_of_table1(monkeypatch, blocked):
    """Engine.fe_results: the interrupt propagates while the other wall's scan still runs."""
    from homlimit.app.engine import Engine
    from homlimit.mechanism import analysis

    make, finished = blocked
    monkeypatch.setattr(analysis, "fe_result", make("B1"))
    with pytest.raises(KeyboardInterrupt):
        Engine(workers=1).fe_results(["B1", "B2"], 0.5, "bedjoints", 6)
    assert not finished.is_set()


def test_an_interrupt_abandons_the_dem_bisections_of_table1(monkeypatch, blocked):
    """table1_dem_records with a map hook: the same for the walls' DEM bisections."""
    from homlimit.app import dem_table1
    from homlimit.app.config import DemConfig

    make, finished = blocked
    first = dem_table1.table1_dem_walls(["B1", "B2"], DemConfig())[0]
    monkeypatch.setattr(dem_table1, "_wall_by_trials", make(first))
    with pytest.raises(KeyboardInterrupt):
        dem_table1.table1_dem_records(["B1", "B2"], map=lambda fn, items: [])
    assert not finished.is_set()


# a command (the mesh command's work, replaced) that starts a Clarabel solve (about 3 s) in a
# daemon thread, as a table's scan does, and is interrupted (SIGTERM) while it runs; an object
# torn down with the modules, after the interpreter has begun to finalise, waits meanwhile, so
# that the solve ends during the finalisation (in a real run: its modules' teardown)
ABANDONED = r'''
import os, signal, sys, time
import numpy as np, scipy.sparse as sp, clarabel
from homlimit import _threads
from homlimit.app import cli
from homlimit.app.commands import case


def solver(n=3000):
    A = sp.vstack([abs(sp.random(2 * n, n, density=5e-4, random_state=1, format="csc"))
                   + sp.vstack([sp.eye(n)] * 2), -sp.eye(n)]).tocsc()
    b = np.concatenate([np.ones(2 * n), np.zeros(n)])
    settings = clarabel.DefaultSettings()
    settings.verbose = False
    return clarabel.DefaultSolver(sp.csc_matrix((n, n)), -np.ones(n), A, b,
                                  [clarabel.NonnegativeConeT(3 * n)], settings)


def mesh(**kwargs):
    _threads.background(solver().solve)
    time.sleep(0.5)                         # the thread in the solve, the GIL released
    os.kill(os.getpid(), signal.SIGTERM)
    time.sleep(60)


class Late:
    def __del__(self, sleep=time.sleep, seconds=float(os.environ["HL_LATE"])):
        sleep(seconds)


case.late = Late()                          # deleted with the module
case.mesh = mesh
sys.argv = ["homlimit", "mesh"]
cli.main()
'''


def test_an_interrupt_never_finalises_with_a_solve_in_native_code(tmp_path):
    """The interrupted command exits 143 with its one line; before, the solve's thread was
    forced to exit by the finalisation as it left Clarabel, which aborted (SIGABRT, exit
    134, "FATAL: exception not rethrown")."""
    proc = subprocess.run([sys.executable, "-c", ABANDONED], cwd=tmp_path, timeout=120,
                          capture_output=True, text=True, env={**os.environ, "HL_LATE": "30"})
    assert proc.returncode == 128 + signal.SIGTERM, proc.stderr
    assert "interrupted (SIGTERM)" in proc.stderr and "FATAL" not in proc.stderr


def test_a_closed_stdout_exits_141_quietly_with_the_files_whole(tmp_path):
    """``homlimit run ... | head``: the reader gone before the table is printed: exit 141,
    nothing on stderr, the result set complete (before: exit 1)."""
    from homlimit import _io

    read, write = os.pipe()
    os.close(read)                          # no reader: the first write fails with EPIPE
    try:
        proc = subprocess.run([sys.executable, "-m", "homlimit", "run", str(CASE), "-q",
                               "-o", str(tmp_path / "out")], stdout=write,
                              stderr=subprocess.PIPE, text=True, timeout=300)
    finally:
        os.close(write)
    assert proc.returncode == 141 and proc.stderr == ""
    assert _io.check_result_set(tmp_path / "out") == []
    assert sorted(p.name for p in (tmp_path / "out").iterdir() if p.name[0] != ".") == [
        "summary.json", "vg_lambda.png"]
