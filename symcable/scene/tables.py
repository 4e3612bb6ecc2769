"""Readers of the scene file's tables (environment, seabed, line types, sections, ends,
motions) and the checks that need a whole line (held ends, reach, stiffness, load, motion
speed), shared by the one-line layout (:mod:`.load`) and the layout of several lines and
points (:mod:`.system`)."""
from __future__ import annotations

import io
import math
import os
from typing import Any, Mapping

import numpy as np

from ..errors import LimitError, SceneError
from ..limits import read_bounded
from .checks import (MAX_NAME, _check_text, _choice, _err, _fmt, _for, _get, _integer, _key, _layout,
                     _number, _num_reader, _required, _suggest, _table, _vector)
from .drag import read_drag_law
from .tow import TOW_KEYS, read_tow
from .wave_table import read_waves
from .line_types import FAMILY_KEYS, LINE_KEYS, LINE_KEYS_DRAG, LINE_KEYS_ROD, family_table
from .model import End, EndCondition, Environment, LineType, Motion, Seabed, Section

_ENV_KEYS = ("gravity", "water_density", "depth", "current", "current_profile", "waves")
_SEABED_KEYS = ("stiffness", "friction", "damping", "friction_axial", "friction_lateral",
                "friction_velocity", "friction_law", "friction_stiffness", "static_friction")
FRICTION_LAWS = ("coulomb", "bristle")
STATIC_FRICTION = ("none", "laid")
_SECTION_KEYS = ("type", "length", "segments", "model")
#: a hybrid section's formulations (``[[sections]] model``)
SECTION_MODELS = ("cable3d", "rod")
_END_KEYS = ("condition", "position", "angle_deg", "force", "motion", "direction", "twist_deg",
             "moment")
_MOTION_KEYS = ("kind", "period", "amplitude", "phase_deg", "file") + TOW_KEYS
_MOTION_KINDS = ("harmonic", "table", "tow")
#: "guided" (model = "rod"): a free end whose tangent is held, read as condition "free" with
#: a direction (End.guided)
_CONDITIONS = tuple(c.value for c in EndCondition) + ("guided",)

# Defaults come from the dataclasses, so the file and the code cannot disagree.
_ENV = Environment()
_SEABED = Seabed()
_LT = LineType(name="", EA=1.0, EI=0.0, mass=1.0, diameter=1.0, weight=0.0)

# ----------------------------------------------------------------------------- tables

def _environment(data: Mapping, dim: int) -> Environment:
    t = _table("environment", _get(data, "environment", {}), _ENV_KEYS)
    num = _num_reader("environment", t)
    depth = _get(t, "depth")
    rho = num("water_density", "kg/m^3", _ENV.water_density, ge=0)
    return Environment(
        gravity=num("gravity", "m/s^2", _ENV.gravity, gt=0),
        water_density=rho,
        depth=None if depth is None else num("depth", "m", gt=0),
        current=_vector("environment.current", _get(t, "current", (0.0,) * dim), dim, "m/s",
                        _for(dim, "U_")),
        current_profile=_current_profile(_get(t, "current_profile"), dim),
        waves=read_waves(_get(t, "waves"), dim, rho),
    )


def _current_profile(raw, dim: int) -> tuple:
    """Rows [z, U_x, U_y, U_z] (m, m/s), at least two, distinct z, sorted by z (cable3d)."""
    key = "environment.current_profile"
    if raw is None:
        return ()
    if dim != 3:
        raise _err(key, raw, "", "a current profile is a cable3d option (model = 'cable3d'); "
                                 "the planar line takes a uniform environment.current")
    rows = []
    if isinstance(raw, (list, tuple)):
        for k, r in enumerate(raw):
            rows.append(_vector(f"{key}[{k}]", r, 4, "m, m/s", "[z, U_x, U_y, U_z]"))
    if len(rows) < 2:
        raise _err(key, raw, "", "must be a list of at least two rows [z, U_x, U_y, U_z] "
                                 "(m, m/s): the current at depth z, linear between rows")
    rows.sort(key=lambda r: r[0])
    zs = [r[0] for r in rows]
    if any(b <= a for a, b in zip(zs, zs[1:])):
        raise _err(key, raw, "", "two rows at the same z: each depth once")
    return tuple(tuple(float(v) for v in r) for r in rows)


