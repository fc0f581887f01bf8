"""Case files the tests build: Table 1's wall B1 in the case file's sections, a TOML writer for
them, and the command line run on one in a subprocess.

B1 (H = 9 m, L = 6 m, s = b = 0.5 m, l = 6 m; a = 0.3 m, c = 0.2 m, f = 0.6) is the paper's
Table 1 row and the embedded default case; ``b1(...)`` adds sections or keys to it.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

B1 = {"wall": {"H": 9.0, "L": 6.0, "s": 0.5, "b": 0.5, "l": 6.0},
      "masonry": {"a": 0.3, "c": 0.2, "f": 0.6}}


def b1(name: str | None = None, **sections) -> dict:
    """B1's case as a dict ``load_case`` reads: ``name`` first if given, then [wall] and
    [masonry], then ``sections`` (section → {key: value}, merged into B1's own sections, or
    a list of tables for an array such as ``tie=[{"z": 9.0, "yield_force": 2e3}]``)."""
    case = {"name": name} if name is not None else {}
    case |= {sec: dict(keys) for sec, keys in B1.items()}
    for sec, keys in sections.items():
        case[sec] = list(keys) if isinstance(keys, list) else {**case.get(sec, {}), **keys}
    return case


def _value(v) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(_value(x) for x in v) + "]"
    if isinstance(v, str):
        return json.dumps(v)
    return repr(v)


def toml(case: dict) -> str:
    """``case`` (as from ``b1``) as a case file: top-level keys, then one [section] per dict,
    then one [[array]] table per entry of a list of dicts."""
    out = [f"{k} = {_value(v)}" for k, v in case.items() if not isinstance(v, (dict, list))]
    for sec, keys in case.items():
        if isinstance(keys, dict):
            out += [f"[{sec}]"] + [f"{k} = {_value(v)}" for k, v in keys.items()]
    for sec, tables in case.items():
        if isinstance(tables, list):
            for t in tables:
                out += [f"[[{sec}]]"] + [f"{k} = {_value(v)}" for k, v in t.items()]
    return "\n".join(out) + "\n"


def run_cli(tmp_path: Path, case: dict | str, *args: str, out: str = "out"):
    """``python -m homlimit <args> case.toml --out <out>`` in ``tmp_path``, ``case`` written
    there first (a dict through ``toml``); the finished process (returncode, stdout, stderr)."""
    path = tmp_path / "case.toml"
    path.write_text(case if isinstance(case, str) else toml(case), encoding="utf-8")
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    return subprocess.run([sys.executable, "-m", "homlimit", *args, str(path), "--out",
                           str(tmp_path / out)], capture_output=True, text=True, env=env,
                          cwd=tmp_path)
