"""What a run shows and writes: the terminal summary, plain-text tables, the result meshes and
one writer per file format.

``write(path, data)`` picks the writer from the file's suffix (``WRITERS``): JSON data, CSV
records, a meshio mesh (.vtu, .xdmf, .msh) or a picture (a function that draws to a path).
Every writer is whole-or-nothing (``homlimit._io``).

Units: ``UNITS`` gives every quantity a result file carries its SI unit, once. JSON and CSV
go through the one writer ``_io.write_output``: every JSON file starts with ``schema_version``
and ``homlimit_version`` and ends with a ``units`` map (summary.json's by section,
``units_table``; other files by key, ``units_of``); CSV headers carry the unit as
``name [unit]`` (``vg [m/s]``, ``lam [-]``; text columns plain, ``mechanism``), the way the
terminal tables do, and the sidecar ``NAME.csv.json`` gives the schema version and the units
by header; floats are written to 15 significant digits. ``read_csv`` reads such a CSV back into
plain keys and numbers.
"""

from __future__ import annotations

import functools
import json
import logging
import math
import re
from collections.abc import Callable, Iterable, Mapping
from pathlib import Path

import numpy as np

from .._io import write_output
from ..errors import ParameterError
from ..fe import mesh as fe_mesh
from . import registry

__all__ = ["OUTPUT_NAMES", "UNITS", "WRITERS", "csv_header", "format_spectra", "format_table",
           "mechanism_mesh", "read_csv", "summary_text", "units_table", "write"]

_DIMENSIONLESS = (
    "lam lam_I lam_II lam_fe lam_dem lam_v lambda_v lam_max vnorm vnorm_I vnorm_II vnorm_fe "
    "vnorm_dem vnorm_eq7 vg_norm multiplier multiplier_fe multiplier_fan multiplier_wedge "
    "critical_multiplier lower_bound bracket_rel_gap ratio ratio_I ratio_II rho alpha alpha2 "
    "beta f c_over_a sqrt_cf_a tanpsi tanpsi_fe tanpsi_fe_edges tanpsi_uncertainty dtanpsi_fe "
    "tanpsi_edges tanpsi_block tanpsi_fixed tan_alpha tan_f tan_c_over_a fan_T1 fan_T2 "
    "explained block_share interior_share eq14_error n_triangles static_triangles polarity "
    "pga_g pT n_impacts "
    "hinge_ratio hinge_ratio_fe hinge_ratio_I hinge_ratio_II multiplier_I multiplier_II rtol "
    "ivp_rtol lam_multiplier retries solver_tol").split()
_TEXT = ("name test mechanism mechanism_fe critical_mechanism vg_method facade mesher pulse "
         "ivp_method fan_admissible wedge_admissible case status critical_at critical_at_fe reason "
         "implausible").split()
