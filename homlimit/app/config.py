"""Case files: TOML (or a plain dict of the same shape) → validated parameter objects.

One section per parameter object, SI units::

    name = "B1"                    # optional; default: the file's stem
    [wall]     H L s b l gamma g   → homlimit.params.Wall
    [masonry]  a c f               → homlimit.params.Masonry
    [mesh]     size ...            → MeshConfig
    [analysis] fe facade ...       → AnalysisConfig
    [dem]      kn dt_fraction ...  → DemConfig (the rigid-block DEM, ``homlimit.dem``)
    [output]   dir png vtu         → OutputConfig

Every problem of a case — a file that is not UTF-8 TOML, unknown section or key, wrong type,
missing required value, value out of its physically meaningful range, the cross-checks between
keys (blocks that fit the wall, a mesh that fits the wall and the problem-size budget) — is
collected and raised at once as one ``ConfigError`` (a ``ParameterError``), each line naming the
file, section, key, value and the allowed range with its unit. Valid values outside the typical
range of masonry are ``warnings`` (not errors). No numerics here beyond the budget's estimate:
nothing is computed before the whole case is valid. ``--set`` overrides that change the inputs
append a short hash of the resolved inputs to the case name (``B1-1a2b3c4d``), so a modified
case never passes for the named one. The full key reference (``docs/case-file.md``) is
generated from ``SCHEMA`` by ``schema_markdown``.
"""

from __future__ import annotations

import dataclasses
import hashlib
import math
import tomllib
import unicodedata
from dataclasses import dataclass, field
from importlib import resources
from pathlib import Path
from typing import Any

from .._io import json_bytes
from ..blocks.geometry import FACADE_BONDS
from ..dynamics.pulses import PULSE_KINDS
from ..errors import ParameterError
from ..params import (
    FACADE_DEFAULT,
    FACADE_MODELS,
    MESHER_DEFAULT,
    MESHERS,
    PART_DIVISIONS,
    Case,
    Floor,
    Masonry,
    Tie,
    Wall,
)
from . import budget, registry

__all__ = ["AnalysisConfig", "BlocksConfig", "CaseConfig", "ConfigError", "DemConfig", "Key",
           "MeshConfig", "OutputConfig", "PulseConfig", "SCHEMA", "case_data", "check_base",
           "check_mesh", "default_case", "load_case", "load_case_inputs", "read_case", "read_text",
           "schema_markdown", "shown"]

REQUIRED = object()
#: the closed forms search the critical slenderness over LAM_MIN_CLOSED <= λ <= λ_max
#: (``closed_form.mechanisms._minimise``'s lam_min); a wall with H/b below it has no part to try
LAM_MIN_CLOSED = 0.5
MAX_CASE_BYTES = 1 << 20          # a case file is a few hundred bytes
MAX_NAME = 100                    # characters of a case name


class ConfigError(ParameterError):
    """A case description is invalid. ``problems`` lists every problem found, one line each."""

    def __init__(self, source: str, problems: list[str], what: str = "the case description"):
        self.source = source
        self.problems = [f"{source}: {p}" for p in problems]
        n = len(self.problems)
        head = f"{source}: {n} problem{'s' if n != 1 else ''} in {what}"
        super().__init__(head + "".join(f"\n  - {p}" for p in self.problems))

    @classmethod
    def merged(cls, errors: list[ConfigError], what: str) -> ConfigError:
        """One error listing the problems of several (each line keeps its own source)."""
        if len(errors) == 1:
            return errors[0]
        err = cls(errors[0].source, [], what)
        err.problems = [p for e in errors for p in e.problems]
        n = len(err.problems)
        err.args = (f"{n} problems in {what}" + "".join(f"\n  - {p}" for p in err.problems),)
        return err


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

    @property
    def required(self) -> bool:
        return self.default is REQUIRED

    def range_text(self, name: str) -> str:
        if self.choices:
            return "one of " + ", ".join(repr(c) for c in self.choices)
        text = name
        if self.lo is not None:
            text = f"{self.lo:g} {'<' if self.lo_open else '<='} {text}"
        if self.hi is not None:
            text = f"{text} {'<' if self.hi_open else '<='} {self.hi:g}"
        return "" if text == name else text


_POS = dict(lo=0.0, lo_open=True)


def _len(hi: float, typical: tuple[float, float]) -> dict:
    """A length [m] between 1 mm and ``hi`` (the physically meaningful range: nothing smaller
    than a millimetre is built of blocks, and the bounds keep every product finite)."""
    return dict(unit="m", lo=1e-3, hi=hi, typical=typical)

