"""The one way a picture is drawn and saved: matplotlib imported lazily with the
non-interactive Agg backend (``pyplot``), so importing homlimit never pulls in a GUI, and
every PNG written atomically at ``DPI`` (``save_png``, ``_io.write_figure``)."""

from __future__ import annotations

from pathlib import Path

from .._io import write_figure

__all__ = ["DPI", "pyplot", "save_png"]

DPI = 120


def pyplot():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def save_png(fig, path: str | Path) -> Path:
    plt = pyplot()
    try:
        return write_figure(path, lambda tmp: fig.savefig(tmp, dpi=DPI, format="png"))
    finally:
        plt.close(fig)
