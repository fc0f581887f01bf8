"""How fast an in-process DEM run stops on a signal (docs/dem.md section 4): the running-bond
panel of tests/test_dem.py (4 courses × 3 blocks) settled, then a run of 300 s of simulated
time, with SIGUSR1 (its handler raising KeyboardInterrupt) sent after ``delay`` s. Printed:
the seconds from the signal to the interrupt, and the seconds a 10 s run takes (the 300 s run
would take about 30 times that). Before the kernel released the GIL the interrupt waited for
the whole run.

    python benchmarks/bench_dem_interrupt.py [delay]        (default 0.1 s)
"""

from __future__ import annotations

import os
import signal
import sys
import threading
import time


def main(delay: float = 0.1) -> None:
    from homlimit.blocks.geometry import running_bond_panel
    from homlimit.dem import build_model, run, settle

    model = build_model(running_bond_panel(3, 4, 0.3, 0.2, density=2000.0), f=0.6)
    settled, _ = settle(model)
    t0 = time.perf_counter()
    run(model, settled, t_max=10.0, stop_on_collapse=False)
    ten = time.perf_counter() - t0

    def handler(signum, frame):
        raise KeyboardInterrupt

    signal.signal(signal.SIGUSR1, handler)
    threading.Timer(delay, os.kill, (os.getpid(), signal.SIGUSR1)).start()
    t0 = time.perf_counter()
    try:
        run(model, settled, t_max=300.0, stop_on_collapse=False)
        print("the 300 s run ended before the signal")
    except KeyboardInterrupt:
        waited = time.perf_counter() - t0 - delay
        print(f"interrupted {1000 * waited:.1f} ms after the signal; a 10 s run takes "
              f"{ten:.2f} s, so the 300 s run about {30 * ten:.0f} s")


if __name__ == "__main__":
    main(*[float(x) for x in sys.argv[1:2]])
