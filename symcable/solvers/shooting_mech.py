"""Shooting on the generalized-alpha period map of any Mechanism.

Method
------
The period map Phi takes the integrator's state at t = 0 through N = ``Shooting.steps``
steps of h = T/N to t = T, chained by ``mapaccum`` into one call, with one of two
integrators of :mod:`~symcable.solvers.integrate` (the very steps of ``integrate``, with
their Newton tolerance):

- second order, :func:`~symcable.solvers.integrate.galpha_step` (q' = v, constraints
  imposed at every step), state x = (q, v, a, abar, z); the fixed point is u = (q, v, a,
  abar): the pseudo-acceleration abar carries memory between steps, so it belongs to the
  fixed point as much as q and v; z is an output of each step (its Newton guess only);
- first order, :func:`~symcable.solvers.integrate.galpha1_step` (Jansen et al. on the DAE
  residual, any kinematics q' = G v + w, n_z = 0), state and fixed point u = (y, y'), y =
  (q, v): the carried rate y' is the scheme's memory. Used where the mechanism has
  kinematics (the planar cable; the second-order scheme needs q' = v). Where it has none
  both apply, and the second order stays: it takes constraints, and on the toy mechanisms
  it is as fast or faster at a smaller error (the numbers: studies/README.md).

The fixed point is found by Anderson acceleration (type II, depth 10, or n_u / 3 up to 50
on a large state: each iterate is the plain march Phi(u) corrected by the least-squares
combination of the last secant pairs; Walker & Ni, SIAM J. Numer. Anal. 49, 2011); when it
has not converged within 60 periods (or n_u + 1, the cost of one monodromy, where that is
more), Newton's method with the exact monodromy takes over from the best iterate: CasADi
differentiates the mapaccum'd period map through each step's rootfinder (the step asked for
with ``newton="rootfinder"``: the implicit function theorem), one call returning Phi(u)
and dPhi/du, and a Newton step that does not reduce the residual is halved (up to 6 times,
each trial a plain period).

Why this order:
Newton needs the fewest periods, but a period with its Jacobian costs about n_u + 1 plain
ones (n_u = 2 (n_q + n_v) forward directions through every step's linear solve), so Anderson
is faster on all three and more so as n_u grows (a cable has hundreds). Newton is kept as
the fallback: its convergence is quadratic whatever the Floquet multipliers, where Anderson
slows down on lightly damped modes, and it is the one that returns the monodromy (its
largest multiplier is reported as ``floquet_max``).

What a monodromy costs decides when Newton takes over. Where the steps run in the virtual
machine, CasADi carries all n_u directions through a step at once and a monodromy costs a few
tens of plain periods: there Anderson stops as soon as its residual has stalled
(:func:`stalled`: the best of the last 10 periods not 0.98^10 below the best of the 10
before, while above a scaled 1e-6) and Newton takes over at once. Where the plain periods run
in generated C (the first-order step) and the monodromy in the virtual machine, a monodromy
costs thousands of periods, and Anderson keeps its whole budget. (The measurements behind
both: studies/README.md.)

Scaling
-------
Second order: u is divided by (scales.q, scales.v, a_ref, a_ref), a_ref = scales.v 2 pi / T;
first order: by (y_scale, y_scale / h), the rates as a change of y over one step. The
residual Phi(u) - u likewise: a change over one period relative to the state's magnitude.

Start
-----
The static equilibrium at rest (the other methods start from
:func:`~symcable.solvers.periodic_start.transient_start`, a
short time run from it; shooting's own first periods are that run, at its own steps, so a
separate one only costs), or a given periodic solution at t = 0, the rates made consistent
(second order: accelerations and constraint forces by the derived
``consistent_acceleration``, abar = a; first order: y' from the equations); or, from a
shooting solution of the same steps, its integrator state (``stats["state0"]``), which one
period confirms.

Checks
------
The N step states are interpolated trigonometrically to 4N uniform samples and checked by
:func:`~symcable.solvers.periodic_common.check_and_wrap`: the integrator's O(h^2) error
shows up as the defect between q' (spectral) and v and between M v' and f. The periodicity
defect is the final scaled residual of the fixed point.
"""
from __future__ import annotations

import dataclasses
import math
import time

import casadi as ca
import numpy as np

