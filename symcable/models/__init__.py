"""The formulations and their registry.

Each formulation lives in its own package (``planar``, ``cable3d``, ``rod`` with the hybrid,
``body``, ``toys``) and imports only :mod:`symcable.scene`, :mod:`symcable.mechanism`,
:mod:`.common` (the shared physics) and :mod:`symcable.analytic`, never another formulation.
:data:`FORMULATIONS` maps a scene's kind to its :class:`Formulation` (how it builds its
Mechanism, which path its analyses take); :func:`build_mechanism` is the one entry, and
:func:`formulation_of` what the layers above ask instead of naming the kind. A scene of several lines, points and bodies is
assembled from its parts by :mod:`.system`.

The planar formulation also keeps its own records (:class:`~.planar.base.Model`, the
linearised :class:`~.planar.dynamic.DynamicModel`), built by :func:`build_model` and
:func:`linearised_model`.
"""
from __future__ import annotations

import dataclasses
from collections import OrderedDict
from typing import Callable

from ..errors import SymcableError
from ..scene import Model as ModelKind, Scene, load_scene
from .planar.base import Guess, Model
from .planar.dynamic import DynamicModel
from .cable3d.line import build_cable3d
from .planar.model import build_planar
from .planar.dynamics import build_planar_dynamics
from .planar.static import static_mechanism
from .planar.in_plane import nonlinear_stand_in
from .rod.hybrid import build_hybrid, is_cable
from .structure import shared_build
from .system import build_system

__all__ = ["FORMULATIONS", "DynamicModel", "Formulation", "formulation_of", "Guess", "Model", "build_mechanism", "build_model",
           "cache_dynamic_model", "cached_dynamic_model", "linearised_model"]

_BUILDERS = {ModelKind.PLANAR: build_planar}
_DYNAMIC_BUILDERS = {ModelKind.PLANAR: build_planar_dynamics}
_CACHE: "OrderedDict[str, Model]" = OrderedDict()
_CACHE_SIZE = 16


def _builder(builders: dict, scene: Scene, what: str):
    """The builder of ``scene.model`` in ``builders``, or a SymcableError saying there is
    none yet (cable3d is a Mechanism, not built here)."""
    builder = builders.get(scene.model)
    if builder is None and scene.model is ModelKind.CABLE3D:
        raise SymcableError(f"model = 'cable3d': no {what} Model record for it; cable3d is a "
                            "Mechanism (symcable.api.cable3d_static.cable3d_mechanism(scene); "
                            "solve_static solves it)")
    if builder is None:
        raise SymcableError(f"model = {scene.model.value!r}: no {what} model for "
                            f"{scene.model.value} yet (allowed: "
                            f"{', '.join(repr(m.value) for m in builders)})")
    return builder


def build_model(scene) -> Model:
    """The scene's planar formulation, discretised, as CasADi expressions.

    Models are cached by the scene's content (the 16 most recent), so solving the same
    scene twice builds its symbolic graph and functions once.

    Parameters
    ----------
    scene : Scene, dict or path
        A Scene, or anything :func:`symcable.load_scene` takes (a dict, a path to TOML or a
        MoorDyn deck); ``model = "planar"``.

    Returns
    -------
    Model
        The planar line's static model (:class:`~symcable.models.planar.base.Model`), as
        :func:`symcable.solve_static` takes it.

    Raises
    ------
    SymcableError
        A scene of another formulation (``cable3d``, ``rod``, ``hybrid``): it has no Model
        record (:func:`symcable.build_mechanism` builds its Mechanism).
    SceneError
        ``scene`` is not a valid scene (from :func:`symcable.load_scene`).
    """
    if not isinstance(scene, Scene):
        scene = load_scene(scene)
    key = repr(scene.to_dict())
    model = _CACHE.get(key)
    if model is None:
        model = _builder(_BUILDERS, scene, "static")(scene)
        _CACHE[key] = model
        if len(_CACHE) > _CACHE_SIZE:
            _CACHE.popitem(last=False)
    else:
        _CACHE.move_to_end(key)
    return model


