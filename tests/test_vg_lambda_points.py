"""vg_lambda.png draws on the FE curve only the parts whose mechanism is a rigid body about a
hinge inside the part (issue 26, point 6); the others are drawn apart."""

import math
from types import SimpleNamespace

import numpy as np

from homlimit.app.plots import plot_vg_lambda, scan_points


def _part(lam, vg, kind, hinge, z0=5.0, H=9.0, b=0.5, L=6.0):
    p = np.array([[0.0, b + L, b + L, 0.0], [z0, z0, H, H]])     # the part's bounding box
    return SimpleNamespace(lam=lam, vg=vg, kind=kind, O=hinge,
                           problem=SimpleNamespace(mesh=SimpleNamespace(p=p)))


def test_only_rigid_bodies_with_their_hinge_in_the_part_make_the_curve(tmp_path):
    scan = [_part(8.0, 0.95, "rigid", (0.0, 6.2)),
            _part(6.0, 0.92, "hinge+fan", (0.0, 5.0)),           # on the part's base: inside
            _part(2.0, 3.1, "distributed", (0.0, 6.0)),          # no rigid body
            _part(4.0, 2.9, "rigid", (0.0, 3.0)),                # hinge below the part
            _part(5.0, math.nan, "rigid", (0.0, 6.0))]           # no v̄_g: not drawn
    on, off = scan_points(scan)
    assert on == [(6.0, 0.92), (8.0, 0.95)]
    assert off == [(2.0, 3.1), (4.0, 2.9)]
    fe = SimpleNamespace(scan=scan)
    lam = np.linspace(1, 18, 20)
    mech = {"I": SimpleNamespace(lam=10.0, vg=0.82)}
    out = plot_vg_lambda(tmp_path / "vg.png", {"I": (lam, 0.8 + 0.01 * lam, "I")}, mech, fe=fe)
    assert out.stat().st_size > 0
