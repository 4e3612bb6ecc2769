"""The sweep file (``CASES.toml``): one scene, one analysis, the outputs to keep, the cases.

::

    name = "OC3 line, offsets and current"   # optional (default: the file's stem)
    scene = "oc3.toml"            # relative to this file: a TOML scene or a MoorDyn v2 deck
    analysis = "simulate"         # "static" | "simulate" | "periodic"
    outputs = ["fairlead_tension_max", "fairlead_tension_min"]   # see symcable.sweep.case
    # codegen = false             # optional: see symcable.sweep.run (default: compile once)

    [simulate]                    # the analysis' options, under its own name:
    duration = 60.0               #   simulate: duration s (required), dt s, method
    dt = 0.1                      #   ("generalized-alpha", "rk4"), discard s (statistics
    discard = 20.0                #   from this long after the start); periodic: method
                                  #   ("shooting", "collocation", "harmonic-balance");
                                  #   static: none

    [grid]                        # every combination of these values: 3 x 2 = 6 cases
    "end_b.position" = [[-5.2, 0.0, -70.0], [0.0, 0.0, -70.0], [5.2, 0.0, -70.0]]
    "environment.current" = [[0.0, 0.0, 0.0], [0.5, 0.0, 0.0]]

    [[cases]]                     # and/or cases one by one, each with a unique name
    name = "long period, fine step"
    "end_b.motion.period" = 14.0
    "simulate.dt" = 0.05

A case overrides keys of the scene by dotted path (:mod:`.overrides`); TOML's own dotted
keys (unquoted, ``end_b.motion.period = 14.0``) are nested tables and mean the same. A key
that starts with the analysis' name sets one of its options for the case
(``"simulate.dt" = 0.05``: a sweep of time steps). Cases
are the ``[[cases]]`` in order and the grid's combinations (its first key varying slowest),
in the order the file gives the two; a grid case is named by its values
(``position=-5.2_0_-70,current=0_0_0``). The first case to run compiles the generated C the
others reuse (:mod:`.run`): put a representative one first.

Every case's scene is loaded before anything runs. A path that cannot be followed, or a key
the scene does not know, is an error of the file (one SceneError naming the case, the key
and what is allowed); a valid file whose case makes an invalid scene (a fairlead the line
cannot reach) makes that case fail, recorded with the message, and the others run.

Limits (:mod:`symcable.limits`): the number of cases, the ``[[cases]]`` and the product of
the grid's list lengths, is checked against ``sweep_cases`` before the grid is expanded;
the file is read as a regular file of at most ``file_bytes`` and nested no deeper than
``nesting``. Case names (and the sweep's ``name``) are 1 to 200 printable characters: one
line of the summary; result files are named by a file-safe form of them (:attr:`Case.stem`).
"""
from __future__ import annotations

import hashlib
import itertools
import json
import math
import os
import re
import reprlib
import sys
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Mapping

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover - exercised on Python 3.10 only
    import tomli as tomllib

from ..data import names, scene_path
from ..errors import SceneError
from ..limits import check, check_nesting, check_toml_nesting, read_bounded
from ..scene import Scene, load_scene, moordyn_deck
from .case import ANALYSES, available_outputs
from .overrides import apply_overrides, parse_path, plain

__all__ = ["Case", "Sweep", "read_sweep"]

#: bump when what a case's hash covers changes (every saved case then runs again)
FORMAT = 1
_TOP_KEYS = ("name", "scene", "analysis", "outputs", "codegen", "grid", "cases", *ANALYSES)
#: each analysis' options: key -> (kind, what is allowed)
_OPTIONS = {
    "static": {},
    "simulate": {"duration": "s > 0 (required)", "dt": "s > 0", "discard": "s >= 0, < duration",
                 "tol": "in (0, 1), not with dt", "method": "'generalized-alpha' or 'rk4'"},
    "periodic": {"method": "'shooting', 'collocation' or 'harmonic-balance'"},
}
_METHODS = {"simulate": ("generalized-alpha", "rk4"),
            "periodic": ("shooting", "collocation", "harmonic-balance")}
_DEFAULT_OUTPUTS = {"static": ("fairlead_tension", "anchor_tension"),
                    "simulate": ("fairlead_tension_max", "fairlead_tension_min",
                                 "fairlead_tension_mean"),
                    "periodic": ("fairlead_tension_max", "fairlead_tension_min",
                                 "fairlead_tension_mean")}