def _seabed(data: Mapping, env: Environment) -> Seabed | None:
    raw = _get(data, "seabed")
    if env.depth is None:
        if raw is not None:
            raise _err("seabed", raw, "", "a seabed needs environment.depth (flat seabed at "
                                          "z = -depth); give the depth or remove [seabed]")
        return None
    t = _table("seabed", _get(data, "seabed", {}), _SEABED_KEYS)
    num = _num_reader("seabed", t)
    return Seabed(stiffness=num("stiffness", "Pa/m", _SEABED.stiffness, gt=0),
                  friction=num("friction", "", _SEABED.friction, ge=0),
                  damping=num("damping", "Pa s/m", _SEABED.damping, ge=0),
                  friction_axial=None if _get(t, "friction_axial") is None
                  else num("friction_axial", "", ge=0),
                  friction_lateral=None if _get(t, "friction_lateral") is None
                  else num("friction_lateral", "", ge=0),
                  friction_velocity=num("friction_velocity", "m/s", _SEABED.friction_velocity,
                                        gt=0),
                  friction_law=_choice("seabed.friction_law",
                                       _get(t, "friction_law", _SEABED.friction_law),
                                       FRICTION_LAWS, "friction law"),
                  friction_stiffness=None if _get(t, "friction_stiffness") is None
                  else num("friction_stiffness", "Pa/m", gt=0),
                  static_friction=_choice("seabed.static_friction",
                                          _get(t, "static_friction", _SEABED.static_friction),
                                          STATIC_FRICTION, "static friction"))


def _check_friction_options(seabed: Seabed | None, model: str, several: bool,
                            ends: Mapping | None) -> None:
    """The seabed's friction law and static friction where they apply: the 3D lines; static
    friction on one line (``several``: scene version 2) with both ends held; the bristle law with
    both coefficients positive (its limit surface divides by each)."""
    if seabed is None:
        return
    options = [(k, getattr(seabed, k), d) for k, d in (("friction_law", "coulomb"),
                                                        ("static_friction", "none"))
               if getattr(seabed, k) != d]
    for key, value, _ in options:
        if model not in ("cable3d", "rod", "hybrid"):
            raise _err(f"seabed.{key}", value, "", "a cable3d option (model = 'cable3d', "
                       "'rod' or 'hybrid'); the planar line's seabed is frictionless")
        if several and key == "static_friction":
            raise _err(f"seabed.{key}", value, "", "runs on one-line scenes for now (scene "
                                                   "version 1: [[sections]], end_a, end_b)")
    mu_a, mu_l = seabed.mu_axial, seabed.mu_lateral
    if seabed.friction_law == "bristle" and (mu_a > 0) != (mu_l > 0):
        raise _err("seabed.friction_law", "bristle", "", f"needs friction_axial and "
                   f"friction_lateral both > 0 (got {mu_a:g} and {mu_l:g}): its limit "
                   "ellipse divides by each; use 'coulomb' for friction in one direction")
    if seabed.static_friction == "laid" and ends is not None and any(
            e.condition is EndCondition.FREE for e in ends.values()):
        raise _err("seabed.static_friction", "laid", "", "needs both ends held (the as-laid "
                   "shape is the catenary between them)")


