"""Tables of the DEM calibration study (docs/dem.md, section 12; issue 29 point 4): reads the JSON
lines of ``benchmarks/dem_table1.py`` (one per wall, each with its DEMParams overrides) and
prints, per parameter set, every wall's v̄_g beside UDEC's (DEM/UDEC − 1), h beside UDEC's,
the slips, trials and CPU, then the ratios of v̄_g/√(gb) of the thin over the thick façade
(B4/B1, B5/B2, B6/B3, C4/C1, C5/C2, C6/C3) beside UDEC's, for the pairs present.

    python benchmarks/dem_calibration.py docs/figures/dem_calib_*.jsonl

It runs no DEM: the thresholds come from dem_table1.py, e.g.
``python benchmarks/dem_table1.py B1 B4 --set ks_over_kn=1 --set kn=0.3e9 >> out.jsonl``.
"""

from __future__ import annotations

import argparse
import json

PAIRS = [("B4", "B1"), ("B5", "B2"), ("B6", "B3"), ("C4", "C1"), ("C5", "C2"), ("C6", "C3")]
ORDER = [f"{s}{i}" for s in "BC" for i in range(1, 7)]


def label(over: dict) -> str:
    return ", ".join(f"{k}={v:g}" if isinstance(v, (int, float)) else f"{k}={v}"
                     for k, v in sorted(over.items())) or "defaults"


def load(paths: list[str]) -> dict[str, dict[str, dict]]:
    """{set label: {wall: record}}; a wall run twice with one set keeps its last record; lines
    that are not thresholds (dem_long_trials.py's single trials) are skipped."""
    sets: dict[str, dict[str, dict]] = {}
    for path in paths:
        with open(path) as fh:
            for line in fh:
                r = json.loads(line) if line.startswith("{") else {}
                if "lo" in r:
                    sets.setdefault(label(r.get("overrides", {})), {})[r["test"]] = r
    return sets


def udec_norm(r: dict) -> float:
    return r["udec_vg"] * r["vg_norm"] / r["v"]       # UDEC's v̄_g/√(gb): same √(gb)


def table(name: str, walls: dict[str, dict]) -> str:
    out = [f"**{name}**", "",
           "| wall | DEM v̄_g [m/s] (safe–collapsed) | UDEC | DEM/UDEC − 1 | DEM h [m] | UDEC h |"
           " base / hinge slip [mm] | trials | CPU [s] |",
           "|---|---|---|---|---|---|---|---|---|"]
    for w in sorted(walls, key=ORDER.index):
        r = walls[w]
        out.append(f"| {w} | {r['v']:.3f} ({r['lo']:.4g}–{r['hi']:.4g}) | {r['udec_vg']:.2f} | "
                   f"{100 * (r['ratio'] - 1):+.1f} % | {r['h']:.2f} | {r['udec_h']:.1f} | "
                   f"{1e3 * r['base_slip']:.0f} / {1e3 * r['hinge_slip']:.0f} | "
                   f"{r['n_trials']} | {r.get('cpu_process', r['cpu']):.0f} |")
    ratios = [f"{a}/{b} {walls[a]['vg_norm'] / walls[b]['vg_norm']:.3f} "
              f"({udec_norm(walls[a]) / udec_norm(walls[b]):.2f})"
              for a, b in PAIRS if a in walls and b in walls]
    dev = [abs(r["ratio"] - 1) for r in walls.values()]
    cpu = sum(r.get("cpu_process", r["cpu"]) for r in walls.values())
    out += ["", "ratios of v̄_g/√(gb), DEM (UDEC): " + (", ".join(ratios) or "none")
            + f"; largest |DEM/UDEC − 1| {100 * max(dev):.1f} %; CPU {cpu:.0f} s"]
    return "\n".join(out)


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("files", nargs="+", help="JSON lines of benchmarks/dem_table1.py")
    args = ap.parse_args(argv)
    for name, walls in load(args.files).items():
        print(table(name, walls), end="\n\n")


if __name__ == "__main__":
    main()
