"""Bad input is a ParameterError naming the parameter, its value and the allowed range, before
any work; a time history that cannot be completed is a SolverError with the reason."""

import math

import pytest

from homlimit import ParameterError, SolverError
from homlimit.app.plots import plot_spectra
from homlimit.dynamics import (
    GeneralisedRocker,
    IntegrationOptions,
    MechanismIRocker,
    OneSinePulse,
    RectangularPulse,
    RigidRocker,
    case_rockers,
    case_spectra,
    critical_pulse,
    free_block,
    overturning_spectrum,
    simulate,
)
from homlimit.dynamics.housner import (
    housner_rectangular,
    linear_block_response,
    one_sine_no_impact,
)
from homlimit.impulse.body import RigidBody
from homlimit.params import Case

B1 = Case()
BODY = RigidBody(m=1000.0, x_G=0.25, z_G=2.0, I_O=1000.0 * (0.25 ** 2 + 4.0) * 4 / 3)
ROCK = RigidRocker(BODY)


@pytest.mark.parametrize("kwargs, match", [
    ({"method": "Euler"}, "method = 'Euler' is out of range"),
    ({"rtol": 0.5}, r"rtol = 0\.5 is out of range"),
    ({"atol": 0.0}, r"atol = 0\.0 is out of range"),
    ({"max_rhs": 5}, "max_rhs = 5 is out of range"),
    ({"max_phases": 0}, "max_phases = 0 is out of range"),
    ({"rest_velocity": -1.0}, r"rest_velocity = -1\.0 is out of range"),
    ({"scan_points": 2}, "scan_points = 2 is out of range"),
    ({"horizon": 0.5}, r"horizon = 0\.5 is out of range"),
])
def test_integration_options(kwargs, match):
    with pytest.raises(ParameterError, match=match):
        IntegrationOptions(**kwargs)


@pytest.mark.parametrize("make, match", [
    (lambda: RigidRocker(RigidBody(m=1.0, x_G=-0.1, z_G=1.0, I_O=2.0)),
     r"x_G = -0\.1 m is out of range"),
    (lambda: RigidRocker(BODY, geometry="small"), "geometry = 'small' is out of range"),
    (lambda: RigidRocker(BODY, restitution=1.5), r"restitution = 1\.5 is out of range"),
    (lambda: RigidRocker(BODY, g=0.0), r"g = 0\.0 m/s\^2 is out of range"),
    (lambda: RigidRocker("body"), "body = 'body' is not a homlimit.impulse.RigidBody"),
    (lambda: MechanismIRocker(B1, gravity="cubic"), "geometry = 'cubic' is out of range"),
    (lambda: MechanismIRocker(B1, lam=30.0), r"lam = 30\.0 is out of range"),
    (lambda: MechanismIRocker(B1, restitution=-0.1), r"restitution = -0\.1 is out of range"),
    (lambda: MechanismIRocker("B1"), "case = 'B1' is not a homlimit.params.Case"),
    (lambda: GeneralisedRocker(1.0, 1.0, BODY), "M = 1.0 kg m\\^2 is out of range"),
    (lambda: GeneralisedRocker(BODY.I_O, 0.0, BODY), r"Pi = 0\.0 kg m is out of range"),
    (lambda: GeneralisedRocker(BODY.I_O, 1.0, BODY, lift_rest=-1.0),
     r"lift_rest = -1\.0 N m is out of range"),
    (lambda: free_block(0.0, 1.0), r"b = 0\.0 m is out of range"),
    (lambda: free_block(1.0, -1.0), r"h = -1\.0 m is out of range"),
    (lambda: free_block(1.0, 1.0, density=0.0), r"density = 0\.0 kg/m\^3 is out of range"),
])
def test_rocker_parameters(make, match):
    with pytest.raises(ParameterError, match=match):
        make()


@pytest.mark.parametrize("kwargs, match", [
    ({"theta0": 2.0}, r"theta0 = 2\.0 rad is out of range"),
    ({"theta0": -0.01}, "an attached mechanism rocks outwards only"),
    ({"theta_dot0": float("inf")}, "theta_dot0 = inf rad/s is out of range"),
    ({"max_impacts": -1}, "max_impacts = -1 is out of range"),
    ({"duration": 0.0}, r"duration = 0\.0 s is out of range"),
])
def test_simulate_arguments(kwargs, match):
    with pytest.raises(ParameterError, match=match):
        simulate(ROCK, OneSinePulse(5.0, 0.5), **kwargs)