def _line_type(path: str, name: str, raw: Any, env: Environment, dim: int) -> LineType:
    t, family = family_table(path, _table(path, raw, LINE_KEYS + LINE_KEYS_DRAG + LINE_KEYS_ROD
                                          + FAMILY_KEYS), dim, _number, _err)
    num = _num_reader(path, t)
    mass = num("mass", "kg/m", gt=0)
    diameter = num("diameter", "m", gt=0)
    default_weight = (mass - env.water_density * math.pi * diameter**2 / 4.0) * env.gravity
    ei, ei_2 = _bending_stiffness(path, t)
    law, loading = read_drag_law(path, t, dim)
    return LineType(
        name=name, EA=num("EA", "N", gt=0), EI=ei, mass=mass,
        diameter=diameter, weight=num("weight", "N/m", default_weight),
        cd_normal=num("cd_normal", "", _LT.cd_normal, ge=0),
        cd_tangential=num("cd_tangential", "", _LT.cd_tangential, ge=0),
        ca_normal=num("ca_normal", "", _LT.ca_normal, ge=0),
        max_strain=num("max_strain", "", _LT.max_strain, gt=0),
        ca_tangential=_only_3d(path, "ca_tangential", num("ca_tangential", "", _LT.ca_tangential,
                                                          ge=0), dim),
        damping=_only_3d(path, "damping", num("damping", "N s", _LT.damping), dim),
        drag_law=law, loading=loading, EI_2=ei_2, GJ=num("GJ", "N m^2", 0.0, ge=0),
        tension_twist=_coupling(path, t, num),
        breaking_load=None if _get(t, "breaking_load") is None
        else num("breaking_load", "N", gt=0), family=family,
    )


def _coupling(path: str, t: Mapping, num) -> float:
    """``tension_twist`` (N m): the axial-torsional coupling K; the stiffness [[EA, K],
    [K, GJ]] must be positive definite."""
    K = num("tension_twist", "N m", 0.0)
    if K != 0.0:
        EA, GJ = num("EA", "N", gt=0), num("GJ", "N m^2", 0.0, ge=0)
        if not K * K < EA * GJ:
            raise _err(_key(path, "tension_twist"), K, "N m", f"must satisfy K^2 < EA GJ "
                       f"= {EA * GJ:.6g} N^2 m^2 (the axial-torsional stiffness [[EA, K], "
                       "[K, GJ]] positive definite; give GJ > 0)")
    return K


def _bending_stiffness(path: str, t: Mapping) -> tuple[float, float | None]:
    """``EI`` of a line type: a number (isotropic; EI_2 None) or ``[EI_1, EI_2]`` (the
    rod's two principal stiffnesses, N m^2, both >= 0)."""
    raw = _get(t, "EI", 0.0)
    if isinstance(raw, (list, tuple)):
        if len(raw) != 2:
            raise _err(_key(path, "EI"), list(raw), "N m^2", "must be a number or two numbers "
                       "[EI_1, EI_2] (the rod's principal bending stiffnesses)")
        ei = [_number(f"{_key(path, 'EI')}[{k}]", v, "N m^2", ge=0) for k, v in enumerate(raw)]
        return ei[0], ei[1]
    return _number(_key(path, "EI"), raw, "N m^2", ge=0), None


def _only_3d(path: str, key: str, value: float, dim: int) -> float:
    """A line-type key only cable3d reads: refused when nonzero in a planar scene."""
    if dim != 3 and value != 0.0:
        raise _err(_key(path, key), value, "", 'read by model = "cable3d" only (the planar '
                   "line has no axial damping or tangential added mass): remove it, or 0")
    return value


def _line_types(data: Mapping, env: Environment, dim: int) -> dict[str, LineType]:
    raw = _required("", data, "line_types", "a table of line types, [line_types.NAME]")
    if not isinstance(raw, Mapping) or not raw:
        raise _err("line_types", raw, "", "must be a non-empty table of line types "
                                          "([line_types.NAME] with EA, mass, diameter, ...)")
    out = {}
    for name, table in raw.items():
        _check_text("line_types", name, "a line type's name", MAX_NAME)
        out[name] = _line_type(_key("line_types", name), name, table, env, dim)
    return out


