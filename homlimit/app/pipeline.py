"""The whole analysis of one wall, shared by the three doors.

``homlimit run CASE.toml``, ``python -m homlimit run CASE.toml`` and ``homlimit.run(CASE)`` all
call ``run`` below, which

1. validates the case (``homlimit.app.config``), before any computation;
2. evaluates the closed-form mechanisms I (eqs 8–14) and II (eqs 16–20) at their critical
   slenderness, and their v̄_g(λ) curves;
3. when ``[analysis] fe`` is on, meshes the T-section, solves the finite-element kinematic
   problem, measures the crack against √(cf/a) and f, and turns the FE body into a collapse
   ground velocity (eq. 7) over a scan of collapse heights;
4. writes the result files (summary.json, .vtu, PNG), each whole or not at all.

The other commands' work is here too: ``table1_records``, ``crack_study_records``,
``mesh_case``. Each analysis module is reached through one private function, the only seam
between the user-facing layer and the analyses:

    _closed_form        homlimit.closed_form.mechanisms (mechanism_I, mechanism_II, vnorm_I, vnorm_II)
    _problem, _mesh     homlimit.fe.problems.t_section, homlimit.fe.mesh.from_skfem
    _fe                 homlimit.mechanism.fe_impulse.h_scan (FE mechanism, crack, v̄_g per height)
    _whole_wall_fields  homlimit.mechanism.rigidfit, homlimit.fe.mesh (fields of the whole wall's solution)
    _fe_table_columns   homlimit.mechanism.fe_impulse.fe_mechanism (Table 1's FE columns)
    _crack_study        homlimit.app.studies.crack_angle_study
"""

from __future__ import annotations

import csv
import math
import sys
import time
from contextlib import contextmanager
from dataclasses import dataclass, field
from importlib import resources
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import MeshError, ParameterError
from ..params import Case
from .config import CaseConfig, load_case

__all__ = ["Progress", "Result", "crack_study_records", "dem_reference", "mesh_case",
           "output_dir", "run", "table1_records"]


class Progress:
    """Stage-by-stage progress on stderr (silent when disabled, e.g. under --json)."""

    def __init__(self, enabled: bool = False, stream=None):
        self.enabled = enabled
        self.stream = stream if stream is not None else sys.stderr
        self.timings: dict[str, float] = {}

    def say(self, msg: str):
        if self.enabled:
            print(f"[homlimit] {msg}", file=self.stream, flush=True)

    @contextmanager
    def stage(self, name: str, detail: str = ""):
        """Time a stage; print its start and its end with the elapsed time."""
        self.say(f"{name}{' (' + detail + ')' if detail else ''} ...")
        t0 = time.perf_counter()
        yield
        dt = time.perf_counter() - t0
        self.timings[name] = self.timings.get(name, 0.0) + dt
        self.say(f"{name} done in {dt:.2f} s")

    def bar(self, items, label: str):
        """Iterate ``items`` with a one-line text progress bar."""
        items = list(items)
        n = len(items)
        tty = self.enabled and getattr(self.stream, "isatty", lambda: False)()
        cr, end = ("\r", "") if tty else ("", "\n")   # redraw one line on a terminal only
        for k, item in enumerate(items):
            if self.enabled:
                done = int(30 * k / max(n, 1))
                print(f"{cr}[homlimit] {label} [{'#' * done}{'.' * (30 - done)}] {k}/{n}",
                      end=end, file=self.stream, flush=True)
            yield item
        if self.enabled:
            print(f"{cr}[homlimit] {label} [{'#' * 30}] {n}/{n}", file=self.stream, flush=True)


