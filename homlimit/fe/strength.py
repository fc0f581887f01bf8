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
(see ``homlimit.fe.conic``), never with per-point Python objects.
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from dataclasses import dataclass, field
from functools import lru_cache

import numpy as np

from ..errors import check_range
from ..fields import set_fields

__all__ = ["ConicBlock", "StrengthDomain", "dissipation_free", "jump_strain"]


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
        e = np.asarray(self.e, float).reshape(m)
        cx = np.asarray(self.cx, float).reshape(3)
        cy = np.zeros(D.shape[1]) if self.cy is None else np.asarray(self.cy, float)
        set_fields(self, A=A, D=D, e=e, cx=cx, cy=cy.reshape(D.shape[1]))
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


def dissipation_free(domain) -> bool:
    """True when ``domain``'s support function π is 0 wherever it is finite: its kinematic
    cone has no cost (cx = 0, cy = 0). So for every cone G with its apex at 0: eq. 15 without
    cohesion (the homogenised masonry), dry bed joints, a rigid region. A mechanism admissible
    there dissipates nothing, whatever its shape."""
    blk = domain.kinematic_cone()
    return not (np.any(blk.cx) or np.any(blk.cy))


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


# ---------------------------------------------------------------------------------------------
# Concrete domains
# ---------------------------------------------------------------------------------------------

__all__ += ["Homogenised", "BedJoints", "Tresca", "MohrCoulomb", "Rigid", "Capped"]


def _norm(x: np.ndarray) -> np.ndarray:
    return np.sqrt(np.sum(np.asarray(x, float) ** 2, axis=-1))


def _polyhedral_support(N: np.ndarray, r: np.ndarray, d: np.ndarray,
                        rtol: float = 1e-9) -> np.ndarray:
    """π(d) = sup{σ·d : Nσ <= r} = min{r·μ : Nᵀμ = d, μ >= 0} (LP duality; N of rank 3).

    An LP attains its optimum at a basic solution, so π is the least cost over the bases B of
    three rows with Nᵀ_B μ_B = d and μ_B >= 0 (+inf if no basis is feasible: d ∉ cone(N)).
    The loop runs over the C(m, 3) <= 20 bases, vectorised over all points d.
    """
    d = np.asarray(d, float)
    best = np.full(d.shape[:-1], np.inf)
    tol = rtol * (1.0 + _norm(d))
    for B in _bases(len(N)):
        NB = N[list(B)]
        if abs(np.linalg.det(NB)) < 1e-12:
            continue
        mu = d @ np.linalg.inv(NB)          # μ_Bᵀ = dᵀ N_B⁻¹  ⇔  N_Bᵀ μ_B = d
        ok = np.all(mu >= -tol[..., None], axis=-1)
        best = np.where(ok, np.minimum(best, mu @ r[list(B)]), best)
    return best


def _bases(m: int):
    from itertools import combinations
    return combinations(range(m), 3)


