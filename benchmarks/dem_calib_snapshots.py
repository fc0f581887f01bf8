"""Snapshots of a Table 1 wall's lowest collapsing DEM trial under a parameter set (docs/dem.md,
section 12): how the wall fails at the calibrated set against the defaults. One trial, recorded
every 0.05 s until the first frame past the collapse criterion; four frames in one PNG
(``homlimit.dem.output.plot_snapshots``, written whole or not at all).

    python benchmarks/dem_calib_snapshots.py C5 1.0979 docs/figures/dem_calib_C5.png \
        --set kn=0.3e9 --set ks_over_kn=1
"""

from __future__ import annotations

import argparse
import time

from dem_table1 import add_overrides, settled_wall


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("wall", help="Table 1 test name, e.g. C5")
    ap.add_argument("v", type=float, help="ideal impulse v_g [m/s]")
    ap.add_argument("png", help="the snapshots' PNG")
    ap.add_argument("--t-max", type=float, default=5.0, help="trial length [s]")
    add_overrides(ap)
    args = ap.parse_args(argv)

    from homlimit.dem.output import plot_snapshots, record_frames

    over = dict(args.over)
    c0 = time.process_time()
    model, settled = settled_wall(args.wall, over)
    frames = record_frames(model, settled, v_g=args.v, t_max=args.t_max)
    sets = ", ".join(f"{k}={v:g}" for k, v in over.items()) or "defaults"
    plot_snapshots(args.png, model, settled, frames,
                   title=f"{args.wall}, {sets}: v_g = {args.v:g} m/s")
    print(f"{args.wall} {sets} v_g {args.v}: {len(frames)} frames to t = {frames[-1].t:.2f} s, "
          f"{time.process_time() - c0:.0f} s CPU -> {args.png}", flush=True)


if __name__ == "__main__":
    main()