@dataclass
class Result:
    """Everything one ``run`` produced: inputs, closed-form and FE results, files written."""

    config: CaseConfig
    mechanism_I: Any = None       # homlimit.closed_form.mechanisms.MechanismResult
    mechanism_II: Any = None
    curves: dict = field(default_factory=dict)   # λ and v̄_g(λ) of both mechanisms
    fe: dict | None = None
    dem: dict | None = None       # the paper's Table 1 DEM row when the case is one of its walls
    files: dict[str, Path] = field(default_factory=dict)
    timings: dict[str, float] = field(default_factory=dict)
    artifacts: dict = field(default_factory=dict, repr=False)  # meshes and drawing data

    @property
    def case(self) -> Case:
        return self.config.case

    @property
    def name(self) -> str:
        return self.config.name

    def critical(self) -> dict | None:
        """The governing mechanism: the lowest collapse velocity among those computed."""
        cands = [(m.vg, m.name) for m in (self.mechanism_I, self.mechanism_II) if m is not None]
        if self.fe and self.fe.get("vg") is not None:
            cands.append((self.fe["vg"], "FE"))
        if not cands:
            return None
        vg, name = min(cands)
        return {"mechanism": name, "vg": vg, "vnorm": vg / math.sqrt(self.case.wall.g *
                                                                   self.case.wall.b)}

    def to_dict(self) -> dict:
        """The JSON summary: every input, every result, the package version."""
        from .. import __version__

        c = self.case
        return {
            "homlimit_version": __version__,
            "case": self.name,
            "source": self.config.source,
            "inputs": self.config.as_dict(),
            "derived": {"rho": c.rho, "alpha": c.alpha, "alpha2": c.alpha ** 2, "beta": c.beta,
                        "lam_max": c.wall.lam_max, "f": c.masonry.f,
                        "c_over_a": c.masonry.c / c.masonry.a},
            "mechanism_I": None if self.mechanism_I is None else self.mechanism_I.as_dict(),
            "mechanism_II": None if self.mechanism_II is None else self.mechanism_II.as_dict(),
            "fe": self.fe,
            "critical": self.critical(),
            "dem_table1": self.dem,
            "files": {k: str(v) for k, v in self.files.items()},
            "timings_s": self.timings,
        }

    def summary(self) -> str:
        """A readable terminal table: each mechanism's λ, h, v̄_g, v̄_g/√(gb), beside the DEM."""
        from .report import format_table

        c = self.case
        rows = []
        for m in (self.mechanism_I, self.mechanism_II):
            if m is not None:
                label = ("I  detachment (eqs 10, 7)" if m.name == "I" else
                         f"II diagonal crack tan psi={m.tanpsi:.3f} (eqs 17-20)")
                rows.append([label, m.lam, m.h, m.vg, m.vnorm])
        if self.fe:
            rows.append([f"FE body, {self.fe.get('critical_mechanism', '?')} (eq. 7)",
                         self.fe.get("lam"), self.fe.get("h"), self.fe.get("vg"),
                         self.fe.get("vnorm")])
        if self.dem:
            rows.append(["DEM, paper's Table 1", self.dem["lambda_v"], self.dem["h_v"],
                         self.dem["vg"], self.dem["vg_norm"]])
        head = (f"case {self.name}: H={c.wall.H:g} m, L={c.wall.L:g} m, s={c.wall.s:g} m, "
                f"b={c.wall.b:g} m, l={c.wall.l:g} m; a={c.masonry.a:g} m, c={c.masonry.c:g} m, "
                f"f={c.masonry.f:g}\n"
                f"  rho=l/s={c.rho:.4g}  alpha^2=cf/a={c.alpha ** 2:.4g}  beta=c/b={c.beta:.4g}"
                f"  (eq. 11)")
        out = [head, "", format_table(["mechanism", "lambda=h/b", "h [m]", "vg [m/s]",
                                       "vg/sqrt(gb)"], rows)]
        if self.fe:
            out += ["", self._fe_lines()]
        crit = self.critical()
        if crit:
            out += ["", f"governing: {crit['mechanism']}, collapse ground velocity "
                        f"vg = {crit['vg']:.3f} m/s (vg/sqrt(gb) = {crit['vnorm']:.3f})"]
        if self.files:
            out += ["", "files:"] + [f"  {v}" for v in self.files.values()]
        return "\n".join(out)

    def _fe_lines(self) -> str:
        fe, c = self.fe, self.case

        def num(x, fmt=".3f"):
            return "–" if x is None or not math.isfinite(x) else format(x, fmt)

        lines = [f"FE, whole wall: {fe['n_triangles']} triangles, façade {fe['facade']}, "
                 f"collapse multiplier {num(fe['multiplier'], '.4g')} (acceleration / g)",
                 *([f"  bracket: static {num(fe['lower_bound'], '.4g')} <= multiplier <= "
                    f"kinematic {num(fe['multiplier'], '.4g')} (gap "
                    f"{100 * fe['bracket_rel_gap']:.1f} %, same mesh)"]
                   if fe.get("lower_bound") is not None else []),
                 f"  {fe['mechanism']} mechanism, hinge at x = {num(fe['hinge'][0], '.2f')} m, "
                 f"z = {num(fe['hinge'][1], '.2f')} m",
                 f"  crack: tan psi = {num(fe['tanpsi'])} ± {num(fe['tanpsi_uncertainty'])} "
                 f"(50 % line), edges {num(fe['tanpsi_edges'][0])} .. "
                 f"{num(fe['tanpsi_edges'][1])}",
                 f"         sqrt(cf/a) = {c.alpha:.3f} (eq. 16), f = {c.masonry.f:.3f}, "
                 f"c/a = {c.masonry.c / c.masonry.a:.3f}"]
        if fe.get("vg") is not None:
            lines += [f"  impulse: lowest vg over {len(fe['scan'])} collapse heights at "
                      f"h = {num(fe['h'], '.2f')} m", f"         ({fe['vg_method']})"]
        return "\n".join(lines)


