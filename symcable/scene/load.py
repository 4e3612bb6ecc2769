"""Reading, validating and writing scenes (the scene-file layout of the README, "A scene file").

:func:`load_scene` turns a TOML file, a dict in the file's layout or a MoorDyn v2 deck
(:mod:`.moordyn`) into a frozen :class:`~symcable.scene.Scene`; :func:`scene_to_dict` and
:func:`scene_to_toml` go back.
Every bad input raises a one-line :class:`~symcable.errors.SceneError` of the form
``<key path> = <value> [unit]: <what is allowed>``, for example
``sections[0].length = -3.0 m: must be > 0``.
A key given as ``None`` (possible in a dict, not in TOML) counts as not given.
"""
from __future__ import annotations

import os
import sys
from types import MappingProxyType
from typing import Any, Mapping

import tomli_w

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover - exercised on Python 3.10 only
    import tomli as tomllib

from ..errors import LimitError, SceneError
from ..data import resolve
from ..limits import check, check_nesting, check_toml_nesting, read_bounded
from .checks import _check_free_surface, _check_keys, _check_text, _choice, _err, _get
from .model import _DIMS, Model, Scene, scene_to_dict
from .moordyn import MoorDynDeck, is_moordyn_deck, parse_moordyn
from .system import read_system
from .tables import (MAX_STIFFNESS_RATIO, _check_geometry, _end, _environment, _line_types,
                     _seabed, _sections, _check_friction_options)

__all__ = ["MAX_STIFFNESS_RATIO", "load_scene", "moordyn_deck", "scene_to_dict", "scene_to_toml"]

_TOP_KEYS = ("name", "model", "environment", "seabed", "line_types", "sections", "end_a", "end_b",
             "points", "lines", "mass_matrix", "bodies", "zones")
_MASS_MATRICES = ("lumped", "consistent")
_ZONES = ("given", "auto")
_MODELS = tuple(m.value for m in Model)


# ----------------------------------------------------------------------------- public API

def _builtin_hint(path: str) -> str:
    """For a name without a folder: the built-in scenes, the closest first."""
    if os.sep in str(path) or "/" in str(path):
        return ""
    from difflib import get_close_matches

    from ..data import names
    close = get_close_matches(str(path).removesuffix(".toml"), names(), n=1)
    return (f" (nor a built-in scene{f'; did you mean {close[0]!r}?' if close else ':'}"
            f"{'' if close else ' ' + ', '.join(names())})")


def _read_text(path: str) -> tuple[str | None, str]:
    """``(text, error)`` of a scene file: its UTF-8 text (None when it is not UTF-8, then
    ``error`` says why), read as a regular file under the ``file_bytes`` limit."""
    try:
        raw = read_bounded(path, "file_bytes", "scene file")
    except FileNotFoundError:
        raise SceneError(f"{path}: scene file not found{_builtin_hint(path)}") from None
    except OSError as exc:
        raise SceneError(f"{path}: cannot read scene file ({exc.strerror or exc})") from None
    try:
        return raw.decode("utf-8"), ""
    except UnicodeDecodeError as exc:
        return None, f"not UTF-8 text ({exc.reason} at byte {exc.start})"


def _parse_toml(text: str, path: str) -> dict:
    """TOML text as a dict; its nesting checked first (the parser recurses per level)."""
    check_toml_nesting(text, f"scene file {path!r}")
    try:
        data = tomllib.loads(text)
    except ValueError as exc:  # TOMLDecodeError
        raise SceneError(f"{path}: invalid TOML: {exc}".replace("\n", " ")) from None
    except RecursionError:
        raise SceneError(f"{path}: invalid TOML: nested too deeply to parse") from None
    check_nesting(data, f"scene file {path!r}")  # dotted keys nest without brackets
    return data


def _read_file(path: str) -> tuple[Any, MoorDynDeck | None]:
    """A scene file's dict: TOML, or else a MoorDyn deck (then also the deck)."""
    text, why = _read_text(path)
    if text is not None and is_moordyn_deck(text):
        try:
            tomllib.loads(text)
        except (ValueError, RecursionError):  # not TOML: a deck
            return _deck(text, path)
    if text is None:
        raise SceneError(f"{path}: invalid TOML: {why}")
    return _parse_toml(text, path), None


def _deck(text: str, path: str) -> tuple[dict, MoorDynDeck]:
    deck = parse_moordyn(text, path)
    check_nesting(deck.scene, f"MoorDyn deck {path!r}")
    return deck.scene, deck


def moordyn_deck(path: str | os.PathLike) -> MoorDynDeck | None:
    """The MoorDyn deck at ``path`` as :func:`load_scene` reads it (its scene dict and its
    notes on what it ignored), or None when the file is TOML, unreadable or not a deck.

    Raises
    ------
    SceneError
        When the file is a deck that cannot be represented (:func:`.moordyn.parse_moordyn`).
    LimitError
        When the file is not a regular file or is larger than the ``file_bytes`` limit.
    """
    name = os.fspath(path)
    try:
        text, _ = _read_text(name)
    except SceneError:
        return None
    if text is None or not is_moordyn_deck(text):
        return None
    try:
        tomllib.loads(text)
        return None
    except (ValueError, RecursionError):
        return _deck(text, name)[1]


