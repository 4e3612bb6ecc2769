"""Reading the layout of several lines and points (scene version 2: ``[points.NAME]``,
``[[lines]]``; the README's "A scene file"), ``model = "cable3d"`` only.

Each ``[[lines]]`` entry has a ``name``, its own ``[[lines.sections]]`` (line types shared
by the scene) and two ends, ``end_a`` and ``end_b``: a point's name, or an inline end table
as version 1's ``[end_a]``. Checks beyond each key's own (every message names the key, the
value and what is allowed):

- a line's end names a point or a body that exists (``"NAME"``, or ``"NAME@[x, y, z]"`` for
  a point fixed on body NAME, body axes, m); every point and body is used by some line;
- a free point gives ``mass`` or ``volume`` (explicitly 0 for a massless joint of lines);
  only free points take mass, volume, drag and force; only vessel points move;
- every group of joined lines (through free points and free bodies) holds at least one
  point, end or fixed body (else it floats away);
- a free body gives mass and inertia (> 0); only free bodies take mass, volume, inertia,
  centres, drag and added mass;
- held points and ends lie above the seabed; two held ends joined by lines (directly or
  through free points) are no farther apart than the shortest such path stretches;
- the line types' stiffness against each line's load, and a vessel point's speed against
  the lines it moves (as version 1).
"""
from __future__ import annotations

import math
from types import MappingProxyType
from typing import Any, Mapping

from ..errors import SceneError
from .checks import (_check_name, _choice, _err, _fmt, _for, _get, _key, _num_reader,
                     _required, _suggest, _table, _vector)
from .bodies import Body, BodyEnd
from .body_table import _bodies, _nonnegative, _offset, body_end, body_held
from .model import End, EndCondition, Environment, LineType
from .points import SPHERE_CA, Line, Point, PointKind
from .tables import (_check_clamp, _check_motion_speed, _check_stiffness, _end_table, _motion,
                     _sections)

__all__ = ["read_system"]

_POINT_KEYS = ("kind", "position", "motion", "mass", "volume", "diameter", "cd", "cd_area", "ca",
               "force")
_FREE_ONLY = ("mass", "volume", "diameter", "cd", "cd_area", "ca", "force")
_LINE_KEYS = ("name", "end_a", "end_b", "sections")
_KINDS = tuple(k.value for k in PointKind)


def _point_key(name: str) -> str:
    return _key("points", name)


def _point(name: str, raw: Any, dim: int, base: str) -> Point:
    path = _point_key(name)
    t = _table(path, raw, _POINT_KEYS)
    kind = PointKind(_choice(f"{path}.kind", _required(path, t, "kind", ", ".join(
        map(repr, _KINDS))), _KINDS, "point kind"))
    position = _vector(f"{path}.position", _required(path, t, "position", "[x, y, z], m"),
                       dim, "m", _for(dim))
    motion = _get(t, "motion")
    if motion is not None and kind is not PointKind.VESSEL:
        raise _err(f"{path}.motion", motion, "", f'only a vessel point moves (this point is '
                   f'{kind.value!r}: kind = "vessel" to move it)')
    if kind is not PointKind.FREE:
        for key in _FREE_ONLY:
            if _get(t, key) is not None:
                raise _err(f"{path}.{key}", _get(t, key), "", f"only a free point takes {key} "
                           f"(this point is {kind.value!r}: its position is given)")
        return Point(name=name, kind=kind, position=position,
                     motion=None if motion is None else _motion(f"{path}.motion", motion, dim, base))
    num = _num_reader(path, t)
    if _get(t, "mass") is None and _get(t, "volume") is None:
        raise SceneError(f"{path}: a free point needs mass (kg) or volume (m^3): a clump "
                         "weight, a buoy, or mass = 0.0 for a massless joint of lines")
    diameter, cd_area = _get(t, "diameter"), _get(t, "cd_area")
    if diameter is not None and cd_area is not None:
        raise _err(f"{path}.cd_area", cd_area, "m^2", "give a diameter (a sphere) or cd_area, "
                   "not both")
    if _get(t, "cd") is not None and diameter is None:
        raise _err(f"{path}.cd", _get(t, "cd"), "", "cd is the drag coefficient of a sphere "
                   "of the given diameter: give diameter, or cd_area = [CdA_x, CdA_y, CdA_z] "
                   "(m^2) without cd")
    force = _get(t, "force")
    return Point(
        name=name, kind=kind, position=position,
        mass=num("mass", "kg", 0.0, ge=0), volume=num("volume", "m^3", 0.0, ge=0),
        diameter=None if diameter is None else num("diameter", "m", gt=0),
        cd=num("cd", "", Point.cd, ge=0),
        cd_area=None if cd_area is None else _nonnegative(
            f"{path}.cd_area", _vector(f"{path}.cd_area", cd_area, dim, "m^2",
                                       "[CdA_x, CdA_y, CdA_z] (drag coefficient x area)")),
        ca=num("ca", "", SPHERE_CA if diameter is not None else 0.0, ge=0),
        force=None if force is None else _vector(f"{path}.force", force, dim, "N", _for(dim, "F_")))


