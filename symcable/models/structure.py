"""Scenes of one structure share one set of expressions and Functions.

A cable3d line reads every number of its sections, line types and seabed contact through its
``line`` parameter block (:mod:`symcable.models.cable3d.line`), its ends' positions and the
current through theirs, and a free point its seabed contact through its ``contact`` block
(:func:`symcable.models.system.point_part`). Two scenes that differ only in those numbers
(a line a metre longer, a fairlead moved, a heavier chain, another sea of as many wave
components) therefore have the same
expressions with other parameter values. Such scenes share one Mechanism's expressions:
the first scene of a structure builds its Mechanism in full (the *template*), every later
one builds only its numbers (``symbols=False``: parameter values, scales, starts, layout,
bounds' limits) and takes the template's expressions (:func:`rebind`); the derived Functions
(:func:`symcable.mechanism.functions.functions`), the fused static solve and its generated C
included, are then the template's.

The structure is the scene with those numbers replaced by their sign (zero or not decides
which terms a line builds) plus the choices the builder makes from numbers (which held end
rests on the seabed): :func:`structure_key`. What the parameters do not carry stays in the
key as it is (depth, water density, seabed stiffness and friction, motions, free points'
masses, a fixed body's orientation, vessel bodies), so a scene that changes one of those
builds afresh. A fixed body's position is not in the key: its lines' ends are held at its
points through their parameters, and its outputs take its reference point from its first
end (:func:`~symcable.models.body.body.body_outputs`), so load cases that move it (a
prescribed offset) share one template. Scenes
with bending (EI > 0), drag loading functions, free bodies or vessels moved by RAOs are not
shared (their builders still read such numbers directly: a free body's scale is its longest
line's length, an RAO vessel's motion is compiled from the sea, which the key reduces to its
component count): :func:`structure_key` returns None.
"""
from __future__ import annotations

import dataclasses
import hashlib
from collections import OrderedDict
from typing import Callable

import numpy as np

from ..mechanism.mechanism import Mechanism
from ..scene import BodyEnd, BodyKind, Model as ModelKind, Scene
from ..scene.one_line import line_scene
from .common.seabed import seabed_numbers
from .common.segments import segment_table

__all__ = ["TEMPLATES", "rebind", "shared_build", "structure_key"]

#: line-type keys whose values enter through the ``line`` parameter block
LINE_TYPE_NUMBERS = ("EA", "mass", "weight", "diameter", "cd_normal", "cd_tangential",
                     "ca_normal", "ca_tangential", "damping")
#: a family's numbers (:mod:`symcable.scene.line_types`): every value they set scales with
#: the nominal diameter squared (its sign is the diameter's), the breaking load is in no
#: equation
FAMILY_NUMBERS = ("nominal_diameter", "breaking_load")
#: most recent templates kept (each holds its expressions and Functions: tens of MB for
#: long lines)
TEMPLATES_KEPT = 8

#: structure key -> the template Mechanism (most recent last)
TEMPLATES: "OrderedDict[str, Mechanism]" = OrderedDict()


def _sign(x) -> str:
    x = float(x)
    return "+" if x > 0 else "-" if x < 0 else "0"


def _mask_sections(sections: list) -> None:
    for sec in sections:
        if "length" in sec:
            sec["length"] = None