def load_scene(source: str | os.PathLike | Mapping | Scene, *,
               base: str | os.PathLike | None = None) -> Scene:
    """Read and validate a scene.

    Parameters
    ----------
    source : str, os.PathLike, dict or Scene
        Path of a TOML scene file or of a MoorDyn v2 deck (a file that is not TOML and looks
        like one, :mod:`.moordyn`); the name of a built-in scene (``"oc3"``, ``"sphere"``:
        :func:`symcable.data.names`) when no file of that name exists; a dict in the scene layout, or a Scene (returned unchanged).
    base : str or os.PathLike, optional
        For a dict: the folder its relative file names (a motion table's ``file``) are read
        from, as a scene file's own folder is for the file (default: the current folder).

    Returns
    -------
    Scene
        Frozen and validated; SI units, vectors as tuples of float, ``line_types`` read-only.

    Raises
    ------
    SceneError
        With a one-line message naming the key, the value and what is allowed (for a deck,
        prefixed with the deck's line the key came from).
    """
    if isinstance(source, Scene):
        return source
    deck = None
    if isinstance(source, (str, os.PathLike)):
        name = os.fspath(resolve(source))
        data, deck = _read_file(name)
    elif isinstance(source, Mapping):
        name, data = "<dict>", source
        check_nesting(data, "scene")
    else:
        raise _err("scene", source, "", "must be a path to a TOML file, a dict or a Scene")
    try:
        if name != "<dict>":
            base = os.path.dirname(os.path.abspath(name))
        base = os.getcwd() if base is None else os.fspath(base)
        return _build(data, str(name), base)
    except (SceneError, LimitError) as exc:
        if deck is None:
            raise
        raise type(exc)(deck.locate(str(exc))) from None  # the deck line the key came from
    except Exception as exc:  # a gap in the checks above: still report it as a scene error
        raise SceneError(f"{name}: invalid scene ({type(exc).__name__}: {exc})"
                         .replace("\n", " ")) from exc


def _build(data: Mapping, source: str, base: str = ".") -> Scene:
    _check_keys("", data, _TOP_KEYS)
    name = _get(data, "name", "unnamed")
    _check_text("name", name, "a scene's name", 200)
    model = Model(_choice("model", _get(data, "model", Model.PLANAR.value), _MODELS, "model"))
    dim = _DIMS[model]
    mass_matrix = _choice("mass_matrix", _get(data, "mass_matrix", "lumped"), _MASS_MATRICES,
                          "mass_matrix")
    if mass_matrix != "lumped" and model is not Model.CABLE3D:
        raise _err("mass_matrix", mass_matrix, "", "a mass matrix other than 'lumped' is a "
                   "cable3d option (model = 'cable3d')")
    env = _environment(data, dim)
    seabed = _seabed(data, env)
    zones = _choice("zones", _get(data, "zones", "given"), _ZONES, "zones")
    if zones != "given" and model is not Model.HYBRID:
        raise _err("zones", zones, "", 'rod zones are chosen in model = "hybrid" only: '
                   "remove zones, or set model = 'hybrid'")
    types = _line_types(data, env, dim)
    rod_keys = model in (Model.ROD, Model.HYBRID)
    if not rod_keys:
        _refuse_rod_keys(types)
    if _get(data, "lines") is not None:  # version 2: several lines and points
        if model not in (Model.CABLE3D,):
            raise _err("lines", "[...]", "", f'several lines ([[lines]]) are read by model = '
                       f'"cable3d" only, not {model.value!r}: give one line ([[sections]], '
                       'end_a, end_b), or set model = "cable3d"')
        _check_friction_options(seabed, model.value, True, None)
        points, lines, bodies = read_system(data, env, types, dim, model.value, base)
        _check_segments({f"lines[{k}].sections": ln.sections for k, ln in enumerate(lines)},
                        model, zones)
        for k, ln in enumerate(lines):
            _check_section_models(model, zones, ln.sections, f"lines[{k}].sections")
        scene = Scene(name=name, model=model, environment=env, seabed=seabed,
                      line_types=MappingProxyType(types), sections=(), end_a=None, end_b=None,
                      source=source, points=points, lines=lines, mass_matrix=mass_matrix,
                      bodies=bodies)
        _check_free_surface(scene)  # a line the held ends put mostly out of the water
        return scene
    for key in ("points", "bodies"):
        if _get(data, key) is not None:
            raise _err(key, "{...}", "", f"{key} are attached to [[lines]] (scene version 2): "
                       f"give [[lines]] with end_a / end_b naming them, or remove [{key}]")
    sections = _sections(data, types)
    _check_segments({"sections": sections}, model, zones)
    _check_section_models(model, zones, sections, "sections")
    ends = {"end_a": _end("end_a", data, dim, base), "end_b": _end("end_b", data, dim, base)}
    for key, end in ends.items():
        # a hybrid's end section: its model, or unknown until zones = "auto" picks it
        sec = sections[0 if key == "end_a" else -1]
        rod_end = model is Model.ROD or (model is Model.HYBRID and (
            zones == "auto" or sec.model == "rod"))
        where = ('model = "rod", or a rod section of model = "hybrid"'
                 if model is Model.HYBRID else 'model = "rod" only')
        if end.guided and model not in (Model.ROD, Model.HYBRID):
            raise _err(f"{key}.direction", list(end.direction), "", 'a guided end (free, its '
                       'tangent held) is read by model = "rod" or "hybrid" only: pin or '
                       "clamp the end, or remove direction")
        if end.twist_deg is not None and not rod_end:
            raise _err(f"{key}.twist_deg", end.twist_deg, "deg", f"read by {where} "
                       "(a cable has no material frame): remove it")
        if end.moment is not None and not rod_end:
            raise _err(f"{key}.moment", list(end.moment), "N m", f"read by {where} (a "
                       "cable carries no moment): remove it")
    _check_geometry(env, sections, ends, dim)
    _check_friction_options(seabed, model.value, False, ends)
    scene = Scene(name=name, model=model, environment=env, seabed=seabed,
                  line_types=MappingProxyType(types), sections=sections,
                  end_a=ends["end_a"], end_b=ends["end_b"], source=source,
                  mass_matrix=mass_matrix, zones=zones)
    _check_free_surface(scene)  # a line the held ends put mostly out of the water
    return scene


