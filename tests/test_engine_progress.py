"""The Dask engine's progress bar (stderr) follows -q and --json on every command that opens
it: shown by default, hidden with -q or --json (table1 --fe, table1 --dem, crack-study)."""

import pytest
from typer.testing import CliRunner

from homlimit.app import door
from homlimit.app.cli import app


class _Stop(Exception):
    pass


@pytest.mark.parametrize("args", [["table1", "--fe", "-t", "B1"], ["table1", "--dem", "-t", "B1"],
                                  ["crack-study"]])
@pytest.mark.parametrize("flag, shown", [([], True), (["-q"], False), (["--json"], False)])
def test_progress_bar_follows_quiet_and_json(args, flag, shown, tmp_path, monkeypatch):
    seen = []

    def engine(workers=None, scheduler=None, progress=True):
        seen.append(progress)
        raise _Stop     # before any work: only the engine's settings are under test

    monkeypatch.setattr(door, "Engine", engine)
    res = CliRunner().invoke(app, [*args, *flag, "--out", str(tmp_path / "o")])
    assert seen == [shown], (res.exit_code, res.output)
