"""Limit-analysis problems: mesh + strength domains + supports + loads, solver-agnostic.

A ``Problem`` says what is to be bounded, not how: a kinematic (upper-bound) or a static
(lower-bound) program can consume the same object. The factories follow cvxpy's test
factories: each returns a problem whose docstring carries the model and the literature value.

Meshes are structured "crossed" meshes (every rectangle cut by its two diagonals into four
triangles, which avoids the locking of incompressible P2 fields on one-diagonal meshes),
graded geometrically towards singular points. Any skfem ``MeshTri`` with named
``subdomains`` and ``boundaries`` can be used instead (``dataclasses.replace(problem, mesh=m)``).
"""

from __future__ import annotations

import dataclasses
import math
import time
from collections.abc import Mapping
from dataclasses import dataclass, field

import numpy as np
from skfem import MeshTri

from ..errors import ParameterError, check_choice, check_range
from ..geometry import REGIONS, TSection
from ..params import FACADE_MODELS, MESHERS, Case
from . import strength
from .geometry import OUTER_GROWTH, tsection
from .mesh import element_areas, to_skfem
from .operators import COMPONENTS

__all__ = [
    "Problem",
    "Rigid",
    "crossed_mesh",
    "graded",
    "prandtl",
    "vertical_cut",
    "mohr_coulomb_footing",
    "free_block",
    "t_section",
    "t_section_on_mesh",
    "MESHERS",
    "PRANDTL",
    "VERTICAL_CUT_LB",
    "VERTICAL_CUT_UB",
    "mohr_coulomb_nc",
]

PRANDTL = 2.0 + math.pi          # q_u / k of a strip footing on weightless Tresca soil
VERTICAL_CUT_LB = 3.7752         # γH/k, best lower bound (Kammoun, Pastor, Smaoui & Pastor 2010)
VERTICAL_CUT_UB = 3.7776         # γH/k, best upper bound (same reference)


def mohr_coulomb_nc(phi_deg: float) -> float:
    """Prandtl–Reissner N_c = (N_q − 1) cot φ, N_q = e^{π tan φ} tan²(45° + φ/2) (exact)."""
    phi = math.radians(check_range("phi_deg", phi_deg, 0.0, 90.0, lo_open=True, hi_open=True))
    nq = math.exp(math.pi * math.tan(phi)) * math.tan(math.pi / 4 + phi / 2) ** 2
    return (nq - 1.0) / math.tan(phi)


