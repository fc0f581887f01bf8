"""The whole analysis of one wall, shared by the three doors.

``homlimit run CASE.toml``, ``python -m homlimit run CASE.toml`` and ``homlimit.run(CASE)`` all
call ``run`` below, which

1. validates the case (``config``), before any computation;
2. runs every registered model the case enables (``registry``, ``models``): the closed-form
   mechanisms I (eqs 8–14) and II (eqs 16–20) at their critical slenderness and their
   v̄_g(λ) curves; with ``[analysis] fe`` the finite-element path (the impulse scan over
   collapse heights, the whole wall's mechanism and crack, its static lower bound); with
   ``[analysis] blocks`` the rigid blocks;
3. checks that every result is a finite number (``ResultError`` naming the mechanism and the
   quantity otherwise);
4. writes the result files (``report.write``) as one result set (``result_folder``): into a
   staging folder that replaces the output folder in one rename at the end, so the folder holds
   the previous set or the new one, never a mix. The output folder is checked (and the staging
   folder created) before any computation.

Progress and warnings go to the ``logging`` module (the command line shows them); the other
commands' work is here too: ``table1_records``, ``crack_study_records``, ``mesh_case``,
``pulse_records``, ``figure2_curves``.
"""

from __future__ import annotations

import dataclasses
import hashlib
import logging
import math
import os
import unicodedata
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from .. import _io
from .._version import package_version
from ..closed_form import mechanisms as mech
from ..closed_form.paper import DemResult, dem_row, table1, table1_rows
from ..dynamics import holding_pulse
from ..errors import ParameterError, ResultError, check_choice, check_range
from ..mechanism.analysis import FEResult, fe_result
from ..params import FACADE_DEFAULT, FACADE_MODELS, MESHER_DEFAULT, MESHERS, Case
from . import budget, models, registry, report
from .config import CaseConfig, check_mesh, load_case
from .models import (
    FERocker,
    fe_cache_path,
    fe_rocker,
    finite,
    read_fe_cache,
    solver_options,
    stage,
    write_fe_cache,
)

__all__ = ["FERocker", "Result", "check_results", "conclude", "crack_study_records",
           "fe_cache_path", "fe_rocker", "figure2_curves", "folder_name", "mesh_case",
           "output_dir", "package_version", "pulse_records", "read_fe_cache", "result_folder",
           "run", "source_of", "table1_blocks_records", "table1_records", "write_fe_cache"]

log = logging.getLogger(__name__)


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
            "files": {k: str(v) for k, v in self.files.items()},
            "timings_s": self.timings,
        }
        d["units"] = report.units_table(d)
        return d

    def summary(self) -> str:
        """The terminal summary (``report.summary_text``)."""
        return report.summary_text(self)


MAX_FOLDER_NAME = 80  # bytes of a folder name made from a case name
MAX_RECORD_BYTES = 64 << 20  # an accelerogram of a million samples is ~30 MB


def folder_name(name: str) -> str:
    """A case name made safe as one folder name: letters, digits and ``-_.+`` kept, anything
    else (separators, control characters, spaces) replaced by ``_``, no leading dots (no
    hidden folder, no ``..``), at most MAX_FOLDER_NAME bytes; when anything was changed, a
    short hash of the original name is appended so that different names stay apart."""
    keep = "".join(ch if (ch.isalnum() or ch in "-_.+") and unicodedata.category(ch)[0] != "C"
                   else "_" for ch in unicodedata.normalize("NFC", name))
    keep = keep.lstrip(".") or "case"
    while len(keep.encode()) > MAX_FOLDER_NAME - 9:
        keep = keep[:-1]
    if keep != name:
        keep += "-" + hashlib.sha256(name.encode("utf-8", "surrogatepass")).hexdigest()[:8]
    return keep


def output_dir(config: CaseConfig, out: str | Path | None = None) -> Path:
    """--out, else [output] dir (both taken as given), else homlimit-out/NAME/ (relative to the
    working folder) with NAME the case name made safe (``folder_name``); a case changed by
    ``--set`` has a hash of its inputs in its name (``config.load_case``)."""
    if out:
        return Path(out)
    if config.output.dir:
        return Path(config.output.dir)
    return Path("homlimit-out") / folder_name(config.name)


