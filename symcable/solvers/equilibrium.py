"""Static equilibrium of any Mechanism: Newton on R(q, z; p) = (f(q, 0, z, 0), g) with its
exact sparse Jacobian. From each start, in order of cost: plain Newton fused into one call
(:mod:`symcable.mechanism.static_functions`, generated C where it pays), then Newton with a backtracking
line search; then, from the starts tried, continuation from a start's own parameters to the
target, continuation in a named parameter block, and pseudo-transient continuation. Every
answer is checked afterwards, in floating point and independently of how it was found: the
residual of the equations, finiteness, the mechanism's admissibility bounds
(:class:`~symcable.mechanism.mechanism.Bound`: segments of positive length, no compression in a
cable, ...), and the stability of the equilibrium (the tangent stiffness reduced to the
constraints' null space). A failed check is never called converged: the next attempt runs.
"""
from __future__ import annotations

import math
import time
from types import SimpleNamespace

import numpy as np

from ..mechanism.bounds import bound_numbers
from ..mechanism.functions import bound_violations, functions
from ..mechanism.static_functions import SOLVE_MAX_ITER
from ..errors import ConvergenceError, SymcableError
from ..mechanism.mechanism import Mechanism
from ..results.generic import Equilibrium
from ..linalg.eigen import lowest_eigenpair
from .newton import NewtonResult, newton

__all__ = ["constraint_null_space", "solve_equilibrium"]

#: largest system whose stability is checked (the lowest eigenvalue of the tangent: banded
#: lines in n b^2, others by a dense solve, n^3; symcable.linalg.eigen)
STABILITY_MAX_N = 3000


def _fused(S, x0, p, tol, max_iter):
    """Plain Newton (at most SOLVE_MAX_ITER steps) in one call of the fused solve: the result
    and the packed outputs at its last iterate (None when the call failed)."""
    try:
        x, its, nr, packed = S.fast("solve")(x0, p, tol)
    except RuntimeError as exc:  # the VM's QR refuses a singular Jacobian
        return NewtonResult(np.array(x0, dtype=float), False, 0, float("nan"),
                            f"plain Newton failed ({exc})"), None
    its, nr = int(its[0]), float(nr[0])
    if nr <= tol and its <= min(max_iter, SOLVE_MAX_ITER):
        # claimed: the check that follows tests it (a max-norm of NaNs can come out as 0)
        return NewtonResult(x, True, its, nr, "converged"), packed
    if not np.isfinite(x).all():
        return NewtonResult(x, False, its, float("nan"),
                            f"plain Newton failed (iterate not finite after {its} steps)"), None
    return NewtonResult(x, False, its, nr,
                        f"plain Newton failed (residual {nr:.3g} N after {its} steps)"), packed


def _continuation(step, x0, p0, p1, opts, polish: bool, dt0: float, dt_max: float,
                  min_step: float = 1e-4):
    """Damped Newton along p(t) = p0 + t (p1 - p0), t from 0 to 1, in adaptive steps (doubled
    after a success up to ``dt_max``, halved after a failure) with a secant predictor. With
    ``polish`` the start is first solved at p0 (it is only close to an equilibrium there).
    Returns (result, accepted steps, Newton iterations)."""
    t, dt, x, prev, iters, steps = 0.0, dt0, np.array(x0, dtype=float), None, 0, 0
    res = None
    if polish:
        res = newton(step, x, p0, **opts)
        iters += res.iterations
        if not res.converged:
            return res, 0, iters
        x = res.x
    while t < 1.0:
        t_new = min(1.0, t + dt)
        pred = x if prev is None else x + (x - prev[1]) * (t_new - t) / (t - prev[0])
        res = newton(step, pred, p0 + t_new * (p1 - p0), **opts)
        iters += res.iterations
        if res.converged:
            prev, x, t = (t, x), res.x, t_new
            steps += 1
            dt = min(2.0 * dt, dt_max)
        else:
            dt *= 0.5
            if dt < min_step:
                res.message = f"continuation stalled at {t:.4g} of the way ({res.message})"
                return res, steps, iters
    return res, steps, iters