#: section -> key -> Key. The single source of truth for case files and their documentation.
SCHEMA: dict[str, dict[str, Key]] = {
    "wall": {
        "H": Key(float, **_len(1e4, (1.0, 40.0)),
                 doc="height of façade and transversal wall (H/b >= 0.5)"),
        "L": Key(float, **_len(1e4, (0.5, 50.0)), doc="length of the transversal wall"),
        "s": Key(float, **_len(1e3, (0.1, 2.0)), doc="thickness of the transversal wall"),
        "b": Key(float, **_len(1e3, (0.1, 2.0)), doc="thickness of the façade"),
        "l": Key(float, **_len(1e4, (0.5, 50.0)),
                 doc="length of the façade between transversal walls (ρ = l/s, eq. 11)"),
        "gamma": Key(float, 2000.0, "kg/m³", 1.0, 1e5, typical=(1000.0, 3000.0),
                     doc="mass density of masonry γ"),
        "g": Key(float, 9.81, "m/s²", 1e-2, 1e3, typical=(9.7, 9.9),
                 doc="gravitational acceleration"),
    },
    "masonry": {
        "a": Key(float, **_len(1e3, (0.03, 1.0)), doc="block height (a <= H)"),
        "c": Key(float, **_len(1e3, (0.03, 1.5)), doc="half block length (2c <= L)"),
        "f": Key(float, unit="", lo=1e-3, hi=100.0, typical=(0.3, 1.0),
                 doc="joint friction coefficient (α = √(cf/a), eq. 11)"),
        "fc": Key(float, 0.0, "Pa", 0.0, 1e10,
                  doc="compressive strength of the masonry; 0 means infinite (the paper's "
                      "rigid blocks). Finite: the hinge of every closed form retreats to the "
                      "resultant of a rectangular stress block, t = N/(2 fc l); both FE "
                      "bounds cap the principal compressive stress at fc; the rigid blocks "
                      "cap every contact at fc (docs/real-walls.md); the DEM does not take "
                      "it yet (it takes ties and floors)"),
        "cohesion": Key(float, 0.0, "Pa", 0.0, 1e10,
                        doc="cohesion of the joints (the strength domains' name); the FE "
                            "bounds of fe.problems.t_section take it, no model of a run takes "
                            "a non-zero value yet (docs/real-walls.md)"),
        "tension": Key(float, 0.0, "Pa", 0.0, 1e10,
                       doc="tensile strength of the joints (the strength domains' name); the "
                           "FE bounds of fe.problems.t_section take it, no model of a run "
                           "takes a non-zero value yet (docs/real-walls.md)"),
    },
    "mesh": {
        "size": Key(float, 0.25, "m", 0.0, 1e4, lo_open=True,
                    doc="element spacing of the T-section mesh along z, and in the wall far "
                        "from the junction (homlimit.fe.problems.t_section h; 4 columns across "
                        "the façade, graded towards the junction); size <= min(H, b + L)"),
        "max_triangles": Key(int, budget.DEFAULT_MAX_TRIANGLES, "", 100, 1e8,
                             doc="problem-size budget: the largest FE problem of the run "
                                 "(estimated from the wall and size before meshing, "
                                 "homlimit.app.budget) must not have more triangles; the "
                                 "default fits a 2-core, 24 GiB machine with margin "
                                 f"(about {budget.memory_gib(budget.DEFAULT_MAX_TRIANGLES):.1f}"
                                 " GiB at its peak; docs/cli.md)"),
        "part_divisions": Key(int, PART_DIVISIONS, "", 2, 1000,
                              doc="elements per height of a failing part in the FE impulse "
                                  "scan: a part of height h is meshed at min(size, "
                                  "h/part_divisions), so short parts stay resolved"),
        "mesher": Key(str, MESHER_DEFAULT, choices=MESHERS,
                      doc="the mesh of the whole wall and of every part of the FE scan: "
                          "\"crossed\" (structured grid, every cell cut by its diagonals), "
                          "\"gmsh\" (unstructured, refined to b/4 along the junction) or "
                          "\"gmsh-strip\" (gmsh with the façade strip a crossed grid of 4 "
                          "columns, the wall unstructured; docs/kinematic.md)"),
        "outer_ratio": Key(float, 25.0, "", 0.0, 1000.0,
                           doc="the static bound's own mesh (crossed mesher only; 0: the "
                               "kinematic bound's mesh): the façade's columns graded to a "
                               "width of size/outer_ratio at the outer face, where an "
                               "overturning façade bears (docs/static.md, \"The outer "
                               "face\"; measured on B1: 25 keeps the columns' aspect "
                               "ratio where linear and quadratic stresses agree)"),
    },
    "adapt": {
        "target_gap": Key(float, 0.01, "", 0.0, 1.0, lo_open=True,
                          doc="adaptive bracket of the whole wall (mesher \"gmsh\" only): stop "
                              "when (λ⁺ − λ⁻)/mean <= target_gap (homlimit.fe.adapt)"),
        "max_cycles": Key(int, 6, "", 1, 50,
                          doc="at most this many meshes of the adaptive bracket (1: one bracket "
                              "on the first mesh)"),
        "min_size": Key(float, 0.005, "m", 0.0, 1e4, lo_open=True,
                        doc="no element of the adaptive bracket is asked to be smaller"),
    },
    "analysis": {
        "closed_form": Key(bool, True, doc="closed-form mechanisms I and II (eqs 8–20)"),
        "tanpsi": Key(float, 0.0, "", lo=0.0, hi=100.0,
                      doc="crack slope tan ψ of mechanism II (0: √(cf/a), eq. 16)"),
        "lam_points": Key(int, 200, "", lo=10, hi=100000,
                          doc="points of the v̄_g(λ) curves over 0 < λ <= H/b"),
        "overturning": Key(bool, False,
                           doc="the simple overturning of the façade about its toe (no "
                               "abutment; closed form with ties, floors and fc; "
                               "docs/real-walls.md)"),
        "fe": Key(bool, True, doc="finite-element kinematic mechanism, crack and impulse"),
        "facade": Key(str, FACADE_DEFAULT, choices=FACADE_MODELS,
                      doc="strength domain of the façade in the FE model: bed joints only "
                          "(its blocks run through the thickness, as in the paper) or eq. 15 "
                          "(homogenised, the β → 0 idealisation)"),
        "heights": Key(int, 6, "", lo=2, hi=200,
                       doc="starting heights of the FE impulse scan, spaced geometrically "
                           "from one course (a) to H, refined around the minimum of v̄_g "
                           "(eq. 7) to one course (two courses within 0.5 %)"),
        "static": Key(bool, True,
                      doc="static lower bound of the whole wall's FE multiplier (the bracket "
                          "λ⁻ <= λ <= λ⁺; on its own graded mesh with [mesh] outer_ratio), "
                          "its stress field in stress.png, and in mechanism.vtu when both "
                          "bounds share a mesh (needs fe)"),
        "tol": Key(float, 0.0, "", lo=0.0, hi=1e-2,
                   doc="Clarabel gap and feasibility tolerance (0: the solver default of "
                       "homlimit.fe.solver.SolverOptions)"),
        "blocks": Key(bool, False, doc="the rigid-block model of the running bond "
                                       "(``homlimit.blocks``, [blocks]): the block size "
                                       "enters; files blocks*.vtu/png/csv"),
        "dem": Key(bool, False, doc="the explicit rigid-block DEM (``homlimit.dem``, [dem]): "
                                    "its collapse threshold by bisection, failing height and "
                                    "slide flags; files dem.pvd + dem/*.vtu, "
                                    "dem_snapshots.png (minutes of CPU per wall: "
                                    "docs/dem.md)"),
        "hinge_check": Key(bool, True, doc="the hinge's impulse ratio |P_x/P_z| against f "
                                           "and the shortest rectangular pulse it holds, "
                                           "per mechanism (summary 'hinges'; about 0.07 s "
                                           "per mechanism: off for large closed-form "
                                           "sweeps)"),
    },
    "blocks": {
        "facade": Key(str, "through", choices=FACADE_BONDS,
                      doc="façade of the block model: one block through its thickness b, as "
                          "the paper builds it, or laid in running bond"),
        "friction": Key(str, "associative", choices=("associative", "non-associative"),
                        doc="joint flow rule: associative Coulomb (the homogenised domain's), "
                            "or no dilatancy by the iterative scheme of Gilbert, Casapulla & "
                            "Ahmed (2006)"),
        "step": Key(int, 1, "", 1, 1000, doc="courses between the scanned part heights"),
        "non_associative_check": Key(bool, False,
                                     doc="also solve the critical height without "
                                         "dilatancy (associative friction only)"),
        "max_blocks": Key(int, 50000, "", 1, 10 ** 6,
                          doc="largest assembly allowed ((H/a)(L/2c + 1) blocks; 20 000 "
                              "blocks solve in about 90 s of CPU)"),
    },
    "dem": {
        "kn": Key(float, 1.0e9, "Pa/m", 1e5, 1e13,
                  doc="joint normal stiffness per unit joint area (a contact point gets kn × "
                      "tributary length × s); not in the paper: the order of UDEC joint "
                      "stiffnesses for masonry, 10⁹–10¹⁰ Pa/m (Lemos 2007), the lower end "
                      "for a longer time step"),
        "ks_over_kn": Key(float, 0.5, "", 0.0, 10.0, lo_open=True,
                          doc="shear over normal joint stiffness; not in the paper: a common "
                              "UDEC choice (an elastic interface: 1/(2(1 + ν)) ≈ 0.4)"),
        "facade_stiffness": Key(float, 0.0, "", 0.0, 1e3,
                                doc="factor on the façade's contact stiffness (0: ρ = l/s, "
                                    "the paper's uniform lowering: contacts stiffened like "
                                    "the façade's density)"),
        "dt_fraction": Key(float, 0.1, "", 0.0, 0.5, lo_open=True,
                           doc="dt = dt_fraction × √(m_min/k_max) (package choice: a block "
                               "held by ~40 such springs stays below the central-difference "
                               "limit)"),
        "settle_damping": Key(float, 0.8, "", 0.0, 1.0, hi_open=True,
                              doc="Cundall's local damping while settling under gravity "
                                  "(UDEC's default for static solutions); none after"),
        "settle_time": Key(float, 2.0, "s", 0.0, 600.0,
                           doc="longest settling run (package choice)"),
        "settle_velocity": Key(float, 1e-5, "m/s", 0.0, 1.0, lo_open=True,
                               doc="settling stops once every block is slower (package "
                                   "choice)"),
        "base_joint": Key(str, "frictional", choices=("frictional", "tied"),
                          doc="joint with the ground: frictional like the others (the "
                              "paper's UDEC base is not described) or tied (the contacts "
                              "present at the start neither open nor slide)"),
        "ground_margin": Key(float, 2.0, "m", 0.0, 100.0,
                             doc="the ground is widened by this on both sides (the "
                                 "assembly's ends flush with the façade's toe; package "
                                 "choice)"),
        "verlet_margin": Key(float, 0.005, "m", 0.0, 0.1, lo_open=True,
                             doc="contact candidates: vertex–edge pairs closer than this; "
                                 "rebuilt after a move of half of it (package choice)"),
        "cone_tolerance": Key(float, 0.05, "rad", 0.0, 0.5,
                              doc="widening of a vertex's normal cone in the contact test "
                                  "(package choice)"),
        "trib_floor": Key(float, 0.05, "", 0.0, 0.5, lo_open=True,
                          doc="least tributary length, as a fraction of the shorter edge "
                              "(package choice)"),
        "loading": Key(str, "impulse", choices=("impulse", "rectangular", "one-sine",
                                                "one-cosine", "ricker"),
                       doc="the load whose threshold is found: the ideal impulse (v̄_g, the "
                           "paper's) or a base-acceleration pulse of duration/period "
                           "pulse_period (its amplitude a_g; homlimit.dynamics.pulses)"),
        "pulse_period": Key(float, 0.2, "s", 1e-3, 100.0,
                            doc="Δt of the pulse (rectangular: its duration; loading other "
                                "than impulse)"),
        "polarity": Key(int, 1, choices=(1, -1),
                        doc="pulse polarity: +1 pushes the ground towards +x first (the "
                            "façade's inertia outwards)"),
        "rel_tol": Key(float, 0.01, "", 0.0, 0.5, lo_open=True,
                       doc="bisection tolerance of the threshold: (hi − lo)/(hi + lo)"),
        "t_max": Key(float, 5.0, "s", 0.0, 600.0, lo_open=True,
                     doc="length of a trial: a trial collapses when a façade or toothing "
                         "block moved outwards by more than H/4 before t_max "
                         "(docs/dem.md, section 3)"),
        "guess": Key(float, 0.0, "", 0.0, 1e4,
                     doc="first trial amplitude (m/s, or m/s² for a pulse; 0: the paper's "
                         "v̄_g rounded to 0.1 for a Table 1 wall, else mechanism I's; a "
                         "pulse: mechanism I's static multiplier × g); it only sets where "
                         "the bracket search (steps of ×1.5) starts"),
        "max_blocks": Key(int, 5000, "", 1, 10 ** 6,
                          doc="largest assembly allowed ((H/a)(L/2c + 1) blocks; B1's 480 "
                              "blocks take ~60 µs per time step, 75–80 s of CPU per "
                              "threshold)"),
        "frame_interval": Key(float, 0.05, "s", 1e-4, 10.0,
                              doc="time between the frames of the ParaView series of the "
                                  "lowest collapsing trial (dem.pvd) and of the animation"),
        "animation": Key(bool, True,
                         doc="with [output] png, write dem_animation.gif: the lowest "
                             "collapsing trial beside the highest standing one (one more "
                             "trial of up to t_max, and the rendering)"),
    },
    "pulse": {
        "kinds": Key(list, ["rectangular", "one-sine"], item=str, choices=tuple(PULSE_KINDS),
                     doc="pulse shapes of the overturning spectra (`homlimit pulse`): "
                         "rectangular (duration = period), one-sine, one-cosine, ricker, mp "
                         "(Mavroeidis–Papageorgiou)"),
        "periods": Key(list, [0.02, 0.05, 0.1, 0.2, 0.5, 1.0, 2.0], "s", 1e-3, 100.0,
                       item=float, doc="pulse periods T_p (rectangular: durations)"),
        "polarities": Key(list, [1, -1], item=int, choices=(1, -1),
                          doc="pulse polarities: +1 pushes the ground towards +x first (the "
                              "façade's inertia outwards)"),
        "mechanisms": Key(list, ["I", "II"], item=str, choices=registry.PULSE_CHOICES,
                          doc="mechanisms whose spectra are computed (FE runs the FE path "
                              "first: its critical body, rigid or one-DOF)"),
        "gravity_I": Key(str, "linearised", choices=("linearised", "exact"),
                         doc="mechanism I's gravity: as eq. 10 (linearised) or exact"),
        "restitution": Key(float, 0.0, "", 0.0, 1.0,
                           doc="coefficient of restitution at re-seating (0: the body "
                               "stays seated)"),
        "rtol": Key(float, 1e-6, "", 1e-13, 1e-2, lo_open=False,
                    doc="relative tolerance of the threshold amplitude (brentq)"),
        "scan_ratio": Key(float, 1.05, "", 1.0, 10.0, lo_open=True,
                          doc="amplitude step of the search from lift-off to overturning"),
        "gamma": Key(float, 2.0, "", 1.0, 10.0, lo_open=True,
                     doc="Mavroeidis–Papageorgiou oscillation parameter γ (kind mp)"),
        "nu": Key(float, 0.0, "rad", -2 * math.pi, 2 * math.pi,
                  doc="Mavroeidis–Papageorgiou phase ν (kind mp)"),
        "record": Key(str, "", doc="a ground-acceleration record, two-column CSV t [s], "
                                   "a_g [m/s²] (relative to the case file): its critical "
                                   "scale per mechanism"),
    },
    "output": {
        "dir": Key(str, "", doc="output folder (empty: homlimit-out/<name>/; --out overrides)"),
        "json": Key(bool, True, doc="write summary.json (every input, result, version)"),
        "png": Key(bool, True, doc="write the PNG pictures"),
        "vtu": Key(bool, True, doc="write the mesh and mechanism as .vtu (ParaView)"),
    },
}
#: arrays of tables ([[tie]], [[floor]]): name -> key -> Key, each entry validated like a
#: section; a sweep or --set addresses an entry's key as tie.0.yield_force
ARRAYS: dict[str, dict[str, Key]] = {
    "tie": {
        "z": Key(float, unit="m", lo=0.0, hi=1e4, lo_open=True,
                 doc="height of the tie above the ground (0 < z <= H)"),
        "yield_force": Key(float, unit="N/m", lo=0.0, hi=1e9,
                           doc="yield force per metre of façade (a bay of length l carries "
                               "yield_force·l)"),
        "stiffness": Key(float, 0.0, "N/m²", 0.0, 1e15,
                         doc="axial stiffness per metre of façade (force per metre per metre "
                             "of elongation); 0: rigid-plastic"),
        "ductility": Key(float, 0.0, "m", 0.0, 1e3,
                         doc="elongation at which the tie breaks; 0: none (it yields without "
                             "limit)"),
    },
    "floor": {
        "z": Key(float, unit="m", lo=0.0, hi=1e4, lo_open=True,
                 doc="height of the floor's bearing on the façade (0 < z <= H)"),
        "load": Key(float, unit="N/m", lo=0.0, hi=1e9,
                    doc="vertical dead load per metre of façade (only the load bears on the "
                        "façade: the floor's mass moves with the building)"),
        "eccentricity": Key(float, unit="m", lo=0.0, hi=1e3,
                            doc="where the load acts, from the façade's outer face "
                                "(0 <= eccentricity <= b)"),
        "restrains": Key(bool, False,
                         doc="the floor holds the façade horizontally at z: a failing body "
                             "lies above it"),
    },
}
MAX_ARRAY = 100                   # entries of a [[tie]] or [[floor]] array
REQUIRED_SECTIONS = ("wall", "masonry")
TOP_LEVEL = {"name": Key(str, "", doc="case name, used in titles and the output folder "
                                      "(empty: the file's stem; at most 100 characters, no "
                                      "control characters; the folder name keeps letters, "
                                      "digits and -_.+ only)")}


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
            f"{k} = {_toml_value(new)} (not {_toml_value(old)})"
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


