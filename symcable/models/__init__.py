"""Formulations: each turns a Scene into a :class:`~symcable.models.base.Model`."""
from __future__ import annotations

from collections import OrderedDict

from ..scene import Model as ModelKind, Scene
from .base import Guess, Model
from .dynamic import DynamicModel
from .planar import build_planar
from .planar_dynamics import build_planar_dynamics

__all__ = ["DynamicModel", "Guess", "Model", "build_dynamic_model", "build_model"]

_BUILDERS = {ModelKind.PLANAR: build_planar}
_DYNAMIC_BUILDERS = {ModelKind.PLANAR: build_planar_dynamics}
_CACHE: "OrderedDict[str, Model]" = OrderedDict()
_CACHE_SIZE = 16


def build_model(scene: Scene) -> Model:
    """The scene's formulation, discretised, as CasADi expressions.

    Models are cached by the scene's content (the 16 most recent), so solving the same
    scene twice builds its symbolic graph and functions once.
    """
    key = repr(scene.to_dict())
    model = _CACHE.get(key)
    if model is None:
        model = _BUILDERS[scene.model](scene)
        _CACHE[key] = model
        if len(_CACHE) > _CACHE_SIZE:
            _CACHE.popitem(last=False)
    else:
        _CACHE.move_to_end(key)
    return model


def build_dynamic_model(scene: Scene, static=None) -> DynamicModel:
    """The scene's dynamics linearised about its static solution (solved here when not
    given), as CasADi expressions. Cached like :func:`build_model` when ``static`` is not
    given."""
    if static is not None:
        return _DYNAMIC_BUILDERS[scene.model](scene, static)
    key = "dyn:" + repr(scene.to_dict())
    model = _CACHE.get(key)
    if model is None:
        from ..solvers.static import solve_static
        model = _DYNAMIC_BUILDERS[scene.model](scene, solve_static(scene))
        _CACHE[key] = model
        if len(_CACHE) > _CACHE_SIZE:
            _CACHE.popitem(last=False)
    return model
