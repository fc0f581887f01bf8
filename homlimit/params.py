"""Immutable parameter objects: the wall, the masonry, and the dimensionless numbers of eq. 11.

Frame (see docs): x horizontal from the façade's outer face into the building, z up.
Façade strip 0 <= x <= b, transversal wall b <= x <= b + L, both of height H. SI units throughout.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields

from .errors import ParameterError, check_range
from .fields import check_fields, ranged, set_fields

__all__ = ["Wall", "Masonry", "Case", "Tie", "Floor", "FacadeOpening", "WallOpening",
           "opening_problems", "G_STANDARD", "FACADE_DEFAULT",
           "FACADE_MODELS", "MESHERS", "MESHER_DEFAULT", "PART_DIVISIONS"]

G_STANDARD = 9.81  # m/s², the value used throughout the paper's examples
# strength of the façade in the section plane: bed joints only (its blocks run through the
# thickness b, as the paper builds it: the default), or eq. 15 like the wall (the β → 0
# idealisation, in which a crack may cut the façade diagonally)
FACADE_MODELS = ("homogenised", "bedjoints")
FACADE_DEFAULT = "bedjoints"
# the meshes of the T-section (fe.problems.t_section): the crossed structured grid (every cell
# cut by its diagonals), gmsh unstructured (refined along the junction), and gmsh with the
# façade strip structured and x-aligned like the crossed grid, the wall unstructured (the
# default of every run and study: the bed-joint façade does not lock on it, and its columns
# grade to the outer face for the static bound; docs/kinematic.md "Meshers")
MESHERS = ("crossed", "gmsh", "gmsh-strip")
MESHER_DEFAULT = "gmsh-strip"
# elements per height of a failing part in the FE impulse scan (element size min(mesh size,
# h_part / PART_DIVISIONS)): at 30 a fan mechanism's v̄_g is within 0.25 % of its h_part/80
# value (B2, part 2.5 m: 0.4575, 0.4629, 0.4638, 0.4640, 0.4640 at /20, /30, /40, /60, /80);
# the scan under halving: docs/fe-impulse.md
PART_DIVISIONS = 30


@dataclass(frozen=True)
class Wall:
    """Geometry and weight of the façade + transversal wall (paper, Figure 1).

    H : height of façade and transversal wall [m]
    L : length of the transversal wall [m]
    s : thickness of the transversal wall [m]
    b : thickness of the façade [m]
    l : length of façade between two transversal walls [m]
    gamma : mass density of masonry [kg/m³]
    g : gravitational acceleration [m/s²]
    """

    H: float = ranged(0.0, lo_open=True, unit="m", default=9.0)
    L: float = ranged(0.0, lo_open=True, unit="m", default=6.0)
    s: float = ranged(0.0, lo_open=True, unit="m", default=0.5)
    b: float = ranged(0.0, lo_open=True, unit="m", default=0.5)
    l: float = ranged(0.0, lo_open=True, unit="m", default=6.0)
    gamma: float = ranged(0.0, lo_open=True, unit="kg/m^3", default=2000.0)
    g: float = ranged(0.0, lo_open=True, unit="m/s^2", default=G_STANDARD)

    def __post_init__(self):
        check_fields(self)

    @property
    def rho(self) -> float:
        """ρ = l/s (eq. 11)."""
        return self.l / self.s

    @property
    def lam_max(self) -> float:
        """Largest slenderness λ = h/b of a failing part: H/b."""
        return self.H / self.b


@dataclass(frozen=True)
class Masonry:
    """Running-bond masonry of rigid blocks of height a and length 2c, dry joints of friction f.

    a : block height [m];  c : half block length [m];  f : joint friction coefficient [-].
    fc : compressive strength [Pa]; 0 means infinite (the paper's rigid blocks, the default);
    cohesion, tension : the joints' cohesion and tensile strength [Pa] (the strength domains'
    names, ``fe.strength``), 0 by default (the paper's dry joints).
    """

    a: float = ranged(0.0, lo_open=True, unit="m", default=0.3)
    c: float = ranged(0.0, lo_open=True, unit="m", default=0.2)
    f: float = ranged(0.0, lo_open=True, default=0.6)
    fc: float = ranged(0.0, unit="Pa", default=0.0)
    cohesion: float = ranged(0.0, unit="Pa", default=0.0)
    tension: float = ranged(0.0, unit="Pa", default=0.0)

    def __post_init__(self):
        check_fields(self)

    @property
    def fc_finite(self) -> bool:
        """Whether the compressive strength is finite (fc > 0; 0 stands for infinite)."""
        return self.fc > 0.0

    @property
    def alpha(self) -> float:
        """α = √(cf/a) (eq. 11); also tan ψ of eq. 16."""
        return math.sqrt(self.c * self.f / self.a)


@dataclass(frozen=True)
class Tie:
    """A tie-rod anchored on the façade at height z [m] above the ground, pulling it inwards.

    yield_force : its yield force per metre of façade [N/m] (a bay of length l carries
    yield_force·l); stiffness : per metre of façade [N/m per m of elongation, N/m²], 0 for a
    rigid-plastic tie; ductility : the elongation at which it breaks [m], 0 for none (it
    yields without limit). docs/real-walls.md.
    """

    z: float = ranged(0.0, unit="m")
    yield_force: float = ranged(0.0, unit="N/m")
    stiffness: float = ranged(0.0, unit="N/m^2", default=0.0)
    ductility: float = ranged(0.0, unit="m", default=0.0)

    def __post_init__(self):
        check_fields(self, prefix="tie ")


@dataclass(frozen=True)
class Floor:
    """A floor bearing on the façade at height z [m]: its vertical dead load per metre of
    façade [N/m] acting at ``eccentricity`` [m] from the façade's outer face (0 <= e <= b);
    ``restrains``: it holds the façade horizontally at z (a failing body lies above it).
    Only its load bears on the façade: its mass moves with the building, not the façade."""

    z: float = ranged(0.0, unit="m")
    load: float = ranged(0.0, unit="N/m")
    eccentricity: float = ranged(0.0, unit="m")
    restrains: bool = False

    def __post_init__(self):
        check_fields(self, prefix="floor ")
        set_fields(self, restrains=bool(self.restrains))


@dataclass(frozen=True)
class FacadeOpening:
    """A band of openings in the façade, z_bottom <= z <= z_top [m] above the ground, open
    over ``fraction`` of the façade's length (0 <= fraction < 1). In the section plane the
    façade's weight and mass over the band scale by (1 − fraction); its strength does not
    (docs/real-walls.md "Openings")."""

    z_bottom: float = ranged(0.0, unit="m")
    z_top: float = ranged(0.0, lo_open=True, unit="m")
    fraction: float = ranged(0.0, 1.0, hi_open=True)

    def __post_init__(self):
        check_fields(self, prefix="facade_opening ")
        if self.z_top <= self.z_bottom:
            raise ParameterError(f"facade_opening z_top = {self.z_top!r} m is out of range: "
                                 f"allowed z_top > z_bottom = {self.z_bottom:g} m")


@dataclass(frozen=True)
class WallOpening:
    """A rectangular opening in the transversal wall, in the section plane: lower-left corner
    (x, z) [m] (x from the façade's outer face), ``width`` along x and ``height`` along z [m];
    it must lie inside the wall, b < x, x + width < b + L, 0 < z, z + height < H."""

    x: float = ranged(0.0, lo_open=True, unit="m")
    z: float = ranged(0.0, lo_open=True, unit="m")
    width: float = ranged(0.0, lo_open=True, unit="m")
    height: float = ranged(0.0, lo_open=True, unit="m")

    def __post_init__(self):
        check_fields(self, prefix="wall_opening ")

    @property
    def box(self) -> tuple[float, float, float, float]:
        """(x0, x1, z0, z1)."""
        return self.x, self.x + self.width, self.z, self.z + self.height


def opening_problems(H: float, b: float, L: float, facade=(), wall=()) -> list[str]:
    """The openings' checks against the wall and each other, one message per problem
    (``facade``, ``wall``: dicts of [[facade_opening]] / [[wall_opening]] entries, the keys
    given): a façade band within 0 <= z <= H with z_bottom < z_top, the bands disjoint; a wall
    rectangle strictly inside the transversal wall (b < x, x + width < b + L, 0 < z,
    z + height < H: it touches no edge), the rectangles neither overlapping nor touching."""
    out = []
    bands = []
    for k, e in enumerate(facade):
        z1, z2 = e.get("z_bottom"), e.get("z_top")
        if z2 is not None and z2 > H:
            out.append(f"[[facade_opening]] {k} z_top = {z2!r} m is out of range: allowed "
                       f"z_top <= H = {H:g} m")
        if z1 is not None and z2 is not None:
            if z2 <= z1:
                out.append(f"[[facade_opening]] {k} z_top = {z2!r} m is out of range: allowed "
                           f"z_top > z_bottom = {z1:g} m (a band of positive height)")
            else:
                bands.append((k, z1, z2))
    for i, (k, lo, hi) in enumerate(bands):
        for j, lo2, hi2 in bands[i + 1:]:
            if lo < hi2 and lo2 < hi:
                out.append(f"[[facade_opening]] {k} z = [{lo:g}, {hi:g}] m overlaps "
                           f"[[facade_opening]] {j} z = [{lo2:g}, {hi2:g}] m: allowed "
                           "disjoint bands")
    boxes = []
    for k, e in enumerate(wall):
        if not all(n in e for n in ("x", "z", "width", "height")):
            continue
        x0, x1, z0, z1 = e["x"], e["x"] + e["width"], e["z"], e["z"] + e["height"]
        bad = []
        if not x0 > b:
            bad.append(f"x = {x0!r} m: allowed x > b = {b:g} m")
        if not x1 < b + L:
            bad.append(f"x + width = {x1!r} m: allowed x + width < b + L = {b + L:g} m")
        if not z1 < H:
            bad.append(f"z + height = {z1!r} m: allowed z + height < H = {H:g} m")
        for msg in bad:
            out.append(f"[[wall_opening]] {k} {msg.split(':')[0]} is out of range "
                       f"(the opening must lie inside the transversal wall, touching no "
                       f"edge):{msg.split(':', 1)[1]}")
        if not bad:
            boxes.append((k, x0, x1, z0, z1))
    for i, (k, a0, a1, c0, c1) in enumerate(boxes):
        for j, d0, d1, e0, e1 in boxes[i + 1:]:
            if a0 <= d1 and d0 <= a1 and c0 <= e1 and e0 <= c1:
                out.append(f"[[wall_opening]] {k} (x {a0:g}..{a1:g}, z {c0:g}..{c1:g} m) "
                           f"overlaps or touches [[wall_opening]] {j} (x {d0:g}..{d1:g}, "
                           f"z {e0:g}..{e1:g} m): allowed separate openings")
    return out


@dataclass(frozen=True)
class Case:
    """One wall built of one masonry, with its tie-rods and floors; checks that the blocks
    fit the wall and the ties and floors lie on it."""

    wall: Wall = Wall()
    masonry: Masonry = Masonry()
    name: str = "case"
    ties: tuple = ()
    floors: tuple = ()
    facade_openings: tuple = ()
    wall_openings: tuple = ()

    def __post_init__(self):
        w, m = self.wall, self.masonry
        set_fields(self, ties=tuple(self.ties), floors=tuple(self.floors),
                   facade_openings=tuple(self.facade_openings),
                   wall_openings=tuple(self.wall_openings))
        bad = opening_problems(w.H, w.b, w.L, [_entry(o) for o in self.facade_openings],
                               [_entry(o) for o in self.wall_openings])
        if bad:
            raise ParameterError(bad[0])
        for k, t in enumerate(self.ties):
            check_range(f"tie {k} z", t.z, 0.0, w.H, lo_open=True, unit="m")
        for k, fl in enumerate(self.floors):
            check_range(f"floor {k} z", fl.z, 0.0, w.H, lo_open=True, unit="m")
            check_range(f"floor {k} eccentricity", fl.eccentricity, 0.0, w.b, unit="m")
        if m.a > w.H:
            raise ParameterError(f"a = {m.a!r} m is out of range: a block must not be taller "
                                 f"than the wall, allowed 0 < a <= H = {w.H:g} m")
        if 2 * m.c > w.L:
            raise ParameterError(f"c = {m.c!r} m is out of range: a block must fit the "
                                 f"transversal wall, allowed 0 < 2c <= L = {w.L:g} m")

    @property
    def rho(self) -> float:
        """ρ = l/s (eq. 11)."""
        return self.wall.rho

    @property
    def alpha(self) -> float:
        """α = √(cf/a) (eq. 11)."""
        return self.masonry.alpha

    @property
    def beta(self) -> float:
        """β = c/b (eq. 11)."""
        return self.masonry.c / self.wall.b

    def lam(self, h: float) -> float:
        """λ = h/b (eq. 11) for a failing part of height h, 0 < h <= H."""
        h = check_range("h", h, 0.0, self.wall.H, lo_open=True, unit="m")
        return h / self.wall.b

    @property
    def real(self) -> bool:
        """Whether the case has any input of a real wall beyond the paper's (finite fc,
        cohesion, tension, ties, floors, openings): docs/real-walls.md."""
        m = self.masonry
        return bool(self.ties or self.floors or m.fc or m.cohesion or m.tension
                    or self.facade_openings or self.wall_openings)

    def real_inputs(self) -> list[str]:
        """The case-file keys of the real-wall inputs this case sets (for the messages of the
        models that do not take them)."""
        m = self.masonry
        out = [f"[masonry] {k}" for k in ("fc", "cohesion", "tension") if getattr(m, k)]
        out += [f"[[tie]] {k}" for k in range(len(self.ties))]
        out += [f"[[floor]] {k}" for k in range(len(self.floors))]
        out += [f"[[facade_opening]] {k}" for k in range(len(self.facade_openings))]
        out += [f"[[wall_opening]] {k}" for k in range(len(self.wall_openings))]
        return out

    def as_dict(self) -> dict:
        return {"name": self.name,
                "wall": {f.name: getattr(self.wall, f.name) for f in fields(self.wall)},
                "masonry": {f.name: getattr(self.masonry, f.name) for f in fields(self.masonry)},
                "tie": [{f.name: getattr(t, f.name) for f in fields(t)} for t in self.ties],
                "floor": [_entry(x) for x in self.floors],
                "facade_opening": [_entry(x) for x in self.facade_openings],
                "wall_opening": [_entry(x) for x in self.wall_openings]}


def _entry(obj) -> dict:
    """A [[...]] entry's dataclass as a dict of its fields."""
    return {f.name: getattr(obj, f.name) for f in fields(obj)}
