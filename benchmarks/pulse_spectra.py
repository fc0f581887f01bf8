"""Overturning spectra of the 12 Table 1 walls: the tables of docs/pulses.md, regenerated.

For every wall, mechanisms I (eq. 10, the paper's linearised model) and II (rigid, exact
geometry) at the critical λ of eq. 7, and the critical FE mechanism of the default FE scan
(bed-joint façade, mesh 0.25 m: its body if the crack is sharp, else its one-DOF shape), the
smallest overturning pulse is searched (homlimit.dynamics.case_spectra) for
- rectangular pulses of duration Δt (the ideal impulse as Δt → 0),
- one-sine pulses (type A, forward velocity pulse) of period T_p, both polarities,
at the periods of PERIODS. Prints markdown tables of pgv/√(gb) (and its ratio to eq. 7),
writes every point to docs/figures/pulse_spectra_table1.csv and the B1 spectrum to
docs/figures/pulse_spectra_B1.png, then the pivot-sliding table (mechanism II: the shortest
rectangular pulse whose lift-off needs a horizontal pivot force at most f times the vertical
one), B1's Ricker and Mavroeidis–Papageorgiou spectra and B1's thresholds with λ minimised.

    python benchmarks/pulse_spectra.py [--out docs/figures] [--quick]
"""

from __future__ import annotations

import argparse
import math
import time
from pathlib import Path

import numpy as np
from scipy.optimize import brentq

from homlimit.app.plots import plot_spectra
from homlimit.app.report import write as write_csv  # unit-suffixed headers
from homlimit.closed_form.mechanisms import mechanism_II
from homlimit.closed_form.paper import table1
from homlimit.dynamics import (
    MechanismIRocker,
    RectangularPulse,
    RigidRocker,
    case_spectra,
    critical_pulse,
    make_pulse,
)
from homlimit.mechanism.analysis import fe_result

PERIODS = (0.05, 0.1, 0.2, 0.5, 1.0, 2.0)  # s
RTOL = 1e-6


def FE_BODY(case):  # noqa: N802 - the FE column's mechanism
    """The critical FE mechanism of the default scan (``mechanism.analysis.fe_result``)."""
    return fe_result(case).critical


def table(points, kind, polarity, walls):
    per = sorted({p.period for p in points if p.pulse == kind})
    head = ("| wall | mech | eq. 7 | " + " | ".join(f"{T:g} s" for T in per)
            + " | DEM |")
    lines = [head, "|" + "---|" * (len(per) + 4)]
    for t in walls:
        for m in ("I", "II", "FE"):
            sel = {p.period: p for p in points if p.pulse == kind and p.mechanism == m
                   and p.polarity == polarity and p.case == t.test}
            if not sel:
                continue
            any_p = next(iter(sel.values()))
            cells = [f"{sel[T].vnorm:.3f} ({sel[T].ratio:.2f})" if T in sel else "–"
                     for T in per]
            lines.append(f"| {t.test} | {m} | {any_p.vnorm_eq7:.3f} | " + " | ".join(cells)
                         + f" | {t.vg_norm:.3f} |")
    return "\n".join(lines)


class Tagged:
    """A SpectrumPoint with the wall's name (for the tables)."""

    def __init__(self, p, case):
        self.__dict__.update(p.as_dict())
        self.case = case
        self.point = p


