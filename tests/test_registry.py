"""The model and mechanism registry (issue 28): a mechanism defined and registered here, in a
test module, reaches ``homlimit run``'s table, summary.json and the hinge (impulse) table, and
``homlimit pulse``'s spectra, without any other file changing.

The toy is the whole façade of Table 1's wall B1 as a free rigid block rocking about its outer
toe (no abutment, no wedge): Housner's block, whose numbers are written out below by hand.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass

import pytest
from typer.testing import CliRunner

from homlimit.app import models, registry
from homlimit.app.cli import app
from homlimit.app.registry import Mechanism, Model
from homlimit.errors import ParameterError
from homlimit.impulse import RigidBody, collapse_velocity, hinge_impulse_ratio

H, B, L_FACADE, GAMMA, G, F = 9.0, 0.5, 6.0, 2000.0, 9.81, 0.6   # B1 (paper's Table 1)


@dataclass(frozen=True)
class Toy:
    """The façade as a free block about its outer toe: the mechanism protocol."""

    body: RigidBody
    b: float
    g: float
    name = "toy"
    label = "toy free block (Housner)"

    @property
    def h(self) -> float:
        return 2 * self.body.z_G

    @property
    def lam(self) -> float:
        return self.h / self.b

    @property
    def vg(self) -> float:
        return collapse_velocity(self.body, g=self.g)

    @property
    def vnorm(self) -> float:
        return self.vg / math.sqrt(self.g * self.b)

    @property
    def hinge_ratio(self) -> float:
        return hinge_impulse_ratio(self.body)

    def as_dict(self) -> dict:
        return {"name": self.name, "lam": self.lam, "h": self.h, "vg": self.vg,
                "vnorm": self.vnorm, "hinge_ratio": self.hinge_ratio,
                "body": {k: getattr(self.body, k) for k in ("m", "x_G", "z_G", "I_O")}}


def run_toy(config, result):
    w = config.case.wall
    m = w.gamma * w.b * w.H * w.l
    result.mechanisms["toy"] = Toy(RigidBody(m=m, x_G=w.b / 2, z_G=w.H / 2,
                                             I_O=m * (w.b ** 2 + w.H ** 2) / 3), w.b, w.g)


@pytest.fixture
def toy():
    with registry.registered(Model("toy", lambda config: True, run_toy),
                             Mechanism("toy", model="toy", rocker=models.rigid_rocker,
                                       body_checked=("m", "x_G", "z_G", "I_O"))):
        yield


# Housner's block of half-diagonal R, slenderness α = atan(b/H): I_O = 4/3 m R², the ideal
# impulse gives θ̇0 = m (H/2) v / I_O, and it overturns when ½ I_O θ̇0² = m g R (1 − cos α)
R = math.hypot(B, H) / 2
ALPHA = math.atan(B / H)
VG_TOY = (4 / 3 * R ** 2) / (H / 2) * math.sqrt(2 * G * R * (1 - math.cos(ALPHA))
                                                 / (4 / 3 * R ** 2))
# the hinge's |P_x/P_z| under that impulse: (i − z_G²)/(x_G z_G), i = I_O/m (eq. 4)
RATIO_TOY = (4 / 3 * R ** 2 - (H / 2) ** 2) / (B / 2 * H / 2)
# the shortest rectangular pulse of a_g = f g that overturns it, linearised (α small):
# t = ln(f / (f − α)) / p, p² = 3 g / (4 R) (Housner 1963); pgv = f g t
P = math.sqrt(3 * G / (4 * R))
PGV_HOLD = F * G * math.log(F / (F - ALPHA)) / P


def test_a_registered_toy_mechanism_reaches_the_run_outputs(toy, tmp_path):
    out = tmp_path / "out"
    res = CliRunner().invoke(app, ["run", "--set", "analysis.fe=false", "--out", str(out)])
    assert res.exit_code == 0, res.output
    s = json.loads((out / "summary.json").read_text(encoding="utf-8"))
    toy_json = s["mechanisms"]["toy"]
    assert toy_json["vg"] == pytest.approx(VG_TOY, rel=1e-12)
    assert toy_json["h"] == pytest.approx(H, rel=1e-12)
    assert toy_json["hinge_ratio"] == pytest.approx(RATIO_TOY, rel=1e-12)
    assert s["mechanisms"]["toy"]["body"]["m"] == pytest.approx(GAMMA * B * H * L_FACADE)
    # the hinge table: the shortest pulse the hinge holds, against Housner's linearised one
    # (the rocker is exact, the reference linearised: they differ by order α² = 0.3 %)
    assert s["hinges"]["toy"]["pgv"] == pytest.approx(PGV_HOLD, rel=ALPHA ** 2)
    # the other mechanisms are still there, in the registry's order
    assert list(s["mechanisms"]) == ["I", "II", "toy"]
    rows = [line for line in res.stdout.splitlines() if line.startswith("toy")]
    assert len(rows) == 2                                   # the results and the hinge table
    assert f"{VG_TOY:.4g}" in rows[0].split() and f"{RATIO_TOY:.4g}" in rows[1].split()


def test_a_registered_toy_mechanism_reaches_the_pulse_spectra(toy, tmp_path):
    out = tmp_path / "pulse"
    res = CliRunner().invoke(app, ["pulse", "--json", "--out", str(out),
                                   "--set", 'pulse.mechanisms=["toy"]',
                                   "--set", 'pulse.kinds=["rectangular"]',
                                   "--set", "pulse.periods=[0.5]",
                                   "--set", "pulse.polarities=[1]"])
    assert res.exit_code == 0, res.output
    (pt,) = json.loads(res.stdout)["points"]
    assert pt["mechanism"] == "toy"
    # a rectangular pulse of 0.5 s: the critical amplitude k g solves (linearised, as above)
    # ln(k / (k − α)) = p T; its pgv is k g T
    k = ALPHA / (1 - math.exp(-P * 0.5))
    assert pt["pgv"] == pytest.approx(k * G * 0.5, rel=ALPHA ** 2)


def test_an_unregistered_name_is_refused_naming_the_allowed_ones():
    with pytest.raises(ParameterError, match=r"mechanism = 'toy' is out of range: allowed "
                                             r"one of 'I', 'II', 'FE'"):
        registry.mechanism("toy")
    res = CliRunner().invoke(app, ["pulse", "--set", 'pulse.mechanisms=["toy"]'])
    assert res.exit_code == 2 and "[pulse] mechanisms[0] = 'toy'" in res.stderr
    assert "one of 'I', 'II', 'FE'" in res.stderr


def test_a_name_is_registered_once():
    with pytest.raises(ParameterError, match="name = 'FE' is already registered"):
        registry.register(Mechanism("FE", model="fe"))


def test_a_sweep_batches_a_case_only_when_all_its_models_batch():
    """The closed forms alone go in vectorised batches; a case that asks for the rigid blocks
    too (or for a registered toy) is run whole, so no model is skipped."""
    from homlimit.app.config import load_case
    from homlimit.app.sweep import SweepCase

    closed = load_case(None, ["analysis.fe=false"])
    blocks = load_case(None, ["analysis.fe=false", "analysis.blocks=true"])
    assert SweepCase(0, {}, "a", closed).closed_form_only
    assert not SweepCase(1, {}, "b", blocks).closed_form_only
    with registry.registered(Model("toy", lambda config: True, run_toy)):
        assert not SweepCase(0, {}, "a", closed).closed_form_only
