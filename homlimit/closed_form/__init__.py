"""Closed-form collapse mechanisms: I and II of the paper (eqs 8–20), the homogenised hinge + fan,
and the paper's Table 1."""
