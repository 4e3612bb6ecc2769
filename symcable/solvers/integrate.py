"""Time integration of any Mechanism: generalized-alpha (implicit, constraints allowed) and
RK4 (explicit, no constraints). Each step is a CasADi Function; batches of steps run inside
CasADi (``mapaccum``), never as a Python loop over steps.

Generalized-alpha in the form of Arnold & Bruels (2007), for M(q) a = f(q, v, z, t),
g(q, v, z, t) = 0, with a pseudo-acceleration abar:

    (1 - alpha_m) abar1 + alpha_m abar0 = (1 - alpha_f) a1 + alpha_f a0
    q1 = q0 + h v0 + h^2 (1/2 - beta) abar0 + h^2 beta abar1
    v1 = v0 + h (1 - gamma) abar0 + h gamma abar1

and the equations of motion and the constraints imposed at t1, unknowns (a1, z1), solved
by Newton on the exact Jacobian. Position-level constraints are met to the Newton
tolerance at every step (no drift). Second order for positions and velocities. It needs
q' = v (no ``kinematics``).

First-order generalized-alpha (Jansen, Whiting & Hulbert 2000) on the DAE residual
F(y', y, t; p) = 0 with y = (q, v), for any kinematics (:func:`galpha1_step`):

    y1 = y0 + h y'0 + gamma h (y'1 - y'0)
    F(y'0 + alpha_m (y'1 - y'0), y0 + alpha_f (y1 - y0), t0 + alpha_f h; p) = 0

unknown y'1, by Newton; the scheme ``simulate`` runs on a DynamicModel. Mechanisms with
constraints (n_z > 0) are refused for now.
"""
from __future__ import annotations

import time

import casadi as ca
import numpy as np

from ..derive import functions
from ..errors import ConvergenceError, SymcableError
from ..models.mechanism import Mechanism
from ..results_mechanism import Equilibrium, MechanismTrajectory
from .options import RK4, GeneralizedAlpha, GeneralizedAlphaFirstOrder

__all__ = ["integrate", "galpha_step", "galpha1_step", "rk4_step"]

_IMPLICIT = (GeneralizedAlpha, GeneralizedAlphaFirstOrder)

#: steps per mapaccum call (bounds the compiled/generated graph)
BATCH = 256


def _seg(x, i: int, j: int):
    """x[i:j] as a column (CasADi gives a 1x0 row for an empty slice of a 1x1 vector)."""
    return x[i:j] if j > i else ca.MX(0, 1)


