"""One line of a version-2 scene as a version-1 scene of its own: how the models build each
line of a system (:mod:`symcable.models.system`) and what their per-line checks read."""
from __future__ import annotations

from .bodies import BodyEnd, BodyKind
from .model import End, EndCondition, Motion, Scene
from .vessel import rigid_path

__all__ = ["line_scene"]


def _end_of(scene: Scene, end, pinned_free: bool = False) -> End:
    """A line's end as a version-1 End: a fixed or vessel point pinned (with its motion), a
    free point a free end with no force (or, with ``pinned_free``, pinned where the scene
    puts it: for the starts), likewise on a free body (pinned at its point as the scene
    places the body) and on a fixed body (pinned at its point), an inline end as it is."""
    if isinstance(end, BodyEnd):
        body = scene.bodies[end.body]
        if body.is_free and not pinned_free:
            return End(EndCondition.FREE)
        motion = None
        if body.kind is BodyKind.VESSEL and not pinned_free:
            env = scene.environment
            sea = None if env.waves is None else env.waves.components_in(env.depth, env.gravity)
            path = rigid_path(body, end.offset, sea, 0.0 if env.waves is None
                              else env.waves.ramp_time)
            motion = Motion(kind="body", period=body.motion.period or path.ramp,
                            amplitude=(0.0, 0.0, 0.0), phase_deg=(0.0, 0.0, 0.0), rigid=path)
        return End(EndCondition.PINNED, position=tuple(body.world(end.offset)), motion=motion)
    if not isinstance(end, str):
        return end
    pt = scene.points[end]
    if pt.is_free and not pinned_free:
        return End(EndCondition.FREE)
    return End(EndCondition.PINNED, position=pt.position,
               motion=None if pinned_free else pt.motion)


def line_scene(scene: Scene, line, *, pinned_free: bool = False) -> Scene:
    """A version-1 scene of one line of ``scene`` (its environment, seabed and line types;
    ends from :func:`_end_of`), not re-validated: ``scene`` was."""
    return Scene(name=f"{scene.name}: {line.name}", model=scene.model,
                 environment=scene.environment, seabed=scene.seabed,
                 line_types=scene.line_types, sections=line.sections,
                 end_a=_end_of(scene, line.end_a, pinned_free),
                 end_b=_end_of(scene, line.end_b, pinned_free), source=scene.source,
                 mass_matrix=scene.mass_matrix)
