"""Re-anchoring in the time march: a Mechanism's optional
:class:`~symcable.models.mechanism.Reanchor` hook called between steps
(:func:`~symcable.solvers.march.run_fixed`, :func:`~symcable.solvers.march.run_adaptive`).

The hook's ``margin`` (the rod: min over edges of 1 + t0 . t) is read at every step the
batched calls return (one mapped CasADi call per batch, nothing added to the step):

- after a call whose steps all kept the margin above ``floor``, the march re-anchors at
  its last state when the margin there is below ``threshold`` (``p := update(q, t, p)``);
- a call in which some step fell below ``floor`` keeps its samples before that step,
  re-anchors at the last of them, and retakes the sample that crossed one step at a time,
  re-anchoring after each step below ``threshold``. A single step from a fresh anchor
  (margin 2) that falls below ``floor`` turned an edge by more than about 160 degrees:
  a failure ("use a smaller dt").

Re-anchoring leaves the state (q, v and the method's carried rates) as it is: the hook
describes the same physical state in the new chart. Each saved sample keeps the
parameters of its step (:meth:`Reanchoring.p_of`), so the outputs of every sample are
computed in the chart it was stepped in.
"""
from __future__ import annotations

import math

import casadi as ca
import numpy as np

from ..models.mechanism import Mechanism, Reanchor

__all__ = ["Reanchoring"]


