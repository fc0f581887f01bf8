"""The package as installed and started: light imports, a fast ``--version`` path, its
metadata (licence, ``py.typed``, entry point) and the top-level docstring's example.

The start-up checks look at which modules an interpreter has loaded rather than at the clock
(wall times depend on the machine's load; ``benchmarks/bench_startup.py`` measures them).
"""

from __future__ import annotations

import doctest
import importlib.metadata
import json
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest

import homlimit

ROOT = Path(__file__).resolve().parents[1]
# the required packages (and the command line's) that `import homlimit` must not load
HEAVY = ["cvxpy", "clarabel", "scipy", "skfem", "gmsh", "meshio", "dask", "distributed",
         "matplotlib", "pyarrow", "h5py", "numpy"]
CLI = ["typer", "click", "rich"]
SHOW = "import json, sys; print(json.dumps(sorted(m for m in {mods!r} if m in sys.modules)))"


def _python(*args: str) -> list[str]:
    r = subprocess.run([sys.executable, *args], capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr
    return r.stdout.splitlines()


def test_import_loads_no_heavy_package():
    out = _python("-c", "import homlimit; " + SHOW.format(mods=HEAVY + CLI))
    assert json.loads(out[-1]) == []


def test_case_schema_takes_dem_defaults_without_numba():
    """[dem]'s defaults are ``dem.params.DEMParams``'s: reading them loads no numba (the
    DEM's model is deferred by ``homlimit.dem.__getattr__``)."""
    code = "import homlimit.app.schema; " + SHOW.format(mods=["numba", "homlimit.dem.model"])
    assert json.loads(_python("-c", code)[-1]) == []


def test_version_answers_before_typer():
    """`python -m homlimit --version` (and the console script, the same `__main__.main`)
    prints the version without loading typer, rich, numpy or any computing package."""
    version = f"homlimit {importlib.metadata.version('homlimit')}"
    code = ("import runpy, sys; sys.argv = ['homlimit', '--version']; "
            "runpy.run_module('homlimit', run_name='__main__'); " + SHOW.format(mods=HEAVY + CLI))
    out = _python("-c", code)
    assert out == [version, "[]"]
    # the console script imports main, then calls it: the import itself runs nothing
    code = ("import sys; sys.argv = ['homlimit', '--version']; "
            "from homlimit.__main__ import main; print('imported'); main(); "
            + SHOW.format(mods=HEAVY + CLI))
    assert _python("-c", code) == ["imported", version, "[]"]


def test_lazy_names():
    from homlimit.app.pipeline import run
    from homlimit.closed_form.mechanisms import mechanism_I

    assert homlimit.run is run and homlimit.mechanism_I is mechanism_I
    assert homlimit.__version__ == importlib.metadata.version("homlimit")
    assert {"run", "__version__", "Case"} <= set(dir(homlimit))
    with pytest.raises(AttributeError, match="no attribute 'nope'"):
        homlimit.nope  # noqa: B018


def test_docstring_example():
    res = doctest.testmod(homlimit, raise_on_error=False, verbose=False)
    assert res.attempted >= 3 and res.failed == 0


def test_metadata():
    meta = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))
    project = meta["project"]
    assert project["license"] == {"text": "MIT"}
    licence = (ROOT / "LICENSE").read_text(encoding="utf-8")
    assert licence.startswith("MIT License") and "2026 the homlimit developers" in licence
    assert project["authors"] == [{"name": "the homlimit developers"}]
    assert "License :: OSI Approved :: MIT License" in project["classifiers"]
    assert "Typing :: Typed" in project["classifiers"] and project["keywords"]
    # PEP 561: the marker ships with the package
    assert (ROOT / "homlimit" / "py.typed").is_file()
    assert "py.typed" in meta["tool"]["setuptools"]["package-data"]["homlimit"]
    assert project["scripts"] == {"homlimit": "homlimit.__main__:main"}