def output_dir(config: CaseConfig, out: str | Path | None = None) -> Path:
    """--out, else [output] dir, else homlimit-out/<case name>/ (relative to the cwd)."""
    if out:
        return Path(out)
    if config.output.dir:
        return Path(config.output.dir)
    return Path("homlimit-out") / config.name


def dem_reference(case: Case) -> dict | None:
    """The paper's Table 1 DEM row whose wall and masonry match ``case`` (ρ = l/s), else None."""
    text = resources.files("homlimit").joinpath("data/table1_dem.csv").read_text("utf-8")
    rows = csv.DictReader(line for line in text.splitlines() if not line.startswith("#"))
    w, m = case.wall, case.masonry
    mine = (w.H, w.L, w.s, w.b, m.a, m.c, m.f, w.rho)
    for r in rows:
        theirs = tuple(float(r[k]) for k in ("H", "L", "s", "b", "a", "c", "f", "rho"))
        if np.allclose(mine, theirs, rtol=1e-9, atol=0):
            return {"test": r["test"]} | {k: float(r[k]) for k in
                                         ("h_v", "lambda_v", "vg", "vg_norm")}
    return None


# ----------------------------------------------------------------------------- the analyses
def _closed_form(config: CaseConfig) -> tuple[Any, Any, dict]:
    """Mechanisms I and II at their critical λ, and v̄_g(λ) over 0 < λ <= H/b (seam: mechanisms)."""
    from ..closed_form import mechanisms as mech

    case, an = config.case, config.analysis
    tanpsi = an.tanpsi or None  # 0 in the case file: eq. 16's √(cf/a)
    m1 = mech.mechanism_I(case)
    m2 = mech.mechanism_II(case, tanpsi=tanpsi)
    w = case.wall
    lam = np.linspace(w.lam_max / an.lam_points, w.lam_max, an.lam_points)
    scale = math.sqrt(w.g * w.b)
    v1 = mech.vnorm_I(lam, case.rho, case.alpha, case.beta) * scale
    lam2 = lam[lam <= m2.lam_max * (1 + 1e-12)]
    v2 = mech.vnorm_II(lam2, case.rho, m2.tanpsi) * scale
    curves = {"lam_I": lam, "vg_I": v1, "lam_II": lam2, "vg_II": v2}
    return m1, m2, curves