class Reanchoring:
    """The hook of one run: the current parameters ``p``, when they changed, the least
    margin seen."""

    def __init__(self, mech: Mechanism, hook: Reanchor, p, first_order: bool = False):
        args = [mech.q, mech.t, mech.p]
        self.margin_fn = ca.Function("frame_margin", args, [hook.margin])
        self.update_fn = ca.Function("reanchor", args, [hook.update])
        self.velocity_fn = None if hook.velocity is None else ca.Function(
            "reanchor_velocity", [mech.q, mech.v, mech.t, mech.p], [hook.velocity])
        self.nv = mech.n_v
        # the carried state: (q, v, ...); first-order generalized-alpha's also carries
        # q' = v next (a Mechanism with q' = v, n_q = n_v), which moves with v
        self.rates_follow = first_order and mech.kinematics is None and mech.n_q == mech.n_v
        self.threshold, self.floor = float(hook.threshold), float(hook.floor)
        self.nq = mech.n_q
        self.p = np.asarray(p, float).copy()
        self.changes: list = []  # (step index k from which the new p holds, time, p)
        self.min_margin = math.inf
        self.retaken = 0  # calls cut short at a step below the floor
        self._maps: dict = {}

    def margins(self, Q: np.ndarray, T: np.ndarray, record: bool = True) -> np.ndarray:
        """(K,) the margins of K states (``Q`` (K, >= n_q), ``T`` (K,) s) in the current
        chart (``record``: kept in the least margin of the run)."""
        K = Q.shape[0]
        if K == 0:
            return np.zeros(0)
        fn = self._maps.get(K)
        if fn is None:
            fn = self._maps[K] = self.margin_fn.map(K)
        out = np.asarray(fn(Q[:, :self.nq].T, np.reshape(T, (1, K)), self.p)).ravel()
        if record:
            self.min_margin = min(self.min_margin, float(np.min(out)))
        return out

    def below_floor(self, Xs: np.ndarray, t_first: float, h: float) -> int | None:
        """The index of the first of the steps ``Xs`` (their states, one a row, the first at
        ``t_first`` s, ``h`` s apart) whose margin is below ``floor``, or None."""
        m = self.margins(Xs, t_first + h * np.arange(Xs.shape[0]), record=False)
        low = np.flatnonzero(~(m >= self.floor))  # NaN counts as below
        kept = m[:low[0]] if low.size else m  # the steps after it are retaken
        if kept.size:
            self.min_margin = min(self.min_margin, float(np.min(kept)))
        if low.size:
            self.retaken += 1
        return int(low[0]) if low.size else None

    def cut(self, Xs: np.ndarray, t_first: float, h: float, S: int):
        """Where a call of fixed steps stops for re-anchoring: None when every step ``Xs``
        (their states, one a row, the first at ``t_first`` s, ``h`` s apart, S per sample)
        kept its margin above ``threshold``; else ``(samples kept, through)``: the samples
        up to the one in which the margin first fell below ``threshold`` (its end is where
        the march re-anchors), or, when that sample also fell below ``floor``, the samples
        before it and ``through`` True (that sample is retaken a step at a time)."""
        m = self.margins(Xs, t_first + h * np.arange(Xs.shape[0]), record=False)
        low = np.flatnonzero(~(m >= self.threshold))  # NaN counts as below
        if not low.size:
            self.min_margin = min(self.min_margin, float(np.min(m, initial=np.inf)))
            return None
        s = int(low[0]) // S
        sample = m[s * S:(s + 1) * S]
        through = bool(np.any(~(sample >= self.floor)))
        kept = m[:(s if through else s + 1) * S]
        if kept.size:
            self.min_margin = min(self.min_margin, float(np.min(kept)))
        self.retaken += through
        return (s, True) if through else (s + 1, False)

    def after(self, x: np.ndarray, k: int, t: float, force: bool = False) -> np.ndarray:
        """The parameters after step ``k`` (the carried state ``x``, time ``t``): re-anchored
        when the margin there is below ``threshold`` (or ``force``), and then the velocities
        in ``x`` moved to the new chart in place (the hook's ``velocity``; a saved sample of
        step k keeps the old chart's, and its outputs the old parameters)."""
        m = float(self.margins(np.asarray(x)[None, :self.nq], np.array([t]))[0])
        if force or m < self.threshold:
            nq, nv = self.nq, self.nv
            if self.velocity_fn is not None:  # in place: the march's carried state
                v = np.asarray(self.velocity_fn(x[:nq], x[nq:nq + nv], t, self.p), float).ravel()
                x[nq:nq + nv] = v
                if self.rates_follow:
                    x[nq + nv:2 * nq + nv] = v
            self.p = np.asarray(self.update_fn(np.asarray(x)[:self.nq], t, self.p),
                                float).ravel()
            self.changes.append((int(k), float(t), self.p.copy()))
        return self.p

    def p_of(self, ks: np.ndarray, p0) -> np.ndarray:
        """(n_s, n_p) the parameters each saved step ``ks`` was stepped in (``p0`` before the
        first change)."""
        ks = np.asarray(ks, float)
        P = np.tile(np.asarray(p0, float), (ks.size, 1))
        for k, _, p in self.changes:
            P[ks > k] = p
        return P

    def p_at_times(self, T: np.ndarray, p0) -> np.ndarray:
        """As :meth:`p_of`, by time (adapted steps)."""
        T = np.asarray(T, float)
        P = np.tile(np.asarray(p0, float), (T.size, 1))
        for _, t, p in self.changes:
            P[T > t] = p
        return P

    def stats(self) -> dict:
        return {"reanchorings": len(self.changes),
                "reanchor_times": [t for _, t, _ in self.changes],
                "min_frame_margin": self.min_margin if math.isfinite(self.min_margin) else None,
                "reanchor_retaken": self.retaken,
                "reanchor_threshold": self.threshold}

    def step_through(self, stepper, x, k, t0, h, S, inv_scale, track, bad_state,
                     substeps=None):
        """S single steps from the carried state ``x`` after step ``k``, re-anchoring after
        each whose margin is below ``threshold``: (x, k, failure or None, Newton
        iterations). ``bad_state`` the march's test of a blown-up state; ``substeps``
        (optional) ``substeps(x, t, h, p) -> (x1, iterations) or None``, the march's retry
        of a failed step as substeps (which keep every substep's margin above ``floor``)."""
        iters = 0.0
        self.after(x, k, t0 + k * h, force=True)
        for _ in range(S):
            t = t0 + k * h
            fail = {"time_last_good": t, "time": t + h, "step": k + 1, "reason": "error",
                    "residual": float("nan"), "method": type(stepper.method).__name__}
            try:
                X, _, _, IT, _, FL, Xs, L = stepper.run(1, 1, x, t, h, self.p)
            except RuntimeError as exc:
                fail["message"] = str(exc).strip().splitlines()[-1]
                return x, k, fail, iters
            if FL[0] > 0 or bad_state(X, inv_scale)[0]:
                done = None if substeps is None else substeps(x, t, h, self.p)
                if done is None:
                    fail["message"] = "the step failed while re-anchoring every step"
                    return x, k, fail, iters
                x, k = done[0], k + 1
                iters += done[1]
                self.after(x, k, t0 + k * h)
                continue
            if self.below_floor(X, t + h, h) is not None:
                fail["message"] = (f"an anchored frame turned to within {self.floor:g} of its "
                                   "half turn (1 + t0 . t) in one step from a fresh anchor: "
                                   "use a smaller dt")
                return x, k, fail, iters
            x, k = X[0].copy(), k + 1
            track.update(h, Xs, L)
            iters += float(IT[0])
            self.after(x, k, t0 + k * h)
        return x, k, None, iters
