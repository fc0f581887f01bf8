"""Interrupts and a full disk while a result set is written: the folder holds the previous set,
intact, or the new one, complete; nothing else is left beside it.

Each scenario runs the real console code (``homlimit.app.cli.main``) in a subprocess whose
writer is made to pause at one point (a driver that wraps ``homlimit._io`` functions; the
result-set and clean-up code under test is the real one): before a file, in the middle of a
file (its temporary holds half the bytes), just before the swap of the whole set, and between
the two renames of the fallback swap. The test sends SIGINT or SIGTERM once the pause is
reached. The full disk is ``ulimit -f`` (RLIMIT_FSIZE) in the child: a write past it fails with
EFBIG, since the command line ignores SIGXFSZ.
"""

from __future__ import annotations

import json
import os
import resource
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from homlimit import _io

pytestmark = pytest.mark.slow      # subprocesses, ~1 min (the in-process logic: test_result_set)

ROOT = Path(__file__).resolve().parents[1]
CASE = ROOT / "examples" / "c4-closed-form" / "case.toml"

DRIVER = r'''
import os, signal, sys, time
# a child of a background job (nohup, CI runners) inherits SIGINT ignored; Ctrl-C at a
# terminal reaches Python's default handler, which is what is tested here
signal.signal(signal.SIGINT, signal.default_int_handler)
from contextlib import contextmanager
from pathlib import Path
from homlimit import _io

kind, _, name = os.environ.get("HL_PAUSE", "").partition(":")
ready = Path(os.environ.get("HL_READY", "/nonexistent"))


def pause(seconds):
    ready.write_text(str(os.getpid()))
    time.sleep(seconds)


real_atomic, real_swap, real_rename = _io.atomic_path, _io._swap, os.rename


@contextmanager
def atomic_path(path):
    if Path(path).name == name and kind == "before":
        pause(60)
    with real_atomic(path) as tmp:
        yield tmp
        if Path(path).name == name and kind == "mid":
            data = tmp.read_bytes()
            tmp.write_bytes(data[: len(data) // 2])     # the file half written
            pause(60)


def swap(staging, target):
    pause(3)                       # interrupts are held back here: the swap completes
    real_swap(staging, target)


def rename(src, dst, *a, **k):
    real_rename(src, dst, *a, **k)
    if "-old-" in str(dst):        # the previous set moved aside, the new one not yet in
        pause(3)


_io.atomic_path = atomic_path
if kind == "swap":
    _io._swap = swap
if kind == "rename":
    _io._exchange = lambda a, b: False
    os.rename = rename

from homlimit.app.cli import main
sys.argv = ["homlimit"] + sys.argv[1:]
main()
'''


def _snapshot(folder: Path) -> dict[str, bytes]:
    return {str(p.relative_to(folder)): p.read_bytes() for p in sorted(folder.rglob("*"))
            if p.is_file()}


@pytest.fixture
def previous(tmp_path):
    """A complete previous result set in tmp_path/out (lam_points = 50) of the case file that
    the new run reads, edited since (lam_points = 200: the same source, so it is replaced)."""
    import homlimit

    old = CASE.read_text().replace("[analysis]", "[analysis]\nlam_points = 50")
    if "[analysis]" not in old:
        old += "\n[analysis]\nlam_points = 50\n"
    (tmp_path / "case.toml").write_text(old)
    homlimit.run(tmp_path / "case.toml", out=tmp_path / "out")
    (tmp_path / "case.toml").write_text(CASE.read_text())
    snap = _snapshot(tmp_path / "out")
    assert _io.check_result_set(tmp_path / "out") == [] and len(snap) == 3
    return snap


