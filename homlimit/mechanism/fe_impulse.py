"""From a finite-element mechanism to the failing body, its crack and the collapse ground velocity.

Glue between the kinematic solver (``homlimit.fe.kinematic``), the rigid fit (``rigidfit``), the
crack measurement (``crack``), the closed-form hinge + fan (``fan``) and the impulse criterion
(``impulse``, eqs 4–7).

One-degree-of-freedom generalisation of eqs 4–7. The FE mechanism is a shape φ(x) = v(x)/ω
(unit rotation rate of the fitted block about O). With q the block's rotation angle and the
whole structure moving as q φ relative to the ground:
- kinetic energy ½ M q̇², generalised mass M = ∫ρ|φ|² dA (for a rigid body M = I_O);
- the impulse v_g (ground moving +x, the structure's inertia pushing −x) gives
  M q̇0 = v_g ∫ρ(−φ_x) dA  (eq. 4; for a rigid body ∫ρ(−φ_x) = m z_G);
- restoring work W(q): the body inside the 50 % participation line (the paper's crack, as
  ``fe_body``) rotates by q about O exactly, W_b = m_b g (x_G sin q + z_G cos q − z_G); every
  other moving element (the outer half of a fan, a smeared crack) is carried to first order,
  W_r = q g ∫_rest ρ φ_z (its dilatant lift);
- the mechanism tips over when the block's G passes over the vertical through O,
  q_m = atan(x_G/z_G), where W_b = m_b g (r_G − z_G) (eq. 18). (The linearised W_r never stops
  growing, so W itself has no peak: a fan's dilatant lift is bounded in real masonry by the
  block size, which the homogenised model does not see.)
- collapse when ½ M q̇0² >= W(q_m), whence (eq. 7)

      v̄_g = √(2 W(q_m) M) / ∫ρ(−φ_x) dA.

What this neglects: the fan's geometry change at finite rotation (its lift is linearised,
and its share of M and W is reported), any dissipation (none in the homogenised model), and
a change of mechanism during the motion. For a rigid mechanism (no deforming zone) it is eq. 7
with eq. 18 exactly. ``fe_body`` gives the other bracket: the rigid body bounded by the 50 %
participation line, fed to eq. 7 + eq. 18 (fan mass split at its mid-line, fan lift ignored).
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
from skfem import Basis, ElementTriP2

from ..closed_form.fan import optimise_fan
from ..errors import ParameterError, check_range
from ..impulse.body import RigidBody
from ..impulse.criterion import collapse_velocity
from ..params import Case
from .crack import fan_edges, mechanism_type
from .rigidfit import measure_mechanism, p2_energy

__all__ = ["p2_nodes", "ray_conforming_mesh", "GeneralisedImpulse", "generalised_impulse",
           "fe_body", "analyse", "fe_mechanism", "h_scan"]


def p2_nodes(solution, densities: dict | None = None):
    """P2 nodes of a KinematicSolution: positions X (n, 2), velocities V (n, 2), triangles
    (n_el, 6) in scikit-fem's P2 order, and per-triangle densities (from ``densities``:
    region → mass per unit area, default 1)."""
    mesh = solution.mesh
    sb = Basis(mesh, ElementTriP2())
    X = sb.doflocs.T.copy()
    V = np.asarray(solution.u, float).reshape(-1, 2)  # vector P2 DOFs interleave (x, z)
    rho = np.ones(mesh.t.shape[1])
    for name, idx in (densities or {}).items():
        rho[solution.regions[name]] = idx
    return X, V, sb.element_dofs.T.copy(), rho


def ray_conforming_mesh(case, z_hinge: float, slopes, h: float, z0: float = 0.0,
                        h_hinge: float | None = None, x_apex: float = 0.0,
                        extra_lines=()):
    """A T-section mesh (gmsh, unstructured) whose edges contain the rays
    x − x_apex = T (z − z_hinge) from (x_apex, z_hinge) (default: the hinge on the façade's
    outer face; x_apex = b: mechanism II's crack from the inner corner), one per slope T, and
    the façade / wall interface x = b; extra_lines: more segments ((x0, z0), (x1, z1)) for the
    mesh to contain (e.g. mechanism II's bed-joint crack under the façade). Returns a
    scikit-fem MeshTri with the boundaries ("base", "outer", "top", "end") and subdomains
    ("facade", "wall") of ``problems.t_section``.

    This is the adapter the conforming-mesh checks use until ``geometry.tsection`` offers
    embedded lines; h_hinge: element size at the hinge (default h/4).
    """
    import gmsh
    from skfem import MeshTri

    w = case.wall
    b, L, H = w.b, w.L, w.H
    z0 = check_range("z0", z0, 0.0, H, hi_open=True, unit="m")
    z_hinge = check_range("z_hinge", z_hinge, z0, H, hi_open=True, unit="m")
    h = check_range("h", h, 0.0, H - z0, lo_open=True, unit="m")
    h_hinge = h / 4 if h_hinge is None else check_range("h_hinge", h_hinge, 0.0, h,
                                                         lo_open=True, unit="m")
    slopes = [check_range("slope", T, 0.0, lo_open=True) for T in slopes]
    gmsh.initialize()
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.model.add("t_section_rays")
        occ = gmsh.model.occ
        r1 = occ.addRectangle(0, z0, 0, b, H - z0)
        r2 = occ.addRectangle(b, z0, 0, L, H - z0)
        x_apex = check_range("x_apex", x_apex, 0.0, b, unit="m")
        ph = occ.addPoint(x_apex, z_hinge, 0)
        lines = []
        for T in slopes:
            ze = min(H, z_hinge + (b + L - x_apex) / T)
            lines.append(occ.addLine(ph, occ.addPoint(x_apex + T * (ze - z_hinge), ze, 0)))
        for (xa, za), (xb, zb) in extra_lines:
            lines.append(occ.addLine(occ.addPoint(xa, za, 0), occ.addPoint(xb, zb, 0)))
        occ.fragment([(2, r1), (2, r2)], [(1, ln) for ln in lines])
        occ.synchronize()
        gmsh.option.setNumber("Mesh.MeshSizeMax", h)
        gmsh.option.setNumber("Mesh.MeshSizeFromPoints", 0)
        gmsh.option.setNumber("Mesh.MeshSizeExtendFromBoundary", 0)
        f = gmsh.model.mesh.field
        fd = f.add("Distance")
        hinge = [t for d, t in gmsh.model.getEntities(0)
                 if np.allclose(gmsh.model.getValue(0, t, []), [x_apex, z_hinge, 0])]
        f.setNumbers(fd, "PointsList", hinge)
        ft = f.add("Threshold")
        f.setNumber(ft, "InField", fd)
        f.setNumber(ft, "SizeMin", h_hinge)
        f.setNumber(ft, "SizeMax", h)
        f.setNumber(ft, "DistMin", 0.0)
        f.setNumber(ft, "DistMax", 2.0)
        f.setAsBackgroundMesh(ft)
        gmsh.model.mesh.generate(2)
        tags, xyz, _ = gmsh.model.mesh.getNodes()
        etypes, _, enodes = gmsh.model.mesh.getElements(2)
    finally:
        gmsh.finalize()
    index = np.zeros(int(tags.max()) + 1, int)
    index[tags.astype(int)] = np.arange(len(tags))
    t = index[np.asarray(enodes[list(etypes).index(2)], int).reshape(-1, 3)]
    p = xyz.reshape(-1, 3)[:, :2]
    used = np.unique(t)
    remap = np.full(len(p), -1)
    remap[used] = np.arange(len(used))
    m = MeshTri(p[used].T.copy(), remap[t].T.copy())
    tol = 1e-9 * H
    return m.with_boundaries({
        "base": lambda x: np.abs(x[1] - z0) < tol,
        "outer": lambda x: np.abs(x[0]) < tol,
        "top": lambda x: np.abs(x[1] - H) < tol,
        "end": lambda x: np.abs(x[0] - (b + L)) < tol,
    }).with_subdomains({"facade": lambda x: x[0] < b, "wall": lambda x: x[0] > b})


def _p2_integral(elements, area, density, F):
    """∫ρ F dA of a P2 scalar field per element (vertex functions integrate to 0, edge ones to
    A/3)."""
    Fe = np.asarray(F, float)[np.asarray(elements, int)]
    return np.asarray(density, float) * area * Fe[:, 3:].sum(axis=1) / 3.0


@dataclasses.dataclass(frozen=True)
class GeneralisedImpulse:
    """The one-degree-of-freedom impulse criterion of a mechanism shape φ (module docstring).

    M [kg m²], Pi = ∫ρ(−φ_x) [kg m], W_m [J] restoring work at the tipping angle q_m [rad],
    vg [m/s];
    block: the RigidBody inside the 50 % line; M_rest_share, W_rest_share: the linearised
    rest's shares of M and of W(q_m).
    """

    M: float
    Pi: float
    W_m: float
    q_m: float
    vg: float
    block: RigidBody | None
    M_rest_share: float
    W_rest_share: float


def generalised_impulse(X, V, elements, density, mm, g: float = 9.81,
                        block: np.ndarray | None = None) -> GeneralisedImpulse:
    """v̄_g of the P2 mechanism (X, V, elements, density) with its fit ``mm`` (eqs 4–7
    generalised; see the module docstring). ``block``: element mask of the part whose
    restoring work is taken at finite rotation (default: the moving elements of mean
    participation >= 1/2, the body bounded by the 50 % line, as ``fe_body``)."""
    g = check_range("g", g, 0.0, lo_open=True, unit="m/s^2")
    el = np.asarray(elements, int)
    phi = np.asarray(V, float) / mm.fit.omega
    rho = np.broadcast_to(np.asarray(density, float), (len(el),))
    e1, e2 = X[el[:, 1]] - X[el[:, 0]], X[el[:, 2]] - X[el[:, 0]]
    area = 0.5 * np.abs(e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0])
    blk = _body_mask(mm) if block is None else np.asarray(block, bool)
    e = p2_energy(el, area, rho, phi)
    M = float(e.sum())
    Pi = float(_p2_integral(el, area, rho, -phi[:, 0]).sum())
    rest = ~blk & (mm.label != 0)
    lift_rest = g * float(_p2_integral(el[rest], area[rest], rho[rest], phi[:, 1]).sum())
    body = None
    if blk.any():
        body = RigidBody.from_triangles(X, el[blk, :3], rho[blk], O=mm.fit.O)

    if body is None or body.x_G <= 0:
        raise ParameterError("block = None is out of range: the mechanism has no rigid block "
                             "with a restoring lever (x_G > 0), allowed a block about O")
    # the block tips over when G passes over the vertical through O (eq. 18)
    q_m = math.atan2(body.x_G, body.z_G)
    W_b = body.m * g * (body.r_G - body.z_G)
    W_m = W_b + q_m * lift_rest
    vg = math.sqrt(2.0 * W_m * M) / Pi
    return GeneralisedImpulse(M, Pi, W_m, q_m, vg, body, float(e[rest].sum()) / M,
                              q_m * lift_rest / W_m)


def _body_mask(mm, level: float = 0.5) -> np.ndarray:
    """Moving elements of mean participation >= level (elements at O belong to the body)."""
    return (np.nan_to_num(mm.participation, nan=1.0) >= level) & (mm.label != 0)


def fe_body(X, elements, density, mm, level: float = 0.5) -> RigidBody:
    """The rigid body bounded by the ``level`` participation line: the triangles whose mean
    participation is at least ``level``, about the fitted O, integrated exactly."""
    el = np.asarray(elements, int)
    sel = _body_mask(mm, level)
    rho = np.broadcast_to(np.asarray(density, float), (len(el),))
    return RigidBody.from_triangles(X, el[sel, :3], rho[sel], O=mm.fit.O)


def analyse(case: Case, mesh_size: float = 0.25, facade: str = "homogenised", z0: float = 0.0,
            mesh=None, options=None, drawing: bool = False) -> dict:
    """FE mechanism of the part above z0 (base fixed at z0): multiplier, rigid fit, crack,
    mechanism type, body and v̄_g. Returns plain data (see ``fe_mechanism`` for the keys).

    drawing: add ``out["drawing"]`` for ``plots.plot_mechanism``: points, triangles and
    velocity at the mesh vertices, the 50 % line ``crack``, the 10 % and 90 % lines
    ``crack_edges`` (polylines) and the ``hinge``; and ``out["solution"]`` (the
    KinematicSolution, e.g. for ``write_vtu``)."""
    from ..fe.kinematic import solve_kinematic
    from ..fe.problems import t_section
    from ..fe.solver import SolverOptions

    w = case.wall
    prob = t_section(case, z0=z0, facade=facade, h=mesh_size)
    if mesh is not None:
        prob = dataclasses.replace(prob, mesh=mesh)
    sol = solve_kinematic(prob, options or SolverOptions())
    X, V, el, rho = p2_nodes(sol, {"facade": case.rho * w.gamma * w.s,
                                   "wall": w.gamma * w.s})
    mm = measure_mechanism(X, V, el, rho)
    fe = fan_edges(X, el, mm, w.b, z_top=w.H) if mm.kind != "distributed" else None
    kind = mechanism_type(mm, fe)
    out = {"multiplier_fe": sol.multiplier, "z0": z0, "facade": facade,
           "mesh_size": mesh_size, "n_triangles": int(prob.n_triangles),
           "O": tuple(mm.fit.O), "omega": mm.fit.omega, "mechanism_fe": kind,
           "explained": mm.explained, "block_share": mm.block_share,
           "interior_share": mm.interior_share, "h": w.H - mm.fit.O[1],
           "lam_fe": (w.H - mm.fit.O[1]) / w.b,
           "tanpsi_fe": fe.T_mid if fe else math.nan,
           "dtanpsi_fe": fe.dT if fe else math.nan,
           "tanpsi_fe_edges": (fe.T1, fe.T2) if fe else (math.nan, math.nan),
           "solve_time": sol.times.get("total", math.nan)}
    if fe is not None and fe.sharp:
        out["tanpsi_fe_edges"] = (fe.T_mid, fe.T_mid)
    try:
        gi = generalised_impulse(X, V, el, rho, mm, g=w.g)
        body50 = fe_body(X, el, rho, mm)
        v_rigid = collapse_velocity(body50, g=w.g)
        out.update({"vg_generalised": gi.vg, "vg_rigid50": v_rigid,
                    "M_rest_share": gi.M_rest_share, "W_rest_share": gi.W_rest_share,
                    "body50": dataclasses.asdict(body50)})
        # a sharp crack: the body inside its 50 % line, eqs 7 + 18 (the limit of the one-DOF
        # value as the smeared band thins); a fan: the one-DOF generalisation, fan included
        if kind == "rigid":
            out["vg_fe"] = v_rigid
            out["vg_method"] = "eq. 7 + eq. 18, body inside the 50 % participation line"
        else:
            out["vg_fe"] = gi.vg
            out["vg_method"] = ("one-DOF generalisation of eqs 4-7 (fe_impulse docstring): "
                                "body inside the 50 % line at finite rotation, the rest "
                                "linearised")
    except ParameterError as exc:
        out.update({"vg_fe": math.nan, "vg_method": f"not available: {exc}"})
    out["vnorm_fe"] = out["vg_fe"] / math.sqrt(w.g * w.b)
    if drawing:
        lines = fe.lines if fe is not None else {}
        out["drawing"] = {
            "points": sol.mesh.p.T.copy(), "triangles": sol.mesh.t.T.copy(),
            "velocity": sol.velocity, "hinge": tuple(mm.fit.O),
            "crack": lines[0.5].polyline if 0.5 in lines else None,
            "crack_edges": [lines[lv].polyline for lv in (0.1, 0.9) if lv in lines]}
        out["solution"] = sol
    return out


def h_scan(case: Case, lams=None, mesh_size: float = 0.25, facade: str = "homogenised",
           options=None) -> list[dict]:
    """``analyse`` on the part above z0 = H − h for h = λ b, λ in ``lams`` (default: 10 values
    spaced geometrically from λ = 2 to H/b). Each record has the analysed h_part and the
    mechanism's own h = H − z_O (the hinge may float above the base of the analysed part).
    The element size is min(mesh_size, h_part/10), so that short parts stay resolved."""
    w = case.wall
    if lams is None:
        lams = np.geomspace(min(2.0, w.H / w.b), w.H / w.b, 10)
    recs = []
    for lam in lams:
        hp = check_range("lam", lam, 0.0, w.H / w.b, lo_open=True) * w.b
        r = analyse(case, min(mesh_size, hp / 10), facade, z0=max(0.0, w.H - hp),
                    options=options)
        r["h_part"] = hp
        recs.append(r)
    return recs


def fe_mechanism(case: Case, mesh_size: float = 0.25, facade: str = "homogenised",
                 lams=None, options=None, verbose: bool = False) -> dict:
    """The FE columns of Table 1 for ``case``: the h-scan's minimum of v̄_g.

    Keys: lam_fe (critical λ = h/b, with h = H − z_O the height of the failing part above
    the mechanism's hinge), vnorm_fe (v̄_g/√(g b)), vg_fe [m/s], tanpsi_fe
    (the 50 % participation line), tanpsi_fe_edges (block side, fixed side), mechanism_fe
    ("rigid", "hinge+fan", "distributed"), multiplier_fe, h, O, omega, vg_method, scan (all
    records), and the closed-form hinge + fan of the whole wall for comparison (fan_*).
    """
    recs = h_scan(case, lams, mesh_size, facade, options)
    ok = [r for r in recs if np.isfinite(r["vg_fe"])]
    if not ok:
        raise ParameterError(f"facade = {facade!r}: no analysed height gave a v̄_g (see the "
                             "scan's vg_method)")
    best = dict(min(ok, key=lambda r: r["vg_fe"]))
    best["scan"] = [{k: r[k] for k in ("h_part", "h", "multiplier_fe", "vnorm_fe",
                                        "mechanism_fe", "tanpsi_fe")} for r in recs]
    opt = optimise_fan(case, facade=facade)
    best.update({"fan_multiplier": opt.lam, "fan_z0": opt.z0, "fan_T1": opt.T1,
                 "fan_T2": opt.T2, "fan_admissible": opt.admissible})
    if verbose:
        for r in best["scan"]:
            print(f"  h_part = {r['h_part']:.2f} m: h = {r['h']:.2f} m, "
                  f"v/sqrt(gb) = {r['vnorm_fe']:.3f}, {r['mechanism_fe']}")
    return best
