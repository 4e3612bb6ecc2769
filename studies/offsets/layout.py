"""The study's moored body, as a symcable scene and as a MoorPy System: the OC3 spar's three
catenary chains (Jonkman 2010: 320 m depth, anchors at 853.87 m radius, fairleads at 5.2 m
radius and 70 m below the water line, 902.2 m of chain of 77.7066 kg/m, 0.09 m, EA 384.243
MN, the lines at 120 degrees), on a body held at the origin (the spar's reference point at
the water line). The body is ``kind = "fixed"``: symcable has no waterplane stiffness, so
the sweep is of the lines' restoring force alone (MoorPy's ``getForces(lines_only=True)``),
about where the scene puts the body."""
from __future__ import annotations

import math

import numpy as np

RHO, G, DEPTH = 1025.0, 9.80665, 320.0
R_ANCHOR, R_FAIR, Z_FAIR, LENGTH = 853.87, 5.2, -70.0, 902.2
CHAIN = {"mass": 77.7066, "diameter": 0.09, "EA": 384.243e6}


def scene(segments: int) -> dict:
    """The symcable scene (dict) with ``segments`` per line."""
    points, lines = {}, []
    for k in range(3):
        th = math.radians(180 + 120 * k)
        points[f"anchor{k}"] = {"kind": "fixed", "position": [R_ANCHOR * math.cos(th),
                                                             R_ANCHOR * math.sin(th), -DEPTH]}
        lines.append({"name": f"line{k}", "end_a": f"anchor{k}",
                      "end_b": f"spar@[{R_FAIR * math.cos(th)}, {R_FAIR * math.sin(th)}, {Z_FAIR}]",
                      "sections": [{"type": "chain", "length": LENGTH, "segments": segments}]})
    return {"name": "oc3-lines", "model": "cable3d",
            "environment": {"depth": DEPTH, "gravity": G, "water_density": RHO},
            "seabed": {"stiffness": 1e8}, "line_types": {"chain": CHAIN}, "points": points,
            "bodies": {"spar": {"kind": "fixed", "position": [0.0, 0.0, 0.0]}},
            "lines": lines}


def moorpy_system():
    """(System, body): MoorPy's elastic catenaries (no seabed friction), the body coupled."""
    import moorpy as mp

    ms = mp.System(depth=DEPTH, rho=RHO, g=G)
    w = (CHAIN["mass"] - RHO * math.pi * CHAIN["diameter"] ** 2 / 4) * G
    ms.setLineType(name="chain", mass=CHAIN["mass"], d_vol=CHAIN["diameter"], EA=CHAIN["EA"],
                   w=w, dnommm=90)
    body = ms.addBody(-1, [0, 0, 0, 0, 0, 0])
    for k in range(3):
        th = math.radians(180 + 120 * k)
        ms.addPoint(1, [R_ANCHOR * math.cos(th), R_ANCHOR * math.sin(th), -DEPTH])
        ms.addPoint(1, [R_FAIR * math.cos(th), R_FAIR * math.sin(th), Z_FAIR], body=1)
        ms.addLine(LENGTH, "chain", pointA=2 * k + 1, pointB=2 * k + 2)
    ms.initialize()
    return ms, body


def moorpy_offset(ms, body, offset) -> np.ndarray:
    """(6,) the lines' force and moment on the body at ``offset`` (m, deg): MoorPy's
    setPosition, each line's staticSolve, getForces(lines_only=True)."""
    o = np.asarray(offset, float)
    body.setPosition(np.r_[o[:3], np.radians(o[3:])])
    for ln in ms.lineList:
        ln.staticSolve()
    return body.getForces(lines_only=True)
