"""Case files: TOML (or a plain dict of the same shape) → validated parameter objects.

One section per parameter object, SI units::

    name = "B1"                    # optional; default: the file's stem
    [wall]     H L s b l gamma g   → homlimit.params.Wall
    [masonry]  a c f               → homlimit.params.Masonry
    [mesh]     size ...            → MeshConfig
    [analysis] fe facade ...       → AnalysisConfig
    [dem]      kn dt_fraction ...  → DemConfig (the rigid-block DEM, ``homlimit.dem``)
    [output]   dir png vtu report  → OutputConfig

Every problem of a case — a file that is not UTF-8 TOML, unknown section or key, wrong type,
missing required value, value out of its physically meaningful range, the cross-checks between
keys (blocks that fit the wall, a mesh that fits the wall and the problem-size budget) — is
collected and raised at once as one ``ConfigError`` (a ``ParameterError``), each line naming the
file, section, key, value and the allowed range with its unit. Valid values outside the typical
range of masonry are ``warnings`` (not errors). No numerics here beyond the budget's estimate:
nothing is computed before the whole case is valid. ``--set`` overrides that change the inputs
append a short hash of the resolved inputs to the case name (``B1-1a2b3c4d``), so a modified
case never passes for the named one. The full key reference (``docs/case-file.md``) is
generated from ``SCHEMA`` by ``schema_markdown``.

The keys live in ``app.schema``, the sections' dataclasses in ``app.sections``, the
checks of values in ``app.case_checks``; this module reads and resolves a case.
"""

from __future__ import annotations

import dataclasses
import hashlib
import tomllib
from importlib import resources
from pathlib import Path

from .._io import json_bytes
from ..check.site import Site
from ..errors import ParameterError
from ..params import Case, FacadeOpening, Floor, Masonry, Tie, Wall, WallOpening
from .accelerogram import record_problems
from .case_checks import array_key, collect, cross_checks, crushing, shown, toml_float, warnings_of
from .schema import (
    ARRAYS,
    MAX_ARRAY,
    REQUIRED_SECTIONS,
    SCHEMA,
    TOP_LEVEL,
    Key,
)
from .schema_doc import schema_markdown
from .sections import (
    SECTIONS,
    AdaptConfig,
    AnalysisConfig,
    BlocksConfig,
    CaseConfig,
    DemConfig,
    MeshConfig,
    OutputConfig,
    PulseConfig,
)

__all__ = ["AdaptConfig", "AnalysisConfig", "BlocksConfig", "CaseConfig", "ConfigError",
           "DemConfig", "Key", "MeshConfig", "OutputConfig", "PulseConfig", "SCHEMA", "TOP_LEVEL",
           "array_key", "case_data", "check_base", "check_mesh", "default_case", "load_case",
           "load_case_inputs", "read_case", "read_text", "resolved_inputs", "schema_markdown",
           "shown", "wall_inputs"]

MAX_CASE_BYTES = 1 << 20          # a case file is a few hundred bytes


class ConfigError(ParameterError):
    """A case description is invalid. ``problems`` lists every problem found, one line each."""

    def __init__(self, source: str, problems: list[str], what: str = "the case description"):
        self.source = source
        self.problems = [f"{source}: {p}" for p in problems]
        n = len(self.problems)
        head = f"{source}: {n} problem{'s' if n != 1 else ''} in {what}"
        super().__init__(head + "".join(f"\n  - {p}" for p in self.problems))

    @classmethod
    def merged(cls, errors: list[ConfigError], what: str) -> ConfigError:
        """One error listing the problems of several (each line keeps its own source)."""
        if len(errors) == 1:
            return errors[0]
        err = cls(errors[0].source, [], what)
        err.problems = [p for e in errors for p in e.problems]
        n = len(err.problems)
        err.args = (f"{n} problems in {what}" + "".join(f"\n  - {p}" for p in err.problems),)
        return err


def _parse(data: dict, source: str, default_name: str) -> CaseConfig:
    if not isinstance(data, dict):
        raise ConfigError(source, [f"the case must be a table/dict, got {type(data).__name__}"])
    problems: list[str] = []
    values = collect(data, problems)
    problems += cross_checks(values)
    if not problems:
        problems += record_problems(values, source)
    if problems:
        raise ConfigError(source, [p.strip() for p in problems])
    name = data.get("name") or default_name
    case = Case(wall=Wall(**values["wall"]), masonry=Masonry(**values["masonry"]), name=name,
                ties=tuple(Tie(**e) for e in values.get("tie", ())),
                floors=tuple(Floor(**e) for e in values.get("floor", ())),
                facade_openings=tuple(FacadeOpening(**e)
                                      for e in values.get("facade_opening", ())),
                wall_openings=tuple(WallOpening(**e) for e in values.get("wall_opening", ())))
    if bad := crushing(case, values["analysis"]):       # needs the built wall
        raise ConfigError(source, bad)
    site = Site(**values["site"], g=case.wall.g) if "site" in values else None
    return CaseConfig(case=case, source=source, warnings=warnings_of(case, values), site=site,
                      **{sec: cls(**{k: tuple(v) if isinstance(v, list) else v
                                     for k, v in values[sec].items()})
                         for sec, cls in SECTIONS.items()})