#: the SI unit of every quantity in a result file ("-": dimensionless, "": text or a flag)
UNITS: dict[str, str] = {
    **dict.fromkeys(_DIMENSIONLESS, "-"), **dict.fromkeys(_TEXT, ""),
    **dict.fromkeys("b h h_part h_v h_min mesh_size hinge hinge_z fan_z0 wedge_z0 x_G z_G"
                    .split(), "m"),
    **dict.fromkeys("vg vg_fe vg_eq7 vg_body pgv".split(), "m/s"),
    **dict.fromkeys("pga a_uplift".split(), "m/s^2"),
    **dict.fromkeys("theta_m theta_m_eq14 theta_m_I theta_m_I_eq14".split(), "rad"),
    **dict.fromkeys("psi_fe_deg psi_alpha_deg psi_f_deg psi_c_over_a_deg".split(), "deg"),
    "W_m": "J", "m": "kg", "I_O": "kg m^2", "omega": "1/s", "p": "rad/s", "period": "s",
    "solve_time": "s", "duration": "s",
    # the rigid-block model's files (blocks_scan.csv, blocks_contacts.csv, table1_blocks.csv)
    **dict.fromkeys("z0 z_base x_O z_O h_dem h_whole z0_crit h_blocks h_na x z".split(), "m"),
    **dict.fromkeys("n_moving n_open n_sliding n_body blocks vnorm_rigid W_rest_share "
                    "W_friction_share M_rest_share multiplier_whole vnorm_whole "
                    "multiplier_crit lam_blocks lam_whole vnorm_blocks vnorm_blocks_rigid "
                    "ratio_blocks_dem multiplier_na vnorm_na na_band W_friction_share_na "
                    "n_x n_z".split(), "-"),
    **dict.fromkeys("friction method na_converged interface end block_a block_b state"
                    .split(), ""),
    "vg_rigid": "m/s", "m_body": "kg", "time": "s",
    # a real wall's blocks (blocks.studies.scan_record): the ties' total force at collapse,
    # the crushing dissipation rate of the mechanism, the parts of W(θ_m)
    "tie_force": "N", "crushing_rate": "W", "W_crushing": "J", "W_floors": "J", "W_ties": "J",
    "N": "N", "T": "N",              # contact forces per slab of thickness s (blocks.limit)
    "opening": "m/s", "slip": "m/s",  # velocity jumps of the normalised mechanism
    # homlimit verify and the adaptive bracket (verify.json, verify.csv, fe_adapt.csv)
    **dict.fromkeys("problem source stop holds converged".split(), ""),
    **dict.fromkeys("lower upper best_lower best_upper exact_lo exact_hi rel_gap lower_err "
                    "upper_err triangles cycles cycle T1 T2 T_mid T1_exact T2_exact f c_over_a "
                    "sqrt_cf_a".split(), "-"),
    "z0_exact": "m", "seconds": "s", "mesh_seconds": "s",
    "adapt": "",                     # summary fe.adapt: the cycles' table, units per column
    # the rigid-block DEM (summary "dem", table1_dem.csv; app.dem_stage)
    **dict.fromkeys("vg_lo vg_hi vg_udec pgv".split(), "m/s"),
    **dict.fromkeys("pga_lo pga_hi".split(), "m/s^2"),
    **dict.fromkeys("h_udec base_slip hinge_slip".split(), "m"),
    **dict.fromkeys("pulse_period t_end cpu dt settle_time".split(), "s"),
    **dict.fromkeys("vnorm_udec dem_over_udec rel_tol n_trials n_blocks".split(), "-"),
    **dict.fromkeys("loading base_slid hinge_slid collapsed settle_converged".split(), ""),
    # real walls (issue 30; closed_form.real, docs/real-walls.md)
    **dict.fromkeys("fc cohesion tension peak_compression".split(), "Pa"),
    "fc_rule": "",
    **dict.fromkeys("yield_force load".split(), "N/m"),
    "stiffness": "N/m^2", "normal_force": "N",
    **dict.fromkeys("ductility eccentricity hinge_retreat tie_elongation".split(), "m"),
    **dict.fromkeys("restrains kind fc_infinite choices per_metre floor_mass hinge_rule tie_law "
                    "abutment_friction_I".split(), ""),
}
#: every file name a homlimit command writes (result sets written before manifests existed
#: are recognised by these, ``_io.is_result_set``)
OUTPUT_NAMES = ("summary.json", "vg_lambda.png", "mesh.png", "mechanism.png", "stress.png",
                "fe_scan.csv", "mechanism.vtu", "mesh.vtu", "table1.csv", "table1.json",
                "table1.png", "figure2.png", "figure2.json", "crack_study.csv",
                "crack_study.png", "spectra.csv", "spectra.png", "mesh.json", "blocks.vtu",
                "blocks_contacts.vtu", "blocks_contacts.csv", "blocks_mechanism.png",
                "blocks_whole.png", "blocks_scan.csv", "table1_blocks.csv",
                "table1_blocks_ratios.json", "sweep.json", "results.parquet", "results.csv",
                "vnorm_swept.png", "critical_map.png", "tanpsi.png", "vg_histogram.png",
                "verify.json", "verify.csv", "fe_adapt.csv", "adapt.png", "dem.pvd",
                "dem_snapshots.png", "table1_dem.csv", "table1_dem_ratios.json")
