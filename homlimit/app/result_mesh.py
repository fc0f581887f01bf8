"""The result meshes: the whole wall's mechanism as a meshio mesh for ParaView
(mechanism.vtu), its fields' units (``MECHANISM_UNITS``) and the notes on the fields left out;
the static bound's stress field on its own mesh (static.vtu) where the mechanism's differs.
"""

from __future__ import annotations

import json

import numpy as np

from .units import unknown_units

__all__ = ["MECHANISM_UNITS", "NO_DISSIPATION", "NO_INTERFACE_DISSIPATION", "interface_cells",
           "mechanism_mesh", "static_mesh"]


#: the unit of every field of static.vtu (``StaticSolution.to_meshio``); mechanism.vtu carries
#: the same fields, prefixed "static_", where both bounds share its mesh
STATIC_UNITS: dict[str, str] = {
    **dict.fromkeys(("sigma_x", "sigma_z", "tau_xz", "sigma_1", "sigma_2"), "Pa"),
    "compression_angle": "rad", "active_facet": "", "lower_bound": "-"}

#: the unit of every field of mechanism.vtu ("-": dimensionless, "": a tag or a flag). The
#: mechanism's amplitude is arbitrary: velocity is v / velocity_scale, and the fields linear in
#: it are divided by velocity_scale [m/s] too: intensity [1/s] / [m/s] = 1/m, dissipation
#: [W/m] / [m/s] = N/m (per unit thickness, per triangle or per interface facet)
MECHANISM_UNITS: dict[str, str] = {
    "velocity": "-", "velocity_scale": "m/s", "intensity": "1/m", "dissipation": "N/m",
    "interface_dissipation": "N/m", "region": "", "stress": "Pa", "participation": "-",
    "label": "", "crack": "", "body": "", "density": "kg/m^2", "interface": "",
    **{f"static_{k}": u for k, u in STATIC_UNITS.items() if k != "lower_bound"},
    "bracket_gap": "-"}

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
                           "its stress field is in static.vtu and stress.png, not here")
    out = interface_cells(out, prob, sol, scale, notes)
    fields = [*out.point_data, *out.cell_data, "velocity_scale"]
    units = {k: MECHANISM_UNITS.get(k) for k in fields}
    unknown_units(k for k, u in units.items() if u is None)
    out.field_data = {"velocity_scale": np.array([scale]),
                      "units": json.dumps(units, ensure_ascii=False),
                      "notes": json.dumps(notes, ensure_ascii=False)}
    return out


def static_mesh(static):
    """The static bound's field on its own mesh for ParaView (``StaticSolution.to_meshio``:
    three points per triangle, so its jumps show): vertex stresses σ_x, σ_z, τ_xz [Pa] and
    the active facet as point data, the triangle means and principal stresses as cell data;
    field data ``lower_bound`` (λ⁻) and ``units``. The section plane is X–Y (X = x, Y = z)."""
    out = static.to_meshio()
    fields = [*out.point_data, *out.cell_data, "lower_bound"]
    units = {k: STATIC_UNITS.get(k) for k in fields}
    unknown_units(k for k, u in units.items() if u is None)
    out.field_data = {"lower_bound": np.array([float(static.multiplier)]),
                      "units": json.dumps(units, ensure_ascii=False)}
    return out


def interface_cells(out, prob, sol, scale: float, notes: dict):
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
