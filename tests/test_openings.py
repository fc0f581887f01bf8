"""Openings (issue 31 step 1): a façade band and rectangles in the transversal wall, from the
case file to every model.

The references are written here by hand: the failing body's mass, centroid, inertia and
participation integral as sums of rectangles (the façade strip cut into the parts below, in
and above the band) and, for mechanism II's wedge cut by a wall opening, the shoelace
(Green's theorem) moments of the clipped polygon whose vertices are worked out below; none
calls the package's integrals.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from homlimit.app.config import ConfigError, load_case
from homlimit.closed_form import real
from homlimit.params import Case, FacadeOpening, Masonry, Wall, WallOpening

from cases import b1, run_cli

B1 = Case(Wall(H=9.0, L=6.0, s=0.5, b=0.5, l=6.0), Masonry(a=0.3, c=0.2, f=0.6), name="B1")
BAND = FacadeOpening(z_bottom=1.0, z_top=2.5, fraction=0.2)


def _rect(x0, x1, z0, z1, rho):
    """(m, ∫x dm, ∫z dm, ∫(x² + z²) dm, ∫z² dm) of a rectangle of areal density rho."""
    if z1 <= z0:
        return np.zeros(5)
    dx, dz = x1 - x0, z1 - z0
    m = rho * dx * dz
    return np.array([m, m * (x0 + x1) / 2, m * (z0 + z1) / 2,
                     rho * ((x1 ** 3 - x0 ** 3) / 3 * dz + (z1 ** 3 - z0 ** 3) / 3 * dx),
                     rho * (z1 ** 3 - z0 ** 3) / 3 * dx])


def _strip_by_hand(h: float) -> np.ndarray:
    """B1's façade strip of height h above its toe (0, 9 − h) with the 20 % band at z in
    [1, 2.5] m: three rectangles, the band's at 0.8 of the density γ l."""
    z_h, rho = 9.0 - h, 2000.0 * 6.0
    cuts = sorted({0.0, h, *(min(max(z - z_h, 0.0), h) for z in (1.0, 2.5))})
    out = np.zeros(5)
    for lo, hi in zip(cuts[:-1], cuts[1:]):
        inside = 1.0 - z_h <= lo and hi <= 2.5 - z_h
        out += _rect(0.0, 0.5, lo, hi, rho * (0.8 if inside else 1.0))
    return out


def _check_body(body, ref):
    m, sx, sz, io, jz = ref
    assert body.m == pytest.approx(m, rel=1e-9, abs=0)
    assert body.x_G == pytest.approx(sx / m, rel=1e-9, abs=0)
    assert body.z_G == pytest.approx(sz / m, rel=1e-9, abs=0)
    assert body.I_O == pytest.approx(io, rel=1e-9, abs=0)
    assert body.J_z == pytest.approx(jz, rel=1e-9, abs=0)


@pytest.mark.parametrize("kind", ["detachment", "overturning"])
def test_band_body_at_the_critical_height_by_hand(kind):
    case = dataclasses.replace(B1, facade_openings=(BAND,))
    r = real.real_mechanism(case, kind)
    _check_body(r.body, _strip_by_hand(r.h))
    # the overturning's critical body is the whole façade: the band lies inside it
    if kind == "overturning":
        assert r.h == 9.0 and r.body.m == pytest.approx(2000 * 6 * 0.5 * (9 - 0.2 * 1.5))


@pytest.mark.parametrize("h", [9.0, 8.0, 7.5, 6.5, 3.0])     # band inside, cut, above
def test_band_body_at_any_height_by_hand(h):
    case = dataclasses.replace(B1, facade_openings=(BAND,))
    r = real.real_mechanism(case, "detachment", lam=h / 0.5)
    _check_body(r.body, _strip_by_hand(h))


def _polygon(P):
    """Shoelace moments (A, ∫x, ∫z, ∫(x² + z²), ∫z²) of a counter-clockwise polygon."""
    x, z = np.asarray(P, float).T
    xn, zn = np.roll(x, -1), np.roll(z, -1)
    c = x * zn - xn * z
    A = c.sum() / 2
    Sx = ((x + xn) * c).sum() / 6
    Sz = ((z + zn) * c).sum() / 6
    Ixx = ((z * z + z * zn + zn * zn) * c).sum() / 12     # ∫z²
    Izz = ((x * x + x * xn + xn * xn) * c).sum() / 12     # ∫x²
    return np.array([A, Sx, Sz, Ixx + Izz, Ixx])


