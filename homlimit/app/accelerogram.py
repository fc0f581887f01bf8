"""A case's accelerogram files ([pulse] record, [dem] record): read and checked in one place,
relative to the case file, with errors that name the key (``read_record``)."""

from __future__ import annotations

import logging
from pathlib import Path

from ..dynamics import RecordPulse
from ..errors import ParameterError

__all__ = ["MAX_RECORD_BYTES", "read_record", "record_problems"]

log = logging.getLogger("homlimit.app.pipeline")

MAX_RECORD_BYTES = 64 << 20  # an accelerogram of a million samples is ~30 MB


def read_record(source: str, value: str, key: str, warn: bool = True) -> RecordPulse:
    """The accelerogram ``value`` of the case key ``key`` (e.g. "[pulse] record"): a
    two-column CSV t [s], a_g [m/s²] (``dynamics.RecordPulse``), relative to the case file
    ``source`` (to the working directory if the case is not a file). ParameterError naming
    the key and its value (no file, over MAX_RECORD_BYTES, not UTF-8, bad rows); its sampling
    warnings are logged if ``warn``."""
    base = Path(source).parent if Path(source).is_file() else Path.cwd()
    path = base / value
    try:
        if path.is_file() and path.stat().st_size > MAX_RECORD_BYTES:
            raise ParameterError(f"{key} = {value!r} has {path.stat().st_size:,} bytes: "
                                 f"allowed at most {MAX_RECORD_BYTES:,}")
        record = RecordPulse.from_csv(path)
    except UnicodeDecodeError as e:     # dynamics reads it as UTF-8 text
        raise ParameterError(f"{key} = {value!r} is not UTF-8 text (byte "
                             f"0x{e.object[e.start]:02x} at offset {e.start}): allowed a "
                             "two-column CSV t [s], a_g [m/s^2]") from None
    except ParameterError as e:         # name the key as well as the record
        if str(e).startswith(f"{key} = "):
            raise
        raise ParameterError(f"{key} = {value!r}: {e}") from None
    for note in record.warnings if warn else ():
        log.warning("warning: %s = %r: %s", key, value, note)
    return record


def record_problems(values: dict, source: str) -> list[str]:
    """The DEM's accelerogram read before any work, when the case asks for it: [] or the
    problem naming [dem] record (``read_record``; its warnings are logged when the DEM runs)."""
    dem = values.get("dem", {})
    if not (values.get("analysis", {}).get("dem") and dem.get("loading") == "record"):
        return []
    try:
        read_record(source, dem["record"], "[dem] record", warn=False)
    except ParameterError as e:
        return [str(e)]
    return []