def _fe(config: CaseConfig, progress: Progress, verbose: bool, fields: bool = True
        ) -> tuple[dict, dict]:
    """The finite-element mechanism, its crack and its collapse ground velocity.

    Numbers come from homlimit.mechanism.fe_impulse.h_scan: one FE analysis of the part above
    z0 = H − h per collapse height h (λ = h/b from 2 to H/b) giving the multiplier, rigid fit,
    crack mid-line and edges, mechanism type and v̄_g. The critical FE mechanism is the
    scan's lowest v̄_g (eq. 7 minimised over λ). The pictures and mechanism.vtu show the
    whole wall (h = H, the scan's last height, fe_impulse.analyse with its drawing data).
    Returns (plain data for the summary, artifacts for the writers: ``mesh`` the meshio mesh,
    ``mechanism`` a meshio mesh with the fields, ``plot`` the drawing data; empty unless
    ``fields``).
    """
    from ..fe.kinematic import SolverOptions
    from ..fe.static import solve_static
    from ..mechanism.fe_impulse import analyse, h_scan

    case, an = config.case, config.analysis
    options = SolverOptions(tol=an.tol or None, verbose=verbose)
    lams = _scan_lams(case, an.heights)
    scan = []
    with progress.stage("FE impulse scan", f"{len(lams)} collapse heights"):
        for lam in progress.bar(lams[:-1], "FE analyses over h"):
            scan += h_scan(case, [lam], mesh_size=config.mesh.size, facade=an.facade,
                           options=options)
    whole = _problem(config)                  # the whole wall's problem, for the static bound
    n_tri = whole.n_triangles
    with progress.stage("FE mechanism of the whole wall", f"{n_tri} triangles, P2"):
        full = analyse(case, config.mesh.size, an.facade, z0=0.0, options=options,
                       drawing=fields)
        full["h_part"] = case.wall.H
        scan.append(full)
    static = None
    if an.static:
        with progress.stage("static lower bound of the whole wall", f"{n_tri} triangles"):
            static = solve_static(whole, options)
    ok = [r for r in scan if np.isfinite(r["vg_fe"])]
    crit = min(ok, key=lambda r: r["vg_fe"]) if ok else None
    fe = {
        # the whole wall (h = H)
        "multiplier": full["multiplier_fe"], "n_triangles": full["n_triangles"],
        "facade": an.facade, "mesh_size": config.mesh.size, "hinge": list(full["O"]),
        "omega": full["omega"], "mechanism": full["mechanism_fe"],
        "explained": full["explained"], "block_share": full["block_share"],
        "tanpsi": full["tanpsi_fe"], "tanpsi_uncertainty": full["dtanpsi_fe"],
        "tanpsi_edges": list(full["tanpsi_fe_edges"]),
        "sqrt_cf_a": case.alpha, "f": case.masonry.f, "c_over_a": case.masonry.c / case.masonry.a,
        # the static bound on the same mesh: λ⁻ <= λ <= λ⁺ = "multiplier"
        "lower_bound": None if static is None else static.multiplier,
        "bracket_rel_gap": None if static is None else
        (full["multiplier_fe"] - static.multiplier)
        / (0.5 * (full["multiplier_fe"] + static.multiplier)),
        # the critical collapse height (lowest v̄_g of the scan)
        "vg": None if crit is None else crit["vg_fe"],
        "vnorm": None if crit is None else crit["vnorm_fe"],
        "lam": None if crit is None else crit["lam_fe"],
        "h": None if crit is None else crit["h"],
        "critical_mechanism": None if crit is None else crit["mechanism_fe"],
        "critical_multiplier": None if crit is None else crit["multiplier_fe"],
        "vg_method": None if crit is None else crit["vg_method"],
        "scan": [{"h_part": r["h_part"], "h": r["h"], "lam": r["lam_fe"], "vg": r["vg_fe"],
                  "vnorm": r["vnorm_fe"], "multiplier": r["multiplier_fe"],
                  "mechanism": r["mechanism_fe"], "tanpsi": r["tanpsi_fe"],
                  "vg_method": r["vg_method"]} for r in scan],
    }
    return fe, (_whole_wall_fields(config, full, static) if fields else {})