def _typed(kind: type, value) -> tuple[bool, Any]:
    """(ok, converted) for TOML values: ints are accepted for floats, bools are never numbers."""
    if isinstance(value, bool):
        return kind is bool, value
    if kind is float and isinstance(value, int | float):
        return True, value if isinstance(value, int) else float(value)
    return isinstance(value, kind), value


_TYPE_NAMES = {float: "a number", int: "an integer", bool: "true or false", str: "a string",
               list: "a list"}


def shown(value) -> str:
    """A value as a message shows it (repr): huge integers and long texts shortened (every
    message about an input, the sweep's too)."""
    if isinstance(value, int) and not isinstance(value, bool) and abs(value) > 10 ** 30:
        digits = len(str(abs(value)))
        return f"{str(value)[:8]}...({digits} digits)"
    text = repr(value)
    return text if len(text) <= 60 else f"{text[:50]}... ({len(text)} characters)"


def _range_problem(where: str, name: str, key: Key, value) -> str | None:
    """The out-of-range line of a number (its unit and the allowed range with units)."""
    x = float(value) if abs(value) < 1e308 else (math.inf if value > 0 else -math.inf)
    bad = not math.isfinite(x)
    if key.lo is not None and (x <= key.lo if key.lo_open else x < key.lo):
        bad = True
    if key.hi is not None and (x >= key.hi if key.hi_open else x > key.hi):
        bad = True
    if not bad:
        return None
    u = f" {key.unit}" if key.unit else ""
    return (f"{where} {name} = {shown(value)}{u} is out of range: allowed "
            f"{key.range_text(name)}{u}")