def sliding_free_duration(rk: RigidRocker, f: float):
    """Shortest rectangular pulse whose critical lift-off keeps |P_x| <= f P_z at the pivot:
    (Δt, pga, pgv/eq. 7), by brentq on Δt; None if even the ideal impulse keeps it."""
    if float(rk.hinge_ratio_at_rest(1e12)) <= f:
        return None

    def excess(log_dt):
        th = critical_pulse(rk, RectangularPulse(1.0, math.exp(log_dt)), rtol=RTOL)
        return float(rk.hinge_ratio_at_rest(th.pga)) - f

    lo, hi = math.log(1e-4), math.log(5.0)
    log_dt = brentq(excess, lo, hi, xtol=1e-4)
    th = critical_pulse(rk, RectangularPulse(1.0, math.exp(log_dt)), rtol=RTOL)
    return math.exp(log_dt), th.pga, th.ratio


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--out", default="docs/figures")
    ap.add_argument("--quick", action="store_true", help="B1 only")
    args = ap.parse_args()
    out = Path(args.out)
    walls = table1()[:1] if args.quick else table1()
    t0 = time.perf_counter()
    pts = []
    for t in walls:
        fe = FE_BODY(t.case)
        got = case_spectra(t.case, ("rectangular",), PERIODS, fe_body=fe, rtol=RTOL)
        got += case_spectra(t.case, ("one-sine",), PERIODS, fe_body=fe, rtol=RTOL,
                            polarities=(1, -1))
        pts += [Tagged(p, t.test) for p in got]
        if t.test == "B1":
            plot_spectra(out / "pulse_spectra_B1.png", got, dem_vnorm=t.vg_norm,
                         title="B1: critical pulses (mechanisms at the critical λ of eq. 7)")
        print(f"# {t.test}: {len(got)} points, {time.perf_counter() - t0:.0f} s so far",
              flush=True)
    rows = []
    for p in pts:
        d = p.point.as_dict()
        d = {"case": p.case, **d}
        rows.append(d)
    write_csv(out / "pulse_spectra_table1.csv", rows)
    print(f"\n{len(pts)} critical pulses in {time.perf_counter() - t0:.0f} s "
          f"(rtol {RTOL:g} on pga; solve_ivp DOP853 rtol 1e-10)\n")
    print("### Rectangular pulse: critical pgv/√(gb) = a_p Δt/√(gb) (ratio to eq. 7), "
          "columns Δt\n")
    print(table(pts, "rectangular", 1, walls))
    print("\n### One-sine pulse, polarity +1 (outward half first): critical pgv/√(gb) "
          "(ratio to eq. 7), columns T_p\n")
    print(table(pts, "one-sine", 1, walls))
    print("\n### One-sine pulse, polarity −1 (inward half first): critical pgv/√(gb) "
          "(ratio to eq. 7), columns T_p\n")
    print(table(pts, "one-sine", -1, walls))

    print("\n### Mechanism II: the pivot's horizontal force at lift-off (f = 0.6)\n")
    print("| wall | p [rad/s] | ratio, ideal impulse | shortest Δt [s] | pga/g | pgv / eq. 7 |")
    print("|---|---|---|---|---|---|")
    for t in walls:
        rk = RigidRocker(mechanism_II(t.case).body, name="II")
        b = rk.body
        lim = (b.i - b.z_G ** 2) / (b.x_G * b.z_G)
        res = sliding_free_duration(rk, t.case.masonry.f)
        if res is None:
            print(f"| {t.test} | {rk.p:.3f} | {lim:.2f} | any | – | 1 |")
        else:
            dt, pga, ratio = res
            print(f"| {t.test} | {rk.p:.3f} | {lim:.2f} | {dt:.3f} | {pga / 9.81:.2f} | "
                  f"{ratio:.3f} |")

    b1 = next(t for t in walls if t.test == "B1")
    print("\n### B1: Ricker and Mavroeidis–Papageorgiou (γ = 2, ν = 0) pulses, polarity +1: "
          "critical pgv/√(gb) (ratio to eq. 7)\n")
    more = case_spectra(b1.case, ("ricker", "mp"), (0.2, 0.5, 1.0, 2.0), rtol=RTOL,
                        pulse_options={"gamma": 2.0, "nu": 0.0})
    more = [Tagged(p, "B1") for p in more]
    for kind in ("ricker", "mp"):
        print(f"{kind}:\n")
        print(table(more, kind, 1, [b1]))
        print()
    write_csv(out / "pulse_spectra_B1_ricker_mp.csv", [{"case": "B1", **p.point.as_dict()}
                                                        for p in more])
    print("\n### B1: critical λ under finite pulses (λ(eq. 7) and 17 values on 2 ... H/b)\n")
    print("| pulse | T_p [s] | mech | λ (eq. 7) | pgv/√(gb) at λ(eq. 7) | best λ | "
          "pgv/√(gb) at best λ |")
    print("|---|---|---|---|---|---|---|")
    lams = np.geomspace(2.0, b1.case.wall.H / b1.case.wall.b, 17)
    sq = math.sqrt(9.81 * b1.case.wall.b)
    for kind, T, pol in (("rectangular", 0.05, 1), ("rectangular", 0.5, 1),
                         ("one-sine", 0.5, -1), ("one-sine", 0.5, 1), ("one-sine", 2.0, 1)):
        pulse = make_pulse(kind, T, 1.0, pol)
        for m in ("I", "II"):
            def rocker(lam, m=m):
                if m == "I":
                    return MechanismIRocker(b1.case, lam=lam)
                return RigidRocker(mechanism_II(b1.case, lam=lam).body, name="II")
            base = rocker(None)
            lam0 = base.lam if m == "I" else mechanism_II(b1.case).lam
            v0 = critical_pulse(base, pulse, rtol=RTOL).pgv / sq
            cands = sorted({lam0, *(lam for lam in lams
                                    if m == "I" or lam <= mechanism_II(b1.case).lam_max)})
            scan = [(lam, critical_pulse(rocker(lam), pulse, rtol=RTOL).pgv / sq)
                    for lam in cands]
            lam_b, v_b = min(scan, key=lambda x: x[1])
            print(f"| {kind} ({pol:+d}) | {T:g} | {m} | {lam0:.2f} | {v0:.3f} | {lam_b:.2f} | "
                  f"{v_b:.3f} |")
    print(f"\ntotal {time.perf_counter() - t0:.0f} s")


if __name__ == "__main__":
    main()
