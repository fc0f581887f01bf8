"""The package's shape: data flows one way, parameters → closed forms / FE → mechanism → app.

Every import of every module (module level and inside functions) is read from the source with
``ast`` and resolved; the test fails on an import cycle between modules and on an import from a
lower layer into a higher one.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

PKG = Path(__file__).resolve().parents[1] / "homlimit"

# the layers, lowest first: a module may import its own subpackage or any lower layer
LAYERS = [("errors", "_version", "_threads"), ("fields",), ("_io",), ("params",), ("geometry",),
          ("impulse",), ("check",), ("closed_form",), ("fe",), ("mechanism",),
          ("blocks", "dynamics"),
          ("dem",), ("app",), ("__init__", "__main__")]
RANK = {name: k for k, names in enumerate(LAYERS) for name in names}


def _modules() -> dict[str, Path]:
    out = {}
    for path in PKG.rglob("*.py"):
        parts = path.relative_to(PKG.parent).with_suffix("").parts
        name = ".".join(parts[:-1] if parts[-1] == "__init__" else parts)
        out[name] = path
    return out


def _imports(name: str, path: Path, modules: dict[str, Path]) -> set[str]:
    """The homlimit modules ``name`` imports (``from . import x`` counts module x)."""
    is_pkg = path.name == "__init__.py"
    base = name.split(".") if is_pkg else name.split(".")[:-1]
    found = set()
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.Import):
            found |= {a.name for a in node.names if a.name.startswith("homlimit")}
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                root = ".".join(base[:len(base) - node.level + 1])
                mod = f"{root}.{node.module}" if node.module else root
            else:
                mod = node.module or ""
            if not mod.startswith("homlimit"):
                continue
            for a in node.names:
                sub = f"{mod}.{a.name}"
                found.add(sub if sub in modules else mod)
    return {m for m in found if m in modules and m != name}


def _layer(module: str) -> str:
    parts = module.split(".")
    return parts[1] if len(parts) > 1 else "__init__"


@pytest.fixture(scope="module")
def graph():
    modules = _modules()
    return {name: _imports(name, path, modules) for name, path in modules.items()}


def test_every_module_has_a_layer(graph):
    missing = sorted({_layer(m) for m in graph} - set(RANK))
    assert not missing, f"subpackages without a layer in LAYERS: {missing}"


def test_no_import_goes_up_a_layer(graph):
    bad = [f"{a} -> {b}" for a, deps in graph.items() for b in deps
           if _layer(a) != _layer(b) and RANK[_layer(b)] >= RANK[_layer(a)]]
    assert not bad, "upward or sideways imports:\n  " + "\n  ".join(sorted(bad))


def test_no_import_cycle(graph):
    # iterative depth-first search; a back edge closes a cycle
    state, stack_path, cycles = {}, [], []

    def visit(start):
        work = [(start, iter(sorted(graph[start])))]
        state[start] = "open"
        stack_path.append(start)
        while work:
            node, it = work[-1]
            nxt = next(it, None)
            if nxt is None:
                state[node] = "done"
                stack_path.pop()
                work.pop()
            elif state.get(nxt) == "open":
                cycles.append(stack_path[stack_path.index(nxt):] + [nxt])
            elif nxt not in state:
                state[nxt] = "open"
                stack_path.append(nxt)
                work.append((nxt, iter(sorted(graph[nxt]))))

    for m in sorted(graph):
        if m not in state:
            visit(m)
    assert not cycles, "import cycles:\n  " + "\n  ".join(" -> ".join(c) for c in cycles)


def test_the_checker_sees_imports():
    """The walker resolves relative imports (a check on the check)."""
    mods = _modules()
    deps = _imports("homlimit.mechanism.analysis", mods["homlimit.mechanism.analysis"], mods)
    assert {"homlimit.params", "homlimit.fe.problems", "homlimit.mechanism.crack"} <= deps


# ----------------------------------------------------------------------------- issue 28
MECHANISM_NAMES = {"I", "II", "FE"}
REGISTRY = "homlimit.app.registry"     # the one module that may compare mechanism names


def _literal_names(node: ast.AST) -> set[str]:
    """The mechanism names a comparison operand spells literally (a string, or a tuple, list
    or set of strings)."""
    items = node.elts if isinstance(node, (ast.Tuple, ast.List, ast.Set)) else [node]
    return {e.value for e in items if isinstance(e, ast.Constant) and e.value in MECHANISM_NAMES}


def _name_comparisons(source: str) -> list[tuple[int, str]]:
    """(line, names) of every comparison (==, !=, in, not in, is, match case) against a
    literal mechanism name, and of every loop over a literal list of them."""
    found = []
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.Compare):
            names = set().union(*(_literal_names(x) for x in [node.left, *node.comparators]))
        elif isinstance(node, ast.MatchValue):
            names = _literal_names(node.value)
        elif isinstance(node, (ast.For, ast.comprehension)) and not isinstance(
                node.iter, ast.Constant):
            names = _literal_names(node.iter)
        else:
            continue
        if names:
            line = node.iter.lineno if isinstance(node, ast.comprehension) else node.lineno
            found.append((line, ", ".join(sorted(names))))
    return sorted(found)


def test_no_module_compares_mechanism_names():
    """Models and mechanisms live in the registry (``app.registry``): no other module
    switches on the names "I", "II" or "FE" (issue 28)."""
    bad = [f"{name}:{line}: compares against {names}"
           for name, path in sorted(_modules().items()) if name != REGISTRY
           for line, names in _name_comparisons(path.read_text(encoding="utf-8"))]
    assert not bad, "mechanism names compared outside the registry:\n  " + "\n  ".join(bad)


def test_the_name_check_sees_comparisons():
    src = ('if m == "I": pass\nif "FE" in x: pass\nif k in ("I", "II"): pass\n'
           'match m:\n    case "II": pass\nif m != "blocks": pass\nd = {"I": 1}\n'
           'for k in ["I", "FE"]: pass\nx = [k for k in ("II",)]\nfor c in "FE": pass\n')
    assert _name_comparisons(src) == [(1, "I"), (2, "FE"), (3, "I, II"), (5, "II"),
                                      (8, "FE, I"), (9, "II")]


def _private_imports(name: str, path: Path, modules: dict[str, Path]) -> list[str]:
    """``from X import _y`` where ``_y`` is a private name of another module X (importing a
    module whose file name starts with "_", such as ``_io``, is importing a module, allowed)."""
    is_pkg = path.name == "__init__.py"
    base = name.split(".") if is_pkg else name.split(".")[:-1]
    bad = []
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if not isinstance(node, ast.ImportFrom):
            continue
        if node.level:
            root = ".".join(base[:len(base) - node.level + 1])
            mod = f"{root}.{node.module}" if node.module else root
        else:
            mod = node.module or ""
        for a in node.names:
            private = a.name.startswith("_") and not a.name.startswith("__")
            if private and f"{mod}.{a.name}" not in modules and mod != name:
                bad.append(f"{name}:{node.lineno}: from {mod} import {a.name}")
    return bad


def test_no_module_imports_another_modules_private_name():
    mods = _modules()
    bad = [b for name, path in sorted(mods.items()) for b in _private_imports(name, path, mods)]
    assert not bad, "private names imported from another module:\n  " + "\n  ".join(bad)


def test_the_private_import_check_sees_one(tmp_path):
    mods = {"homlimit.app.a": tmp_path / "a.py", "homlimit.app._b": tmp_path / "_b.py"}
    mods["homlimit.app.a"].write_text("from .pipeline import _hinges\nfrom . import _b\n"
                                      "from .pipeline import run\nimport numpy._core\n")
    assert _private_imports("homlimit.app.a", mods["homlimit.app.a"], mods) == [
        "homlimit.app.a:1: from homlimit.app.pipeline import _hinges"]


APP_MAX_LINES = 400


def test_every_app_module_is_at_most_400_lines():
    """One concept per module in the app layer (issue 28): none longer than 400 lines."""
    long = {str(p.relative_to(PKG)): n for p in sorted((PKG / "app").rglob("*.py"))
            if (n := len(p.read_text(encoding="utf-8").splitlines())) > APP_MAX_LINES}
    assert not long, f"app/ modules over {APP_MAX_LINES} lines: {long}"


def _calls(source: str, name: str) -> list[int]:
    """Lines calling ``name`` (as a bare name or an attribute)."""
    return [node.lineno for node in ast.walk(ast.parse(source)) if isinstance(node, ast.Call)
            and getattr(node.func, "id", getattr(node.func, "attr", None)) == name]


def test_result_files_have_one_writer():
    """Every JSON, CSV and Parquet result file is written by ``app.writers.write`` (the output
    registry), which alone calls ``_io.write_output`` (issue 28: one writer per file)."""
    bad = [f"{name}:{line}" for name, path in sorted(_modules().items())
           if name not in ("homlimit._io", "homlimit.app.writers")
           for line in _calls(path.read_text(encoding="utf-8"), "write_output")]
    assert not bad, "write_output called outside app.writers:\n  " + "\n  ".join(bad)


def test_frozen_fields_are_set_through_one_helper():
    """A ``__post_init__`` stores what it checked or converted through ``fields.set_fields``
    (issue 28: one idiom), the one caller of ``object.__setattr__``."""
    bad = [f"{name}:{node.lineno}" for name, path in sorted(_modules().items())
           if name != "homlimit.fields"
           for node in ast.walk(ast.parse(path.read_text(encoding="utf-8")))
           if isinstance(node, ast.Attribute) and node.attr == "__setattr__"
           and getattr(node.value, "id", None) == "object"]
    assert not bad, "object.__setattr__ outside fields.set_fields:\n  " + "\n  ".join(bad)


def test_the_suite_runs_one_blas_thread_as_the_engines_workers():
    # the engine tests compare results made here with the workers' bit for bit; OpenBLAS's
    # sums depend on its thread count, so conftest sets the workers' BLAS_ENV before numpy
    # loads (measured: B1's h = 0.3 m part, v̄_g ...7734 with two threads, ...7736 with one)
    import os

    import conftest

    from homlimit.app.engine import BLAS_ENV

    assert not conftest._NUMPY_EARLY
    assert all(os.environ.get(k) == v for k, v in BLAS_ENV.items())
