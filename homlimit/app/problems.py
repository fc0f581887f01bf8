"""Every problem of a command's options (or a function's arguments) at once: ``Problems``
runs each check, keeps its message and raises them together as one ``ConfigError``, as a case
file's checks do (``config._parse``)."""

from __future__ import annotations

from collections.abc import Callable

from ..errors import ParameterError
from .config import ConfigError

__all__ = ["Problems"]


class Problems:
    """The problems found so far; ``source`` and ``what`` head the ConfigError (``homlimit:
    error: crack-study: 2 problems in the options``)."""

    def __init__(self, source: str, what: str = "the options"):
        self.source, self.what = source, what
        self.lines: list[str] = []

    def check(self, fn: Callable, *args, **kwargs):
        """``fn(*args, **kwargs)``, or None after keeping the ParameterError's message(s)."""
        try:
            return fn(*args, **kwargs)
        except ConfigError as e:       # a list already: its lines without their own source
            self.lines += [p.removeprefix(f"{e.source}: ") for p in e.problems]
        except ParameterError as e:
            self.lines.append(str(e))
        return None

    def add(self, message: str):
        self.lines.append(message)

    def raise_any(self):
        """ConfigError listing every problem kept, if any."""
        if self.lines:
            raise ConfigError(self.source, self.lines, self.what)
