"""The validated sections of a case: one frozen dataclass per section of the case file, its
defaults the schema's (``section``, ``schema.SCHEMA``), and ``CaseConfig``, the whole case."""

from __future__ import annotations

from dataclasses import dataclass, field

from ..check.site import Site
from ..params import Case
from .schema import ARRAYS, SCHEMA
from .schema_doc import toml_value

__all__ = ["AdaptConfig", "AnalysisConfig", "BlocksConfig", "CaseConfig", "DemConfig",
           "MeshConfig", "OutputConfig", "PulseConfig", "SECTIONS", "section"]


def section(name: str):
    """A frozen dataclass of the section ``name`` whose fields' defaults are the schema's
    (``SCHEMA[name]``: written once, there; lists become tuples). The class body lists the
    fields with their types only, in the schema's order."""

    def make(cls):
        keys = SCHEMA[name]
        if list(cls.__annotations__) != list(keys):
            raise TypeError(f"{cls.__name__}'s fields {list(cls.__annotations__)} are not "
                            f"[{name}]'s keys {list(keys)}")
        for k, key in keys.items():
            setattr(cls, k, tuple(key.default) if isinstance(key.default, list)
                    else key.default)
        return dataclass(frozen=True)(cls)

    return make


@section("mesh")
class MeshConfig:
    """[mesh]: the T-section triangulation of ``homlimit.fe.problems.t_section``."""

    size: float
    max_triangles: int
    part_divisions: int
    mesher: str
    outer_ratio: float


@section("adapt")
class AdaptConfig:
    """[adapt]: the adaptive bracket of the whole wall (``homlimit.fe.adapt``)."""

    target_gap: float
    max_cycles: int
    min_size: float
    conform: bool
    crack_cycles: int
    crack_tol: float


@section("analysis")
class AnalysisConfig:
    """[analysis]: which analyses run and how."""

    closed_form: bool
    tanpsi: float
    lam_points: int
    overturning: bool
    fe: bool
    facade: str
    heights: int
    static: bool
    stress_degree: int
    tol: float
    blocks: bool
    dem: bool
    hinge_check: bool


@section("blocks")
class BlocksConfig:
    """[blocks]: the rigid-block model (``homlimit.blocks.analyse_blocks``)."""

    facade: str
    friction: str
    step: int
    non_associative_check: bool
    max_blocks: int


@section("dem")
class DemConfig:
    """[dem]: the explicit rigid-block DEM (``homlimit.dem``; ``app.dem_stage``)."""

    kn: float
    ks_over_kn: float
    facade_stiffness: float
    toothing: str
    dt_fraction: float
    settle_damping: float
    settle_time: float
    settle_velocity: float
    base_joint: str
    ground_margin: float
    verlet_margin: float
    cone_tolerance: float
    trib_floor: float
    joint_segments: int
    loading: str
    pulse_period: float
    polarity: int
    record: str
    rel_tol: float
    t_max: float
    guess: float
    max_blocks: int
    frame_interval: float
    animation: bool


@section("pulse")
class PulseConfig:
    """[pulse]: the overturning spectra of ``homlimit pulse`` (``homlimit.dynamics``)."""

    kinds: tuple
    periods: tuple
    polarities: tuple
    mechanisms: tuple
    gravity_I: str
    restitution: float
    rtol: float
    scan_ratio: float
    gamma: float
    nu: float
    record: str


@section("output")
class OutputConfig:
    """[output]: what is written and where."""

    dir: str
    json: bool
    png: bool
    vtu: bool
    report: bool


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
    site: Site | None = None           # [site] (the code check), only when the case has it
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
               **{arr: d[arr] for arr in ARRAYS}}
        for sec in SECTIONS:
            obj = getattr(self, sec)
            out[sec] = {k: (list(v) if isinstance(v, tuple) else v)
                        for k in SCHEMA[sec] for v in [getattr(obj, k)]}
        if self.site is not None:
            out["site"] = {k: getattr(self.site, k) for k in SCHEMA["site"]}
        return out

