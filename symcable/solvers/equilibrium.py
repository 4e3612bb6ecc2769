"""Static equilibrium of any Mechanism: Newton on R(q, z; p) = (f(q, 0, z, 0), g) with its
exact sparse Jacobian, a backtracking line search, and continuation in a named parameter
block. Every answer is checked afterwards, in floating point and independently of how it was
found: the residual of the equations, finiteness, and the stability of the equilibrium (the
tangent stiffness reduced to the constraints' null space). A failed check is never called
converged.
"""
from __future__ import annotations

import time

import numpy as np

from ..derive import functions
from ..errors import ConvergenceError, SymcableError
from ..models.mechanism import Mechanism
from ..results_mechanism import Equilibrium
from .newton import newton

__all__ = ["constraint_null_space", "solve_equilibrium"]

#: largest system whose stability is checked by a dense eigenvalue solve
STABILITY_MAX_N = 3000


def _newton(F, x0, p, tol, max_iter, x_scale):
    def step(x, pp):
        r, dx = F.static_step(x, pp)
        return np.asarray(r).ravel(), np.asarray(dx).ravel()
    return newton(step, x0, p, tol=tol, max_iter=max_iter, x_scale=x_scale)


def _continuation(F, x0, p0, p1, tol, max_iter, x_scale, min_step=1e-4):
    """Newton along p(s) = p0 + s (p1 - p0), s from 0 to 1, adaptive steps."""
    s, ds, x, iters, steps = 0.0, 1.0, np.array(x0, float), 0, 0
    while s < 1.0:
        s_try = min(1.0, s + ds)
        res = _newton(F, x, p0 + s_try * (p1 - p0), tol, max_iter, x_scale)
        iters += res.iterations
        if res.converged:
            s, x, steps = s_try, res.x, steps + 1
            ds = min(2 * ds, 1.0)
        else:
            ds /= 2
            if ds < min_step:
                res.message = f"continuation stalled at s = {s:.4g} ({res.message})"
                res.iterations = iters
                return res, steps
    res.iterations = iters
    return res, steps


#: pseudo-transient continuation: most steps, the first pseudo-time step, when it counts as
#: Newton (the regularisation then is 1e-10 of the stiffness scale)
PTC_MAX_STEPS, PTC_DT0, PTC_DT_NEWTON = 400, 1e-2, 1e10


def _ptc(F, mech, x0, p, tol):
    """Pseudo-transient continuation (Kelley & Keyes 1998): steps (D/dtau - J) dx = R(x) of
    a damped relaxation in pseudo-time, D = force scale / coordinate scale per unknown. For a
    conservative system (R = -grad E, J = -Hessian) a short step goes down the energy, so it
    relaxes toward a stable equilibrium where Newton from a far start stalls or lands on a
    saddle; the robust form of the dynamic relaxation MoorDyn uses. The pseudo-time step
    doubles after every accepted step (so the end is Newton's quadratic convergence) and is
    cut by 4 when the residual jumps: not switched evolution relaxation, whose step shrinks
    while the residual grows, as it does for a while along a buckling path (measured: SER
    stalled on compressed chains under gravity at steps of 3e-5 m)."""
    from types import SimpleNamespace

    D = mech.scales.force / np.concatenate([mech.scales.q, np.ones(mech.n_z)])
    if mech.n_z:
        D[mech.n_q:] = 0.0  # constraint rows are not relaxed: they hold at every step
    x = np.array(x0, dtype=float)
    dtau = PTC_DT0
    r = np.asarray(F.static_residual(x, p)).ravel()
    nr = float(np.max(np.abs(r))) if r.size else 0.0
    for it in range(1, PTC_MAX_STEPS + 1):
        if nr <= tol:
            return SimpleNamespace(x=x, converged=True, iterations=it - 1, residual_norm=nr,
                                   message="converged")
        _, dx = (np.asarray(a).ravel() for a in F.static_ptc_step(x, p, D / dtau))
        x_new = x + dx
        r_new = np.asarray(F.static_residual(x_new, p)).ravel() if np.all(np.isfinite(dx)) \
            else np.full(r.shape, np.inf)
        nr_new = float(np.max(np.abs(r_new))) if r_new.size else 0.0
        if not np.isfinite(nr_new) or nr_new > 100.0 * nr:
            dtau /= 4.0
            if dtau < 1e-12:
                break
            continue
        x, nr = x_new, nr_new
        dtau = min(2.0 * dtau, PTC_DT_NEWTON)
    return SimpleNamespace(x=x, converged=nr <= tol, iterations=PTC_MAX_STEPS, residual_norm=nr,
                           message="converged" if nr <= tol else
                           f"pseudo-transient continuation: residual {nr:.3g} after "
                           f"{PTC_MAX_STEPS} steps")


