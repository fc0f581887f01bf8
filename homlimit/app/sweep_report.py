"""The standard plots of a sweep (``homlimit sweep report RESULTS``), from its table.

- ``vnorm_swept.png``: v̄_g/√(gb) of the governing mechanism and of I, II and FE against each
  swept key (one panel per key; the other keys vary within a panel);
- ``critical_map.png``: the governing mechanism over the first two swept keys (one key: along
  it);
- ``tanpsi.png``: the FE crack's measured tan ψ (50 % line) against eq. 16's √(cf/a), when the
  sweep ran the FE analysis;
- ``vg_histogram.png``: the histogram of the governing v̄_g [m/s] and the share of cases each
  mechanism governs (a building stock's summary).

Only cases with status "ok" are drawn. Every picture is written atomically.
"""

from __future__ import annotations

import json
import os
from pathlib import Path

import numpy as np

from ..errors import ParameterError
from . import registry
from .plots import pyplot, save_png

__all__ = ["load_results", "report"]

#: bytes of a sweep.json at most (100 000 cases take about 20 MB)
MAX_META_BYTES = 1 << 30


def load_results(results: str | Path) -> tuple[list[dict], list[str], Path]:
    """(rows, swept columns, sweep folder) from a sweep folder or its results file. A file
    that cannot be read as what it should be (a garbled or truncated Parquet, CSV or
    sweep.json, a named pipe, a folder) is a ParameterError naming it, before any plot."""
    path = Path(results)
    folder = path if path.is_dir() else path.parent
    if path.is_dir():
        path = folder / "results.parquet"
        if not path.is_file():
            path = folder / "results.csv"
    if not path.is_file() or path.suffix not in (".parquet", ".csv"):
        raise ParameterError(f"results = {str(results)!r} is out of range: allowed a sweep "
                             "folder or its results.parquet / results.csv")
    rows = _read_rows(path)
    meta = folder / "sweep.json"
    swept = _read_swept(meta) if meta.exists() else []
    if not swept:  # the inputs that vary
        swept = [k for k in (rows[0] if rows else {}) if k.startswith("inputs.")
                 and len({r.get(k) for r in rows}) > 1]
    return rows, swept, folder


_HINT = "allowed a sweep's results, as `homlimit sweep` writes them (run the sweep again to " \
        "write them anew)"


def _reason(e: BaseException) -> str:
    """An exception's first line, short and printable (a parser may quote the file's bytes)."""
    text = (str(e).splitlines() or [type(e).__name__])[0]
    text = "".join(ch if " " <= ch <= "~" else "?" for ch in text)
    return text if len(text) <= 120 else text[:117] + "..."


def _read_rows(path: Path) -> list[dict]:
    """The rows of a results table; ParameterError naming the file when it is not one."""
    import pyarrow as pa
    import pyarrow.csv as pcsv
    import pyarrow.parquet as pq

    try:
        table = pq.read_table(path) if path.suffix == ".parquet" else pcsv.read_csv(path)
        return table.to_pylist()
    except (pa.ArrowException, OSError, ValueError) as e:
        kind = "Parquet" if path.suffix == ".parquet" else "CSV"
        reason = _reason(e)
        raise ParameterError(f"results = {str(path)!r} cannot be read as {kind} ({reason}): "
                             f"{_HINT}") from None


def _read_swept(meta: Path) -> list[str]:
    """sweep.json's swept columns; ParameterError naming the file when it is not a sweep's."""

    def bad(why: str):
        raise ParameterError(f"sweep.json = {str(meta)!r} {why}: {_HINT}") from None

    if not meta.is_file():
        bad("is not a regular file")
    if meta.stat().st_size > MAX_META_BYTES:
        bad(f"has {meta.stat().st_size:,} bytes: allowed at most {MAX_META_BYTES:,}")
    try:
        data = json.loads(meta.read_bytes())
    except (OSError, UnicodeDecodeError, ValueError, RecursionError) as e:
        bad(f"is not valid JSON ({_reason(e)})")
    swept = data.get("swept") if isinstance(data, dict) else None
    if not isinstance(swept, list) or not all(isinstance(k, str) for k in swept):
        bad("has no list of swept columns (\"swept\")")
    return swept


def _col(rows, key) -> np.ndarray:
    try:
        return np.array([np.nan if r.get(key) is None else r[key] for r in rows], dtype=float)
    except (TypeError, ValueError):
        raise ParameterError(f"results column {key!r} holds values that are not numbers: "
                             f"{_HINT}") from None


def _numeric(rows, key) -> bool:
    return all(isinstance(r.get(key), int | float) and not isinstance(r.get(key), bool)
               for r in rows)


