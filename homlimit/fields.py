"""Declarative field checks: a value's allowed range written once, beside the field it bounds.

``ranged(lo, hi, unit=...)`` is a dataclass field whose metadata holds its ``Range``;
``check_fields(self)`` in ``__post_init__`` checks every such field and stores the checked
float (``errors.check_range``: the message names the parameter, its value and the allowed
range, ``b = -0.5 m is out of range: allowed 0 < b``) with ``set_fields``, the one way a
``__post_init__`` of a frozen dataclass stores a checked or converted value. The case-file
schema's ``Key`` (``app.schema``) holds the same ``Range``, and can take a field's range and
default from the dataclass it fills (``range_of``, ``default_of``), so that a range or a
default shared by a case-file key and a parameter object is written once.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

from .errors import check_range

__all__ = ["RANGE", "Range", "check_fields", "default_of", "range_of", "ranged", "set_fields"]

RANGE = "homlimit.range"   # the metadata key of a ranged field


@dataclass(frozen=True)
class Range:
    """lo <= x <= hi (``lo_open``/``hi_open``: strict), either bound None for none; ``unit``
    the value's SI unit as messages show it."""

    lo: float | None = None
    hi: float | None = None
    lo_open: bool = False
    hi_open: bool = False
    unit: str = ""

    def check(self, name: str, value) -> float:
        """``float(value)`` if it lies in the range, else ParameterError naming ``name``."""
        return check_range(name, value, self.lo, self.hi, lo_open=self.lo_open,
                           hi_open=self.hi_open, unit=self.unit)

    def holds(self, x: float) -> bool:
        """Whether the finite number ``x`` lies in the range (no message)."""
        if not math.isfinite(x):
            return False
        if self.lo is not None and (x <= self.lo if self.lo_open else x < self.lo):
            return False
        return not (self.hi is not None and (x >= self.hi if self.hi_open else x > self.hi))

    def text(self, name: str) -> str:
        """The range as one chain, ``0 < name <= 1`` ("" without bounds)."""
        text = name
        if self.lo is not None:
            text = f"{self.lo:g} {'<' if self.lo_open else '<='} {text}"
        if self.hi is not None:
            text = f"{text} {'<' if self.hi_open else '<='} {self.hi:g}"
        return "" if text == name else text


def ranged(lo: float | Range | None = None, hi: float | None = None, *, lo_open: bool = False,
           hi_open: bool = False, unit: str = "", **field_kw) -> dataclasses.Field:
    """A dataclass field checked against ``Range(lo, hi, ...)`` (or the ``Range`` given as
    ``lo``, shared by several fields) by ``check_fields``; ``field_kw`` as
    ``dataclasses.field`` (``default=...``)."""
    spec = lo if isinstance(lo, Range) else Range(lo, hi, lo_open, hi_open, unit)
    return dataclasses.field(metadata={RANGE: spec}, **field_kw)


def set_fields(obj, **values) -> None:
    """Store ``values`` (name → value, in order) on the dataclass instance ``obj``, frozen or
    not: for its ``__post_init__``, which converts or checks what it was given."""
    for name, value in values.items():
        object.__setattr__(obj, name, value)


def check_fields(obj, prefix: str = "") -> None:
    """Check every ranged field of the dataclass instance ``obj`` in field order, storing the
    checked float; the first bad one raises ParameterError named ``prefix + name``."""
    for f in dataclasses.fields(obj):
        spec = f.metadata.get(RANGE)
        if spec is not None:
            set_fields(obj, **{f.name: spec.check(prefix + f.name, getattr(obj, f.name))})


def _field(cls, name: str) -> dataclasses.Field:
    for f in dataclasses.fields(cls):
        if f.name == name:
            return f
    raise KeyError(f"{cls.__name__} has no field {name!r}")


def range_of(cls, name: str) -> Range:
    """The ``Range`` of the ranged field ``name`` of the dataclass ``cls``."""
    return _field(cls, name).metadata[RANGE]


def default_of(cls, name: str):
    """The default value of the field ``name`` of the dataclass ``cls``."""
    f = _field(cls, name)
    if f.default is not dataclasses.MISSING:
        return f.default
    if f.default_factory is not dataclasses.MISSING:
        return f.default_factory()
    raise KeyError(f"{cls.__name__}.{name} has no default")
