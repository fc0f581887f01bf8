"""The checks of a case's values: each key's type, range and choices (``check_key``, from
its ``schema.Key``), every section at once (``collect``), the checks between keys
(``cross_checks``: blocks that fit the wall, a mesh that fits the wall and the problem-size
budget, ties and floors on the wall) and the warnings of valid but implausible values. Each
returns problem lines; ``app.config`` raises them as one ConfigError.
"""

from __future__ import annotations

import dataclasses
import math
import unicodedata
from typing import Any

from ..closed_form.real import fc_problem
from ..params import MESHER_DEFAULT, PART_DIVISIONS, Case, opening_problems
from . import budget, registry
from .case_openings import openings_refused
from .schema import ARRAYS, MAX_ARRAY, OPTIONAL_SECTIONS, REQUIRED_SECTIONS, SCHEMA, TOP_LEVEL, Key

__all__ = ["LAM_MIN_CLOSED", "MAX_NAME", "Overflow", "array_key", "check_key", "collect",
           "crushing", "cross_checks", "range_problem", "shown", "toml_float", "warnings_of"]

#: the closed forms search the critical slenderness over LAM_MIN_CLOSED <= λ <= λ_max
#: (``closed_form.mechanisms._minimise``'s lam_min); a wall with H/b below it has no part to try
LAM_MIN_CLOSED = 0.5
MAX_NAME = 100                    # characters of a case name


class Overflow(float):
    """A number written beyond the largest float (1e400 reads as inf), keeping its text for
    the messages: ``[wall] H = 1e400 (beyond the largest float, about 1.8e308) m``."""

    text: str

    def __new__(cls, text: str):
        obj = super().__new__(cls, text)
        obj.text = text
        return obj

    def __repr__(self) -> str:
        return f"{self.text} (beyond the largest float, about 1.8e308)"


def toml_float(text: str) -> float:
    """A TOML float (``tomllib``'s parse_float): an ``Overflow`` where finite digits overflow."""
    x = float(text)
    return Overflow(text) if math.isinf(x) and "inf" not in text.lower() else x


def typed(kind: type, value) -> tuple[bool, Any]:
    """(ok, converted) for TOML values: ints are accepted for floats, bools are never numbers."""
    if isinstance(value, bool):
        return kind is bool, value
    if kind is float and isinstance(value, int | float):
        return True, value if isinstance(value, int | Overflow) else float(value)
    return isinstance(value, kind), value


TYPE_NAMES = {float: "a number", int: "an integer", bool: "true or false", str: "a string",
               list: "a list"}


def shown(value) -> str:
    """A value as a message shows it (repr): huge integers and long texts shortened (every
    message about an input, the sweep's too)."""
    if isinstance(value, int) and not isinstance(value, bool) and abs(value) > 10 ** 30:
        digits = len(str(abs(value)))
        return f"{str(value)[:8]}...({digits} digits)"
    text = repr(value)
    return text if len(text) <= 60 else f"{text[:50]}... ({len(text)} characters)"


def range_problem(where: str, name: str, key: Key, value) -> str | None:
    """The out-of-range line of a number (its unit and the allowed range with units)."""
    x = float(value) if abs(value) < 1e308 else (math.inf if value > 0 else -math.inf)
    if key.range.holds(x):
        return None
    u = f" {key.unit}" if key.unit else ""
    return (f"{where} {name} = {shown(value)}{u} is out of range: allowed "
            f"{key.range_text(name)}{u}")


def check_key(where: str, name: str, key: Key, value, problems: list[str]):
    """Append a problem for a wrong type or an out-of-range value; return the converted value
    (a list: every item checked against the key's type, range and choices)."""
    if key.kind is list:
        if not isinstance(value, list) or not value:
            problems.append(f"{where} {name} = {shown(value)} has the wrong type: expected "
                            f"a non-empty list, each item {TYPE_NAMES[key.item]}")
            return None
        item = dataclasses.replace(key, kind=key.item, item=None)
        n = len(problems)
        out = [check_key(where, f"{name}[{k}]", item, v, problems) for k, v in enumerate(value)]
        return out if len(problems) == n else None
    ok, value = typed(key.kind, value)
    if not ok:
        problems.append(f"{where} {name} = {shown(value)} has the wrong type: expected "
                        f"{TYPE_NAMES[key.kind]}")
        return None
    if key.choices and value not in key.choices:
        problems.append(f"{where} {name} = {shown(value)} is not allowed: allowed "
                        f"{key.range_text(name)}")
        return None
    if key.kind is str and any(unicodedata.category(ch) == "Cc" for ch in value):
        problems.append(f"{where} {name} = {shown(value)} contains control characters (a NUL "
                        "byte, a newline, an escape, ...): allowed printable text")
        return None
    if key.kind in (float, int):
        bad = range_problem(where, name, key, value)
        if bad:
            problems.append(bad)
            return None
        return float(value) if key.kind is float else value
    return value


