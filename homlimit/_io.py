"""Whole-or-nothing writing, of one file and of a whole result set.

Every writer writes a temporary file in the destination folder and renames it over the target
with ``os.replace``, so a file is either whole or absent (a crash or an error while writing
leaves the previous file, or nothing). Files get the permissions the umask gives (0644 under
umask 022), as any file a program creates. JSON is plain data: numpy scalars and arrays become
numbers and lists, non-finite floats become ``null``.

``result_set(folder)`` does the same for a folder of files: the files are written into a fresh
staging folder beside it, which replaces the folder in one rename at the end, so a reader sees
the previous set or the new one, never a mix, and no file of an earlier run survives into a
new set. It replaces only what the previous set wrote (the files its manifest lists): anything
else in the folder (another command's nested set such as ``sweep/`` or ``pulse/``, a user's
file) is carried over into the new set, and a folder holding another source's or another
command's set is refused (``check_output_folder``). A failure while writing (a full disk,
``EFBIG`` under ``ulimit -f``) raises ``errors.OutputError`` naming the file.
"""

from __future__ import annotations

import csv
import io
import json
import math
import os
import secrets
from collections.abc import Callable, Iterable, Mapping
from contextlib import contextmanager
from pathlib import Path

import numpy as np
import orjson

from ._version import package_version
from .errors import OutputError

__all__ = ["SCHEMA_VERSION", "atomic_path", "package_version", "rounded", "to_jsonable",
           "write_csv", "write_figure", "write_json", "write_output", "write_text"]


def _new_file(folder: Path, prefix: str, suffix: str) -> Path:
    """Create an empty file with a fresh random name in ``folder``, mode 0666 less the umask
    (``tempfile.mkstemp`` would make it 0600 whatever the umask)."""
    for _ in range(100):
        tmp = folder / f"{prefix}{secrets.token_hex(4)}{suffix}"
        try:
            os.close(os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o666))
            return tmp
        except FileExistsError:
            continue
    raise FileExistsError(f"no free temporary name in {folder}")  # pragma: no cover


@contextmanager
def atomic_path(path: str | Path):
    """Yield a temporary path next to ``path`` (same suffix); rename it onto ``path`` on success.

    On any exception (an interrupt included) the temporary file is removed and ``path`` is left
    untouched; an ``OSError`` of the file system (no space, file too large, permission) is
    raised as ``OutputError`` naming ``path``.
    """
    path = Path(path)
    tmp = None
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        tmp = _new_file(path.parent, f".{path.stem[:64]}.", path.suffix)
        yield tmp
        os.replace(tmp, path)
    except BaseException as exc:
        if tmp is not None and os.path.lexists(tmp):
            os.unlink(tmp)
        if isinstance(exc, OSError) and not isinstance(exc, OutputError):
            raise OutputError(f"cannot write {path}: {exc.strerror or exc}") from exc
        raise


def write_text(path: str | Path, text: str) -> Path:
    """Write ``text`` (UTF-8) to ``path`` atomically."""
    with atomic_path(path) as tmp:
        tmp.write_text(text, encoding="utf-8")
    return Path(path)