def _whole_wall_fields(config: CaseConfig, full: dict, static=None) -> dict:
    """The whole wall's mechanism (``fe_impulse.analyse(drawing=True)``) as drawing data and
    a meshio mesh with its fields (the rigid-fit measures are recomputed from the solution:
    no second solve), plus the static stress field as ``static_*`` cell data and each
    triangle's share of the bracket's gap as ``bracket_gap`` when given."""
    from ..fe.mesh import from_skfem
    from ..fe.static import attach_cell_fields
    from ..mechanism.fe_impulse import p2_nodes
    from ..mechanism.rigidfit import measure_mechanism

    w = config.case.wall
    sol, plot = full.pop("solution"), full.pop("drawing")
    X, V, el, rho = p2_nodes(sol, {"facade": w.rho * w.gamma * w.s, "wall": w.gamma * w.s})
    mm = measure_mechanism(X, V, el, density=rho)
    out = {"mesh": from_skfem(sol.mesh), "mechanism": _mechanism_mesh(sol, mm, plot["crack"]),
           "plot": plot}
    if static is not None:
        if not np.array_equal(static.mesh.t, sol.mesh.t):
            raise MeshError("the static and kinematic meshes of the whole wall differ; the "
                            "stress field cannot be attached to mechanism.vtu")
        from ..fe.bracket import gap_contributions

        mech = attach_cell_fields(out["mechanism"], static)
        gap = gap_contributions(static, sol)  # per-triangle share of λ⁺ − λ⁻ (virtual power)
        mech.cell_data["bracket_gap"] = [gap] + [np.full(len(b.data), np.nan)
                                                 for b in mech.cells[1:]]
        out["mechanism"], out["static"] = mech, static
    return out


def _mechanism_mesh(sol, mm, crack):
    """The solution's meshio mesh plus the block participation and label per triangle and,
    as a line block, the detected crack (the 50 % participation line)."""
    import meshio

    m = sol.to_meshio()
    cells = [meshio.CellBlock("triangle", m.cells[0].data)]
    data = {k: [np.asarray(v[0], float)] for k, v in m.cell_data.items()}
    data["participation"] = [np.asarray(mm.participation, float)]
    data["label"] = [np.asarray(mm.label, float)]
    pts = m.points
    if crack is not None and len(crack) > 1:
        k0 = len(pts)
        pts = np.vstack([pts, np.c_[crack, np.zeros(len(crack))]])
        cells.append(meshio.CellBlock("line", np.c_[np.arange(len(crack) - 1),
                                                    np.arange(1, len(crack))] + k0))
        for k, v in data.items():
            pad = np.full((len(crack) - 1,) + v[0].shape[1:], np.nan)
            v.append(pad)
        data["crack"] = [np.zeros(len(cells[0].data)), np.ones(len(crack) - 1)]
    pdata = {k: np.vstack([v, np.zeros((len(pts) - len(v),) + v.shape[1:])])
             for k, v in m.point_data.items()}
    return meshio.Mesh(pts, cells, point_data=pdata, cell_data=data)


def _problem(config: CaseConfig, z0: float = 0.0):
    """The FE T-section problem of the case (seam: homlimit.fe.problems.t_section)."""
    from ..fe.problems import t_section

    return t_section(config.case, z0=z0, facade=config.analysis.facade, h=config.mesh.size)


def _mesh(config: CaseConfig):
    """The T-section mesh the FE analysis uses, as a meshio.Mesh with named regions and
    boundaries (seam: homlimit.fe.mesh.from_skfem)."""
    from ..fe.mesh import from_skfem

    return from_skfem(_problem(config).mesh)