def test_wedge_loses_the_hole_by_hand():
    """Mechanism II at h = 6 m (toe at z = 3), tan ψ = 0.5: the wedge x <= 0.5 + 0.5 ζ. The
    opening x 1.0..2.0, z 4.0..6.0 (ζ 1..3): the crack x = 0.5 + 0.5 ζ crosses x = 1 at
    ζ = 1 and x = 2 at ζ = 3, so the wedge's part of the hole is the triangle (1, 1), (2, 3),
    (1, 3)."""
    t, h = 0.5, 6.0
    hole = WallOpening(x=1.0, z=4.0, width=1.0, height=2.0)
    case = dataclasses.replace(B1, wall_openings=(hole,))
    r = real.real_mechanism(case, "crack", tanpsi=t, lam=h / 0.5)
    strip = _rect(0.0, 0.5, 0.0, h, 2000.0 * 6.0)
    wedge = 2000.0 * 0.5 * _polygon([(0.5, 0.0), (0.5 + t * h, h), (0.5, h)])
    cut = 2000.0 * 0.5 * _polygon([(1.0, 1.0), (2.0, 3.0), (1.0, 3.0)])
    _check_body(r.body, strip + wedge - cut)
    # a hole the crack passes below (ζ 4..5, x 3.0..3.4 > 0.5 + 0.5·5): a pentagon is cut
    hole2 = WallOpening(x=2.5, z=7.0, width=0.9, height=1.0)      # ζ 4..5, x 2.5..3.4
    case2 = dataclasses.replace(B1, wall_openings=(hole2,))
    r2 = real.real_mechanism(case2, "crack", tanpsi=t, lam=h / 0.5)
    # crack at x = 2.5: ζ = 4; at ζ = 5: x = 3.0 < 3.4, so the part is (2.5, 4), (3, 5), (2.5, 5)
    cut2 = 2000.0 * 0.5 * _polygon([(2.5, 4.0), (3.0, 5.0), (2.5, 5.0)])
    _check_body(r2.body, strip + wedge - cut2)
    # a hole straddling the crack with its lower left corner inside the wedge: x 1..3,
    # ζ 3..4 (z 6..7): crack at ζ = 3 is x = 2, at ζ = 4 is x = 2.5: pentagon
    hole3 = WallOpening(x=1.0, z=6.0, width=2.0, height=1.0)
    r3 = real.real_mechanism(dataclasses.replace(B1, wall_openings=(hole3,)), "crack",
                             tanpsi=t, lam=h / 0.5)
    cut3 = 2000.0 * 0.5 * _polygon([(1.0, 3.0), (2.0, 3.0), (2.5, 4.0), (1.0, 4.0)])
    _check_body(r3.body, strip + wedge - cut3)
    # mechanism I takes the façade only: a wall opening changes nothing
    r1 = real.real_mechanism(case, "detachment", lam=h / 0.5)
    _check_body(r1.body, strip)


def test_no_opening_is_the_paper_body():
    for kind in real.KINDS:
        a = real.real_mechanism(B1, kind, lam=12.0).body
        b = real.real_mechanism(dataclasses.replace(
            B1, facade_openings=(FacadeOpening(1.0, 2.5, 0.0),)), kind, lam=12.0).body
        assert a == b