#: pseudo-transient continuation: most steps, the first pseudo-time step, when it counts as
#: Newton (the regularisation then is 1e-10 of the stiffness scale)
PTC_MAX_STEPS, PTC_DT0, PTC_DT_NEWTON = 400, 1e-2, 1e10


def _ptc(F, mech, x0, p, tol, max_steps: int = PTC_MAX_STEPS, dtau0: float = PTC_DT0,
         charts=None):
    """Pseudo-transient continuation (Kelley & Keyes 1998): steps (D/dtau - J) dx = R(x) of
    a damped relaxation in pseudo-time, D = force scale / coordinate scale per unknown. For a
    conservative system (R = -grad E, J = -Hessian) a short step goes down the energy, so it
    relaxes toward a stable equilibrium where Newton from a far start stalls or lands on a
    saddle; the robust form of the dynamic relaxation MoorDyn uses. The pseudo-time step
    doubles after every accepted step (so the end is Newton's quadratic convergence) and is
    cut by 4 when the residual jumps: not switched evolution relaxation, whose step shrinks
    while the residual grows, as it does for a while along a buckling path (SER stalls on
    compressed chains under gravity at vanishing steps). At most ``max_steps``
    steps from the pseudo-time step ``dtau0``. ``charts`` (optional, a Mechanism with
    anchored frames): ``charts.ok(x, p)`` False rejects a step (it turned some edge too near
    the half turn from its anchor, where the frame is singular), ``charts.renew(q, p) ->
    (p, renewed, q)`` re-anchors after each accepted step (q: the same state in the new
    chart); the result's ``p`` is the last parameters."""
    D = mech.scales.force / np.concatenate([mech.scales.q, np.ones(mech.n_z)])
    if mech.n_z:
        D[mech.n_q:] = 0.0  # constraint rows are not relaxed: they hold at every step
    x = np.array(x0, dtype=float)
    dtau = dtau0
    r = np.asarray(F.static_residual(x, p)).ravel()
    nr = float(np.max(np.abs(r))) if r.size else 0.0
    for it in range(1, max_steps + 1):
        if nr <= tol:
            return SimpleNamespace(x=x, converged=True, iterations=it - 1, residual_norm=nr,
                                   message="converged", dtau=dtau, p=p)
        try:
            _, dx = (np.asarray(a).ravel() for a in F.static_ptc_step(x, p, D / dtau))
        except RuntimeError:  # a singular matrix (the VM's QR refuses it): a smaller step
            dx = np.full(x.shape, np.nan)  # has a larger diagonal; rejected below
        x_new = x + dx
        r_new = np.asarray(F.static_residual(x_new, p)).ravel() if np.all(np.isfinite(dx)) \
            else np.full(r.shape, np.inf)
        nr_new = float(np.max(np.abs(r_new))) if r_new.size else 0.0
        if not np.isfinite(nr_new) or nr_new > 100.0 * nr or (
                charts is not None and not charts.ok(x_new[:mech.n_q], p)):
            dtau /= 4.0
            if dtau < 1e-12:
                break
            continue
        x, nr = x_new, nr_new
        dtau = min(2.0 * dtau, PTC_DT_NEWTON)
        if charts is not None:
            p, _, q = charts.renew(x[:mech.n_q], p)
            x = np.concatenate([q, x[mech.n_q:]])
    return SimpleNamespace(x=x, converged=nr <= tol, iterations=max_steps, residual_norm=nr,
                           message="converged" if nr <= tol else
                           f"pseudo-transient continuation: residual {nr:.3g} after "
                           f"{max_steps} steps", dtau=dtau, p=p)


def constraint_null_space(B: np.ndarray, n: int) -> np.ndarray:
    """(n, k) orthonormal basis of the coordinates that keep the constraints, the null space
    of the constraint Jacobian B (n_z, n); the identity without constraints."""
    if B.size == 0 or B.shape[0] == 0:
        return np.eye(n)
    _, sv, vt = np.linalg.svd(B)
    return vt[int(np.sum(sv > sv.max() * 1e-10)):].T


