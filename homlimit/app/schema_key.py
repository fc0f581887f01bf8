"""The case file's key: ``Key`` (type, default or REQUIRED, unit, range, meaning), shared by
the schema's sections (``app.schema``, ``app.schema_dem``)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from ..fields import Range, default_of, range_of

__all__ = ["REQUIRED", "Key"]

REQUIRED = object()


@dataclass(frozen=True)
class Key:
    """One case-file key: its type, default (or REQUIRED), unit, allowed range and meaning."""

    kind: type                    # float, int, bool, str, or list (of ``item``)
    default: Any = REQUIRED
    unit: str = ""
    lo: float | None = None
    hi: float | None = None
    lo_open: bool = False
    hi_open: bool = False
    choices: tuple = ()
    doc: str = ""
    item: type | None = None      # the type of a list's items (range and choices apply to each)
    typical: tuple[float, float] | None = None   # outside: a warning (valid but implausible)

    @classmethod
    def of(cls, owner, name: str, kind: type = float, required: bool = False, **kw) -> Key:
        """The key of the ranged field ``name`` of the dataclass ``owner``
        (``fields.ranged``): its default (``required``: none) and range are the field's,
        written once there; ``kw``: the rest (``doc``, ``typical``, ``unit`` as the docs
        spell it)."""
        r = range_of(owner, name)
        return cls(kind, REQUIRED if required else default_of(owner, name),
                   kw.pop("unit", r.unit), r.lo, r.hi, r.lo_open, r.hi_open, **kw)

    @property
    def required(self) -> bool:
        return self.default is REQUIRED

    @property
    def range(self) -> Range:
        """The allowed range of a number (``fields.Range``, shared with the parameter
        objects' fields)."""
        return Range(self.lo, self.hi, self.lo_open, self.hi_open, self.unit)

    def range_text(self, name: str) -> str:
        if self.choices:
            return "one of " + ", ".join(repr(c) for c in self.choices)
        return self.range.text(name)
