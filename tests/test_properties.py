"""Property test of the command line over generated case files (hypothesis): valid ones,
invalid ones (wrong types, out of range, missing and unknown keys, hostile names) and extreme
ones (values at the ends of their ranges, huge integers, non-finite numbers, random bytes).

For every case, ``homlimit run CASE``:
- exits 0, 2 or 3, and never prints a traceback;
- writes nothing outside its output folder (the working folder is three levels down in a
  sandbox, and the names include ``../..``, absolute paths and separators);
- leaves the output folder with the previous complete result set, untouched, or a new complete
  one (``_io.check_result_set``): half the examples write into a folder that already holds a
  set of another case, recorded as made from the same case file before an edit (a set of
  another source is refused: tests/test_dataloss.py).

Closed forms only for most examples (``[analysis] fe = false``), a handful with a coarse FE
mesh in ``test_fe_cases``; both run in well under a minute.
"""

from __future__ import annotations

import json
import math
import os
import tempfile
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from typer.testing import CliRunner

from homlimit import _io
from homlimit.app.cli import app

# ----------------------------------------------------------------------------- TOML writing


def _toml_value(v) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        return "nan" if math.isnan(v) else ("inf" if v > 0 else "-inf") if math.isinf(v) \
            else repr(v)
    if isinstance(v, str):
        return json.dumps(v)        # a TOML basic string (JSON escapes are TOML escapes)
    if isinstance(v, list):
        return "[" + ", ".join(_toml_value(x) for x in v) + "]"
    raise TypeError(v)


def to_toml(case: dict) -> str:
    lines = [f"{k} = {_toml_value(v)}" for k, v in case.items() if not isinstance(v, dict)]
    for sec, keys in case.items():
        if isinstance(keys, dict):
            lines.append(f"[{sec}]")
            lines += [f"{k} = {_toml_value(v)}" for k, v in keys.items()]
    return "\n".join(lines) + "\n"


# ----------------------------------------------------------------------------- strategies
#: key → (typical range, hard range): the plausible values of a wall, and the valid ones
RANGES = {
    "wall": {"H": ((2.0, 20.0), (1e-3, 1e4)), "L": ((1.0, 10.0), (1e-3, 1e4)),
             "s": ((0.2, 1.0), (1e-3, 1e3)), "b": ((0.2, 1.0), (1e-3, 1e3)),
             "l": ((1.0, 10.0), (1e-3, 1e4)), "gamma": ((1500.0, 2500.0), (1.0, 1e5)),
             "g": ((9.7, 9.9), (1e-2, 1e3))},
    "masonry": {"a": ((0.1, 0.5), (1e-3, 1e3)), "c": ((0.1, 0.5), (1e-3, 1e3)),
                "f": ((0.3, 1.0), (1e-3, 100.0))},
}
HOSTILE = st.one_of(
    st.sampled_from([0, -1, 0.0, -0.5, 10 ** 400, -(10 ** 400), 1e308, -1e308, 5e-324,
                     True, "9", "", [1.0], 9e999]),
    st.floats(allow_nan=True, allow_infinity=True),
    st.integers(-(10 ** 30), 10 ** 30),
    st.text(max_size=5))
NAMES = st.one_of(st.sampled_from(["B1", "../../x", "..", ".", "/tmp/hl-abs", "a/b", "a\\b",
                                   "x\x00y", "ü" * 60, "x" * 150, " ", "", "-rf", "~",
                                   "$HOME", "nul\n", "CON", "a" * 100]),
                  st.text(max_size=30))


def _log_uniform(lo: float, hi: float):
    return st.floats(math.log(lo), math.log(hi)).map(math.exp)


@st.composite
def case_files(draw, fe: bool = False):
    """A plausible wall (typical ranges), or an extreme but valid one (anywhere in the hard
    ranges, log-uniform), then none, one or a few hostile changes: a value replaced by
    nonsense, a key removed, an unknown key or section, a hostile name, odd analysis keys."""
    extreme = not fe and draw(st.integers(0, 3)) == 0
    case = {}
    for sec, keys in RANGES.items():
        case[sec] = {k: draw(_log_uniform(*(hard if extreme else typical)))
                     for k, (typical, hard) in keys.items()}
    if not extreme:                                  # keep the blocks inside the wall
        case["masonry"]["a"] = min(case["masonry"]["a"], case["wall"]["H"])
        case["masonry"]["c"] = min(case["masonry"]["c"], case["wall"]["L"] / 2)
    case["analysis"] = {"fe": fe, "lam_points": draw(st.sampled_from([10, 20, 40])),
                        "closed_form": True, "tanpsi": 0.0}
    if fe:
        case["analysis"].update(heights=1, static=draw(st.booleans()))
        case["mesh"] = {"size": draw(st.sampled_from([1.5, 2.0, 3.0]))}
    case["output"] = {"png": draw(st.integers(0, 9)) == 0, "vtu": draw(st.booleans()),
                      "json": draw(st.integers(0, 9)) != 0}
    if draw(st.booleans()):
        case["name"] = draw(NAMES)
    for _ in range(draw(st.sampled_from([0, 0, 0, 0, 1] if fe else [0, 0, 0, 1, 1, 2, 4]))):
        what = draw(st.integers(0, 6))
        sec = draw(st.sampled_from(["wall", "masonry"]))
        key = draw(st.sampled_from(sorted(RANGES[sec])))
        if not isinstance(case[sec], dict):            # replaced by a later change below
            continue
        if what <= 2:
            case[sec][key] = draw(HOSTILE)
        elif what == 3:
            case[sec].pop(key, None)
        elif what == 4:
            case[sec]["unknown_key"] = 1
        elif what == 5:
            case["analysis"].update(draw(st.sampled_from([
                {"closed_form": False}, {"lam_points": 9}, {"lam_points": 10 ** 9},
                {"tanpsi": -1.0}, {"tanpsi": 1e300}, {"tanpsi": 3.0}, {"fe": "yes"},
                {"closed_form": False, "fe": False}])))
        else:
            case[draw(st.sampled_from(["oops", "wall", "mesh"]))] = draw(st.sampled_from(
                [{"x": 1}, 3, "text", {"size": -1.0}, {"size": 1e-6}]))
    return case