def collect(data: dict, problems: list[str]) -> dict[str, dict[str, Any]]:
    """The valid values of every section (defaults filled in); a problem for each bad one.
    A key missing from the result was reported (or its section was)."""
    values: dict[str, dict[str, Any]] = {}
    for top, v in data.items():
        if top in ARRAYS:
            values[top] = collect_array(top, v, problems)
        elif top in SCHEMA:
            if not isinstance(v, dict):
                problems.append(f"[{top}] must be a section (table), got {shown(v)}")
        elif top in TOP_LEVEL:
            out = check_key("", top, TOP_LEVEL[top], v, problems)
            if isinstance(out, str) and len(out) > MAX_NAME:
                problems.append(f"name = {out[:20]!r}... ({len(out)} characters) is out of "
                                f"range: allowed at most {MAX_NAME} characters")
        else:
            allowed = ", ".join([f"[{s}]" for s in SCHEMA] + [f"[[{a}]]" for a in ARRAYS]
                                + list(TOP_LEVEL))
            problems.append(f"unknown {'section' if isinstance(v, dict) else 'key'} "
                            f"{str(top)[:40]!r}: allowed {allowed}")
    for sec, keys in SCHEMA.items():
        given = data.get(sec, {})
        if not isinstance(given, dict):
            continue  # already reported above
        if sec in OPTIONAL_SECTIONS and sec not in data:
            continue        # absent: no [site], no code check
        vals = values.setdefault(sec, {})
        if sec in REQUIRED_SECTIONS and sec not in data:
            problems.append(f"[{sec}] section is missing: required keys "
                            + ", ".join(k for k, key in keys.items() if key.required))
            continue
        vals.update(_table(f"[{sec}]", keys, given, problems))
    return values


def _table(where: str, keys: dict[str, Key], given: dict, problems: list[str]) -> dict:
    """The valid values of one table (a section, or an entry of an array), defaults filled
    in; a problem for each unknown, bad or missing required key, named ``where``."""
    vals = {}
    for name, v in given.items():
        if name not in keys:
            problems.append(f"{where} unknown key {str(name)[:40]!r}: allowed "
                            + ", ".join(keys))
            continue
        out = check_key(where, name, keys[name], v, problems)
        if out is not None:
            vals[name] = out
    for name, key in keys.items():
        if name in given:
            continue
        if key.required:
            u = f" {key.unit}" if key.unit else ""
            problems.append(f"{where} {name} is missing ({key.doc}, {key.unit or '-'}; "
                            f"allowed {key.range_text(name)}{u})")
        else:
            vals[name] = key.default
    return vals


def collect_array(name: str, given, problems: list[str]) -> list[dict]:
    """The valid entries of a [[tie]] or [[floor]] array (defaults filled in); a problem for
    each bad one, named "[[tie]] 0 yield_force" (entry 0, as a sweep's tie.0.yield_force)."""
    if not isinstance(given, list) or not all(isinstance(e, dict) for e in given):
        problems.append(f"[[{name}]] = {shown(given)} has the wrong type: expected an array "
                        f"of tables ([[{name}]] entries)")
        return []
    if len(given) > MAX_ARRAY:
        problems.append(f"[[{name}]] has {len(given)} entries: allowed at most {MAX_ARRAY}")
        return []
    keys, out = ARRAYS[name], []
    for k, entry in enumerate(given):
        n = len(problems)
        vals = _table(f"[[{name}]] {k}", keys, entry, problems)
        if len(problems) == n:
            out.append(vals)
    return out


def array_key(key: str) -> bool:
    """Whether ``key`` names a key of a [[tie]]/[[floor]] entry, as tie.0.yield_force."""
    arr, _, rest = str(key).partition(".")
    idx, dot, name = rest.partition(".")
    return arr in ARRAYS and idx.isdigit() and int(idx) < MAX_ARRAY and bool(dot) \
        and name in ARRAYS[arr]


