"""The one-page report of a run (``[output] report = true``): report.html, one self-contained
file (the run's PNG pictures embedded as base64 data URIs, no script, no external link) with
the inputs and their units, the pictures, each mechanism's multipliers and collapse
velocities, the code check (NTC 2018 / Circolare 2019 §C8.7.1.2, both e* readings; the
floors' Q_k reading and the nonlinear check at the ground beside it) and the package version.
Built from ``Result.to_dict()`` (summary.json's numbers) with the standard library's
``html.escape`` only; written by ``writers.write`` (whole or nothing), after the
pictures and before summary.json (``outputs.write_result``). docs/report.md."""

from __future__ import annotations

import base64
import math
from html import escape
from pathlib import Path

from . import registry
from .schema import ARRAYS, SCHEMA

__all__ = ["PICTURES", "page"]

#: the pictures a run may write, in the report's order, with their captions
PICTURES = {
    "vg_lambda.png": "collapse velocity v̄_g against λ = h/b (closed forms, FE scan)",
    "mechanism.png": "FE collapse mechanism of the whole wall (velocity, crack)",
    "stress.png": "FE static bound: the stress field",
    "adapt.png": "FE bracket: the bounds against the mesh",
    "mesh.png": "FE mesh of the T-section",
    "blocks_mechanism.png": "rigid blocks: the critical mechanism",
    "blocks_whole.png": "rigid blocks: the whole wall's mechanism",
    "dem_snapshots.png": "DEM: the lowest collapsing trial",
}

#: the input sections shown, and when (a model's own section only when it runs)
_SHOWN = ("wall", "masonry", "tie", "floor", "facade_opening", "wall_opening", "site")
_WHEN = {"mesh": "fe", "adapt": "fe", "blocks": "blocks", "dem": "dem"}

_STYLE = """body{font:13px/1.35 sans-serif;max-width:1100px;margin:1em auto;color:#111}
h1{font-size:20px;margin:0 0 .2em}h2{font-size:15px;margin:1em 0 .3em;border-bottom:1px solid #999}
table{border-collapse:collapse;margin:.2em 0}td,th{border:1px solid #bbb;padding:1px 6px}
th{background:#eee}td.n{text-align:right;font-variant-numeric:tabular-nums}
.inputs{display:flex;flex-wrap:wrap;gap:10px;align-items:flex-start}
figure{display:inline-block;margin:4px;width:48%}figure img{width:100%}
figcaption{font-size:11px;color:#444}p.note{font-size:11px;color:#444;margin:.2em 0}
.no{color:#b00;font-weight:bold}"""


def _num(x, digits: int = 4) -> str:
    """A number as the tables show it (``digits`` significant digits), – for none."""
    if x is None or isinstance(x, bool):
        return "–" if x is None else ("yes" if x else "no")
    if isinstance(x, (int, float)):
        if not math.isfinite(x):
            return "–"
        if isinstance(x, int):
            return str(x)
        if x == 0 or 1e-3 <= abs(x) < 10 ** max(digits, 6):
            return f"{x:.{digits}f}".rstrip("0").rstrip(".") if x.is_integer() else \
                f"{x:.{digits}g}"
        return f"{x:.3e}"
    return escape(str(x))


def _cell(x, key: str = "", digits: int = 4) -> str:
    """A table cell: numbers right-aligned to ``digits`` significant digits with their full
    value (15 significant digits, summary.json's) in ``data-value``, and the quantity's name
    in ``data-key``."""
    if isinstance(x, float) and math.isfinite(x):
        return (f'<td class="n" data-key="{escape(key)}" data-value="{x:.15g}">'
                f"{_num(x, digits)}</td>")
    if isinstance(x, int) and not isinstance(x, bool):
        return f'<td class="n">{x}</td>'
    return f"<td>{_num(x)}</td>"


def _table(header: list[str], rows: list[list[str]], cls: str = "") -> str:
    head = "".join(f"<th>{escape(h)}</th>" for h in header)
    body = "".join("<tr>" + "".join(r) + "</tr>" for r in rows)
    return f'<table class="{cls}"><tr>{head}</tr>{body}</table>'


def _unit(key) -> str:
    return key.unit or ("–" if float in (key.kind, key.item) or int in (key.kind, key.item)
                        else "")


