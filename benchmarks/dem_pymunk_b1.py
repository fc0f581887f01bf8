"""B1's ideal-impulse threshold in an independent engine, pymunk (Chipmunk2D: rigid bodies,
impulse-based contacts, elasticity 0, friction 0.6), beside this package's DEM (docs/dem.md,
section 4; issue 29 point 7).

The same assembly as the DEM (``t_section_blocks(case, facade="through")``, its ground widened
by 2 m on both sides), settled for 0.5 s under gravity (velocities then zeroed), then every free
block given −v_g; the DEM's criterion (a façade or toothing block outwards by more than H/4
from the settled state before t_max = 5 s) and bisection (×1.5 steps from the first trial,
halved to ±1 %). The façade's density ρ enters through the masses; pymunk has no contact
stiffness, so the façade's stiffness factor has no counterpart. Printed: µs per step, each
trial, the threshold and its bracket, CPU.

    python benchmarks/dem_pymunk_b1.py [--dt 1e-4] [--iterations 10] [--guess 0.8] [--test B1]

Measured (docs/dem.md, section 4): B1 1.056 m/s (1.050–1.0625; 30 iterations 1.055), B4
0.977 m/s (0.970–0.984), against the default DEM's 0.881 and 0.801; 156–307 s of CPU each.
"""

from __future__ import annotations

import argparse
import time

import numpy as np


def build(assembly, iterations: int, margin: float = 2.0):
    import pymunk

    a = assembly
    space = pymunk.Space()
    space.gravity = (0, -float(a.meta.get("g", 9.81)))
    space.iterations = iterations
    space.collision_slop = 1e-5
    f = float(a.meta["f"])
    bodies, index = [], []
    for i in range(a.n_blocks):
        v = a.vertices[a.offsets[i]:a.offsets[i + 1]].astype(float)
        if a.fixed[i]:
            v = v.copy()
            lo, hi = v[:, 0].min(), v[:, 0].max()
            v[np.isclose(v[:, 0], lo), 0] -= margin
            v[np.isclose(v[:, 0], hi), 0] += margin
            s = pymunk.Poly(space.static_body, [tuple(p) for p in v])
            s.friction, s.elasticity = 1.0, 0.0          # Chipmunk multiplies: f × 1
            space.add(s)
            continue
        c = a.centroid[i]
        b = pymunk.Body(float(a.mass[i]), float(a.inertia[i]))
        b.position = (float(c[0]), float(c[1]))
        s = pymunk.Poly(b, [tuple(p - c) for p in v])
        s.friction, s.elasticity = f, 0.0
        space.add(b, s)
        bodies.append(b)
        index.append(i)
    return space, bodies, np.array(index)


def settled_space(assembly, dt: float, iterations: int, settle: float = 0.5):
    """(space, bodies, index) of ``build``, stepped for ``settle`` s under gravity and its
    velocities zeroed; a trial runs on ``space.copy()`` (same body order), so one settling
    serves every trial."""
    space, bodies, idx = build(assembly, iterations)
    for _ in range(int(round(settle / dt))):
        space.step(dt)
    for b in bodies:
        b.velocity, b.angular_velocity = (0.0, 0.0), 0.0
    return space, bodies, idx


def trial(assembly, settled, v: float, dt: float, t_max: float = 5.0):
    """One ideal-impulse trial on a copy of ``settled`` (``settled_space``): every free block
    given −v [m/s]; collapsed when a façade or toothing block moved outwards by more than H/4
    (checked every 20 steps). Returns (collapsed, t [s], CPU [s], steps)."""
    from homlimit.blocks.geometry import FACADE, TOOTHING

    space, _, idx = settled
    space = space.copy()
    bodies = list(space.bodies)
    limit = 0.25 * float(assembly.meta["H"])
    wb = [b for b, w in zip(bodies, np.isin(assembly.kind[idx], (FACADE, TOOTHING))) if w]
    x0 = np.array([b.position.x for b in wb])
    for b in bodies:
        b.velocity = (-v, 0.0)
    c0 = time.process_time()
    n = int(round(t_max / dt))
    for k in range(n):
        space.step(dt)
        if k % 20 == 19 and np.any(x0 - np.array([b.position.x for b in wb]) > limit):
            return True, (k + 1) * dt, time.process_time() - c0, k + 1
    return False, t_max, time.process_time() - c0, n


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--test", default="B1", help="a Table 1 wall")
    ap.add_argument("--dt", type=float, default=1e-4, help="time step [s]")
    ap.add_argument("--iterations", type=int, default=10, help="Chipmunk solver iterations")
    ap.add_argument("--guess", type=float, default=0.8, help="first trial [m/s]")
    ap.add_argument("--t-max", type=float, default=5.0, help="trial length [s]")
    args = ap.parse_args(argv)

    from homlimit.blocks.geometry import t_section_blocks
    from homlimit.closed_form.paper import table1

    row = {r.test: r for r in table1()}[args.test]
    a = t_section_blocks(row.case, facade="through")
    dt = args.dt
    cpu0 = time.process_time()
    settled = settled_space(a, dt, args.iterations)
    trials = []
    lo = hi = None
    v = args.guess
    while lo is None or hi is None or (hi - lo) / (hi + lo) > 0.01:
        if lo is not None and hi is not None:
            v = 0.5 * (lo + hi)
        c, t, cpu, steps = trial(a, settled, v, dt, args.t_max)
        trials.append((v, c, t))
        print(f"vg {v:.4g} m/s {'collapsed' if c else 'stood'} at {t:.2f} s "
              f"({1e6 * cpu / steps:.0f} µs/step, {cpu:.0f} s CPU)", flush=True)
        if c:
            hi = v
        else:
            lo = v
        if lo is None:
            v = v / 1.5
        elif hi is None:
            v = v * 1.5
    print(f"{args.test} pymunk (dt {dt:g} s, {args.iterations} iterations): vg = "
          f"{0.5 * (lo + hi):.4f} m/s (stood {lo:.4g}, collapsed {hi:.4g}); UDEC {row.vg}; "
          f"{len(trials)} trials, {time.process_time() - cpu0:.0f} s CPU")


if __name__ == "__main__":
    main()
