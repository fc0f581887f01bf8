"""The failing body of a velocity field: the best-fitting rigid motion and how parts follow it.

A rigid rotation of rate ω about O = (x_O, z_O) has the velocity

    v_R(x) = ω (−(z − z_O), x − x_O) = (p_0 − ω z, p_1 + ω x),   O = (−p_1/ω, p_0/ω),

linear in (p_0, p_1, ω). ``fit_rigid`` finds it by iterated least squares over the nodes the fit
explains: start from the fastest nodes, fit, keep every moving node within ``rtol`` · max|v| of
the fit, refit, until the set stops changing; then tighten the tolerance by decades (a deforming
zone's nodes next to the block pass a loose test and bias the fit) while each decade keeps
90 % of the block's nodes. Nodes that do not move (|v| <= rtol · max|v|) are
the fixed part; the rest are neither (a smeared crack, a fan, a second body).

Per node the participation p = v·v_R / |v_R|² is 1 on the block and 0 on the fixed part (the
crack is an iso-line of p, see ``homlimit.mechanism.crack``). Per P2 element: the local spin over ω
(1 on the block, 0 fixed, 1/2 in a hinge + fan's fan) and the strain-rate intensity |d|/ω.

The kinetic-energy measures use the exact P2 mass matrix, ∫ρ|v|² = Σ_e ρ_e v_eᵀ M_e v_e.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import ParameterError, check_range

__all__ = ["RigidFit", "fit_rigid", "MechanismMeasures", "measure_mechanism", "p2_energy",
           "p2_gradients_at_centroid", "MECHANISM_TYPES"]

MECHANISM_TYPES = ("rigid", "hinge+fan", "distributed")

# P2 shape functions at the centroid, dofs (v1, v2, v3, e12, e23, e13)
_P2_CENTROID = np.array([-1, -1, -1, 4, 4, 4], float) / 9.0

# P2 mass matrix of a triangle of unit area, same dofs
_M_P2 = np.array([[6, -1, -1, 0, -4, 0],
                  [-1, 6, -1, 0, 0, -4],
                  [-1, -1, 6, -4, 0, 0],
                  [0, 0, -4, 32, 16, 16],
                  [-4, 0, 0, 16, 32, 16],
                  [0, -4, 0, 16, 16, 32]], float) / 180.0


@dataclass(frozen=True)
class RigidFit:
    """Rigid rotation of rate ω [1/s] about O (x, z) [m] fitted to the explained nodes.

    block: nodes the rigid motion explains, closer to it than to rest (slow ones near O
    included); fixed: the other nodes at rest (|v| <= rtol max|v|);
    rms: RMS residual over the block nodes [m/s]; vmax: max |v| [m/s]; n_iter: iterations.
    """

    O: tuple[float, float]  # noqa: E741 (the paper's rotation centre)
    omega: float
    block: np.ndarray
    fixed: np.ndarray
    rms: float
    vmax: float
    n_iter: int

    def velocity(self, X: np.ndarray) -> np.ndarray:
        """v_R at points X (n, 2)."""
        X = np.asarray(X, float)
        return self.omega * np.stack([-(X[:, 1] - self.O[1]), X[:, 0] - self.O[0]], axis=1)

    def participation(self, X: np.ndarray, V: np.ndarray, r_min: float = 0.0) -> np.ndarray:
        """p = v·v_R/|v_R|² (1 on the block, 0 at rest); NaN closer than r_min to O."""
        vr = self.velocity(X)
        n2 = np.einsum("ij,ij->i", vr, vr)
        p = np.full(len(vr), np.nan)
        ok = n2 > (self.omega * r_min) ** 2 + 1e-300
        p[ok] = np.einsum("ij,ij->i", np.asarray(V, float)[ok], vr[ok]) / n2[ok]
        return p


def _lstsq(X, V):
    n = len(X)
    A = np.zeros((2 * n, 3))
    A[:n, 0] = 1.0
    A[:n, 2] = -X[:, 1]
    A[n:, 1] = 1.0
    A[n:, 2] = X[:, 0]
    p, *_ = np.linalg.lstsq(A, np.r_[V[:, 0], V[:, 1]], rcond=None)
    return p


def fit_rigid(X: np.ndarray, V: np.ndarray, rtol: float = 0.02, max_iter: int = 100,
              seed: np.ndarray | None = None) -> RigidFit:
    """Best-fitting rigid rotation of the moving part of the nodal field V at nodes X.

    X, V: (n, 2) positions [m] and velocities [m/s]. rtol: a node is explained when
    |v − v_R| <= rtol · max|v|, and at rest when |v| <= rtol · max|v|. seed: the nodes of the
    first fit (default: the nodes faster than max|v|/2; ``measure_mechanism`` seeds with the
    nodes of strain-free elements, which a wide fan's fast nodes would otherwise outvote).
    """
    X = np.asarray(X, float)
    V = np.asarray(V, float)
    if X.ndim != 2 or X.shape[1] != 2 or V.shape != X.shape:
        raise ParameterError(f"X, V have shapes {X.shape}, {V.shape}: allowed equal (n, 2)")
    rtol = check_range("rtol", rtol, 0.0, 0.5, lo_open=True)
    speed = np.linalg.norm(V, axis=1)
    vmax = float(speed.max()) if len(speed) else 0.0
    if not vmax > 0:
        raise ParameterError(f"max |V| = {vmax!r} is out of range: the field must move (> 0)")
    moving = speed > rtol * vmax
    sel = speed >= 0.5 * vmax if seed is None else np.asarray(seed, bool) & moving
    if sel.sum() < 2:
        sel = speed >= np.sort(speed)[-2]
    n_prev, tol_ok = None, rtol * vmax
    it = 0
    # tighten the acceptance tolerance by decades: nodes of a deforming zone next to the block
    # pass a loose tolerance and bias the fit; stop when a decade would drop 10 % of the block
    # (a block that is rigid only to that precision, e.g. a non-unique optimum)
    for k in range(6):
        tol = rtol * 10.0 ** (-k) * vmax
        cur = sel
        for _ in range(max_iter):
            it += 1
            p = _lstsq(X[cur], V[cur])
            vr = np.stack([p[0] - p[2] * X[:, 1], p[1] + p[2] * X[:, 0]], axis=1)
            new = moving & (np.linalg.norm(V - vr, axis=1) <= tol)
            if np.array_equal(new, cur) or new.sum() < 3:
                break
            cur = new
        if new.sum() < 3 or (n_prev is not None and new.sum() < 0.9 * n_prev):
            break
        sel, n_prev, tol_ok = new, int(new.sum()), tol
    p = _lstsq(X[sel], V[sel])
    vr = np.stack([p[0] - p[2] * X[:, 1], p[1] + p[2] * X[:, 0]], axis=1)
    # the block: every node the fit explains and that is closer to v_R than to rest (slow
    # nodes near O included); at rest: the other nodes slower than the tolerance
    resid = np.linalg.norm(V - vr, axis=1)
    block = (resid <= tol_ok) & (resid <= np.maximum(speed, 1e-12 * vmax))
    om = float(p[2])
    if om == 0.0:
        raise ParameterError("omega = 0 is out of range: the fitted motion is a translation, "
                             "allowed omega != 0 (a rotation about a finite centre)")
    res = np.linalg.norm(V[sel] - vr[sel], axis=1)
    return RigidFit(O=(float(-p[1] / om), float(p[0] / om)), omega=om, block=block,
                    fixed=~moving & ~block, rms=float(np.sqrt(np.mean(res ** 2))), vmax=vmax,
                    n_iter=it)


def p2_energy(elements: np.ndarray, area: np.ndarray, density: np.ndarray,
              V: np.ndarray) -> np.ndarray:
    """Per-element ∫ρ|v|² dA of a P2 field (exact): ρ_e Σ_c v_eᶜᵀ (A_e M̂) v_eᶜ."""
    Ve = np.asarray(V, float)[np.asarray(elements, int)]  # (n_el, 6, 2)
    q = np.einsum("eic,ij,ejc->e", Ve, _M_P2, Ve)
    return np.asarray(density, float) * np.asarray(area, float) * q


def p2_gradients_at_centroid(Xv: np.ndarray, Ve: np.ndarray):
    """Velocity gradient of P2 elements at their centroids, and their areas.

    Xv: (n_el, 3, 2) vertex coordinates; Ve: (n_el, 6, 2) nodal velocities (v1, v2, v3, e12,
    e23, e13). At λ = 1/3: ∇φ_i = ∇λ_i / 3, ∇φ_ij = 4(∇λ_i + ∇λ_j) / 3.
    Returns (G (n_el, 2, 2) with G[:, i, j] = ∂v_i/∂x_j, area (n_el,)).
    """
    x, z = Xv[..., 0], Xv[..., 1]
    det = (x[:, 1] - x[:, 0]) * (z[:, 2] - z[:, 0]) - (x[:, 2] - x[:, 0]) * (z[:, 1] - z[:, 0])
    # ∇λ_i = (z_j − z_k, x_k − x_j) / det for (i, j, k) cyclic
    j, k = [1, 2, 0], [2, 0, 1]
    gl = np.stack([z[:, j] - z[:, k], x[:, k] - x[:, j]], axis=-1) / det[:, None, None]
    gphi = np.concatenate([gl / 3.0, 4.0 / 3.0 * np.stack(
        [gl[:, 0] + gl[:, 1], gl[:, 1] + gl[:, 2], gl[:, 0] + gl[:, 2]], axis=1)], axis=1)
    G = np.einsum("eai,eaj->eij", Ve, gphi)
    return G, 0.5 * np.abs(det)


@dataclass(frozen=True)
class MechanismMeasures:
    """How a velocity field splits into a rigid block, a fixed part and the rest.

    fit: the RigidFit. Energies are ∫ρ|v|² [kg m²/s² per unit thickness, i.e. 2 × kinetic].
    explained: 1 − (∫ρ|v − v̂|² on block and fixed elements + ∫ρ|v|² on the others) / ∫ρ|v|²,
    v̂ = v_R on block nodes and 0 at rest: the share of the energy the rigid fit explains;
    block_share: energy of the block elements over the total; deforming_share: energy of the
    other elements (neither block nor at rest: a smeared crack, a fan, a second body).
    Per element: participation (p at the centroid, P2 interpolant of the nodal p), spin
    (local spin / ω), strain (|d| / |ω|), label 0 fixed, 1 block, 2 deforming;
    interior_share: energy of the deforming elements touching neither a block nor a rest
    node (nil for a crack smeared over one element layer, finite for a fan several elements
    wide or a second body).
    kind: "distributed" (no rigid block carries half the energy), "rigid" (block + fixed part,
    the deforming zone one element thick) or "deforming" (a block beside a deforming zone).
    """

    fit: RigidFit
    energy: float
    explained: float
    block_share: float
    deforming_share: float
    participation: np.ndarray
    spin: np.ndarray
    strain: np.ndarray
    label: np.ndarray
    node_participation: np.ndarray
    interior_share: float

    @property
    def kind(self) -> str:
        if self.block_share < 0.5:
            return "distributed"
        return "rigid" if self.interior_share < 0.02 else "deforming"


def measure_mechanism(X: np.ndarray, V: np.ndarray, elements: np.ndarray,
                      density=1.0, rtol: float = 0.02, r_min: float = 0.0) -> MechanismMeasures:
    """Rigid fit + per-element measures of a P2 velocity field.

    X, V: (n, 2) P2 node positions and velocities; elements: (n_el, 6) node indices in the
    order (v1, v2, v3, e12, e23, e13) (scikit-fem's ElementTriP2); density: scalar or (n_el,).
    """
    X = np.asarray(X, float)
    V = np.asarray(V, float)
    el = np.asarray(elements, int)
    if el.ndim != 2 or el.shape[1] != 6:
        raise ParameterError(f"elements has shape {el.shape}: allowed (n_el, 6) P2 triangles")
    rho = np.broadcast_to(np.asarray(density, float), (len(el),))
    G, area = p2_gradients_at_centroid(X[el[:, :3]], V[el])
    w = 0.5 * (G[:, 1, 0] - G[:, 0, 1])
    d = np.stack([G[:, 0, 0], G[:, 1, 1], G[:, 0, 1] + G[:, 1, 0]], axis=1)
    dn = np.linalg.norm(d, axis=1)
    # seed: strain-free spinning elements at the dominant spin (the block's ω)
    rigid = (dn <= 1e-3 * np.abs(w)) & (np.abs(w) > 0.05 * np.abs(w).max())
    seed = None
    if rigid.sum() >= 3:
        w0 = np.median(w[rigid])
        seed = np.zeros(len(X), bool)
        seed[el[rigid & (np.abs(w - w0) <= 0.01 * abs(w0))].ravel()] = True
    fit = fit_rigid(X, V, rtol=rtol, seed=seed)
    spin = w / fit.omega
    strain = dn / abs(fit.omega)
    pn = fit.participation(X, V, r_min=r_min)
    # participation at the centroid from the P2 interpolant (vertex weight −1/9, mid-side
    # 4/9): an element with one edge on a sharp crack's fixed side gets 2/9, not 1/2
    part = pn[el] @ _P2_CENTROID  # NaN next to O (|v_R| too small to divide by)
    blk, fix = fit.block[el], fit.fixed[el]
    label = np.where(fix.all(axis=1), 0, np.where(blk.all(axis=1), 1, 2))
    e_tot = p2_energy(el, area, rho, V)
    Vhat = np.where(fit.block[:, None], fit.velocity(X), 0.0)
    keep = label < 2
    e_res = p2_energy(el, area, rho, V - Vhat)
    E = float(e_tot.sum())
    explained = 1.0 - float(e_res[keep].sum() + e_tot[~keep].sum()) / E
    interior = (label == 2) & ~blk.any(axis=1) & ~fix.any(axis=1)
    return MechanismMeasures(fit, E, explained, float(e_tot[label == 1].sum() / E),
                             float(e_tot[label == 2].sum() / E), part, spin, strain, label, pn,
                             float(e_tot[interior].sum() / E))
