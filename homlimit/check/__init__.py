"""The code check of a local mechanism: the linear kinematic analysis of NTC 2018 /
Circolare 2019 §C8.7.1.2 (``ntc``) against the site's elastic spectrum (``site``).
docs/code-check.md states what is computed and which reading of the code is taken."""

from .ntc import (
    LinearKinematic,
    NonlinearKinematic,
    StaticMechanism,
    linear_kinematic,
    nonlinear_kinematic,
    participation,
)
from .site import SOILS, TOPOGRAPHIES, Site, elastic_spectrum, soil_factors, topography_factor

__all__ = ["LinearKinematic", "NonlinearKinematic", "SOILS", "Site", "StaticMechanism",
           "TOPOGRAPHIES", "elastic_spectrum", "linear_kinematic", "nonlinear_kinematic",
           "participation", "soil_factors", "topography_factor"]