class _Polyhedral(StrengthDomain):
    """G = {σ : N_k·σ <= r_k}: facts shared by the polyhedral domains."""

    normals: np.ndarray   # (m, 3) outward normals N_k
    rhs: np.ndarray       # (m,)   right-hand sides r_k >= 0 (so σ = 0 is admissible)

    def residual(self, sigma: np.ndarray) -> np.ndarray:
        """N_k·σ − r_k for every facet, shape (..., m); <= 0 inside G."""
        return np.asarray(sigma, float) @ self.normals.T - self.rhs

    def is_admissible(self, sigma, tol: float = 1e-9):
        sigma = np.asarray(sigma, float)
        scale = 1.0 + _norm(sigma)[..., None] + np.abs(self.rhs)
        return np.all(self.residual(sigma) <= tol * scale, axis=-1)

    def active_facet(self, sigma, rtol: float = 1e-6) -> np.ndarray:
        """Index k of the facet N_k·σ = r_k the stress σ (..., 3) lies on, −1 if σ is interior.

        The facet is the one of largest normalised residual (N_k·σ − r_k)/|N_k|; σ counts as
        interior when that residual is below −rtol·(|σ| + max r).
        """
        sigma = np.asarray(sigma, float)
        res = self.residual(sigma) / _norm(self.normals)
        k = np.argmax(res, axis=-1)
        top = np.take_along_axis(res, k[..., None], axis=-1)[..., 0]
        inside = top < -rtol * (_norm(sigma) + np.max(self.rhs, initial=0.0))
        return np.where(inside, -1, k)

    def static_cone(self) -> ConicBlock:
        """σ ∈ G  ⇔  −Nσ + r >= 0 (one linear row per facet, no auxiliary variable)."""
        return ConicBlock(A=-self.normals, D=np.zeros((len(self.rhs), 0)), e=self.rhs,
                          n_lin=len(self.rhs))

    def generator_cone(self) -> ConicBlock:
        """π(d) = min r·μ  s.t.  d − Nᵀμ = 0, μ >= 0 (LP duality; m auxiliary variables μ)."""
        m = len(self.rhs)
        A = np.vstack([np.eye(3), np.zeros((m, 3))])
        D = np.vstack([-self.normals.T, np.eye(m)])
        return ConicBlock(A=A, D=D, e=np.zeros(3 + m), n_eq=3, n_lin=m, cy=self.rhs)


def _micro_field_rows(a, c, f, C, T):
    """The static micro field behind eq. 15, as linear rows over z = (σ_x, σ_z, τ, u, w) <= r.

    Piecewise-constant stresses in a running-bond cell (blocks 2c × a): bed joints carry
    (σ_z − w, τ + u) on one half of a block and (σ_z + w, τ − u) on the other; head joints
    carry (σ_h, τ_h). Block equilibrium gives σ_x = σ_h − (c/a) u (horizontal force through
    the staggered cell) and τ_h = τ − (c/a) w (moment). Every joint obeys |τ_j| + fσ_j <= C,
    σ_j <= T.
    """
    k = c / a
    rows = []
    for s in (1.0, -1.0):
        rows += [([0, f, s, s, -f], C), ([0, f, s, -s, f], C),       # bed joint, two halves
                 ([f, 0, s, f * k, -s * k], C)]                      # head joint (σ_h, τ_h)
    rows += [([0, 1, 0, 0, -1], T), ([0, 1, 0, 0, 1], T), ([1, 0, 0, k, 0], T)]
    return np.array([r for r, _ in rows], float), np.array([v for _, v in rows], float)


def _eliminate(A, b, j):
    """Fourier–Motzkin: project {A z <= b} along coordinate j (then drop redundant rows)."""
    pos, neg = np.flatnonzero(A[:, j] > 1e-13), np.flatnonzero(A[:, j] < -1e-13)
    zer = np.flatnonzero(np.abs(A[:, j]) <= 1e-13)
    P, Q = np.meshgrid(pos, neg, indexing="ij")
    P, Q = P.ravel(), Q.ravel()
    wp, wq = -A[Q, j][:, None], A[P, j][:, None]
    A2 = np.vstack([A[zer], wp * A[P] + wq * A[Q]])
    b2 = np.concatenate([b[zer], wp[:, 0] * b[P] + wq[:, 0] * b[Q]])
    return _prune(np.delete(A2, j, axis=1), b2)


def _prune(A, b):
    """Normalised, de-duplicated, irredundant rows of {A z <= b} (one LP per row, HiGHS)."""
    from scipy.optimize import linprog

    n = np.abs(A).max(axis=1)
    keep = n > 1e-12
    if np.any(~keep & (b < -1e-12)):
        raise ValueError("empty polyhedron")
    A, b = A[keep] / n[keep, None], b[keep] / n[keep]
    _, first = np.unique(np.round(np.column_stack([A, b]), 10), axis=0, return_index=True)
    A, b = A[np.sort(first)], b[np.sort(first)]
    i = 0
    while i < len(A):
        rest = np.arange(len(A)) != i
        res = linprog(-A[i], A_ub=A[rest], b_ub=b[rest], bounds=(None, None), method="highs")
        if res.status == 0 and -res.fun <= b[i] + 1e-9 * (1.0 + abs(b[i])):
            A, b = A[rest], b[rest]
        else:
            i += 1
    return A, b


