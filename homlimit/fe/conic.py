"""Stack a per-point ConicBlock over n points as a few batched cvxpy constraints.

Given X, an affine cvxpy expression of shape (n, 3) (one σ or d per row), ``stack`` returns
the constraints  X Aᵀ + Y Dᵀ + 1 eᵀ ∈ K (row-wise), the auxiliary variable Y (n, n_aux) and the
objective term Σ_points (cx·x + cy·y) (times optional per-point weights w, e.g. area/3).
One constraint object per cone kind: no per-point Python objects.
"""

from __future__ import annotations

import cvxpy as cp
import numpy as np

from .strength import ConicBlock

__all__ = ["stack"]


def stack(X: cp.Expression, block: ConicBlock, weights: np.ndarray | None = None):
    """Return (constraints, Y, cost) for X (n, 3) under ``block`` at every row."""
    n = X.shape[0]
    Y = cp.Variable((n, block.n_aux)) if block.n_aux else None
    Z = X @ block.A.T
    if Y is not None:
        Z = Z + Y @ block.D.T
    if np.any(block.e):
        Z = Z + np.ones((n, 1)) @ block.e.reshape(1, -1)
    cons = []
    r = 0
    if block.n_eq:
        cons.append(Z[:, r:r + block.n_eq] == 0)
        r += block.n_eq
    if block.n_lin:
        cons.append(Z[:, r:r + block.n_lin] >= 0)
        r += block.n_lin
    for q in block.soc:
        cons.append(cp.SOC(Z[:, r], Z[:, r + 1:r + q], axis=1))
        r += q
    w = np.ones(n) if weights is None else np.asarray(weights, float)
    cost = 0
    if np.any(block.cx):
        cost = cost + w @ (X @ block.cx)
    if Y is not None and np.any(block.cy):
        cost = cost + w @ (Y @ block.cy)
    return cons, Y, cost