def _points(data: Mapping, dim: int, base: str) -> dict[str, Point]:
    raw = _get(data, "points", {})
    if not isinstance(raw, Mapping):
        raise _err("points", raw, "", "must be a table of points ([points.NAME] with kind, "
                                      "position, ...)")
    out = {}
    for name, table in raw.items():
        _check_name("points", name, "point")
        out[name] = _point(name, table, dim, base)
    return out


def _line_end(path: str, raw: Any, points: Mapping[str, Point], dim: int, base: str,
              bodies: Mapping[str, Body]):
    """A point's name (checked), a body's point (:class:`BodyEnd`) or an inline end table."""
    if isinstance(raw, str):
        name, at, offset = raw.partition("@")
        if name in bodies:
            return BodyEnd(name, _offset(path, raw, offset) if at else (0.0, 0.0, 0.0))
        if at or raw not in points:
            known = ", ".join(map(repr, points)) or "none"
            which = f"unknown body{_suggest(name, bodies)}" if at else \
                f"unknown point{_suggest(raw, list(points) + list(bodies))}"
            raise _err(path, raw, "", f"{which} (points: {known}; bodies: "
                       f"{', '.join(map(repr, bodies)) or 'none'}, or 'NAME@[x, y, z]' for a "
                       "point fixed on body NAME; or an inline end table with condition and "
                       "position)")
        return raw
    if raw is None:
        raise SceneError(f"{path}: required key missing (a point's name, or an inline end "
                         "table with condition and position)")
    if not isinstance(raw, Mapping):
        raise _err(path, raw, "", "must be a point's name or an end table (condition, "
                                  "position, ...)")
    return _end_table(path, raw, dim, base)


def _lines(data: Mapping, types: Mapping[str, LineType], points: Mapping[str, Point],
           dim: int, base: str, bodies: Mapping[str, Body]) -> tuple[Line, ...]:
    raw = _get(data, "lines")
    if not isinstance(raw, (list, tuple)) or not raw:
        raise _err("lines", raw, "", "must be a non-empty array of tables ([[lines]] with name, "
                                     "end_a, end_b and [[lines.sections]])")
    out, names = [], {}
    for i, table in enumerate(raw):
        path = f"lines[{i}]"
        t = _table(path, table, _LINE_KEYS)
        name = _get(t, "name", f"line{i + 1}")
        _check_name(f"{path}.name", name, "line")
        if name in names:
            raise _err(f"{path}.name", name, "", f"already the name of lines[{names[name]}]: "
                                                 "line names must be unique")
        if name in points or name in bodies:
            what, key = ("point", _point_key(name)) if name in points else \
                ("body", _key("bodies", name))
            raise _err(f"{path}.name", name, "", f"already a {what}'s name ({key}): a line and "
                                                 f"a {what} cannot share a name")
        names[name] = i
        ends = [_line_end(f"{path}.{k}", _get(t, k), points, dim, base, bodies)
                for k in ("end_a", "end_b")]
        out.append(Line(name=name, sections=_sections(t, types, path), end_a=ends[0],
                        end_b=ends[1]))
    return tuple(out)


def _held_position(line: Line, which: str, points: Mapping[str, Point],
                   bodies: Mapping[str, Body]):
    """(key path, position) of a line's end where it is held, else None."""
    end = line.end(which)
    if isinstance(end, BodyEnd):
        return body_held(end, bodies)
    if isinstance(end, str):
        pt = points[end]
        return None if pt.is_free else (f"{_point_key(end)}.position", pt.position)
    return None if end.condition is EndCondition.FREE else (f"{which}.position", end.position)