# ------------------------------------------------------------------------ bad openings
BAD = [
    (dict(facade_opening=[{"z_bottom": 1.0, "z_top": 2.5, "fraction": 1.0}]),
     "[[facade_opening]] 0 fraction = 1.0 is out of range: allowed 0 <= fraction < 1"),
    (dict(facade_opening=[{"z_bottom": 1.0, "z_top": 12.0, "fraction": 0.2}]),
     "[[facade_opening]] 0 z_top = 12.0 m is out of range: allowed z_top <= H = 9 m"),
    (dict(facade_opening=[{"z_bottom": 2.0, "z_top": 2.0, "fraction": 0.2}]),
     "[[facade_opening]] 0 z_top = 2.0 m is out of range: allowed z_top > z_bottom = 2 m"),
    (dict(facade_opening=[{"z_bottom": 1.0, "z_top": 3.0, "fraction": 0.2},
                          {"z_bottom": 2.0, "z_top": 4.0, "fraction": 0.2}]),
     "[[facade_opening]] 0 z = [1, 3] m overlaps [[facade_opening]] 1 z = [2, 4] m"),
    (dict(wall_opening=[{"x": 0.4, "z": 1.0, "width": 1.0, "height": 1.0}]),
     "[[wall_opening]] 0 x = 0.4 m is out of range (the opening must lie inside the "
     "transversal wall, touching no edge): allowed x > b = 0.5 m"),
    (dict(wall_opening=[{"x": 5.0, "z": 1.0, "width": 1.5, "height": 1.0}]),
     "[[wall_opening]] 0 x + width = 6.5 m is out of range"),
    (dict(wall_opening=[{"x": 2.0, "z": 8.0, "width": 1.0, "height": 1.0}]),
     "[[wall_opening]] 0 z + height = 9.0 m is out of range"),
    (dict(wall_opening=[{"x": 2.0, "z": 0.0, "width": 1.0, "height": 1.0}]),
     "[[wall_opening]] 0 z = 0.0 m is out of range: allowed 0 < z"),
    (dict(wall_opening=[{"x": 2.0, "z": 1.0, "width": 0.0, "height": 1.0}]),
     "[[wall_opening]] 0 width = 0.0 m is out of range: allowed 0 < width"),
    (dict(wall_opening=[{"x": 2.0, "z": 1.0, "width": 1.0, "height": 1.0},
                        {"x": 2.5, "z": 1.5, "width": 1.0, "height": 1.0}]),
     "[[wall_opening]] 0 (x 2..3, z 1..2 m) overlaps or touches [[wall_opening]] 1"),
    (dict(wall_opening=[{"x": 2.0, "z": 1.0, "width": 1.0, "height": 1.0},
                        {"x": 3.0, "z": 1.0, "width": 1.0, "height": 1.0}]),
     "overlaps or touches [[wall_opening]] 1"),
]


@pytest.mark.parametrize("parts, message", BAD)
def test_bad_openings_name_the_key(parts, message):
    with pytest.raises(ConfigError) as e:
        load_case(b1(analysis={"hinge_check": False}, **parts))
    assert message in str(e.value), str(e.value)


def test_bad_opening_exits_2_before_any_work(tmp_path):
    case = b1(analysis={"fe": False, "hinge_check": False},
              wall_opening=[{"x": 0.5, "z": 1.0, "width": 1.0, "height": 1.0}])
    r = run_cli(tmp_path, case, "run")
    assert r.returncode == 2 and "[[wall_opening]] 0 x = 0.5 m is out of range" in r.stderr
    assert "Traceback" not in r.stderr and not (tmp_path / "out").exists()


def test_the_api_checks_too():
    with pytest.raises(ValueError, match="allowed x > b = 0.5 m"):
        dataclasses.replace(B1, wall_openings=(WallOpening(0.5, 1.0, 1.0, 1.0),))
    with pytest.raises(ValueError, match="fraction = 1.0 is out of range"):
        FacadeOpening(1.0, 2.0, 1.0)


def test_every_model_takes_openings():
    # the DEM takes the blocks' holes and lintels (tests below; it refused them before)
    c = load_case(b1(analysis={"hinge_check": False, "fe": False, "dem": True},
                     wall_opening=[{"x": 2.0, "z": 1.0, "width": 1.0, "height": 1.0}]))
    assert c.case.wall_openings == (WallOpening(2.0, 1.0, 1.0, 1.0),)
    # and refuses, as the blocks do, an opening without a course above it for the lintel
    with pytest.raises(ConfigError, match="with \\[analysis\\] dem = true: .*leaves no course "
                                          "above it for its lintel"):
        load_case(b1(analysis={"hinge_check": False, "fe": False, "dem": True},
                     wall_opening=[{"x": 2.0, "z": 8.0, "width": 1.0, "height": 0.86}]))
    # the hinge check's rockers take them: their bodies are the closed forms' real ones
    # (dynamics.real_rocker; tests/test_real_rockers.py)
    assert load_case(b1(analysis={"fe": False}, facade_opening=[
        {"z_bottom": 1.0, "z_top": 2.5, "fraction": 0.2}])).case.facade_openings


