"""docs/case-file.md's key reference, generated from the schema (``schema_markdown``), and
its writer ``update_case_file_doc``, which replaces the tables under "## Keys" with the
schema's (the tests check that the page holds them)::

  python -c "from homlimit.app import schema_doc as d; d.update_case_file_doc('docs/case-file.md')"
"""

from __future__ import annotations

from pathlib import Path

from .._io import write_text
from .schema import ARRAYS, OPTIONAL_SECTIONS, REQUIRED_SECTIONS, SCHEMA, TOP_LEVEL

__all__ = ["schema_markdown", "toml_value", "update_case_file_doc"]

#: the generated part of docs/case-file.md lies between these two lines
DOC_START = "that this page lists exactly that.\n"
DOC_END = "## Output files"


def schema_markdown() -> str:
    """The key reference of docs/case-file.md, generated from SCHEMA (one table per section)."""
    lines = []
    for sec, keys in ([("(top level)", TOP_LEVEL)] + [(f"[{s}]", k) for s, k in SCHEMA.items()]
                      + [(f"[[{a}]] (array of tables; a sweep's {a}.0.z)", k)
                         for a, k in ARRAYS.items()]):
        req = (" (required section)" if sec.strip("[]") in REQUIRED_SECTIONS else
               " (optional section: absent, no code check; its required keys are required "
               "when it is given; docs/code-check.md)" if sec.strip("[]") in OPTIONAL_SECTIONS
               else "")
        lines += [f"### {sec}{req}", "",
                  "| key | type | default | unit | allowed | typical | meaning |",
                  "|---|---|---|---|---|---|---|"]
        for name, key in keys.items():
            default = "**required**" if key.required else f"`{toml_value(key.default)}`"
            kind = key.kind.__name__ + (f" of {key.item.__name__}" if key.item else "")
            typical = f"{key.typical[0]:g} .. {key.typical[1]:g}" if key.typical else "–"
            lines.append(f"| `{name}` | {kind} | {default} | {key.unit or '–'} | "
                         f"{key.range_text(name) or 'any'} | {typical} | {key.doc} |")
        lines.append("")
    return "\n".join(lines)


def toml_value(v) -> str:
    if isinstance(v, list | tuple):
        return "[" + ", ".join(toml_value(x) for x in v) + "]"
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, str):
        return f'"{v}"'
    return f"{v:g}" if isinstance(v, float) else str(v)


def update_case_file_doc(path: str | Path) -> bool:
    """Rewrite the key tables of docs/case-file.md at ``path`` from the schema; whether the
    page changed."""
    path = Path(path)
    text = path.read_text(encoding="utf-8")
    head, sep, rest = text.partition(DOC_START)
    _, sep2, tail = rest.partition(DOC_END)
    if not (sep and sep2):
        raise ValueError(f"{path}: no generated part between {DOC_START!r} and {DOC_END!r}")
    new = f"{head}{DOC_START}\n{schema_markdown()}\n{DOC_END}{tail}"
    if new != text:
        write_text(path, new)
    return new != text

