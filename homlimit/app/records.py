"""The sweep's records: one JSON file per finished task, or a batch file of many, keyed by a
hash of the task's resolved inputs and the package version (``record_key``), in a folder
(``RecordStore``) whose every file is written whole or not at all, so a stop loses nothing
and a rerun resumes."""

from __future__ import annotations

import hashlib
import json
import re
from pathlib import Path

import orjson

from .._io import MANIFEST, json_bytes, to_jsonable, write_json, write_text

__all__ = ["RECORD_NAME", "RecordStore", "batch_json", "json_text", "read_json", "record_key"]


def json_text(data, indent: bool = False) -> str:
    """``data`` as JSON text (``_io.json_bytes``), ending with a newline."""
    return json_bytes(data, indent=indent).decode("utf-8") + "\n"


#: a record file's name: ``<key>.json`` or ``batch-<key>.json``
RECORD_NAME = re.compile(r"(batch-)?[0-9a-f]{20}\.json")


def record_key(kind: str, inputs, version: str | None = None) -> str:
    """The key of a record: SHA-256 (20 hex digits) of the task kind, its resolved inputs and
    the package version, as canonical JSON (sorted keys). Same inputs, same key."""
    if version is None:
        from .pipeline import package_version

        version = package_version()
    text = json_bytes({"kind": kind, "inputs": inputs, "homlimit_version": version},
                       sort_keys=True)
    return hashlib.sha256(text).hexdigest()[:20]


def batch_json(records: dict[str, dict]) -> str:
    """The text of a batch file, ``{"records": {key: record}}`` as compact JSON (NaN as null,
    as ``write_json``): a batch holds thousands of records; indented, it takes 3x as long."""
    return json_text({"records": records})


def read_json(text: str | bytes):
    """A record or batch file's data (orjson: the fast reader of what ``batch_json`` wrote;
    Python's reader for a record ``RecordStore.put(exact=True)`` wrote with NaN)."""
    try:
        return orjson.loads(text)
    except orjson.JSONDecodeError:
        return json.loads(text)


class RecordStore:
    """A folder of records: ``<key>.json`` per task, or ``batch-<key>.json`` holding
    ``{"records": {key: record}}`` for a vectorised batch. Every file is written whole or not
    at all, so whatever a stop leaves here is complete; hidden temporary files are ignored.
    The folder carries a result-set manifest (``_io.MANIFEST``, command "records"), so that a
    result set around it (``_io.result_set``) accepts it and carries it over when it is
    replaced: the records of an interrupted study stay for its resume."""

    def __init__(self, folder: str | Path):
        self.folder = Path(folder)

    def _mark(self):
        if not (self.folder / MANIFEST).is_file():
            write_json(self.folder / MANIFEST, {"command": "records", "files": []})

    def _files(self):
        """The records: ``<key>.json`` and ``batch-<key>.json`` (``record_key``'s 20 hex
        digits); nothing else in the folder is read or removed."""
        if not self.folder.is_dir():
            return []
        return sorted(p for p in self.folder.glob("*.json") if RECORD_NAME.fullmatch(p.name))

    def load(self) -> dict[str, dict]:
        """Every stored record, key → record."""
        out = {}
        for p in self._files():
            data = read_json(p.read_bytes())
            recs = data["records"] if p.name.startswith("batch-") else {p.stem: data}
            for key, rec in recs.items():   # a success recorded later wins over a failure
                if out.get(key, {}).get("status", "failed") != "ok":
                    out[key] = rec
        return out

    def put(self, key: str, record: dict, exact: bool = False) -> Path:
        """Write one record; ``exact``: NaN kept as NaN (Python's JSON reads it back), so a
        record read back equals the one computed; otherwise null, as summary.json has it."""
        self._mark()
        path = self.folder / f"{key}.json"
        if not exact:
            return write_json(path, record)
        return write_text(path, json.dumps(record, indent=1, ensure_ascii=False,
                                           default=to_jsonable) + "\n")

    def put_batch(self, records: dict[str, dict]) -> Path:
        """Write a batch of records as one file (its name: the key of its keys)."""
        return self.put_batch_json(list(records), batch_json(records))

    def put_batch_json(self, keys: list[str], text: str) -> Path:
        """Write a batch file whose text ``batch_json`` made (where the records were
        computed: a worker), holding the records of ``keys``."""
        self._mark()
        name = record_key("batch", sorted(keys), version="")
        return write_text(self.folder / f"batch-{name}.json", text)

    def clear(self):
        """Remove every record (a sweep run with resume off starts from nothing)."""
        for p in self._files():
            p.unlink()

