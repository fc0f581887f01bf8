"""Static (lower-bound) finite-element limit analysis with linear equilibrium triangles.

The stress field σ = (σ_x, σ_z, τ_xz) is linear on each triangle and discontinuous between
triangles: three stress vectors per triangle, one at each vertex. A field is *statically
admissible* for the live multiplier λ when

- equilibrium holds inside every triangle (div σ is constant there, so two equations each):
      ∂σ_x/∂x + ∂τ_xz/∂z + λ b_x + b⁰_x = 0,   ∂τ_xz/∂x + ∂σ_z/∂z + λ b_z + b⁰_z = 0,
  with b the live and b⁰ the dead body force per unit volume [N/m³];
- the traction t = σ n is continuous across every interior edge (t is linear along an edge,
  so equality at both ends: four equations per edge);
- t = λ t_live + t_dead on free boundaries, for every traction component whose displacement
  component is not supported (a roller u_x = 0 leaves t_x free and imposes t_z);
- σ ∈ G at the three vertices of every triangle, which for a convex G and a linear σ means
  σ ∈ G everywhere in the triangle;
- regions of ``strength.Rigid`` carry no stress: each connected one is a body whose resultant
  force and moment vanish (body forces, boundary tractions, the tractions of the neighbouring
  triangles, reactions, and joint forces including concentrated ones at the joint's ends).

By the static theorem of limit analysis the largest such λ, λ⁻, is a lower bound of the
collapse multiplier (for the discrete problem as posed: see docs/static.md on truncated
domains). The program is a conic program, max λ over (σ, λ, y) with the strength condition
written through each domain's ``static_cone()`` (σ ∈ G ⇔ ∃y: Aσ + Dy + e ∈ K), assembled
here directly as one sparse matrix for Clarabel: no per-element Python objects and no loop
over elements or edges.
"""

from __future__ import annotations

import dataclasses
import time
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp

from ..errors import ParameterError, SolverError, check_range
from .strength import ConicBlock, Rigid, StrengthDomain

__all__ = [
    "StaticSolution",
    "attach_cell_fields",
    "solve_static",
    "static_from_problem",
    "triangle_gradients",
    "edge_tables",
]

Traction = np.ndarray | tuple | Callable[[np.ndarray, np.ndarray], np.ndarray]

# Clarabel settings as in the kinematic program (kinematic.SolverOptions): 'qdldl', tolerance
# 1e-9 for a linear program and 1e-7 with second-order cones (tighter stalls). The equilibrium
# programs are more degenerate (many optimal stress fields away from the mechanism), so a
# static regularisation 1e-7 (Clarabel's default 1e-8 stalled on most Prandtl meshes) comes
# first; a stalled solve is retried with 1e-6, then the other factorisation, then Clarabel's
# defaults. Above FAER_ABOVE unknowns faer on one thread factors faster than qdldl (measured,
# docs/static.md: 7091 triangles 26 s against 45 s; a tie near 4 000 triangles; two threads
# are slower on a 2-core machine).
CLARABEL_DEFAULTS = {"direct_solve_method": "qdldl", "max_iter": 300}
FAER_ABOVE = 30_000
RETRIES = ({"static_regularization_constant": 1e-7}, {"static_regularization_constant": 1e-6},
           "other factorisation", {})


def _clarabel_opts(n_unknowns: int, tol: float, *overrides) -> dict:
    """Clarabel settings: size-dependent defaults, tolerance ``tol``, then ``overrides``."""
    opts = {**clarabel_defaults(n_unknowns), "tol_gap_abs": tol, "tol_gap_rel": tol,
            "tol_feas": tol}
    for o in overrides:
        opts.update(o or {})
    return opts


def clarabel_defaults(n_unknowns: int) -> dict:
    """Clarabel settings for a static program of ``n_unknowns`` unknowns (before overrides)."""
    if n_unknowns > FAER_ABOVE:
        return {**CLARABEL_DEFAULTS, "direct_solve_method": "faer", "max_threads": 1}
    return dict(CLARABEL_DEFAULTS)
_STALLED = ("AlmostSolved", "NumericalError", "InsufficientProgress", "MaxIterations")


# --------------------------------------------------------------------------- geometry


def triangle_gradients(p: np.ndarray, t: np.ndarray):
    """Gradients of the three P1 shape functions and the area of every triangle.

    Returns (dNdx, dNdz, area), the first two of shape (3, nt): ∇N_i = (z_j − z_k, x_k − x_j)/2A
    for (i, j, k) cyclic, with the signed area A (either orientation works).
    """
    x, z = p[0, t], p[1, t]
    area2 = (x[1] - x[0]) * (z[2] - z[0]) - (x[2] - x[0]) * (z[1] - z[0])
    tiny = np.abs(area2) <= 1e-14 * np.ptp(p, axis=1).max() ** 2
    if np.any(tiny):
        bad = np.flatnonzero(tiny)
        raise ParameterError(f"mesh has {bad.size} degenerate triangle(s) of zero area "
                             f"(first: element {bad[0]}); allowed: triangles of positive area")
    dNdx = np.stack([z[1] - z[2], z[2] - z[0], z[0] - z[1]]) / area2
    dNdz = np.stack([x[2] - x[1], x[0] - x[2], x[1] - x[0]]) / area2
    return dNdx, dNdz, 0.5 * np.abs(area2)


def edge_tables(mesh):
    """Edge data of a skfem MeshTri: endpoints, unit normals, adjacent triangles, local indices.

    Returns a dict with ``ends`` (2, nf) node indices, ``n`` (2, nf) unit normals (outward from
    ``tri[0]`` on boundary edges), ``tri`` (2, nf) adjacent triangles (−1 outside), ``loc``
    (2 sides, 2 ends, nf) local vertex index of each end in each adjacent triangle (−1 outside),
    ``length`` (nf,) and ``interior`` (nf,) bool.
    """
    p, t = mesh.p, mesh.t
    ends = mesh.facets
    tri = mesh.f2t
    tang = p[:, ends[1]] - p[:, ends[0]]
    length = np.hypot(tang[0], tang[1])
    n = np.stack([tang[1], -tang[0]]) / length
    # orient every normal outward from tri[0]
    mid = 0.5 * (p[:, ends[0]] + p[:, ends[1]])
    cen = p[:, t[:, tri[0]]].mean(axis=1)
    flip = np.einsum("ij,ij->j", n, mid - cen) < 0
    n[:, flip] *= -1
    loc = np.full((2, 2, ends.shape[1]), -1, dtype=np.int64)
    for side in (0, 1):
        has = tri[side] >= 0
        tt = t[:, tri[side, has]]
        for k in (0, 1):
            loc[side, k, has] = np.argmax(tt == ends[k, has], axis=0)
    return {"ends": ends, "n": n, "tri": tri, "loc": loc, "length": length,
            "interior": tri[1] >= 0}