@lru_cache(maxsize=64)
def _cohesive_rows(a, c, f, C, T):
    """Facets of (micro-field domain) + cone(eq. 15), rows parallel to N_1..N_4 first (scaled
    like them), the others normalised to a largest coefficient of 1. Cached: a few LPs."""
    eq15 = _eq15(a, c, f)
    A, b = _micro_field_rows(a, c, f, C, T)
    for _ in range(2):                                 # eliminate u, w
        A, b = _eliminate(A, b, 3)
    # Minkowski sum with the eq. 15 cone: σ = σ1 + σ2, A σ1 <= b, N σ2 <= 0; eliminate σ2
    Z = np.zeros((len(eq15), 3))
    A = np.vstack([np.hstack([A, -A]), np.hstack([Z, eq15])])
    b = np.concatenate([b, np.zeros(len(eq15))])
    for _ in range(3):
        A, b = _eliminate(A, b, 3)
    rows, rhs, used = [], [], np.zeros(len(A), bool)
    for N in eq15:
        for i, Ai in enumerate(A):
            s = np.abs(N).max() / np.abs(Ai).max()
            if not used[i] and np.allclose(Ai * s, N, atol=1e-9):
                rows.append(N)
                rhs.append(b[i] * s)
                used[i] = True
    order = np.lexsort(np.column_stack([A, b])[~used].T[::-1])
    rows += list(A[~used][order])
    rhs += list(b[~used][order])
    return tuple(map(tuple, rows)), tuple(rhs)


def _eq15(a, c, f):
    """Normals N_k of eq. 15: ±τ + fσ_z <= 0, (a/c)σ_x + fσ_z ± (1 + fa/c)τ <= 0."""
    k = a / c
    return np.array([(0.0, f, 1.0), (0.0, f, -1.0), (k, f, 1.0 + f * k), (k, f, -(1.0 + f * k))])