RAW = st.one_of(st.binary(max_size=300),
                st.text(max_size=200).map(lambda t: t.encode("utf-8", "surrogatepass")))


# ----------------------------------------------------------------------------- the property
_PREVIOUS: dict[str, dict[str, bytes]] = {}


def _previous_set() -> dict[str, bytes]:
    """A complete result set of another case (C4, closed forms), made once."""
    if not _PREVIOUS:
        import homlimit

        with tempfile.TemporaryDirectory() as tmp:
            out = Path(tmp) / "set"
            homlimit.run(Path(__file__).parents[1] / "examples" / "c4-closed-form" / "case.toml",
                         out=out)
            _PREVIOUS.update({str(p.relative_to(out)): p.read_bytes()
                              for p in out.rglob("*") if p.is_file()})
    return _PREVIOUS


def _check_run(content: bytes, use_out: bool):
    """Run ``homlimit run case.toml`` in a fresh sandbox and check the property."""
    previous = _previous_set()
    with tempfile.TemporaryDirectory() as tmp:
        root = Path(tmp)
        cwd = root / "a" / "b" / "c"
        cwd.mkdir(parents=True)
        (cwd / "case.toml").write_bytes(content)
        args = ["run", "case.toml", "-q"]
        if use_out:
            out = cwd / "out"
            out.mkdir()
            manifest = json.loads(previous[_io.MANIFEST])            # this case file's set,
            manifest["source"] = os.path.realpath(cwd / "case.toml")  # edited since
            previous = {**previous, _io.MANIFEST: json.dumps(manifest).encode()}
            for name, data in previous.items():
                (out / name).write_bytes(data)
            args += ["--out", "out"]
        old = os.getcwd()
        os.chdir(cwd)
        try:
            res = CliRunner().invoke(app, args)
        finally:
            os.chdir(old)
        assert res.exit_code in (0, 2, 3), (res.exit_code, res.output, repr(res.exception))
        assert "Traceback" not in res.output and "Traceback" not in res.stderr
        files = {p.relative_to(root) for p in root.rglob("*")}
        outside = sorted(str(p) for p in files
                         if p.parts[:3] != ("a", "b", "c") and len(p.parts) > 3
                         or (len(p.parts) <= 3 and p not in
                             {Path("a"), Path("a/b"), Path("a/b/c")}))
        assert not outside, outside
        inside = [p for p in files if len(p.parts) > 3 and p.parts[3] != "case.toml"]
        base = cwd / "out" if use_out else cwd / "homlimit-out"
        assert all((root / p).is_relative_to(base) for p in inside), inside
        if use_out:
            now = {str(p.relative_to(cwd / "out")): p.read_bytes()
                   for p in (cwd / "out").rglob("*") if p.is_file()}
            if res.exit_code == 0:
                assert _io.check_result_set(cwd / "out") == []
                assert now != previous
            else:
                assert now == previous                       # untouched, byte for byte
        elif res.exit_code == 0:
            (folder,) = (cwd / "homlimit-out").iterdir()
            assert _io.check_result_set(folder) == []
            assert not folder.name.startswith(".") and "/" not in folder.name
        else:
            assert not (cwd / "homlimit-out").exists()
        staging = [p for p in root.rglob(".homlimit-*") if p.name != _io.MANIFEST]
        assert not staging                                   # no staging folder left


SETTINGS = dict(deadline=None, derandomize=True, database=None,
                suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])


@settings(max_examples=120, **SETTINGS)
@given(case=case_files(), use_out=st.booleans())
def test_any_case_file(case, use_out):
    _check_run(to_toml(case).encode(), use_out)


@settings(max_examples=25, **SETTINGS)
@given(raw=RAW, use_out=st.booleans())
def test_any_bytes(raw, use_out):
    _check_run(raw, use_out)


@pytest.mark.slow
@settings(max_examples=6, **SETTINGS)
@given(case=case_files(fe=True), use_out=st.booleans())
def test_fe_cases(case, use_out):
    _check_run(to_toml(case).encode(), use_out)


def test_the_generator_makes_valid_cases_too():
    """A check on the check: among generated cases some are valid (exit 0), some not."""
    from hypothesis import find

    valid = find(case_files(), _ok, settings=settings(database=None, max_examples=200))
    invalid = find(case_files(), lambda c: not _ok(c), settings=settings(database=None,
                                                                        max_examples=200))
    assert valid["wall"] and invalid


def _ok(case) -> bool:
    from homlimit.app.config import ConfigError, load_case

    try:
        load_case({k: v for k, v in case.items()})
    except ConfigError:
        return False
    return True