OUTPUT_NAMES += tuple(n + ".json" for n in OUTPUT_NAMES if n.endswith(".csv"))  # sidecars


def csv_header(key: str) -> str:
    """The CSV header of a column: ``key [unit]`` (``key`` for text); ParameterError if the
    quantity has no unit in ``UNITS``."""
    if key not in UNITS:
        raise ParameterError(f"column = {key!r} is out of range: allowed a quantity of "
                             "report.UNITS (give it its unit there)")
    return f"{key} [{UNITS[key]}]" if UNITS[key] else key


def _unknown_units(keys) -> list[str]:
    """Keys without a unit in UNITS, logged: a result file is still written (their CSV header
    ``key [?]``, their unit null), the tests require every key to have one."""
    missing = sorted(set(keys) - set(UNITS))
    if missing:
        logging.getLogger(__name__).warning("no unit registered for %s (report.UNITS)",
                                            ", ".join(missing))
    return missing


def _write_csv(path: Path, records: Iterable[Mapping], columns: list[str] | None = None):
    records = [dict(r) for r in records]
    if columns is None:
        columns = list(dict.fromkeys(k for r in records for k in r))
    _unknown_units(columns)
    head = {k: csv_header(k) if k in UNITS else f"{k} [?]" for k in columns}
    return write_output(path, [{head[k]: v for k, v in r.items()} for r in records],
                        units={head[k]: UNITS.get(k) for k in columns},
                        columns=[head[k] for k in columns])


def _write_json(path: Path, data) -> Path:
    """JSON data with its units: the ``units`` table ``data`` carries (summary.json's, by
    section), else the unit of every key it holds (``units_of``)."""
    units = data["units"] if isinstance(data, Mapping) and "units" in data else units_of(data)
    return write_output(path, data, units=units)


_UNIT_SUFFIX = re.compile(r"^(.*?) \[[^\]]*\]$")


def read_csv(path: str | Path) -> list[dict]:
    """Read a CSV written by ``write``: plain keys (the unit suffix dropped), numbers as floats
    (ints where integral text), empty cells as NaN, other text as is."""
    import csv

    def value(text: str):
        if text == "":
            return math.nan
        for conv in (int, float):
            try:
                return conv(text)
            except ValueError:
                pass
        return text

    with open(path, newline="", encoding="utf-8") as fh:
        rows = list(csv.DictReader(fh))
    return [{(_UNIT_SUFFIX.match(k).group(1) if _UNIT_SUFFIX.match(k) else k): value(v)
             for k, v in r.items()} for r in rows]


def column_unit(path: str) -> str | None:
    """The unit of a sweep table column named by its summary.json path ("inputs.wall.H": m,
    "mechanisms.I.vg": m/s, "fe.edges.0": that of "edges"); None if none is registered."""
    parts = path.split(".")
    if parts[0] == "timings_s":
        return "s"
    if parts[0] == "inputs" and len(parts) >= 2:
        units = input_units()
        u = units.get(parts[1])
        return u.get(parts[2]) if isinstance(u, dict) and len(parts) > 2 else \
            (u if isinstance(u, str) else None)
    names = [p for p in parts if not p.isdigit()]
    return UNITS.get(names[-1]) if names else None


@functools.cache
def input_units() -> dict:
    """The unit of every case-file key, by section (the schema's, fixed)."""
    from .config import SCHEMA, TOP_LEVEL

    def unit(key):
        numeric = float in (key.kind, key.item) or int in (key.kind, key.item)
        return key.unit.replace("³", "^3").replace("²", "^2") or ("-" if numeric else "")

    inputs = {sec: {k: unit(key) for k, key in keys.items()} for sec, keys in SCHEMA.items()}
    inputs["name"] = unit(TOP_LEVEL["name"])
    return inputs


