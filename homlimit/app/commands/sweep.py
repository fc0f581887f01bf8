"""``homlimit sweep run`` and ``homlimit sweep report``."""

from __future__ import annotations

import typer

from ...errors import ParameterError
from .. import report
from ..door import (
    EXIT_SOLVER,
    emit_json,
    interruptible,
    setup_logging,
    stdout_quiet,
)
from ..sweep import sweep
from ..sweep_report import report as draw_report


def sweep_run(base, as_json, verbose, quiet, out, grid, table, workers, scheduler, resume,
              retry_failed, max_cases):
    """``homlimit sweep run``'s work: see ``cli.sweep_run``."""
    if not grid and table is None:
        raise ParameterError("--grid / --table = none is out of range: allowed at least one "
                             "--grid key=v1,v2 or a --table CSV")
    setup_logging(verbose, quiet, as_json)
    where = out or "the sweep folder"
    with stdout_quiet(as_json) as stdout, interruptible(where):
        res = sweep(base, grid, table, out, workers=workers, scheduler=scheduler,
                    resume=resume, retry_failed=retry_failed, progress=not (quiet or as_json),
                    max_cases=max_cases)
    info = {"folder": res.folder, "n_cases": len(res.rows), "ok": res.n_ok,
            "failed": res.n_failed, "resumed": res.n_resumed, "elapsed_s": res.elapsed,
            "swept": res.swept, "files": res.files,
            "failures": [{k: r.get(k) for k in ("case_index", "key", "error")}
                         for r in res.failed()]}
    if as_json:
        emit_json(stdout, info)
    else:
        cols = [c for c in ["case_index", *res.swept, "status", "critical.mechanism",
                            "critical.vg", "critical.vnorm"]]
        shown = res.rows[:20]
        print(report.format_table(cols, [[r.get(c) for c in cols] for r in shown],
                                  title=f"sweep of {len(res.rows)} cases: {res.n_ok} ok, "
                                        f"{res.n_failed} failed, {res.n_resumed} resumed "
                                        f"({res.elapsed:.1f} s)"
                                        + ("; first 20 rows" if len(res.rows) > 20 else "")))
        for f in info["failures"][:10]:
            print(f"failed case {f['case_index']}: {f['error']}".splitlines()[0])
        print("\nfiles: " + ", ".join(str(v) for v in res.files.values()))
    if res.n_failed:
        raise typer.Exit(EXIT_SOLVER)


def sweep_report(results, out, as_json):
    """``homlimit sweep report``'s work: see ``cli.sweep_report_cmd``."""
    with stdout_quiet(as_json) as stdout:
        files = draw_report(results, out)
    if as_json:
        emit_json(stdout, {"files": files})
    else:
        print("files: " + ", ".join(str(v) for v in files.values()))