def source_of(where) -> dict:
    """A result set's source, as its manifest records it: ``{"source": absolute path,
    "source_sha256": hash of the file's bytes}`` for a case file, ``{"source":
    "embedded:B1"}`` for the embedded default case (``None``, or a CaseConfig read from it),
    ``{"source": "<dict>", "source_sha256": hash of its JSON}`` for a dict given in Python.
    ``where``: a path, None, a dict or a CaseConfig (its ``source``)."""
    if isinstance(where, CaseConfig):
        if where.source.startswith("<default"):
            return {"source": "embedded:B1"}
        if where.source.startswith("<"):
            return {"source": where.source, "source_sha256": hashlib.sha256(
                _io.json_bytes(where.as_dict(), sort_keys=True)).hexdigest()}
        where = Path(where.source)
    if where is None:
        return {"source": "embedded:B1"}
    if isinstance(where, dict):
        return {"source": "<dict>", "source_sha256": hashlib.sha256(
            _io.json_bytes(where, sort_keys=True)).hexdigest()}
    path = Path(os.path.abspath(where))
    try:
        digest = hashlib.sha256(path.read_bytes()).hexdigest() if path.is_file() else None
    except OSError:
        digest = None
    return {"source": str(path), "source_sha256": digest}


@contextmanager
def result_folder(out: str | Path, command: str, **info):
    """Write one command's result set into ``out`` (``_io.result_set``): checks the folder and
    creates the staging folder now, before any work; yields the staging folder, where the
    caller writes its files under their final names; on success the set (with its manifest:
    version, ``command``, ``info``, files) replaces ``out`` whole, on failure or interrupt
    ``out`` is left as it was. The reusable door for every command that writes files.
    ``info``'s ``source`` (``source_of``; default ``embedded:<command>``) and ``command``
    must match the set already in ``out``, if any: another command's or another source's set
    is refused before any work (exit 2 with an ``--out`` hint, ``_io.check_owner``), and
    what that set did not write (nested sets, a user's files) is kept."""
    info = {"source": f"embedded:{command}", **info}
    with _io.result_set(out, info={"homlimit_version": package_version(), "command": command,
                                   **info}, names=report.OUTPUT_NAMES) as staging:
        yield staging


def announce(config: CaseConfig):
    """Log what a user must know before reading the results: a case changed by --set, and
    the valid but implausible inputs (warnings, also in summary.json)."""
    if config.modified:
        log.info("case %s: %s", config.name, config.describe_changes())
    for w in config.warnings:
        log.warning("warning: %s", w)


# ----------------------------------------------------------------------------- other commands
def _check_budget(option: str, cases, size: float, max_triangles: int, scan: bool = True,
                  mesher: str = MESHER_DEFAULT):
    """ParameterError when the largest FE problem over ``cases`` at mesh ``size`` (with
    ``scan``, the impulse scan's parts too, from one course a up) on the ``mesher``'s mesh
    exceeds ``max_triangles`` (``budget``)."""
    n = max(budget.fe_triangles(c.wall.H, c.wall.b, c.wall.L, size,
                                (c.masonry.a / c.wall.b,) if scan else (), mesher=mesher)
            for c in cases)
    if n > max_triangles:
        raise ParameterError(
            f"{option} = {size!r} m gives about {n:.3g} triangles in the largest FE problem "
            f"(estimated before meshing; about {budget.memory_gib(n):.3g} GiB): out of range: "
            f"allowed at most --max-triangles = {max_triangles:,}; raise {option} or, on a "
            "machine with the memory, --max-triangles")


