"""Damped Newton iteration on a square system with an exact Jacobian.

Generic: it sees two callables, ``step(x, p) -> (r, dx)`` (residual and full Newton step)
and nothing about what the unknowns mean, apart from a per-unknown scale that bounds the
step length.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Callable

import casadi as ca
import numpy as np


@dataclass
class NewtonResult:
    """Outcome of :func:`newton`.

    Attributes
    ----------
    x : ndarray (n,)       last iterate (the solution when ``converged``)
    converged : bool
    iterations : int       Newton steps taken
    residual_norm : float  max-norm of the residual at ``x``, in the residual's units
    message : str          why it stopped
    history : list of dict per iteration: ``residual_norm``, ``step_factor`` (line search)
    """

    x: np.ndarray
    converged: bool
    iterations: int
    residual_norm: float
    message: str
    history: list = field(default_factory=list)


StepFn = Callable[[np.ndarray, np.ndarray], tuple]

#: a time step's first predictor whose scaled residual (max-norm) is at most this is taken
#: as Newton's start without trying the others (:func:`best_start`): an accurate step pays
#: one residual, a large one three more. Not larger: near rest the accelerations are the
#: round-off of the forces, which on light nodes and stiff segments h^2 a turns into a
#: residual of the order of a force scale in the constant-acceleration start of a long
#: step, where rest has round-off, and Newton from the former can run off; after a release
#: the former is far worse. Not smaller: a chain's first residuals at coarse steps (up to
#: 1e-1) would pay three residuals more in nearly every step for starts that are never
#: chosen (a tenth of the step's time)
PREDICTOR_TRUST = 1e-1
#: another predictor replaces the first only where its residual is below this fraction of
#: the first's: a residual dominated by a stiff (axial) row is a poor distance, and on a
#: smooth periodic rod a start at rest with a 10 times smaller residual can take more
#: iterations than the constant acceleration; the starts it is for (after a release, near
#: rest) are many orders of magnitude better
PREDICTOR_MARGIN = 1e-3


def _choose(first, candidates: list, norms: list):
    """The candidate whose residual norm is smallest, another than the first only where its
    norm is below PREDICTOR_MARGIN times the first's ``first`` (module constants)."""
    best, best_norm = candidates[0], PREDICTOR_MARGIN * first
    for w, nrm in zip(candidates[1:], norms):
        nrm = _finite(nrm)
        best, best_norm = ca.if_else(nrm < best_norm, w, best), ca.fmin(nrm, best_norm)
    return best


def _finite(nrm):
    return ca.if_else(nrm - nrm == 0, nrm, ca.inf)  # NaN or inf: never chosen


def _lead(items: list) -> tuple:
    """Of ``items`` (tuples of CasADi expressions whose last entry is a finite residual
    norm), the one whose norm is smallest (the earlier on a tie), entry by entry."""
    best = items[0]
    for item in items[1:]:
        better = item[-1] < best[-1]
        best = tuple(ca.if_else(better, a, b) for a, b in zip(item[:-1], best[:-1])) \
            + (ca.fmin(item[-1], best[-1]),)
    return best


def best_start(res: Callable, candidates: list, lead: int = 1):
    """Newton's start among ``candidates`` (CasADi expressions): the first when its
    ``res(candidate)`` (a scaled residual norm, CasADi scalar) is at most PREDICTOR_TRUST,
    else the one whose residual is smallest, another than the first only where its
    residual is below PREDICTOR_MARGIN times the first's (the earlier on a tie; a residual
    that is not finite is never chosen). The first ``lead`` candidates are always evaluated
    and the one with the smallest residual stands first. In CasADi's graph: the other
    residuals are evaluated only where the first is above the bound (a short-circuiting
    ``if_else``)."""
    w0, first = _lead([(w, _finite(res(w))) for w in candidates[:lead]])
    candidates = [w0] + list(candidates[lead:])
    best = _choose(first, candidates, [res(w) for w in candidates[1:]])
    # a start, not a function of the step's inputs to differentiate: the solution does not
    # depend on it (an exact Newton's; the unrolled loop's derivative through its start
    # decays with its contraction), and its derivative would cost as many residual
    # derivatives as candidates
    return ca.if_else(first <= PREDICTOR_TRUST, w0, best, True)


