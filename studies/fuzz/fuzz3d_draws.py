"""Random draws in 3D for the fuzz study's cable3d scenes (:mod:`fuzz3d_scenes`): directions,
end positions, the seabed (stiffness, friction) and the current."""
from __future__ import annotations

import math

import numpy as np

from fuzz_draws import log_uniform

def sphere(rng) -> np.ndarray:
    v = rng.normal(size=3)
    return v / np.linalg.norm(v)


def horizontal(phi: float) -> np.ndarray:
    return np.array([math.cos(phi), math.sin(phi), 0.0])


def origin3(rng) -> np.ndarray:
    return np.array([rng.uniform(-1000.0, 1000.0), rng.uniform(-1000.0, 1000.0),
                     rng.uniform(-500.0, 0.0)])


def pinned3(p) -> dict:
    return {"condition": "pinned", "position": [float(v) for v in p]}


def seabed3(rng, depth: float) -> dict:
    """``environment.depth`` and a ``[seabed]``: stiffness drawn (70 %) or default; friction
    in half the scenes, isotropic or axial/lateral apart (statics must not depend on it)."""
    sb = {}
    if rng.uniform() < 0.7:
        sb["stiffness"] = log_uniform(rng, 1e4, 1e7)
    u = rng.uniform()
    if u < 0.3:
        sb["friction"] = rng.uniform(0.1, 1.2)
    elif u < 0.5:
        sb["friction_axial"] = rng.uniform(0.1, 1.0)
        sb["friction_lateral"] = rng.uniform(0.3, 1.5)
    return {"environment": {"depth": float(depth)}, "seabed": sb}


def current3(rng, plane: np.ndarray | None) -> list:
    """A uniform current, 0.1-2 m/s: along the horizontal direction ``plane`` (in the ends'
    vertical plane) or at any azimuth (oblique) when ``plane`` is None; a vertical component
    in 30 %."""
    speed = rng.uniform(0.1, 2.0) * rng.choice([-1.0, 1.0])
    d = plane if plane is not None else horizontal(rng.uniform(-math.pi, math.pi))
    u = speed * d
    if rng.uniform() < 0.3:
        u[2] = rng.uniform(-0.2, 0.2)
    return [float(v) for v in u]


def one_line(types, secs, a, b, **extra) -> dict:
    scene = {"line_types": types, "sections": secs, "end_a": a, "end_b": b}
    for k, v in extra.items():
        if k == "environment" and "environment" in scene:
            scene["environment"].update(v)
        else:
            scene[k] = v
    return scene
