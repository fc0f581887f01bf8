"""The failure classes a hostile tester found (issue 15), one or more tests each: the command
line exits 0, 2 or 3 with a one-line reason naming the case-file key (never an internal
variable, never a traceback), writes only inside its output folder, refuses what it cannot do
before computing, and says what it did to a modified case. Every message quoted here is in the
error table of docs/cli.md (``DOCUMENTED``, checked at the end)."""

from __future__ import annotations

import json
import os
import re
import stat
import types
from pathlib import Path

import pytest
from typer.testing import CliRunner

from homlimit import _io
from homlimit.app import models, models_rigid, pipeline
from homlimit.app.cli import app

ROOT = Path(__file__).resolve().parents[1]
B1 = ("[wall]\nH = 9\nL = 6\ns = 0.5\nb = 0.5\nl = 6\n"
      "[masonry]\na = 0.3\nc = 0.2\nf = 0.6\n")
FAST = "[analysis]\nfe = false\n[output]\npng = false\n"
DOCUMENTED: set[str] = set()     # message fragments that docs/cli.md's error table must list


def doc(fragment: str) -> str:
    DOCUMENTED.add(fragment)
    return fragment


def invoke(*args, **kw):
    res = CliRunner().invoke(app, [str(a) for a in args], **kw)
    assert res.exit_code in (0, 2, 3), (res.exit_code, res.output, res.exception)
    assert "Traceback" not in res.stderr
    return res


def files_under(root: Path) -> set[str]:
    return {str(p.relative_to(root)) for p in root.rglob("*") if p.is_file()}


@pytest.fixture
def no_compute(monkeypatch):
    """Any computation fails the test: for checks that must come first."""
    def boom(*a, **k):  # pragma: no cover - must never run
        raise AssertionError("computation started")

    for name in ("compute", "table1_records", "crack_study_records", "pulse_records"):
        monkeypatch.setattr(pipeline, name, boom)
    monkeypatch.setattr(models, "whole_problem", boom)
    import homlimit.fe.problems

    monkeypatch.setattr(homlimit.fe.problems, "t_section", boom)


# ----------------------------------------------------------------------------- output paths
@pytest.mark.parametrize("name", ["../../x", "..", "/tmp/homlimit-abs", "a/b\\c", ".hidden",
                                  "B1 façade (Nord)"])
def test_case_names_stay_inside_homlimit_out(sandbox, name):
    case = sandbox / "case.toml"
    case.write_text(f"name = {json.dumps(name)}\n" + B1 + FAST)
    res = invoke("run", case)
    assert res.exit_code == 0, res.stderr
    (folder,) = (sandbox / "homlimit-out").iterdir()
    assert folder.name == pipeline.folder_name(name)
    assert "/" not in folder.name and not folder.name.startswith(".")
    assert files_under(sandbox.parents[2]) == {
        "a/b/c/case.toml", f"a/b/c/homlimit-out/{folder.name}/summary.json",
        f"a/b/c/homlimit-out/{folder.name}/{_io.MANIFEST}"}
    assert not Path("/tmp/homlimit-abs").exists()


def test_folder_names_are_distinct_and_bounded():
    assert pipeline.folder_name("B1") == "B1"
    assert pipeline.folder_name("a/b") != pipeline.folder_name("a_b")
    assert len(pipeline.folder_name("é" * 100).encode()) <= pipeline.MAX_FOLDER_NAME
    assert pipeline.folder_name("..") .startswith("case-")


@pytest.mark.parametrize("name, message", [
    ("x\u0000y", doc("contains control characters")),
    ("x" * 300, doc("characters) is out of range: allowed at most 100 characters")),
])
def test_bad_names_exit_2(sandbox, name, message):
    case = sandbox / "case.toml"
    case.write_text(f"name = {json.dumps(name)}\n" + B1 + FAST)
    res = invoke("run", case)
    assert res.exit_code == 2 and message in res.stderr
    assert not (sandbox / "homlimit-out").exists()


