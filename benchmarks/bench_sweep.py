"""The sweep engine's speed (issue 18): prints its figures, asserts nothing.

1. ``table1 --fe`` (12 walls, adaptive scans from 6 starting heights, 0.25 m mesh: every
   height a Dask task) on one embedded worker, then on two: the speed-up (target >= 1.7x
   on a 2-core machine).
2. The scheduling overhead per FE task, against the mean task run time (target <= 1 %), from
   the task run times the workers measured (Dask's task stream), two ways: the time a worker
   sat idle between two of its tasks (dispatch, results to the client, the next round of a
   scan submitted), per task; and everything that was not computing, (wall x workers − busy)
   / tasks, which also counts the end of the run, when one worker has no task left.
3. 10 000 closed-form cases (random façades, ``analysis.fe = false``, ``analysis.hinge_check
   = false``: the hinge check integrates a rocking history per mechanism, about 0.07 s each,
   which no batch vectorises) through ``sweep``: vectorised batches, records and table
   written (target < 10 s).

Run on a quiet machine (the speed-up needs both cores free): ``python benchmarks/bench_sweep.py
[--quick] [--only table1|closed-form]`` (--quick: 4 walls, 4 heights, 0.5 m mesh, 2 000
closed-form cases).
"""

from __future__ import annotations

import argparse
import os
import tempfile
import time
from pathlib import Path


def _table1(workers: int, kw: dict) -> tuple[float, list, list]:
    from distributed import get_task_stream

    from homlimit.app.engine import Engine
    from homlimit.app.pipeline import table1_records

    with Engine(workers=workers, progress=False) as eng:
        eng.client.run(lambda: __import__("homlimit.app.pipeline"))   # imports done before
        eng.map(_warm, range(workers))                                 # the clock starts
        t0 = time.perf_counter()
        with get_task_stream(eng.client) as ts:
            rows = table1_records(fe=True, fe_results=eng.fe_results, **kw)
        wall = time.perf_counter() - t0
    return wall, rows, ts.data


def _warm(_):
    """A tiny FE solve on each worker (first-call costs of gmsh, scikit-fem, cvxpy)."""
    from homlimit.app.pipeline import run

    run(None, write=False, overrides={"mesh.size": 1.5, "analysis.heights": 2,
                                      "analysis.static": False})


def _busy(stream) -> tuple[float, int]:
    """Seconds the workers spent computing, and the number of tasks."""
    busy = 0.0
    for t in stream:
        busy += sum(s["stop"] - s["start"] for s in t["startstops"] if s["action"] == "compute")
    return busy, len(stream)


def _gaps(stream) -> float:
    """Seconds the workers sat idle between two consecutive tasks of their own."""
    by_worker: dict = {}
    for t in stream:
        for s in t["startstops"]:
            if s["action"] == "compute":
                by_worker.setdefault(t["worker"], []).append((s["start"], s["stop"]))
    gaps = 0.0
    for spans in by_worker.values():
        spans.sort()
        gaps += sum(max(0.0, b[0] - a[1]) for a, b in zip(spans, spans[1:]))
    return gaps


def _stock_table(n: int, path: Path):
    import numpy as np

    rng = np.random.default_rng(18)
    H = rng.uniform(4, 15, n).round(2)
    b = rng.uniform(0.3, 0.9, n).round(3)
    lines = ["name,wall.H,wall.b,wall.l,wall.s,wall.L,masonry.a,masonry.c,masonry.f"]
    for k in range(n):
        lines.append(f"W{k},{H[k]},{b[k]},{rng.uniform(3, 12):.2f},{rng.uniform(0.3, 0.7):.3f},"
                     f"{rng.uniform(4, 10):.2f},{rng.uniform(0.1, 0.35):.3f},"
                     f"{rng.uniform(0.1, 0.3):.3f},{rng.uniform(0.4, 0.9):.3f}")
    path.write_text("\n".join(lines) + "\n")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--only", choices=("table1", "closed-form"), help="one part only")
    args = ap.parse_args()
    kw = (dict(mesh_size=0.5, heights=4, tests=["B1", "B4", "C1", "C4"]) if args.quick
          else dict(mesh_size=0.25, heights=6))
    n_cf = 2000 if args.quick else 10000
    print(f"machine: {os.cpu_count()} cores, load average {os.getloadavg()[0]:.2f} "
          "(the speed-up needs a quiet machine)")

    if args.only != "closed-form":
        _bench_table1(kw)
    if args.only != "table1":
        _bench_closed_form(n_cf)


def _bench_table1(kw: dict):
    t1, rows1, s1 = _table1(1, kw)
    t2, rows2, s2 = _table1(2, kw)
    same = rows1 == rows2
    print(f"table1 --fe ({len(rows1)} walls, {kw['heights']} heights, mesh {kw['mesh_size']} m):"
          f" 1 worker {t1:.1f} s, 2 workers {t2:.1f} s, speed-up {t1 / t2:.2f}x "
          f"(target >= 1.7x); same numbers: {same}")
    busy, n = _busy(s2)
    mean = busy / n
    gap = _gaps(s2) / n
    over = (t2 * 2 - busy) / n
    print(f"FE tasks: {n} on 2 workers, mean run time {mean:.2f} s; scheduling overhead "
          f"between tasks {gap * 1e3:.0f} ms per task = {100 * gap / mean:.2f} % (target <= 1 %);"
          f" all idle time incl. the end of the run {over * 1e3:.0f} ms per task = "
          f"{100 * over / mean:.2f} %")
    busy1, n1 = _busy(s1)
    over1 = (t1 - busy1) / n1
    print(f"  1 worker: overhead {over1 * 1e3:.0f} ms per task = "
          f"{100 * over1 / (busy1 / n1):.2f} % of its run time")



def _bench_closed_form(n_cf: int):
    from homlimit.app.engine import Engine
    from homlimit.app.sweep import sweep

    with tempfile.TemporaryDirectory() as d, Engine(workers=2, progress=False) as eng:
        d = Path(d)
        _stock_table(n_cf, d / "stock.csv")
        base = {"name": "stock", "analysis": {"fe": False, "hinge_check": False}}
        eng.map(_warm, range(2))
        t0 = time.perf_counter()
        res = sweep(base, table=d / "stock.csv", out=d / "out", engine=eng, progress=False)
        dt = time.perf_counter() - t0
    print(f"{n_cf} closed-form cases (2 workers, vectorised batches): {dt:.1f} s "
          f"({res.n_ok} ok, {res.n_failed} failed; target < 10 s for 10 000)")


if __name__ == "__main__":
    main()