def _unstable_direction(F, mech, q, z, p):
    """(lowest eigenvalue, its direction in q) of the reduced tangent stiffness, or
    (None, None) where stability is not judged (too large, a formulation without mass
    whose residual rows are not the gradient of an energy, or where its
    ``stability_when`` is not negative)."""
    if mech.n_q > STABILITY_MAX_N:
        return None, None
    if mech.stability_when is not None and not float(F.stability_when(q, z, p)) < 0.0:
        return None, None
    if F.massless or mech.rest is not None:  # first-order states: eliminated as internal
        return _schur_direction(F, mech, q, z, p)
    K, _, _, B, *_ = F.tangents(q, np.zeros(mech.n_v), z, 0.0, p)
    K, B = np.asarray(K), np.asarray(B)
    if B.size == 0 and K.size:  # no constraints: K itself (no n^3 products with I)
        return lowest_eigenpair(0.5 * (K + K.T))
    N = constraint_null_space(B, mech.n_q)
    Kr = N.T @ (0.5 * (K + K.T)) @ N
    if Kr.size == 0:
        return float("inf"), np.zeros(mech.n_q)
    lam, vec = lowest_eigenpair(Kr)  # banded where the line orders its unknowns
    return lam, N @ vec


def _schur_direction(F, mech, q, z, p):
    """Stability of a massless mechanism from its ``stability_coordinates`` c: the tangent
    K = -df/dq eliminated onto c by its Schur complement, K_cc - K_ci K_ii^-1 K_ic (the
    internal unknowns i follow c through their own rows); its symmetric part's lowest
    eigenvalue, and the direction in q (the internal unknowns following)."""
    c = mech.stability_coordinates
    if c is None or mech.n_z:
        return None, None
    c = np.asarray(c, dtype=int)
    i = np.setdiff1d(np.arange(mech.n_q), c)
    K = -np.asarray(F.static_jacobian(q, p)[1])
    Kcc, Kci, Kic, Kii = K[np.ix_(c, c)], K[np.ix_(c, i)], K[np.ix_(i, c)], K[np.ix_(i, i)]
    try:
        X = np.linalg.solve(Kii, Kic) if i.size else np.zeros((0, c.size))
    except np.linalg.LinAlgError:
        return None, None
    S = Kcc - Kci @ X
    if S.size == 0:
        return float("inf"), np.zeros(mech.n_q)
    lam, vec = lowest_eigenpair(0.5 * (S + S.T))
    direction = np.zeros(mech.n_q)
    direction[c] = vec
    direction[i] = -X @ vec
    return lam, direction


def _stability(F, mech, q, z, p):
    lam, _ = _unstable_direction(F, mech, q, z, p)
    if lam is None:
        return None, float("nan")
    if not np.isfinite(lam):
        return True, lam
    if F.massless or mech.rest is not None:
        K = np.asarray(F.static_jacobian(q, p)[1])
    else:
        K = np.asarray(F.tangents(q, np.zeros(mech.n_v), z, 0.0, p)[0])
    scale = max(float(np.max(np.abs(K))), 1e-300)
    return bool(lam > -1e-9 * scale), lam


#: escapes from an unstable equilibrium (a push along its unstable mode, then relaxation)
ESCAPES = 3


def _ptc_stable(F, mech, x0, p, tol):
    """Pseudo-transient continuation, and from an unstable equilibrium a push along its
    most unstable mode (both ways, 10 % of the coordinate scale) and again, up to ESCAPES
    times: a buckled or sagging branch is reached from the straight state it bifurcates from."""
    res = _ptc(F, mech, x0, p, tol)
    for _ in range(ESCAPES):
        if not res.converged:
            return res
        q, z = res.x[:mech.n_q], res.x[mech.n_q:]
        lam, mode = _unstable_direction(F, mech, q, z, p)
        if lam is None or _stability(F, mech, q, z, p)[0] is not False:
            return res
        push = 0.1 * float(np.median(mech.scales.q)) * mode / max(np.max(np.abs(mode)), 1e-300)
        tries = [_ptc(F, mech, np.concatenate([q + sgn * push, z]), p, tol) for sgn in (1.0, -1.0)]
        ok = [t for t in tries if t.converged]
        if not ok:
            return res
        stable = [t for t in ok if _stability(F, mech, t.x[:mech.n_q], t.x[mech.n_q:], p)[0]]
        res = (stable or ok)[0]
    return res