class Homogenised(_Polyhedral):
    """Running-bond masonry homogenised (de Buhan & de Felice 1997), paper eq. 15.

    Blocks of height a and length 2c, rigid and infinitely strong; joints with Coulomb friction
    f, cohesion C (``cohesion``, Pa) and a tensile cut-off T (``tension``, Pa): a joint carries
    (σ_n, τ) with |τ| + fσ_n <= C and σ_n <= T (T beyond the Coulomb apex C/f, or T without C,
    has no effect). With C = 0 this is eq. 15 as printed:
        N_k·σ <= 0,  N_1,2 = (0, f, ±1),  N_3,4 = (a/c, f, ±(1 + f a/c)).
    With C > 0, G is the set of macroscopic stresses carried by the piecewise-constant micro
    field of the static proof of eq. 15 (``_micro_field_rows``), plus the cone of eq. 15
    (Minkowski sum: the true domain is convex and contains both); its facets are computed by
    Fourier–Motzkin elimination. For T >= C/f this gives
        ±τ + fσ_z <= C,   (a/c)σ_x + fσ_z ± (1 + fa/c)τ <= C + (a/c)(C/f),
    the eq. 15 cone translated to the apex σ* = (C/f, C/f, 0): π(d) = (C/f)(d_xx + d_zz);
    a lower T adds facets (σ_z <= T among them). It is a static (inner) estimate of the cohesive
    homogenised domain, equal to eq. 15 for C = 0.
    """

    def __init__(self, a: float, c: float, f: float, cohesion: float = 0.0,
                 tension: float = 0.0):
        self.a = check_range("a", a, 0.0, lo_open=True, unit="m")
        self.c = check_range("c", c, 0.0, lo_open=True, unit="m")
        self.f = check_range("f", f, 0.0, lo_open=True)
        self.cohesion = check_range("cohesion", cohesion, 0.0, unit="Pa")
        self.tension = check_range("tension", tension, 0.0, unit="Pa")
        if self.cohesion == 0.0:
            self.normals, self.rhs = _eq15(self.a, self.c, self.f), np.zeros(4)
        else:
            rows, rhs = _cohesive_rows(self.a, self.c, self.f, self.cohesion,
                                       min(self.tension, self.cohesion / self.f))
            self.normals, self.rhs = np.array(rows), np.array(rhs)

    @property
    def dry(self) -> bool:
        """True without cohesion: G is the cone of eq. 15 and π is 0 or +inf."""
        return self.cohesion == 0.0

    @property
    def facets(self) -> np.ndarray:
        """Rows F of the cone generated by N_1..N_4: d ∈ cone(N) ⇔ F d >= 0, i.e.
        d_xx >= 0,  d_zz >= f (c/a) d_xx,  |γ_xz| <= d_zz/f + f d_xx   (eliminating μ >= 0 in
        d = Σ μ_k N_k: μ_3 + μ_4 = (c/a) d_xx, μ_1 + μ_2 = d_zz/f − (c/a) d_xx)."""
        a, c, f = self.a, self.c, self.f
        return np.array([[1.0, 0.0, 0.0], [-f * c / a, 1.0, 0.0],
                         [f, 1.0 / f, -1.0], [f, 1.0 / f, 1.0]])

    def support(self, d):
        return _polyhedral_support(self.normals, self.rhs, d)

    def kinematic_cone(self) -> ConicBlock:
        """Facet form F d >= 0 when G has the four facets of eq. 15; π is then linear on it.

        With r_1 = r_2 = C and r_3 = r_4 = R, π = C(μ_1 + μ_2) + R(μ_3 + μ_4)
        = C (d_zz/f − (c/a) d_xx) + R (c/a) d_xx, whatever the split of the μ's: cx·d with
        cx = ((R − C) c/a, C/f, 0), and cx = 0 in the dry case. Otherwise (a tension cut-off
        below C/f adds facets) the generator form (``generator_cone``) is used.
        """
        r = self.rhs
        four = (self.normals.shape == (4, 3)
                and np.allclose(self.normals, _eq15(self.a, self.c, self.f), rtol=1e-12)
                and np.isclose(r[0], r[1], rtol=1e-12) and np.isclose(r[2], r[3], rtol=1e-12))
        if not four:
            return self.generator_cone()
        C, R, k = 0.5 * (r[0] + r[1]), 0.5 * (r[2] + r[3]), self.c / self.a
        return ConicBlock(A=self.facets, D=np.zeros((4, 0)), e=np.zeros(4), n_lin=4,
                          cx=np.array([(R - C) * k, C / self.f, 0.0]))