def _leaf_keys(x) -> set[str]:
    """The keys of the values of nested mappings and lists of mappings that are not
    themselves mappings or lists of mappings (the quantities a JSON result holds)."""
    found: set[str] = set()

    def mapping(v):
        return type(v) is dict or isinstance(v, Mapping)

    def walk(x):
        if mapping(x):
            for k, v in x.items():
                kind = type(v)
                if kind is float or kind is int or kind is str or v is None or kind is bool:
                    found.add(k)       # the plain values first: most of a summary
                elif mapping(v) or (isinstance(v, list) and v and mapping(v[0])):
                    walk(v)
                else:
                    found.add(k)
        elif isinstance(x, list):
            for v in x:
                walk(v)

    walk(x)
    return found


def units_of(data) -> dict:
    """The unit of every quantity (leaf key) of JSON data, by name (``UNITS``; None and a
    logged warning where none is registered)."""
    found = _leaf_keys(data)
    _unknown_units(found)
    return {k: UNITS.get(k) for k in sorted(found)}


def units_table(summary: Mapping) -> dict:
    """The ``units`` table of summary.json: the unit of every case-file key (by section) and of
    every result quantity the summary holds (by name; "-" dimensionless, "" text)."""
    inputs = {sec: dict(u) if isinstance(u, dict) else u for sec, u in input_units().items()}
    found: set[str] = set()
    for k in ("derived", "mechanisms", "hinges", "fe", "critical", "dem_table1", "dem"):
        found |= _leaf_keys(summary.get(k))
    _unknown_units(found)
    return {"inputs": inputs, "results": {k: UNITS.get(k) for k in sorted(found)},
            "timings_s": "s"}


WRITERS: dict[str, Callable] = {
    ".json": _write_json, ".csv": _write_csv, ".png": lambda path, draw: draw(path),
    **dict.fromkeys((".vtu", ".xdmf", ".msh"), lambda path, mesh: fe_mesh.write(mesh, path))}


def write(path: str | Path, data) -> Path:
    """Write ``data`` to ``path`` with the writer of its suffix (``WRITERS``)."""
    path = Path(path)
    writer = WRITERS.get(path.suffix.lower())
    if writer is None:
        raise ParameterError(f"file suffix = {path.suffix!r} is out of range: allowed one of "
                             + ", ".join(WRITERS))
    writer(path, data)
    return path


def _fmt(x) -> str:
    if x is None:
        return "–"
    if isinstance(x, bool):
        return "yes" if x else "no"
    if isinstance(x, (int, np.integer)):
        return str(int(x))
    if isinstance(x, (float, np.floating)):
        x = float(x)
        if not math.isfinite(x):
            return "–"
        return f"{x:.4g}" if (x == 0 or 1e-3 <= abs(x) < 1e5) else f"{x:.3e}"
    return str(x)


def format_table(header: list[str], rows: list[list], title: str | None = None) -> str:
    """A plain-text table with aligned columns (numbers to 4 significant digits)."""
    cells = [[_fmt(c) for c in r] for r in rows]
    widths = [max([len(h)] + [len(r[i]) for r in cells]) for i, h in enumerate(header)]
    line = "  ".join("-" * w for w in widths)
    out = [] if title is None else [title]
    out += ["  ".join(h.ljust(w) for h, w in zip(header, widths)), line]
    out += ["  ".join(c.rjust(w) if i else c.ljust(w) for i, (c, w) in
                      enumerate(zip(r, widths))) for r in cells]
    return "\n".join(out)


