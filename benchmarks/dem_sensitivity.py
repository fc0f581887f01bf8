"""Sensitivity of the DEM's collapse threshold to its unknowns (docs/dem.md, section 8; issue 29
point 4): one parameter changed at a time from the defaults (``DEMParams()``), the same for
every wall, nothing tuned per wall.

Variants: kn × 0.3, 3, 10; ks/kn 0.1 and 1 (default 0.5); the base joint tied (default
frictional); instead of the ideal impulse, a base-acceleration pulse of period 0.1 s of each
finite shape of ``homlimit.dynamics.pulses.make_pulse``: rectangular (Δt = 0.1 s), one-sine,
one-cosine, Ricker, all of polarity +1 (the first or main lobe throws the façade outwards),
on the default frictional base and (one-sine, one-cosine, Ricker) on a tied one. A pulse's
threshold is its amplitude a_g, given as its pgv, the peak |∫a_g dt|
(``dem_table1.pulse_loading``: the pulses' closed forms, a_g Δt for the rectangle, a_g T/π
one-sine, a_g T/(2π) one-cosine, a_g T e^{-1/2}/(π√2) Ricker), comparable with v̄_g. Each
threshold is ``homlimit.dem.threshold.collapse_threshold``'s on the T-section with the
façade "through" (its trials run here, to print their slips), bisection to ±1 %, t_max 5 s,
the first trial UDEC's v̄_g rounded to 0.1 m/s (as benchmarks/dem_table1.py, so the base row
repeats docs/dem.md's section 5 trial for trial; a pulse's first trial is the a_g whose pgv is
that, so its trials start at the impulse's).

Printed: one line per threshold as it ends, then the table as Markdown (the change from the
wall's base row; the B4/B1 ratio of v̄_g/√(gb) for a variant run on both walls); written as CSV
(whole or not at all, ``homlimit._io.write_csv``). One threshold costs 1–5 min of CPU on one
core (kn × 10: dt / √10; a pulse that stands to --max-pgv: 2–5 min); the default selection
about 45 min. Each trial is also printed on stderr as it ends.

    python benchmarks/dem_sensitivity.py [--walls B1 B4] [--b4-variants base kn*0.3 ...]
        [--csv homlimit-out/dem-sensitivity/dem_sensitivity.csv] [--max-pgv 10]
    python benchmarks/dem_sensitivity.py --table a.csv b.csv [--base B1=0.88125]  # no run
"""

from __future__ import annotations

import argparse
import math
import sys
import time

from dem_table1 import pulse_loading

#: name -> (DEMParams overrides, loading); loading None: the ideal impulse, else (kind, Δt)
VARIANTS = {
    "base": ({}, None),
    "kn*0.3": ({"kn": 0.3e9}, None),
    "kn*3": ({"kn": 3e9}, None),
    "kn*10": ({"kn": 10e9}, None),
    "ks/kn=0.1": ({"ks_over_kn": 0.1}, None),
    "ks/kn=1": ({"ks_over_kn": 1.0}, None),
    "tied base": ({"base_joint": "tied"}, None),
    "rect 0.1 s": ({}, ("rectangular", 0.1)),
    "one-sine 0.1 s": ({}, ("one-sine", 0.1)),
    "one-cosine 0.1 s": ({}, ("one-cosine", 0.1)),
    "ricker 0.1 s": ({}, ("ricker", 0.1)),
    # the same pulses on a tied base: what the frictional base's sliding does to them
    "one-sine 0.1 s, tied": ({"base_joint": "tied"}, ("one-sine", 0.1)),
    "one-cosine 0.1 s, tied": ({"base_joint": "tied"}, ("one-cosine", 0.1)),
    "ricker 0.1 s, tied": ({"base_joint": "tied"}, ("ricker", 0.1)),
}
#: pgv [m/s] past which a pulse that still stands ends the search: over 3× the project's
#: bound of recorded ground motion (3 m/s, docs/pulses.md)
MAX_PGV = 10.0
#: B4 (the smaller blocks) where cheap enough: without kn × 10 and the pulses
B4_DEFAULT = ["base", "kn*0.3", "kn*3", "ks/kn=0.1", "ks/kn=1", "tied base"]


class _Beyond(Exception):
    """A pulse stood at a pgv past the cap: the bracket search stops there."""


