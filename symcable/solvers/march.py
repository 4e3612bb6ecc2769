"""Marching a Mechanism with fixed or adapted steps, in batches that run inside CasADi.

A method's step Function is chained by ``mapaccum``: S steps between two saved samples, and
m samples per call, so a long run pays the Python interpreter once per call (about
_CALL_TARGET s of stepping), never once per step. A call whose samples include a failed step
(Newton did not converge) or a state that blew up (not finite, or beyond BLOWUP times its
scale) is replayed one step at a time from its last good sample to find the step, its time
and its residual or worst entry. Every call returns every step's state, from which
:class:`RunningEstimate` makes the run's error estimate in NumPy (the step itself is unchanged).
:func:`symcable.solvers.integrate.integrate` is the user's entry point.
"""
from __future__ import annotations

import math
import time
from collections import OrderedDict

import casadi as ca
import numpy as np

from ..mechanism.codegen import FastCall
from ..limits import check as check_limit
from ..mechanism.mechanism import Mechanism
from ..progress import ProgressBar
from .galpha1 import galpha1_kernel, galpha1_residual, step_scales
from .options import RK4, GeneralizedAlpha, GeneralizedAlphaFirstOrder
from .schedule import runs, with_checkpoints
from .stepcache import STEP_CACHE, maybe_compiled
from .steps import galpha_step, rk4_step
from .time_estimate import EstimatePlan, RunningEstimate, leaky_sum  # noqa: F401 (re-exported)

__all__ = ["BLOWUP", "IMPLICIT", "EstimatePlan", "RunningEstimate", "leaky_sum", "method_name", "run_adaptive",
           "get_stepper", "run_fixed"]

IMPLICIT = (GeneralizedAlpha, GeneralizedAlphaFirstOrder)
#: a state beyond this multiple of its scale (or not finite) means the run blew up
BLOWUP = 1e6
#: target wall time of one batched call, s (sets the progress bar's granularity)
_CALL_TARGET = 0.2
#: a batch already built is used for up to this many times fewer samples per call than
#: wanted (a run repeated at its own cost per step builds no new batch)
REUSE_RATIO = 16
#: adaptive steps: safety factor, largest growth and cut per batch
SAFETY, GROW, CUT = 0.8, 2.0, 0.2
#: a fixed step whose Newton iteration fails is retried as 2, 4, ... up to this many substeps
MAX_SUBSTEPS = 16


def method_name(method) -> str:
    """The method's name in stats and messages."""
    return {GeneralizedAlpha: "generalized-alpha",
            GeneralizedAlphaFirstOrder: "generalized-alpha-first-order"}.get(type(method), "rk4")


