"""Real walls (issue 30): finite f_c, ties and floors in mechanisms I, II and the simple
overturning, against analytic/real_walls.py (sympy: the body integrated, eq. 8's friction
integrated, θ_m by nsolve) and hand numbers; the paper's forms unchanged; the new keys'
bad input."""

from __future__ import annotations

import dataclasses
import json
import math

import numpy as np
import pytest

from analytic import real_walls as R
from homlimit.app.config import ConfigError, load_case
from homlimit.closed_form import mechanisms as M
from homlimit.closed_form import real
from homlimit.params import Case, Floor, Masonry, Tie, Wall

from cases import b1, run_cli

WALL, MAS = R.B1
B1 = Case(Wall(**WALL), Masonry(**MAS), name="B1")


def rel(a, b):
    return abs(a / b - 1)


def _check(case, kind, lam, ties=(), floors=(), fc=0.0):
    st = real._state(case, kind, [lam])
    v, th, W, _ = (float(x[0]) for x in real._velocity(case, kind, st))
    ref = R.reference(kind, WALL, MAS, lam, ties=ties, floors=floors, fc=fc, theta0=th)
    # θ_m from comparing W's values: W is flat at its peak, so θ_m is known to ~√ε (W and
    # v̄_g, which depend on it to second order, to 1e-11)
    assert rel(th, ref["theta_m"]) < 1e-6, (kind, lam, th, ref)
    assert rel(W, ref["W_m"]) < 1e-11
    assert rel(v, ref["vg"]) < 1e-10
    assert rel(float(real.multiplier_real(case, kind, [lam])[0]), ref["multiplier"]) < 1e-12
    assert float(st["t"][0]) == pytest.approx(ref["t"], rel=1e-14, abs=0)
    return ref


@pytest.mark.parametrize("kind", real.KINDS)
@pytest.mark.parametrize("Ty", [1000.0, 5000.0, 10000.0])
def test_top_tie_against_sympy(kind, Ty):
    case = dataclasses.replace(B1, ties=(Tie(9.0, Ty),))
    for lam in (18.0, 10.0):
        _check(case, kind, lam, ties=[(9.0, Ty)])


@pytest.mark.parametrize("kind", real.KINDS)
@pytest.mark.parametrize("e", [0.1, 0.4])
def test_mid_floor_against_sympy(kind, e):
    case = dataclasses.replace(B1, floors=(Floor(4.5, 20000.0, e),))
    for lam in (18.0, 12.0, 6.0):     # the floor bears on the body (z0 = 0, 3 m), not (6 m)
        _check(case, kind, lam, floors=[(4.5, 20000.0, e)])
    # a restraining floor bounds the body above it: λ <= (9 − 4.5)/0.5 = 9
    held = dataclasses.replace(B1, floors=(Floor(4.5, 20000.0, e, restrains=True),))
    r = real.real_mechanism(held, kind)
    assert r.lam_max == 9.0 if kind != "crack" else r.lam_max <= 9.0
    assert r.lam <= r.lam_max


@pytest.mark.parametrize("kind", real.KINDS)
@pytest.mark.parametrize("fc", [1e6, 2e6, 5e6])
def test_fc_hinge_retreat_against_sympy(kind, fc):
    case = dataclasses.replace(B1, masonry=dataclasses.replace(B1.masonry, fc=fc))
    ref = _check(case, kind, 18.0, fc=fc)
    if kind != "crack":     # by hand: N = γ l b H g = 529 740 N, t = N/(2 f_c l)
        assert ref["t"] == pytest.approx(2000 * 6 * 0.5 * 9 * 9.81 / (2 * fc * 6), rel=1e-14)
    _check(case, kind, 7.0, fc=fc)


@pytest.mark.parametrize("kind", real.KINDS)
def test_critical_is_a_minimum_of_the_reference(kind):
    """The critical λ of a case with a tie at 6 m and f_c: the reference v̄_g there is the
    code's, and no larger than at λ ± 1 % (a local minimum found independently)."""
    case = dataclasses.replace(B1, ties=(Tie(6.0, 3000.0),),
                               masonry=dataclasses.replace(B1.masonry, fc=2e6))
    r = real.real_mechanism(case, kind)
    kw = dict(ties=[(6.0, 3000.0)], fc=2e6)
    ref = R.reference(kind, WALL, MAS, r.lam, **kw)
    assert rel(r.vg, ref["vg"]) < 1e-9
    for lam in (r.lam * 0.99, r.lam * 1.01):
        if real.LAM_MIN <= lam <= r.lam_max:
            assert R.reference(kind, WALL, MAS, lam, **kw)["vg"] >= ref["vg"] * (1 - 1e-12)


