"""Static starts of the cable3d line (:mod:`symcable.models.cable3d.line`), in order, each built
only when the ones before it have failed:

0. a clamped end and a free end: the line straight along the clamp's direction, unloaded
   (an equilibrium at load = 0, continued in ``load``);
1. two held ends: the planar line's closed-form elastic catenary (with seabed, piles and
   folds built segment by segment) in the vertical plane through the two ends;
2. two held ends: the straight line between them;
3. the minimum of the line's potential energy over the node positions
   (:func:`~symcable.models.common.relax.relaxed_positions`, the current's drag frozen at the last
   shape), from the first start (or, with a free end, from the line hanging straight down
   from its held end).
"""
from __future__ import annotations

import numpy as np

from ...errors import ConvergenceError, SymcableError
from ...scene import EndCondition, Scene
from ...mechanism.mechanism import Start
from .catenary import catenary_start
from .segments import force_scale_of, slack_law
from .relax import relax_line

__all__ = ["force_scale", "laid_shape", "starts_of"]


def force_scale(scene: Scene, seg: dict) -> float:
    """A characteristic force, N: the planar line's (weight, applied forces, 1e-6 EA), or
    the tension of the line stretched straight between its held ends when that is more
    (a weightless string in air)."""
    F = force_scale_of(scene, seg)
    a, b = scene.end_a, scene.end_b
    if a.position is not None and b.position is not None:
        reach = float(np.linalg.norm(np.subtract(b.position, a.position)))
        F = max(F, float(np.min(seg["EA"])) * max(0.0, reach / float(seg["s"][-1]) - 1.0))
    return F


def _plane(pa, pb):
    """Unit horizontal direction from A to B (x when B is straight above or below A)."""
    h = np.array([pb[0] - pa[0], pb[1] - pa[1]])
    n = float(np.hypot(*h))
    return np.array([1.0, 0.0]) if n < 1e-12 * (1.0 + abs(pb[2] - pa[2])) else h / n


def _catenary(scene, seg):
    """Node positions (N+1, 3) from the planar closed form in the ends' vertical plane, or
    None."""
    pa, pb = np.asarray(scene.end_a.position, float), np.asarray(scene.end_b.position, float)
    u = _plane(pa, pb)
    span = float(np.dot(pb[:2] - pa[:2], u))
    try:
        start = catenary_start(np.array([0.0, pa[2]]), np.array([span, pb[2]]), seg, scene)
    except (ConvergenceError, ValueError, FloatingPointError):
        return None
    if start is None:
        return None
    pos2, _, source = start
    pos = np.empty((len(pos2), 3))
    pos[:, :2] = pa[:2] + np.outer(pos2[:, 0], u)
    pos[:, 2] = pos2[:, 1]
    return pos, source + " (in the ends' vertical plane)"


def _hanging(scene, seg):
    """The line hanging straight from its held end along its load (weight and the free
    end's force), each segment at its length."""
    a, b = scene.end_a, scene.end_b
    free_a = a.condition is EndCondition.FREE
    held = np.asarray((b if free_a else a).position, float)
    load = np.array([0.0, 0.0, -float(np.sum(seg["w"] * seg["ds"]))])
    f = (a if free_a else b).force
    if f is not None:
        load = load + np.asarray(f, float)
    n = float(np.linalg.norm(load))
    direction = load / n if n > 0 else np.array([0.0, 0.0, -1.0])
    s = seg["s"] if not free_a else seg["s"][-1] - seg["s"]
    return held + np.outer(s, direction)


def laid_shape(scene, seg) -> np.ndarray:
    """The as-laid horizontal node positions (2 (N+1),), m, node by node: the closed-form
    catenary in the ends' vertical plane (the static solve's first start), or the straight
    line between the ends where it has none."""
    if any(e.condition is EndCondition.FREE for e in (scene.end_a, scene.end_b)):
        raise SymcableError(f"scene {scene.name!r}: seabed.static_friction = 'laid' needs both "
                            "ends held")
    cat = _catenary(scene, seg)
    if cat is None:
        pa, pb = np.asarray(scene.end_a.position, float), np.asarray(scene.end_b.position, float)
        pos = pa + np.outer(seg["s"] / seg["s"][-1], pb - pa)
    else:
        pos = cat[0]
    return np.ascontiguousarray(pos[:, :2]).ravel()


def starts_of(scene, seg, params, moving):
    """Start objects for :class:`~symcable.mechanism.mechanism.Mechanism` (lazily)."""
    p0 = params.with_values(motion=0.0)
    idx = np.asarray(moving, dtype=int)  # empty: one segment between two held ends

    def start(pos, source):
        return Start(np.ascontiguousarray(pos[idx]).ravel(), np.zeros(0), p0, source)

    a, b = scene.end_a, scene.end_b
    first = None
    for held, other, sign in ((a, b, 1.0), (b, a, -1.0)):
        if held.condition is EndCondition.CLAMPED and other.condition is EndCondition.FREE:
            s = seg["s"] if sign > 0 else seg["s"] - seg["s"][-1]
            pos = np.asarray(held.position, float) + np.outer(s, held.direction)
            yield Start(np.ascontiguousarray(pos[idx]).ravel(), np.zeros(0),
                        params.with_values(p0, load=0.0), "straight along the clamp, unloaded",
                        "load")
    if a.condition is not EndCondition.FREE and b.condition is not EndCondition.FREE:
        cat = _catenary(scene, seg)
        if cat is not None:
            first = cat[0]
            yield start(*cat)
        pa, pb = np.asarray(a.position, float), np.asarray(b.position, float)
        straight = pa + np.outer(seg["s"] / seg["s"][-1], pb - pa)
        first = straight if first is None else first
        yield start(straight, "straight line")
    else:
        first = _hanging(scene, seg)
        yield start(first, "line hanging straight along its load")
    if np.all(seg["EI"] <= 0.0):
        F = force_scale(scene, seg)
        pos = relax_line(scene, seg, first, slack_law(seg, F), F)
        if pos is not None:
            yield start(pos, "minimum of the potential energy")