def real_wall_checks(v: dict[str, Any]) -> list[str]:
    """Ties and floors on the wall (0 < z <= H, 0 <= eccentricity <= b), and the real-wall
    inputs refused by the models and checks that do not take them (docs/real-walls.md)."""
    w, m, an = (v.get(k, {}) for k in ("wall", "masonry", "analysis"))
    out = []
    for arr in ("tie", "floor"):
        for k, e in enumerate(v.get(arr) or ()):
            if "H" in w and "z" in e and e["z"] > w["H"]:
                out.append(f"[[{arr}]] {k} z = {e['z']!r} m is out of range: allowed "
                           f"0 < z <= H = {w['H']:g} m")
            if "b" in w and "eccentricity" in e and e["eccentricity"] > w["b"]:
                out.append(f"[[{arr}]] {k} eccentricity = {e['eccentricity']!r} m is out of "
                           f"range: allowed 0 <= eccentricity <= b = {w['b']:g} m")
    if all(k in w for k in ("H", "b", "L")):
        out += opening_problems(w["H"], w["b"], w["L"], v.get("facade_opening") or (),
                                v.get("wall_opening") or ())
    closed = an.get("closed_form") or an.get("overturning")
    held = [(k, e["z"]) for k, e in enumerate(v.get("floor") or ())
            if e.get("restrains") and "z" in e]
    if closed and held and "H" in w and "b" in w:
        k, zr = max(held, key=lambda p: p[1])
        if (w["H"] - zr) / w["b"] < LAM_MIN_CLOSED:
            out.append(f"[[floor]] {k} z = {zr!r} m with restrains = true leaves the closed "
                       f"forms a failing body of (H − z)/b = {(w['H'] - zr) / w['b']:.4g}: out "
                       f"of range: allowed z <= H − {LAM_MIN_CLOSED:g} b = "
                       f"{w['H'] - LAM_MIN_CLOSED * w['b']:g} m (the body lies above it)")
    out += openings_refused(v, an)
    keys = [f"[masonry] {k} = {m[k]!r} Pa" for k in ("fc", "cohesion", "tension") if m.get(k)]
    keys += [f"[[{arr}]] ({len(v[arr])} entries)"
             for arr in ("tie", "floor", "facade_opening", "wall_opening") if v.get(arr)]
    if not keys:
        return out
    given = ", ".join(keys)
    # the FE path takes fc, ties, floors, cohesion and tension (both bounds, the mechanism);
    # with a cohesion its impulse scan's v̄_g is "not available" (mechanism.fe_impulse.
    # bond_reason: a bond's dissipation at finite rotation needs a softening rule)
    dem_no = [f"[masonry] {k} = {m[k]!r} Pa" for k in ("cohesion", "tension") if m.get(k)]
    if an.get("dem") and dem_no:      # the DEM takes fc, ties and floors, not these
        out.append(f"[analysis] dem = true: the DEM does not take {', '.join(dem_no)} yet "
                   "(its joints are no-tension Coulomb contacts); allowed 0 Pa with "
                   "[analysis] dem = true (docs/real-walls.md)")
    # the blocks' LA takes fc, ties, floors, cohesion and tension (associative friction
    # only); with cohesion or tension their v̄_g is "not available" (blocks.impulse.no_bond)
    if an.get("blocks"):
        bl = v.get("blocks", {})
        if bl.get("friction") == "non-associative" or bl.get("non_associative_check"):
            out.append(f"[blocks] friction = non-associative (or non_associative_check) with "
                       f"{given}: the non-associative scheme does not take them; allowed "
                       "friction = \"associative\", non_associative_check = false "
                       "(docs/real-walls.md)")
    if an.get("hinge_check"):   # every rocker (the FE body's too) takes fc, ties, floors
        held = [f"[masonry] {k} = {m[k]!r} Pa" for k in ("cohesion", "tension") if m.get(k)]
        if held:
            out.append(f"[analysis] hinge_check = true: the hinge check's rockers do not take "
                       f"{', '.join(held)} yet (they take fc, ties and floors); allowed "
                       "[analysis] hinge_check = false with these inputs (docs/real-walls.md)")
    for k in ("cohesion", "tension"):
        if m.get(k) and (an.get("closed_form") or an.get("overturning")):
            out.append(f"[masonry] {k} = {m[k]!r} Pa: the closed forms (mechanisms I, II, "
                       "overturning) do not take a joint " + k + " (no clean derivation "
                       "yet); allowed 0 Pa (docs/real-walls.md)")
    return out