def solve_equilibrium(mech: Mechanism, p=None, *, tol: float | None = None,
                      max_iter: int = 50, starts=None, continuation: str | bool | None = None,
                      require_stable: bool = True, codegen: bool | None = None) -> Equilibrium:
    """The static equilibrium of ``mech``.

    Attempts, until one passes the checks: from each start in turn, plain Newton fused into
    one call (``"newton"``) and Newton with a line search (``"damped newton"``), both at
    ``p`` (between them, for a start that is an equilibrium at its own parameters,
    ``Start.exact``, the continuation from those to ``p``); then from the starts tried, continuation from a start's own parameters when they
    differ from ``p`` (``"continuation in <its homotopy>"``), in the block ``continuation``
    when one is named, and pseudo-transient continuation (``"pseudo-transient
    continuation"``, from starts at ``p``).

    Parameters
    ----------
    mech : Mechanism
    p : ndarray (n_p,), optional
        Parameters; default the mechanism's static parameters.
    tol : float, optional
        N, converged when max |R| <= tol (constraint rows are scaled to forces by
        ``scales.force / q_ref``); default max(1e-9 force scale, 10 x the residual floor).
    max_iter : int
        Newton iterations per attempt (per continuation step); the fused plain Newton takes
        at most min(max_iter, SOLVE_MAX_ITER).
    starts : iterable of Start, optional
        Default ``mech.starts()`` (consumed lazily: a start is built only when the ones
        before it have failed their Newton attempts).
    continuation : str, bool or None
        None or True: the continuations above; a parameter block name (e.g. ``"load"``): also
        continuation from that block at zero to its value in ``p``; False: none, Newton from
        each start only.
    require_stable : bool
        An unstable equilibrium (negative reduced stiffness) is a failed attempt; with False
        it is returned with ``stats["stable"] = False`` and a warning.
    codegen : bool or None
        Run the fused Newton, the residual check and the line-search steps in generated C
        (see :func:`symcable.mechanism.static_functions.static_solver`; None: where it pays, when a
        compiler is found). The answer agrees with the virtual machine's to round-off.

    Returns
    -------
    Equilibrium
        ``stats``: ``iterations`` (Newton iterations of every attempt, failed ones included),
        ``residual_norm`` (N, recomputed by the check), ``tolerance`` (N), ``path``,
        ``start`` (its source), ``continuation_steps``, ``attempts``, ``stable``,
        ``min_stiffness``, ``compiled``, ``wall_time`` (s).

    Raises
    ------
    ConvergenceError
        No start led to an equilibrium that passes the checks; ``diagnostics["attempts"]``
        has one line per attempt, ``diagnostics["best"]`` the path, start, message and
        residual of the attempt with the lowest residual, and ``partial`` its iterate.
        Also when the static system is not square (n_q != n_v).
    SymcableError
        ``p`` of the wrong size, an unknown ``continuation`` block, a bad ``codegen``.
    """
    t0 = time.perf_counter()
    F = functions(mech)
    p = mech.static_p if p is None else np.asarray(p, dtype=float).ravel()
    if p.size != mech.params.n:
        raise SymcableError(f"p has {p.size} entries, the mechanism {mech.name!r} {mech.params.n}")
    if continuation is True:
        continuation = None
    if isinstance(continuation, str):
        mech.params.slice(continuation)  # an unknown block is refused before any work
    elif continuation not in (None, False):
        raise SymcableError(f"continuation = {continuation!r}: must be a parameter block name "
                            f"({', '.join(mech.params.names) or 'none'}), True, False or None")
    n_rest = 0 if mech.rest is None else int(mech.rest.numel())
    if mech.n_v + n_rest != mech.n_q:
        raise ConvergenceError(
            f"no static equilibrium of {mech.name!r} can be solved for: its static residual has "
            f"n_v + n_z = {mech.n_v + mech.n_z} rows for n_q + n_z = {mech.n_q + mech.n_z} "
            "unknowns (kinematics q' = G(q) v with G not square); statics need n_q = n_v, or "
            "rest rows for the first-order states",
            diagnostics={"attempts": [], "best": {}, "iterations": 0})
    S = F.static_solver(codegen)
    if tol is None:
        tol = mech.scales.static_tolerance()
    opts = dict(tol=tol, max_iter=max_iter, x_scale=_x_scale(mech), merit_weights=mech.scales.merit)
    step = S.fast("step")
    attempts, best, iterations = [], None, 0

    def judge(start, path, res, steps=0, packed=None):
        """Check an attempt's claim and log it: the Equilibrium when it passes, else None."""
        nonlocal best, iterations
        iterations += res.iterations
        ok, why, info = _check(S, F, mech, res.x, p, tol, require_stable) if res.converged \
            else (False, res.message, None)
        attempts.append(f"{start.source} / {path}: {'ok' if ok else why}")
        if ok:
            return _result(F, S, mech, res.x, p, "converged", {
                "iterations": iterations, "residual_norm": info["residual_norm"],
                "tolerance": tol, "path": path, "start": start.source,
                "continuation_steps": steps, "attempts": attempts,
                "stable": info["stable"], "min_stiffness": info["min_stiffness"],
                "compiled": S.compiled, "wall_time": time.perf_counter() - t0},
                info["warnings"], packed)
        if best is None or (np.isfinite(res.residual_norm) and np.isfinite(res.x).all()
                            and not res.residual_norm >= best[0].residual_norm):
            best = (res, start, path, why)
        return None

    seen, followed = [], set()
    for start in (mech.starts() if starts is None else starts):
        x0 = _x0(mech, start)
        seen.append((start, x0))
        res, packed = _fused(S, x0, p, tol, max_iter)
        eq = judge(start, "newton", res, 0, packed)
        if eq is None and start.exact and continuation is not False \
                and not np.array_equal(np.asarray(start.p, float), p):
            followed.add(id(start))
            eq = judge(start, f"continuation in {start.homotopy or 'parameters'}",
                       *_cont(step, x0, np.asarray(start.p, float), p, opts, True, 0.25, 0.5))
        if eq is None:
            eq = judge(start, "damped newton", newton(step, x0, p, **opts))
        if eq is not None:
            return eq
    if continuation is not False:
        for start, path, attempt in _continuations(F, mech, p, tol, opts, step, seen,
                                                   continuation, followed):
            eq = judge(start, path, *attempt())
            if eq is not None:
                return eq
    partial, info = None, {}
    if best is not None:
        res, start, path, why = best
        info = {"path": path, "start": start.source, "message": why,
                "residual_norm": res.residual_norm}
        if np.all(np.isfinite(res.x)):
            partial = _result(F, S, mech, res.x, p, "failed", {
                "iterations": iterations, "residual_norm": res.residual_norm,
                "tolerance": tol, "path": path, "start": start.source,
                "attempts": attempts, "compiled": S.compiled,
                "wall_time": time.perf_counter() - t0}, ())
    raise ConvergenceError(
        f"no static equilibrium of {mech.name!r} passed the checks; attempts: "
        + "; ".join(attempts), partial=partial,
        diagnostics={"attempts": attempts, "best": info, "iterations": iterations})


