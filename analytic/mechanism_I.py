"""Mechanism I (detachment of the façade), derived symbolically from eq. 8.

Run ``python -m analytic.mechanism_I`` to print every step.
"""

from __future__ import annotations

import sympy as sp

theta, thdot, z, h, b, c, a, f, g, gamma, s, l = sp.symbols(
    "theta thetadot z h b c a f g gamma s l", positive=True)
lam, rho, alpha, beta = sp.symbols("lambda rho alpha beta", positive=True)

# eq. 8: friction force per unit height at the abutment while the joint at z still overlaps
f_a = g * gamma * s * f * (h - z) * (c - theta * z) / a
# The relative horizontal displacement is u = θ z, so the friction power is ∫ f_a u̇ dz with
# u̇ = θ̇ z (the printed eq. 9 writes f_a θ̇ dz, a misprint: its results include the factor z).
power_left = sp.integrate(f_a * thdot * z, (z, 0, h))            # θ < c/h: all joints overlap
power_right = sp.integrate(f_a * thdot * z, (z, 0, c / theta))   # θ >= c/h: only z < c/θ
eq9_left = g * gamma * s * f * h ** 3 * (2 * c - h * theta) / (12 * a) * thdot
eq9_right = g * gamma * s * f * c ** 3 * (2 * h * theta - c) / (12 * a * theta ** 3) * thdot

# work of friction: integrate the power over dt = dθ/θ̇, the right branch from the switch c/h
u = sp.Symbol("u", positive=True)
W_f_left = sp.integrate((power_left / thdot).subs(theta, u), (u, 0, theta))
W_f_switch = W_f_left.subs(theta, c / h)
W_f_right = W_f_switch + sp.integrate((power_right / thdot).subs(theta, u), (u, c / h, theta))

# gravity: exact rise of the façade's centre of gravity (b/2, h/2) rotating outwards about the
# toe, and its second-order expansion (the linearised term of eq. 10)
m_facade = gamma * h * b * l
W_g_exact = m_facade * g * (b / 2 * sp.sin(theta) + h / 2 * sp.cos(theta) - h / 2)
W_g = sp.series(W_g_exact, theta, 0, 3).removeO()

W_left = W_g + W_f_left
W_right = W_g + W_f_right
eq10 = (sp.Rational(1, 2) * g * gamma * h * l * b ** 2 * (1 - h / (2 * b) * theta) * theta
        + g * gamma * s * f * c ** 2 * (6 * h ** 2 * theta ** 2 + c ** 2 - 4 * c * h * theta)
        / (24 * a * theta ** 2))

# eq. 11 substitutions: h = λb, l = ρs, c = βb, f/a = α²/c
subs11 = {h: lam * b, l: rho * s, c: beta * b, f: alpha ** 2 * a / (beta * b)}
w_right = sp.simplify(sp.expand(W_right.subs(subs11) / (g * gamma * s * b ** 3)))
w_left = sp.simplify(sp.expand(W_left.subs(subs11) / (g * gamma * s * b ** 3)))
eq12_corrected = (12 * rho * lam * theta - 6 * rho * lam ** 2 * theta ** 2
                  + 6 * alpha ** 2 * beta * lam ** 2 - 4 * alpha ** 2 * beta ** 2 * lam / theta
                  + alpha ** 2 * beta ** 3 / theta ** 2) / 24
eq12_printed = 24 * (-6 * rho * lam ** 2 * theta ** 2 + 12 * rho * lam * theta
                     + 6 * alpha ** 2 * lam ** 2 * beta - 4 / theta * alpha ** 2 * beta ** 2 * lam
                     + alpha ** 2 * beta ** 2 / theta ** 2)

# eq. 13: dW/dθ = 0 as a monic quartic
quartic = sp.expand(-sp.diff(w_right, theta) * theta ** 3 * 24 / (12 * rho * lam ** 2))
eq13_printed = (theta ** 4 - theta ** 3 / lam - alpha ** 2 * beta ** 2 * theta / (3 * rho * lam)
                - alpha ** 2 * beta ** 3 / (6 * rho * lam ** 2))

# eq. 14: the quartic expanded to second order about θ̄ = 1/λ, larger root of the quadratic
t0 = 1 / lam


def _taylor_root(q):
    q2 = sum(sp.diff(q, theta, k).subs(theta, t0) * (theta - t0) ** k / sp.factorial(k)
             for k in range(3))
    roots = sp.solve(sp.expand(q2), theta)
    # the larger root is the one near 1/λ (the other is spurious)
    return [r for r in roots if sp.N(r.subs({lam: 10, rho: 12, alpha: 0.6, beta: 0.4}))
            == max(sp.N(rr.subs({lam: 10, rho: 12, alpha: 0.6, beta: 0.4})) for rr in roots)][0]


k = (alpha * beta * lam) ** 2
eq14_printed = (sp.Rational(5, 6) + k / (18 * rho)
                + sp.sqrt(9 * rho ** 2 + k * rho * (30 + 18 * beta) + k ** 2) / (18 * rho)) / lam
eq14_corrected = (sp.Rational(5, 6) + k / (18 * rho)
                  + sp.sqrt(9 * rho ** 2 + k * rho * (30 - 18 * beta) + k ** 2) / (18 * rho)) / lam

# numeric functions for the cross-checks (normalised W/(gγsb³), both branches)
_args = (theta, lam, rho, alpha, beta)
work_right = sp.lambdify(_args, w_right, "numpy")
work_left = sp.lambdify(_args, w_left, "numpy")
quartic_coeffs = sp.lambdify((lam, rho, alpha, beta),
                             sp.Poly(quartic, theta).all_coeffs(), "numpy")
theta14 = sp.lambdify((lam, rho, alpha, beta), eq14_printed, "numpy")
theta14_corrected = sp.lambdify((lam, rho, alpha, beta), eq14_corrected, "numpy")


def checks() -> dict[str, bool]:
    """Every identity this module establishes, True where it holds."""
    zero = lambda e: sp.simplify(e) == 0  # noqa: E731
    return {
        "eq. 9, left branch (with u̇ = θ̇ z)": zero(power_left - eq9_left),
        "eq. 9, right branch (with u̇ = θ̇ z)": zero(power_right - eq9_right),
        "eq. 10 (θ >= c/h)": zero(W_right - eq10),
        "eq. 12 corrected (1/24, β³)": zero(w_right - eq12_corrected),
        "eq. 12 as printed": zero(w_right - eq12_printed),
        "eq. 13 as printed": zero(quartic - eq13_printed),
        "eq. 13 corrected (+α²β³/(6ρλ²))": zero(
            quartic - (eq13_printed + alpha ** 2 * beta ** 3 / (3 * rho * lam ** 2))),
        "eq. 14 = Taylor root of the printed eq. 13": zero(_taylor_root(eq13_printed)
                                                          - eq14_printed),
        "eq. 14 corrected = Taylor root of the corrected quartic": zero(_taylor_root(quartic)
                                                                       - eq14_corrected),
    }


if __name__ == "__main__":
    print("eq. 9 (left):  ", sp.factor(power_left))
    print("eq. 9 (right): ", sp.factor(power_right))
    print("W, θ < c/h:    ", sp.factor(W_left))
    print("W, θ >= c/h:   ", sp.simplify(W_right))
    print("24 W/(gγsb³):  ", sp.expand(24 * w_right))
    print("quartic:       ", quartic)
    for name, ok in checks().items():
        print(f"{'holds ' if ok else 'FAILS '} {name}")