def galpha_step(mech: Mechanism, opts: GeneralizedAlpha) -> ca.Function:
    """``step(x, t, h, p) -> (x1, err, lte)`` with x = (q, v, a, abar, z): one
    generalized-alpha step of size h (s) from t (s); err is the max-norm of the residual at
    the returned state, force rows over ``scales.force`` and constraint rows over
    ``scales.g_scale()`` (the solve failed when it exceeds ``opts.tol``); lte the estimated
    local error of the positions over ``scales.q`` (max-norm)."""
    F = functions(mech)
    am, af, gamma, beta = opts.coefficients
    nq, nv, nz = mech.n_q, mech.n_v, mech.n_z
    if mech.kinematics is not None:
        raise SymcableError(f"mechanism {mech.name!r}: GeneralizedAlpha needs q' = v; its "
                            "kinematics q' = G(q) v (+ w) runs with GeneralizedAlphaFirstOrder()")
    fs, ms = mech.scales.force, mech.scales.mass
    x0 = ca.MX.sym("x", nq + 3 * nv + nz)
    q0, v0 = _seg(x0, 0, nq), _seg(x0, nq, nq + nv)
    a0, ab0 = _seg(x0, nq + nv, nq + 2 * nv), _seg(x0, nq + 2 * nv, nq + 3 * nv)
    t, h, p = ca.MX.sym("t"), ca.MX.sym("h"), ca.MX.sym("p", mech.params.n)
    w = ca.MX.sym("w", nv + nz)

    def state(w_):
        a1, z1 = _seg(w_, 0, nv), _seg(w_, nv, nv + nz)
        ab1 = ((1 - af) * a1 + af * a0 - am * ab0) / (1 - am)
        q1 = q0 + h * v0 + h ** 2 * ((0.5 - beta) * ab0 + beta * ab1)
        v1 = v0 + h * ((1 - gamma) * ab0 + gamma * ab1)
        return q1, v1, a1, ab1, z1

    def residual(w_):
        q1, v1, a1, _, z1 = state(w_)
        r_f, r_g = F.acc_residual(q1, v1, a1, z1, t + h, p)
        return ca.vertcat(r_f / fs, r_g * (ms / (beta * h ** 2 * fs)))

    G = ca.Function("ga_res", [w, x0, t, h, p], [residual(w)])
    rf = ca.rootfinder(f"{mech.name}_ga_newton", "newton", G,
                       {"abstol": opts.tol, "abstolStep": 1e-14, "max_iter": opts.max_iter,
                        "error_on_fail": False})
    w_guess = ca.vertcat(a0, _seg(x0, nq + 3 * nv, nq + 3 * nv + nz))
    w1 = rf(w_guess, x0, t, h, p)
    q1, v1, a1, ab1, z1 = state(w1)
    # convergence is judged in the rows' own units (forces over the force scale, constraint
    # rows over their scale), not in the conditioned scaling Newton uses, whose constraint rows
    # carry a 1/h^2 that lifts their round-off floor above any fixed tolerance at small h
    q1c, v1c, a1c, _, z1c = state(w1)
    r_f1, r_g1 = F.acc_residual(q1c, v1c, a1c, z1c, t + h, p)
    err = ca.norm_inf(ca.vertcat(r_f1 / fs, r_g1 / ca.DM(mech.scales.g_scale())))
    # local error of the positions, Newmark's estimate (beta - 1/6) h^2 (a1 - a0) (the h^3
    # jerk term the update leaves out), relative to the coordinate scales
    lte = ca.norm_inf(abs(beta - 1.0 / 6.0) * h ** 2 * (a1 - a0) / ca.DM(mech.scales.q))
    return ca.Function(f"{mech.name}_ga_step", [x0, t, h, p],
                       [ca.vertcat(q1, v1, a1, ab1, z1), err, lte], ["x", "t", "h", "p"],
                       ["x1", "err", "lte"])


def _taylor_jet(mech: Mechanism) -> ca.Function:
    """``jet(q, v, a, z, t, p) -> (q'', b)`` along the motion q' = kinematics, v' = a (z
    held): q'' = d(kinematics)/dt and b = df/dt - (dM/dt) a, so that v'' = M^-1 b."""
    m = mech
    a = ca.SX.sym("a", m.n_v) if isinstance(m.v, ca.SX) else ca.MX.sym("a", m.n_v)
    kin = m.v if m.kinematics is None else m.kinematics

    def ddt(expr):
        return (ca.jtimes(expr, m.q, kin) + ca.jtimes(expr, m.v, a) + ca.jacobian(expr, m.t))

    b = ddt(m.force) - ca.jtimes(ca.mtimes(m.mass, a), m.q, kin)
    return ca.Function(f"{m.name}_jet", [m.q, m.v, a, m.z, m.t, m.p], [ddt(kin), b])


