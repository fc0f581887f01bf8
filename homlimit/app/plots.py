"""Pictures (PNG) of v̄_g(λ) curves, tables, spectra and studies; the FE model's pictures
(mesh, mechanism, stress, adaptive bracket) are ``app.plots_fe``'s, importable from here.

matplotlib is imported lazily, with the non-interactive Agg backend, so importing homlimit never
pulls in a GUI. Every picture is written atomically (``_io.write_figure``), with axis
labels in SI units and a title naming the case. Frame: x from the façade's outer face into the
building, z up (see homlimit.params).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from . import registry
from .plot_base import DPI, pyplot, save_png
from .plots_fe import (
    STRESS_GAMMA,
    plot_adapt,
    plot_mechanism,
    plot_mesh,
    plot_stress,
    triangle_regions,
)

__all__ = ["DPI", "STRESS_GAMMA", "figure2", "plot_adapt", "plot_crack_study", "plot_mechanism",
           "plot_mesh", "plot_spectra", "plot_stress", "plot_table1", "plot_vg_lambda", "pyplot",
           "save_png", "scan_points", "triangle_regions"]


def scan_points(scan) -> tuple[list, list]:
    """The FE scan's (λ, v̄_g) split for vg_lambda.png: a rigid or hinge + fan body whose
    fitted hinge lies in the analysed part (its mesh's bounding box) is a point of the curve;
    a distributed mechanism, or a fit whose hinge lies outside the part, has a v̄_g of the
    one-DOF generalisation that is no rigid body's and is drawn apart (issue 26: such points
    made spikes of 2.9 m/s on the curve). Returns (on, off), each sorted by λ."""
    on, off = [], []
    for m in scan:
        if not math.isfinite(m.vg):
            continue
        inside = False
        if m.kind != "distributed":
            x0, z0 = (float(v) for v in m.O)
            p = m.problem.mesh.p
            inside = (p[0].min() - 1e-9 <= x0 <= p[0].max() + 1e-9
                      and p[1].min() - 1e-9 <= z0 <= p[1].max() + 1e-9)
        (on if inside else off).append((m.lam, m.vg))
    return sorted(on), sorted(off)


def plot_vg_lambda(path: str | Path, curves: dict, mechanisms: dict, *, fe=None, dem=None,
                   title: str = "", b: float | None = None) -> Path:
    """Collapse ground velocity v̄_g against slenderness λ = h/b (eq. 7).

    ``curves``: name → (λ, v̄_g(λ), label), e.g. mechanism I (eq. 10) and II (eqs 17–20);
    every mechanism of ``mechanisms``
    (name → object with ``lam``, ``vg``) at its critical point; the FE scan over collapse
    heights (``fe``: a ``mechanism.analysis.FEResult``) and the paper's DEM value (``dem``: a
    ``paper.DemResult``) when given.
    """
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(8, 5.5))
    for name, (lam, vg, label) in curves.items():
        ax.plot(lam, vg, color=registry.mechanism(name).colour, label=label)
    if fe is not None:
        on, off = scan_points(fe.scan)
        if on:
            ax.plot(*zip(*on), "s--", color="C2", mec="k",
                    label="finite-element body (one analysis per collapse height)")
        if off:
            ax.plot(*zip(*off), "x", color="C2", ms=7,
                    label="FE part without a rigid body about a hinge in it (distributed, or "
                          "the fitted hinge outside the part): not on the curve")
    for name, m in mechanisms.items():
        look = registry.mechanism(name)
        if math.isfinite(m.vg):
            ax.plot([m.lam], [m.vg], look.marker, color=look.colour, ms=look.size, mec="k",
                    label=f"critical {name}: λ = {m.lam:.2f}, v̄_g = {m.vg:.3f} m/s")
    if dem is not None:
        ax.plot([dem.lam_v], [dem.vg], "D", color="C3", ms=9, mec="k",
                label=f"DEM, paper's Table 1 ({dem.test}): λ = {dem.lam_v:g}, "
                      f"v̄_g = {dem.vg:g} m/s")
    finite = np.concatenate([np.asarray(vg, float) for _, vg, _ in curves.values()])
    finite = finite[np.isfinite(finite)]
    # a real wall's curve may be NaN throughout (every λ of the grid crushes, its critical
    # part below the grid's first λ): the critical points set the axis then
    top = min(float(np.max(finite)) if finite.size else math.inf,
              2.5 * max(mechanisms[name].vg for name in curves))
    ax.set_ylim(0.0, top * 1.05)
    # a curve may be empty (II's wedge fits no λ of the grid): the others set the axis
    ax.set_xlim(0.0, max((float(np.max(lam)) for lam, _, _ in curves.values() if len(lam)),
                         default=1.0) * 1.02)
    ax.set_xlabel("slenderness of the failing part λ = h/b [-]")
    ax.set_ylabel("collapse ground velocity v̄_g [m/s]")
    if b:
        sec = ax.secondary_xaxis("top", functions=(lambda x: x * b, lambda h: h / b))
        sec.set_xlabel("height of the failing part h [m]")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, loc="upper right")
    ax.set_title(f"{title}: collapse ground velocity against slenderness".lstrip(": "))
    return save_png(fig, path)




def _identity_axes(ax, top: float, label: str, xlabel: str, ylabel: str, fontsize: int):
    """Square axes from 0 to 1.1 × ``top`` with the line measured = predicted (``label``)."""
    lim = [0.0, 1.1 * top if top > 0 else 1.0]
    ax.plot(lim, lim, "k--", lw=1, label=label)
    ax.set_xlim(lim)
    ax.set_ylim(lim)
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=fontsize, loc="upper left")


def plot_crack_study(path: str | Path, records: list[dict], title: str = "crack-angle study"
                     ) -> Path:
    """The crack-angle study: the FE crack against the closed-form slopes.

    Left: the 50 % participation line tan ψ (with its uncertainty ``dtanpsi_fe``) against
    √(cf/a) of eq. 16. Right (when records carry ``tanpsi_block``/``tanpsi_fixed``): the fan's
    block-side and fixed-side edges against min(f, c/a) and max(f, c/a), the prototype's
    hinge + fan optimum. Colour: joint friction f; marker: façade model. Records need
    c_over_a, f and tanpsi_fe; mechanisms without a crack (NaN) are left out.
    """
    plt = pyplot()

    def finite(r, k):
        x = r.get(k)
        return x is not None and math.isfinite(x)

    recs = [r for r in records if finite(r, "tanpsi_fe")]
    edges = [r for r in recs if finite(r, "tanpsi_block") and finite(r, "tanpsi_fixed")]
    fig, axes = plt.subplots(1, 2 if edges else 1, figsize=(13 if edges else 7, 6),
                             squeeze=False)
    ax = axes[0, 0]
    fmin = min((r["f"] for r in recs), default=0.0)
    fmax = max((r["f"] for r in recs), default=1.0)
    norm = plt.Normalize(fmin, max(fmax, fmin + 1e-9))
    cmap = plt.get_cmap("plasma")
    facades = sorted({str(r.get("facade", "")) for r in recs})
    markers = dict(zip(facades, "os^vD"))
    top = 0.0
    for fac in facades:
        sel = [r for r in recs if str(r.get("facade", "")) == fac]
        pred = np.array([math.sqrt(r["c_over_a"] * r["f"]) for r in sel])
        meas = np.array([r["tanpsi_fe"] for r in sel])
        err = np.array([r.get("dtanpsi_fe") or 0.0 for r in sel])
        col = cmap(norm(np.array([r["f"] for r in sel])))
        ax.errorbar(pred, meas, yerr=err, fmt="none", ecolor="0.6", lw=1, zorder=1)
        ax.scatter(pred, meas, c=col, marker=markers[fac], edgecolors="k", zorder=2,
                   label=f"FE 50 % line{', façade ' + fac if fac else ''}")
        top = max(top, pred.max(), (meas + err).max())
    _identity_axes(ax, top, "tan ψ = √(cf/a) (eq. 16)", "predicted slope √(cf/a) [-]",
                   "measured crack slope tan ψ (50 % participation line) [-]", fontsize=8)
    if edges:
        ax2 = axes[0, 1]
        top = 0.0
        for fac in facades:
            sel = [r for r in edges if str(r.get("facade", "")) == fac]
            if not sel:
                continue
            lo = np.array([min(r["f"], r["c_over_a"]) for r in sel])
            hi = np.array([max(r["f"], r["c_over_a"]) for r in sel])
            t1 = np.array([r["tanpsi_block"] for r in sel])
            t2 = np.array([r["tanpsi_fixed"] for r in sel])
            col = cmap(norm(np.array([r["f"] for r in sel])))
            ax2.scatter(lo, t1, c=col, marker=markers[fac], edgecolors="k",
                        label=f"block-side edge vs min(f, c/a), {fac}")
            ax2.scatter(hi, t2, facecolors="none", edgecolors=col, marker=markers[fac],
                        linewidths=1.5, label=f"fixed-side edge vs max(f, c/a), {fac}")
            top = max(top, hi.max(), t1.max(), t2.max())
        _identity_axes(ax2, top, "edge = closed-form hinge + fan edge",
                       "closed-form fan edge: min(f, c/a) or max(f, c/a) [-]",
                       "measured fan edge tan ψ [-]", fontsize=7)
    sm = plt.cm.ScalarMappable(norm=norm, cmap=cmap)
    fig.colorbar(sm, ax=list(axes.ravel()), label="joint friction f [-]", shrink=0.9)
    fig.suptitle(title)
    return save_png(fig, path)


# Figure 2 of the paper (figure2) is drawn by the closed-form core; it belongs below.


def figure2(path: str | Path, data: dict) -> Path:
    """The paper's Figure 2 from ``pipeline.figure2_curves()``: critical v̄_g/√(gb) (top) and
    critical λ (bottom) against ρ = l/s, one column per β, one colour per α²; mechanism I
    solid, mechanism II dashed; Table 1's DEM results as markers."""
    plt = pyplot()
    rho = np.asarray(data["rho"])
    colours = ["tab:blue", "tab:orange", "tab:green"]
    fig, axes = plt.subplots(2, 2, figsize=(10, 7.5), sharex=True)
    for j, panel in enumerate(data["panels"]):
        for col, cv in zip(colours, panel["curves"]):
            a2 = cv["alpha2"]
            axes[0, j].plot(rho, cv["vnorm_I"], "-", color=col, label=f"I, α² = {a2:g}")
            axes[0, j].plot(rho, cv["vnorm_II"], "--", color=col, label=f"II, α² = {a2:g}")
            axes[1, j].plot(rho, cv["lam_I"], "-", color=col)
            axes[1, j].plot(rho, cv["lam_II"], "--", color=col)
            pts = [d for d in panel["dem"] if abs(d["alpha2"] - a2) < 1e-9]
            axes[0, j].plot([d["rho"] for d in pts], [d["vnorm"] for d in pts], "o",
                            color=col, mec="k", label=f"DEM, α² = {a2:g}")
            axes[1, j].plot([d["rho"] for d in pts], [d["lam"] for d in pts], "o", color=col,
                            mec="k")
        axes[0, j].set_title(f"β = c/b = {panel['beta']:g} (b = {panel['b']:g} m)")
        axes[0, j].set_ylabel("v̄_g / √(g b)  [-]")
        axes[1, j].set_ylabel("critical λ = h / b  [-]")
        axes[1, j].set_xlabel("ρ = l / s  [-]")
        for ax in axes[:, j]:
            ax.grid(alpha=0.3)
    axes[0, 0].legend(fontsize=7, ncol=3, loc="upper right")
    fig.suptitle("Figure 2: collapse ground velocity and slenderness of the overturning part "
                 "(lines: mechanisms I solid, II dashed; dots: DEM, Table 1)", fontsize=10)
    fig.tight_layout()
    return save_png(fig, path)




