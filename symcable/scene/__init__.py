"""Scenes: what is modelled (the README's "A scene file").

:mod:`.model` holds the frozen, validated dataclasses (and :func:`scene_to_dict`, their
plain-dict form); :mod:`.load` reads TOML files and dicts into them, checking every key, and
writes scenes back as TOML; :mod:`.moordyn` reads MoorDyn v2 decks into the same layout.
"""
from __future__ import annotations

from .load import load_scene, moordyn_deck, scene_to_toml
from .model import (End, EndCondition, Environment, LineType, Model, Motion, Scene, Seabed, Section,
                    scene_to_dict)
from .bodies import Body, BodyEnd, BodyKind
from .points import Line, Point, PointKind

__all__ = [
    "EndCondition", "Model", "LineType", "Section", "Motion", "End", "Environment", "Seabed",
    "Scene", "Point", "PointKind", "Line", "Body", "BodyEnd", "BodyKind", "load_scene",
    "moordyn_deck", "scene_to_dict", "scene_to_toml",
]
