"""Lower and upper bounds side by side: Prandtl, vertical cut, blocks, Table 1 T-sections.

Prints, per mesh: triangles, λ⁻ (static), λ⁺ (kinematic), relative gap (λ⁺ − λ⁻)/mean, and the
seconds of each bound (each its own wall clock: ``bracket`` solves the two at once, in two
threads). The T-section section prints the markdown table of docs/static.md. ``concurrent``:
the demo's whole-wall problem (B1, its first mesh), the two bounds one after the other against
``bracket``'s two at once, and whether the multipliers are equal bit for bit (measured: 8.4 s
against 5.9 s on 3278 triangles, equal).

    python benchmarks/bench_bracket.py [prandtl] [cut] [blocks] [tsection] [concurrent]
                                                          (default: all but concurrent)
"""

from __future__ import annotations

import math
import sys
import time

from homlimit.closed_form import paper
from homlimit.fe import problems
from homlimit.fe.bracket import bracket, prandtl_fan


def _row(name, n, br):
    print(f"{name:<28s} {n:>7d} {br.lower:>10.5f} {br.upper:>10.5f} {100 * br.rel_gap:>7.2f}% "
          f"{br.times['static']:>8.1f}s {br.times['kinematic']:>8.1f}s", flush=True)


def _head(title, ref):
    print(f"\n## {title} (reference {ref})")
    print(f"{'mesh':<28s} {'tri':>7s} {'lower':>10s} {'upper':>10s} {'gap':>8s} "
          f"{'static':>9s} {'kinem.':>9s}", flush=True)


def prandtl():
    _head("Prandtl, weightless Tresca, fan mesh at the footing edge", f"2+π = {2 + math.pi:.5f}")
    for size, h_min, n_fan in ((0.4, 0.05, 8), (0.3, 0.03, 12), (0.2, 0.02, 16),
                               (0.12, 0.012, 24)):
        pr = prandtl_fan(size=size, h_min=h_min, radius=0.5, n_fan=n_fan)
        _row(f"fan size={size} h={h_min} rays={n_fan}", pr.n_triangles, bracket(pr))
    for h_min in (0.05, 0.02):
        pr = problems.prandtl(h_min=h_min, h_max=0.5, growth=1.3)
        _row(f"crossed h_min={h_min}", pr.n_triangles, bracket(pr))


def cut():
    _head("Vertical cut, Tresca, γH/k", "[3.7752, 3.7776]")
    for h_min in (0.1, 0.05, 0.03, 0.02):
        pr = problems.vertical_cut(h_min=h_min, h_max=0.25)
        _row(f"crossed h_min={h_min}", pr.n_triangles, bracket(pr))


def blocks():
    _head("Free-standing block b=0.5 h=3 on a dry bed joint, rigid", f"b/h = {0.5 / 3:.6f}")
    for n_b in (1, 2, 4):
        pr = problems.free_block(b=0.5, h=3.0, n_b=n_b)
        _row(f"rigid, n_b={n_b}", pr.n_triangles, bracket(pr))
    _head("The same block of bed-joint masonry (continuum)", "below b/h (docs/kinematic.md)")
    for n_b in (2, 4, 8):
        pr = problems.free_block(b=0.5, h=3.0, n_b=n_b, interior="bedjoints")
        _row(f"bed joints, n_b={n_b}", pr.n_triangles, bracket(pr))
    _head("Prandtl with a rigid rough footing 0.25 thick", f"2+π = {2 + math.pi:.5f}")
    for size, h_min, n_fan in ((0.4, 0.05, 8), (0.3, 0.03, 12), (0.2, 0.02, 16)):
        pr = prandtl_fan(size=size, h_min=h_min, radius=0.5, n_fan=n_fan, footing=0.25)
        _row(f"fan size={size} h={h_min} rays={n_fan}", pr.n_triangles, bracket(pr))


def tsection():
    print("\n## T-section (homogenised eq. 15 in façade and wall), multiplier a/g")
    levels = ((1.0, 1), (0.5, 2), (0.25, 4))
    cols = " | ".join(f"h={h} m, n_b={nb}: tri, λ⁻, λ⁺, gap" for h, nb in levels)
    print(f"| test | {cols} |")
    print("|---" * (1 + len(levels)) + "|")
    for r in paper.table1():
        case = r.case
        cells = []
        for h, nb in levels:
            t0 = time.perf_counter()
            pr = problems.t_section(case, h=h, n_b=nb, growth=1.3)
            br = bracket(pr)
            cells.append(f"{pr.n_triangles}, {br.lower:.4f}, {br.upper:.4f}, "
                         f"{100 * br.rel_gap:.1f} %")
            print(f"  [{r.test} h={h}: {time.perf_counter() - t0:.1f} s]", file=sys.stderr,
                  flush=True)
        print(f"| {r.test} | " + " | ".join(cells) + " |", flush=True)


def concurrent():
    from homlimit.app.config import load_case
    from homlimit.app.models import solver_options, whole_problem
    from homlimit.fe.kinematic import solve_kinematic
    from homlimit.fe.static import solve_static

    config = load_case(None)
    pr = whole_problem(config)
    opt = solver_options(config.analysis.tol, config.analysis.stress_degree)
    print(f"\n## The demo's whole wall (B1), {pr.n_triangles} triangles", flush=True)
    solve_kinematic(pr, opt)                                     # warm: imports, first call
    t0 = time.perf_counter()
    kin, sta = solve_kinematic(pr, opt), solve_static(pr, opt)
    one_after = time.perf_counter() - t0
    t0 = time.perf_counter()
    br = bracket(pr, options=opt)
    at_once = time.perf_counter() - t0
    same = (br.upper == kin.multiplier, br.lower == sta.multiplier)
    print(f"one after the other {one_after:.1f} s, bracket (at once) {at_once:.1f} s; "
          f"multipliers equal bit for bit: {all(same)} (λ⁻ {br.lower:.6f}, λ⁺ {br.upper:.6f})")


if __name__ == "__main__":
    which = sys.argv[1:] or ["prandtl", "cut", "blocks", "tsection"]
    for name in which:
        {"prandtl": prandtl, "cut": cut, "blocks": blocks, "tsection": tsection,
         "concurrent": concurrent}[name]()
