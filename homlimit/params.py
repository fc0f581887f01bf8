"""Immutable parameter objects: the wall, the masonry, and the dimensionless numbers of eq. 11.

Frame (see docs): x horizontal from the façade's outer face into the building, z up.
Façade strip 0 <= x <= b, transversal wall b <= x <= b + L, both of height H. SI units throughout.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields

from .errors import ParameterError, check_range
from .fields import check_fields, ranged, set_fields

__all__ = ["Wall", "Masonry", "Case", "Tie", "Floor", "G_STANDARD", "FACADE_DEFAULT",
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
class Case:
    """One wall built of one masonry, with its tie-rods and floors; checks that the blocks
    fit the wall and the ties and floors lie on it."""

    wall: Wall = Wall()
    masonry: Masonry = Masonry()
    name: str = "case"
    ties: tuple = ()
    floors: tuple = ()

    def __post_init__(self):
        w, m = self.wall, self.masonry
        set_fields(self, ties=tuple(self.ties), floors=tuple(self.floors))
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
        cohesion, tension, ties, floors): docs/real-walls.md."""
        m = self.masonry
        return bool(self.ties or self.floors or m.fc or m.cohesion or m.tension)

    def real_inputs(self) -> list[str]:
        """The case-file keys of the real-wall inputs this case sets (for the messages of the
        models that do not take them)."""
        m = self.masonry
        out = [f"[masonry] {k}" for k in ("fc", "cohesion", "tension") if getattr(m, k)]
        out += [f"[[tie]] {k}" for k in range(len(self.ties))]
        out += [f"[[floor]] {k}" for k in range(len(self.floors))]
        return out

    def as_dict(self) -> dict:
        return {"name": self.name,
                "wall": {f.name: getattr(self.wall, f.name) for f in fields(self.wall)},
                "masonry": {f.name: getattr(self.masonry, f.name) for f in fields(self.masonry)},
                "tie": [{f.name: getattr(t, f.name) for f in fields(t)} for t in self.ties],
                "floor": [{f.name: getattr(x, f.name) for f in fields(x)}
                          for x in self.floors]}
