"""The FE collapse velocity of the 12 Table 1 walls, and its convergence (docs/fe-impulse.md).

For every wall, the FE impulse scan (``mechanism.analysis.fe_result``: failing parts from one
course a to H, refined around the minimum) at the default settings (bed-joint façade, mesh
0.25 m, parts meshed at min(0.25 m, h/N) with N = ``params.PART_DIVISIONS``, scan step a) and
with the element size and the scan step halved (0.125 m and h/2N, a/2; the h/N rule governs
short parts, so it is halved too):
critical λ, h, v̄_g/√(gb), mechanism kind, where the minimum lies, the hinge's impulse ratio
|P_x/P_z|, retries of the solver ladder, and the relative change of v̄_g between the two.

    python benchmarks/fe_collapse_velocity.py [--tests B1 C6] [--facade homogenised]
                                              [--json out.json]
"""

from __future__ import annotations

import argparse
import json
import time

from homlimit.closed_form.paper import table1
from homlimit.mechanism.analysis import fe_result
from homlimit.params import PART_DIVISIONS as N

p = argparse.ArgumentParser()
p.add_argument("--tests", nargs="*")
p.add_argument("--facade", default="bedjoints")
p.add_argument("--json")
p.add_argument("--settings", nargs="*", default=["default", "halved"],
               choices=["default", "halved", "quartered"])
args = p.parse_args()

rows = []
print("| wall | setting | λ | h [m] | v̄_g/√(gb) | kind | minimum | |Px/Pz| | heights | "
      "retries | time [s] | change |")
print("|---|---|---|---|---|---|---|---|---|---|---|---|")
for t in table1():
    if args.tests and t.test not in args.tests:
        continue
    a = t.case.masonry.a
    ref = None
    for label, size, step, div in (("default", 0.25, a, N), ("halved", 0.125, a / 2, 2 * N),
                                   ("quartered", 0.0625, a / 4, 4 * N)):
        if label not in args.settings:
            continue
        t0 = time.perf_counter()
        res = fe_result(t.case, size, args.facade, step=step, divisions=div)
        dt = time.perf_counter() - t0
        c = res.critical
        change = "" if ref is None else f"{c.vnorm / ref - 1:+.2%}"
        ref = ref or c.vnorm
        retries = sum(m.record()["retries"] for m in res.scan)
        rows.append({"test": t.test, "setting": label, "mesh_size": size, "step": step,
                     "divisions": div,
                     "lam": c.lam, "h": c.h, "vnorm": c.vnorm, "kind": c.kind,
                     "critical_at": res.critical_at, "hinge_ratio": c.hinge_ratio,
                     "heights": len(res.scan), "retries": retries, "time_s": dt,
                     "vnorm_dem": t.vg_norm, "lam_dem": t.lam_v})
        print(f"| {t.test} | {label} | {c.lam:.2f} | {c.h:.2f} | {c.vnorm:.4f} | {c.kind} | "
              f"{res.critical_at} | {c.hinge_ratio:.2f} | {len(res.scan)} | {retries} | "
              f"{dt:.0f} | {change} |", flush=True)
if args.json:
    with open(args.json, "w") as fh:
        json.dump(rows, fh, indent=1)
