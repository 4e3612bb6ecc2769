"""Periodic steady state by shooting on the generalized-α period map, in generated C.

Generic over every formulation: the solver sees a :class:`~symcable.models.dynamic.DynamicModel`
through the step Function of :mod:`symcable.solvers.stepping` and nothing about cables.

The period map ``Phi`` takes the integrator's state at t = 0, ``(y, ydot)``, through ``N``
generalized-α steps of dt = T/N to t = T: the very integrator of ``simulate`` (same step
Function, same Newton tolerance), chained over one period by ``mapaccum`` into one call, so
in generated C a period costs one call from Python. The periodic steady state is the fixed
point ``z = Phi(z)`` of the scaled state ``z = (y / y_scale, ydot dt / y_scale)``: both
parts are changes of the state over one step relative to its scale (with ydot scaled by
the period instead, the rates of the fast, barely damped axial modes, invisible in the
positions and tensions, dominated the residual and took a third more periods).

It is found by Anderson acceleration (type II, the multisecant quasi-Newton method of
Walker & Ni, SIAM J. Numer. Anal. 49, 2011): each iterate is the plain march ``Phi(z)``
corrected by the least-squares combination of the last ``memory`` secant pairs. Where a few
slow modes dominate it converges in far fewer periods than marching: a lightly damped line
excited at its first natural period (studies/stability) in 58 periods, where plain
marching is still far from it after 150 (there, though, the integrator's period error sets
the amplitude: 13 % of the tension range from collocation at T/100, 3 % at T/200).
Where every mode decays alike (uniform drag damps all transverse modes of a line at one
rate, so the Floquet multipliers lie on one circle, 0.5 to 0.58 on seed 001 at T/100), no
Krylov-type method beats marching by much: 17 periods from rest to 1e-8, against 21. A bad
accelerated iterate (a step that fails, or a residual grown tenfold over the best) restarts
from the plain march of the best.

The result carries the time discretisation error of generalized-α (second order in dt; on
seed 001 at T/100, 1.3e-3 of the fairlead tension range against converged collocation),
not the ~1e-5 of the default collocation: it is the steady state ``simulate`` would reach
with the same step, found without running the transient out.

Along exact linear invariants of the model (:func:`~symcable.solvers.harmonic_balance.
linear_invariants`) the period map is neutral; their level is set at the start as the
collocation solver sets it (period-mean at the rest state's) and the iteration keeps it.
"""
from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np

from ..codegen import use_codegen
from ..errors import SymcableError
from . import harmonic_balance as hbm
from .stepping import NEWTON_TOL, _batch, step_function

__all__ = ["DEFAULT_STEPS", "DEFAULT_MEMORY", "MAX_PERIODS", "PeriodMap", "solve_shooting"]

#: Steps per period: generalized-α's error at T/100 is ~1e-3 of the tension range (seed 001)
DEFAULT_STEPS = 100
#: Secant pairs kept by Anderson acceleration. On seed 001 (tol 1e-8) marching takes 21
#: periods and Anderson 17-18 with 3 to 40 pairs; on the lightly damped resonance case of
#: studies/stability (mode 1, 20 segments) 246 periods with 10 pairs, 97 with 20, 71 with 30,
#: 58 with 50 or 80
DEFAULT_MEMORY = 50
#: Default tolerance, scaled states per second: the fixed point to ~1e-10 of the fairlead
#: tension range on seed 001 (measured: 7e-11 at 18 periods; 1e-10, 24 periods, gives 1e-12),
#: far below the integrator's own error at any usable step
TOL = 1e-8
#: Periods marched before the solve counts as failed
MAX_PERIODS = 300
#: An accelerated iterate whose residual exceeds this multiple of the best so far is dropped
RESTART_GROWTH = 10.0


