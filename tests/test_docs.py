"""The documentation's code runs as written: every ```python block of README.md and docs/*.md
is saved as a script and run by a fresh interpreter (in a scratch folder holding a copy of
examples/, so relative paths resolve as from the repository root), as a reader who copies it
would run it: a block that starts worker processes without an ``if __name__ == "__main__":``
guard fails here as it fails there, which ``exec`` inside pytest never showed. Every
`homlimit ...` command line of their shell blocks names a real command with real options
(parsed by the command line itself)."""

from __future__ import annotations

import re
import shlex
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
DOCS = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]
FENCE = re.compile(r"^```(\w*)\n(.*?)^```", re.S | re.M)


def blocks(lang: set[str]) -> list[tuple[str, str]]:
    """(id, code) of the fenced blocks whose language is in ``lang``."""
    out = []
    for path in DOCS:
        text = path.read_text(encoding="utf-8")
        for k, m in enumerate(FENCE.finditer(text)):
            if m.group(1) in lang:
                line = text[:m.start()].count("\n") + 1
                out.append((f"{path.relative_to(ROOT)}:{line}", m.group(2)))
    return out


PYTHON = blocks({"python"})
SHELL = blocks({"bash", "console", "sh", ""})


def test_the_docs_have_code():
    assert len(PYTHON) >= 6 and any(i.startswith("README.md") for i, _ in PYTHON)


# blocks that solve a program, mesh, plot or start workers (seconds to minutes); the others
# (imports and closed forms) run in the fast tier. Matched on the block's text, not its line.
SLOW_CALLS = ("homlimit.run(", "sweep(", "solve_kinematic(", "bracket(", "analyse_blocks(",
              "case_spectra(", "critical_pulse(", "collapse_threshold(")


def _tier(where: str, code: str):
    slow = any(call in code for call in SLOW_CALLS)
    return pytest.param(where, code, id=where, marks=[pytest.mark.slow] if slow else [])


@pytest.mark.parametrize("where, code", [_tier(w, c) for w, c in PYTHON])
def test_python_blocks_run_as_saved_scripts(where, code, tmp_path):
    shutil.copytree(ROOT / "examples", tmp_path / "examples",
                    ignore=shutil.ignore_patterns("*.py"))
    script = tmp_path / (re.sub(r"\W", "_", where) + ".py")
    script.write_text(code, encoding="utf-8")
    r = subprocess.run([sys.executable, script.name], cwd=tmp_path, capture_output=True,
                       text=True, timeout=900)
    assert r.returncode == 0, f"{where} fails as a script:\n{r.stderr[-3000:]}"
    assert "Traceback" not in r.stderr, f"{where}:\n{r.stderr[-3000:]}"


def _command_lines(code: str) -> list[list[str]]:
    """The argument lists of every `homlimit` (or `python -m homlimit`) command in a shell
    block: prompts, comments and `a && b` chains handled, optional `[ARG]`s dropped."""
    out = []
    for line in code.splitlines():
        line = line.strip().removeprefix("$ ")
        if line.startswith(">>>") or "homlimit" not in line:
            continue
        for part in line.split("&&"):
            words = shlex.split(part, comments=True)
            if words[:3] == ["python", "-m", "homlimit"] or words[:3] == ["python3", "-m",
                                                                          "homlimit"]:
                words = ["homlimit"] + words[3:]
            if words and words[0].endswith("homlimit"):
                out.append([w for w in words[1:] if not (w.startswith("[")
                                                         and w.endswith("]"))])
    return out


COMMANDS = [(where, args) for where, code in SHELL for args in _command_lines(code)]


def test_shell_commands_parse():
    """Every documented command line parses: the command exists, every option is one of its
    options with a valid value."""
    import typer.main

    from homlimit.app.cli import app

    group = typer.main.get_command(app)
    assert len(COMMANDS) >= 8
    for where, args in COMMANDS:
        assert args and not args[0].startswith("-") or args == ["--version"], (where, args)
        if args == ["--version"]:
            continue
        ctx = group.make_context("homlimit", ["--help"], resilient_parsing=True)
        name, cmd, rest = group.resolve_command(ctx, list(args))
        assert cmd is not None, (where, args)
        cmd.make_context(name, rest, parent=ctx)          # raises on an unknown option