def best_start_residual(residual: Callable, measure: Callable, candidates: list,
                        symbols: list, lead: int = 1):
    """``(start, residual(start), measure(residual(start)))``: :func:`best_start` with the
    residual vector ``residual(w)`` and its norm ``measure(r)`` apart, so that Newton's
    first iteration reuses the chosen start's residual and norm instead of evaluating them
    again; ``candidates`` and the residual are MX expressions of the MX symbols ``symbols``
    (the caller's inputs). The first ``lead`` candidates are always evaluated and the one
    with the smallest residual (the earlier on a tie) stands first. The branch is a
    Function of the first residual computed once (``Function.if_else``; CasADi's
    short-circuiting ``if_else`` of expressions would compute it again inside)."""
    n = candidates[0].numel()
    firsts = [(w, residual(w)) for w in candidates[:lead]]
    w0, r0, m0 = _lead([(w, r, _finite(measure(r))) for w, r in firsts])
    rest = candidates[lead:]
    r0_sym, m0_sym = ca.MX.sym("r0", n), ca.MX.sym("m0")
    w0_sym = ca.MX.sym("w0", n)
    best = _choose(m0_sym, [w0_sym] + rest, [measure(residual(w)) for w in rest])
    r_best = residual(best)
    args = list(symbols) + [w0_sym, r0_sym, m0_sym]
    pick = ca.Function.if_else(
        "predictor", ca.Function("predictor_first", args, [w0_sym, r0_sym, m0_sym]),
        ca.Function("predictor_best", args, [best, r_best, measure(r_best)]))
    return pick(m0 <= PREDICTOR_TRUST, *symbols, w0, r0, m0)


class _Singular(Exception):
    """The Jacobian could not be factorised."""


def _call(step: StepFn, x, p):
    try:
        r, dx = step(x, p)
    except RuntimeError as exc:  # CasADi refuses to factorise a singular Jacobian
        raise _Singular(str(exc).strip().splitlines()[-1]) from None
    return np.asarray(r, dtype=float).ravel(), np.asarray(dx, dtype=float).ravel()


def newton(step: StepFn, x0: np.ndarray, p: np.ndarray, *, tol: float, max_iter: int = 50,
           x_scale: np.ndarray | None = None, merit_weights: np.ndarray | None = None,
           armijo: float = 1e-4,
           min_step: float = 1.0 / 1024) -> NewtonResult:
    """Solve r(x; p) = 0 by Newton's method with a backtracking (Armijo) line search.

    Parameters
    ----------
    step : callable
        ``step(x, p) -> (r, dx)`` with ``dx = -J(x)^-1 r(x)``.
    x0 : ndarray (n,)
        Start.
    p : ndarray
        Parameters passed through to ``step``.
    tol : float
        Converged when ``max |r| <= tol`` (units of r).
    max_iter : int
        Largest number of Newton steps.
    x_scale : ndarray (n,), optional
        A step is shortened so that no unknown moves by more than its scale.
    merit_weights : ndarray (n,), optional
        Row weights D of the line-search merit 0.5 |D r|^2 (the Newton direction is a
        descent direction for any such weighting).
    armijo : float
        Sufficient-decrease constant of the line search on 0.5 |r|^2.
    min_step : float
        Smallest step factor the line search tries before giving up.
    """
    x = np.array(x0, dtype=float)
    D = np.ones_like(x) if merit_weights is None else np.asarray(merit_weights, dtype=float)
    history: list = []
    try:
        return _iterate(step, x, p, D, tol, max_iter, x_scale, armijo, min_step, history)
    except _Singular as exc:
        return NewtonResult(x, False, 0, float("nan"), f"singular Jacobian at the start ({exc})",
                            history)


def _iterate(step, x, p, D, tol, max_iter, x_scale, armijo, min_step, history) -> NewtonResult:
    r, dx = _call(step, x, p)
    for it in range(max_iter + 1):
        nr = float(np.max(np.abs(r))) if r.size else 0.0
        if not np.isfinite(nr):
            return NewtonResult(x, False, it, nr, "residual is not finite", history)
        if nr <= tol:
            return NewtonResult(x, True, it, nr, "converged", history)
        if it == max_iter:
            break
        if not np.all(np.isfinite(dx)):
            return NewtonResult(x, False, it, nr, "singular Jacobian (Newton step not finite)", history)
        if x_scale is not None:
            worst = float(np.max(np.abs(dx) / x_scale))
            if worst > 1.0:
                dx = dx / worst
        merit = 0.5 * float(np.sum((D * r) ** 2))
        alpha = 1.0
        while True:
            x_new = x + alpha * dx
            try:
                r_new, dx_new = _call(step, x_new, p)
                merit_new = 0.5 * float(np.sum((D * r_new) ** 2))
            except _Singular:  # a trial point where the Jacobian is singular: step shorter
                merit_new = np.inf
            if np.isfinite(merit_new) and merit_new <= (1.0 - 2.0 * armijo * alpha) * merit:
                break
            alpha *= 0.5
            if alpha < min_step:
                history.append({"residual_norm": nr, "step_factor": 0.0})
                return NewtonResult(x, False, it, nr, "line search found no decrease", history)
        history.append({"residual_norm": nr, "step_factor": alpha})
        x, r, dx = x_new, r_new, dx_new
    return NewtonResult(x, False, max_iter, nr, f"no convergence in {max_iter} iterations", history)
