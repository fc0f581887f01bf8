"""Strength domains in plane (σ_x, σ_z, τ_xz) and their conic representations.

Conventions (used by every module):
- stress vector   σ = (σ_x, σ_z, τ_xz), tension positive;
- strain-rate vector d = (d_xx, d_zz, γ_xz) with γ_xz = 2 d_xz (engineering shear), so σ : d = σ·d;
- a velocity jump [v] across a line of unit normal n is tested as the strain rate
  sym([v] ⊗ n) = ([v]_x n_x, [v]_z n_z, [v]_x n_z + [v]_z n_x) (per unit length of the line).

Every domain G exposes the same interface, consumed by the kinematic (upper-bound) and static
(lower-bound) programs:
- ``is_admissible(sigma)``: σ ∈ G (vectorised over leading axes);
- ``support(d)``: π(d) = sup_{σ∈G} σ·d, +inf where unbounded;  ``support_jump(v, n)``;
- ``kinematic_cone()``: a ConicBlock with π(d) = min_y cx·d + cy·y  s.t.  A d + D y + e ∈ K;
- ``static_cone()``: a ConicBlock with σ ∈ G  ⇔  ∃y: A σ + D y + e ∈ K.
A ConicBlock describes ONE point; programs stack it over all points with sparse/batched algebra
(see ``homlimit.conic``), never with per-point Python objects.
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from dataclasses import dataclass, field

import numpy as np

__all__ = ["ConicBlock", "StrengthDomain", "jump_strain"]


@dataclass(frozen=True)
class ConicBlock:
    """Conic representation at one point:  A x + D y + e ∈ K,  objective cx·x + cy·y.

    x is the 3-vector (σ or d), y holds ``n_aux`` auxiliary variables. The rows of
    A x + D y + e are ordered as K = {0}^n_eq × R₊^n_lin × SOC(q_1) × SOC(q_2) × ...,
    where SOC(q) = {(t, u) ∈ R × R^(q-1): |u| <= t}.
    """

    A: np.ndarray
    D: np.ndarray
    e: np.ndarray
    n_eq: int = 0
    n_lin: int = 0
    soc: tuple[int, ...] = ()
    cx: np.ndarray = field(default_factory=lambda: np.zeros(3))
    cy: np.ndarray | None = None

    def __post_init__(self):
        A = np.atleast_2d(np.asarray(self.A, float))
        m = A.shape[0]
        D = np.asarray(self.D, float).reshape(m, -1) if np.size(self.D) else np.zeros((m, 0))
        object.__setattr__(self, "A", A)
        object.__setattr__(self, "D", D)
        object.__setattr__(self, "e", np.asarray(self.e, float).reshape(m))
        object.__setattr__(self, "cx", np.asarray(self.cx, float).reshape(3))
        cy = np.zeros(D.shape[1]) if self.cy is None else np.asarray(self.cy, float)
        object.__setattr__(self, "cy", cy.reshape(D.shape[1]))
        if A.shape[1] != 3:
            raise ValueError(f"ConicBlock.A must have 3 columns, got {A.shape}")
        if self.n_eq + self.n_lin + sum(self.soc) != m:
            raise ValueError(f"ConicBlock rows {m} != n_eq + n_lin + sum(soc) = "
                             f"{self.n_eq} + {self.n_lin} + {sum(self.soc)}")

    @property
    def n_aux(self) -> int:
        return self.D.shape[1]

    @property
    def n_rows(self) -> int:
        return self.A.shape[0]


def jump_strain(v: np.ndarray, n: np.ndarray) -> np.ndarray:
    """sym([v] ⊗ n) as a strain-rate vector (d_xx, d_zz, γ_xz); v, n of shape (..., 2)."""
    v = np.asarray(v, float)
    n = np.asarray(n, float)
    return np.stack([v[..., 0] * n[..., 0], v[..., 1] * n[..., 1],
                     v[..., 0] * n[..., 1] + v[..., 1] * n[..., 0]], axis=-1)


class StrengthDomain(ABC):
    """A convex strength domain G in (σ_x, σ_z, τ_xz). Subclasses hold only facts about G."""

    @abstractmethod
    def is_admissible(self, sigma: np.ndarray, tol: float = 1e-9) -> np.ndarray:
        """σ ∈ G for σ of shape (..., 3); returns a bool array of shape (...)."""

    @abstractmethod
    def support(self, d: np.ndarray) -> np.ndarray:
        """Support function π(d) = sup_{σ∈G} σ·d for d of shape (..., 3); +inf where unbounded."""

    def support_jump(self, v: np.ndarray, n: np.ndarray) -> np.ndarray:
        """Dissipation per unit length of a velocity jump v across a line of unit normal n."""
        return self.support(jump_strain(v, n))

    @abstractmethod
    def kinematic_cone(self) -> ConicBlock:
        """π(d) = min_y cx·d + cy·y  s.t.  A d + D y + e ∈ K  (finite exactly where π is)."""

    @abstractmethod
    def static_cone(self) -> ConicBlock:
        """σ ∈ G  ⇔  ∃ y:  A σ + D y + e ∈ K."""