def galpha1_step(mech: Mechanism, opts: GeneralizedAlphaFirstOrder, *,
                 exact_derivatives: bool = False) -> ca.Function:
    """``step(x, t, h, p) -> (x1, err, lte)`` with x = (y, y'), y = (q, v): one first-order
    generalized-alpha step (see the module docstring) of size h (s) from t (s).

    ``exact_derivatives=True`` asks for the step solved by CasADi's Newton rootfinder,
    whose derivative with respect to (x, t, h, p) is the exact one of the converged step (the
    implicit function theorem): shooting's Newton iteration differentiates the period map
    through it (its monodromy). The default may be a faster step whose derivative need not
    be that (today both are the rootfinder).

    ``err`` is the max-norm of the step residual scaled to a change of y over the step
    relative to its scales (kinematic rows h |r| / scales.q, momentum rows
    h |r| / (scales.mass scales.v)): the Newton iteration stops at ``opts.tol``, and the step
    failed above it.

    ``lte`` estimates the local error of y over its scales (max-norm) by the difference from
    the second-order Taylor predictor y0 + h y'(t0) + h^2/2 y''(t0), whose local error is
    h^3/6 y^(3) (y', y'' exact, from the equations, not the carried y'): on the principal
    root of y' = A y the step's error is C h^3 y^(3) (C = ``opts.error_constant``, 1/9 at
    rho_inf = 1/2), so the error is C / (C + 1/6) times that difference. Where the solution
    is driven by an explicit forcing rather than by its own dynamics (pure quadrature
    y' = g(t)) the step's h^3 error vanishes and the estimate overstates it.
    """
    if mech.n_z:
        raise SymcableError(f"mechanism {mech.name!r} has {mech.n_z} constraints: "
                            "GeneralizedAlphaFirstOrder takes n_z = 0 only for now; use "
                            "GeneralizedAlpha()")
    F = functions(mech)
    am, af, gamma = opts.coefficients
    nq, nv = mech.n_q, mech.n_v
    ny = nq + nv
    x0 = ca.MX.sym("x", 2 * ny)
    y0, yd0 = x0[:ny], x0[ny:]
    t, h, p = ca.MX.sym("t"), ca.MX.sym("h"), ca.MX.sym("p", mech.params.n)
    w = ca.MX.sym("w", ny)
    z0 = ca.MX(0, 1)
    row_scale = np.concatenate([1.0 / np.asarray(mech.scales.q, float),
                                1.0 / (mech.scales.mass * np.asarray(mech.scales.v, float))])
    y_scale = np.concatenate([mech.scales.q, mech.scales.v])

    def y_next(w_):
        return y0 + h * yd0 + gamma * h * (w_ - yd0)

    def residual(w_):
        r = F.dae_residual(yd0 + am * (w_ - yd0), y0 + af * (y_next(w_) - y0), t + af * h, p)
        return h * r * ca.DM(row_scale)

    G = ca.Function("ga1_res", [w, x0, t, h, p], [residual(w)])
    rf = ca.rootfinder(f"{mech.name}_ga1_newton", "newton", G,
                       {"abstol": opts.tol, "abstolStep": 1e-14, "max_iter": opts.max_iter,
                        "error_on_fail": False})
    w1 = rf(yd0, x0, t, h, p)
    y1 = y_next(w1)
    err = ca.norm_inf(residual(w1))
    # the Taylor predictor from the exact derivatives at (y0, t)
    q0, v0 = _seg(y0, 0, nq), _seg(y0, nq, ny)
    tan = F.tangents
    M0 = tan(q0, v0, z0, t, p)[2]
    r_f, _ = F.acc_residual(q0, v0, ca.MX.zeros(nv), z0, t, p)  # = -f
    a0 = ca.solve(M0, -r_f) if nv else ca.MX(0, 1)
    qd0 = F.qdot(q0, v0, z0, t, p)
    qdd0, b0 = _taylor_jet(mech)(q0, v0, a0, z0, t, p)
    ad0 = ca.solve(M0, b0) if nv else ca.MX(0, 1)
    y_pred = y0 + h * ca.vertcat(qd0, a0) + 0.5 * h ** 2 * ca.vertcat(qdd0, ad0)
    C = opts.error_constant
    lte = ca.norm_inf(C / (C + 1.0 / 6.0) * (y1 - y_pred) / ca.DM(y_scale))
    return ca.Function(f"{mech.name}_ga1_step", [x0, t, h, p], [ca.vertcat(y1, w1), err, lte],
                       ["x", "t", "h", "p"], ["x1", "err", "lte"])


