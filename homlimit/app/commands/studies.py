"""``homlimit figure2``, ``verify`` and ``crack-study``."""

from __future__ import annotations

from pathlib import Path

from ...fe.adapt import AdaptOptions
from .. import pipeline, plots, report
from ..door import (
    LOG,
    check_verbosity,
    emit_json,
    interruptible,
    setup_logging,
    show,
    stdout_quiet,
    stored_tasks,
)
from ..engine import RecordStore
from ..problems import Problems
from ..tables import check_option, crack_study_checks
from ..verify import check_first_meshes, check_name, verify_records

CRACK_STUDY_FLAGS = {"mesh_size": "--mesh-size", "finer": "--finer", "c_over_a": "--c-over-a",
                     "f": "--friction", "facade": "--facade", "mesher": "--mesher",
                     "max_triangles": "--max-triangles"}


def figure2(as_json, out):
    """``homlimit figure2``'s work: see ``cli.figure2``."""
    out = out or Path("homlimit-out") / "figure2"
    with stdout_quiet(as_json) as stdout, pipeline.result_folder(out, "figure2") as staging:
        curves = pipeline.figure2_curves()
        plots.figure2(staging / "figure2.png", curves)
        report.write(staging / "figure2.json", curves)
    files = {"figure2_png": str(out / "figure2.png"), "figure2_json": str(out / "figure2.json")}
    if as_json:
        emit_json(stdout, {"curves": curves, "files": files})
    else:
        print(f"Figure 2 written to {files['figure2_png']} (curves: {files['figure2_json']})")


def verify(as_json, out, verbose, quiet, problem, target_gap, max_cycles, min_size,
           max_triangles, stress_degree):
    """``homlimit verify``'s work: see ``cli.verify``."""
    out = out or Path("homlimit-out") / "verify"
    problems = Problems("verify")
    problems.check(check_verbosity, verbose, quiet)
    for key, value in (("target_gap", target_gap), ("max_cycles", max_cycles),
                       ("min_size", min_size)):
        problems.check(check_option, "adapt", key, value, "--" + key.replace("_", "-"))
    budget_ok = problems.check(check_option, "mesh", "max_triangles", max_triangles,
                               "--max-triangles")
    problems.check(check_option, "analysis", "stress_degree", stress_degree,
                   "--stress-degree")
    names = [n for n in problem or () if problems.check(check_name, n, "--problem")]
    if budget_ok is not None and len(names) == len(problem or ()):
        problems.check(check_first_meshes, problem, max_triangles, "--max-triangles")
    problems.raise_any()
    setup_logging(verbose, quiet, as_json)
    opts = AdaptOptions(target_gap=target_gap, max_cycles=max_cycles, min_size=min_size,
                        max_triangles=max_triangles)
    with stdout_quiet(as_json or verbose) as stdout, \
            pipeline.result_folder(out, "verify") as staging:
        records = verify_records(problem, opts, stress_degree=stress_degree,
                                 progress=lambda n, c: LOG.info(
            "verify %s: cycle %d, %d triangles, %.6g <= lambda <= %.6g; best %.6g .. %.6g "
            "(gap %.3g %%), %.1f s", n, c.cycle, c.triangles, c.lower, c.upper, c.best_lower,
            c.best_upper, 100 * c.rel_gap, c.seconds))
        cycles = [{"problem": r["problem"], **c} for r in records for c in r["adapt"]]
        report.write(staging / "verify.json", {"problems": records})
        report.write(staging / "verify.csv", cycles)
    files = [out / "verify.json", out / "verify.csv"]
    cols = ["problem", "triangles", "cycles", "lower", "upper", "rel_gap", "exact_lo",
            "exact_hi", "holds"]
    show(stdout, as_json, {"problems": records, "files": list(map(str, files))}, records,
         cols, "known-answer problems, adaptive bracket", files)
    if not as_json:
        for r in records:
            if r["problem"] == "tsection" and r.get("T1") is not None:
                print(f"tsection crack: hinge z = {r['z0']:.3f} m (exact {r['z0_exact']:.3f}), "
                      f"fan edges {r['T1']:.3f} .. {r['T2']:.3f} (f = {r['f']:.3f}, "
                      f"c/a = {r['c_over_a']:.3f}), sqrt(T1 T2) = "
                      f"{(r['T1'] * r['T2']) ** 0.5:.3f} against sqrt(cf/a) = "
                      f"{r['sqrt_cf_a']:.3f}, mid-line {r['T_mid']:.3f} (the exact fan's "
                      f"50 % ray {r['T_mid_exact']:.3f})")
                if r.get("conform"):
                    c = r["conform"]
                    print(f"  lambda+ also searched over {c['trials']} meshes conforming to a "
                          f"hinge + fan ({c['seconds']:.0f} s; docs/adaptive.md): best "
                          f"{c['lam']:.6f}")


def crack_study(as_json, out, verbose, quiet, mesh_size, finer, quick, c_over_a, friction,
                facade, max_triangles, mesher, conform, workers, scheduler, resume):
    """``homlimit crack-study``'s work: see ``cli.crack_study``."""
    out = out or Path("homlimit-out") / "crack-study"
    grid = dict(mesh_size=mesh_size, finer=finer or None, quick=quick, c_over_a=c_over_a,
                frictions=friction, facades=facade, max_triangles=max_triangles,
                mesher=mesher)
    problems = Problems("crack-study")
    problems.check(check_verbosity, verbose, quiet)
    crack_study_checks(problems, **grid, names=CRACK_STUDY_FLAGS)
    problems.raise_any()
    setup_logging(verbose, quiet, as_json)
    grid["conform"] = conform
    store = RecordStore(out / "records")   # a nested set: kept when the set is replaced
    with stdout_quiet(as_json or verbose) as stdout, interruptible(store.folder), \
            pipeline.result_folder(out, "crack-study") as staging:
        with stored_tasks(store, "crack-study", "crack-study", resume=resume, workers=workers,
                          scheduler=scheduler, quiet=quiet or as_json) as map_:
            records = pipeline.crack_study_records(**grid, map=map_)
        report.write(staging / "crack_study.csv", records)
        plots.plot_crack_study(staging / "crack_study.png", records,
                               title="crack-angle study: FE crack against √(cf/a), f and c/a")
    files = {"csv": out / "crack_study.csv", "png": out / "crack_study.png"}
    cols = ["facade", "mesh_size", "c_over_a", "f", "mechanism_fe", "tanpsi_fe", "dtanpsi_fe",
            "tan_alpha", "tanpsi_block", "tanpsi_fixed", "conform_T1", "conform_T2",
            "multiplier_fe", "conform_multiplier", "multiplier_fan"]
    show(stdout, as_json, {"records": records, "files": files}, records, cols,
         "crack-angle study: FE crack slope tan psi (50 % line, edges) beside tan_alpha = "
         "sqrt(cf/a)", files.values())