def _check_system(env: Environment, lines: tuple[Line, ...], points: Mapping[str, Point],
                  bodies: Mapping[str, Body]) -> None:
    used = {e for ln in lines for e in (ln.end_a, ln.end_b) if isinstance(e, str)}
    used |= {e.body for ln in lines for e in (ln.end_a, ln.end_b) if isinstance(e, BodyEnd)}
    for name, pt in points.items():
        if name not in used:
            raise _err(f"{_point_key(name)}", name, "", "no line uses this point (every point "
                       "is a line's end_a or end_b): attach a line or remove the point")
        if not pt.is_free and env.depth is not None and pt.position[-1] < -env.depth * (1 + 1e-9):
            raise _err(f"{_point_key(name)}.position", list(pt.position), "m", "below the "
                       f"seabed at z = {-env.depth!r} m (environment.depth = {env.depth!r})")
    for name in bodies:
        if name not in used:
            raise _err(_key("bodies", name), name, "", "no line attaches to this body (a line's "
                       "end_a or end_b is NAME or NAME@[x, y, z]): attach a line or remove it")
    for i, ln in enumerate(lines):
        path = f"lines[{i}]"
        ends = {}
        for which, section in (("end_a", ln.sections[0]), ("end_b", ln.sections[-1])):
            end = ln.end(which)
            if isinstance(end, BodyEnd):
                ends[which] = body_end(end, bodies, env)
                if ends[which].position is not None and env.depth is not None \
                        and ends[which].position[-1] < -env.depth * (1 + 1e-9):
                    raise _err(f"{path}.{which}", end.text, "", "this point of the fixed body "
                               f"is at z = {_fmt(ends[which].position[-1])} m, below the seabed "
                               f"at z = {-env.depth!r} m (environment.depth = {env.depth!r})")
                continue
            if isinstance(end, str):
                pt = points[end]
                if pt.motion is not None:
                    _check_motion_speed(_point_key(end), pt.motion, section.line_type)
                ends[which] = End(EndCondition.FREE if pt.is_free else EndCondition.PINNED,
                                  position=pt.position, force=pt.force)
                continue
            ends[which] = end
            _check_clamp(f"{path}.{which}", end, section.line_type)
            if end.position is not None and env.depth is not None \
                    and end.position[-1] < -env.depth * (1 + 1e-9):
                raise _err(f"{path}.{which}.position", list(end.position), "m", "below the "
                           f"seabed at z = {-env.depth!r} m (environment.depth = {env.depth!r})")
            if end.motion is not None:
                _check_motion_speed(f"{path}.{which}", end.motion, section.line_type)
        _check_stiffness(ln.sections, ends)
    _check_held(lines, points, bodies)
    _check_reach(lines, points, bodies)


def _node(line: Line, i: int, which: str, bodies: Mapping[str, Body]) -> str:
    """A graph node for a line's end: its point's name, a free body's key path (every point
    of a free body is one node), a fixed body's point, or the inline end's key path."""
    end = line.end(which)
    if isinstance(end, BodyEnd):
        key = _key("bodies", end.body)
        return key if bodies[end.body].is_free else f"{key}@{list(end.offset)}"
    return end if isinstance(end, str) else f"lines[{i}].{which}"


