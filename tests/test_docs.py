"""The documentation's code runs as written: every ```python block of README.md and docs/*.md
is executed (in a scratch folder holding a copy of examples/, so relative paths resolve as from
the repository root), and every `homlimit ...` command line of their shell blocks names a real
command with real options (parsed by the command line itself)."""

from __future__ import annotations

import re
import shlex
import shutil
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


@pytest.mark.slow
@pytest.mark.parametrize("where, code", PYTHON, ids=[i for i, _ in PYTHON])
def test_python_blocks_run_as_written(where, code, tmp_path, monkeypatch):
    shutil.copytree(ROOT / "examples", tmp_path / "examples",
                    ignore=shutil.ignore_patterns("*.py"))
    monkeypatch.chdir(tmp_path)
    exec(compile(code, where, "exec"), {"__name__": "__doc_block__"})


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
