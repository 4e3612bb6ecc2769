"""Messages and validators shared by the scene readers (:mod:`.tables`, :mod:`.system`,
:mod:`.load`): every bad input becomes a one-line :class:`~symcable.errors.SceneError` of the
form ``<key path> = <value> [unit]: <what is allowed>``. A key given as ``None`` (possible in
a dict, not in TOML) counts as not given."""
from __future__ import annotations

import difflib
import json
import math
import numbers
import re
from typing import Any, Mapping

import numpy as np

from ..errors import SceneError
from .bodies import BodyEnd
from .model import _DIMS, EndCondition, Model

_AXES = {2: ("x", "z"), 3: ("x", "y", "z")}  # vectors per dimension, z up in both
_DIM_MODEL = {d: m for m, d in reversed(_DIMS.items())}  # the first model of each dimension
_MISSING = object()
_BARE_KEY = re.compile(r"[A-Za-z0-9_-]+")
#: largest magnitude of a number in a scene (SI units)
MAX_MAGNITUDE = 1e30
#: longest name of a line, point or body
MAX_NAME = 64
_NAME = re.compile(rf"[A-Za-z0-9_-]{{1,{MAX_NAME}}}")


def _check_text(path: str, text: Any, what: str, longest: int) -> None:
    """Free text a scene names things by (its title, a line type's name): a string of 1 to
    ``longest`` printable characters, no control characters (it is shown on one line)."""
    if not isinstance(text, str) or not 0 < len(text) <= longest or not text.isprintable():
        raise _err(path, text, "", f"{what} must be a string of 1 to {longest} printable "
                   "characters (no newlines or control characters)")


def _check_name(path: str, name: Any, what: str) -> None:
    """The one rule for the names of lines, points and bodies: 1 to MAX_NAME letters,
    digits, ``_`` and ``-`` (ASCII). Every later stage takes them: the names of CasADi
    Functions and generated C are made from them by
    :func:`~symcable.mechanism.mechanism.casadi_name`."""
    if not isinstance(name, str) or not _NAME.fullmatch(name):
        raise _err(path, name, "", f"{what} names must be 1 to {MAX_NAME} ASCII letters, "
                   "digits, _ and - (they prefix the outputs)")

# ----------------------------------------------------------------------------- messages

def _key(path: str, key: str) -> str:
    """Dotted key path ``path.key`` (TOML-quoting keys that are not bare)."""
    k = key if _BARE_KEY.fullmatch(key) else _quote(key)
    return f"{path}.{k}" if path else k


def _quote(text: str) -> str:
    """A TOML basic string (JSON's escapes are TOML's, except DEL must be escaped too)."""
    return json.dumps(text, ensure_ascii=False).replace("\x7f", "\\u007f")


def _show(value: Any) -> str:
    text = repr(value)
    return text if len(text) <= 100 else text[:97] + "..."


def _err(path: str, value: Any, unit: str, allowed: str) -> SceneError:
    """``<path> = <value> [unit]: <allowed>`` as a one-line SceneError."""
    unit = f" {unit}" if unit else ""
    return SceneError(f"{path} = {_show(value)}{unit}: {allowed}".replace("\n", " "))


def _suggest(word: Any, choices) -> str:
    """``"; did you mean 'x'?"`` when a choice is close to ``word``, else ``""``."""
    if not isinstance(word, str):
        return ""
    close = difflib.get_close_matches(word, list(choices), n=1)
    return f"; did you mean {close[0]!r}?" if close else ""


def _fmt(x: float) -> str:
    """About four significant digits, at least one decimal (lengths in messages)."""
    digits = 3 - math.floor(math.log10(abs(x))) if x != 0 else 1
    return f"{x:.{max(1, digits)}f}"


def _layout(dim: int, prefix: str = "") -> str:
    """The components of a vector in ``dim`` dimensions, e.g. ``[F_x, F_y, F_z]``."""
    return "[" + ", ".join(prefix + a for a in _AXES[dim]) + "]"


def _for(dim: int, prefix: str = "") -> str:
    """``[x, y, z] for model "cable3d"``: what a vector must be, in messages."""
    return f'{_layout(dim, prefix)} for model "{_DIM_MODEL[dim].value}"'


# ----------------------------------------------------------------------------- validators

def _check_keys(path: str, table: Mapping, allowed) -> None:
    """Reject keys of ``table`` that are not in ``allowed``, suggesting the closest one."""
    for key in table:
        if not isinstance(key, str):
            raise SceneError(f"{path or 'scene'}: key {_show(key)} must be a string "
                             f"(allowed: {', '.join(allowed)})")
        if key not in allowed:
            raise SceneError(f"{_key(path, key)}: unknown key{_suggest(key, allowed)} "
                             f"(allowed: {', '.join(allowed)})")


