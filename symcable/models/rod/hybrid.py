"""The hybrid rod-catenary line (Goyal & Perkins), ``model = "hybrid"``, as a Mechanism: one
line whose sections are ``rod`` (:mod:`.rod`) or ``cable3d`` (:mod:`.cable3d`), joined at
each interface by Goyal & Perkins' moment-free spherical joint (their Eqs. 12-14).

In the discrete elastic rod this is the rod Mechanism with a per-segment mask
(:func:`~symcable.models.rod.rod.build_rod` with ``rod``; what changes is in
:mod:`.hybrid_terms`): bending and twisting vertices only inside rod sections (none at an
interface node: that node is the joint, shared by both sides, passing force and no
moment), twist unknowns and ``frame`` anchors only on rod edges, cable3d's element kernel
everywhere and cable3d's own bending on cable3d edges with EI > 0. So a hybrid builds what
its scene needs:

- every section ``rod``: exactly the rod's Mechanism (named ``"rod"``);
- every section ``cable3d`` and no guided end: exactly cable3d's (:func:`is_cable` says so;
  the registry, :func:`symcable.models.build_mechanism`, then builds cable3d's line, with
  every option cable3d has: seabed, current profile, consistent mass, slack continuation);
- otherwise the generalised rod (named ``"hybrid"``; a guided end on a cable3d section
  with EI > 0 holds its tangent by cable3d's bending term and a ghost that moves with the
  node; cable3d edges with EI = 0 take the tension-only law at its sharp corner), with
  cable3d's seabed contact, friction and current profile on every node
  (:mod:`.loads`).

``zones = "auto"`` scenes are resolved first (:func:`symcable.api.rod_static.hybrid_zones`, a
static solve, which no formulation may call): this module refuses them.
"""
from __future__ import annotations

import numpy as np

from ...errors import SymcableError
from ...scene import Scene
from .hybrid_terms import rod_mask
from ...mechanism.mechanism import Mechanism
from .rod import build_rod

__all__ = ["build_hybrid", "is_cable"]


def is_cable(scene: Scene) -> bool:
    """Whether a hybrid (or rod) scene with its zones given has no rod section and no guided
    end: then it is exactly a cable3d line (the registry builds it as one)."""
    return not np.any(rod_mask(scene)) and not any(e is not None and e.guided
                                                   for e in (scene.end_a, scene.end_b))


def build_hybrid(scene: Scene) -> Mechanism:
    """The scene's line (``model = "hybrid"`` or ``"rod"``, zones given, some rod section or
    a guided end) as the generalised rod's Mechanism (module docstring)."""
    if scene.zones != "given":
        raise SymcableError(f"scene {scene.name!r}: zones = {scene.zones!r} is chosen from a "
                            "static solve: resolve it first (symcable.api.rod_static.hybrid_zones, "
                            "or rod_mechanism(scene), which does)")
    return build_rod(scene, rod_mask(scene))