_UNSAFE = re.compile(r"[^A-Za-z0-9._=,+-]+")
#: longest grid case name made of its values (and longest file-safe name in a result
#: file's name); longer ones, or with characters that are not printable, are named
#: grid0001, ...
MAX_NAME = 80
#: longest name of a case or of the sweep
MAX_CASE_NAME = 200
_NAME_RULE = (f"1 to {MAX_CASE_NAME} printable characters, not all spaces (no newlines or "
              "control characters: a name is one line of the summary)")
_REPR = reprlib.Repr()
_REPR.maxlevel, _REPR.maxlist, _REPR.maxtuple, _REPR.maxdict = 4, 8, 8, 8
_REPR.maxstring = _REPR.maxother = 100


@dataclass(frozen=True)
class Case:
    """One case: its ``name``, its ``overrides`` (dotted path -> value; a path that starts
    with the analysis' name, ``simulate.dt``, sets one of its options), its loaded ``scene``
    (None when the overrides make an invalid scene: ``error`` then has the SceneError's
    message), its analysis ``options``, and ``hash``: 12 hex digits of everything its result
    depends on (the scene with its overrides and motion tables, the analysis and its
    options)."""

    name: str
    overrides: Mapping[str, Any]
    scene: Scene | None
    error: str
    hash: str
    options: Mapping[str, Any] = field(default_factory=dict)

    @property
    def stem(self) -> str:
        """The name of its result file without ``.json``: its name made file-safe, its hash."""
        return f"{_UNSAFE.sub('_', self.name)[:MAX_NAME]}-{self.hash}"


@dataclass(frozen=True)
class Sweep:
    """A read and validated sweep file (:func:`read_sweep`)."""

    name: str
    source: str
    scene_source: str
    analysis: str
    options: Mapping[str, Any]
    outputs: tuple
    codegen: bool | None
    cases: tuple
    keys: tuple = ()
    out: Path | None = None
    model: str = "planar"
    lines: tuple = field(default=())


def _show(value: Any) -> str:
    """``repr(value)`` shortened (long lists, deep nesting, long strings) to 100 characters."""
    if isinstance(value, int) and value.bit_length() > 300:  # repr of a huge int may raise
        return f"<an integer of {value.bit_length()} bits>"
    text = _REPR.repr(value)
    return text if len(text) <= 100 else text[:97] + "..."


def _err(key: str, value: Any, allowed: str, where: str = "") -> SceneError:
    return SceneError(f"{where}{key} = {_show(value)}: {allowed}".replace("\n", " "))


def _name(key: str, value: Any, where: str, allowed: str = _NAME_RULE) -> str:
    """``value``, a name of a case or of the sweep: checked (SceneError otherwise)."""
    if (not isinstance(value, str) or not 0 < len(value) <= MAX_CASE_NAME
            or not value.isprintable() or not value.strip()):
        raise _err(key, value, allowed, where)
    return value


def _flatten(table: Mapping) -> dict:
    """``{"a": {"b": 1}}`` -> ``{"a.b": 1}`` (TOML's dotted keys are nested tables), in the
    table's order; walked without recursion."""
    out = {}
    stack = [("", iter(table.items()))]
    while stack:
        prefix, items = stack[-1]
        for k, v in items:
            key = f"{prefix}.{k}" if prefix else str(k)
            if isinstance(v, Mapping):
                stack.append((key, iter(v.items())))
                break
            out[key] = v
        else:
            stack.pop()
    return out


def _read_file(path: Path, what: str = "sweep file") -> dict:
    """The TOML file ``path`` (a sweep or scene file), read within the limits: a regular file
    of at most ``file_bytes``, nested no deeper than ``nesting``."""
    try:
        text = read_bounded(path, "file_bytes", what).decode("utf-8")
    except FileNotFoundError:
        raise SceneError(f"{path}: {what} not found") from None
    except OSError as exc:
        raise SceneError(f"{path}: cannot read {what} ({exc.strerror or exc})") from None
    except UnicodeDecodeError as exc:
        raise SceneError(f"{path}: invalid TOML: not UTF-8 text ({exc.reason} at byte "
                         f"{exc.start})") from None
    check_toml_nesting(text, f"{what} {str(path)!r}")
    try:
        data = tomllib.loads(text)
    except (ValueError, RecursionError) as exc:
        raise SceneError(f"{path}: invalid TOML: {exc}".replace("\n", " ")) from None
    check_nesting(data, f"{what} {str(path)!r}")
    return data