def constraint_null_space(B: np.ndarray, n: int) -> np.ndarray:
    """(n, k) orthonormal basis of the coordinates that keep the constraints, the null space
    of the constraint Jacobian B (n_z, n); the identity without constraints."""
    if B.size == 0 or B.shape[0] == 0:
        return np.eye(n)
    _, sv, vt = np.linalg.svd(B)
    return vt[int(np.sum(sv > sv.max() * 1e-10)):].T


def _unstable_direction(F, mech, q, z, p):
    """(lowest eigenvalue, its direction in q) of the reduced tangent stiffness, or
    (None, None) where stability is not judged (too large, or a formulation without mass
    whose residual rows are not the gradient of an energy)."""
    if mech.n_q > STABILITY_MAX_N or mech.mass.nnz() == 0:
        return None, None
    K, _, _, B, *_ = F.tangents(q, np.zeros(mech.n_v), z, 0.0, p)
    K = np.asarray(K)
    N = constraint_null_space(np.asarray(B), mech.n_q)
    Kr = N.T @ (0.5 * (K + K.T)) @ N
    if Kr.size == 0:
        return float("inf"), np.zeros(mech.n_q)
    lam, vec = np.linalg.eigh(Kr)
    return float(lam[0]), N @ vec[:, 0]


def _stability(F, mech, q, z, p):
    lam, _ = _unstable_direction(F, mech, q, z, p)
    if lam is None:
        return None, float("nan")
    if not np.isfinite(lam):
        return True, lam
    K, *_ = F.tangents(q, np.zeros(mech.n_v), z, 0.0, p)
    scale = max(float(np.max(np.abs(np.asarray(K)))), 1e-300)
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
                      max_iter: int = 50, starts=None, continuation: str | None = None,
                      require_stable: bool = True) -> Equilibrium:
    """The static equilibrium of ``mech``.

    Parameters
    ----------
    mech : Mechanism
    p : ndarray (n_p,), optional
        Parameters; default the mechanism's static parameters.
    tol : float, optional
        N, converged when max |R| <= tol (constraint rows are scaled to forces by
        ``scales.force / q_ref``); default max(1e-9 force scale, 10 x the residual floor).
    max_iter : int
        Newton iterations per attempt (per continuation step).
    starts : iterable of Start, optional
        Default ``mech.starts()``.
    continuation : str, optional
        A parameter block to continue in when a start fails directly: from the block at
        zero (e.g. ``"load"``) to its target value.
    require_stable : bool
        An unstable equilibrium (negative reduced stiffness) is a failed attempt; with False
        it is returned with ``stats["stable"] = False`` and a warning.

    Raises
    ------
    ConvergenceError
        No start led to an equilibrium that passes the checks; ``diagnostics["attempts"]``
        has one line per attempt and ``partial`` the best iterate.
    """
    F = functions(mech)
    p = mech.static_p if p is None else np.asarray(p, dtype=float).ravel()
    if p.size != mech.params.n:
        raise SymcableError(f"p has {p.size} entries, the mechanism {mech.name!r} {mech.params.n}")
    if tol is None:
        tol = max(1e-9 * mech.scales.force, 10 * mech.scales.residual_floor)
    x_scale = np.concatenate([mech.scales.q, mech.scales.z * 1e3]) if mech.n_z else mech.scales.q
    t0 = time.perf_counter()
    attempts, best = [], None
    for start in (mech.starts() if starts is None else starts):
        x0 = np.concatenate([np.asarray(start.q, float), np.asarray(start.z, float)])
        paths = []
        if np.allclose(start.p, p):
            paths.append(("newton", None))
        else:
            paths.append((f"continuation in {start.homotopy or 'parameters'}", np.asarray(start.p, float)))
        if continuation:
            p0 = p.copy()
            p0[mech.params.slice(continuation)] = 0.0
            paths.append((f"continuation in {continuation}", p0))
        paths.append(("pseudo-transient continuation", "ptc"))
        for path, p_from in paths:
            if p_from is None:
                res, steps = _newton(F, x0, p, tol, max_iter, x_scale), 0
            elif isinstance(p_from, str):
                if not np.allclose(start.p, p):
                    continue
                res, steps = _ptc_stable(F, mech, x0, p, tol), 0
            else:
                res, steps = _continuation(F, x0, p_from, p, tol, max_iter, x_scale)
            ok, why, info = _check(F, mech, res.x, p, tol, require_stable) if res.converged \
                else (False, res.message, {})
            attempts.append(f"{start.source} / {path}: {'ok' if ok else why}")
            if best is None or (np.isfinite(res.residual_norm)
                                and res.residual_norm < best[0].residual_norm):
                best = (res, start, path, info)
            if ok:
                return _result(F, mech, res.x, p, "converged", {
                    "iterations": res.iterations, "residual_norm": info["residual_norm"],
                    "tolerance": tol, "path": path, "start": start.source,
                    "continuation_steps": steps, "attempts": attempts,
                    "stable": info["stable"], "min_stiffness": info["min_stiffness"],
                    "wall_time": time.perf_counter() - t0}, info.get("warnings", ()))
    partial = None
    if best is not None and np.all(np.isfinite(best[0].x)):
        partial = _result(F, mech, best[0].x, p, "failed", {"attempts": attempts}, ())
    raise ConvergenceError(
        f"no static equilibrium of {mech.name!r} passed the checks; attempts: "
        + "; ".join(attempts), partial=partial, diagnostics={"attempts": attempts})


