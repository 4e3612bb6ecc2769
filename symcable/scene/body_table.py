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
from .tables import read_rows
from .vessel import BODY_MOTION_KINDS, BodyMotion

_BODY_KEYS = ("kind", "position", "orientation", "mass", "inertia", "volume",
              "center_of_gravity", "center_of_buoyancy", "cd_area", "ca_volume", "motion")
_FREE_BODY_ONLY = _BODY_KEYS[3:-1]
_MOTION_KEYS = ("kind", "period", "amplitude", "phase_deg", "file", "omegas")
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


def read_body_motion(path: str, raw: Any, base: str, env: Environment) -> BodyMotion:
    """A vessel's ``motion`` table (:mod:`.vessel`) at key ``path``."""
    t = _table(path, raw, _MOTION_KEYS)
    kind = _choice(f"{path}.kind", _get(t, "kind", "harmonic"), BODY_MOTION_KINDS,
                   "vessel motion kind")
    allowed = {"harmonic": ("kind", "period", "amplitude", "phase_deg"),
               "table": ("kind", "file"), "rao": ("kind", "omegas", "amplitude", "phase_deg")}
    for key in t:
        if key not in allowed[kind]:
            raise _err(f"{path}.{key}", t[key], "", f"kind = {kind!r} reads "
                       f"{', '.join(allowed[kind][1:])}")
    if kind == "table":
        full, rows = read_rows(path, _required(path, t, "file", "a file of rows t x y z roll "
                                               "pitch yaw (s, m, deg), relative to the scene "
                                               "file"), base, 7, "t x y z roll pitch yaw")
        return BodyMotion(kind="table", period=float(rows[-1, 0] - rows[0, 0]), file=full,
                          samples=tuple(tuple(float(v) for v in r) for r in rows))
    six = "[x, y, z, roll, pitch, yaw]"
    if kind == "harmonic":
        return BodyMotion(kind="harmonic", period=_num_reader(path, t)("period", "s", gt=0),
                          amplitude=_vector(f"{path}.amplitude", _required(
                              path, t, "amplitude", f"{six}, m and deg"), 6, "m, deg", six),
                          phase_deg=_vector(f"{path}.phase_deg", _get(t, "phase_deg", (0.0,) * 6),
                                            6, "deg", six))
    if env.waves is None:
        raise _err(f"{path}.kind", "rao", "", "response amplitude operators move the vessel "
                   "with the waves: give [environment.waves]")
    omegas = _get(t, "omegas")
    if not isinstance(omegas, (list, tuple)) or len(omegas) < 2:
        raise _err(f"{path}.omegas", omegas, "rad/s", "must be a list of at least two angular "
                   "frequencies, increasing")
    w = tuple(_number(f"{path}.omegas[{i}]", v, "rad/s", ge=0) for i, v in enumerate(omegas))
    if any(b <= a for a, b in zip(w, w[1:])):
        raise _err(f"{path}.omegas", list(omegas), "rad/s", "must increase")
    rows = {}
    for key, unit in (("amplitude", "m/m, deg/m"), ("phase_deg", "deg")):
        raw_rows = _required(path, t, key, f"one row {six} per frequency, {unit}")
        if not isinstance(raw_rows, (list, tuple)) or len(raw_rows) != len(w):
            raise _err(f"{path}.{key}", f"<{len(raw_rows) if isinstance(raw_rows, (list, tuple)) else raw_rows}>",
                       "", f"must be {len(w)} rows (one per frequency) of {six}, {unit}")
        rows[key] = tuple(_vector(f"{path}.{key}[{i}]", r, 6, unit, six)
                          for i, r in enumerate(raw_rows))
    return BodyMotion(kind="rao", omegas=w, rao_amplitude=rows["amplitude"],
                      rao_phase_deg=rows["phase_deg"])


def _body(name: str, raw: Any, dim: int, points: Mapping[str, Point], base: str = ".",
          env: Environment | None = None) -> Body:
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
    if kind is not BodyKind.VESSEL and _get(t, "motion") is not None:
        raise _err(f"{path}.motion", "{...}", "", f"only a vessel (kind = 'vessel') moves by a "
                   f"given motion (this body is {kind.value!r})")
    if kind is not BodyKind.FREE:
        for key in _FREE_BODY_ONLY:
            if _get(t, key) is not None:
                raise _err(f"{path}.{key}", _get(t, key), "", f"only a free body takes {key} "
                           f"(this body is {kind.value!r}: its pose is given)")
        motion = None
        if kind is BodyKind.VESSEL:
            motion = read_body_motion(f"{path}.motion", _required(
                path, t, "motion", "a table: kind = 'harmonic', 'table' or 'rao'"), base,
                env if env is not None else Environment())
        return Body(name=name, kind=kind, position=position, orientation_deg=orientation,
                    motion=motion)
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


def _bodies(data: Mapping, dim: int, points: Mapping[str, Point], base: str = ".",
            env: Environment | None = None) -> dict[str, Body]:
    raw = _get(data, "bodies", {})
    if not isinstance(raw, Mapping):
        raise _err("bodies", raw, "", "must be a table of bodies ([bodies.NAME] with mass, "
                                      "inertia, position, ...)")
    out = {}
    for name, table in raw.items():
        _check_name("bodies", name, "body")
        out[name] = _body(name, table, dim, points, base, env)
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
