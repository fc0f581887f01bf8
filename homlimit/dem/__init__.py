"""An explicit rigid-block DEM of the package's block assemblies (issue 29), UDEC-style.

    from homlimit.blocks.geometry import t_section_blocks
    from homlimit.dem import DEMParams, build_model, settle, run
    model = build_model(t_section_blocks(case))
    settled, info = settle(model)
    out = run(model, settled, v_g=0.8)          # the ideal impulse

Modules: ``params`` (``DEMParams``, every parameter with its default's source), ``kernels``
(the numba loops), ``model`` (the model of an assembly, settling, time histories, the
collapse criterion), ``threshold`` (the collapse threshold by bisection). Write-up: docs/dem.md.
"""

from .model import DEMModel, DEMState, Outcome, build_model, run, settle
from .params import BASE_JOINTS, DEMParams

__all__ = ["BASE_JOINTS", "DEMModel", "DEMParams", "DEMState", "Outcome", "build_model", "run",
           "settle"]
