"""The openings' checks of a case that depend on the models it asks for: the models that do
not take an opening yet, and the FE settings that cannot take the transversal wall's holes
and their rigid lintels (docs/real-walls.md "Openings"). The openings' own checks against the
wall and each other: ``params.opening_problems``."""

from __future__ import annotations

from typing import Any

from ..blocks.geometry import course_levels, open_courses
from ..errors import ParameterError
from ..geometry import TSection, lintel_boxes
from ..params import opening_problems

__all__ = ["OPENINGS_REFUSED", "openings_refused"]

#: the models that do not take an opening yet: (array, [analysis] key) → what says so
OPENINGS_REFUSED = {("wall_opening", "dem"): "the DEM"}


def openings_refused(v: dict[str, Any], an: dict[str, Any]) -> list[str]:
    """An opening given with a model that does not take it (``OPENINGS_REFUSED``), and the
    FE settings that cannot take the wall's holes and rigid lintels."""
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
    model = "fe" if an.get("fe") else "blocks"
    if holes and an.get(model) and all(k in w for k in "HbL") and all(k in m for k in "ac") \
            and all(all(k in e for k in keys) for e in v["wall_opening"]) \
            and not opening_problems(w["H"], w["b"], w["L"], (), v["wall_opening"]):
        boxes = tuple((e["x"], e["x"] + e["width"], e["z"], e["z"] + e["height"])
                      for e in v["wall_opening"])
        try:
            TSection(w["H"], w["b"], w["L"], holes=boxes, lintels=lintel_boxes(
                boxes, w["H"], w["b"], w["L"], m["a"], m["c"]))
            if an.get("blocks"):
                for k, box in enumerate(boxes):
                    open_courses(course_levels(w["H"], m["a"]), box, k)
        except ParameterError as e:
            out.append(f"[[wall_opening]] with [analysis] {model} = true: {e}")
    return out + [f"[[{arr}]] ({len(v[arr])} entries) with [analysis] {model} = true: {what} "
                  f"does not take a {arr.replace('_', ' ')} yet; allowed [analysis] {model} = "
                  "false with it (docs/real-walls.md \"Openings\")"
                  for (arr, model), what in OPENINGS_REFUSED.items()
                  if v.get(arr) and an.get(model)]
