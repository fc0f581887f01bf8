"""The DEM's doors (issue 29): the [dem] case section, ``[analysis] dem = true`` in ``run``,
``homlimit table1 --dem`` on the Dask engine, and the ParaView series and snapshots.

Every DEM run here is cheap: a small stack or a short, coarse setting; never a full Table 1
wall's threshold (that is benchmarks/dem_table1.py's, minutes per wall).
"""

from __future__ import annotations

import dataclasses
import json
import math
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from homlimit.app.cli import app
from homlimit.app.config import SCHEMA, ConfigError, DemConfig, load_case
from homlimit.app.dem_stage import dem_params
from homlimit.dem import DEMParams

from cases import B1


# ----------------------------------------------------------------------------- [dem] section
def test_dem_section_defaults_are_the_models_defaults():
    cfg = load_case(B1)
    assert cfg.dem == DemConfig()
    assert cfg.analysis.dem is False                    # off by default
    for name, key in SCHEMA["dem"].items():
        assert getattr(cfg.dem, name) == key.default, name
    # every parameter of DEMParams is a [dem] key, with the same default ("rho" is 0)
    assert dem_params(cfg.dem) == DEMParams()
    assert {f.name for f in dataclasses.fields(DEMParams)} <= set(SCHEMA["dem"])
    p = dem_params(dataclasses.replace(cfg.dem, facade_stiffness=3.0, base_joint="tied"))
    assert p.facade_stiffness == 3.0 and p.base_joint == "tied"


def test_bad_dem_values_are_reported_at_once_with_key_value_and_range():
    with pytest.raises(ConfigError) as e:
        load_case({**B1, "dem": {"kn": -1.0, "dt_fraction": 0.9, "loading": "sine",
                                 "base_joint": "glued", "frame": 1}})
    text = str(e.value)
    assert "[dem] kn = -1.0 Pa/m is out of range: allowed 100000 <= kn <= 1e+13 Pa/m" in text
    assert "[dem] dt_fraction = 0.9 is out of range: allowed 0 < dt_fraction <= 0.5" in text
    assert "[dem] loading = 'sine' is not allowed: allowed one of 'impulse'" in text
    assert "[dem] base_joint = 'glued' is not allowed" in text
    assert "[dem] unknown key 'frame'" in text
    assert len(e.value.problems) == 5


def test_dem_refuses_an_assembly_over_max_blocks():
    with pytest.raises(ConfigError, match=r"\[analysis\] dem = true needs about 480 blocks .* "
                                          r"\[dem\] max_blocks = 100"):
        load_case({**B1, "analysis": {"dem": True}, "dem": {"max_blocks": 100}})
    load_case({**B1, "dem": {"max_blocks": 100}})       # only when the DEM runs


def test_cli_bad_dem_value_exits_2_before_any_work(tmp_path):
    out = tmp_path / "o"
    res = CliRunner().invoke(app, ["run", "--set", "analysis.dem=true", "--set",
                                   "dem.rel_tol=0", "--out", str(out)])
    assert res.exit_code == 2, res.output
    assert "[dem] rel_tol = 0 is out of range: allowed 0 < rel_tol <= 0.5" in res.output
    assert "Traceback" not in res.output
    assert not out.exists()


# ----------------------------------------------------------------------------- homlimit run
#: a small T-section (4 courses, 13 blocks): a threshold in about a second
SMALL = {"name": "small",
         "wall": {"H": 1.2, "L": 0.8, "s": 0.3, "b": 0.3, "l": 1.2},
         "masonry": {"a": 0.3, "c": 0.2, "f": 0.6},
         "analysis": {"fe": False, "hinge_check": False, "dem": True},
         "dem": {"rel_tol": 0.05, "t_max": 2.0, "frame_interval": 0.1}}


@pytest.fixture(scope="module")
def small_run(tmp_path_factory):
    from homlimit.app import pipeline

    out = tmp_path_factory.mktemp("small")
    return pipeline.run(SMALL, out=out), out