def _head(name: str, key) -> str:
    return f"{name} [{_unit(key)}]" if _unit(key) else name


def _inputs(inputs: dict) -> str:
    """One small table per input section: key, value, unit (the schema's)."""
    analysis = inputs.get("analysis", {})
    sections = [s for s in _SHOWN] + [s for s, on in _WHEN.items() if analysis.get(on)]
    out = []
    for sec in sections:
        value = inputs.get(sec)
        if not value:
            continue
        if sec in ARRAYS:
            keys = ARRAYS[sec]
            header = ["#"] + [_head(k, keys[k]) for k in keys]
            rows = [[f"<td>{i}</td>"] + [_cell(e.get(k), f"{sec}.{i}.{k}", 10) for k in keys]
                    for i, e in enumerate(value)]
            out.append(f"<div><b>[[{sec}]]</b>{_table(header, rows)}</div>")
            continue
        keys = SCHEMA[sec]
        rows = [[f"<td>{escape(k)}</td>", _cell(v, f"{sec}.{k}", 10),
                 f"<td>{escape(_unit(keys[k]))}</td>"]
                for k, v in value.items() if k in keys and not isinstance(v, (list, dict))]
        out.append(f"<div><b>[{sec}]</b>{_table(['key', 'value', 'unit'], rows)}</div>")
    on = ", ".join(k for k in ("closed_form", "overturning", "fe", "static", "blocks", "dem")
                   if analysis.get(k))
    return (f'<div class="inputs">{"".join(out)}</div>'
            f'<p class="note">models run ([analysis]): {escape(on or "none")}</p>')


def _mechanisms(d: dict, labels: dict) -> str:
    """Each mechanism's λ = h/b, h, static multiplier a/g, v̄_g and v̄_g/√(gb); the FE bracket
    and the DEM's threshold beside them."""
    rows = []
    for k, m in d["mechanisms"].items():
        entry = next((e for e in registry.mechanisms() if e.name == k), None)
        smallest = entry is not None and entry.static     # a/g smallest over h, else at h
        mult = _cell(m.get("multiplier"), f"{k}.multiplier")
        if m.get("multiplier") is not None and not smallest:
            mult = mult.replace("</td>", " (at h)</td>")
        rows.append([f"<td>{escape(k)}</td>", f"<td>{escape(labels.get(k, k))}</td>",
                     _cell(m.get("lam"), f"{k}.lam"), _cell(m.get("h"), f"{k}.h"),
                     mult, _cell(m.get("vg"), f"{k}.vg"),
                     _cell(m.get("vnorm"), f"{k}.vnorm")])
    dem = d.get("dem")
    if dem:
        rows.append(["<td>DEM</td>", f"<td>homlimit.dem, {escape(dem['loading'])}"
                     f" (bisection ±{100 * dem['rel_tol']:g} %)</td>",
                     _cell(dem.get("lam"), "dem.lam"), _cell(dem.get("h"), "dem.h"),
                     "<td>–</td>", _cell(dem.get("pgv"), "dem.pgv"),
                     _cell(dem.get("vnorm"), "dem.vnorm")])
    out = _table(["mechanism", "model", "λ = h/b [–]", "h [m]", "static a/g [–]",
                  "v̄_g [m/s]", "v̄_g/√(gb) [–]"], rows)
    fe = d.get("fe")
    if fe and fe.get("lower_bound") is not None:
        out += (f'<p class="note">FE bracket of the whole wall: static λ⁻ = '
                f'{_num(fe["lower_bound"])} ≤ a/g ≤ kinematic λ⁺ = {_num(fe["multiplier"])} '
                f'(gap {_num(100 * fe["bracket_rel_gap"], 3)} %, {fe["n_triangles"]} '
                "triangles)</p>")
    crit = d.get("critical")
    if crit:
        out += (f'<p class="note">governing (lowest v̄_g): {escape(crit["mechanism"])}, '
                f'v̄_g = {_num(crit["vg"])} m/s. λ, h, v̄_g: the impulse criterion (eq. 7) at '
                "the height of the smallest v̄_g; static a/g: the closed forms' smallest over "
                "the height (the static check's), the FE's and blocks' of the body at that h "
                "(\"at h\"; the whole wall's is the code check's α₀).</p>")
    return out


