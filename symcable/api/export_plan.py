"""What ``symcable codegen`` writes out for a scene: the static problem the library solves
and the time step its ``simulate`` runs, each as a Mechanism with the numbers that go with
it (start, parameters, tolerance, step), found through the functions the analyses
themselves use, for every formulation alike:

* statics: the scene's Mechanism and its equilibrium (:func:`~symcable.api.scene3d.
  scene_equilibrium`: the planar line's static Mechanism, the cable's, the rod's), the start
  the library's successful attempt began from, its parameters and tolerance;
* dynamics: :func:`~symcable.api.analyses.dynamics_scene` (the scene, or the stand-in its
  dynamics run as) and :func:`~symcable.api.analyses.runs_on_mechanism` say which path
  ``simulate`` takes. On the Mechanism path (:func:`~symcable.api.cable3d.simulate_3d`) the
  step is the Mechanism's own (:func:`~symcable.api.scene3d.start_state`: the static state
  at rest, or the steady tow), at that path's rho_inf, Newton tolerance and default step;
  on the linearised path (:func:`~symcable.api.planar_time.simulate`) it is the linearised
  model's Mechanism (:func:`~symcable.models.planar.mechanism.mechanism_of`) from its rest
  state, at its own defaults.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import SymcableError
from ..mechanism.mechanism import Mechanism
from ..models.planar.mechanism import mechanism_of, state_permutation
from ..models.rod.reanchor import reanchor_hook
from ..scene import Scene
from ..solvers.integrate import start_rates
from ..solvers.options import GeneralizedAlphaFirstOrder
from ..solvers.reanchor import Reanchoring
from . import cable3d as _c3
from . import planar_time as _linear
from .analyses import build_dynamic_model, dynamics_scene, runs_on_mechanism
from .scene3d import scene_equilibrium, start_state

__all__ = ["LINEARISED_RHO_INF", "DynamicPlan", "StaticPlan", "default_duration",
           "dynamic_plan", "static_plan"]

#: rho_inf of ``simulate`` on the linearised path (:func:`symcable.simulate`'s default there)
LINEARISED_RHO_INF = 0.5


@dataclass(frozen=True)
class StaticPlan:
    """The scene's static problem as the library solves it.

    ``mech`` the static Mechanism; ``start`` x0 = (q, z) of the start the library's
    successful attempt began from (``start_source`` names it; the first start when none
    matches); ``solution`` x of the library's equilibrium; ``p`` its parameters; ``tol`` its
    residual tolerance (N, max-norm); ``path`` how it was found (``"newton"``: plain Newton
    from ``start``, the fused solve that is exported); ``outputs`` its named outputs."""

    mech: Mechanism
    start: np.ndarray
    start_source: str
    solution: np.ndarray
    p: np.ndarray
    tol: float
    path: str
    outputs: dict


@dataclass(frozen=True)
class DynamicPlan:
    """The time step ``simulate`` runs for the scene.

    ``mech`` the Mechanism stepped; ``opts`` the generalized-alpha options (rho_inf, Newton
    tolerance and iterations); ``t0`` (s) where a run starts; ``dt`` (s) the default step;
    ``y0`` = (q0, v0) the start and ``x0`` = (y0, y0') with its rates (the step's carried
    state); ``p`` the parameters; ``reanchor`` the Mechanism's re-anchoring hook (a rod's
    anchored frames, :func:`~symcable.models.rod.reanchor.reanchor_hook`) or None; ``path``
    ``"mechanism"`` or ``"linearised"``; ``stand_in`` True when the dynamics run as a
    stand-in scene (another formulation's, :func:`~symcable.api.analyses.dynamics_scene`),
    ``model`` the ``model`` of the scene they run; ``start`` how a run starts (``"rest"``,
    ``"steady tow"``); ``reanchored`` True when the march re-anchors the frames at the start
    (``y0``, ``x0`` and ``p`` are then the new chart's)."""

    mech: Mechanism
    opts: GeneralizedAlphaFirstOrder
    t0: float
    dt: float
    y0: np.ndarray
    x0: np.ndarray
    p: np.ndarray
    reanchor: object
    path: str
    stand_in: bool
    model: str
    start: str
    reanchored: bool = False


def _x(mech: Mechanism, q, z) -> np.ndarray:
    """The static unknowns x = (q, z)."""
    return np.concatenate([np.asarray(q, float).ravel(), np.asarray(z, float).ravel()[:mech.n_z]])


def static_plan(scene: Scene) -> StaticPlan:
    """The scene's static problem and the library's solution of it (see the module)."""
    mech, eq = scene_equilibrium(scene, codegen=False)
    source = eq.stats.get("start")
    first = None
    for st in mech.starts():  # built lazily: up to the one the library's solve began from
        first = st if first is None else first
        if st.source == source:
            break
    else:
        st = first
    if st is None:
        raise SymcableError(f"scene {scene.name!r}: its Mechanism has no static start")
    return StaticPlan(mech, _x(mech, st.q, st.z), str(st.source), _x(mech, eq.q, eq.z),
                      np.asarray(eq.p, float), float(eq.stats["tolerance"]),
                      str(eq.stats.get("path", "")), dict(eq.outputs))


def default_duration(scene: Scene) -> float:
    """The run ``symcable simulate`` makes by default, s: a table's span, a tow's turns and
    a minute more, ten periods of a harmonic motion, else a minute."""
    motions = _c3._motions(scene)
    table = next((m for m in motions if m.kind == "table"), None)
    tow = next((m for m in motions if m.kind == "tow"), None)
    period = _c3._period(scene)
    return (table.period if table else tow.period + 60.0 if tow
            else 10.0 * period if period else 60.0)


def dynamic_plan(scene: Scene) -> tuple[DynamicPlan | None, str]:
    """``(plan, "")`` for a scene with a prescribed motion (an end, point or towpoint), else
    ``(None, why not)``; raises SymcableError (or ConvergenceError) when the library cannot
    build or start the scene's dynamics."""
    if not _c3._motions(scene):
        return None, "the scene prescribes no motion (no moving end, point or towpoint)"
    run = dynamics_scene(scene)
    if runs_on_mechanism(scene):
        return _mechanism_plan(run, run is not scene), ""
    return _linearised_plan(run), ""


def _mechanism_plan(scene: Scene, stand_in: bool) -> DynamicPlan:
    """The Mechanism path (:func:`~symcable.api.cable3d.simulate_3d` at its defaults)."""
    t0 = _c3.run_start(scene)
    mech, eq, v0, info, _ = start_state(scene, t0, None, False)
    p = np.asarray(mech.params.values, float)
    dt = _c3.default_dt(scene, default_duration(scene), _c3._start_tensions(scene, eq))
    opts = GeneralizedAlphaFirstOrder(rho_inf=_c3.RHO_INF, tol=_c3.newton_tolerance(scene, mech))
    q0 = np.asarray(eq.q, float)
    return _plan(scene, mech, opts, t0, dt, q0, np.asarray(v0, float), p,
                 reanchor_hook(mech), "mechanism", stand_in, str(info.get("start", "rest")))


def _linearised_plan(scene: Scene) -> DynamicPlan:
    """The linearised path (:func:`~symcable.api.planar_time.simulate` at its defaults)."""
    dyn = build_dynamic_model(scene)
    mech = mechanism_of(dyn)
    iq, iv = state_permutation(dyn)
    y0 = np.asarray(dyn.y0, float)
    opts = GeneralizedAlphaFirstOrder(rho_inf=LINEARISED_RHO_INF, tol=_linear.NEWTON_TOL,
                                      max_iter=_linear.NEWTON_MAX_ITER)
    dt = (dyn.period or default_duration(scene)) / 100.0
    return _plan(scene, mech, opts, 0.0, dt, y0[iq], y0[iv], np.asarray(dyn.p_value, float),
                 None, "linearised", False, "rest")


def _plan(scene, mech, opts, t0, dt, q0, v0, p, hook, path, stand_in, start) -> DynamicPlan:
    """The plan of a run from (q0, v0) at t0 with its rates, as the march carries it: where
    the Mechanism re-anchors, its start already in the chart the march's first step takes
    (:meth:`~symcable.solvers.reanchor.Reanchoring.after` at step 0: a rod whose static
    state is turned far from its anchors, as the built-in seed000_rod's, is re-anchored there)."""
    qd, vd = start_rates(mech, q0, v0, t0, p)
    x0 = np.concatenate([q0, v0, qd, vd])
    renewed = False
    if hook is not None:
        ra = Reanchoring(mech, hook, p, isinstance(opts, GeneralizedAlphaFirstOrder))
        p = np.asarray(ra.after(x0, 0, t0), float)  # x0 in place: the new chart's q, v
        renewed = bool(ra.changes)
    ny = mech.n_q + mech.n_v
    return DynamicPlan(mech, opts, float(t0), float(dt), x0[:ny].copy(), x0, p, hook, path,
                       stand_in, str(getattr(scene.model, "value", scene.model)), start,
                       renewed)