@dataclass(frozen=True)
class Problem:
    """What a limit analysis bounds, per unit out-of-plane thickness, SI units.

    mesh           skfem MeshTri with named ``subdomains`` (regions) and ``boundaries``
    domains        region → strength domain (``homlimit.fe.strength``); regions cover every
                   triangle exactly once
    supports       boundary → "fixed" or "xz" (both velocity components zero), "x" or "z" (one)
    interfaces     boundary → strength domain of a joint between the body and a fixed ground
                   (the velocity jump across it is tested by that domain)
    live_body      region → body force (f_x, f_z) [N/m³] scaled by the load multiplier λ
    live_traction  boundary → traction (t_x, t_z) [N/m²] scaled by λ
    dead_body      region → body force [N/m³] kept constant (e.g. self-weight)
    dead_traction  boundary → traction [N/m²] kept constant
    ties           boundary → traction (t_x, t_z) [N/m²] of a tie at its yield force: the tie
                   applies ν·t with 0 <= ν <= 1 free (a bounded force, issue 30). Static: ν a
                   column of the program; kinematic: dissipation max(0, −∫ t·v ds), the
                   largest power the tie can resist
    reference      literature value of λ, if any; ``bounds`` its known (lower, upper) bracket
    meta           free-form facts about the set-up (geometry, mesh time, ...)
    """

    name: str
    mesh: MeshTri
    domains: Mapping[str, object]
    supports: Mapping[str, str] = field(default_factory=dict)
    interfaces: Mapping[str, object] = field(default_factory=dict)
    live_body: Mapping[str, tuple] = field(default_factory=dict)
    live_traction: Mapping[str, tuple] = field(default_factory=dict)
    dead_body: Mapping[str, tuple] = field(default_factory=dict)
    dead_traction: Mapping[str, tuple] = field(default_factory=dict)
    ties: Mapping[str, tuple] = field(default_factory=dict)
    reference: float | None = None
    bounds: tuple[float, float] | None = None
    meta: Mapping[str, object] = field(default_factory=dict)

    def __post_init__(self):
        subs = self.mesh.subdomains or {}
        bnds = self.mesh.boundaries or {}
        for kind, names, have in (("region", self.domains, subs),
                                  ("region", self.live_body, subs),
                                  ("region", self.dead_body, subs),
                                  ("boundary", self.supports, bnds),
                                  ("boundary", self.interfaces, bnds),
                                  ("boundary", self.live_traction, bnds),
                                  ("boundary", self.dead_traction, bnds),
                                  ("boundary", self.ties, bnds)):
            for name in names:
                if name not in have:
                    raise ParameterError(f"{kind} = {name!r} is out of range: the mesh has "
                                         f"{kind}s {sorted(have)}")
        count = np.zeros(self.mesh.t.shape[1], int)
        for name in self.domains:
            count[subs[name]] += 1
        if np.any(count != 1):
            raise ParameterError(f"domains = {sorted(self.domains)} is out of range: the regions "
                                 f"must cover each of the {count.size} triangles exactly once "
                                 f"({np.sum(count == 0)} uncovered, {np.sum(count > 1)} twice)")
        for kind, loads, unit in (("live_body", self.live_body, "N/m³"),
                                  ("dead_body", self.dead_body, "N/m³"),
                                  ("live_traction", self.live_traction, "Pa"),
                                  ("dead_traction", self.dead_traction, "Pa"),
                                  ("ties", self.ties, "Pa")):
            for name, v in loads.items():
                arr = np.asarray(v, float)
                if arr.shape != (2,) or not np.all(np.isfinite(arr)):
                    raise ParameterError(f"{kind}[{name!r}] = {v!r} has shape {arr.shape}: "
                                         f"allowed a finite vector (x, z) [{unit}]")
        for name, comp in self.supports.items():
            check_choice(f"supports[{name!r}]", comp, sorted(COMPONENTS))
        for kind, doms in (("domains", self.domains), ("interfaces", self.interfaces)):
            for name, dom in doms.items():
                if not isinstance(dom, strength.StrengthDomain):
                    raise ParameterError(f"{kind}[{name!r}] = {dom!r} is out of range: allowed "
                                         f"a homlimit.fe.strength.StrengthDomain")
        if not any(np.any(v) for v in (*self.live_body.values(), *self.live_traction.values())):
            raise ParameterError(f"live loads = {dict(self.live_body) | dict(self.live_traction)}"
                                 f" is out of range: at least one non-zero live body force or "
                                 f"traction is needed to define the multiplier")

    @property
    def stress_degrees(self) -> tuple[int, ...]:
        """The static program's stress degrees this problem takes: quadratic stresses are not
        built on rigid bodies and joints, so (1,) where it has either, else (1, 2)."""
        rigid = any(isinstance(d, strength.Rigid) for d in self.domains.values())
        return (1,) if rigid or self.interfaces else (1, 2)

    @property
    def n_triangles(self) -> int:
        return int(self.mesh.t.shape[1])


Rigid = strength.Rigid  # re-exported: the rigid-block adapter lives with the domains


# ---------------------------------------------------------------------------------------------
# structured graded meshes
# ---------------------------------------------------------------------------------------------

def graded(lo: float, hi: float, h_min: float, h_max: float, foci=(), breaks=(),
           growth: float = 1.15) -> np.ndarray:
    """Coordinates from lo to hi with spacing min(h_max, h_min + (growth − 1)·distance to foci).

    Every focus and break is a coordinate; without foci the spacing is h_max.
    """
    if not (hi > lo and 0 < h_min <= h_max and growth >= 1.0):
        raise ParameterError(f"graded(lo={lo}, hi={hi}, h_min={h_min}, h_max={h_max}, "
                             f"growth={growth}) is out of range: allowed lo < hi, "
                             f"0 < h_min <= h_max, growth >= 1")
    foci = np.asarray(sorted(foci), float)
    stops = np.unique(np.r_[lo, hi, foci, np.asarray(breaks, float)])
    stops = stops[(stops >= lo) & (stops <= hi)]

    def size(x):
        if foci.size == 0:
            return h_max
        return min(h_max, h_min + (growth - 1.0) * np.min(np.abs(x - foci)))

    out = [np.array([lo])]
    for a, b in zip(stops[:-1], stops[1:]):
        # march from both ends towards the middle so both ends see their own size
        xs_a, xs_b = [a], [b]
        while xs_b[-1] - xs_a[-1] > 1e-12 * (hi - lo):
            ha, hb = size(xs_a[-1]), size(xs_b[-1])
            if xs_b[-1] - xs_a[-1] <= max(ha, hb) * 1.0001:
                break
            if ha <= hb:
                xs_a.append(xs_a[-1] + ha)
            else:
                xs_b.append(xs_b[-1] - hb)
        gap = xs_b[-1] - xs_a[-1]
        if gap < 0.5 * min(size(xs_a[-1]), size(xs_b[-1])):
            # a sliver in the middle: drop the nearer marched point, the gap grows to < 1.5 h
            if len(xs_a) > 1:
                xs_a.pop()
            elif len(xs_b) > 1:
                xs_b.pop()
        seg = np.r_[xs_a, xs_b[::-1]]
        out.append(seg[1:])
    return np.concatenate(out)