class _Stepper:
    """A method's step Function with its constant inputs, and batches of it:
    ``batch(S, m)(x, t0, h, p) -> (X (n_x, S m), err, lte, iterations, failed)``, the S m
    steps of m samples S steps apart from t0, every step's values (each (1, S m)); the
    last column of every S is a sample (see :meth:`run`)."""

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
        #: not compiled whole, but calling its kernels' generated C (galpha1_kernel)
        self.compiled_kernels = not self.compiled and any(
            f.is_a("External") for f in self.fn.find_functions())
        #: the size of the method's state x; the batches carry x and a flag, 1 once a step
        #: failed, after which the rest of the batch is skipped (``extend``)
        self.n_x = self.fn.size1_in(0)
        self.n_carry = self.n_x + 1
        self._guarded = None
        self.est = EstimatePlan.of(mech, method)
        self._batches: OrderedDict = OrderedDict()
        #: seconds per step of the first batch of several samples (sizes later batches)
        self.sec_per_step: float | None = None

    def extend(self, x: np.ndarray) -> np.ndarray:
        """The state ``x`` as the batches carry it (the failure flag 0 appended)."""
        return np.append(np.asarray(x, dtype=float).ravel()[:self.n_x], 0.0)

    def guarded(self) -> ca.Function:
        """The step on the carried state (x, failed): once a step has failed (its Newton
        iteration, or a state that is not finite), the later steps of a batch return at
        once instead of iterating from a bad state (the batch is replayed from its last
        good sample: :func:`run_fixed`)."""
        if self._guarded is None:
            f, n = self.fn, self.n_x
            ins = [ca.MX.sym(f.name_in(i), f.sparsity_in(i)) for i in range(f.n_in())]
            xe = ca.MX.sym("x", n + 1)
            rest = ins[1:]
            out = f(xe[:n], *rest)
            bad = out[4] if self.full else 1 - (out[1] <= self.tol)
            total = ca.sum1(out[0])
            bad = ca.logic_or(bad, ca.logic_not(total - total == 0))  # NaN or inf
            go = ca.Function("go", [xe] + rest, [ca.vertcat(out[0], bad)] + list(out[1:]))
            nan = ca.MX(np.nan)
            skip_out = [xe, nan, nan] + ([ca.MX(0), ca.MX(1)] if self.full else [])
            skip = ca.Function("skip", [xe] + rest, skip_out + [ca.MX(0)] * (len(out) - len(skip_out)))
            cond = ca.Function.if_else(f"{f.name()}_guard", go, skip)
            self._guarded = ca.Function(f"{f.name()}_guarded", [xe] + rest,
                                        cond(xe[n] == 0, xe, *rest))
        return self._guarded

    def size(self, S: int, m: int) -> int:
        """The samples per call to use where ``m`` are wanted: the largest batch already built
        for ``S`` steps a sample with between m / REUSE_RATIO and m samples, else m (building
        a batch costs 0.1-0.3 s of ``mapaccum``, a call of a smaller one a few ms)."""
        have = [mm for (ss, mm) in self._batches if ss == S and m / REUSE_RATIO <= mm <= m]
        return max(have) if have else m

    def batch(self, S: int, m: int) -> FastCall:
        fn = self._batches.get((S, m))
        if fn is not None:
            self._batches.move_to_end((S, m))
            return fn
        f = self.guarded()
        x, t0, h = ca.MX.sym("x", f.size1_in(0)), ca.MX.sym("t0"), ca.MX.sym("h")
        p = ca.MX.sym("p", f.size1_in(3))
        inner = f.mapaccum(f"{f.name()}_x{S}", S, [0], [0])
        out = inner(x, t0 + h * ca.DM(np.arange(S)).T, h, p, *self.consts)
        X, E, L = out[:3]
        IT, FL = (out[3], out[4]) if self.full else (ca.MX.zeros(1, S), 1 - (E <= self.tol))
        sample = ca.Function(f"{f.name()}_sample{S}", [x, t0, h, p],
                             [X[:, S - 1], X[:self.n_x, :], E, L, IT, FL])
        outer = sample.mapaccum(f"{f.name()}_sample{S}_x{m}", m, [0], [0])
        fn = FastCall(ca.Function(f"batch{S}x{m}", [x, t0, h, p],
                                  outer(x, t0 + (S * h) * ca.DM(np.arange(m)).T, h, p)))
        self._batches[(S, m)] = fn
        if len(self._batches) > 64:
            self._batches.popitem(last=False)
        return fn

    def run(self, S, m, x, t0, h, p) -> tuple:
        """``batch(S, m)`` evaluated from the carried state ``x`` (:meth:`extend`): numpy
        arrays, X (m, n_x + 1) (the carried state at each sample, a row each) and the
        per-sample values (m,): the largest err and lte over its S steps, the Newton
        iterations summed and largest, the failed steps; then every step's states
        (S m, n_x) and lte (S m,)."""
        Xc, Xs, E, L, IT, FL = self.batch(S, m)(x, t0, h, p)
        Xs = Xs.reshape(S * m, -1)
        per = [a.reshape(m, S) for a in (E, L, IT, FL)]
        E, Lm = (np.fmax.reduce(a, axis=1) for a in per[:2])  # NaN skipped, as CasADi's mmax
        IT, FL = per[2], per[3]
        return (Xc.reshape(m, -1), E, Lm, IT.sum(axis=1), IT.max(axis=1), FL.sum(axis=1), Xs, L)


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


