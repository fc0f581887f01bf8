"""homlimit: out-of-plane collapse of masonry façades bonded to transversal walls.

Closed-form mechanisms I and II of the reference paper, a homogenised-continuum finite-element
limit analysis (cvxpy + Clarabel) that finds the collapse mechanism and its crack, and the
energy-based impulse criterion that turns any mechanism into a collapse ground velocity.
"""

from .app.pipeline import run
from .errors import HomlimitError, MeshError, ParameterError, SolverError
from .params import Case, Masonry, Wall

__version__ = "0.1.0"

__all__ = [
    "__version__",
    "Case",
    "HomlimitError",
    "Masonry",
    "MeshError",
    "ParameterError",
    "SolverError",
    "Wall",
    "run",
]