def check_mesh(config: CaseConfig):
    """The mesh checks of the whole wall (size within the wall, the triangle budget), whatever
    [analysis] says: the ``mesh`` command's. Raises ConfigError."""
    problems = cross_checks(config.as_dict(), mesh_only=True)
    if problems:
        raise ConfigError(config.source, problems)


def read_text(path: Path, what: str, max_bytes: int, fail, size_hint: str = "",
              bom: bool = False) -> str:
    """The text of a UTF-8 input file (a case file, a sweep's table), or ``fail(message)``
    naming what is wrong with it: not readable, not a regular file (a folder, a named pipe,
    a device: refused before opening, so nothing can hang), over ``max_bytes`` (``size_hint``
    says why), not UTF-8 (a byte-order mark unless ``bom``, UTF-16, binary). ``what``: the
    file's role in the messages."""
    try:
        st = path.stat()
        if not path.is_file():
            fail(f"cannot read the {what}: not a regular file")
        if st.st_size > max_bytes:
            fail(f"the {what} has {st.st_size:,} bytes: allowed at most {max_bytes:,}"
                 + (f" ({size_hint})" if size_hint else ""))
        raw = path.read_bytes()
    except OSError as e:
        fail(f"cannot read the {what}: {e.strerror or e}")
    if bom and raw.startswith(b"\xef\xbb\xbf"):   # as spreadsheets save "CSV UTF-8"
        raw = raw[3:]
    if raw.startswith(b"\xef\xbb\xbf"):
        fail(f"the {what} starts with a UTF-8 byte-order mark (BOM), which TOML does not "
             "allow: save it as UTF-8 without BOM (in many editors: 'UTF-8', not 'UTF-8 with "
             "BOM')")
    if raw.startswith((b"\xff\xfe", b"\xfe\xff")):
        fail(f"the {what} is UTF-16 (it starts with a UTF-16 byte-order mark): save it as "
             "UTF-8")
    try:
        return raw.decode("utf-8")
    except UnicodeDecodeError as e:
        line = raw[:e.start].count(b"\n") + 1
        fail(f"the {what} is not UTF-8 text: byte 0x{raw[e.start]:02x} at offset {e.start} "
             f"(line {line}) cannot be decoded; a binary file, or another encoding? Save it "
             "as UTF-8")


def read_case(path: str | Path) -> dict:
    """The TOML table of a case file; ConfigError naming what is wrong with the file
    (``read_text``; then: not TOML, an integer of more than 4300 digits, nesting too deep).
    The one reader of case files: ``load_case`` and the sweep's base use it."""
    path = Path(path)
    source = str(path)

    def fail(msg: str):
        raise ConfigError(source, [msg])

    text = read_text(path, "case file", MAX_CASE_BYTES, fail,
                     size_hint="a case file is a few hundred bytes")
    try:
        return tomllib.loads(text, parse_float=toml_float)
    except tomllib.TOMLDecodeError as e:
        fail(f"not valid TOML: {e}")
    except ValueError as e:          # e.g. an integer of more than 4300 digits
        fail(f"not valid TOML: {_long_integer(text) or e}")
    except RecursionError:
        fail("not valid TOML: arrays or tables nested too deeply")


def _long_integer(text: str) -> str | None:
    """Where a TOML text has an integer too long for Python (more than 4300 digits), named
    by its line and key, as tomllib's error does not say it; None if there is none."""
    import re

    for n, line in enumerate(text.splitlines(), 1):
        run = max(re.findall(r"\d+", line), key=len, default="")
        if len(run) > 4300:
            key = line.partition("=")[0].strip()[:40] or "a value"
            return (f"{key} = {run[:8]}...({len(run)} digits) at line {n}: an integer of "
                    "more than 4300 digits")
    return None


