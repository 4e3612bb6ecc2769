"""A motion table given to a loaded scene (``symcable simulate SCENE --motion FILE``): the
scene's fairlead end, its body or its vessel points moved by rows ``t x y z [roll pitch
yaw]`` (s, m, deg)."""
from __future__ import annotations

import os

import numpy as np

from ..errors import SceneError
from .bodies import BodyEnd, BodyKind
from .load import load_scene
from .model import Scene

__all__ = ["with_motion"]


def with_motion(scene: Scene, file: str, target: str | None = None) -> Scene:
    """``scene`` with the motion table ``file`` (rows t x y z [roll pitch yaw]; s, m, deg;
    displacements from the scene's pose) given to ``target``:

    - a one-line scene: its end B (``target`` None or ``"end_b"``; ``"end_a"``), which
      takes the translations (an end is a point);
    - a body (by name; None: the scene's one fixed or vessel body): made a vessel moved by
      the six columns about its reference point;
    - None in a scene of several lines without such a body: all its vessel points, made one
      vessel whose reference point is their horizontal centroid at z = 0 (a floater's
      fairleads moved by its six degrees of freedom); a point by name: that point alone,
      by the translations.

    Raises SceneError naming ``target`` when it is none of these."""
    path = os.path.abspath(os.path.expanduser(file))
    d = scene.to_dict()
    if scene.version == 1:
        key = target or "end_b"
        if key not in ("end_a", "end_b") or not getattr(scene, key).is_fixed:
            raise SceneError(f"--motion: {key!r} is not a held end of this one-line scene "
                             "(give end_a or end_b, pinned or clamped)")
        d[key]["motion"] = {"kind": "table", "file": path}
        return load_scene(d)
    held = [n for n, b in scene.bodies.items() if not b.is_free]
    vessels = [n for n, p in scene.points.items() if p.kind.value == "vessel"]
    if target is None:
        if len(held) == 1:
            target = held[0]
        elif not held and vessels:
            return load_scene(_points_on_a_vessel(d, vessels, path))
        else:
            raise SceneError(f"--motion: the scene has {len(held)} fixed or vessel bodies and "
                             f"{len(vessels)} vessel points: name the one to move "
                             f"(--moving NAME, one of {', '.join(held + vessels) or 'none'})")
    if target in scene.bodies:
        if scene.bodies[target].is_free:
            raise SceneError(f"--moving {target}: a free body's motion is solved for; move a "
                             "fixed body or a vessel point")
        d["bodies"][target].update(kind=BodyKind.VESSEL.value, motion={"kind": "table",
                                                                      "file": path})
        return load_scene(d)
    if target in scene.points and not scene.points[target].is_free:
        d["points"][target].update(kind="vessel", motion={"kind": "table", "file": path})
        return load_scene(d)
    raise SceneError(f"--moving {target!r}: not a fixed or vessel body or point of the scene "
                     f"(bodies: {', '.join(held) or 'none'}; points: "
                     f"{', '.join(n for n, p in scene.points.items() if not p.is_free) or 'none'})")


def _points_on_a_vessel(d: dict, names: list, path: str) -> dict:
    """The scene dict with the vessel points ``names`` made points of one vessel body."""
    pos = np.array([d["points"][n]["position"] for n in names], float)
    ref = np.array([pos[:, 0].mean(), pos[:, 1].mean(), 0.0])
    body = "vessel"
    while body in d.get("points", {}) or body in d.get("bodies", {}):
        body += "_"
    d.setdefault("bodies", {})[body] = {"kind": "vessel", "position": ref.tolist(),
                                        "motion": {"kind": "table", "file": path}}
    at = {n: BodyEnd(body, tuple(float(v) for v in p - ref)).text for n, p in zip(names, pos)}
    for line in d["lines"]:
        for key in ("end_a", "end_b"):
            if isinstance(line[key], str) and line[key] in at:
                line[key] = at[line[key]]
    for n in names:
        d["points"].pop(n)
    return d
