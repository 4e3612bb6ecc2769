"""Time integration of any Mechanism: generalized-alpha (implicit; second order in time with
constraints, :func:`galpha_step`, or first order on the DAE residual with any kinematics,
:func:`galpha1_step`) and RK4 (explicit, no constraints), with fixed steps (saved samples,
a progress bar, blow-up and Newton-failure reports) or steps adapted to a local error
tolerance.

Every step is one CasADi Function ``step(x, t, h, p) -> (x1, err, lte)`` (first-order
generalized-alpha adds the Newton iterations and a failure flag); ``mapaccum`` chains many
steps into one call, so a long run pays the Python interpreter once per batch of saved
samples, never once per step. The first-order generalized-alpha step and RK4 run in
generated C when ``codegen`` resolves to True (:func:`symcable.codegen.use_codegen`).
"""
from __future__ import annotations

import math
import time
from collections import OrderedDict

import casadi as ca
import numpy as np

from ..derive import functions
from ..errors import ConvergenceError, SymcableError
from ..models.mechanism import Mechanism
from ..progress import ProgressBar
from ..results_mechanism import Equilibrium, MechanismTrajectory
from .galpha1 import galpha1_kernel, galpha1_residual, galpha1_step, step_scales
from .options import RK4, GeneralizedAlpha, GeneralizedAlphaFirstOrder
from .schedule import runs, save_indices, with_checkpoints
from .stepcache import STEP_CACHE, maybe_compiled
from .steps import check_second_order, galpha_step, rk4_stability_limit, rk4_step

__all__ = ["BLOWUP", "integrate", "galpha_step", "galpha1_step", "method_name",
           "rk4_stability_limit", "rk4_step"]

_IMPLICIT = (GeneralizedAlpha, GeneralizedAlphaFirstOrder)
#: steps per mapaccum call of the adaptive run (bounds the compiled/generated graph)
BATCH = 256
#: a state beyond this multiple of its scale (or not finite) means the run blew up
BLOWUP = 1e6
#: target wall time of one batched call, s (sets the progress bar's granularity)
_CALL_TARGET = 0.2
#: adaptive steps: safety factor, largest growth and cut per batch
SAFETY, GROW, CUT = 0.8, 2.0, 0.2


def method_name(method) -> str:
    return {GeneralizedAlpha: "generalized-alpha",
            GeneralizedAlphaFirstOrder: "generalized-alpha-first-order"}.get(type(method), "rk4")


class _Stepper:
    """A method's step Function with its constant inputs, and batches of it:
    ``batch(S, m)(x, t0, h, p) -> (X (n_x, m), err, lte, iterations, iterations_max,
    failed)``, m samples S steps apart from t0, each (1, m) per sample (the largest err and
    lte over its S steps, the Newton iterations summed and largest, the failed steps)."""

    def __init__(self, mech: Mechanism, method, codegen, lte: bool = False):
        self.mech, self.method = mech, method
        self.consts, self.full = (), False
        if isinstance(method, GeneralizedAlphaFirstOrder):
            self.fn = galpha1_kernel(mech, method, lte=lte, codegen=codegen)
            self.consts = (ca.DM([method.rho_inf, method.tol]), ca.DM(step_scales(mech)))
            self.full = True
        elif isinstance(method, GeneralizedAlpha):
            self.fn = STEP_CACHE.get(mech, ("ga_step", method), lambda: galpha_step(mech, method))
        else:
            self.fn = maybe_compiled(mech, ("rk4_step",), rk4_step(mech), codegen, "the RK4 step")
        self.tol = method.tol if isinstance(method, _IMPLICIT) else math.inf
        self.compiled = bool(self.fn.is_a("External"))
        self._batches: OrderedDict = OrderedDict()

    def batch(self, S: int, m: int) -> ca.Function:
        fn = self._batches.get((S, m))
        if fn is not None:
            self._batches.move_to_end((S, m))
            return fn
        f = self.fn
        x, t0, h = ca.MX.sym("x", f.size1_in(0)), ca.MX.sym("t0"), ca.MX.sym("h")
        p = ca.MX.sym("p", f.size1_in(3))
        inner = f.mapaccum(f"{f.name()}_x{S}", S, [0], [0])
        out = inner(x, t0 + h * ca.DM(np.arange(S)).T, h, p, *self.consts)
        X, E, L = out[:3]
        IT, FL = (out[3], out[4]) if self.full else (ca.MX.zeros(1, S), 1 - (E <= self.tol))
        sample = ca.Function(f"{f.name()}_sample{S}", [x, t0, h, p],
                             [X[:, S - 1], ca.mmax(E), ca.mmax(L), ca.sum2(IT), ca.mmax(IT),
                              ca.sum2(FL)])
        outer = sample.mapaccum(f"{f.name()}_sample{S}_x{m}", m, [0], [0])
        fn = ca.Function(f"batch{S}x{m}", [x, t0, h, p],
                         outer(x, t0 + (S * h) * ca.DM(np.arange(m)).T, h, p))
        self._batches[(S, m)] = fn
        if len(self._batches) > 64:
            self._batches.popitem(last=False)
        return fn

    def run(self, S, m, x, t0, h, p) -> tuple:
        """``batch(S, m)`` evaluated: numpy arrays, the per-sample rows flattened."""
        X, *rest = (np.asarray(a, dtype=float) for a in self.batch(S, m)(x, t0, h, p))
        return (X.reshape(-1, m),) + tuple(r.ravel() for r in rest)