def test_run_with_dem_brackets_its_threshold_and_reports_it(small_run):
    from homlimit.blocks.geometry import t_section_blocks
    from homlimit.dem import build_model, run, settle

    result, out = small_run
    d = json.loads((out / "summary.json").read_text(encoding="utf-8"))["dem"]
    assert d["loading"] == "impulse" and d["n_trials"] == len(d["trials"]) >= 2
    assert d["vg_lo"] < d["vg"] < d["vg_hi"]
    assert (d["vg_hi"] - d["vg_lo"]) / (d["vg_hi"] + d["vg_lo"]) <= 0.05
    assert d["vnorm"] == pytest.approx(d["vg"] / math.sqrt(9.81 * 0.3), rel=1e-12)
    # the failing part is whole courses of a = 0.3 m, at most the wall
    assert 0 < d["h"] <= 1.2 and d["h"] / 0.3 == pytest.approx(round(d["h"] / 0.3), abs=1e-9)
    assert isinstance(d["base_slid"], bool) and isinstance(d["hinge_slid"], bool)
    # the bracket holds when the engine is called directly on the same model: the lower end
    # stands for t_max, the upper collapses
    model = build_model(t_section_blocks(result.case, facade="through"))
    settled, _ = settle(model)
    assert not run(model, settled, v_g=d["vg_lo"], t_max=2.0).collapsed
    assert run(model, settled, v_g=d["vg_hi"], t_max=2.0).collapsed
    text = result.summary()
    assert "DEM (homlimit.dem), ideal impulse" in text
    assert f"{d['n_trials']} trials" in text and "base slid" in text
    assert d["seconds"] > 0 and d["cpu"] > 0
    assert json.loads((out / "summary.json").read_text())["units"]["results"]["vg_lo"] == "m/s"


@pytest.mark.slow
def test_run_with_dem_makes_every_trial_a_task_and_resumes(small_run, tmp_path):
    # `homlimit run` with [analysis] dem: every trial a Dask task with its record kept in
    # OUT/records/ (issue 29): the trials and threshold of the run here (small_run), a rerun
    # that reads them all back, a run cut short that resumes at the trial where it stopped
    from cases import toml

    result, _ = small_run
    here = result.dem_run.as_dict()
    case = tmp_path / "small.toml"
    case.write_text(toml({**SMALL, "output": {"png": False, "vtu": False}}), encoding="utf-8")
    out = tmp_path / "o"
    args = ["run", str(case), "--workers", "1", "--json", "--out", str(out)]
    first = CliRunner().invoke(app, args)
    assert first.exit_code == 0, first.output
    d = json.loads(first.stdout)["dem"]
    for k in ("vg", "vg_lo", "vg_hi", "h", "z0", "base_slip", "hinge_slip", "dt"):
        assert d[k] == pytest.approx(here[k], rel=1e-12), k      # the JSON's 15 digits
    assert (d["base_slid"], d["hinge_slid"], d["n_blocks"]) == (
        here["base_slid"], here["hinge_slid"], here["n_blocks"])
    assert [(t["vg"], t["collapsed"]) for t in d["trials"]] == [
        (pytest.approx(t["vg"], rel=1e-12), t["collapsed"]) for t in here["trials"]]
    # every digit of each trial's amplitude, as text, to re-run it exactly
    assert [float(t["exact"]) for t in d["trials"]] == [t["vg"] for t in here["trials"]]
    records = sorted((out / "records").glob("[!.]*.json"))
    assert len(records) == d["n_trials"] >= 2                  # one per trial
    stamps = {p: p.stat().st_mtime_ns for p in records}
    again = CliRunner().invoke(app, args)
    assert again.exit_code == 0, again.output
    assert json.loads(again.stdout)["dem"]["trials"] == d["trials"]
    assert {p: p.stat().st_mtime_ns for p in records} == stamps   # read back, not re-run
    # cut short: the last trial's record lost; the rerun runs that trial alone
    last = max(records, key=lambda p: p.stat().st_mtime_ns)
    last.unlink()
    resumed = CliRunner().invoke(app, args)
    assert resumed.exit_code == 0, resumed.output
    assert json.loads(resumed.stdout)["dem"]["trials"] == d["trials"]
    now = sorted((out / "records").glob("[!.]*.json"))
    assert len(now) == len(records)
    assert [p for p in now if p.stat().st_mtime_ns != stamps.get(p)] == [last]
    # --no-resume clears them first: every trial runs again
    fresh = CliRunner().invoke(app, [*args, "--no-resume"])
    assert fresh.exit_code == 0, fresh.output
    assert all(p.stat().st_mtime_ns > stamps[p] for p in records if p != last)


