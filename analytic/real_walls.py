"""Real walls (issue 30): the restoring work W(θ), its peak, v̄_g (eq. 7) and the static
multiplier of mechanisms I, II and the simple overturning with a finite f_c, tie-rods and
floors, derived here from the body itself and not from homlimit's formulas:

- the body's potential energy by integrating the rotated coordinates of every point of the
  façade strip (and II's wedge) about the retreated hinge (t, 0) (exact for II and the
  overturning; expanded to second order in θ for I, as eq. 10 does);
- mechanism I's abutment friction from eq. 8 itself: power θ̇ ∫ f_a(z) z dz over the joints
  still overlapping (u = zθ < c), integrated over θ across the switch θ = c/h;
- a floor: a dead load Q at (e − t, z_Q) raised by the rotation; a rigid-plastic tie: T_y
  times the horizontal displacement of the point (t, d) (d θ for I, d sin θ exactly);
- I about the hinge by integrating (x − t)² + z² over the body;
- t = N/(2 f_c l): the rectangular stress block's resultant (docs/real-walls.md).

Numbers per bay of length l (a tie or floor per metre of façade × l). ``reference(...)``
evaluates everything for one λ; its θ_m is the root of dW/dθ found by sympy's nsolve.
Run ``python -m analytic.real_walls`` for B1 with a top tie.
"""

from __future__ import annotations

import math

import sympy as sp

x, z, th, ph = sp.symbols("x z theta phi", real=True)
b, h, t, tp, gam, l, s, g = sp.symbols("b h t tanpsi gamma l s g", positive=True)
a, c, f = sp.symbols("a c f", positive=True)


def _rotated_rise(xx, zz, theta, exact=True):
    """Rise of the point (xx, zz) (relative to the hinge) turned outwards by θ."""
    rise = xx * sp.sin(theta) + zz * sp.cos(theta) - zz
    if exact:
        return rise
    return sp.series(rise, theta, 0, 3).removeO()


def _body(kind: str):
    """[(density per unit area in the section, x range, z range)] of the body."""
    strip = (gam * l, (x, 0, b), (z, 0, h))
    if kind == "crack":
        return [strip, (gam * s, (x, b, b + z * tp), (z, 0, h))]
    return [strip]


def _integrate(expr, kind):
    return sum(sp.integrate(sp.integrate(rho * expr, xr), zr) for rho, xr, zr in _body(kind))


def gravity_work(kind: str):
    """The body's restoring work against gravity about (t, 0) [J] (symbolic in θ)."""
    exact = kind != "detachment"
    return sp.simplify(g * _integrate(_rotated_rise(x - t, z, th, exact), kind))


def mass(kind):
    return sp.simplify(_integrate(sp.Integer(1), kind))


def inertia(kind):
    """I about the retreated hinge (t, 0)."""
    return sp.simplify(_integrate((x - t) ** 2 + z ** 2, kind))


def z_G(kind):
    return sp.simplify(_integrate(z, kind) / mass(kind))


def friction_work():
    """Mechanism I's abutment friction from eq. 8: W_a(θ) = ∫_0^θ φ-power dφ, the power
    ∫ f_a(z) z dz over z < min(h, c/φ); (left: θ < c/h, right: θ >= c/h)."""
    fa = g * gam * s * f * (h - z) * (c - z * ph) / a
    p_left = sp.integrate(fa * z, (z, 0, h))
    p_right = sp.integrate(fa * z, (z, 0, c / ph))
    left = sp.integrate(p_left, (ph, 0, th))
    right = sp.integrate(p_left, (ph, 0, c / h)) + sp.integrate(p_right, (ph, c / h, th))
    return sp.simplify(left), sp.simplify(right)


_CACHE: dict = {}


def _forms(kind):
    if kind not in _CACHE:
        out = {"W": gravity_work(kind), "m": mass(kind), "I": inertia(kind), "zG": z_G(kind)}
        if kind == "detachment":
            out["Wa"] = friction_work()
        _CACHE[kind] = out
    return _CACHE[kind]