def run_fixed(stepper, x, t0, h, p, idx, scale, progress, label, tau, reanchor=None):
    """Fixed steps to ``idx[-1]``, saving the steps ``idx``: (saved k, saved x (n, n_keep),
    failure diagnostics or None, stats); ``tau`` the running error estimate's memory, s
    (its stats: :meth:`RunningEstimate.stats`); ``reanchor`` a
    :class:`~symcable.solvers.reanchor.Reanchoring` (its ``p`` the one stepped in) or None."""
    inv_scale = 1.0 / scale
    track = RunningEstimate(stepper.est, x, tau)
    x = stepper.extend(x)
    keep_cols = slice(0, stepper.n_keep if stepper.n_keep is not None else stepper.n_x)
    saved_x, saved_k = ([x[None, keep_cols].copy()], [np.zeros(1, int)]) if idx[0] == 0 \
        else ([], [])  # a copy: re-anchoring changes x in place
    k, iters, iters_max, worst, lte_max, step_time = 0, 0.0, 0.0, 0.0, -np.inf, 0.0
    # the cost per step measured by this stepper's first run sizes every later batch, so
    # that repeated runs (sweeps, studies) reuse the batches built (a mapaccum of a mapaccum
    # costs tens of ms to build, a fair part of a short run)
    sec_per_step, failure = stepper.sec_per_step, None
    sub = {"substepped_steps": 0, "max_substeps": 1, "first_substep_time": None}
    wanted = idx
    idx = with_checkpoints(idx)
    bar = ProgressBar(int(idx[-1]), progress, label=f"simulate {label}")
    # substeps of a failed step are taken only where they keep the frames off their floor
    accept = None if reanchor is None else \
        (lambda Xs_, t1, hs: reanchor.below_floor(Xs_, t1, hs) is None)
    try:
        for S, count in runs(idx):
            while count > 0 and failure is None:
                if reanchor is not None:
                    p = reanchor.after(x, k, t0 + k * h)
                m = 1 if sec_per_step is None else max(1, int(_CALL_TARGET / (S * sec_per_step)))
                m = min(count, 1 << (m.bit_length() - 1))  # a power of two: few distinct batches
                m = stepper.size(S, m)  # or one already built (a second run builds none)
                stepper.batch(S, m)  # built outside the timed call
                t_call = time.perf_counter()
                known = None  # the failed step's own outputs, where a sample is one step
                try:
                    X, E, L, IT, ITM, FL, Xs, Ls = stepper.run(S, m, x, t0 + k * h, h, p)
                    bad = (FL > 0) | _bad_state(X, inv_scale)
                    n_good = int(np.argmax(bad)) if np.any(bad) else m
                    if S == 1 and n_good < m:
                        j = slice(n_good, n_good + 1)
                        known = (X[j], E[j], L[j], IT[j], ITM[j], FL[j], Xs[j], Ls[j])
                except RuntimeError:  # e.g. a singular Newton matrix: located step by step
                    n_good = 0
                cut = None if reanchor is None or not n_good else \
                    reanchor.cut(Xs[:n_good * S], t0 + (k + 1) * h, h, S)
                if cut is not None:  # stop where it re-anchors (module reanchor)
                    n_good = cut[0]
                elapsed = time.perf_counter() - t_call
                step_time += elapsed
                if n_good:
                    saved_x.append(X[:n_good, keep_cols])
                    saved_k.append(k + S * np.arange(1, n_good + 1))
                    x, k = X[n_good - 1].copy(), k + S * n_good
                    track.update(h, Xs[:n_good * S], Ls[:n_good * S])
                    iters += float(np.sum(IT[:n_good]))
                    iters_max = max(iters_max, float(np.max(ITM[:n_good])))
                    worst = max(worst, float(np.nanmax(np.r_[E[:n_good], 0.0])))
                    lte_max = max(lte_max, float(np.nanmax(np.r_[L[:n_good], -np.inf])))
                if cut is not None:
                    count -= n_good
                    if cut[1]:  # the sample that crossed the floor, a step at a time
                        x, k, failure, it_good = reanchor.step_through(
                            stepper, x, k, t0, h, S, inv_scale, track, _bad_state,
                            lambda x_, t_, h_, p_: _substeps(
                                stepper, x_, t_, h_, p_, inv_scale, track, sub, accept))
                        iters += it_good
                        if failure is not None:
                            break
                        if k in set(idx.tolist()):  # a copy: re-anchoring shifts x
                            saved_k.append(np.array([k]))
                            saved_x.append(x[None, keep_cols].copy())
                        count -= 1
                    continue
                if n_good < m:
                    k_bad, t_replay = k, time.perf_counter()
                    failure, x, k, extra, it_good = _replay(
                        stepper, x, k, t0, h, p, (m - n_good) * S, set(idx.tolist()), inv_scale,
                        track, sub, S, accept, known)
                    step_time += time.perf_counter() - t_replay
                    for kk, xx in extra:
                        saved_k.append(np.array([kk]))
                        saved_x.append(xx[None, keep_cols])
                    iters += it_good
                    # the samples of this call that were stepped (the replay returns on a
                    # sample once the bad step is through, and batches resume from there)
                    count -= n_good + (k - k_bad) // S
                    if failure is not None:
                        break
                    continue
                count -= m
                sec_per_step = sec_per_step or elapsed / (S * m)
                # kept as this run sized its batches by it (not re-measured: on a loaded
                # machine a later measurement sizes batches the first run never built)
                if stepper.sec_per_step is None:
                    stepper.sec_per_step = sec_per_step
                bar.update(k)
            if failure is not None:
                break
    finally:
        bar.close()
    ks, Xs = _saved_samples(saved_k, saved_x, wanted, failure is not None, x, k, keep_cols,
                            reanchor)
    if failure is not None:
        failure["dt"] = h
        _residual_of_failure(stepper, failure, h, p)
    extra = _run_stats(stepper, k, iters, iters_max, worst, lte_max, step_time, ks.size, sub,
                       track)
    return ks.astype(float), Xs, failure, extra