@dataclass
class PeriodMap:
    """One period of generalized-α steps of ``model`` at parameters ``p``, N steps of T/N.

    ``__call__(z)`` returns ``(Phi(z), Y, iterations)`` with ``Y`` (n_y, N) the states after
    each step (``Y[:, -1]`` is y at T), or None when a step failed or the state blew up."""

    model: object
    p: np.ndarray
    steps: int
    rho_inf: float
    codegen: bool | None

    def __post_init__(self):
        m = self.model
        self.T = hbm.period_of(m, self.p)
        self.dt = self.T / self.steps
        self.n = m.n_y
        self.scale = np.asarray(m.y_scale, dtype=float)
        self.step = step_function(m, "generalized-alpha", self.codegen)
        self.compiled = bool(self.step.is_a("External"))
        self._batch = _batch(m, self.step, 1, self.steps)
        self._settings = np.array([self.rho_inf, NEWTON_TOL])

    def scaled(self, y: np.ndarray, yd: np.ndarray) -> np.ndarray:
        return np.concatenate([y / self.scale, yd * self.dt / self.scale])

    def unscaled(self, z: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        return z[:self.n] * self.scale, z[self.n:] * self.scale / self.dt

    def __call__(self, z: np.ndarray):
        y, yd = self.unscaled(z)
        N = self.steps
        try:
            Y, YD, _, IT, _, FAIL, _ = self._batch(y, yd, 0, 0.0, self.dt, self.p, self.scale,
                                                  self._settings)
        except RuntimeError:  # e.g. a singular Newton matrix on the way
            return None
        Y, YD = Y.reshape(N, -1).T, YD.reshape(N, -1).T
        if np.any(FAIL) or not (np.all(np.isfinite(Y)) and np.all(np.isfinite(YD))):
            return None
        return self.scaled(Y[:, -1], YD[:, -1]), Y, int(np.sum(IT))


def _anderson(z, r, X, F, memory):
    """Type-II Anderson update from iterate z with residual r = Phi(z) - z, given the
    history of iterates X and residuals F (lists, oldest first, z and r last); memory 0 is
    plain marching."""
    if len(X) < 2 or memory < 1:
        return z + r
    dX = np.diff(np.array(X[-memory - 1:]), axis=0).T
    dF = np.diff(np.array(F[-memory - 1:]), axis=0).T
    gamma = np.linalg.lstsq(dF, r, rcond=1e-12)[0]
    return z + r - (dX + dF) @ gamma


def solve_shooting(pm: PeriodMap, z0: np.ndarray, *, tol: float, memory: int = DEFAULT_MEMORY,
                   max_periods: int = MAX_PERIODS) -> tuple[hbm.SquareResult, np.ndarray | None, int]:
    """Fixed point of the period map from ``z0`` (scaled, see the module docstring).

    Converged when ``max |Phi(z) - z| / T <= tol`` (scaled states per second, the unit of the
    collocation residual). Returns the result (``x`` the scaled state at t = 0, ``iterations``
    the periods marched) and the states over the period from it, (N, n_y) at t = k T/N,
    k = 0..N-1 (from the best iterate when not converged; None when no period ran), and the
    generalized-α Newton iterations of every period marched."""
    t0 = time.perf_counter()
    T = pm.T
    X, F, history = [], [], []
    best = None  # (residual norm, z, Phi(z), states over the period from z)
    z, periods, newton_its, samples, status = np.asarray(z0, dtype=float), 0, 0, None, ""
    converged = False
    while periods < max_periods:
        out = pm(z)
        periods += 1
        if out is None:
            if best is None:
                status = "the first period failed (a generalized-α step did not converge)"
                break
            history.append({"period": periods, "event": "step failed: restart from the best iterate"})
            if np.array_equal(z, best[2]):
                status = "a plain period from the best iterate failed"
                break
            X, F, z = [], [], best[2]
            continue
        g, Y, its = out
        newton_its += its
        r = g - z
        rn = float(np.max(np.abs(r))) / T
        history.append({"period": periods, "residual_norm": rn})
        if best is not None and rn > RESTART_GROWTH * best[0]:
            history[-1]["event"] = "residual grew: restart from the best iterate"
            X, F, z = [], [], best[2]
            continue
        if best is None or rn < best[0]:
            best = (rn, z, g, Y)
        if rn <= tol:
            converged, status = True, "converged"
            break
        X.append(z)
        F.append(r)
        del X[:-memory - 1], F[:-memory - 1]
        z = _anderson(z, r, X, F, memory)
    else:
        status = f"not converged in {max_periods} periods" + _rate_note(history)
    x, rn = (best[1], best[0]) if best is not None else (z, float("nan"))
    if best is not None:  # the states at t_k = k T/N, k = 0..N-1 (column N-1 is y at T)
        samples = np.roll(best[3], 1, axis=1).T
    res = hbm.SquareResult(x=x, converged=converged, iterations=periods, residual_norm=rn,
                           return_status=status, solver="anderson",
                           wall_time=time.perf_counter() - t0, history=history, compiled=pm.compiled)
    return res, samples, newton_its


def _rate_note(history: list, last: int = 20) -> str:
    """Why marching is slow: the mean factor by which the residual fell per period lately."""
    rn = [h["residual_norm"] for h in history[-last:] if "residual_norm" in h]
    if len(rn) < 2 or not rn[0] > 0:
        return ""
    rate = (rn[-1] / rn[0]) ** (1.0 / (len(rn) - 1))
    return (f" (the residual fell by a factor {rate:.3f} per period over the last {len(rn)}: "
            "slowly decaying modes, as on a lightly damped line; method='collocation' solves "
            "for the steady state directly)")


def check_shooting_args(steps, rho_inf) -> tuple[int, float]:
    """Validated ``steps`` (default DEFAULT_STEPS) and ``rho_inf``."""
    steps = DEFAULT_STEPS if steps is None else steps
    if not isinstance(steps, (int, np.integer)) or steps < 8:
        raise SymcableError(f"steps = {steps!r}: must be an integer >= 8 (time steps per period)")
    try:
        rho = float(rho_inf)
    except (TypeError, ValueError):
        rho = float("nan")
    if not 0.0 <= rho <= 1.0:
        raise SymcableError(f"rho_inf = {rho_inf!r}: must be in [0, 1]")
    return int(steps), rho


def period_map(model, p, steps: int, rho_inf: float, codegen: bool | None) -> PeriodMap:
    """The period map, its step Function compiled once per model (see ``step_function``)."""
    return PeriodMap(model, np.asarray(p, dtype=float), steps, rho_inf, use_codegen(codegen))


def start_state(pm: PeriodMap, y0: np.ndarray, inv: hbm.Invariants, gauge: np.ndarray | None):
    """Scaled start ``z`` from positions ``y0`` at t = 0 with the consistent rate
    ``f(y0, 0; p)``, its invariant components set to ``gauge`` (scaled, (r,))."""
    w = np.asarray(y0, dtype=float) / pm.scale
    if inv.r and gauge is not None:
        w = w + inv.G.T @ (gauge - inv.G @ w)
    y = w * pm.scale
    yd = np.asarray(pm.model.functions().rhs(y, 0.0, pm.p).full()).ravel()
    if not np.all(np.isfinite(yd)):
        raise SymcableError("the start state has a non-finite rate f(y, 0): check the scene")
    return pm.scaled(y, yd)