def _sections(data: Mapping, types: Mapping[str, LineType], where: str = "") -> tuple[Section, ...]:
    """The ``sections`` array of ``data`` (the scene, or the line ``where``, e.g.
    ``lines[0]``, whose key path prefixes the messages)."""
    key = _key(where, "sections")
    raw = _required(where, data, "sections", f"a non-empty array of tables [[{key}]]")
    if not isinstance(raw, (list, tuple)) or not raw:
        raise _err(key, raw, "", f"must be a non-empty array of tables ([[{key}]] with "
                                 "type, length, segments), from end A to end B")
    out = []
    for i, table in enumerate(raw):
        path = f"{key}[{i}]"
        t = _table(path, table, _SECTION_KEYS)
        name = _required(path, t, "type", f"the name of a line type: {', '.join(map(repr, types))}")
        if not isinstance(name, str) or name not in types:
            raise _err(f"{path}.type", name, "", f"unknown line type{_suggest(name, types)} "
                                                 f"(defined: {', '.join(map(repr, types))})")
        length = _num_reader(path, t)("length", "m", gt=0)
        segments = _integer(f"{path}.segments",
                            _required(path, t, "segments", "an integer >= 1"), ge=1)
        model = _get(t, "model")
        if model is not None:
            model = _choice(f"{path}.model", model, SECTION_MODELS, "section model")
        out.append(Section(line_type=types[name], length=length, segments=segments,
                           model=model))
    return tuple(out)


def _motion(path: str, raw: Any, dim: int, base: str = ".") -> Motion:
    t = _table(path, raw, _MOTION_KEYS)
    kind = _choice(f"{path}.kind", _get(t, "kind", "harmonic"), _MOTION_KINDS, "motion kind")
    if kind == "table":
        return _table_motion(path, t, dim, base)
    if kind == "tow":
        return read_tow(path, t, dim)
    for key in TOW_KEYS:
        if _get(t, key) is not None:
            raise _err(f"{path}.{key}", _get(t, key), "", 'only kind = "tow" reads it')
    if _get(t, "file") is not None:
        raise _err(f"{path}.file", _get(t, "file"), "", 'only kind = "table" reads a file')
    amplitude = _required(path, t, "amplitude", f"{_layout(dim, 'A_')}, m")
    return Motion(
        kind=kind,
        period=_num_reader(path, t)("period", "s", gt=0),
        amplitude=_vector(f"{path}.amplitude", amplitude, dim, "m", _for(dim, "A_")),
        phase_deg=_vector(f"{path}.phase_deg", _get(t, "phase_deg", (0.0,) * dim), dim, "deg",
                          _for(dim, "phase_")),
    )


def read_rows(path: str, name: Any, base: str, columns: int, what: str):
    """``(full path, rows)`` of the motion table file ``name`` (relative to ``base``) at key
    ``path``: at least two rows of at least ``columns`` finite numbers (``what``), times
    increasing; read within the ``table_bytes`` limit."""
    if not isinstance(name, str):
        raise _err(f"{path}.file", name, "", "must be a path string")
    full = os.path.abspath(os.path.join(base, os.path.expanduser(name)))
    try:
        rows = np.loadtxt(io.BytesIO(read_bounded(full, "table_bytes", f"{path}.file")),
                          ndmin=2)
    except LimitError:
        raise
    except (OSError, ValueError) as exc:
        raise _err(f"{path}.file", name, "", f"cannot be read as rows of numbers "
                   f"({type(exc).__name__}: {str(exc).splitlines()[0] if str(exc) else ''})") from None
    if rows.shape[0] < 2 or rows.shape[1] < columns or not np.all(np.isfinite(rows[:, :columns])):
        raise _err(f"{path}.file", name, "", f"needs at least 2 rows of {what} (got "
                   f"{rows.shape[0]} rows of {rows.shape[1]} finite numbers)")
    if not np.all(np.diff(rows[:, 0]) > 0):
        raise _err(f"{path}.file", name, "", "its times (first column) must increase")
    return full, rows[:, :columns]