def table1_records(fe: bool = False, mesh_size: float = 0.25, heights: int = 6,
                   tests: list[str] | None = None, facade: str = FACADE_DEFAULT,
                   max_triangles: int = budget.DEFAULT_MAX_TRIANGLES, fe_results=None,
                   mesher: str = MESHER_DEFAULT) -> list[dict]:
    """Table 1 reproduced (``paper.table1_rows``), optionally with the FE body's columns
    lam_fe, vnorm_fe, vg_fe, tanpsi_fe, tanpsi_fe_edges, mechanism_fe, multiplier_fe,
    critical_at_fe, hinge_ratio_fe (the critical height of the FE scan, ``fe_result``, from
    ``heights`` starting heights). ``tests``: a subset of the test names (B1 ... C6).
    ``max_triangles``: the problem-size budget of the FE meshes (``budget``), checked before
    any work; ``mesher``: the FE meshes (``problems.MESHERS``).
    ``fe_results(cases, mesh_size, facade, heights, options, mesher)``: the FE path of the
    walls, one ``FEResult`` each (default: ``fe_result`` wall after wall here;
    ``engine.Engine.fe_results`` runs every height as a Dask task)."""
    check_range("mesh_size", mesh_size, 0.0, 9.0, lo_open=True, unit="m")
    check_range("heights", heights, 2, 200)
    check_choice("facade", facade, FACADE_MODELS)
    check_choice("mesher", mesher, MESHERS)
    check_range("max_triangles", max_triangles, 100, 1e8)
    cases = {t.test: t.case for t in table1()}
    for t in tests or ():
        check_choice("test", t, tuple(cases))
    if fe:
        _check_budget("--mesh-size", [c for t, c in cases.items() if not tests or t in tests],
                      mesh_size, max_triangles, mesher=mesher)
    timings: dict[str, float] = {}
    with stage(timings, "closed forms for Table 1"):
        rows = [r for r in table1_rows() if not tests or r["test"] in tests]
    walls = [cases[row["test"]] for row in rows] if fe else []
    results = []
    if walls:
        with stage(timings, "FE body", f"{len(walls)} walls"):
            if fe_results is None:
                results = [fe_result(case, mesh_size, facade, solver_options(),
                                     heights=heights, mesher=mesher) for case in walls]
            else:
                results = fe_results(walls, mesh_size, facade, heights, solver_options(),
                                     mesher)
    for row, res in zip(rows, results):
        crit = res.critical
        if crit is None:
            raise ParameterError(f"test = {row['test']!r}: no analysed height gave a v̄_g "
                                 "(see the scan's vg_method)")
        row.update({"lam_fe": crit.lam, "vnorm_fe": crit.vnorm, "vg_fe": crit.vg,
                    "tanpsi_fe": crit.tanpsi, "tanpsi_fe_edges": crit.tanpsi_edges,
                    "mechanism_fe": crit.kind, "multiplier_fe": crit.multiplier,
                    "critical_at_fe": res.critical_at, "hinge_ratio_fe": crit.hinge_ratio})
    return rows


def table1_blocks_records(tests: list[str] | None = None, step: int = 1,
                          facade: str = "through", non_associative_check: bool = False
                          ) -> tuple[list[dict], dict]:
    """Table 1 with the rigid-block column (``blocks.table1_blocks``): rows and the ratios
    B4/B1, B5/B2, B6/B3 of v̄_g/√(gb) of the DEM, I, II and the blocks."""
    from ..blocks import table1_blocks
    from ..blocks.geometry import FACADE_BONDS

    check_range("step", step, 1, 1000)
    check_choice("facade", facade, FACADE_BONDS)
    names = [t.test for t in table1()]
    for t in tests or ():
        check_choice("test", t, names)
    return table1_blocks(step, facade, non_associative_check, solver_options(), tests=tests)


def figure2_curves(rho=None) -> dict:
    """The data of the paper's Figure 2: critical v̄_g/√(gb) and critical λ of mechanisms I
    and II against ρ = l/s (one vectorised call per mechanism), one panel per β of Table 1
    (0.4: b = 0.5 m, 0.8: b = 0.25 m; c = 0.2 m, H = 9 m, L = 6 m), one curve per
    α² ∈ {0.4, 0.6, 0.8}; mechanism II limited to λ <= H/b and λ tan ψ <= L/b; Table 1's DEM
    results as points. All numbers dimensionless.

    Returns {"rho": [...], "alpha2": [...], "panels": [{"beta", "b", "curves": [{"alpha2",
    "lam_I", "vnorm_I", "lam_II", "vnorm_II"}], "dem": [{"test", "rho", "alpha2", "lam",
    "vnorm"}]}]}.
    """
    rho = np.linspace(1.0, 20.0, 96) if rho is None else np.asarray(rho, float)
    alpha2 = np.array([0.4, 0.6, 0.8])
    H, L, c = 9.0, 6.0, 0.2
    dem = table1()
    panels = []
    for beta in (0.4, 0.8):
        b = c / beta
        R, A2 = np.meshgrid(rho, alpha2)  # (3, n)
        lam_I, v_I = mech.critical_I(R, np.sqrt(A2), beta, H / b)
        lam_II, v_II = mech.critical_II(R, np.sqrt(A2), mech.lam_max_II(H / b, L / b,
                                                                         np.sqrt(A2)))
        panels.append({
            "beta": beta, "b": b,
            "curves": [{"alpha2": float(a2), "lam_I": lam_I[k], "vnorm_I": v_I[k],
                        "lam_II": lam_II[k], "vnorm_II": v_II[k]}
                       for k, a2 in enumerate(alpha2)],
            "dem": [{"test": t.test, "rho": t.case.rho, "alpha2": t.case.alpha ** 2,
                     "lam": t.lam_v, "vnorm": t.vg_norm}
                    for t in dem if abs(t.case.beta - beta) < 1e-9]})
    return {"rho": rho, "alpha2": alpha2, "panels": panels}


