"""Whole result sets (``homlimit._io.result_set``): a folder holds the previous set or the new
one, never a mix; stale files never survive; nothing is left behind on any exit path; files get
the umask's permissions; an unusable folder is refused before any work."""

from __future__ import annotations

import errno
import json
import os
import stat
from pathlib import Path

import pytest

from homlimit import _io
from homlimit.errors import OutputError, ParameterError


def _set(folder: Path, files: dict[str, str]):
    """Write ``files`` (name → text) as one result set in ``folder``."""
    with _io.result_set(folder, info={"command": "test"}) as staging:
        for name, text in files.items():
            _io.write_text(staging / name, text)


def _contents(folder: Path) -> dict[str, str]:
    return {str(p.relative_to(folder)): p.read_text() for p in sorted(folder.rglob("*"))
            if p.is_file()}


def _leftovers(parent: Path, keep: set[str]) -> list[str]:
    """Anything in ``parent`` that is not one of ``keep`` (staging folders, temporaries)."""
    return sorted(p.name for p in parent.iterdir() if p.name not in keep)


@pytest.fixture
def umask022():
    old = os.umask(0o022)
    yield
    os.umask(old)


def test_a_new_set_with_its_manifest_and_umask_modes(tmp_path, umask022):
    out = tmp_path / "deep" / "er" / "B1"
    _set(out, {"summary.json": "{}", "vg_lambda.png": "png"})
    assert _io.check_result_set(out) == []
    manifest = json.loads((out / _io.MANIFEST).read_text())
    assert manifest == {"command": "test", "files": ["summary.json", "vg_lambda.png"]}
    # the umask's modes (0644 files, 0755 folders), not mkstemp's 0600 / mkdtemp's 0700
    for p in (out / "summary.json", out / "vg_lambda.png", out / _io.MANIFEST):
        assert stat.S_IMODE(p.stat().st_mode) == 0o644, p
    assert stat.S_IMODE(out.stat().st_mode) == 0o755
    assert _leftovers(tmp_path / "deep" / "er", {"B1"}) == []


def test_umask_027_is_respected(tmp_path):
    old = os.umask(0o027)
    try:
        _io.write_text(tmp_path / "a.txt", "x")
        _set(tmp_path / "s", {"b.txt": "y"})
    finally:
        os.umask(old)
    assert stat.S_IMODE((tmp_path / "a.txt").stat().st_mode) == 0o640
    assert stat.S_IMODE((tmp_path / "s" / "b.txt").stat().st_mode) == 0o640
    assert stat.S_IMODE((tmp_path / "s").stat().st_mode) == 0o750


@pytest.mark.parametrize("exchange", [True, False], ids=["renameat2", "two-renames"])
def test_a_new_set_replaces_the_old_one_whole(tmp_path, monkeypatch, exchange):
    """A run without the FE stage leaves no mechanism.vtu of an earlier FE run behind."""
    if not exchange:
        monkeypatch.setattr(_io, "_exchange", lambda a, b: False)
    out = tmp_path / "B1"
    _set(out, {"summary.json": "old", "mechanism.vtu": "old", "fe_scan.csv": "old"})
    _set(out, {"summary.json": "new"})
    assert _contents(out) == {"summary.json": "new", _io.MANIFEST: (out / _io.MANIFEST)
                              .read_text()}
    assert _io.check_result_set(out) == []
    assert _leftovers(tmp_path, {"B1"}) == []


@pytest.mark.parametrize("error", [RuntimeError("solver died"), KeyboardInterrupt(),
                                   OSError(errno.ENOSPC, "No space left on device")],
                         ids=["error", "interrupt", "disk-full"])
def test_a_failure_while_writing_keeps_the_previous_set(tmp_path, error):
    out = tmp_path / "B1"
    _set(out, {"summary.json": "old", "vg_lambda.png": "old"})
    before = _contents(out)
    with pytest.raises((type(error), OutputError)) as info:
        with _io.result_set(out) as staging:
            _io.write_text(staging / "vg_lambda.png", "new")   # half the set written ...
            raise error                                         # ... then the failure
    if isinstance(error, OSError):
        assert isinstance(info.value, OSError)
    assert _contents(out) == before
    assert _leftovers(tmp_path, {"B1"}) == []


def test_a_writer_that_fails_mid_file_leaves_no_temporary(tmp_path):
    """EFBIG/ENOSPC inside one file's write: OutputError naming the file, no temporary."""
    def draw(tmp):
        tmp.write_bytes(b"half a picture")
        raise OSError(errno.EFBIG, "File too large")

    with pytest.raises(OutputError, match=r"cannot write .*x\.png: File too large"):
        _io.write_figure(tmp_path / "x.png", draw)
    assert list(tmp_path.iterdir()) == []