def plot_table1(path: str | Path, rows: list[dict]) -> Path:
    """Table 1 side by side: v̄_g/√(gb) and critical λ of mechanisms I, II, the FE body (when
    the rows carry ``vnorm_fe``) and the DEM, one group of markers per test."""
    plt = pyplot()
    tests = [r["test"] for r in rows]
    x = np.arange(len(rows))
    series = [("I", "o", "tab:blue", "mechanism I (closed form)"),
              ("II", "s", "tab:orange", "mechanism II (closed form)"),
              ("fe", "^", "tab:green", "finite-element body"),
              ("dem", "D", "tab:red", "DEM, paper's Table 1")]
    fig, axes = plt.subplots(2, 1, figsize=(9, 7), sharex=True)
    for key, marker, col, label in series:
        v = [r.get(f"vnorm_{key}") for r in rows]
        lam = [r.get(f"lam_{key}") for r in rows]
        if all(a is None for a in v):
            continue
        v = np.array([np.nan if a is None else a for a in v], float)
        lam = np.array([np.nan if a is None else a for a in lam], float)
        axes[0].plot(x, v, marker, color=col, mec="k", label=label)
        axes[1].plot(x, lam, marker, color=col, mec="k")
    axes[0].set_ylabel("v̄_g / √(g b)  [-]")
    axes[1].set_ylabel("critical λ = h / b  [-]")
    axes[1].set_xticks(x, tests)
    axes[1].set_xlabel("Table 1 test")
    for ax in axes:
        ax.grid(alpha=0.3)
    axes[0].legend(fontsize=8)
    axes[0].set_title("Table 1: collapse ground velocity and slenderness, closed forms, FE and DEM")
    fig.tight_layout()
    return save_png(fig, path)