def test_a_modified_case_gets_its_own_folder_and_says_so(sandbox):
    """demo --set wall.l=3 neither overwrites homlimit-out/B1/ nor calls itself B1."""
    assert invoke("demo", "--set", "analysis.fe=false").exit_code == 0
    res = invoke("demo", "--set", "analysis.fe=false", "--set", "wall.l=3")
    assert res.exit_code == 0
    names = sorted(p.name for p in (sandbox / "homlimit-out").iterdir())
    assert len(names) == 2 and all(n.startswith("B1-") for n in names)
    first = res.stdout.splitlines()[0]
    assert first.startswith("case B1-") and not first.startswith("case B1:")
    assert doc("modified by --set: B1 with") in res.stdout
    assert "wall.l = 3 (not 6)" in res.stdout
    again = invoke("demo", "--set", "wall.l=3", "--set", "analysis.fe=false")  # same inputs,
    assert sorted(p.name for p in (sandbox / "homlimit-out").iterdir()) == names   # same folder
    s = json.loads(next((sandbox / "homlimit-out").glob("*/summary.json")).read_text())
    assert s["modified"]["from"] == "B1"
    assert again.exit_code == 0
    # only --set name=..., or an output option: the named case itself, no hash
    assert invoke("demo", "--set", "name='Z'", "--set", "analysis.fe=false",
                  "--set", "output.png=false").exit_code == 0
    assert (sandbox / "homlimit-out" / "Z-" ).exists() is False


def test_out_is_taken_as_given(sandbox):
    res = invoke("run", "--set", "analysis.fe=false", "--out", "../given")
    assert res.exit_code == 0
    assert (sandbox.parent / "given" / "summary.json").is_file()


# ----------------------------------------------------------------------------- late failures
@pytest.mark.parametrize("kind, message", [
    ("file", doc("is a file, not a folder")),
    ("inside-file", doc("cannot be created: ")),
    ("read-only", doc("is not writable")),
    ("foreign", doc("is a folder that holds other files")),
    ("cwd", doc("is the working folder or one of its parents")),
    ("long", doc("bytes per folder name here")),
])
def test_an_unusable_output_folder_is_refused_before_computing(sandbox, no_compute, monkeypatch,
                                                               kind, message):
    (sandbox / "f").write_text("a file")
    (sandbox / "mine").mkdir()
    (sandbox / "mine" / "notes.txt").write_text("keep me")
    (sandbox / "ro").mkdir()
    real = os.access
    monkeypatch.setattr(os, "access",
                        lambda p, m: False if Path(p).name == "ro" and m & os.W_OK
                        else real(p, m))
    out = {"file": "f", "inside-file": "f/x", "read-only": "ro", "foreign": "mine",
           "cwd": ".", "long": "x" * 300}[kind]
    for cmd in (["demo"], ["table1"], ["figure2"], ["crack-study", "--quick"], ["mesh"],
                ["pulse"]):
        res = invoke(*cmd, "--out", out)
        assert res.exit_code == 2, (cmd, res.output)
        assert message in res.stderr, (cmd, res.stderr)
    assert (sandbox / "mine" / "notes.txt").read_text() == "keep me"
    assert sorted(p.name for p in sandbox.iterdir()) == ["f", "mine", "ro"]


def test_stale_files_of_an_earlier_run_never_survive(sandbox):
    """An FE run, then a run without FE into the same folder: no mechanism.vtu, mesh.png or
    fe_scan.csv of the FE run beside the new summary.json."""
    # the cheapest FE run that writes its files: 3 elements per part height (the default 30
    # meshes the one-course part at a/30: 22 s for the same files)
    fe = ["--set", "mesh.size=3", "--set", "mesh.part_divisions=3", "--set",
          "analysis.heights=2", "--set", "analysis.static=false", "--set", "output.png=false"]
    assert invoke("run", *fe, "--out", "o").exit_code == 0
    assert {"mechanism.vtu", "fe_scan.csv"} <= {p.name for p in (sandbox / "o").iterdir()}
    assert invoke("run", "--set", "analysis.fe=false", "--out", "o").exit_code == 0
    assert sorted(p.name for p in (sandbox / "o").iterdir()) == [_io.MANIFEST,
                                                                 "summary.json",
                                                                 "vg_lambda.png"]
    assert _io.check_result_set(sandbox / "o") == []


