"""Issue 30: a run's FE path with a joint cohesion and tension.

Both bounds, the mechanism and its crack take them (the domains' cohesive forms: their own
checks in tests/test_fe_real.py); v̄_g does not (its dissipation at finite rotation needs a
softening rule the case file does not state), so every height of the impulse scan and the
critical one report it "not available" with the reason, worded as the rigid blocks', and never
a number. There is no closed form of B1 with a cohesion to compare with: the checks are the
bracket λ⁻ <= λ⁺ and that a cohesion makes the wall stronger than the dry wall's upper bound.
"""

from __future__ import annotations

import csv
import json
import math

import pytest

from homlimit.errors import ParameterError
from homlimit.params import Case, Masonry

from cases import b1, run_cli

C = 1e4                    # Pa: 10 kPa of cohesion
WET = Case(masonry=Masonry(cohesion=C, tension=5e3))
SOFT = "their dissipation at finite rotation needs a softening rule the case file does not state"


def test_the_reason_is_the_blocks_wording():
    """The FE path's reason is the rigid blocks' (``impulse.no_bond_reason``), naming both
    keys; a tension without a cohesion does not act (``fe.strength``): no reason, v̄_g is the
    dry wall's."""
    from homlimit.blocks.geometry import stack
    from homlimit.blocks.impulse import no_bond
    from homlimit.blocks.real import RealActions
    from homlimit.mechanism.fe_impulse import bond_reason

    fe = bond_reason(WET)
    assert fe.startswith("[masonry] cohesion = 10000.0 Pa, tension = 5000.0 Pa: v̄_g (eq. 7) "
                         "of the FE mechanism does not take a joint cohesion or tension: ")
    assert SOFT in fe and fe.endswith("allowed 0 Pa for v̄_g")
    A = stack([0.5], [1.0], density=1800.0,
              meta={"f": 0.6, "g": 9.81, "real": RealActions(cohesion=C, tension=5e3)})
    with pytest.raises(ParameterError) as e:
        no_bond(A)
    tail = lambda s: s.split("tension = 5000.0 Pa: ")[1].split(" does not take")[1]  # noqa: E731
    assert tail(str(e.value)).split("(")[0] == tail(fe).split("(")[0]
    assert bond_reason(Case(masonry=Masonry(tension=5e3))) == ""
    assert bond_reason(Case()) == ""


def test_remeshing_keeps_the_strengths():
    """``t_section_on_mesh`` (the adaptive bracket's and the fan search's remesh) keeps the
    cohesive domains of the case."""
    from homlimit.fe.problems import t_section, t_section_on_mesh

    coarse = t_section(WET, facade="bedjoints", h=2.0)
    moved = t_section_on_mesh(coarse, WET, t_section(Case(), facade="bedjoints", h=1.0).mesh)
    assert moved.domains is coarse.domains
    assert moved.domains["wall"].cohesion == C and moved.domains["wall"].tension == 5e3
    assert moved.domains["facade"].cohesion == pytest.approx(WET.rho * C)


def test_fe_result_with_cohesion_brackets_and_has_no_vg():
    """B1 on a coarse crossed mesh with C = 10 kPa, T = 5 kPa: λ⁻ <= λ⁺, both above the dry
    wall's λ⁺ on the same mesh; no height has a v̄_g (NaN, the reason in vg_method, the body
    alone's eq. 7 neither), the scan stops at its starting heights, the whole wall keeps its
    body for the code check, and the summary's section says why."""
    from homlimit.fe.kinematic import solve_kinematic
    from homlimit.fe.problems import t_section
    from homlimit.mechanism.analysis import fe_result

    dry = solve_kinematic(t_section(Case(), facade="bedjoints", h=1.0)).multiplier
    fe = fe_result(WET, mesh_size=1.0, facade="bedjoints", static=True, heights=2,
                   divisions=4, mesher="crossed")
    lo, up = fe.lower_bound, fe.whole.multiplier
    assert lo <= up * (1 + 1e-7)
    assert lo > dry                                  # stronger than the dry wall's λ⁺
    assert [m.h_part for m in fe.scan] == [0.3, 9.0]  # no bisection without a v̄_g
    for m in fe.scan:
        assert math.isnan(m.vg) and math.isnan(m.vnorm) and m.impulse is None
        assert math.isnan(m.vg_body) and math.isnan(m.hinge_ratio)
        assert m.vg_method == m.vg_unavailable and m.vg_method.startswith("not available: ")
        assert SOFT in m.vg_method and math.isfinite(m.multiplier)
    assert fe.critical is None and fe.vg_unavailable == fe.whole.vg_method
    sm = fe.whole.static_mechanism
    assert sm is not None and sm.alpha0 == up and sm.body.m > 0
    d = fe.as_dict()
    assert d["vg"] is None and d["vnorm"] is None and SOFT in d["vg_unavailable"]
    assert d["critical_multiplier"] == up and d["lam"] == fe.whole.lam
    assert (d["cohesion"], d["tension"], d["tension_effective"]) == (C, 5e3, 5e3)
    assert d["critical_at"].startswith("the whole wall")


