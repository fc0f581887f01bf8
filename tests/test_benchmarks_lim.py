"""Classical limit-analysis benchmarks: the kinematic FE bound against published exact values.

- Prandtl strip footing, weightless Tresca: q/k = 2 + π (exact); an upper bound never below it.
- Vertical cut, Tresca with weight: 3.7752 <= γH/k <= 3.7776 (Kammoun et al. 2010).
- Weightless Mohr–Coulomb footing, φ = 30°: N_c = (N_q − 1) cot φ = 30.14 (Prandtl–Reissner).
- Free-standing rigid block on a frictional bed joint: λ = min(b/h, f) (rigid-block statics).
Finer meshes and the fitted convergence rates are in benchmarks/bench_classical.py.
"""

from __future__ import annotations

import numpy as np
import pytest

from homlimit.fe.kinematic import solve_kinematic
from homlimit.fe.problems import (
    PRANDTL,
    VERTICAL_CUT_LB,
    VERTICAL_CUT_UB,
    free_block,
    mohr_coulomb_footing,
    mohr_coulomb_nc,
    prandtl,
    vertical_cut,
)
from homlimit.fe.static import solve_static


def test_mohr_coulomb_nc_closed_form():
    assert mohr_coulomb_nc(30.0) == pytest.approx(30.14, abs=0.005)
    # φ → 0: N_c → 2 + π
    assert mohr_coulomb_nc(1e-4) == pytest.approx(PRANDTL, rel=1e-4)


@pytest.mark.slow
def test_prandtl_upper_bound_within_one_percent_and_converging():
    meshes = [(0.08, 0.6), (0.04, 0.4), (0.02, 0.3)]
    lams, tris = [], []
    for h_min, h_max in meshes:
        prob = prandtl(h_min=h_min, h_max=h_max)
        lams.append(solve_kinematic(prob).multiplier)
        tris.append(prob.n_triangles)
    err = np.array(lams) / PRANDTL - 1
    assert np.all(err >= -1e-7), f"upper bound below 2 + π: {lams}"
    assert np.all(np.diff(err) < 0), f"error does not fall with refinement: {err}"
    assert tris[-1] <= 20_000 and err[-1] < 0.01, f"{tris[-1]} triangles: error {err[-1]:.4f}"
    rate = -np.polyfit(np.log(tris), np.log(err), 1)[0]
    assert rate > 0.3, f"fitted rate of the error in the number of triangles: {rate:.2f}"


@pytest.mark.slow
def test_vertical_cut_within_two_percent_above_the_best_upper_bound():
    sol = solve_kinematic(vertical_cut(h_min=0.02, h_max=0.1))
    lam = sol.multiplier
    assert lam >= VERTICAL_CUT_LB
    assert VERTICAL_CUT_UB <= lam <= 1.02 * VERTICAL_CUT_UB, f"γH/k = {lam:.4f}"
    assert lam < 3.83                     # better than the classical one-wedge mechanism


@pytest.mark.slow
def test_mohr_coulomb_footing_within_two_percent_above_nc():
    prob = mohr_coulomb_footing(30.0, h_min=0.05, h_max=0.5)
    lam = solve_kinematic(prob).multiplier
    assert prob.reference <= lam <= 1.02 * prob.reference, f"N_c = {lam:.3f}"


@pytest.mark.parametrize("b, h, expect", [(0.5, 3.0, 0.5 / 3.0), (0.4, 5.0, 0.08),
                                          (0.5, 0.5, 0.6)])
def test_rigid_block_on_a_bed_joint_tilts_at_b_over_h(b, h, expect):
    """Tilting about the toe (λ = b/h) or, for a squat block, dilatant sliding (λ = f = 0.6)."""
    sol = solve_kinematic(free_block(b=b, h=h, f=0.6))
    assert sol.multiplier == pytest.approx(expect, rel=1e-6)


def test_bed_joint_continuum_is_weaker_than_the_rigid_block():
    """A strip of thin full-width courses (BedJoints everywhere) bends its courses for free:
    the multiplier falls below b/h (an admissible field proves it; values in docs)."""
    prob = free_block(b=0.5, h=3.0, n_b=4, interior="bedjoints")
    lam = solve_kinematic(prob).multiplier
    assert lam < 0.95 * (0.5 / 3.0)
    # and above a statically admissible field's (lower-bound theorem): 0.1273 <= 0.1538
    assert 0.0 < solve_static(prob).multiplier <= lam * (1 + 1e-7)