def cross_checks(v: dict[str, dict[str, Any]], *, mesh_only: bool = False) -> list[str]:
    """The checks between keys, each run when the keys it needs are valid (so they are
    reported together with the field problems). ``mesh_only``: the checks of the mesh of the
    whole wall (the ``mesh`` command), whatever [analysis] says."""
    w, m, me, an = (v.get(k, {}) for k in ("wall", "masonry", "mesh", "analysis"))
    has = lambda d, *ks: all(k in d for k in ks)  # noqa: E731
    out = [] if mesh_only else real_wall_checks(v)
    st = v.get("site", {})
    if (not mesh_only and has(w, "H") and has(st, "building_height", "z_base")
            and 0 < st["building_height"] < st["z_base"] + w["H"] * (1 - 1e-12)):
        out.append(f"[site] building_height = {st['building_height']!r} m is out of range: "
                   f"allowed 0 (the wall's top) or building_height >= z_base + H = "
                   f"{st['z_base'] + w['H']:g} m (the wall within the building)")
    if not mesh_only and has(w, "H") and has(m, "a") and m["a"] > w["H"]:
        out.append(f"[masonry] a = {m['a']!r} m is out of range: a block must not be taller "
                   f"than the wall, allowed 0.001 <= a <= H = {w['H']:g} m")
    if not mesh_only and has(w, "L") and has(m, "c") and 2 * m["c"] > w["L"]:
        out.append(f"[masonry] c = {m['c']!r} m is out of range: a block must fit the "
                   f"transversal wall, allowed 0.001 <= 2c <= L = {w['L']:g} m")
    if (not mesh_only and an.get("closed_form") is False and an.get("fe") is False
            and not an.get("overturning") and not an.get("blocks")):
        out.append("[analysis] closed_form = false and fe = false: nothing to compute; allowed "
                   "at least one of them true (or overturning, blocks)")
    closed = not mesh_only and an.get("closed_form", False)
    if closed and has(w, "H", "b") and w["H"] / w["b"] < LAM_MIN_CLOSED:
        out.append(f"[wall] H = {w['H']!r} m, b = {w['b']!r} m: H/b = {w['H'] / w['b']:.4g} is "
                   f"out of range: allowed H/b >= {LAM_MIN_CLOSED:g} (the closed forms search "
                   f"the critical slenderness λ = h/b over {LAM_MIN_CLOSED:g} <= λ <= H/b; a "
                   "façade this squat does not overturn)")
    if closed and has(w, "L", "b") and has(m, "a", "c", "f") and has(an, "tanpsi"):
        t = an["tanpsi"] or math.sqrt(m["c"] * m["f"] / m["a"])
        what = ("[analysis] tanpsi" if an["tanpsi"] else "tan ψ = √(cf/a) ([masonry] a, c, f)")
        if w["L"] / (w["b"] * t) < LAM_MIN_CLOSED:
            out.append(f"[wall] L = {w['L']!r} m, b = {w['b']!r} m and {what} = {t:.4g}: "
                       f"L/(b tan ψ) = {w['L'] / (w['b'] * t):.4g} is out of range: allowed "
                       f"L/(b tan ψ) >= {LAM_MIN_CLOSED:g} (mechanism II's wedge must fit the "
                       f"transversal wall at λ = {LAM_MIN_CLOSED:g}: λ tan ψ <= L/b)")
    for model in ("blocks", "dem"):   # the block models' assembly size
        lim = v.get(model, {})
        if (not mesh_only and an.get(model) and has(w, "H", "L") and has(m, "a", "c")
                and has(lim, "max_blocks")):
            n = math.ceil(w["H"] / m["a"]) * (math.ceil(w["L"] / (2 * m["c"])) + 1)
            if n > lim["max_blocks"]:
                out.append(f"[analysis] {model} = true needs about {n} blocks ((H/a)(L/2c + "
                           f"1)): out of range: allowed up to [{model}] max_blocks = "
                           f"{lim['max_blocks']} (larger blocks a, c, or raise max_blocks)")
    dem = v.get("dem", {})
    if not mesh_only and has(dem, "loading", "record"):    # the accelerogram and its file
        if dem["loading"] == "record" and not dem["record"]:
            out.append("[dem] loading = 'record' needs [dem] record: out of range: allowed a "
                       "two-column CSV t [s], a_g [m/s^2] (relative to the case file)")
        elif dem["record"] and dem["loading"] != "record":
            out.append(f"[dem] record = {dem['record']!r} is used only with loading = "
                       f"'record': out of range with loading = {dem['loading']!r}: allowed "
                       "loading = 'record', or record = '' (none)")
    pulse_fe = registry.needs_mesh(v.get("pulse", {}).get("mechanisms") or ())  # FE for `pulse`
    fe = mesh_only or an.get("fe", False) or pulse_fe
    if not (fe and has(me, "size", "max_triangles") and has(w, "H", "b", "L")):
        return out
    size = me["size"]
    span = min(w["H"], w["b"] + w["L"])
    if size > span:
        out.append(f"[mesh] size = {size!r} m is out of range: "
                   f"allowed 0 < size <= min(H, b + L) = {span:g} m")
        return out
    # the impulse scan's parts run from one course (a) to H, each meshed at
    # min(size, h/part_divisions)
    parts = (m["a"] / w["b"],) if not mesh_only and has(m, "a") else ()
    n = budget.fe_triangles(w["H"], w["b"], w["L"], size, parts,
                            mesher=me.get("mesher", MESHER_DEFAULT),
                            divisions=me.get("part_divisions", PART_DIVISIONS),
                            outer_ratio=me.get("outer_ratio", 0.0)
                            if an.get("static", False) else 0.0)
    whole = budget.fe_triangles(w["H"], w["b"], w["L"], size)
    if n > me["max_triangles"] and whole <= me["max_triangles"] and "part_divisions" in me:
        # the whole wall fits: the shortest part of the scan, meshed at a/part_divisions
        pd, spec = me["part_divisions"], SCHEMA["mesh"]["part_divisions"]
        out.append(f"[mesh] part_divisions = {pd} gives about {n:.3g} triangles in the "
                   f"shortest part of the FE impulse scan (one course a = {m['a']:g} m meshed "
                   f"at a/part_divisions = {m['a'] / pd:.3g} m; about "
                   f"{budget.memory_gib(n):.3g} GiB): out of range: allowed at most [mesh] "
                   f"max_triangles = {me['max_triangles']:,}; lower [mesh] part_divisions "
                   f"(allowed {spec.range_text('part_divisions')}, default {spec.default}) or, "
                   "on a machine with the memory, raise [mesh] max_triangles")
    elif n > me["max_triangles"]:
        keys = "[mesh] size" + ("" if mesh_only else " (or [analysis] fe = false)")
        out.append(f"[mesh] size = {size!r} m gives about {n:.3g} triangles in the largest FE "
                   f"problem (estimated from H, b, L before meshing; about "
                   f"{budget.memory_gib(n):.3g} GiB): out of range: allowed at most "
                   f"[mesh] max_triangles = {me['max_triangles']:,}; raise {keys} or, on a "
                   "machine with the memory, [mesh] max_triangles")
    return out


