"""Reading rigid bodies (``[bodies.NAME]``, :mod:`.bodies`) and the line ends attached to
them (``"NAME"``, ``"NAME@[x, y, z]"``), for :mod:`.system`; every message names the key,
the value and what is allowed."""
from __future__ import annotations

import json
import math
from typing import Any, Mapping

from .bodies import Body, BodyEnd, BodyKind
from .checks import (_check_name, _choice, _err, _for, _get, _key, _num_reader, _number,
                     _required, _table, _vector)
from .model import End, EndCondition, Environment
from .points import Point

_BODY_KEYS = ("kind", "position", "orientation", "mass", "inertia", "volume",
              "center_of_gravity", "center_of_buoyancy", "cd_area", "ca_volume")
_FREE_BODY_ONLY = _BODY_KEYS[3:]
_BODY_KINDS = tuple(k.value for k in BodyKind)


def _nonnegative(path: str, values: tuple[float, ...], unit: str = "m^2") -> tuple[float, ...]:
    for i, v in enumerate(values):
        _number(f"{path}[{i}]", v, unit, ge=0)
    return values


def _offset(path: str, raw: str, text: str) -> tuple[float, ...]:
    """The body point of ``"NAME@[x, y, z]"``, m, body axes."""
    try:
        value = json.loads(text)
    except ValueError:
        value = None
    if not isinstance(value, list) or len(value) != 3 or not all(
            isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v)
            for v in value):
        raise _err(path, raw, "", "a body's point is written NAME@[x, y, z]: three numbers, m, "
                                  "in body axes from its reference point")
    return tuple(float(v) for v in value)


def _body(name: str, raw: Any, dim: int, points: Mapping[str, Point]) -> Body:
    path = _key("bodies", name)
    if name in points:
        raise _err(path, name, "", f"already a point's name ({_key('points', name)}): a point "
                                   "and a body cannot share a name")
    t = _table(path, raw, _BODY_KEYS)
    kind = BodyKind(_choice(f"{path}.kind", _get(t, "kind", "free"), _BODY_KINDS, "body kind"))
    vec = lambda key, unit, what, default=None: default if _get(t, key) is None else \
        _vector(f"{path}.{key}", _get(t, key), dim, unit, what)  # noqa: E731
    position = _vector(f"{path}.position", _required(path, t, "position", "[x, y, z], m"),
                       dim, "m", _for(dim))
    orientation = vec("orientation", "deg", "[roll, pitch, yaw]", (0.0, 0.0, 0.0))
    if kind is BodyKind.FIXED:
        for key in _FREE_BODY_ONLY:
            if _get(t, key) is not None:
                raise _err(f"{path}.{key}", _get(t, key), "", f"only a free body takes {key} "
                           "(this body is 'fixed': its position and orientation are given)")
        return Body(name=name, kind=kind, position=position, orientation_deg=orientation)
    num = _num_reader(path, t)
    inertia = _vector(f"{path}.inertia", _required(path, t, "inertia", "[Ixx, Iyy, Izz], "
                                                   "kg m^2 about body axes at the centre of "
                                                   "gravity"), dim, "kg m^2", "[Ixx, Iyy, Izz]")
    for i, v in enumerate(inertia):
        _number(f"{path}.inertia[{i}]", v, "kg m^2", gt=0)
    zeros = (0.0, 0.0, 0.0)
    return Body(
        name=name, kind=kind, position=position, orientation_deg=orientation,
        mass=num("mass", "kg", gt=0), inertia=inertia, volume=num("volume", "m^3", 0.0, ge=0),
        center_of_gravity=vec("center_of_gravity", "m", "[x, y, z] in body axes", zeros),
        center_of_buoyancy=vec("center_of_buoyancy", "m", "[x, y, z] in body axes", zeros),
        cd_area=_nonnegative(f"{path}.cd_area", vec("cd_area", "m^2", "[CdA_x, CdA_y, CdA_z] "
                                                    "along body axes", zeros)),
        ca_volume=_nonnegative(f"{path}.ca_volume", vec("ca_volume", "m^3", "[V_x, V_y, V_z] "
                                                        "along body axes", zeros), "m^3"))


def _bodies(data: Mapping, dim: int, points: Mapping[str, Point]) -> dict[str, Body]:
    raw = _get(data, "bodies", {})
    if not isinstance(raw, Mapping):
        raise _err("bodies", raw, "", "must be a table of bodies ([bodies.NAME] with mass, "
                                      "inertia, position, ...)")
    out = {}
    for name, table in raw.items():
        _check_name("bodies", name, "body")
        out[name] = _body(name, table, dim, points)
    return out




def body_end(end: BodyEnd, bodies: Mapping[str, Body], env: Environment) -> End:
    """A body end as the checks of one line take it: on a free body, a free end pulled by the
    body's weight less its buoyancy (N); on a fixed body, pinned at its point."""
    body = bodies[end.body]
    if not body.is_free:
        return End(EndCondition.PINNED, position=tuple(body.world(end.offset)))
    rho = 0.0 if env.in_air else env.water_density
    return End(EndCondition.FREE, force=(0.0, 0.0, -(body.mass - rho * body.volume) * env.gravity))


def body_held(end: BodyEnd, bodies: Mapping[str, Body]):
    """(key path, position) of a line's end on a fixed body, else None (a free body)."""
    body = bodies[end.body]
    return None if body.is_free else (f"{_key('bodies', end.body)}.position",
                                      tuple(body.world(end.offset)))