def _table(path: str, value: Any, allowed) -> Mapping:
    """A table (dict) with only ``allowed`` keys."""
    if not isinstance(value, Mapping):
        raise _err(path, value, "", f"must be a table with keys {', '.join(allowed)}")
    _check_keys(path, value, allowed)
    return value


def _get(table: Mapping, key: str, default: Any = None) -> Any:
    value = table.get(key)
    return default if value is None else value


def _required(path: str, table: Mapping, key: str, what: str) -> Any:
    value = table.get(key)
    if value is None:
        raise SceneError(f"{_key(path, key)}: required key missing ({what})")
    return value


def _number(path: str, value: Any, unit: str = "", *, gt: float | None = None,
            ge: float | None = None) -> float:
    """A finite real number (bools rejected), optionally ``> gt`` or ``>= ge``; as float."""
    bound = f" > {gt:g}" if gt is not None else f" >= {ge:g}" if ge is not None else ""
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise _err(path, value, unit, f"must be a number{bound}")
    try:
        x = float(value)
    except (OverflowError, ValueError, TypeError):
        x = math.nan
    if not math.isfinite(x):
        raise _err(path, value, unit, f"must be a finite number{bound}")
    if abs(x) > MAX_MAGNITUDE:
        raise _err(path, value, unit, f"must be a number{bound} of magnitude at most "
                   f"{MAX_MAGNITUDE:g} (SI units: beyond any physical value, and its powers "
                   "would overflow)")
    if (gt is not None and not x > gt) or (ge is not None and not x >= ge):
        raise _err(path, value, unit, f"must be{bound}")
    return x


def _integer(path: str, value: Any, *, ge: int) -> int:
    """An int (not a bool, not a float even if integral) ``>= ge``."""
    if isinstance(value, bool) or not isinstance(value, numbers.Integral):
        raise _err(path, value, "", f"must be an integer >= {ge}")
    if value < ge:
        raise _err(path, value, "", f"must be >= {ge}")
    return int(value)


def _vector(path: str, value: Any, n: int, unit: str = "", what: str = "") -> tuple[float, ...]:
    """A list of ``n`` finite numbers, as a tuple of float."""
    if hasattr(value, "tolist") and not isinstance(value, (str, bytes)):
        value = value.tolist()  # NumPy arrays in dict input
    if not isinstance(value, (list, tuple)) or len(value) != n:
        raise _err(path, value, unit, f"must be a list of {n} numbers {what}".rstrip())
    return tuple(_number(f"{path}[{i}]", v, unit) for i, v in enumerate(value))


def _choice(path: str, value: Any, allowed: tuple[str, ...], what: str) -> str:
    """One of the strings ``allowed``."""
    if not isinstance(value, str) or value not in allowed:
        raise _err(path, value, "", f"unknown {what}{_suggest(value, allowed)} "
                                    f"(allowed: {', '.join(map(repr, allowed))})")
    return str(value.value if isinstance(value, Model | EndCondition) else value)


def _num_reader(path: str, table: Mapping):
    """``num(key, unit, default=<required>, gt=, ge=)`` reading numbers from ``table``."""
    def num(key: str, unit: str, default: Any = _MISSING, *, gt=None, ge=None) -> float:
        value = _get(table, key, default)
        if value is _MISSING:
            bound = f" > {gt:g}" if gt is not None else f" >= {ge:g}" if ge is not None else ""
            what = f"{unit}, a number{bound}" if unit else f"a number{bound}"
            raise SceneError(f"{_key(path, key)}: required key missing ({what})")
        return _number(_key(path, key), value, unit, gt=gt, ge=ge)
    return num


# ----------------------------------------------------------------------------- free surface

