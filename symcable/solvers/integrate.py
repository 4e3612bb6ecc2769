"""Time integration of any Mechanism: generalized-alpha (implicit; second order in time with
constraints, :func:`galpha_step`, or first order on the DAE residual with any kinematics,
:func:`galpha1_step`) and RK4 (explicit, no constraints), with fixed steps (saved samples,
a progress bar, blow-up and Newton-failure reports) or steps adapted to a local error
tolerance.

Every step is one CasADi Function ``step(x, t, h, p) -> (x1, err, lte)`` (first-order
generalized-alpha adds the Newton iterations and a failure flag); ``mapaccum`` chains many
steps into one call, so a long run pays the Python interpreter once per batch of saved
samples, never once per step. The first-order generalized-alpha step and RK4 run in
generated C when ``codegen`` resolves to True (:func:`symcable.mechanism.codegen.use_codegen`).
Generalized-alpha runs estimate their own time-stepping error and warn when it exceeds 1 %
(``stats["error_estimate"]``, see :func:`integrate`).
"""
from __future__ import annotations

import math
import time

import casadi as ca
import numpy as np

from ..mechanism.functions import functions
from ..errors import ConvergenceError, SymcableError
from ..mechanism.codegen import FastCall
from ..limits import check as check_limit
from ..linalg.sparse import qr_solve
from ..mechanism.mechanism import Mechanism
from ..results.generic import Equilibrium, MechanismTrajectory
from .galpha1 import galpha1_kernel, galpha1_step
from .march import BLOWUP, IMPLICIT as _IMPLICIT, get_stepper, method_name, run_adaptive, run_fixed
from .options import RK4, GeneralizedAlpha, GeneralizedAlphaFirstOrder
from .reanchor import Reanchoring
from .schedule import save_indices
from .stepcache import STEP_CACHE, maybe_compiled
from .steps import check_second_order, galpha_step, rk4_stability_limit, rk4_step

__all__ = ["BLOWUP", "ERROR_TARGET", "accurate_dt", "check_positive", "check_steps", "error_warning",
           "integrate", "substep_warning",
           "galpha_step", "galpha1_step", "method_name", "rk4_stability_limit", "rk4_step",
           "start_rates"]

#: steps per mapaccum call of the adaptive run (bounds the compiled/generated graph)
BATCH = 256
#: samples per call of the mapped outputs: building CasADi's map of a long line's outputs
#: grows with its instances (601 samples of a 2000-segment line: 1.8 s and 0.7 GB), while a
#: chunk of them costs as much per sample to evaluate
OUTPUT_CHUNK = 32
#: a run whose error estimate (relative to the range of its motion) exceeds this warns
ERROR_TARGET = 0.01
#: safety factor on the step order 2 suggests for ERROR_TARGET (see :func:`accurate_dt`)
DT_SAFETY = 0.7


def check_positive(name: str, value, unit: str = "") -> float:
    """``value`` as a finite float > 0, or a SymcableError naming ``name``, the value and its
    unit."""
    try:
        v = float("nan") if isinstance(value, (str, bytes, bool)) else float(value)
    except (TypeError, ValueError):
        v = float("nan")
    if not (math.isfinite(v) and v > 0.0):
        raise SymcableError(f"{name} = {value!r}{' ' + unit if unit else ''}: must be > 0 "
                            "(a finite number)")
    return v


def check_steps(duration, dt=None, period=None, *, names=("duration", "dt"),
                fixed: bool = True) -> tuple[float, float | None]:
    """``(duration, dt)`` (s) as floats, or a one-line SymcableError naming the option
    (``names``: the parameters', or a command's ``--duration``/``--dt``), its value and what
    is allowed: each a finite number > 0 (``dt`` None keeps the default), dt at most the
    duration (one step fills the run), and for fixed steps (``fixed``) with a motion of
    ``period`` s at most half the period: fewer than two steps per period cannot follow the
    motion (at dt = T every step sees the motion at one phase, as if it stood still, and
    the run "converges" to a line at rest)."""
    d = check_positive(names[0], duration, "s")
    if dt is None:
        return d, None
    h = check_positive(names[1], dt, "s")
    if h > d * (1.0 + 1e-9):
        raise SymcableError(f"{names[1]} = {dt!r} s: larger than the {names[0].lstrip('-')} "
                            f"({d:.6g} s): must be > 0 and at most the {names[0].lstrip('-')}")
    if fixed and period is not None and h > 0.5 * float(period) * (1.0 + 1e-9):
        raise SymcableError(f"{names[1]} = {dt!r} s: more than half the motion's period "
                            f"({float(period):.6g} s), which the steps cannot follow: must be > 0 "
                            f"and at most {0.5 * float(period):.6g} s (about period / 100 = "
                            f"{float(period) / 100:.3g} s for 1 % accuracy)")
    return d, h