def plot_spectra(path: str | Path, points, *, dem_vnorm: float | None = None,
                 title: str | None = None) -> Path:
    """Critical pgv/√(g b) against pulse period, one panel per pulse kind, one line per
    mechanism (and polarity), eq. 7 (the ideal impulse) as a dashed line of the same colour
    (the short-period asymptote of the rectangular pulse), the DEM value of Table 1 when given.
    ``points``: ``dynamics.SpectrumPoint`` records."""
    from ..errors import ParameterError

    plt = pyplot()
    if not points:
        raise ParameterError("points = [] is out of range: nothing to plot")
    kinds = list(dict.fromkeys(p.pulse for p in points))
    mechs = list(dict.fromkeys(p.mechanism for p in points))
    colours = dict(zip(mechs, plt.rcParams["axes.prop_cycle"].by_key()["color"]))
    fig, axes = plt.subplots(1, len(kinds), figsize=(5.2 * len(kinds), 4.8), squeeze=False,
                             sharey=True, layout="constrained")
    for ax, kind in zip(axes[0], kinds):
        for m in mechs:
            for pol in sorted({p.polarity for p in points}, reverse=True):
                sel = sorted((p for p in points if p.pulse == kind and p.mechanism == m
                              and p.polarity == pol), key=lambda p: p.period)
                if not sel:
                    continue
                lab = m if pol > 0 else f"{m} (polarity -1)"
                ax.plot([p.period for p in sel], [p.vnorm for p in sel], "o-" if pol > 0
                        else "s:", color=colours[m], label=lab, ms=4)
            eq7 = next((p.vnorm_eq7 for p in points if p.mechanism == m), None)
            if eq7 is not None:
                ax.axhline(eq7, color=colours[m], ls="--", lw=1,
                           label=f"{m}: eq. 7 (ideal impulse)")
        if dem_vnorm is not None:
            ax.axhline(dem_vnorm, color="k", ls="-.", lw=1, label="DEM (Table 1)")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("pulse period T_p [s]" if kind != "rectangular"
                      else "pulse duration Δt [s]")
        ax.set_title(kind)
        ax.grid(True, which="both", alpha=0.3)
    axes[0][0].set_ylabel("critical pgv / √(g b)")
    handles, labels = axes[0][0].get_legend_handles_labels()
    for ax in axes[0][1:]:
        for hd, lb in zip(*ax.get_legend_handles_labels()):
            if lb not in labels:
                handles.append(hd)
                labels.append(lb)
    fig.legend(handles, labels, fontsize=7, loc="outside lower center",
               ncol=min(len(labels), 4))
    if title:
        fig.suptitle(title)

    return save_png(fig, path)




