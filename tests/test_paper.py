"""Table 1 data shipped in the package, and Figure 2 drawn to a PNG."""

import numpy as np

from homlimit.closed_form.paper import table1


def test_table1_is_shipped_and_consistent_with_its_own_columns():
    rows = table1()
    assert len(rows) == 12
    for t in rows:
        c = t.case
        # the paper rounds h_v to 0.1 m, λ_v to 0.1, v_g to 0.01 m/s and v_g/√(gb) to 0.001
        b, sqgb = c.wall.b, np.sqrt(9.81 * c.wall.b)
        assert abs(t.lam_v - t.h_v / b) <= 0.05 / b + 0.05 + 1e-12
        assert abs(t.vg_norm - t.vg / sqgb) <= 0.005 / sqgb + 0.0005 + 1e-12


def test_figure2_png(tmp_path):
    from matplotlib.image import imread

    from homlimit.app.plots import figure2

    path = figure2(tmp_path / "fig2.png")
    img = imread(path)
    assert img.shape[0] > 600 and img.shape[1] > 900
    assert img[..., :3].std() > 0.05  # not blank
    assert not list(tmp_path.glob("*.tmp*"))  # written whole: no temporary left behind


def test_table1_png(tmp_path):
    from matplotlib.image import imread

    from homlimit.app.plots import plot_table1
    from homlimit.closed_form.paper import table1_rows

    img = imread(plot_table1(tmp_path / "t1.png", table1_rows()))
    assert img.shape[0] > 500 and img.shape[1] > 700
    assert img[..., :3].std() > 0.05
