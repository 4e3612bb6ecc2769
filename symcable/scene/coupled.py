"""What a host program moves (:class:`symcable.Coupling`): the scene's coupled points, bodies
and ends, their degrees of freedom, and the scene with each coupled thing's line ends held
where the host puts them (:func:`coupled_scene`, their motion ``"coupled"``).

A coupled point (a fixed or vessel point of a version-2 scene, or a version-1 scene's held
end ``"end_a"`` / ``"end_b"``) has three degrees of freedom, its position x, y, z (m); a
coupled body (fixed or vessel) six, its reference point's position (m) and its roll, pitch
and yaw (rad, :func:`~symcable.scene.bodies.rotation_rpy`'s convention). Their velocities
are the position's rates (m/s) and, for a body, its angular velocity in global axes (rad/s).
"""
from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from types import MappingProxyType

import numpy as np

from ..errors import SymcableError
from .bodies import BodyEnd, BodyKind, rotation_rpy
from .model import End, EndCondition, Motion, Scene

__all__ = ["COUPLED_MOTION", "CoupledEnd", "CoupledThing", "coupled_scene", "coupled_things"]

#: the motion of a line end that a host program moves
COUPLED_MOTION = Motion(kind="coupled", period=0.0, amplitude=(0.0, 0.0, 0.0),
                        phase_deg=(0.0, 0.0, 0.0))


@dataclass(frozen=True)
class CoupledEnd:
    """One line end on a coupled thing: its line (``""`` in a version-1 scene), ``"end_a"``
    or ``"end_b"``, and its offset from a body's reference point (m, body axes; zeros on a
    point)."""

    line: str
    end: str
    offset: tuple = (0.0, 0.0, 0.0)


@dataclass(frozen=True)
class CoupledThing:
    """A point or body a host program moves: its name, ``"point"`` or ``"body"``, its pose
    in the scene (3 or 6 numbers: m, and rad for a body's roll, pitch, yaw) and the line
    ends on it."""

    name: str
    kind: str
    pose: tuple
    ends: tuple

    @property
    def dofs(self) -> int:
        """3 for a point, 6 for a body."""
        return 3 if self.kind == "point" else 6

    def dof_names(self) -> list:
        """``"NAME.x"``, ... , and for a body ``"NAME.roll"``, ``"NAME.pitch"``, ``"NAME.yaw"``."""
        axes = ("x", "y", "z") + (("roll", "pitch", "yaw") if self.kind == "body" else ())
        return [f"{self.name}.{a}" for a in axes]

    def end_kinematics(self, pose, rate) -> tuple[np.ndarray, np.ndarray]:
        """Each end's position (n_ends, 3), m, and velocity (n_ends, 3), m/s, with the thing
        at ``pose`` moving at ``rate`` (module docstring)."""
        pose, rate = np.asarray(pose, float), np.asarray(rate, float)
        if self.kind == "point":
            n = len(self.ends)
            return np.tile(pose, (n, 1)), np.tile(rate, (n, 1))
        R = rotation_rpy(np.degrees(pose[3:6]))
        arm = np.array([R @ np.asarray(e.offset, float) for e in self.ends]).reshape(-1, 3)
        return pose[:3] + arm, rate[:3] + np.cross(rate[3:6], arm)

    def load(self, pose, end_forces) -> np.ndarray:
        """The force (N) the lines exert on the thing, and on a body their moment about its
        reference point (N m), global axes: from each end's force (n_ends, 3), N."""
        f = np.asarray(end_forces, float).reshape(-1, 3)
        force = f.sum(axis=0)
        if self.kind == "point":
            return force
        x, _ = self.end_kinematics(pose, np.zeros(6))
        return np.concatenate([force, np.cross(x - np.asarray(pose, float)[:3], f).sum(axis=0)])


def _candidates(scene: Scene) -> dict:
    """Every thing a host may move, by name: held points and bodies (version 2), the held
    ends (version 1)."""
    if scene.version == 1:
        return {k: "point" for k in ("end_a", "end_b")
                if getattr(scene, k).condition is EndCondition.PINNED}
    out = {n: "point" for n, pt in scene.points.items() if not pt.is_free}
    out.update({n: "body" for n, b in scene.bodies.items() if not b.is_free})
    return out