def plot_code_check(path: str | Path, checks: dict, impulse: dict, title: str = "",
                    floors: dict | None = None) -> Path:
    """code_check.png: per mechanism, the code check's capacity/demand a₀*/demand (NTC 2018 /
    Circolare 2019 §C8.7.1.2, e* by integration) beside the impulse view's v̄_g/PGV (PGV =
    0.16 a_g S T_C, §3.2.3.3), on one log axis with the limit 1 (docs/code-check.md); with
    ``floors`` (name → check in the floors' Q_k reading) a hatched bar of its ratio between."""
    plt = pyplot()
    names = list(dict.fromkeys([*checks, *impulse]))
    y = np.arange(len(names))
    fig, ax = plt.subplots(figsize=(8, 1.2 + 0.6 * len(names)), layout="constrained")
    acc = [checks[n].ratio if n in checks else np.nan for n in names]
    vel = [impulse[n] if n in impulse else np.nan for n in names]
    w = 0.4 if floors is None else 0.27
    ax.barh(y - w / 2 - (0 if floors is None else w / 2), acc, w, color="C0",
            label="code check: a0*/demand (acceleration)")
    if floors is not None:
        ax.barh(y, [floors[n].ratio if n in floors else np.nan for n in names], w,
                color="white", edgecolor="C0", hatch="///",
                label="code check, floors' Q_k reading (transcription C8.7.1.1/.5)")
    ax.barh(y + w / 2 + (0 if floors is None else w / 2), vel, w, color="C3",
            label="impulse view: v̄_g/PGV (velocity)")
    ax.axvline(1.0, color="k", lw=1.0, ls="--")
    ax.set_xscale("log")
    ax.set_yticks(y, names)
    ax.invert_yaxis()
    ax.set_xlabel("capacity / demand [-] (>= 1: met)")
    fig.legend(loc="outside lower center", ncols=2, fontsize=8)
    ax.set_title(f"{title}: the code check and the impulse view" if title
                 else "the code check and the impulse view")
    return save_png(fig, path)
