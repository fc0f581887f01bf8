"""An explicit rigid-block DEM of the package's block assemblies (issue 29), UDEC-style.

    from homlimit.dem import DEMParams, settle, run, t_section_model
    model = t_section_model(case)                # or build_model(any assembly, DEMParams())
    settled, info = settle(model)
    out = run(model, settled, v_g=0.8)          # the ideal impulse

Modules: ``params`` (``DEMParams``, every parameter with its default's source), ``kernels``
(the numba loops), ``model`` (the model of an assembly, settling, time histories, the
collapse criterion), ``threshold`` (the collapse threshold by bisection). Write-up: docs/dem.md.

Start-up: the parameters load with the package; the model's names, which load numba (half a
second, and its JIT), are imported on first use by the module ``__getattr__`` below (PEP 562,
as ``homlimit``'s own), so that the case file's [dem] defaults come from ``DEMParams``
(``app.schema``) without numba.
"""

from typing import TYPE_CHECKING

from .params import BASE_JOINTS, DEMParams

if TYPE_CHECKING:  # the deferred names, for type checkers and editors
    from .model import DEMModel, DEMState, Outcome, build_model, run, settle, t_section_model

__all__ = ["BASE_JOINTS", "DEMModel", "DEMParams", "DEMState", "Outcome", "build_model", "run",
           "settle", "t_section_model"]
_MODEL = ("DEMModel", "DEMState", "Outcome", "build_model", "run", "settle", "t_section_model")


def __getattr__(name: str):
    """The model's names, imported on first use (PEP 562)."""
    if name not in _MODEL:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    from . import model

    value = getattr(model, name)
    globals()[name] = value  # later look-ups skip __getattr__
    return value


def __dir__():
    return sorted(set(globals()) | set(__all__))