def test_no_real_input_is_the_paper():
    """Without ties, floors and f_c the real-wall code agrees with the paper's forms (so a
    case that does not set them may keep the paper's code path); the run keeps it."""
    lam = np.array([2.0, 6.0, 12.0, 18.0])
    args = (B1.rho, B1.alpha, B1.beta)
    np.testing.assert_allclose(real.vnorm_real(B1, "detachment", lam),
                               M.vnorm_I(lam, *args), rtol=1e-14)
    np.testing.assert_allclose(real.vnorm_real(B1, "crack", lam),
                               M.vnorm_II(lam, B1.rho, B1.alpha), rtol=1e-14)
    np.testing.assert_allclose(real.multiplier_real(B1, "detachment", lam),
                               M.multiplier_I(lam, B1.rho, B1.alpha), rtol=1e-15)
    # the overturning without friction: a/g = b/h (a rigid block on its toe)
    np.testing.assert_allclose(real.multiplier_real(B1, "overturning", lam), 1 / lam,
                               rtol=1e-15)
    assert not B1.real
    from homlimit.app.models import closed_forms
    mechs, _ = closed_forms(load_case())
    assert mechs["I"] == M.mechanism_I(B1) and type(mechs["I"]) is M.MechanismResult


def test_uncapped_tie_peaks_late_and_ductility_caps_it():
    """The issue's remark: an uncapped yielding tie at 10 kN/m on B1 peaks after ~2.4 m of
    elongation (the overturning: d sin θ_m = 9 sin 0.2749 m); a ductility limit of 0.1 m
    stops the tie's work at T_y·l·0.1 = 6 kJ."""
    tied = dataclasses.replace(B1, ties=(Tie(9.0, 10000.0),))
    r = real.real_mechanism(tied, "overturning")
    assert r.tie_elongation[0] == pytest.approx(9 * math.sin(0.27493809034879), rel=1e-9)
    capped = dataclasses.replace(B1, ties=(Tie(9.0, 10000.0, ductility=0.1),))
    W = real.work_real(capped, "overturning", 18.0, [0.5, 0.6])
    free = real.work_real(B1, "overturning", 18.0, [0.5, 0.6])
    np.testing.assert_allclose(W - free, 10000.0 * 6 * 0.1, rtol=1e-14)


# ----------------------------------------------------------------------------- bad input
BASE = {"wall": dict(WALL), "masonry": dict(MAS),
        "analysis": {"fe": False, "hinge_check": False}}


def _with(**parts):
    d = json.loads(json.dumps(BASE))
    for k, v in parts.items():
        if k == "masonry":
            d["masonry"].update(v)
        else:
            d[k] = v
    return d


