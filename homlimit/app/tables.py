"""The other commands' work: the paper's Table 1 (closed forms, with the FE body's or the
rigid blocks' column), its Figure 2, the crack-angle study and a case's mesh alone."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..blocks import table1_blocks
from ..blocks.geometry import FACADE_BONDS
from ..closed_form import mechanisms as mech
from ..closed_form.paper import table1, table1_rows
from ..errors import ParameterError, check_choice, check_range
from ..fe.mesh import from_skfem
from ..mechanism.analysis import fe_result
from ..params import FACADE_DEFAULT, FACADE_MODELS, MESHER_DEFAULT, MESHERS, PART_DIVISIONS, Case
from . import budget, models, plots, report
from .config import CaseConfig, check_mesh
from .models import solver_options, stage
from .outputs import result_folder, source_of
from .problems import Problems
from .schema import SCHEMA
from .studies import FINER, STUDY_WALL, check_finer, crack_angle_study

__all__ = ["check_budget", "check_option", "crack_study_checks", "crack_study_records",
           "figure2_curves", "mesh_case", "table1_blocks_records", "table1_checks",
           "table1_records"]


def check_option(section: str, key: str, value, name: str | None = None) -> float:
    """A command's option checked against its case-file key's range (one range, the
    schema's): ParameterError naming the option (``name``, default the key), its value and
    the range."""
    return SCHEMA[section][key].range.check(name or key, value)


def check_budget(option: str, cases, size: float, max_triangles: int, scan: bool = True,
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


def table1_checks(problems: Problems, fe: bool = False, mesh_size: float = 0.25,
                  heights: int = 6, tests: list[str] | None = None,
                  facade: str = FACADE_DEFAULT,
                  max_triangles: int = budget.DEFAULT_MAX_TRIANGLES,
                  mesher: str = MESHER_DEFAULT, part_divisions: int = PART_DIVISIONS,
                  names: dict | None = None):
    """Every problem of ``table1_records``' arguments into ``problems`` (a ``Problems``),
    each value checked whatever ``fe`` says; with ``fe`` also the triangle budget of the
    walls' FE problems (``check_budget``). ``names``: argument → the name the messages give
    it (the command line's flags; default the argument's own)."""
    name = (names or {}).get
    size = problems.check(check_range, name("mesh_size", "mesh_size"), mesh_size, 0.0, 9.0,
                          lo_open=True, unit="m")
    problems.check(check_option, "analysis", "heights", heights, name("heights"))
    problems.check(check_choice, name("facade", "facade"), facade, FACADE_MODELS)
    mesher_ok = problems.check(check_choice, name("mesher", "mesher"), mesher, MESHERS)
    budget_ok = problems.check(check_option, "mesh", "max_triangles", max_triangles,
                               name("max_triangles"))
    problems.check(check_option, "mesh", "part_divisions", part_divisions,
                   name("part_divisions"))
    cases = {t.test: t.case for t in table1()}
    tests_ok = all([problems.check(check_choice, name("test", "test"), t, tuple(cases))
                    is not None for t in tests or ()])
    if fe and None not in (size, mesher_ok, budget_ok) and tests_ok:
        problems.check(check_budget, "--mesh-size",
                       [c for t, c in cases.items() if not tests or t in tests], size,
                       max_triangles, mesher=mesher)


def table1_records(fe: bool = False, mesh_size: float = 0.25, heights: int = 6,
                   tests: list[str] | None = None, facade: str = FACADE_DEFAULT,
                   max_triangles: int = budget.DEFAULT_MAX_TRIANGLES, fe_results=None,
                   mesher: str = MESHER_DEFAULT, part_divisions: int = PART_DIVISIONS
                   ) -> list[dict]:
    """Table 1 reproduced (``paper.table1_rows``), optionally with the FE body's columns
    lam_fe, vnorm_fe, vg_fe, tanpsi_fe, tanpsi_fe_edges, mechanism_fe, multiplier_fe,
    critical_at_fe, hinge_ratio_fe (the critical height of the FE scan, ``fe_result``, from
    ``heights`` starting heights). ``tests``: a subset of the test names (B1 ... C6).
    ``max_triangles``: the problem-size budget of the FE meshes (``budget``), checked before
    any work; ``mesher``: the FE meshes (``problems.MESHERS``); ``part_divisions``: elements
    per part height of the scan's parts ([mesh] part_divisions).
    ``fe_results(cases, mesh_size, facade, heights, options, mesher, divisions)``: the FE
    path of the walls, one ``FEResult`` each (default: ``fe_result`` wall after wall here;
    ``engine.Engine.fe_results`` runs every height as a Dask task)."""
    problems = Problems("table1_records", "the arguments")
    table1_checks(problems, fe=fe, mesh_size=mesh_size, heights=heights, tests=tests,
                  facade=facade, max_triangles=max_triangles, mesher=mesher,
                  part_divisions=part_divisions)
    problems.raise_any()
    cases = {t.test: t.case for t in table1()}
    timings: dict[str, float] = {}
    with stage(timings, "closed forms for Table 1"):
        rows = [r for r in table1_rows() if not tests or r["test"] in tests]
    walls = [cases[row["test"]] for row in rows] if fe else []
    results = []
    if walls:
        with stage(timings, "FE body", f"{len(walls)} walls"):
            if fe_results is None:
                results = [fe_result(case, mesh_size, facade, solver_options(),
                                     heights=heights, mesher=mesher, divisions=part_divisions)
                           for case in walls]
            else:
                results = fe_results(walls, mesh_size, facade, heights, solver_options(),
                                     mesher, part_divisions)
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
    check_option("blocks", "step", step)
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


def crack_study_checks(problems: Problems, mesh_size: float = 0.5,
                       finer: float | None = FINER, quick: bool = False, c_over_a=None,
                       frictions=None, facades=None,
                       max_triangles: int = budget.DEFAULT_MAX_TRIANGLES,
                       mesher: str = MESHER_DEFAULT, names: dict | None = None):
    """Every problem of ``crack_study_records``' arguments into ``problems`` (a
    ``Problems``), the triangle budget of its finest mesh last (``check_budget``).
    ``names``: argument → the name the messages give it (default the argument's own)."""
    name = (names or {}).get
    w = STUDY_WALL
    size = problems.check(check_range, name("mesh_size", "mesh_size"), mesh_size, 0.0,
                          min(w.H, w.b + w.L), lo_open=True, unit="m")
    finer = None if quick else finer                # --quick: one mesh, no second one
    finer_ok = not finer or problems.check(         # below a bad mesh_size: >= 0 at least
        check_finer, size, finer, name("finer", "finer"),
        name("mesh_size", "mesh_size")) is not None
    budget_ok = problems.check(check_option, "mesh", "max_triangles", max_triangles,
                               name("max_triangles"))
    mesher_ok = problems.check(check_choice, name("mesher", "mesher"), mesher, MESHERS)
    for arg, values in (("c_over_a", c_over_a), ("f", frictions)):
        for v in values or ():
            problems.check(check_range, name(arg, arg), v, 0.0, 100.0, lo_open=True)
    for fac in facades or ():
        problems.check(check_choice, name("facade", "facade"), fac, FACADE_MODELS)
    if None not in (size, budget_ok, mesher_ok) and finer_ok:
        finest = finer or size
        problems.check(check_budget, "--finer" if finest != size else "--mesh-size",
                       [Case(w)], finest, max_triangles, scan=False, mesher=mesher)


def crack_study_records(mesh_size: float = 0.5, finer: float | None = FINER, quick: bool = False,
                        c_over_a=None, frictions=None, facades=None,
                        max_triangles: int = budget.DEFAULT_MAX_TRIANGLES, map=map,
                        mesher: str = MESHER_DEFAULT, conform: bool = False) -> list[dict]:
    """The crack-angle study over a grid of c/a and f (``studies.crack_angle_study``): each
    grid argument left None takes the study's default. ``max_triangles``: the problem-size
    budget of its meshes (``budget``), checked before any work; ``map``: how the grid points
    are evaluated (``crack_angle_study``); ``mesher``: ``problems.MESHERS``; ``conform``: the
    ray-conforming search on the homogenised façade (``mechanism.conform``)."""
    problems = Problems("crack_study_records", "the arguments")
    crack_study_checks(problems, mesh_size=mesh_size, finer=finer, quick=quick,
                       c_over_a=c_over_a, frictions=frictions, facades=facades,
                       max_triangles=max_triangles, mesher=mesher)
    problems.raise_any()
    grid = {k: tuple(v) for k, v in (("c_over_a", c_over_a), ("frictions", frictions),
                                     ("facades", facades)) if v}
    return crack_angle_study(mesh_size=mesh_size, finer=finer, quick=quick,
                             options=solver_options(), map=map, mesher=mesher,
                             conform=conform, **grid)


def mesh_case(config: CaseConfig, out: Path) -> dict:
    """Mesh the case's T-section only; write mesh.vtu and mesh.png as one result set in
    ``out`` (the mesh checks and the triangle budget first, ``config.check_mesh``); return
    counts and files."""
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
