"""The planar line as the nonlinear 3D cable in its plane: the stand-in for dynamics the
linearised planar model cannot represent.

The planar dynamics are the model of Boral, Hickey & Basu, linearised about the static
state, with no seabed contact. A planar scene whose static line rests on the seabed still
has dynamics: the same line as a ``model = "cable3d"`` scene in the x-z plane (y = 0), whose
element is nonlinear and carries seabed contact and friction. Its statics agree with the
planar solve's to the discretisation (both are the same elastic catenary on the same
segments).
"""
from __future__ import annotations

import copy

from ...errors import SceneError
from ...scene import Scene, load_scene
from .dynamics import grounded_tolerance

__all__ = ["as_cable3d", "nonlinear_stand_in"]

#: end keys holding a planar vector [x, z] (m, N, or per-component motion data)
_END_VECTORS = ("position", "force")
_MOTION_VECTORS = ("amplitude", "phase_deg")


def _lift(v) -> list:
    """A planar vector [x, z] as [x, 0, z]."""
    return [float(v[0]), 0.0, float(v[1])]


def as_cable3d(scene: Scene) -> Scene:
    """The planar ``scene`` as a ``model = "cable3d"`` scene in the x-z plane: every
    position, force, current and motion vector [x, z] becomes [x, 0, z]; the line types,
    sections, seabed and name are kept.

    Raises
    ------
    SceneError
        A planar key the 3D cable does not read (a clamped end's ``angle_deg``), naming it.
    """
    data = copy.deepcopy(scene.to_dict())
    data["model"] = "cable3d"
    for lt in data.get("line_types", {}).values():  # a family's 3D tangential added mass
        if "family" in lt:                          # is not the planar line's
            lt.setdefault("ca_tangential", 0.0)
    env = data.get("environment", {})
    if "current" in env:
        env["current"] = _lift(env["current"])
    for name in ("end_a", "end_b"):
        end = data[name]
        if end.get("angle_deg") is not None:
            raise SceneError(f"{name}.angle_deg = {end['angle_deg']!r} deg: a clamped end of "
                             "the planar line has no stand-in in the 3D cable here; give "
                             'model = "cable3d" with direction = [t_x, t_y, t_z]')
        for key in _END_VECTORS:
            if end.get(key) is not None:
                end[key] = _lift(end[key])
        motion = end.get("motion")
        if motion is not None:
            for key in _MOTION_VECTORS:
                if motion.get(key) is not None:
                    motion[key] = _lift(motion[key])
    return load_scene(data)


def nonlinear_stand_in(scene: Scene, static) -> Scene | None:
    """The scene the dynamic analyses of the planar ``scene`` run: None when its linearised
    dynamics represent it about ``static`` (its StaticSolution), else
    :func:`as_cable3d` of it: a static line resting on the seabed (grounded length over
    :func:`~.dynamics.grounded_tolerance`)."""
    if scene.seabed is None or static.status != "converged":
        return None
    if static.grounded_length <= grounded_tolerance(scene):
        return None
    return as_cable3d(scene)
