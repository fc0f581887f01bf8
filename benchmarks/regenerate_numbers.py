"""Write the numbers the documentation quotes to one folder, so that a refactoring can be
checked to leave them unchanged: run it at two commits and diff the two folders.

    python benchmarks/regenerate_numbers.py OUT --quick   # seconds: table1, blocks on B1
    python benchmarks/regenerate_numbers.py OUT           # minutes: also demo, table1 --fe,
                                                          #   table1 --blocks (all 12 walls)
    diff -r OUT_before OUT_after

Each part runs the real command line (``python -m homlimit ...``) in a scratch folder and
keeps, under OUT/<part>/:
- ``stdout.txt``: the terminal output (for ``demo``, the README's "The main job" block;
  for ``table1 --fe``, docs/fe-impulse.md's FE column; for ``table1 --blocks``,
  docs/blocks.md section 6's table);
- the tables and summaries it wrote (CSV, JSON), with what changes from run to run
  removed: timings, the package version, the case source's absolute path.

Parts (``--quick`` runs the first two):
- ``table1``: ``homlimit table1`` (the closed forms beside the paper's DEM);
- ``blocks-B1``: ``homlimit run --set analysis.fe=false --set analysis.blocks=true`` (B1's
  rigid blocks beside I and II) and ``homlimit table1 --blocks -t B1``;
- ``demo``: ``homlimit demo`` (about 70 s);
- ``table1-fe``: ``homlimit table1 --fe`` (about 20 min of CPU on 2 cores);
- ``table1-blocks``: ``homlimit table1 --blocks`` (about 6 min).
"""

from __future__ import annotations

import argparse
import csv
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

#: part → the command lines it runs (arguments of ``python -m homlimit``)
PARTS: dict[str, list[list[str]]] = {
    "table1": [["table1"]],
    "blocks-B1": [["run", "--set", "analysis.fe=false", "--set", "analysis.blocks=true"],
                  ["table1", "--blocks", "-t", "B1"]],
    "demo": [["demo"]],
    "table1-fe": [["table1", "--fe"]],
    "table1-blocks": [["table1", "--blocks"]],
}
QUICK = ("table1", "blocks-B1")

#: JSON keys and CSV columns (their name before " [unit]") whose values change from run to
#: run without the numbers changing; any name containing "time" too (solve_time, times)
VOLATILE = {"timings_s", "homlimit_version", "elapsed_s", "seconds", "cpu", "cpu_s",
            "wall_s", "source", "source_sha256", "files", "manifest"}


def _volatile(name: str) -> bool:
    name = name.split(" [")[0]
    return name in VOLATILE or "time" in name
#: files worth keeping (the pictures and meshes are not compared)
KEPT = (".csv", ".json")


def _clean(data):
    """``data`` without the VOLATILE keys, at any depth."""
    if isinstance(data, dict):
        return {k: _clean(v) for k, v in data.items() if not _volatile(str(k))}
    if isinstance(data, list):
        return [_clean(v) for v in data]
    return data


def _keep(src: Path, dst: Path):
    """Copy the CSV and JSON files of the result set ``src`` to ``dst``, JSON cleaned."""
    for path in sorted(src.rglob("*")):
        if path.suffix not in KEPT or not path.is_file() or path.name.startswith("."):
            continue
        if "records" in path.relative_to(src).parts:
            continue
        target = dst / path.relative_to(src)
        target.parent.mkdir(parents=True, exist_ok=True)
        if path.suffix == ".json":
            data = _clean(json.loads(path.read_text()))
            target.write_text(json.dumps(data, indent=1, sort_keys=True) + "\n")
        else:
            with path.open(newline="") as src_f, target.open("w", newline="") as dst_f:
                rows = list(csv.reader(src_f))
                keep = [j for j, name in enumerate(rows[0] if rows else [])
                        if not _volatile(name)]
                csv.writer(dst_f, lineterminator="\n").writerows(
                    [[row[j] for j in keep if j < len(row)] for row in rows])


def run_part(name: str, out: Path, python: str) -> float:
    """Run part ``name`` in a scratch folder; its terminal output and files to out/name/."""
    dest = out / name
    if dest.exists():
        shutil.rmtree(dest)
    dest.mkdir(parents=True)
    t0 = time.perf_counter()
    with tempfile.TemporaryDirectory(prefix=f"numbers-{name}-") as scratch:
        texts = []
        for args in PARTS[name]:
            proc = subprocess.run([python, "-m", "homlimit", *args, "-q"], cwd=scratch,
                                  capture_output=True, text=True, env=os.environ)
            if proc.returncode != 0:
                raise SystemExit(f"homlimit {' '.join(args)} failed ({proc.returncode}):\n"
                                 f"{proc.stderr}")
            texts.append(f"$ homlimit {' '.join(args)}\n{proc.stdout}")
        (dest / "stdout.txt").write_text("\n".join(texts))
        _keep(Path(scratch) / "homlimit-out", dest / "files")
    return time.perf_counter() - t0


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("out", type=Path, help="folder of the numbers (its parts are replaced)")
    ap.add_argument("--quick", action="store_true",
                    help=f"only {', '.join(QUICK)} (seconds)")
    ap.add_argument("--part", action="append", choices=list(PARTS),
                    help="only this part (repeatable)")
    ap.add_argument("--python", default=sys.executable,
                    help="the interpreter that runs homlimit [default: this one]")
    args = ap.parse_args(argv)
    parts = args.part or (QUICK if args.quick else list(PARTS))
    for name in parts:
        seconds = run_part(name, args.out, args.python)
        print(f"{name}: {seconds:.1f} s -> {args.out / name}", file=sys.stderr)


if __name__ == "__main__":
    main()