def _table_motion(path: str, t: Mapping, dim: int, base: str) -> Motion:
    """A motion read from a table file (see :class:`Motion`): cable3d only."""
    if dim != 3:
        raise _err(f"{path}.kind", "table", "", 'table motions are read by model = "cable3d" '
                   'only (the planar dynamics take "harmonic")')
    for key in ("period", "amplitude", "phase_deg") + TOW_KEYS:
        if _get(t, key) is not None:
            raise _err(f"{path}.{key}", _get(t, key), "", 'a table motion takes only "file"')
    name = _required(path, t, "file", "a file of rows t x y z [rx ry rz] (s, m; displacement "
                     "from the end's position), relative to the scene file")
    full, rows = read_rows(path, name, base, 4, "t x y z")
    rows = rows[:, :4]
    return Motion(kind="table", period=float(rows[-1, 0] - rows[0, 0]),
                  amplitude=tuple(float(v) for v in np.max(np.abs(rows[:, 1:]), axis=0)),
                  phase_deg=(0.0, 0.0, 0.0), file=full,
                  samples=tuple(tuple(float(v) for v in r) for r in rows))


def _end(path: str, data: Mapping, dim: int, base: str = ".") -> End:
    return _end_table(path, _required("", data, path, "a table with condition and position"),
                      dim, base)


def _end_table(path: str, raw: Any, dim: int, base: str = ".") -> End:
    """An end table (``[end_a]``, or a line's inline ``end_a``) at key path ``path``."""
    t = _table(path, raw, _END_KEYS)
    raw_cond = _choice(f"{path}.condition", _required(
        path, t, "condition", f"one of {', '.join(map(repr, _CONDITIONS))}"), _CONDITIONS,
        "end condition")
    if raw_cond == "guided" and dim != 3:
        raise _err(f"{path}.condition", raw_cond, "", 'a guided end (free, its tangent held) '
                   'is read by model = "rod" (or a rod section of "hybrid"); the planar line '
                   'takes "pinned", "clamped" or "free"')
    guided = raw_cond == "guided" or (raw_cond == "free" and dim == 3
                                      and _get(t, "direction") is not None)
    cond = EndCondition.FREE if guided else EndCondition(raw_cond)
    position, angle, force, motion = (_get(t, k) for k in _END_KEYS[1:5])
    this = f"(this end is {cond.value})"
    if cond is EndCondition.FREE:
        if position is not None:
            raise _err(f"{path}.position", position, "m", "a free end has no position: it is "
                       "unknown and solved for (remove it, or make the end pinned)")
        if motion is not None:
            raise _err(f"{path}.motion", motion, "", f"only a pinned or clamped end moves {this}")
    else:
        if position is None:
            raise SceneError(f"{path}.position: required key missing ({_layout(dim)}, m; "
                             f"a {cond.value} end needs its position)")
        if force is not None:
            raise _err(f"{path}.force", force, "N", f"only a free end takes a force {this}")
    direction = _get(t, "direction")
    if dim == 3 and angle is not None:
        raise _err(f"{path}.angle_deg", angle, "deg", "cable3d gives a clamped end its "
                   "tangent as direction = [t_x, t_y, t_z], not an angle: remove angle_deg")
    if dim != 3 and direction is not None:
        raise _err(f"{path}.direction", direction, "", 'a clamped end\'s direction is read by '
                   'model = "cable3d"; the planar line takes angle_deg')
    if (cond is EndCondition.CLAMPED or guided) and dim == 3:
        direction = _direction(f"{path}.direction", _required(
            path, t, "direction", f"[t_x, t_y, t_z]; a {raw_cond} end needs the line's "
            "tangent there, pointing from end A towards end B"))
    elif cond is EndCondition.CLAMPED:
        angle = _number(f"{path}.angle_deg", _required(
            path, t, "angle_deg", "deg; a clamped end needs its tangent angle from +x"), "deg")
    elif angle is not None:
        raise _err(f"{path}.angle_deg", angle, "deg", f"only a clamped end takes angle_deg {this}")
    elif direction is not None:
        raise _err(f"{path}.direction", direction, "", f"only a clamped end takes a direction "
                   f"{this}")
    if position is not None:
        position = _vector(f"{path}.position", position, dim, "m", _for(dim))
    if cond is EndCondition.FREE:
        force = _vector(f"{path}.force", _get(t, "force", (0.0,) * dim), dim, "N", _for(dim, "F_"))
    if motion is not None:
        motion = _motion(f"{path}.motion", motion, dim, base)
    twist = _get(t, "twist_deg")
    if twist is not None:
        if cond is not EndCondition.CLAMPED or dim != 3:
            raise _err(f"{path}.twist_deg", twist, "deg", 'only a clamped end of model = "rod" '
                       f"takes a twist {this}")
        twist = _number(f"{path}.twist_deg", twist, "deg")
    moment = _get(t, "moment")
    if moment is not None:
        if cond is not EndCondition.FREE or guided or dim != 3:
            raise _err(f"{path}.moment", moment, "N m", 'only a free end of model = "rod" '
                       f"takes a moment {'(this end is guided)' if guided else this}")
        moment = _vector(f"{path}.moment", moment, 3, "N m", "[M_x, M_y, M_z]")
    return End(condition=cond, position=position, angle_deg=angle, force=force, motion=motion,
               direction=direction, twist_deg=twist, moment=moment)


