"""The Mechanism and the linearised dynamic model of a scene, for the generic solvers and
for repeated analyses of one scene."""
from __future__ import annotations

from ..mechanism.mechanism import Mechanism
from ..models import DynamicModel, cache_dynamic_model, cached_dynamic_model, formulation_of, \
    linearised_model
from ..scene import Scene, load_scene
from .planar_static import solve_static
from .scene3d import scene_mechanism

__all__ = ["build_dynamic_model", "build_mechanism"]


def build_mechanism(scene) -> Mechanism:
    """The scene's statics as a Mechanism, for any formulation, built once per scene content.

    Planar, cable3d, rod, hybrid, or a scene of several lines, points and bodies: the
    object the generic solvers take (:func:`symcable.solve_equilibrium`,
    :func:`symcable.linearize_mechanism`, :func:`symcable.mechanism_modes`, ...). A hybrid
    with ``zones = "auto"`` has its zones chosen first (a static solve).

    Parameters
    ----------
    scene : Scene, dict or path
        Anything :func:`symcable.load_scene` takes.

    Returns
    -------
    Mechanism
        Its statics: coordinates q (m, rad), parameter blocks p, outputs.

    Raises
    ------
    SceneError
        ``scene`` is not a valid scene.
    """
    scene = load_scene(scene)
    form = formulation_of(scene)
    return form.build(scene) if form.linearised else scene_mechanism(scene)


def build_dynamic_model(scene, static=None) -> DynamicModel:
    """The scene's dynamics linearised about its static solution, as CasADi expressions.

    Planar scenes only. Cached like :func:`symcable.build_model` when ``static`` is not
    given.

    Parameters
    ----------
    scene : Scene, dict or path
        Anything :func:`symcable.load_scene` takes (``model = "planar"``).
    static : StaticSolution, optional
        The static state to linearise about. Default None: solved here
        (:func:`symcable.solve_static`, no error estimate) and the model cached.

    Returns
    -------
    DynamicModel
        The linearised model, for ``simulate``, ``solve_periodic`` and ``modal_analysis``
        (their ``model`` argument).

    Raises
    ------
    SymcableError
        A scene of another formulation (it has no linearised model).
    ConvergenceError
        The static solve failed.
    """
    if not isinstance(scene, Scene):
        scene = load_scene(scene)
    if static is not None:
        return linearised_model(scene, static)
    model = cached_dynamic_model(scene)
    if model is None:
        static = solve_static(scene, estimate=False)
        model = cache_dynamic_model(scene, linearised_model(scene, static))
    return model
