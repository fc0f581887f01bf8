"""Convergence of B1's DEM threshold in the joint normal stiffness kn (docs/dem.md, section 8;
issue 29): the ideal impulse's v̄_g of B1 (the T-section with the façade "through", every other
parameter the default ``DEMParams``) for kn = factor × 10⁹ Pa/m, with ``dt_fraction`` fixed, so
dt = 0.1 √(m_min/k_max) shrinks as 1/√kn and a trial's steps grow as √kn.

Each threshold is ``collapse_threshold`` with the bracket searched by steps of ×1.1 from a
guess near the expected value (the step only saves trials: it does not move the threshold
beyond the tolerance), bisection to ±rel_tol (default 1 %), t_max 5 s. One process per factor
keeps each run short (1–4 min of CPU on one core).

Printed: one JSON line per factor as it ends (kn, dt, steps per simulated second, v̄_g with its
bracket, h, base and hinge slips, trials, steps per trial, CPU per threshold and per trial, µs
per step); then a Markdown table of those lines. ``--table FILE`` prints the table of JSON
lines saved from earlier runs (one process per factor), ``--plot PNG`` draws v̄_g against kn
with the brackets and UDEC's value (written whole or not at all).

    python benchmarks/dem_kn.py [--factors 0.25 0.5 1 2 4] [--rel-tol 0.01]
    python benchmarks/dem_kn.py --table kn.jsonl --plot docs/figures/dem_kn.png
"""

from __future__ import annotations

import argparse
import json
import time

#: first trials [m/s]: near the thresholds measured before (docs/dem.md, section 8: kn × 0.3,
#: 1, 3, 10 gave 0.788, 0.881, 1.069, 1.131 m/s)
GUESS = {0.25: 0.78, 0.5: 0.83, 1.0: 0.88, 2.0: 1.0, 4.0: 1.08}
#: the same thresholds from the sensitivity run (docs/dem.md section 8, bracket steps of ×1.5
#: from UDEC's 0.8 m/s): kn [Pa/m] -> v̄_g [m/s]; drawn beside this study's
SECTION8 = {0.3e9: 0.788, 1e9: 0.881, 3e9: 1.069, 10e9: 1.131}


def one(factor: float, rel_tol: float, t_max: float) -> dict:
    from homlimit.dem import DEMParams, t_section_model
    from homlimit.dem.threshold import collapse_threshold
    from homlimit.params import Case

    p = DEMParams()
    model = t_section_model(Case(), DEMParams(kn=factor * p.kn))
    guess = GUESS.get(factor, 0.9)
    t0 = time.process_time()
    th = collapse_threshold(model, guess=guess, rel_tol=rel_tol, t_max=t_max, step=1.1)
    cpu = time.process_time() - t0
    steps = [round(t / model.dt) for _, _, t in th.trials]
    return {"factor": factor, "kn": factor * p.kn, "dt": model.dt,
            "steps_per_s": 1.0 / model.dt, "v": th.v, "lo": th.lo, "hi": th.hi,
            "rel_tol": rel_tol, "h": th.h, "base_slip_mm": 1e3 * th.base_slip,
            "hinge_slip_mm": 1e3 * th.hinge_slip, "trials": len(th.trials),
            "steps_per_trial": sum(steps) / len(steps), "cpu_threshold": cpu,
            "cpu_trials": th.cpu, "cpu_per_trial": th.cpu / len(th.trials),
            "us_per_step": 1e6 * th.cpu / sum(steps),
            "settle_s": th.settle.get("time"),
            "trial_list": [[v, bool(c), t] for v, c, t in th.trials]}


def table(rows: list[dict]) -> str:
    base = next((r["v"] for r in rows if r["factor"] == 1.0), None)
    out = ["| kn [Pa/m] | dt [s] | v̄_g [m/s] (safe–collapsed) | vs kn = 10⁹ | h [m] | "
           "base / hinge slip [mm] | trials | steps per trial | CPU per run [s] | µs/step |",
           "|---|---|---|---|---|---|---|---|---|---|"]
    for r in sorted(rows, key=lambda r: r["factor"]):
        vs = "–" if base is None or r["factor"] == 1.0 else f"{100 * (r['v'] / base - 1):+.1f} %"
        out.append(f"| {r['kn']:.3g} | {r['dt']:.3g} | {r['v']:.3f} ({r['lo']:.4g}–"
                   f"{r['hi']:.4g}) | {vs} | {r['h']:.2f} | {r['base_slip_mm']:.0f} / "
                   f"{r['hinge_slip_mm']:.0f} | {r['trials']} | {r['steps_per_trial']:.0f} | "
                   f"{r['cpu_threshold']:.0f} | {r['us_per_step']:.0f} |")
    return "\n".join(out)


def plot(rows: list[dict], path: str) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from homlimit._io import write_figure

    rows = sorted(rows, key=lambda r: r["kn"])
    kn = [r["kn"] for r in rows]
    v = [r["v"] for r in rows]
    err = [[r["v"] - r["lo"] for r in rows], [r["hi"] - r["v"] for r in rows]]
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(9, 3.6))
    ax.errorbar(kn, v, yerr=err, marker="o", capsize=3, label="DEM, B1 (safe–collapsed)")
    ax.plot(list(SECTION8), list(SECTION8.values()), "x", color="grey",
            label="sensitivity run (dem.md section 8)")
    ax.axhline(0.83, color="k", ls="--", lw=1, label="UDEC 0.83 m/s (Table 1)")
    ticks = sorted(set(kn) | {k for k in SECTION8 if k > max(kn)} | {3e9})
    for a in (ax, bx):
        a.set_xscale("log")
        a.set_xticks(ticks, [f"{t / 1e9:g}" for t in ticks], minor=False)
        a.set_xticks([], minor=True)
    ax.set_xlabel("kn [10⁹ Pa/m] (dt_fraction 0.1 fixed)")
    ax.set_ylabel("v̄_g [m/s]")
    ax.legend(fontsize=8)
    ax.set_title("B1: the DEM's threshold against kn", fontsize=9)
    bx.plot(kn, [r["h"] for r in rows], marker="s", label="failing height h [m]")
    bx.plot(kn, [r["hinge_slip_mm"] / 10 for r in rows], marker="^",
            label="hinge slip [cm]")
    bx.plot(kn, [r["base_slip_mm"] / 10 for r in rows], marker="v", label="base slip [cm]")
    bx.set_xlabel("kn [10⁹ Pa/m]")
    bx.legend(fontsize=8)
    bx.set_title("at the lowest collapsing trial", fontsize=9)
    fig.tight_layout()
    write_figure(path, lambda tmp: fig.savefig(tmp, dpi=110, format="png"))
    plt.close(fig)


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--factors", type=float, nargs="+", default=[0.25, 0.5, 1.0, 2.0, 4.0],
                    help="kn / 1e9 Pa/m")
    ap.add_argument("--rel-tol", type=float, default=0.01, help="bisection tolerance")
    ap.add_argument("--t-max", type=float, default=5.0, help="trial length [s]")
    ap.add_argument("--table", help="a file of JSON lines from earlier runs: print its table")
    ap.add_argument("--plot", help="draw v̄_g against kn into this PNG")
    args = ap.parse_args(argv)
    if args.table:
        with open(args.table) as fh:
            rows = [json.loads(x) for x in fh if x.startswith("{")]
    else:
        rows = []
        for f in args.factors:
            rows.append(one(f, args.rel_tol, args.t_max))
            print(json.dumps(rows[-1]), flush=True)
    print(table(rows))
    if args.plot:
        plot(rows, args.plot)


if __name__ == "__main__":
    main()
