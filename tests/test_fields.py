"""One home for a field's range and default (issue 28): ``fields.ranged`` on the parameter
objects, read by ``check_fields`` and by the case-file schema's ``Key.of``; the section
dataclasses take their defaults from the schema."""

from __future__ import annotations

import dataclasses
import math

import pytest

from homlimit.app.config import SCHEMA, load_case
from homlimit.app.sections import SECTIONS
from homlimit.dynamics.pulses import MavroeidisPapageorgiouPulse, RectangularPulse
from homlimit.dynamics.rocking import RigidRocker
from homlimit.errors import ParameterError
from homlimit.fields import Range, check_fields, range_of, ranged
from homlimit.params import Masonry, Tie, Wall

from cases import B1


@dataclasses.dataclass(frozen=True)
class _Toy:
    x: float = ranged(0.0, 1.0, hi_open=True, unit="m", default=0.5)
    y: float = ranged(default=2)          # any finite number

    def __post_init__(self):
        check_fields(self, prefix="toy ")


def test_a_ranged_field_is_checked_and_converted():
    t = _Toy(0, 3)
    assert (t.x, t.y) == (0.0, 3.0) and type(t.x) is float and type(t.y) is float
    with pytest.raises(ParameterError, match=r"^toy x = 1 m is out of range: allowed "
                                             r"0 <= toy x and toy x < 1 m$"):
        _Toy(1)
    with pytest.raises(ParameterError, match=r"toy y = inf is out of range"):
        _Toy(0.5, math.inf)
    with pytest.raises(ParameterError, match=r"toy x = 'a' is not a number"):
        _Toy("a")


def test_the_parameter_objects_keep_their_messages():
    with pytest.raises(ParameterError, match=r"^b = -0.5 m is out of range: allowed 0 < b m$"):
        Wall(b=-0.5)
    with pytest.raises(ParameterError, match=r"^f = 0 is out of range: allowed 0 < f$"):
        Masonry(f=0)
    with pytest.raises(ParameterError, match=r"^tie yield_force = -1 N/m is out of range"):
        Tie(z=3.0, yield_force=-1)
    with pytest.raises(ParameterError, match=r"^duration = 0 s is out of range"):
        RectangularPulse(1.0, 0)


def test_range_text_is_one_chain():
    assert Range(0.0, 1.0, lo_open=True).text("e") == "0 < e <= 1"
    assert Range().text("e") == ""
    assert Range(0.0, 1.0, hi_open=True).holds(0.0) and not Range(0.0, 1.0, hi_open=True).holds(1)


@pytest.mark.parametrize("section, key, owner, name", [
    ("pulse", "gamma", MavroeidisPapageorgiouPulse, "gamma"),
    ("pulse", "nu", MavroeidisPapageorgiouPulse, "nu"),
    ("pulse", "restitution", RigidRocker, "restitution")])
def test_a_shared_range_is_written_once(section, key, owner, name):
    """The case-file key and the parameter object's field have one range and one default;
    both refuse the same value, each message naming the key, the value and the range."""
    spec = SCHEMA[section][key]
    r = range_of(owner, name)
    assert spec.range == r
    assert spec.default == next(f.default for f in dataclasses.fields(owner) if f.name == name)
    bad = r.lo if r.lo_open else r.hi + 1.0
    with pytest.raises(ParameterError, match=rf"\[{section}\] {key} = {bad!r}.* is out of "
                                             rf"range: allowed {spec.range_text(key)}"):
        load_case({**B1, section: {key: bad}})
    with pytest.raises(ParameterError, match=rf"{name} = {bad!r}.* is out of range"):
        r.check(name, bad)


def test_the_section_dataclasses_take_the_schema_defaults():
    for sec, cls in SECTIONS.items():
        got = dataclasses.asdict(cls())
        want = {k: tuple(key.default) if isinstance(key.default, list) else key.default
                for k, key in SCHEMA[sec].items()}
        assert got == want, sec
    assert SCHEMA["wall"]["gamma"].default == Wall().gamma == 2000.0
    assert SCHEMA["wall"]["g"].default == Wall().g == 9.81