def start_rates(mech: Mechanism, q0, v0, t0: float, p) -> tuple[np.ndarray, np.ndarray]:
    """(q', v') at the state (q0, v0) at t0 (n_z = 0): the kinematics and v' = M^-1 f."""
    F = functions(mech)
    z = np.zeros(0)
    qd = np.asarray(F.qdot(q0, v0, z, t0, p), dtype=float).ravel()
    if not mech.n_v:
        return qd, np.zeros(0)
    f = -np.asarray(F.acc_residual(q0, v0, np.zeros(mech.n_v), z, t0, p)[0], dtype=float).ravel()
    mass = STEP_CACHE.get(mech, ("mass",),
                          lambda: ca.Function("mass", [mech.q, mech.t, mech.p], [mech.mass]))
    M = ca.DM(mass(q0, t0, p))
    diag = np.asarray(ca.diag(M).full()).ravel()
    if M.sparsity().is_diag() and M.nnz() == mech.n_v:
        return qd, f / diag
    # scaled by its diagonal (S M S y = S f, v' = S y): a rod's rotary inertia (1e-13 kg m^2
    # and less) beside its nodes' masses is below the sparse QR's absolute pivot threshold
    scale = np.abs(diag)
    scale = 1.0 / np.sqrt(np.where(scale > 0.0, scale, 1.0))
    S = ca.DM(ca.Sparsity.diag(mech.n_v), scale)
    try:
        y = qr_solve(ca.mtimes([S, M, S]), ca.DM(scale * f))
    except RuntimeError as exc:
        raise ConvergenceError(f"the mass matrix is singular at the start (t = {t0:g} s): "
                               f"v' = M^-1 f has no solution ({exc})".replace("\n", " "),
                               diagnostics={"reason": "mass", "time": t0}) from None
    return qd, scale * np.asarray(y.full(), dtype=float).ravel()


def _initial_state(mech, F, method, q0, v0, z_guess, t0, p):
    if isinstance(method, GeneralizedAlphaFirstOrder):
        if mech.n_z:
            galpha1_kernel(mech, method)  # refuses n_z > 0
        qd0, a0 = start_rates(mech, q0, v0, t0, p)
        return np.concatenate([q0, v0, qd0, a0]), np.zeros(0)
    if isinstance(method, RK4):
        rk4_step(mech)  # refuses n_z > 0
        return np.concatenate([q0, v0]), np.zeros(mech.n_z)
    check_second_order(mech)
    a0, z0 = (np.asarray(x).ravel() for x in F.consistent_acceleration(q0, v0, z_guess, t0, p))
    if mech.n_z and method.rho_inf >= 1.0:
        # without numerical damping the multipliers of position constraints (index 3)
        # are not damped and grow without bound
        raise SymcableError(f"rho_inf = {method.rho_inf}: a mechanism with constraints "
                            "needs rho_inf < 1 (e.g. 0.9) for its constraint forces to stay "
                            "bounded")
    return np.concatenate([q0, v0, a0, a0, z0]), z0