def structure_key(scene: Scene) -> str | None:
    """The structure of a cable3d scene (module docstring) as a hex digest, or None when
    its Mechanism is not shared (not cable3d, bending, loading functions, free bodies,
    RAO vessels)."""
    if scene.model is not ModelKind.CABLE3D or any(
            b.is_free or (b.motion is not None and b.motion.kind == "rao")
            for b in scene.bodies.values()):
        return None
    d = scene.to_dict()
    d.pop("name", None)
    for lt in d.get("line_types", {}).values():
        if float(lt.get("EI", 0.0) or 0.0) > 0.0 or lt.get("drag_law", "morison") != "morison" \
                or "loading" in lt:
            return None
        for k in LINE_TYPE_NUMBERS + FAMILY_NUMBERS:
            if lt.get(k) is not None:
                lt[k] = _sign(lt[k])
    for end in ("end_a", "end_b"):
        if isinstance(d.get(end), dict) and "position" in d[end]:
            d[end]["position"] = None
    _mask_sections(d.get("sections", []))
    for line in d.get("lines", []):
        _mask_sections(line.get("sections", []))
    for pt in d.get("points", {}).values():
        pt.pop("position", None)
    for name, body in d.get("bodies", {}).items():  # a fixed body's: its line ends' numbers
        if scene.bodies[name].kind is BodyKind.FIXED and _held_ends(scene, name):
            body.pop("position", None)
    env = d.get("environment", {})
    if "current" in env:
        env["current"] = [_sign(u) for u in env["current"]]
    if "waves" in env:  # the sea's numbers are parameters: its component count is structure
        w = scene.environment.waves
        env["waves"] = (w.count, w.stretching)
    text = repr(sorted(d.items())) + repr(_choices(scene))
    return hashlib.sha256(text.encode()).hexdigest()


def _held_ends(scene: Scene, body: str) -> bool:
    """Whether a line end is on ``body`` (its outputs then take the body's position from
    that end's, :func:`~symcable.models.body.body.body_outputs`)."""
    return any(isinstance(e, BodyEnd) and e.body == body
               for ln in scene.lines for e in (ln.end_a, ln.end_b))


def _choices(scene: Scene) -> tuple:
    """What the builders decide from numbers that the key masks: for each line with a
    seabed, which of its held ends rests on it (:func:`~symcable.models.common.seabed.seabed_numbers`)."""
    if scene.seabed is None:
        return ()
    scenes = [scene] if scene.version == 1 else [line_scene(scene, ln) for ln in scene.lines]
    out = []
    for ls in scenes:
        seg = segment_table(ls)
        probe = seabed_numbers(ls, seg)["probe"]
        out.append((probe[0], probe[-1]))
    return tuple(out)


def rebind(template: Mechanism, numbers: Mechanism) -> Mechanism | None:
    """``template``'s expressions with the numbers of ``numbers`` (the same structure
    built with ``symbols=False``), or None when the two do not match (then build afresh)."""
    t, n = template, numbers
    if (t.params.names != n.params.names or t.params.sizes != n.params.sizes
            or (t.n_q, t.n_v, t.n_z) != (n.n_q, n.n_v, n.n_z) or set(t.bounds) != set(n.bounds)
            or t.terms != n.terms or (t.elements is None) != (n.elements is None)):
        return None
    bounds = {k: dataclasses.replace(b, lower=n.bounds[k].lower, upper=n.bounds[k].upper,
                                     scale=n.bounds[k].scale)
              for k, b in t.bounds.items()}
    for k, b in bounds.items():
        if np.size(b.lower) not in (1, int(b.expr.numel())) \
                or np.size(b.upper) not in (1, int(b.expr.numel())):
            return None
    elements = None if t.elements is None else dataclasses.replace(
        t.elements, constants=n.elements.constants)
    return dataclasses.replace(
        t, params=n.params, scales=n.scales, starts=n.starts, static_params=n.static_params,
        layout=n.layout, bounds=bounds, elements=elements,
        functions_of=t.functions_of or t)


def shared_build(scene: Scene, build: Callable[..., Mechanism]) -> Mechanism:
    """``build(scene)``, or, when a scene of the same structure was built before (module
    docstring), its template rebound to this scene's numbers
    (``build(scene, symbols=False)``)."""
    key = structure_key(scene)
    if key is None:
        return build(scene)
    template = TEMPLATES.get(key)
    if template is not None:
        TEMPLATES.move_to_end(key)
        mech = rebind(template, build(scene, symbols=False))
        if mech is not None:
            return mech
    mech = TEMPLATES[key] = build(scene)
    if len(TEMPLATES) > TEMPLATES_KEPT:
        TEMPLATES.popitem(last=False)
    return mech