def crossed_mesh(xs: np.ndarray, zs: np.ndarray, keep=None) -> MeshTri:
    """Tensor grid xs × zs, each cell split by its diagonals into 4 triangles.

    ``keep(xc, zc)`` (cell centres, arrays) selects the cells to mesh (default: all).
    """
    xs, zs = np.asarray(xs, float), np.asarray(zs, float)
    nx, nz = xs.size - 1, zs.size - 1
    X, Z = np.meshgrid(xs, zs, indexing="ij")
    vid = np.arange(X.size).reshape(nx + 1, nz + 1)
    xc, zc = np.meshgrid(0.5 * (xs[1:] + xs[:-1]), 0.5 * (zs[1:] + zs[:-1]), indexing="ij")
    mask = np.ones((nx, nz), bool) if keep is None else np.asarray(keep(xc, zc), bool)
    cid = X.size + np.arange(nx * nz).reshape(nx, nz)
    p00, p10, p11, p01 = vid[:-1, :-1], vid[1:, :-1], vid[1:, 1:], vid[:-1, 1:]
    t = np.concatenate([np.stack([a[mask], b[mask], cid[mask]])
                        for a, b in ((p00, p10), (p10, p11), (p11, p01), (p01, p00))], axis=1)
    p = np.c_[np.stack([X.ravel(), Z.ravel()]), np.stack([xc.ravel(), zc.ravel()])]
    used = np.unique(t)
    renum = np.full(p.shape[1], -1)
    renum[used] = np.arange(used.size)
    return MeshTri(np.ascontiguousarray(p[:, used]), np.ascontiguousarray(renum[t]))


def _near(a, b, tol):
    return np.abs(a - b) < tol


# ---------------------------------------------------------------------------------------------
# classical benchmarks
# ---------------------------------------------------------------------------------------------

def _footing_mesh(width: float, depth: float, h_min: float, h_max: float, growth: float):
    """Half-domain 0 <= x <= width, −depth <= z <= 0 of a strip footing of half-width 1, graded
    towards the footing edge (1, 0); boundaries footing, symmetry, bottom, far; region soil."""
    xs = graded(0.0, width, h_min, h_max, foci=(1.0,), growth=growth)
    zs = graded(-depth, 0.0, h_min, h_max, foci=(0.0,), growth=growth)
    tol = 1e-9
    return crossed_mesh(xs, zs).with_boundaries({
        "footing": lambda x: _near(x[1], 0.0, tol) & (x[0] < 1.0),
        "symmetry": lambda x: _near(x[0], 0.0, tol),
        "bottom": lambda x: _near(x[1], -depth, tol),
        "far": lambda x: _near(x[0], width, tol),
    }).with_subdomains({"soil": lambda x: x[0] > -1.0})


def prandtl(h_min: float = 0.01, h_max: float = 0.25, growth: float = 1.25,
            k: float = 1.0, width: float = 4.5, depth: float = 3.0) -> Problem:
    """Prandtl strip footing on a weightless Tresca half-space (plane strain), half-domain.

    Footing of width B = 2 (half-width 1) loaded by a uniform pressure q on 0 <= x <= 1 of the
    surface z = 0; symmetry on x = 0 (v_x = 0); soil 0 <= x <= ``width``, −``depth`` <= z <= 0,
    fixed on its bottom and far side. Tresca cohesion k. The multiplier is q/k.
    Reference (Prandtl 1920; exact): q_u/k = 2 + π ≈ 5.1416; an upper bound is never below it.
    The mesh is graded towards the footing edge (1, 0).
    """
    k = check_range("k", k, 0.0, lo_open=True, unit="Pa")
    t0 = time.perf_counter()
    m = _footing_mesh(width, depth, h_min, h_max, growth)
    return Problem(
        name="prandtl", mesh=m, domains={"soil": strength.Tresca(k)},
        supports={"symmetry": "x", "bottom": "fixed", "far": "fixed"},
        live_traction={"footing": (0.0, -k)}, reference=PRANDTL, bounds=(PRANDTL, math.inf),
        meta={"mesh_time": time.perf_counter() - t0, "k": k})


