"""The rod and hybrid cases of the work-precision and stability studies (run_rod.py in
studies/work_precision/ and studies/stability/): scene dicts, and the straight start of seed
000's relaxation (studies are scripts: each loads this file by path).

Cases (SI units throughout):

* ``cantilever``: tests/test_rod_api.py's rod, 2 m clamped at 0.7 rad in plan, two principal
  stiffnesses EI = [10, 20] N m^2, GJ 7 N m^2, 1 kg/m, 2.5 N/m of weight, EA 2.5e4 N
  (inextensible to 1e-4), in air, 8 segments, damped (material damping 5), its clamp heaving
  2 cm at T = 1 s;
* ``hose``: tests/test_hybrid.py's taut hose (10 m, 100 N of weight, pinned 9.9 m apart,
  140-190 N of tension, EI 1 N m^2, GJ 0.8 N m^2), three sections of 6 segments:
  cable3d, rod, cable3d (``model = "hybrid"``) or all rod; end B heaving 5 cm at T = 2 s;
* ``seed``: seed 000's benchmark (Table 1: 2 m, D = 1 mm, pinned at the origin, end B guided
  30 deg below the horizontal with 0.01 N normal to it), at ``n`` segments, pure rod or
  hybrid (rod on the last quarter, the seed's joint at s = 1.5 m);
* ``hanging``: a rod hanging from a pinned top, its lower end free (tension falling to zero
  there), the top heaving;
* ``greenhill``: tests/test_rod_greenhill.py's straight rod clamped at both ends (B = 1,
  GJ = 5, L = 1), end B's frame turned to a fraction of Greenhill's moment 8.98682 B / L.
"""
from __future__ import annotations

import math

import numpy as np

GREENHILL = 8.98682  # M L / B, clamped-clamped, no tension


def cantilever(segments: int = 8, period: float = 1.0, heave: float = 0.02,
               damping: float = 5.0, EI: float = 10.0) -> dict:
    L = 2.0
    return {"model": "rod", "name": f"rod cantilever ({segments} segments)",
            "environment": {"water_density": 0.0},
            "line_types": {"beam": {"EA": 1e4 * 10.0 / L**2, "EI": [EI, 2 * EI], "GJ": 0.7 * EI,
                                    "mass": 1.0, "diameter": 0.02, "weight": 2.0 * 10.0 / L**3,
                                    "damping": damping}},
            "sections": [{"type": "beam", "length": L, "segments": segments}],
            "end_a": {"condition": "clamped", "position": [0.0, 0.0, 0.0],
                      "direction": [math.cos(0.7), math.sin(0.7), 0.0], "twist_deg": 30.0,
                      "motion": {"kind": "harmonic", "amplitude": [0.0, 0.0, heave],
                                 "period": period}},
            "end_b": {"condition": "free"}}


def hose(model: str = "hybrid", period: float = 2.0, heave: float = 0.05, EI: float = 1.0,
         segments: int = 6) -> dict:
    sections = {"hybrid": ("cable3d", "rod", "cable3d"), "rod": (None, None, None)}[model]
    lt = {"EA": 1e5, "EI": EI, "GJ": 0.8 * EI, "mass": 2.0, "diameter": 0.05, "weight": 10.0}
    secs = [dict({"type": "hose", "length": 10.0 / 3, "segments": segments},
                 **({"model": m} if m else {})) for m in sections]
    return {"model": model, "name": f"taut hose ({model}, EI {EI:g})",
            "environment": {"water_density": 0.0},
            "line_types": {"hose": lt}, "sections": secs,
            "end_a": {"condition": "pinned", "position": [0.0, 0.0, 0.0]},
            "end_b": {"condition": "pinned", "position": [8.0, 3.0, 5.0],
                      "motion": {"kind": "harmonic", "amplitude": [0.0, 0.0, heave],
                                 "period": period}}}


SEED_DIRECTION = (math.sqrt(3) / 2, 0.0, -0.5)


def seed(n: int = 20, hybrid: bool = False) -> dict:
    """Seed 000's benchmark (tests/test_hybrid.py's ``seed``), n segments; hybrid: cable3d
    on the first 3/4 (with the cable's bending), rod on the last quarter."""
    lt = {"EA": 3926.990816987241, "EI": 2.454369260617026e-4, "GJ": 1.9634954084936207e-4,
          "mass": 7.853981633974483e-4, "diameter": 1e-3, "cd_normal": 1.0,
          "cd_tangential": math.pi * 0.1, "ca_normal": 0.0}
    d = {"model": "hybrid" if hybrid else "rod",
         "name": f"seed 000 benchmark ({'hybrid' if hybrid else 'rod'}, {n} segments)",
         "environment": {"gravity": 9.8, "water_density": 1.0},
         "line_types": {"cable": lt},
         "sections": [{"type": "cable", "length": 2.0, "segments": n}],
         "end_a": {"condition": "pinned", "position": [0.0, 0.0, 0.0]},
         "end_b": {"condition": "guided", "direction": list(SEED_DIRECTION),
                   "force": [0.005, 0.0, 0.005 * math.sqrt(3)]}}
    if hybrid:
        k = (3 * n) // 4
        d["sections"] = [{"type": "cable", "length": 2.0 * k / n, "segments": k,
                          "model": "cable3d"},
                         {"type": "cable", "length": 2.0 * (n - k) / n, "segments": n - k,
                          "model": "rod"}]
    return d