def test_a_failure_in_a_new_folder_removes_the_folders_it_made(tmp_path):
    with pytest.raises(RuntimeError):
        with _io.result_set(tmp_path / "a" / "b" / "B1"):
            raise RuntimeError("stop")
    assert list(tmp_path.iterdir()) == []


def test_unusable_folders_are_refused_before_any_work(tmp_path, monkeypatch):
    ran = []

    def attempt(target, names=()):
        with pytest.raises(ParameterError) as info:
            with _io.result_set(target, names=names):
                ran.append(target)                 # never reached
        return str(info.value)

    (tmp_path / "file").write_text("x")
    assert "is a file, not a folder" in attempt(tmp_path / "file")
    assert "cannot be created: " in attempt(tmp_path / "file" / "sub")
    (tmp_path / "mine").mkdir()
    (tmp_path / "mine" / "thesis.tex").write_text("precious")
    assert "holds other files" in attempt(tmp_path / "mine")
    assert (tmp_path / "mine" / "thesis.tex").read_text() == "precious"
    assert "NUL" in attempt(str(tmp_path / "a\x00b"))
    assert "bytes per folder name" in attempt(tmp_path / ("x" * 300))
    (tmp_path / "link").symlink_to(tmp_path / "mine")
    assert "symbolic link" in attempt(tmp_path / "link")
    monkeypatch.chdir(tmp_path / "mine")
    assert "working folder" in attempt(".")
    assert "working folder" in attempt(tmp_path)
    monkeypatch.chdir(tmp_path)
    # a read-only folder or parent (as the permission check sees it: tests may run as root)
    real = os.access
    monkeypatch.setattr(os, "access", lambda p, m: False if Path(p).name == "ro" else real(p, m))
    (tmp_path / "ro").mkdir()
    assert "is not writable" in attempt(tmp_path / "ro")
    assert "is not writable" in attempt(tmp_path / "ro" / "B1")
    assert ran == []


@pytest.mark.skipif(os.geteuid() == 0, reason="root writes into read-only folders")
def test_a_really_read_only_parent_is_refused(tmp_path):
    ro = tmp_path / "ro"
    ro.mkdir()
    ro.chmod(0o555)
    try:
        with pytest.raises(ParameterError, match="is not writable"):
            with _io.result_set(ro / "B1"):
                pass
    finally:
        ro.chmod(0o755)


def test_nested_sets_of_other_commands_are_carried_over(tmp_path):
    """homlimit-out/B1/pulse/ (the pulse command's set) survives a new run's set in B1/."""
    out = tmp_path / "B1"
    _set(out / "pulse", {"spectra.csv": "pulse"})
    _set(out, {"summary.json": "run 1", "mechanism.vtu": "run 1"})   # parent made by pulse
    _set(out, {"summary.json": "run 2"})
    assert _contents(out / "pulse")["spectra.csv"] == "pulse"
    assert (out / "summary.json").read_text() == "run 2" and not (out / "mechanism.vtu").exists()
    assert _io.check_result_set(out) == [] and _io.check_result_set(out / "pulse") == []


def test_files_without_a_manifest_are_never_taken_for_a_set(tmp_path):
    """A folder of files with homlimit's names but no manifest (the user's own results.csv, a
    set copied with ``cp dir/*``, which drops the dot-file) is refused before any work, and
    nothing in it is touched; a folder holding nothing but nested sets is accepted."""
    out = tmp_path / "mine"
    out.mkdir()
    (out / "results.csv").write_text("my,own,data")
    (out / "summary.json").write_text("mine too")
    before = _contents(out)
    with pytest.raises(ParameterError, match="holds other files"):
        with _io.result_set(out, names=("summary.json", "results.csv")):
            pytest.fail("the work started")
    assert _contents(out) == before
    nested = tmp_path / "B1"
    _set(nested / "pulse", {"spectra.csv": "pulse"})
    _set(nested, {"summary.json": "run"})
    assert _contents(nested / "pulse")["spectra.csv"] == "pulse"