def _held_ends(scene) -> list:
    """``[(label, sections, ends)]``, one per line of ``scene``: ``label`` names the line in
    messages, ``ends`` its ends held at a given position (pinned or clamped ends, fixed and
    vessel points, points of fixed bodies), each ``(key path, value shown, position,
    max_strain of the section at it)``. Free ends, free points and free bodies (their
    positions solved for) are left out."""
    if scene.version == 1:
        ends = [(f"{which}.position", list(end.position), end.position,
                 sec.line_type.max_strain)
                for which, end, sec in (("end_a", scene.end_a, scene.sections[0]),
                                        ("end_b", scene.end_b, scene.sections[-1]))
                if end.position is not None]
        return [("the line", scene.sections, ends)]
    out = []
    for i, ln in enumerate(scene.lines):
        ends = []
        for which, sec in (("end_a", ln.sections[0]), ("end_b", ln.sections[-1])):
            end, strain = ln.end(which), sec.line_type.max_strain
            if isinstance(end, BodyEnd):
                if not scene.bodies[end.body].is_free:
                    world = scene.bodies[end.body].world(end.offset)
                    ends.append((f"lines[{i}].{which}", end.text,
                                 tuple(float(v) for v in world), strain))
            elif isinstance(end, str):
                if not scene.points[end].is_free:
                    pt = scene.points[end]
                    ends.append((f"{_key('points', end)}.position", list(pt.position),
                                 pt.position, strain))
            elif end.position is not None:
                ends.append((f"lines[{i}].{which}.position", list(end.position),
                             end.position, strain))
        out.append((f"lines[{i}] ({ln.name!r})", ln.sections, ends))
    return out


def _lowest_reach(a, b, reach: float) -> float:
    """The lowest z that a line of stretched length at most ``reach`` between the points
    ``a`` and ``b`` can reach: the bottom of the ellipsoid of foci a, b and major axis
    ``reach`` (the points p with |pa| + |pb| <= reach)."""
    a, b = np.asarray(a, float), np.asarray(b, float)
    d = float(np.linalg.norm(b - a))
    half = 0.5 * reach
    minor2 = max(half * half - 0.25 * d * d, 0.0)
    ez = float(b[-1] - a[-1]) / d if d > 0 else 0.0
    return float(0.5 * (a[-1] + b[-1])) - math.sqrt(half * half * ez * ez
                                                    + minor2 * (1.0 - ez * ez))


def _check_free_surface(scene) -> None:
    """Refuse a line that the scene's held ends put mostly out of the water, in a scene in
    water (``environment.water_density > 0``; a scene in air is not checked).

    symcable has no free surface: every line is loaded as submerged (its buoyancy, drag and
    added mass in water of ``water_density``) wherever it is, and the free surface is z = 0
    (the README's "A scene file"). A line may rise out of the water to an end held above
    it (a fairlead or a towpoint on a deck): that part is computed with water's loads, an
    error in proportion to its length which that idealisation accepts. What the held ends
    alone put out of the water, before any solve, is at least: the whole line when it
    cannot reach z = 0 even stretched to its line types' ``max_strain`` (both ends held);
    else, for each held end a height h above the surface, h / (1 + max_strain) of
    unstretched line (the line has to come down that far to reach the water). When that is
    more than half of the line's length, the line is certainly mostly in air while the
    scene computes it in water: one SceneError naming the highest end, its position, how
    much of the line is in air and what is allowed. A line found out of the water only by
    the solve, and a free point or body floating up out of it, are checked on the solution
    (:mod:`symcable.api.above_water`)."""
    if scene.environment.in_air:
        return
    for label, sections, ends in _held_ends(scene):
        length = sum(s.length for s in sections)
        tol = 1e-9 * length
        up = [e for e in ends if e[2][-1] > tol]
        if not up:
            continue
        reach = sum(s.length * (1.0 + s.line_type.max_strain) for s in sections)
        whole = len(ends) == 2 and _lowest_reach(ends[0][2], ends[1][2], reach) > 0.0
        out = length if whole else sum(e[2][-1] / (1.0 + e[3]) for e in up)
        if not out > 0.5 * length:
            continue
        key, shown, position, _ = max(up, key=lambda e: e[2][-1])
        also = "".join(f", and {k} at z = {_fmt(p[-1])} m" for k, _, p, _ in ends if k != key)
        amount = (f"it cannot reach the water even stretched to max_strain: all of its "
                  f"{_fmt(length)} m is in air" if whole else
                  f"at least {_fmt(out)} m of its {_fmt(length)} m "
                  f"({100 * out / length:.0f} %) is then in air")
        unit = "m" if key.endswith(".position") else ""
        what = "" if unit else "this point of the fixed body is "
        raise _err(key, shown, unit,
                   f"{what}{_fmt(position[-1])} m above the free surface (z = 0){also}: "
                   f"{label} hangs mostly out of the water ({amount}), yet symcable loads every "
                   "line as submerged (water's buoyancy, drag and added mass: it has no free "
                   "surface); a line may rise out of the water to an end above it (a fairlead), "
                   "not lie mostly in air: lower the end below z = 0, lengthen the line, or set "
                   "environment.water_density = 0 for a line in air")