def test_simulate_types():
    with pytest.raises(ParameterError, match="rocker = 'x' is not a homlimit.dynamics Rocker"):
        simulate("x")
    with pytest.raises(ParameterError, match="pulse = 3 is not a homlimit.dynamics Pulse"):
        simulate(ROCK, 3)


@pytest.mark.parametrize("kwargs, match", [
    ({"rtol": 0.1}, r"rtol = 0\.1 is out of range"),
    ({"scan_ratio": 1.0}, r"scan_ratio = 1\.0 is out of range"),
    ({"max_scan": 0}, "max_scan = 0 is out of range"),
])
def test_threshold_arguments(kwargs, match):
    with pytest.raises(ParameterError, match=match):
        critical_pulse(ROCK, OneSinePulse(1.0, 0.5), **kwargs)


def test_a_pulse_that_never_pushes_outwards():
    with pytest.raises(ParameterError, match="polarity -1 never pushes"):
        critical_pulse(ROCK, RectangularPulse(1.0, 0.1, polarity=-1))


def test_solver_errors_carry_the_reason():
    with pytest.raises(SolverError, match="max_rhs = 100") as exc:
        simulate(ROCK, OneSinePulse(20.0, 1.0), options=IntegrationOptions(max_rhs=100))
    assert exc.value.status == "max_rhs"
    with pytest.raises(SolverError, match="no overturning found") as exc:
        critical_pulse(ROCK, RectangularPulse(1.0, 0.01), max_scan=2)
    assert exc.value.status == "no bracket"
    with pytest.raises(SolverError, match="max_phases = 1") as exc:
        simulate(free_block(0.5, 5.0), None, theta0=0.05, duration=30.0,
                 options=IntegrationOptions(max_phases=1))
    assert exc.value.status == "max_phases"


@pytest.mark.parametrize("call, match", [
    (lambda: overturning_spectrum({"II": ROCK}, "sawtooth", [0.1], b=0.5),
     "pulse kind = 'sawtooth' is out of range"),
    (lambda: overturning_spectrum({"II": ROCK}, "ricker", [], b=0.5), "periods = \\[\\]"),
    (lambda: overturning_spectrum({"II": ROCK}, "ricker", [-0.1], b=0.5),
     r"period = -0\.1 s is out of range"),
    (lambda: overturning_spectrum({"II": ROCK}, "ricker", [0.1], b=0.0),
     r"b = 0\.0 m is out of range"),
    (lambda: overturning_spectrum({}, "ricker", [0.1], b=0.5), "rockers = {}"),
    (lambda: case_rockers(B1, mechanisms=("III",)), "mechanism = 'III' is out of range"),
    (lambda: case_spectra(B1, kinds=("square",)), "pulse kind = 'square' is out of range"),
    (lambda: plot_spectra("x.png", []), r"points = \[\] is out of range"),
    (lambda: housner_rectangular(0.0, 1.0, 1.0), r"alpha = 0\.0 rad is out of range"),
    (lambda: housner_rectangular(0.1, 1.0, 0.0), r"duration = 0\.0 s is out of range"),
    (lambda: one_sine_no_impact(0.1, -1.0, 1.0), r"p = -1\.0 rad/s is out of range"),
    (lambda: linear_block_response(0.1, 1.0, "ricker", 1.0, 1.0, 0.9),
     "kind = 'ricker' is out of range"),
    (lambda: linear_block_response(0.1, 1.0, "one-sine", 1.0, 1.0, 1.2),
     r"e = 1\.2 is out of range"),
])
def test_spectra_and_closed_form_arguments(call, match):
    with pytest.raises(ParameterError, match=match):
        call()


def test_errors_come_before_work(tmp_path):
    """A bad key fails at once, without integrating anything or writing a file."""
    out = tmp_path / "x.png"
    with pytest.raises(ParameterError):
        plot_spectra(out, [])
    assert not out.exists()
    assert math.isfinite(ROCK.vg_impulse)
