"""v̄_g of B1 against the top tie's yield force and against fc (issue 30 point 6), on the Dask
engine: closed-form mechanisms I, II, the simple overturning and the rigid blocks.

    python examples/real-walls-sweep/run_sweep.py [--workers 2] [--out homlimit-out/real-sweep]

One sweep of 4 × 4 cases (tie.0.yield_force × masonry.fc, the base case.toml: a tie at the
top of B1), each case as `homlimit run` runs it; then docs/figures/real_walls_sweep.png (the
two panels: v̄_g against T_y at fc infinite and 2 MPa, against fc at T_y = 0 and 5 kN/m) and
the table printed. docs/real-walls.md quotes it.
"""

from __future__ import annotations

import argparse
import math
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parents[1]
TIES = [0.0, 2000.0, 5000.0, 10000.0]          # N/m
FCS = [0.0, 1e6, 2e6, 5e6]                      # Pa; 0: infinite
MECHS = [("I", "I", "o-"), ("II", "II", "s-"), ("overturning", "overturning", "^-"),
         ("blocks", "rigid blocks", "D-")]


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--out", default="homlimit-out/real-walls-sweep")
    ap.add_argument("--figure", default=str(ROOT / "docs" / "figures" / "real_walls_sweep.png"))
    args = ap.parse_args(argv)

    from homlimit.app.sweep import sweep

    res = sweep(str(HERE / "case.toml"),
                grid={"tie.0.yield_force": TIES, "masonry.fc": FCS},
                out=args.out, workers=args.workers)
    rows = [r for r in res.rows if r["status"] == "ok"]
    if res.n_failed:
        raise SystemExit(f"{res.n_failed} case(s) failed: see {res.folder}")

    def vg(T, fc, mech):
        for r in rows:
            if r["inputs.tie.0.yield_force"] == T and r["inputs.masonry.fc"] == fc:
                return r.get(f"mechanisms.{mech}.vg", math.nan)
        return math.nan

    print(f"{'T_y [kN/m]':>10} {'fc [MPa]':>9} " + " ".join(f"{n:>12}" for _, n, _ in MECHS))
    for T in TIES:
        for fc in FCS:
            print(f"{T / 1e3:10g} {fc / 1e6 if fc else math.inf:9g} "
                  + " ".join(f"{vg(T, fc, m):12.4f}" for m, _, _ in MECHS))
    plot(vg, args.figure)
    print(f"figure: {args.figure}")


def plot(vg, path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from homlimit._io import write_figure

    fig, axes = plt.subplots(1, 2, figsize=(11, 4.4), sharey=True)
    ax = axes[0]
    for fc, ls in ((0.0, "-"), (2e6, "--")):
        for m, name, style in MECHS:
            ax.plot([T / 1e3 for T in TIES], [vg(T, fc, m) for T in TIES], style[:-1] + ls,
                    label=f"{name}, fc {'∞' if not fc else f'{fc / 1e6:g} MPa'}",
                    color=f"C{[x[0] for x in MECHS].index(m)}", ms=4)
    ax.set_xlabel("tie at the top: yield force T_y [kN per m of façade]")
    ax.set_ylabel("v̄_g [m/s] (each mechanism at its critical height)")
    ax.legend(fontsize=7, ncol=2)
    ax.grid(alpha=0.3)
    ax = axes[1]
    xs = [fc / 1e6 for fc in FCS[1:]]
    for T, ls in ((0.0, "-"), (5000.0, "--")):
        for m, name, style in MECHS:
            color = f"C{[x[0] for x in MECHS].index(m)}"
            ax.plot(xs, [vg(T, fc, m) for fc in FCS[1:]], style[:-1] + ls, color=color, ms=4,
                    label=f"{name}, T_y = {T / 1e3:g} kN/m")
            ax.axhline(vg(T, 0.0, m), color=color, ls=ls, lw=0.6, alpha=0.6)
    ax.set_xscale("log")
    ax.set_xticks(xs, [f"{x:g}" for x in xs])
    ax.minorticks_off()
    ax.set_xlabel("compressive strength fc [MPa] (thin lines: fc infinite)")
    ax.legend(fontsize=7, ncol=2)
    ax.grid(alpha=0.3)
    fig.suptitle("B1 (H = 9 m, b = 0.5 m, l = 6 m): v̄_g against a top tie's T_y and fc "
                 "(homlimit sweep, Dask; docs/real-walls.md)", fontsize=10)
    fig.tight_layout()
    write_figure(path, lambda tmp: fig.savefig(tmp, dpi=120, format="png"))
    plt.close(fig)


if __name__ == "__main__":        # the embedded Dask workers import this script
    main()
