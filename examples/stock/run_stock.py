"""The closed-form + FE sweep over the 200 made-up façades of stock.csv, and its plots.

The same as the command line::

    homlimit sweep examples/stock/case.toml --table examples/stock/stock.csv \
        --out examples/stock/out
    homlimit sweep report examples/stock/out

Each façade is one task (closed forms I and II, then the FE impulse scan on a 0.6 m mesh);
records land in out/records/ as they finish, so a stopped run resumes where it was. Prints the
share of façades each mechanism governs and the median collapse velocity; the plots
(out/report/vg_histogram.png: the histogram of v̄_g and the shares) come from ``report``.
"""

from __future__ import annotations

from collections import Counter
from pathlib import Path

HERE = Path(__file__).resolve().parent


def main():
    import numpy as np

    from homlimit.app.sweep import sweep
    from homlimit.app.sweep_report import report

    res = sweep(HERE / "case.toml", table=HERE / "stock.csv", out=HERE / "out")
    ok = [r for r in res.rows if r["status"] == "ok"]
    share = Counter(r["critical.mechanism"] for r in ok)
    vg = np.array([r["critical.vg"] for r in ok], float)
    print(f"{len(res.rows)} façades: {res.n_ok} ok, {res.n_failed} failed "
          f"({res.elapsed:.0f} s)")
    print("governing mechanism: " + ", ".join(f"{m} {100 * k / len(ok):.0f} %"
                                              for m, k in share.most_common()))
    print(f"governing vg: median {np.median(vg):.3f} m/s, 10-90 % {np.percentile(vg, 10):.3f}"
          f" .. {np.percentile(vg, 90):.3f} m/s")
    print("plots: " + ", ".join(str(p) for p in report(res.folder).values()))


if __name__ == "__main__":
    main()
