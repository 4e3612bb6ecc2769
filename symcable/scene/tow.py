"""The tow motion of a vessel point or a held end (``[points.NAME.motion]``,
``[end_b.motion]`` with ``kind = "tow"``; cable3d only).

Keys: ``speed`` (m/s, > 0), ``heading`` (degrees: the direction of travel in the x-y plane
from +x, counter-clockwise), optional ``start`` (s, default 0: when the point passes its
scene position) and optional ``turns``, a list of tables ``{after = s, radius = m,
angle = deg}``: after a straight run of ``after`` s, a circular turn of that radius through
that angle (positive to port: counter-clockwise seen from above), then straight on the new
heading. The displacement from the point's scene position is
:func:`symcable.models.common.tow.tow_path`.

The tow runs at its speed from t = -inf: before its first turn the point moves on a
straight line for all earlier times (``start`` only places it on that line). So the path
is C1 everywhere (no moment where the vessel sets off with a jump in velocity, nor an
acceleration law the scene would have to choose), and at any time before the first turn the
steady tow, the static solution in the frame moving with the point, is an exact solution
of the dynamics: ``simulate`` starts there (or from rest with ``start="rest"``, the vessel
then setting off at full speed at the run's first instant).
"""
from __future__ import annotations

import math
from typing import Mapping

from .checks import _err, _get, _num_reader, _table
from .model import Motion

__all__ = ["read_tow", "TOW_KEYS"]

#: keys of a tow motion's table (the motion table's own: kind)
TOW_KEYS = ("speed", "heading", "start", "turns")
_TURN_KEYS = ("after", "radius", "angle")


def read_tow(path: str, t: Mapping, dim: int) -> Motion:
    """A ``kind = "tow"`` motion table ``t`` at key path ``path`` (module docstring), one
    SceneError per bad key naming it, its value and what is allowed."""
    if dim != 3:
        raise _err(f"{path}.kind", "tow", "", 'tow motions are read by model = "cable3d" '
                   'only (the planar dynamics take "harmonic")')
    for key in ("period", "amplitude", "phase_deg", "file"):
        if _get(t, key) is not None:
            raise _err(f"{path}.{key}", _get(t, key), "", 'a tow motion takes speed, heading, '
                       'start and turns (not the keys of "harmonic" or "table")')
    num = _num_reader(path, t)
    speed = num("speed", "m/s", gt=0)
    heading = num("heading", "deg")
    start = num("start", "s", 0.0)
    raw = _get(t, "turns", [])
    if not isinstance(raw, (list, tuple)):
        raise _err(f"{path}.turns", raw, "", "must be a list of tables {after = s, "
                   "radius = m, angle = deg}")
    turns = []
    for i, row in enumerate(raw):
        key = f"{path}.turns[{i}]"
        rt = _table(key, row, _TURN_KEYS)
        rnum = _num_reader(key, rt)
        after = rnum("after", "s", ge=0)
        radius = rnum("radius", "m", gt=0)
        angle = rnum("angle", "deg")
        if angle == 0.0:
            raise _err(f"{key}.angle", angle, "deg", "must be nonzero: positive to port "
                       "(counter-clockwise seen from above), negative to starboard")
        turns.append((after, radius, angle))
    span = sum(a + r * math.radians(abs(g)) / speed for a, r, g in turns)
    return Motion(kind="tow", period=span, amplitude=(0.0, 0.0, 0.0), phase_deg=(0.0, 0.0, 0.0),
                  speed=speed, heading_deg=heading, start=start, turns=tuple(turns))