def crack_study_records(mesh_size: float = 0.5, finer: float | None = 0.25, quick: bool = False,
                        c_over_a=None, frictions=None, facades=None,
                        max_triangles: int = budget.DEFAULT_MAX_TRIANGLES, map=map,
                        mesher: str = MESHER_DEFAULT) -> list[dict]:
    """The crack-angle study over a grid of c/a and f (``studies.crack_angle_study``): each
    grid argument left None takes the study's default. ``max_triangles``: the problem-size
    budget of its meshes (``budget``), checked before any work; ``map``: how the grid points
    are evaluated (``crack_angle_study``); ``mesher``: ``problems.MESHERS``."""
    from .studies import STUDY_WALL, crack_angle_study

    w = STUDY_WALL
    check_range("mesh_size", mesh_size, 0.0, min(w.H, w.b + w.L), lo_open=True, unit="m")
    if finer is not None:
        check_range("finer", finer, 0.0, mesh_size, lo_open=True, hi_open=True, unit="m")
    check_range("max_triangles", max_triangles, 100, 1e8)
    check_choice("mesher", mesher, MESHERS)
    for name, values in (("c_over_a", c_over_a), ("f", frictions)):
        for v in values or ():
            check_range(name, v, 0.0, 100.0, lo_open=True)
    finest = finer if finer is not None and not quick else mesh_size
    _check_budget("--finer" if finest != mesh_size else "--mesh-size", [Case(w)], finest,
                  max_triangles, scan=False, mesher=mesher)
    for fac in facades or ():
        check_choice("facade", fac, FACADE_MODELS)
    grid = {k: tuple(v) for k, v in (("c_over_a", c_over_a), ("frictions", frictions),
                                     ("facades", facades)) if v}
    return crack_angle_study(mesh_size=mesh_size, finer=finer, quick=quick,
                             options=solver_options(), map=map, mesher=mesher, **grid)


def mesh_case(config: CaseConfig, out: Path) -> dict:
    """Mesh the case's T-section only; write mesh.vtu and mesh.png as one result set in
    ``out`` (the mesh checks and the triangle budget first, ``config.check_mesh``); return
    counts and files."""
    from ..fe.mesh import from_skfem
    from . import plots

    check_mesh(config)
    with result_folder(out, "mesh", case=config.name, **source_of(config)) as staging:
        m = from_skfem(models.whole_problem(config).mesh)
        _, tri, region, names = plots.triangle_regions(m)
        report.write(staging / "mesh.vtu", m)
        plots.plot_mesh(staging / "mesh.png", m, title=f"case {config.name}")
    files = {"mesh_vtu": out / "mesh.vtu", "mesh_png": out / "mesh.png"}
    return {"case": config.name, "n_triangles": int(len(tri)), "n_nodes": int(len(m.points)),
            "regions": {n: int(np.count_nonzero(region == k)) for k, n in enumerate(names)},
            "mesh": {"size": config.mesh.size, "mesher": config.mesh.mesher},
            "files": {k: str(v) for k, v in files.items()}}