class BedJoints(_Polyhedral):
    """Façade cut across its thickness: horizontal bed joints only, Coulomb friction f.

    G = {±τ + fσ_z <= C, σ_z <= T_h} with σ_x unbounded (no head joints cross the section);
    T_h = min(T, C/f). Dry (C = T = 0): |τ| + fσ_z <= 0. Since σ_x is free, π(d) = +inf unless
    d_xx = 0; then π = T_h d_zz + (C − f T_h)|γ| where d_zz >= f|γ| (vertex (T_h, ±(C − fT_h))
    of the joint domain), +inf otherwise.

    ``fc`` > 0 (a joint's compression cap, issue 30; 0: none) adds the linear facet
    −σ_z <= fc: the joint's normal stress σ_n = σ_z >= −fc. Its dual splits the jump into a
    Coulomb part and a pure closing normal part j2 = (0, j2_zz <= 0, 0) dissipating
    fc·(−j2_zz): π = T_h d_zz + (C − fT_h)|γ| where d_zz >= f|γ|, and
    π = −fc d_zz + (C + f fc)|γ| where d_zz < f|γ| (the vertex (−fc, ±(C + f fc))), finite
    whenever d_xx = 0. For a joint the cap is this linear row; a continuum of bed joints takes
    the principal-stress cap instead (``Capped``).
    """

    def __init__(self, f: float, cohesion: float = 0.0, tension: float = 0.0,
                 fc: float = 0.0):
        self.f = check_range("f", f, 0.0, lo_open=True)
        self.cohesion = check_range("cohesion", cohesion, 0.0, unit="Pa")
        self.tension = check_range("tension", tension, 0.0, unit="Pa")
        self.fc = check_range("fc", fc, 0.0, unit="Pa")
        f, C = self.f, self.cohesion
        self.t_h = min(self.tension, C / f)
        rows, rhs = [(0.0, f, 1.0), (0.0, f, -1.0)], [C, C]
        if C > 0 and self.t_h < C / f:
            rows.append((0.0, 1.0, 0.0))
            rhs.append(self.t_h)
        if self.fc > 0:
            rows.append((0.0, -1.0, 0.0))
            rhs.append(self.fc)
        self.normals = np.array(rows)
        self.rhs = np.array(rhs)

    def support(self, d, rtol: float = 1e-9):
        d = np.asarray(d, float)
        dxx, dzz, g = d[..., 0], d[..., 1], d[..., 2]
        tol = rtol * (1.0 + _norm(d))
        opening = dzz - self.f * np.abs(g) >= -tol
        ok = (np.abs(dxx) <= tol) & (opening | (self.fc > 0))
        val = self.t_h * dzz + (self.cohesion - self.f * self.t_h) * np.abs(g)
        if self.fc > 0:
            val = np.where(opening, val,
                           -self.fc * dzz + (self.cohesion + self.f * self.fc) * np.abs(g))
        return np.where(ok, val, np.inf)

    def kinematic_cone(self) -> ConicBlock:
        """Dry: d_xx = 0 (equality) and d_zz/f ∓ γ >= 0, π = 0. Otherwise (cohesion or a cap)
        the generator form, whose first equality row reads d_xx = 0 since every N_k has
        N_k,x = 0."""
        if self.cohesion > 0 or self.fc > 0:
            return self.generator_cone()
        f = self.f
        A = np.array([[1.0, 0.0, 0.0], [0.0, 1.0 / f, -1.0], [0.0, 1.0 / f, 1.0]])
        return ConicBlock(A=A, D=np.zeros((3, 0)), e=np.zeros(3), n_eq=1, n_lin=2)


class Tresca(StrengthDomain):
    """Plane-strain Tresca (von Mises in plane strain): √(((σ_x − σ_z)/2)² + τ²) <= k.

    π(d) = k √((d_xx − d_zz)² + γ²) if d_xx + d_zz = 0 (isochoric), +inf otherwise.
    """

    def __init__(self, k: float):
        self.k = check_range("k", k, 0.0, lo_open=True, unit="Pa")

    def is_admissible(self, sigma, tol: float = 1e-9):
        s = np.asarray(sigma, float)
        q = np.hypot(0.5 * (s[..., 0] - s[..., 1]), s[..., 2])
        return q <= self.k + tol * (self.k + _norm(s))

    def support(self, d, rtol: float = 1e-9):
        d = np.asarray(d, float)
        ok = np.abs(d[..., 0] + d[..., 1]) <= rtol * (1.0 + _norm(d))
        val = self.k * np.hypot(d[..., 0] - d[..., 1], d[..., 2])
        return np.where(ok, val, np.inf)

    def kinematic_cone(self) -> ConicBlock:
        """d_xx + d_zz = 0;  (t, d_xx − d_zz, γ) ∈ SOC(3);  π = k t (one auxiliary t)."""
        A = np.array([[1.0, 1.0, 0.0], [0.0, 0.0, 0.0], [1.0, -1.0, 0.0], [0.0, 0.0, 1.0]])
        D = np.array([[0.0], [1.0], [0.0], [0.0]])
        return ConicBlock(A=A, D=D, e=np.zeros(4), n_eq=1, soc=(3,), cy=np.array([self.k]))

    def static_cone(self) -> ConicBlock:
        """(k, (σ_x − σ_z)/2, τ) ∈ SOC(3)."""
        A = np.array([[0.0, 0.0, 0.0], [0.5, -0.5, 0.0], [0.0, 0.0, 1.0]])
        return ConicBlock(A=A, D=np.zeros((3, 0)), e=np.array([self.k, 0.0, 0.0]), soc=(3,))


