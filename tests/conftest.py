"""Shared scene builders for the tests (plain dicts in the scene-file layout)."""
from __future__ import annotations

import copy

import pytest

OC3 = {
    "name": "OC3 line",
    "model": "planar",
    "environment": {"water_density": 1025.0, "depth": 320.0},
    "seabed": {"stiffness": 1.0e5},
    "line_types": {"chain": {"EA": 3.84243e8, "mass": 77.7066, "diameter": 0.09,
                             "weight": 698.094, "cd_normal": 1.6, "cd_tangential": 0.1}},
    "sections": [{"type": "chain", "length": 902.2, "segments": 50}],
    "end_a": {"condition": "pinned", "position": [-853.87, -320.0]},
    "end_b": {"condition": "pinned", "position": [-5.2, -70.0]},
}


def two_point(a, b, *, length=100.0, segments=40, EA=1e7, weight=100.0, EI=0.0,
              depth=None, stiffness=None, **extra):
    """A single-section line pinned at a and b; weight given directly (N/m)."""
    d = {
        "name": "two-point line",
        "environment": {"water_density": 1025.0},
        "line_types": {"rope": {"EA": EA, "EI": EI, "mass": 20.0, "diameter": 0.05, "weight": weight}},
        "sections": [{"type": "rope", "length": length, "segments": segments}],
        "end_a": {"condition": "pinned", "position": list(a)},
        "end_b": {"condition": "pinned", "position": list(b)},
    }
    if depth is not None:
        d["environment"]["depth"] = depth
        d["seabed"] = {"stiffness": stiffness or 1e5}
    for k, v in extra.items():
        d[k] = v
    return d


@pytest.fixture
def oc3():
    return copy.deepcopy(OC3)
