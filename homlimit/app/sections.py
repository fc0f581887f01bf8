"""The validated sections of a case: one frozen dataclass per section of the case file
(``schema.SCHEMA``), and ``CaseConfig``, the whole case."""

from __future__ import annotations

from dataclasses import dataclass, field

from ..params import FACADE_DEFAULT, MESHER_DEFAULT, PART_DIVISIONS, Case
from . import budget
from .schema import SCHEMA, toml_value

__all__ = ["AdaptConfig", "AnalysisConfig", "BlocksConfig", "CaseConfig", "DemConfig",
           "MeshConfig", "OutputConfig", "PulseConfig", "SECTIONS"]


@dataclass(frozen=True)
class MeshConfig:
    """[mesh]: the T-section triangulation of ``homlimit.fe.problems.t_section``."""

    size: float = 0.25
    max_triangles: int = budget.DEFAULT_MAX_TRIANGLES
    part_divisions: int = PART_DIVISIONS
    mesher: str = MESHER_DEFAULT
    outer_ratio: float = 25.0


@dataclass(frozen=True)
class AdaptConfig:
    """[adapt]: the adaptive bracket of the whole wall (``homlimit.fe.adapt``)."""

    target_gap: float = 0.01
    max_cycles: int = 6
    min_size: float = 0.005


@dataclass(frozen=True)
class AnalysisConfig:
    """[analysis]: which analyses run and how."""

    closed_form: bool = True
    tanpsi: float = 0.0
    lam_points: int = 200
    overturning: bool = False
    fe: bool = True
    facade: str = FACADE_DEFAULT
    heights: int = 6
    static: bool = True
    tol: float = 0.0
    blocks: bool = False
    dem: bool = False
    hinge_check: bool = True


@dataclass(frozen=True)
class BlocksConfig:
    """[blocks]: the rigid-block model (``homlimit.blocks.analyse_blocks``)."""

    facade: str = "through"
    friction: str = "associative"
    step: int = 1
    non_associative_check: bool = False
    max_blocks: int = 50000


@dataclass(frozen=True)
class DemConfig:
    """[dem]: the explicit rigid-block DEM (``homlimit.dem``; ``app.dem_stage``)."""

    kn: float = 1.0e9
    ks_over_kn: float = 0.5
    facade_stiffness: float = 0.0
    dt_fraction: float = 0.1
    settle_damping: float = 0.8
    settle_time: float = 2.0
    settle_velocity: float = 1e-5
    base_joint: str = "frictional"
    ground_margin: float = 2.0
    verlet_margin: float = 0.005
    cone_tolerance: float = 0.05
    trib_floor: float = 0.05
    loading: str = "impulse"
    pulse_period: float = 0.2
    polarity: int = 1
    rel_tol: float = 0.01
    t_max: float = 5.0
    guess: float = 0.0
    max_blocks: int = 5000
    frame_interval: float = 0.05
    animation: bool = True


@dataclass(frozen=True)
class PulseConfig:
    """[pulse]: the overturning spectra of ``homlimit pulse`` (``homlimit.dynamics``)."""

    kinds: tuple = ("rectangular", "one-sine")
    periods: tuple = (0.02, 0.05, 0.1, 0.2, 0.5, 1.0, 2.0)
    polarities: tuple = (1, -1)
    mechanisms: tuple = ("I", "II")
    gravity_I: str = "linearised"
    restitution: float = 0.0
    rtol: float = 1e-6
    scan_ratio: float = 1.05
    gamma: float = 2.0
    nu: float = 0.0
    record: str = ""


@dataclass(frozen=True)
class OutputConfig:
    """[output]: what is written and where."""

    dir: str = ""
    json: bool = True
    png: bool = True
    vtu: bool = True


SECTIONS = {"mesh": MeshConfig, "adapt": AdaptConfig, "analysis": AnalysisConfig,
            "blocks": BlocksConfig, "dem": DemConfig, "pulse": PulseConfig,
            "output": OutputConfig}


@dataclass(frozen=True)
class CaseConfig:
    """A whole validated case description."""

    case: Case
    mesh: MeshConfig = field(default_factory=MeshConfig)
    adapt: AdaptConfig = field(default_factory=AdaptConfig)
    analysis: AnalysisConfig = field(default_factory=AnalysisConfig)
    blocks: BlocksConfig = field(default_factory=BlocksConfig)
    dem: DemConfig = field(default_factory=DemConfig)
    pulse: PulseConfig = field(default_factory=PulseConfig)
    output: OutputConfig = field(default_factory=OutputConfig)
    source: str = "<dict>"
    warnings: tuple[str, ...] = ()     # valid but implausible values, one line each
    base_name: str = ""                # the case's own name when --set changed its inputs
    changes: tuple = ()                # (section.key, value in the case, value used) of --set

    @property
    def name(self) -> str:
        return self.case.name

    @property
    def modified(self) -> bool:
        """True when ``--set`` overrides changed the inputs of the named case."""
        return bool(self.changes)

    def describe_changes(self) -> str:
        """"B1 with wall.l = 3 (not 6)" for a modified case, "" otherwise."""
        if not self.changes:
            return ""
        return (f"{self.base_name} with " + ", ".join(
            f"{k} = {toml_value(new)} (not {toml_value(old)})"
            for k, old, new in self.changes))

    def as_dict(self) -> dict:
        """Every input, in the case-file layout (round-trips through ``load_case``)."""
        d = self.case.as_dict()
        out = {"name": d["name"], "wall": d["wall"], "masonry": d["masonry"],
               "tie": d["tie"], "floor": d["floor"]}
        for sec in SECTIONS:
            obj = getattr(self, sec)
            out[sec] = {k: (list(v) if isinstance(v, tuple) else v)
                        for k in SCHEMA[sec] for v in [getattr(obj, k)]}
        return out