def _base_scene(raw: Any, base: Path, where: str) -> tuple:
    """``(scene dict, folder its files are read from, Scene, source)`` of ``scene = ...``."""
    if isinstance(raw, Scene):
        return plain(raw.to_dict()), Path.cwd(), raw, raw.source
    if isinstance(raw, Mapping):
        return plain(raw), base, load_scene(raw, base=base), "<dict>"
    if not isinstance(raw, (str, os.PathLike)):
        raise _err("scene", raw, "must be the path of a scene file (TOML or a MoorDyn deck), "
                   "relative to the sweep file, or a built-in scene's name", where)
    path = base / Path(raw)
    if not path.exists():
        builtin = scene_path(str(raw)) if isinstance(raw, str) else None
        if builtin is None:
            raise _err("scene", str(raw), f"no such file ({path}), nor a built-in scene "
                       f"({', '.join(names())})", where)
        scene = load_scene(str(raw))
        return plain(scene.to_dict()), base, scene, scene.source
    try:
        scene = load_scene(path)
    except SceneError as exc:
        raise SceneError(f"{where}scene = {str(raw)!r}: {exc}") from None
    deck = moordyn_deck(path)
    data = deck.scene if deck is not None else _read_file(path, "scene file")
    return plain(data), path.parent, scene, str(path)


def _options(analysis: str, raw: Any, where: str) -> dict:
    """The analysis' options ``raw`` (its table, or with a case's own), checked."""
    if not isinstance(raw, Mapping):
        raise _err(f"[{analysis}]", raw, "must be a table of the analysis' options", where)
    allowed = _OPTIONS[analysis]
    for key in raw:
        if key not in allowed:
            what = (", ".join(f"{k} ({v})" for k, v in allowed.items()) if allowed
                    else "none: a static analysis has no options")
            raise _err(f"{analysis}.{key}", raw[key], f"unknown option (allowed: {what})", where)
    out = dict(raw)
    for key in ("duration", "dt", "discard"):
        if key in out:
            v = out[key]
            ok = isinstance(v, (int, float)) and not isinstance(v, bool) and v == v
            if not ok or (v < 0 if key == "discard" else v <= 0) or v == float("inf"):
                raise _err(f"{analysis}.{key}", v, f"must be a number, {allowed[key]}", where)
            out[key] = float(v)
    if "tol" in out:
        v = out["tol"]
        if isinstance(v, bool) or not isinstance(v, (int, float)) or not 0.0 < v < 1.0:
            raise _err(f"{analysis}.tol", v, f"must be a number {allowed['tol']}", where)
        if "dt" in out:
            raise _err(f"{analysis}.tol", v, "give dt (a fixed step) or tol (the step chosen "
                       "for it), not both", where)
        out["tol"] = float(v)
    if analysis == "simulate":
        if "duration" not in out:
            raise SceneError(f"{where}simulate.duration: required key missing (s > 0: how long "
                             "each case runs)")
        if out.get("discard", 0.0) >= out["duration"]:
            raise _err("simulate.discard", out["discard"], f"must be < simulate.duration = "
                       f"{out['duration']:g} s (statistics need samples after it)", where)
    if "method" in out and out["method"] not in _METHODS[analysis]:
        raise _err(f"{analysis}.method", out["method"], f"must be {allowed['method']}", where)
    return out


def _outputs(raw: Any, analysis: str, scene: Scene, where: str) -> tuple:
    lines = tuple(ln.name for ln in scene.lines)
    allowed = available_outputs(analysis, scene, lines)
    if raw is None:
        names = _DEFAULT_OUTPUTS[analysis]
        return tuple(f"{ln}.{n}" for ln in lines for n in names) if lines else names
    if not isinstance(raw, list) or not raw or not all(isinstance(x, str) for x in raw):
        raise _err("outputs", raw, "must be a non-empty list of output names", where)
    for name in raw:
        if name not in allowed:
            head = f"line outputs of a scene of several lines are NAME.output, NAME one of " \
                   f"{', '.join(lines)}; " if lines else ""
            raise _err("outputs", name, f"not an output of a {scene.model.value} '{analysis}' "
                       f"analysis ({head}allowed: {', '.join(allowed)})", where)
    if len(set(raw)) != len(raw):
        raise _err("outputs", raw, "names an output twice", where)
    return tuple(raw)


def _fmt(v: Any) -> str:
    if isinstance(v, float):
        return f"{v:g}"
    if isinstance(v, (list, tuple)):
        return "_".join(_fmt(x) for x in v)
    return str(v)


