"""Re-anchoring in the time march: a Mechanism's optional
:class:`~symcable.mechanism.mechanism.Reanchor` hook called between steps
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

Re-anchoring describes the same physical state in the new chart, with two exceptions the
march handles: the hook's ``velocity`` (twist rates moved to the new chart), and whole turns
of twist (:class:`TwistTurns`). The new chart takes each vertex's reference twist afresh
(an atan2, modulo 2 pi): where the old chart's exceeded pi (a coarse, strongly writhed or
twisted rod), the vertex's twist would jump by a whole turn and the rod lose a turn of link.
The edge twists (the entries of q the output ``twist_angles`` selects) are shifted by the
whole turns that restore every vertex's twist (their rates unchanged: a shift by a constant);
where no shift can (the clamps hold the total), the renewal is refused and the march goes
on in the old chart, which stays valid up to the floor; it retries after every later call,
and a step below the floor while refused stops the run (reason ``"reanchor"``, the vertices
and turns in the diagnostics) instead of retaking it: the wrap is the state's, not the
step's, so smaller steps would not help. Each saved sample keeps the parameters of its step
(:meth:`Reanchoring.p_of`) and its own q, so the outputs of every sample are computed in
the chart it was stepped in.
"""
from __future__ import annotations

import math

import casadi as ca
import numpy as np

from ..mechanism.mechanism import Mechanism, Reanchor
from .stepcache import STEP_CACHE

#: a vertex twist that changes by more than this (rad) at a renewal has jumped
JUMP_TOL = 1e-9


class TwistTurns:
    """The whole turns of twist a renewal of the anchors would lose, and the edge twists that
    restore them, for a Mechanism with outputs ``twist`` (each vertex's) and
    ``twist_angles`` (each edge's, an entry of q or 0): ``turns(q, p_old, p_new, t)`` is q
    with its edge twists shifted by whole turns so that every vertex twist is the same in
    ``p_new`` as in ``p_old``, or None where no shift does (built once per Mechanism:
    :func:`twist_turns`)."""

    def __init__(self, mech: Mechanism):
        args = [mech.q, mech.t, mech.p]
        tw = ca.vec(mech.outputs["twist"].expr)
        self.twist = ca.Function("vertex_twist", args, [tw])
        self.twist_q = ca.Function("vertex_twist_q", args, [ca.jacobian(tw, mech.q)])
        # the q slot of each edge twist that is a coordinate (a row of the selection)
        sel = ca.jacobian(ca.vec(mech.outputs["twist_angles"].expr), mech.q)
        self.idx = np.unique(np.asarray(sel.sparsity().get_triplet()[1], int))

    def jump(self, q, p_old, p_new, t: float = 0.0) -> np.ndarray:
        """Each vertex's twist at q in the chart ``p_old`` minus in ``p_new`` (rad)."""
        return (np.asarray(self.twist(q, t, p_old), float)
                - np.asarray(self.twist(q, t, p_new), float)).ravel()

    def __call__(self, q, p_old, p_new, t: float = 0.0):
        """q (a new array where shifted) with every vertex twist of ``p_old`` kept in
        ``p_new``, or None (see the class)."""
        jump = self.jump(q, p_old, p_new, t)
        if not np.max(np.abs(jump), initial=0.0) > JUMP_TOL:
            return q
        if not self.idx.size:
            return None
        # least squares on the twists' Jacobian (+-1 per edge twist), rounded to whole
        # turns and checked exact
        A = np.asarray(self.twist_q(q, t, p_new), float)[:, self.idx]
        shift = np.linalg.lstsq(A, jump, rcond=None)[0]
        shift = 2.0 * math.pi * np.round(shift / (2.0 * math.pi))
        if not np.max(np.abs(A @ shift - jump)) <= JUMP_TOL * (1.0 + np.max(np.abs(jump))):
            return None
        q_new = np.array(q, float).ravel()
        q_new[self.idx] += shift
        return q_new


def twist_turns(mech: Mechanism) -> TwistTurns | None:
    """The Mechanism's :class:`TwistTurns` (cached with it), or None without the outputs
    ``twist`` and ``twist_angles`` of (q, t, p) (nothing to restore)."""
    def build():
        if "twist" not in mech.outputs or "twist_angles" not in mech.outputs:
            return None
        try:
            return TwistTurns(mech)
        except RuntimeError:  # outputs of more than (q, t, p)
            return None
    return STEP_CACHE.get(mech, ("twist_turns",), build)

