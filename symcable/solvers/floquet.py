"""Floquet multipliers of a periodic solution of any Mechanism: its stability.

Method
------
The monodromy is the Jacobian of the period map Phi (shooting's
:class:`~symcable.solvers.shooting_mech.PeriodMap`: ``steps`` generalized-alpha steps over one
period, chained by ``mapaccum``) with respect to the integrator's state at t = 0, exact: CasADi
differentiates every step through its rootfinder (the implicit function theorem). Its
eigenvalues are the multipliers mu; a periodic solution is stable when every |mu| < 1.

Whatever method found the solution (collocation, harmonic balance, shooting), the map is
evaluated at the integrator's state made from the solution's (q, v, z) at t = 0 (rates made
consistent by :meth:`PeriodMap.initial_state`), or a shooting solution's own state
(``stats["state0"]``) when it has the same steps. The integrator's periodic state differs
from another method's by the integrator's O(h^2) error; up to ``refine`` Newton iterations on
Phi(u) = u (the Jacobian at hand) take the state to the integrator's own fixed point first,
so the multipliers are those of a periodic solution of the map, not of a point near one (on
an unstable branch too: Newton does not care about stability).

Which multipliers count
-----------------------
The map's state u is larger than the mechanism's: second order (q, v, a, abar), first order
(y, y') with y = (q, v). The extra entries (accelerations, rates: the integrator's memory) and
the directions the constraints remove (2 n_z) add multipliers that the scheme damps like
rho_inf^steps (negligible at the usual step counts); they are identified as the
n_u - (n_q + n_v - 2 n_z) smallest in modulus, reported only as ``dropped_max`` (their
largest modulus). The rest are the mechanism's: ``multipliers``, largest modulus first.

Stable means max |mu| < 1 + ``margin`` (:data:`STABILITY_MARGIN`, 1e-4): a mode that no
damping acts on to first order (a hanging line's lateral sway under quadratic drag with no
current: the drag's derivative is 0 at zero relative velocity) has |mu| = 1 up to the
integrator's numerical damping and round-off, and is called stable (neutral), not unstable;
a multiplier beyond 1 + margin grows by that factor every period (an instability that
doubles its amplitude within 7000 periods or fewer). The eigenvalues of the scaled monodromy
(states at their scales) are accurate to about the Newton tolerance of the steps, well
inside the margin.

Accuracy
--------
The multipliers are those of the discrete map: for a linear oscillator with eigenvalues
lambda, mu = exp(lambda T) up to generalized-alpha's second-order phase and amplitude error
(falling as h^2, of the order of 1e-3 at 100 steps per period).
"""
from __future__ import annotations

import dataclasses
import time

import numpy as np

from ..errors import SymcableError
from ..mechanism.mechanism import Mechanism
from ..results.periodic_generic import MechanismPeriodic
from .options import Shooting
from .periodic_common import Scaling
from .shooting_mech import period_map

__all__ = ["Floquet", "floquet", "STABILITY_MARGIN"]

#: a multiplier of modulus below 1 + this is stable (see the module docstring)
STABILITY_MARGIN = 1e-4
#: scaled periodicity residual of the integrator's state below which it is not refined
REFINE_TOL = 1e-8


@dataclasses.dataclass(frozen=True)
class Floquet:
    """The Floquet multipliers of one periodic solution.

    Attributes
    ----------
    multipliers : ndarray (n,), complex
        The mechanism's multipliers (n = n_q + n_v - 2 n_z), largest modulus first.
    max_modulus : float
        max |mu| (0 for a mechanism without states).
    stable : bool
        ``max_modulus < 1 + margin``.
    margin : float
    steps : int
        Generalized-alpha steps of the period map the monodromy is of.
    residual : float
        Scaled periodicity residual max |Phi(u) - u| / scale at the state the monodromy was
        taken at (after refinement).
    refinements : int
        Newton iterations taking the given state to the map's fixed point.
    dropped_max : float
        The largest modulus of the integrator-memory and constraint multipliers left out.
    wall_time : float, s
    vectors : ndarray (n_q, n), complex
        The coordinates' part of each multiplier's eigenvector (column j for
        ``multipliers[j]``), each column of unit norm in q scaled by ``scales.q``: which
        coordinates a growing or slowly decaying perturbation moves.
    """

    multipliers: np.ndarray
    max_modulus: float
    stable: bool
    margin: float
    steps: int
    residual: float
    refinements: int
    dropped_max: float
    wall_time: float
    vectors: np.ndarray = dataclasses.field(default_factory=lambda: np.zeros((0, 0), complex))

    def stats(self) -> dict:
        """The entries a periodic result's ``stats`` gets: ``floquet_multipliers`` (ndarray
        (n, 2): real and imaginary parts, largest modulus first; real, so that the stats
        export to JSON), ``floquet_max``, ``stable``, ``floquet_margin``, ``floquet_steps``,
        ``floquet_residual``, ``floquet_refinements``, ``floquet_dropped_max``,
        ``floquet_time`` (s)."""
        mu = np.asarray(self.multipliers, complex)
        return {"floquet_multipliers": np.column_stack([mu.real, mu.imag]),
                "floquet_max": self.max_modulus, "stable": self.stable,
                "floquet_margin": self.margin, "floquet_steps": self.steps,
                "floquet_residual": self.residual, "floquet_refinements": self.refinements,
                "floquet_dropped_max": self.dropped_max, "floquet_time": self.wall_time}

    def summary(self) -> str:
        """One line: ``stable: yes, largest Floquet multiplier |mu| = 0.9731``."""
        return (f"stable: {'yes' if self.stable else 'no'}, largest Floquet multiplier "
                f"|mu| = {self.max_modulus:.6g}")


