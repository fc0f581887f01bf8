"""Rocking dynamics: the impulse criterion (eqs 1–7) checked by time history, and extended
from the ideal impulse to real pulses.

- ``pulses``: ground-motion pulses a_g(t) (rectangular, one-sine, one-cosine, Ricker,
  Mavroeidis–Papageorgiou, user record);
- ``rocking``: one-DOF equations of motion of mechanisms I and II, any rigid body (the FE
  body), the FE one-DOF shape, a free-standing block with Housner's impact;
- ``real_rocker``: a real wall's closed-form mechanisms (fc, ties, floors: issue 30);
- ``integrate``: ``simulate`` (solve_ivp between events, energy decision after the pulse);
- ``threshold``: ``critical_pulse`` (smallest overturning amplitude, brentq);
- ``spectra``: overturning spectra per mechanism (typed records);
- ``housner``: small-angle closed forms of the free-standing block (the references).
"""

from .integrate import IntegrationOptions, Response, simulate
from .pulses import (
    PULSE_KINDS,
    MavroeidisPapageorgiouPulse,
    OneCosinePulse,
    OneSinePulse,
    RecordPulse,
    RectangularPulse,
    RickerPulse,
    make_pulse,
)
from .real_rocker import RealWallRocker
from .rocking import GeneralisedRocker, MechanismIRocker, RigidRocker, free_block
from .spectra import SpectrumPoint, case_rockers, case_spectra, overturning_spectrum
from .threshold import HoldingPulse, Threshold, critical_pulse, holding_pulse

__all__ = [
    "PULSE_KINDS", "GeneralisedRocker", "IntegrationOptions", "MavroeidisPapageorgiouPulse",
    "MechanismIRocker", "OneCosinePulse", "OneSinePulse", "RecordPulse", "RectangularPulse",
    "HoldingPulse", "RealWallRocker", "Response", "RickerPulse", "RigidRocker", "SpectrumPoint",
    "Threshold",
    "case_rockers", "holding_pulse",
    "case_spectra", "critical_pulse", "free_block", "make_pulse", "overturning_spectrum",
    "simulate",
]