def test_closed_forms_run_with_a_band(tmp_path):
    case = b1(analysis={"fe": False, "hinge_check": False, "overturning": True},
              facade_opening=[{"z_bottom": 1.0, "z_top": 2.5, "fraction": 0.2}])
    r = run_cli(tmp_path, case, "run")
    assert r.returncode == 0, r.stderr
    import json
    s = json.loads((tmp_path / "out" / "summary.json").read_text())
    assert s["inputs"]["facade_opening"] == [{"z_bottom": 1.0, "z_top": 2.5, "fraction": 0.2}]
    over = s["mechanisms"]["overturning"]
    assert over["body"]["m"] == pytest.approx(2000 * 6 * 0.5 * (9 - 0.2 * 1.5), rel=1e-12)


# ------------------------------------------------------------------------------ FE
def _weights(p):
    """Σ body force × area of every region of the problem (dead, live) [N per m of section]."""
    from homlimit.fe.operators import element_areas
    area = element_areas(p.mesh)
    out = []
    for loads in (p.dead_body, p.live_body):
        tot = np.zeros(2)
        for reg, f in loads.items():
            tot += np.asarray(f) * area[p.mesh.subdomains[reg]].sum()
        out.append(tot)
    return out


def test_fe_band_scales_the_facade_weight_and_the_bracket_holds():
    from homlimit.fe.kinematic import solve_kinematic
    from homlimit.fe.problems import t_section
    from homlimit.fe.static import solve_static
    case = dataclasses.replace(B1, facade_openings=(BAND,))
    p = t_section(case, facade="bedjoints", h=0.5)      # rows at 0.5 m: the band's edges
    # by hand: façade ρ γ g b (H − f (z_top − z_bottom)) + wall γ g L H, ρ = l/s = 12
    g = B1.wall.g
    weight = 12 * 2000 * g * 0.5 * (9.0 - 0.2 * 1.5) + 2000 * g * 6.0 * 9.0
    dead, live = _weights(p)
    assert dead == pytest.approx([0.0, -weight], rel=1e-12, abs=1e-6)
    assert live == pytest.approx([-weight, 0.0], rel=1e-12, abs=1e-6)
    lo, up = solve_static(p).multiplier, solve_kinematic(p).multiplier
    assert lo <= up * (1 + 1e-7)
    rf = solve_kinematic(t_section(B1, facade="bedjoints", h=0.5))
    # the band lies below the wall's mechanism, which moves there at a few % of its top speed
    # (a P2 tail across the hinge's rows): lightening the façade there changes the dead and live
    # powers only through that tail, so the multiplier stays put (measured −7.4e-4)
    z, speed = rf.mesh.p[1], np.linalg.norm(rf.velocity, axis=1)
    assert speed[z <= BAND.z_top].max() < 0.05 * speed.max()
    assert up == pytest.approx(rf.multiplier, rel=5e-3)


