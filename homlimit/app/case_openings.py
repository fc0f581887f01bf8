"""The openings' checks of a case that depend on the models it asks for: the FE settings that
cannot take the transversal wall's holes and their rigid lintels, an opening with no course
above it for the blocks' lintel, and a jamb that leaves the DEM a piece of block narrower than
its contact detection takes (docs/real-walls.md "Openings"). The openings' own checks against
the wall and each other: ``params.opening_problems``."""

from __future__ import annotations

from typing import Any

from ..blocks.geometry import course_blocks
from ..dem.params import DEMParams
from ..errors import ParameterError
from ..geometry import TSection, lintel_boxes
from ..params import opening_problems

__all__ = ["openings_refused"]


def openings_refused(v: dict[str, Any], an: dict[str, Any]) -> list[str]:
    """The FE settings that cannot take the wall's holes and rigid lintels, the openings the
    block models cannot cut (no course above for the lintel), and the jamb pieces too narrow
    for the DEM (``_dem_pieces``)."""
    holes = len(v.get("wall_opening") or ())
    me = v.get("mesh", {})
    out = [f"[[wall_opening]] ({holes} entries) with [mesh] mesher = \"crossed\": the "
           "crossed grid does not cut holes; allowed mesher = \"gmsh\" or \"gmsh-strip\""
           for _ in [0] if holes and an.get("fe") and me.get("mesher") == "crossed"]
    out += [f"[[wall_opening]] ({holes} entries) with [analysis] stress_degree = 2: the "
            "openings' rigid lintels take linear stresses only; allowed stress_degree = 1"
            for _ in [0] if holes and an.get("fe") and an.get("stress_degree") == 2]
    w, m = v.get("wall", {}), v.get("masonry", {})
    keys = ("x", "z", "width", "height")
    model = next((k for k in ("fe", "blocks", "dem") if an.get(k)), None)
    if not (holes and model and all(k in w for k in "HbL") and all(k in m for k in "ac")
            and all(all(k in e for k in keys) for e in v["wall_opening"])
            and not opening_problems(w["H"], w["b"], w["L"], (), v["wall_opening"])):
        return out
    boxes = tuple((e["x"], e["x"] + e["width"], e["z"], e["z"] + e["height"])
                  for e in v["wall_opening"])
    try:
        geo = TSection(w["H"], w["b"], w["L"], holes=boxes, lintels=lintel_boxes(
            boxes, w["H"], w["b"], w["L"], m["a"], m["c"]))
        if an.get("blocks") or an.get("dem"):     # the same assembly (t_section_blocks)
            _, _, _, _, narrow = course_blocks(geo, m["a"], m["c"])
            if an.get("dem"):
                out += _dem_pieces(v, narrow)
    except ParameterError as e:
        out.append(f"[[wall_opening]] with [analysis] {model} = true: {e}")
    return out


def _dem_pieces(v: dict[str, Any], narrow) -> list[str]:
    """A wall opening whose jamb cuts a block of the DEM's assembly leaving a piece no wider
    than [dem] verlet_margin: the Verlet list's contact detection does not hold such a block
    (measured: 2, 4 mm pieces fell out of the wall while settling at 5 mm, a 4 mm one stood at
    2 mm, an 8 mm one fell at 10 mm; docs/dem.md "Openings")."""
    margin = v.get("dem", {}).get("verlet_margin", DEMParams().verlet_margin)
    if not isinstance(margin, (int, float)):        # reported by its own check
        return []
    return [f"[[wall_opening]] {k} (x {e['x']:g}..{e['x'] + e['width']:g} m) with [analysis] "
            f"dem = true: a jamb cuts a block leaving a piece {1e3 * n:.3g} mm wide: out of "
            f"range: allowed pieces wider than [dem] verlet_margin = {margin:g} m (move the "
            "jamb onto the course's joint or away from it)"
            for k, (e, n) in enumerate(zip(v["wall_opening"], narrow)) if n <= margin]
