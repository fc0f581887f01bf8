"""The installed package's version, read without importing anything heavy (``--version``)."""

from __future__ import annotations

import functools
from importlib.metadata import PackageNotFoundError, version

__all__ = ["package_version"]


@functools.cache  # importlib.metadata reads the install's files: ~5 ms a call
def package_version() -> str:
    """The installed package's version (``importlib.metadata``)."""
    try:
        return version("homlimit")
    except PackageNotFoundError:  # running from a source tree that was never installed
        return "0+unknown"