# ----------------------------------------------------------------------------- pulse spectra
def pulse_records(config: CaseConfig) -> tuple[list, FERocker | None]:
    """The overturning spectra of ``[pulse]`` (``homlimit.dynamics``): every pulse kind ×
    mechanism × polarity × period, and the critical scale of ``[pulse] record`` if given.
    Each chosen mechanism (in the registry's order) comes from its ``alone`` (``registry``):
    the FE body from the FE cache, or the FE path (as ``run``, without the static bound),
    which is then cached (``models.fe_rocker``). Returns the spectrum points and the FE
    rocker (None unless chosen), which says whether it came from the cache."""
    from ..dynamics import RecordPulse, overturning_spectrum
    from ..dynamics.spectra import record_thresholds

    case, pc = config.case, config.pulse
    w = case.wall
    record = None
    if pc.record:
        base = Path(config.source).parent if Path(config.source).is_file() else Path.cwd()
        path = base / pc.record
        try:
            if path.is_file() and path.stat().st_size > MAX_RECORD_BYTES:
                raise ParameterError(f"[pulse] record = {pc.record!r} has "
                                     f"{path.stat().st_size:,} bytes: allowed at most "
                                     f"{MAX_RECORD_BYTES:,}")
            record = RecordPulse.from_csv(path)
        except UnicodeDecodeError as e:     # dynamics reads it as UTF-8 text
            raise ParameterError(f"[pulse] record = {pc.record!r} is not UTF-8 text (byte "
                                 f"0x{e.object[e.start]:02x} at offset {e.start}): allowed a "
                                 "two-column CSV t [s], a_g [m/s^2]") from None
        except ParameterError as e:         # name the key as well as the record
            raise ParameterError(f"[pulse] record = {pc.record!r}: {e}") from None
        for note in record.warnings:
            log.warning("warning: [pulse] record = %r: %s", pc.record, note)
    chosen = {e.name: _alone(e, config) for e in registry.mechanisms()
              if e.name in pc.mechanisms}
    rockers = {name: registry.mechanism(name).rocker(case, m, gravity_I=pc.gravity_I,
                                                     restitution=pc.restitution)
               for name, m in chosen.items()}
    kw = dict(b=w.b, g=w.g, rtol=pc.rtol, scan_ratio=pc.scan_ratio)
    points = []
    for kind in pc.kinds:
        with stage({}, "overturning spectrum", f"{kind}, {len(rockers)} mechanisms"):
            points += overturning_spectrum(
                rockers, kind, pc.periods, polarities=pc.polarities,
                pulse_options={"gamma": pc.gamma, "nu": pc.nu} if kind == "mp" else None, **kw)
    if record is not None:
        with stage({}, "critical scale of the record", pc.record):
            points += record_thresholds(rockers, record, **kw)
    _warn_implausible(points)
    return points, next((m for m in chosen.values() if isinstance(m, FERocker)), None)


def _alone(entry: registry.Mechanism, config: CaseConfig):
    """The mechanism ``entry`` of the case for the pulse spectra: its ``alone`` (the FE
    path's through the FE cache), else what its model gives on the case."""
    if entry.alone is not None:
        return entry.alone(config)
    result = Result(config=config)
    registry.model(entry.model).run(config, result)
    return result.mechanisms[entry.name]


def _warn_implausible(points) -> None:
    """One warning for the critical pulses beyond any recorded ground motion (kept in the
    results, marked ``implausible``)."""
    from ..dynamics.spectra import PLAUSIBLE_PGA_G, PLAUSIBLE_PGV

    bad = [p for p in points if p.implausible]
    if not bad:
        return
    shown = "; ".join(f"{p.pulse} {p.polarity:+d} T_p = {p.period:g} s, {p.mechanism}: "
                      f"pga {p.pga_g:.3g} g, pgv {p.pgv:.3g} m/s" for p in bad[:3])
    more = f"; and {len(bad) - 3} more" if len(bad) > 3 else ""
    log.warning("warning: %d of %d critical pulses need pga > %g g or pgv > %g m/s, beyond "
                "recorded ground motion (kept, column implausible = true): %s%s", len(bad),
                len(points), PLAUSIBLE_PGA_G, PLAUSIBLE_PGV, shown, more)


# ----------------------------------------------------------------------------- the outputs
def _outputs(result: Result) -> dict[str, tuple[str, object]]:
    """Key → (file name, what ``report.write`` writes there) for the files the case asks for:
    each model's (``registry.Model.files``), in the registry's order."""
    out: dict[str, tuple[str, object]] = {}
    for model in registry.models():
        if model.files is not None:
            out.update(model.files(result))
    return out


def _write(result: Result, staging: Path, out: Path) -> dict[str, Path]:
    """Write every output of ``result`` into ``staging`` (a ``result_folder``), under the names
    they will have in ``out``; summary.json last, listing them all. Returns key → final path."""
    files = {}
    with stage(result.timings, "writing files"):
        for key, (name, data) in _outputs(result).items():
            report.write(staging / name, data)
            files[key] = out / name
        if result.dem_run is not None:
            from .dem_stage import write_files

            files.update(write_files(result.dem_run, result.config.output, staging, out,
                                     f"case {result.name}"))
        if result.config.output.json:
            files["summary_json"] = out / "summary.json"
            result.files = files
            report.write(staging / "summary.json", result.to_dict())
    return files