def _check_reach(lines: tuple[Line, ...], points: Mapping[str, Point],
                 bodies: Mapping[str, Body]) -> None:
    """Two held ends (points, inline ends, fixed bodies' points) joined by lines, directly or
    through free points and free bodies, are no farther apart than the shortest such path
    stretches (each line's length at its line types' max_strain; through a free body, each
    attachment point's distance from its reference point added)."""
    held: dict[str, tuple[str, tuple]] = {}  # node -> (key path of its position, position)
    edges: dict[tuple[str, str], tuple[float, list[str]]] = {}
    for i, ln in enumerate(lines):
        a, b = _node(ln, i, "a", bodies), _node(ln, i, "b", bodies)
        for node, which in ((a, "a"), (b, "b")):
            pos = _held_position(ln, which, points, bodies)
            if pos is not None:
                key = pos[0] if isinstance(ln.end(which), (str, BodyEnd)) \
                    else f"lines[{i}].{pos[0]}"
                held[node] = (key, pos[1])
        reach = sum(s.length * (1.0 + s.line_type.max_strain) for s in ln.sections)
        reach += sum(math.hypot(*e.offset) for e in (ln.end_a, ln.end_b)
                     if isinstance(e, BodyEnd) and bodies[e.body].is_free)
        for u, w in ((a, b), (b, a)):
            if reach < edges.get((u, w), (math.inf, []))[0]:
                edges[(u, w)] = (reach, [ln.name])
    nodes = sorted({u for u, _ in edges})
    best = {(u, w): edges.get((u, w), (0.0 if u == w else math.inf, []))
            for u in nodes for w in nodes}
    for k in nodes:  # Floyd-Warshall; paths through held nodes are no shorter than direct
        if k in held:
            continue
        for u in nodes:
            for w in nodes:
                via = best[(u, k)][0] + best[(k, w)][0]
                if via < best[(u, w)][0]:
                    best[(u, w)] = (via, best[(u, k)][1] + best[(k, w)][1])
    names = sorted(held)
    for x, u in enumerate(names):
        for w in names[x + 1:]:
            reach, path = best[(u, w)]
            distance = math.dist(held[u][1], held[w][1])
            if distance > reach:
                raise _err(held[w][0], list(held[w][1]), "m", f"the ends are {_fmt(distance)} "
                           f"m apart ({held[u][0]} to {held[w][0]}) but the lines between "
                           f"them ({', '.join(path)}) stretch to at most {_fmt(reach)} m "
                           "at their line types' max_strain")


def _show_end(end) -> Any:
    if isinstance(end, BodyEnd):
        return end.text
    return end if isinstance(end, str) else "<inline end>"


def _joint(end, points: Mapping[str, Point], bodies: Mapping[str, Body]):
    """The free point or free body a line's end joins others at (a key), else None."""
    if isinstance(end, BodyEnd):
        return f"body {end.body}" if bodies[end.body].is_free else None
    return end if isinstance(end, str) and points[end].is_free else None


def _check_held(lines: tuple[Line, ...], points: Mapping[str, Point],
                bodies: Mapping[str, Body]) -> None:
    """Every group of lines joined through free points and free bodies holds at least one
    end."""
    group = list(range(len(lines)))

    def find(i):
        while group[i] != i:
            group[i] = group[group[i]]
            i = group[i]
        return i

    at: dict[str, int] = {}
    for i, ln in enumerate(lines):
        for end in (ln.end_a, ln.end_b):
            joint = _joint(end, points, bodies)
            if joint is not None:
                if joint in at:
                    group[find(i)] = find(at[joint])
                at.setdefault(joint, i)
    held = {find(i) for i, ln in enumerate(lines)
            if any(_held_position(ln, w, points, bodies) is not None for w in ("a", "b"))}
    for i, ln in enumerate(lines):
        if find(i) not in held:
            names = [lines[j].name for j in range(len(lines)) if find(j) == find(i)]
            raise _err(f"lines[{i}].end_a", _show_end(ln.end_a), "", f"the lines {names} are "
                       "joined only through free points, free bodies and free ends: nothing "
                       "holds them (attach one to a fixed or vessel point, or pin an end)")


def read_system(data: Mapping, env: Environment, types: Mapping[str, LineType], dim: int,
                model: str, base: str = ".") -> tuple[Mapping[str, Point], tuple[Line, ...],
                                                      Mapping[str, Body]]:
    """The points, lines and bodies of a version-2 scene ``data`` (module docstring),
    checked.

    Raises
    ------
    SceneError
        One line naming the key, the value and what is allowed.
    """
    for key in ("sections", "end_a", "end_b"):
        if _get(data, key) is not None:
            raise _err(key, _get(data, key), "", "a scene of [[lines]] gives each line its own "
                       f"{key} ([[lines.sections]], lines[i].end_a, lines[i].end_b): remove "
                       f"the top-level {key}")
    if dim != 3:
        raise _err("lines", "[...]", "", f'several lines and points are read by model = '
                   f'"cable3d" only (model = {model!r}): one line with [[sections]], [end_a], '
                   '[end_b]')
    points = _points(data, dim, base)
    bodies = _bodies(data, dim, points, base, env)
    lines = _lines(data, types, points, dim, base, bodies)
    _check_system(env, lines, points, bodies)
    return MappingProxyType(points), lines, MappingProxyType(bodies)
