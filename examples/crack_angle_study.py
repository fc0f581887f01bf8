"""Crack-angle study: the FE mechanism's crack against tan ψ = √(cf/a) (eq. 16), f and c/a.

Runs ``homlimit.app.studies.crack_angle_study`` over c/a ∈ {0.5, 0.75, 1, 1.5, 2, 3} and
f ∈ {0.3, 0.6, 0.9}, both façade models, the default mesh (h = 0.5 m) and a finer one
(h = 0.25 m), and writes

    <out>/crack_angle_study.csv    one record per point (columns: studies.CRACK_COLUMNS,
                                   headers with units: report.csv_header)
    <out>/crack_angle_study.png    measured fan edges and mid-line against the predictions

Usage: python examples/crack_angle_study.py [--out DIR] [--quick]
(about 10 minutes on 2 cores; --quick: a 3 × 2 grid, default mesh, about 1 minute).
The conclusions are written up in docs/crack-angle.md.
"""

from __future__ import annotations

import argparse
import math
from pathlib import Path

import numpy as np

from homlimit.app.report import read_csv, write
from homlimit.app.studies import CRACK_COLUMNS, crack_angle_study
from homlimit.mechanism.crack import fan_ray


def plot(path: Path, recs: list[dict]) -> Path:
    """Three panels per façade model: block-side edge vs min(f, c/a), fixed-side edge vs
    max(f, c/a), mid-line (50 % participation) vs √(cf/a); finer mesh filled markers."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    facades = sorted({r["facade"] for r in recs})
    fig, axes = plt.subplots(len(facades), 3, figsize=(13, 4.3 * len(facades)), squeeze=False)
    sizes = sorted({r["mesh_size"] for r in recs})
    for i, fac in enumerate(facades):
        for j, (key, pred, lab) in enumerate((
                ("tanpsi_block", lambda r: min(r["f"], r["c_over_a"]), "min(f, c/a)"),
                ("tanpsi_fixed", lambda r: max(r["f"], r["c_over_a"]), "max(f, c/a)"),
                ("tanpsi_fe", lambda r: math.sqrt(r["f"] * r["c_over_a"]), "√(cf/a)"))):
            ax = axes[i, j]
            for h in sizes:
                sel = [r for r in recs if r["facade"] == fac and r["mesh_size"] == h
                       and np.isfinite(r.get(key, math.nan))]
                if not sel:
                    continue
                x = np.array([pred(r) for r in sel])
                y = np.array([r[key] for r in sel])
                dy = np.array([r["dtanpsi_fe"] for r in sel])
                ax.errorbar(x, y, yerr=dy, fmt="o" if h == min(sizes) else "s",
                            mfc="C0" if h == min(sizes) else "none", ms=5, capsize=2,
                            label=f"FE, h = {h:g} m")
            if key == "tanpsi_fe":  # the exact fan's own 50 % ray, t(1/2; T1, T2)
                pts = sorted({(r["f"], r["c_over_a"]) for r in recs})
                x = [math.sqrt(f * ca) for f, ca in pts]
                y = [fan_ray(0.5, min(f, ca), max(f, ca)) if f != ca else f for f, ca in pts]
                ax.plot(x, y, "kx", ms=7, label="50 % ray of the closed-form fan")
            lim = [0, 3.2]
            ax.plot(lim, lim, "k--", lw=1, label="measured = predicted")
            ax.set_xlim(lim)
            ax.set_ylim(lim)
            ax.set_xlabel(f"predicted tan ψ = {lab}")
            ax.set_ylabel(f"measured {key}")
            ax.set_title(f"{fac} façade: {key}")
            ax.grid(alpha=0.3)
            ax.legend(fontsize=8)
    fig.tight_layout()
    tmp = path.with_suffix(".tmp.png")
    fig.savefig(tmp, dpi=120)
    plt.close(fig)
    tmp.replace(path)
    return path


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default="homlimit-out/crack-angle")
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--replot", metavar="CSV", help="only redraw the plot from a study CSV")
    args = ap.parse_args()
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    if args.replot:
        recs = read_csv(Path(args.replot))
    else:
        import logging

        logging.basicConfig(level=logging.INFO, format="%(message)s")   # progress per point
        recs = crack_angle_study(quick=args.quick)
        write(out / "crack_angle_study.csv", [{k: r.get(k) for k in CRACK_COLUMNS}
                                              for r in recs])
    plot(out / "crack_angle_study.png", recs)
    print(f"wrote {'' if args.replot else str(out / 'crack_angle_study.csv') + ' and '}"
          f"{out / 'crack_angle_study.png'}")


if __name__ == "__main__":
    main()
