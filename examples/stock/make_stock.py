"""Draw the made-up building stock of examples/stock/stock.csv (200 façades).

The façades are NOT a survey of real buildings: they are drawn at random (seed 18) from ranges
that are plausible for historical masonry town houses, to show a stock-scale study:

- storeys n ∈ {2, 3, 4, 5} (weights 0.3, 0.35, 0.25, 0.1), storey height 3.0–4.0 m
  (uniform): H = n × storey height;
- façade thickness b = 0.30 + 0.03 n + U(−0.05, 0.10) m (thicker façades on taller houses);
- façade length between transversal walls l ~ U(4, 10) m; transversal walls s ~ U(0.30,
  0.55) m thick and L ~ U(4, 10) m long;
- masonry: 40 % brick (a ~ U(0.055, 0.075) m, c ~ U(0.11, 0.13) m, f ~ U(0.55, 0.75)),
  60 % rubble/dressed stone (a ~ U(0.15, 0.35) m, c ~ U(0.15, 0.30) m, f ~ U(0.45, 0.75));
- γ = 2000 kg/m³ (the case default) for all.

``python make_stock.py`` rewrites stock.csv (same numbers every time).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

N = 200
HERE = Path(__file__).resolve().parent


def draw(n: int = N, seed: int = 18) -> list[dict]:
    rng = np.random.default_rng(seed)
    storeys = rng.choice([2, 3, 4, 5], size=n, p=[0.3, 0.35, 0.25, 0.1])
    H = storeys * rng.uniform(3.0, 4.0, n)
    b = 0.30 + 0.03 * storeys + rng.uniform(-0.05, 0.10, n)
    brick = rng.random(n) < 0.4
    a = np.where(brick, rng.uniform(0.055, 0.075, n), rng.uniform(0.15, 0.35, n))
    c = np.where(brick, rng.uniform(0.11, 0.13, n), rng.uniform(0.15, 0.30, n))
    f = np.where(brick, rng.uniform(0.55, 0.75, n), rng.uniform(0.45, 0.75, n))
    l, s, L = rng.uniform(4, 10, n), rng.uniform(0.30, 0.55, n), rng.uniform(4, 10, n)  # noqa: E741
    return [{"name": f"F{k + 1:03d}", "wall.H": round(H[k], 2), "wall.b": round(b[k], 3),
             "wall.l": round(l[k], 2), "wall.s": round(s[k], 3), "wall.L": round(L[k], 2),
             "masonry.a": round(a[k], 3), "masonry.c": round(c[k], 3),
             "masonry.f": round(f[k], 3)} for k in range(n)]


def main():
    rows = draw()
    cols = list(rows[0])
    text = "# made-up façades (examples/stock/make_stock.py): plausible, not surveyed\n"
    text += ",".join(cols) + "\n"
    text += "".join(",".join(str(r[k]) for k in cols) + "\n" for r in rows)
    (HERE / "stock.csv").write_text(text)


if __name__ == "__main__":
    main()
