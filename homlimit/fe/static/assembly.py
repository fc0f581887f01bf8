"""The static program's rows: equilibrium, traction continuity, boundary, joints, bodies, strength.

Unknowns x = (σ̂ at the n_loc points of every triangle, λ, extra columns): σ = s_ref σ̂ with
the reference stress s_ref; column 3 n_loc e + 3 i + c is σ_c at local point i of triangle e,
column 3 n_loc nt is λ, then the joints' σ_j, the recession-cone forces, the reactions on rigid
bodies and the cones' auxiliaries, in the order the steps add them. Every step is index
arithmetic over all triangles or edges at once: the only loops run over the few equation kinds,
the 3 vertices, the 2 or 3 edge points and the 2 components.

Degree 1 (n_loc = 3): σ linear, its values at the vertices. Degree 2 (n_loc = 6): σ quadratic
in Bernstein form, σ = Σ_α c_α B_α(λ₁, λ₂, λ₃) with control coefficients c_α at the vertices
(i = 0, 1, 2: B = λ_i², where c is the vertex value) and at the edges (i = 3, 4, 5 for the
edges 01, 12, 20: B = 2λ_iλ_j). The B_α are non-negative and sum to 1, so σ(x) is a convex
combination of the c_α: c_α ∈ G for all six makes σ ∈ G everywhere, and traction continuity
holds along an edge when its three Bernstein coefficients (σ n at the edge's three control
points) agree. div σ is linear with vertex values 2 Σ_k c_{jk} ∇λ_k (c_{jj} the vertex
coefficient), so equilibrium is three rows per component.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import scipy.sparse as sp

from ...errors import ParameterError
from ..conic import stack
from ..operators import COMPONENTS
from ..strength import Rigid
from .bodies import NodalForces, rigid_bodies

__all__ = ["StaticProgram", "triangle_gradients", "edge_tables", "EDGE_CONTROL"]

# local control point of the edge between local vertices i and j, indexed by i + j
# (01 → 3, 12 → 4, 20 → 5)
EDGE_CONTROL = np.array([-1, 3, 5, 4])


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


class _Coo:
    """Sparse rows M x + e gathered piece by piece as COO triplets."""

    def __init__(self):
        self.rows, self.cols, self.vals, self.rhs, self.n = [], [], [], [], 0

    def new(self, m: int, rhs=None) -> np.ndarray:
        """Indices of m new rows with constants ``rhs`` (default 0)."""
        self.rhs.append(np.zeros(m) if rhs is None else rhs)
        self.n += m
        return self.n - m + np.arange(m)

    def add(self, rows, terms, sign: float = 1.0):
        """Add Σ sign·val·x[col] over ``terms`` [(col, val)] to ``rows``."""
        for col, val in terms:
            self.rows.append(rows)
            self.cols.append(col)
            self.vals.append(sign * val)

    def matrix(self, n_var: int) -> tuple[sp.csr_matrix, np.ndarray]:
        M = sp.coo_matrix((np.concatenate(self.vals), (np.concatenate(self.rows),
                                                       np.concatenate(self.cols))),
                          shape=(self.n, n_var)).tocsr()
        return M, np.concatenate(self.rhs)


class StaticProgram:
    """The static program of a ``problems.Problem``, its rows added by the numbered steps."""

    def __init__(self, problem, stress_scale: float | None = None, degree: int = 1):
        mesh = self.mesh = problem.mesh
        self.degree, self.nloc = degree, (3 if degree == 1 else 6)
        p, t = self.p, self.t = np.asarray(mesh.p, float), np.asarray(mesh.t)
        nt = self.nt = t.shape[1]
        self.dNdx, self.dNdz, self.area = triangle_gradients(p, t)
        self.parts = [(dom, np.asarray(mesh.subdomains[reg]))
                      for reg, dom in problem.domains.items()]
        self.rigid = np.zeros(nt, bool)
        for dom, els in self.parts:
            self.rigid[els] |= isinstance(dom, Rigid)
        self.b_live, self.b_dead = np.zeros((nt, 2)), np.zeros((nt, 2))
        for loads, acc in ((problem.live_body, self.b_live), (problem.dead_body, self.b_dead)):
            for reg, val in loads.items():
                acc[mesh.subdomains[reg]] += np.asarray(val, float)
        E = self.E = edge_tables(mesh)
        nf = E["ends"].shape[1]
        self.body, self.n_body = rigid_bodies(E, self.rigid)
        self.side_rigid = np.stack([self.rigid[E["tri"][0]],
                                    self.rigid[np.maximum(E["tri"][1], 0)] & E["interior"]])
        # prescribed tractions at both ends (axis 1) and support flags per edge
        bnd = mesh.boundaries
        self.t_live, self.t_dead = np.zeros((2, 2, nf)), np.zeros((2, 2, nf))
        for loads, acc in ((problem.live_traction, self.t_live),
                           (problem.dead_traction, self.t_dead)):
            for tag, val in loads.items():
                acc[:, :, np.asarray(bnd[tag])] += np.asarray(val, float)[:, None, None]
        # ties (issue 30): traction ν_k t_k at yield on boundary k, 0 <= ν_k <= 1 a column
        self.t_ties = []
        for tag, val in problem.ties.items():
            acc = np.zeros((2, 2, nf))
            acc[:, :, np.asarray(bnd[tag])] += np.asarray(val, float)[:, None, None]
            self.t_ties.append(acc)
        self.fix = np.zeros((2, nf), bool)
        for tag, comp in problem.supports.items():
            f = np.asarray(bnd[tag])
            self.fix[0, f] |= "u^1" in COMPONENTS[comp]
            self.fix[1, f] |= "u^2" in COMPONENTS[comp]
        self.interfaces = {tag: (dom, np.asarray(bnd[tag]))
                           for tag, dom in problem.interfaces.items()}
        self.is_joint = np.zeros(nf, bool)
        for _, f in self.interfaces.values():
            self.is_joint[f] = True
        self.fix[:, self.is_joint] = True  # the joint's traction is unknown, tested by its domain
        loaded = np.any(self.t_live != 0, axis=(0, 1)) | np.any(self.t_dead != 0, axis=(0, 1))
        for t_k in self.t_ties:
            loaded |= np.any(t_k != 0, axis=(0, 1))
        if np.any(loaded & E["interior"]):
            raise ParameterError("a traction is prescribed on interior edges; allowed: tractions "
                                 "on boundary tags only")
        # scaling: σ = s_ref σ̂ with s_ref the largest of strength, body force × ℓ and traction
        ell = float(np.ptp(p, axis=1).max())
        # a compression cap (``Capped``) is left out: its 2 f_c would set s_ref far above the
        # stresses the loads need (B1, f_c = 5 MPa: 1.2e8 Pa in the façade strip) and the
        # relative equilibrium check would then read the solver's noise
        e_max = max((np.abs(getattr(dom, "base", dom).static_cone().e).max(initial=0.0)
                     for dom, _ in self.parts), default=0.0)
        self.s_ref = stress_scale or max(
            e_max, np.abs(self.b_dead).max() * ell, np.abs(self.b_live).max() * ell,
            np.abs(self.t_dead).max(initial=0.0), np.abs(self.t_live).max(initial=0.0),
            *(np.abs(t_k).max() for t_k in self.t_ties))
        self.n_sig = 3 * self.nloc * nt
        self.lam = self.n_sig          # the column of λ
        self.n_var = self.n_sig + 1
        self.nu = self.columns(len(self.t_ties))  # the ties' ν_k (none without ties)
        self.eq, self.joint_rows = _Coo(), _Coo()
        self.eq_mid = _Coo()           # degree 2: rows at the edges' middle control points
        self.row_node = []             # the mesh node of every vertex-local row of ``eq``
        self.n_equil = 0               # rows of ``eq`` before the vertex-local ones
        self.forces = NodalForces(p, t, E, self.body, self.n_body, self.area)
        self.joint_cones = []          # (static cone block, columns (n, 3) of its σ_j)
        self.cones = []                # (block, elements or None, stacked rows) per part

    @property
    def edge_points(self) -> tuple[int, ...]:
        """Where traction rows are written along an edge: its two ends (k = 0, 1) and, for
        degree 2, its middle control point (k = 2)."""
        return (0, 1) if self.degree == 1 else (0, 1, 2)

    def columns(self, m: int) -> np.ndarray:
        """m new unknowns."""
        self.n_var += m
        return self.n_var - m + np.arange(m)

    def sig(self, e, i, c):
        """Column of σ_c at local point i of element e."""
        return 3 * self.nloc * e + 3 * i + c

    def traction_terms(self, side, k, comp, f):
        """σ n at end k of edges f from side ``side``: x: σ_x n_x + τ n_z, z: σ_z n_z + τ n_x.
        k = 2: at the edge's middle control point (degree 2)."""
        E = self.E
        nx, nz = E["n"]
        tri = E["tri"][side, f]
        loc = (E["loc"][side, k, f] if k < 2
               else EDGE_CONTROL[E["loc"][side, 0, f] + E["loc"][side, 1, f]])
        if comp == 0:
            return [(self.sig(tri, loc, 0), nx[f]), (self.sig(tri, loc, 2), nz[f])]
        return [(self.sig(tri, loc, 1), nz[f]), (self.sig(tri, loc, 2), nx[f])]

    def equilibrium(self):
        """1. Two rows per triangle, each times the triangle's size h_e so that its coefficients
        are O(1): h_e div σ̂ + λ h_e b/s_ref + h_e b⁰/s_ref = 0. Rigid triangles carry no stress
        (their region is one body, step 4b)."""
        e_all = np.flatnonzero(~self.rigid)
        h_e = np.sqrt(2.0 * self.area[e_all])
        # the vertex values of div σ: degree 1 one constant, degree 2 one per vertex j
        points = ([[(i, 1.0) for i in range(3)]] if self.degree == 1 else
                  [[(j if k == j else EDGE_CONTROL[j + k], 2.0) for k in range(3)]
                   for j in range(3)])
        for comp, terms in ((0, ((0, self.dNdx), (2, self.dNdz))),
                            (1, ((2, self.dNdx), (1, self.dNdz)))):
            for ctrl in points:
                rows = self.eq.new(e_all.size, h_e * self.b_dead[e_all, comp] / self.s_ref)
                self.eq.add(rows, [(self.sig(e_all, i, c), w * h_e * g[k, e_all])
                                   for c, g in terms for k, (i, w) in enumerate(ctrl)])
                self.eq.add(rows, [(np.full(e_all.size, self.lam),
                                    h_e * self.b_live[e_all, comp] / self.s_ref)])
        self.n_equil = self.eq.n

    def continuity(self):
        """2. t(T1) − t(T2) = 0 at both ends of every interior edge between continuum triangles
        (4 rows per edge)."""
        E, sr = self.E, self.side_rigid
        fi = np.flatnonzero(E["interior"] & ~sr[0] & ~sr[1])
        for k in self.edge_points:
            for comp in (0, 1):
                coo = self.eq if k < 2 else self.eq_mid
                rows = coo.new(fi.size)
                if k < 2:
                    self.row_node.append(E["ends"][k, fi])
                for side, sgn in ((0, 1.0), (1, -1.0)):
                    coo.add(rows, self.traction_terms(side, k, comp, fi), sgn)

    def boundary(self):
        """3. t = λ t_live + t_dead at both ends of boundary edges, per unsupported component."""
        E = self.E
        fb = np.flatnonzero(~E["interior"] & ~self.side_rigid[0])
        for comp in (0, 1):
            fc = fb[~self.fix[comp, fb]]
            for k in self.edge_points:
                # a linear prescribed traction's middle Bernstein coefficient is its mean
                t_live, t_dead = ((self.t_live[comp, k, fc], self.t_dead[comp, k, fc]) if k < 2
                                  else (self.t_live[comp, :, fc].mean(axis=1),
                                        self.t_dead[comp, :, fc].mean(axis=1)))
                coo = self.eq if k < 2 else self.eq_mid
                rows = coo.new(fc.size, -t_dead / self.s_ref)
                if k < 2:
                    self.row_node.append(E["ends"][k, fc])
                coo.add(rows, self.traction_terms(0, k, comp, fc))
                coo.add(rows, [(np.full(fc.size, self.lam), -t_live / self.s_ref)])
                for nu, t_k in zip(self.nu, self.t_ties):
                    t_tie = t_k[comp, k, fc] if k < 2 else t_k[comp, :, fc].mean(axis=1)
                    coo.add(rows, [(np.full(fc.size, nu), -t_tie / self.s_ref)])

    def joints(self):
        """4. Joints to a fixed ground: σ n = σ_j n at both ends of each joint edge, σ_j ∈ G_j.

        On a rigid body the joint acts through its traction σ_j n, linear along the edge, plus
        concentrated end forces ρ_j n with ρ_j in the recession cone of G_j (a contact force at a
        toe). For a cone G_j (dry joint) the concentrated part covers both.
        """
        nx, nz = self.E["n"]

        def joint_terms(cols, k, comp, f):  # σ_j n at end k: x uses (σ_x, τ), z uses (σ_z, τ)
            nn_ = [(nx[f], nz[f]), (nz[f], nx[f])][comp]
            return [(cols[k, :, c], v) for c, v in zip([(0, 2), (1, 2)][comp], nn_)]

        for dom, f_all in self.interfaces.values():
            cols_all = self.columns(6 * f_all.size).reshape(2, f_all.size, 3)  # [end, edge, σ]
            on_body = self.side_rigid[0, f_all]
            f, cols = f_all[~on_body], cols_all[:, ~on_body]
            for k in (0, 1):
                for comp in (0, 1):
                    rows = self.joint_rows.new(f.size)
                    self.joint_rows.add(rows, self.traction_terms(0, k, comp, f))
                    self.joint_rows.add(rows, joint_terms(cols, k, comp, f), -1.0)
            blk = dom.static_cone()
            fb_, cb_ = f_all[on_body], cols_all[:, on_body]
            kinds = [(cb_, True)]
            if np.any(blk.e):                                 # not a cone
                rec = self.columns(6 * fb_.size).reshape(2, fb_.size, 3)
                kinds = [(cb_, False), (rec, True)]
                self.joint_cones.append((dataclasses.replace(blk, e=np.zeros_like(blk.e)),
                                         rec.reshape(-1, 3)))
            for cc, lumped in kinds:
                for k in (0, 1):
                    for comp in (0, 1):
                        self.forces.traction(fb_, k, comp, joint_terms(cc, k, comp, fb_),
                                             lumped=lumped)
            self.joint_cones.append((blk, cols_all.reshape(-1, 3)))

    def bodies(self):
        """4b. Forces on rigid bodies: body forces, prescribed tractions, reactions on supports,
        and the tractions of the continuum triangles across their boundary."""
        if not self.n_body:
            return
        E, forces, s_ref, lam = self.E, self.forces, self.s_ref, self.lam
        rb = np.flatnonzero(self.rigid)
        cen = self.p[:, self.t[:, rb]].mean(axis=1)
        area = self.area[rb]
        for comp in (0, 1):
            forces.add(self.body[rb], cen, comp,
                       [(np.full(rb.size, lam), area * self.b_live[rb, comp] / s_ref)],
                       area * self.b_dead[rb, comp] / s_ref)
        fbb = np.flatnonzero(~E["interior"] & self.side_rigid[0] & ~self.is_joint)
        for comp in (0, 1):
            fixed, free_ = fbb[self.fix[comp, fbb]], fbb[~self.fix[comp, fbb]]
            for k in (0, 1):
                forces.traction(free_, k, comp, [(np.full(free_.size, lam),
                                                  self.t_live[comp, k, free_] / s_ref)]
                                + [(np.full(free_.size, nu), t_k[comp, k, free_] / s_ref)
                                   for nu, t_k in zip(self.nu, self.t_ties)],
                                const=self.t_dead[comp, k, free_] / s_ref)
                reac = self.columns(fixed.size)   # a free reaction at each supported end
                forces.traction(fixed, k, comp, [(reac, np.ones(fixed.size))], lumped=True)
        for s_c in (0, 1):  # continuum on side s_c, body on the other: −(σ n_out) on the body
            sr = self.side_rigid
            fcb = np.flatnonzero(E["interior"] & ~sr[s_c] & sr[1 - s_c])
            sgn = -1.0 if s_c == 0 else 1.0
            for k in (0, 1):
                for comp in (0, 1):
                    forces.traction(fcb, k, comp, [(c, sgn * v) for c, v in
                                                   self.traction_terms(s_c, k, comp, fcb)],
                                    body_side=1 - s_c)

    def strength(self):
        """5. σ ∈ G at the three vertices of every triangle, domain by domain, and σ_j ∈ G_j at
        the joints: ``conic.stack`` on a 0/1 selection of the σ columns, scaled by s_ref."""
        nl = self.nloc
        parts = [(dom.static_cone(), els,
                  np.stack([self.sig(np.repeat(els, nl), np.tile(np.arange(nl), els.size), c)
                            for c in range(3)], axis=1)) for dom, els in self.parts]
        parts += [(blk, None, cols) for blk, cols in self.joint_cones]
        aux = [self.columns(cols.shape[0] * blk.n_aux) for blk, _, cols in parts]
        for (blk, els, cols), y in zip(parts, aux):
            blk = dataclasses.replace(blk, e=blk.e / self.s_ref)
            X = _selection(cols.ravel(), self.n_var)
            self.cones.append((blk, els, stack(blk, X), _selection(y, self.n_var)))

    def matrix(self):
        """All rows M x + e ∈ {0} × R₊ × SOC(q_1) × ... as (blocks, constants) to stack, the
        layout (zero rows, non-negative rows, SOC sizes), the global rows of each cone part per
        kind [{kind: slice}], and the equality rows of steps 1–3 before the dependent ones were
        dropped, (M, e), which the solution must satisfy too."""
        n_var = self.n_var
        M_eq, e_eq = self.eq.matrix(n_var)
        # linearly dependent traction rows (e.g. where two straight lines of edges cross, or two
        # boundary edges of one triangle meet) make the KKT system singular: keep a basis per
        # node
        keep = np.ones(M_eq.shape[0], bool)
        keep[self.n_equil:] = _independent_vertex_rows(M_eq[self.n_equil:, :self.n_sig],
                                                       np.concatenate(self.row_node), self.t,
                                                       self.nloc)
        blocks, rhs = [M_eq[keep]], [e_eq[keep]]
        if self.eq_mid.n:
            M_mid, e_mid = self.eq_mid.matrix(n_var)
            blocks.append(M_mid)
            rhs.append(e_mid)
        if self.joint_rows.n:
            blocks.append(self.joint_rows.matrix(n_var)[0])
            rhs.append(np.zeros(self.joint_rows.n))
        if self.n_body:
            M_b, e_b = self.forces.equilibrium_rows(n_var)
            blocks.append(M_b)
            rhs.append(e_b)
        self.n_equilibrium = sum(b.shape[0] for b in blocks)
        where = [{} for _ in self.cones]
        n_rows = dict.fromkeys(("eq", "lin", "soc"), 0)
        row = self.n_equilibrium
        for kind in n_rows:
            for k, (blk, els, st, Y) in enumerate(self.cones):
                if kind in st.kinds:
                    r = st.kinds[kind]
                    blocks.append(r.M if r.D is None else r.M + r.D @ Y)
                    rhs.append(r.e)
                    where[k][kind] = slice(row, row + r.e.size)
                    n_rows[kind] += r.e.size
                    row += r.e.size
            if kind == "lin" and self.nu.size:   # the ties: ν_k >= 0, 1 − ν_k >= 0
                m = self.nu.size
                blocks.append(sp.csr_matrix((np.r_[np.ones(m), -np.ones(m)],
                                             (np.arange(2 * m), np.r_[self.nu, self.nu])),
                                            shape=(2 * m, n_var)))
                rhs.append(np.r_[np.zeros(m), np.ones(m)])
                n_rows[kind] += 2 * m
                row += 2 * m
        socs = [q for _, _, st, _ in self.cones for q in st.soc]
        layout = (self.n_equilibrium + n_rows["eq"], n_rows["lin"], socs)
        return blocks, rhs, layout, where, (M_eq, e_eq)


def _selection(cols: np.ndarray, n_var: int) -> sp.csr_matrix:
    """The 0/1 map (len(cols) × n_var) that picks the unknowns ``cols``."""
    return sp.csr_matrix((np.ones(cols.size), (np.arange(cols.size), cols)),
                         shape=(cols.size, n_var))


def _independent_vertex_rows(R: sp.csr_matrix, row_node: np.ndarray, t: np.ndarray,
                             nloc: int = 3, tol: float = 1e-6) -> np.ndarray:
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
    point = R.col // 3                       # nloc e + i; the rows use vertices only (i < 3)
    lcol = 3 * slot[3 * (point // nloc) + point % nloc] + R.col % 3
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