def vertical_cut(h_min: float = 0.01, h_max: float = 0.1, growth: float = 1.25,
                 H: float = 1.0, k: float = 1.0) -> Problem:
    """Vertical cut of height H in a Tresca soil (cohesion k, unit weight γ), plane strain.

    Soil: 0 <= x <= 2.5 H above the toe level (0 <= z <= H, cut face x = 0) and
    −1.5 H <= x <= 2.5 H, −H <= z <= 0 below it; fixed on the bottom and both far sides. The
    self-weight is the live load, a unit weight k/H, so the multiplier is the stability number γH/k.
    Reference (Kammoun, Pastor, Smaoui & Pastor 2010): 3.7752 <= γH/k <= 3.7776; the classical
    one-wedge upper bound is 3.83. The mesh is graded towards the toe (0, 0) and the crest (0, H).
    """
    H = check_range("H", H, 0.0, lo_open=True, unit="m")
    k = check_range("k", k, 0.0, lo_open=True, unit="Pa")
    t0 = time.perf_counter()
    xs = graded(-1.5 * H, 2.5 * H, h_min * H, h_max * H, foci=(0.0,), growth=growth)
    zs = graded(-H, H, h_min * H, h_max * H, foci=(0.0, H), growth=growth)
    tol = 1e-9 * H
    m = crossed_mesh(xs, zs, keep=lambda xc, zc: (xc > 0) | (zc < 0)).with_boundaries({
        "bottom": lambda x: _near(x[1], -H, tol),
        "sides": lambda x: _near(x[0], -1.5 * H, tol) | _near(x[0], 2.5 * H, tol),
    }).with_subdomains({"soil": lambda x: x[0] > -np.inf})
    return Problem(
        name="vertical_cut", mesh=m, domains={"soil": strength.Tresca(k)},
        supports={"bottom": "fixed", "sides": "fixed"},
        live_body={"soil": (0.0, -k / H)},  # λ k/H is the critical unit weight γ
        reference=VERTICAL_CUT_UB, bounds=(VERTICAL_CUT_LB, VERTICAL_CUT_UB),
        meta={"mesh_time": time.perf_counter() - t0, "H": H, "k": k,
              "multiplier": "γH/k"})


def mohr_coulomb_footing(phi_deg: float = 30.0, h_min: float = 0.02, h_max: float = 0.6,
                         growth: float = 1.2, cohesion: float = 1.0) -> Problem:
    """Strip footing (half-width 1) on a weightless Mohr–Coulomb soil, half-domain.

    Same set-up as ``prandtl`` on a larger box (0 <= x <= 14, −7 <= z <= 0): the log-spiral
    mechanism of φ = 30° reaches x ≈ 9.6. The multiplier is q/c = N_c.
    Reference (Prandtl–Reissner, exact): N_c = (N_q − 1) cot φ = 30.14 at φ = 30°.
    """
    phi_deg = check_range("phi_deg", phi_deg, 0.0, 60.0, lo_open=True, unit="deg")
    cohesion = check_range("cohesion", cohesion, 0.0, lo_open=True, unit="Pa")
    t0 = time.perf_counter()
    width, depth = 14.0, 7.0
    m = _footing_mesh(width, depth, h_min, h_max, growth)
    nc = mohr_coulomb_nc(phi_deg)
    return Problem(
        name="mohr_coulomb_footing", mesh=m,
        domains={"soil": strength.MohrCoulomb(cohesion, phi_deg)},
        supports={"symmetry": "x", "bottom": "fixed", "far": "fixed"},
        live_traction={"footing": (0.0, -cohesion)}, reference=nc, bounds=(nc, math.inf),
        meta={"mesh_time": time.perf_counter() - t0, "phi_deg": phi_deg})