def _code_check(cc: dict | None, has_floors: bool = False) -> str:
    if cc is None:
        return ('<p class="note">none: the case has no [site] section '
                "(docs/code-check.md)</p>")
    s = cc["site"]
    rows = []
    for k, c in cc["mechanisms"].items():
        rows.append([f"<td>{escape(k)}</td>"] + [
            _cell(c[q], f"code_check.{k}.{q}") for q in
            ("alpha0", "e_star", "a0_star", "Z", "demand_ground", "demand_height", "demand",
             "ratio", "a0_star_lumped", "ratio_lumped")] + [_met(c["passes"])])
    out = (f'<p class="note">site: S = {_num(s["S"])} (S_S = {_num(s["S_S"])}, S_T = '
           f'{_num(s["S_T"])}), T_B, T_C, T_D = {_num(s["T_B"], 3)}, {_num(s["T_C"], 3)}, '
           f'{_num(s["T_D"], 3)} s; building H = {_num(s["H_building"])} m, T₁ = '
           f'{_num(s["first_period"], 3)} s, S_e(T₁) = {_num(s["Se_T1"])} m/s²</p>')
    out += _table(["mechanism", "α₀ [–]", "e* [–]", "a₀* [m/s²]", "Z [m]",
                   "ground a_g S/q [m/s²]", "at height [m/s²]", "demand [m/s²]",
                   "ratio a₀*/demand [–]", "a₀* (e* = 1) [m/s²]", "ratio (e* = 1) [–]",
                   "met"], rows)
    out += "".join(f'<p class="note">not checked: {escape(n["mechanism"])} '
                   f'({escape(n["reason"])})</p>' for n in cc["not_checked"])
    impulse = cc.get("impulse")          # the impulse view beside it, where the run has it
    if impulse and s.get("pgv") is not None:
        out += (f'<p class="note">beside it, the impulse view: the site\'s PGV = '
                f'{_num(s["pgv"])} m/s against each mechanism\'s v̄_g</p>')
        out += _table(["mechanism", "v̄_g [m/s]", "v̄_g/PGV [–]"], [
            [f"<td>{escape(k)}</td>", _cell(v["vg"], f"impulse.{k}.vg"),
             _cell(v["vg_over_pgv"], f"impulse.{k}.vg_over_pgv")]
            for k, v in impulse.items()])
    if cc["governing"] is not None:
        out += (f'<p class="note">governing in the code check: {escape(cc["governing"])}, '
                f'ratio {_num(cc["ratio"])}</p>')
    out += _floors(cc, has_floors) + _nonlinear(cc)
    out += "".join(f'<p class="note">{escape(k.replace("_reading", ""))}: {escape(v)}</p>'
                   for k, v in cc["reading"].items())
    return out


def _skipped(rows: list[dict], what: str) -> str:
    """One note per reason for the mechanisms ``what`` was not computed for (the same reason
    once, its mechanisms listed)."""
    by_reason: dict[str, list[str]] = {}
    for r in rows:
        by_reason.setdefault(r["reason"], []).append(r["mechanism"])
    return "".join(f'<p class="note">{escape(what)} not computed for {escape(", ".join(ks))}: '
                   f"{escape(why)}</p>" for why, ks in by_reason.items())


def _met(passes: bool) -> str:
    return "<td>yes</td>" if passes else '<td><span class="no">NO</span></td>'


def _floors(cc: dict, has_floors: bool) -> str:
    """The floors' Q_k reading beside the used check (``code_check.floors_Qk``; docs/
    code-check.md, reading 3): a small table where the case has floors, else one line."""
    fq = cc.get("floors_Qk")
    title = "the floors' Q_k reading (Circolare 2019 transcription, C8.7.1.1/.5)"
    if fq is None:
        return ""
    if not has_floors:
        return f'<p class="note">{title}: the case has no floors, the readings coincide</p>'
    rows = [[f"<td>{escape(k)}</td>"]
            + [_cell(c[q], f"code_check.floors_Qk.{k}.{q}", 5 if q == "m_floors" else 4)
               for q in ("alpha0", "m_floors", "e_star", "a0_star", "Z", "demand", "ratio")]
            + [_cell(cc["mechanisms"][k]["ratio"], f"code_check.{k}.ratio"), _met(c["passes"])]
            for k, c in fq["mechanisms"].items()]
    out = (f'<p class="note">beside it, {title}: the floors\' weights pushed horizontally in '
           "α₀ and summed in M*, e*, at that reading's smallest a/g over h</p>")
    if rows:
        out += _table(["mechanism", "α₀ [–]", "floors [kg]", "e* [–]", "a₀* [m/s²]", "Z [m]",
                       "demand [m/s²]", "ratio [–]", "ratio used [–]", "met"], rows)
    out += _skipped(fq["not_computed"], "floors' reading")
    if fq["governing"] is not None:
        out += (f'<p class="note">governing in the floors\' reading: '
                f'{escape(fq["governing"])}, ratio {_num(fq["ratio"])}</p>')
    return out