class MohrCoulomb(StrengthDomain):
    """Plane-strain Mohr–Coulomb, tension positive: √(((σ_x − σ_z)/2)² + τ²) <= c cosφ − p sinφ,
    p = (σ_x + σ_z)/2.

    π(d) = c cotφ (d_xx + d_zz) if d_xx + d_zz >= sinφ √((d_xx − d_zz)² + γ²), +inf otherwise
    (the supremum over p of p (tr d − sinφ |e|) + c cosφ |e| is reached at the apex p = c cotφ).
    """

    def __init__(self, cohesion: float, phi_deg: float):
        self.cohesion = check_range("cohesion", cohesion, 0.0, lo_open=True, unit="Pa")
        self.phi_deg = check_range("phi_deg", phi_deg, 0.0, 90.0, lo_open=True, hi_open=True,
                                   unit="deg")
        phi = np.radians(self.phi_deg)
        self.sin, self.cos = float(np.sin(phi)), float(np.cos(phi))

    def is_admissible(self, sigma, tol: float = 1e-9):
        s = np.asarray(sigma, float)
        q = np.hypot(0.5 * (s[..., 0] - s[..., 1]), s[..., 2])
        p = 0.5 * (s[..., 0] + s[..., 1])
        return q <= self.cohesion * self.cos - p * self.sin + tol * (self.cohesion + _norm(s))

    def support(self, d, rtol: float = 1e-9):
        d = np.asarray(d, float)
        tr = d[..., 0] + d[..., 1]
        ok = tr - self.sin * np.hypot(d[..., 0] - d[..., 1], d[..., 2]) >= -rtol * (1 + _norm(d))
        return np.where(ok, self.cohesion * self.cos / self.sin * tr, np.inf)

    def kinematic_cone(self) -> ConicBlock:
        """(d_xx + d_zz, sinφ (d_xx − d_zz), sinφ γ) ∈ SOC(3);  π = c cotφ (d_xx + d_zz)."""
        s = self.sin
        A = np.array([[1.0, 1.0, 0.0], [s, -s, 0.0], [0.0, 0.0, s]])
        cot = self.cos / self.sin
        return ConicBlock(A=A, D=np.zeros((3, 0)), e=np.zeros(3), soc=(3,),
                          cx=self.cohesion * cot * np.array([1.0, 1.0, 0.0]))

    def static_cone(self) -> ConicBlock:
        """(c cosφ − sinφ (σ_x + σ_z)/2, (σ_x − σ_z)/2, τ) ∈ SOC(3)."""
        s = self.sin
        A = np.array([[-0.5 * s, -0.5 * s, 0.0], [0.5, -0.5, 0.0], [0.0, 0.0, 1.0]])
        return ConicBlock(A=A, D=np.zeros((3, 0)), e=np.array([self.cohesion * self.cos, 0, 0]),
                          soc=(3,))


class Rigid(StrengthDomain):
    """An infinitely strong, rigid material: π(d) = 0 if d = 0, +inf otherwise; G = R³.

    For rigid blocks (e.g. the free-standing block). Kinematic cone: d = 0. The static program
    does not put stresses in a rigid region: each connected rigid region is one body in
    equilibrium under the resultants on its boundary (``homlimit.fe.static``).
    """

    def is_admissible(self, sigma, tol: float = 1e-9):
        return np.ones(np.shape(sigma)[:-1], bool)

    def support(self, d, rtol: float = 1e-9):
        d = np.asarray(d, float)
        return np.where(np.all(np.abs(d) <= rtol, axis=-1), 0.0, np.inf)

    def kinematic_cone(self) -> ConicBlock:
        return ConicBlock(A=np.eye(3), D=np.zeros((3, 0)), e=np.zeros(3), n_eq=3)

    def static_cone(self) -> ConicBlock:
        return ConicBlock(A=np.zeros((0, 3)), D=np.zeros((0, 0)), e=np.zeros(0))