def integrate(mech: Mechanism, duration: float, dt: float | None = None, *, method=None,
              t0: float = 0.0, p=None, save_every: int | None = None, save_times=None,
              max_samples: int | None = None,
              start: Equilibrium | None = None, q0=None, v0=None, tol: float | None = None,
              batch: int = BATCH, progress: bool | None = None, codegen: bool | None = None,
              label: str | None = None, period: float | None = None,
              reanchor=None) -> MechanismTrajectory:
    """March ``mech`` over ``duration`` s from ``t0``, with fixed steps ``dt`` s or, given
    ``tol``, steps adapted to keep the local error below ``tol`` times the scales.

    Parameters
    ----------
    mech : Mechanism
    duration : float, s
    dt : float, s, optional
        The step (fixed), shortened when needed so that a whole number of steps fills
        ``duration`` (``stats["dt_requested"]`` keeps the value asked for); the first step
        with ``tol``. At most the duration, and (fixed steps) at most half the ``period``
        (:func:`check_steps`). Default ``duration / 100`` (``period / 100`` when shorter);
        RK4: at most 0.8 times its stability limit (:func:`rk4_stability_limit`,
        ``stats["dt_stable"]``).
    method : GeneralizedAlpha | GeneralizedAlphaFirstOrder | RK4, default GeneralizedAlpha()
    q0, v0 : initial coordinates and velocities (default: ``start``'s q, or the mechanism's
        first static start, at rest)
    start : Equilibrium, optional  where to start (its q and z)
    p : parameters (default the mechanism's own, i.e. with motion)
    save_every : int, optional
        Fixed steps: keep every k-th step and the last (default every step, or about
        ``max_samples`` evenly spaced when given and there are more steps). Every accepted
        step is kept with ``tol``.
    save_times : array_like, optional
        Fixed steps: the times to keep (s from ``t0``), each rounded to the nearest step;
        the run stops at the last of them. Not with ``save_every``.
    max_samples : int, optional
        See ``save_every``.
    tol : float, optional
        Local error per step, relative to the scales (generalized-alpha only: Newmark's
        (beta - 1/6) h^2 |a1 - a0| on q for :class:`GeneralizedAlpha`, the Taylor estimate
        on q and v of :func:`galpha1_step`). Steps run in batches of ``batch`` at one size
        inside CasADi; a batch whose largest estimate exceeds ``tol`` is redone with a
        smaller step, and the next batch's step follows the estimate (order 3). ``stats``
        reports the steps taken, rejected batches and the smallest and largest step.
    progress : bool, optional
        A progress bar on stderr (fixed steps): True always, False never, None only on a
        terminal once the run has lasted a second.
    codegen : bool, optional
        Steps (first-order generalized-alpha, RK4) and outputs in generated C: None where it
        pays and a compiler exists, True, or False (the virtual machine); results agree to
        round-off.
    label : str, optional
        The method's name in messages and on the progress bar (default its own).
    period : float, optional
        The motion's characteristic period, s (a forced run: the excitation's), which sets
        the error estimate's memory, ``period / (2 pi)``. Default: ``duration``.
    reanchor : Reanchor, optional
        A re-anchoring hook (:class:`~symcable.mechanism.mechanism.Reanchor`; default the
        Mechanism's own ``reanchor``, None for most): the run re-anchors between steps
        (:mod:`symcable.solvers.reanchor`), each sample's outputs in its own chart, and
        ``stats`` adds ``reanchorings``, ``reanchor_times`` (s), ``min_frame_margin``,
        ``reanchor_retaken`` (calls of steps cut short at a step below the hook's floor),
        ``reanchor_threshold`` and ``p_final`` (the parameters at the end, a list).

    Returns
    -------
    MechanismTrajectory
        ``stats``: ``method``, ``dt``, ``dt_requested``, ``steps``, ``newton_iterations``
        (total) and ``newton_iterations_max`` (per step; first-order generalized-alpha),
        ``max_step_residual``, ``max_error_estimate`` (the largest ``tol`` estimate: adaptive
        runs), ``step_time`` (s in the step calls), ``us_per_step``, ``samples``,
        ``compiled`` (the step is generated C), ``compiled_kernels`` (it is not, but its
        loops call their kernels' generated C: a step too large to compile whole),
        ``max_constraint``, ``wall_time``; fixed steps: ``substepped_steps``
        (steps whose Newton iteration failed and that converged as 2, 4, ... up to
        MAX_SUBSTEPS = 16 equal substeps, with a warning: a snap or an impact),
        ``max_substeps`` and ``first_substep_time`` (s); and the run's error estimate
        (generalized-alpha, fixed or adapted steps; None with RK4):

        * ``error_estimate``: the estimated largest error of the state over the run from
          the time discretisation, relative to the range of the motion (the largest range
          of a state entry over its scale): about the error of an output that follows the
          state (a tension, a position) relative to its range over the run (at or somewhat
          above the true error on a damped periodic response over a wide range of steps;
          low by about the resonant gain for a lightly damped linear resonance: the
          time-error study, in the docs);
        * ``error_estimate_scaled``: the same error relative to the state's scales;
        * ``motion_range``: that largest range over its scale;
        * ``error_memory``: period / (2 pi), s;
        * ``dt_accurate`` (fixed steps): the step that should bring ``error_estimate`` to
          ERROR_TARGET (1 %) (:func:`accurate_dt`).

        How (:class:`~symcable.solvers.march.RunningEstimate`): each step's local error
        relative to the scales (first-order generalized-alpha: C h |y'_{n+1} - 2 y'_n +
        y'_{n-1}| from the carried rates, C its error constant; second order: Newmark's
        |beta - 1/6| h^2 |a_{n+1} - a_n| on q) is summed with a memory of one radian of the
        motion, E_{n+1} = exp(-h / error_memory) E_n + d_n: local error times steps per
        radian, the error of a harmonic response. Computed in NumPy on the states the
        batched steps return, nothing added to the step (a few per cent of the step time in
        generated C). A warning says how far off the run likely is and which dt would do
        when ``error_estimate`` exceeds ERROR_TARGET; the status stays "converged".

    Raises
    ------
    SymcableError
        A bad argument (named, with its value and what is allowed).
    ConvergenceError
        A step's Newton iteration did not converge (not even as 16 substeps), or the state
        blew up (not finite, or
        beyond BLOWUP times its scale: RK4 above its stability limit); ``partial`` holds the
        run up to the last good step (status "failed"); ``diagnostics`` has ``reason``
        ("newton", "blowup" or "error"), ``time`` (end of the failed step, s),
        ``time_last_good``, ``step``, ``dt``, ``method``, and ``residual`` (scaled, at the
        last Newton iterate) or ``state_norm`` (max |state| / scale) and ``worst`` (the entry
        reaching it, e.g. ``"v[12]"``).
    """
    method = GeneralizedAlpha() if method is None else method
    if not isinstance(method, (*_IMPLICIT, RK4)):
        raise SymcableError(f"method = {method!r}: must be GeneralizedAlpha(...), "
                            "GeneralizedAlphaFirstOrder(...) or RK4()")
    label = label or method_name(method)
    period = None if period is None else check_positive("period", period, "s")
    duration, dt = check_steps(duration, dt, period, fixed=tol is None)
    if tol is not None:
        if not isinstance(method, _IMPLICIT):
            raise SymcableError("tol: adaptive steps need generalized-alpha (RK4 here has no "
                                "error estimate); give dt instead")
        if not tol > 0:
            raise SymcableError(f"tol = {tol!r}: must be > 0")
    t_start = time.perf_counter()
    F = functions(mech)
    p = mech.params.values if p is None else np.asarray(p, float).ravel()
    if p.shape != (mech.params.n,):
        raise SymcableError(f"p: length {p.size}: must have the mechanism's {mech.params.n} parameters")
    if q0 is None:
        q0 = start.q if start is not None else next(iter(mech.starts())).q
    q0 = np.asarray(q0, float).ravel()
    v0 = np.zeros(mech.n_v) if v0 is None else np.asarray(v0, float).ravel()
    z_guess = start.z if start is not None else np.zeros(mech.n_z)
    x, _ = _initial_state(mech, F, method, q0, v0, z_guess, t0, p)
    stats: dict = {"method": method_name(method)}
    if isinstance(method, _IMPLICIT):
        stats["rho_inf"] = method.rho_inf
    default = min(duration, period or duration) / 100.0
    if isinstance(method, RK4):
        stats["dt_stable"] = rk4_stability_limit(mech, p, t0, q0, v0)
        default = min(default, 0.8 * stats["dt_stable"])
    dt_req = check_positive("dt", default if dt is None else dt, "s")
    if tol is None:
        check_limit("steps", duration / dt_req, f"the run's time steps (duration "
                    f"{duration:.6g} s / dt {dt_req:.6g} s)", "a guard against runs that "
                    "exhaust memory and time")
    tau = (duration if period is None else period) / (2.0 * math.pi)
    hook = reanchor if reanchor is not None else getattr(mech, "reanchor", None)
    ra = None if hook is None else Reanchoring(mech, hook, p,
                                               isinstance(method, GeneralizedAlphaFirstOrder))
    stepr = get_stepper(mech, method, codegen, lte=tol is not None)
    scale = np.concatenate([mech.scales.q, mech.scales.v]).astype(float)
    if tol is None:
        n_steps = max(1, math.ceil(duration / dt_req * (1.0 - 1e-12)))
        h = duration / n_steps
        idx = save_indices(n_steps, h, duration, save_every, save_times, max_samples, period)
        ks, Xs, failure, extra = run_fixed(stepr, x, t0, h, p, idx, scale, progress, label, tau,
                                           ra)
        T = t0 + ks * (duration / n_steps)  # k h to within one ulp
        stats.update(dt=h, dt_requested=dt_req)
    else:
        T, Xs, failure, extra = run_adaptive(stepr, x, t0, dt_req, duration, p, method, tol,
                                             batch, tau, ra)
    stats.update(extra)
    if stats["error_estimate"] is not None:
        stats["error_memory"] = tau
        stats["dt_accurate"] = accurate_dt(stats["dt"], stats["error_estimate"])
    stats["compiled"] = stepr.compiled
    stats["compiled_kernels"] = stepr.compiled_kernels
    nq, nv = mech.n_q, mech.n_v
    q, v = Xs[:, :nq], Xs[:, nq:nq + nv]
    z = Xs[:, -mech.n_z:].copy() if (mech.n_z and isinstance(method, GeneralizedAlpha)) \
        else np.zeros((T.size, mech.n_z))
    P = p
    if ra is not None:  # each sample in the chart it was stepped in
        stats.update(ra.stats(), p_final=ra.p.tolist())
        P = ra.p_of(ks, p) if tol is None else ra.p_at_times(T, p)
    outputs = F.unpack(_outputs(mech, codegen, q, v, z, T, P).T)
    if mech.n_z:
        g = np.asarray(F.acc_residual.map(T.size)(q.T, v.T, np.zeros((nv, T.size)), z.T,
                                                   T[None, :], p)[1])
        stats["max_constraint"] = float(np.max(np.abs(g))) if g.size else 0.0
    else:
        stats["max_constraint"] = 0.0
    stats["wall_time"] = time.perf_counter() - t_start
    status = "failed" if failure is not None else "converged"
    warnings = (_message(failure, label, method, stats),) if failure is not None else ()
    if failure is None and (stats["error_estimate"] or 0.0) > ERROR_TARGET:
        warnings += (error_warning(label, stats, "the motion", period),)
    if stats.get("substepped_steps"):
        warnings += (substep_warning(label, stats),)
    traj = MechanismTrajectory(mech.name, T, q, v, z, outputs, status, stats, warnings)
    if failure is not None:
        raise ConvergenceError(warnings[0], partial=traj, diagnostics=failure)
    return traj


