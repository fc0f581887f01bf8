"""The FE cache: the critical FE mechanism's one-DOF impulse that ``homlimit run`` keeps for
``homlimit pulse`` (its FE rocker), keyed by every input the FE path depends on and by the
FE source code, written atomically with a checksum, never trusted when unsound."""

from __future__ import annotations

import dataclasses
import functools
import hashlib
import json
import logging
import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from .. import _io
from .._version import package_version
from ..errors import OutputError, ParameterError
from ..fe.mesh import cache_dir
from ..impulse import LoadWork, RigidBody
from ..mechanism.analysis import FEResult
from ..mechanism.fe_impulse import GeneralisedImpulse
from .config import CaseConfig
from .schema import ARRAYS
from .stages import solver_options

__all__ = ["FE_CACHE_FORMAT", "FERocker", "fe_cache_inputs", "fe_cache_path", "read_fe_cache",
           "write_fe_cache"]

log = logging.getLogger("homlimit.app.models")   # the FE path's log lines, as before the split


FE_CACHE_FORMAT = "homlimit FE rocker 2"    # 2: the impulse's W_floors, W_ties, load_work
IMPULSE_FLOATS = ("M", "Pi", "W_m", "q_m", "vg", "lift_rest", "M_rest_share", "W_rest_share",
                  "W_floors", "W_ties")     # the GeneralisedImpulse's numbers the cache keeps


@dataclass(frozen=True)
class FERocker:
    """What the pulse spectra need of the FE path (``dynamics.case_rockers``' ``fe_body``):
    the critical mechanism's one-DOF impulse (``fe_impulse.GeneralisedImpulse``), its height
    h [m] and v̄_g [m/s]; ``cache``: its entry in the FE cache, ``from_cache``: read from it
    (rather than computed now)."""

    impulse: Any
    h: float
    vg: float
    cache: Path | None = None
    from_cache: bool = False
    name = "FE"                  # the mechanism it stands for (not a field)


@functools.cache
def _fe_code_digest() -> str:
    """SHA-256 of the source of every module the FE path runs (fe, mechanism, impulse,
    params): a cache entry made by other code is never read, whatever the version says."""
    root = Path(__file__).resolve().parents[1]
    h = hashlib.sha256()
    for path in sorted([*root.joinpath("fe").rglob("*.py"), *root.joinpath("mechanism")
                        .rglob("*.py"), *root.joinpath("impulse").rglob("*.py"),
                        root / "params.py"]):
        h.update(str(path.relative_to(root)).encode() + b"\0" + path.read_bytes())
    return h.hexdigest()


def fe_cache_inputs(config: CaseConfig) -> dict:
    """Every input the FE path of ``config`` depends on: the case's wall, masonry, mesh,
    adapt (the whole wall's mesh and crack splits) and analysis sections, the solver settings,
    the package version and its FE source code."""
    opts = dataclasses.asdict(solver_options(config.analysis.tol, config.analysis.stress_degree))
    opts.pop("verbose")                       # the solver log changes no number
    d = config.as_dict()
    real = {k: d[k] for k in ARRAYS if d.get(k)}     # none: the paper's inputs
    return {"format": FE_CACHE_FORMAT, **{k: d[k] for k in ("wall", "masonry", "mesh",
                                                            "adapt", "analysis")}, **real,
            "solver": opts, "homlimit_version": package_version(), "code": _fe_code_digest()}


def fe_cache_path(config: CaseConfig) -> Path:
    """The FE cache entry of ``config``: ``fe-<hash of fe_cache_inputs>.json`` in the
    package's cache folder (``fe.mesh.cache_dir()``, ``$HOMLIMIT_MESH_CACHE``)."""
    text = _io.json_bytes(fe_cache_inputs(config), sort_keys=True)
    return cache_dir() / f"fe-{hashlib.sha256(text).hexdigest()[:24]}.json"


def _checksum(entry: dict) -> str:
    return hashlib.sha256(_io.json_bytes({k: v for k, v in entry.items() if k != "sha256"},
                                         sort_keys=True)).hexdigest()


def write_fe_cache(config: CaseConfig, fe: FEResult) -> Path | None:
    """Keep the critical FE mechanism's one-DOF impulse of ``fe`` (the FE path of ``config``)
    in the FE cache, atomically, with its inputs and a checksum; None (and a warning) when
    the cache folder cannot be written, which fails nothing else. With ties or floors it
    keeps their work too (``impulse.LoadWork``, the rocker's ``load_work``)."""
    crit = fe.critical
    if crit is None or crit.impulse is None:
        return None
    gi = crit.impulse
    lw = getattr(gi, "load_work", None)
    entry = {"inputs": fe_cache_inputs(config),
             "impulse": {**{k: getattr(gi, k) for k in IMPULSE_FLOATS},
                         "block": dataclasses.asdict(gi.block),
                         "load_work": None if lw is None else lw.as_dict()},
             "h": crit.h, "vg": crit.vg, "scan": [m.record() for m in fe.scan]}
    entry["sha256"] = _checksum(entry)
    path = fe_cache_path(config)
    try:      # the exact floats: json writes the shortest repr that reads back the same
        _io.write_text(path, json.dumps(_io.to_jsonable(entry), indent=1) + "\n")
    except (OSError, OutputError) as exc:
        log.warning("warning: FE cache %s not written: %s", path, exc)
        return None
    return path


def read_fe_cache(config: CaseConfig) -> FERocker | None:
    """The FE cache entry of ``config`` (``fe_cache_path``) if there is one and it is sound:
    its checksum holds, its inputs are ``config``'s, its impulse a valid one. A corrupt or
    foreign entry is never trusted: None (and a warning), so that the caller computes the
    FE path again and rewrites it."""
    path = fe_cache_path(config)
    if not path.is_file():
        return None
    try:
        entry = json.loads(path.read_text(encoding="utf-8"))
        if entry.get("sha256") != _checksum(entry):
            raise ValueError("checksum mismatch")
        if entry["inputs"] != json.loads(_io.json_bytes(fe_cache_inputs(config))):
            raise ValueError("inputs differ")
        imp = dict(entry["impulse"])
        lw = imp.pop("load_work")
        gi = GeneralisedImpulse(block=RigidBody(**imp.pop("block")),
                                load_work=None if lw is None else LoadWork.from_dict(lw),
                                **{k: float(imp.pop(k)) for k in IMPULSE_FLOATS})
        if imp:
            raise ValueError(f"unknown impulse keys {sorted(imp)}")
        if not all(math.isfinite(getattr(gi, k)) and getattr(gi, k) > 0
                   for k in ("M", "Pi", "W_m", "vg")):
            raise ValueError("impulse not positive and finite")
        return FERocker(gi, float(entry["h"]), float(entry["vg"]), path, True)
    except (OSError, ValueError, KeyError, TypeError, AttributeError, ParameterError) as exc:
        log.warning("warning: FE cache entry %s ignored (%s): computing the FE path again",
                    path, exc)
        return None
