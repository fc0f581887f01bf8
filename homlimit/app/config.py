"""Case files: TOML (or a plain dict of the same shape) → validated parameter objects.

One section per parameter object, SI units::

    name = "B1"                    # optional; default: the file's stem
    [wall]     H L s b l gamma g   → homlimit.params.Wall
    [masonry]  a c f               → homlimit.params.Masonry
    [mesh]     size ...            → MeshConfig
    [analysis] fe facade ...       → AnalysisConfig
    [output]   dir png vtu         → OutputConfig

Every problem of a case — unknown section or key, wrong type, missing required value, value out
of range, blocks that do not fit the wall — is collected and raised at once as one
``ConfigError`` (a ``ParameterError``), each line naming the file, section, key, value and the
allowed range. No numerics here: nothing is computed before the whole case is valid.
The full key reference (``docs/case-file.md``) is generated from ``SCHEMA`` by ``schema_markdown``.
"""

from __future__ import annotations

import dataclasses
import math
import tomllib
from dataclasses import dataclass, field
from importlib import resources
from pathlib import Path
from typing import Any

from ..blocks.geometry import FACADE_BONDS
from ..dynamics.pulses import PULSE_KINDS
from ..errors import ParameterError, check_range
from ..params import FACADE_DEFAULT, FACADE_MODELS, Case, Masonry, Wall

__all__ = ["AnalysisConfig", "BlocksConfig", "CaseConfig", "ConfigError", "Key", "MeshConfig",
           "OutputConfig", "PulseConfig", "SCHEMA", "default_case", "load_case", "schema_markdown"]

REQUIRED = object()


class ConfigError(ParameterError):
    """A case description is invalid. ``problems`` lists every problem found, one line each."""

    def __init__(self, source: str, problems: list[str]):
        self.source = source
        self.problems = [f"{source}: {p}" for p in problems]
        n = len(self.problems)
        head = f"{source}: {n} problem{'s' if n != 1 else ''} in the case description"
        super().__init__(head + "".join(f"\n  - {p}" for p in self.problems))


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

    @property
    def required(self) -> bool:
        return self.default is REQUIRED

    def range_text(self, name: str) -> str:
        if self.choices:
            return "one of " + ", ".join(repr(c) for c in self.choices)
        parts = []
        if self.lo is not None:
            parts.append(f"{self.lo:g} {'<' if self.lo_open else '<='} {name}")
        if self.hi is not None:
            parts.append(f"{name} {'<' if self.hi_open else '<='} {self.hi:g}")
        return " and ".join(parts)


_POS = dict(lo=0.0, lo_open=True)