# --------------------------------------------------------------------------- blocks, DEM
def test_blocks_band_masses_by_hand():
    from homlimit.blocks.geometry import FACADE, t_section_blocks
    case = dataclasses.replace(B1, facade_openings=(BAND,))
    A = t_section_blocks(case)
    free = ~A.fixed
    # façade ρ γ s b (H − f × 1.5 m) + wall γ s L H, ρ γ s = γ l = 12000 kg/m³·m
    assert A.mass[free].sum() == pytest.approx(12000 * 0.5 * (9 - 0.2 * 1.5)
                                               + 1000 * 6.0 * 9.0, rel=1e-12)
    # course 3 (z 0.9..1.2, not toothed): the façade block [0, 0.5] is cut at z = 1.0,
    # 0.1 m full and 0.2 m at 80 %
    bb = A.bounds()
    k = np.flatnonzero((A.kind == FACADE) & np.isclose(bb[:, 1], 0.9))
    assert k.size == 1
    m = 12000 * 0.5 * (0.1 + 0.8 * 0.2)
    zg = 12000 * 0.5 * (0.1 * 0.95 + 0.8 * 0.2 * 1.1) / m
    assert A.mass[k[0]] == pytest.approx(m, rel=1e-12)
    assert A.centroid[k[0]] == pytest.approx([0.25, zg], rel=1e-12)
    # about its centroid: Σ ρ_i A_i ((b² + dz_i²)/12 + (z_i − z_G)²)
    inertia = sum(12000 * 0.5 * rho * dz * ((0.25 + dz ** 2) / 12 + (zc - zg) ** 2)
                  for rho, dz, zc in ((1.0, 0.1, 0.95), (0.8, 0.2, 1.1)))
    assert A.inertia[k[0]] == pytest.approx(inertia, rel=1e-12)


def test_dem_takes_the_band_masses():
    from homlimit.blocks.geometry import t_section_blocks
    from homlimit.dem import build_model
    case = dataclasses.replace(B1, facade_openings=(BAND,))
    model = build_model(t_section_blocks(case, facade="through"))
    assert model.mass.sum() == pytest.approx(12000 * 0.5 * 8.7 + 1000 * 6.0 * 9.0, rel=1e-12)
    assert load_case(b1(analysis={"hinge_check": False, "fe": False, "dem": True,
                                  "blocks": True}, facade_opening=[
        {"z_bottom": 1.0, "z_top": 2.5, "fraction": 0.2}])).case.facade_openings == (BAND,)


# ------------------------------------------------------------------------ FE, wall holes
HOLES = (WallOpening(x=2.0, z=3.0, width=1.0, height=2.0),
         WallOpening(x=4.0, z=1.0, width=1.0, height=1.5))


@pytest.mark.parametrize("mesher", ["gmsh", "gmsh-strip"])
@pytest.mark.parametrize("z0", [0.0, 3.5])
def test_fe_mesh_area_is_the_section_less_the_holes(mesher, z0):
    from homlimit.fe.mesh import element_areas
    from homlimit.fe.problems import t_section
    case = dataclasses.replace(B1, wall_openings=HOLES)
    p = t_section(case, z0=z0, h=0.5, mesher=mesher, facade="bedjoints")
    # by hand: (b + L)(H − z0) less the holes' parts above z0 (the first cut by z0 = 3.5 to
    # 1 × 1.5, the second below it)
    holes = 1.0 * 2.0 + 1.0 * 1.5 if z0 == 0.0 else 1.0 * 1.5
    area = element_areas(p.mesh)
    assert area.sum() == pytest.approx(6.5 * (9.0 - z0) - holes, rel=1e-12)
    assert area[p.mesh.subdomains["facade"]].sum() == pytest.approx(0.5 * (9.0 - z0), rel=1e-12)
    # no triangle's centroid inside a hole
    cen = p.mesh.p[:, p.mesh.t].mean(axis=1)
    for op in HOLES:
        x0, x1, z_0, z_1 = op.box
        assert not np.any((cen[0] > x0) & (cen[0] < x1) & (cen[1] > z_0) & (cen[1] < z_1))


def test_crossed_grid_refuses_holes():
    from homlimit.fe.problems import t_section
    with pytest.raises(ValueError, match="the crossed grid does not cut holes"):
        t_section(dataclasses.replace(B1, wall_openings=HOLES), h=0.5, mesher="crossed")