@pytest.mark.parametrize("extra, flag", [(["--workers", "2"], "--workers 2"),
                                         (["--no-resume"], "--no-resume")])
def test_run_refuses_engine_options_without_the_dem(tmp_path, extra, flag):
    out = tmp_path / "o"
    res = CliRunner().invoke(app, ["run", "--set", "analysis.fe=false", *extra, "--out",
                                   str(out)])
    assert res.exit_code == 2, res.output
    assert f"{flag} is out of range without [analysis] dem = true" in res.output
    assert not out.exists()


def test_dem_is_off_by_default(tmp_path):
    from homlimit.app import pipeline

    res = pipeline.run({**SMALL, "analysis": {"fe": False, "hinge_check": False}},
                       out=tmp_path / "o")
    assert res.dem_run is None
    assert json.loads((tmp_path / "o" / "summary.json").read_text())["dem"] is None
    assert not (tmp_path / "o" / "dem.pvd").exists()


def test_pulse_loading_finds_the_pulse_amplitude(tmp_path):
    from homlimit.app import pipeline
    from homlimit.dynamics.pulses import make_pulse

    case = {**SMALL, "dem": {**SMALL["dem"], "loading": "rectangular", "pulse_period": 0.3,
                             "rel_tol": 0.1, "t_max": 1.5},
            "output": {"vtu": False, "png": False}}
    res = pipeline.run(case, out=tmp_path / "o")
    d = res.to_dict()["dem"]
    assert d["loading"] == "rectangular" and d["pulse_period"] == 0.3
    assert d["pga_lo"] < d["pga"] < d["pga_hi"]
    # a rectangular pulse's pgv is a_g × Δt
    assert d["pgv"] == pytest.approx(make_pulse("rectangular", 0.3, d["pga"]).pgv, rel=1e-12)
    assert d["pgv"] == pytest.approx(0.3 * d["pga"], rel=1e-9)
    assert not (tmp_path / "o" / "dem.pvd").exists()


@pytest.mark.parametrize("loading, period, expected", [
    ("impulse", 0.2, 0.8),            # B1: UDEC's 0.83 m/s rounded to 0.1
    ("rectangular", 0.1, 8.0),        # the a_g whose pgv a_g Δt is 0.8 m/s
    ("one-sine", 0.1, 0.8 * math.pi / 0.1),   # pgv = a_g T/π
    ("rectangular", 2.0, "static")])  # 0.4 m/s² is below mechanism I's λ g: that instead
def test_a_pulse_search_starts_where_its_pgv_is_the_impulse_guess(loading, period, expected):
    from homlimit.app.dem_stage import _guess
    from homlimit.closed_form.mechanisms import mechanism_I

    config = load_case(overrides={"dem.loading": loading, "dem.pulse_period": period})
    case = config.case
    assert case.name.startswith("B1")      # B1-<hash> once --set changed an input
    lam_g = mechanism_I(case).multiplier * case.wall.g       # 2.07 m/s² for B1
    assert 0.4 < lam_g < 8.0
    want = lam_g if expected == "static" else expected
    assert _guess(case, config.dem) == pytest.approx(want, rel=1e-12)


def _one_sine_csv(path, period=0.3, step=1e-3):
    """A one-sine pulse of a_g = 1 m/s² sampled every ``step`` s as a record CSV."""
    t = np.arange(0.0, period + step / 2, step)
    a = np.sin(2 * np.pi * t / period)
    path.write_text("t,a_g\n" + "".join(f"{x!r},{y!r}\n" for x, y in zip(t.tolist(), a.tolist())))
    return path


