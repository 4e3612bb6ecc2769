"""The planar line's time response: its DynamicModel re-expressed as a Mechanism
(:func:`~symcable.models.planar.mechanism.mechanism_of`), marched by the generic integrator
(:func:`~symcable.solvers.integrate.integrate`), and returned as a
:class:`~symcable.results.trajectory.Trajectory` with the states in the DynamicModel's order
(:func:`~symcable.models.planar.mechanism.state_permutation`).

``method="generalized-alpha"`` is the first-order generalized-alpha of Jansen, Whiting &
Hulbert (2000) on the DAE residual (:mod:`symcable.solvers.galpha1`), ``"rk4"`` classical
RK4; what each does, and the run's options, are the generic integrator's. This module only
translates: the planar method names and defaults (dt = period / 100), the parameter vector
and rest state of the DynamicModel, and the result.
"""
from __future__ import annotations

import enum
import time as _time

import casadi as ca
import numpy as np

from ..errors import ConvergenceError, SymcableError
from ..linalg.sparse import jacobian
from ..models.planar.dynamic import DynamicModel
from ..models.planar.mechanism import mechanism_of, state_permutation
from ..results.trajectory import Trajectory
from ..scene import load_scene
from ..solvers import steps as _steps
from ..solvers.galpha1 import coefficients, galpha1_residual
from ..solvers.integrate import (ERROR_TARGET, check_positive, check_steps, error_warning,
                                integrate)
from ..solvers.options import RK4, GeneralizedAlphaFirstOrder
from ..solvers.stepcache import STEP_CACHE

__all__ = ["Method", "NEWTON_MAX_ITER", "NEWTON_TOL", "ga_coefficients", "ga_residual_function",
           "rk4_stability_limit", "simulate"]

#: Newton iterations per generalized-α step before the step counts as failed
NEWTON_MAX_ITER = 10
#: default Newton tolerance on the scaled residual and step (see ``simulate``)
NEWTON_TOL = 1e-10
#: default largest number of saved samples (``save_every=None``)
MAX_SAMPLES = 2000


class Method(str, enum.Enum):
    """Time integration methods of :func:`simulate`."""

    RK4 = "rk4"
    GENERALIZED_ALPHA = "generalized-alpha"

    @classmethod
    def parse(cls, value) -> "Method":
        try:
            return cls(value)
        except ValueError:
            allowed = ", ".join(repr(m.value) for m in cls)
            raise SymcableError(f"method = {value!r}: must be one of {allowed}") from None


def ga_coefficients(rho_inf: float) -> tuple[float, float, float]:
    """``(alpha_m, alpha_f, gamma)`` of first-order generalized-α for a spectral radius at
    infinity ``rho_inf`` in [0, 1] (Jansen, Whiting & Hulbert 2000, eqs. 20 and 17)."""
    return tuple(float(c) for c in coefficients(float(rho_inf)))


def _rest(model: DynamicModel):
    iq, iv = state_permutation(model)
    y0 = np.asarray(model.y0, dtype=float)
    return iq, iv, y0[iq], y0[iv]


def rk4_stability_limit(model: DynamicModel, p=None, t: float = 0.0) -> float:
    """Largest stable RK4 step of the model linearised at rest, s
    (:func:`symcable.solvers.steps.rk4_stability_limit` on its dynamics Mechanism)."""
    _, _, q0, v0 = _rest(model)
    p = np.asarray(model.p_value if p is None else p, dtype=float)
    return _steps.rk4_stability_limit(mechanism_of(model), p, t, q0, v0)


def ga_residual_function(model: DynamicModel, rho_inf: float) -> ca.Function:
    """The generalized-α step residual and its exact Jacobian in the DynamicModel's state
    order and units: ``ga_residual(ydot_next, y, ydot, t, dt, p) -> (r, dr_dydot_next)``,
    ``y, ydot`` at t_n = ``t`` (s), the unknown rate ``ydot_next`` at t_n + dt; ``r`` (n_y,)
    in units of y per second (the Mechanism's momentum rows over their masses),
    ``dr_dydot_next`` (n_y, n_y) sparse, alpha_m I - alpha_f gamma dt df/dy. Built once per
    model and ``rho_inf``, kept with the model's Mechanism in
    :data:`~symcable.solvers.stepcache.STEP_CACHE`."""
    mech = mechanism_of(model)
    return STEP_CACHE.get(mech, ("planar_ga_residual", float(rho_inf)),
                          lambda: _ga_residual(model, mech, float(rho_inf)))


