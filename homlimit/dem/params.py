"""The DEM's parameters: every unknown the paper leaves open, named, validated, with its source.

The paper (seed paper, "Numerical prediction of collapse load") states only: rigid blocks,
point contacts with a no-tension elastic normal spring and an elastic–plastic tangential
spring with Coulomb friction f = 0.6, the façade's density raised by ρ = l/s and "the contact
stiffnesses similarly modified so as to obtain a uniform lowering of the wall under its own
weight", no damping, an impulsive load. Everything else below is a choice of this package.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass

import numpy as np

from ..blocks.geometry import TOOTHINGS  # a T-section's toothing blocks' density
from ..errors import ParameterError, check_range

__all__ = ["DEMParams", "BASE_JOINTS", "AUTO_SEGMENTS", "TOOTHINGS"]

BASE_JOINTS = ("frictional", "tied")
#: joint_segments = 0 (auto) with a finite f_c: each free block's bottom edge in 8 segments
AUTO_SEGMENTS = 8


@dataclass(frozen=True)
class DEMParams:
    """Parameters of the explicit rigid-block DEM (SI units).

    kn [Pa/m]: joint normal stiffness per unit joint area; a contact point gets
        kn × (its tributary length) × (slab thickness s), fixed when the contact is created.
        Default 1e9 Pa/m: not given by the paper; the order of the joint stiffnesses used in
        UDEC models of masonry (10⁹–10¹⁰ Pa/m; see the review of Lemos 2007, Int. J. Archit.
        Herit. 1(2), whose figures were not re-checked here). The lower end keeps the time
        step long; the self-weight lowering of B1's 9 m wall is then 2.8 mm at the top
        (measured, tests/test_dem.py).
    ks_over_kn [-]: shear over normal stiffness. Default 0.5: not given by the paper; a
        common UDEC choice (an elastic interface of Poisson's ratio ν has 1/(2(1 + ν)) ≈ 0.4).
    facade_stiffness: "rho" (default: the paper's uniform lowering, the façade's contacts
        stiffened by ρ = l/s like its density) or a positive factor [-]. Applies to contacts
        whose tributary segment lies in the façade strip x < b (T-sections only).
    toothing: the density of a T-section's toothing blocks, each [0, b + c] across the façade
        and its tooth in the wall (``t_section_model`` builds it; ``t_section_blocks``):
        "split" (default: ρ·γ over the façade, γ over the tooth) or "block" (ρ·γ over the
        whole block, as a DEM that gives each block one material, assigned by where the
        block lies: its centroid lies in the façade when c < b, as in all of Table 1). Not
        in the paper (docs/dem.md sections 16-17).
    dt_fraction [-]: dt = dt_fraction × √(m_min / k_max), m_min the lightest free block,
        k_max the stiffest contact that can form (normal or shear, whichever is stiffer).
        Default 0.1 (package choice: a block held by up to ~40 such springs stays below the
        central-difference limit ω dt < 2).
    settle_damping [-]: Cundall's local damping coefficient while settling under gravity
        (each force component reduced by α|F| against the velocity). Default 0.8, UDEC's
        default for static solutions (Itasca UDEC manual). No damping after settling
        (the paper: damping nil).
    settle_time [s]: the longest settling run; settle_velocity [m/s]: settling stops once
        every block is slower than this. Defaults 2 s and 1e-5 m/s (package choice).
    base_joint: "frictional" (default; the paper's UDEC base is a joint like the others,
        friction f) or "tied" (the contacts with the ground present at the start neither open
        nor slide).
    ground_margin [m]: the ground is widened by this on both sides (the assembly's ground
        ends flush with the façade's toe). Default 2 m.
    verlet_margin [m]: contact candidates are every vertex–edge pair closer than this; the
        list is rebuilt once a block has moved (translation + rotation × radius) by half of
        it. Default 5 mm.
    cone_tolerance [rad]: a vertex touches an edge only if the edge's inward normal lies in
        the vertex's normal cone widened by this. Default 0.05 rad (package choice).
    trib_floor [-]: a contact's tributary length is at least this fraction of the shorter
        of its edge and the vertex's adjacent edge (corner-to-edge contacts). Default 0.05.
    joint_segments [-]: contact points along the bed joints: every free block's bottom edge
        is split into this many equal segments by vertices on it (each a contact point with
        its tributary; a point within verlet_margin of another block's vertex is left out,
        so it never doubles a corner contact). 1: the corners only (the paper's UDEC model,
        two points per joint). 0 (default, auto): 1 with f_c infinite, ``AUTO_SEGMENTS`` = 8
        with a finite ``[masonry] fc``, whose cap per point (f_c × tributary × depth) forms
        the stress block only with points along the joint (package choice: B1's façade
        joint of 0.5 m in 62.5 mm; docs/dem.md, "Crushing cap"). The points also change the
        joint's rotational stiffness (kn L³/4 with corners only, → kn L³/12 with many).
    """

    kn: float = 1.0e9
    ks_over_kn: float = 0.5
    facade_stiffness: object = "rho"
    toothing: str = "split"
    dt_fraction: float = 0.1
    settle_damping: float = 0.8
    settle_time: float = 2.0
    settle_velocity: float = 1.0e-5
    base_joint: str = "frictional"
    ground_margin: float = 2.0
    verlet_margin: float = 0.005
    cone_tolerance: float = 0.05
    trib_floor: float = 0.05
    joint_segments: int = 0

    def __post_init__(self):
        check_range("kn", self.kn, 0.0, lo_open=True, unit="Pa/m")
        check_range("ks_over_kn", self.ks_over_kn, 0.0, 10.0, lo_open=True)
        fs = self.facade_stiffness
        if not (fs == "rho" or (not isinstance(fs, (str, bool)) and _positive(fs))):
            raise ParameterError(f"facade_stiffness = {fs!r} is out of range: allowed 'rho' or "
                                 "a number > 0")
        if self.toothing not in TOOTHINGS:
            raise ParameterError(f"toothing = {self.toothing!r} is out of range: allowed "
                                 f"{', '.join(TOOTHINGS)}")
        check_range("dt_fraction", self.dt_fraction, 0.0, 0.5, lo_open=True)
        check_range("settle_damping", self.settle_damping, 0.0, 1.0, hi_open=True)
        check_range("settle_time", self.settle_time, 0.0, unit="s")
        check_range("settle_velocity", self.settle_velocity, 0.0, lo_open=True, unit="m/s")
        if self.base_joint not in BASE_JOINTS:
            raise ParameterError(f"base_joint = {self.base_joint!r} is out of range: allowed "
                                 f"{', '.join(BASE_JOINTS)}")
        check_range("ground_margin", self.ground_margin, 0.0, unit="m")
        check_range("verlet_margin", self.verlet_margin, 0.0, lo_open=True, unit="m")
        check_range("cone_tolerance", self.cone_tolerance, 0.0, 0.5, unit="rad")
        check_range("trib_floor", self.trib_floor, 0.0, 0.5, lo_open=True)
        js = self.joint_segments
        if isinstance(js, bool) or not isinstance(js, (int, np.integer)) or not 0 <= js <= 64:
            raise ParameterError(f"joint_segments = {js!r} is out of range: allowed an integer "
                                 "0 <= joint_segments <= 64 (0: auto)")

    def segments(self, fc: float) -> int:
        """The bottom edges' segments for a compressive strength fc [Pa] (0: infinite)."""
        return self.joint_segments or (AUTO_SEGMENTS if fc > 0 else 1)

    def as_dict(self) -> dict:
        return asdict(self)


def _positive(x) -> bool:
    try:
        return float(x) > 0 and float(x) < float("inf")
    except (TypeError, ValueError):
        return False