def test_sets_of_other_commands_live_beside_the_run(sandbox):
    """mesh writes homlimit-out/NAME/mesh/ (it used to overwrite the run's folder), and a new
    run keeps it (and pulse/)."""
    case = sandbox / "w.toml"
    case.write_text(B1 + FAST + "[mesh]\nsize = 3.0\n")
    assert invoke("run", case).exit_code == 0
    assert invoke("mesh", case).exit_code == 0
    assert invoke("run", case).exit_code == 0
    out = sandbox / "homlimit-out" / "w"
    assert (out / "mesh" / "mesh.vtu").is_file() and (out / "summary.json").is_file()
    assert _io.check_result_set(out) == [] and _io.check_result_set(out / "mesh") == []


def test_files_get_the_umask_modes(sandbox):
    old = os.umask(0o022)
    try:
        assert invoke("run", "--set", "analysis.fe=false", "--out", "o").exit_code == 0
    finally:
        os.umask(old)
    for p in (sandbox / "o").iterdir():
        assert stat.S_IMODE(p.stat().st_mode) == 0o644, p
    assert stat.S_IMODE((sandbox / "o").stat().st_mode) == 0o755


# ----------------------------------------------------------------------------- input bytes
@pytest.mark.parametrize("raw, message", [
    (b"\xef\xbb\xbf" + B1.encode(), doc("starts with a UTF-8 byte-order mark (BOM)")),
    ("\ufeff".encode("utf-16") + B1.encode("utf-16-le"), doc("the case file is UTF-16")),
    (b"[wall]\nH = 9\nname = \"caf\xe9\"\n", doc("the case file is not UTF-8 text: byte 0xe9")),
    (bytes(range(128, 256)) * 4, "the case file is not UTF-8 text: byte 0x80 at offset 0"),
    (b"\x00\x01\x02binary", doc("not valid TOML")),
    (B1.replace("H = 9", "H = 1" + "0" * 5000).encode(), "H = 10000000...(5001 digits) at line "
     "2: an integer of more than 4300 digits"),
    (B1.replace("H = 9", "H = 1" + "0" * 400).encode(), doc("...(401 digits) m is out of range")),
    (B1.replace("H = 9", "H = 1e308").encode(), doc("H = 1e+308 m is out of range: allowed "
                                                    "0.001 <= H <= 10000 m")),
    (B1.replace("H = 9", "H = inf").encode(), "H = inf m is out of range"),
    (B1.replace("H = 9", "H = nan").encode(), "H = nan m is out of range"),
    (B1.replace("H = 9", "H = 9e999").encode(),     # shown as written, not as inf
     "H = 9e999 (beyond the largest float, about 1.8e308) m is out of range"),
    (b"x = " + b"[" * 3000 + b"]" * 3000, "not valid TOML"),
])
def test_hostile_bytes_exit_2_naming_the_problem(sandbox, no_compute, raw, message):
    case = sandbox / "case.toml"
    case.write_bytes(raw)
    res = invoke("run", case)
    assert res.exit_code == 2, res.output
    assert message in res.stderr and str(case) in res.stderr
    assert len(res.stderr) < 2000                          # one line per problem, not a dump
    assert not (sandbox / "homlimit-out").exists()


def test_a_huge_case_file_and_a_folder_are_refused(sandbox, no_compute):
    big = sandbox / "big.toml"
    big.write_bytes(b"# " + b"x" * (2 << 20))
    assert doc("bytes: allowed at most 1,048,576") in invoke("run", big).stderr
    (sandbox / "dir.toml").mkdir()
    assert doc("cannot read the case file") in invoke("run", sandbox / "dir.toml").stderr


