"""Accuracy per second on B1: the bracket's relative gap against the seconds it cost, uniform
meshes beside the adaptive chain (issue 26, point 7).

For each façade model (bed joints, the default; homogenised):
- uniform: one bracket (both bounds) on gmsh-strip meshes whose strip rows are the element
  size, its columns graded from size/25 at the outer face (a run's mesh with
  ``[adapt] max_cycles = 1``), at a few sizes;
- adaptive: ``mechanism.adaptive.adaptive_bracket`` from 0.5 m, the best gap after every
  cycle against the cumulative seconds (homogenised: with and without the fan search of
  ``mechanism.conform``);
- bed joints, the run's chain: the adaptive bracket from the run's size (0.25 m, target 1 %)
  and then the crack's nested splits (``mechanism.adaptive.refine_crack``), each a point; and
  the same from 0.5 m with one bracket (``[mesh] size = 0.5``, ``[adapt] max_cycles = 1``).

For the run's chain it prints, at each of its points, the best gap the uniform meshes had
reached by the same second (a step curve) and whether the chain's lies at or below it.
Prints one row per point, writes docs/figures/accuracy_per_second.json and .png. Seconds are
wall-clock on this machine with the load average printed first.

    python benchmarks/bench_accuracy_per_second.py [--sizes 0.5 0.35 0.25 0.2 0.15 0.125]
        [--cycles 3] [--facades bedjoints homogenised]
    python benchmarks/bench_accuracy_per_second.py --chains-only   # the run's chains only

Curves not re-run (another façade, or all but the chains with --chains-only) are kept from
the last .json and named as kept.
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
from homlimit.mechanism.adaptive import adaptive_bracket, refine_crack  # noqa: E402
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


def run_chain(case, size=0.25, max_cycles=3):
    """The run's chain on the bed-joint façade ([adapt] defaults): the adaptive bracket from
    ``size`` (at most ``max_cycles`` meshes), then the crack's splits; every cycle a point
    (best gap, cumulative seconds)."""
    out, t0 = [], time.perf_counter()

    def progress(c):
        out.append({"cycle": c.cycle, "kind": c.kind, "triangles": c.triangles,
                    "lower": c.best_lower, "upper": c.best_upper, "gap": c.rel_gap,
                    "seconds": time.perf_counter() - t0, **c.measures})
        print(f"  run's chain from {size} m {c.kind:9s} cycle {c.cycle} {c.triangles:6d} tri  "
              f"{c.best_lower:.5f} .. {c.best_upper:.5f}  gap {100 * c.rel_gap:5.2f} %  "
              f"{out[-1]['seconds']:6.1f} s", flush=True)

    res = adaptive_bracket(case, "bedjoints", size, AdaptOptions(max_cycles=max_cycles),
                           SolverOptions(), progress, mesher="gmsh-strip", h_outer=size / 25)
    refine_crack(case, res, progress=progress)
    return out


def below(chain, uniform_pts):
    """Per point of ``chain``: the best uniform gap reached by the same second (None before
    the first uniform mesh ends) and whether the chain's gap is at or below it."""
    rows = []
    for p in chain:
        done = [u["gap"] for u in uniform_pts if u["seconds"] <= p["seconds"]]
        ref = min(done) if done else None
        rows.append({"seconds": p["seconds"], "gap": p["gap"], "uniform_best": ref,
                     "at_or_below": None if ref is None else p["gap"] <= ref})
        print(f"  at {p['seconds']:6.1f} s: chain {100 * p['gap']:5.2f} %, uniform best so far "
              + ("-" if ref is None else f"{100 * ref:5.2f} %")
              + ("" if ref is None else ("  (at or below)" if p["gap"] <= ref else "  (ABOVE)")),
              flush=True)
    return rows


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", type=float, nargs="+",
                    default=[0.5, 0.35, 0.3, 0.275, 0.25, 0.2, 0.15, 0.125])
    ap.add_argument("--cycles", type=int, default=3)
    ap.add_argument("--facades", nargs="+", default=["bedjoints", "homogenised"],
                    choices=["bedjoints", "homogenised"])
    ap.add_argument("--chains-only", action="store_true",
                    help="re-run the run's chains only, into the existing .json")
    args = ap.parse_args()
    print(f"load average before the runs: {os.getloadavg()[0]:.2f} on {os.cpu_count()} cores")
    case = Case()
    path = FIG / "accuracy_per_second.json"
    # curves not re-run here are kept from the last file (say which)
    res = json.loads(path.read_text()) if path.exists() else {}
    checks = res.pop("checks", {})
    for facade in args.facades:
        if not args.chains_only:
            res[f"{facade}, uniform"] = uniform(case, facade, args.sizes)
        if facade == "bedjoints":
            for name, size, cycles in (("0.25 m + crack splits", 0.25, 3),
                                       ("0.5 m, one bracket + crack splits", 0.5, 1)):
                res[f"bedjoints, the run's chain ({name})"] = chain = run_chain(case, size,
                                                                                cycles)
                checks[f"the run's chain ({name}) against uniform"] = below(
                    chain, res["bedjoints, uniform"])
        if not args.chains_only:
            res[f"{facade}, adaptive"] = adaptive(case, facade, args.cycles, False)
    if "homogenised" in args.facades and not args.chains_only:
        res["homogenised, adaptive + fan search"] = adaptive(case, "homogenised", args.cycles,
                                                             True)
    kept = [k for k in res if not any(k.startswith(f) for f in args.facades)
            or (args.chains_only and "chain" not in k)]
    if kept:
        print("kept from the last run:", ", ".join(kept))
    FIG.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps(res | {"checks": checks}, indent=1) + "\n")
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