def hanging(segments: int = 12, heave: float = 0.05, period: float = 2.0,
            EI: float = 1.0, hybrid: bool = False) -> dict:
    """A 5 m rod (2 kg/m, 10 N/m of weight, EI 1, GJ 0.8) hanging from a pinned top, its
    lower end free: the tension falls from 50 N at the top to zero at the end; bending
    length sqrt(EI / T) = 0.14 m at the top, the whole rod's length near the end; the top
    moved 5 cm in x and 2.5 cm in y at T = 2 s. ``hybrid``: cable3d on the upper 3/4, rod
    on the lowest quarter (where the tension vanishes)."""
    lt = {"EA": 1e5, "EI": EI, "GJ": 0.8 * EI, "mass": 2.0, "diameter": 0.05, "weight": 10.0}
    secs = [{"type": "hose", "length": 5.0, "segments": segments}]
    if hybrid:
        k = (3 * segments) // 4
        secs = [{"type": "hose", "length": 5.0 * k / segments, "segments": k, "model": "cable3d"},
                {"type": "hose", "length": 5.0 * (segments - k) / segments,
                 "segments": segments - k, "model": "rod"}]
    return {"model": "hybrid" if hybrid else "rod",
            "name": f"hanging {'hybrid' if hybrid else 'rod'} ({segments} segments)",
            "environment": {"water_density": 0.0},
            "line_types": {"hose": lt},
            "sections": secs,
            "end_a": {"condition": "pinned", "position": [0.0, 0.0, 0.0],
                      "motion": {"kind": "harmonic", "amplitude": [heave, 0.5 * heave, 0.0],
                                 "period": period}},
            "end_b": {"condition": "free"}}


def greenhill(segments: int = 20, fraction: float = 0.95, kick: float = 0.01) -> dict:
    """tests/test_rod_greenhill.py's rod (B = 1, GJ = 5, L = 1 m, 1 kg/m, in air), end B's
    frame turned by Phi = M L / GJ with M = fraction x 8.98682 B / L; end A moved sideways
    by ``kick`` m over 0.1 s and back (a table-free harmonic: one period of 0.2 s would
    keep shaking, so a small sideways sine of period 1 s is used)."""
    B, GJ, L = 1.0, 5.0, 1.0
    M = fraction * GREENHILL * B / L
    d = {"model": "rod", "name": f"twisted rod at {fraction:g} of Greenhill ({segments} segments)",
         "environment": {"water_density": 0.0},
         "line_types": {"r": {"EA": 1e6, "EI": B, "GJ": GJ, "mass": 1.0, "diameter": 0.01,
                              "weight": 0.0}},
         "sections": [{"type": "r", "length": L, "segments": segments}],
         "end_a": {"condition": "clamped", "position": [0.0, 0.0, 0.0],
                   "direction": [1.0, 0.0, 0.0]},
         "end_b": {"condition": "clamped", "position": [L, 0.0, 0.0],
                   "direction": [1.0, 0.0, 0.0], "twist_deg": math.degrees(M * L / GJ)}}
    if kick:
        d["end_a"]["motion"] = {"kind": "harmonic", "amplitude": [0.0, kick, 0.0],
                                "period": 1.0}
    return d


def straight_start(mech, eq, direction=SEED_DIRECTION, length: float = 2.0) -> np.ndarray:
    """q of the line straight from the origin along ``direction`` (the seed's initial state),
    every twist 0, the other coordinates as in ``eq.q``: node i's coordinates are named
    ``node{i}.x/y/z`` by the Mechanism (``coordinate_names``)."""
    q = np.array(eq.q, float)
    names, _ = mech.coordinate_names()
    n = len(mech.layout.parts["line"].s) - 1
    for k, name in enumerate(names):
        head, _, axis = name.rpartition(".")
        if head.startswith("node") and axis in "xyz" and head[4:].isdigit():
            q[k] = length * int(head[4:]) / n * direction["xyz".index(axis)]
        elif not head.startswith("node"):
            q[k] = 0.0
    return q