def crushing(case: Case, analysis: dict) -> list[str]:
    """A finite [masonry] fc under which every part of a closed form the case runs crushes at
    its hinge (``closed_form.real.fc_problem``: a bound of the wall), checked on the built
    ``Case`` before any work (the FE path included)."""
    kinds = (("detachment", "crack") if analysis.get("closed_form") else ()) \
        + (("overturning",) if analysis.get("overturning") else ())
    bad = fc_problem(case, kinds, analysis.get("tanpsi") or None) if kinds else None
    return [bad] if bad else []


def warnings_of(case: Case, values: dict) -> tuple[str, ...]:
    """Valid values outside the typical range of masonry walls (each a line)."""
    out = []
    for sec in ("wall", "masonry"):
        for name, key in SCHEMA[sec].items():
            x = values[sec][name]
            if key.typical and not key.typical[0] <= x <= key.typical[1]:
                u = f" {key.unit}" if key.unit else ""
                out.append(f"[{sec}] {name} = {x:g}{u} is outside the typical range of masonry "
                           f"walls {key.typical[0]:g} .. {key.typical[1]:g}{u} ({key.doc}): "
                           "a valid input, check it")
    for what, x, lo, hi in (("ρ = l/s", case.rho, 1.0, 50.0),
                            ("H/b (slenderness of the whole façade)", case.wall.lam_max, 2.0,
                             60.0),
                            ("c/a (block proportion)", case.masonry.c / case.masonry.a, 0.25,
                             5.0)):
        if not lo <= x <= hi:
            out.append(f"{what} = {x:.4g} is outside the typical range {lo:g} .. {hi:g}: a "
                       "valid input, check it")
    return tuple(out)

