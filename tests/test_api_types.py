"""``homlimit.run``'s arguments of the wrong type: ParameterError naming the argument, its
value and what is allowed, before anything is read or written (once a bare TypeError, and
write="no" counted as true and wrote files)."""

from __future__ import annotations

import pytest

import homlimit
from homlimit.app import pipeline

BASE = {"wall": {"H": 9.0, "L": 6.0, "s": 0.5, "b": 0.25, "l": 2.5},
        "masonry": {"a": 0.3, "c": 0.2, "f": 0.6}, "analysis": {"fe": False}}


@pytest.mark.parametrize("args, kw, message", [
    ((123,), {}, "path_or_dict = 123 (int) has the wrong type: allowed a case file's path"),
    ((b"case.toml",), {}, "path_or_dict = b'case.toml' (bytes) has the wrong type"),
    ((BASE,), {"out": 5}, "out = 5 (int) has the wrong type: allowed a folder's path"),
    ((BASE,), {"write": "no"}, "write = 'no' (str) has the wrong type: allowed True or False"),
    ((BASE,), {"write": 0}, "write = 0 (int) has the wrong type: allowed True or False"),
    ((BASE,), {"overrides": 5}, "overrides = 5 (int) has the wrong type: allowed a list of"),
])
def test_wrong_types_are_parameter_errors(tmp_path, monkeypatch, args, kw, message):
    monkeypatch.chdir(tmp_path)
    monkeypatch.setattr(pipeline, "compute", lambda *a, **k: pytest.fail("computed"))
    with pytest.raises(homlimit.ParameterError) as e:
        homlimit.run(*args, **kw)
    assert message in str(e.value)
    assert not any(tmp_path.iterdir())        # nothing written


def test_the_right_types_still_run(tmp_path):
    assert homlimit.run(BASE, write=False).files == {}
    res = homlimit.run(BASE, out=tmp_path / "o", write=True)
    assert (tmp_path / "o" / "summary.json").is_file() and res.mechanisms["I"].vg > 0