def linearised_model(scene: Scene, static) -> DynamicModel:
    """The scene's dynamics linearised about ``static`` (its
    :class:`~symcable.results.static.StaticSolution`), as CasADi expressions; not cached.
    :func:`symcable.api.analyses.build_dynamic_model` solves the static state and caches."""
    return _builder(_DYNAMIC_BUILDERS, scene, "dynamic")(scene, static)


def cached_dynamic_model(scene: Scene) -> DynamicModel | None:
    """The dynamic model cached for this scene's content by :func:`cache_dynamic_model`,
    or None."""
    return _CACHE.get("dyn:" + repr(scene.to_dict()))


def cache_dynamic_model(scene: Scene, model: DynamicModel) -> DynamicModel:
    """Cache ``model`` as the scene's dynamic model (in the cache of :func:`build_model`,
    the 16 most recent models); returns it."""
    _CACHE["dyn:" + repr(scene.to_dict())] = model
    if len(_CACHE) > _CACHE_SIZE:
        _CACHE.popitem(last=False)
    return model


def _planar(scene: Scene):
    """The planar line's statics as a Mechanism."""
    return static_mechanism(build_model(scene))


def _cable3d(scene: Scene):
    """One cable3d line, or a scene of several lines, points and bodies assembled; a scene
    whose structure was built before takes that Mechanism's expressions with its own
    numbers (:mod:`symcable.models.structure`)."""
    return shared_build(scene, build_system if scene.version == 2 else build_cable3d)


def _rod(scene: Scene):
    """A rod or hybrid line (zones given): cable3d's line where it has no rod section and
    no guided end, else the generalised rod."""
    return build_cable3d(scene) if is_cable(scene) else build_hybrid(scene)


@dataclasses.dataclass(frozen=True)
class Formulation:
    """What the analyses read of a formulation: how it builds its Mechanism and which
    path its analyses take. Everything above :mod:`symcable.models` asks these questions
    instead of naming the formulation.

    Attributes
    ----------
    build : callable
        ``build(scene) -> Mechanism``: the scene's statics as a Mechanism.
    linearised : bool
        True: its dynamics are a model linearised about the static state (a
        :class:`DynamicModel`, :func:`linearised_model`) and its static solve keeps a
        :class:`Model` record; False: every analysis runs on the Mechanism itself
        (nonlinear dynamics, several lines, points and bodies).
    twists : bool
        Its Mechanism carries twist coordinates and material frames (a rod): the dynamics
        add the frames' reference spin and the results the twists.
    stand_in : callable or None
        ``stand_in(scene, static) -> Scene | None``: the scene whose dynamics the analyses
        run when this formulation cannot represent them about ``static`` (the same line
        in another formulation, said in a note), or None when it can.
    """

    build: Callable
    linearised: bool = False
    twists: bool = False
    stand_in: Callable | None = None


#: scene kind -> its Formulation
FORMULATIONS = {
    ModelKind.PLANAR: Formulation(_planar, linearised=True, stand_in=nonlinear_stand_in),
    ModelKind.CABLE3D: Formulation(_cable3d),
    ModelKind.ROD: Formulation(_rod, twists=True),
    ModelKind.HYBRID: Formulation(_rod, twists=True),
}


def formulation_of(scene: Scene) -> Formulation:
    """The :class:`Formulation` of ``scene`` (its ``model`` key)."""
    return FORMULATIONS[scene.model]


def build_mechanism(scene: Scene):
    """The scene's Mechanism, by its formulation (:data:`FORMULATIONS`; not cached).

    Raises
    ------
    SymcableError
        A hybrid scene whose rod zones are to be chosen from a static solve
        (``zones = "auto"``): :func:`symcable.api.rod_static.hybrid_zones` resolves them.
    """
    return formulation_of(scene).build(scene)