# --------------------------------------------------------------------------- inputs


_SUPPORTS = {"fixed": (True, True), "xz": (True, True), "x": (True, False), "z": (False, True),
             "free": (False, False)}


def _support_flags(value, tag: str) -> tuple[bool, bool]:
    """(u_x fixed, u_z fixed) from 'fixed' | 'x' | 'z' | 'free' or a pair of bools."""
    if isinstance(value, str):
        if value not in _SUPPORTS:
            raise ParameterError(f"supports[{tag!r}] = {value!r} is not a support: allowed "
                                 f"{sorted(_SUPPORTS)} or a pair (fix_x, fix_z)")
        return _SUPPORTS[value]
    try:
        fx, fz = value
    except (TypeError, ValueError):
        raise ParameterError(f"supports[{tag!r}] = {value!r} is not a support: allowed "
                             f"{sorted(_SUPPORTS)} or a pair (fix_x, fix_z)") from None
    return bool(fx), bool(fz)


def _region_values(mesh, spec, name: str, shape: tuple, nt: int) -> np.ndarray:
    """Per-element values from a constant, a {region: value} mapping, or an (nt, ...) array."""
    out = np.zeros((nt,) + shape)
    if spec is None:
        return out
    if isinstance(spec, Mapping):
        subs = getattr(mesh, "subdomains", None) or {}
        for reg, val in spec.items():
            if reg not in subs:
                raise ParameterError(f"{name}[{reg!r}]: no region {reg!r} in the mesh; allowed "
                                     f"regions: {sorted(subs)}")
            out[subs[reg]] = np.broadcast_to(np.asarray(val, float), shape)
    elif (arr := np.asarray(spec, float)).shape in (shape, (nt,) + shape):
        out[:] = arr
    else:
        raise ParameterError(f"{name} has shape {arr.shape}; allowed {shape}, ({nt},)+{shape} "
                             f"or a mapping region -> value")
    if not np.all(np.isfinite(out)):
        raise ParameterError(f"{name} has non-finite entries; allowed: finite numbers")
    return out


def _domain_per_element(mesh, domains, nt: int):
    """List of (StrengthDomain, element indices) covering every element exactly once."""
    if isinstance(domains, StrengthDomain):
        return [(domains, np.arange(nt))]
    if not isinstance(domains, Mapping) or not domains:
        raise ParameterError(f"domains = {domains!r} is not a strength domain: allowed a "
                             f"StrengthDomain or a mapping region -> StrengthDomain")
    subs = getattr(mesh, "subdomains", None) or {}
    owner = np.full(nt, -1)
    out = []
    for k, (reg, dom) in enumerate(domains.items()):
        if reg not in subs:
            raise ParameterError(f"domains[{reg!r}]: no region {reg!r} in the mesh; allowed "
                                 f"regions: {sorted(subs)}")
        if not isinstance(dom, StrengthDomain):
            raise ParameterError(f"domains[{reg!r}] = {dom!r} is not a StrengthDomain")
        els = np.asarray(subs[reg])
        if np.any(owner[els] >= 0):
            raise ParameterError(f"domains[{reg!r}]: region overlaps another region")
        owner[els] = k
        out.append((dom, els))
    if np.any(owner < 0):
        raise ParameterError(f"domains cover {np.sum(owner >= 0)} of {nt} elements; allowed: "
                             f"regions covering the whole mesh, got {sorted(domains)}")
    return out


def _edge_traction(spec: Traction, xy: np.ndarray, tag: str) -> np.ndarray:
    """Traction (2, 2, m) at both ends (axis 1) of m boundary edges from a vector or callable."""
    if callable(spec):
        out = np.stack([np.asarray(spec(xy[0, k], xy[1, k]), float).reshape(2, -1)
                        * np.ones((1, xy.shape[2])) for k in (0, 1)], axis=1)
    else:
        v = np.asarray(spec, float)
        if v.shape != (2,):
            raise ParameterError(f"traction[{tag!r}] = {spec!r} has shape {v.shape}; allowed a "
                                 f"vector (t_x, t_z) in Pa or a callable (x, z) -> (2, n)")
        out = np.broadcast_to(v[:, None, None], (2, 2, xy.shape[2])).copy()
    if not np.all(np.isfinite(out)):
        raise ParameterError(f"traction[{tag!r}] has non-finite values; allowed: finite Pa")
    return out


# --------------------------------------------------------------------------- conic blocks


def _stack_block(block: ConicBlock, cols: np.ndarray, aux0: int):
    """Sparse rows of one ConicBlock repeated at n points, grouped by cone kind.

    ``cols`` (n, 3) are the columns of σ at each point; the auxiliary variables of point k take
    columns aux0 + k·n_aux + j. Returns {kind: ((values, rows, cols, n_rows), e)} for kind in
    'eq', 'lin', 'soc' (COO pieces of M, rows local to the kind), with M x + e ∈ K row-wise;
    SOC rows stay point-major, so the cones are ``block.soc`` × n.
    """
    n = cols.shape[0]
    m, na = block.n_rows, block.n_aux
    full = np.hstack([block.A, block.D])  # (m, 3 + na)
    r, c = np.nonzero(full)
    v = full[r, c]
    # replicate over points: row (k, r), column σ or aux of point k
    K = np.repeat(np.arange(n), r.size)
    R = np.tile(r, n)
    C = np.tile(c, n)
    V = np.tile(v, n)
    col = np.where(C < 3, cols[K, np.minimum(C, 2)], aux0 + K * na + (C - 3))
    out = {}
    bounds = {"eq": (0, block.n_eq), "lin": (block.n_eq, block.n_eq + block.n_lin),
              "soc": (block.n_eq + block.n_lin, m)}
    for kind, (lo, hi) in bounds.items():
        width = hi - lo
        if width == 0:
            continue
        sel = (R >= lo) & (R < hi)
        rows = K[sel] * width + (R[sel] - lo)
        out[kind] = ((V[sel], rows, col[sel], n * width), np.tile(block.e[lo:hi], n))
    return out


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


