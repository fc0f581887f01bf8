"""Start-up time of the command line and of the library (issue 27's targets).

Each command runs ``--runs`` times in a fresh interpreter (the operating system's file cache
warm after the first); the median wall time is printed against its target:

    python -m homlimit --version     target 0.5 s  (typer, rich and the solvers are not loaded)
    python -c "import homlimit"      target 1.0 s  (the heavy packages load on first use)
    python -c "pass"                 the interpreter alone, for scale

and, when the ``homlimit`` console script is on the PATH, ``homlimit --version`` as well (an
editable install made before the entry point moved to ``homlimit.__main__:main`` still goes
through typer: reinstall). The load average is printed with the figures: on a busy machine the
times grow with it.

Run: python benchmarks/bench_startup.py [--runs 7]
"""

from __future__ import annotations

import argparse
import os
import shutil
import statistics
import subprocess
import sys
import time


def median_time(cmd: list[str], runs: int) -> float:
    """Median wall time of ``runs`` runs of ``cmd``; the command must succeed."""
    subprocess.run(cmd, check=True, capture_output=True)  # warm the file cache
    times = []
    for _ in range(runs):
        t0 = time.perf_counter()
        subprocess.run(cmd, check=True, capture_output=True)
        times.append(time.perf_counter() - t0)
    return statistics.median(times)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=7, help="runs per command (median)")
    args = parser.parse_args()
    py = sys.executable
    cases = [("python -m homlimit --version", [py, "-m", "homlimit", "--version"], 0.5),
             ('python -c "import homlimit"', [py, "-c", "import homlimit"], 1.0),
             ('python -c "pass"', [py, "-c", "pass"], None)]
    script = shutil.which("homlimit")
    if script:
        cases.insert(1, ("homlimit --version", [script, "--version"], 0.5))
    print(f"load average before: {os.getloadavg()[0]:.2f} {os.getloadavg()[1]:.2f} "
          f"{os.getloadavg()[2]:.2f} on {os.cpu_count()} cores; median of {args.runs} runs")
    missed = 0
    for label, cmd, target in cases:
        t = median_time(cmd, args.runs)
        verdict = "" if target is None else (f"  target {target:.1f} s: "
                                             + ("met" if t <= target else "MISSED"))
        missed += target is not None and t > target
        print(f"{label:32s} {t:6.3f} s{verdict}")
    la = os.getloadavg()
    print(f"load average after: {la[0]:.2f} {la[1]:.2f} {la[2]:.2f}")
    return 1 if missed else 0


if __name__ == "__main__":
    sys.exit(main())
