"""Overturning spectra of a case: the records against the threshold search and hand formulas,
and the CSV / PNG writers."""

import csv
import math

import pytest

from homlimit.app import report
from homlimit.app.plots import plot_spectra
from homlimit.closed_form.mechanisms import mechanism_I, mechanism_II
from homlimit.dynamics import (
    RectangularPulse,
    case_rockers,
    case_spectra,
    critical_pulse,
)
from homlimit.dynamics.spectra import SPECTRUM_COLUMNS


@pytest.fixture(scope="module")
def spectra(b1):
    return (case_spectra(b1, kinds=("rectangular",), periods=(0.005, 0.05, 0.5),
                         polarities=(1, -1))
            + case_spectra(b1, kinds=("one-sine",), periods=(0.01,), polarities=(1, -1)))


@pytest.mark.slow
def test_points_and_normalisation(b1, spectra):
    # rectangular: polarity −1 never pushes outwards, so 2 mechanisms × 3 periods; one-sine:
    # both polarities
    assert len(spectra) == 2 * 3 + 2 * 2 * 1
    sq = math.sqrt(b1.wall.g * b1.wall.b)
    v7 = {"I": mechanism_I(b1).vg, "II": mechanism_II(b1).vg}
    for p in spectra:
        assert p.vnorm == pytest.approx(p.pgv / sq, rel=1e-14)
        assert p.vg_eq7 == pytest.approx(v7[p.mechanism], rel=1e-12)
        assert p.ratio == pytest.approx(p.pgv / p.vg_eq7, rel=1e-14)
        assert p.pga >= p.a_uplift  # nothing moves below the uplift acceleration
        assert p.ivp_rtol == 1e-10 and p.ivp_method == "DOP853"


@pytest.mark.slow
def test_rectangular_spectrum_tends_to_eq7_and_longer_pulses_need_less_acceleration(b1, spectra):
    for m in ("I", "II"):
        rect = sorted((p for p in spectra if p.pulse == "rectangular" and p.mechanism == m),
                      key=lambda p: p.period)
        ratios = [p.ratio for p in rect]
        assert ratios == sorted(ratios)  # longer pulses need more velocity
        assert 1 < ratios[0] < 1.01  # Δt = 5 ms: within 1 % of eq. 7
        pgas = [p.pga for p in rect]
        assert pgas == sorted(pgas, reverse=True)  # ... and less acceleration
        # the point is the threshold search itself
        rk = case_rockers(b1)[m]
        th = critical_pulse(rk, RectangularPulse(1.0, 0.05), rtol=1e-6)
        assert rect[1].pga == pytest.approx(th.pga, rel=3e-6)


@pytest.mark.slow
def test_one_sine_of_polarity_minus_one_is_an_outward_half_sine(spectra):
    """With polarity −1 the first half of the one-sine only presses the façade on its seat;
    the second half is an outward half-sine whose impulse is the pgv: at short periods the
    threshold pgv tends to eq. 7, while polarity +1 (outward, then braking) needs far more."""
    for m in ("I", "II"):
        neg = [p for p in spectra if p.pulse == "one-sine" and p.mechanism == m
               and p.polarity == -1][0]
        pos = [p for p in spectra if p.pulse == "one-sine" and p.mechanism == m
               and p.polarity == 1][0]
        assert 1 < neg.ratio < 1.01  # T_p = 10 ms
        assert pos.ratio > 30


@pytest.mark.slow
def test_hinge_ratio_of_a_rectangular_pulse(b1, spectra):
    """Mechanism II: |P_x|/P_z at lift-off has the closed form ``hinge_ratio_at_rest``, which
    tends to (i − z_G²)/(x_G z_G) = 1.78 (mechanics.md: 1.8) for the ideal impulse; the
    largest value during the pulse (the spectrum's hinge_ratio) is at least that and within
    1 % of it (1.459 against 1.446 at Δt = 5 ms). NaN for mechanism I, whose abutment forces
    also act on the body."""
    rk = case_rockers(b1)["II"]
    b = rk.body
    limit = (b.i - b.z_G ** 2) / (b.x_G * b.z_G)
    assert limit == pytest.approx(1.781, abs=1e-3)
    assert float(rk.hinge_ratio_at_rest(1e9)) == pytest.approx(limit, rel=1e-6)
    for p in spectra:
        if p.mechanism == "I":
            assert math.isnan(p.hinge_ratio)
        elif p.pulse == "rectangular":
            onset = float(rk.hinge_ratio_at_rest(p.pga))
            assert onset * (1 - 1e-5) <= p.hinge_ratio <= 1.01 * onset
            assert p.hinge_ratio < limit


@pytest.mark.slow
def test_csv_round_trip_and_plot(spectra, tmp_path):
    path = report.write(tmp_path / "out" / "spectra.csv", [p.as_dict() for p in spectra])
    with path.open() as fh:
        rows = list(csv.DictReader(fh))
    assert len(rows) == len(spectra)
    for r, p in zip(rows, spectra):
        assert r["mechanism"] == p.mechanism and r["pulse"] == p.pulse
        assert float(r["pgv [m/s]"]) == pytest.approx(p.pgv, rel=1e-15)   # units in headers
        assert float(r["period [s]"]) == p.period
    assert list(rows[0]) == [report.csv_header(k) for k in SPECTRUM_COLUMNS]
    back = report.read_csv(path)                     # read back into plain keys
    assert list(back[0]) == SPECTRUM_COLUMNS        # floats written to 15 digits (_io.DIGITS)
    assert back[0]["pgv"] == pytest.approx(spectra[0].pgv, rel=1e-14)
    png = plot_spectra(tmp_path / "out" / "spectra.png", spectra, dem_vnorm=0.377, title="B1")
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert sorted(x.name for x in (tmp_path / "out").iterdir()) == [
        "spectra.csv", "spectra.csv.json", "spectra.png"]
    text = report.format_spectra(spectra)
    assert "one-sine" in text and "pgv/vg(eq.7)" in text
