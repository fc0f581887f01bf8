"""Stage "case": the validated case of a run (``config.load_case``) and what a user must know
about it before the results."""

from __future__ import annotations

import logging
import os
from pathlib import Path

from ..errors import ParameterError, check_type
from .config import CaseConfig, load_case

__all__ = ["announce", "resolve_case"]

log = logging.getLogger("homlimit.app.pipeline")


def resolve_case(path_or_dict: str | Path | dict | CaseConfig | None = None,
                 overrides: list[str] | dict | None = None) -> CaseConfig:
    """The case ``run`` takes: a CaseConfig as it is (no ``overrides`` then: ParameterError),
    else a case file, a dict or None (the embedded B1) read and validated with ``overrides``
    applied first (``config.load_case``: ConfigError listing every problem); anything else
    is a ParameterError naming it."""
    check_type("path_or_dict", path_or_dict, (str, os.PathLike, dict, CaseConfig, type(None)),
               "a case file's path (str or pathlib.Path), a dict of the case file's shape, a "
               "CaseConfig, or None (the embedded B1)")
    if isinstance(path_or_dict, CaseConfig):
        if overrides:
            raise ParameterError("overrides = given with a CaseConfig is out of range: allowed "
                                 "only with a path, a dict or None")
        return path_or_dict
    return load_case(path_or_dict, overrides)


def announce(config: CaseConfig):
    """Log what a user must know before reading the results: a case changed by --set, and
    the valid but implausible inputs (warnings, also in summary.json)."""
    if config.modified:
        log.info("case %s: %s", config.name, config.describe_changes())
    for w in config.warnings:
        log.warning("warning: %s", w)
