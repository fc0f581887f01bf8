"""Cost of the rocking dynamics: one time history, one threshold search, one spectrum.

Prints wall-clock times (best of a few runs) on this machine; the figures in docs/pulses.md
were measured on 2 shared cores.

    python benchmarks/bench_pulse.py
"""

import time

from homlimit.closed_form.paper import table1
from homlimit.dynamics import (
    OneSinePulse,
    RectangularPulse,
    RickerPulse,
    case_rockers,
    case_spectra,
    critical_pulse,
    free_block,
    simulate,
)


def best_of(fn, n=3):
    ts, out = [], None
    for _ in range(n):
        t0 = time.perf_counter()
        out = fn()
        ts.append(time.perf_counter() - t0)
    return min(ts), out


B1 = table1()[0].case
rk = case_rockers(B1)
print("one time history (B1, default tolerances: DOP853 rtol 1e-10):")
for name, r in rk.items():
    for pulse in (RectangularPulse(9.0, 0.1), OneSinePulse(12.0, 0.5), RickerPulse(15.0, 0.5)):
        t, res = best_of(lambda: simulate(r, pulse))
        print(f"  {name:2s} {pulse.kind:11s} T={pulse.period:g} s: {t * 1e3:7.1f} ms "
              f"({res.n_rhs} rhs evaluations, {res.reason})")
blk = free_block(0.5, 5.0)
t, res = best_of(lambda: simulate(blk, None, theta0=0.09, duration=30.0))
print(f"  free block, 30 s of free rocking: {t * 1e3:.1f} ms ({res.n_impacts} impacts, "
      f"{res.n_rhs} rhs)")

print("one threshold search (rtol 1e-6 on pga, scan x1.05 from uplift):")
for name, r in rk.items():
    for pulse in (RectangularPulse(1.0, 0.005), RectangularPulse(1.0, 0.5),
                  OneSinePulse(1.0, 0.5), OneSinePulse(1.0, 0.5, polarity=-1),
                  RickerPulse(1.0, 0.5)):
        t, th = best_of(lambda: critical_pulse(r, pulse), n=2)
        print(f"  {name:2s} {pulse.kind:11s} T={pulse.period:g} s pol {pulse.polarity:+d}: "
              f"{t:6.2f} s ({th.n_simulations} time histories, "
              f"{t / th.n_simulations * 1e3:.1f} ms each)")

print("one spectrum (B1, I and II, 7 periods 0.02-2 s):")
for kinds, pols in ((("rectangular",), (1,)), (("one-sine",), (1, -1))):
    t, pts = best_of(lambda: case_spectra(B1, kinds, polarities=pols), n=1)
    print(f"  {kinds[0]:11s} polarities {pols}: {t:6.1f} s for {len(pts)} points "
          f"({t / len(pts):.2f} s per point)")
