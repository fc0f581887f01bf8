"""The whole analysis of one wall, shared by the three doors.

``homlimit run CASE.toml``, ``python -m homlimit run CASE.toml`` and ``homlimit.run(CASE)`` all
call ``run`` below, which

1. validates the case (``config``), before any computation;
2. evaluates the closed-form mechanisms I (eqs 8–14) and II (eqs 16–20) at their critical
   slenderness, and their v̄_g(λ) curves (``closed_form.mechanisms``);
3. when ``[analysis] fe`` is on, runs the finite-element path (``mechanism.analysis``): the
   impulse scan over collapse heights, the whole wall's mechanism and crack, and its static
   lower bound on the same mesh;
4. writes the result files (``report.write``), each whole or not at all.

Progress goes to the ``logging`` module (the command line shows it); the other commands' work
is here too: ``table1_records``, ``crack_study_records``, ``mesh_case``.
"""

from __future__ import annotations

import functools
import logging
import math
import time
from contextlib import contextmanager
from dataclasses import dataclass, field
from importlib.metadata import PackageNotFoundError, version
from pathlib import Path
from typing import Any

import numpy as np

from ..closed_form import mechanisms as mech
from ..closed_form.paper import DemResult, dem_row, table1, table1_rows
from ..errors import ParameterError, check_choice, check_range
from ..mechanism.analysis import FEResult, fe_result, scan_lams
from ..params import FACADE_MODELS, Case
from . import report
from .config import CaseConfig, load_case

__all__ = ["Result", "crack_study_records", "mesh_case", "output_dir", "package_version",
           "pulse_records", "run", "table1_records"]

log = logging.getLogger(__name__)


@functools.cache  # importlib.metadata reads the install's files: ~5 ms a call
def package_version() -> str:
    """The installed package's version (``importlib.metadata``)."""
    try:
        return version("homlimit")
    except PackageNotFoundError:  # running from a source tree that was never installed
        return "0+unknown"


@contextmanager
def _stage(timings: dict[str, float], name: str, detail: str = ""):
    """Log a stage's start and end and add its wall time to ``timings``."""
    log.info("%s%s ...", name, f" ({detail})" if detail else "")
    t0 = time.perf_counter()
    yield
    dt = time.perf_counter() - t0
    timings[name] = timings.get(name, 0.0) + dt
    log.info("%s done in %.2f s", name, dt)


@dataclass
class Result:
    """Everything one ``run`` produced.

    mechanisms: name → mechanism ("I", "II": ``closed_form.mechanisms.MechanismResult``;
    "FE": the critical ``mechanism.analysis.FEMechanism``), each with ``label``, ``lam``,
    ``h``, ``vg``, ``vnorm`` and ``as_dict()``; fe: the whole FE path (``FEResult``);
    curves: λ and v̄_g(λ) of the closed forms; dem: the paper's Table 1 row of this wall.
    """

    config: CaseConfig
    mechanisms: dict[str, Any] = field(default_factory=dict)
    curves: dict = field(default_factory=dict)
    fe: FEResult | None = None
    dem: DemResult | None = None
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
        """The JSON summary: every input, every result, the package version."""
        c = self.case
        return {
            "homlimit_version": package_version(),
            "case": self.name,
            "source": self.config.source,
            "inputs": self.config.as_dict(),
            "derived": {"rho": c.rho, "alpha": c.alpha, "alpha2": c.alpha ** 2, "beta": c.beta,
                        "lam_max": c.wall.lam_max, "f": c.masonry.f,
                        "c_over_a": c.masonry.c / c.masonry.a},
            "mechanisms": {k: m.as_dict() for k, m in self.mechanisms.items()},
            "fe": None if self.fe is None else self.fe.as_dict(),
            "critical": self.critical(),
            "dem_table1": None if self.dem is None else self.dem.as_dict(),
            "files": {k: str(v) for k, v in self.files.items()},
            "timings_s": self.timings,
        }

    def summary(self) -> str:
        """The terminal summary (``report.summary_text``)."""
        return report.summary_text(self)