def case_data(path_or_dict: str | Path | dict | None = None,
              source: str | None = None) -> tuple[dict, str, str]:
    """(data, source, default name) of a case: a TOML path (``read_case``; its stem names
    the case), a dict (source ``source`` or "<dict>", name "case"), or None (the embedded B1).
    Nothing is validated here but the file itself."""
    if path_or_dict is None:
        return _default_data(), "<default: B1>", "B1"
    if isinstance(path_or_dict, dict):
        return path_or_dict, source or "<dict>", "case"
    path = Path(path_or_dict)
    return read_case(path), str(path), path.stem


def check_base(data: dict, source: str, overridden) -> None:
    """The checks of a sweep's base case (``sweep.plan_sweep``) before any case is planned:
    every problem of the keys that no grid key or table column (``overridden``: section.key
    and name) replaces, as ``load_case`` finds them (unknown section or key, wrong type, out
    of range, a required key given nowhere), at once. The checks between keys are each
    case's. Raises ConfigError."""
    if not isinstance(data, dict):
        raise ConfigError(source, [f"the case must be a table/dict, got {type(data).__name__}"])
    overridden = set(overridden)
    kept = {}
    for top, v in data.items():
        if top in SCHEMA and isinstance(v, dict):
            kept[top] = {k: x for k, x in v.items() if f"{top}.{k}" not in overridden}
        elif top in ARRAYS and isinstance(v, list):   # tie.0.yield_force given by the sweep
            kept[top] = [{k: x for k, x in e.items() if f"{top}.{n}.{k}" not in overridden}
                         if isinstance(e, dict) else e for n, e in enumerate(v)]
        elif top not in overridden:
            kept[top] = v
    problems: list[str] = []
    collect(kept, problems)
    missing = [f"{sec}.{name}" for sec in REQUIRED_SECTIONS
               for name, key in SCHEMA[sec].items() if key.required]
    problems = [p for p in problems if not _overridden_missing(p, overridden, missing)
                and not _overridden_entry(p, overridden)]
    if problems:
        raise ConfigError(source, [p.strip() for p in problems])


def _overridden_entry(problem: str, overridden: set) -> bool:
    """True for the "is missing" line of a [[tie]]/[[floor]] entry's key the sweep gives."""
    for key in overridden:
        arr, _, rest = str(key).partition(".")
        idx, _, name = rest.partition(".")
        if arr in ARRAYS and problem.startswith(f"[[{arr}]] {idx} {name} is missing"):
            return True
    return False


def _overridden_missing(problem: str, overridden: set, required: list[str]) -> bool:
    """True for ``collect``'s "is missing" line of a key (or section) that the sweep gives."""
    for key in required:
        sec, name = key.split(".")
        if key in overridden and problem.startswith(f"[{sec}] {name} is missing"):
            return True
    for sec in REQUIRED_SECTIONS:
        if problem.startswith(f"[{sec}] section is missing"):
            need = [k for k in required if k.startswith(sec + ".")]
            return all(k in overridden for k in need)
    return False


def load_case(path_or_dict: str | Path | dict | None = None,
              overrides: list[str] | dict | None = None,
              source: str | None = None) -> CaseConfig:
    """Read and validate a case: a TOML path, a dict of the same shape, or None (the default).

    ``overrides``: "section.key=value" strings (value in TOML syntax; a bare word is a string)
    or a {"section.key": value} dict, applied before validation (the CLI's ``--set``). When
    they change any input outside [output], the name gets a short hash of the resolved inputs
    (``base_name`` and ``changes`` record what changed). ``source``: where a dict came from
    (default "<dict>").
    Raises ConfigError (a ParameterError) listing every problem, before any computation.
    """
    return load_case_inputs(path_or_dict, overrides, source)[0]


def load_case_inputs(path_or_dict=None, overrides=None,
                     source: str | None = None) -> tuple[CaseConfig, dict]:
    """``load_case`` and the case's resolved inputs: ``as_dict()`` without the name and
    [output] (what the name's hash, and a sweep record's key, are made of)."""
    data, src, stem = case_data(path_or_dict, source)
    new = _override(data, overrides, src) if overrides else data
    config = _parse(new, src, stem)
    inputs = resolved_inputs(config)
    changes = _changes(data, new) if overrides else ()
    if not changes:
        return config, inputs
    digest = hashlib.sha256(json_bytes(inputs, sort_keys=True)).hexdigest()[:8]
    case = dataclasses.replace(config.case, name=f"{config.name}-{digest}")
    return dataclasses.replace(config, case=case, base_name=config.name,
                               changes=changes), inputs


def resolved_inputs(config: CaseConfig) -> dict:
    """A case's resolved inputs: ``as_dict()`` without the name and [output]."""
    return {k: v for k, v in config.as_dict().items() if k not in ("name", "output")}


