"""A sweep's tasks, run on the Dask workers: one case as ``run`` evaluates it (``run_case``), a
batch of closed-form-only cases at once (``batch_closed_form``), a batch's records as the
text of its record file (``evaluate_item``)."""

from __future__ import annotations

import time
import traceback
from dataclasses import dataclass

import numpy as np

from ..closed_form import mechanisms as mech
from ..closed_form.paper import dem_row
from .code_check import code_check
from .config import CaseConfig
from .engine import batch_json
from .pipeline import Result, conclude, package_version, run
from .sweep_cases import no_gc
from .sweep_table import record_row

__all__ = ["BatchText", "batch_closed_form", "evaluate_item", "failed_record", "run_case"]


def failed_record(config: CaseConfig | None, exc: BaseException, t0: float) -> dict:
    return {"homlimit_version": package_version(),
            "case": None if config is None else config.name,
            "source": None if config is None else config.source,
            "inputs": None if config is None else config.as_dict(),
            "status": "failed", "error": f"{type(exc).__name__}: {exc}",
            "traceback": "".join(traceback.format_exception(exc)),
            "timings_s": {"total": time.perf_counter() - t0}}


def run_case(config: CaseConfig) -> dict:
    """One case's record: ``run(config, write=False).to_dict()`` and status "ok", or the
    error of a case that failed (status "failed", error, traceback). Runs on a worker."""
    t0 = time.perf_counter()
    try:
        rec = run(config, write=False).to_dict()
    except Exception as exc:  # a failed case never stops the sweep: it is recorded
        return failed_record(config, exc, t0)
    rec.pop("files", None)
    return {**rec, "status": "ok"}


def batch_closed_form(configs: list[CaseConfig]) -> list[dict]:
    """Records of closed-form-only cases, as ``run_case`` gives them: the critical λ of
    mechanisms I and II of every case at once (``critical_I``, ``critical_II`` on arrays, the
    same arithmetic element by element as one case) and mechanism I's θ_m there, then
    ``mechanisms_I/II`` at that λ (arrays again) and ``Result.to_dict()`` per case.
    ``timings_s`` holds each case's share of the batch."""
    with no_gc():
        return batch_records(configs)


def batch_records(configs: list[CaseConfig]) -> list[dict]:
    t0 = time.perf_counter()
    cases = [c.case for c in configs]
    walls = mech.wall_arrays(cases)
    rho, alpha, beta = walls["rho"], walls["alpha"], walls["beta"]
    H_b, L_b = walls["H"] / walls["b"], walls["L"] / walls["b"]
    tanpsi = np.array([cf.analysis.tanpsi or c.alpha for cf, c in zip(configs, cases)])
    lam_I, _ = mech.critical_I(rho, alpha, beta, H_b)
    theta_I = mech.theta_m_I(lam_I, rho, alpha, beta)
    lam_max_II = mech.lam_max_II(H_b, L_b, tanpsi)
    lam_II, _ = mech.critical_II(rho, tanpsi, lam_max_II)
    static_II = mech.static_critical_II(rho, tanpsi, lam_max_II)
    res_I = mech.mechanisms_I(cases, lam_I, theta_I, walls)
    res_II = mech.mechanisms_II(cases, tanpsi, lam_II, static_II, walls)
    out = []
    for config, m1, m2 in zip(configs, res_I, res_II):
        t1 = time.perf_counter()
        try:
            if isinstance(m2, Exception):
                raise m2
            res = Result(config=config, dem=dem_row(config.case),
                         mechanisms={m1.name: m1, m2.name: m2})
            conclude(res)          # as compute(): results checked, then the hinge check
            res.code_check = code_check(res)                       # and the code check
            rec = {**res.to_dict(), "status": "ok"}
            rec.pop("files", None)
        except Exception as exc:  # recorded, as run_case records it
            rec = failed_record(config, exc, t1)
        out.append(rec)
    share = (time.perf_counter() - t0) / max(len(configs), 1)
    for rec in out:
        if rec["status"] == "ok":
            rec["timings_s"] = {"closed-form mechanisms I and II (batch share)": share}
    return out



@dataclass(frozen=True)
class BatchText:
    """A batch's records as the text of its record file (``engine.batch_json``) and as table
    rows (``record_row``), both made on the worker: the client writes the text as it is."""

    keys: list[str]
    text: str
    rows: list[dict]
    n_failed: int


def evaluate_item(item):
    kind, payload = item
    if kind == "case":
        return run_case(payload)
    configs, keys = payload
    recs = batch_closed_form(configs)
    return BatchText(keys, batch_json(dict(zip(keys, recs))), [record_row(r) for r in recs],
                      sum(1 for r in recs if r["status"] != "ok"))
