"""Accuracy per second on B1: the bracket's relative gap against the seconds it cost, uniform
meshes beside the adaptive chain (issue 26, point 7).

For each façade model (bed joints, the default; homogenised):
- uniform: one bracket (both bounds) on gmsh-strip meshes whose strip rows are the element
  size, its columns graded from size/25 at the outer face (a run's mesh with
  ``[adapt] max_cycles = 1``), at a few sizes;
- adaptive: ``mechanism.adaptive.adaptive_bracket`` from 0.5 m, the best gap after every
  cycle against the cumulative seconds (homogenised: with and without the fan search of
  ``mechanism.conform``).

Prints one row per point, writes docs/figures/accuracy_per_second.json and .png. Seconds are
wall-clock on this machine with the load average printed first.

    python benchmarks/bench_accuracy_per_second.py [--sizes 0.5 0.35 0.25] [--cycles 3]
"""

from __future__ import annotations

import argparse
import json
import os
import time
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from homlimit.fe.adapt import AdaptOptions  # noqa: E402
from homlimit.fe.bracket import bracket  # noqa: E402
from homlimit.fe.problems import t_section  # noqa: E402
from homlimit.fe.solver import SolverOptions  # noqa: E402
from homlimit.mechanism.adaptive import adaptive_bracket  # noqa: E402
from homlimit.mechanism.conform import conform_hook  # noqa: E402
from homlimit.params import Case  # noqa: E402

FIG = Path(__file__).resolve().parents[1] / "docs" / "figures"


def uniform(case, facade, sizes):
    out = []
    for h in sizes:
        t0 = time.perf_counter()
        p = t_section(case, facade=facade, h=h, mesher="gmsh-strip", h_outer=h / 25)
        br = bracket(p, options=SolverOptions())
        s = time.perf_counter() - t0
        out.append({"size": h, "triangles": p.n_triangles, "lower": br.lower,
                    "upper": br.upper, "gap": br.rel_gap, "seconds": s})
        print(f"  uniform {facade:11s} {h:5.3f} m {p.n_triangles:6d} tri  {br.lower:.5f} .. "
              f"{br.upper:.5f}  gap {100 * br.rel_gap:5.2f} %  {s:6.1f} s", flush=True)
    return out


def adaptive(case, facade, cycles, conform):
    out, t0 = [], time.perf_counter()

    def progress(c):
        out.append({"cycle": c.cycle, "triangles": c.triangles, "lower": c.best_lower,
                    "upper": c.best_upper, "gap": c.rel_gap,
                    "seconds": time.perf_counter() - t0})
        print(f"  adaptive {facade:11s}{' + search' if conform else ''} cycle {c.cycle} "
              f"{c.triangles:6d} tri  {c.best_lower:.5f} .. {c.best_upper:.5f}  gap "
              f"{100 * c.rel_gap:5.2f} %  {out[-1]['seconds']:6.1f} s", flush=True)

    adaptive_bracket(case, facade, 0.5, AdaptOptions(target_gap=1e-4, max_cycles=cycles),
                     SolverOptions(), progress, mesher="gmsh-strip", h_outer=0.5 / 25,
                     improve_upper=conform_hook(case, facade) if conform else None)
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", type=float, nargs="+", default=[0.5, 0.35, 0.25])
    ap.add_argument("--cycles", type=int, default=3)
    args = ap.parse_args()
    print(f"load average before the runs: {os.getloadavg()[0]:.2f} on {os.cpu_count()} cores")
    case = Case()
    res = {}
    for facade in ("bedjoints", "homogenised"):
        res[f"{facade}, uniform"] = uniform(case, facade, args.sizes)
        res[f"{facade}, adaptive"] = adaptive(case, facade, args.cycles, False)
    res["homogenised, adaptive + fan search"] = adaptive(case, "homogenised", args.cycles,
                                                         True)
    FIG.mkdir(parents=True, exist_ok=True)
    (FIG / "accuracy_per_second.json").write_text(json.dumps(res, indent=1) + "\n")
    fig, ax = plt.subplots(figsize=(7, 4.5), dpi=120)
    for name, pts in res.items():
        ax.plot([p["seconds"] for p in pts], [100 * p["gap"] for p in pts],
                "o-" if "uniform" in name else "s--", label=name)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("wall-clock seconds (cumulative for the adaptive chain)")
    ax.set_ylabel("relative gap (λ⁺ − λ⁻)/mean [%]")
    ax.set_title("B1: accuracy per second")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(FIG / "accuracy_per_second.png")
    print(f"written {FIG / 'accuracy_per_second.json'} and .png")


if __name__ == "__main__":
    main()
