"""The rod's re-anchoring hook (:class:`~symcable.mechanism.mechanism.Reanchor`): what a time
march calls between steps so that no edge of a ``model = "rod"`` Mechanism nears the half
turn from its anchor, where the anchored reference frame is singular
(:mod:`symcable.models.rod.rod`).

- ``margin`` = min over edges of 1 + t0_j . t_j (2 with every edge on its anchor, 0 at the
  half turn; 0.5 is a turn of 120 degrees);
- ``update`` = the parameters with the block ``frame`` replaced by the output
  ``reference_frame`` (each edge's current tangent and reference director): the reference
  director at the state is then the same vector, so the twists q, the material frames and
  the energy are unchanged;
- ``velocity`` (a Mechanism with the frames' spin in its kinetic energy,
  :func:`~symcable.models.rod.spin.with_reference_spin`) = v with each twist rate plus its
  reference frame's spin in the old chart (:func:`~symcable.models.rod.spin.reference_spins`):
  the new anchor's frame does not spin at the state, so theta' carries the material frame's
  whole spin rate. Without the spin in the kinetic energy theta' is the model's spin rate
  and stays (moving it there degrades the energy's conservation by an order of magnitude).

Built from the Mechanism's own expressions, so it needs nothing from the rod's builder and
serves any Mechanism with a ``frame`` block and a ``reference_frame`` output.
"""
from __future__ import annotations

import casadi as ca

from ...errors import SymcableError
from ...mechanism.mechanism import Mechanism, Reanchor
from .spin import reference_spins

__all__ = ["FLOOR", "THRESHOLD", "frame_margin", "reanchor_hook"]

#: the march re-anchors once some edge's 1 + t0 . t falls below this (a turn of 120 deg)
THRESHOLD = 0.5
#: a step that takes some edge's 1 + t0 . t below this (a turn of 162 deg) is retaken
FLOOR = 0.05


def frame_margin(mech: Mechanism):
    """Expression (1, 1) of (q, t, p): min over edges of 1 + t0 . t (see the module)."""
    if "frame" not in mech.params.names or "reference_frame" not in mech.outputs:
        raise SymcableError(f"mechanism {mech.name!r} has no anchored frames (a parameter "
                            "block 'frame' and an output 'reference_frame'): nothing to "
                            "re-anchor")
    anchors = ca.reshape(mech.p[mech.params.slice("frame")], 6, -1)
    now = ca.reshape(mech.outputs["reference_frame"].expr, 6, -1)
    dots = ca.sum1(anchors[0:3, :] * now[0:3, :])
    return ca.mmin(1.0 + dots)


def reanchor_hook(mech: Mechanism, threshold: float = THRESHOLD,
                  floor: float = FLOOR) -> Reanchor | None:
    """The :class:`~symcable.mechanism.mechanism.Reanchor` of a rod or hybrid Mechanism (module
    docstring); the Mechanism's own when it carries one; None for one without anchored
    frames (a hybrid with no rod edge, cable3d)."""
    if getattr(mech, "reanchor", None) is not None:
        return mech.reanchor
    if "frame" not in mech.params.names:
        return None
    margin = frame_margin(mech)
    sl = mech.params.slice("frame")
    p = mech.p
    update = ca.vertcat(p[:sl.start], mech.outputs["reference_frame"].expr, p[sl.stop:])
    velocity = None
    if "reference spin" in mech.terms:  # the material frame's spin rate kept
        velocity = mech.v
        for i, spin in reference_spins(mech):
            velocity = velocity + spin * ca.DM.eye(mech.n_v)[:, i]
    return Reanchor(margin, update, float(threshold), float(floor), velocity)
