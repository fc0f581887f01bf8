"""homlimit: out-of-plane collapse of masonry façades bonded to transversal walls.

Closed-form mechanisms I and II of the reference paper, a homogenised-continuum finite-element
limit analysis (cvxpy + Clarabel) that finds the collapse mechanism and its crack, and the
energy-based impulse criterion that turns any mechanism into a collapse ground velocity.

>>> import homlimit
>>> case = homlimit.Case(homlimit.Wall(H=9, L=6, s=0.5, b=0.5, l=6),
...                      homlimit.Masonry(a=0.3, c=0.2, f=0.6))
>>> round(homlimit.mechanism_I(case).vg, 3), round(homlimit.mechanism_II(case).vg, 3)
(0.819, 1.094)
"""

from .app.pipeline import package_version, run
from .closed_form.mechanisms import mechanism_I, mechanism_II
from .errors import HomlimitError, MeshError, ParameterError, SolverError
from .params import Case, Masonry, Wall

__version__ = package_version()

__all__ = [
    "__version__",
    "Case",
    "HomlimitError",
    "Masonry",
    "MeshError",
    "ParameterError",
    "SolverError",
    "Wall",
    "mechanism_I",
    "mechanism_II",
    "run",
]
