"""Stack one point's ConicBlock over n points as sparse rows, one matrix per cone kind.

A ``strength.ConicBlock`` states A x + D y + e ∈ K for ONE point, K = {0}^n_eq × R₊^n_lin ×
SOC(q_1) × SOC(q_2) × ...; a program has n points whose vectors x_p = X_p u are 3-row slices of
a sparse map X (3n × N) from its unknowns u: the strain-rate rows B_p of the kinematic bound,
a 0/1 selection of the stress columns in the static one. With row scales s_p (default 1),

    s_p (A X_p u + D y_p + e)  for all p  =  (S kron(I_n, A) X) u + (S kron(I_n, D)) y + s ⊗ e,

y holding the n·n_aux auxiliaries point by point. Both bounds take their rows from ``stack``
and only wrap them in their solver's constraints (cvxpy constraints; Clarabel cones): no
per-point Python object.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from .strength import ConicBlock

__all__ = ["Rows", "Stack", "stack"]


@dataclass(frozen=True)
class Rows:
    """The rows M u + D y + e of one cone kind (D is None without auxiliaries)."""

    M: sp.csr_matrix
    D: sp.csr_matrix | None
    e: np.ndarray


@dataclass(frozen=True)
class Stack:
    """A ConicBlock at n points: ``kinds`` maps 'eq', 'lin', 'soc' (those the block has) to
    their Rows. ``order`` "point": the rows of point 0, then of point 1, ... (the second-order
    cones are ``soc``, consecutive); "row": row r of every point, then row r + 1 (cone j of the
    block then spans the rows [o_j n, (o_j + q_j) n) of its kind, o_j = Σ_{i<j} q_i)."""

    block: ConicBlock
    n: int
    order: str
    kinds: dict[str, Rows]

    @property
    def soc(self) -> list[int]:
        """Sizes of the second-order cones in point order (the block's, n times)."""
        return list(self.block.soc) * self.n

    def per_point(self, values: Mapping[str, np.ndarray]) -> np.ndarray:
        """Per-kind vectors in row order of ``kinds`` (duals, slacks) as one (n, m) array,
        column r the block's row r (zero in kinds not given)."""
        out = np.zeros((self.n, self.block.n_rows))
        for kind, v in values.items():
            lo, hi = _span(self.block, kind)
            v = np.asarray(v, float)
            out[:, lo:hi] = (v.reshape(self.n, hi - lo) if self.order == "point"
                             else v.reshape(hi - lo, self.n).T)
        return out

    def cost(self, X: sp.spmatrix, weights: np.ndarray):
        """Objective Σ_p w_p (cx·x_p + cy·y_p) as (vector on u or None, vector on y or None)."""
        blk = self.block
        c_u = (np.kron(weights, blk.cx) @ X) if np.any(blk.cx) else None
        c_y = np.kron(weights, blk.cy) if (blk.n_aux and np.any(blk.cy)) else None
        return c_u, c_y


def _span(block: ConicBlock, kind: str) -> tuple[int, int]:
    """Rows [lo, hi) of ``kind`` in one point's block."""
    ends = np.cumsum([0, block.n_eq, block.n_lin, sum(block.soc)])
    k = ("eq", "lin", "soc").index(kind)
    return int(ends[k]), int(ends[k + 1])


def stack(block: ConicBlock, X: sp.spmatrix, scale: np.ndarray | None = None,
          order: str = "point") -> Stack:
    """Stack ``block`` at the n = X.shape[0] / 3 points of X, rows times ``scale`` (n,)."""
    n, m = X.shape[0] // 3, block.n_rows
    scale = np.ones(n) if scale is None else np.asarray(scale, float)
    S = sp.diags(np.repeat(scale, m))
    eye = sp.identity(n, format="csr")
    M = (S @ sp.kron(eye, sp.csr_matrix(block.A)) @ X).tocsr()
    D = (S @ sp.kron(eye, sp.csr_matrix(block.D))).tocsr() if block.n_aux else None
    e = np.kron(scale, block.e)
    kinds = {}
    for kind in ("eq", "lin", "soc"):
        lo, hi = _span(block, kind)
        if hi == lo:
            continue
        r = np.arange(lo, hi)
        p = np.arange(n)
        idx = ((p[:, None] * m + r).ravel() if order == "point"
               else (p[None, :] * m + r[:, None]).ravel())
        kinds[kind] = Rows(M[idx], None if D is None else D[idx], e[idx])
    return Stack(block, n, order, kinds)