def to_jsonable(obj):
    """Plain JSON data from nested containers of numbers, numpy values, paths."""
    kind = type(obj)   # the plain types first (a record is mostly dicts and floats)
    if kind is float:
        return obj if math.isfinite(obj) else None
    if kind is str or kind is int or kind is bool or obj is None:
        return obj
    if kind is dict:
        return {str(k): to_jsonable(v) for k, v in obj.items()}
    if isinstance(obj, Mapping):
        return {str(k): to_jsonable(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [to_jsonable(v) for v in obj]
    if isinstance(obj, np.ndarray):
        return to_jsonable(obj.tolist())
    if isinstance(obj, (bool, np.bool_)):
        return bool(obj)
    if isinstance(obj, (int, np.integer)):
        return int(obj)
    if isinstance(obj, (float, np.floating)):
        x = float(obj)
        return x if math.isfinite(x) else None
    if isinstance(obj, Path):
        return str(obj)
    if obj is None or isinstance(obj, str):
        return obj
    raise TypeError(f"cannot write {type(obj).__name__} to JSON: {obj!r}")


def json_bytes(data, sort_keys: bool = False, indent: bool = False) -> bytes:
    """``data`` as UTF-8 JSON (compact, or indented by 2), NaN and ±inf as null (as
    ``write_json``), numpy values and paths as ``to_jsonable`` makes them: orjson, ~10x the
    standard library's speed (a sweep writes and reads thousands of records); the standard
    library for what orjson refuses (integers beyond 64 bits, in an invalid case's input)."""
    opt = (orjson.OPT_SERIALIZE_NUMPY | orjson.OPT_NON_STR_KEYS
           | (orjson.OPT_SORT_KEYS if sort_keys else 0) | (orjson.OPT_INDENT_2 if indent else 0))
    try:
        return orjson.dumps(data, option=opt, default=to_jsonable)
    except TypeError:
        return json.dumps(to_jsonable(data), sort_keys=sort_keys, ensure_ascii=True,
                          indent=2 if indent else None,
                          separators=(",", ": ") if indent else (",", ":")).encode("ascii")


def write_json(path: str | Path, data) -> Path:
    """Write ``data`` as indented JSON, atomically."""
    return write_text(path, json.dumps(to_jsonable(data), indent=2, ensure_ascii=False) + "\n")


def write_csv(path: str | Path, records: Iterable[Mapping], columns: list[str] | None = None
              ) -> Path:
    """Write a list of flat records as CSV with a header row, atomically."""
    records = [to_jsonable(r) for r in records]
    if columns is None:
        columns = list(dict.fromkeys(k for r in records for k in r))
    buf = io.StringIO()
    w = csv.DictWriter(buf, fieldnames=columns, extrasaction="raise", lineterminator="\n")
    w.writeheader()
    for r in records:
        w.writerow({k: ("" if r.get(k) is None else r.get(k)) for k in columns})
    return write_text(path, buf.getvalue())


def write_figure(path: str | Path, draw: Callable[[Path], None]) -> Path:
    """Run ``draw(tmp_path)`` (which saves a picture there), then rename onto ``path``."""
    with atomic_path(path) as tmp:
        draw(tmp)
    return Path(path)


# ----------------------------------------------------------------------------- result files
#: the version of the layout of homlimit's result files (JSON keys, CSV columns, the Parquet
#: metadata), written into every one by ``write_output``; raised when a layout changes in a
#: way a reader of the previous one would misread
SCHEMA_VERSION = 1
#: significant digits of a float in a result file: the 16th and 17th digits of a double are
#: noise of the arithmetic (alpha2 = 0.6000000000000001), not information
DIGITS = 15


def _round(x: float) -> float:
    return float(f"{x:.{DIGITS}g}")


def rounded(obj):
    """``to_jsonable(obj)`` with every finite float rounded to ``DIGITS`` significant digits
    (``float(f"{x:.15g}")``: 0.6000000000000001 becomes 0.6)."""
    obj = to_jsonable(obj)

    def walk(x):
        kind = type(x)
        if kind is float:
            return _round(x)
        if kind is dict:
            return {k: walk(v) for k, v in x.items()}
        if kind is list:
            return [walk(v) for v in x]
        return x

    return walk(obj)


def round_array(a) -> np.ndarray:
    """``_round`` of every element of a float array, the same doubles, 20x faster: with
    k = DIGITS − 1 − ⌊log10|x|⌋ in 0..22 (10^k exact), n = round(x·10^k) is the significand
    and n / 10^k the nearest double to it, as ``float(f"{x:.15g}")`` gives, unless x·10^k
    (exact to 0.07) lies within 0.1 of a half, or n does not have DIGITS digits: those
    values (and the tiny, huge and non-finite ones) are rounded one by one."""
    a = np.asarray(a, float)
    out = a.copy()
    idx = np.flatnonzero(np.isfinite(a) & (a != 0))
    x = a[idx]
    with np.errstate(all="ignore"):
        k = (DIGITS - 1) - np.floor(np.log10(np.abs(x)))
        ok = (k >= 0) & (k <= 22)
        scale = 10.0 ** np.where(ok, k, 0)
        y = x * scale
        n = np.round(y)
        ok &= np.abs(np.abs(y - np.trunc(y)) - 0.5) > 0.1
        ok &= (np.abs(n) >= 10.0 ** (DIGITS - 1)) & (np.abs(n) < 10.0 ** DIGITS)
        r = n / scale
    r[~ok] = [_round(v) for v in x[~ok].tolist()]
    out[idx] = r
    return out


def _rounded_table(table):
    """A pyarrow Table with its floating-point columns rounded as ``rounded`` (nulls kept)."""
    import pyarrow as pa

    cols = []
    for col in table.columns:
        if pa.types.is_floating(col.type):
            values = col.to_numpy(zero_copy_only=False)      # nulls: NaN, masked again
            col = pa.array(round_array(values), type=col.type, mask=col.is_null().to_numpy(
                zero_copy_only=False))
        cols.append(col)
    return pa.Table.from_arrays(cols, schema=table.schema)


def sidecar(path: str | Path) -> Path:
    """The JSON description of a CSV result file: ``NAME.csv.json`` beside ``NAME.csv``."""
    path = Path(path)
    return path.with_name(path.name + ".json")


def write_output(path: str | Path, data, *, units: Mapping, version: str | None = None,
                 schema: int = SCHEMA_VERSION, columns: list[str] | None = None) -> Path:
    """Write one result file with its units and schema version, atomically: THE writer of
    homlimit's JSON, CSV and Parquet outputs (``report.write`` calls it with the units of
    ``report.UNITS``). Floats in text (JSON, CSV) are rounded to ``DIGITS`` significant digits
    (``rounded``); Parquet keeps its binary doubles exact (the values of the sweep's records).

    - ``.json``: ``data`` (a mapping; a list is kept under ``"rows"``) as indented JSON, led by
      ``schema_version`` and ``homlimit_version`` and ended by ``units`` (replacing keys of
      those names in ``data``);
    - ``.csv``: ``data`` (records: flat mappings, keyed by the column headers; or a pyarrow
      Table) as CSV with one header row, and beside it ``sidecar(path)`` (``NAME.csv.json``):
      ``schema_version``, ``homlimit_version``, ``file``, ``columns`` (the headers in order)
      and ``units`` (header → unit). The CSV itself stays plain, for any CSV reader; written in
      the same result set, the two are replaced together;
    - ``.parquet``: ``data`` (a pyarrow Table), with ``units`` (JSON), ``schema_version`` and
      ``homlimit_version`` in the schema metadata.

    ``units``: the unit of each quantity ("-": dimensionless, "": text or a flag, None: none
    registered), by key (JSON, Parquet) or header (CSV); ``version``: the package's version
    (default ``package_version()``); ``columns``: the CSV columns in order (default: the
    records' keys in first-seen order).
    """
    path = Path(path)
    suffix = path.suffix.lower()
    head = {"schema_version": int(schema),
            "homlimit_version": package_version() if version is None else version}
    units = to_jsonable(dict(units))
    if suffix == ".json":
        body = rounded(data if isinstance(data, Mapping) else {"rows": data})
        body = {**head, **{k: v for k, v in body.items() if k not in (*head, "units")},
                "units": units}
        return write_text(path, json.dumps(body, indent=2, ensure_ascii=False) + "\n")
    if suffix == ".parquet":
        import pyarrow.parquet as pq

        meta = dict(data.schema.metadata or {})
        meta.update({b"units": json_bytes(units), b"schema_version": str(schema).encode(),
                     b"homlimit_version": head["homlimit_version"].encode()})
        table = data.replace_schema_metadata(meta)    # binary doubles: kept exact
        with atomic_path(path) as tmp:
            pq.write_table(table, tmp)
        return path
    if suffix == ".csv":
        if hasattr(data, "schema") and hasattr(data, "column_names"):   # a pyarrow Table
            import pyarrow.csv as pcsv

            columns = list(data.column_names)
            with atomic_path(path) as tmp:
                pcsv.write_csv(_rounded_table(data), tmp)
        else:
            records = [rounded(r) for r in data]
            if columns is None:
                columns = list(dict.fromkeys(k for r in records for k in r))
            write_csv(path, records, columns)
        write_text(sidecar(path), json.dumps(
            {**head, "file": path.name, "columns": columns,
             "units": {c: units.get(c) for c in columns}}, indent=2, ensure_ascii=False) + "\n")
        return path
    raise ValueError(f"write_output: no writer for {path.name} (allowed .json, .csv, .parquet)")


# ----------------------------------------------------------------------------- result sets
#: the manifest of a result set: what wrote it and the files it holds (written last)
MANIFEST = ".homlimit-set.json"
_DEFERRED = ("SIGINT", "SIGTERM", "SIGHUP")


@contextmanager
def _signals_deferred():
    """Hold back SIGINT, SIGTERM and SIGHUP while a swap or a clean-up must run to its end:
    their handlers are replaced by a recorder, and a signal that came is sent again on exit,
    to the handlers then in place. (Python runs signal handlers in the main thread, whichever
    thread the system delivered to, so blocking with ``pthread_sigmask`` would not do; outside
    the main thread no handler interrupts this code anyway.)"""
    import signal
    import threading

    if threading.current_thread() is not threading.main_thread():
        yield
        return
    caught: list[int] = []
    saved = {}
    for name in _DEFERRED:
        sig = getattr(signal, name, None)
        if sig is not None and signal.getsignal(sig) is not None:
            saved[sig] = signal.signal(sig, lambda signum, frame: caught.append(signum))
    try:
        yield
    finally:
        for sig, handler in saved.items():
            signal.signal(sig, handler)
        if caught:
            os.kill(os.getpid(), caught[0])


def _exchange(a: Path, b: Path) -> bool:
    """Swap two paths atomically (Linux ``renameat2(RENAME_EXCHANGE)``); False where the
    system or the file system cannot."""
    import ctypes
    import errno

    try:
        fn = ctypes.CDLL(None, use_errno=True).renameat2
    except (AttributeError, OSError):
        return False
    at_fdcwd, rename_exchange = -100, 2
    if fn(at_fdcwd, os.fsencode(a), at_fdcwd, os.fsencode(b), rename_exchange) == 0:
        return True
    err = ctypes.get_errno()
    if err in (errno.ENOSYS, errno.EINVAL, errno.ENOTSUP):
        return False
    raise OSError(err, os.strerror(err), str(b))


def _remove(path: Path):
    """Remove a file or a folder tree, ignoring what is already gone."""
    import shutil

    if path.is_dir() and not path.is_symlink():
        shutil.rmtree(path, ignore_errors=True)
    elif os.path.lexists(path):
        os.unlink(path)


def _tag(target: Path) -> str:
    """The prefix of ``target``'s staging and previous folders (short whatever its name)."""
    import hashlib

    return ".homlimit-" + hashlib.sha256(os.fsencode(target.name)).hexdigest()[:10]


def _alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    return True


def _recover(target: Path):
    """Clean what a killed run (SIGKILL, power loss) left beside ``target``: a previous set
    moved aside but not replaced is put back; what a dead process's staging folder carried
    over from ``target`` (its manifest's ``kept``) is moved back; then its staging folders
    are removed."""
    tag = _tag(target)
    dead = []
    for p in target.parent.glob(tag + "-*"):
        kind, _, rest = p.name[len(tag) + 1:].partition("-")
        pid = rest.partition("-")[0]
        if pid.isdigit() and not _alive(int(pid)):
            dead.append((kind, p))
    for kind, p in dead:           # first the previous set back in its place, then what
        if kind == "old" and not os.path.lexists(target):
            os.rename(p, target)
    for kind, p in dead:           # a staging folder had carried out of it
        if os.path.lexists(p):
            if target.is_dir() and not target.is_symlink():
                for name in _kept(p):
                    if os.path.lexists(p / name) and not os.path.lexists(target / name):
                        os.rename(p / name, target / name)
            _remove(p)


def _manifest(folder: Path) -> dict:
    """The manifest of the set in ``folder`` ({} when there is none or it cannot be read)."""
    try:
        data = json.loads((folder / MANIFEST).read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return {}
    return data if isinstance(data, dict) else {}


def _kept(folder: Path) -> list[str]:
    """The entries the set in ``folder`` carried over (its manifest's ``kept``): plain names."""
    kept = _manifest(folder).get("kept")
    return [n for n in kept if isinstance(n, str) and n and "/" not in n
            and n not in (".", "..")] if isinstance(kept, list) else []


def _staging_name(name: str) -> bool:
    """A staging or previous-set folder of a nested set (``_tag``): never part of a set."""
    return name.startswith(".homlimit-") and name != MANIFEST


def _readable_manifest(folder: Path) -> bool:
    """Does ``folder`` hold a manifest that says which files its set wrote?"""
    return isinstance(_manifest(folder).get("files"), list)


def is_result_set(folder: Path) -> bool:
    """True when ``folder`` holds a result set: its manifest, or nothing but folders that are
    result sets (``homlimit-out/B1/`` holding only ``pulse/``). A file without a manifest
    is never taken for a set's, whatever its name: nothing says a set wrote it."""
    folder = Path(folder)
    if (folder / MANIFEST).is_file():
        return True
    for p in folder.iterdir():
        if _staging_name(p.name) and p.is_dir() and not p.is_symlink():
            continue                      # a nested set's staging (a killed run's leftover)
        if p.is_symlink() or not p.is_dir() or not is_result_set(p):
            return False
    return True


def _written(folder: Path) -> set[str]:
    """The entries of ``folder`` that the set there wrote: the top-level names of the files
    its manifest lists, and the manifest; none without a readable manifest."""
    manifest = _manifest(folder)
    if isinstance(manifest.get("files"), list):
        return {MANIFEST} | {str(f).split("/")[0] for f in manifest["files"]}
    return set()


def _foreign(folder: Path) -> list[str]:
    """The entries of ``folder`` that the set there did not write (nested sets of other
    commands, a user's files): a new set carries them over."""
    if not folder.is_dir() or folder.is_symlink():
        return []
    written = _written(folder)
    return sorted(p.name for p in folder.iterdir() if p.name not in written)


def source_text(info: Mapping) -> str:
    """How a manifest's source reads in a message: the case path or ``embedded:B1``."""
    src = info.get("source")
    return "an unrecorded source" if src is None else str(src)


def same_owner(old: Mapping, new: Mapping) -> bool:
    """May a set described by ``new`` (its manifest's command and source) replace the set
    whose manifest is ``old``? Yes for the same command and the same source: the same path
    (a case file edited since counts as the same source) or the same content hash (a copy of
    the file). A set of the same command written before manifests recorded sources is
    replaced."""
    if "command" not in new:
        return True
    if old.get("command") != new.get("command"):
        return False                 # first: a sweep's records/ records no source
    if "source" not in old or old.get("source") == new.get("source"):
        return True
    digest = old.get("source_sha256")
    return digest is not None and digest == new.get("source_sha256")


def check_owner(target: str | Path, info: Mapping | None):
    """ParameterError (a one-line message with an ``--out`` hint) when ``target`` holds a
    result set of another command or another source than ``info`` describes
    (``same_owner``); nothing otherwise."""
    from .errors import ParameterError

    old = _manifest(Path(target)) if info else {}
    if not old or same_owner(old, info):
        return
    raise ParameterError(
        f"output folder = {os.fspath(target)!r} holds the result set of 'homlimit "
        f"{old.get('command')}' on {source_text(old)}: this 'homlimit {info.get('command')}' "
        f"on {source_text(info)} would replace it; give it a folder of its own with --out DIR "
        "(out= in Python), or remove that folder")


def check_output_folder(target: str | Path, names: Iterable[str] = (),
                        info: Mapping | None = None) -> Path:
    """Check that ``target`` can become a result set, before any work: its name is a path
    (no NUL byte, no component longer than the file system allows), it is not the working
    folder or one of its parents, it is a folder (or absent) that is empty or a result set
    (``is_result_set``) and writable, the nearest existing parent is a writable folder, and
    a set already there is of the command and source ``info`` names (``check_owner``), its
    manifest readable, and no file it did not write bears one of ``names`` (the files a new
    set may write). Raises ParameterError naming the folder and the reason; returns the
    path."""
    from .errors import ParameterError

    text = os.fspath(target)
    if "\x00" in text or not text.strip():
        raise ParameterError(f"output folder = {text!r} is out of range: allowed a non-empty "
                             "path without NUL bytes")
    target = Path(text)

    def bad(reason: str):
        raise ParameterError(f"output folder = {text!r} {reason}")

    absolute = Path(os.path.abspath(target))
    cwd = Path(os.getcwd())
    if absolute == cwd or absolute in cwd.parents:
        bad("is the working folder or one of its parents: a result set replaces its folder "
            "whole; give a folder of its own (e.g. --out results/NAME)")
    existing = absolute
    while not os.path.lexists(existing):
        existing = existing.parent
    try:
        name_max = os.pathconf(existing if existing.is_dir() else existing.parent, "PC_NAME_MAX")
    except (OSError, ValueError):  # pragma: no cover - no pathconf
        name_max = 255
    for part in absolute.parts:
        if len(os.fsencode(part)) > name_max:
            bad(f"has a component of {len(os.fsencode(part))} bytes: allowed at most "
                f"{name_max} bytes per folder name here")
    if target.is_symlink():
        bad("is a symbolic link: give the folder itself")
    if existing == absolute:
        if not absolute.is_dir():
            bad("is a file, not a folder")
        if not os.access(absolute, os.W_OK | os.X_OK):
            bad("is not writable")
        if (absolute / MANIFEST).is_file() and not _readable_manifest(absolute):
            bad(f"holds a {MANIFEST} that cannot be read (no list of its files), so what its "
                "set wrote is unknown and nothing there may be replaced; give a new or empty "
                "folder, or remove it")
        if any(absolute.iterdir()) and not is_result_set(absolute):
            bad(f"is a folder that holds other files (no {MANIFEST}): a result set replaces "
                "its folder whole; give a new or empty folder, or remove it")
        check_owner(target, info)
        clash = sorted(set(_foreign(target)) & set(names))
        if clash:
            bad(f"holds {clash[0]!r}, which the set there did not write and a new set may "
                "write: move it away, or give another folder with --out DIR (out= in Python)")
    elif not existing.is_dir():
        bad(f"cannot be created: {existing} is a file")
    parent = absolute.parent if existing == absolute else existing
    if not os.access(parent, os.W_OK | os.X_OK):
        bad(f"cannot be written: {parent} is not writable")
    return target


@contextmanager
def result_set(target: str | Path, *, info: Mapping | None = None,
               names: Iterable[str] = ()):
    """Write a whole set of files into the folder ``target``, replacing it in one rename.

    Yields a fresh staging folder beside ``target`` (created now, so an impossible or read-only
    output folder fails before any work: ``check_output_folder``); the caller writes its files
    there, under the names they will have in ``target``. On success the manifest
    (``MANIFEST``: ``info`` and the list of files) is written last and the staging folder
    replaces ``target`` in one atomic exchange (Linux ``renameat2``; elsewhere two renames with
    the interrupts held back in between), then the previous set is removed. Folders inside
    the previous set that are result sets themselves (another command's, e.g. ``pulse/``) are
    carried over. On any exception or interrupt the staging folder is removed and ``target``
    is left as it was. ``names``: the file names a new set may write (``check_output_folder``:
    such a file that the set there did not write is refused before any work). Files and
    folders get the modes the umask gives.
    """
    names = tuple(names)
    target = check_output_folder(target, names, info)
    created = []
    staging = None
    try:
        with _signals_deferred():
            for p in reversed(Path(os.path.abspath(target)).parents):
                if not p.exists():
                    os.mkdir(p, 0o777)
                    created.append(p)
            _recover(target)
            staging = target.parent / f"{_tag(target)}-new-{os.getpid()}-{secrets.token_hex(3)}"
            os.mkdir(staging, 0o777)
    except OSError as exc:
        for p in reversed(created):
            with _quiet_oserror():
                os.rmdir(p)
        from .errors import ParameterError

        raise ParameterError(f"output folder = {os.fspath(target)!r} cannot be created: "
                             f"{exc.strerror or exc}") from None
    def abandon():
        with _signals_deferred():
            _remove(staging)
            for p in reversed(created):
                with _quiet_oserror():
                    os.rmdir(p)

    try:
        yield staging
    except BaseException:
        abandon()
        raise
    try:
        files = sorted(str(p.relative_to(staging)) for p in staging.rglob("*")
                       if p.is_file() and not _inside_nested(p, staging))
        with _signals_deferred():
            kept = _foreign(target)
            clash = [n for n in kept if os.path.lexists(staging / n)]
            if clash:
                from .errors import ParameterError

                raise ParameterError(
                    f"output folder = {os.fspath(target)!r} holds {clash[0]!r}, which the set "
                    "there did not write and the new set would replace: move it away, or "
                    "give another folder with --out DIR (out= in Python)")
            write_json(staging / MANIFEST, {**(info or {}), "files": files,
                                            **({"kept": kept} if kept else {})})
            _swap(staging, target)
    except BaseException as exc:
        abandon()
        if isinstance(exc, OSError) and not isinstance(exc, OutputError):
            raise OutputError(f"cannot write the result set {target}: "
                              f"{exc.strerror or exc}") from exc
        raise


@contextmanager
def _quiet_oserror():
    try:
        yield
    except OSError:
        pass


def _inside_nested(path: Path, root: Path) -> bool:
    """Is ``path`` inside a folder of ``root`` that holds its own manifest?"""
    return any((q / MANIFEST).is_file() for q in path.parents
               if q != root and root in q.parents)


def _swap(staging: Path, target: Path):
    """Put ``staging`` in the place of ``target``, carrying over what the set in ``target`` did
    not write (the ``kept`` entries of the staged manifest): they are moved into ``staging``
    first, and moved back if the exchange fails (a killed process's are put back by the next
    run's ``_recover``)."""
    if not os.path.lexists(target):
        os.rename(staging, target)
        return
    moved = []
    old = None
    try:
        for name in _kept(staging):
            if os.path.lexists(target / name) and not os.path.lexists(staging / name):
                os.rename(target / name, staging / name)
                moved.append(name)
        if not _exchange(staging, target):
            old = target.parent / f"{_tag(target)}-old-{os.getpid()}-{secrets.token_hex(3)}"
            os.rename(target, old)
            try:
                os.rename(staging, target)
            except BaseException:
                os.rename(old, target)
                raise
    except BaseException:
        for name in moved:                   # the exchange did not happen: give them back
            if os.path.lexists(staging / name) and not os.path.lexists(target / name):
                os.rename(staging / name, target / name)
        raise
    _remove(staging if old is None else old)     # now the previous set


def check_result_set(folder: str | Path) -> list[str]:
    """Problems of the result set in ``folder`` (empty: complete): its manifest is missing or
    unreadable, a listed file is missing, or a file is not listed (what the set carried over,
    its manifest's ``kept`` entries, is not its own and not checked)."""
    folder = Path(folder)
    try:
        manifest = json.loads((folder / MANIFEST).read_text(encoding="utf-8"))
        listed = set(manifest["files"])
        kept = set(manifest.get("kept", ()))
    except (OSError, ValueError, KeyError, TypeError, AttributeError) as exc:
        return [f"{folder}: no readable {MANIFEST} ({exc})"]
    present = {str(p.relative_to(folder)) for p in folder.rglob("*")
               if p.is_file() and p.name != MANIFEST and not _inside_nested(p, folder)
               and p.relative_to(folder).parts[0] not in kept}
    return ([f"{folder}: {n} is listed but missing" for n in sorted(listed - present)]
            + [f"{folder}: {n} is not listed" for n in sorted(present - listed)])