def test_fe_bracket_holds_with_holes_under_rigid_lintels():
    from homlimit.fe.kinematic import solve_kinematic
    from homlimit.fe.problems import t_section
    from homlimit.fe.static import solve_static
    from homlimit.fe.strength import Rigid
    case = dataclasses.replace(B1, wall_openings=HOLES)
    p = t_section(case, h=0.5, mesher="gmsh-strip", facade="bedjoints")
    # each lintel: one course a = 0.3 m above its hole, c = 0.2 m beyond either side, rigid
    from homlimit.fe.mesh import element_areas
    area = element_areas(p.mesh)
    for k, (x0, x1, z1) in enumerate(((2.0, 3.0, 5.0), (4.0, 5.0, 2.5))):
        assert isinstance(p.domains[f"lintel{k}"], Rigid)
        els = p.mesh.subdomains[f"lintel{k}"]
        assert area[els].sum() == pytest.approx((x1 - x0 + 0.4) * 0.3, rel=1e-12)
        cen = p.mesh.p[:, p.mesh.t[:, els]].mean(axis=1)
        assert np.all((cen[0] > x0 - 0.2) & (cen[0] < x1 + 0.2) & (cen[1] > z1)
                      & (cen[1] < z1 + 0.3))
    lo, up = solve_static(p).multiplier, solve_kinematic(p).multiplier
    assert 0 < lo <= up * (1 + 1e-7)


def test_fe_refuses_what_cannot_take_holes():
    hole = [{"x": 2.0, "z": 3.0, "width": 1.0, "height": 2.0}]
    for parts, msg in (
            (dict(mesh={"mesher": "crossed"}), "the crossed grid does not cut holes"),
            (dict(analysis={"hinge_check": False, "stress_degree": 2}),
             "rigid lintels take linear stresses only; allowed stress_degree = 1")):
        with pytest.raises(ConfigError, match=msg):
            load_case(b1(**({"analysis": {"hinge_check": False}} | parts),
                         wall_opening=hole))
    # a second opening within the first's lintel (z 5.0..5.3, x 1.8..3.2)
    with pytest.raises(ConfigError, match="lintels"):
        load_case(b1(analysis={"hinge_check": False}, wall_opening=hole + [
            {"x": 3.1, "z": 5.1, "width": 0.5, "height": 0.5}]))


def test_blocks_cut_the_holes_under_whole_lintels():
    from homlimit.blocks.geometry import t_section_blocks
    case = dataclasses.replace(B1, wall_openings=HOLES)
    A = t_section_blocks(case)
    free = ~A.fixed
    # by hand (a = 0.3): the courses whose mid-height lies in the hole open, 3.0..5.1 m
    # (7 courses) over x 2..3 and 0.9..2.4 m (5) over x 4..5: γ s × (2.1 + 1.5) m² less
    full = 12000 * 0.5 * 9.0 + 1000 * 6.0 * 9.0
    assert A.mass[free].sum() == pytest.approx(full - 1000 * 3.6, rel=1e-12)
    bb = A.bounds()
    G = A.centroid
    for op, z_open, z_top in ((HOLES[0], 3.0, 5.1), (HOLES[1], 0.9, 2.4)):
        x0, x1, z0, z1 = op.box
        assert not np.any(free & (G[:, 0] > x0) & (G[:, 0] < x1) & (G[:, 1] > z0)
                          & (G[:, 1] < z1))
        # nothing at all in the opened courses over the opening
        assert not np.any(free & (bb[:, 0] < x1 - 1e-9) & (bb[:, 2] > x0 + 1e-9)
                          & (bb[:, 1] < z_top - 1e-9) & (bb[:, 3] > z_open + 1e-9))
        # one whole block spans it in the course above
        over = free & np.isclose(bb[:, 1], z_top) & (bb[:, 0] <= x0) & (bb[:, 2] >= x1)
        assert over.sum() == 1


def test_blocks_refuse_an_opening_without_a_course_above():
    with pytest.raises(ConfigError, match="leaves no course above it for its lintel"):
        load_case(b1(analysis={"hinge_check": False, "fe": False, "blocks": True},
                     wall_opening=[{"x": 2.0, "z": 8.0, "width": 1.0, "height": 0.86}]))


def test_sweep_keys_address_opening_entries():
    c = load_case(b1(analysis={"hinge_check": False}),
                  ["facade_opening.0.z_bottom=1", "facade_opening.0.z_top=2.5",
                   "facade_opening.0.fraction=0.2", "wall_opening.0.x=2",
                   "wall_opening.0.z=3", "wall_opening.0.width=1", "wall_opening.0.height=2"])
    assert c.case.facade_openings == (BAND,) and c.case.wall_openings == (HOLES[0],)
    assert c.as_dict()["wall_opening"] == [{"x": 2.0, "z": 3.0, "width": 1.0, "height": 2.0}]