BAD = [
    (dict(masonry={"fc": -1.0}), "[masonry] fc = -1.0 Pa is out of range"),
    (dict(masonry={"fc": math.nan}), "[masonry] fc = nan Pa is out of range"),
    (dict(masonry={"fc": "1 MPa"}), "[masonry] fc = '1 MPa' has the wrong type"),
    (dict(masonry={"cohesion": -5.0}), "[masonry] cohesion = -5.0 Pa is out of range"),
    (dict(masonry={"tension": True}), "[masonry] tension = True has the wrong type"),
    (dict(tie=[{"z": 9.0, "yield_force": -1.0}]), "[[tie]] 0 yield_force = -1.0 N/m"),
    (dict(tie=[{"z": math.nan, "yield_force": 1.0}]), "[[tie]] 0 z = nan m is out of range"),
    (dict(tie=[{"z": 10.0, "yield_force": 1.0}]), "[[tie]] 0 z = 10.0 m is out of range: "
                                                  "allowed 0 < z <= H = 9 m"),
    (dict(tie=[{"z": 0.0, "yield_force": 1.0}]), "[[tie]] 0 z = 0.0 m is out of range"),
    (dict(tie=[{"z": 9.0, "yield_force": 1.0, "stiffness": -1}]), "[[tie]] 0 stiffness = -1"),
    (dict(tie=[{"z": 9.0, "yield_force": 1.0, "ductility": "x"}]),
     "[[tie]] 0 ductility = 'x' has the wrong type"),
    (dict(tie=[{"z": 9.0}]), "[[tie]] 0 yield_force is missing"),
    (dict(tie={"z": 9.0}), "[[tie]] = {'z': 9.0} has the wrong type"),
    (dict(floor=[{"z": -1.0, "load": 1.0, "eccentricity": 0.1}]), "[[floor]] 0 z = -1.0 m"),
    (dict(floor=[{"z": 4.0, "load": math.inf, "eccentricity": 0.1}]),
     "[[floor]] 0 load = inf N/m is out of range"),
    (dict(floor=[{"z": 4.0, "load": 1.0, "eccentricity": 0.6}]),
     "[[floor]] 0 eccentricity = 0.6 m is out of range: allowed 0 <= eccentricity <= b"),
    (dict(floor=[{"z": 4.0, "load": 1.0, "eccentricity": 0.1, "restrains": 1}]),
     "[[floor]] 0 restrains = 1 has the wrong type"),
    (dict(floor=[{"z": 9.0, "load": 1.0, "eccentricity": 0.1, "restrains": True}]),
     "[[floor]] 0 z = 9.0 m with restrains = true leaves the closed forms a failing body"),
    (dict(masonry={"cohesion": 1e5}), "[masonry] cohesion = 100000.0 Pa: the closed forms"),
    (dict(masonry={"cohesion": 1e4}, tie=[{"z": 9.0, "yield_force": 1.0}],
          analysis={"fe": True, "closed_form": False}),
     "[analysis] hinge_check = true: the hinge check's rockers do not take [masonry] "
     "cohesion = 10000.0 Pa"),
    (dict(masonry={"fc": 2e6, "tension": 1e4}, analysis={"fe": True, "hinge_check": False}),
     "[masonry] tension = 10000.0 Pa: the closed forms (mechanisms I, II, overturning) do "
     "not take a joint tension"),
    (dict(masonry={"tension": 1e5}, analysis={"fe": False, "blocks": True,
                                              "hinge_check": False, "closed_form": False},
          blocks={"friction": "non-associative"}),
     "[blocks] friction = non-associative (or non_associative_check) with [masonry] tension "
     "= 100000.0 Pa: the non-associative scheme does not take them"),
    (dict(masonry={"cohesion": 1e4}, analysis={"fe": False, "blocks": True,
                                               "hinge_check": False, "closed_form": False,
                                               "overturning": True}),
     "[masonry] cohesion = 10000.0 Pa: the closed forms (mechanisms I, II, overturning) do "
     "not take a joint cohesion"),
    (dict(tie=[{"z": 9.0, "yield_force": 1.0}], analysis={"fe": False, "blocks": True,
                                                          "hinge_check": False},
          blocks={"friction": "non-associative"}),
     "[blocks] friction = non-associative (or non_associative_check) with [[tie]]"),
    (dict(masonry={"fc": 2e6, "cohesion": 1e4},
          floor=[{"z": 4.0, "load": 1.0, "eccentricity": 0.1}],
          analysis={"fe": False, "dem": True, "hinge_check": False, "closed_form": False}),
     "[analysis] dem = true: the DEM does not take [masonry] cohesion = 10000.0 Pa"),
    (dict(masonry={"tension": 1e4}, analysis={"fe": False, "closed_form": False}),
     "[analysis] hinge_check = true: the hinge check's rockers do not take [masonry] tension "
     "= 10000.0 Pa yet"),
]


@pytest.mark.parametrize("parts, message", BAD)
def test_bad_input_names_the_key(parts, message):
    with pytest.raises(ConfigError) as e:
        load_case(_with(**parts))
    assert message in str(e.value), str(e.value)