def _grid_table(raw: Any, where: str) -> dict:
    """The grid, flattened (dotted key -> its list of values) and checked, not expanded."""
    if not isinstance(raw, Mapping) or not raw:
        raise _err("[grid]", raw, "must be a table of scene keys, each with a list of values",
                   where)
    grid = _flatten(raw)
    for key, values in grid.items():
        parse_path(key, f"{where}grid key")
        if not isinstance(values, list) or not values:
            raise _err(f"grid.{key!r}", values, "must be a non-empty list of values (one case "
                       "per value; a vector's values are lists: [[0.5, 0, 0], [1.0, 0, 0]])",
                       where)
    return grid


def _count(data: Mapping, grid: Mapping | None, where: str) -> None:
    """Refuse a sweep of more cases than the ``sweep_cases`` limit: its ``[[cases]]`` and the
    product of its grid's list lengths, counted without expanding the grid."""
    listed = data.get("cases")
    n_listed = len(listed) if isinstance(listed, list) else 0
    sizes = [len(v) for v in grid.values()] if grid else []
    n = n_listed + (math.prod(sizes) if sizes else 0)
    parts = [f"[[cases]] {n_listed:,}"] if n_listed else []
    if sizes:
        shown = sizes if len(sizes) <= 6 else [*sizes[:3], "...", sizes[-1]]
        parts.append(f"[grid] {' x '.join(map(str, shown))}"
                     + (f" ({len(sizes):,} keys)" if len(sizes) > 6 else ""))
    check("sweep_cases", n if n.bit_length() < 1000 else math.inf,
          f"{where}cases ({' + '.join(parts)})", "every case's scene is built and checked "
          "before the first runs")


def _grid(grid: Mapping) -> list:
    """The grid's cases: ``[(name, overrides, label)]`` (its first key varying slowest); a
    case is named by its values, or ``grid0001``, ... when that name would be longer than
    MAX_NAME or not printable."""
    keys = list(grid)
    short = [k.split(".")[-1] for k in keys]
    short = [s if short.count(s) == 1 else k for s, k in zip(short, keys)]
    width = len(str(math.prod(len(v) for v in grid.values())))
    out = []
    for i, values in enumerate(itertools.product(*grid.values())):
        name = ",".join(f"{s}={_fmt(v)}" for s, v in zip(short, values))
        ok = len(name) <= MAX_NAME and name.isprintable()
        out.append((name if ok else f"grid{i + 1:0{width}d}", dict(zip(keys, values)),
                    f"grid case {i}"))
    return out


def _listed(raw: Any, where: str) -> list:
    if not isinstance(raw, list) or not all(isinstance(c, Mapping) for c in raw):
        raise _err("[[cases]]", raw, "must be an array of tables, each with a name and scene "
                   "keys", where)
    out = []
    for i, case in enumerate(raw):
        name = _name(f"cases[{i}].name", case.get("name"), where,
                     f"required: a string naming the case, {_NAME_RULE}")
        overrides = _flatten({k: v for k, v in case.items() if k != "name"})
        for key in overrides:
            parse_path(key, f"{where}cases[{i}] ({name!r}) key")
        out.append((name, overrides, f"cases[{i}]"))
    return out


def _tables(scene: Scene) -> list:
    """The rows of every motion table of the scene (a table file's content is part of a
    case: its hash changes with the file)."""
    ends = [scene.end_a, scene.end_b] + [e for ln in scene.lines for e in (ln.end_a, ln.end_b)]
    motions = [getattr(e, "motion", None) for e in ends if e is not None and not isinstance(e, str)]
    motions += [pt.motion for pt in scene.points.values()]
    return [list(map(list, m.samples)) for m in motions if m is not None and m.kind == "table"]


def case_hash(scene_dict: Mapping, scene: Scene | None, analysis: str, options: Mapping) -> str:
    """12 hex digits of SHA-256 over a case's full content (canonical JSON)."""
    content = {"format": FORMAT, "scene": scene_dict, "analysis": analysis,
               "options": dict(sorted(options.items())),
               "tables": _tables(scene) if scene is not None else None}
    text = json.dumps(content, sort_keys=True, separators=(",", ":"), default=str)
    return hashlib.sha256(text.encode()).hexdigest()[:12]


def _case(name: str, overrides: dict, raw: dict, folder: Path, analysis: str,
          options: Mapping, where: str) -> Case:
    own = {k.split(".", 1)[1]: v for k, v in overrides.items() if k.startswith(analysis + ".")}
    if own:
        options = _options(analysis, {**options, **own}, f"{where}: ")
    merged = apply_overrides(raw, {k: v for k, v in overrides.items()
                                   if not k.startswith(analysis + ".")}, where)
    try:
        scene, error = load_scene(merged, base=folder), ""
    except SceneError as exc:
        if ": unknown key" in str(exc):  # the base scene loads: the case's key is wrong
            raise SceneError(f"{where}: {exc}") from None
        scene, error = None, f"SceneError: {exc}"
    return Case(name, overrides, scene, error, case_hash(merged, scene, analysis, options),
                dict(options))