def _check_key(where: str, name: str, key: Key, value, problems: list[str]):
    """Append a problem for a wrong type or an out-of-range value; return the converted value
    (a list: every item checked against the key's type, range and choices)."""
    if key.kind is list:
        if not isinstance(value, list) or not value:
            problems.append(f"{where} {name} = {shown(value)} has the wrong type: expected "
                            f"a non-empty list, each item {_TYPE_NAMES[key.item]}")
            return None
        item = dataclasses.replace(key, kind=key.item, item=None)
        n = len(problems)
        out = [_check_key(where, f"{name}[{k}]", item, v, problems) for k, v in enumerate(value)]
        return out if len(problems) == n else None
    ok, value = _typed(key.kind, value)
    if not ok:
        problems.append(f"{where} {name} = {shown(value)} has the wrong type: expected "
                        f"{_TYPE_NAMES[key.kind]}")
        return None
    if key.choices and value not in key.choices:
        problems.append(f"{where} {name} = {shown(value)} is not allowed: allowed "
                        f"{key.range_text(name)}")
        return None
    if key.kind is str and any(unicodedata.category(ch) == "Cc" for ch in value):
        problems.append(f"{where} {name} = {shown(value)} contains control characters (a NUL "
                        "byte, a newline, an escape, ...): allowed printable text")
        return None
    if key.kind in (float, int):
        bad = _range_problem(where, name, key, value)
        if bad:
            problems.append(bad)
            return None
        return float(value) if key.kind is float else value
    return value


def _collect(data: dict, problems: list[str]) -> dict[str, dict[str, Any]]:
    """The valid values of every section (defaults filled in); a problem for each bad one.
    A key missing from the result was reported (or its section was)."""
    values: dict[str, dict[str, Any]] = {}
    for top, v in data.items():
        if top in ARRAYS:
            values[top] = _collect_array(top, v, problems)
        elif top in SCHEMA:
            if not isinstance(v, dict):
                problems.append(f"[{top}] must be a section (table), got {shown(v)}")
        elif top in TOP_LEVEL:
            out = _check_key("", top, TOP_LEVEL[top], v, problems)
            if isinstance(out, str) and len(out) > MAX_NAME:
                problems.append(f"name = {out[:20]!r}... ({len(out)} characters) is out of "
                                f"range: allowed at most {MAX_NAME} characters")
        else:
            allowed = ", ".join([f"[{s}]" for s in SCHEMA] + [f"[[{a}]]" for a in ARRAYS]
                                + list(TOP_LEVEL))
            problems.append(f"unknown {'section' if isinstance(v, dict) else 'key'} "
                            f"{str(top)[:40]!r}: allowed {allowed}")
    for sec, keys in SCHEMA.items():
        given = data.get(sec, {})
        if not isinstance(given, dict):
            continue  # already reported above
        vals = values.setdefault(sec, {})
        if sec in REQUIRED_SECTIONS and sec not in data:
            problems.append(f"[{sec}] section is missing: required keys "
                            + ", ".join(k for k, key in keys.items() if key.required))
            continue
        for name, v in given.items():
            if name not in keys:
                problems.append(f"[{sec}] unknown key {str(name)[:40]!r}: allowed "
                                + ", ".join(keys))
                continue
            out = _check_key(f"[{sec}]", name, keys[name], v, problems)
            if out is not None:
                vals[name] = out
        for name, key in keys.items():
            if name in given:
                continue
            if key.required:
                u = f" {key.unit}" if key.unit else ""
                problems.append(f"[{sec}] {name} is missing ({key.doc}, {key.unit or '-'}; "
                                f"allowed {key.range_text(name)}{u})")
            else:
                vals[name] = key.default
    return values