def test_a_remesh_keeps_the_band_and_the_lintels():
    from homlimit.fe.geometry import tsection
    from homlimit.fe.mesh import to_skfem
    from homlimit.fe.problems import t_section, t_section_on_mesh
    from homlimit.geometry import TSection
    case = dataclasses.replace(B1, facade_openings=(BAND,), wall_openings=HOLES[:1])
    p = t_section(case, h=0.5, mesher="gmsh-strip", facade="bedjoints")
    geo = TSection.from_case(case)
    mesh = to_skfem(tsection(9.0, 0.5, 6.0, size=0.25, strip="structured", rows=0.25,
                             holes=geo.holes, lintels=geo.lintels))
    q = t_section_on_mesh(p, case, mesh)
    g = B1.wall.g
    # by hand: façade less the band's 20 %, the wall less the hole (lintel included)
    weight = 12 * 2000 * g * 0.5 * (9.0 - 0.2 * 1.5) + 2000 * g * (6.0 * 9.0 - 2.0)
    dead, live = _weights(q)
    assert dead == pytest.approx([0.0, -weight], rel=1e-12, abs=1e-6)
    assert live == pytest.approx([-weight, 0.0], rel=1e-12, abs=1e-6)
    assert q.mesh.t.shape[1] > p.mesh.t.shape[1] and "lintel0" in q.domains


# ------------------------------------------------------------------------ DEM, wall holes
#: a small T-section (8 courses) with one opening spanning courses 2–4 (z 0.6..1.5 m) over
#: x 1.0..1.6 m: 45 free blocks, settled in ~0.5 s
SMALL = Case(Wall(H=2.4, L=2.0, s=0.3, b=0.3, l=1.2, gamma=2000.0),
             Masonry(a=0.3, c=0.2, f=0.6), name="small-hole",
             wall_openings=(WallOpening(x=1.0, z=0.6, width=0.6, height=0.9),))


@pytest.fixture(scope="module")
def small_dem():
    from homlimit.app.config import default_case
    from homlimit.app.dem_stage import _model
    from homlimit.dem import settle
    model = _model(SMALL, default_case().dem)   # a run's DEM model of the case, [dem] defaults
    settled, info = settle(model)
    return model, settled, info


def test_dem_takes_the_blocks_assembly_with_its_hole(small_dem):
    from homlimit.app.config import default_case
    from homlimit.blocks.geometry import t_section_blocks
    model, _, _ = small_dem
    la = t_section_blocks(SMALL, facade=default_case().blocks.facade)   # the blocks LA's
    A = model.assembly
    # by hand: 6 blocks a course (toothed: breaks 0, .5, .9, 1.3, 1.7, 2.1, 2.3; plain: 0,
    # .3, .7, 1.1, 1.5, 1.9, 2.3), 48; the hole removes [1.1, 1.5] of course 3 and merges
    # course 5's three blocks over it into the lintel [0.7, 1.9]: 45
    assert A.n_free == la.n_free == 45 and model.n_blocks == la.n_blocks == 46
    np.testing.assert_array_equal(A.bounds(), la.bounds())
    np.testing.assert_array_equal(A.mass, la.mass)
    # façade γ l b H + wall γ s (L H − the hole's 0.6 × 0.9 m²), per slab
    hand = 2000 * 1.2 * 0.3 * 2.4 + 2000 * 0.3 * (2.0 * 2.4 - 0.6 * 0.9)
    assert model.mass[~A.fixed].sum() == pytest.approx(hand, rel=1e-12)
    bb = A.bounds()
    lintel = np.flatnonzero(np.isclose(bb[:, 1], 1.5) & (bb[:, 0] < 1.0) & (bb[:, 2] > 1.6))
    np.testing.assert_allclose(bb[lintel], [[0.7, 1.5, 1.9, 1.8]], atol=1e-12)


