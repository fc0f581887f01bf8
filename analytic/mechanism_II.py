"""Mechanism II (diagonal crack): eqs 17 and 20 by integrating the rotating body.

The body, per unit thickness s of the transversal wall, in the frame of O (the façade's outer
toe at the base of the failing part): the façade strip 0 <= x <= b, 0 <= z <= h with density
ργ (the paper's 2D reduction, ρ = l/s), and the wedge b <= x <= b + z tan ψ, 0 <= z <= h with
density γ. Run ``python -m analytic.mechanism_II``.
"""

from __future__ import annotations

import sympy as sp

x, z, b, h, t = sp.symbols("x z b h t", positive=True)
lam, rho = sp.symbols("lambda rho", positive=True)


def _moments(density, x_lo, x_hi, z_lo, z_hi):
    integ = lambda q: sp.integrate(sp.integrate(density * q, (x, x_lo, x_hi)),  # noqa: E731
                                   (z, z_lo, z_hi))
    return integ(1), integ(x), integ(z), integ(x ** 2 + z ** 2)


facade = _moments(rho, 0, b, 0, h)
wedge = _moments(1, b, b + z * t, 0, h)
m, Sx, Sz, I_O = (sp.simplify(p + q) for p, q in zip(facade, wedge))
x_G = sp.simplify((Sx / m).subs(h, lam * b))
z_G = sp.simplify((Sz / m).subs(h, lam * b))
i = sp.simplify((I_O / m).subs(h, lam * b))

eq17_x = b / 3 * (3 * rho + lam ** 2 * t ** 2 + 3 * t * lam) / (2 * rho + lam * t)
eq17_z = b / 3 * lam * (3 * rho + 2 * lam * t) / (2 * rho + lam * t)
eq20 = b ** 2 / 6 * ((3 * t + t ** 3) * lam ** 3 + 4 * (rho + t ** 2) * lam ** 2 + 6 * lam * t
                     + 4 * rho) / (2 * rho + lam * t)

# eq. 19 from eqs 7 and 18, normalised by √(g b)
r_G = sp.sqrt(x_G ** 2 + z_G ** 2)
vnorm = sp.sqrt(2 * i / z_G * (r_G / z_G - 1) / b)

_args = (lam, rho, t)
xg = sp.lambdify(_args, x_G.subs(b, 1), "numpy")
zg = sp.lambdify(_args, z_G.subs(b, 1), "numpy")
ig = sp.lambdify(_args, i.subs(b, 1), "numpy")
vnorm_fn = sp.lambdify(_args, vnorm.subs(b, 1), "numpy")


def checks() -> dict[str, bool]:
    """Every identity this module establishes, True where it holds."""
    zero = lambda e: sp.simplify(e) == 0  # noqa: E731
    return {"eq. 17, x_G": zero(x_G - eq17_x), "eq. 17, z_G": zero(z_G - eq17_z),
            "eq. 20, i = I/m": zero(i - eq20)}


if __name__ == "__main__":
    print("m  =", m)
    print("x_G =", sp.factor(x_G))
    print("z_G =", sp.factor(z_G))
    print("i   =", sp.factor(i))
    for name, ok in checks().items():
        print(f"{'holds ' if ok else 'FAILS '} {name}")