def _collect_array(name: str, given, problems: list[str]) -> list[dict]:
    """The valid entries of a [[tie]] or [[floor]] array (defaults filled in); a problem for
    each bad one, named "[[tie]] 0 yield_force" (entry 0, as a sweep's tie.0.yield_force)."""
    if not isinstance(given, list) or not all(isinstance(e, dict) for e in given):
        problems.append(f"[[{name}]] = {shown(given)} has the wrong type: expected an array "
                        f"of tables ([[{name}]] entries)")
        return []
    if len(given) > MAX_ARRAY:
        problems.append(f"[[{name}]] has {len(given)} entries: allowed at most {MAX_ARRAY}")
        return []
    keys, out = ARRAYS[name], []
    for k, entry in enumerate(given):
        where, vals, n = f"[[{name}]] {k}", {}, len(problems)
        for key, v in entry.items():
            if key not in keys:
                problems.append(f"{where} unknown key {str(key)[:40]!r}: allowed "
                                + ", ".join(keys))
                continue
            got = _check_key(where, key, keys[key], v, problems)
            if got is not None:
                vals[key] = got
        for key, spec in keys.items():
            if key in entry:
                continue
            if spec.required:
                u = f" {spec.unit}" if spec.unit else ""
                problems.append(f"{where} {key} is missing ({spec.doc}, {spec.unit or '-'}; "
                                f"allowed {spec.range_text(key)}{u})")
            else:
                vals[key] = spec.default
        if len(problems) == n:
            out.append(vals)
    return out


def array_key(key: str) -> bool:
    """Whether ``key`` names a key of a [[tie]]/[[floor]] entry, as tie.0.yield_force."""
    arr, _, rest = str(key).partition(".")
    idx, dot, name = rest.partition(".")
    return arr in ARRAYS and idx.isdigit() and int(idx) < MAX_ARRAY and bool(dot) \
        and name in ARRAYS[arr]


def _real_wall_checks(v: dict[str, Any]) -> list[str]:
    """Ties and floors on the wall (0 < z <= H, 0 <= eccentricity <= b), and the real-wall
    inputs refused by the models and checks that do not take them (docs/real-walls.md)."""
    w, m, an = (v.get(k, {}) for k in ("wall", "masonry", "analysis"))
    out = []
    for arr in ("tie", "floor"):
        for k, e in enumerate(v.get(arr) or ()):
            if "H" in w and "z" in e and e["z"] > w["H"]:
                out.append(f"[[{arr}]] {k} z = {e['z']!r} m is out of range: allowed "
                           f"0 < z <= H = {w['H']:g} m")
            if "b" in w and "eccentricity" in e and e["eccentricity"] > w["b"]:
                out.append(f"[[{arr}]] {k} eccentricity = {e['eccentricity']!r} m is out of "
                           f"range: allowed 0 <= eccentricity <= b = {w['b']:g} m")
    closed = an.get("closed_form") or an.get("overturning")
    held = [(k, e["z"]) for k, e in enumerate(v.get("floor") or ())
            if e.get("restrains") and "z" in e]
    if closed and held and "H" in w and "b" in w:
        k, zr = max(held, key=lambda p: p[1])
        if (w["H"] - zr) / w["b"] < LAM_MIN_CLOSED:
            out.append(f"[[floor]] {k} z = {zr!r} m with restrains = true leaves the closed "
                       f"forms a failing body of (H − z)/b = {(w['H'] - zr) / w['b']:.4g}: out "
                       f"of range: allowed z <= H − {LAM_MIN_CLOSED:g} b = "
                       f"{w['H'] - LAM_MIN_CLOSED * w['b']:g} m (the body lies above it)")
    keys = [f"[masonry] {k} = {m[k]!r} Pa" for k in ("fc", "cohesion", "tension") if m.get(k)]
    keys += [f"[[{arr}]] ({len(v[arr])} entries)" for arr in ("tie", "floor") if v.get(arr)]
    if not keys:
        return out
    given = ", ".join(keys)
    # the FE path takes fc (both bounds, and the scan's mechanisms turn about the hinge they
    # find); its impulse scan has no tie, floor, cohesion or tension work in v̄_g yet, though
    # both bounds take them (fe.problems.t_section; docs/real-walls.md "FE bounds")
    not_fe = [k for k in keys if not k.startswith("[masonry] fc")]
    if an.get("fe") and not_fe:
        out.append(f"[analysis] fe = true: the FE path's impulse scan (v̄_g of the FE "
                   f"mechanism) does not take {', '.join(not_fe)} yet (the FE bounds do, "
                   "through homlimit.fe.problems.t_section); allowed [analysis] fe = false "
                   "with these inputs, or only [masonry] fc (docs/real-walls.md)")
    dem_no = [f"[masonry] {k} = {m[k]!r} Pa" for k in ("fc", "cohesion", "tension")
              if m.get(k)]
    if an.get("dem") and dem_no:      # the DEM takes ties and floors, not these
        out.append(f"[analysis] dem = true: the DEM does not take {', '.join(dem_no)} yet "
                   "(its contacts are the blocks' corners: a cap per corner is not the stress "
                   "block); allowed 0 Pa with [analysis] dem = true (docs/real-walls.md)")
    if an.get("blocks"):        # the blocks take fc, ties, floors (associative friction only)
        joint = [f"[masonry] {k} = {m[k]!r} Pa" for k in ("cohesion", "tension") if m.get(k)]
        if joint:
            out.append(f"[analysis] blocks = true: the rigid blocks do not take "
                       f"{', '.join(joint)} yet; allowed 0 Pa with [analysis] blocks = true "
                       "(docs/real-walls.md)")
        bl = v.get("blocks", {})
        if bl.get("friction") == "non-associative" or bl.get("non_associative_check"):
            out.append(f"[blocks] friction = non-associative (or non_associative_check) with "
                       f"{given}: the non-associative scheme does not take them; allowed "
                       "friction = \"associative\", non_associative_check = false "
                       "(docs/real-walls.md)")
    if an.get("hinge_check"):
        out.append(f"[analysis] hinge_check = true: the hinge check's rockers do not take "
                   f"{given} yet; allowed [analysis] hinge_check = false with these inputs "
                   "(docs/real-walls.md)")
    for k in ("cohesion", "tension"):
        if m.get(k) and (an.get("closed_form") or an.get("overturning")):
            out.append(f"[masonry] {k} = {m[k]!r} Pa: the closed forms (mechanisms I, II, "
                       "overturning) do not take a joint " + k + " (no clean derivation "
                       "yet); allowed 0 Pa (docs/real-walls.md)")
    return out


