"""The shared solver layer: the conic stacker against a per-point loop, the retry ladder against
the measured defaults it must encode (docs/kinematic.md, docs/static.md), status causes."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp

from homlimit.errors import ParameterError, SolverError
from homlimit.fe.conic import stack
from homlimit.fe.solver import (
    FAER_ABOVE,
    REFINE_ABOVE,
    STATIC_REG,
    SolverOptions,
    check_status,
    run_ladder,
)
from homlimit.fe.strength import ConicBlock


def _block():
    """One eq row, two lin rows, SOC(3) and SOC(2): 8 rows, 2 auxiliaries."""
    rng = np.random.default_rng(1)
    return ConicBlock(A=rng.normal(size=(8, 3)), D=rng.normal(size=(8, 2)),
                      e=rng.normal(size=8), n_eq=1, n_lin=2, soc=(3, 2))


@pytest.mark.parametrize("order", ["point", "row"])
def test_stack_matches_a_loop_over_points(order):
    """s_p (A X_p u + D y_p + e) at every point, compared row by row with the stacked rows."""
    rng = np.random.default_rng(2)
    blk, n, N = _block(), 4, 9
    X = sp.random(3 * n, N, density=0.5, random_state=3, format="csr")
    u, y, s = rng.normal(size=N), rng.normal(size=2 * n), rng.uniform(1, 2, n)
    st = stack(blk, X, s, order=order)
    per_point = np.stack([s[p] * (blk.A @ (X[3 * p:3 * p + 3] @ u) + blk.D @ y[2 * p:2 * p + 2]
                                  + blk.e) for p in range(n)])          # (n, 8)
    got = {k: r.M @ u + r.D @ y + r.e for k, r in st.kinds.items()}
    assert set(got) == {"eq", "lin", "soc"}
    assert np.allclose(st.per_point(got), per_point, rtol=1e-13, atol=1e-13)
    if order == "point":  # the cones are consecutive, point by point
        assert st.soc == [3, 2] * n
        assert np.allclose(got["soc"].reshape(n, 5), per_point[:, 3:], rtol=1e-13)
    else:                 # row 3 (the first cone's t) of every point first
        assert np.allclose(got["soc"][:n], per_point[:, 3], rtol=1e-13)


def test_static_ladder_is_the_measured_one():
    """Static: regularisation 1e-7, 1e-6, the other factorisation (one thread), Clarabel's
    defaults; faer on one thread above FAER_ABOVE unknowns; raw settings applied last."""
    ladder = SolverOptions(settings={"max_iter": 50}).ladder("static", 100, conic=True)
    rungs = [r for r, _ in ladder]
    assert rungs == [{"static_regularization_constant": 1e-7},
                     {"static_regularization_constant": 1e-6},
                     {"direct_solve_method": "faer", "max_threads": 1}, {}]
    first = ladder[0][1]
    assert first["tol_feas"] == 1e-7 and first["max_iter"] == 50
    assert first["direct_solve_method"] == "qdldl"
    big = SolverOptions().ladder("static", FAER_ABOVE + 1, conic=False)
    assert big[0][1]["max_iter"] == 300 and big[0][1]["tol_gap_rel"] == 1e-9
    assert big[2][0] == {"direct_solve_method": "qdldl", "max_threads": 1}
    assert len(SolverOptions(retries=False).ladder("static", 100, False)) == 1


def test_kinematic_ladder_retries_a_stalled_lp_with_refinement_then_tol_1e7():
    """Kinematic: refinement off for an LP up to REFINE_ABOVE free unknowns, retried with it,
    then with tolerance 1e-7 (default tolerance only), then with static regularisation 1e-6 at the
    previous rung's tolerance; refinement on for larger LPs (then the 1e-7 and step rungs
    follow); no retry with cones; a chosen tolerance is kept."""
    lp = SolverOptions().ladder("kinematic", REFINE_ABOVE, conic=False)
    assert [s["iterative_refinement_enable"] for _, s in lp] == [False, True, True, True]
    assert [s["tol_gap_rel"] for _, s in lp] == [1e-9, 1e-9, 1e-7, 1e-7]
    assert [s.get("static_regularization_constant") for _, s in lp] == [None] * 3 + [1e-6]
    assert STATIC_REG == 1e-6
    assert lp[0][1]["max_iter"] == 400 and lp[0][1]["direct_solve_method"] == "qdldl"
    big = SolverOptions().ladder("kinematic", REFINE_ABOVE + 1, conic=False)
    assert [s["tol_gap_rel"] for _, s in big] == [1e-9, 1e-7, 1e-7]
    assert len(SolverOptions().ladder("kinematic", 10, conic=True)) == 1
    chosen = SolverOptions(tol=1e-8).ladder("kinematic", 10, False)   # the user's tolerance
    assert [s["tol_gap_rel"] for _, s in chosen] == [1e-8, 1e-8, 1e-8]
    assert chosen[-1][0] == {"iterative_refinement_enable": True,
                             "static_regularization_constant": 1e-6}
    forced = SolverOptions(iterative_refinement=False).ladder("kinematic", 10, False)
    assert [s["tol_gap_rel"] for _, s in forced] == [1e-9, 1e-7, 1e-7]


def test_run_ladder_stops_at_the_first_solve_that_does_not_stall():
    statuses = iter(["AlmostSolved", "NumericalError", "Solved", "never reached"])
    status, attempts = run_ladder(lambda s: (next(statuses), 7),
                                  SolverOptions().ladder("static", 100, False))
    assert status == "Solved"
    assert [a[1] for a in attempts] == ["AlmostSolved", "NumericalError", "Solved"]


def test_statuses_read_as_duals_of_each_other():
    """The kinematic program's infeasibility is the static one's unboundedness (and vice versa):
    both name the same cause; optimal statuses pass."""
    check_status("kinematic", "optimal", "CLARABEL")
    check_status("static", "Solved", "CLARABEL")
    msgs = {}
    for bound, status in (("kinematic", "infeasible"), ("static", "DualInfeasible"),
                          ("kinematic", "unbounded"), ("static", "PrimalInfeasible")):
        with pytest.raises(SolverError) as exc:
            check_status(bound, status, "CLARABEL")
        assert exc.value.status == status and repr(status) in str(exc.value)
        msgs[bound, status] = str(exc.value).split(": ", 1)[1]
    assert msgs["kinematic", "infeasible"] == msgs["static", "DualInfeasible"]
    assert msgs["kinematic", "unbounded"] == msgs["static", "PrimalInfeasible"]
    with pytest.raises(SolverError, match="2 attempt"):
        check_status("static", "AlmostSolved", "CLARABEL",
                     [({}, "AlmostSolved", 3), ({}, "AlmostSolved", 4)])


def test_one_chain_for_the_three_programs():
    """The rigid-block LP takes the kinematic LP's settings and rungs, and faer on one thread
    above FAER_ABOVE unknowns like the static program (the FE kinematic LP keeps qdldl); a
    status reads by the program: cvxpy's "unbounded" on the static program (λ unbounded) is
    the kinematic program's "infeasible"."""
    kin = SolverOptions().ladder("kinematic", 1000, conic=False)
    blk = SolverOptions().ladder("blocks", 1000, conic=False)
    assert blk == kin
    assert SolverOptions().ladder("blocks", FAER_ABOVE + 1, False)[0][1]["direct_solve_method"] \
        == "faer"
    assert SolverOptions().ladder("blocks", FAER_ABOVE + 1, False)[0][1]["max_threads"] == 1
    assert SolverOptions().ladder("blocks", FAER_ABOVE, False)[0][1]["direct_solve_method"] \
        == "qdldl"
    big_kin = SolverOptions().ladder("kinematic", FAER_ABOVE + 1, False)[0][1]
    assert big_kin["direct_solve_method"] == "qdldl" and "max_threads" not in big_kin
    chosen = SolverOptions(direct_solve_method="qdldl").ladder("blocks", FAER_ABOVE + 1, False)
    assert chosen[0][1]["direct_solve_method"] == "qdldl"
    with pytest.raises(ParameterError, match="program = 'dem'"):
        SolverOptions().ladder("dem", 10, False)
    msgs = {}
    for program, status in (("kinematic", "infeasible"), ("blocks", "infeasible"),
                            ("static", "unbounded"), ("static", "DualInfeasible"),
                            ("blocks", "unbounded"), ("static", "infeasible")):
        with pytest.raises(SolverError) as exc:
            check_status(program, status, "CLARABEL")
        msgs[program, status] = str(exc.value).split(": ", 1)[1]
    assert (msgs["kinematic", "infeasible"] == msgs["blocks", "infeasible"]
            == msgs["static", "unbounded"] == msgs["static", "DualInfeasible"])
    assert msgs["blocks", "unbounded"] == msgs["static", "infeasible"]
    assert "dead loads" in msgs["blocks", "unbounded"]
    with pytest.raises(SolverError, match="^rigid-block limit analysis ended"):
        check_status("blocks", "user_limit", "CLARABEL")


@pytest.mark.slow
def test_a_very_low_friction_part_is_solved_on_the_regularised_rung():
    """B1 at f = 0.001 (issue 27), the scan's part of 1.169 m (default mesh, h/30): Clarabel
    stalls at primal/dual residual 1.6e-7 > tol 1e-7 with and without iterative refinement
    (AlmostSolved), and solves with static regularisation 1e-6 at the same tolerance. The
    collapse multiplier of a wall whose joints hardly hold is the friction coefficient (the
    whole wall slides): 0.001 (measured 1.0000045e-3)."""
    import dataclasses

    from homlimit.mechanism.analysis import _analyse_height
    from homlimit.params import Case

    case = Case(name="B1")
    case = dataclasses.replace(case, masonry=dataclasses.replace(case.masonry, f=0.001))
    rec = _analyse_height(case, 0.25, "bedjoints", None, 30,             # the crossed grid:
                          float(np.geomspace(0.3, 9.0, 6)[2]), mesher="crossed").record()
    assert rec["retries"] == 2 and rec["solver_tol"] == 1e-7
    assert rec["multiplier"] == pytest.approx(0.001, rel=1e-4)
