"""The case file's keys: one ``Key`` (``app.schema_key``) per key of every section, the single
source of truth for reading case files (``app.config``), checking them (``app.case_checks``)
and their documentation (``app.schema_doc``: ``schema_markdown`` → docs/case-file.md); the
[dem] section's keys live in ``app.schema_dem``.

SCHEMA: section → key → Key; ARRAYS: the arrays of tables ([[tie]], [[floor]]); TOP_LEVEL: the
keys outside any section (the case name).
"""

from __future__ import annotations

from ..blocks.geometry import FACADE_BONDS
from ..check.site import SOILS, TOPOGRAPHIES, Site
from ..dynamics.pulses import PULSE_KINDS, MavroeidisPapageorgiouPulse
from ..dynamics.rocking import RigidRocker
from ..fields import default_of
from ..params import (
    FACADE_DEFAULT,
    FACADE_MODELS,
    MESHER_DEFAULT,
    MESHERS,
    PART_DIVISIONS,
    Floor,
    Masonry,
    Tie,
    Wall,
)
from . import budget, registry
from .schema_dem import DEM_KEYS
from .schema_key import REQUIRED, Key

__all__ = ["ARRAYS", "MAX_ARRAY", "OPTIONAL_SECTIONS", "REQUIRED", "REQUIRED_SECTIONS", "SCHEMA",
           "TOP_LEVEL", "Key"]


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
        "gamma": Key(float, default_of(Wall, "gamma"), "kg/m³", 1.0, 1e5, typical=(1000.0, 3000.0),
                     doc="mass density of masonry γ"),
        "g": Key(float, default_of(Wall, "g"), "m/s²", 1e-2, 1e3, typical=(9.7, 9.9),
                 doc="gravitational acceleration"),
    },
    "masonry": {
        "a": Key(float, **_len(1e3, (0.03, 1.0)), doc="block height (a <= H)"),
        "c": Key(float, **_len(1e3, (0.03, 1.5)), doc="half block length (2c <= L)"),
        "f": Key(float, unit="", lo=1e-3, hi=100.0, typical=(0.3, 1.0),
                 doc="joint friction coefficient (α = √(cf/a), eq. 11)"),
        "fc": Key(float, default_of(Masonry, "fc"), "Pa", 0.0, 1e10,
                  doc="compressive strength of the masonry; 0 means infinite (the paper's "
                      "rigid blocks). Finite: the hinge of every closed form retreats to the "
                      "resultant of a rectangular stress block, t = N/(2 fc l), and a finite "
                      "fc below N/(b l) of the smallest part (λ = 0.5: γ g b/2 on a plain "
                      "wall) is refused, the bound named; both FE "
                      "bounds cap the principal compressive stress at fc; the rigid blocks "
                      "cap every contact at fc (docs/real-walls.md); the DEM caps every "
                      "contact point's normal spring at fc × tributary × depth, on points "
                      "along the bed joints ([dem] joint_segments; docs/dem.md)"),
        "cohesion": Key(float, default_of(Masonry, "cohesion"), "Pa", 0.0, 1e10,
                        doc="cohesion of the joints (the strength domains' name); both FE "
                            "bounds ([analysis] fe: the bracket, the mechanism) and the rigid "
                            "blocks' limit analysis ([analysis] blocks, associative) take it, "
                            "their v̄_g is then not available; the closed forms, the DEM and "
                            "the rockers refuse a non-zero value (docs/real-walls.md)"),
        "tension": Key(float, default_of(Masonry, "tension"), "Pa", 0.0, 1e10,
                       doc="tensile strength of the joints (the strength domains' name), "
                           "acting up to the Coulomb apex cohesion/f (none without a "
                           "cohesion); taken and refused as cohesion (docs/real-walls.md)"),
    },
    "mesh": {
        "size": Key(float, 0.25, "m", 0.0, 1e4, lo_open=True,
                    doc="element spacing of the T-section mesh along z, and in the wall far "
                        "from the junction (homlimit.fe.problems.t_section h; the wall graded "
                        "towards the junction). Across the façade (crossed, gmsh-strip): 4 "
                        "equal columns on the FE scan's parts and on homlimit mesh's mesh; "
                        "with outer_ratio > 0, the whole wall's bracket (gmsh-strip's "
                        "adaptive chain, both bounds; else the static bound's copy) has "
                        "columns graded to size/outer_ratio at the outer face (B1: 9 columns "
                        "from 1 cm, homlimit.fe.geometry.graded_columns(0.5, 0.01)); "
                        "size <= min(H, b + L)"),
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
                          "\"gmsh-strip\" (the default: gmsh with the façade strip a crossed "
                          "grid of 4 columns or more, x-aligned so the bed-joint façade does "
                          "not lock, the wall unstructured; docs/kinematic.md)"),
        "outer_ratio": Key(float, 25.0, "", 0.0, 1000.0,
                           doc="the static bound's mesh (gmsh-strip: the adaptive chain's "
                               "one mesh of both bounds, or with [adapt] max_cycles = 1 a "
                               "graded copy, as on the crossed grid; 0: equal columns): the "
                               "façade's columns graded to a "
                               "width of size/outer_ratio at the outer face, where an "
                               "overturning façade bears (docs/static.md, \"The outer "
                               "face\"; measured on B1: 25 keeps the columns' aspect "
                               "ratio where linear and quadratic stresses agree)"),
    },
    "adapt": {
        "target_gap": Key(float, 0.01, "", 0.0, 1.0, lo_open=True,
                          doc="adaptive bracket of the whole wall (gmsh meshers): stop when "
                              "(λ⁺ − λ⁻)/mean <= target_gap (homlimit.fe.adapt)"),
        "max_cycles": Key(int, 3, "", 1, 50, doc="at most this many meshes of the adaptive "
                          "bracket (1: one; each gmsh-strip cycle halves the strip's rows)"),
        "min_size": Key(float, 0.005, "m", 0.0, 1e4, lo_open=True,
                        doc="no element of the adaptive bracket is asked to be smaller"),
        "conform": Key(bool, True, doc="homogenised façade: each cycle also searches λ⁺ over "
                       "meshes conforming to a hinge + fan, the crack resolved (docs/adaptive.md)"),
        "crack_cycles": Key(int, 3, "", 0, 20,
                            doc="after the bracket (where the fan search does not run): at "
                                "most this many nested splits of the crack's band, λ⁺ only, "
                                "until the crack settles (0: none; docs/adaptive.md)"),
        "crack_tol": Key(float, 0.01, "", 0.0, 1.0, lo_open=True,
                         doc="the crack has settled when its fan edges and mid-line each "
                             "move by at most this (relative) over the last split"),
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
        "stress_degree": Key(int, 1, "", lo=1, hi=2,
                             doc="degree of the static bound's stresses: 1 (linear) or 2 "
                                 "(quadratic, Bernstein form: a higher λ⁻ on the same mesh for "
                                 "about twice its seconds; docs/static.md)"),
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
                                           "sweeps). A real wall: every rocker (the FE "
                                           "body's too) takes fc, ties, floors; cohesion, "
                                           "tension refused"),
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
    "dem": DEM_KEYS,
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
                              "first: its critical body, rigid or one-DOF). A real wall: I, "
                              "II, overturning take fc, ties, floors (docs/real-walls.md "
                              "\"Rockers\"), FE only fc"),
        "gravity_I": Key(str, "linearised", choices=("linearised", "exact"),
                         doc="mechanism I's gravity: as eq. 10 (linearised) or exact"),
        "restitution": Key.of(RigidRocker, "restitution",
                              doc="coefficient of restitution at re-seating (0: the body "
                                  "stays seated)"),
        "rtol": Key(float, 1e-6, "", 1e-13, 1e-2, lo_open=False,
                    doc="relative tolerance of the threshold amplitude (brentq)"),
        "scan_ratio": Key(float, 1.05, "", 1.0, 10.0, lo_open=True,
                          doc="amplitude step of the search from lift-off to overturning"),
        "gamma": Key.of(MavroeidisPapageorgiouPulse, "gamma",
                        doc="Mavroeidis–Papageorgiou oscillation parameter γ (kind mp)"),
        "nu": Key.of(MavroeidisPapageorgiouPulse, "nu",
                     doc="Mavroeidis–Papageorgiou phase ν (kind mp)"),
        "record": Key(str, "", doc="a ground-acceleration record, two-column CSV t [s], "
                                   "a_g [m/s²] (relative to the case file): its critical "
                                   "scale per mechanism"),
    },
    "site": {
        "ag": Key.of(Site, "ag", required=True, unit="m/s²",
                     doc="a_g on rigid soil of the limit state checked, in m/s² (a_g/g × g)"),
        "F0": Key.of(Site, "F0", required=True,
                     doc="largest spectral amplification F₀ of the same hazard"),
        "Tc_star": Key.of(Site, "Tc_star", required=True,
                          doc="T_C* of the same hazard (the constant-velocity branch's start)"),
        "soil": Key(str, default_of(Site, "soil"), choices=tuple(SOILS),
                    doc="soil category (NTC 2018 Tab. 3.2.IV)"),
        "topography": Key(str, default_of(Site, "topography"), choices=tuple(TOPOGRAPHIES),
                          doc="topographic category (S_T at the relief's top: Tab. 3.2.V)"),
        "q": Key.of(Site, "q", doc="behaviour factor of the kinematic check (§C8.7.1.2: 2.0)"),
        "FC": Key.of(Site, "FC", doc="confidence factor (knowledge levels LC1/2/3: 1.35/1.2/1)"),
        "T1": Key.of(Site, "T1", doc="the building's first period T₁ (0: 0.05 H^(3/4), masonry)"),
        "building_height": Key.of(Site, "building_height", doc="the building's height H (0: "
                                  "the wall's top, z_base + [wall] H); ψ(Z) = Z/H"),
        "storeys": Key(int, default_of(Site, "storeys"), "", 1, 200,
                       doc="number of storeys N (γ = 3N/(2N + 1))"),
        "z_base": Key.of(Site, "z_base", doc="the wall's base above the ground: a mechanism's "
                                             "base is at Z = z_base + its hinge's height"),
    },
    "output": {
        "dir": Key(str, "", doc="output folder (empty: homlimit-out/<name>/; --out overrides)"),
        "json": Key(bool, True, doc="write summary.json (every input, result, version)"),
        "png": Key(bool, True, doc="write the PNG pictures"),
        "vtu": Key(bool, True, doc="write the mesh and mechanism as .vtu (ParaView)"),
        "report": Key(bool, False, doc="write report.html: one self-contained page of the "
                                       "run (inputs with units, the pictures embedded, the "
                                       "multipliers and collapse velocities, the code check "
                                       "with a [site], the version; docs/report.md)"),
    },
}
#: arrays of tables ([[tie]], [[floor]], [[facade_opening]], [[wall_opening]]): name -> key
#: -> Key, each entry validated like a section; a sweep or --set addresses an entry's key as
#: tie.0.yield_force
ARRAYS: dict[str, dict[str, Key]] = {
    "tie": {
        "z": Key(float, unit="m", lo=0.0, hi=1e4, lo_open=True,
                 doc="height of the tie above the ground (0 < z <= H)"),
        "yield_force": Key(float, unit="N/m", lo=0.0, hi=1e9,
                           doc="yield force per metre of façade (a bay of length l carries "
                               "yield_force·l)"),
        "stiffness": Key(float, default_of(Tie, "stiffness"), "N/m²", 0.0, 1e15,
                         doc="axial stiffness per metre of façade (force per metre per metre "
                             "of elongation); 0: rigid-plastic"),
        "ductility": Key(float, default_of(Tie, "ductility"), "m", 0.0, 1e3,
                         doc="elongation at which the tie breaks (0: it yields without limit)"),
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
        "restrains": Key(bool, default_of(Floor, "restrains"),
                         doc="the floor holds the façade horizontally at z: a failing body "
                             "lies above it"),
    },
    "facade_opening": {
        "z_bottom": Key(float, unit="m", lo=0.0, hi=1e4,
                        doc="bottom of a band of openings in the façade (windows, doors), "
                            "above the ground"),
        "z_top": Key(float, unit="m", lo=0.0, hi=1e4, lo_open=True,
                     doc="top of the band (z_bottom < z_top <= H; bands disjoint)"),
        "fraction": Key(float, unit="", lo=0.0, hi=1.0, hi_open=True,
                        doc="the part of the façade's length l that is open over the band "
                            "(0 <= fraction < 1): the façade's weight and mass there scale by "
                            "1 − fraction in every model, its strength does not "
                            "(docs/real-walls.md \"Openings\")"),
    },
    "wall_opening": {
        "x": Key(float, unit="m", lo=0.0, hi=1e4, lo_open=True,
                 doc="left edge of a rectangular opening in the transversal wall, from the "
                     "façade's outer face (b < x)"),
        "z": Key(float, unit="m", lo=0.0, hi=1e4, lo_open=True,
                 doc="bottom edge of the opening above the ground (0 < z)"),
        "width": Key(float, unit="m", lo=0.0, hi=1e4, lo_open=True,
                     doc="its width along x (x + width < b + L)"),
        "height": Key(float, unit="m", lo=0.0, hi=1e4, lo_open=True,
                      doc="its height along z (z + height < H); openings must not overlap or "
                          "touch. The closed forms take it in mechanism II's wedge, the FE "
                          "as a hole under a rigid lintel, the blocks as courses cut under "
                          "a lintel block, the DEM on the blocks' assembly (a jamb must not "
                          "leave it a piece thinner than [dem] verlet_margin) "
                          "(docs/real-walls.md \"Openings\")"),
    },
}
MAX_ARRAY = 100                   # entries of a [[tie]], [[floor]], ... array
REQUIRED_SECTIONS = ("wall", "masonry")
#: sections that exist only when the case file has them (the code check runs with [site])
OPTIONAL_SECTIONS = ("site",)
TOP_LEVEL = {"name": Key(str, "", doc="case name, used in titles and the output folder "
                                      "(empty: the file's stem; at most 100 characters, no "
                                      "control characters; the folder name keeps letters, "
                                      "digits and -_.+ only)")}
