"""Time the vectorised closed forms: Figure 2's whole family of curves in one call per mechanism.

Run: python benchmarks/bench_closed_form.py
"""

import time

import numpy as np

from homlimit.closed_form.mechanisms import critical_I, critical_II, lam_max_II, vnorm_I


def best_of(fn, n=5):
    ts = []
    for _ in range(n):
        t0 = time.perf_counter()
        fn()
        ts.append(time.perf_counter() - t0)
    return min(ts)


rho = np.linspace(1.0, 20.0, 96)
A2 = np.array([0.4, 0.6, 0.8])
R, AA = np.meshgrid(rho, A2)
for beta, b in ((0.4, 0.5), (0.8, 0.25)):
    t1 = best_of(lambda: critical_I(R, np.sqrt(AA), beta, 9.0 / b))
    t2 = best_of(lambda: critical_II(R, np.sqrt(AA), lam_max_II(9.0 / b, 6.0 / b, np.sqrt(AA))))
    print(f"Figure 2 panel beta={beta}: {R.size} critical-lambda searches, "
          f"mechanism I {t1 * 1e3:.1f} ms, mechanism II {t2 * 1e3:.1f} ms")

n = 1_000_000
rng = np.random.default_rng(0)
args = (rng.uniform(1, 30, n), rng.uniform(1, 40, n), rng.uniform(0.2, 1.5, n),
        rng.uniform(0.05, 0.9, n))
t = best_of(lambda: vnorm_I(*args), n=2)
print(f"vnorm_I at {n:,} points (exact theta_m by batched 4x4 eigenvalues): {t:.2f} s "
      f"({t / n * 1e9:.0f} ns/point)")