def output_dir(config: CaseConfig, out: str | Path | None = None) -> Path:
    """--out, else [output] dir, else homlimit-out/<case name>/ (relative to the cwd)."""
    if out:
        return Path(out)
    if config.output.dir:
        return Path(config.output.dir)
    return Path("homlimit-out") / config.name


def _solver_options(tol: float | None = None):
    """Solver settings of a run: the measured defaults, the solver log when debugging."""
    from ..fe.solver import SolverOptions

    return SolverOptions(tol=tol or None, verbose=log.isEnabledFor(logging.DEBUG))


# ----------------------------------------------------------------------------- the analyses
def _closed_form(config: CaseConfig) -> tuple[dict, dict]:
    """Mechanisms I and II at their critical λ, and v̄_g(λ) over 0 < λ <= H/b."""
    case, an = config.case, config.analysis
    m1 = mech.mechanism_I(case)
    m2 = mech.mechanism_II(case, tanpsi=an.tanpsi or None)  # 0: eq. 16's √(cf/a)
    w = case.wall
    lam = np.linspace(w.lam_max / an.lam_points, w.lam_max, an.lam_points)
    scale = math.sqrt(w.g * w.b)
    lam2 = lam[lam <= m2.lam_max * (1 + 1e-12)]
    curves = {"lam_I": lam, "vg_I": mech.vnorm_I(lam, case.rho, case.alpha, case.beta) * scale,
              "lam_II": lam2, "vg_II": mech.vnorm_II(lam2, case.rho, m2.tanpsi) * scale}
    return {"I": m1, "II": m2}, curves


def _whole_problem(config: CaseConfig):
    """The whole wall's T-section problem (``problems.t_section``, base at z = 0)."""
    from ..fe.problems import t_section

    return t_section(config.case, facade=config.analysis.facade, h=config.mesh.size)


# ----------------------------------------------------------------------------- other commands
def table1_records(fe: bool = False, mesh_size: float = 0.25, heights: int = 10,
                   tests: list[str] | None = None, fe_results=None) -> list[dict]:
    """Table 1 reproduced (``paper.table1_rows``), optionally with the FE body's columns
    lam_fe, vnorm_fe, vg_fe, tanpsi_fe, tanpsi_fe_edges, mechanism_fe, multiplier_fe (the
    critical height of an FE scan over ``heights`` collapse heights, ``analysis.scan_lams``).
    ``tests``: a subset of the test names (B1 ... C6); ``fe_results(cases, lams, mesh_size,
    options)``: the FE path of the walls, one ``FEResult`` each (default: ``fe_result`` wall
    after wall here; ``engine.Engine.fe_results`` runs every height as a Dask task)."""
    check_range("mesh_size", mesh_size, 0.0, lo_open=True, unit="m")
    check_range("heights", heights, 1, 200)
    cases = {t.test: t.case for t in table1()}
    for t in tests or ():
        check_choice("test", t, tuple(cases))
    chosen = [c for t, c in cases.items() if not tests or t in tests]
    h_min = min(min(2.0 * c.wall.b, c.wall.H) for c in chosen)
    if fe and heights > 1 and mesh_size > h_min:
        raise ParameterError(f"mesh_size = {mesh_size!r} m is out of range: allowed "
                             f"mesh_size <= {h_min:g} m, the smallest part of the FE scan "
                             "(λ = 2, i.e. 2b)")
    timings: dict[str, float] = {}
    with _stage(timings, "closed forms for Table 1"):
        rows = [r for r in table1_rows() if not tests or r["test"] in tests]
    walls = [cases[row["test"]] for row in rows] if fe else []
    lams = [scan_lams(case, int(heights)) for case in walls]
    results = []
    if walls:
        with _stage(timings, "FE body", f"{len(walls)} walls"):
            if fe_results is None:
                results = [fe_result(case, lam, mesh_size, options=_solver_options())
                           for case, lam in zip(walls, lams)]
            else:
                results = fe_results(walls, lams, mesh_size, _solver_options())
    for row, res in zip(rows, results):
        crit = res.critical
        if crit is None:
            raise ParameterError(f"test = {row['test']!r}: no analysed height gave a v̄_g "
                                 "(see the scan's vg_method)")
        row.update({"lam_fe": crit.lam, "vnorm_fe": crit.vnorm, "vg_fe": crit.vg,
                    "tanpsi_fe": crit.tanpsi, "tanpsi_fe_edges": crit.tanpsi_edges,
                    "mechanism_fe": crit.kind, "multiplier_fe": crit.multiplier})
    return rows