def format_spectra(points, title: str | None = None) -> str:
    """The overturning spectra (``dynamics.SpectrumPoint``) as a text table: pulse, mechanism,
    polarity, T_p, critical pga/g, pgv, pgv/√(gb), pgv over eq. 7's v̄_g, impacts, and the flag
    "implausible" (pga > 3 g or pgv > 3 m/s)."""
    rows = [[p.pulse, p.mechanism, p.polarity, p.period, p.pga_g, p.pgv, p.vnorm, p.ratio,
             p.n_impacts, "implausible" if p.implausible else ""] for p in points]
    return format_table(["pulse", "mech", "pol", "T_p [s]", "pga/g", "pgv [m/s]",
                         "pgv/sqrt(gb)", "pgv/vg(eq.7)", "impacts", "flag"], rows, title)


# ----------------------------------------------------------------------------- the summary
def summary_text(result) -> str:
    """A readable terminal table of a ``pipeline.Result``: each mechanism's λ, h, v̄_g and
    v̄_g/√(gb) beside the paper's DEM value, the FE details, the governing mechanism, files."""
    c = result.case
    rows = [[m.label, m.lam, m.h, m.vg, m.vnorm] for m in result.mechanisms.values()]
    if result.dem:
        d = result.dem
        rows.append(["DEM, paper's Table 1", d.lam_v, d.h_v, d.vg, d.vg_norm])
    run = getattr(result, "dem_run", None)
    if run is not None:
        d = run.as_dict()
        rows.append([run.label(), d["lam"], d["h"], d["pgv"], d["vnorm"]])
    head = (f"case {result.name}: H={c.wall.H:g} m, L={c.wall.L:g} m, s={c.wall.s:g} m, "
            f"b={c.wall.b:g} m, l={c.wall.l:g} m; a={c.masonry.a:g} m, c={c.masonry.c:g} m, "
            f"f={c.masonry.f:g}\n"
            f"  rho=l/s={c.rho:.4g}  alpha^2=cf/a={c.alpha ** 2:.4g}  beta=c/b={c.beta:.4g}"
            f"  (eq. 11)")
    cfg = result.config
    if cfg.modified:
        head += f"\n  modified by --set: {cfg.describe_changes()}"
    head += "".join(f"\n  warning: {w}" for w in cfg.warnings)
    out = [head, "", format_table(["mechanism", "lambda=h/b", "h [m]", "vg [m/s]",
                                   "vg/sqrt(gb)"], rows)]
    statics = [f"{k} {m.multiplier:.4g} at h = {m.lam_multiplier * c.wall.b:.2f} m"
               for k, m in result.mechanisms.items() if registry.mechanism(k).static]
    if statics:
        out += ["", "collapse acceleration a/g of a static check (smallest over h): "
                + "; ".join(statics)]
    if run is not None:
        out += ["", run.lines()]
    if result.fe:
        out += ["", _fe_lines(result.fe, c)]
    if result.hinges:
        out += ["", _hinge_lines(result, c.masonry.f)]
    crit = result.critical()
    if crit:
        out += ["", f"governing: {crit['mechanism']}, collapse ground velocity "
                    f"vg = {crit['vg']:.3f} m/s (vg/sqrt(gb) = {crit['vnorm']:.3f})"]
    if result.files:
        out += ["", "files:"] + [f"  {v}" for v in result.files.values()]
    return "\n".join(out)


def _num(x, fmt=".3f") -> str:
    return "–" if x is None or not math.isfinite(x) else format(x, fmt)


