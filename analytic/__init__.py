"""Symbolic (sympy) derivations of the paper's closed forms, rebuilt from the mechanics.

``analytic.mechanism_I`` rebuilds eq. 8 → eq. 9 → eq. 10 → eqs 12–14; ``analytic.mechanism_II``
rebuilds eqs 17 and 20 by integrating the façade strip and the wedge. Both expose lambdified
functions that tests/test_analytic.py checks against homlimit's numeric ones. NOTES.md records
the corrected forms and the paper's misprints. Not installed with the package: run from the
repository root (``python -m analytic``).
"""