def test_an_unreadable_manifest_is_refused_before_any_work(tmp_path):
    """A truncated manifest cannot say which files its set wrote: nothing may be replaced."""
    out = tmp_path / "sweep"
    _set(out, {"results.csv": "the sweep's", "sweep.json": "{}"})
    (out / _io.MANIFEST).write_text("{")
    before = _contents(out)
    with pytest.raises(ParameterError, match="cannot be read"):
        with _io.result_set(out, info={"command": "run"}, names=("summary.json",)):
            pytest.fail("the work started")
    assert _contents(out) == before


def test_a_file_the_set_did_not_write_with_a_name_it_may_write_is_refused_first(tmp_path):
    """Before any work, not after it: the user's fe_scan.csv in a run's folder."""
    out = tmp_path / "B1"
    _set(out, {"summary.json": "run 1"})
    (out / "fe_scan.csv").write_text("the user's")
    with pytest.raises(ParameterError, match="holds 'fe_scan.csv', which the set there did "
                                             "not write and a new set may write.*--out"):
        with _io.result_set(out, info={"command": "test"}, names=("fe_scan.csv",)):
            pytest.fail("the work started")
    assert (out / "fe_scan.csv").read_text() == "the user's"


def test_what_a_killed_run_left_is_cleaned_by_the_next(tmp_path):
    """SIGKILL leaves a staging folder (or, between two renames, the previous set moved
    aside): the next run removes the first and puts the second back."""
    out = tmp_path / "B1"
    _set(out, {"summary.json": "old"})
    dead = 2 ** 22 + 12345                     # beyond pid_max: no such process
    tag = _io._tag(out)
    (tmp_path / f"{tag}-new-{dead}-abc").mkdir()
    os.rename(out, tmp_path / f"{tag}-old-{dead}-abc")     # killed between the renames
    with _io.result_set(out) as staging:
        assert (out / "summary.json").read_text() == "old"  # restored before the new run
        _io.write_text(staging / "summary.json", "new")
    assert (out / "summary.json").read_text() == "new"
    assert _leftovers(tmp_path, {"B1"}) == []


def test_check_result_set_finds_a_mix(tmp_path):
    out = tmp_path / "B1"
    _set(out, {"summary.json": "a", "vg_lambda.png": "b"})
    (out / "vg_lambda.png").unlink()
    (out / "mechanism.vtu").write_text("stale")
    assert _io.check_result_set(out) == [f"{out}: vg_lambda.png is listed but missing",
                                         f"{out}: mechanism.vtu is not listed"]
    assert "no readable" in _io.check_result_set(tmp_path)[0]


# ------------------------------------------------------------------ what it did not write
@pytest.mark.parametrize("exchange", [True, False], ids=["renameat2", "two-renames"])
def test_what_the_previous_set_did_not_write_is_kept(tmp_path, monkeypatch, exchange):
    """A sweep stored in the run's folder (no manifest of its own: an interrupted first sweep)
    and a user's file survive a new set; the files the previous set wrote do not."""
    if not exchange:
        monkeypatch.setattr(_io, "_exchange", lambda a, b: False)
    out = tmp_path / "B1"
    _set(out, {"summary.json": "run 1", "mechanism.vtu": "run 1"})
    (out / "sweep" / "records").mkdir(parents=True)
    (out / "sweep" / "records" / "k.json").write_text("record")
    (out / "notes.txt").write_text("mine")
    _set(out, {"summary.json": "run 2"})
    assert _contents(out) == {"summary.json": "run 2", "notes.txt": "mine",
                              "sweep/records/k.json": "record",
                              _io.MANIFEST: (out / _io.MANIFEST).read_text()}
    assert json.loads((out / _io.MANIFEST).read_text())["kept"] == ["notes.txt", "sweep"]
    assert _io.check_result_set(out) == []
    _set(out, {"summary.json": "run 3"})                    # kept again, not adopted
    assert (out / "notes.txt").read_text() == "mine" and (out / "sweep").is_dir()
    assert _leftovers(tmp_path, {"B1"}) == []


def test_a_new_file_over_one_it_did_not_write_is_refused(tmp_path):
    out = tmp_path / "B1"
    _set(out, {"summary.json": "run 1"})
    (out / "fe_scan.csv").write_text("the user's")
    before = _contents(out)
    with pytest.raises(ParameterError, match="holds 'fe_scan.csv', which the set there did "
                                             "not write.*--out"):
        _set(out, {"summary.json": "run 2", "fe_scan.csv": "new"})
    assert _contents(out) == before
    assert _leftovers(tmp_path, {"B1"}) == []