def test_a_record_is_a_base_acceleration_equal_to_the_pulse_it_samples(tmp_path):
    # a one-sine of 0.3 s sampled every 1 ms, linear between samples: a_g within
    # (2π·1e-3/0.3)²/8 = 5.5e-5 of the pulse's (measured below). Its threshold, as its pga,
    # is the one-sine's within the bisection's tolerance, from the same first trial
    from homlimit.app import pipeline
    from homlimit.app.config import resolved_inputs, wall_inputs
    from homlimit.app.dem_stage import _pulse, _record, dem_threshold, threshold_by_trials

    csv = _one_sine_csv(tmp_path / "sine.csv")
    dem = {**SMALL["dem"], "rel_tol": 0.1, "t_max": 1.5, "guess": 10.0}
    runs = {}
    for loading in ("one-sine", "record"):
        extra = {"loading": loading, "pulse_period": 0.3}
        if loading == "record":
            extra["record"] = str(csv)
        case = {**SMALL, "dem": {**dem, **extra}, "output": {"vtu": False, "png": False}}
        runs[loading] = pipeline.run(case, out=tmp_path / loading).to_dict()["dem"]
    sine, rec = runs["one-sine"], runs["record"]
    assert rec["loading"] == "record" and rec["record"] == str(csv)
    assert rec["pga_lo"] < rec["pga"] < rec["pga_hi"]
    assert rec["pga"] == pytest.approx(sine["pga"], rel=0.1)
    # the record's pgv at its threshold: a_g T/π of the one-sine, within the sampling error
    assert rec["pgv"] == pytest.approx(rec["pga"] * 0.3 / math.pi, rel=1e-4)
    config = load_case({**SMALL, "dem": {**dem, "loading": "record", "record": str(csv)}})
    record = _record(config)
    t = np.linspace(0.0, 0.3, 3001)
    err = _pulse(config.dem, 7.0, record).a(t) - 7.0 * np.sin(2 * np.pi * t / 0.3)
    assert np.abs(err).max() < 7.0 * 5.6e-5
    # every trial a task carries the samples: the same trials as the run here, bit for bit
    here = dem_threshold(config).threshold
    item = {"wall": wall_inputs(resolved_inputs(config)),
            "dem": dataclasses.asdict(config.dem), "record": {
                "t": record.t.tolist(), "a_g": record.a_g.tolist(), "name": record.name}}
    tasks, _ = threshold_by_trials(item, config.case, config.dem,
                                   lambda fn, items: [fn(x) for x in items], "a_g")
    assert tasks.trials == here.trials


@pytest.mark.parametrize("dem, message", [
    ({"loading": "record"}, "[dem] loading = 'record' needs [dem] record: out of range"),
    ({"record": "a.csv"}, "[dem] record = 'a.csv' is used only with loading = 'record': out "
                          "of range with loading = 'impulse'"),
    ({"loading": "record", "record": "nope.csv"}, "[dem] record = 'nope.csv': record = ")])
def test_a_bad_record_is_refused_before_any_work(tmp_path, monkeypatch, dem, message):
    monkeypatch.chdir(tmp_path)
    with pytest.raises(ConfigError) as e:
        load_case({**SMALL, "dem": {**SMALL["dem"], **dem}})
    assert message in str(e.value)
    res = CliRunner().invoke(app, ["run", "--set", "analysis.dem=true",
                               *[x for k, v in dem.items() for x in ("--set", f"dem.{k}={v}")],
                               "--out", str(tmp_path / "o")])
    assert res.exit_code == 2 and message in res.output, res.output
    assert not (tmp_path / "o").exists()


# ----------------------------------------------------------------------------- table1 --dem
#: a cheap, coarse setting for the door only (never the table's): short trials from a high
#: first guess, so a wall takes three trials; a 5 cm Verlet margin, since the blocks fly at
#: 10-20 m/s (a 5 mm one rebuilds the list every few steps)
CHEAP = ["--set", "dem.t_max=0.2", "--set", "dem.rel_tol=0.5", "--set", "dem.settle_time=0.05",
         "--set", "dem.guess=20", "--set", "dem.verlet_margin=0.05"]