def read_sweep(source: Any) -> Sweep:
    """Read and validate a sweep: its scene, analysis, outputs and every case's scene.

    The layout is the sweep file's (module docstring). Every case's scene is loaded here,
    before anything runs; a case whose scene is invalid is kept with its error (it fails
    when run), a key the scene does not know is an error of the file.

    Parameters
    ----------
    source : str, path, dict or Sweep
        The path of a sweep file (TOML; its ``scene`` relative to the file), a dict in its
        layout (``scene`` a path relative to the current folder, a scene dict or a Scene),
        or a :class:`Sweep` (returned as it is).

    Returns
    -------
    Sweep
        The validated sweep: its cases in run order (``[[cases]]`` and the grid's
        combinations, in the file's order), each with its scene and content hash; ``out``
        the results folder ``<stem>-results`` beside the file (None for a dict).

    Raises
    ------
    SceneError
        One line naming the file, the key, the value and what is allowed.
    LimitError
        More cases than the ``sweep_cases`` limit, a file larger than ``file_bytes`` or
        nested deeper than ``nesting`` (:func:`symcable.limits`).
    """
    if isinstance(source, Sweep):
        return source
    if isinstance(source, (str, os.PathLike)):
        path = Path(source)
        data, base, label = _read_file(path), path.resolve().parent, str(path)
        out = path.resolve().parent / f"{path.stem}-results"
    elif isinstance(source, Mapping):
        check_nesting(source, "<dict>")
        data, base, label, out = dict(source), Path.cwd(), "<dict>", None
    else:
        raise _err("sweep", source, "must be the path of a sweep file (TOML), a dict in its "
                   "layout or a Sweep")
    where = f"{label}: "
    for key in data:
        if key not in _TOP_KEYS:
            raise _err(str(key), data[key], f"unknown key (allowed: {', '.join(_TOP_KEYS)})",
                       where)
    if "name" in data:
        name = _name("name", data["name"], where, f"must be a string, {_NAME_RULE}")
    else:
        name = Path(label).stem if label != "<dict>" else "sweep"
    grid = _grid_table(data["grid"], where) if data.get("grid") is not None else None
    _count(data, grid, where)
    if "scene" not in data:
        raise SceneError(f"{where}scene: required key missing (the scene file the cases change)")
    raw, folder, scene, scene_source = _base_scene(data["scene"], base, where)
    analysis = data.get("analysis")
    if analysis not in ANALYSES:
        raise _err("analysis", analysis, f"must be one of {', '.join(map(repr, ANALYSES))}",
                   where)
    for other in ANALYSES:
        if other != analysis and data.get(other) is not None:
            raise _err(f"[{other}]", data[other], f"options of analysis '{other}', but "
                       f"analysis = '{analysis}': remove it or change the analysis", where)
    options = _options(analysis, data.get(analysis, {}), where)
    outputs = _outputs(data.get("outputs"), analysis, scene, where)
    codegen = data.get("codegen")
    if codegen is not None and not isinstance(codegen, bool):
        raise _err("codegen", codegen, "must be true or false (absent: symcable's default)",
                   where)
    listed = []
    for key in data:  # in the file's order
        if key == "cases" and data["cases"] is not None:
            listed += _listed(data["cases"], where)
        elif key == "grid" and grid is not None:
            listed += _grid(grid)
    if not listed:
        raise SceneError(f"{where}no cases: give [[cases]] (each a name and scene keys) or "
                         "[grid] (scene keys with lists of values)")
    seen: dict = {}
    for n, _, label in listed:
        if n in seen:
            grid = label.startswith("grid") and seen[n].startswith("grid")
            raise _err(label if grid else f"{label}.name", n, f"already the name of {seen[n]}"
                       + (" (the grid gives the same values twice)" if grid else "")
                       + ": names must be unique", where)
        seen[n] = label
    cases = tuple(_case(n, ov, raw, folder, analysis, options, f"{where}{label} ({n!r})")
                  for n, ov, label in listed)
    keys = tuple(dict.fromkeys(k for c in cases for k in c.overrides))
    return Sweep(name, label, scene_source, analysis, options, outputs, codegen, cases, keys,
                 out, scene.model.value, tuple(ln.name for ln in scene.lines))
