"""What every stage of every command shares: its timing and log lines (``stage``), the
solver settings of a run (``solver_options``) and the finiteness test of a result
(``finite``)."""

from __future__ import annotations

import logging
import math
import time
from contextlib import contextmanager

from ..fe.solver import SolverOptions

__all__ = ["finite", "solver_options", "stage"]

log = logging.getLogger("homlimit.app.models")   # the stages' log lines, as before the split


@contextmanager
def stage(timings: dict[str, float], name: str, detail: str = ""):
    """Log a stage's start and end and add its wall time to ``timings``."""
    log.info("%s%s ...", name, f" ({detail})" if detail else "")
    t0 = time.perf_counter()
    yield
    dt = time.perf_counter() - t0
    timings[name] = timings.get(name, 0.0) + dt
    log.info("%s done in %.2f s", name, dt)


def solver_options(tol: float | None = None, stress_degree: int = 1):
    """Solver settings of a run: the measured defaults, the solver log when debugging, the
    static bound's stress degree (``[analysis] stress_degree``)."""
    return SolverOptions(tol=tol or None, verbose=log.isEnabledFor(logging.DEBUG),
                         stress_degree=stress_degree)


def finite(x) -> bool:
    """Whether ``x`` is a finite number (None and text are not)."""
    try:
        return x is not None and math.isfinite(float(x))
    except (TypeError, ValueError):
        return False