def test_a_binary_pulse_record_exits_2(sandbox):
    (sandbox / "rec.csv").write_bytes(bytes(range(128, 256)))
    res = invoke("pulse", "--set", "pulse.record=rec.csv", "--set", "pulse.periods=[0.5]",
                 "--set", 'pulse.kinds=["rectangular"]')
    assert res.exit_code == 2
    assert doc("[pulse] record = 'rec.csv' is not UTF-8 text") in res.stderr
    assert not (sandbox / "homlimit-out").exists()


def test_a_missing_pulse_record_names_the_case_file(sandbox):
    case = sandbox / "case.toml"
    case.write_text(B1 + FAST, encoding="utf-8")
    res = invoke("pulse", case, "--set", "pulse.record=nowhere.csv")
    assert res.exit_code == 2
    assert f"{case}: " + doc("[pulse] record = 'nowhere.csv': record = '") in res.stderr
    assert "nowhere.csv' is not a file" in res.stderr
    assert not (sandbox / "homlimit-out").exists()


@pytest.mark.parametrize("args, message", [
    # the default --finer (0.25 m) above a lowered --mesh-size: the flag the user gave first
    (["crack-study", "--mesh-size", "1e-4"],
     doc("--mesh-size = 0.0001 m is not above --finer = 0.25 m (the default of --finer, the "
         "study's second, finer mesh): out of range: allowed --finer < --mesh-size")),
    (["crack-study", "--finer", "-1"],
     doc("--finer = -1.0 m is out of range: allowed 0 <= --finer and --finer < 0.5 m (below "
         "--mesh-size; 0: none)")),
    (["verify", "--min-size", "inf"],          # its range is bounded above (the option's)
     "--min-size = inf m is out of range: allowed 0 < --min-size and --min-size <= 10000 m"),
    (["demo", "--set", "wall.H=1e400"],
     doc("[wall] H = 1e400 (beyond the largest float, about 1.8e308) m is out of range")),
])
def test_option_messages_say_what_the_user_gave(sandbox, no_meshing, args, message):
    res = invoke(*args)
    assert res.exit_code == 2 and message in res.stderr, res.stderr
    assert not (sandbox / "homlimit-out").exists()


def test_a_range_open_above_says_finite():
    from homlimit.errors import ParameterError
    from homlimit.fe.adapt import AdaptOptions

    with pytest.raises(ParameterError, match=re.escape(doc(
            "adapt.min_size = inf m is out of range: allowed 0 < adapt.min_size m, finite"))):
        AdaptOptions(min_size=float("inf"))


def test_finer_0_is_none_and_the_quick_grid_takes_no_finer(monkeypatch):
    from homlimit.app import studies, tables

    seen = []
    monkeypatch.setattr(studies, "crack_point", lambda point, **kw: seen.append(point[3]))
    tables.crack_study_records(mesh_size=0.6, finer=0.0, c_over_a=[1.0], frictions=[0.6],
                               facades=["homogenised"])
    tables.crack_study_records(mesh_size=0.1, quick=True, max_triangles=10 ** 6)
    assert set(seen) == {0.6, 0.1}


# ----------------------------------------------------------------------------- problem size
@pytest.fixture
def no_meshing(monkeypatch):
    """Meshing or solving fails the test (the budget must stop a case first)."""
    def boom(*a, **k):  # pragma: no cover - must never run
        raise AssertionError("meshing started")

    import homlimit.app.studies
    import homlimit.fe.problems
    import homlimit.mechanism.analysis

    for mod in (homlimit.fe.problems, homlimit.app.studies, homlimit.mechanism.analysis):
        monkeypatch.setattr(mod, "t_section", boom)
    monkeypatch.setattr(models, "fe_result", boom)
    monkeypatch.setattr(models, "whole_problem", boom)


