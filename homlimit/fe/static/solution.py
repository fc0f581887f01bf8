"""The static program's result: λ⁻, the vertex stresses that prove it, and their fields."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ...errors import ParameterError
from ..mesh import element_areas
from ..solver import SolveRecord

__all__ = ["StaticSolution", "attach_cell_fields", "peak_compression"]


@dataclass(frozen=True)
class StaticSolution(SolveRecord):
    """Result of the lower-bound program.

    ``multiplier`` is λ⁻; ``stress`` (nt, 3, 3) is σ at [element, local vertex, component] with
    components (σ_x, σ_z, τ_xz) in Pa; ``active`` (nt, 3) is the index of the active facet of the
    element's strength domain at each vertex (rows of its static cone counted as 'eq' rows
    skipped, each linear row one facet, each second-order cone one facet), or −1 where no facet
    is active within ``active_tol``. ``control`` (nt, 6, 3), degree 2 only: the Bernstein
    coefficients (``stress`` holds their vertex values). ``rigid`` (nt,) marks elements of rigid
    regions (``strength.Rigid``): each connected one is a body in equilibrium as a whole, its
    stress is NaN. The solve's fields (``solver.SolveRecord``): status in Clarabel's names,
    primal_objective and dual_objective λ⁻ as Clarabel reports them (scaled units; the dual NaN
    through cvxpy with HiGHS), iterations, times (assembly, solve, post), sizes.
    """

    multiplier: float
    stress: np.ndarray
    active: np.ndarray
    mesh: object
    rigid: np.ndarray | None = None
    control: np.ndarray | None = None

    @property
    def degree(self) -> int:
        """1: σ linear (``stress`` holds it all); 2: σ quadratic, its six Bernstein coefficients
        per triangle in ``control`` (nt, 6, 3): vertices 0–2, then the edges 01, 12, 20."""
        return 1 if self.control is None else 2

    @property
    def gap(self) -> float:
        """Clarabel's absolute primal–dual objective gap (scaled units)."""
        return abs(self.primal_objective - self.dual_objective)

    def element_areas(self) -> np.ndarray:
        """Triangle areas (nt,) [m²]."""
        return element_areas(self.mesh)

    def element_mean(self) -> np.ndarray:
        """Mean stress of every triangle, (nt, 3): (σ_x, σ_z, τ_xz) at the centroid."""
        return self.stress.mean(axis=1)

    def principal(self, at: str = "centroid"):
        """Principal stresses (s1 ≥ s2) and the angle θ of s2 (the most compressive) from x.

        ``at='centroid'`` gives arrays of shape (nt,); ``'vertex'`` of shape (nt, 3).
        """
        s = self.element_mean() if at == "centroid" else self.stress
        sx, sz, txz = s[..., 0], s[..., 1], s[..., 2]
        c = 0.5 * (sx + sz)
        r = np.hypot(0.5 * (sx - sz), txz)
        theta1 = 0.5 * np.arctan2(2 * txz, sx - sz)  # direction of s1
        return c + r, c - r, theta1 + 0.5 * np.pi

    def fields(self) -> dict:
        """Per element-vertex arrays (nt, 3): sigma_x, sigma_z, tau_xz, active_facet."""
        return {"sigma_x": self.stress[..., 0], "sigma_z": self.stress[..., 1],
                "tau_xz": self.stress[..., 2], "active_facet": self.active}

    def cell_fields(self) -> dict:
        """Per element arrays (nt,) for attaching to a continuous mesh's cell data.

        Mean σ_x, σ_z, τ_xz, the principal stresses, and the active facet (the most frequent
        active facet index over the three vertices, −1 if none).
        """
        s = self.element_mean()
        s1, s2, th = self.principal()
        act = self.active
        # most frequent non-negative index per row (ties: the smaller), -1 if none
        best = np.full(act.shape[0], -1)
        cnt = np.zeros(act.shape[0], int)
        for k in np.unique(act[act >= 0]):
            ck = (act == k).sum(axis=1)
            upd = ck > cnt
            best[upd], cnt[upd] = k, ck[upd]
        return {"sigma_x": s[:, 0], "sigma_z": s[:, 1], "tau_xz": s[:, 2],
                "sigma_1": s1, "sigma_2": s2, "compression_angle": th, "active_facet": best}

    def to_meshio(self):
        """A discontinuous meshio.Mesh (three own points per triangle) with the vertex stresses.

        Point data: sigma_x, sigma_z, tau_xz [Pa] and active_facet; cell data: the element
        means and principal stresses of ``cell_fields``. ParaView shows the discontinuities.
        """
        import meshio

        p, t = self.mesh.p, self.mesh.t
        nt = t.shape[1]
        pts = np.zeros((3 * nt, 3))
        pts[:, :2] = p[:, t.T.reshape(-1)].T
        cells = np.arange(3 * nt).reshape(nt, 3)
        pdata = {k: np.asarray(v, float).reshape(-1) for k, v in self.fields().items()}
        cdata = {k: [np.asarray(v, float)] for k, v in self.cell_fields().items()}
        return meshio.Mesh(pts, [("triangle", cells)], point_data=pdata, cell_data=cdata)



def attach_cell_fields(mesh, static: StaticSolution, prefix: str = "static_"):
    """A copy of a meshio.Mesh (e.g. the mechanism's) with the static field as cell data.

    The mesh's first "triangle" block must be the static solution's triangles, in order (as in
    ``KinematicSolution.to_meshio()`` on the same mesh); other blocks (e.g. a crack polyline)
    get NaN. Fields: ``prefix`` + sigma_x, sigma_z, tau_xz, sigma_1, sigma_2,
    compression_angle, active_facet (see ``StaticSolution.cell_fields``).
    """
    import meshio

    blocks = list(mesh.cells)
    tri = [k for k, b in enumerate(blocks) if b.type == "triangle"]
    nt = static.mesh.t.shape[1]
    if not tri or len(blocks[tri[0]].data) != nt:
        raise ParameterError(f"mesh has triangle blocks of sizes "
                             f"{[len(blocks[k].data) for k in tri]}; allowed: a first triangle "
                             f"block of the static solution's {nt} triangles")
    data = {k: list(v) for k, v in mesh.cell_data.items()}
    for name, val in static.cell_fields().items():
        data[prefix + name] = [np.asarray(val, float) if k == tri[0]
                               else np.full(len(b.data), np.nan) for k, b in enumerate(blocks)]
    return meshio.Mesh(mesh.points, blocks, point_data=dict(mesh.point_data), cell_data=data)


def peak_compression(static, rho: float = 1.0) -> float:
    """The largest compression −σ₂ [Pa] of a static field over its vertex values (and, for
    quadratic stresses, every Bernstein control coefficient: σ is their convex combination,
    so this bounds −σ₂ everywhere); 0 for a field without stress. The T-section's façade
    strip (region "facade") carries ρ = l/s times the façade's stresses: divided by ``rho``."""
    s = static.control if getattr(static, "control", None) is not None else static.stress
    s = np.array(s, float)
    fac = (static.mesh.subdomains or {}).get("facade")
    if fac is not None:
        s[np.asarray(fac)] /= rho
    s = s.reshape(-1, 3)
    s = s[~np.isnan(s).any(axis=1)]
    low = 0.5 * (s[:, 0] + s[:, 1]) - np.hypot(0.5 * (s[:, 0] - s[:, 1]), s[:, 2])
    return float(max(0.0, -low.min(initial=0.0)))