def substep_warning(label: str, stats: dict) -> str:
    """The note of a fixed-step run some of whose steps needed substeps to converge."""
    return (f"{label}: {stats['substepped_steps']} step(s) of dt = {stats['dt']:.3g} s converged "
            f"only as up to {stats['max_substeps']} substeps (first at t = "
            f"{stats['first_substep_time']:.6g} s): a sudden event such as a snap (a slack line "
            "jerked taut) or an impact; its peak is resolved only as far as the steps around it")


def _outputs(mech, codegen, q, v, z, T, P) -> np.ndarray:
    """The stacked outputs (:meth:`~symcable.mechanism.functions.MechanismFunctions.unpack`)
    at every sample, (n_t, n_y): ``q``, ``v``, ``z`` (n_t, n) and ``T`` (n_t,) the samples,
    ``P`` the parameters, (n_p,) or one row per sample. Evaluated OUTPUT_CHUNK samples per
    call of one map kept per Mechanism, the last chunk padded with its last sample."""
    fn = maybe_compiled(mech, ("outputs",), functions(mech).outputs, codegen, "the outputs")
    n_t = T.size
    k = max(1, min(OUTPUT_CHUNK, n_t))
    call = STEP_CACHE.get(mech, ("output_map", fn.name(), id(fn), k),
                          lambda: FastCall(fn.map(k)))
    P = np.asarray(P, dtype=float)
    out = np.empty((n_t, fn.nnz_out(0)))
    for s in range(0, n_t, k):
        e = min(s + k, n_t)
        idx = np.minimum(np.arange(s, s + k), n_t - 1)
        out[s:e] = call(q[idx], v[idx], z[idx], T[idx], P[idx] if P.ndim == 2 else P)[0] \
            .reshape(k, -1)[:e - s]
    return out


