"""homlimit: out-of-plane collapse of masonry façades bonded to transversal walls.

Closed-form mechanisms I and II of the reference paper, a homogenised-continuum finite-element
limit analysis (cvxpy + Clarabel) that finds the collapse mechanism and its crack, and the
energy-based impulse criterion that turns any mechanism into a collapse ground velocity.

>>> import homlimit
>>> case = homlimit.Case(homlimit.Wall(H=9, L=6, s=0.5, b=0.5, l=6),
...                      homlimit.Masonry(a=0.3, c=0.2, f=0.6))
>>> round(homlimit.mechanism_I(case).vg, 3), round(homlimit.mechanism_II(case).vg, 3)
(0.819, 1.094)

Start-up: this is the one place where the dependencies are deferred. ``import homlimit`` loads
the parameters and the errors (pure Python); the closed forms (numpy), ``run`` (cvxpy, Clarabel,
scikit-fem, gmsh, meshio, scipy, matplotlib, dask and pyarrow, through ``app.pipeline``) and
``__version__`` are imported on first use by the module ``__getattr__`` below (PEP 562). The
command line defers the same way: ``homlimit --version`` answers in ``__main__`` before typer is
imported, and each command of ``app.cli`` imports the pipeline when it runs. ``homlimit.dem``
defers its numba-backed model the same way (its parameters load without numba, for the case
file's [dem] defaults). Every other module imports at its top.
"""

from typing import TYPE_CHECKING

from .errors import HomlimitError, MeshError, ParameterError, SolverError
from .params import Case, Masonry, Wall

if TYPE_CHECKING:  # the deferred names, for type checkers and editors
    from .app.pipeline import run
    from .closed_form.mechanisms import mechanism_I, mechanism_II

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


def __getattr__(name: str):
    """The deferred names, imported on first use (PEP 562)."""
    if name == "__version__":
        from ._version import package_version

        value = package_version()
    elif name == "run":
        from .app.pipeline import run as value
    elif name in ("mechanism_I", "mechanism_II"):
        from .closed_form import mechanisms

        value = getattr(mechanisms, name)
    else:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    globals()[name] = value  # later look-ups skip __getattr__
    return value


def __dir__():
    return sorted(set(globals()) | set(__all__))