def _fe_table_columns(case: Case, mesh_size: float, heights: int, verbose: bool) -> dict:
    """The FE body's Table 1 columns (seam: homlimit.mechanism.fe_impulse.fe_mechanism)."""
    from ..fe.kinematic import SolverOptions
    from ..mechanism.fe_impulse import fe_mechanism

    r = fe_mechanism(case, mesh_size=mesh_size, lams=_scan_lams(case, heights),
                     options=SolverOptions(verbose=verbose))
    keys = ("lam_fe", "vnorm_fe", "vg_fe", "tanpsi_fe", "tanpsi_fe_edges", "mechanism_fe",
            "multiplier_fe")
    return {k: r[k] for k in keys}


def _scan_lams(case: Case, heights: int) -> np.ndarray:
    """Slenderness values of the FE impulse scan: ``heights`` values spaced geometrically
    from λ = 2 to H/b (fe_impulse.h_scan's range; one value: the whole wall)."""
    lam_max = case.wall.lam_max
    return np.geomspace(min(2.0, lam_max), lam_max, heights) if heights > 1 else \
        np.array([lam_max])


def _crack_study(progress: Progress, verbose: bool, **grid) -> list[dict]:
    """Records of the crack-angle study (seam: homlimit.app.studies.crack_angle_study)."""
    from .studies import crack_angle_study

    return crack_angle_study(verbose=verbose, progress=progress, **grid)


# ----------------------------------------------------------------------------- other commands
def table1_records(fe: bool = False, mesh_size: float = 0.25, heights: int = 10,
                   tests: list[str] | None = None, verbose: bool = False,
                   progress: Progress | None = None) -> list[dict]:
    """Table 1 reproduced (homlimit.closed_form.paper.table1_rows), optionally with the FE body's columns
    lam_fe, vnorm_fe, vg_fe, tanpsi_fe, tanpsi_fe_edges, mechanism_fe, multiplier_fe
    (homlimit.mechanism.fe_impulse.fe_mechanism over ``heights`` collapse heights, λ from 2 to H/b).
    ``tests``: a subset of the test names (B1 ... C6)."""
    from ..closed_form.paper import table1, table1_rows
    from ..errors import check_range

    progress = progress or Progress(False)
    check_range("mesh_size", mesh_size, 0.0, lo_open=True, unit="m")
    check_range("heights", heights, 1, 200)
    cases = {t.test: t.case for t in table1()}
    unknown = [t for t in tests or () if t not in cases]
    if unknown:
        raise ParameterError(f"test = {unknown[0]!r} is out of range: allowed one of "
                             + ", ".join(cases))
    chosen = [c for t, c in cases.items() if not tests or t in tests]
    h_min = min(min(2.0 * c.wall.b, c.wall.H) for c in chosen)
    if fe and heights > 1 and mesh_size > h_min:
        raise ParameterError(f"mesh_size = {mesh_size!r} m is out of range: allowed "
                             f"mesh_size <= {h_min:g} m, the smallest part of the FE scan "
                             "(λ = 2, i.e. 2b)")
    with progress.stage("closed forms for Table 1"):
        rows = [r for r in table1_rows() if not tests or r["test"] in tests]
    if fe:
        for row in progress.bar(rows, "FE body per Table 1 wall"):
            row.update(_fe_table_columns(cases[row["test"]], mesh_size, int(heights), verbose))
    return rows


def crack_study_records(mesh_size: float = 0.5, finer: float | None = 0.25, quick: bool = False,
                        c_over_a=None, frictions=None, facades=None, verbose: bool = False,
                        progress: Progress | None = None) -> list[dict]:
    """The crack-angle study over a grid of c/a and f (homlimit.app.studies.crack_angle_study):
    each grid argument left None takes the study's default."""
    from ..errors import check_range

    check_range("mesh_size", mesh_size, 0.0, lo_open=True, unit="m")
    if finer is not None:
        check_range("finer", finer, 0.0, mesh_size, lo_open=True, hi_open=True, unit="m")
    for name, values in (("c_over_a", c_over_a), ("f", frictions)):
        for v in values or ():
            check_range(name, v, 0.0, lo_open=True)
    for fac in facades or ():
        if fac not in ("homogenised", "bedjoints"):
            raise ParameterError(f"facade = {fac!r} is out of range: allowed 'homogenised', "
                                 "'bedjoints'")
    grid = {k: tuple(v) for k, v in (("c_over_a", c_over_a), ("frictions", frictions),
                                     ("facades", facades)) if v}
    return _crack_study(progress or Progress(False), verbose, mesh_size=mesh_size,
                        finer=finer, quick=quick, **grid)


