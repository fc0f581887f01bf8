"""The [dem] section's keys (``app.schema``'s SCHEMA["dem"]): the rigid-block DEM's
parameters, their defaults read from ``dem.params.DEMParams`` (no numba imported)."""

from __future__ import annotations

from ..dem.params import BASE_JOINTS, TOOTHINGS, DEMParams
from .schema_key import Key

__all__ = ["DEM_KEYS"]

_DEM = DEMParams()   # [dem]'s defaults (facade_stiffness: the case file's 0 is its "rho")

#: key -> Key of the [dem] section
DEM_KEYS: dict[str, Key] = {
    "kn": Key(float, _DEM.kn, "Pa/m", 1e5, 1e13,
              doc="joint normal stiffness per unit joint area (a contact point gets kn × "
                  "tributary length × s); not in the paper: the order of UDEC joint "
                  "stiffnesses for masonry, 10⁹–10¹⁰ Pa/m (Lemos 2007), the lower end "
                  "for a longer time step"),
    "ks_over_kn": Key(float, _DEM.ks_over_kn, "", 0.0, 10.0, lo_open=True,
                      doc="shear over normal joint stiffness; not in the paper: a common "
                          "UDEC choice (an elastic interface: 1/(2(1 + ν)) ≈ 0.4)"),
    "facade_stiffness": Key(float, 0.0, "", 0.0, 1e3,
                            doc="factor on the façade's contact stiffness (0: ρ = l/s, "
                                "the paper's uniform lowering: contacts stiffened like "
                                "the façade's density)"),
    "toothing": Key(str, _DEM.toothing, choices=TOOTHINGS,
                    doc="density of the toothing blocks (each spans the façade and its "
                        "tooth in the wall): split (ρ·γ over the façade, γ over the "
                        "tooth) or block (ρ·γ over the whole block: a DEM's one material "
                        "per block, its centroid in the façade; docs/dem.md sections "
                        "16-17)"),
    "dt_fraction": Key(float, _DEM.dt_fraction, "", 0.0, 0.5, lo_open=True,
                       doc="dt = dt_fraction × √(m_min/k_max) (package choice: a block "
                           "held by ~40 such springs stays below the central-difference "
                           "limit)"),
    "settle_damping": Key(float, _DEM.settle_damping, "", 0.0, 1.0, hi_open=True,
                          doc="Cundall's local damping while settling under gravity "
                              "(UDEC's default for static solutions); none after"),
    "settle_time": Key(float, _DEM.settle_time, "s", 0.0, 600.0,
                       doc="longest settling run (package choice)"),
    "settle_velocity": Key(float, _DEM.settle_velocity, "m/s", 0.0, 1.0, lo_open=True,
                           doc="settling stops once every block is slower (package "
                               "choice)"),
    "base_joint": Key(str, _DEM.base_joint, choices=BASE_JOINTS,
                      doc="joint with the ground: frictional like the others (the "
                          "paper's UDEC base is not described) or tied (the contacts "
                          "present at the start neither open nor slide)"),
    "ground_margin": Key(float, _DEM.ground_margin, "m", 0.0, 100.0,
                         doc="the ground is widened by this on both sides (the "
                             "assembly's ends flush with the façade's toe; package "
                             "choice)"),
    "verlet_margin": Key(float, _DEM.verlet_margin, "m", 0.0, 0.1, lo_open=True,
                         doc="contact candidates: vertex–edge pairs closer than this; "
                             "rebuilt after a move of half of it (package choice)"),
    "cone_tolerance": Key(float, _DEM.cone_tolerance, "rad", 0.0, 0.5,
                          doc="widening of a vertex's normal cone in the contact test "
                              "(package choice)"),
    "trib_floor": Key(float, _DEM.trib_floor, "", 0.0, 0.5, lo_open=True,
                      doc="least tributary length, as a fraction of the shorter edge "
                          "(package choice)"),
    "joint_segments": Key(int, _DEM.joint_segments, "", 0, 64,
                          doc="contact points along the bed joints: each free block's "
                              "bottom edge split into this many segments (1: the corners "
                              "only, the paper's UDEC model; 0: auto, 1 with [masonry] fc "
                              "infinite, 8 with a finite fc, whose cap per point forms the "
                              "stress block only with points along the joint; package "
                              "choice, docs/dem.md)"),
    "loading": Key(str, "impulse", choices=("impulse", "rectangular", "one-sine",
                                            "one-cosine", "ricker", "record"),
                   doc="the load whose threshold is found: the ideal impulse (v̄_g, the "
                       "paper's), a base-acceleration pulse of duration/period "
                       "pulse_period (its amplitude a_g; homlimit.dynamics.pulses) or the "
                       "accelerogram of record (its scale, as its pga)"),
    "pulse_period": Key(float, 0.2, "s", 1e-3, 100.0,
                        doc="Δt of the pulse (rectangular: its duration; loading other "
                            "than impulse)"),
    "polarity": Key(int, 1, choices=(1, -1),
                    doc="pulse polarity: +1 pushes the ground towards +x first (the "
                        "façade's inertia outwards)"),
    "record": Key(str, "", doc="with loading = \"record\": a ground-acceleration record, "
                               "two-column CSV t [s], a_g [m/s²] (relative to the case "
                               "file), applied as base acceleration from t = 0, scaled by "
                               "polarity; the threshold is its pga"),
    "rel_tol": Key(float, 0.01, "", 0.0, 0.5, lo_open=True,
                   doc="bisection tolerance of the threshold: (hi − lo)/(hi + lo)"),
    "t_max": Key(float, 5.0, "s", 0.0, 600.0, lo_open=True,
                 doc="length of a trial: a trial collapses when a façade or toothing "
                     "block moved outwards by more than H/4 before t_max "
                     "(docs/dem.md, section 3)"),
    "guess": Key(float, 0.0, "", 0.0, 1e4,
                 doc="first trial amplitude (m/s, or m/s² for a pulse; 0: the paper's "
                     "v̄_g rounded to 0.1 for a Table 1 wall, else mechanism I's; a "
                     "pulse: the larger of mechanism I's static multiplier × g and the "
                     "a_g whose pgv is that v̄_g); it only sets where "
                     "the bracket search (steps of ×1.5) starts"),
    "max_blocks": Key(int, 5000, "", 1, 10 ** 6,
                      doc="largest assembly allowed ((H/a)(L/2c + 1) blocks; B1's 480 "
                          "blocks take ~60 µs per time step, 75–80 s of CPU per "
                          "threshold)"),
    "frame_interval": Key(float, 0.05, "s", 1e-4, 10.0,
                          doc="time between the frames of the ParaView series of the "
                              "lowest collapsing trial (dem.pvd) and of the animation"),
    "animation": Key(bool, True,
                     doc="with [output] png, write dem_animation.gif: the lowest "
                         "collapsing trial beside the highest standing one (one more "
                         "trial of up to t_max, and the rendering)"),
}
