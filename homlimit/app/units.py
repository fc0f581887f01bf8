"""The unit of every quantity a result file carries, once (``UNITS``), and the unit tables
the writers put in every JSON file and CSV sidecar: summary.json's by section
(``units_table``), other files' by key (``units_of``), a CSV column's header ``name [unit]``
(``csv_header``). The files themselves: ``app.writers.OUTPUTS``.
"""

from __future__ import annotations

import functools
import logging
from collections.abc import Mapping

from ..errors import ParameterError
from .schema import SCHEMA, TOP_LEVEL

__all__ = ["UNITS", "column_unit", "csv_header", "input_units", "unknown_units",
           "units_of", "units_table"]

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
    "W_m": "J", "m": "kg", "I_O": "kg m^2", "J_z": "kg m^2",
    # the code check (app.code_check, check.ntc, check.site)
    **dict.fromkeys("alpha0 e_star e_star_lumped psi_Z gamma_N ratio_lumped S_S C_C S_T S"
                    .split(), "-"),
    **dict.fromkeys("a0_star a0_star_lumped demand demand_ground demand_height Se_T1"
                    .split(), "m/s^2"),
    **dict.fromkeys("T_B T_C T_D first_period".split(), "s"),
    "M_star": "kg", "Z": "m", "H_building": "m", "vg_over_pgv": "-",   # pgv: the DEM's m/s
    "impulse_reading": "", "impulse": "", "m_floors": "kg",
    **dict.fromkeys("floors_Qk floors_Qk_reading not_computed".split(), ""),
    **dict.fromkeys("dk0 d0_star du_star ds_star SDe_Ts d_SLV SDe_SLV".split(), "m"),
    **dict.fromkeys("as_star a_SLV".split(), "m/s^2"), "Ts": "s", "T_SLV": "s",
    "theta0": "rad", "xi_SLV": "%", "ratio_SLV": "-",
    **dict.fromkeys("nonlinear nonlinear_reading".split(), ""),
    **dict.fromkeys("what passes governing not_checked e_star_reading alpha0_reading "
                    "demand_reading source_reading".split(), ""),
    "omega": "1/s", "p": "rad/s", "period": "s",
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
    # the crushing and the bond's (cohesion, tension) dissipation rates of the mechanism,
    # the parts of W(θ_m)
    "tie_force": "N", "crushing_rate": "W", "bond_rate": "W", "W_crushing": "J",
    "W_floors": "J", "W_ties": "J",
    "loads_rule": "",                 # the FE path's summary: how ties and floors enter W
    "N": "N", "T": "N",              # contact forces per slab of thickness s (blocks.limit)
    "opening": "m/s", "slip": "m/s",  # velocity jumps of the normalised mechanism
    # homlimit verify and the adaptive bracket (verify.json, verify.csv, fe_adapt.csv)
    **dict.fromkeys("problem source stop holds converged kind mechanism_stop".split(), ""),
    **dict.fromkeys("lower upper best_lower best_upper exact_lo exact_hi rel_gap lower_err "
                    "upper_err triangles cycles cycle T1 T2 T_mid T1_exact T2_exact f c_over_a "
                    "sqrt_cf_a".split(), "-"),
    "z0_exact": "m", "hinge_z": "m", "seconds": "s",
    "mesh_seconds": "s", "T_mid_exact": "-",
    "crack_change": "", "over": "", "resolution": "-",   # summary fe.crack_change
    # the ray-conforming search (mechanism.conform; verify.json "conform", crack_study.csv)
    **dict.fromkeys("conformed T1_rays T2_rays trials stress_degree conform_multiplier "
                    "conform_T1 conform_T2 conform_T_mid conform_trials".split(), "-"),
    **dict.fromkeys("z_h conform_hinge_z".split(), "m"), "conform_seconds": "s",
    "adapt": "",                     # summary fe.adapt: the cycles' table, units per column
    # the rigid-block DEM (summary "dem", table1_dem.csv; app.dem_stage)
    **dict.fromkeys("vg_lo vg_hi vg_udec pgv".split(), "m/s"),
    **dict.fromkeys("pga_lo pga_hi".split(), "m/s^2"),
    **dict.fromkeys("h_udec base_slip hinge_slip".split(), "m"),
    **dict.fromkeys("pulse_period t_end cpu dt settle_time".split(), "s"),
    **dict.fromkeys("vnorm_udec dem_over_udec rel_tol n_trials n_blocks joint_segments "
                     "joint_points".split(), "-"),
    **dict.fromkeys("loading base_slid hinge_slid collapsed settle_converged exact".split(),
                    ""),
    # real walls (issue 30; closed_form.real, docs/real-walls.md)
    **dict.fromkeys("fc cohesion tension tension_effective peak_compression".split(), "Pa"),
    "fc_rule": "", "bond_rule": "", "vg_unavailable": "",   # the FE path with a cohesion
    **dict.fromkeys("yield_force load".split(), "N/m"),
    "stiffness": "N/m^2", "normal_force": "N",
    **dict.fromkeys("ductility eccentricity hinge_retreat tie_elongation".split(), "m"),
    **dict.fromkeys("restrains kind fc_infinite choices per_metre floor_mass hinge_rule tie_law "
                    "abutment_friction_I".split(), ""),
}
def csv_header(key: str) -> str:
    """The CSV header of a column: ``key [unit]`` (``key`` for text); ParameterError if the
    quantity has no unit in ``UNITS``."""
    if key not in UNITS:
        raise ParameterError(f"column = {key!r} is out of range: allowed a quantity of "
                             "report.UNITS (give it its unit there)")
    return f"{key} [{UNITS[key]}]" if UNITS[key] else key


def unknown_units(keys) -> list[str]:
    """Keys without a unit in UNITS, logged: a result file is still written (their CSV header
    ``key [?]``, their unit null), the tests require every key to have one."""
    missing = sorted(set(keys) - set(UNITS))
    if missing:
        logging.getLogger(__name__).warning("no unit registered for %s (report.UNITS)",
                                            ", ".join(missing))
    return missing



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
    unknown_units(found)
    return {k: UNITS.get(k) for k in sorted(found)}


def units_table(summary: Mapping) -> dict:
    """The ``units`` table of summary.json: the unit of every case-file key (by section) and of
    every result quantity the summary holds (by name; "-" dimensionless, "" text)."""
    inputs = {sec: dict(u) if isinstance(u, dict) else u for sec, u in input_units().items()}
    found: set[str] = set()
    for k in ("derived", "mechanisms", "hinges", "fe", "critical", "dem_table1", "dem",
              "code_check"):
        found |= _leaf_keys(summary.get(k))
    unknown_units(found)
    return {"inputs": inputs, "results": {k: UNITS.get(k) for k in sorted(found)},
            "timings_s": "s"}

