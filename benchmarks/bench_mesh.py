"""Meshing and conversion timings for the Table 1 T-section (B1: H = 9, b = 0.5, L = 6 m).

    python benchmarks/bench_mesh.py

Prints, per global size h (junction and façade-top refinement h/3): triangles, gmsh time,
meshio -> skfem time, smallest angle, and the element-count ratio to the previous size.
"""

import time

from homlimit.fe.geometry import tsection
from homlimit.fe.mesh import quality, to_skfem


def main():
    print(f"{'h [m]':>7} {'triangles':>10} {'ratio':>6} {'gmsh [s]':>9} {'to_skfem [s]':>13} "
          f"{'min angle':>10}")
    prev = None
    for h in (1.0, 0.5, 0.25, 0.125, 0.0625):
        t0 = time.perf_counter()
        m = tsection(9.0, 0.5, 6.0, h, size_junction=h / 3, size_top=h / 3)
        t1 = time.perf_counter()
        s = to_skfem(m)
        t2 = time.perf_counter()
        q = quality(s)
        n = q["n_elements"]
        ratio = f"{n / prev:6.2f}" if prev else " " * 6
        print(f"{h:7.4f} {n:10d} {ratio} {t1 - t0:9.3f} {t2 - t1:13.3f} "
              f"{q['min_angle_deg']:9.1f}°")
        prev = n


if __name__ == "__main__":
    main()
