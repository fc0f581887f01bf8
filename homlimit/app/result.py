"""Stage "models" → its product: ``Result``, what one case's models produced (the mechanisms,
the FE path, the curves, the hinge checks, the files), its JSON summary and terminal text."""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from .._version import package_version
from ..closed_form.paper import DemResult
from ..mechanism.analysis import FEResult
from ..params import Case
from . import report
from .config import CaseConfig

__all__ = ["Result"]


@dataclass
class Result:
    """Everything one ``run`` produced.

    mechanisms: name → mechanism, in the registry's order (``registry``: what each offers;
    "I", "II": ``closed_form.mechanisms.MechanismResult``, "FE": the critical
    ``mechanism.analysis.FEMechanism``, "blocks": ``blocks.BlocksAnalysis``); fe: the whole
    FE path (``FEResult``); curves: name → (λ, v̄_g(λ), label) of the closed forms; dem: the
    paper's Table 1 row of this wall; hinges: per mechanism with a rocker, the shortest
    rectangular pulse whose acceleration the hinge holds (a_g <= f g) that still overturns
    it (``dynamics.holding_pulse``).
    """

    config: CaseConfig
    mechanisms: dict[str, Any] = field(default_factory=dict)
    curves: dict = field(default_factory=dict)
    fe: FEResult | None = None
    dem: DemResult | None = None
    hinges: dict[str, Any] = field(default_factory=dict)   # name → dynamics.HoldingPulse
    blocks: Any = None                   # blocks.BlocksAnalysis ([analysis] blocks)
    dem_run: Any = None                  # app.dem_stage.DemRun ([analysis] dem)
    code_check: Any = None               # app.code_check.CodeCheck (with [site])
    files: dict[str, Path] = field(default_factory=dict)
    timings: dict[str, float] = field(default_factory=dict)

    @property
    def case(self) -> Case:
        return self.config.case

    @property
    def name(self) -> str:
        return self.config.name

    def critical(self) -> dict | None:
        """The governing mechanism: the lowest finite collapse velocity."""
        cands = [(m.vg, name) for name, m in self.mechanisms.items() if math.isfinite(m.vg)]
        if not cands:
            return None
        vg, name = min(cands)
        return {"mechanism": name, "vg": vg,
                "vnorm": vg / math.sqrt(self.case.wall.g * self.case.wall.b)}

    def to_dict(self) -> dict:
        """The JSON summary: every input, every result, the package version, the warnings
        about implausible inputs, what ``--set`` changed, and the unit of every quantity."""
        c, cfg = self.case, self.config
        d = {
            "homlimit_version": package_version(),
            "case": self.name,
            "source": cfg.source,
            "modified": None if not cfg.modified else {
                "from": cfg.base_name, "changes": {k: {"case": old, "used": new}
                                                   for k, old, new in cfg.changes}},
            "warnings": list(cfg.warnings),
            "inputs": cfg.as_dict(),
            "derived": {"rho": c.rho, "alpha": c.alpha, "alpha2": c.alpha ** 2, "beta": c.beta,
                        "lam_max": c.wall.lam_max, "f": c.masonry.f,
                        "c_over_a": c.masonry.c / c.masonry.a},
            "mechanisms": {k: m.as_dict() for k, m in self.mechanisms.items()},
            "hinges": {k: dataclasses.asdict(h) for k, h in self.hinges.items()},
            "fe": None if self.fe is None else self.fe.as_dict(),
            "blocks": None if self.blocks is None else self.blocks.summary(),
            "critical": self.critical(),
            "dem_table1": None if self.dem is None else self.dem.as_dict(),
            "dem": None if self.dem_run is None else self.dem_run.as_dict(),
            "code_check": None if self.code_check is None else self.code_check.as_dict(),
            "files": {k: str(v) for k, v in self.files.items()},
            "timings_s": self.timings,
        }
        d["units"] = report.units_table(d)
        return d

    def summary(self) -> str:
        """The terminal summary (``report.summary_text``)."""
        return report.summary_text(self)