def _check(F, mech, x, p, tol, require_stable):
    """Independent checks of a claimed solution: (ok, reason, info)."""
    x = np.asarray(x, float)
    if not np.all(np.isfinite(x)):
        return False, "iterate not finite", {}
    r = np.asarray(F.static_residual(x, p)).ravel()
    nr = float(np.max(np.abs(r))) if r.size else 0.0
    if not np.isfinite(nr) or nr > tol:
        return False, f"residual {nr:.3g} N > tolerance {tol:.3g} N", {}
    q, z = x[:mech.n_q], x[mech.n_q:]
    stable, lam = _stability(F, mech, q, z, p)
    info = {"residual_norm": nr, "stable": stable, "min_stiffness": lam, "warnings": ()}
    if stable is False:
        if require_stable:
            return False, f"unstable equilibrium (reduced stiffness eigenvalue {lam:.3g})", info
        info["warnings"] = (f"the equilibrium is unstable (reduced stiffness eigenvalue {lam:.3g})",)
    return True, "", info


def _result(F, mech, x, p, status, stats, warnings) -> Equilibrium:
    q, z = x[:mech.n_q], x[mech.n_q:]
    outs = F.evaluate_outputs(q, np.zeros(mech.n_v), z, 0.0, p)
    return Equilibrium(mech.name, q, z, p, outs, status, stats, tuple(warnings))