@pytest.mark.slow
def test_table1_dem_runs_walls_on_dask_beside_udec_and_resumes(tmp_path, table1_ref):
    out = tmp_path / "t1"
    args = ["table1", "--dem", "-t", "C4", "-t", "C1", *CHEAP, "--workers", "2", "--json",
            "--out", str(out)]
    res = CliRunner().invoke(app, args)
    assert res.exit_code == 0, res.output
    data = json.loads(res.stdout)
    rows = {r["test"]: r for r in data["rows"]}
    assert list(rows) == ["C1", "C4"]                       # Table 1's order
    for t, r in rows.items():
        ref = table1_ref[t]
        assert (r["vg_udec"], r["h_udec"], r["vnorm_udec"]) == (ref["vg"], ref["h_v"],
                                                                ref["vg_norm"])
        assert r["vg_lo"] < r["vg"] < r["vg_hi"] and r["n_trials"] == 3
        assert r["dem_over_udec"] == pytest.approx(r["vg"] / ref["vg"], rel=1e-12)
        assert r["vnorm"] == pytest.approx(r["vg"] / math.sqrt(9.81 * ref["b"]), rel=1e-12)
    ratio = data["ratios"]["C4/C1"]
    assert ratio["vnorm_udec"] == pytest.approx(table1_ref["C4"]["vg_norm"]
                                                / table1_ref["C1"]["vg_norm"], rel=1e-12)
    assert ratio["vnorm"] == pytest.approx(rows["C4"]["vnorm"] / rows["C1"]["vnorm"])
    records = sorted((out / "records").glob("[!.]*.json"))
    assert len(records) == 6                                # one per trial (issue 29)
    stamps = [p.stat().st_mtime_ns for p in records]
    # a rerun reads the walls back from the records instead of running them again
    again = CliRunner().invoke(app, args)
    assert again.exit_code == 0, again.output
    assert json.loads(again.stdout)["rows"] == data["rows"]
    assert [p.stat().st_mtime_ns for p in sorted((out / "records").glob("[!.]*.json"))] == stamps
    assert (out / "table1_dem.csv").is_file() and (out / "table1_dem_ratios.json").is_file()


@pytest.mark.slow
def test_table1_dem_one_trial_per_task_repeats_the_walls_run_here():
    # every trial a call of map with one item (a task on an engine), the walls' bisections in
    # threads: the same trials and thresholds as one wall after the other, every trial here
    from homlimit.app import dem_table1

    # half CHEAP's trial length, twice its first guess: three trials
    section = dem_table1.dem_section([*(s for s in CHEAP[1::2] if not s.startswith(
        ("dem.t_max=", "dem.guess="))), "dem.t_max=0.1", "dem.guess=40"])
    calls = []

    def fake_map(fn, items):
        calls.append((fn.__name__, [dict(x) for x in items]))
        return [fn(x) for x in items]

    here, r_here = dem_table1.table1_dem_records(["C1"], section)
    tasks, r_tasks = dem_table1.table1_dem_records(["C1"], section, map=fake_map)
    assert len(calls) == sum(r["n_trials"] for r in here) == 3
    assert all(name == "trial_task" and len(items) == 1 for name, items in calls)
    timing = ("seconds", "cpu")
    for a, b in zip(here, tasks):
        assert {k: v for k, v in a.items() if k not in timing} == \
            {k: v for k, v in b.items() if k not in timing}
    assert r_here == r_tasks


@pytest.mark.parametrize("extra, message", [
    (["--set", "dem.kn=0"], "[dem] kn = 0 Pa/m is out of range: allowed 100000 <= kn"),
    (["--set", "wall.H=3"], "--set 'wall.H=3' is out of range for table1 --dem"),
    (["--set", "dem.loading=ricker"], "[dem] loading = 'ricker' is out of range for table1"),
    (["-t", "B9"], "test = 'B9'"),
])
def test_table1_dem_refuses_bad_input_before_any_work(tmp_path, extra, message):
    out = tmp_path / "t1"
    res = CliRunner().invoke(app, ["table1", "--dem", *extra, "--out", str(out)])
    assert res.exit_code == 2, res.output
    assert message in res.output and "Traceback" not in res.output
    assert not out.exists()