def test_the_triangle_budget_stops_before_meshing(sandbox, no_meshing):
    res = invoke("demo", "--set", "mesh.size=0.001")
    assert res.exit_code == 2
    assert doc("triangles in the largest FE problem") in res.stderr
    assert "[mesh] size" in res.stderr and "[mesh] max_triangles" in res.stderr
    # a wall so tall: the same
    res = invoke("demo", "--set", "wall.H=9000")
    assert res.exit_code == 2 and "triangles in the largest FE problem" in res.stderr
    res = invoke("mesh", "--set", "mesh.size=0.002", "--set", "analysis.fe=false")
    assert res.exit_code == 2 and "[mesh] max_triangles" in res.stderr
    res = invoke("table1", "--fe", "--mesh-size", "0.005", "-t", "B1")
    assert res.exit_code == 2 and doc("--max-triangles") in res.stderr
    res = invoke("table1", "--fe", "--part-divisions", "1", "-t", "B1")   # [mesh]'s range
    assert res.exit_code == 2 and ("--part-divisions = 1 is out of range: allowed 2 <= "
                                   "--part-divisions and --part-divisions <= 1000") in res.stderr
    res = invoke("crack-study", "--mesh-size", "0.05", "--finer", "0.004")
    assert res.exit_code == 2 and "--finer = 0.004 m gives about" in res.stderr
    assert not (sandbox / "homlimit-out").exists()


def test_the_budget_can_be_raised(sandbox):
    """A case just over a lowered budget passes once [mesh] max_triangles allows it."""
    res = invoke("mesh", "--set", "mesh.size=0.5", "--set", "mesh.max_triangles=200")
    assert res.exit_code == 2 and "max_triangles = 200" in res.stderr
    res = invoke("mesh", "--json", "--set", "mesh.size=0.5", "--set", "mesh.max_triangles=20000")
    assert res.exit_code == 0, res.output
    n = json.loads(res.stdout)["n_triangles"]
    from homlimit.app.budget import estimate_triangles
    from homlimit.params import MESHER_DEFAULT

    assert n <= estimate_triangles(9.0, 0.5, 6.0, 0.5, MESHER_DEFAULT) <= 1.5 * n


# ----------------------------------------------------------------------------- silent nonsense
def test_cross_checks_are_reported_with_the_field_problems(sandbox, no_compute):
    case = sandbox / "case.toml"
    case.write_text(B1.replace("a = 0.3", "a = 10").replace("f = 0.6", "f = -1")
                    + "[mesh]\nsize = 100.0\n[analysis]\nheights = 0\n")
    res = invoke("run", case)
    assert res.exit_code == 2
    for piece in ("4 problems", "[masonry] a = 10.0 m is out of range: a block must not be "
                  "taller than the wall", "[masonry] f = -1 is out of range",
                  "[mesh] size = 100.0 m is out of range: allowed 0 < size <= min(H, b + L)",
                  "[analysis] heights = 0 is out of range"):
        assert piece in res.stderr, piece


@pytest.mark.parametrize("sets, message", [
    (["wall.H=0.2", "masonry.a=0.1"], doc("H/b = 0.4 is out of range: allowed H/b >= 0.5")),
    (["wall.L=0.4", "masonry.c=0.2", "masonry.f=10", "masonry.a=0.01"],
     doc("L/(b tan ψ) = 0.05657 is out of range: allowed L/(b tan ψ) >= 0.5")),
    (["analysis.tanpsi=1e300"], "[analysis] tanpsi = 1e+300 is out of range"),
])
def test_internal_names_never_reach_the_user(sandbox, no_compute, sets, message):
    """Squat walls and wedges that do not fit used to fail inside the closed forms'
    λ search as 'lam = array(0.5) is out of range'."""
    args = [a for s in ["analysis.fe=false", *sets] for a in ("--set", s)]
    res = invoke("demo", *args)
    assert res.exit_code == 2 and message in res.stderr, res.stderr
    assert "array(" not in res.stderr and "lam =" not in res.stderr


def test_a_crushing_fc_is_refused_before_the_fe_path(sandbox, no_compute):
    """fc below the wall's bound (every part crushes at its hinge) used to end in numpy's
    'All-NaN slice encountered' (exit 1); now exit 2 naming [masonry] fc and the bound,
    before any work: the demo's FE path is on."""
    res = invoke("demo", "--set", "masonry.fc=1000")
    assert res.exit_code == 2, res.stderr
    assert "[masonry] fc = 1000.0 Pa" in res.stderr
    assert doc("Pa is too low for this wall: every part of mechanism II (crack) crushes at its "
               "hinge; allowed fc = 0 (infinite) or fc >= ") in res.stderr
    assert not (sandbox / "homlimit-out").exists()


