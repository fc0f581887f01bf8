"""B1's kinematic bound under nested refinement of the demo's mesh: does λ⁺ fall, and does
the crack settle?

The demo's first mesh (B1, bed-joint façade, gmsh-strip, size 0.25 m, outer column 1 cm:
``t_section(Case(), facade="bedjoints", h=0.25, mesher="gmsh-strip", h_outer=0.01)``) is
split uniformly ``LEVELS`` times (skfem's ``refined()``: every triangle into four, the regions
and named lines kept). Each mesh's P2 space contains the last one's and the strength cones
are checked at points of the same triangles, so λ⁺ cannot rise beyond the solver's
tolerance: a falling λ⁺ here says the bed-joint façade does not lock on this mesher, which
remeshing at a finer size cannot show (its meshes are not nested: docs/kinematic.md).
Prints per level: triangles, λ⁺, the hinge and crack (``mechanism.adaptive.crack_figures``),
the seconds and the solver's attempts.

    python benchmarks/bench_nested.py [LEVELS]        (default 1: up to 15 992 triangles)
"""

from __future__ import annotations

import os
import sys
import time

from homlimit.fe.kinematic import solve_kinematic
from homlimit.fe.problems import t_section, t_section_on_mesh
from homlimit.mechanism.adaptive import crack_figures
from homlimit.params import Case


def main(levels: int) -> None:
    case = Case()
    print(f"load average before the runs: {os.getloadavg()[0]:.2f} on {os.cpu_count()} cores")
    first = t_section(case, facade="bedjoints", h=0.25, mesher="gmsh-strip", h_outer=0.01)
    mesh = first.mesh
    print("level  triangles  lambda+    hinge z  T1      T2      T_mid   seconds  attempts")
    for level in range(levels + 1):
        problem = first if level == 0 else t_section_on_mesh(first, case, mesh)
        t0 = time.perf_counter()
        k = solve_kinematic(problem)
        sec = time.perf_counter() - t0
        c = crack_figures(case, k)
        row = [f"{c[key]:.4f}" if c[key] is not None else "-"
               for key in ("hinge_z", "T1", "T2", "T_mid")]
        print(f"{level:5d}  {mesh.t.shape[1]:9d}  {k.multiplier:.6f}  {row[0]:>7s}  "
              f"{row[1]}  {row[2]}  {row[3]}  {sec:7.1f}  {len(k.sizes['attempts'])}",
              flush=True)
        mesh = mesh.refined()


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 1)
