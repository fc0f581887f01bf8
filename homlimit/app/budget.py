"""The problem-size budget: how many triangles a run will mesh, known before it meshes.

A run's memory is that of its largest conic program (the kinematic or the static bound of the
whole wall, or of the largest part of the FE impulse scan), and grows linearly with its
triangle count. ``estimate_triangles`` predicts the count of ``fe.problems.t_section`` from the
wall and the mesh size alone, without meshing; ``fe_triangles`` takes the largest problem of a
run; above ``[mesh] max_triangles`` the case is refused before any work (exit 2), naming the
keys to change. Calibration and the default: ``benchmarks/bench_memory.py``.
"""

from __future__ import annotations

import math

from ..fe.geometry import OUTER_GROWTH, graded_columns
from ..params import MESHERS, PART_DIVISIONS

__all__ = ["DEFAULT_MAX_TRIANGLES", "KIB_PER_TRIANGLE", "MEMORY_BUDGET_GIB", "MESHERS",
           "estimate_triangles", "fe_triangles", "memory_gib"]

N_B = 4          # columns across the façade (t_section's n_b)
GROWTH = 1.15    # growth of the crossed mesh's column widths away from the junction
# gmsh: triangles per unit area at size h is GMSH_AREA/h² (equilateral: 4/√3 = 2.31), and a
# band of width b on either side of the junction is refined to min(h, b/N_B), with a linear
# transition over a further b; coefficients fitted to 46 gmsh meshes (1e2 .. 4e4 triangles):
# the estimate lies within 0.95 .. 1.05 of the count above 5 000 triangles
GMSH_AREA = 2.36
GMSH_TRANSITION = 2.76
# checked again on B1 (H 9, b 0.5, L 6; count, estimate/count): gmsh at h 0.5, 0.25, 0.125 m:
# 2118 (0.94), 3530 (0.98), 8834 (1.01). gmsh-strip: the strip is exact, 4·N_B per row of h,
# the wall is gmsh's: B1 at h 1, 0.5, 0.25, 0.125 m: 366 (2.81), 1388 (1.15), 3278 (1.02),
# 9236 (1.02); H 4, b 0.3, L 3: 456 (1.78), 1214 (1.07), 2766 (1.02) at h 0.5 .. 0.125 m. The
# coarse meshes are over-estimated (the safe side): there the junction's edges are h long, so
# the wall's band is coarser than b/N_B.

# Peak memory of the conic programs per triangle: the largest measured above 5 000 triangles
# (B1, both meshers, 4 300 .. 19 000 triangles, benchmarks/bench_memory.py): kinematic
# 33.0 .. 37.5 KiB, static 24.4 .. 35.3 KiB; the larger sizes the default.
KIB_PER_TRIANGLE = {"kinematic": 37.5, "static": 35.3}
#: memory a run may take on the reference machine (2 cores, 24 GiB, shared with others)
MEMORY_BUDGET_GIB = 8.0
#: 150 000 triangles: 5.4 GiB at 37.5 KiB each, leaving a quarter of MEMORY_BUDGET_GIB for
#: the fill-in of the sparse factorisation growing faster than linearly beyond the measured
#: sizes (~n log n: +25 % from 15k to 150k) and for the scan's solutions held in memory
DEFAULT_MAX_TRIANGLES = 150_000


def estimate_triangles(H: float, b: float, L: float, h: float, mesher: str = "crossed",
                       h_outer: float | None = None) -> float:
    """Triangles of ``t_section`` on a part of height H (façade thickness b, wall length L)
    at mesh size h [m], without meshing.

    crossed: 4 triangles per cell, ceil(H/h) rows; columns: N_B across the façade, the wall's
    far spacing max(h, b/N_B) over L, plus the graded columns between the two sizes
    (ln(max/min)/ln(GROWTH)); exact to within +0 .. +32 % above 5 000 triangles.
    gmsh: area over h² (GMSH_AREA) plus the junction band at min(h, b/N_B).
    gmsh-strip: the façade's crossed rows exactly, 4·N_B·max(2, ⌈H/h⌉), plus gmsh's wall at
    max(h, b/N_B).
    ``h_outer``: the façade's columns graded from that width at the outer face (the static
    bound's mesh): crossed, ln(b/N_B / h_outer)/ln(OUTER_GROWTH) more columns at most;
    gmsh-strip, the columns of ``geometry.graded_columns`` exactly.
    Returns a float (inf when the count would not fit a float).
    """
    h_j = min(h, b / N_B)
    try:
        if mesher in ("gmsh", "gmsh-strip"):
            hw = max(h, b / N_B) if mesher == "gmsh-strip" else h   # problems.t_section's wall
            band = min(b, L)
            transition = H * min(b, max(L - band, 0.0)) / (h_j * hw)
            far = H * max(L - 2 * b, 0.0) / hw ** 2
            wall = GMSH_AREA * (H * band / h_j ** 2 + far) + GMSH_TRANSITION * transition
            if mesher == "gmsh-strip":
                cols = N_B
                if h_outer is not None and h_outer < b / N_B:
                    cols = graded_columns(b, h_outer, N_B)[0]
                return 4.0 * cols * max(2, math.ceil(H / h)) + wall
            return GMSH_AREA * H * b / h_j ** 2 + wall
        h_far = max(h, b / N_B)
        graded = math.log(h_far / h_j) / math.log(GROWTH)
        if h_outer is not None and h_outer < b / N_B:
            graded += math.log(b / N_B / h_outer) / math.log(OUTER_GROWTH)
        return 4.0 * math.ceil(H / h) * (N_B + L / h_far + graded)
    except OverflowError:
        return math.inf


def fe_triangles(H: float, b: float, L: float, size: float, lams=(),
                 mesher: str = "crossed", divisions: int = PART_DIVISIONS,
                 outer_ratio: float = 0.0) -> float:
    """The largest problem of an FE run [triangles]: the whole wall at ``size`` (and on the
    static bound's graded mesh, ``outer_ratio`` > 0 on crossed or gmsh-strip) and each part of the
    impulse scan (``lams``: slenderness λ = h/b of the parts; a part of height h is meshed at
    min(size, h/divisions), ``mechanism.analysis.part_problem``)."""
    n = estimate_triangles(H, b, L, size, mesher)
    if mesher in ("crossed", "gmsh-strip") and outer_ratio > 0:
        n = max(n, estimate_triangles(H, b, L, size, mesher,
                                      h_outer=min(size / outer_ratio, b / N_B)))
    for lam in lams:
        hp = min(float(lam) * b, H)
        n = max(n, estimate_triangles(hp, b, L, min(size, hp / divisions), mesher))
    return n


def memory_gib(triangles: float) -> float:
    """Peak memory [GiB] of the larger bound on ``triangles`` triangles (KIB_PER_TRIANGLE)."""
    return triangles * max(KIB_PER_TRIANGLE.values()) / 2 ** 20