def test_the_dem_takes_fc():
    # the DEM's crushing cap (docs/dem.md section 10): fc with [analysis] dem is a valid case,
    # its [dem] joint_segments auto (0) by default
    c = load_case(_with(masonry={"fc": 2e6}, analysis={"fe": False, "dem": True,
                                                       "hinge_check": False}))
    assert c.case.masonry.fc == 2e6 and c.dem.joint_segments == 0


def test_sweep_keys_address_array_entries():
    c = load_case(_with(tie=[{"z": 9.0, "yield_force": 1000.0}]),
                  ["tie.0.yield_force=5000", "tie.1.z=6", "tie.1.yield_force=2000",
                   "floor.0.z=4.5", "floor.0.load=1e4", "floor.0.eccentricity=0.1"])
    assert c.case.ties == (Tie(9.0, 5000.0), Tie(6.0, 2000.0))
    assert c.case.floors == (Floor(4.5, 1e4, 0.1),)
    with pytest.raises(ConfigError, match="tie.<entry>.<key>"):
        load_case(_with(), ["tie.3.z=1"])
    from homlimit.app.sweep import parse_grid
    assert parse_grid(["tie.0.yield_force=1000,2000"]) == {"tie.0.yield_force": [1000, 2000]}


def _tied(z: float) -> dict:
    return b1(masonry={"fc": 2e6}, analysis={"fe": False, "hinge_check": False,
                                             "overturning": True},
              tie=[{"z": z, "yield_force": 5000.0}])


def test_cli_exit_2_writes_nothing_and_a_good_case_runs(tmp_path):
    r = run_cli(tmp_path, _tied(12.0), "run")
    assert r.returncode == 2 and "[[tie]] 0 z = 12.0 m is out of range" in r.stderr
    assert "Traceback" not in r.stderr and not (tmp_path / "out").exists()
    # cohesion stays refused by every rocker, the FE body's with it (exit 2, nothing written)
    r = run_cli(tmp_path, b1(masonry={"cohesion": 1e4}, tie=[{"z": 9.0, "yield_force": 5e3}],
                             analysis={"closed_form": False, "hinge_check": False},
                             pulse={"mechanisms": ["FE"]}), "pulse")
    assert r.returncode == 2 and "[masonry] cohesion = 10000.0 Pa" in r.stderr \
        and "Traceback" not in r.stderr and not (tmp_path / "out").exists()
    r = run_cli(tmp_path, _tied(9.0), "run")
    assert r.returncode == 0, r.stderr
    s = json.loads((tmp_path / "out" / "summary.json").read_text())
    assert set(s["mechanisms"]) == {"I", "II", "overturning"}
    over = s["mechanisms"]["overturning"]
    assert over["fc_infinite"] is False and over["hinge_retreat"] > 0
    assert s["inputs"]["tie"] == [{"z": 9.0, "yield_force": 5000.0, "stiffness": 0.0,
                                   "ductility": 0.0}]
    ref = R.reference("overturning", WALL, MAS, over["lam"], ties=[(9.0, 5000.0)], fc=2e6)
    assert rel(over["vg"], ref["vg"]) < 1e-9


def test_sweep_table_has_the_entry_columns():
    from homlimit.app.sweep import flatten
    row = flatten({"inputs": {"tie": [{"z": 9.0, "yield_force": 5.0}], "floor": []},
                   "fe": {"scan": [{"x": 1}]}})
    assert row == {"inputs.tie.0.z": 9.0, "inputs.tie.0.yield_force": 5.0}


def test_elastic_plastic_tie_work_by_hand():
    """k = 1e5 N/m² and T_y = 10 kN/m per metre: per bay k l = 6e5 N/m, T_y l = 6e4 N,
    δ_y = 0.1 m; the top tie of the overturning stretches by 9 sin θ."""
    tied = dataclasses.replace(B1, ties=(Tie(9.0, 10000.0, stiffness=1e5),))
    th = np.array([0.005, 0.5])
    d = 9 * np.sin(th)
    W = real.work_real(tied, "overturning", 18.0, th) - real.work_real(B1, "overturning",
                                                                       18.0, th)
    np.testing.assert_allclose(W, [0.5 * 6e5 * d[0] ** 2, 6e4 * (d[1] - 0.05)], rtol=1e-12)
