"""What the command line prints: help pages that show every bracketed word of their text and no
value after a flag, and a solver log (-v) that stays off stdout."""

from __future__ import annotations

import re
import subprocess
import sys

import click
import pytest
import typer.main
from typer.testing import CliRunner

from homlimit.app.cli import app

BRACKETED = re.compile(r"\[[^\[\]]*\]")
GROUP = typer.main.get_command(app)


def _commands(group, path=()):
    """(argument path, click command) of every command, groups included."""
    yield path, group
    for name, cmd in getattr(group, "commands", {}).items():
        yield from _commands(cmd, (*path, name))


COMMANDS = list(_commands(GROUP))


def _flat(text: str) -> str:
    return " ".join(text.split())


@pytest.mark.parametrize("path, cmd", COMMANDS, ids=[" ".join(p) or "homlimit"
                                                     for p, _ in COMMANDS])
def test_help_keeps_brackets_and_shows_no_bool_metavar(path, cmd):
    res = CliRunner().invoke(app, [*path, "--help"], prog_name="homlimit",
                             terminal_width=200)
    assert res.exit_code == 0, res.output
    shown = _flat(res.output)
    texts = [cmd.help or ""] + [p.help or "" for p in cmd.params if isinstance(p, click.Option)
                                or hasattr(p, "help")]
    wanted = {_flat(m) for t in texts for m in BRACKETED.findall(t)}
    missing = sorted(w for w in wanted if w not in shown)
    assert not missing, f"bracketed text lost from the help of {path}: {missing}"
    assert "<bool>" not in shown
    for p in cmd.params:            # a flag is shown bare: its option, then its help
        if getattr(p, "is_flag", False) and p.help:
            opt = max(p.opts, key=len)
            assert re.search(rf"{re.escape(opt)}( / --\S+)?\s+{re.escape(_flat(p.help)[:20])}",
                             shown), (opt, shown)


def test_the_bracketed_names_a_user_reads():
    """The cases of the issue: "[pulse]" in pulse's help, units in table1's."""
    def helptext(*args):
        return _flat(CliRunner().invoke(app, [*args, "--help"], terminal_width=200).output)

    assert "against pulse period ([pulse]);" in helptext("pulse")
    t1 = helptext("table1")
    assert "FE mesh size [m] (with --fe)." in t1 and "[default: all 12]" in t1
    assert "--grid wall.l=3,6,9 [--table cases.csv]" in helptext("sweep")


def test_verbose_solver_log_goes_to_stderr(tmp_path):
    """`homlimit demo -v` solving a conic program (the rigid-block model, the cheapest path
    through cvxpy and Clarabel): cvxpy's and Clarabel's logs (Clarabel's printed by its Rust core
    on file descriptor 1) reach stderr, and stdout holds the summary alone."""
    r = subprocess.run([sys.executable, "-m", "homlimit", "demo", "-v", "--set",
                        "analysis.fe=false", "--set", "analysis.blocks=true", "--set",
                        "blocks.step=10", "--set", "output.png=false", "--set",
                        "output.vtu=false", "--out", str(tmp_path / "o")],
                       capture_output=True, text=True, cwd=tmp_path, timeout=600)
    assert r.returncode == 0, r.stderr
    assert "Clarabel" in r.stderr and "pcost" in r.stderr
    assert "Clarabel" not in r.stdout and "pcost" not in r.stdout and "CVXPY" not in r.stdout
    assert r.stdout.startswith("case B1-") and "files:" in r.stdout