def _stack_kinds(*parts):
    """Rows (A, D, e) of several blocks' pieces, each piece tagged with its kind, reordered
    into one ConicBlock's order eq, lin, soc: [(kind, A, D, e, soc sizes)]."""
    out = {}
    for kind in ("eq", "lin", "soc"):
        got = [p for p in parts if p[0] == kind and p[1].shape[0]]
        out[kind] = got
    rows = [p for kind in ("eq", "lin", "soc") for p in out[kind]]
    A = np.vstack([p[1] for p in rows])
    D = np.vstack([p[2] for p in rows])
    e = np.concatenate([p[3] for p in rows])
    soc = tuple(q for p in out["soc"] for q in p[4])
    return A, D, e, sum(p[1].shape[0] for p in out["eq"]), \
        sum(p[1].shape[0] for p in out["lin"]), soc


def _pieces(blk: ConicBlock, A: np.ndarray, D: np.ndarray):
    """``blk``'s rows split by kind, with their A and D columns replaced by ``A``, ``D``."""
    ends = np.cumsum([0, blk.n_eq, blk.n_lin, sum(blk.soc)])
    return [(kind, A[lo:hi], D[lo:hi], blk.e[lo:hi], blk.soc if kind == "soc" else ())
            for kind, lo, hi in zip(("eq", "lin", "soc"), ends[:-1], ends[1:])]


# σ + fc I ⪰ 0 (a 2×2 symmetric matrix is PSD iff its trace bounds the norm of the rest):
# (σ_x + σ_z + 2fc, σ_x − σ_z, 2τ) ∈ SOC(3)
_PSD_ROWS = np.array([[1.0, 1.0, 0.0], [1.0, -1.0, 0.0], [0.0, 0.0, 2.0]])
# D ⪯ 0 for the tensor D = [[d_xx, γ/2], [γ/2, d_zz]] of d = (d_xx, d_zz, γ):
# (−d_xx − d_zz, d_xx − d_zz, γ) ∈ SOC(3)
_NSD_ROWS = np.array([[-1.0, -1.0, 0.0], [1.0, -1.0, 0.0], [0.0, 0.0, 1.0]])


