"""The running error estimate of a time march (:class:`RunningEstimate`, planned by
:class:`EstimatePlan`): each step's local error, carried as a leaky sum over the decay time of
the error (:func:`leaky_sum`), relative to the range of the motion (at least MOTION_FLOOR of
the state's scales: a run at rest has no range to speak of). Made in NumPy from the
states a batched call returns; the step itself is unchanged
(:mod:`symcable.solvers.march` runs it)."""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..mechanism.mechanism import Mechanism
from .options import GeneralizedAlpha, GeneralizedAlphaFirstOrder

__all__ = ["EstimatePlan", "RunningEstimate", "leaky_sum", "MOTION_FLOOR"]

#: steps the running error estimate takes at once (its arrays stay in the cache)
_CHUNK = 256
#: the least range of the motion (relative to the scales, the state's typical change) the
#: error estimate is relative to: a state that moves by less is at rest, and its error is
#: measured against this fraction of its scale. Why not less: a line at rest still moves by
#: its Newton tolerance and the settling of its start (seed000_hybrid's rod: 2.5e-6 of its
#: velocity scale), against which its error of 6e-7 of the scale read as "25 % of the
#: range" (the floor was 1e-6: seed000_rod and seed000_hybrid warned at rest, 25 to 133 %;
#: the end tensions' own floor is the same fraction of the largest tension,
#: :data:`symcable.api.cable3d.TENSION_RANGE_FLOOR`). The built-in scenes that move have
#: ranges of 0.06 (oc3) to 28 (towed_body) of their scales
MOTION_FLOOR = 1e-3


@dataclass(frozen=True)
class EstimatePlan:
    """How a method's steps feed the running error estimate (:class:`RunningEstimate`).

    ``kind``: ``"rates"`` (first-order generalized-alpha: the local error of y = (q, v) from
    the second difference of the carried rates y', C h |y'_{n+1} - 2 y'_n + y'_{n-1}|, C the
    scheme's error constant), ``"step"`` (second-order generalized-alpha: the step's own
    Newmark estimate of the position error, its ``lte`` output) or ``"none"`` (RK4). The
    estimate and the range of the motion cover the ``n_est`` leading entries of the state
    (y, or q), over ``scale``."""

    kind: str
    n_est: int
    scale: np.ndarray
    constant: float = 0.0

    @staticmethod
    def of(mech: Mechanism, method) -> "EstimatePlan":
        sq, sv = (np.asarray(s, dtype=float) for s in (mech.scales.q, mech.scales.v))
        if isinstance(method, GeneralizedAlphaFirstOrder):
            return EstimatePlan("rates", mech.n_q + mech.n_v, np.concatenate([sq, sv]),
                                method.error_constant)
        if isinstance(method, GeneralizedAlpha):
            return EstimatePlan("step", mech.n_q, sq)
        return EstimatePlan("none", 0, np.zeros(0))


class RunningEstimate:
    """The run's error estimate, fed with every step's state as the run goes (in NumPy, on
    the states the batched calls return: nothing is added to the step itself).

    Each step's local error d_j relative to the scales (max-norm; :class:`EstimatePlan`)
    feeds a leaky sum E_{j+1} = exp(-h / tau) E_j + d_j. The global error of a response of
    period P = 2 pi tau is about the local errors of its last radian: a harmonic error
    source of d per step, d / h per unit time, integrated over time gives an error of
    amplitude d / (h omega), local error times steps per radian; the leak forgets older
    errors as a forced, damped response does. A step whose three carried rates do not all
    come from steps of its size adds nothing (the first two of a run, and the two after a
    change of step: the rates carry an offset proportional to h). Also kept: the least and
    largest value of each covered state entry (the range of the motion)."""

    def __init__(self, plan: EstimatePlan, x: np.ndarray, tau: float):
        self.plan, self.tau = plan, tau
        y = np.asarray(x, dtype=float)
        n = plan.n_est
        self.lo, self.hi = y[:n].copy(), y[:n].copy()
        self.rates = y[n:2 * n].copy() if plan.kind == "rates" else None  # the last y'
        self.prev_rates = None  # the y' before it
        self.h_prev = (math.nan, math.nan)  # sizes of the steps that made them
        self.E, self.E_max = 0.0, 0.0

    def update(self, h: float, X: np.ndarray, lte: np.ndarray) -> None:
        """Take k more steps of size h (s): their states X (k, n_x) and lte (k,)."""
        if self.plan.kind == "none":
            return
        for s in range(0, X.shape[0], _CHUNK):  # pieces that stay in the cache
            self._update(h, X[s:s + _CHUNK], lte[s:s + _CHUNK])

    def _update(self, h, X, lte):
        plan, k = self.plan, X.shape[0]
        n = plan.n_est
        self.lo = np.minimum(self.lo, X[:, :n].min(axis=0))
        self.hi = np.maximum(self.hi, X[:, :n].max(axis=0))
        if plan.kind == "step":
            d = np.maximum(np.asarray(lte, dtype=float), 0.0)
        else:
            R = np.vstack([self.prev_rates if self.prev_rates is not None else self.rates,
                           self.rates, X[:, n:2 * n]])
            d2 = np.abs(R[2:] - 2.0 * R[1:-1] + R[:-2]) * (1.0 / plan.scale)
            d = plan.constant * h * np.max(d2, axis=1)
            if not (h == self.h_prev[0] and h == self.h_prev[1]):
                d[0] = 0.0
            if k > 1 and not h == self.h_prev[0]:
                d[1] = 0.0
            self.prev_rates = R[-2].copy()
            self.rates = R[-1].copy()
        self.h_prev = (h, h) if k > 1 else (h, self.h_prev[0])
        E = leaky_sum(self.E, d, h / self.tau)
        self.E, self.E_max = float(E[-1]), max(self.E_max, float(np.max(E)))

    def stats(self) -> dict:
        """``error_estimate_scaled`` (the largest running estimate, relative to the scales),
        ``motion_range`` (max_i (hi_i - lo_i) / scale_i over the run) and ``error_estimate``
        (their ratio: the error relative to the range of the motion, or to MOTION_FLOOR
        when the motion is smaller: a state at rest up to a thousandth of its scale is not a
        motion, and an error relative to its range would be noise over noise); None
        without an estimate (RK4)."""
        if self.plan.kind == "none":
            return {"error_estimate": None, "error_estimate_scaled": None, "motion_range": None}
        rng = float(np.max((self.hi - self.lo) / self.plan.scale)) if self.lo.size else 0.0
        e = self.E_max
        return {"error_estimate": e / max(rng, MOTION_FLOOR), "error_estimate_scaled": e,
                "motion_range": rng}


def leaky_sum(E0: float, d: np.ndarray, a: float) -> np.ndarray:
    """E_j = exp(-a) E_{j-1} + d_j from E0, for every j, in chunks short enough that
    exp(a j) stays below e^30 (E_j = exp(-a j) (E0 + sum_i exp(a i) d_i) within a chunk)."""
    out = np.empty(d.size)
    c = max(1, int(30.0 / a)) if a > 0 else max(d.size, 1)
    E = E0
    for s in range(0, d.size, c):
        dd = d[s:s + c]
        j = a * np.arange(1, dd.size + 1)
        out[s:s + dd.size] = np.exp(-j) * (E + np.cumsum(np.exp(j) * dd))
        E = out[s + dd.size - 1]
    return out
