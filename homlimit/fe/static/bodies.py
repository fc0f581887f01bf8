"""Rigid bodies of the static program: connected ``strength.Rigid`` regions and the forces on them.

A rigid region carries no stress field; each connected set of its triangles (linked through
shared edges, as the kinematic program's continuous velocity links them) is one body with three
equilibrium rows: ΣF_x, ΣF_z and the moment about its centroid.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

__all__ = ["rigid_bodies", "NodalForces"]


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


class NodalForces:
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