def _saved_samples(saved_k: list, saved_x: list, wanted, failed: bool, x: np.ndarray, k: int,
                   keep_cols: slice, reanchor) -> tuple[np.ndarray, np.ndarray]:
    """(ks (n,), Xs (n, n_keep)): the saved steps (``saved_k``, ``saved_x``: lists of
    arrays, ``saved_x`` emptied) that were asked for (``wanted``) and, after a failure, the
    last good state ``x`` at step ``k`` (in its chart), saved or not."""
    ks = np.concatenate(saved_k) if saved_k else np.zeros(0, int)
    chosen = np.isin(ks, wanted)
    # filled piece by piece, each batch's array let go once copied: a long line's samples
    # are 100 MB, and concatenating then choosing held three copies at once
    Xs = np.empty((int(np.count_nonzero(chosen)), x[keep_cols].size))
    row = start = 0
    for i, piece in enumerate(saved_x):
        c = chosen[start:start + len(piece)]
        n = int(np.count_nonzero(c))
        Xs[row:row + n] = piece[c]
        row, start = row + n, start + len(piece)
        saved_x[i] = None
    ks = ks[chosen]
    if failed and (not ks.size or ks[-1] != k):
        last = x if reanchor is None else reanchor.state_at(k, x)
        ks, Xs = np.append(ks, k), np.vstack([Xs, last[None, keep_cols]])
    return ks, Xs


def _run_stats(stepper, k: int, iters: float, iters_max: float, worst: float, lte_max: float,
               step_time: float, samples: int, sub: dict, track) -> dict:
    """The fixed-step run's stats: steps, Newton iterations (None where a rootfinder reports
    none), the largest step residual (N) and error estimate, the stepping time (s, and us per
    step), the samples, the substeps' (``sub``) and the running estimate's (``track``)."""
    full = stepper.full
    # (a rootfinder Newton reports no iteration counts: NaN)
    counted = full and math.isfinite(iters) and math.isfinite(iters_max)
    extra = {"steps": k, "newton_iterations": int(iters) if counted else None,
             "newton_iterations_max": int(iters_max) if counted else None,
             "max_step_residual": worst if isinstance(stepper.method, IMPLICIT) else None,
             "max_error_estimate": lte_max if np.isfinite(lte_max) else None,
             "step_time": step_time, "us_per_step": 1e6 * step_time / max(k, 1),
             "samples": int(samples), **sub}
    extra.update(track.stats())
    return extra