def rk4_step(mech: Mechanism) -> ca.Function:
    """``step(x, t, h, p) -> (x1, err, lte)`` with x = (q, v): one RK4 step (err = 0, and
    lte = NaN: no embedded estimate)."""
    if mech.n_z:
        raise SymcableError(f"method = 'rk4': mechanism {mech.name!r} has {mech.n_z} "
                            "constraints; use generalized-alpha")
    F = functions(mech)
    nq, nv = mech.n_q, mech.n_v
    x0 = ca.MX.sym("x", nq + nv)
    t, h, p = ca.MX.sym("t"), ca.MX.sym("h"), ca.MX.sym("p", mech.params.n)
    tan = F.tangents  # M from here: M(q)
    z0 = ca.MX.zeros(0)

    def rhs(x, tt):
        q, v = _seg(x, 0, nq), _seg(x, nq, nq + nv)
        M = tan(q, v, z0, tt, p)[2]
        r_f, _ = F.acc_residual(q, v, ca.MX.zeros(nv), z0, tt, p)  # = -f
        return ca.vertcat(F.qdot(q, v, z0, tt, p), ca.solve(M, -r_f))

    k1 = rhs(x0, t)
    k2 = rhs(x0 + h / 2 * k1, t + h / 2)
    k3 = rhs(x0 + h / 2 * k2, t + h / 2)
    k4 = rhs(x0 + h * k3, t + h)
    x1 = x0 + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
    return ca.Function(f"{mech.name}_rk4_step", [x0, t, h, p], [x1, ca.MX(0), ca.MX(np.nan)],
                       ["x", "t", "h", "p"], ["x1", "err", "lte"])


class _Stepper:
    """A step Function and its mapaccum batches (built once per batch length)."""

    def __init__(self, step: ca.Function):
        self.step = step
        self._batches: dict = {}

    def batch(self, k: int) -> ca.Function:
        fn = self._batches.get(k)
        if fn is None:
            x, t0, h, p = (ca.MX.sym(n, *s) for n, s in (
                ("x", self.step.size_in(0)), ("t0", (1, 1)), ("h", (1, 1)),
                ("p", self.step.size_in(3))))
            acc = self.step.mapaccum("acc", k, [0], [0])
            # the time of each step: t0 + i h
            ts = t0 + h * ca.DM(np.arange(k)).T
            X, E, LTE = acc(x, ts, h, p)
            fn = ca.Function(f"batch{k}", [x, t0, h, p], [X, E, LTE])
            self._batches[k] = fn
        return fn


def _initial_state(mech, F, method, q0, v0, z_guess, t0, p):
    if isinstance(method, GeneralizedAlphaFirstOrder):
        step = galpha1_step(mech, method)  # refuses n_z > 0 first
        a0 = np.linalg.solve(np.atleast_2d(np.asarray(F.tangents(q0, v0, z_guess, t0, p)[2])),
                             -np.asarray(F.acc_residual(q0, v0, np.zeros(mech.n_v), z_guess,
                                                        t0, p)[0]).ravel()) \
            if mech.n_v else np.zeros(0)
        qd0 = np.asarray(F.qdot(q0, v0, z_guess, t0, p)).ravel()
        return step, np.concatenate([q0, v0, qd0, a0]), np.zeros(0)
    a0, z0 = (np.asarray(x).ravel() for x in F.consistent_acceleration(q0, v0, z_guess, t0, p))
    if isinstance(method, GeneralizedAlpha):
        if mech.n_z and method.rho_inf >= 1.0:
            # without numerical damping the multipliers of position constraints (index 3)
            # are not damped and grow: on the toy pendulum z reached 1e6 times its value in
            # 1900 steps at T/800
            raise SymcableError(f"rho_inf = {method.rho_inf}: a mechanism with constraints "
                                "needs rho_inf < 1 (e.g. 0.9) for its constraint forces to stay "
                                "bounded")
        return galpha_step(mech, method), np.concatenate([q0, v0, a0, a0, z0]), z0
    return rk4_step(mech), np.concatenate([q0, v0]), z0


