"""[mesh] mesher: every FE path meshes with the chosen mesher, the default ("gmsh-strip") is
what a run without the key uses, a bad value is refused before any work (exit 2, the key
named)."""

from __future__ import annotations

import pytest
from typer.testing import CliRunner

from homlimit.app import pipeline
from homlimit.app.budget import estimate_triangles
from homlimit.app.cli import app
from homlimit.fe.problems import t_section
from homlimit.params import MESHERS, Case

# B1 on a coarse mesh with short parts: a few seconds per mesher
TINY = {"mesh.size": 1.0, "mesh.part_divisions": 3, "analysis.heights": 2,
        "analysis.static": False, "analysis.hinge_check": False, "analysis.closed_form": False}


def _fe(mesher: str | None) -> dict:
    over = TINY if mesher is None else {**TINY, "mesh.mesher": mesher}
    return pipeline.run(None, write=False, overrides=over).to_dict()


@pytest.mark.slow
def test_gmsh_run_records_its_mesher_and_gmsh_strip_is_the_default(monkeypatch):
    from homlimit.mechanism import analysis

    used = []                                 # the mesher of every part of the scan

    def spy(*args, **kw):
        used.append((kw.get("z0", 0.0), kw.get("mesher")))
        return t_section(*args, **kw)

    monkeypatch.setattr(analysis, "t_section", spy)
    g = _fe("gmsh")
    parts = [m for z0, m in used if z0 > 0]
    assert len(parts) >= 2 and set(parts) == {"gmsh"}
    assert g["inputs"]["mesh"]["mesher"] == "gmsh" and g["fe"]["mesher"] == "gmsh"
    # the whole wall's mesh is gmsh's (its triangle count, not the crossed grid's)
    n_gmsh = t_section(Case(), facade="bedjoints", h=1.0, mesher="gmsh").n_triangles
    n_crossed = t_section(Case(), facade="bedjoints", h=1.0).n_triangles
    assert g["fe"]["n_triangles"] == n_gmsh != n_crossed
    c = _fe("crossed")
    assert c["fe"]["n_triangles"] == n_crossed and c["fe"]["mesher"] == "crossed"
    d, s = _fe(None), _fe("gmsh-strip")
    assert d["inputs"]["mesh"]["mesher"] == "gmsh-strip" == d["fe"]["mesher"]
    n_strip = t_section(Case(), facade="bedjoints", h=1.0, mesher="gmsh-strip").n_triangles
    assert d["fe"]["n_triangles"] == n_strip != n_crossed
    keep = ("multiplier", "n_triangles", "hinge", "tanpsi", "vg", "lam", "critical_at")
    assert {k: s["fe"][k] for k in keep} == {k: d["fe"][k] for k in keep}


def test_bad_mesher_exits_2_naming_the_key(tmp_path):
    res = CliRunner().invoke(app, ["run", "--set", "mesh.mesher=delaunay", "--out",
                                   str(tmp_path / "o")])
    assert res.exit_code == 2, res.output
    assert ("[mesh] mesher = 'delaunay' is not allowed: allowed one of 'crossed', 'gmsh', "
            "'gmsh-strip'") in res.stderr
    assert not (tmp_path / "o").exists()
    for cmd in (["table1", "--fe"], ["crack-study"]):
        res = CliRunner().invoke(app, [*cmd, "--mesher", "gmesh", "--out", str(tmp_path / "t")])
        assert res.exit_code == 2, res.output
        assert "mesher = 'gmesh' is out of range: allowed one of 'crossed', 'gmsh'" in res.stderr


@pytest.mark.parametrize("mesher", MESHERS)
def test_budget_estimates_each_mesher(mesher):
    """Within 10 % of the count at 0.25 m on B1 (the fits: app/budget.py)."""
    n = t_section(Case(), h=0.25, mesher=mesher).n_triangles
    assert estimate_triangles(9.0, 0.5, 6.0, 0.25, mesher) == pytest.approx(n, rel=0.10)