def _cross_checks(v: dict[str, dict[str, Any]], *, mesh_only: bool = False) -> list[str]:
    """The checks between keys, each run when the keys it needs are valid (so they are
    reported together with the field problems). ``mesh_only``: the checks of the mesh of the
    whole wall (the ``mesh`` command), whatever [analysis] says."""
    w, m, me, an = (v.get(k, {}) for k in ("wall", "masonry", "mesh", "analysis"))
    has = lambda d, *ks: all(k in d for k in ks)  # noqa: E731
    out = [] if mesh_only else _real_wall_checks(v)
    if not mesh_only and has(w, "H") and has(m, "a") and m["a"] > w["H"]:
        out.append(f"[masonry] a = {m['a']!r} m is out of range: a block must not be taller "
                   f"than the wall, allowed 0.001 <= a <= H = {w['H']:g} m")
    if not mesh_only and has(w, "L") and has(m, "c") and 2 * m["c"] > w["L"]:
        out.append(f"[masonry] c = {m['c']!r} m is out of range: a block must fit the "
                   f"transversal wall, allowed 0.001 <= 2c <= L = {w['L']:g} m")
    if (not mesh_only and an.get("closed_form") is False and an.get("fe") is False
            and not an.get("overturning")):
        out.append("[analysis] closed_form = false and fe = false: nothing to compute; allowed "
                   "at least one of them true")
    closed = not mesh_only and an.get("closed_form", False)
    if closed and has(w, "H", "b") and w["H"] / w["b"] < LAM_MIN_CLOSED:
        out.append(f"[wall] H = {w['H']!r} m, b = {w['b']!r} m: H/b = {w['H'] / w['b']:.4g} is "
                   f"out of range: allowed H/b >= {LAM_MIN_CLOSED:g} (the closed forms search "
                   f"the critical slenderness λ = h/b over {LAM_MIN_CLOSED:g} <= λ <= H/b; a "
                   "façade this squat does not overturn)")
    if closed and has(w, "L", "b") and has(m, "a", "c", "f") and has(an, "tanpsi"):
        t = an["tanpsi"] or math.sqrt(m["c"] * m["f"] / m["a"])
        what = ("[analysis] tanpsi" if an["tanpsi"] else "tan ψ = √(cf/a) ([masonry] a, c, f)")
        if w["L"] / (w["b"] * t) < LAM_MIN_CLOSED:
            out.append(f"[wall] L = {w['L']!r} m, b = {w['b']!r} m and {what} = {t:.4g}: "
                       f"L/(b tan ψ) = {w['L'] / (w['b'] * t):.4g} is out of range: allowed "
                       f"L/(b tan ψ) >= {LAM_MIN_CLOSED:g} (mechanism II's wedge must fit the "
                       f"transversal wall at λ = {LAM_MIN_CLOSED:g}: λ tan ψ <= L/b)")
    bl = v.get("blocks", {})
    if (not mesh_only and an.get("blocks") and has(w, "H", "L") and has(m, "a", "c")
            and has(bl, "max_blocks")):
        n = math.ceil(w["H"] / m["a"]) * (math.ceil(w["L"] / (2 * m["c"])) + 1)
        if n > bl["max_blocks"]:
            out.append(f"[analysis] blocks = true needs about {n} blocks ((H/a)(L/2c + 1)): "
                       f"out of range: allowed up to [blocks] max_blocks = {bl['max_blocks']} "
                       "(larger blocks a, c, or raise max_blocks)")
    dm = v.get("dem", {})
    if (not mesh_only and an.get("dem") and has(w, "H", "L") and has(m, "a", "c")
            and has(dm, "max_blocks")):
        n = math.ceil(w["H"] / m["a"]) * (math.ceil(w["L"] / (2 * m["c"])) + 1)
        if n > dm["max_blocks"]:
            out.append(f"[analysis] dem = true needs about {n} blocks ((H/a)(L/2c + 1)): out "
                       f"of range: allowed up to [dem] max_blocks = {dm['max_blocks']} "
                       "(larger blocks a, c, or raise max_blocks)")
    pulse_fe = registry.needs_mesh(v.get("pulse", {}).get("mechanisms") or ())  # FE for `pulse`
    fe = mesh_only or an.get("fe", False) or pulse_fe
    if not (fe and has(me, "size", "max_triangles") and has(w, "H", "b", "L")):
        return out
    size = me["size"]
    span = min(w["H"], w["b"] + w["L"])
    if size > span:
        out.append(f"[mesh] size = {size!r} m is out of range: "
                   f"allowed 0 < size <= min(H, b + L) = {span:g} m")
        return out
    # the impulse scan's parts run from one course (a) to H, each meshed at
    # min(size, h/part_divisions)
    parts = (m["a"] / w["b"],) if not mesh_only and has(m, "a") else ()
    n = budget.fe_triangles(w["H"], w["b"], w["L"], size, parts,
                            mesher=me.get("mesher", MESHER_DEFAULT),
                            divisions=me.get("part_divisions", PART_DIVISIONS),
                            outer_ratio=me.get("outer_ratio", 0.0)
                            if an.get("static", False) else 0.0)
    whole = budget.fe_triangles(w["H"], w["b"], w["L"], size)
    if n > me["max_triangles"] and whole <= me["max_triangles"] and "part_divisions" in me:
        # the whole wall fits: the shortest part of the scan, meshed at a/part_divisions
        pd, spec = me["part_divisions"], SCHEMA["mesh"]["part_divisions"]
        out.append(f"[mesh] part_divisions = {pd} gives about {n:.3g} triangles in the "
                   f"shortest part of the FE impulse scan (one course a = {m['a']:g} m meshed "
                   f"at a/part_divisions = {m['a'] / pd:.3g} m; about "
                   f"{budget.memory_gib(n):.3g} GiB): out of range: allowed at most [mesh] "
                   f"max_triangles = {me['max_triangles']:,}; lower [mesh] part_divisions "
                   f"(allowed {spec.range_text('part_divisions')}, default {spec.default}) or, "
                   "on a machine with the memory, raise [mesh] max_triangles")
    elif n > me["max_triangles"]:
        keys = "[mesh] size" + ("" if mesh_only else " (or [analysis] fe = false)")
        out.append(f"[mesh] size = {size!r} m gives about {n:.3g} triangles in the largest FE "
                   f"problem (estimated from H, b, L before meshing; about "
                   f"{budget.memory_gib(n):.3g} GiB): out of range: allowed at most "
                   f"[mesh] max_triangles = {me['max_triangles']:,}; raise {keys} or, on a "
                   "machine with the memory, [mesh] max_triangles")
    return out


def _warnings(case: Case, values: dict) -> tuple[str, ...]:
    """Valid values outside the typical range of masonry walls (each a line)."""
    out = []
    for sec in ("wall", "masonry"):
        for name, key in SCHEMA[sec].items():
            x = values[sec][name]
            if key.typical and not key.typical[0] <= x <= key.typical[1]:
                u = f" {key.unit}" if key.unit else ""
                out.append(f"[{sec}] {name} = {x:g}{u} is outside the typical range of masonry "
                           f"walls {key.typical[0]:g} .. {key.typical[1]:g}{u} ({key.doc}): "
                           "a valid input, check it")
    for what, x, lo, hi in (("ρ = l/s", case.rho, 1.0, 50.0),
                            ("H/b (slenderness of the whole façade)", case.wall.lam_max, 2.0,
                             60.0),
                            ("c/a (block proportion)", case.masonry.c / case.masonry.a, 0.25,
                             5.0)):
        if not lo <= x <= hi:
            out.append(f"{what} = {x:.4g} is outside the typical range {lo:g} .. {hi:g}: a "
                       "valid input, check it")
    return tuple(out)