from ..mechanism.codegen import FastCall, use_codegen
from ..mechanism.functions import functions
from ..errors import SymcableError
from ..limits import current as current_limits, remaining_seconds
from ..mechanism.mechanism import Mechanism
from ..results.periodic_generic import trig_interp
from .galpha1 import galpha1_kernel, step_scales
from .integrate import galpha1_step, galpha_step
from .options import GeneralizedAlpha, GeneralizedAlphaFirstOrder, Shooting
from .periodic_common import PERIODIC_CACHE, Scaling, StartFn, check_and_wrap

__all__ = ["PeriodMap", "period_map", "solve_shooting"]

#: halvings of a Newton step that does not reduce the residual
MAX_HALVINGS = 6
#: secant pairs of Anderson acceleration, and the periods it may take before Newton takes over
ANDERSON_DEPTH = 10
ANDERSON_PERIODS = 60
#: the most secant pairs on a large state (n_u / 3 up to this): a lightly damped line needs
#: many pairs, a line whose modes decay alike does not mind (studies/README.md)
ANDERSON_MAX_DEPTH = 50


#: Anderson stops early, and Newton takes over, when the best residual of the last
#: ANDERSON_STALL_PERIODS / 2 periods is above ANDERSON_STALL_RATE ** (that many) times the
#: best of the half before: a stalled iteration; converging runs fall much faster per period,
#: and a stall cut short costs nothing Newton would not fix (studies/README.md)
ANDERSON_STALL_RATE = 0.98
ANDERSON_STALL_PERIODS = 20
#: ... while its residual is above this (scaled): a stall far from any solution. Below it the
#: residual is near the round-off of the steps' Newton solves (1e-8 of the state's scale),
#: where Newton cannot do better either, and Anderson keeps its budget
ANDERSON_STALL_FLOOR = 1e-6
#: a first period with its monodromy is taken to cost this many plain periods when judging
#: whether it fits before the call's time limit (in the virtual machine it costs a few tens)
MONODROMY_PERIODS = 30


def stalled(history: list) -> bool:
    """Whether Anderson's residual ``history`` (one per period) has stalled (see
    ANDERSON_STALL_RATE)."""
    n = ANDERSON_STALL_PERIODS // 2
    if len(history) < 2 * n:
        return False
    recent, before = min(history[-n:]), min(history[-2 * n:-n])
    return bool(np.isfinite(before) and recent > ANDERSON_STALL_FLOOR
                and recent > before * ANDERSON_STALL_RATE ** n)