def test_table1_set_needs_dem(tmp_path):
    out = tmp_path / "t1"
    res = CliRunner().invoke(app, ["table1", "--set", "dem.kn=3e9", "--out", str(out)])
    assert res.exit_code == 2, res.output
    assert "--set 'dem.kn=3e9' is out of range without --dem" in res.output
    assert not out.exists()


# ----------------------------------------------------------------------------- outputs
def test_paraview_series_reads_back_and_ends_in_the_models_state(small_run):
    import meshio

    from homlimit.dem import run

    result, out = small_run
    dr = result.dem_run
    root = ET.parse(out / "dem.pvd").getroot()
    sets = root.findall("./Collection/DataSet")
    blocks = [s for s in sets if s.get("part") == "0"]
    contacts = [s for s in sets if s.get("part") == "1"]
    assert len(blocks) == len(contacts) >= 2
    times = [float(s.get("timestep")) for s in blocks]
    assert times[0] == 0 and np.all(np.diff(times) > 0)
    n = dr.model.n_blocks
    last = meshio.read(out / blocks[-1].get("file"))
    assert sum(len(c.data) for c in last.cells) == n
    rot = np.concatenate(last.cell_data["rotation"])
    idx = np.concatenate(last.cell_data["block"])
    # the same history run in one piece by the engine ends in the state of the last frame
    whole = run(dr.model, dr.settled, v_g=dr.threshold.hi,
                t_max=times[-1] - 0.5 * dr.model.dt, stop_on_collapse=False)
    top = int(np.argmax(dr.model.assembly.bounds()[:, 3] * dr.model.watch))
    assert rot[idx == top][0] == pytest.approx(whole.state.th[top], rel=1e-9, abs=1e-12)
    np.testing.assert_allclose(rot[np.argsort(idx)], whole.state.th, rtol=1e-9, atol=1e-12)
    assert abs(whole.state.th[top]) > 0.05           # the frame shows the collapse
    # the settled frame's contacts carry the weight: the ground's reactions sum to m g
    first = meshio.read(out / contacts[0].get("file"))
    on_ground = first.point_data["other"] == 0
    assert first.point_data["force"][on_ground, 1].sum() == pytest.approx(
        9.81 * dr.model.assembly.mass[~dr.model.assembly.fixed].sum(), rel=1e-3)
    assert (out / "dem_snapshots.png").stat().st_size > 10_000
    assert not any(p.name.startswith(".") for p in (out / "dem").iterdir())


def test_series_is_written_whole_or_not_at_all(tmp_path, monkeypatch):
    from homlimit.blocks.geometry import stack
    from homlimit.dem import build_model, settle
    from homlimit.dem.output import record_frames, write_series
    from homlimit.errors import OutputError
    from homlimit.fe import mesh as fe_mesh

    model = build_model(stack([0.5, 0.45], [1.0, 1.0], density=2000.0, meta={"f": 0.6}))
    settled, _ = settle(model)
    frames = record_frames(model, settled, v_g=0.3, t_max=0.1, interval=0.05)
    pvd = write_series(tmp_path, model, settled, frames)          # a first, whole series
    before = pvd.read_text()
    real, calls = fe_mesh.write, []

    def failing(mesh, path):
        calls.append(path)
        if len(calls) == 3:
            raise OSError(28, "No space left on device")
        return real(mesh, path)

    monkeypatch.setattr(fe_mesh, "write", failing)
    with pytest.raises(OutputError, match="No space left on device"):
        write_series(tmp_path, model, settled, frames)
    # the previous series is kept whole (every frame its .pvd lists), no temporary left
    assert sorted(p.name for p in tmp_path.iterdir()) == ["dem", "dem.pvd"]
    assert pvd.read_text() == before
    listed = [d.get("file") for d in ET.parse(pvd).getroot().iter("DataSet")]
    assert sorted(listed) == sorted(f"dem/{p.name}" for p in (tmp_path / "dem").iterdir())
    # a new series replaces it
    monkeypatch.setattr(fe_mesh, "write", real)
    short = write_series(tmp_path, model, settled, frames[:2])
    assert len(list(ET.parse(short).getroot().iter("DataSet"))) == 4
    assert len(list((tmp_path / "dem").iterdir())) == 4
    assert sorted(p.name for p in tmp_path.iterdir()) == ["dem", "dem.pvd"]