def test_dem_lintel_over_the_hole_stays_up(small_dem):
    from homlimit.dem import run
    model, settled, info = small_dem
    A = model.assembly
    assert info["converged"]
    bb = A.bounds()
    lintel = int(np.flatnonzero(np.isclose(bb[:, 1], 1.5) & (bb[:, 0] < 1.0)
                                & (bb[:, 2] > 1.6))[0])
    sink = A.centroid[lintel, 1] - settled.pos[lintel, 1]
    # by hand: the joints under it (z = 0, 0.3, ..., 1.5) closing as a 1D column under the
    # section's weight, σ_k/kn = γ g (H − z_k)/kn (façade and wall alike: the façade's
    # stiffness × ρ), 0.194 mm; at most every joint loaded over the section less the hole,
    # × (b + L)/(b + L − 0.6) = 1.353, 0.263 mm. A lintel falling into the hole drops 0.9 m.
    column = 2000 * 9.81 * sum(2.4 - 0.3 * k for k in range(6)) / 1e9
    assert column <= sink <= column * 2.3 / 1.7
    assert abs(settled.th[lintel]) < 1e-4
    # static: 0.5 s more, undamped and unloaded, nothing moves by more than the settling's
    # velocity tolerance (1e-5 m/s) times the time
    out = run(model, settled, v_g=0.0, t_max=0.5)
    assert not out.collapsed
    moved = np.abs(out.state.pos - settled.pos)[~A.fixed].max()
    assert moved < 1e-5 * 0.5


def test_dem_refuses_a_jamb_piece_thinner_than_its_contact_margin():
    from homlimit.blocks.geometry import t_section_blocks
    from homlimit.dem import build_model
    from homlimit.errors import ParameterError
    # the jamb x = 0.904 cuts course 2's block [0.9, 1.3]: a piece 4 mm wide (it fell 0.74 m
    # out of the wall while settling at verlet_margin 5 mm, and stood at 2 mm)
    thin = dataclasses.replace(SMALL, wall_openings=(WallOpening(0.904, 0.6, 0.6, 0.9),))
    with pytest.raises(ParameterError, match=r"0\.004 x 0\.3 m: out of range: allowed free "
                                             r"blocks wider and taller than verlet_margin"):
        build_model(t_section_blocks(thin))
    hole = [{"x": 1.904, "z": 3.0, "width": 1.0, "height": 2.0}]   # B1: [1.9, 2.3] → 4 mm
    with pytest.raises(ConfigError, match=r"\[\[wall_opening\]\] 0 \(x 1.904..2.904 m\) with "
                                          r"\[analysis\] dem = true: a jamb cuts a block "
                                          r"leaving a piece 4 mm wide"):
        load_case(b1(analysis={"hinge_check": False, "fe": False, "dem": True},
                     wall_opening=hole))
    # the margin is the DEM's: a smaller one takes the piece
    assert load_case(b1(analysis={"hinge_check": False, "fe": False, "dem": True},
                        dem={"verlet_margin": 0.002}, wall_opening=hole)).case.wall_openings


def test_run_brackets_the_dem_threshold_with_a_hole(tmp_path):
    import json

    from homlimit.app import pipeline
    case = {"name": "small-hole",
            "wall": {"H": 2.4, "L": 2.0, "s": 0.3, "b": 0.3, "l": 1.2, "gamma": 2000.0},
            "masonry": {"a": 0.3, "c": 0.2, "f": 0.6},
            "analysis": {"fe": False, "hinge_check": False, "dem": True},
            "dem": {"rel_tol": 0.05, "t_max": 2.0},
            "wall_opening": [{"x": 1.0, "z": 0.6, "width": 0.6, "height": 0.9}],
            "output": {"png": False, "vtu": False}}
    pipeline.run(case, out=tmp_path)
    d = json.loads((tmp_path / "summary.json").read_text(encoding="utf-8"))["dem"]
    assert d["n_blocks"] == 46 and d["settle_converged"]      # SMALL's 45 blocks + ground
    assert d["vg_lo"] < d["vg_hi"] and (d["vg_hi"] - d["vg_lo"]) / (d["vg_hi"] + d["vg_lo"]) \
        <= 0.05