def _check_segments(by_key: Mapping[str, tuple], model: Model, zones: str) -> None:
    """The scene's segments, all lines together, within the ``segments`` limit, and those of
    its rod sections within ``rod_segments`` (a section over a limit alone is named by its
    key)."""
    def is_rod(sec) -> bool:
        return model is Model.ROD or (model is Model.HYBRID and (zones == "auto" or
                                                                 sec.model == "rod"))

    for name, what, mine in (("segments", "", lambda sec: True),
                             ("rod_segments", "rod ", is_rod)):
        why = (f"a guard against scenes that exhaust memory: each {what}segment costs "
               f"{'about 0.7 MB' if what else 'tens of kB'} of symbolic graph and solver")
        for key, sections in by_key.items():
            for i, sec in enumerate(sections):
                if mine(sec):
                    check(name, sec.segments, f"{key}[{i}].segments"
                          + (" (rod segments)" if what else ""), why)
        check(name, sum(sec.segments for secs in by_key.values() for sec in secs if mine(sec)),
              f"the scene's {what}segments, all lines together", why)


def _check_section_models(model: Model, zones: str, sections, key: str) -> None:
    """A section's ``model`` is read by ``model = "hybrid"`` with zones given; a rod section
    needs EI > 0 and GJ > 0 in its line type."""
    for i, sec in enumerate(sections):
        if sec.model is None:
            continue
        path = f"{key}[{i}].model"
        if model is not Model.HYBRID:
            raise _err(path, sec.model, "", 'a section\'s formulation is read by model = '
                       f'"hybrid" only (this scene is model = {model.value!r}): remove it, '
                       "or set model = 'hybrid'")
        if zones == "auto":
            raise _err(path, sec.model, "", 'zones = "auto" chooses every section\'s '
                       "formulation: remove it, or remove zones")
        lt = sec.line_type
        if sec.model == "rod" and not (lt.EI > 0 and (lt.EI_2 is None or lt.EI_2 > 0)
                                       and lt.GJ > 0):
            raise _err(path, sec.model, "", f"a rod section needs EI > 0 and GJ > 0 in its "
                       f"line type, but line_types.{lt.name} has EI = {lt.EI!r}, GJ = "
                       f"{lt.GJ!r} N m^2 (give them, or model = 'cable3d')")


def _refuse_rod_keys(types) -> None:
    """Torsion and two principal bending stiffnesses are read by ``model = "rod"`` (and
    ``"hybrid"``) only."""
    for name, lt in types.items():
        if lt.EI_2 is not None:
            raise _err(f"line_types.{name}.EI", [lt.EI, lt.EI_2], "N m^2", 'two principal '
                       'stiffnesses are read by model = "rod" only: give one number')
        if lt.GJ != 0.0:
            raise _err(f"line_types.{name}.GJ", lt.GJ, "N m^2", 'torsion is read by model = '
                       '"rod" only: remove it, or 0')
        if lt.tension_twist != 0.0:
            raise _err(f"line_types.{name}.tension_twist", lt.tension_twist, "N m", 'read by '
                       'model = "rod" only: remove it, or 0')


def scene_to_toml(scene: Scene) -> str:
    """The scene as TOML text (the layout of :func:`scene_to_dict`), ready to write to a file."""
    return tomli_w.dumps(scene_to_dict(scene))
