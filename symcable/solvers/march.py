"""Marching a Mechanism with fixed or adapted steps, in batches that run inside CasADi.

A method's step Function is chained by ``mapaccum``: S steps between two saved samples, and
m samples per call, so a long run pays the Python interpreter once per call (about
_CALL_TARGET s of stepping), never once per step. A call whose samples include a failed step
(Newton did not converge) or a state that blew up (not finite, or beyond BLOWUP times its
scale) is replayed one step at a time from its last good sample to find the step, its time
and its residual or worst entry. :func:`symcable.solvers.integrate.integrate` is the user's
entry point.
"""
from __future__ import annotations

import math
import time
from collections import OrderedDict

import casadi as ca
import numpy as np

from ..codegen import FastCall
from ..models.mechanism import Mechanism
from ..progress import ProgressBar
from .galpha1 import galpha1_kernel, galpha1_residual, step_scales
from .options import RK4, GeneralizedAlpha, GeneralizedAlphaFirstOrder
from .schedule import runs, with_checkpoints
from .stepcache import STEP_CACHE, maybe_compiled
from .steps import galpha_step, rk4_step

__all__ = ["BLOWUP", "IMPLICIT", "method_name", "run_adaptive", "get_stepper", "run_fixed"]

IMPLICIT = (GeneralizedAlpha, GeneralizedAlphaFirstOrder)
#: a state beyond this multiple of its scale (or not finite) means the run blew up
BLOWUP = 1e6
#: target wall time of one batched call, s (sets the progress bar's granularity)
_CALL_TARGET = 0.2
#: adaptive steps: safety factor, largest growth and cut per batch
SAFETY, GROW, CUT = 0.8, 2.0, 0.2


def method_name(method) -> str:
    """The method's name in stats and messages."""
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
        self.tol = method.tol if isinstance(method, IMPLICIT) else math.inf
        # what a trajectory keeps of x: (q, v), and with GeneralizedAlpha also z (last)
        self.n_keep = mech.n_q + mech.n_v if self.full or isinstance(method, RK4) else None
        self.compiled = bool(self.fn.is_a("External"))
        self._batches: OrderedDict = OrderedDict()

    def batch(self, S: int, m: int) -> FastCall:
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
        fn = FastCall(ca.Function(f"batch{S}x{m}", [x, t0, h, p],
                                  outer(x, t0 + (S * h) * ca.DM(np.arange(m)).T, h, p)))
        self._batches[(S, m)] = fn
        if len(self._batches) > 64:
            self._batches.popitem(last=False)
        return fn

    def run(self, S, m, x, t0, h, p) -> tuple:
        """``batch(S, m)`` evaluated: numpy arrays, X (m, n_x) (a sample per row) and the
        per-sample values (m,)."""
        X, *rest = self.batch(S, m)(x, t0, h, p)
        return (X.reshape(m, -1),) + tuple(rest)


def get_stepper(mech, method, codegen, lte) -> _Stepper:
    """The _Stepper of (method, resolved codegen), kept with the Mechanism so that its
    batches are built once."""
    st = _Stepper(mech, method, codegen, lte)
    return STEP_CACHE.get(mech, ("stepper", method, lte, st.fn.name(), id(st.fn)), lambda: st)


def _bad_state(X: np.ndarray, inv_scale: np.ndarray) -> np.ndarray:
    """Per sample (row of X): a state entry beyond BLOWUP times its scale or not finite, or
    another entry (rates, multipliers) not finite."""
    n = inv_scale.size
    with np.errstate(invalid="ignore", over="ignore"):
        big = np.max(np.abs(X[:, :n]) * inv_scale, axis=1) if n else np.zeros(X.shape[0])
        rest = np.sum(X[:, n:], axis=1) if X.shape[1] > n else np.zeros(X.shape[0])
    return ~(big <= BLOWUP) | ~np.isfinite(rest)  # NaN fails every comparison


def run_fixed(stepper, x, t0, h, p, idx, scale, progress, label):
    """Fixed steps to ``idx[-1]``, saving the steps ``idx``: (saved k, saved x (n, n_keep),
    failure diagnostics or None, stats)."""
    inv_scale = 1.0 / scale
    keep_cols = slice(0, stepper.n_keep)
    saved_x, saved_k = ([x[None, keep_cols]], [np.zeros(1, int)]) if idx[0] == 0 else ([], [])
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
                    saved_x.append(X[:n_good, keep_cols])
                    saved_k.append(k + S * np.arange(1, n_good + 1))
                    x, k = X[n_good - 1].copy(), k + S * n_good
                    iters += float(np.sum(IT[:n_good]))
                    iters_max = max(iters_max, float(np.max(ITM[:n_good])))
                    worst = max(worst, float(np.nanmax(np.r_[E[:n_good], 0.0])))
                    lte_max = max(lte_max, float(np.nanmax(np.r_[L[:n_good], -np.inf])))
                if n_good < m:
                    failure, x, k, extra, it_good = _replay(stepper, x, k, t0, h, p, (m - n_good) * S,
                                                            set(idx.tolist()), inv_scale)
                    for kk, xx in extra:
                        saved_k.append(np.array([kk]))
                        saved_x.append(xx[None, keep_cols])
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
    ks = np.concatenate(saved_k) if saved_k else np.zeros(0, int)
    Xs = np.concatenate(saved_x) if saved_x else np.zeros((0, x[keep_cols].size))
    chosen = np.isin(ks, wanted)
    ks, Xs = ks[chosen], Xs[chosen]
    if failure is not None:
        failure["dt"] = h
        if not ks.size or ks[-1] != k:  # the last good state, saved or not
            ks, Xs = np.append(ks, k), np.vstack([Xs, x[None, keep_cols]])
        _residual_of_failure(stepper, failure, h, p)
    full = stepper.full
    extra = {"steps": k, "newton_iterations": int(iters) if full else None,
             "newton_iterations_max": int(iters_max) if full else None,
             "max_step_residual": worst if isinstance(stepper.method, IMPLICIT) else None,
             "max_error_estimate": lte_max if np.isfinite(lte_max) else None,
             "step_time": step_time, "us_per_step": 1e6 * step_time / max(k, 1),
             "samples": int(ks.size)}
    return ks.astype(float), Xs, failure, extra


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
        x1 = X[0]
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


def run_adaptive(stepper, x, t0, h, duration, p, method, tol, batch):
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
            Xs.append(X[i])
        steps += k
        h_min, h_max = min(h_min, h), max(h_max, h)
        worst_lte = max(worst_lte, est)
        x = X[-1]
        t += k * h
        h *= min(GROW, SAFETY * (tol / max(est, 1e-300)) ** (1.0 / 3.0))
    extra = {"dt": None, "steps": steps, "rejected_batches": rejected, "dt_min": h_min,
             "dt_max": h_max, "max_error_estimate": worst_lte, "tol": tol, "samples": len(times)}
    return np.array(times), np.array(Xs), failure, extra
