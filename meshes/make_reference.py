"""Regenerate the small reference meshes of the Table 1 T-sections kept in meshes/ for the tests.

    python meshes/make_reference.py

Each file is the x–z section (façade 0 <= x <= b, transversal wall b <= x <= b + L, height H)
meshed by homlimit.fe.geometry.tsection and written by homlimit.fe.mesh.write as gmsh 2.2 ASCII with
physical groups facade, wall, base, outer, top, end, junction.
"""

from pathlib import Path

from homlimit.fe.geometry import tsection
from homlimit.fe.mesh import write

HERE = Path(__file__).resolve().parent

# name: (H, b, L) from Table 1 of the paper [m]; mesh sizes [m]
REFERENCE = {
    "tsection_B1_coarse": dict(H=9.0, b=0.50, L=6.0, size=0.75, size_junction=0.25,
                               size_top=0.25),
    "tsection_B4_coarse": dict(H=9.0, b=0.25, L=6.0, size=0.75, size_junction=0.25,
                               size_top=0.25),
}

if __name__ == "__main__":
    for name, kw in REFERENCE.items():
        path = write(tsection(**kw), HERE / f"{name}.msh")
        print(f"{path.name}: {kw}")
