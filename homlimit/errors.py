"""Failure types of homlimit: one place for every error the package raises on purpose."""

from __future__ import annotations

import math

__all__ = ["HomlimitError", "ParameterError", "MeshError", "OutputError", "ResultError",
           "SolverError", "check_choice", "check_range", "check_type"]


class HomlimitError(Exception):
    """Base class of every expected homlimit failure."""


class ParameterError(HomlimitError, ValueError):
    """An input value is outside its allowed range. The message names parameter, value and range."""


class MeshError(HomlimitError, RuntimeError):
    """Meshing failed (gmsh error, empty or inconsistent mesh)."""


class SolverError(HomlimitError, RuntimeError):
    """A conic program did not end optimal. ``status`` holds the solver's status string."""

    def __init__(self, message: str, status: str | None = None):
        super().__init__(message)
        self.status = status


class OutputError(HomlimitError, OSError):
    """A result file or set could not be written (no space, file too large, permissions).
    Nothing half-written is left: the previous file or result set is kept."""


class ResultError(HomlimitError, RuntimeError):
    """A computation ended without a finite result (the message names the mechanism and the
    quantity); nothing is written."""


def check_range(
    name: str,
    value,
    lo: float | None = None,
    hi: float | None = None,
    *,
    lo_open: bool = False,
    hi_open: bool = False,
    unit: str = "",
    note: str = "",
) -> float:
    """Return ``float(value)`` if it lies in the stated (finite) interval, else raise
    ParameterError.

    The message names the parameter, its value and the allowed range, e.g.
    ``b = -0.5 m is out of range: allowed 0 < b``; a range open above adds "finite" for
    inf and NaN (``min_size = inf m is out of range: allowed 0 < min_size m, finite``);
    ``note`` is added in brackets (``0: none``).
    """
    u = f" {unit}" if unit else ""
    try:
        x = float(value)
    except (TypeError, ValueError):
        raise ParameterError(f"{name} = {value!r} is not a number") from None
    bad = not math.isfinite(x)
    if lo is not None and (x <= lo if lo_open else x < lo):
        bad = True
    if hi is not None and (x >= hi if hi_open else x > hi):
        bad = True
    if bad:
        parts = []
        if lo is not None:
            parts.append(f"{lo:g} {'<' if lo_open else '<='} {name}")
        if hi is not None:
            parts.append(f"{name} {'<' if hi_open else '<='} {hi:g}")
        rng = (" and ".join(parts) if parts else f"{name} finite") + u
        if parts and hi is None and not math.isfinite(x):
            rng += ", finite"
        rng += f" ({note})" if note else ""
        raise ParameterError(f"{name} = {value!r}{u} is out of range: allowed {rng}")
    return x


def check_choice(name: str, value, choices) -> object:
    """Return ``value`` if it is one of ``choices``, else raise ParameterError naming both."""
    if value not in tuple(choices):
        raise ParameterError(f"{name} = {value!r} is out of range: allowed one of "
                             + ", ".join(repr(c) for c in choices))
    return value


def check_type(name: str, value, types: tuple, allowed: str):
    """Return ``value`` if it is an instance of one of ``types`` (a bool is no int here),
    else raise ParameterError naming the argument, its value and ``allowed``."""
    ok = isinstance(value, types) and not (isinstance(value, bool) and bool not in types)
    if not ok:
        text = repr(value)
        text = text if len(text) <= 60 else f"{text[:50]}... ({len(text)} characters)"
        raise ParameterError(f"{name} = {text} ({type(value).__name__}) has the wrong type: "
                             f"allowed {allowed}")
    return value
