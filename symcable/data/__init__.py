"""The built-in scenes: every ``NAME.toml`` in this folder, found by name.

``symcable simulate sphere`` (any command taking a scene) reads ``sphere.toml`` from here when
no file of that name exists where it is run (:func:`resolve`).
"""
from __future__ import annotations

import os
from importlib.resources import files

__all__ = ["names", "scene_path", "resolve"]


def names() -> list[str]:
    """The names of the built-in scenes (the stems of this folder's TOML files), sorted."""
    return sorted(p.name[:-5] for p in files(__name__).iterdir() if p.name.endswith(".toml"))


def scene_path(name: str):
    """Path of the built-in scene ``name`` (a Traversable), or None if there is none."""
    path = files(__name__) / f"{name}.toml"
    return path if path.is_file() else None


def resolve(arg):
    """A command line's scene argument: the argument itself when it names an existing file
    (or is not a string), else the built-in scene of that name (``sphere``, ``sphere.toml``),
    else the argument unchanged (the loader then reports the missing file)."""
    if not isinstance(arg, str) or os.path.exists(arg):
        return arg
    stem = arg[:-5] if arg.endswith(".toml") else arg
    path = scene_path(stem) if stem and os.sep not in stem and "/" not in stem else None
    return str(path) if path is not None else arg