def threshold(row, name: str, max_pgv: float = MAX_PGV) -> dict:
    """One wall's threshold under one variant: a flat record. A pulse that still stands at a
    pgv above max_pgv [m/s] ends the search: the record has lo = that amplitude, hi, vg, h
    and the hinge slip NaN (no collapse found), base_slip and bed_slip (the largest bed-joint
    slip of any block) of that trial, n_trials and CPU as spent. The trials are
    ``collapse_threshold``'s (settle, then ``bisect`` over ``run``), each printed on stderr
    with its largest base and bed slips."""
    from homlimit.dem import DEMParams, t_section_model
    from homlimit.dem.model import run, settle
    from homlimit.dem.threshold import bisect, threshold_of, trial_record

    over, loading = VARIANTS[name]
    params = DEMParams(**over)
    model = t_section_model(row.case, params)
    guess = round(row.vg, 1)
    load, pgv_of = (lambda v: {"v_g": v}), (lambda a: a)     # the ideal impulse
    if loading is not None:
        load, pgv_of, per_ag = pulse_loading(*loading)
        guess /= per_ag
    t0 = time.perf_counter()
    c0 = time.process_time()
    settled, settle_info = settle(model)
    wall = row.case.wall
    last = {"n": 0}

    def trial(a):      # collapse_threshold's trial, with every trial's largest slips printed
        out = run(model, settled, t_max=5.0, **load(a))
        rec = trial_record(model, settled, out, a)
        last.update(n=last["n"] + 1, base_slip=float(out.slip_base.max()),
                    bed_slip=float(out.slip_bed.max()))
        print(f"  {row.test} {name}: a {a:.6g} (pgv {pgv_of(a):.4g} m/s) "
              f"{'collapsed' if out.collapsed else 'stood'} at {out.t_end:.2f} s, largest "
              f"base slip {1e3 * last['base_slip']:.0f} mm, bed slip "
              f"{1e3 * last['bed_slip']:.0f} mm", file=sys.stderr, flush=True)
        if loading is not None and not out.collapsed and pgv_of(a) > max_pgv:
            raise _Beyond(a, last["n"])
        return rec

    try:
        lo, hi, recs = bisect(trial, guess=guess, rel_tol=0.01)
    except _Beyond as stop:
        a, n = stop.args
        nan = float("nan")
        return {"wall": row.test, "variant": name, "kn": params.kn,
                "ks_over_kn": params.ks_over_kn, "base_joint": params.base_joint,
                "loading": f"{loading[0]} {loading[1]:g} s", "amplitude": nan, "lo": a,
                "hi": nan, "vg": nan, "vg_lo": pgv_of(a), "vnorm": nan, "vg_udec": row.vg,
                "h": nan, "h_udec": row.h_v, "base_slid": None, "hinge_slid": None,
                "base_slip": last["base_slip"], "hinge_slip": nan,
                "bed_slip": last["bed_slip"], "n_trials": n, "dt": model.dt,
                "cpu": time.process_time() - c0, "wall_clock": time.perf_counter() - t0}
    th = threshold_of(lo, hi, recs, 0.01, model.dt, settle_info)
    cpu = time.process_time() - c0       # settling included
    pgv = pgv_of(th.v)
    return {"wall": row.test, "variant": name, "kn": params.kn,
            "ks_over_kn": params.ks_over_kn, "base_joint": params.base_joint,
            "loading": "impulse" if loading is None else f"{loading[0]} {loading[1]:g} s",
            "amplitude": th.v, "lo": th.lo, "hi": th.hi, "vg": pgv, "vg_lo": pgv_of(th.lo),
            "vnorm": pgv / math.sqrt(wall.g * wall.b), "vg_udec": row.vg,
            "h": th.h, "h_udec": row.h_v, "base_slid": th.base_slid,
            "hinge_slid": th.hinge_slid, "base_slip": th.base_slip, "bed_slip": math.nan,
            "hinge_slip": th.hinge_slip, "n_trials": len(th.trials), "dt": th.dt,
            "cpu": cpu, "wall_clock": time.perf_counter() - t0}


#: the CSV's text columns; the others are numbers (empty: NaN)
_TEXT = {"wall", "variant", "base_joint", "loading", "base_slid", "hinge_slid"}


def read_rows(paths) -> list[dict]:
    """The records of earlier runs' CSVs (``main``'s), in file order."""
    import csv

    rows = []
    for path in paths:
        with open(path, newline="", encoding="utf-8") as fh:
            for r in csv.DictReader(fh):
                rows.append({k: v if k in _TEXT else int(v) if k == "n_trials"
                             else float(v) if v != "" else math.nan for k, v in r.items()})
    return rows