def test_a_failed_exchange_gives_back_what_it_carried(tmp_path, monkeypatch):
    out = tmp_path / "B1"
    _set(out, {"summary.json": "run 1"})
    _set(out / "sweep", {"sweep.json": "sweep"})
    before = _contents(out)

    def fail(a, b):
        raise OSError(errno.EIO, "Input/output error")

    monkeypatch.setattr(_io, "_exchange", fail)
    with pytest.raises(OutputError, match="Input/output error"):
        _set(out, {"summary.json": "run 2"})
    assert _contents(out) == before
    assert _leftovers(tmp_path, {"B1"}) == []


def test_what_a_killed_swap_had_carried_is_put_back(tmp_path):
    """SIGKILL after sweep/ was moved into the staging folder, before the exchange: the next
    run moves it back (the dead staging folder's manifest lists it as kept)."""
    out = tmp_path / "B1"
    _set(out, {"summary.json": "old"})
    _set(out / "sweep", {"sweep.json": "sweep"})
    dead = tmp_path / f"{_io._tag(out)}-new-{2 ** 22 + 12345}-abc"
    dead.mkdir()
    _io.write_text(dead / "summary.json", "new, never swapped in")
    _io.write_json(dead / _io.MANIFEST, {"command": "test", "files": ["summary.json"],
                                         "kept": ["sweep"]})
    os.rename(out / "sweep", dead / "sweep")
    _set(out, {"summary.json": "next"})
    assert _contents(out / "sweep")["sweep.json"] == "sweep"
    assert (out / "summary.json").read_text() == "next"
    assert _leftovers(tmp_path, {"B1"}) == []


# ----------------------------------------------------------------------------- whose set
def _owned(folder: Path, command: str, source: str, digest: str | None, text: str = "x"):
    with _io.result_set(folder, info={"command": command, "source": source,
                                      "source_sha256": digest}) as staging:
        _io.write_text(staging / "summary.json", text)


def test_another_source_or_command_is_refused_before_any_work(tmp_path):
    out = tmp_path / "B1"
    _owned(out, "demo", "embedded:B1", None)
    _set(out / "sweep", {"sweep.json": "sweep"})
    before = _contents(out)
    for command, source, digest in (("run", "/x/b1.toml", "aa"), ("run", "embedded:B1", None),
                                    ("pulse", "embedded:B1", None)):
        with pytest.raises(ParameterError) as info:
            with _io.result_set(out, info={"command": command, "source": source,
                                           "source_sha256": digest}):
                pytest.fail("the work started")
        msg = str(info.value)
        assert "\n" not in msg and "--out DIR" in msg and "'homlimit demo' on embedded:B1" \
            in msg and f"'homlimit {command}' on {source}" in msg, msg
    assert _contents(out) == before and _leftovers(tmp_path, {"B1"}) == []
    _owned(out, "demo", "embedded:B1", None, "again")        # the same: replaced as before
    assert (out / "summary.json").read_text() == "again" and (out / "sweep").is_dir()


def test_the_same_case_file_edited_or_copied_is_the_same_source(tmp_path):
    out = tmp_path / "C4"
    _owned(out, "run", "/cases/c4.toml", "h1")
    _owned(out, "run", "/cases/c4.toml", "h2", "edited")      # same path, new content
    _owned(out, "run", "/copy/c4.toml", "h2", "copied")       # same content, other path
    assert (out / "summary.json").read_text() == "copied"
    with pytest.raises(ParameterError, match="'homlimit run' on /copy/c4.toml"):
        _owned(out, "run", "/other/c4.toml", "h3")
    # a set of the same command written before manifests recorded sources: replaced
    with _io.result_set(tmp_path / "legacy", info={"command": "run"}) as staging:
        _io.write_text(staging / "summary.json", "old")
    _owned(tmp_path / "legacy", "run", "/cases/c4.toml", "h1", "new")
    assert (tmp_path / "legacy" / "summary.json").read_text() == "new"


def test_a_sweeps_records_folder_takes_no_other_set(tmp_path):
    """records/ (command "records", no source) is no place for a run's set, and clearing it
    removes the records alone."""
    from homlimit.app.records import RecordStore, record_key

    store = RecordStore(tmp_path / "records")
    key = record_key("case", {"x": 1}, version="0")
    store.put(key, {"status": "ok"})
    with pytest.raises(ParameterError, match="'homlimit records'"):
        _owned(tmp_path / "records", "run", "/cases/c4.toml", "h1")
    (tmp_path / "records" / "notes.json").write_text("mine")
    store.clear()
    assert sorted(p.name for p in (tmp_path / "records").iterdir()) == [_io.MANIFEST,
                                                                         "notes.json"]