def test_a_non_finite_result_is_exit_3_naming_mechanism_and_quantity(sandbox, monkeypatch):
    real = models_rigid.closed_forms

    def nan_II(config):
        mechs, curves = real(config)
        mechs["II"] = types.SimpleNamespace(**{**vars(mechs["II"]), "vg": float("nan")})
        return mechs, curves

    monkeypatch.setattr(models_rigid, "closed_forms", nan_II)
    res = invoke("demo", "--set", "analysis.fe=false", "--json")
    assert res.exit_code == 3 and res.stdout == ""
    assert doc("no result: mechanism II: vg = nan is not a finite number") in res.stderr
    assert not (sandbox / "homlimit-out").exists()


def test_no_fe_collapse_velocity_is_exit_3(sandbox, monkeypatch):
    whole = types.SimpleNamespace(multiplier=0.15, vg=float("nan"),
                                  vg_method="not available: no block")
    monkeypatch.setattr(models, "adaptive", lambda config: False)   # no bracket to solve
    monkeypatch.setattr(models, "whole_problem",
                        lambda config: types.SimpleNamespace(n_triangles=10))
    monkeypatch.setattr(models, "fe_result", lambda *a, **k: types.SimpleNamespace(
        whole=whole, critical=None, static=None, lower_bound=None))
    res = invoke("demo")
    assert res.exit_code == 3
    assert doc("mechanism FE: no collapse height of the scan gave a collapse velocity") \
        in res.stderr


def test_out_of_memory_is_exit_3(sandbox, monkeypatch):
    def oom(config, *map):
        raise MemoryError

    monkeypatch.setattr(pipeline, "compute", oom)
    res = invoke("demo")
    assert res.exit_code == 3 and doc("out of memory") in res.stderr


@pytest.mark.parametrize("sets, warning", [
    (["masonry.f=50"], "[masonry] f = 50 is outside the typical range of masonry walls "
                       "0.3 .. 1"),
    (["wall.l=0.01"], "ρ = l/s = 0.02 is outside the typical range 1 .. 50"),
    (["wall.H=9000", "masonry.a=0.3"], "[wall] H = 9000 m is outside the typical range"),
])
def test_implausible_values_warn(sandbox, sets, warning):
    args = [a for s in ["analysis.fe=false", "output.png=false", *sets] for a in ("--set", s)]
    res = invoke("demo", "--json", *args)
    assert res.exit_code == 0
    assert doc("is outside the typical range") in res.stderr and warning in res.stderr
    assert any(warning in w for w in json.loads(res.stdout)["warnings"])


# ----------------------------------------------------------------------------- newcomer
def test_version_and_help_show_defaults_and_units():
    import homlimit

    res = invoke("--version")
    assert res.exit_code == 0 and res.stdout.strip() == f"homlimit {homlimit.__version__}"
    def helptext(cmd):
        out = CliRunner().invoke(app, [cmd, "--help"], env={"COLUMNS": "160"}).stdout
        text = " ".join(out.replace("│", " ").split())     # rich's box drawn away
        return re.sub(r"(\w)- (\w)", r"\1-\2", text)       # a word wrapped at its hyphen

    for cmd, folder in (("run", "NAME/"), ("demo", "NAME/"), ("table1", "table1/"),
                        ("figure2", "figure2/"), ("crack-study", "crack-study/"),
                        ("pulse", "NAME/pulse/"), ("mesh", "NAME/mesh/")):
        text = helptext(cmd)
        assert "Output folder ." not in text and "FE mesh size ." not in text, cmd
        assert f"[default: homlimit-out/{folder}" in text, cmd
    t1 = helptext("table1")
    assert "FE mesh size [m] (with --fe). [default: 0.25]" in t1
    from homlimit.app.budget import DEFAULT_MAX_TRIANGLES

    assert "--max-triangles" in t1 and f"[default: {DEFAULT_MAX_TRIANGLES}]" in t1
    cs = helptext("crack-study")
    assert "A second, finer mesh size [m] (0: none). [default: 0.25]" in cs
    assert "Joint friction f [-]" in cs and "[default: 0.3, 0.6, 0.9]" in cs


