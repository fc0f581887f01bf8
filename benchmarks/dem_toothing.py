"""One density per toothing block (docs/dem.md sections 16-17, criteria in
docs/figures/dem_toothing*_criterion.md): a Table 1 wall's ideal-impulse threshold with the
toothing blocks [0, b + c] at the façade's density ρ·γ over their whole area (T1: DEMParams
toothing = "block"), and also with the façade's contact factor ρ out to x = b + c (T2).
Everything else at the defaults or ``--set``, as ``benchmarks/dem_table1.py``. Prints one
JSON line (every trial; stderr: each trial). The sections' JSON lines were made before
``toothing`` was a parameter, by this script setting the same masses, centroids and
inertias itself (equal to ``t_section_blocks(..., toothing="block")``'s within 1e-11).

    python benchmarks/dem_toothing.py B1 T1      # B1 or any Table 1 wall; T1 or T2
    python benchmarks/dem_toothing.py B1 T1 --set ks_over_kn=1     # DEMParams overrides, as
                                                                   # dem_table1.py's --set

Measured (section 16): B1 0.906 / 0.981 m/s, B4 0.867 / 0.811 m/s (T1 / T2); 65-79 s of CPU
each.
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import sys
import time

import numpy as np
from dem_table1 import add_overrides  # benchmarks/ is on sys.path when run


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("wall", help="a Table 1 wall")
    ap.add_argument("variant", choices=("T1", "T2"))
    add_overrides(ap)
    args = ap.parse_args(argv)
    over = dict(args.over)

    from homlimit.blocks.geometry import TOOTHING
    from homlimit.closed_form.paper import table1
    from homlimit.dem import DEMParams, settle, t_section_model
    from homlimit.dem.threshold import collapse_threshold

    row = {r.test: r for r in table1()}[args.wall]
    model = t_section_model(row.case, DEMParams(toothing="block", **over))
    a, m = model.assembly, model.assembly.meta
    if args.variant == "T2":
        model = dataclasses.replace(model, fac_x=float(m["b"] + m["c"]))
    c0 = time.process_time()
    settled, info = settle(model)

    def progress(v, c, t_end, trials):
        print(f"{args.wall} {args.variant} vg {v!r} {'collapsed' if c else 'stood'} at "
              f"{t_end:.2f} s", file=sys.stderr, flush=True)

    th = collapse_threshold(model, settled, guess=round(row.vg, 1), rel_tol=0.01, t_max=5.0,
                            progress=progress)
    g, b = m["g"], m["b"]
    print(json.dumps({
        "wall": args.wall, "variant": args.variant, "set": over, "vg": th.v, "lo": th.lo,
        "hi": th.hi,
        "vnorm": th.v / (g * b) ** 0.5, "udec": row.vg, "err": th.v / row.vg - 1, "h": th.h,
        "udec_h": row.h_v, "base_slip": th.base_slip, "hinge_slip": th.hinge_slip,
        "trials": th.trials, "dt": model.dt, "settle": info,
        "toothing_blocks": int(np.sum(a.kind == TOOTHING)),
        "cpu": time.process_time() - c0}), flush=True)


if __name__ == "__main__":
    main()