def mesh_case(config: CaseConfig, out: Path) -> dict:
    """Mesh the case's T-section only; write mesh.vtu and mesh.png; return counts and files."""
    from . import plots, report

    m = _mesh(config)
    _, tri, region, names = plots.triangle_regions(m)
    files = {"mesh_vtu": report.write_vtu(out / "mesh.vtu", m),
             "mesh_png": plots.plot_mesh(out / "mesh.png", m, title=f"case {config.name}")}
    return {"case": config.name, "n_triangles": int(len(tri)), "n_nodes": int(len(m.points)),
            "regions": {n: int(np.count_nonzero(region == k)) for k, n in enumerate(names)},
            "mesh": {"size": config.mesh.size},
            "files": {k: str(v) for k, v in files.items()}}


# ----------------------------------------------------------------------------- the outputs
def _write(result: Result, out: Path, progress: Progress) -> dict[str, Path]:
    from . import report

    cfg = result.config.output
    files: dict[str, Path] = {}
    title = f"case {result.name}"
    if cfg.png:
        from . import plots

        with progress.stage("pictures"):
            if result.mechanism_I is not None:
                files["vg_lambda_png"] = plots.plot_vg_lambda(
                    out / "vg_lambda.png", result.curves, result.mechanism_I,
                    result.mechanism_II, fe=result.fe, dem=result.dem, title=title,
                    b=result.case.wall.b)
            art = result.artifacts
            if "mesh" in art:
                files["mesh_png"] = plots.plot_mesh(out / "mesh.png", art["mesh"], title=title)
            if "plot" in art:
                files["mechanism_png"] = plots.plot_mechanism(
                    out / "mechanism.png", art["plot"], result.case, title=title)
            if "static" in art:
                files["stress_png"] = plots.plot_stress(
                    out / "stress.png", art["static"],
                    title=f"{title}: lower-bound stress field, λ⁻ = "
                          f"{art['static'].multiplier:.4g}")
    if result.fe and result.fe.get("scan"):
        files["fe_scan_csv"] = report.write_csv(out / "fe_scan.csv", result.fe["scan"])
    if cfg.vtu and "mechanism" in result.artifacts:
        files["mechanism_vtu"] = report.write_vtu(out / "mechanism.vtu",
                                                  result.artifacts["mechanism"])
    if cfg.json:
        files["summary_json"] = out / "summary.json"
        result.files = {**result.files, **files}
        report.write_json(out / "summary.json", result.to_dict())
    return files


def run(path_or_dict: str | Path | dict | CaseConfig | None = None, *,
        out: str | Path | None = None, write: bool = True, progress: bool | Progress = False,
        verbose: bool = False, overrides: list[str] | dict | None = None) -> Result:
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
    prog = progress if isinstance(progress, Progress) else Progress(bool(progress))
    result = Result(config=config, dem=dem_reference(config.case))
    if config.analysis.closed_form:
        with prog.stage("closed-form mechanisms I and II"):
            result.mechanism_I, result.mechanism_II, result.curves = _closed_form(config)
    if config.analysis.fe:
        out_cfg = config.output
        result.fe, result.artifacts = _fe(config, prog, verbose,
                                          fields=write and (out_cfg.png or out_cfg.vtu))
    result.timings = dict(prog.timings)
    if write:
        result.files = _write(result, output_dir(config, out), prog)
    return result