def reference(kind: str, wall: dict, masonry: dict, lam: float, ties=(), floors=(),
              fc: float = 0.0, tanpsi: float | None = None, theta0: float | None = None):
    """θ_m, W(θ_m) [J], v̄_g [m/s], a/g of the mechanism at λ, the numbers of ``wall``
    (H L s b l gamma g) and ``masonry`` (a c f); ties [(z, T_y per m)], floors
    [(z, q per m, e)] (rigid-plastic ties, no ductility limit: the cases of the tests)."""
    F = _forms(kind)
    H, bb, ll = wall["H"], wall["b"], wall["l"]
    hh = lam * bb
    z0 = H - hh
    tpsi = (tanpsi or math.sqrt(masonry["c"] * masonry["f"] / masonry["a"])
            if kind == "crack" else 0.0)
    num = {b: bb, h: hh, gam: wall["gamma"], l: ll, s: wall["s"], g: wall["g"], tp: tpsi,
           a: masonry["a"], c: masonry["c"], f: masonry["f"]}
    m = float(F["m"].subs(num))
    loads = [(q * ll, e, zf - z0) for zf, q, e in floors if zf > z0]
    N = m * wall["g"] + sum(Q for Q, _, _ in loads)
    tt = N / (2 * fc * ll) if fc else 0.0
    num[t] = tt
    W = F["W"].subs(num)
    for Q, e, zq in loads:
        W += Q * _rotated_rise(e - tt, zq, th, kind != "detachment")
    for zt, Ty in ties:
        if zt > z0:
            d = zt - z0
            W += Ty * ll * (d * th if kind == "detachment" else d * sp.sin(th))
    if kind == "detachment":
        left, right = (w.subs(num) for w in F["Wa"])
        theta_c = masonry["c"] / hh
    dW = sp.diff(W, th)
    M0 = float(dW.subs(th, 0))
    if kind == "detachment":
        M0 += float(sp.diff(left, th).subs(th, 0))
    zg = float(F["zG"].subs(num))
    a_g = M0 / (m * wall["g"] * zg)
    # θ_m: a root of dW/dθ (each branch of I's friction; the best W wins)
    cands = []
    if kind == "detachment":
        for Wb, ok in ((W + left, lambda v: v < theta_c), (W + right, lambda v: v >= theta_c)):
            for guess in (theta0 or 0.3, theta_c * 0.5, theta_c * 2, 1.0 / lam):
                try:
                    r = float(sp.nsolve(sp.diff(Wb, th), th, guess, prec=30))
                except (ValueError, ZeroDivisionError):
                    continue
                if r > 0 and ok(r):
                    cands.append((float(Wb.subs(th, r)), r))
        cands.append((float((W + left).subs(th, theta_c)), theta_c))
    else:
        r = float(sp.nsolve(dW, th, theta0 or 0.2, prec=30))
        cands.append((float(W.subs(th, r)), r))
    Wm, theta_m = max(cands)
    I_h = float(F["I"].subs(num))
    vg = math.sqrt(2 * Wm * I_h) / (m * zg)
    return {"theta_m": theta_m, "W_m": Wm, "vg": vg, "multiplier": a_g, "t": tt, "N": N}


B1 = ({"H": 9.0, "L": 6.0, "s": 0.5, "b": 0.5, "l": 6.0, "gamma": 2000.0, "g": 9.81},
      {"a": 0.3, "c": 0.2, "f": 0.6})

if __name__ == "__main__":
    for kind in ("detachment", "crack", "overturning"):
        for Ty in (0.0, 2000.0, 10000.0):
            r = reference(kind, *B1, 18.0, ties=[(9.0, Ty)])
            print(kind, Ty, {k: round(v, 6) for k, v in r.items()})