def table(rows: list[dict], base: dict | None = None) -> str:
    """The Markdown table: per variant, each wall's v̄_g, its change from the base row (or
    from ``base``: wall -> v̄_g of a base row run before), h, slips, and the B4/B1 ratio of
    v̄_g/√(gb) where both walls ran."""
    base = {**(base or {}), **{r["wall"]: r["vg"] for r in rows if r["variant"] == "base"}}
    by = {(r["wall"], r["variant"]): r for r in rows}
    out = ["| variant | wall | v̄_g [m/s] (safe–collapsed) | vs base | h [m] | base slip "
           "[mm] | hinge slip [mm] | trials | dt [s] | CPU [s] | B4/B1 of v̄_g/√(gb) |",
           "|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        if math.isnan(r["vg"]):            # no collapse up to the cap
            out.append(f"| {r['variant']} | {r['wall']} | none: stood at {r['vg_lo']:.4g} "
                       f"| – | – | {1e3 * r['base_slip']:.0f} (that trial) | – | "
                       f"{r['n_trials']} | {r['dt']:.3g} | {r['cpu']:.0f} | – |")
            continue
        lo, hi = r["lo"], r["hi"]
        if r["loading"] != "impulse":      # the bracket in pgv (pgv is linear in a_g)
            s = r["vg"] / r["amplitude"]
            lo, hi = lo * s, hi * s
        d = (f"{100 * (r['vg'] / base[r['wall']] - 1):+.1f} %"
             if r["wall"] in base and r["variant"] != "base" else "–")
        ratio = "–"
        b1 = by.get(("B1", r["variant"]))
        if r["wall"] == "B4" and b1 is not None and not math.isnan(b1["vg"]):
            ratio = f"{r['vnorm'] / b1['vnorm']:.3f}"
        out.append(f"| {r['variant']} | {r['wall']} | {r['vg']:.3f} ({lo:.4g}–{hi:.4g}) | "
                   f"{d} | {r['h']:.2f} | {1e3 * r['base_slip']:.0f} | "
                   f"{1e3 * r['hinge_slip']:.0f} | {r['n_trials']} | {r['dt']:.3g} | "
                   f"{r['cpu']:.0f} | {ratio} |")
    return "\n".join(out)


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--walls", nargs="+", default=["B1", "B4"], help="Table 1 walls")
    ap.add_argument("--variants", nargs="+", default=list(VARIANTS), choices=list(VARIANTS),
                    help="variants of B1 (and of walls other than B4)")
    ap.add_argument("--b4-variants", nargs="+", default=B4_DEFAULT, choices=list(VARIANTS),
                    help="variants of B4 (default: without kn*10 and the pulses)")
    ap.add_argument("--max-pgv", type=float, default=MAX_PGV,
                    help="a pulse that stands at a pgv above this [m/s] ends its search "
                    "(no collapse found)")
    ap.add_argument("--csv", default="homlimit-out/dem-sensitivity/dem_sensitivity.csv",
                    help="the table as CSV")
    ap.add_argument("--table", nargs="+", metavar="CSV", default=None,
                    help="print the table of earlier runs' CSVs and stop (no run)")
    ap.add_argument("--base", nargs="+", default=[], metavar="WALL=VG",
                    help="with --table: a wall's base v̄_g [m/s] from a run not in the CSVs")
    args = ap.parse_args(argv)
    if args.table:
        base = {w: float(v) for w, _, v in (b.partition("=") for b in args.base)}
        print(table(read_rows(args.table), base))
        return

    from homlimit._io import write_csv
    from homlimit.closed_form.paper import table1

    walls = {r.test: r for r in table1()}
    rows = []
    for w in args.walls:
        for name in (args.b4_variants if w == "B4" else args.variants):
            r = threshold(walls[w], name, args.max_pgv)
            rows.append(r)
            found = (f"vg {r['vg']:.4f} m/s ({r['lo']:.4g}..{r['hi']:.4g}), h {r['h']:.2f} m"
                     if not math.isnan(r["vg"]) else
                     f"no collapse: stood at pgv {r['vg_lo']:.4g} m/s (a_g {r['lo']:.4g})")
            print(f"{w} {name}: {found}, {r['n_trials']} trials, {r['cpu']:.0f} s CPU, "
                  f"{r['wall_clock']:.0f} s", flush=True)
            write_csv(args.csv, rows)           # whole after every threshold
    print()
    print(table(rows))
    print(f"\ntotal CPU {sum(r['cpu'] for r in rows):.0f} s; CSV {args.csv}")


if __name__ == "__main__":
    main()
