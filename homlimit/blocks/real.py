"""The actions of a real wall on a rigid-block assembly: finite compressive strength, the
joints' cohesion and tensile strength, tie-rods and floors (issue 30; conventions of
docs/real-walls.md, the blocks' terms: docs/real-walls.md "Rigid blocks").

The section's forces are per slab (the assembly's masses are per slab: the façade's ρ γ s is
γ l, the bay of length l), so a tie or a floor given per metre of façade carries its value × l,
as in the closed forms. ``RealActions`` holds them in the section's units and lives in
``Assembly.meta["real"]`` (``t_section_blocks`` puts it there from the case; ``fix_below``
keeps it), so the h-scan and every solve see them.

- f_c: every contact of length L and out-of-plane depth d (the façade's l where the contact's
  midpoint lies in the façade, x < b, the transversal wall's s elsewhere) carries normal
  stresses 0 <= σ <= f_c: with the end-point forces N_0, N_1 of ``limit`` the domain is
  exactly N_e >= (N_0 + N_1)² / (2 C), C = f_c d L, per end (the rectangular stress block: the
  resultant at least w/2 = N/(2 f_c d) from either end).
- cohesion C and tension T: every contact carries, pointwise, a normal stress σ >= −T_h
  (tension) and a shear |τ| <= f σ + C (Mohr–Coulomb), T_h = min(T, C/f): a tension beyond
  the Coulomb apex C/f, or without cohesion, has no effect (the FE's ``fe.strength.
  BedJoints`` and ``Homogenised`` rule). Over the contact's area A = L d (d as for f_c):
  N_e >= −T_h A/2 per end and |V| <= f N + C A (``limit``, module docstring).
- a tie at height z: a force 0 <= F <= T_y pulling the façade block at that height towards the
  wall (+x), at the outer face (x = 0): the block whose outer face holds z (the lower one at a
  joint, as the closed forms: a tie at a hinge does not act on the part above).
- a floor at height z: a dead vertical load Q at (e, z) on that block; ``restrains``: a
  horizontal support there (no horizontal velocity of the block's point at height z).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..errors import ParameterError, check_range
from ..fields import set_fields

__all__ = ["RealActions", "from_case", "real_of", "anchor_blocks"]


@dataclass(frozen=True)
class RealActions:
    """Ties, floors, f_c, cohesion and tension of an assembly in the section's units (module
    docstring).

    fc            compressive strength [Pa]; 0: infinite (no cap)
    cohesion      the joints' cohesion C [Pa] (0: none)
    tension       the joints' tensile strength T [Pa]; it acts up to the Coulomb apex,
                  T_h = min(T, C/f) (``tension_effective``)
    depth_facade  out-of-plane depth of a contact in the façade (x_mid < x_junction) [m]
    depth_wall    ... elsewhere (the transversal wall) [m]
    x_junction    the façade's inner face b [m] (inf: every contact is the façade's)
    ties          (n, 4): z [m], yield force T_y [N], stiffness [N/m], ductility [m] (0: none)
    floors        (n, 4): z [m], load Q [N], eccentricity e [m], restrains (1.0 or 0.0)
    """

    fc: float = 0.0
    depth_facade: float = 1.0
    depth_wall: float = 1.0
    x_junction: float = math.inf
    ties: np.ndarray = field(default_factory=lambda: np.zeros((0, 4)))
    floors: np.ndarray = field(default_factory=lambda: np.zeros((0, 4)))
    cohesion: float = 0.0
    tension: float = 0.0

    def __post_init__(self):
        for name in ("fc", "cohesion", "tension"):
            set_fields(self, **{name: check_range(name, getattr(self, name), 0.0,
                                                  unit="Pa")})
        for name in ("depth_facade", "depth_wall"):
            set_fields(self, **{name: check_range(name, getattr(self, name), 0.0, lo_open=True,
                                                  unit="m")})
        for name in ("ties", "floors"):
            arr = np.asarray(getattr(self, name), float).reshape(-1, 4)
            if not np.all(np.isfinite(arr[:, :3])) or np.any(arr[:, :3] < 0):
                raise ParameterError(f"{name} = {arr.tolist()!r} is out of range: allowed "
                                     "finite values >= 0 (z, force, stiffness or e)")
            set_fields(self, **{name: arr})

    @property
    def active(self) -> bool:
        """Whether there is anything to add to the paper's program (a tension acts only with
        a cohesion: ``tension_effective``)."""
        return bool(self.fc > 0 or len(self.ties) or len(self.floors) or self.cohesion > 0)

    @property
    def bond(self) -> bool:
        """Whether the joints have a strength of their own (a cohesion; a tension acts only
        with one: ``tension_effective``)."""
        return self.cohesion > 0

    def tension_effective(self, f: float) -> float:
        """T_h = min(T, C/f) [Pa]: the tension cut-off inside the Coulomb apex."""
        return min(self.tension, self.cohesion / f)

    def depth(self, x_mid: np.ndarray) -> np.ndarray:
        """Out-of-plane depth [m] of contacts with midpoints at x_mid."""
        return np.where(np.asarray(x_mid) < self.x_junction - 1e-12, self.depth_facade,
                        self.depth_wall)

    def as_dict(self) -> dict:
        return {"fc": self.fc, "fc_infinite": not self.fc, "cohesion": self.cohesion,
                "tension": self.tension, "depth_facade": self.depth_facade,
                "depth_wall": self.depth_wall,
                "ties": [dict(zip(("z", "yield_force_N", "stiffness_N_per_m", "ductility"),
                                  map(float, t))) for t in self.ties],
                "floors": [dict(zip(("z", "load_N", "eccentricity", "restrains"),
                                    (float(f[0]), float(f[1]), float(f[2]), bool(f[3]))))
                           for f in self.floors]}


def from_case(case) -> RealActions | None:
    """The case's real-wall actions per bay (a value per metre of façade × l), or None when
    the case has none (the paper's program, unchanged). Cohesion and tension are stresses:
    the contact's depth carries them (``RealActions.depth``)."""
    w, m = case.wall, case.masonry
    if not (case.ties or case.floors or m.fc or m.cohesion or m.tension):
        return None
    ties = [(t.z, t.yield_force * w.l, t.stiffness * w.l, t.ductility) for t in case.ties]
    floors = [(f.z, f.load * w.l, f.eccentricity, float(f.restrains)) for f in case.floors]
    return RealActions(fc=m.fc, cohesion=m.cohesion, tension=m.tension,
                       depth_facade=w.l, depth_wall=w.s, x_junction=w.b,
                       ties=np.array(ties, float).reshape(-1, 4),
                       floors=np.array(floors, float).reshape(-1, 4))


def real_of(assembly) -> RealActions | None:
    """The assembly's active ``RealActions`` (meta["real"]), or None."""
    r = assembly.meta.get("real")
    if r is None:
        return None
    if not isinstance(r, RealActions):
        raise ParameterError(f"meta['real'] = {type(r).__name__} is out of range: allowed a "
                             "homlimit.blocks.real.RealActions")
    return r if r.active else None


def anchor_blocks(assembly, z: np.ndarray) -> np.ndarray:
    """Per height z, the free block whose outer face (x = 0) holds z: x_min <= 0 < x_max and
    z_min < z <= z_max (the lower block at a joint); −1 where none is free (a fixed part of the
    h-scan: the action is taken by the support)."""
    z = np.atleast_1d(np.asarray(z, float))
    bb = assembly.bounds()
    tol = 1e-9 * max(1.0, float(np.ptp(assembly.vertices[:, 1])))
    outer = (bb[:, 0] <= tol) & (bb[:, 2] > tol)
    hit = (outer[None, :] & (bb[None, :, 1] < z[:, None] - tol)
           & (z[:, None] <= bb[None, :, 3] + tol))
    idx = np.where(hit.any(axis=1), hit.argmax(axis=1), -1)
    return np.where((idx >= 0) & ~assembly.fixed[np.maximum(idx, 0)], idx, -1)