def _child(tmp_path, pause: str = "", limit: int | None = None):
    env = {**os.environ, "HL_PAUSE": pause, "HL_READY": str(tmp_path / "ready"),
           "PYTHONDONTWRITEBYTECODE": "1"}

    def preexec():
        if limit is not None:
            resource.setrlimit(resource.RLIMIT_FSIZE, (limit, limit))

    return subprocess.Popen([sys.executable, "-c", DRIVER, "run", "case.toml", "-q", "--out",
                             str(tmp_path / "out")], cwd=tmp_path, env=env,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            preexec_fn=preexec)


def _interrupt(tmp_path, pause: str, sig: int) -> tuple[int, str]:
    proc = _child(tmp_path, pause)
    t0 = time.monotonic()
    while not (tmp_path / "ready").exists():
        if proc.poll() is not None or time.monotonic() - t0 > 120:
            out, err = proc.communicate(timeout=10)
            pytest.fail(f"the pause {pause} was never reached: {proc.returncode}\n{err}")
        time.sleep(0.05)
    proc.send_signal(sig)
    _, err = proc.communicate(timeout=120)
    return proc.returncode, err


def _assert_clean(tmp_path):
    """Beside the result set: nothing (no staging folder, no temporary)."""
    assert sorted(p.name for p in tmp_path.iterdir() if p.name != "ready") == ["case.toml",
                                                                                "out"]
    assert not [p for p in (tmp_path / "out").rglob(".*") if p.name != _io.MANIFEST]


def _assert_new_and_complete(tmp_path):
    assert _io.check_result_set(tmp_path / "out") == []
    summary = json.loads((tmp_path / "out" / "summary.json").read_text())
    assert summary["inputs"]["analysis"]["lam_points"] == 200       # the new run's set
    assert sorted(summary["files"]) == ["summary_json", "vg_lambda_png"]


@pytest.mark.parametrize("sig", [signal.SIGTERM, signal.SIGINT], ids=["SIGTERM", "SIGINT"])
@pytest.mark.parametrize("pause", ["mid:vg_lambda.png", "before:summary.json",
                                   "mid:summary.json"])
def test_an_interrupt_while_writing_keeps_the_previous_set(tmp_path, previous, pause, sig):
    code, err = _interrupt(tmp_path, pause, sig)
    assert code == 128 + sig, err
    assert f"interrupted ({signal.Signals(sig).name})" in err and "Traceback" not in err
    assert _snapshot(tmp_path / "out") == previous                  # byte for byte
    _assert_clean(tmp_path)


@pytest.mark.parametrize("pause", ["swap", "rename"])
def test_an_interrupt_at_the_swap_completes_the_new_set(tmp_path, previous, pause):
    """The swap holds interrupts back: SIGTERM during it ends with the new set, complete
    (the atomic exchange, and the fallback's two renames)."""
    code, err = _interrupt(tmp_path, pause, signal.SIGTERM)
    assert code == 128 + signal.SIGTERM and "Traceback" not in err
    _assert_new_and_complete(tmp_path)
    _assert_clean(tmp_path)


@pytest.mark.parametrize("limit", [20_000, 100])
def test_a_full_disk_keeps_the_previous_set(tmp_path, previous, limit):
    """ulimit -f: vg_lambda.png (~75 kB) fails with EFBIG half written (20 kB), or the first
    file at once (100 B): exit 3, one line naming the file, the previous set intact."""
    proc = _child(tmp_path, limit=limit)
    _, err = proc.communicate(timeout=300)
    assert proc.returncode == 3, err
    assert "File too large" in err and "the previous result set, if any, is kept" in err
    assert "Traceback" not in err
    assert _snapshot(tmp_path / "out") == previous
    _assert_clean(tmp_path)


def test_without_interrupt_the_driver_writes_the_new_set(tmp_path, previous):
    """The driver itself changes nothing when no pause is asked for (a check on the check)."""
    proc = _child(tmp_path)
    _, err = proc.communicate(timeout=300)
    assert proc.returncode == 0, err
    _assert_new_and_complete(tmp_path)
    _assert_clean(tmp_path)