def _independent_vertex_rows(R: sp.csr_matrix, row_node: np.ndarray, t: np.ndarray,
                             tol: float = 1e-6) -> np.ndarray:
    """Mask of a maximal independent subset of vertex-local rows (greedy, batched Gram–Schmidt).

    Every row of R involves only the stresses at one mesh node (``row_node``) of the triangles
    around it, so dependencies are local: per node the rows are tested in order against the span
    of the rows kept before them. Nodes are batched by their number of triangles (a loop over a
    handful of group sizes and local row positions, not over nodes or elements).
    """
    R = R.tocoo()
    nrow = R.shape[0]
    keep = np.ones(nrow, bool)
    if nrow == 0:
        return keep
    nn = t.max() + 1
    inc_node = t.T.reshape(-1)  # incidence 3T + i → node t[i, T]
    order = np.argsort(inc_node, kind="stable")
    ntri = np.bincount(inc_node, minlength=nn)
    start = np.concatenate([[0], np.cumsum(ntri)[:-1]])
    slot = np.empty_like(order)
    slot[order] = np.arange(order.size) - start[inc_node[order]]
    lcol = 3 * slot[R.col // 3] + R.col % 3
    # local row position within its node
    rorder = np.argsort(row_node, kind="stable")
    nrows_node = np.bincount(row_node, minlength=nn)
    rstart = np.concatenate([[0], np.cumsum(nrows_node)[:-1]])
    lrow = np.empty(nrow, int)
    lrow[rorder] = np.arange(nrow) - rstart[row_node[rorder]]
    for k in np.unique(ntri[row_node]):
        nodes = np.flatnonzero((ntri == k) & (nrows_node > 0))
        gid = np.full(nn, -1)
        gid[nodes] = np.arange(nodes.size)
        rmax = nrows_node[nodes].max()
        B = np.zeros((nodes.size, rmax, 3 * k))
        sel = gid[row_node[R.row]] >= 0
        np.add.at(B, (gid[row_node[R.row[sel]]], lrow[R.row[sel]], lcol[sel]), R.data[sel])
        norm = np.linalg.norm(B, axis=2)
        Q = np.zeros((nodes.size, 3 * k, 3 * k))  # accepted orthonormal rows (as columns)
        nq = np.zeros(nodes.size, int)
        ok = np.zeros((nodes.size, rmax), bool)
        for j in range(rmax):
            r = B[:, j, :] / np.where(norm[:, j] > 0, norm[:, j], 1.0)[:, None]
            for _ in range(2):  # Gram–Schmidt twice for orthogonality
                r = r - np.einsum("gcq,gq->gc", Q, np.einsum("gcq,gc->gq", Q, r))
            res = np.linalg.norm(r, axis=1)
            acc = (res > tol) & (norm[:, j] > 0)
            g = np.flatnonzero(acc)
            Q[g, :, np.minimum(nq[g], 3 * k - 1)] = r[g] / res[g, None]
            nq[g] += 1
            ok[:, j] = acc | (norm[:, j] == 0)
        rows = np.flatnonzero(gid[row_node] >= 0)
        keep[rows] = ok[gid[row_node[rows]], lrow[rows]]
    # rows with no stress entry (pure load rows) are kept; the solver judges them
    keep |= np.bincount(R.row, minlength=nrow) == 0
    return keep


# --------------------------------------------------------------------------- rigid bodies


def rigid_bodies(E: dict, rigid: np.ndarray) -> tuple[np.ndarray, int]:
    """Label the connected rigid regions: (body index per element, −1 if not rigid; count).

    Rigid triangles sharing an edge move together (the kinematic program's velocity is
    continuous), so each connected set of them is one body.
    """
    from scipy.sparse.csgraph import connected_components

    nt = rigid.size
    both = E["interior"] & rigid[E["tri"][0]] & rigid[np.maximum(E["tri"][1], 0)]
    a, b = E["tri"][0, both], E["tri"][1, both]
    graph = sp.coo_matrix((np.ones(a.size), (a, b)), shape=(nt, nt))
    _, label = connected_components(graph, directed=False)
    body = np.full(nt, -1)
    uniq, body[rigid] = np.unique(label[rigid], return_inverse=True)
    return body, uniq.size


class _NodalForces:
    """Forces on rigid bodies at points, gathered as sparse terms; 3 equilibrium rows per body.

    A force component is Σ coefficient × unknown + constant (in units of s_ref × length). A
    traction linear along an edge acts on the body as the consistent end forces
    L (t_k/3 + t_j/6) at end k (exact resultant and moment); ``lumped`` puts L t_k/2 at end k
    instead: concentrated forces, exact for a joint whose traction set is a cone (no cohesion,
    no tension), as at the toe of a tilting block.
    """

    def __init__(self, p, t, E, body, n_body, area):
        self.p, self.E, self.body, self.n_body = p, E, body, n_body
        self.terms, self.consts = [], []
        rig = np.flatnonzero(body >= 0)
        w = np.bincount(body[rig], area[rig], n_body)
        cen = p[:, t[:, rig]].mean(axis=1)
        self.centre = np.stack([np.bincount(body[rig], area[rig] * cen[c], n_body) / w
                                for c in (0, 1)]) if n_body else np.zeros((2, 0))
        self.ell = np.sqrt(w)

    def add(self, b, xy, comp, terms, const=None):
        """Force component ``comp`` at points xy (2, m) on bodies b (m,): Σ col·val + const."""
        for col, val in terms:
            self.terms.append((b, xy, comp, np.asarray(col), np.asarray(val, float)))
        if const is not None:
            self.consts.append((b, xy, comp, np.asarray(const, float)))

    def traction(self, f, k, comp, terms, const=None, lumped=False, body_side=0):
        """The traction at end k of edges f (value Σ col·val + const) on the body of side
        ``body_side``, spread to the edge's two ends."""
        if f.size == 0:
            return
        E = self.E
        L = E["length"][f]
        b = self.body[E["tri"][body_side, f]]
        share = ((k, 0.5),) if lumped else ((k, 1.0 / 3.0), (1 - k, 1.0 / 6.0))
        for end, w in share:
            xy = self.p[:, E["ends"][end, f]]
            self.add(b, xy, comp, [(c, w * L * v) for c, v in terms],
                     None if const is None else w * L * const)

    def equilibrium_rows(self, n_var: int):
        """(M, e) with M x + e = 0: ΣF_x, ΣF_z and Σ r × F about each body's centroid, divided
        by the body's size ℓ = √area (ℓ² for the moment) so that the coefficients are O(1)."""
        nb, ell = self.n_body, self.ell

        def rows(B, X, C, V):
            r = X - self.centre[:, B]
            arm = np.where(C == 0, -r[1], r[0])  # r × F = r_x F_z − r_z F_x
            return (np.r_[3 * B + C, 3 * B + 2],
                    np.r_[V / ell[B], V * arm / ell[B] ** 2])

        cat = [np.concatenate(v, axis=-1) for v in zip(*[
            (b, xy, np.full(b.size, c), np.broadcast_to(col, b.shape), val)
            for b, xy, c, col, val in self.terms])]
        B, X, C, COL, V = cat
        R, VV = rows(B, X, C, V)
        M = sp.coo_matrix((VV, (R, np.r_[COL, COL])), shape=(3 * nb, n_var)).tocsr()
        e = np.zeros(3 * nb)
        if self.consts:
            B, X, C, V = [np.concatenate(v, axis=-1) for v in zip(*[
                (b, xy, np.full(b.size, c), val) for b, xy, c, val in self.consts])]
            R, VV = rows(B, X, C, V)
            e = np.bincount(R, VV, 3 * nb)
        return M, e


# --------------------------------------------------------------------------- solution


@dataclass
class StaticSolution:
    """Result of the lower-bound program.

    ``multiplier`` is λ⁻; ``stress`` (nt, 3, 3) is σ at [element, local vertex, component] with
    components (σ_x, σ_z, τ_xz) in Pa; ``active`` (nt, 3) is the index of the active facet of the
    element's strength domain at each vertex (rows of its static cone counted as 'eq' rows
    skipped, each linear row one facet, each second-order cone one facet), or −1 where no facet
    is active within ``active_tol``. ``rigid`` (nt,) marks elements of rigid regions
    (``strength.Rigid``): each connected one is a body in equilibrium as a whole, its stress is
    NaN.
    """

    multiplier: float
    stress: np.ndarray
    active: np.ndarray
    mesh: object
    status: str
    primal_objective: float
    dual_objective: float
    iterations: int
    sizes: dict = field(default_factory=dict)
    timings: dict = field(default_factory=dict)
    rigid: np.ndarray | None = None

    @property
    def gap(self) -> float:
        """Clarabel's absolute primal–dual objective gap (scaled units)."""
        return abs(self.primal_objective - self.dual_objective)

    def element_areas(self) -> np.ndarray:
        """Triangle areas (nt,) [m²]."""
        return triangle_gradients(self.mesh.p, self.mesh.t)[2]

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

    def write(self, path) -> None:
        """Write ``to_meshio()`` to ``path`` (any meshio format) whole or not at all."""
        import meshio

        from .._io import atomic_path

        with atomic_path(path) as tmp:
            meshio.write(tmp, self.to_meshio())


# --------------------------------------------------------------------------- solvers


def _solve_direct(M, e, q, cones, tol, retries, solver_settings, verbose) -> dict:
    """Clarabel on min qᵀx s.t. M x + e ∈ K, i.e. A x + s = b, s ∈ K with A = −M, b = e; a
    stalled solve is retried with the settings of ``RETRIES``."""
    import clarabel

    P = sp.csc_matrix((q.size, q.size))
    attempts = []
    for retry in RETRIES if retries else RETRIES[:1]:
        if isinstance(retry, str):  # the other factorisation
            method = clarabel_defaults(q.size)["direct_solve_method"]
            retry = {"direct_solve_method": "qdldl" if method == "faer" else "faer",
                     "max_threads": 1}
        opts = _clarabel_opts(q.size, tol, retry, solver_settings)
        settings = clarabel.DefaultSettings()
        settings.verbose = bool(verbose)
        for key, val in opts.items():
            setattr(settings, key, val)
        res = clarabel.DefaultSolver(P, q, -M, e, cones, settings).solve()
        status = str(res.status).split(".")[-1]
        attempts.append((retry, status, int(res.iterations)))
        if status not in _STALLED:
            break
    return {"x": np.asarray(res.x), "status": status,
            "obj": float(res.obj_val), "obj_dual": float(res.obj_val_dual),
            "iterations": int(res.iterations), "attempts": attempts}


_CVXPY_STATUS = {"optimal": "Solved", "optimal_inaccurate": "AlmostSolved",
                 "infeasible": "PrimalInfeasible", "infeasible_inaccurate": "PrimalInfeasible",
                 "unbounded": "DualInfeasible", "unbounded_inaccurate": "DualInfeasible"}


def _solve_cvxpy(M, e, q, layout, tol, solver, solver_settings, verbose) -> dict:
    """The same program through cvxpy: M x + e = 0 on the first n_zero rows, >= 0 on the next
    n_lin, then one second-order cone per entry of ``socs`` (cones of equal size batched)."""
    import cvxpy as cp

    n_zero, n_lin, socs = layout
    if socs and solver.upper() == "HIGHS":
        raise ParameterError(f"cvxpy_solver = {solver!r} is out of range for a program with "
                             f"{len(socs)} second-order cones: allowed a conic solver "
                             f"('CLARABEL', 'SCS', ...)")
    M = sp.csr_matrix(M)
    x = cp.Variable(q.size)
    cons = [M[:n_zero] @ x + e[:n_zero] == 0]
    if n_lin:
        cons.append(M[n_zero:n_zero + n_lin] @ x + e[n_zero:n_zero + n_lin] >= 0)
    dims = np.asarray(socs, int)
    start = n_zero + n_lin + np.r_[0, np.cumsum(dims)[:-1]].astype(int)
    for d in np.unique(dims):
        rows = start[dims == d][:, None] + np.arange(d)  # (cones, d)
        t = M[rows[:, 0]] @ x + e[rows[:, 0]]
        X = cp.vstack([M[rows[:, j]] @ x + e[rows[:, j]] for j in range(1, d)])
        cons.append(cp.SOC(t, X, axis=0))
    prob = cp.Problem(cp.Minimize(q @ x), cons)
    if solver.upper() == "CLARABEL":
        opts = _clarabel_opts(q.size, tol, RETRIES[0], solver_settings)
    else:
        opts = dict(solver_settings or {})
    try:
        prob.solve(solver=solver.upper(), verbose=bool(verbose), **opts)
    except cp.error.SolverError as exc:
        return {"x": None, "status": f"SolverError ({exc})", "obj": np.nan,
                "obj_dual": np.nan, "iterations": 0, "attempts": [(solver, "SolverError", 0)]}
    status = _CVXPY_STATUS.get(prob.status, str(prob.status))
    iters = int(prob.solver_stats.num_iters or 0)
    ok = x.value is not None
    return {"x": x.value if ok else None, "status": status,
            "obj": float(prob.value) if ok else np.nan, "obj_dual": np.nan,
            "iterations": iters, "attempts": [(solver, status, iters)]}


# --------------------------------------------------------------------------- the program


def solve_static(
    mesh,
    domains: StrengthDomain | Mapping[str, StrengthDomain],
    *,
    live_body=None,
    dead_body=None,
    live_traction: Mapping[str, Traction] | None = None,
    dead_traction: Mapping[str, Traction] | None = None,
    supports: Mapping[str, object] | None = None,
    interfaces: Mapping[str, StrengthDomain] | None = None,
    stress_scale: float | None = None,
    solver_settings: Mapping | None = None,
    active_tol: float = 1e-6,
    retries: bool = True,
    verbose: bool = False,
    backend: str = "direct",
    cvxpy_solver: str = "CLARABEL",
) -> StaticSolution:
    """Largest live multiplier λ⁻ carried by a statically admissible linear stress field.

    mesh : skfem.MeshTri with ``subdomains`` (region → elements) and ``boundaries``
        (tag → facets).
    domains : one StrengthDomain, or region → StrengthDomain covering every element.
    live_body, dead_body : body force per unit volume (b_x, b_z) [N/m³]; a vector, an
        (nt, 2) array, or region → vector (e.g. self-weight ``{"wall": (0, -γ g)}``).
    live_traction, dead_traction : boundary tag → traction (t_x, t_z) [Pa] (a vector or a
        callable (x, z) → (2, n)); boundary parts not named here and not supported are free.
    supports : boundary tag → 'fixed' | 'x' (u_x = 0) | 'z' (u_z = 0) | 'free'; on a supported
        component the traction is unknown (no condition), on the others it is prescribed.
    interfaces : boundary tag → StrengthDomain of a joint to a fixed ground: at both ends of each
        of its edges the traction σ n must equal σ_j n for some σ_j in that domain (the static
        dual of testing the jump sym([v] ⊗ n) by the same domain in the kinematic program).
    stress_scale : reference stress [Pa] for scaling the program (default from the data).
    solver_settings : overrides of Clarabel settings (defaults ``clarabel_defaults``, tolerance
        1e-9 for a linear program, 1e-7 with second-order cones).
    retries : on a stalled solve, retry with the settings of ``RETRIES`` in turn.
    backend : "direct" (default: the program handed to Clarabel as assembled) or "cvxpy" (the
        same matrices as a cvxpy problem, the kinematic program's path; solved by
        ``cvxpy_solver``, e.g. "CLARABEL", or "HIGHS" for a linear program). Without retries;
        ``dual_objective`` is NaN there.
    """
    import clarabel

    if backend not in ("direct", "cvxpy"):
        raise ParameterError(f"backend = {backend!r} is out of range: allowed 'direct', 'cvxpy'")
    if backend == "cvxpy":
        import cvxpy as cp

        if str(cvxpy_solver).upper() not in cp.installed_solvers():
            raise ParameterError(f"cvxpy_solver = {cvxpy_solver!r} is out of range: allowed an "
                                 f"installed cvxpy solver {sorted(cp.installed_solvers())}")
    timings = {}
    t0 = time.perf_counter()
    p, t = np.asarray(mesh.p, float), np.asarray(mesh.t)
    nt = t.shape[1]
    check_range("active_tol", active_tol, 0.0, lo_open=True)
    dNdx, dNdz, area = triangle_gradients(p, t)
    parts = _domain_per_element(mesh, domains, nt)
    rigid = np.zeros(nt, bool)
    for dom, els in parts:
        rigid[els] |= isinstance(dom, Rigid)
    b_live = _region_values(mesh, live_body, "live_body", (2,), nt)
    b_dead = _region_values(mesh, dead_body, "dead_body", (2,), nt)
    bnd = getattr(mesh, "boundaries", None) or {}
    for name, spec in (("live_traction", live_traction), ("dead_traction", dead_traction),
                       ("supports", supports), ("interfaces", interfaces)):
        for tag in (spec or {}):
            if tag not in bnd:
                raise ParameterError(f"{name}[{tag!r}]: no boundary {tag!r} in the mesh; "
                                     f"allowed tags: {sorted(bnd)}")
    E = edge_tables(mesh)
    nf = E["ends"].shape[1]
    body, n_body = rigid_bodies(E, rigid)
    side_rigid = np.stack([rigid[E["tri"][0]], rigid[np.maximum(E["tri"][1], 0)] & E["interior"]])
    ends_xy = p[:, E["ends"]]  # (2 coords, 2 ends, nf)

    # prescribed tractions and support flags per edge
    t_live = np.zeros((2, 2, nf))
    t_dead = np.zeros((2, 2, nf))
    for spec, acc in ((live_traction, t_live), (dead_traction, t_dead)):
        for tag, val in (spec or {}).items():
            f = np.asarray(bnd[tag])
            acc[:, :, f] += _edge_traction(val, ends_xy[:, :, f], tag)
    fix = np.zeros((2, nf), bool)
    for tag, val in (supports or {}).items():
        fx, fz = _support_flags(val, tag)
        f = np.asarray(bnd[tag])
        fix[0, f] |= fx
        fix[1, f] |= fz
    is_joint = np.zeros(nf, bool)
    for tag, dom in (interfaces or {}).items():
        if not isinstance(dom, StrengthDomain):
            raise ParameterError(f"interfaces[{tag!r}] = {dom!r} is not a StrengthDomain")
        is_joint[np.asarray(bnd[tag])] = True
    fix[:, is_joint] = True  # the joint's traction is unknown, tested by its domain below
    loaded = np.any(t_live != 0, axis=(0, 1)) | np.any(t_dead != 0, axis=(0, 1))
    if np.any(loaded & E["interior"]):
        raise ParameterError("a traction is prescribed on interior edges; allowed: tractions on "
                             "boundary tags only")

    # scaling: σ = s_ref σ̂ with s_ref the largest of strength, body force × ℓ and traction
    ell = float(np.ptp(p, axis=1).max())
    e_max = max((np.abs(dom.static_cone().e).max(initial=0.0) for dom, _ in parts), default=0.0)
    s_ref = stress_scale or max(e_max, np.abs(b_dead).max() * ell, np.abs(b_live).max() * ell,
                                np.abs(t_dead).max(initial=0.0), np.abs(t_live).max(initial=0.0))
    if not s_ref > 0:
        raise ParameterError("the problem has no load and no strength scale: allowed data with "
                             "a non-zero live load")
    s_ref = check_range("stress_scale", s_ref, 0.0, lo_open=True, unit="Pa")
    if not (np.any(b_live) or np.any(t_live)):
        raise ParameterError("no live load: allowed a non-zero live_body or live_traction")

    n_sig = 9 * nt
    lam_col = n_sig

    def sig(e, i, c):  # column of σ_c at local vertex i of element e
        return 9 * e + 3 * i + c

    eq_rows, eq_cols, eq_vals, eq_rhs = [], [], [], []  # M x + e = 0
    n_eq = 0

    # 1. equilibrium in each triangle (2 rows), each row times the triangle's size h_e so that
    #    its coefficients are O(1): h_e div σ̂ + λ h_e b/s_ref + h_e b⁰/s_ref = 0
    e_all = np.flatnonzero(~rigid)  # rigid elements carry no stress (one body each region)
    h_e = np.sqrt(2.0 * area[e_all])
    for comp, terms in ((0, ((0, dNdx), (2, dNdz))), (1, ((2, dNdx), (1, dNdz)))):
        rows = n_eq + np.arange(e_all.size)
        for c, g in terms:
            for i in range(3):
                eq_rows.append(rows)
                eq_cols.append(sig(e_all, i, c))
                eq_vals.append(h_e * g[i, e_all])
        eq_rows.append(rows)
        eq_cols.append(np.full(e_all.size, lam_col))
        eq_vals.append(h_e * b_live[e_all, comp] / s_ref)
        eq_rhs.append(h_e * b_dead[e_all, comp] / s_ref)
        n_eq += e_all.size

    # traction σ n at end k of an edge seen from side s: x: σ_x n_x + τ n_z, z: σ_z n_z + τ n_x
    nx, nz = E["n"]

    def traction_terms(side, k, comp, f):
        tri, loc = E["tri"][side, f], E["loc"][side, k, f]
        if comp == 0:
            return [(sig(tri, loc, 0), nx[f]), (sig(tri, loc, 2), nz[f])]
        return [(sig(tri, loc, 1), nz[f]), (sig(tri, loc, 2), nx[f])]

    # 2. continuity across interior edges (4 rows): t(T1) − t(T2) = 0 at both ends
    n_equil = n_eq
    row_node = []  # the mesh node of every traction row (rows 2 and 3 are vertex-local)
    fi = np.flatnonzero(E["interior"] & ~side_rigid[0] & ~side_rigid[1])
    for k in (0, 1):
        for comp in (0, 1):
            rows = n_eq + np.arange(fi.size)
            row_node.append(E["ends"][k, fi])
            for side, sgn in ((0, 1.0), (1, -1.0)):
                for col, val in traction_terms(side, k, comp, fi):
                    eq_rows.append(rows)
                    eq_cols.append(col)
                    eq_vals.append(sgn * val)
            eq_rhs.append(np.zeros(fi.size))
            n_eq += fi.size

    # 3. boundary edges, unsupported components: t = λ t_live + t_dead at both ends
    fb = np.flatnonzero(~E["interior"] & ~side_rigid[0])
    for comp in (0, 1):
        fc = fb[~fix[comp, fb]]
        for k in (0, 1):
            rows = n_eq + np.arange(fc.size)
            row_node.append(E["ends"][k, fc])
            for col, val in traction_terms(0, k, comp, fc):
                eq_rows.append(rows)
                eq_cols.append(col)
                eq_vals.append(val)
            eq_rows.append(rows)
            eq_cols.append(np.full(fc.size, lam_col))
            eq_vals.append(-t_live[comp, k, fc] / s_ref)
            eq_rhs.append(-t_dead[comp, k, fc] / s_ref)
            n_eq += fc.size

    # 4. joints to a fixed ground: σ n = σ_j n at both ends of each joint edge, σ_j ∈ G_j
    n_var = n_sig + 1
    j_rows, j_cols, j_vals, n_j = [], [], [], 0
    joint_parts = []  # (static cone block, columns (n, 3) of its σ_j)
    forces = _NodalForces(p, t, E, body, n_body, area)  # what acts on each rigid body

    def joint_terms(cols, k, comp, f):  # σ_j n at end k: x uses (σ_x, τ), z uses (σ_z, τ)
        nn_ = [(nx[f], nz[f]), (nz[f], nx[f])][comp]
        return [(cols[k, :, c], v) for c, v in zip([(0, 2), (1, 2)][comp], nn_)]

    for tag, dom in (interfaces or {}).items():
        f_all = np.asarray(bnd[tag])
        cols_all = n_var + np.arange(6 * f_all.size).reshape(2, f_all.size, 3)  # [end, edge, σ]
        n_var += 6 * f_all.size
        on_body = side_rigid[0, f_all]
        f, cols = f_all[~on_body], cols_all[:, ~on_body]
        for k in (0, 1):
            for comp in (0, 1):
                rows = n_j + np.arange(f.size)
                for col, val in traction_terms(0, k, comp, f):
                    j_rows += [rows]
                    j_cols += [col]
                    j_vals += [val]
                for col, val in joint_terms(cols, k, comp, f):
                    j_rows += [rows]
                    j_cols += [col]
                    j_vals += [-val]
                n_j += f.size
        # on a rigid body the joint acts through its traction σ_j n, linear along the edge,
        # plus concentrated end forces ρ_j n with ρ_j in the recession cone of G_j (a contact
        # force at a toe). For a cone G_j (dry joint) the concentrated part covers both.
        blk = dom.static_cone()
        cone = not np.any(blk.e)
        fb_, cb_ = f_all[on_body], cols_all[:, on_body]
        kinds = [(cb_, True)]
        if not cone:
            rec = n_var + np.arange(6 * fb_.size).reshape(2, fb_.size, 3)
            n_var += 6 * fb_.size
            kinds = [(cb_, False), (rec, True)]
            joint_parts.append((dataclasses.replace(blk, e=np.zeros_like(blk.e)),
                                rec.reshape(-1, 3)))
        for cc, lumped in kinds:
            for k in (0, 1):
                for comp in (0, 1):
                    forces.traction(fb_, k, comp, joint_terms(cc, k, comp, fb_),
                                    lumped=lumped)
        joint_parts.append((blk, cols_all.reshape(-1, 3)))

    # 4b. rigid bodies: body forces, prescribed tractions, reactions on supports, and the
    #     tractions of the continuum elements across their boundary
    if n_body:
        rb = np.flatnonzero(rigid)
        cen = p[:, t[:, rb]].mean(axis=1)
        for comp in (0, 1):
            forces.add(body[rb], cen, comp, [(np.full(rb.size, lam_col),
                                              area[rb] * b_live[rb, comp] / s_ref)],
                       area[rb] * b_dead[rb, comp] / s_ref)
        fbb = np.flatnonzero(~E["interior"] & side_rigid[0] & ~is_joint)
        for comp in (0, 1):
            fixed, free_ = fbb[fix[comp, fbb]], fbb[~fix[comp, fbb]]
            for k in (0, 1):
                forces.traction(free_, k, comp, [(np.full(free_.size, lam_col),
                                                  t_live[comp, k, free_] / s_ref)],
                                const=t_dead[comp, k, free_] / s_ref)
                reac = n_var + np.arange(fixed.size)  # free reaction at each supported end
                n_var += fixed.size
                forces.traction(fixed, k, comp, [(reac, np.ones(fixed.size))], lumped=True)
        for s_c in (0, 1):  # continuum on side s_c, body on the other: −(σ n_out) on the body
            fcb = np.flatnonzero(E["interior"] & ~side_rigid[s_c] & side_rigid[1 - s_c])
            sgn = -1.0 if s_c == 0 else 1.0
            for k in (0, 1):
                for comp in (0, 1):
                    forces.traction(fcb, k, comp, [(c, sgn * v) for c, v in
                                                   traction_terms(s_c, k, comp, fcb)],
                                    body_side=1 - s_c)

    # 5. strength at the three vertices of every triangle, domain by domain (scaled by s_ref)
    groups = {"eq": [], "lin": [], "soc": []}
    socs = []
    dom_rows = []  # per part: (elements, block, offsets of its lin/soc rows) for 'active'
    cone_parts = [(dom.static_cone(), els,
                   np.stack([sig(np.repeat(els, 3), np.tile(np.arange(3), els.size), c)
                             for c in range(3)], axis=1)) for dom, els in parts]
    cone_parts += [(blk, None, cols) for blk, cols in joint_parts]
    for blk, els, cols in cone_parts:
        blk = ConicBlock(A=blk.A, D=blk.D, e=blk.e / s_ref, n_eq=blk.n_eq, n_lin=blk.n_lin,
                         soc=blk.soc)
        st = _stack_block(blk, cols, n_var)
        n_var += cols.shape[0] * blk.n_aux
        info = {"els": els, "block": blk, "npt": cols.shape[0]}
        for kind in ("eq", "lin", "soc"):
            if kind in st:
                info[kind] = sum(g[0][3] for g in groups[kind])
                groups[kind].append(st[kind])
        socs.extend(list(blk.soc) * cols.shape[0])
        dom_rows.append(info)

    def assemble(pieces):
        rows, cols, vals, rhs, off = [], [], [], [], 0
        for (v, r, c, m), e in pieces:
            rows.append(r + off)
            cols.append(c)
            vals.append(v)
            rhs.append(e)
            off += m
        return rows, cols, vals, rhs, off

    M_eq = sp.coo_matrix((np.concatenate(eq_vals), (np.concatenate(eq_rows),
                                                    np.concatenate(eq_cols))),
                         shape=(n_eq, n_var)).tocsr()
    b_eq = np.concatenate(eq_rhs)
    # linearly dependent traction rows (e.g. where two straight lines of edges cross, or two
    # boundary edges of one triangle meet) make the KKT system singular: keep a basis per node
    keep = np.ones(n_eq, bool)
    keep[n_equil:] = _independent_vertex_rows(M_eq[n_equil:, :n_sig], np.concatenate(row_node),
                                              t)
    M_eq_full, b_eq_full = M_eq, b_eq
    M_eq, b_eq = M_eq[keep], b_eq[keep]
    if n_j:
        M_j = sp.coo_matrix((np.concatenate(j_vals), (np.concatenate(j_rows),
                                                      np.concatenate(j_cols))),
                            shape=(n_j, n_var)).tocsr()
        M_eq, b_eq = sp.vstack([M_eq, M_j], format="csr"), np.r_[b_eq, np.zeros(n_j)]
    if n_body:
        M_b, b_b = forces.equilibrium_rows(n_var)
        M_eq, b_eq = sp.vstack([M_eq, M_b], format="csr"), np.r_[b_eq, b_b]
    n_eq = M_eq.shape[0]
    blocks = [M_eq]
    rhs = [b_eq]
    cones = []
    n_eq_total = n_eq
    for kind in ("eq", "lin", "soc"):
        r, c, v, e, m = assemble(groups[kind])
        if not m:
            continue
        blocks.append(sp.coo_matrix((np.concatenate(v), (np.concatenate(r), np.concatenate(c))),
                                    shape=(m, n_var)).tocsr())
        rhs.append(np.concatenate(e))
        if kind == "eq":
            n_eq_total += m
        elif kind == "lin":
            cones.append(clarabel.NonnegativeConeT(m))
    cones = [clarabel.ZeroConeT(n_eq_total)] + cones + [clarabel.SecondOrderConeT(q) for q in socs]
    M = sp.vstack(blocks, format="csc")
    M.eliminate_zeros()
    e_vec = np.concatenate(rhs)
    # the stress columns of rigid elements are unused: leave them out of the program
    live = np.ones(n_var, bool)
    rb = np.flatnonzero(rigid)
    live[sig(rb[:, None, None], np.arange(3)[:, None], np.arange(3)).ravel()] = False
    M_full, M = M, M[:, live]
    timings["assembly"] = time.perf_counter() - t0

    t1 = time.perf_counter()
    q = np.zeros(n_var)
    q[lam_col] = -1.0
    q = q[live]
    tol = 1e-7 if socs else 1e-9
    n_lin = sum(g[0][3] for g in groups["lin"])
    if backend == "direct":
        res = _solve_direct(M, e_vec, q, cones, tol, retries, solver_settings, verbose)
    else:
        res = _solve_cvxpy(M, e_vec, q, (n_eq_total, n_lin, socs), tol, cvxpy_solver,
                           solver_settings, verbose)
    status, attempts = res["status"], res["attempts"]
    timings["solve"] = time.perf_counter() - t1
    if status != "Solved":
        causes = {"PrimalInfeasible": "no admissible stress field carries the dead loads "
                                      "(check supports and dead loads: with no tension a load "
                                      "needs a compressive path to a support)",
                  "DualInfeasible": "λ is unbounded: the live load does no work on any "
                                    "mechanism (check supports and the live load direction)",
                  "MaxIterations": "numerical trouble or poor scaling; try another "
                                   "stress_scale or a looser tolerance"}
        why_default = (f"numerical trouble after {len(attempts)} attempt(s) "
                       f"{[a[1] for a in attempts]}; try a looser tolerance or a better-graded "
                       f"mesh")
        why = next((v for k, v in causes.items() if k in status), why_default)
        raise SolverError(f"static limit analysis ended with Clarabel status {status}: {why}",
                          status=status)
    x = np.zeros(n_var)
    x[live] = res["x"]
    lam = float(x[lam_col])
    # the dropped rows must hold too (they do unless prescribed tractions contradict at a node)
    resid = np.abs(M_eq_full @ x + b_eq_full).max(initial=0.0)
    resid /= max(1.0, np.abs(x[:n_sig]).max(initial=0.0))
    if resid > 1e-5:
        raise SolverError(f"static limit analysis: relative equilibrium residual {resid:.3g} after "
                          f"dropping dependent traction rows; the prescribed tractions are "
                          f"inconsistent at some boundary node", status="Inconsistent")
    stress = (x[:n_sig] * s_ref).reshape(nt, 3, 3)
    stress[rigid] = np.nan  # a rigid body's inner stresses are not determined

    # active facet per vertex from the slacks of the lin rows and SOC cones
    active = np.full((nt, 3), -1)
    s_all = M_full @ x + e_vec
    off_lin = n_eq_total
    off_soc = off_lin + sum(g[0][3] for g in groups["lin"])
    for info in dom_rows:
        blk, els, npt = info["block"], info["els"], info["npt"]
        slack = []
        if blk.n_lin:
            r0 = off_lin + info["lin"]
            sl = s_all[r0:r0 + npt * blk.n_lin].reshape(npt, blk.n_lin)
            norm = np.linalg.norm(blk.A[blk.n_eq:blk.n_eq + blk.n_lin], axis=1)
            slack.append(sl / np.where(norm > 0, norm, 1.0))
        if blk.soc:
            r0 = off_soc + info["soc"]
            sq = s_all[r0:r0 + npt * sum(blk.soc)].reshape(npt, sum(blk.soc))
            j = 0
            for qd in blk.soc:
                slack.append((sq[:, j] - np.linalg.norm(sq[:, j + 1:j + qd], axis=1))[:, None])
                j += qd
        if slack and els is not None:
            sl = np.hstack(slack)
            k = np.argmin(sl, axis=1)
            val = sl[np.arange(npt), k]
            act = np.where(val <= active_tol, k, -1)
            active[els] = act.reshape(els.size, 3)
    timings["post"] = time.perf_counter() - t1 - timings["solve"]
    sizes = {"triangles": nt, "variables": int(live.sum()), "rows": M.shape[0], "nnz": M.nnz,
             "equilibrium_rows": n_eq, "soc_cones": len(socs), "rigid_bodies": n_body,
             "attempts": attempts}
    return StaticSolution(multiplier=lam, stress=stress, active=active, mesh=mesh, status=status,
                          primal_objective=-res["obj"], dual_objective=-res["obj_dual"],
                          iterations=res["iterations"], sizes=sizes, timings=timings,
                          rigid=rigid)


def static_from_problem(problem, **kwargs) -> StaticSolution:
    """Run ``solve_static`` on a solver-agnostic Problem (homlimit.fe.problems); see bracket.py."""
    from .bracket import _static_inputs

    return solve_static(**_static_inputs(problem), **kwargs)