def _x_scale(mech) -> np.ndarray:
    """The largest move of each unknown per Newton step (coordinates: their scale;
    constraint forces: 1000 times theirs): numbers of the scene, not of its Functions."""
    if not mech.n_z:
        return np.asarray(mech.scales.q, float)
    return np.concatenate([mech.scales.q, mech.scales.z * 1e3])


def _x0(mech, start) -> np.ndarray:
    """A start's unknowns x = (q, z)."""
    if not mech.n_z:
        return np.asarray(start.q, float)
    return np.concatenate([np.asarray(start.q, float), np.asarray(start.z, float)])


def _continuations(F, mech, p, tol, opts, step, seen, continuation, followed=()):
    """``(start, path, attempt)`` of the continuations, in the order :func:`solve_equilibrium`
    documents, from the starts ``seen`` (start, x0); ``attempt() -> (result, steps)``.
    ``followed``: ids of the starts whose continuation from their own parameters was
    already tried."""
    same = [np.array_equal(np.asarray(s.p, float), p) for s, _ in seen]
    for (start, x0), at_p in zip(seen, same):
        if not at_p and id(start) not in followed:
            p0 = np.asarray(start.p, float)
            yield (start, f"continuation in {start.homotopy or 'parameters'}",
                   lambda x0=x0, p0=p0: _cont(step, x0, p0, p, opts, True, 0.25, 0.5))
    if continuation:
        p0 = p.copy()
        p0[mech.params.slice(continuation)] = 0.0
        for start, x0 in seen:
            yield (start, f"continuation in {continuation}",
                   lambda x0=x0: _cont(step, x0, p0, p, opts, False, 1.0, 1.0))
    # pseudo-transient continuation at p, from every start (those at p first): a start built
    # for a continuation (no bending, the slack law's wide corner) is still a shape to relax
    # from, and the relaxation's push off an unstable equilibrium reaches a buckled branch
    # that no continuation from the straight state does
    for (start, x0), at_p in sorted(zip(seen, same), key=lambda item: not item[1]):
        yield (start, "pseudo-transient continuation",
               lambda x0=x0: (_ptc_stable(F, mech, x0, p, tol), 0))


