"""The design study's mooring: a floating body (an OC3-like spar's fairleads, 5.2 m radius,
70 m below the water line) on three studless R4 chains in 200 m of water, lines at 180,
300 and 60 degrees; per line the design variables are its length, its chain's nominal
diameter and its anchor radius. The body is held (``kind = "fixed"``) at the prescribed
offset of each load case."""
from __future__ import annotations

import math

DEPTH, R_FAIR, Z_FAIR = 200.0, 5.2, -70.0
HEADINGS = (180.0, 300.0, 60.0)  # deg, each line's direction from the body to its anchor


def scene(lengths=(560.0,) * 3, diameters=(0.1,) * 3, radii=(520.0,) * 3, offset=(0.0, 0.0),
          segments: int = 20) -> dict:
    """The scene (dict) with the given per-line variables (m, m, m) and the body's offset
    (m, x and y)."""
    points, lines, types = {}, [], {}
    for k, th in enumerate(HEADINGS):
        c, s = math.cos(math.radians(th)), math.sin(math.radians(th))
        types[f"chain{k}"] = {"family": "studless_chain", "nominal_diameter": diameters[k],
                              "grade": "R4"}
        points[f"anchor{k}"] = {"kind": "fixed", "position": [radii[k] * c, radii[k] * s,
                                                             -DEPTH]}
        lines.append({"name": f"line{k}", "end_a": f"anchor{k}",
                      "end_b": f"hull@[{R_FAIR * c}, {R_FAIR * s}, {Z_FAIR}]",
                      "sections": [{"type": f"chain{k}", "length": lengths[k],
                                    "segments": segments}]})
    return {"name": "design", "model": "cable3d",
            "environment": {"depth": DEPTH},
            "seabed": {"stiffness": 1e6}, "line_types": types, "points": points,
            "bodies": {"hull": {"kind": "fixed", "position": [offset[0], offset[1], 0.0]}},
            "lines": lines}