def test_a_sweep_case_with_the_dem_is_not_batched_as_closed_form_only():
    from homlimit.app.sweep import SweepCase

    closed = load_case({**B1, "analysis": {"fe": False}})
    dem = load_case({**B1, "analysis": {"fe": False, "dem": True}})
    assert SweepCase(0, {}, "k", closed).closed_form_only
    assert not SweepCase(0, {}, "k", dem).closed_form_only      # run_case runs its DEM


def test_run_writes_the_animation_as_a_gif_of_both_trials(small_run):
    from PIL import Image

    result, out = small_run
    th = result.dem_run.threshold
    gif = out / "dem_animation.gif"
    with Image.open(gif) as im:
        assert im.format == "GIF"
        # the standing trial runs t_max = 2 s in frames of 0.1 s: 21 frames, t = 0 included
        assert im.n_frames == 21
        assert im.info["duration"] == 100          # real time: 0.1 s per frame
        im.seek(0)
        first = np.asarray(im.convert("RGB"), float)
        im.seek(im.n_frames - 1)
        last = np.asarray(im.convert("RGB"), float)
    assert np.abs(first - last).max() > 50          # the blocks moved between them
    d = json.loads((out / "summary.json").read_text(encoding="utf-8"))
    assert d["files"]["dem_animation_gif"].endswith("dem_animation.gif")
    assert th.lo < th.hi
    assert not any(p.name.startswith(".") for p in out.iterdir()
                   if p.name != ".homlimit-set.json")


def test_animation_is_written_whole_or_not_at_all(tmp_path, monkeypatch):
    from matplotlib.animation import PillowWriter

    from homlimit.blocks.geometry import stack
    from homlimit.dem import build_model, settle
    from homlimit.dem.output import plot_animation, record_frames
    from homlimit.errors import OutputError

    model = build_model(stack([0.5, 0.45], [1.0, 1.0], density=2000.0, meta={"f": 0.6}))
    settled, _ = settle(model)
    frames = record_frames(model, settled, v_g=0.3, t_max=0.2, interval=0.05)
    gif = plot_animation(tmp_path / "a.gif", model, settled, [("x", frames), ("y", frames[:2])])
    before = gif.read_bytes()

    def failing(self):            # the disk fills while the GIF is being written
        Path(self.outfile).write_bytes(b"GIF89a")
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(PillowWriter, "finish", failing)
    with pytest.raises(OutputError, match="No space left on device"):
        plot_animation(tmp_path / "a.gif", model, settled, [("x", frames)])
    assert [p.name for p in tmp_path.iterdir()] == ["a.gif"]
    assert gif.read_bytes() == before


def test_the_trial_log_gives_every_digit_where_four_are_not_the_amplitude():
    """The multi-storey example's bisection (0.8 m/s times 1.5ⁿ, then midpoints) tries
    1.5000000000000002 and 1.2750000000000001 m/s in floating point, one unit in the last place
    above 1.5 and 1.275, which moved its collapses by a second (docs/dem.md section 3): the
    log shows every digit there; values that four digits give exactly keep four."""
    from homlimit.app.dem_stage import trial_amplitude

    lo, hi = 0.8 * 1.5, 0.8 * 1.5 * 1.5          # 1.2000000000000002, 1.8000000000000003
    mid = 0.5 * (lo + hi)
    assert trial_amplitude(mid) == "1.5 (1.5000000000000002)"
    mid2 = 0.5 * (lo + mid)
    assert trial_amplitude(mid2) == "1.35"
    assert trial_amplitude(0.5 * (lo + mid2)) == "1.275 (1.2750000000000001)"
    assert trial_amplitude(1.275) == "1.275" and trial_amplitude(0.88) == "0.88"
