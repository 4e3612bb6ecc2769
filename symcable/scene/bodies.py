"""Rigid bodies of a scene of several lines (scene version 2, ``[bodies.NAME]``; the README's
"A scene file"), and the line ends attached to them (``"NAME"`` or ``"NAME@[x, y, z]"``).

A body is six degrees of freedom: a reference point (``position``, where lines attach by
default) and an orientation (``orientation`` = [roll, pitch, yaw], degrees: the rotation
R = Rz(yaw) Ry(pitch) Rx(roll) from body axes to global axes, MoorPy's convention). Its
mass acts at the centre of gravity, its buoyancy (the body is taken as submerged wherever
it is) and its drag and added mass at the centre of buoyancy, both given in body axes
relative to the reference point. ``kind = "fixed"`` holds it where the scene puts it (the
lines attached to it are then held at its points, as at fixed points); ``kind = "vessel"``
moves it by a given motion in six degrees of freedom about that pose (:mod:`.vessel`), the
lines' ends following its points.

The reader is :func:`symcable.scene.system.read_bodies`; this module is the dataclasses
only. Units are SI; vectors are (x, y, z), z up.
"""
from __future__ import annotations

import enum
import math
from dataclasses import dataclass
from typing import Any

import numpy as np

__all__ = ["Body", "BodyEnd", "BodyKind", "body_dict", "rotation_rpy"]


class BodyKind(str, enum.Enum):
    """How a body moves."""

    FREE = "free"    #: solved for: six degrees of freedom
    FIXED = "fixed"  #: held at its position and orientation
    VESSEL = "vessel"  #: moved by a given motion in six degrees of freedom (.vessel)


def rotation_rpy(roll_pitch_yaw_deg) -> np.ndarray:
    """(3, 3) the rotation from body axes to global axes of ``[roll, pitch, yaw]`` (degrees):
    R = Rz(yaw) Ry(pitch) Rx(roll) (the z-y'-x'' convention of MoorPy's ``rotationMatrix``)."""
    r, p, y = (math.radians(a) for a in roll_pitch_yaw_deg)
    cr, sr, cp, sp, cy, sy = math.cos(r), math.sin(r), math.cos(p), math.sin(p), \
        math.cos(y), math.sin(y)
    return np.array([[cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
                     [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
                     [-sp, cp * sr, cp * cr]])


@dataclass(frozen=True)
class Body:
    """A rigid body (``[bodies.NAME]``).

    Attributes
    ----------
    name : str
    kind : BodyKind
    position : tuple of float
        m, global (x, y, z) of the reference point: where a fixed body is held, where a
        free body starts (its static pose is solved for).
    orientation_deg : tuple of float
        [roll, pitch, yaw], degrees (:func:`rotation_rpy`); the starting orientation of a
        free body.
    mass : float
        kg (> 0), at the centre of gravity (free bodies).
    inertia : tuple of float
        [Ixx, Iyy, Izz], kg m^2 (> 0), about body axes through the centre of gravity.
    volume : float
        Displaced volume, m^3 (>= 0): buoyancy rho g volume at the centre of buoyancy.
    center_of_gravity, center_of_buoyancy : tuple of float
        m, body axes, relative to the reference point (default zeros).
    cd_area : tuple of float
        Drag coefficient times area along body axes, m^2 (>= 0, MoorDyn's CdA): the drag
        along body axis i is 0.5 rho cd_area_i |u| u_i at the centre of buoyancy, u the
        water's velocity relative to that point in body axes.
    ca_volume : tuple of float
        Added-mass volumes along body axes, m^3 (>= 0, the added-mass coefficient times
        the volume): added mass rho ca_volume_i along body axis i, at the centre of buoyancy.
    motion : BodyMotion or None
        A vessel's motion in six degrees of freedom about its pose
        (:class:`~symcable.scene.vessel.BodyMotion`).
    """

    name: str
    kind: BodyKind
    position: tuple[float, ...]
    orientation_deg: tuple[float, ...] = (0.0, 0.0, 0.0)
    mass: float = 0.0
    inertia: tuple[float, ...] = (0.0, 0.0, 0.0)
    volume: float = 0.0
    center_of_gravity: tuple[float, ...] = (0.0, 0.0, 0.0)
    center_of_buoyancy: tuple[float, ...] = (0.0, 0.0, 0.0)
    cd_area: tuple[float, ...] = (0.0, 0.0, 0.0)
    ca_volume: tuple[float, ...] = (0.0, 0.0, 0.0)
    motion: Any = None

    @property
    def is_free(self) -> bool:
        return self.kind is BodyKind.FREE

    @property
    def rotation(self) -> np.ndarray:
        """(3, 3) body axes to global axes at the scene's orientation."""
        return rotation_rpy(self.orientation_deg)

    def world(self, offset) -> np.ndarray:
        """(3,) m: the global position of the body point ``offset`` (body axes, m) at the
        scene's pose."""
        return np.asarray(self.position, float) + self.rotation @ np.asarray(offset, float)


@dataclass(frozen=True)
class BodyEnd:
    """A line's end attached to a body: at the point ``offset`` (m, body axes, relative to
    the reference point) of body ``body``. Written ``"NAME"`` (offset zero: the reference
    point) or ``"NAME@[x, y, z]"`` in a scene file."""

    body: str
    offset: tuple[float, ...] = (0.0, 0.0, 0.0)

    @property
    def text(self) -> str:
        """The end as a scene file writes it."""
        if not any(self.offset):
            return self.body
        return f"{self.body}@[{', '.join(repr(float(x)) for x in self.offset)}]"


def body_dict(body: Body) -> dict:
    """A body's table, every key that applies written out (so it loads back equal)."""
    out = {"kind": BodyKind(body.kind).value, "position": list(body.position),
           "orientation": list(body.orientation_deg)}
    if body.is_free:
        out.update(mass=body.mass, inertia=list(body.inertia), volume=body.volume,
                   center_of_gravity=list(body.center_of_gravity),
                   center_of_buoyancy=list(body.center_of_buoyancy),
                   cd_area=list(body.cd_area), ca_volume=list(body.ca_volume))
    if body.motion is not None:
        out["motion"] = body.motion.to_dict()
    return out