def wall_inputs(inputs: dict) -> dict:
    """The part of resolved inputs (``resolved_inputs``) that makes the ``Case``: [wall],
    [masonry] and the arrays of tables (ties, floors, openings); ``load_case`` of it (with
    any sections added) gives the same wall under the name "case"."""
    return {k: v for k, v in inputs.items() if k not in SECTIONS and k != "site"}


def _changes(old: dict, new: dict) -> tuple:
    """(section.key, old value, new value) for every key outside [output] whose value the
    overrides changed (a key absent from ``old`` counts at its default)."""
    out = []
    for sec, keys in SCHEMA.items():
        if sec == "output" or not isinstance(new.get(sec), dict):
            continue
        before = old.get(sec) if isinstance(old.get(sec), dict) else {}
        for name, value in new[sec].items():
            key = keys.get(name)
            was = before.get(name, key.default if key and not key.required else None)
            if not _same(was, value):
                out.append((f"{sec}.{name}", was, value))
    for arr in ARRAYS:                # [[tie]], [[floor]]: entry by entry, key by key
        before = old.get(arr) if isinstance(old.get(arr), list) else []
        after = new.get(arr) if isinstance(new.get(arr), list) else []
        for k, entry in enumerate(after):
            was_entry = before[k] if k < len(before) and isinstance(before[k], dict) else {}
            for name, value in (entry.items() if isinstance(entry, dict) else ()):
                was = was_entry.get(name)
                if not _same(was, value):
                    out.append((f"{arr}.{k}.{name}", was, value))
    return tuple(out)


def _same(a, b) -> bool:
    if isinstance(a, list | tuple) and isinstance(b, list | tuple):
        return len(a) == len(b) and all(_same(x, y) for x, y in zip(a, b))
    if isinstance(a, bool) or isinstance(b, bool):
        return a is b
    if isinstance(a, int | float) and isinstance(b, int | float):
        return a == b
    return a == b and type(a) is type(b)


def _override(data: dict, overrides, source: str) -> dict:
    """A copy of ``data`` with "section.key=value" overrides applied (see ``load_case``)."""
    items = overrides.items() if isinstance(overrides, dict) else []
    problems = []
    if not isinstance(overrides, dict):
        parsed, seen = [], {}
        for text in overrides:
            key, sep, raw = str(text).partition("=")
            if not sep:
                problems.append(f"--set {text!r}: expected section.key=value")
                continue
            if key.strip() in seen:   # which one was meant? (never the last silently)
                problems.append(f"--set {key.strip()!r} is given twice ({seen[key.strip()]!r}, "
                                f"{text!r}): allowed once")
                continue
            seen[key.strip()] = text
            try:
                value = tomllib.loads(f"v = {raw.strip()}", parse_float=toml_float)["v"]
            except tomllib.TOMLDecodeError:
                value = raw.strip()                   # a bare word: a string
            parsed.append((key.strip(), value))
        items = parsed
    out = {k: dict(v) if isinstance(v, dict) else
           [dict(e) if isinstance(e, dict) else e for e in v] if isinstance(v, list) else v
           for k, v in data.items()}
    for key, value in items:
        sec, dot, name = key.partition(".")
        if sec in ARRAYS:             # tie.0.yield_force: entry 0 (0..n: n appends one)
            idx, dot2, entry_key = name.partition(".")
            arr = out.setdefault(sec, [])
            if (dot and dot2 and idx.isdigit() and isinstance(arr, list)
                    and int(idx) <= len(arr) and int(idx) < MAX_ARRAY):
                if int(idx) == len(arr):
                    arr.append({})
                if isinstance(arr[int(idx)], dict):
                    arr[int(idx)][entry_key] = value
                    continue
            problems.append(f"--set {key!r}: expected {sec}.<entry>.<key> with an entry "
                            f"0 .. {len(arr) if isinstance(arr, list) else 0} of [[{sec}]] "
                            f"(e.g. {sec}.0.z)")
        elif not dot and sec in TOP_LEVEL:
            out[sec] = value
        elif dot and isinstance(out.setdefault(sec, {}), dict):
            out[sec][name] = value
        else:
            problems.append(f"--set {key!r}: expected section.key (e.g. mesh.size) or name")
    if problems:
        raise ConfigError(source, problems)
    return out


def _default_data() -> dict:
    text = resources.files("homlimit").joinpath("data/default.toml").read_text(encoding="utf-8")
    return tomllib.loads(text)


def default_case() -> CaseConfig:
    """The embedded default case: Table 1's wall B1 (homlimit/data/default.toml)."""
    return _parse(_default_data(), "<default: B1>", "B1")