def test_summary_json_has_units(sandbox):
    assert invoke("demo", "--set", "analysis.fe=false", "--out", "o").exit_code == 0
    u = json.loads((sandbox / "o" / "summary.json").read_text())["units"]
    assert u["inputs"]["wall"]["H"] == "m" and u["inputs"]["wall"]["gamma"] == "kg/m^3"
    assert u["results"]["vg"] == "m/s" and u["results"]["lam"] == "-"
    assert u["results"]["I_O"] == "kg m^2" and u["results"]["theta_m"] == "rad"
    assert None not in u["results"].values()                # every quantity has its unit


# ----------------------------------------------------------------------------- options
@pytest.fixture
def no_table1(no_compute, monkeypatch):
    """No column of table1 may start, nor verify's meshing: for option checks."""
    def boom(*a, **k):  # pragma: no cover - must never run
        raise AssertionError("computation started")

    from homlimit.app import verify
    from homlimit.app.commands import table1

    monkeypatch.setattr(pipeline, "table1_blocks_records", boom)
    monkeypatch.setattr(table1, "table1_dem_records", boom)
    monkeypatch.setattr(verify, "known_problem", boom)


@pytest.mark.parametrize("flags, named", [
    (["--blocks", "--fe"], doc("--fe and --blocks cannot be combined: allowed one of --fe, "
                               "--blocks, --dem")),
    (["--dem", "--fe"], "--fe and --dem cannot be combined"),
    (["--blocks", "--dem"], "--blocks and --dem cannot be combined"),
])
def test_table1_runs_one_column_at_a_time(sandbox, no_table1, flags, named):
    res = invoke("table1", *flags, "-t", "C4")
    assert res.exit_code == 2, res.output
    assert named in res.stderr
    assert not (sandbox / "homlimit-out").exists()


def test_table1_checks_every_option_whatever_the_flags(sandbox, no_table1):
    res = invoke("table1", "--blocks-facade", "foo")                 # without --blocks
    assert res.exit_code == 2
    assert "--blocks-facade = 'foo' is out of range: allowed one of 'through'" in res.stderr
    res = invoke("table1", "--blocks", "--heights", "0")             # --fe's, with --blocks
    assert res.exit_code == 2 and "--heights = 0 is out of range" in res.stderr
    # a valid option that the column run does not use
    res = invoke("table1", "--blocks-facade", "running-bond")
    assert res.exit_code == 2 and doc("--blocks-facade 'running-bond' is out of range "
                                      "without --blocks: allowed only with table1 "
                                      "--blocks") in res.stderr
    res = invoke("table1", "--blocks", "--mesher", "gmsh", "--workers", "2")
    assert res.exit_code == 2 and "2 problems in the options" in res.stderr
    assert "--mesher 'gmsh' is out of range without --fe" in res.stderr
    assert "--workers 2 is out of range without --fe or --dem" in res.stderr
    assert not (sandbox / "homlimit-out").exists()


def test_option_problems_are_listed_at_once_naming_the_flags(sandbox, no_table1):
    res = invoke("crack-study", "--mesh-size", "0", "--friction", "-1", "--finer", "-1")
    assert res.exit_code == 2
    for piece in (doc("crack-study: 3 problems in the options"),
                  doc("--mesh-size = 0.0 m is out of range: allowed 0 < --mesh-size and "
                      "--mesh-size <= 6.5 m"),
                  doc("--friction = -1.0 is out of range: allowed 0 < --friction"),
                  "--finer = -1.0 m is out of range"):
        assert piece in res.stderr, piece
    assert "mesh_size" not in res.stderr and "f =" not in res.stderr
    res = invoke("verify", "--target-gap", "0", "--max-cycles", "0", "-p", "nope")
    assert res.exit_code == 2 and "3 problems in the options" in res.stderr
    assert doc("verify: --target-gap = 0.0 is out of range") in res.stderr
    assert "--max-cycles = 0 is out of range" in res.stderr
    assert "--problem = 'nope' is not a known-answer problem" in res.stderr
    assert "adapt." not in res.stderr
    res = invoke("table1", "--fe", "--heights", "0", "-t", "B9")
    assert res.exit_code == 2 and "2 problems in the options" in res.stderr
    assert "--heights = 0 is out of range" in res.stderr and "--test = 'B9'" in res.stderr
    assert not (sandbox / "homlimit-out").exists()