def _check_positive(name, value, unit):
    try:
        v = float(value)
    except (TypeError, ValueError):
        v = float("nan")
    if not (math.isfinite(v) and v > 0.0):
        raise SymcableError(f"{name} = {value!r}{' ' + unit if unit else ''}: must be > 0 "
                            "(a finite number)")
    return v


def _bad_state(X: np.ndarray, inv_scale: np.ndarray) -> np.ndarray:
    """Per column: an entry not finite, or a state entry beyond BLOWUP times its scale."""
    n = inv_scale.size
    with np.errstate(invalid="ignore", over="ignore"):
        big = np.abs(X[:n]) * inv_scale[:, None]
        return ~(np.all(np.isfinite(X), axis=0) & np.all(big <= BLOWUP, axis=0))


def _start_rates(mech, q0, v0, t0, p):
    """(q', v') at rest-or-moving start (q0, v0): the kinematics and v' = M^-1 f."""
    F = functions(mech)
    z = np.zeros(0)
    qd = np.asarray(F.qdot(q0, v0, z, t0, p), dtype=float).ravel()
    if not mech.n_v:
        return qd, np.zeros(0)
    f = -np.asarray(F.acc_residual(q0, v0, np.zeros(mech.n_v), z, t0, p)[0], dtype=float).ravel()
    mass = STEP_CACHE.get(mech, ("mass",), lambda: ca.Function("mass", [mech.q, mech.p], [mech.mass]))
    M = ca.DM(mass(q0, p))
    if M.sparsity().is_diag() and M.nnz() == mech.n_v:
        return qd, f / np.asarray(ca.diag(M).full()).ravel()
    return qd, np.asarray(ca.solve(M, ca.DM(f), "qr").full(), dtype=float).ravel()


def _initial_state(mech, F, method, q0, v0, z_guess, t0, p):
    if isinstance(method, GeneralizedAlphaFirstOrder):
        if mech.n_z:
            galpha1_kernel(mech, method)  # refuses n_z > 0
        qd0, a0 = _start_rates(mech, q0, v0, t0, p)
        return np.concatenate([q0, v0, qd0, a0]), np.zeros(0)
    if isinstance(method, RK4):
        rk4_step(mech)  # refuses n_z > 0
        return np.concatenate([q0, v0]), np.zeros(mech.n_z)
    check_second_order(mech)
    a0, z0 = (np.asarray(x).ravel() for x in F.consistent_acceleration(q0, v0, z_guess, t0, p))
    if mech.n_z and method.rho_inf >= 1.0:
        # without numerical damping the multipliers of position constraints (index 3)
        # are not damped and grow: on the toy pendulum z reached 1e6 times its value in
        # 1900 steps at T/800
        raise SymcableError(f"rho_inf = {method.rho_inf}: a mechanism with constraints "
                            "needs rho_inf < 1 (e.g. 0.9) for its constraint forces to stay "
                            "bounded")
    return np.concatenate([q0, v0, a0, a0, z0]), z0