def _direction(path: str, raw: Any) -> tuple[float, ...]:
    """A clamped end's tangent [t_x, t_y, t_z] (cable3d), normalised; not zero."""
    v = np.asarray(_vector(path, raw, 3, "", _for(3, "t_")), float)
    n = float(np.linalg.norm(v))
    if not n > 0.0:
        raise _err(path, raw, "", "must be a nonzero vector [t_x, t_y, t_z] (the line's "
                   "tangent at the clamp, from end A towards end B; normalised)")
    return tuple(float(x) for x in v / n)


def _check_clamp(name: str, end: End, lt: LineType) -> None:
    """A clamped end (key path ``name``) needs bending stiffness in its section's type."""
    if end.condition is EndCondition.CLAMPED and not lt.EI > 0:
        ei = _key(_key("line_types", lt.name), "EI")
        raise _err(f"{name}.condition", "clamped", "", "a clamped end needs bending stiffness "
                   f"EI > 0, but {ei} = {lt.EI!r} N m^2 in the section touching it "
                   "(give EI > 0 or pin the end)")


def _check_geometry(env: Environment, sections: tuple[Section, ...], ends: dict[str, End],
                    dim: int) -> None:
    """Checks that need the whole scene: a held end, bending at clamps, seabed, reach.
    Vectors have ``dim`` components, the last one z (up)."""
    if not any(e.is_fixed for e in ends.values()):
        raise _err("end_b.condition", "free", "", "at least one end must be pinned or clamped "
                                                   "(both ends are free)")
    for name, end in ends.items():
        section = sections[0] if name == "end_a" else sections[-1]
        lt = section.line_type
        _check_clamp(name, end, lt)
        if end.position is not None and env.depth is not None \
                and end.position[-1] < -env.depth - 1e-9 * env.depth:
            raise _err(f"{name}.position", list(end.position), "m", "below the seabed at "
                       f"z = {-env.depth!r} m (environment.depth = {env.depth!r})")
        if end.motion is not None:
            _check_motion_speed(name, end.motion, lt)
    _check_stiffness(sections, ends)
    _check_loaded(env, sections, ends, dim)
    a, b = ends["end_a"].position, ends["end_b"].position
    if a is not None and b is not None:
        distance = math.dist(a, b)
        length = sum(s.length for s in sections)
        reach = sum(s.length * (1.0 + s.line_type.max_strain) for s in sections)
        if distance > reach:
            strains = {s.line_type.max_strain for s in sections}
            strain = f"max_strain {strains.pop()!r}" if len(strains) == 1 else "max_strain per type"
            raise SceneError(f"end_b.position = {list(b)!r}: the ends are {_fmt(distance)} m apart "
                             f"but the line stretches to at most {_fmt(reach)} m (length "
                             f"{_fmt(length)} m at {strain})")