def test_verify_refuses_a_budget_its_first_mesh_exceeds(sandbox, no_table1):
    res = invoke("verify", "--max-triangles", "1")              # table1's and crack-study's range
    assert res.exit_code == 2
    assert ("--max-triangles = 1 is out of range: allowed 100 <= --max-triangles and "
            "--max-triangles <= 1e+08") in res.stderr
    res = invoke("verify", "-p", "prandtl", "--max-triangles", "100")   # nothing meshed
    assert res.exit_code == 2
    assert doc("verify: --max-triangles = 100 is out of range: the first mesh of problem "
               "prandtl has about 1,261 triangles (known before meshing): allowed "
               "--max-triangles >= 1,261, or leave prandtl out") in res.stderr
    res = invoke("verify", "-p", "free_block", "-p", "vertical_cut", "--max-triangles", "1000")
    assert res.exit_code == 2 and "problem vertical_cut has about 1,760" in res.stderr
    assert not (sandbox / "homlimit-out").exists()


@pytest.mark.parametrize("cmd", [["demo"], ["table1"], ["crack-study"], ["verify"], ["pulse"],
                                 ["sweep", "--grid", "wall.l=3,6", "--max-cases", "1"]])
def test_quiet_and_verbose_together_are_refused(sandbox, no_table1, cmd):
    res = invoke(*cmd, "-q", "-v")
    assert res.exit_code == 2, res.output
    assert doc("-q/--quiet and -v/--verbose contradict each other") in res.stderr
    assert not (sandbox / "homlimit-out").exists()


def test_a_key_set_twice_is_refused(sandbox, no_compute):
    for cmd in (["demo"], ["mesh"], ["table1", "--dem"]):
        key = "dem.kn" if "--dem" in cmd else "wall.H"
        res = invoke(*cmd, "--set", f"{key}=3e9", "--set", f"{key}=4e9")
        assert res.exit_code == 2, (cmd, res.output)
        assert f"--set {key!r} is given twice ('{key}=3e9', '{key}=4e9'): allowed once" \
            in res.stderr, cmd
    assert doc("--set 'wall.H' is given twice ('wall.H=3', 'wall.H=4'): allowed once") in \
        invoke("run", "--set", "wall.H=3", "--set", "wall.H=4").stderr
    assert not (sandbox / "homlimit-out").exists()


def test_demo_takes_runs_engine_options(sandbox, no_compute):
    """demo is run with no case: --workers, --scheduler, --resume as run takes them (used
    with [analysis] dem only, as run)."""
    for opts in (["--workers", "2"], ["--scheduler", "tcp://127.0.0.1:1"], ["--no-resume"]):
        res = invoke("demo", *opts)
        assert res.exit_code == 2, res.output
        assert "is out of range without [analysis] dem = true" in res.stderr, res.stderr
    assert "--resume / --no-resume" in invoke("demo", "--help").stdout


def test_the_error_table_lists_every_message():
    """docs/cli.md's error table quotes every message these tests check."""
    import ast

    quoted = {node.args[0].value for node in ast.walk(ast.parse(Path(__file__).read_text()))
              if isinstance(node, ast.Call) and getattr(node.func, "id", "") == "doc"}
    text = (ROOT / "docs" / "cli.md").read_text(encoding="utf-8")
    table = text[text.index("## When something goes wrong"):]
    missing = sorted(f for f in quoted if f not in table)
    assert not missing, f"docs/cli.md's error table lacks: {missing}"
    assert len(quoted) >= 25 and DOCUMENTED <= quoted
