"""Time `homlimit demo` (B1, the embedded default case) stage by stage, and its bracket.

Prints the load average before the run, each stage's seconds (``Result.timings``), the whole
run's wall and CPU seconds, the peak memory, and the FE bracket (λ⁻, λ⁺, gap, the static
bound's triangles). The README's demo time comes from this script.

    python benchmarks/bench_demo.py [OUT]        (default OUT: a temporary folder)
"""

from __future__ import annotations

import os
import resource
import sys
import tempfile
import time
from pathlib import Path

from homlimit.app import pipeline


def main(out: Path) -> None:
    print(f"load average before the run: {os.getloadavg()[0]:.2f} "
          f"on {os.cpu_count()} cores", flush=True)
    w0, c0 = time.perf_counter(), time.process_time()
    res = pipeline.run(None, out=out)
    wall, cpu = time.perf_counter() - w0, time.process_time() - c0
    for stage, sec in res.timings.items():
        print(f"  {stage:<40s} {sec:8.2f} s")
    rss = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    print(f"demo: {wall:.1f} s wall, {cpu:.1f} s CPU, peak {rss:.0f} MB")
    fe = res.to_dict()["fe"]
    print(f"bracket: {fe['lower_bound']:.5f} <= lambda <= {fe['multiplier']:.5f}, gap "
          f"{100 * fe['bracket_rel_gap']:.2f} %, static on {fe['static_triangles']} triangles, "
          f"kinematic on {fe['n_triangles']}")


if __name__ == "__main__":
    if len(sys.argv) > 1:
        main(Path(sys.argv[1]))
    else:
        with tempfile.TemporaryDirectory() as tmp:
            main(Path(tmp) / "B1")