class Capped(StrengthDomain):
    """A continuum domain G with a compression cap (issue 30): G_c = G ∩ C,
    C = {σ : σ + fc I ⪰ 0}, i.e. the most compressive principal stress >= −fc.

    Static: G's rows plus one second-order cone (σ_x + σ_z + 2fc, σ_x − σ_z, 2τ) ∈ SOC(3).

    Kinematic (the support function of the intersection). π_C(d) = sup{σ : D, σ ⪰ −fc I}
    = −fc tr D if D ⪯ 0, +inf otherwise (D the strain-rate tensor of d, σ : D = σ·d with the
    engineering shear γ): σ = −fc I + S, S ⪰ 0, and sup_S S : D is 0 for D ⪯ 0, +inf otherwise.
    Since 0 ∈ G lies in the interior of C, the support function of G ∩ C is the infimal
    convolution (Rockafellar, Convex Analysis, Cor. 16.4.1)

        π_c(d) = min{ π_G(d1) + fc·(−tr d2) : d = d1 + d2, d2 ⪯ 0 },

    (d1 in the domain of π_G, d2 a compaction; finite for every d when that domain holds a
    positive definite strain rate, as eq. 15's cone does). As a ConicBlock: y = (G's
    auxiliaries, d2), G's rows on d − d2, the cone
    (−d2_xx − d2_zz, d2_xx − d2_zz, d2_γ) ∈ SOC(3), cost cx·(d − d2) + cy·y_G − fc tr d2.
    Quadratic static stresses stay rigorous with the cap on every Bernstein coefficient
    (C is convex).
    """

    def __init__(self, base: StrengthDomain, fc: float):
        if not isinstance(base, StrengthDomain) or isinstance(base, (Capped, Rigid)):
            raise ValueError(f"Capped: base = {base!r} is out of range: allowed a continuum "
                             "StrengthDomain (not Rigid, not already capped)")
        self.base = base
        self.fc = check_range("fc", fc, 0.0, lo_open=True, unit="Pa")

    def __getattr__(self, name):          # the base's facts (f, cohesion, a, c, ...)
        if name == "base":
            raise AttributeError(name)
        return getattr(self.base, name)

    def is_admissible(self, sigma, tol: float = 1e-9):
        s = np.asarray(sigma, float)
        low = 0.5 * (s[..., 0] + s[..., 1]) - np.hypot(0.5 * (s[..., 0] - s[..., 1]), s[..., 2])
        return self.base.is_admissible(s, tol) & (low >= -self.fc - tol * (self.fc + _norm(s)))

    def support(self, d):
        """π_c(d) by the ConicBlock (a small conic program per point: for checks, not for the
        programs, which stack the block)."""
        import cvxpy as cp

        d = np.asarray(d, float)
        blk = self.kinematic_cone()
        out = np.empty(d.shape[:-1])
        for idx in np.ndindex(out.shape):
            y = cp.Variable(blk.n_aux)
            r = blk.A @ d[idx] + blk.D @ y + blk.e
            cons, o = [], 0
            if blk.n_eq:
                cons.append(r[:blk.n_eq] == 0)
            if blk.n_lin:
                cons.append(r[blk.n_eq:blk.n_eq + blk.n_lin] >= 0)
            o = blk.n_eq + blk.n_lin
            for q in blk.soc:
                cons.append(cp.SOC(r[o], r[o + 1:o + q]))
                o += q
            prob = cp.Problem(cp.Minimize(blk.cx @ d[idx] + blk.cy @ y), cons)
            prob.solve(solver="CLARABEL")
            out[idx] = prob.value if prob.status in ("optimal", "optimal_inaccurate") else np.inf
        return out

    def static_cone(self) -> ConicBlock:
        b = self.base.static_cone()
        na = b.n_aux
        A, D, e, n_eq, n_lin, soc = _stack_kinds(
            *_pieces(b, b.A, b.D),
            ("soc", _PSD_ROWS, np.zeros((3, na)), np.array([2.0 * self.fc, 0.0, 0.0]), (3,)))
        return ConicBlock(A=A, D=D, e=e, n_eq=n_eq, n_lin=n_lin, soc=soc)

    def kinematic_cone(self) -> ConicBlock:
        b = self.base.kinematic_cone()
        na = b.n_aux
        # y = (y_G, d2): G's rows on d1 = d − d2, i.e. A d + D y_G − A d2 + e
        D_base = np.hstack([b.D, -b.A])
        D_cap = np.hstack([np.zeros((3, na)), _NSD_ROWS])
        A, D, e, n_eq, n_lin, soc = _stack_kinds(
            *_pieces(b, b.A, D_base),
            ("soc", np.zeros((3, 3)), D_cap, np.zeros(3), (3,)))
        cy = np.concatenate([b.cy, -b.cx - self.fc * np.array([1.0, 1.0, 0.0])])
        return ConicBlock(A=A, D=D, e=e, n_eq=n_eq, n_lin=n_lin, soc=soc, cx=b.cx, cy=cy)


def capped(domain: StrengthDomain, fc: float) -> StrengthDomain:
    """``domain`` with the compression cap fc (``Capped``), or ``domain`` itself for fc = 0
    (infinite strength: the paper's programs, unchanged)."""
    return domain if fc == 0 else Capped(domain, fc)