def free_block(b: float = 0.5, h: float = 3.0, f: float = 0.6, gamma: float = 2000.0,
               g: float = 9.81, n_b: int = 2, interior: str = "rigid") -> Problem:
    """A free-standing façade strip (width b, height h) on a bed joint to the ground.

    The base z = 0 is a dry bed joint (``BedJoints(f)``) to a fixed ground; the strip is
    ``interior`` = "rigid" (one block: ``Rigid``) or "bedjoints" (a continuum of bed joints,
    ``BedJoints(f)``, i.e. thin full-width courses). Self-weight γg is the dead load, a
    horizontal body force −x proportional to it the live load.
    Reference (rigid-block statics): the block tilts about its outer toe at λ = b/h, provided
    b/h < f (otherwise it slides first, at λ = f). The bed-joint continuum is weaker: its thin
    courses bend freely, and its multiplier lies below b/h (docs/kinematic.md).
    """
    b = check_range("b", b, 0.0, lo_open=True, unit="m")
    h = check_range("h", h, 0.0, lo_open=True, unit="m")
    f = check_range("f", f, 0.0, lo_open=True)
    n_b = int(check_range("n_b", n_b, 1))
    check_choice("interior", interior, ("rigid", "bedjoints"))
    t0 = time.perf_counter()
    dx = b / n_b
    xs = np.linspace(0.0, b, n_b + 1)
    zs = np.linspace(0.0, h, max(2, int(round(h / dx))) + 1)
    tol = 1e-9 * h
    m = crossed_mesh(xs, zs).with_boundaries({"base": lambda x: _near(x[1], 0.0, tol)}) \
        .with_subdomains({"facade": lambda x: x[0] > -np.inf})
    w = gamma * g
    lam = min(b / h, f)
    return Problem(
        name="free_block", mesh=m,
        domains={"facade": Rigid() if interior == "rigid" else strength.BedJoints(f)},
        interfaces={"base": strength.BedJoints(f)},
        live_body={"facade": (-w, 0.0)}, dead_body={"facade": (0.0, -w)},
        reference=lam, bounds=(lam, lam) if interior == "rigid" else (0.0, lam),
        meta={"mesh_time": time.perf_counter() - t0, "b": b, "h": h, "f": f,
              "interior": interior})


# ---------------------------------------------------------------------------------------------
# the masonry T-section
# ---------------------------------------------------------------------------------------------



