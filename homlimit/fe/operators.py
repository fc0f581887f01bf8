"""Finite-element operators of the kinematic approach (scikit-fem, scipy.sparse; no optimisation).

Velocities v = (v_x, v_z) are continuous and quadratic on triangles (P2). Their strain rate

    d = (d_xx, d_zz, γ_xz) = (∂v_x/∂x, ∂v_z/∂z, ∂v_x/∂z + ∂v_z/∂x)

is linear on each triangle, so it is fixed by its values at the three vertices. Every operator
here is one sparse matrix acting on the global DOF vector u of ``p2_basis(mesh)``:

- ``strain_rate_operator``: d at the 3 vertices of every triangle, rows (triangle, vertex, comp),
  with the quadrature weights area/3 of the vertex rule (exact for linear integrands);
- ``body_force_power`` / ``traction_power``: the power ∫ f·v of a body force on a region / of a
  surface traction on a tagged boundary, as a vector F with P = F·u;
- ``support_dofs``: the DOFs fixed by a support on a tagged boundary (all or one component);
- ``boundary_jump_operator``: the jump [v] = v − 0 across a tagged boundary to a rigid, fixed
  ground, as strain rates sym([v] ⊗ n) at the three Bernstein control points of every facet
  (the quadratic jump along an edge lies in the convex hull of its control points).

Built with numpy broadcasting over all triangles at once: no Python loop over elements or DOFs.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
from skfem import (
    Basis,
    CellBasis,
    ElementTriP2,
    ElementVector,
    FacetBasis,
    LinearForm,
    MeshTri,
    asm,
)

from ..errors import ParameterError, check_choice
from .mesh import element_areas

__all__ = [
    "p2_basis",
    "strain_rate_operator",
    "vertex_points",
    "body_force_power",
    "traction_power",
    "support_dofs",
    "boundary_jump_operator",
    "element_areas",
    "COMPONENTS",
]

#: component names of a support: "x" fixes v_x, "z" fixes v_z, "xz" (or "fixed") both
COMPONENTS = {"x": ("u^1",), "z": ("u^2",), "xz": ("u^1", "u^2"), "fixed": ("u^1", "u^2")}

# reference-triangle vertices as quadrature points: the vertex rule, weights 1/6 each
_VERTEX_RULE = (np.array([[0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]), np.full(3, 1.0 / 6.0))


_INTORDER = 4  # exact for the P2 load integrals on straight triangles


def p2_basis(mesh: MeshTri, intorder: int = _INTORDER) -> CellBasis:
    """The global P2 vector basis; DOF numbering of every operator of this module."""
    return Basis(mesh, ElementVector(ElementTriP2()), intorder=intorder)


def vertex_points(mesh: MeshTri) -> np.ndarray:
    """Coordinates of the strain-rate points (triangle, vertex), shape (3 nel, 2)."""
    return mesh.p[:, mesh.t].transpose(2, 1, 0).reshape(-1, 2)


def strain_rate_operator(basis: CellBasis) -> tuple[sp.csr_matrix, np.ndarray]:
    """(B, w): d = B u at the 3 vertices of every triangle, and the vertex-rule weights.

    Row 3 p + j holds component j (d_xx, d_zz, γ_xz) at point p = 3 e + k, vertex k of triangle
    e (the order of ``mesh.t``). w[p] = area_e / 3, so Σ_p w_p g(d_p) integrates any g that is
    linear on triangles exactly, and is an upper bound of ∫ g for convex positively homogeneous
    g (the dissipation) because g(d) ≤ Σ_k φ_k g(d_k) pointwise with φ_k the P1 hat functions.
    """
    mesh = basis.mesh
    vb = CellBasis(mesh, basis.elem, quadrature=_VERTEX_RULE)
    nel, nb = mesh.t.shape[1], vb.Nbfun
    # grad[i] has shape (2 components, 2 derivatives, nel, 3 vertices)
    g = np.stack([vb.basis[i][0].grad for i in range(nb)])          # (nb, 2, 2, nel, 3)
    d = np.stack([g[:, 0, 0], g[:, 1, 1], g[:, 0, 1] + g[:, 1, 0]])  # (3 comps, nb, nel, 3)
    vals = d.transpose(2, 3, 0, 1)                                   # (nel, vertex, comp, nb)
    rows = np.broadcast_to(np.arange(9 * nel).reshape(nel, 3, 3, 1), vals.shape)
    cols = np.broadcast_to(vb.element_dofs.T.reshape(nel, 1, 1, nb), vals.shape)
    B = sp.csr_matrix((vals.ravel(), (rows.ravel(), cols.ravel())), shape=(9 * nel, basis.N))
    B.eliminate_zeros()
    w = np.repeat(element_areas(mesh) / 3.0, 3)
    return B, w


def _force_form(fx: float, fz: float) -> LinearForm:
    @LinearForm
    def power(v, w):
        return fx * v[0] + fz * v[1]
    return power


def body_force_power(basis: CellBasis, region: str | None, force) -> np.ndarray:
    """F with F·u = ∫_region f·v dA for a uniform body force f = (f_x, f_z) [N/m³].

    ``region`` names a subdomain of the mesh, or None for the whole mesh.
    """
    fx, fz = (float(c) for c in force)
    mesh = basis.mesh
    if region is None:
        sub = basis
    else:
        elems = _named(mesh.subdomains, region, "region")
        sub = CellBasis(mesh, basis.elem, elements=elems, intorder=_INTORDER)
    return asm(_force_form(fx, fz), sub)


def traction_power(basis: CellBasis, boundary: str, traction) -> np.ndarray:
    """F with F·u = ∫_boundary t·v ds for a uniform surface traction t = (t_x, t_z) [N/m²]."""
    tx, tz = (float(c) for c in traction)
    facets = _named(basis.mesh.boundaries, boundary, "boundary")
    fb = FacetBasis(basis.mesh, basis.elem, facets=facets, intorder=_INTORDER)
    return asm(_force_form(tx, tz), fb)


def support_dofs(basis: CellBasis, boundary: str, components: str = "fixed") -> np.ndarray:
    """Global DOFs fixed by a support on ``boundary``: components "fixed"/"xz", "x" or "z"."""
    check_choice("support components", components, sorted(COMPONENTS))
    facets = _named(basis.mesh.boundaries, boundary, "boundary")
    return np.unique(basis.get_dofs(facets).all(list(COMPONENTS[components])))


def boundary_jump_operator(basis: CellBasis, boundary: str) -> tuple[sp.csr_matrix, np.ndarray]:
    """(J, w): the jump to a fixed ground across ``boundary`` as strain rates sym([v] ⊗ n).

    [v] = v (the ground does not move) and n is the unit normal pointing from the ground into
    the body (minus the outward normal), so opening is d_nn > 0. Along a facet of length L the
    jump is quadratic; with end values v0, v1 and mid-edge value vm its Bernstein control
    points are v0, 2 vm − (v0 + v1)/2, v1. A convex cone holds on the whole edge if it holds at
    the control points, and ∫ π([v]) ≤ (L/3) Σ π(control point) since π is sublinear and each
    Bernstein quadratic integrates to L/3. Rows: 3 q + j, component j at control point
    q = 3 f + k of boundary facet f; w[q] = L_f / 3.
    """
    mesh = basis.mesh
    facets = _named(mesh.boundaries, boundary, "boundary")
    nodes = mesh.facets[:, facets]                                   # (2, nf)
    tang = mesh.p[:, nodes[1]] - mesh.p[:, nodes[0]]
    length = np.linalg.norm(tang, axis=0)
    n_out = np.stack([tang[1], -tang[0]]) / length
    # orient outward: away from the centroid of the element owning the facet
    elem = mesh.f2t[0, facets]
    c = mesh.p[:, mesh.t[:, elem]].mean(axis=1)
    flip = np.sum(n_out * (mesh.p[:, nodes[0]] - c), axis=0) < 0
    n = np.where(flip, n_out, -n_out)                                # inward normal
    nf = facets.size
    # velocity DOFs (component, control point) and Bernstein coefficients
    v0 = basis.nodal_dofs[:, nodes[0]]                               # (2, nf)
    v1 = basis.nodal_dofs[:, nodes[1]]
    vm = basis.facet_dofs[:, facets]
    dofs = np.stack([v0, vm, v1], axis=-1)                           # (2 comp, nf, 3 dofs)
    coef = np.array([[1.0, 0.0, 0.0], [-0.5, 2.0, -0.5], [0.0, 0.0, 1.0]])  # (q, dof)
    # sym([v] ⊗ n) = (v_x n_x, v_z n_z, v_x n_z + v_z n_x): weight of (out comp j, vel comp i)
    nx, nz = n
    S = np.stack([np.stack([nx, 0 * nx]), np.stack([0 * nz, nz]), np.stack([nz, nx])])  # (j,i,nf)
    vals = (S[:, :, :, None, None] * coef[None, None, None, :, :])   # (j, i, nf, q, dof)
    vals = vals.transpose(2, 3, 0, 1, 4)                             # (nf, q, j, i, dof)
    rows = np.broadcast_to(np.arange(9 * nf).reshape(nf, 3, 3, 1, 1), vals.shape)
    cols = np.broadcast_to(dofs.transpose(1, 0, 2).reshape(nf, 1, 1, 2, 3), vals.shape)
    J = sp.csr_matrix((vals.ravel(), (rows.ravel(), cols.ravel())), shape=(9 * nf, basis.N))
    J.eliminate_zeros()
    return J, np.repeat(length / 3.0, 3)


def _named(table, name: str, kind: str) -> np.ndarray:
    if not table or name not in table:
        have = sorted(table) if table else []
        raise ParameterError(f"{kind} = {name!r} is out of range: the mesh has {kind}s {have}")
    return np.asarray(table[name])