def anderson_depth(n_u: int) -> int:
    """Secant pairs kept: ANDERSON_DEPTH, or n_u / 3 on large states, at most
    ANDERSON_MAX_DEPTH."""
    return min(ANDERSON_MAX_DEPTH, max(ANDERSON_DEPTH, n_u // 3))


class PeriodMap:
    """The period map of one mechanism for (steps, rho_inf), on one of two integrators.

    Second order (:func:`~symcable.solvers.integrate.galpha_step`, q' = v), x = (q, v, a,
    abar, z), the fixed point u = (q, v, a, abar) (n_u = 2 n_q + 2 n_v); first order
    (:func:`~symcable.solvers.integrate.galpha1_step`, any kinematics q' = G v + w, n_z = 0),
    x = u = (y, y') with y = (q, v) (n_u = 2 (n_q + n_v)). ``march(x0, T, p) -> (X, err)``:
    the N states after each step (columns) and each step's scaled Newton residual;
    ``with_jacobian(x0, T, p) -> (X, err, J)`` adds J = dX[:n_u, -1]/dx0[:n_u], through the
    rootfinder-based step (exact, by the implicit function theorem)."""

    def __init__(self, mech: Mechanism, steps: int, rho_inf: float | None, first_order: bool,
                 codegen: bool = False, newton_tol: float | None = None):
        self.mech, self.steps, self.first_order = mech, steps, first_order
        nq, nv, nz = mech.n_q, mech.n_v, mech.n_z
        given = {k: v for k, v in (("rho_inf", rho_inf), ("tol", newton_tol)) if v is not None}
        if first_order:
            self.method = GeneralizedAlphaFirstOrder(**given)
            # the step kernel itself, mapped: a wrapper Function per step would cost a
            # virtual-machine call per step around the compiled one
            kern = galpha1_kernel(mech, self.method, lte=False, codegen=codegen)
            self.compiled = kern.is_a("External")
            consts = (ca.DM([self.method.rho_inf, self.method.tol]), ca.DM(step_scales(mech)))
            fast = (kern, consts)
            exact = galpha1_step(mech, dataclasses.replace(self.method, newton="rootfinder"),
                                 lte=False)
            self.n_u = 2 * (nq + nv)
            n_x = self.n_u
        else:
            self.method = GeneralizedAlpha(**given)
            fast = exact = galpha_step(mech, self.method)
            self.compiled = False
            self.n_u = 2 * nq + 2 * nv
            n_x = self.n_u + nz
        self._exact, self._n_x, self._jac = exact, n_x, None
        X, E = self._period(fast, "period")
        self.march = ca.Function(f"{mech.fname}_period_march", [self._x0, self._T, self._p],
                                 [X, E], ["x0", "T", "p"], ["X", "err"])

    def _period(self, step: ca.Function, tag: str) -> tuple:
        self._x0, self._T = ca.MX.sym("x0", self._n_x), ca.MX.sym("T")
        self._p = ca.MX.sym("p", self.mech.params.n)
        h = self._T / self.steps
        times = h * ca.DM(np.arange(self.steps)).T
        consts = ()
        if isinstance(step, tuple):
            step, consts = step
        acc = step.mapaccum(f"{self.mech.fname}_{tag}", self.steps, [0], [0])
        X, E = acc(self._x0, times, h, self._p, *consts)[:2]
        return X, E

    @property
    def with_jacobian(self) -> ca.Function:
        """Built on first use (only Newton needs it): its graph is the period's and its
        forward derivative in n_u directions."""
        if self._jac is None:
            X, E = self._period(self._exact, "period_exact")
            J = ca.jacobian(X[:self.n_u, -1], self._x0)[:, :self.n_u]
            self._jac = ca.Function(f"{self.mech.fname}_period_map", [self._x0, self._T, self._p],
                                    [X, E, J], ["x0", "T", "p"], ["X", "err", "J"])
        return self._jac

    def initial_state(self, q, v, z, t, p) -> tuple:
        """(x, z): the integrator's state at (q, v, z) and time t, its rates made consistent
        (second order: a and z by ``consistent_acceleration``, abar = a; first order:
        y' = (q', M^-1 f) from the equations)."""
        F = functions(self.mech)
        if self.first_order:
            qd = np.asarray(F.qdot(q, v, z, t, p)).ravel()
            nv = self.mech.n_v
            M = np.atleast_2d(np.asarray(F.tangents(q, v, z, t, p)[2]))
            r_f = np.asarray(F.acc_residual(q, v, np.zeros(nv), z, t, p)[0]).ravel()
            a = np.linalg.solve(M, -r_f) if nv else np.zeros(0)
            return np.concatenate([q, v, qd, a]), np.zeros(0)
        a, z1 = (np.asarray(x).ravel() for x in F.consistent_acceleration(q, v, z, t, p))
        return np.concatenate([q, v, a, a, z1]), z1

    def u_scale(self, sc: Scaling, period: float) -> np.ndarray:
        """Scales of u: (q, v, a_ref, a_ref), a_ref = scales.v 2 pi / T (second order);
        (y, y' h / y) for the first order, h = T/N: the rates as the change of y over one
        step relative to its scale (scaled by the period instead, the rates of fast, barely
        damped modes, invisible in y, dominate the residual: on the planar cable a third
        more periods)."""
        if self.first_order:
            y = np.concatenate([sc.q, sc.v])
            return np.concatenate([y, y * self.steps / period])
        a_ref = sc.v * 2 * math.pi / period
        return np.concatenate([sc.q, sc.v, a_ref, a_ref])

    def samples(self, X: np.ndarray) -> tuple:
        """(q, v, z) at the step times t = 0, h, .., (N-1) h from the states after each step
        (the state after N steps is the one at t = 0)."""
        nq, nv = self.mech.n_q, self.mech.n_v
        cols = np.concatenate([X[:, -1:], X[:, :-1]], axis=1)
        z = cols[self.n_u:].T if (self.mech.n_z and not self.first_order) \
            else np.zeros((cols.shape[1], self.mech.n_z))
        return cols[:nq].T, cols[nq:nq + nv].T, z


def first_order(mech: Mechanism) -> bool:
    """Whether shooting runs the first-order generalized-alpha on ``mech``: where it has
    kinematics (the second-order scheme needs q' = v)."""
    return mech.kinematics is not None


def period_map(mech: Mechanism, opts: Shooting, codegen: bool | None = False) -> PeriodMap:
    """The period map of ``mech`` for ``opts``, built once per mechanism and options; with
    ``codegen`` (resolved by :func:`symcable.mechanism.codegen.use_codegen`) the first-order step runs
    in generated C (compiled once, with a notice; the exact-derivative step of the Newton
    fallback stays in the virtual machine)."""
    fo = first_order(mech)
    cg = bool(use_codegen(codegen)) if fo else False
    return PERIODIC_CACHE.get(mech, ("shooting", opts.steps, opts.rho_inf, fo, cg, opts.newton_tol),
                              lambda: PeriodMap(mech, opts.steps, opts.rho_inf, fo, cg,
                                                opts.newton_tol))


def _rate_note(history: list, last: int = 20) -> str:
    """Why the iteration is slow: the mean factor by which the residual fell per period over
    the last ``last`` periods (slowly decaying modes, as on a lightly damped line)."""
    rn = [r for r in history[-last:] if np.isfinite(r)]
    if len(rn) < 2 or not rn[0] > 0:
        return ""
    rate = (rn[-1] / rn[0]) ** (1.0 / (len(rn) - 1))
    return (f" (the residual fell by a factor {rate:.3f} per period over the last {len(rn)} "
            "periods: slowly decaying modes; collocation solves for the steady state directly)")


def anderson_budget(n_u: int) -> int:
    """Periods Anderson may take before Newton takes over: ANDERSON_PERIODS up to
    ANDERSON_PERIODS unknowns, and in proportion to n_u + 1 beyond, the cost of one Newton
    iteration (a monodromy costs about n_u + 1 periods)."""
    return int(math.ceil(ANDERSON_PERIODS * max(1.0, (n_u + 1) / 60.0)))


def solve_shooting(mech: Mechanism, period: float, opts: Shooting, p, start: StartFn,
                   start_info: dict, *, tol: float, defect_tol: float, max_iter: int = 30,
                   state0: np.ndarray | None = None, codegen: bool | None = False):
    """Shooting of ``mech`` from ``start`` (see the module docstring); ``state0``: the
    integrator's state at t = 0 to start from instead (a shooting solution's
    ``stats["state0"]`` with the same steps and rho_inf); ``codegen``: the step in generated
    C (:func:`period_map`)."""
    t0 = time.perf_counter()
    pm = period_map(mech, opts, codegen)
    sc = Scaling.of(mech)
    nz, nu, N = mech.n_z, pm.n_u, opts.steps
    su = pm.u_scale(sc, period)
    if state0 is not None:
        x0 = np.asarray(state0, float).ravel()
        if x0.size != pm.march.size1_in(0):
            raise SymcableError(f"state0 has {x0.size} entries, the period map's state "
                                f"{pm.march.size1_in(0)}")
        u, z = x0[:nu], x0[nu:]
    else:
        q0, v0, z0 = (np.asarray(a, float)[0] for a in start(np.zeros(1)))
        x0, z = pm.initial_state(q0, v0, z0, 0.0, p)
        u = x0[:nu]
    # NumPy in and out: a DM of N states costs ms to convert
    limit = current_limits().solve_seconds
    sh = _Shots(pm, FastCall(pm.march), period, p, su, z, nz, pm.march.size1_out(0),
                pm.method.tol, time.perf_counter() + remaining_seconds())
    # phase 1: Anderson acceleration of the plain march (cheap periods, no Jacobian)
    res, u, X, r, history, periods = _anderson(sh, u, z, tol, anderson_budget(nu),
                                               anderson_depth(nu))
    anderson_periods = periods
    # phase 2: Newton with the exact monodromy, where Anderson did not get there
    u, X, res, J, iters, periods, why = _newton_phase(sh, u, X, res, r, tol, max_iter, history,
                                                      periods)
    solved = res <= tol
    if not solved and not why:
        why = (f"{anderson_periods} Anderson periods and {iters} Newton iterations: residual "
               f"{res:.3g} > tol = {tol:.3g}")
    if not solved and (sh.timed_out or sh.late()):
        why = (f"stopped at the time limit of {limit} s, {periods} periods marched "
               f"(residual {res:.3g} > tol = {tol:.3g}): the response may have no period (a "
               "line that snaps, a subharmonic); run simulate to see what it does, or raise "
               "the limit (sc.limits(solve_seconds=...), --max-solve-seconds)")
    elif not solved:
        why += _rate_note(history)
    qs, vs, zs = pm.samples(X)
    m = 4 * N
    tf = period * np.arange(m) / m
    q, v, zf = (trig_interp(a, period, tf) for a in (qs, vs, zs))
    stats = dict(start_info)
    stats.update({"solver": "anderson" + (" + newton (exact monodromy)" if J is not None
                                          else ""),
                  "iterations": anderson_periods + iters, "anderson_periods": anderson_periods,
                  "newton_iterations": iters, "periods": periods, "residual": res,
                  "periodicity_defect": res, "integrator": "generalized-alpha" +
                  (" (first order)" if pm.first_order else ""),
                  "history": history, "steps": N, "rho_inf": pm.method.rho_inf,
                  "newton_tol": pm.method.tol,
                  "tolerance": tol, "unknowns": nu, "wall_time": time.perf_counter() - t0,
                  "compiled": pm.compiled,
                  "state0": np.concatenate([X[:nu, -1], sh.z_of(X)])})
    if J is not None:
        mult = np.linalg.eigvals(J)
        stats["floquet_max"] = float(np.max(np.abs(mult))) if mult.size else 0.0
    return check_and_wrap(mech, period, p, q, v, zf, method="shooting", solved=solved, tol=tol,
                          defect_tol=defect_tol, stats=stats, why=why,
                          codegen=codegen)


@dataclasses.dataclass
class _Shots:
    """The period map evaluated at one period (s) and parameters ``p`` (n_p,): ``march`` its
    plain march (NumPy in and out), ``su`` (n_u,) the scales of the shooting unknowns u,
    ``z0`` the start's constraint forces (kept where the marched state carries none),
    ``n_x`` the integrator's state size, ``step_tol`` a step's largest accepted residual."""

    pm: PeriodMap
    march: FastCall
    period: float
    p: np.ndarray
    su: np.ndarray
    z0: np.ndarray
    nz: int
    n_x: int
    step_tol: float
    deadline: float = math.inf  #: time.perf_counter() past which no more periods are marched
    #: wall time (s) of the last plain period and of the last period with its monodromy
    t_plain: float = 0.0
    t_jac: float = 0.0
    #: set once :meth:`late` has said so (the solve stopped for the time limit)
    timed_out: bool = False

    def late(self, monodromy: bool = False) -> bool:
        """Whether the deadline has passed, or (``monodromy``) would pass during a period
        with its monodromy: as long as the last one, or MONODROMY_PERIODS plain periods
        before the first (one such call can take tens of seconds on a large system)."""
        cost = (self.t_jac or MONODROMY_PERIODS * self.t_plain) if monodromy else 0.0
        if time.perf_counter() + cost > self.deadline:
            self.timed_out = True
        return self.timed_out

    def evaluate(self, u_, z_, jac):
        """(X (n_x, N+1) the states over the period, residual max |r|, r (n_u,) the scaled
        periodicity defect, J (n_u, n_u) the monodromy with ``jac``, else None); residual inf
        and r None where a step failed."""
        t0 = time.perf_counter()
        try:
            return self._evaluate(u_, z_, jac)
        finally:
            if jac:
                self.t_jac = time.perf_counter() - t0
            else:
                self.t_plain = time.perf_counter() - t0

    def _evaluate(self, u_, z_, jac):
        pm, nu = self.pm, self.pm.n_u
        if jac:
            out = pm.with_jacobian(np.concatenate([u_, z_]), self.period, self.p)
            X, E = np.asarray(out[0]), np.asarray(out[1]).ravel()
        else:
            out = self.march(np.concatenate([u_, z_]), float(self.period), self.p)
            X, E = out[0].reshape(-1, self.n_x).T.copy(), out[1].copy()
        if not (np.all(E <= self.step_tol) and np.all(np.isfinite(X))):
            return X, np.inf, None, None
        r = (X[:nu, -1] - u_) / self.su
        J = np.asarray(out[2]) if jac else None
        return X, float(np.max(np.abs(r))), r, J

    def z_of(self, X):
        """The constraint forces to start the next period from: the last state's, where the
        marched state carries them, else the start's."""
        return X[self.pm.n_u:, -1] if (self.nz and not self.pm.first_order) else self.z0


def _anderson(sh: _Shots, u, z, tol: float, budget: int, depth: int):
    """Phase 1: Anderson acceleration of the plain march from u (n_u,), up to ``budget``
    periods with memory ``depth``: (the best iterate's residual, u and X; the last r; the
    residual history; the periods marched)."""
    nu, su = sh.pm.n_u, sh.su
    X, res, r, _ = sh.evaluate(u, z, False)
    history = [res]
    periods, best = 1, (res, u, X)
    Fs, Gs = [], []
    while res > tol and r is not None and periods < budget:
        g = X[:nu, -1] / su
        f = r
        Fs, Gs = (Fs + [f])[-depth - 1:], (Gs + [g])[-depth - 1:]
        u_next = g
        if len(Fs) > 1:
            dF = np.diff(np.array(Fs), axis=0).T
            dG = np.diff(np.array(Gs), axis=0).T
            gam = np.linalg.lstsq(dF, f, rcond=None)[0]
            u_next = g - dG @ gam
        z = sh.z_of(X)
        X_t, res_t, r_t, _ = sh.evaluate(u_next * su, z, False)
        periods += 1
        if r_t is None or res_t > 10 * best[0]:
            # a bad accelerated iterate: restart the memory from the plain march of the best
            Fs, Gs = [], []
            X_t, res_t, r_t, _ = sh.evaluate(best[2][:nu, -1], z, False)
            periods += 1
            if r_t is None:
                break
            u_next = best[2][:nu, -1] / su
        u, X, res, r = u_next * su, X_t, res_t, r_t
        history.append(res)
        if res < best[0]:
            best = (res, u, X)
        if not sh.pm.compiled and stalled(history):
            break  # (a plain period in generated C costs ~1/2000 of a monodromy: go on)
        if sh.late():
            break
    res, u, X = best
    return res, u, X, r, history, periods


def _newton_phase(sh: _Shots, u, X, res: float, r, tol: float, max_iter: int, history: list,
                  periods: int):
    """Phase 2: Newton with the exact monodromy from u (n_u,), where Anderson did not get
    there, each step halved until it reduces the residual; appends to ``history``: (u, X,
    residual, the last monodromy J or None, Newton iterations, periods marched, why it
    stopped short or "")."""
    nu, su = sh.pm.n_u, sh.su
    iters, J, why = 0, None, ""
    if res > tol and np.isfinite(res) and not sh.late(monodromy=True):
        z = sh.z_of(X)
        X, res, r, J = sh.evaluate(u, z, True)
        periods += 1
    while res > tol and iters < max_iter and not sh.late():
        if r is None:
            why = "a generalized-alpha step failed inside the period"
            break
        if J is None:  # not evaluated: the time limit would have passed during it
            break
        Jr = (J - np.eye(nu)) * su[None, :] / su[:, None]
        try:
            du = -np.linalg.solve(Jr, r) * su
        except np.linalg.LinAlgError:
            why = "singular I - monodromy (a neutral Floquet multiplier)"
            break
        lam, accepted = 1.0, False
        for _ in range(MAX_HALVINGS + 1):
            u_try = u + lam * du
            X_t, res_t, r_t, _ = sh.evaluate(u_try, sh.z_of(X), False)
            periods += 1
            if res_t < res:
                accepted = True
                break
            lam /= 2
        iters += 1
        if not accepted:
            why = f"Newton step not reducing the residual {res:.3g}"
            break
        u, X, res, r = u_try, X_t, res_t, r_t
        z = sh.z_of(X)
        history.append(res)
        if res > tol and sh.late(monodromy=True):
            break  # the time limit would pass during the next monodromy
        if res > tol:  # the monodromy at the new iterate for the next step
            _, _, _, J = sh.evaluate(u, z, True)
            periods += 1
    return u, X, res, J, iters, periods, why