def _fe_lines(fe, case) -> str:
    """The FE block of the summary: the whole wall, its bracket, hinge, crack and scan."""
    full, crit = fe.whole, fe.critical
    e1, e2 = full.tanpsi_edges
    lines = [f"FE, whole wall: {full.n_triangles} triangles, façade {full.facade}, "
             f"collapse multiplier {_num(full.multiplier, '.4g')} (acceleration / g)"]
    if fe.static is not None:
        ns = fe.static.mesh.t.shape[1]
        how = ("same mesh" if ns == full.n_triangles else
               f"static on its own mesh, {ns} triangles, façade columns graded to the "
               f"outer face") if fe.adapt is None else (
            f"adaptive gmsh mesh, {len(fe.adapt.cycles)} cycles, "
            + ("target reached" if fe.adapt.converged else f"stopped: {fe.adapt.stop}"))
        lines.append(f"  bracket: static {_num(fe.lower_bound, '.4g')} <= multiplier <= "
                     f"kinematic {_num(full.multiplier, '.4g')} (gap "
                     f"{100 * fe.bracket_rel_gap:.1f} %, {how})")
    lines += [f"  {full.kind} mechanism, hinge at x = {_num(full.O[0], '.2f')} m, "
              f"z = {_num(full.O[1], '.2f')} m",
              f"  crack: tan psi = {_num(full.tanpsi)} ± {_num(full.tanpsi_uncertainty)} "
              f"(50 % line), edges {_num(e1)} .. {_num(e2)}",
              f"         sqrt(cf/a) = {case.alpha:.3f} (eq. 16), f = {case.masonry.f:.3f}, "
              f"c/a = {case.masonry.c / case.masonry.a:.3f}"]
    if crit is not None:
        lines += [f"  impulse: lowest vg over {len(fe.scan)} heights of the failing part "
                  f"({fe.h_min:g} m, one course, to H) at h = {_num(crit.h, '.2f')} m: "
                  f"{fe.critical_at}", f"         ({crit.vg_method})"]
    return "\n".join(lines)


def _hinge_lines(result, f: float) -> str:
    """The hinge under the ideal impulse: |P_x/P_z| against f, and the shortest rectangular
    pulse of a_g = f g that still overturns each mechanism."""
    rows = [[k, result.mechanisms[k].hinge_ratio, "yes" if result.mechanisms[k].hinge_ratio > f
             else "no", h.duration, h.pgv, h.ratio] for k, h in result.hinges.items()]
    out = [format_table(["mechanism", "|Px/Pz|", "slides", "holding pulse [s]", "pgv [m/s]",
                         "pgv/vg"], rows,
                        title=f"hinge under the ideal impulse (it slides where |Px/Pz| > "
                              f"f = {f:g}) and the shortest rectangular pulse of a_g = f g "
                              "that still overturns")]
    slid = [k for k, r in zip(result.hinges, rows) if r[2] == "yes"]
    if slid:
        out.append(f"  the ideal-impulse vg of {', '.join(slid)} is not attainable without the "
                   "hinge sliding: a pulse the hinge holds needs the pgv above")
    out += [f"  {k}: {h.reason}" for k, h in result.hinges.items() if h.reason]
    return "\n".join(out)


# ----------------------------------------------------------------------------- result meshes
#: the unit of every field of mechanism.vtu ("-": dimensionless, "": a tag or a flag). The
#: mechanism's amplitude is arbitrary: velocity is v / velocity_scale, and the fields linear in
#: it are divided by velocity_scale [m/s] too: intensity [1/s] / [m/s] = 1/m, dissipation
#: [W/m] / [m/s] = N/m (per unit thickness, per triangle or per interface facet)
MECHANISM_UNITS: dict[str, str] = {
    "velocity": "-", "velocity_scale": "m/s", "intensity": "1/m", "dissipation": "N/m",
    "interface_dissipation": "N/m", "region": "", "stress": "Pa", "participation": "-",
    "label": "", "crack": "", "body": "", "density": "kg/m^2", "interface": "",
    **dict.fromkeys(("static_sigma_x", "static_sigma_z", "static_tau_xz", "static_sigma_1",
                     "static_sigma_2"), "Pa"),
    "static_compression_angle": "rad", "static_active_facet": "", "bracket_gap": "-"}

#: why a dissipation field is left out of mechanism.vtu (field data "notes")
NO_DISSIPATION = (
    "not written: every region's strength domain is a cone with its apex at 0 (eq. 15 without "
    "cohesion, dry bed joints, rigid), whose support function is 0 wherever it is finite "
    "(fe.strength.dissipation_free), so an admissible mechanism dissipates nothing there and "
    "the multiplier comes from gravity alone")