def integrate(mech: Mechanism, duration: float, dt: float | None = None, *, method=None,
              t0: float = 0.0, p=None, save_every: int | None = 1, save_times=None,
              start: Equilibrium | None = None, q0=None, v0=None, tol: float | None = None,
              batch: int = BATCH, progress: bool | None = None, codegen: bool | None = None,
              label: str | None = None) -> MechanismTrajectory:
    """March ``mech`` over ``duration`` s from ``t0``, with fixed steps ``dt`` s or, given
    ``tol``, steps adapted to keep the local error below ``tol`` times the scales.

    Parameters
    ----------
    mech : Mechanism
    duration : float, s
    dt : float, s, optional
        The step (fixed), shortened when needed so that a whole number of steps fills
        ``duration`` (``stats["dt_requested"]`` keeps the value asked for); the first step
        with ``tol``. Default ``duration / 100``; RK4: at most 0.8 times its stability limit
        (:func:`rk4_stability_limit`, ``stats["dt_stable"]``).
    method : GeneralizedAlpha | GeneralizedAlphaFirstOrder | RK4, default GeneralizedAlpha()
    q0, v0 : initial coordinates and velocities (default: ``start``'s q, or the mechanism's
        first static start, at rest)
    start : Equilibrium, optional  where to start (its q and z)
    p : parameters (default the mechanism's own, i.e. with motion)
    save_every : int or None
        Fixed steps: keep every k-th step and the last (None: every step below 2000 steps,
        else about 2000 evenly spaced). Every accepted step is kept with ``tol``.
    save_times : array_like, optional
        Fixed steps: the times to keep (s from ``t0``), each rounded to the nearest step;
        the run stops at the last of them.
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

    Returns
    -------
    MechanismTrajectory
        ``stats``: ``method``, ``dt``, ``dt_requested``, ``steps``, ``newton_iterations``
        (total) and ``newton_iterations_max`` (per step; first-order generalized-alpha),
        ``max_step_residual``, ``max_error_estimate``, ``step_time`` (s in the step calls),
        ``us_per_step``, ``samples``, ``compiled``, ``max_constraint``, ``wall_time``.

    Raises
    ------
    SymcableError
        A bad argument (named, with its value and what is allowed).
    ConvergenceError
        A step's Newton iteration did not converge, or the state blew up (not finite, or
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
    duration = _check_positive("duration", duration, "s")
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
    default = duration / 100.0
    if isinstance(method, RK4):
        stats["dt_stable"] = rk4_stability_limit(mech, p, t0, q0, v0)
        default = min(default, 0.8 * stats["dt_stable"])
    dt_req = _check_positive("dt", default if dt is None else dt, "s")
    stepper = _Stepper(mech, method, codegen, lte=tol is not None)
    scale = np.concatenate([mech.scales.q, mech.scales.v]).astype(float)
    if tol is None:
        n_steps = max(1, math.ceil(duration / dt_req * (1.0 - 1e-12)))
        h = duration / n_steps
        idx = save_indices(n_steps, h, duration, save_every, save_times)
        ks, Xs, failure, extra = _run_fixed(stepper, x, t0, h, p, idx, scale, progress, label)
        T = t0 + ks * (duration / n_steps)  # k h to within one ulp
        stats.update(dt=h, dt_requested=dt_req)
    else:
        T, Xs, failure, extra = _run_adaptive(stepper, x, t0, dt_req, duration, p, method, tol, batch)
    stats.update(extra)
    stats["compiled"] = stepper.compiled
    nq, nv = mech.n_q, mech.n_v
    q, v = Xs[:, :nq], Xs[:, nq:nq + nv]
    z = Xs[:, -mech.n_z:].copy() if (mech.n_z and isinstance(method, GeneralizedAlpha)) \
        else np.zeros((T.size, mech.n_z))
    outputs = F.unpack(np.asarray(_outputs_fn(mech, codegen, T.size)(q.T, v.T, z.T, T[None, :], p)))
    if mech.n_z:
        g = np.asarray(F.acc_residual.map(T.size)(q.T, v.T, np.zeros((nv, T.size)), z.T,
                                                   T[None, :], p)[1])
        stats["max_constraint"] = float(np.max(np.abs(g))) if g.size else 0.0
    else:
        stats["max_constraint"] = 0.0
    stats["wall_time"] = time.perf_counter() - t_start
    status = "failed" if failure is not None else "converged"
    warnings = (_message(failure, label, method, stats),) if failure is not None else ()
    traj = MechanismTrajectory(mech.name, T, q, v, z, outputs, status, stats, warnings)
    if failure is not None:
        raise ConvergenceError(warnings[0], partial=traj, diagnostics=failure)
    return traj


def _outputs_fn(mech, codegen, n_t):
    F = functions(mech)
    return maybe_compiled(mech, ("outputs",), F.outputs, codegen, "the outputs").map(n_t)


def _message(failure, label, method, stats) -> str:
    reason = failure["reason"]
    if reason == "newton":
        msg = (f"{label}: Newton did not converge in {method.max_iter} iterations in the step "
               f"from t = {failure['time_last_good']:.6g} to {failure['time']:.6g} s (scaled "
               f"residual {failure['residual']:.3g}, tolerance {method.tol:.3g}): try a smaller dt")
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


def _run_fixed(stepper, x, t0, h, p, idx, scale, progress, label):
    """Fixed steps to ``idx[-1]``, saving the steps ``idx``: (saved k, saved x (n, n_x),
    failure diagnostics or None, stats)."""
    inv_scale = 1.0 / scale
    saved_x, saved_k = ([x.copy()], [0]) if idx[0] == 0 else ([], [])
    k, iters, iters_max, worst, lte_max, step_time = 0, 0.0, 0.0, 0.0, -np.inf, 0.0
    sec_per_step, failure = None, None
    wanted = idx
    idx = with_checkpoints(idx)
    bar = ProgressBar(int(idx[-1]), progress, label=f"simulate {label}")
    try:
        for S, count in runs(idx):
            while count > 0 and failure is None:
                m = 1 if sec_per_step is None else max(1, int(_CALL_TARGET / (S * sec_per_step)))
                m = min(count, 1 << (m.bit_length() - 1))  # a power of two: few distinct batches
                stepper.batch(S, m)  # built outside the timed call
                t_call = time.perf_counter()
                try:
                    X, E, L, IT, ITM, FL = stepper.run(S, m, x, t0 + k * h, h, p)
                    bad = (FL > 0) | _bad_state(X, inv_scale)
                    n_good = int(np.argmax(bad)) if np.any(bad) else m
                except RuntimeError:  # e.g. a singular Newton matrix: located step by step
                    n_good = 0
                elapsed = time.perf_counter() - t_call
                step_time += elapsed
                if n_good:
                    saved_x.extend(X[:, :n_good].T)
                    saved_k.extend(k + S * (i + 1) for i in range(n_good))
                    x, k = X[:, n_good - 1].copy(), k + S * n_good
                    iters += float(np.sum(IT[:n_good]))
                    iters_max = max(iters_max, float(np.max(ITM[:n_good])))
                    worst = max(worst, float(np.nanmax(np.r_[E[:n_good], 0.0])))
                    lte_max = max(lte_max, float(np.nanmax(np.r_[L[:n_good], -np.inf])))
                if n_good < m:
                    failure, x, k, extra, it_good = _replay(stepper, x, k, t0, h, p, (m - n_good) * S,
                                                            set(idx.tolist()), inv_scale)
                    for kk, xx in extra:
                        saved_k.append(kk)
                        saved_x.append(xx)
                    iters += it_good
                    count -= m
                    if failure is not None:
                        break
                    continue
                count -= m
                sec_per_step = elapsed / (S * m)
                bar.update(k)
            if failure is not None:
                break
    finally:
        bar.close()
    keep = set(wanted.tolist())
    chosen = [i for i, kk in enumerate(saved_k) if kk in keep]
    saved_x, saved_k = [saved_x[i] for i in chosen], [saved_k[i] for i in chosen]
    if failure is not None:
        failure["dt"] = h
        if not saved_k or saved_k[-1] != k:  # the last good state, saved or not
            saved_x.append(x.copy())
            saved_k.append(k)
        _residual_of_failure(stepper, failure, h, p)
    full = stepper.full
    extra = {"steps": k, "newton_iterations": int(iters) if full else None,
             "newton_iterations_max": int(iters_max) if full else None,
             "max_step_residual": worst if isinstance(stepper.method, _IMPLICIT) else None,
             "max_error_estimate": lte_max if np.isfinite(lte_max) else None,
             "step_time": step_time, "us_per_step": 1e6 * step_time / max(k, 1),
             "samples": len(saved_k)}
    return np.array(saved_k, dtype=float), np.array(saved_x), failure, extra


def _replay(stepper, x, k, t0, h, p, n_max, save_set, inv_scale):
    """Step one at a time from a good state to find the first bad step: (failure or None,
    x, k of the last good step, the (k, x) of saved steps passed, Newton iterations)."""
    saved, good_iters = [], 0.0
    for _ in range(n_max):
        diag = {"time_last_good": t0 + k * h, "time": t0 + (k + 1) * h, "step": k + 1,
                "method": method_name(stepper.method)}
        try:
            X, E, _, IT, _, FL = stepper.run(1, 1, x, t0 + k * h, h, p)
        except RuntimeError as exc:
            diag.update(reason="error", message=str(exc).strip().splitlines()[-1], residual=float("nan"))
            return diag, x, k, saved, good_iters
        x1 = X[:, 0]
        if _bad_state(X, inv_scale)[0]:
            n = inv_scale.size
            with np.errstate(invalid="ignore", over="ignore"):
                rel = np.abs(x1[:n]) * inv_scale
            rel = np.where(np.isfinite(rel), rel, np.inf)
            i = int(np.argmax(rel))
            nq = stepper.mech.n_q
            diag.update(reason="blowup", state_norm=float(rel[i]),
                        worst=f"q[{i}]" if i < nq else f"v[{i - nq}]")
            return diag, x, k, saved, good_iters
        if FL[0] > 0:
            diag.update(reason="newton", newton_iterations=int(IT[0]) if stepper.full else None,
                        newton_correction=float(E[0]), residual=float(E[0]), _x=(x, x1))
            return diag, x, k, saved, good_iters
        x, k = x1, k + 1
        good_iters += float(IT[0])
        if k in save_set:
            saved.append((k, x.copy()))
    return None, x, k, saved, good_iters


def _residual_of_failure(stepper, failure, h, p):
    """The scaled residual of a failed first-order generalized-alpha step at its last
    Newton iterate (the second-order step reports its own)."""
    x_prev, x_fail = failure.pop("_x", (None, None))
    if x_prev is None or not isinstance(stepper.method, GeneralizedAlphaFirstOrder):
        return
    mech, ny = stepper.mech, stepper.mech.n_q + stepper.mech.n_v
    st = [stepper.method.rho_inf, stepper.method.tol]
    r = np.asarray(galpha1_residual(mech)(x_fail[ny:], x_prev, failure["time_last_good"], h, p,
                                          st)[0], dtype=float).ravel()
    with np.errstate(invalid="ignore", over="ignore"):
        failure["residual"] = float(np.max(np.abs(h * r * step_scales(mech)[ny:])))


def _run_adaptive(stepper, x, t0, h, duration, p, method, tol, batch):
    t_end = t0 + duration
    times, Xs = [t0], [x.copy()]
    t, steps, rejected = t0, 0, 0
    h_min, h_max, worst_lte = np.inf, 0.0, 0.0
    k_batch = max(1, min(batch, 32))
    failure = None
    while t < t_end - 1e-12 * duration:
        remaining = t_end - t
        k = k_batch
        if k * h >= remaining:
            k = max(1, int(np.ceil(remaining / h - 1e-9)))
            h = remaining / k
        X, E, LTE, _, _, FL = stepper.run(1, k, x, t, h, p)
        est = float(np.max(LTE)) if np.all(np.isfinite(LTE)) else np.inf
        newton_ok = not np.any(FL > 0)
        if not newton_ok or est > tol:
            rejected += 1
            factor = CUT if not (newton_ok and np.isfinite(est)) else \
                max(CUT, SAFETY * (tol / est) ** (1.0 / 3.0))
            h *= factor
            if h < 1e-12 * duration:
                failure = {"reason": "step", "time": t, "time_last_good": t, "dt": h,
                           "method": method_name(method),
                           "message": f"t = {t:.6g} s: the step fell below {1e-12 * duration:.3g} s "
                                      f"(error estimate {est:.3g}, Newton {'ok' if newton_ok else 'failed'})"}
                break
            continue
        for i in range(k):
            times.append(t + (i + 1) * h)
            Xs.append(X[:, i])
        steps += k
        h_min, h_max = min(h_min, h), max(h_max, h)
        worst_lte = max(worst_lte, est)
        x = X[:, -1]
        t += k * h
        h *= min(GROW, SAFETY * (tol / max(est, 1e-300)) ** (1.0 / 3.0))
    extra = {"dt": None, "steps": steps, "rejected_batches": rejected, "dt_min": h_min,
             "dt_max": h_max, "max_error_estimate": worst_lte, "tol": tol, "samples": len(times)}
    return np.array(times), np.array(Xs), failure, extra