def _parse(data: dict, source: str, default_name: str) -> CaseConfig:
    if not isinstance(data, dict):
        raise ConfigError(source, [f"the case must be a table/dict, got {type(data).__name__}"])
    problems: list[str] = []
    values = _collect(data, problems)
    problems += _cross_checks(values)
    if problems:
        raise ConfigError(source, [p.strip() for p in problems])
    name = data.get("name") or default_name
    case = Case(wall=Wall(**values["wall"]), masonry=Masonry(**values["masonry"]), name=name,
                ties=tuple(Tie(**e) for e in values.get("tie", ())),
                floors=tuple(Floor(**e) for e in values.get("floor", ())))
    return CaseConfig(case=case, source=source, warnings=_warnings(case, values), **{
        sec: cls(**{k: tuple(v) if isinstance(v, list) else v for k, v in values[sec].items()})
        for sec, cls in SECTIONS.items()})


def check_mesh(config: CaseConfig):
    """The mesh checks of the whole wall (size within the wall, the triangle budget), whatever
    [analysis] says: the ``mesh`` command's. Raises ConfigError."""
    problems = _cross_checks(config.as_dict(), mesh_only=True)
    if problems:
        raise ConfigError(config.source, problems)


def read_text(path: Path, what: str, max_bytes: int, fail, size_hint: str = "",
              bom: bool = False) -> str:
    """The text of a UTF-8 input file (a case file, a sweep's table), or ``fail(message)``
    naming what is wrong with it: not readable, not a regular file (a folder, a named pipe,
    a device: refused before opening, so nothing can hang), over ``max_bytes`` (``size_hint``
    says why), not UTF-8 (a byte-order mark unless ``bom``, UTF-16, binary). ``what``: the
    file's role in the messages."""
    try:
        st = path.stat()
        if not path.is_file():
            fail(f"cannot read the {what}: not a regular file")
        if st.st_size > max_bytes:
            fail(f"the {what} has {st.st_size:,} bytes: allowed at most {max_bytes:,}"
                 + (f" ({size_hint})" if size_hint else ""))
        raw = path.read_bytes()
    except OSError as e:
        fail(f"cannot read the {what}: {e.strerror or e}")
    if bom and raw.startswith(b"\xef\xbb\xbf"):   # as spreadsheets save "CSV UTF-8"
        raw = raw[3:]
    if raw.startswith(b"\xef\xbb\xbf"):
        fail(f"the {what} starts with a UTF-8 byte-order mark (BOM), which TOML does not "
             "allow: save it as UTF-8 without BOM (in many editors: 'UTF-8', not 'UTF-8 with "
             "BOM')")
    if raw.startswith((b"\xff\xfe", b"\xfe\xff")):
        fail(f"the {what} is UTF-16 (it starts with a UTF-16 byte-order mark): save it as "
             "UTF-8")
    try:
        return raw.decode("utf-8")
    except UnicodeDecodeError as e:
        line = raw[:e.start].count(b"\n") + 1
        fail(f"the {what} is not UTF-8 text: byte 0x{raw[e.start]:02x} at offset {e.start} "
             f"(line {line}) cannot be decoded; a binary file, or another encoding? Save it "
             "as UTF-8")


def read_case(path: str | Path) -> dict:
    """The TOML table of a case file; ConfigError naming what is wrong with the file
    (``read_text``; then: not TOML, an integer of more than 4300 digits, nesting too deep).
    The one reader of case files: ``load_case`` and the sweep's base use it."""
    path = Path(path)
    source = str(path)

    def fail(msg: str):
        raise ConfigError(source, [msg])

    text = read_text(path, "case file", MAX_CASE_BYTES, fail,
                     size_hint="a case file is a few hundred bytes")
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as e:
        fail(f"not valid TOML: {e}")
    except ValueError as e:          # e.g. an integer of more than 4300 digits
        fail(f"not valid TOML: {_long_integer(text) or e}")
    except RecursionError:
        fail("not valid TOML: arrays or tables nested too deeply")


def _long_integer(text: str) -> str | None:
    """Where a TOML text has an integer too long for Python (more than 4300 digits), named
    by its line and key, as tomllib's error does not say it; None if there is none."""
    import re

    for n, line in enumerate(text.splitlines(), 1):
        run = max(re.findall(r"\d+", line), key=len, default="")
        if len(run) > 4300:
            key = line.partition("=")[0].strip()[:40] or "a value"
            return (f"{key} = {run[:8]}...({len(run)} digits) at line {n}: an integer of "
                    "more than 4300 digits")
    return None


def case_data(path_or_dict: str | Path | dict | None = None,
              source: str | None = None) -> tuple[dict, str, str]:
    """(data, source, default name) of a case: a TOML path (``read_case``; its stem names
    the case), a dict (source ``source`` or "<dict>", name "case"), or None (the embedded B1).
    Nothing is validated here but the file itself."""
    if path_or_dict is None:
        return _default_data(), "<default: B1>", "B1"
    if isinstance(path_or_dict, dict):
        return path_or_dict, source or "<dict>", "case"
    path = Path(path_or_dict)
    return read_case(path), str(path), path.stem


def check_base(data: dict, source: str, overridden) -> None:
    """The checks of a sweep's base case (``sweep.plan_sweep``) before any case is planned:
    every problem of the keys that no grid key or table column (``overridden``: section.key
    and name) replaces, as ``load_case`` finds them (unknown section or key, wrong type, out
    of range, a required key given nowhere), at once. The checks between keys are each
    case's. Raises ConfigError."""
    if not isinstance(data, dict):
        raise ConfigError(source, [f"the case must be a table/dict, got {type(data).__name__}"])
    overridden = set(overridden)
    kept = {}
    for top, v in data.items():
        if top in SCHEMA and isinstance(v, dict):
            kept[top] = {k: x for k, x in v.items() if f"{top}.{k}" not in overridden}
        elif top in ARRAYS and isinstance(v, list):   # tie.0.yield_force given by the sweep
            kept[top] = [{k: x for k, x in e.items() if f"{top}.{n}.{k}" not in overridden}
                         if isinstance(e, dict) else e for n, e in enumerate(v)]
        elif top not in overridden:
            kept[top] = v
    problems: list[str] = []
    _collect(kept, problems)
    missing = [f"{sec}.{name}" for sec in REQUIRED_SECTIONS
               for name, key in SCHEMA[sec].items() if key.required]
    problems = [p for p in problems if not _overridden_missing(p, overridden, missing)
                and not _overridden_entry(p, overridden)]
    if problems:
        raise ConfigError(source, [p.strip() for p in problems])


def _overridden_entry(problem: str, overridden: set) -> bool:
    """True for the "is missing" line of a [[tie]]/[[floor]] entry's key the sweep gives."""
    for key in overridden:
        arr, _, rest = str(key).partition(".")
        idx, _, name = rest.partition(".")
        if arr in ARRAYS and problem.startswith(f"[[{arr}]] {idx} {name} is missing"):
            return True
    return False


def _overridden_missing(problem: str, overridden: set, required: list[str]) -> bool:
    """True for ``_collect``'s "is missing" line of a key (or section) that the sweep gives."""
    for key in required:
        sec, name = key.split(".")
        if key in overridden and problem.startswith(f"[{sec}] {name} is missing"):
            return True
    for sec in REQUIRED_SECTIONS:
        if problem.startswith(f"[{sec}] section is missing"):
            need = [k for k in required if k.startswith(sec + ".")]
            return all(k in overridden for k in need)
    return False