def _message(failure, label, method, stats) -> str:
    reason = failure["reason"]
    if reason == "newton":
        msg = (f"{label}: Newton did not converge in {method.max_iter} iterations in the step "
               f"from t = {failure['time_last_good']:.6g} to {failure['time']:.6g} s (scaled "
               f"residual {failure['residual']:.3g}, tolerance {method.tol:.3g}"
               + ("; its iterate ran off beyond the blow-up bound" if failure.get("diverged")
                  else "") + "): try a smaller dt")
    elif reason == "error":
        msg = (f"{label}: the step from t = {failure['time_last_good']:.6g} s failed "
               f"({failure['message']})")
    elif reason == "blowup":
        msg = (f"{label}: the state blew up (not finite, or beyond {BLOWUP:g} times its scale) in "
               f"the step to t = {failure['time']:.6g} s with dt = {failure['dt']:.6g} s (worst "
               f"entry {failure['worst']}, {failure['state_norm']:.3g} times its scale)")
    else:  # the adaptive run's step fell below its floor
        msg = f"{label}: {failure['message']}"
    if isinstance(method, RK4) and reason in ("blowup", "error"):
        msg += (f"; RK4 is stable here only for dt < {stats['dt_stable']:.4g} s: use a smaller "
                "dt or method='generalized-alpha'")
    return msg