def _nonlinear(cc: dict) -> str:
    """The nonlinear kinematic check at the ground (``code_check.nonlinear``): d_u*,
    S_De(T_s), the ratio and the 2019 form's beside, where computed; else the reason."""
    nl = cc.get("nonlinear")
    if nl is None:
        return ""
    rows = [[f"<td>{escape(k)}</td>"]
            + [_cell(c[q], f"code_check.nonlinear.{k}.{q}") for q in
               ("d0_star", "du_star", "Ts", "SDe_Ts", "ratio")] + [_met(c["passes"])]
            + [_cell(c[q], f"code_check.nonlinear.{k}.{q}") for q in
               ("T_SLV", "SDe_SLV", "ratio_SLV")]
            for k, c in nl["mechanisms"].items()]
    out = ""
    if rows:
        out += ('<p class="note">nonlinear kinematic analysis at the ground (2009 C8A.4.2 '
                "form: d_u* = 0.4 d₀* ≥ S_De(T_s), 5 %; beside it the 2019 transcription's "
                "d_SLV = 0.4 d₀*, T_SLV = 1.68π √(d/a), 8 %)</p>")
        out += _table(["mechanism", "d₀* [m]", "d_u* [m]", "T_s [s]", "S_De(T_s) [m]",
                       "ratio d_u*/S_De [–]", "met", "T_SLV [s]", "S_De(T_SLV) [m]",
                       "ratio (2019) [–]"], rows)
    return out + _skipped(nl["not_computed"], "nonlinear check")


def _pictures(folder: Path) -> str:
    """The run's pictures found in ``folder`` (those of ``PICTURES`` in its order, any other
    after them), embedded as base64 PNG data URIs."""
    out = []
    others = sorted(p.name for p in folder.glob("*.png") if p.name not in PICTURES)
    for name, caption in [*PICTURES.items(), *((n, "") for n in others)]:
        path = folder / name
        if path.is_file():
            data = base64.b64encode(path.read_bytes()).decode("ascii")
            out.append(f'<figure><img alt="{escape(name)}" src="data:image/png;base64,{data}">'
                       f"<figcaption>{escape(name)}{': ' * bool(caption)}{escape(caption)}"
                       "</figcaption></figure>")
    return "".join(out) or '<p class="note">none ([output] png = false)</p>'


def page(result, folder: str | Path) -> str:
    """report.html's text for ``result`` (a ``Result``), its pictures read from ``folder``
    (the result set's staging folder, where the run's PNG files were just written)."""
    d = result.to_dict()
    labels = {k: getattr(m, "label", k) for k, m in result.mechanisms.items()}
    version = escape(str(d["homlimit_version"]))
    name = escape(d["case"])
    return "".join([
        '<!DOCTYPE html>\n<html lang="en"><head><meta charset="utf-8">',
        f"<title>homlimit report: {name}</title><style>{_STYLE}</style></head><body>",
        f"<h1>homlimit report: case {name}</h1>",
        f'<p class="note">homlimit version <span id="version">{version}</span>; case file '
        f"{escape(str(d['source']))}</p>",
        "".join(f'<p class="note">warning: {escape(w)}</p>' for w in d["warnings"]),
        "<h2>Inputs</h2>", _inputs(d["inputs"]),
        "<h2>Multipliers and collapse velocities</h2>", _mechanisms(d, labels),
        "<h2>Code check: kinematic analysis (NTC 2018 / Circolare 2019 §C8.7.1.2)</h2>",
        _code_check(d["code_check"], bool(d["inputs"].get("floor"))),
        "<h2>Mechanisms</h2>", _pictures(Path(folder)),
        "</body></html>\n"])