def integrate(mech: Mechanism, duration: float, dt: float | None = None, *, method=None,
              t0: float = 0.0, p=None, save_every: int = 1, start: Equilibrium | None = None,
              q0=None, v0=None, tol: float | None = None,
              batch: int = BATCH) -> MechanismTrajectory:
    """March ``mech`` over ``duration`` s, with fixed steps ``dt`` s or, given ``tol``,
    steps adapted to keep the local error of the positions below ``tol`` times their scales.

    Parameters
    ----------
    mech : Mechanism
    duration : float, s
    dt : float, s
        The step (fixed), or the first step with ``tol`` (default duration/100 there).
    method : GeneralizedAlpha | GeneralizedAlphaFirstOrder | RK4, default GeneralizedAlpha()
    q0, v0 : initial coordinates and velocities (default: ``start``'s q, or the mechanism's
        first static start, at rest)
    start : Equilibrium, optional  where to start (its q and z)
    p : parameters (default the mechanism's own, i.e. with motion)
    save_every : int
        Keep every k-th step (fixed steps); every accepted step is kept with ``tol``.
    tol : float, optional
        Local error per step, relative to ``mech.scales.q`` (generalized-alpha only: its
        estimate is Newmark's (beta - 1/6) h^2 |a1 - a0|; first-order generalized-alpha's is
        on q and v over their scales, see :func:`galpha1_step`). Steps run in batches of ``batch``
        at one size inside CasADi; a batch whose largest estimate exceeds ``tol`` is redone
        with a smaller step, and the next batch's step follows the estimate (order 3).
        ``stats`` reports the steps taken, rejected batches and the smallest and largest step.

    Raises
    ------
    ConvergenceError
        A step's Newton iteration did not converge; ``partial`` holds the run up to there.
    """
    method = GeneralizedAlpha() if method is None else method
    if not isinstance(method, (*_IMPLICIT, RK4)):
        raise SymcableError(f"method = {method!r}: must be GeneralizedAlpha(...), "
                            "GeneralizedAlphaFirstOrder(...) or RK4()")
    if tol is not None:
        if not isinstance(method, _IMPLICIT):
            raise SymcableError("tol: adaptive steps need generalized-alpha (RK4 here has no "
                                "error estimate); give dt instead")
        if not tol > 0:
            raise SymcableError(f"tol = {tol!r}: must be > 0")
        dt = duration / 100 if dt is None else dt
    if dt is None or not (duration > 0 and dt > 0):
        raise SymcableError(f"duration = {duration!r} s, dt = {dt!r} s: both must be > 0")
    t_start = time.perf_counter()
    F = functions(mech)
    p = mech.params.values if p is None else np.asarray(p, float).ravel()
    if q0 is None:
        q0 = start.q if start is not None else next(iter(mech.starts())).q
    q0 = np.asarray(q0, float).ravel()
    v0 = np.zeros(mech.n_v) if v0 is None else np.asarray(v0, float).ravel()
    z_guess = start.z if start is not None else np.zeros(mech.n_z)
    step, x, z0 = _initial_state(mech, F, method, q0, v0, z_guess, t0, p)
    stepper = _Stepper(step)
    if tol is None:
        n_steps = int(round(duration / dt))
        if abs(n_steps * dt - duration) > 1e-9 * duration:
            raise SymcableError(f"duration = {duration} s is not a whole number of steps dt = {dt} s")
        run = _run_fixed(stepper, x, t0, dt, n_steps, p, method, save_every, batch)
    else:
        run = _run_adaptive(stepper, x, t0, dt, duration, p, method, tol, batch)
    T, Xs, status, warnings, extra = run
    nq, nv = mech.n_q, mech.n_v
    q, v = Xs[:, :nq], Xs[:, nq:nq + nv]
    z = Xs[:, -mech.n_z:].copy() if (mech.n_z and isinstance(method, GeneralizedAlpha)) \
        else np.zeros((T.size, mech.n_z))
    z[0] = z0
    outs = F.outputs.map(T.size)(q.T, v.T, z.T, T[None, :], p)
    outputs = F.unpack(np.asarray(outs))
    g = np.asarray(F.acc_residual.map(T.size)(q.T, v.T, np.zeros((nv, T.size)), z.T,
                                               T[None, :], p)[1])
    name = {GeneralizedAlpha: "generalized-alpha",
            GeneralizedAlphaFirstOrder: "generalized-alpha-first-order"}.get(type(method), "rk4")
    stats = {"method": name,
             **extra, "max_constraint": float(np.max(np.abs(g))) if g.size else 0.0,
             "wall_time": time.perf_counter() - t_start}
    if isinstance(method, _IMPLICIT):
        stats["rho_inf"] = method.rho_inf
    traj = MechanismTrajectory(mech.name, T, q, v, z, outputs, status, stats, tuple(warnings))
    if status == "failed":
        raise ConvergenceError(f"simulation of {mech.name!r} failed: {warnings[-1]}",
                               partial=traj, diagnostics=stats)
    return traj