def _replay(stepper, x, k, t0, h, p, n_max, save_set, inv_scale, track, sub, S=None,
            accept=None, known=None):
    """Step one at a time from a good state to find the first bad step: (failure or None,
    x, k of the last good step, the (k, x) of saved steps passed, Newton iterations); the
    good steps update ``track``. A step whose Newton iteration fails (or whose matrix is
    singular) is retried as 2, 4, ... MAX_SUBSTEPS substeps (:func:`_substeps`) before it
    counts as failed; ``sub`` counts such steps. With ``S``, it returns at the first
    multiple of S steps after such a step is through (the caller's batches of S-step
    samples take over again), else after ``n_max`` steps. ``accept``: as
    :func:`_substeps`'. ``known``: the first step's outputs as ``stepper.run(1, 1, ...)``
    gives them, where the caller's batch already took it (a failed step is not taken
    twice: it would fail the same way, after as many Newton iterations)."""
    saved, good_iters, k0, through = [], 0.0, k, False
    for _ in range(n_max):
        if through and S and (k - k0) % S == 0:
            break
        diag = {"time_last_good": t0 + k * h, "time": t0 + (k + 1) * h, "step": k + 1,
                "method": method_name(stepper.method)}
        try:
            X, E, _, IT, _, FL, _, L = known or stepper.run(1, 1, x, t0 + k * h, h, p)
            known = None
            failed = FL[0] > 0
        except RuntimeError as exc:
            X, failed, message = None, True, str(exc).strip().splitlines()[-1]
        # a Newton iteration that failed, or one that ran off to a blown-up state without
        # saying so (a violent start: the iterate left the basin), is retried in substeps
        bad = X is not None and bool(_bad_state(X, inv_scale)[0])
        if (failed or bad) and isinstance(stepper.method, IMPLICIT):
            done = _substeps(stepper, x, t0 + k * h, h, p, inv_scale, track, sub, accept)
            if done is not None:
                x, k, through = done[0], k + 1, True
                good_iters += done[1]
                if k in save_set:
                    saved.append((k, x.copy()))
                continue
        if X is None:
            diag.update(reason="error", message=message, residual=float("nan"))
            return diag, x, k, saved, good_iters
        x1 = X[0]
        if bad and not failed:  # a step that said it converged, to a blown-up state
            n = inv_scale.size
            with np.errstate(invalid="ignore", over="ignore"):
                rel = np.abs(x1[:n]) * inv_scale
            rel = np.where(np.isfinite(rel), rel, np.inf)
            i = int(np.argmax(rel))
            nq = stepper.mech.n_q
            diag.update(reason="blowup", state_norm=float(rel[i]),
                        worst=f"q[{i}]" if i < nq else f"v[{i - nq}]")
            return diag, x, k, saved, good_iters
        if failed:
            its = int(IT[0]) if stepper.full and np.isfinite(IT[0]) else None
            # (its last iterate may have run off, ``diverged``: never accepted)
            diag.update(reason="newton", newton_iterations=its, diverged=bad,
                        newton_correction=float(E[0]), residual=float(E[0]), _x=(x, x1))
            return diag, x, k, saved, good_iters
        x, k = x1, k + 1
        track.update(h, X, L)
        good_iters += float(IT[0])
        if k in save_set:
            saved.append((k, x.copy()))
    return None, x, k, saved, good_iters