def crack_study_records(mesh_size: float = 0.5, finer: float | None = 0.25, quick: bool = False,
                        c_over_a=None, frictions=None, facades=None, map=map) -> list[dict]:
    """The crack-angle study over a grid of c/a and f (``studies.crack_angle_study``): each
    grid argument left None takes the study's default; ``map``: how the grid points are
    evaluated (``crack_angle_study``)."""
    from .studies import crack_angle_study

    check_range("mesh_size", mesh_size, 0.0, lo_open=True, unit="m")
    if finer is not None:
        check_range("finer", finer, 0.0, mesh_size, lo_open=True, hi_open=True, unit="m")
    for name, values in (("c_over_a", c_over_a), ("f", frictions)):
        for v in values or ():
            check_range(name, v, 0.0, lo_open=True)
    for fac in facades or ():
        check_choice("facade", fac, FACADE_MODELS)
    grid = {k: tuple(v) for k, v in (("c_over_a", c_over_a), ("frictions", frictions),
                                     ("facades", facades)) if v}
    return crack_angle_study(mesh_size=mesh_size, finer=finer, quick=quick,
                             options=_solver_options(), map=map, **grid)


def mesh_case(config: CaseConfig, out: Path) -> dict:
    """Mesh the case's T-section only; write mesh.vtu and mesh.png; return counts and files."""
    from ..fe.mesh import from_skfem
    from . import plots

    m = from_skfem(_whole_problem(config).mesh)
    _, tri, region, names = plots.triangle_regions(m)
    files = {"mesh_vtu": report.write(out / "mesh.vtu", m),
             "mesh_png": plots.plot_mesh(out / "mesh.png", m, title=f"case {config.name}")}
    return {"case": config.name, "n_triangles": int(len(tri)), "n_nodes": int(len(m.points)),
            "regions": {n: int(np.count_nonzero(region == k)) for k, n in enumerate(names)},
            "mesh": {"size": config.mesh.size},
            "files": {k: str(v) for k, v in files.items()}}


def pulse_records(config: CaseConfig) -> tuple[list, FEResult | None]:
    """The overturning spectra of ``[pulse]`` (``homlimit.dynamics``): every pulse kind ×
    mechanism × polarity × period, and the critical scale of ``[pulse] record`` if given.
    Mechanism "FE" runs the FE path first (as ``run``, without the static bound). Returns the
    spectrum points and the FE result (None without "FE")."""
    from ..dynamics import RecordPulse, case_rockers, overturning_spectrum
    from ..dynamics.spectra import record_thresholds

    case, pc, an = config.case, config.pulse, config.analysis
    w = case.wall
    record = None
    if pc.record:
        base = Path(config.source).parent if Path(config.source).is_file() else Path.cwd()
        record = RecordPulse.from_csv(base / pc.record)
    fe = None
    if "FE" in pc.mechanisms:
        with _stage({}, "FE path for the FE rocker"):
            fe = fe_result(case, scan_lams(case, an.heights), config.mesh.size, an.facade,
                           _solver_options(an.tol))
        if fe.critical is None:
            raise ParameterError("[pulse] mechanisms = 'FE': the FE scan found no mechanism "
                                 "with a v̄_g (see fe_scan's vg_method)")
    rockers = case_rockers(case, [m for m in pc.mechanisms if m != "FE"],
                           fe_body=None if fe is None else fe.critical,
                           gravity_I=pc.gravity_I, restitution=pc.restitution)
    kw = dict(b=w.b, g=w.g, rtol=pc.rtol, scan_ratio=pc.scan_ratio)
    points = []
    for kind in pc.kinds:
        with _stage({}, "overturning spectrum", f"{kind}, {len(rockers)} mechanisms"):
            points += overturning_spectrum(
                rockers, kind, pc.periods, polarities=pc.polarities,
                pulse_options={"gamma": pc.gamma, "nu": pc.nu} if kind == "mp" else None, **kw)
    if record is not None:
        with _stage({}, "critical scale of the record", pc.record):
            points += record_thresholds(rockers, record, **kw)
    return points, fe