__all__ = ["Reanchoring", "TwistTurns", "twist_turns"]


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
        self.turns = twist_turns(mech)
        self.shifted = 0  # renewals whose edge twists were shifted by whole turns
        self.refusals = 0  # renewals refused (no shift restores every vertex twist)
        #: the refused renewal pending (None once renewed): its time (s), the vertices whose
        #: twist would jump and by how many turns
        self.refused: dict | None = None
        self.before: tuple | None = None  # (k, the carried state before the last renewal)

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
        when the margin there is below ``threshold`` (or ``force``), and then, in ``x`` in
        place, the velocities moved to the new chart (the hook's ``velocity``) and the edge
        twists shifted by the whole turns that keep every vertex twist (:class:`TwistTurns`;
        their rates are unchanged). A saved sample of step k keeps the old chart's q, v,
        and its outputs the old parameters. Where no shift keeps the vertex twists the
        renewal is refused: ``p`` stays, ``refused`` says why (module docstring)."""
        m = float(self.margins(np.asarray(x)[None, :self.nq], np.array([t]))[0])
        if force or m < self.threshold:
            nq, nv = self.nq, self.nv
            q = np.asarray(x[:nq], float)
            p_new = np.asarray(self.update_fn(q, t, self.p), float).ravel()
            q_new = q if self.turns is None else self.turns(q, self.p, p_new, t)
            if q_new is None:
                self.refusals += 1
                jump = self.turns.jump(q, self.p, p_new, t)
                where = np.flatnonzero(np.abs(jump) > 1e-6)
                self.refused = {"time": float(t), "step": int(k), "vertices": where.tolist(),
                                "turns": (jump[where] / (2.0 * math.pi)).tolist(),
                                "margin": m}
                return self.p
            if q_new is not q:
                self.shifted += 1
            self.before = (int(k), np.array(x, float))  # step k's state in the old chart
            if self.velocity_fn is not None:  # in place: the march's carried state
                v = np.asarray(self.velocity_fn(q, x[nq:nq + nv], t, self.p), float).ravel()
                x[nq:nq + nv] = v
                if self.rates_follow:
                    x[nq + nv:2 * nq + nv] = v
            x[:nq] = q_new
            self.p = p_new
            self.refused = None
            self.changes.append((int(k), float(t), self.p.copy()))
        return self.p

    def state_at(self, k: int, x: np.ndarray) -> np.ndarray:
        """The carried state ``x`` of step ``k`` as saved: in the chart it was stepped in
        (:meth:`p_of` gives step k the parameters before a renewal at k), i.e. as it was
        before that renewal where the last one happened at k."""
        if self.before is not None and self.before[0] == k and self.changes \
                and self.changes[-1][0] == k:
            return self.before[1]
        return x

    def refused_failure(self, t: float, h: float, k: int) -> dict:
        """The march's failure (diagnostics of its ConvergenceError) where a step from
        ``t`` s (step ``k``) fell below the floor while a renewal is refused."""
        r = self.refused
        turns = ", ".join(f"vertex {i}: {n:+.3g}" for i, n in zip(r["vertices"], r["turns"]))
        return {"reason": "reanchor", "time_last_good": float(t), "time": float(t + h),
                "step": int(k) + 1, "refused": dict(r),
                "message": (f"the anchored frames must be renewed (an edge turned to within "
                            f"{self.floor:g} of its half turn, 1 + t0 . t), but re-anchoring "
                            f"(refused since t = {r['time']:.6g} s) would change the twist at "
                            f"{turns} turn(s), which no shift of the edge twists undoes: the "
                            "rod would lose link. A reference twist beyond pi at a vertex: "
                            "the rod is too coarse for its twist or writhe (more segments)")}

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
                "reanchor_shifted": self.shifted, "reanchor_refused": self.refusals,
                "reanchor_threshold": self.threshold}

    def step_through(self, stepper, x, k, t0, h, S, inv_scale, track, bad_state,
                     substeps=None):
        """S single steps from the carried state ``x`` after step ``k``, re-anchoring after
        each but the last whose margin is below ``threshold``: (x, k, failure or None, Newton
        iterations). ``bad_state`` the march's test of a blown-up state; ``substeps``
        (optional) ``substeps(x, t, h, p) -> (x1, iterations) or None``, the march's retry
        of a failed step as substeps (which keep every substep's margin above ``floor``)."""
        iters = 0.0
        self.after(x, k, t0 + k * h, force=True)
        for i in range(S):
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
                x, k = np.array(done[0], float), k + 1
                iters += done[1]
                if i < S - 1:  # as below: the march's next call re-anchors after the last
                    self.after(x, k, t0 + k * h)
                continue
            if self.below_floor(X, t + h, h) is not None:
                if self.refused is not None:
                    return x, k, self.refused_failure(t, h, k), iters
                fail["message"] = (f"an anchored frame turned to within {self.floor:g} of its "
                                   "half turn (1 + t0 . t) in one step from a fresh anchor: "
                                   "use a smaller dt")
                return x, k, fail, iters
            x, k = X[0].copy(), k + 1
            track.update(h, Xs, L)
            iters += float(IT[0])
            if i < S - 1:  # after the last, the march's next call re-anchors (the sample
                self.after(x, k, t0 + k * h)  # it saves keeps its own chart)
        return x, k, None, iters