def _substeps(stepper, x, t, h, p, inv_scale, track, sub, accept=None):
    """The step from ``t`` over ``h`` as n = 2, 4, ... MAX_SUBSTEPS equal substeps, the first n
    whose every Newton iteration converges and whose state stays bounded (and, given
    ``accept``, for which ``accept(Xs, t1, h / n)`` holds, Xs the n substeps' states, the
    first at t1 = t + h / n: the re-anchoring's margins above its floor): (state at t + h,
    Newton iterations), ``track`` and ``sub`` updated; None when none does. A snap (a slack
    line jerked taut) or an impact concentrates in a fraction of a step what the step was
    sized for; the few steps that need it pay for it, the others keep ``h``."""
    n = 2
    while n <= MAX_SUBSTEPS:
        try:
            X, _, _, IT, _, FL, Xs, L = stepper.run(n, 1, x, t, h / n, p)
        except RuntimeError:
            X = None
        if X is not None and FL[0] == 0 and not _bad_state(X, inv_scale)[0] \
                and (accept is None or accept(Xs, t + h / n, h / n)):
            track.update(h / n, Xs, L)
            sub["substepped_steps"] += 1
            sub["max_substeps"] = max(sub["max_substeps"], n)
            if sub["first_substep_time"] is None:
                sub["first_substep_time"] = t
            return X[0].copy(), float(IT[0])
        n *= 2
    return None


def _residual_of_failure(stepper, failure, h, p):
    """The scaled residual of a failed first-order generalized-alpha step at its last
    Newton iterate (the second-order step reports its own)."""
    x_prev, x_fail = failure.pop("_x", (None, None))
    if x_prev is None or not isinstance(stepper.method, GeneralizedAlphaFirstOrder):
        return
    mech, ny = stepper.mech, stepper.mech.n_q + stepper.mech.n_v
    st = [stepper.method.rho_inf, stepper.method.tol]
    r = np.asarray(galpha1_residual(mech)(x_fail[ny:2 * ny], x_prev[:2 * ny], failure["time_last_good"], h, p,
                                          st)[0], dtype=float).ravel()
    with np.errstate(invalid="ignore", over="ignore"):
        failure["residual"] = float(np.max(np.abs(h * r * step_scales(mech)[ny:])))


def run_adaptive(stepper, x, t0, h, duration, p, method, tol, batch, tau, reanchor=None):
    """Steps adapted in batches to keep the Taylor estimate of each step's local error
    below ``tol`` (see :func:`symcable.solvers.integrate.integrate`): (times, states, failure
    or None, stats, with the running error estimate of :meth:`RunningEstimate.stats`).
    ``reanchor`` (or None): re-anchored after each batch whose last margin is low; a batch
    with a step below the floor is redone from a fresh anchor (then with a cut step)."""
    t_end = t0 + duration
    track = RunningEstimate(stepper.est, x, tau)
    times, Xs, n_x = [t0], [np.asarray(x, float).copy()], stepper.n_x
    x = stepper.extend(x)
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
        if reanchor is not None:
            p = reanchor.after(x, len(times) - 1, t)
        X, E, LTE, _, _, FL, _, _ = stepper.run(1, k, x, t, h, p)
        est = float(np.max(LTE)) if np.all(np.isfinite(LTE)) else np.inf
        newton_ok = not np.any(FL > 0)
        if reanchor is not None and newton_ok and \
                reanchor.below_floor(X, t + h, h) is not None:
            fresh = bool(reanchor.changes) and reanchor.changes[-1][1] == t
            if not fresh:  # from a fresh anchor first, then with a cut step
                reanchor.after(x, len(times) - 1, t, force=True)
                if reanchor.refused is None:
                    continue
                # no fresh anchor keeps the vertex twists: a cut step would not help
                failure = reanchor.refused_failure(t, h, len(times) - 1)
                break
            newton_ok = False
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
            Xs.append(X[i, :n_x])
        steps += k
        check_limit("steps", steps, f"the adaptive run's time steps by t = {t + k * h:.6g} s "
                    f"(of {duration:.6g} s)", "a guard against runs that exhaust memory and "
                    "time; a larger tol takes fewer steps")
        h_min, h_max = min(h_min, h), max(h_max, h)
        worst_lte = max(worst_lte, est)
        x = X[-1].copy()  # not the saved sample's row: re-anchoring changes x in place
        track.update(h, X, LTE)
        t += k * h
        h *= min(GROW, SAFETY * (tol / max(est, 1e-300)) ** (1.0 / 3.0))
    extra = {"dt": None, "steps": steps, "rejected_batches": rejected, "dt_min": h_min,
             "dt_max": h_max, "max_error_estimate": worst_lte, "tol": tol, "samples": len(times)}
    extra.update(track.stats())
    return np.array(times), np.array(Xs), failure, extra