def load_case(path_or_dict: str | Path | dict | None = None,
              overrides: list[str] | dict | None = None,
              source: str | None = None) -> CaseConfig:
    """Read and validate a case: a TOML path, a dict of the same shape, or None (the default).

    ``overrides``: "section.key=value" strings (value in TOML syntax; a bare word is a string)
    or a {"section.key": value} dict, applied before validation (the CLI's ``--set``). When
    they change any input outside [output], the name gets a short hash of the resolved inputs
    (``base_name`` and ``changes`` record what changed). ``source``: where a dict came from
    (default "<dict>").
    Raises ConfigError (a ParameterError) listing every problem, before any computation.
    """
    return load_case_inputs(path_or_dict, overrides, source)[0]


def load_case_inputs(path_or_dict=None, overrides=None,
                     source: str | None = None) -> tuple[CaseConfig, dict]:
    """``load_case`` and the case's resolved inputs: ``as_dict()`` without the name and
    [output] (what the name's hash, and a sweep record's key, are made of)."""
    data, src, stem = case_data(path_or_dict, source)
    new = _override(data, overrides, src) if overrides else data
    config = _parse(new, src, stem)
    inputs = {k: v for k, v in config.as_dict().items() if k not in ("name", "output")}
    changes = _changes(data, new) if overrides else ()
    if not changes:
        return config, inputs
    digest = hashlib.sha256(json_bytes(inputs, sort_keys=True)).hexdigest()[:8]
    case = dataclasses.replace(config.case, name=f"{config.name}-{digest}")
    return dataclasses.replace(config, case=case, base_name=config.name,
                               changes=changes), inputs


def _changes(old: dict, new: dict) -> tuple:
    """(section.key, old value, new value) for every key outside [output] whose value the
    overrides changed (a key absent from ``old`` counts at its default)."""
    out = []
    for sec, keys in SCHEMA.items():
        if sec == "output" or not isinstance(new.get(sec), dict):
            continue
        before = old.get(sec) if isinstance(old.get(sec), dict) else {}
        for name, value in new[sec].items():
            key = keys.get(name)
            was = before.get(name, key.default if key and not key.required else None)
            if not _same(was, value):
                out.append((f"{sec}.{name}", was, value))
    for arr in ARRAYS:                # [[tie]], [[floor]]: entry by entry, key by key
        before = old.get(arr) if isinstance(old.get(arr), list) else []
        after = new.get(arr) if isinstance(new.get(arr), list) else []
        for k, entry in enumerate(after):
            was_entry = before[k] if k < len(before) and isinstance(before[k], dict) else {}
            for name, value in (entry.items() if isinstance(entry, dict) else ()):
                was = was_entry.get(name)
                if not _same(was, value):
                    out.append((f"{arr}.{k}.{name}", was, value))
    return tuple(out)


def _same(a, b) -> bool:
    if isinstance(a, list | tuple) and isinstance(b, list | tuple):
        return len(a) == len(b) and all(_same(x, y) for x, y in zip(a, b))
    if isinstance(a, bool) or isinstance(b, bool):
        return a is b
    if isinstance(a, int | float) and isinstance(b, int | float):
        return a == b
    return a == b and type(a) is type(b)


def _override(data: dict, overrides, source: str) -> dict:
    """A copy of ``data`` with "section.key=value" overrides applied (see ``load_case``)."""
    items = overrides.items() if isinstance(overrides, dict) else []
    problems = []
    if not isinstance(overrides, dict):
        parsed = []
        for text in overrides:
            key, sep, raw = str(text).partition("=")
            if not sep:
                problems.append(f"--set {text!r}: expected section.key=value")
                continue
            try:
                value = tomllib.loads(f"v = {raw.strip()}")["v"]
            except tomllib.TOMLDecodeError:
                value = raw.strip()                   # a bare word: a string
            parsed.append((key.strip(), value))
        items = parsed
    out = {k: dict(v) if isinstance(v, dict) else
           [dict(e) if isinstance(e, dict) else e for e in v] if isinstance(v, list) else v
           for k, v in data.items()}
    for key, value in items:
        sec, dot, name = key.partition(".")
        if sec in ARRAYS:             # tie.0.yield_force: entry 0 (0..n: n appends one)
            idx, dot2, entry_key = name.partition(".")
            arr = out.setdefault(sec, [])
            if (dot and dot2 and idx.isdigit() and isinstance(arr, list)
                    and int(idx) <= len(arr) and int(idx) < MAX_ARRAY):
                if int(idx) == len(arr):
                    arr.append({})
                if isinstance(arr[int(idx)], dict):
                    arr[int(idx)][entry_key] = value
                    continue
            problems.append(f"--set {key!r}: expected {sec}.<entry>.<key> with an entry "
                            f"0 .. {len(arr) if isinstance(arr, list) else 0} of [[{sec}]] "
                            f"(e.g. {sec}.0.z)")
        elif not dot and sec in TOP_LEVEL:
            out[sec] = value
        elif dot and isinstance(out.setdefault(sec, {}), dict):
            out[sec][name] = value
        else:
            problems.append(f"--set {key!r}: expected section.key (e.g. mesh.size) or name")
    if problems:
        raise ConfigError(source, problems)
    return out


def _default_data() -> dict:
    text = resources.files("homlimit").joinpath("data/default.toml").read_text(encoding="utf-8")
    return tomllib.loads(text)


def default_case() -> CaseConfig:
    """The embedded default case: Table 1's wall B1 (homlimit/data/default.toml)."""
    return _parse(_default_data(), "<default: B1>", "B1")


def schema_markdown() -> str:
    """The key reference of docs/case-file.md, generated from SCHEMA (one table per section)."""
    lines = []
    for sec, keys in ([("(top level)", TOP_LEVEL)] + [(f"[{s}]", k) for s, k in SCHEMA.items()]
                      + [(f"[[{a}]] (array of tables; a sweep's {a}.0.z)", k)
                         for a, k in ARRAYS.items()]):
        req = " (required section)" if sec.strip("[]") in REQUIRED_SECTIONS else ""
        lines += [f"### {sec}{req}", "",
                  "| key | type | default | unit | allowed | typical | meaning |",
                  "|---|---|---|---|---|---|---|"]
        for name, key in keys.items():
            default = "**required**" if key.required else f"`{_toml_value(key.default)}`"
            kind = key.kind.__name__ + (f" of {key.item.__name__}" if key.item else "")
            typical = f"{key.typical[0]:g} .. {key.typical[1]:g}" if key.typical else "–"
            lines.append(f"| `{name}` | {kind} | {default} | {key.unit or '–'} | "
                         f"{key.range_text(name) or 'any'} | {typical} | {key.doc} |")
        lines.append("")
    return "\n".join(lines)


def _toml_value(v) -> str:
    if isinstance(v, list | tuple):
        return "[" + ", ".join(_toml_value(x) for x in v) + "]"
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, str):
        return f'"{v}"'
    return f"{v:g}" if isinstance(v, float) else str(v)