def t_section(case: Case = Case(), z0: float = 0.0, facade: str = "homogenised",
              h: float = 0.25, n_b: int = 4, growth: float = 1.15,
              h_far: float | None = None, mesher: str = "crossed",
              h_outer: float | None = None) -> Problem:
    """The façade strip + transversal wall of the paper in the section plane x–z.

    Façade 0 <= x <= b (region "facade", density ρ·γ with ρ = l/s, the paper's 2D reduction),
    transversal wall b <= x <= b + L (region "wall", density γ), both from z0 to H; base z = z0
    fixed. Dead load: self-weight; live load: a horizontal body force towards −x (outwards)
    equal to the weight on both regions, so the multiplier is the collapse acceleration a/g.
    Wall domain: ``Homogenised(a, c, f)`` (eq. 15). Façade domain: "homogenised" (default; the
    same eq. 15, as the prototype) or "bedjoints" (``BedJoints(f)``: a façade cut across its
    thickness shows bed joints only). Boundaries: "base", "outer" (x = 0), "top", "end"
    (x = b + L). Mesh: n_b columns across the façade, spacing h in z, and in the wall a spacing
    growing from b/n_b at the junction to h (or ``h_far``) at rate ``growth``.
    ``mesher``: "crossed" (this builder's default: the structured grid, meshed without gmsh;
    a run's default is ``params.MESHER_DEFAULT``). ``mesher="gmsh"``: an unstructured gmsh
    mesh instead (``geometry.tsection`` with size h,
    refined to b/n_b along the junction; adds the interior boundary "junction").
    ``mesher="gmsh-strip"``: gmsh with the façade strip structured and x-aligned like the
    crossed grid (n_b columns, rows of h, crossed cells) and the wall unstructured at
    max(h, b/n_b) (the crossed grid's wall columns), refined to min(h, b/n_b) along the
    junction and conforming to the strip's nodes there (``geometry.tsection(strip=
    "structured")``).
    ``h_outer`` (crossed and gmsh-strip; on gmsh-strip a geometric progression,
    ``geometry.graded_columns``): the façade's columns graded from this width at the outer face
    x = 0 (spacing h_outer + (OUTER_GROWTH − 1)·x up to b/n_b, the last column at most 1.5
    b/n_b: ``graded``). An overturning façade bears on its outer face, and a static field can
    put its compression resultant no nearer to that face than about a third of the outermost
    column: the lever arm it loses is O(column width) (docs/static.md, "The outer face").
    Real walls (issue 30, docs/real-walls.md "FE bounds"): ``case.masonry`` fc (0: infinite),
    cohesion and tension enter both domains, the façade's times ρ = l/s (its stresses in the
    section are ρ times the façade's, as its density is ρ γ): fc caps the principal
    compressive stress (``strength.Capped``). Ties and floors: ``_ties_and_floors``.
    Wall openings (``case.wall_openings``): holes in the gmsh meshes (``geometry.tsection``
    holes; the crossed grid refuses them), each under a rigid lintel (region "lintel<k>",
    ``strength.Rigid``, the wall's weight: one course above the hole, bearing a half block c
    beyond either side), since a dry no-tension continuum cannot span a hole (gravity alone
    drops the masonry above it); façade opening bands: ``_facade_bands``.
    Reference: the prototype's hinge + fan mechanism (docs/kinematic.md); no closed form.
    """
    w, mas = case.wall, case.masonry
    z0 = check_range("z0", z0, 0.0, w.H, hi_open=True, unit="m")
    h = check_range("h", h, 0.0, w.H - z0, lo_open=True, unit="m")
    n_b = int(check_range("n_b", n_b, 1))
    check_choice("facade", facade, FACADE_MODELS)
    check_choice("mesher", mesher, MESHERS)
    t0 = time.perf_counter()
    geo = TSection.from_case(case, z0)
    b, H = geo.b, geo.H
    h_far = h if h_far is None else check_range("h_far", h_far, 0.0, lo_open=True, unit="m")
    if h_outer is not None:
        h_outer = check_range("h_outer", h_outer, 0.0, b / n_b, lo_open=True, unit="m")
        if mesher == "gmsh":
            raise ParameterError(f"h_outer = {h_outer} with mesher = {mesher!r} is out of "
                                 f"range: allowed only with mesher = 'crossed' or 'gmsh-strip'")
    if geo.holes and mesher == "crossed":
        raise ParameterError(f"mesher = {mesher!r} with [[wall_opening]] ({len(geo.holes)} "
                             "entries) is out of range: the crossed grid does not cut holes; "
                             "allowed mesher = 'gmsh' or 'gmsh-strip'")
    if mesher == "gmsh":
        m = to_skfem(tsection(H, b, geo.L, size=h, size_junction=min(h, b / n_b), z0=z0,
                              holes=geo.holes, lintels=geo.lintels))
    elif mesher == "gmsh-strip":
        m = to_skfem(tsection(H, b, geo.L, size=min(max(h, b / n_b), geo.span),
                              size_junction=min(h, b / n_b), holes=geo.holes,
                              lintels=geo.lintels,
                              z0=z0, strip="structured", n_b=n_b, rows=h, h_outer=h_outer))
    else:
        xf = (np.linspace(0.0, b, n_b + 1) if h_outer is None else
              graded(0.0, b, h_outer, b / n_b, foci=(0.0,), growth=OUTER_GROWTH))
        xs = np.r_[xf[:-1],
                   graded(b, geo.x_end, min(b / n_b, h_far), max(b / n_b, h_far), foci=(b,),
                          growth=growth)]
        zs = np.linspace(z0, H, max(2, int(math.ceil(geo.height / h))) + 1)
        m = crossed_mesh(xs, zs).with_boundaries({
            name: (lambda x, name=name: geo.on_boundary(name, x))
            for name in ("base", "outer", "top", "end")
        }).with_subdomains({name: (lambda x, name=name: geo.in_region(name, x))
                            for name in REGIONS})
    wg = w.gamma * w.g
    wf = w.rho * wg
    # the façade strip stands for a bay of length l in a section of thickness s, so its
    # stresses are ρ = l/s times the façade's: its strengths (fc, cohesion, tension) scale too
    rho = case.rho
    joint = {"cohesion": rho * mas.cohesion, "tension": rho * mas.tension}
    fac = (strength.Homogenised(mas.a, mas.c, mas.f, **joint) if facade == "homogenised"
           else strength.BedJoints(mas.f, **joint))
    wall = strength.Homogenised(mas.a, mas.c, mas.f, cohesion=mas.cohesion,
                                tension=mas.tension)
    meta = {"mesh_time": time.perf_counter() - t0, "case": case.as_dict(), "z0": z0,
            "facade": facade, "mesher": mesher, "h": h}
    real = {}
    if case.ties or case.floors:
        m, real, meta["real_wall"] = _ties_and_floors(m, case, z0)
    m, live_open, dead_open = _facade_bands(m, case)
    # the openings' lintels (geometry.TSection.lintels): rigid parts of the wall, its weight
    lint = [k for k in (m.subdomains or {}) if k.startswith("lintel")]
    live_open |= {k: (-wg, 0.0) for k in lint}
    dead_open |= {k: (0.0, -wg) for k in lint}
    if mas.fc:
        meta["fc"] = {"facade": rho * mas.fc, "wall": mas.fc}
    supports = {"base": "fixed"} | real.get("supports", {})
    return Problem(
        name=f"t_section[{case.name}]", mesh=m,
        domains={"facade": strength.capped(fac, rho * mas.fc),
                 "wall": strength.capped(wall, mas.fc)} | {k: strength.Rigid() for k in lint},
        supports=supports,
        live_body={"facade": (-wf, 0.0), "wall": (-wg, 0.0)} | live_open,
        dead_body={"facade": (0.0, -wf), "wall": (0.0, -wg)} | real.get("dead_body", {})
        | dead_open, ties=real.get("ties", {}), meta=meta)


