"""Shared fixtures: the paper's Table 1 (walls and DEM results) as an independent reference.

The table is read from ``../shared/reference/table1_dem.csv`` (the paper's Table 1 as data,
kept outside the package), not from the copy homlimit ships, so that tests comparing against it
also check the shipped copy. Without it those tests fail (they are not skipped).
"""

from __future__ import annotations

import csv
import os
import sys
from pathlib import Path

# one BLAS thread, as the engine's workers run (app.engine.BLAS_ENV), so that a result computed
# here equals the engine's bit for bit (OpenBLAS's sums depend on its thread count); set before
# numpy loads its BLAS
_NUMPY_EARLY = "numpy" in sys.modules     # False: checked under pytest -n 2 and -n 0
for _k in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_k, "1")

import pytest  # noqa: E402  (after the BLAS threads above)

from homlimit.params import Case, Masonry, Wall  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
SHARED_TABLE1 = ROOT.parent / "shared" / "reference" / "table1_dem.csv"


def _read_table1() -> dict[str, dict]:
    if not SHARED_TABLE1.is_file():
        # a failure, not a skip: these tests are the package's check against the paper
        pytest.fail(f"the paper's Table 1 reference {SHARED_TABLE1} is not beside the "
                    f"checkout; the tests that compare with the paper need the project's "
                    f"shared/ folder next to it (README, 'Set-up')", pytrace=False)
    lines = [ln for ln in SHARED_TABLE1.read_text(encoding="utf-8").splitlines()
             if ln and not ln.startswith("#")]
    return {r["test"]: {k: float(v) for k, v in r.items() if k != "test"}
            for r in csv.DictReader(lines)}


@pytest.fixture(scope="session")
def table1_ref() -> dict[str, dict]:
    """Table 1 of the paper: test → {H, L, s, b, a, c, f, rho, beta, alpha2, h_v, lambda_v,
    vg, vg_norm} (metres, m/s)."""
    return _read_table1()


@pytest.fixture(scope="session")
def dem(table1_ref) -> dict[str, tuple[float, float]]:
    """The DEM results of Table 1: test → (λ_v, v_g/√(gb))."""
    return {t: (r["lambda_v"], r["vg_norm"]) for t, r in table1_ref.items()}


@pytest.fixture(scope="session")
def table1_case(table1_ref):
    """A function test name → the Case of that Table 1 wall (l = ρ s, the 2D reduction)."""
    def make(test: str) -> Case:
        r = table1_ref[test]
        return Case(Wall(H=r["H"], L=r["L"], s=r["s"], b=r["b"], l=r["rho"] * r["s"]),
                    Masonry(a=r["a"], c=r["c"], f=r["f"]), name=test)

    return make


@pytest.fixture(scope="session")
def table1_walls() -> dict[str, Case]:
    """The Table 1 walls B1 ... C6 as the package ships them (``closed_form.paper.table1``):
    test name → ``params.Case`` (named by its test). ``table1_case`` builds the same walls
    from the independent reference instead."""
    from homlimit.closed_form.paper import table1

    return {t.test: t.case for t in table1()}


@pytest.fixture(scope="session")
def b1(table1_walls) -> Case:
    """Table 1's wall B1 (H = 9 m, L = 6 m, s = b = 0.5 m, l = 6 m; a = 0.3 m, c = 0.2 m,
    f = 0.6), the embedded default case."""
    return table1_walls["B1"]


@pytest.fixture
def sandbox(tmp_path, monkeypatch):
    """A working folder three levels down, so that writes above it can be seen (the hostile
    input tests; test modules with other needs define their own)."""
    cwd = tmp_path / "a" / "b" / "c"
    cwd.mkdir(parents=True)
    monkeypatch.chdir(cwd)
    return cwd
