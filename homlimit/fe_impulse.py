"""From a finite-element mechanism to the failing body, its crack and the collapse ground velocity.

Glue between the kinematic solver (``homlimit.kinematic``), the rigid fit (``rigidfit``), the
crack measurement (``crack``), the closed-form hinge + fan (``fan``) and the impulse criterion
(``impulse``, eqs 4–7).
"""

from __future__ import annotations

import numpy as np
from skfem import Basis, ElementTriP2

from .errors import check_range

__all__ = ["p2_nodes"]


def p2_nodes(solution, densities: dict | None = None):
    """P2 nodes of a KinematicSolution: positions X (n, 2), velocities V (n, 2), triangles
    (n_el, 6) in scikit-fem's P2 order, and per-triangle densities (from ``densities``:
    region → mass per unit area, default 1)."""
    mesh = solution.mesh
    sb = Basis(mesh, ElementTriP2())
    X = sb.doflocs.T.copy()
    V = np.asarray(solution.u, float).reshape(-1, 2)  # vector P2 DOFs interleave (x, z)
    rho = np.ones(mesh.t.shape[1])
    for name, idx in (densities or {}).items():
        rho[solution.regions[name]] = idx
    return X, V, sb.element_dofs.T.copy(), rho


def ray_conforming_mesh(case, z_hinge: float, slopes, h: float, z0: float = 0.0,
                        h_hinge: float | None = None):
    """A T-section mesh (gmsh, unstructured) whose edges contain the rays x = T (z − z_hinge)
    from the hinge (0, z_hinge) on the façade's outer face, one per slope T, and the façade /
    wall interface x = b. Returns a scikit-fem MeshTri with the boundaries ("base", "outer",
    "top", "end") and subdomains ("facade", "wall") of ``problems.t_section``.

    This is the adapter the conforming-mesh checks use until ``geometry.tsection`` offers
    embedded lines; h_hinge: element size at the hinge (default h/4).
    """
    import gmsh
    from skfem import MeshTri

    w = case.wall
    b, L, H = w.b, w.L, w.H
    z0 = check_range("z0", z0, 0.0, H, hi_open=True, unit="m")
    z_hinge = check_range("z_hinge", z_hinge, z0, H, hi_open=True, unit="m")
    h = check_range("h", h, 0.0, H - z0, lo_open=True, unit="m")
    h_hinge = h / 4 if h_hinge is None else check_range("h_hinge", h_hinge, 0.0, h,
                                                         lo_open=True, unit="m")
    slopes = [check_range("slope", T, 0.0, lo_open=True) for T in slopes]
    gmsh.initialize()
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.model.add("t_section_rays")
        occ = gmsh.model.occ
        r1 = occ.addRectangle(0, z0, 0, b, H - z0)
        r2 = occ.addRectangle(b, z0, 0, L, H - z0)
        ph = occ.addPoint(0, z_hinge, 0)
        lines = []
        for T in slopes:
            ze = min(H, z_hinge + (b + L) / T)
            lines.append(occ.addLine(ph, occ.addPoint(T * (ze - z_hinge), ze, 0)))
        occ.fragment([(2, r1), (2, r2)], [(1, ln) for ln in lines])
        occ.synchronize()
        gmsh.option.setNumber("Mesh.MeshSizeMax", h)
        gmsh.option.setNumber("Mesh.MeshSizeFromPoints", 0)
        gmsh.option.setNumber("Mesh.MeshSizeExtendFromBoundary", 0)
        f = gmsh.model.mesh.field
        fd = f.add("Distance")
        hinge = [t for d, t in gmsh.model.getEntities(0)
                 if np.allclose(gmsh.model.getValue(0, t, []), [0, z_hinge, 0])]
        f.setNumbers(fd, "PointsList", hinge)
        ft = f.add("Threshold")
        f.setNumber(ft, "InField", fd)
        f.setNumber(ft, "SizeMin", h_hinge)
        f.setNumber(ft, "SizeMax", h)
        f.setNumber(ft, "DistMin", 0.0)
        f.setNumber(ft, "DistMax", 2.0)
        f.setAsBackgroundMesh(ft)
        gmsh.model.mesh.generate(2)
        tags, xyz, _ = gmsh.model.mesh.getNodes()
        etypes, _, enodes = gmsh.model.mesh.getElements(2)
    finally:
        gmsh.finalize()
    index = np.zeros(int(tags.max()) + 1, int)
    index[tags.astype(int)] = np.arange(len(tags))
    t = index[np.asarray(enodes[list(etypes).index(2)], int).reshape(-1, 3)]
    p = xyz.reshape(-1, 3)[:, :2]
    used = np.unique(t)
    remap = np.full(len(p), -1)
    remap[used] = np.arange(len(used))
    m = MeshTri(p[used].T.copy(), remap[t].T.copy())
    tol = 1e-9 * H
    return m.with_boundaries({
        "base": lambda x: np.abs(x[1] - z0) < tol,
        "outer": lambda x: np.abs(x[0]) < tol,
        "top": lambda x: np.abs(x[1] - H) < tol,
        "end": lambda x: np.abs(x[0] - (b + L)) < tol,
    }).with_subdomains({"facade": lambda x: x[0] < b, "wall": lambda x: x[0] > b})