def _facade_bands(m: MeshTri, case: Case):
    """The façade's opening bands (``case.facade_openings``, docs/real-walls.md "Openings"):
    the façade triangles whose centroid lies in a band form region "facade_open<k>" (always
    present, maybe empty), on which body forces of −fraction times the façade's weight and
    horizontal load are added (regions' loads add up), so the band carries (1 − fraction) of
    them; its strength is the façade's. The band's edges are those of the rows of triangles
    its centroids select (within one row of z_bottom and z_top). Returns the mesh with the
    regions, and the live and dead body forces to add."""
    live, dead, sub = {}, {}, {}
    if not case.facade_openings:
        return m, live, dead
    w = case.wall
    wf = case.rho * w.gamma * w.g
    fac = np.asarray(m.subdomains["facade"])
    zc = m.p[1, m.t[:, fac]].mean(axis=0)
    for k, op in enumerate(case.facade_openings):
        sub[f"facade_open{k}"] = fac[(zc >= op.z_bottom) & (zc <= op.z_top)]
        if op.fraction > 0 and sub[f"facade_open{k}"].size:
            live[f"facade_open{k}"] = (op.fraction * wf, 0.0)
            dead[f"facade_open{k}"] = (0.0, op.fraction * wf)
    return m.with_subdomains(sub), live, dead


def _real_tag(name: str) -> bool:
    """Whether a region or boundary name is one ``_ties_and_floors`` adds."""
    return name.startswith(("tie", "floor"))


def _band_tag(name: str) -> bool:
    """Whether a region name is one ``_facade_bands`` adds."""
    return name.startswith("facade_open")


def t_section_on_mesh(problem: Problem, case: Case, mesh: MeshTri) -> Problem:
    """The T-section ``problem`` of ``case`` carried to ``mesh`` (the same regions and
    boundaries, e.g. a remesh of ``fe.adapt``): its ties and floors placed anew there
    (``_ties_and_floors``: their bands and patch forces depend on the mesh)."""
    mesh, live_open, dead_open = _facade_bands(mesh, case)
    no_band = lambda d: {k: v for k, v in d.items() if not _band_tag(k)}  # noqa: E731
    live = no_band(problem.live_body) | live_open
    dead = no_band(problem.dead_body) | dead_open
    if not (case.ties or case.floors):
        return dataclasses.replace(problem, mesh=mesh, live_body=live, dead_body=dead)
    keep = lambda d: {k: v for k, v in d.items() if not _real_tag(k)}  # noqa: E731
    m, real, placed = _ties_and_floors(mesh, case, float(problem.meta.get("z0", 0.0)))
    return dataclasses.replace(
        problem, mesh=m, supports=keep(problem.supports) | real["supports"], live_body=live,
        dead_body=keep(dead) | real["dead_body"], ties=real["ties"],
        meta={**problem.meta, "real_wall": placed})


def _outer_band(m: MeshTri, z: float, half: float) -> np.ndarray:
    """The façade's outer-face facets (boundary "outer") whose midpoint lies within ``half``
    of z, or the one nearest to z if none does."""
    facets = np.asarray(m.boundaries["outer"])
    zm = m.p[1, m.facets[:, facets]].mean(axis=0)
    sel = np.abs(zm - z) <= half * (1 + 1e-9)
    return facets[sel] if np.any(sel) else facets[[np.argmin(np.abs(zm - z))]]