# ----------------------------------------------------------------------------- the outputs
def _outputs(result: Result) -> dict[str, tuple[str, object]]:
    """Key → (file name, what ``report.write`` writes there) for the files the case asks for."""
    from . import plots

    cfg, art, title = result.config.output, result.fe, f"case {result.name}"
    out: dict[str, tuple[str, object]] = {}
    if cfg.png:
        if "I" in result.mechanisms and "II" in result.mechanisms:
            out["vg_lambda_png"] = ("vg_lambda.png", lambda p: plots.plot_vg_lambda(
                p, result.curves, result.mechanisms, fe=art, dem=result.dem, title=title,
                b=result.case.wall.b))
        if art is not None:
            from ..fe.mesh import from_skfem

            out["mesh_png"] = ("mesh.png", lambda p: plots.plot_mesh(
                p, from_skfem(art.whole.problem.mesh), title=title))
            out["mechanism_png"] = ("mechanism.png", lambda p: plots.plot_mechanism(
                p, art.whole.drawing(), result.case, title=title))
            if art.static is not None:
                out["stress_png"] = ("stress.png", lambda p: plots.plot_stress(
                    p, art.static, title=f"{title}: lower-bound stress field, λ⁻ = "
                                         f"{art.static.multiplier:.4g}"))
    if art is not None:
        out["fe_scan_csv"] = ("fe_scan.csv", [m.record() for m in art.scan])
        if cfg.vtu:
            out["mechanism_vtu"] = ("mechanism.vtu", report.mechanism_mesh(art))
    return out


def _write(result: Result, out: Path) -> dict[str, Path]:
    """Write every output of ``result`` into ``out``; summary.json last, listing them all."""
    files = {}
    with _stage(result.timings, "writing files"):
        for key, (name, data) in _outputs(result).items():
            files[key] = report.write(out / name, data)
        if result.config.output.json:
            files["summary_json"] = out / "summary.json"
            result.files = files
            report.write(files["summary_json"], result.to_dict())
    return files


def run(path_or_dict: str | Path | dict | CaseConfig | None = None, *,
        out: str | Path | None = None, write: bool = True,
        overrides: list[str] | dict | None = None) -> Result:
    """Run the case: validate, closed forms, FE (if asked), write files to ``out``.

    ``path_or_dict``: a TOML case file, a dict of the same shape, a CaseConfig, or None for the
    embedded default (Table 1's B1); ``overrides``: "section.key=value" strings or a
    {"section.key": value} dict applied before validation. ``out`` defaults to [output] dir or
    homlimit-out/<name>/.
    Raises ConfigError/ParameterError for bad input (before any computation), SolverError
    when a conic program does not end optimal.
    """
    if isinstance(path_or_dict, CaseConfig):
        if overrides:
            raise ParameterError("overrides = given with a CaseConfig is out of range: allowed "
                                 "only with a path, a dict or None")
        config = path_or_dict
    else:
        config = load_case(path_or_dict, overrides)
    case, an = config.case, config.analysis
    result = Result(config=config, dem=dem_row(case))
    if an.closed_form:
        with _stage(result.timings, "closed-form mechanisms I and II"):
            mechanisms, result.curves = _closed_form(config)
            result.mechanisms.update(mechanisms)
    if an.fe:
        whole = _whole_problem(config)
        lams = scan_lams(case, an.heights)
        with _stage(result.timings, "FE analyses",
                    f"{len(lams)} collapse heights, whole wall {whole.n_triangles} triangles"
                    f"{', static bound' if an.static else ''}"):
            result.fe = fe_result(case, lams, config.mesh.size, an.facade,
                                  _solver_options(an.tol), whole=whole, static=an.static)
        if result.fe.critical is not None:
            result.mechanisms["FE"] = result.fe.critical
    if write:
        result.files = _write(result, output_dir(config, out))
    return result