NO_INTERFACE_DISSIPATION = (
    "not written: every interface is a dry joint (no cohesion), whose support function is 0 "
    "wherever it is finite (fe.strength.dissipation_free)")


def mechanism_mesh(fe):
    """The whole wall's mechanism as a meshio mesh for ParaView: the solution's fields
    (velocity, intensity, region, stress estimate, dissipation where not zero in theory), the
    block participation and label per triangle, the detected crack (the 50 % line) as a line
    block, the failing body (inside the 50 % line) as a triangle block of its own (cell fields
    ``body`` = 1 and its ``density`` [kg/m²]) and, with the static bound, its stress field
    (``static_*``) and each triangle's share of the bracket's gap.

    The section plane is the file's X–Y plane (X = x, Y = z, Z out of plane). ``stress`` is
    the mean per triangle of the stress read from the kinematic program's duals as a 3×3
    tensor [Pa] (9 components; ParaView reads it as a tensor), the out-of-plane components 0.

    A mechanism's amplitude is arbitrary (the solver normalises the live load's power to 1,
    which leaves velocities of order 1e-6 m/s): the velocity is divided by its largest
    magnitude, so max |v| = 1 and ParaView's "Warp By Vector" works at scale factors of the
    order of the wall; ``intensity`` and ``dissipation``, linear in the velocity, are divided
    by the same number, kept as field data ``velocity_scale`` [m/s].

    Dissipation (``fe.strength.dissipation_free``): the per-triangle ``dissipation`` is written
    only when some region's strength domain dissipates (cohesion); for cohesionless masonry
    eq. 15's support function vanishes on its admissible cone, an admissible mechanism
    dissipates nothing, and the field is left out with a note. Interfaces to a fixed ground
    (``Problem.interfaces``) that dissipate get line cells (``interface`` = 1) with their
    per-facet ``interface_dissipation``. ``participation`` (1 on the block, 0 at rest) is
    clipped to [0, 1]: near the hinge the ratio of the FE to the rigid velocity is
    ill-conditioned and its raw centroid values stray outside (NaN: at the hinge itself).

    Field data: ``velocity_scale``, ``units`` (JSON: field → unit, ``MECHANISM_UNITS``) and
    ``notes`` (JSON: field → why it is absent or how to read it); text field data is stored
    as its UTF-8 bytes (``fe.mesh.write``)."""
    import meshio

    from ..fe.bracket import gap_contributions, same_mesh
    from ..fe.static import attach_cell_fields
    from ..fe.strength import dissipation_free

    full = fe.whole
    sol, prob = full.solution, full.problem
    m = sol.to_meshio()
    crack = full.drawing()["crack"]
    cells = [meshio.CellBlock("triangle", m.cells[0].data)]
    data = {k: [np.asarray(v[0], float)] for k, v in m.cell_data.items()}
    vel = np.asarray(m.point_data["velocity"], float)
    scale = float(np.max(np.linalg.norm(vel, axis=1), initial=0.0)) or 1.0
    m.point_data["velocity"] = vel / scale
    notes = {"velocity": "v / velocity_scale (max |v| = 1); the mechanism's amplitude is "
                         "arbitrary",
             "frame": "the section plane is X-Y: X = x (from the outer face into the wall), "
                      "Y = z (height); Z is out of plane"}
    for k in ("dissipation", "intensity"):
        data[k] = [data[k][0] / scale]
    if all(dissipation_free(d) for d in prob.domains.values()):
        del data["dissipation"]
        notes["dissipation"] = NO_DISSIPATION
    data["participation"] = [np.clip(np.asarray(full.measures.participation, float), 0, 1)]
    data["label"] = [np.asarray(full.measures.label, float)]
    pts = m.points
    if crack is not None and len(crack) > 1:
        k0 = len(pts)
        pts = np.vstack([pts, np.c_[crack, np.zeros(len(crack))]])
        cells.append(meshio.CellBlock("line", np.c_[np.arange(len(crack) - 1),
                                                    np.arange(1, len(crack))] + k0))
        for v in data.values():
            v.append(np.full((len(crack) - 1,) + v[0].shape[1:], np.nan))
        data["crack"] = [np.zeros(len(cells[0].data)), np.ones(len(crack) - 1)]
    body, rho = full.body_pieces()                # the failing body: its own triangle block
    k0, nb = len(pts), len(body)
    pts = np.vstack([pts, np.c_[body.reshape(-1, 2), np.zeros(3 * nb)]])
    cells.append(meshio.CellBlock("triangle", k0 + np.arange(3 * nb).reshape(-1, 3)))
    for v in data.values():
        v.append(np.full((nb,) + v[0].shape[1:], np.nan))
    data["body"] = [np.zeros(len(c.data)) for c in cells[:-1]] + [np.ones(nb)]
    data["density"] = [np.full(len(c.data), np.nan) for c in cells[:-1]] + [rho]
    pdata = {k: np.vstack([v, np.zeros((len(pts) - len(v),) + v.shape[1:])])
             for k, v in m.point_data.items()}
    out = meshio.Mesh(pts, cells, point_data=pdata, cell_data=data)
    if fe.static is not None and same_mesh(fe.static.mesh, sol.mesh):
        out = attach_cell_fields(out, fe.static)
        gap = gap_contributions(fe.static, full.solution)  # share of λ⁺ − λ⁻ (virtual power)
        out.cell_data["bracket_gap"] = [gap] + [np.full(len(b.data), np.nan)
                                                for b in out.cells[1:]]
    elif fe.static is not None:
        notes["static"] = ("the static bound lives on another mesh than the mechanism's (its "
                           "own graded mesh, or the adaptive bracket's best lower bound's): "
                           "its stress field is drawn in stress.png, not written here")
    out = _interface_cells(out, prob, sol, scale, notes)
    fields = [*out.point_data, *out.cell_data, "velocity_scale"]
    units = {k: MECHANISM_UNITS.get(k) for k in fields}
    _unknown_units(k for k, u in units.items() if u is None)
    out.field_data = {"velocity_scale": np.array([scale]),
                      "units": json.dumps(units, ensure_ascii=False),
                      "notes": json.dumps(notes, ensure_ascii=False)}
    return out