def report(results: str | Path, out: str | Path | None = None) -> dict[str, Path]:
    """Draw the standard plots of a sweep into ``out`` (default RESULTS/report/)."""
    rows, swept, folder = load_results(results)
    ok = [r for r in rows if r.get("status") == "ok"]
    if not ok:
        raise ParameterError(f"results = {str(results)!r} is out of range: allowed a sweep "
                             "with at least one case of status ok")
    out = Path(out) if out else folder / "report"
    from .pipeline import result_folder

    with result_folder(out, "sweep report", results=str(results),
                       source=os.path.abspath(folder)) as staging:
        files = _draw(rows, ok, swept, staging)
    return {k: out / p.name for k, p in files.items()}


def _draw(rows, ok, swept, staging: Path) -> dict[str, Path]:
    """The report's figures, drawn into ``staging``."""
    plt = pyplot()
    files = {}
    num = [k for k in swept if _numeric(ok, k)]
    colour = {m.name: m.colour for m in registry.mechanisms()}
    mechs = [m for m in colour if f"mechanisms.{m}.vnorm" in ok[0]
             or any(r.get(f"mechanisms.{m}.vnorm") is not None for r in ok)]
    crit = [str(r.get("critical.mechanism") or "none") for r in ok]
    if num:
        ncol = min(4, len(num))
        nrow = -(-len(num) // ncol)
        fig, axes = plt.subplots(nrow, ncol, figsize=(4.5 * ncol, 3.8 * nrow), squeeze=False)
        for ax in axes.flat[len(num):]:
            ax.set_visible(False)
        for ax, key in zip(axes.flat, num):
            x = _col(ok, key)
            for m in mechs:
                ax.plot(x, _col(ok, f"mechanisms.{m}.vnorm"), "o", ms=3, alpha=0.5,
                        color=colour[m], label=m)
            ax.plot(x, _col(ok, "critical.vnorm"), "k_", ms=9, label="governing")
            ax.set_xlabel(key)
            ax.set_ylabel("v̄_g / √(g b)")
            ax.grid(alpha=0.3)
        axes[0][0].legend()
        fig.suptitle(f"sweep of {len(ok)} cases: v̄_g/√(gb) against each swept key")
        fig.tight_layout()
        files["vnorm_swept_png"] = save_png(fig, staging / "vnorm_swept.png")
    if num:
        fig, ax = plt.subplots(figsize=(6, 4.5))
        x = _col(ok, num[0])
        y = _col(ok, num[1]) if len(num) > 1 else np.zeros(len(ok))
        for m in sorted(set(crit)):
            sel = np.array([c == m for c in crit])
            ax.scatter(x[sel], y[sel], s=25, color=colour.get(m, "grey"), label=m)
        ax.set_xlabel(num[0])
        ax.set_ylabel(num[1] if len(num) > 1 else "")
        ax.legend(title="governing")
        ax.set_title("critical mechanism map")
        files["critical_map_png"] = save_png(fig, staging / "critical_map.png")
    if any(r.get("fe.tanpsi") is not None for r in ok):
        fig, ax = plt.subplots(figsize=(5, 5))
        pred, meas = _col(ok, "fe.sqrt_cf_a"), _col(ok, "fe.tanpsi")
        ax.plot(pred, meas, "o", color="tab:green")
        lim = [0, np.nanmax(np.r_[pred, meas]) * 1.1]
        ax.plot(lim, lim, "k--", lw=1, label="tan ψ = √(cf/a) (eq. 16)")
        ax.set_xlabel("predicted tan ψ = √(cf/a)")
        ax.set_ylabel("measured tan ψ (FE, 50 % line)")
        ax.legend()
        ax.set_title("FE crack slope against eq. 16")
        files["tanpsi_png"] = save_png(fig, staging / "tanpsi.png")
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(10, 4), gridspec_kw={"width_ratios": [2, 1]})
    vg = _col(ok, "critical.vg")
    a1.hist(vg[np.isfinite(vg)], bins=min(30, max(5, len(ok) // 5)), color="tab:grey")
    a1.set_xlabel("governing v̄_g [m/s]")
    a1.set_ylabel("cases")
    a1.set_title(f"{len(ok)} cases: median {np.nanmedian(vg):.3g} m/s")
    names = sorted(set(crit))
    share = [100 * crit.count(m) / len(crit) for m in names]
    a2.bar(names, share, color=[colour.get(m, "grey") for m in names])
    a2.set_ylabel("share of cases governed [%]")
    a2.set_title("governing mechanism")
    fig.tight_layout()
    files["vg_histogram_png"] = save_png(fig, staging / "vg_histogram.png")
    return files