def coupled_things(scene: Scene, names=None) -> tuple:
    """The :class:`CoupledThing` of each of ``names`` (a name or a list of them), in order;
    default: every vessel point and vessel body (version 1: every end with a motion, else
    ``end_b``). One SymcableError naming what is wrong and what may be coupled."""
    can = _candidates(scene)
    if names is None:
        if scene.version == 1:
            names = [k for k in can if getattr(scene, k).motion is not None] or \
                [k for k in ("end_b",) if k in can]
        else:
            names = [n for n, pt in scene.points.items() if pt.kind.value == "vessel"] + \
                [n for n, b in scene.bodies.items() if b.kind is BodyKind.VESSEL]
        if not names:
            raise SymcableError(f"scene {scene.name!r} has no vessel point or body to couple: "
                                f"name what the host moves (coupled = [...], one of "
                                f"{sorted(can) or 'none: nothing is held'})")
    names = [names] if isinstance(names, str) else list(names)
    if len(set(names)) != len(names) or not names:
        raise SymcableError(f"coupled = {names!r}: must name each thing once (at least one)")
    out = []
    for n in names:
        if n not in can and scene.version == 1 and n in ("end_a", "end_b"):
            cond = getattr(scene, n).condition.value
            raise SymcableError(f"coupled: {n!r} is {cond}: a host moves a pinned end only "
                                f"(one of {sorted(can) or 'none'})")
        if n not in can:
            free = n in getattr(scene, "points", {}) or n in getattr(scene, "bodies", {})
            raise SymcableError(f"coupled: {n!r} " + ("is free (symcable solves for it; a host "
                                "moves held things only)" if free else "is not in the scene")
                                + f": must be one of {sorted(can) or 'none: nothing is held'}")
        out.append(_thing(scene, n, can[n]))
    if not any(t.ends for t in out):
        raise SymcableError(f"coupled = {names!r}: no line ends on them, nothing to couple")
    return tuple(out)


def _thing(scene: Scene, name: str, kind: str) -> CoupledThing:
    if scene.version == 1:
        return CoupledThing(name, "point", tuple(getattr(scene, name).position),
                            (CoupledEnd("", name),))
    ends = []
    for ln in scene.lines:
        for key in ("end_a", "end_b"):
            ref = getattr(ln, key)
            if kind == "point" and ref == name:
                ends.append(CoupledEnd(ln.name, key))
            elif kind == "body" and isinstance(ref, BodyEnd) and ref.body == name:
                ends.append(CoupledEnd(ln.name, key, tuple(float(x) for x in ref.offset)))
    if kind == "point":
        return CoupledThing(name, kind, tuple(scene.points[name].position), tuple(ends))
    body = scene.bodies[name]
    pose = tuple(body.position) + tuple(math.radians(a) for a in body.orientation_deg)
    return CoupledThing(name, kind, pose, tuple(ends))


def coupled_scene(scene: Scene, things: tuple, poses: list) -> Scene:
    """``scene`` with every line end on ``things`` an inline end held where the thing's pose
    (``poses``, one per thing) puts it, its motion :data:`COUPLED_MOTION`; the coupled points
    and bodies themselves removed (version 2; version 1: the coupled ends replaced). Not
    re-validated: ``scene`` was."""
    held = {}
    for th, pose in zip(things, poses):
        x, _ = th.end_kinematics(pose, np.zeros(th.dofs))
        for e, xe in zip(th.ends, x):
            held[(e.line, e.end)] = End(EndCondition.PINNED, position=tuple(float(v) for v in xe),
                                        motion=COUPLED_MOTION)
    if scene.version == 1:
        return dataclasses.replace(scene, **{k: held[("", k)] for _, k in held})
    lines = tuple(dataclasses.replace(ln, **{k: held[(ln.name, k)] for k in ("end_a", "end_b")
                                             if (ln.name, k) in held}) for ln in scene.lines)
    gone = {th.name for th in things}
    return dataclasses.replace(
        scene, lines=lines,
        points=MappingProxyType({n: p for n, p in scene.points.items() if n not in gone}),
        bodies=MappingProxyType({n: b for n, b in scene.bodies.items() if n not in gone}))