def floquet(mech: Mechanism, per: MechanismPeriodic, *, steps: int | None = None,
            rho_inf: float | None = None, newton_tol: float | None = None,
            margin: float = STABILITY_MARGIN, refine: int = 3) -> Floquet:
    """The Floquet multipliers of ``per``, a periodic solution of ``mech`` (any method).

    Parameters
    ----------
    mech : Mechanism
        The mechanism ``per`` solves (same parameters ``per.p``).
    per : MechanismPeriodic
    steps : int, optional
        Steps of the period map (default: the solution's own if it is a shooting solution,
        else :class:`Shooting`'s default, 100).
    rho_inf : float, optional
        The integrator's spectral radius at infinite step (default: the solution's own if
        shooting, else the integrator's default).
    newton_tol : float, optional
        Each step's scaled Newton tolerance (default: the solution's own if shooting, else
        the integrator's default).
    margin : float
        Stable when max |mu| < 1 + margin.
    refine : int
        Newton iterations at most to the map's fixed point (0: the monodromy at the given
        state as it is).

    Returns
    -------
    Floquet

    Raises
    ------
    SymcableError
        A solution of another mechanism (sizes), or a step failing inside the period.
    """
    t0 = time.perf_counter()
    if per.q.shape[1] != mech.n_q or per.v.shape[1] != mech.n_v:
        raise SymcableError(f"per: a periodic solution of {per.q.shape[1]} coordinates, "
                            f"mechanism {mech.name!r} has {mech.n_q}")
    if not (isinstance(margin, (int, float)) and margin >= 0):
        raise SymcableError(f"margin = {margin!r}: must be a number >= 0")
    own = per.method == "shooting" and per.stats.get("state0") is not None
    if steps is None:
        steps = int(per.stats.get("steps", Shooting().steps)) if own else Shooting().steps
    if rho_inf is None and own:
        rho_inf = per.stats.get("rho_inf")
    if newton_tol is None and own:
        newton_tol = per.stats.get("newton_tol")
    opts = Shooting(steps=steps, rho_inf=rho_inf, newton_tol=newton_tol)
    pm = period_map(mech, opts, codegen=False)
    T, p = float(per.period), np.asarray(per.p, float)
    nu = pm.n_u
    if own and per.stats.get("steps") == steps and (
            opts.rho_inf is None or per.stats.get("rho_inf") == opts.rho_inf) and (
            opts.newton_tol is None or per.stats.get("newton_tol") == opts.newton_tol):
        x0 = np.asarray(per.stats["state0"], float)
    else:
        x0, _ = pm.initial_state(per.q[0], per.v[0], per.z[0], 0.0, p)
        x0 = np.asarray(x0, float)
    su = pm.u_scale(Scaling.of(mech), T)

    def evaluate(x):
        X, E, J = (np.asarray(a, float) for a in pm.with_jacobian(x, T, p))
        if not (np.all(E.ravel() <= pm.method.tol) and np.all(np.isfinite(X))):
            raise SymcableError(f"floquet: a generalized-alpha step failed inside the period "
                                f"of {per.method} solution ({steps} steps)")
        r = (X[:nu, -1] - x[:nu]) / su
        return X, r, J

    X, r, J = evaluate(x0)
    res, its = float(np.max(np.abs(r))) if nu else 0.0, 0
    while res > REFINE_TOL and its < refine:
        Js = (J - np.eye(nu)) * su[None, :] / su[:, None]
        try:
            du = -np.linalg.solve(Js, r) * su
        except np.linalg.LinAlgError:
            break  # a multiplier at exactly 1: keep the monodromy at hand
        x1 = x0.copy()
        x1[:nu] += du
        if x1.size > nu:  # the constraint forces: the step's own output as the next guess
            x1[nu:] = X[nu:, -1]
        X1, r1, J1 = evaluate(x1)
        res1 = float(np.max(np.abs(r1)))
        its += 1
        if not res1 < res:
            break
        x0, X, r, J, res = x1, X1, r1, J1, res1
    Js = J * su[None, :] / su[:, None]  # similar to J: the same eigenvalues, better conditioned
    mu, vec = np.linalg.eig(Js) if nu else (np.zeros(0, complex), np.zeros((0, 0), complex))
    order = np.argsort(-np.abs(mu), kind="stable")
    mu, vec = mu[order], vec[:, order]
    keep = max(0, min(nu, mech.n_q + mech.n_v - 2 * mech.n_z))
    kept, dropped = mu[:keep], mu[keep:]
    vq = vec[:mech.n_q, :keep]  # scaled q part (Js is in scaled states)
    vq = vq / np.maximum(np.linalg.norm(vq, axis=0), 1e-300)
    mx = float(np.abs(kept[0])) if kept.size else 0.0
    return Floquet(multipliers=kept, max_modulus=mx, stable=bool(mx < 1.0 + margin),
                   margin=float(margin), steps=int(steps), residual=res, refinements=its,
                   dropped_max=float(np.abs(dropped[0])) if dropped.size else 0.0,
                   wall_time=time.perf_counter() - t0, vectors=vq)