def _ga_residual(model: DynamicModel, mech, rho_inf: float) -> ca.Function:
    iq, iv = state_permutation(model)
    order = np.concatenate([iq, iv]).tolist()
    back = np.argsort(order).tolist()
    mass = np.diag(np.atleast_2d(np.asarray(ca.evalf(mech.mass), dtype=float)))
    n = model.n_y
    z, y, yd = (ca.SX.sym(k, n) for k in ("ydot_next", "y", "ydot"))
    t, dt, p = ca.SX.sym("t"), ca.SX.sym("dt"), ca.SX.sym("p", model.p.numel())
    F = galpha1_residual(mech)(z[order], ca.vertcat(y[order], yd[order]), t, dt, p,
                               ca.DM([rho_inf, 0.0]))[0]
    r = (F / ca.DM(np.concatenate([np.ones(mech.n_q), mass])))[back]
    return ca.Function("ga_residual", [z, y, yd, t, dt, p], [r, jacobian(r, z)],
                       ["ydot_next", "y", "ydot", "t", "dt", "p"], ["r", "dr_dydot_next"])


def simulate(scene, duration: float, dt: float | None = None, method: str = "generalized-alpha", *,
             rho_inf: float = 0.5, save_every: int | None = None, save_times=None,
             progress: bool | None = None, model: DynamicModel | None = None, params=None,
             newton_tol: float | None = None, codegen: bool | None = None,
             started: float | None = None) -> Trajectory:
    """Time response of a line from rest at t = 0 (where its excitation starts), for a
    dynamic model already built; :func:`symcable.simulate` builds it from a scene and
    documents the parameters, the result and the errors. ``started`` is
    ``time.perf_counter()`` when the caller began (``stats["wall_time"]`` counts from it)."""
    wall0 = _time.perf_counter() if started is None else started
    meth = Method.parse(method)
    duration, dt = check_steps(duration, dt)
    if scene is None and model is None:
        raise SymcableError("scene = None: give a scene, or a model to integrate")
    if model is None:
        raise SymcableError("model = None: give the dynamic model to integrate "
                            "(symcable.simulate builds it from a scene)")
    sc = load_scene(scene) if scene is not None else None
    scene_name = sc.name if sc is not None else getattr(model.info.get("scene"), "name", model.name)
    p = np.array(model.p_value if params is None else params, dtype=float).ravel()
    if p.shape != np.shape(model.p_value):
        raise SymcableError(f"params: length {p.size}: must have the model's {np.size(model.p_value)} "
                            "parameters (use model.with_params(...))")
    tol = NEWTON_TOL if newton_tol is None else check_positive("newton_tol", newton_tol)
    ga = meth is Method.GENERALIZED_ALPHA
    opts = GeneralizedAlphaFirstOrder(rho_inf=rho_inf, tol=tol, max_iter=NEWTON_MAX_ITER) if ga else RK4()
    mech = mechanism_of(model)
    iq, iv, q0, v0 = _rest(model)
    check_steps(duration, dt, model.period or None)  # dt against the motion's period
    default_dt = (model.period / 100.0) if model.period else duration / 100.0
    if dt is None:
        dt = default_dt if ga else min(0.8 * rk4_stability_limit(model, p), default_dt)
        dt = min(dt, duration)  # a run shorter than the default step is one step
    failure = None
    try:
        run = integrate(mech, duration, check_positive("dt", dt, "s"), method=opts, p=p, q0=q0, v0=v0,
                        save_every=save_every, save_times=save_times, max_samples=MAX_SAMPLES,
                        progress=progress, codegen=codegen, label=meth.value,
                        period=model.period or None)
    except ConvergenceError as exc:
        failure, run = exc, exc.partial
    st = run.stats
    stats = {"method": meth.value}
    if not ga:
        stats["dt_stable"] = st["dt_stable"]
    stats.update(dt=st["dt"], dt_requested=st["dt_requested"], newton_tol=tol if ga else None)
    if ga:
        am, af, gamma = ga_coefficients(opts.rho_inf)
        stats.update(rho_inf=opts.rho_inf, alpha_m=am, alpha_f=af, gamma=gamma)
    stats.update({k: st[k] for k in ("compiled", "steps", "newton_iterations",
                                      "newton_iterations_max", "step_time", "us_per_step",
                                      "samples")})
    if ga:
        stats.update({k: st.get(k) for k in ("error_estimate", "error_estimate_scaled",
                                              "motion_range", "error_memory", "dt_accurate")})
    warns = ()
    if failure is None and ga and (stats["error_estimate"] or 0.0) > ERROR_TARGET:
        warns = (error_warning(meth.value, stats, "the response (states and tensions alike)",
                               model.period or None),)
    states = np.hstack([run.q, run.v])[:, np.argsort(np.concatenate([iq, iv]))]
    stats["wall_time"] = _time.perf_counter() - wall0
    traj = Trajectory.from_outputs(model, scene_name=scene_name, time=run.time, states=states,
                                   outputs=run.outputs, method=meth.value, dt=st["dt"],
                                   status="failed" if failure is not None else "converged",
                                   stats=stats, warnings=warns)
    if failure is not None:
        diag = dict(failure.diagnostics, method=meth.value)
        raise ConvergenceError(str(failure), partial=traj, diagnostics=diag)
    return traj