def test_dry_case_reports_no_bond():
    """The dry wall's FE summary section has no bond keys and its scan's v̄_g is a number
    (one part, no solve of the whole wall: the record of ``analyse``)."""
    from homlimit.fe.problems import t_section
    from homlimit.mechanism.analysis import analyse

    m = analyse(Case(), t_section(Case(), z0=7.0, facade="bedjoints", h=0.5))
    assert m.vg_unavailable == "" and math.isfinite(m.vg) and math.isfinite(m.vg_body)


def test_the_rockers_still_refuse_cohesion_and_tension(monkeypatch):
    """The hinge check (exit 2 at load), ``homlimit pulse`` with the FE body and the FE
    body's rocker refuse a joint cohesion or tension, before any FE work."""
    from homlimit.app import models
    from homlimit.app.config import ConfigError, load_case
    from homlimit.app.pulses import pulse_records

    with pytest.raises(ConfigError, match=r"\[analysis\] hinge_check = true: the hinge "
                                          r"check's rockers do not take \[masonry\] cohesion"):
        load_case(b1(masonry={"cohesion": C}, analysis={"fe": True, "closed_form": False}))

    def forbidden(*a, **k):
        raise AssertionError("the FE path ran")

    monkeypatch.setattr(models, "fe_result", forbidden)
    config = load_case(b1(masonry={"cohesion": C}, pulse={"mechanisms": ["FE"]},
                          analysis={"fe": True, "closed_form": False, "hinge_check": False}))
    with pytest.raises(ParameterError, match=r"\[masonry\] cohesion = 10000.0 Pa: the pulse"):
        pulse_records(config)
    for call in (lambda: models.fe_rocker(config), lambda: models.rocker_fe(config.case, None)):
        with pytest.raises(ParameterError, match=r"cohesion = 10000.0 Pa: the FE body's rocker"):
            call()


def test_cli_refusals_that_remain_exit_2(tmp_path):
    """With [analysis] fe and a cohesion, the hinge check (on by default) and `homlimit pulse`
    with the FE body still refuse it: exit 2, the key named, nothing written."""
    case = b1(masonry={"cohesion": C}, analysis={"fe": True, "closed_form": False})
    r = run_cli(tmp_path, case, "run")
    assert r.returncode == 2 and "hinge check's rockers do not take [masonry] cohesion = " \
        "10000.0 Pa" in r.stderr, r.stderr
    assert "Traceback" not in r.stderr and not (tmp_path / "out").exists()
    case = {**case, "analysis": {**case["analysis"], "hinge_check": False},
            "pulse": {"mechanisms": ["FE"]}}
    r = run_cli(tmp_path, case, "pulse")
    assert r.returncode == 2 and "[masonry] cohesion = 10000.0 Pa: the pulse spectra's " \
        "rocker of every mechanism does not take" in r.stderr, r.stderr
    assert "Traceback" not in r.stderr and not (tmp_path / "out").exists()


@pytest.mark.slow
def test_cli_run_fe_with_cohesion(tmp_path):
    """`homlimit run` on a coarse B1 with C = 10 kPa, [analysis] fe and a [site], on the
    default adaptive gmsh-strip bracket (2 cycles: 11 s): exit 0, every cycle's bracket in
    order and above the dry wall's λ⁺ on the crossed grid (0.161 at h = 1 m: well below), v̄_g
    null with the reason in the FE section, the FE mechanism's row, fe_scan.csv and the
    terminal; the code check takes λ⁺ and the body."""
    case = b1(masonry={"cohesion": C},
              analysis={"fe": True, "closed_form": False, "hinge_check": False,
                        "heights": 2},
              mesh={"size": 1.0, "part_divisions": 4},
              adapt={"max_cycles": 2, "crack_cycles": 0},   # two brackets, both bounds each
              output={"png": False, "vtu": False},
              site={"ag": 1.962, "F0": 2.5, "Tc_star": 0.3})
    r = run_cli(tmp_path, case, "run")
    assert r.returncode == 0, r.stderr
    s = json.loads((tmp_path / "out" / "summary.json").read_text())
    fe = s["fe"]
    assert fe["lower_bound"] <= fe["multiplier"] * (1 + 1e-7)
    cycles = list(csv.DictReader(open(tmp_path / "out" / "fe_adapt.csv", encoding="utf-8")))
    assert len(cycles) == 2
    for c in cycles:
        lo, up = (float(v) for k, v in c.items() if k.split()[0] in ("lower", "upper"))
        assert 0.161 < lo <= up * (1 + 1e-7)
    assert fe["vg"] is None and SOFT in fe["vg_unavailable"] and s["critical"] is None
    row = s["mechanisms"]["FE"]
    assert row["vg"] is None and row["vg_method"].startswith("not available: [masonry] "
                                                             "cohesion = 10000.0 Pa")
    assert row["multiplier"] == fe["multiplier"]
    assert s["code_check"]["mechanisms"]["FE"]["alpha0"] == fe["multiplier"]
    rows = list(csv.DictReader(open(tmp_path / "out" / "fe_scan.csv", encoding="utf-8")))
    assert len(rows) == 2 and all(SOFT in r_["vg_method"] for r_ in rows)
    assert all(r_["vg [m/s]"] in ("", "nan") for r_ in rows)
    assert "vg not available at any of 2 heights" in r.stdout
    assert "FE: vg not available: [masonry] cohesion" in r.stdout
    assert "FE whole wall, " in r.stdout and (tmp_path / "out" / "fe_adapt.csv").exists()