def _ties_and_floors(m: MeshTri, case: Case, z0: float):
    """Ties and floors of ``case`` on the T-section mesh ``m`` (issue 30, docs/real-walls.md
    "FE bounds"), per unit thickness of the section: a value per metre of façade times ρ = l/s
    (the façade's density is ρ γ, the paper's 2D reduction). Each acts over one course
    (height a) centred on its z:

    - a tie: a uniform traction (ρ T_y / ℓ, 0) towards the wall on the outer-face facets whose
      midpoint lies within a/2 of z (``_outer_band``; ℓ their length), a bounded force
      0 <= N <= T_y (``Problem.ties``). Its stiffness and ductility are dynamic (W(θ)) and do
      not enter limit analysis.
    - a floor: its load ρ Q as vertical dead body forces on the façade's triangles whose
      centroid lies within a/2 of z (at least the row nearest z), split into those with
      centroid x <= e and > e with uniform forces whose resultant acts at x = e (clipped to the
      groups' mean x's: ``e_used``); a rigid motion of the patch takes the same power as a
      point load Q at (e, z) (``z_used``: the resultant's height). ``restrains``: v_x = 0 on
      the outer-face facets of the band (a support "x"; the static reaction there is free).

    Ties and floors at or below the base z0 do not act on the part. Returns the mesh with the
    tags added, the Problem fields and what was placed (for ``meta``)."""
    w, a = case.wall, case.masonry.a
    rho = case.rho
    bnd, sub, out = {}, {}, {"ties": {}, "dead_body": {}, "supports": {}}
    placed = {"ties": [], "floors": []}
    for k, tie in enumerate(case.ties):
        if tie.z <= z0 or tie.yield_force == 0:
            continue
        f = _outer_band(m, tie.z, a / 2)
        zs = m.p[1, m.facets[:, f]]
        ell = np.abs(zs[1] - zs[0])
        length = float(ell.sum())
        bnd[f"tie{k}"] = f
        out["ties"][f"tie{k}"] = (rho * tie.yield_force / length, 0.0)
        placed["ties"].append({"index": k, "z": tie.z, "yield_force": tie.yield_force,
                               "band": (float(zs.min()), float(zs.max())),
                               "z_used": float(ell @ zs.mean(axis=0) / length)})
    fac = np.asarray(m.subdomains["facade"])
    cen = m.p[:, m.t[:, fac]].mean(axis=1)
    area = element_areas(m)[fac]
    for k, fl in enumerate(case.floors):
        if fl.z <= z0:
            continue
        near = np.abs(cen[1] - fl.z)
        sel = near <= a / 2 * (1 + 1e-9)
        if not np.any(sel):
            sel = near <= near.min() * (1 + 1e-9) + 1e-12 * w.H
        x_c, A_c, els = cen[0, sel], area[sel], fac[sel]
        left = x_c <= fl.eccentricity
        if not np.any(left):
            left = x_c <= x_c.min() * (1 + 1e-12)
        if np.all(left):
            left = x_c < x_c.max() * (1 - 1e-12) if np.ptp(x_c) > 0 else left
        groups = [g for g in (left, ~left) if np.any(g)]
        xg = [float(np.average(x_c[g], weights=A_c[g])) for g in groups]
        e_used = float(np.clip(fl.eccentricity, min(xg), max(xg)))
        share = ([1.0] if len(groups) == 1 else
                 [(xg[1] - e_used) / (xg[1] - xg[0]), (e_used - xg[0]) / (xg[1] - xg[0])])
        # the resultant's height: each group's uniform force acts at its area centroid
        z_used = float(sum(q * np.average(cen[1, sel][g], weights=A_c[g])
                           for g, q in zip(groups, share)))
        for j, (g, q) in enumerate(zip(groups, share)):
            if q > 0:
                sub[f"floor{k}_{j}"] = els[g]
                out["dead_body"][f"floor{k}_{j}"] = (0.0, -rho * fl.load * q / A_c[g].sum())
        rec = {"index": k, "z": fl.z, "load": fl.load, "eccentricity": fl.eccentricity,
               "e_used": e_used, "z_used": z_used, "band": (float(m.p[1, m.t[:, els]].min()),
                                          float(m.p[1, m.t[:, els]].max())),
               "restrains": fl.restrains}
        if fl.restrains:
            bnd[f"floor{k}_held"] = _outer_band(m, fl.z, a / 2)
            out["supports"][f"floor{k}_held"] = "x"
        placed["floors"].append(rec)
    if bnd:
        m = m.with_boundaries(bnd)
    if sub:
        m = m.with_subdomains(sub)
    return m, out, placed