#: Largest axial stiffness over the line's load, EA / (|w| L + |end forces|): beyond it the
#: strain the load causes, below 1e-9, is not resolved by a float64 static solve. The
#: compatibility rows (EA/ds) (r_{j+1} - r_j - ds (1 + eps) t) carry the round-off of the
#: coordinates, eps_64 |r|, magnified by EA/ds, so the residual floor relative to the line's
#: weight grows as 100 eps_64 N EA / (|w| L) (N segments): at 1e9 and 50 segments it is
#: already 2e-3 of the weight, and the closed-form start (an elastic catenary) is not built
#: past it. The bound is where Newton stops converging on slack, taut and grounded lines of
#: 10-200 segments ("singular Jacobian", "no decrease"); far beyond it a solve may report
#: convergence to a wrong shape.
MAX_STIFFNESS_RATIO = 1e9


def _check_stiffness(sections: tuple[Section, ...], ends: dict[str, End]) -> None:
    """Reject an EA so large against the line's load that float64 cannot resolve its strain
    (see :data:`MAX_STIFFNESS_RATIO`). A line with no weight and no end force takes its
    strain from the end positions alone, and is not checked."""
    load = sum(abs(s.line_type.weight) * s.length for s in sections)
    load += sum(math.hypot(*e.force) for e in ends.values() if e.force is not None)
    # a weight below round-off of the dry weight (mass equal to the displaced water, to
    # the last bits) is no load
    dry = sum(s.line_type.mass * 9.81 * s.length for s in sections)
    if not load > 1e-9 * dry:
        return
    for s in sections:
        lt = s.line_type
        if lt.EA > MAX_STIFFNESS_RATIO * load:
            raise _err(_key(_key("line_types", lt.name), "EA"), lt.EA, "N",
                       f"too stiff for float64: the strain the line's load causes, "
                       f"(|weight| * length + end forces) / EA = {load:.4g} N / EA = "
                       f"{load / lt.EA:.3g}, is below the 1e-9 that a double-precision static "
                       f"solve resolves: must be <= {MAX_STIFFNESS_RATIO * load:.4g} N "
                       f"(EA / load <= {MAX_STIFFNESS_RATIO:g}; the line is then practically "
                       "inextensible anyway)")


def _check_loaded(env: Environment, sections: tuple[Section, ...], ends: dict[str, End],
                  dim: int) -> None:
    """Refuse a free end that nothing pulls on: with no submerged weight (to round-off of
    the dry weight), no force on the free end and no current, nothing sets the direction
    of the line below a pinned end, and its static shape is undetermined (unless bending
    and a clamped end hold it straight)."""
    dry = sum(s.line_type.mass * 9.81 * s.length for s in sections)
    weight = sum(abs(s.line_type.weight) * s.length for s in sections)
    current = not env.in_air and any(u != 0.0 for u in env.current)
    if weight > 1e-9 * dry or current:
        return
    free = [n for n, e in ends.items() if e.condition is EndCondition.FREE]
    if free:
        name = free[0]
        force = ends[name].force
        held = [e for e in ends.values() if e.condition is EndCondition.CLAMPED]
        if (force is not None and any(force)) or held:
            return
        raise _err(f"{name}.condition", "free", "", "the line has no submerged weight (mass "
                   "equal to the water it displaces), no force on its free end and no current: "
                   "nothing pulls it, so its static shape is undetermined; give the free end a "
                   f"force ({name}.force = {_layout(dim, 'F_')}, N), a line weight, a current, "
                   "or hold the end")
    length = sum(s.length for s in sections)
    distance = math.dist(ends["end_a"].position, ends["end_b"].position)
    if distance < length and not any(s.line_type.EI > 0 for s in sections):
        raise _err("end_b.position", list(ends["end_b"].position), "m",
                   f"the ends are {_fmt(distance)} m apart, less than the line's length "
                   f"{_fmt(length)} m, and the line has no submerged weight, no bending "
                   "stiffness and no current: a slack cable that nothing pulls has no "
                   "determined shape; move the ends apart (a taut line), or give it weight, "
                   "EI or a current")


