"""The result of a kinematic limit analysis: multiplier, mechanism, powers, duals, timings."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .solver import SolveRecord

__all__ = ["KinematicSolution", "stress_tensor"]


def stress_tensor(sigma: np.ndarray) -> np.ndarray:
    """Plane stress vectors (σ_x, σ_z, τ_xz), shape (n, 3), as 3×3 tensors in the frame
    (x, z, out of plane), flattened row by row to shape (n, 9): [[σ_x, τ_xz, 0],
    [τ_xz, σ_z, 0], [0, 0, 0]] (symmetric; the out-of-plane components 0)."""
    sigma = np.asarray(sigma, float)
    t = np.zeros((len(sigma), 3, 3))
    t[:, 0, 0], t[:, 1, 1] = sigma[:, 0], sigma[:, 1]
    t[:, 0, 1] = t[:, 1, 0] = sigma[:, 2]
    return t.reshape(-1, 9)


@dataclass(frozen=True)
class KinematicSolution(SolveRecord):
    """Collapse multiplier and mechanism of ``solve_kinematic`` (per unit thickness, SI).

    multiplier      λ⁺ = D(u) − P_dead(u) at the optimum, with P_live(u) = 1 (an upper bound)
    u               global P2 DOF vector of the velocity field (``operators.p2_basis`` numbering)
    velocity        nodal velocities at the mesh vertices, shape (n_vertices, 2)
    dissipation     dissipation per triangle (area × mean of its vertex values) [W/m]
    interface_dissipation  dissipation per facet of every interface boundary [W/m]
    strain_rate     strain rate (d_xx, d_zz, γ_xz) at the 3 vertices of each triangle, (nel, 3, 3)
    intensity       strain-rate intensity per triangle: mean over vertices of
                    √(d_xx² + d_zz² + γ_xz²/2) [1/s]
    stress          stress estimate (σ_x, σ_z, τ_xz) at the 3 vertices of each triangle from the
                    duals of the cone constraints, (nel, 3, 3) [Pa]; None if not available
    live_power, dead_power   P_live(u) (= 1) and P_dead(u) [W/m]
    gap             primal_objective − dual_objective
    status, solver, primal_objective, dual_objective, iterations: the solve's
    (``solver.SolveRecord``); times: seconds per stage (mesh, assembly, build, solve, total);
    sizes: triangles, dofs, free unknowns, variables, constraint rows, nonzeros, attempts
    """

    multiplier: float
    u: np.ndarray
    velocity: np.ndarray
    dissipation: np.ndarray
    interface_dissipation: dict
    strain_rate: np.ndarray
    intensity: np.ndarray
    stress: np.ndarray | None
    live_power: float
    dead_power: float
    gap: float
    mesh: object = None
    regions: dict = field(default_factory=dict)

    @property
    def total_dissipation(self) -> float:
        return float(self.dissipation.sum()
                     + sum(np.sum(v) for v in self.interface_dissipation.values()))

    def to_meshio(self):
        """meshio.Mesh (triangles) with point data "velocity" and cell data "dissipation",
        "intensity", "region" (index into sorted region names) and "stress": the mean per
        triangle as a 3×3 tensor [Pa], 9 components row by row, which ParaView reads as a
        tensor. The section plane is the file's X–Y plane (X = x, Y = z, Z out of plane), so
        the tensor is [[σ_x, τ_xz, 0], [τ_xz, σ_z, 0], [0, 0, 0]] (plane, out-of-plane 0)."""
        import meshio

        m = self.mesh
        pts = np.c_[m.p.T, np.zeros(m.p.shape[1])]
        vel = np.c_[self.velocity, np.zeros(len(self.velocity))]
        region = np.full(m.t.shape[1], -1, int)
        for i, name in enumerate(sorted(self.regions)):
            region[self.regions[name]] = i
        cell_data = {"dissipation": [self.dissipation], "intensity": [self.intensity],
                     "region": [region]}
        if self.stress is not None:
            cell_data["stress"] = [stress_tensor(self.stress.mean(axis=1))]
        return meshio.Mesh(pts, [("triangle", m.t.T)], point_data={"velocity": vel},
                           cell_data=cell_data)
