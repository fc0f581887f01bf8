"""Files of a rigid-block analysis (homlimit.blocks.output, studies): VTU round trips, the
contact-force CSV, the PNG, the front-door entry point."""

import json

import meshio
import numpy as np
import pytest

from homlimit.app import report
from homlimit.blocks.geometry import t_section_blocks
from homlimit.blocks.limit import solve_blocks
from homlimit.blocks.output import (
    contact_records,
    plot_blocks_mechanism,
    write_blocks_vtu,
    write_contacts_vtu,
)
from homlimit.blocks.studies import analyse_blocks, h_scan_blocks, table1_blocks
from homlimit.errors import ParameterError
from homlimit.params import Case, Masonry, Wall

SMALL = Case(Wall(H=3.0, L=1.6, s=0.5, b=0.5, l=6.0), Masonry(a=0.3, c=0.2, f=0.6),
             name="small")


@pytest.fixture(scope="module")
def solved():
    A = t_section_blocks(SMALL)
    return A, solve_blocks(A)


def test_blocks_vtu_round_trip(solved, tmp_path):
    A, r = solved
    path = write_blocks_vtu(tmp_path / "blocks.vtu", A, r)
    m = meshio.read(path)
    assert sum(len(c.data) for c in m.cells) == A.n_blocks
    assert all(c.type == "polygon" for c in m.cells)
    block = np.concatenate(m.cell_data["block"])
    assert np.array_equal(np.sort(block), np.arange(A.n_blocks))
    u = np.concatenate(m.cell_data["u"])
    assert u == pytest.approx(r.velocity[block, 0])
    assert m.point_data["velocity"][:, :2] == pytest.approx(r.vertex_velocity(A))
    assert m.points[:, :2] == pytest.approx(A.vertices)


def test_contacts_csv_and_vtu_hold_the_static_dual(solved, tmp_path):
    A, r = solved
    # written by the one writer of result tables (as a run writes blocks_contacts.csv)
    path = report.write(tmp_path / "blocks_contacts.csv", contact_records(A, r))
    assert path.read_text().splitlines()[0] == (
        "interface,end,block_a,block_b,x [m],z [m],n_x [-],n_z [-],N [N],T [N],"
        "opening [m/s],slip [m/s],state")
    rows = report.read_csv(path)
    assert len(rows) == 2 * int(r.active.sum())
    # the ground carries the whole weight: sum of N over the base joints (normal +z)
    base = [row for row in rows if row["block_a"] == 0]
    assert sum(row["N"] for row in base) == pytest.approx(A.mass.sum() * 9.81, rel=1e-6)
    # and resists the live load λ m g towards −x: the force on the wall is T t, t = (−1, 0)
    assert sum(-row["T"] for row in base) == pytest.approx(
        r.multiplier * A.mass.sum() * 9.81, rel=1e-6)
    assert {row["state"] for row in rows} <= {"closed", "open", "sliding"}
    m = meshio.read(write_contacts_vtu(tmp_path / "c.vtu", A, r))
    assert len(m.cells[0].data) == int(r.active.sum())
    assert m.point_data["normal_force"] == pytest.approx(
        np.array([float(row["N"]) for row in contact_records(A, r)]))


def test_mechanism_png(solved, tmp_path):
    A, r = solved
    p = plot_blocks_mechanism(tmp_path / "m.png", A, r, r.moving, (0.0, 1.0))
    assert p.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_front_door_entry_point_writes_every_file(tmp_path):
    an = analyse_blocks(SMALL, step=2)
    scan_vg = [r["vg"] for r in an.scan if np.isfinite(r["vg"])]
    assert an.critical["vg"] == min(scan_vg)
    assert an.whole_record["multiplier"] == an.whole.multiplier
    assert an.critical_impulse.vg == pytest.approx(an.critical["vg"], rel=1e-12)
    # the scan agrees with an independent call
    again = h_scan_blocks(SMALL, step=2)
    assert [r["multiplier"] for r in again] == pytest.approx([r["multiplier"] for r in an.scan],
                                                             rel=1e-9)
    # every file through the one writer of result files, by suffix
    paths = [report.write(tmp_path / name, data) for name, data in an.files().items()]
    names = sorted(p.name for p in paths)
    assert names == sorted(["blocks.vtu", "blocks_contacts.vtu", "blocks_contacts.csv",
                            "blocks_mechanism.png", "blocks_whole.png", "blocks_scan.csv"])
    assert all(p.stat().st_size > 0 for p in paths)
    side = json.loads((tmp_path / "blocks_contacts.csv.json").read_text())
    assert side["units"]["N [N]"] == "N"
    summary = an.summary()
    assert summary["critical"]["vnorm"] == pytest.approx(an.critical["vnorm"])
    assert summary["settings"]["facade"] == "through"


def test_bad_input(solved, tmp_path):
    A, r = solved
    with pytest.raises(ParameterError, match="assembly, result"):
        write_blocks_vtu(tmp_path / "x.vtu", A, None)
    with pytest.raises(ParameterError, match="case"):
        analyse_blocks("B1")
    with pytest.raises(ParameterError, match="step = 0"):
        h_scan_blocks(SMALL, step=0)
    with pytest.raises(ParameterError, match=r"tests = \['B9'\]"):
        table1_blocks(tests=["B1", "B9"])
    assert not (tmp_path / "x.vtu").exists()