def _first_bad(E, tol):
    bad = np.flatnonzero(~(E <= tol))
    return None if bad.size == 0 else int(bad[0])


def _run_fixed(stepper, x, t, dt, n_steps, p, method, save_every, batch):
    tol_newton = method.tol if isinstance(method, _IMPLICIT) else np.inf
    times, Xs = [t], [x.copy()]
    worst, lte_max, done = 0.0, 0.0, 0
    status, warnings = "converged", []
    while done < n_steps:
        k = min(batch, n_steps - done)
        X, E, LTE = (np.asarray(a) for a in stepper.batch(k)(x, t, dt, p))
        E, LTE = E.ravel(), LTE.ravel()
        if not isinstance(method, _IMPLICIT):
            E = np.where(np.all(np.isfinite(X), axis=0), 0.0, np.inf)
        bad = _first_bad(E, tol_newton)
        good = k if bad is None else bad
        for i in range(good):
            if (done + i + 1) % save_every == 0 or done + i + 1 == n_steps:
                times.append(t + (i + 1) * dt)
                Xs.append(X[:, i])
        if good:
            worst = max(worst, float(np.max(E[:good])))
            lte_max = max(lte_max, float(np.max(LTE[:good])))
        if bad is not None:
            status = "failed"
            warnings.append(f"step {done + good + 1} at t = {t + good * dt:.6g} s: Newton "
                            f"did not converge (scaled residual {E[good]:.3g} > {tol_newton:.3g})")
            done += good
            break
        x = X[:, -1]
        t += k * dt
        done += k
    extra = {"dt": dt, "steps": done, "max_step_residual": worst,
             "max_error_estimate": lte_max if isinstance(method, _IMPLICIT) else None}
    return np.array(times), np.array(Xs), status, warnings, extra


#: adaptive steps: safety factor, largest growth and cut per batch
SAFETY, GROW, CUT = 0.8, 2.0, 0.2


def _run_adaptive(stepper, x, t0, h, duration, p, method, tol, batch):
    t_end = t0 + duration
    times, Xs = [t0], [x.copy()]
    t, steps, rejected = t0, 0, 0
    h_min, h_max, worst_lte = np.inf, 0.0, 0.0
    k_batch = max(1, min(batch, 32))
    status, warnings = "converged", []
    while t < t_end - 1e-12 * duration:
        remaining = t_end - t
        k = k_batch
        if k * h >= remaining:
            k = max(1, int(np.ceil(remaining / h - 1e-9)))
            h = remaining / k
        X, E, LTE = (np.asarray(a) for a in stepper.batch(k)(x, t, h, p))
        E, LTE = E.ravel(), LTE.ravel()
        est = float(np.max(LTE)) if np.all(np.isfinite(LTE)) else np.inf
        newton_ok = _first_bad(E, method.tol) is None
        if not newton_ok or est > tol:
            rejected += 1
            factor = CUT if not (newton_ok and np.isfinite(est)) else \
                max(CUT, SAFETY * (tol / est) ** (1.0 / 3.0))
            h *= factor
            if h < 1e-12 * duration:
                status = "failed"
                warnings.append(f"t = {t:.6g} s: the step fell below {1e-12 * duration:.3g} s "
                                f"(error estimate {est:.3g}, Newton {'ok' if newton_ok else 'failed'})")
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
             "dt_max": h_max, "max_error_estimate": worst_lte, "tol": tol}
    return np.array(times), np.array(Xs), status, warnings, extra