def accurate_dt(dt: float | None, estimate: float, target: float = ERROR_TARGET) -> float | None:
    """The step (s) that should bring a fixed-step run's ``estimate`` to ``target``:
    ``DT_SAFETY dt sqrt(target / estimate)``, from the scheme's order 2 (on coarse steps, a
    few per period, the error falls more slowly, about as order 1.5, which DT_SAFETY
    covers). None for adapted steps or a zero estimate."""
    if dt is None or not estimate > 0:
        return None
    return DT_SAFETY * dt * math.sqrt(target / estimate) if math.isfinite(estimate) else 0.0


def error_warning(label: str, stats: dict, what: str, period: float | None = None) -> str:
    """The warning of a run whose ``stats["error_estimate"]`` exceeds ERROR_TARGET: how far
    off it likely is (relative to the range of ``what`` over the run) and which dt should
    meet ERROR_TARGET (with ``period``, s, a whole number of steps per period, T/n)."""
    est, dt, ok = stats["error_estimate"], stats.get("dt"), stats.get("dt_accurate")
    pct = 100.0 * est
    msg = (f"{label}: the time step is too coarse: the estimated time-stepping error is "
           f"about {f'{pct:.2g}' if pct < 100 else f'{pct:.0f}'} % of the range of {what} "
           "over the run")
    if dt is not None and ok:
        now, want = f"{dt:.3g} s", f"{ok:.3g} s"
        if period:
            n = math.ceil(period / ok - 1e-9)
            now, want = f"{now} = T/{period / dt:.3g}", f"{period / n:.3g} s = T/{n}"
        msg += f" (dt = {now}); dt <= {want} should bring it under {100 * ERROR_TARGET:g} %"
    return msg