def _cont(step, x0, p0, p1, opts, polish, dt0, dt_max):
    res, steps, iters = _continuation(step, x0, p0, p1, opts, polish, dt0, dt_max)
    res.iterations = iters
    return res, steps


def _check(S, F, mech, x, p, tol, require_stable):
    """Independent checks of a claimed solution: (ok, reason, info)."""
    try:  # R(x) afresh, its max-norm, and whether x and R(x) are finite, in one call
        nr, probe, margin = S.fast("check")(x, p, bound_numbers(mech))
    except RuntimeError as exc:
        return False, f"residual not evaluated ({exc})", {}
    nr = float(nr[0])
    if not math.isfinite(probe[0]):  # (a sum past 1e308 counts as not finite too)
        return False, "iterate or residual not finite", {}
    if nr > tol:
        return False, f"residual {nr:.3g} N > tolerance {tol:.3g} N", {}
    if not margin[0] >= 0.0:  # an admissibility bound violated (or NaN)
        why = bound_violations(mech, x[:mech.n_q], np.zeros(mech.n_v), x[mech.n_q:], 0.0, p)
        return False, "not admissible: " + "; ".join(why or ["a bound is NaN"]), {}
    stable, lam = _stability(F, mech, x[:mech.n_q], x[mech.n_q:], p)
    info = {"residual_norm": nr, "stable": stable, "min_stiffness": lam, "warnings": ()}
    if stable is False:
        if require_stable:
            return False, f"unstable equilibrium (reduced stiffness eigenvalue {lam:.3g})", info
        info["warnings"] = (f"the equilibrium is unstable (reduced stiffness eigenvalue {lam:.3g})",)
    return True, "", info


def _result(F, S, mech, x, p, status, stats, warnings, packed=None) -> Equilibrium:
    """The Equilibrium at x; ``packed`` the stacked outputs at x when already evaluated."""
    x = np.asarray(x, float)  # every path returns an array of its own: q and z are views
    if packed is None:
        packed = S.packed_outputs(x, p)
    n_q = mech.n_q
    return Equilibrium(mech.name, x[:n_q], x[n_q:], np.array(p), F.unpack(packed), status,
                       stats, tuple(warnings))