def _interface_cells(out, prob, sol, scale: float, notes: dict):
    """``out`` with a line block per dissipating interface of ``prob`` (its facets, in the
    solution's facet order): cell fields ``interface`` = 1 and ``interface_dissipation`` (per
    facet, divided by ``scale``); a note for dry interfaces, which dissipate nothing."""
    import meshio

    from ..fe.strength import dissipation_free

    wet = [k for k, d in prob.interfaces.items() if not dissipation_free(d)]
    if prob.interfaces and not wet:
        notes["interface_dissipation"] = NO_INTERFACE_DISSIPATION
    if not wet:
        return out
    mesh = sol.mesh
    nodes = [mesh.facets[:, np.asarray(mesh.boundaries[k])].T for k in wet]
    values = [np.asarray(sol.interface_dissipation[k], float) / scale for k in wet]
    cells = list(out.cells) + [meshio.CellBlock("line", n) for n in nodes]
    data = {}
    for key, blocks in out.cell_data.items():
        fill = 0.0 if key in ("crack", "body") else np.nan
        data[key] = list(blocks) + [np.full((len(n),) + np.shape(blocks[0])[1:], fill)
                                    for n in nodes]
    data["interface"] = [np.zeros(len(c.data)) for c in out.cells] + [np.ones(len(n))
                                                                       for n in nodes]
    data["interface_dissipation"] = [np.full(len(c.data), np.nan) for c in out.cells] + values
    return meshio.Mesh(out.points, cells, point_data=dict(out.point_data), cell_data=data)
