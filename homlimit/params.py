"""Immutable parameter objects: the wall, the masonry, and the dimensionless numbers of eq. 11.

Frame (see docs): x horizontal from the façade's outer face into the building, z up.
Façade strip 0 <= x <= b, transversal wall b <= x <= b + L, both of height H. SI units throughout.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields

from .errors import ParameterError, check_range

__all__ = ["Wall", "Masonry", "Case", "G_STANDARD", "FACADE_DEFAULT", "FACADE_MODELS",
           "MESHERS", "MESHER_DEFAULT", "PART_DIVISIONS"]

G_STANDARD = 9.81  # m/s², the value used throughout the paper's examples
# strength of the façade in the section plane: bed joints only (its blocks run through the
# thickness b, as the paper builds it: the default), or eq. 15 like the wall (the β → 0
# idealisation, in which a crack may cut the façade diagonally)
FACADE_MODELS = ("homogenised", "bedjoints")
FACADE_DEFAULT = "bedjoints"
# the meshes of the T-section (fe.problems.t_section): the crossed structured grid (every cell
# cut by its diagonals; the default), gmsh unstructured (refined along the junction), and gmsh
# with the façade strip structured and x-aligned like the crossed grid, the wall unstructured
MESHERS = ("crossed", "gmsh", "gmsh-strip")
MESHER_DEFAULT = "crossed"
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

    H: float = 9.0
    L: float = 6.0
    s: float = 0.5
    b: float = 0.5
    l: float = 6.0
    gamma: float = 2000.0
    g: float = G_STANDARD

    def __post_init__(self):
        for name, unit in (("H", "m"), ("L", "m"), ("s", "m"), ("b", "m"), ("l", "m"),
                           ("gamma", "kg/m^3"), ("g", "m/s^2")):
            object.__setattr__(self, name, check_range(name, getattr(self, name), 0.0,
                                                       lo_open=True, unit=unit))

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
    """

    a: float = 0.3
    c: float = 0.2
    f: float = 0.6

    def __post_init__(self):
        object.__setattr__(self, "a", check_range("a", self.a, 0.0, lo_open=True, unit="m"))
        object.__setattr__(self, "c", check_range("c", self.c, 0.0, lo_open=True, unit="m"))
        object.__setattr__(self, "f", check_range("f", self.f, 0.0, lo_open=True))

    @property
    def alpha(self) -> float:
        """α = √(cf/a) (eq. 11); also tan ψ of eq. 16."""
        return math.sqrt(self.c * self.f / self.a)


@dataclass(frozen=True)
class Case:
    """One wall built of one masonry; checks that the blocks fit the wall."""

    wall: Wall = Wall()
    masonry: Masonry = Masonry()
    name: str = "case"

    def __post_init__(self):
        w, m = self.wall, self.masonry
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

    def as_dict(self) -> dict:
        return {"name": self.name,
                "wall": {f.name: getattr(self.wall, f.name) for f in fields(self.wall)},
                "masonry": {f.name: getattr(self.masonry, f.name) for f in fields(self.masonry)}}