#: section -> key -> Key. The single source of truth for case files and their documentation.
SCHEMA: dict[str, dict[str, Key]] = {
    "wall": {
        "H": Key(float, unit="m", **_POS, doc="height of façade and transversal wall"),
        "L": Key(float, unit="m", **_POS, doc="length of the transversal wall"),
        "s": Key(float, unit="m", **_POS, doc="thickness of the transversal wall"),
        "b": Key(float, unit="m", **_POS, doc="thickness of the façade"),
        "l": Key(float, unit="m", **_POS,
                 doc="length of the façade between transversal walls (ρ = l/s, eq. 11)"),
        "gamma": Key(float, 2000.0, "kg/m³", **_POS, doc="mass density of masonry γ"),
        "g": Key(float, 9.81, "m/s²", **_POS, doc="gravitational acceleration"),
    },
    "masonry": {
        "a": Key(float, unit="m", **_POS, doc="block height (a <= H)"),
        "c": Key(float, unit="m", **_POS, doc="half block length (2c <= L)"),
        "f": Key(float, unit="", **_POS, doc="joint friction coefficient (α = √(cf/a), eq. 11)"),
    },
    "mesh": {
        "size": Key(float, 0.25, "m", **_POS,
                    doc="element spacing of the T-section mesh along z, and in the wall far "
                        "from the junction (homlimit.fe.problems.t_section h; 4 columns across "
                        "the façade, graded towards the junction)"),
    },
    "analysis": {
        "closed_form": Key(bool, True, doc="closed-form mechanisms I and II (eqs 8–20)"),
        "tanpsi": Key(float, 0.0, "", lo=0.0,
                      doc="crack slope tan ψ of mechanism II (0: √(cf/a), eq. 16)"),
        "lam_points": Key(int, 200, "", lo=10, hi=100000,
                          doc="points of the v̄_g(λ) curves over 0 < λ <= H/b"),
        "fe": Key(bool, True, doc="finite-element kinematic mechanism, crack and impulse"),
        "facade": Key(str, FACADE_DEFAULT, choices=FACADE_MODELS,
                      doc="strength domain of the façade in the FE model: bed joints only "
                          "(its blocks run through the thickness, as in the paper) or eq. 15 "
                          "(homogenised, the β → 0 idealisation)"),
        "heights": Key(int, 6, "", lo=2, hi=200,
                       doc="starting heights of the FE impulse scan, spaced geometrically "
                           "from one course (a) to H, refined around the minimum of v̄_g "
                           "(eq. 7) to one course or 0.5 %"),
        "static": Key(bool, True,
                      doc="static lower bound of the whole wall's FE multiplier on the same "
                          "mesh (the bracket λ⁻ <= λ <= λ⁺), its stress field in "
                          "mechanism.vtu and stress.png (needs fe)"),
        "tol": Key(float, 0.0, "", lo=0.0, hi=1e-2,
                   doc="Clarabel gap and feasibility tolerance (0: the solver default of "
                       "homlimit.fe.solver.SolverOptions)"),
        "blocks": Key(bool, False, doc="the rigid-block model of the running bond "
                                       "(``homlimit.blocks``, [blocks]): the block size "
                                       "enters; files blocks*.vtu/png/csv"),
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
        "mechanisms": Key(list, ["I", "II"], item=str, choices=("I", "II", "FE"),
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
REQUIRED_SECTIONS = ("wall", "masonry")
TOP_LEVEL = {"name": Key(str, "", doc="case name, used in titles and the output folder "
                                      "(empty: the file's stem)")}


@dataclass(frozen=True)
class MeshConfig:
    """[mesh]: the T-section triangulation of ``homlimit.fe.problems.t_section``."""

    size: float = 0.25


@dataclass(frozen=True)
class AnalysisConfig:
    """[analysis]: which analyses run and how."""

    closed_form: bool = True
    tanpsi: float = 0.0
    lam_points: int = 200
    fe: bool = True
    facade: str = FACADE_DEFAULT
    heights: int = 6
    static: bool = True
    tol: float = 0.0
    blocks: bool = False


@dataclass(frozen=True)
class BlocksConfig:
    """[blocks]: the rigid-block model (``homlimit.blocks.analyse_blocks``)."""

    facade: str = "through"
    friction: str = "associative"
    step: int = 1
    non_associative_check: bool = False
    max_blocks: int = 50000


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


SECTIONS = {"mesh": MeshConfig, "analysis": AnalysisConfig, "blocks": BlocksConfig,
            "pulse": PulseConfig, "output": OutputConfig}


@dataclass(frozen=True)
class CaseConfig:
    """A whole validated case description."""

    case: Case
    mesh: MeshConfig = field(default_factory=MeshConfig)
    analysis: AnalysisConfig = field(default_factory=AnalysisConfig)
    blocks: BlocksConfig = field(default_factory=BlocksConfig)
    pulse: PulseConfig = field(default_factory=PulseConfig)
    output: OutputConfig = field(default_factory=OutputConfig)
    source: str = "<dict>"

    @property
    def name(self) -> str:
        return self.case.name

    def as_dict(self) -> dict:
        """Every input, in the case-file layout (round-trips through ``load_case``)."""
        d = self.case.as_dict()
        out = {"name": d["name"], "wall": d["wall"], "masonry": d["masonry"]}
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
        return True, float(value)
    return isinstance(value, kind), value


_TYPE_NAMES = {float: "a number", int: "an integer", bool: "true or false", str: "a string",
               list: "a list"}


def _check_key(where: str, name: str, key: Key, value, problems: list[str]):
    """Append a problem for a wrong type or an out-of-range value; return the converted value
    (a list: every item checked against the key's type, range and choices)."""
    if key.kind is list:
        if not isinstance(value, list) or not value:
            problems.append(f"{where} {name} = {value!r} has the wrong type: expected a "
                            f"non-empty list, each item {_TYPE_NAMES[key.item]}")
            return None
        item = dataclasses.replace(key, kind=key.item, item=None)
        n = len(problems)
        out = [_check_key(where, f"{name}[{k}]", item, v, problems) for k, v in enumerate(value)]
        return out if len(problems) == n else None
    ok, value = _typed(key.kind, value)
    if not ok:
        problems.append(f"{where} {name} = {value!r} has the wrong type: expected "
                        f"{_TYPE_NAMES[key.kind]}")
        return None
    if key.choices and value not in key.choices:
        problems.append(f"{where} {name} = {value!r} is not allowed: allowed "
                        f"{key.range_text(name)}")
        return None
    if key.kind in (float, int):
        try:
            check_range(name, value, key.lo, key.hi, lo_open=key.lo_open, hi_open=key.hi_open,
                        unit=key.unit)
        except ParameterError as e:
            problems.append(f"{where} {e}")
            return None
        if not math.isfinite(value):  # pragma: no cover - check_range already rejects
            return None
    return value


def _parse(data: dict, source: str, default_name: str) -> CaseConfig:
    problems: list[str] = []
    if not isinstance(data, dict):
        raise ConfigError(source, [f"the case must be a table/dict, got {type(data).__name__}"])
    values: dict[str, dict[str, Any]] = {}
    for top, v in data.items():
        if top in SCHEMA:
            if not isinstance(v, dict):
                problems.append(f"[{top}] must be a section (table), got {v!r}")
        elif top in TOP_LEVEL:
            _check_key("", top, TOP_LEVEL[top], v, problems)
        else:
            allowed = ", ".join([f"[{s}]" for s in SCHEMA] + list(TOP_LEVEL))
            problems.append(f"unknown {'section' if isinstance(v, dict) else 'key'} "
                            f"{top!r}: allowed {allowed}")
    for sec, keys in SCHEMA.items():
        given = data.get(sec, {})
        if not isinstance(given, dict):
            continue  # already reported above
        if sec in REQUIRED_SECTIONS and sec not in data:
            problems.append(f"[{sec}] section is missing: required keys "
                            + ", ".join(k for k, key in keys.items() if key.required))
            continue
        vals = values.setdefault(sec, {})
        for name, v in given.items():
            if name not in keys:
                problems.append(f"[{sec}] unknown key {name!r}: allowed " + ", ".join(keys))
                continue
            out = _check_key(f"[{sec}]", name, keys[name], v, problems)
            if out is not None:
                vals[name] = out
        for name, key in keys.items():
            if name in given:
                continue
            if key.required:
                problems.append(f"[{sec}] {name} is missing ({key.doc}, {key.unit or '-'}; "
                                f"allowed {key.range_text(name)})")
            else:
                vals[name] = key.default
    name = data.get("name") if isinstance(data.get("name"), str) else ""
    name = name or default_name
    case = None
    if not problems:
        try:
            case = Case(wall=Wall(**values["wall"]), masonry=Masonry(**values["masonry"]),
                        name=name)
        except ParameterError as e:  # cross-key checks of params.Case (a <= H, 2c <= L)
            problems.append(f"[wall]/[masonry] {e}")
    if case is not None:
        size, span = values["mesh"]["size"], min(case.wall.H, case.wall.b + case.wall.L)
        if size > span:
            problems.append(f"[mesh] size = {size!r} m is out of range: "
                            f"allowed 0 < size <= min(H, b + L) = {span:g} m")
    if case is not None and values["analysis"]["blocks"]:
        w, m = case.wall, case.masonry
        n = math.ceil(w.H / m.a) * (math.ceil(w.L / (2 * m.c)) + 1)
        if n > values["blocks"]["max_blocks"]:
            problems.append(f"[analysis] blocks = true needs about {n} blocks ((H/a)(L/2c + "
                            f"1)): allowed up to [blocks] max_blocks = "
                            f"{values['blocks']['max_blocks']} (larger blocks a, c, or "
                            f"raise max_blocks)")
    if problems:
        raise ConfigError(source, [p.strip() for p in problems])
    return CaseConfig(case=case, source=source, **{
        sec: cls(**{k: tuple(v) if isinstance(v, list) else v for k, v in values[sec].items()})
        for sec, cls in SECTIONS.items()})


def load_case(path_or_dict: str | Path | dict | None = None,
              overrides: list[str] | dict | None = None) -> CaseConfig:
    """Read and validate a case: a TOML path, a dict of the same shape, or None (the default).

    ``overrides``: "section.key=value" strings (value in TOML syntax; a bare word is a string)
    or a {"section.key": value} dict, applied before validation (the CLI's ``--set``).
    Raises ConfigError (a ParameterError) listing every problem, before any computation.
    """
    if path_or_dict is None:
        data, source, stem = _default_data(), "<default: B1>", "B1"
    elif isinstance(path_or_dict, dict):
        data, source, stem = path_or_dict, "<dict>", "case"
    else:
        path = Path(path_or_dict)
        source, stem = str(path), path.stem
        try:
            text = path.read_text(encoding="utf-8")
        except OSError as e:
            raise ConfigError(source, [f"cannot read the case file: {e.strerror or e}"]) \
                from None
        try:
            data = tomllib.loads(text)
        except tomllib.TOMLDecodeError as e:
            raise ConfigError(source, [f"not valid TOML: {e}"]) from None
    if overrides:
        data = _override(data, overrides, source)
    return _parse(data, source, stem)


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
    out = {k: dict(v) if isinstance(v, dict) else v for k, v in data.items()}
    for key, value in items:
        sec, dot, name = key.partition(".")
        if not dot and sec in TOP_LEVEL:
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
    for sec, keys in [("(top level)", TOP_LEVEL)] + [(f"[{s}]", k) for s, k in SCHEMA.items()]:
        req = " (required section)" if sec.strip("[]") in REQUIRED_SECTIONS else ""
        lines += [f"### {sec}{req}", "", "| key | type | default | unit | allowed | meaning |",
                  "|---|---|---|---|---|---|"]
        for name, key in keys.items():
            default = "**required**" if key.required else f"`{_toml_value(key.default)}`"
            kind = key.kind.__name__ + (f" of {key.item.__name__}" if key.item else "")
            lines.append(f"| `{name}` | {kind} | {default} | {key.unit or '–'} | "
                         f"{key.range_text(name) or 'any'} | {key.doc} |")
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