def check_results(result: Result):
    """Every result a run reports is a finite number: ResultError naming the mechanism and
    the quantity otherwise (never a summary with ``null`` where a number belongs). Quantities
    that do not apply (mechanism I's tan ψ, the crack of a distributed mechanism, a scan
    height without a block, whose ``vg_method`` says why) are exempt."""
    for name, m in result.mechanisms.items():
        entry = registry.mechanism(name)
        for q in entry.checked:
            if not finite(getattr(m, q)):
                raise ResultError(f"mechanism {name}: {q} = {getattr(m, q)!r} is not a finite "
                                  f"number for this case ({_what(q)}); nothing written")
        for q in entry.body_checked:
            if not finite(getattr(m.body, q)):
                raise ResultError(f"mechanism {name}: body {q} = {getattr(m.body, q)!r} is not "
                                  "a finite number for this case; nothing written")
    for model in registry.models():
        if model.check is not None:
            model.check(result)
    if result.critical() is None:
        raise ResultError("no mechanism gave a collapse velocity vg; nothing written")


def _what(q: str) -> str:
    unit = report.UNITS.get(q, "")
    return {"lam": "critical slenderness λ = h/b", "h": "height of the failing part",
            "vg": "collapse ground velocity v̄_g", "vnorm": "v̄_g/√(gb)",
            "theta_m": "rotation at the peak of the restoring work",
            "W_m": "peak restoring work"}[q] + (f" [{unit}]" if unit not in ("", "-") else "")


def compute(config: CaseConfig) -> Result:
    """The models the case asks for (``registry.models``: the closed forms, the FE path, the
    rigid blocks, ...), in the registry's order, then ``conclude``; writes nothing."""
    result = Result(config=config, dem=dem_row(config.case))
    for model in registry.models():
        if model.enabled(config):
            model.run(config, result)
    return conclude(result)


def conclude(result: Result) -> Result:
    """The last step of every evaluated case, ``run``'s and a sweep's batch alike: every
    result checked to be a finite number (``check_results``: ResultError naming the
    mechanism and the quantity), then, with ``[analysis] hinge_check``, the hinge check of
    each mechanism (``_hinges``). Returns ``result``, its ``hinges`` filled in."""
    check_results(result)
    if result.mechanisms and result.config.analysis.hinge_check:
        with stage(result.timings, "hinge check", "the shortest pulse the hinge holds"):
            result.hinges = _hinges(result)
    return result


def _hinges(result: Result) -> dict:
    """Per mechanism with a rocker (``registry``), the shortest rectangular pulse of a_g = f g
    (the most the bed joint under the hinge holds) that still overturns it
    (``dynamics.holding_pulse``): the ideal impulse needs |P_x/P_z| (``hinge_ratio``), more
    than f for the Table 1 walls."""
    case, out = result.case, {}
    for name, m in result.mechanisms.items():
        rocker = registry.mechanism(name).rocker
        if rocker is not None:
            out[name] = holding_pulse(rocker(case, m), case.masonry.f)
    return out


def run(path_or_dict: str | Path | dict | CaseConfig | None = None, *,
        out: str | Path | None = None, write: bool = True,
        overrides: list[str] | dict | None = None, command: str = "run") -> Result:
    """Run the case: validate, closed forms, FE (if asked), write files to ``out``.

    ``path_or_dict``: a TOML case file, a dict of the same shape, a CaseConfig, or None for the
    embedded default (Table 1's B1); ``overrides``: "section.key=value" strings or a
    {"section.key": value} dict applied before validation. ``out`` defaults to [output] dir or
    homlimit-out/NAME/ (``output_dir``); the files are one result set (``result_folder``):
    the folder is checked before any computation and replaced whole at the end; a folder
    holding the set of another source or another command (``command``, recorded in the
    manifest: "run", or "demo" for the command line's demo) is refused.
    Raises ConfigError/ParameterError for bad input and an unusable output folder (before any
    computation), SolverError when a conic program does not end optimal, ResultError when a
    result is not a finite number, OutputError when the files cannot be written (the previous
    set is then kept).
    """
    if isinstance(path_or_dict, CaseConfig):
        if overrides:
            raise ParameterError("overrides = given with a CaseConfig is out of range: allowed "
                                 "only with a path, a dict or None")
        config = path_or_dict
    else:
        config = load_case(path_or_dict, overrides)
    announce(config)
    if not write:
        return compute(config)
    target = output_dir(config, out)
    with result_folder(target, command, case=config.name, **source_of(config)) as staging:
        result = compute(config)
        result.files = _write(result, staging, target)
    if result.fe is not None:       # for `homlimit pulse` on this case (``fe_rocker``)
        write_fe_cache(config, result.fe)
    return result