def _check_motion_speed(name: str, motion: Motion, lt: LineType) -> None:
    """Reject a motion too fast for the line to follow within its strain range.

    Physical basis: an end moved at speed v along the line launches an axial wave whose strain
    is v / c, with c = sqrt(EA / mass) the line's axial wave speed (the impedance relation
    of an elastic rod, force = EA v / c). So an end speed above ``max_strain * c`` asks for
    more strain than the line takes, whatever the rest of the scene. Which part of the motion
    runs along the line is only known after the statics, so the bound is applied to the
    end's largest speed: it then also rejects a purely transverse motion that fast, which is
    just as meaningless (the bound is tens to hundreds of m/s for mooring lines; a fairlead
    moves at a few m/s). Slower motions that still overstretch the line are caught
    on the result, whose status is then "invalid" (symcable.results.trajectory.strain_warnings)."""
    if motion.kind == "table":
        r = np.asarray(motion.samples, float)
        v = np.linalg.norm(np.diff(r[:, 1:], axis=0), axis=1) / np.diff(r[:, 0])
        limit = lt.max_strain * math.sqrt(lt.EA / lt.mass)
        if float(v.max()) > limit:
            raise _err(f"{name}.motion.file", motion.file, "",
                       f"the end would move at up to {float(v.max()):.3g} m/s, faster than "
                       f"max_strain * sqrt(EA / mass) = {limit:.3g} m/s of line type {lt.name!r}")
        return
    if motion.kind == "tow":  # set off at full speed by a start from rest
        limit = lt.max_strain * math.sqrt(lt.EA / lt.mass)
        if motion.speed > limit:
            raise _err(f"{name}.motion.speed", motion.speed, "m/s",
                       f"faster than max_strain * sqrt(EA / mass) = {limit:.3g} m/s of line "
                       f"type {lt.name!r} (a line set off at this speed takes an axial wave "
                       "of strain speed / sqrt(EA / mass), beyond its max_strain)")
        return
    if motion.kind != "harmonic":
        return
    # max over t of |(A_i w sin(wt + p_i))_i|: with c_i = A_i exp(i p_i), the squared speed
    # over w^2 is sum |c_i|^2 / 2 + Re(sum c_i^2 exp(2 i w t)) / 2, largest at
    # (sum |c_i|^2 + |sum c_i^2|) / 2
    c = [a * complex(math.cos(p), math.sin(p)) for a, p in zip(motion.amplitude, motion.phase)]
    peak = math.sqrt(0.5 * sum(abs(ci) ** 2 for ci in c) + 0.5 * abs(sum(ci * ci for ci in c)))
    limit = lt.max_strain * math.sqrt(lt.EA / lt.mass)
    if peak * motion.omega > limit:
        raise _err(f"{name}.motion.period", motion.period, "s",
                   f"the end would move at up to {peak * motion.omega:.3g} m/s, faster than "
                   f"max_strain * sqrt(EA / mass) = {limit:.3g} m/s of line type {lt.name!r} "
                   "(an end moving along the line at v launches an axial wave of strain "
                   f"v / sqrt(EA / mass), beyond max_strain = {lt.max_strain:g}): must be >= "
                   f"{2 * math.pi * peak / limit:.3g} s for this amplitude")
