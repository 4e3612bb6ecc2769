"""Static configuration: Newton with line search on the model's exact sparse Jacobian,
with continuation from the model's starting point when a plain Newton solve fails."""
from __future__ import annotations

import itertools
import time

import numpy as np

from ..errors import ConvergenceError
from ..functions import SOLVE_MAX_ITER, static_functions
from ..models import build_model
from ..models.base import Model
from ..results import StaticSolution
from ..scene import Scene, load_scene
from .newton import NewtonResult, newton

#: default residual tolerance, relative to the model's force scale
RTOL = 1e-9
#: plain Newton from a good start converges in a handful of steps or not at all
FAST_MAX_ITER = SOLVE_MAX_ITER


def solve_static(scene, *, tol: float | None = None, max_iter: int = 50,
                 continuation: bool = True, model: Model | None = None,
                 codegen: bool | None = None) -> StaticSolution:
    """Static configuration of a scene.

    Parameters
    ----------
    scene : Scene, dict or path
        Anything :func:`symcable.load_scene` takes.
    tol : float, optional
        Residual tolerance, N (max-norm over all equations, each a force). Default
        ``1e-9`` times the scene's force scale (total submerged weight, applied forces),
        or the model's round-off floor when that is larger.
    max_iter : int
        Newton iterations allowed per solve (per continuation step).
    continuation : bool
        When a plain Newton solve from the start fails, continue from the start's own
        parameters (no bending, or no load) to the scene's, in adaptive steps.
    model : Model, optional
        A model already built for this scene (:func:`symcable.build_model`).
    codegen : bool, optional
        Run the solve in generated C (compiled once per model structure, then loaded from
        the build cache) rather than the CasADi virtual machine. Default None: generated C
        when a C compiler is found (see :mod:`symcable.codegen`); True without a compiler
        warns once and uses the virtual machine. The results agree to round-off.

    Returns
    -------
    StaticSolution
        ``stats`` gives ``iterations``, ``residual_norm`` (N), ``tolerance`` (N),
        ``wall_time`` (s), ``compiled`` (generated C or not), ``path`` (``"newton"``:
        plain Newton in one CasADi call;
        ``"damped newton"``: with a line search; ``"continuation in <what>"``) and
        ``start`` (where the initial guess came from).

    Raises
    ------
    ConvergenceError
        With ``partial`` (a StaticSolution of the last iterate, status "failed") and the
        diagnostics of every attempt.
    """
    if not isinstance(scene, Scene):
        scene = load_scene(scene)
    t0 = time.perf_counter()
    model = model or build_model(scene)
    fns = static_functions(model, codegen)
    if tol is None:
        tol = max(RTOL * model.force_scale, model.residual_floor)
    tol = float(tol)
    target = model.p_target
    step = fns.fast("step")
    opts = dict(tol=tol, max_iter=max_iter, x_scale=model.w_scale, merit_weights=model.merit_weights)

    attempts, total_it, n_steps = [], 0, 0
    res, path, guess, tried = None, "newton", None, []
    # the first start is a function of the model alone: computed once per model, and the
    # further starts only when the fast path fails
    first = model._cache.get("first_guess")
    if first is None:
        first = model._cache["first_guess"] = next(iter(model.initial_guess()))
    # fast path: plain Newton from the first start, iterated in one call, outputs included
    res, packed = _fast_newton(fns, first.w, target, tol, max_iter)
    attempts.append({"path": "newton (one call)", "start": first.source,
                     "message": res.message, "iterations": res.iterations,
                     "residual_norm": res.residual_norm})
    total_it += res.iterations
    if res.converged:
        guess, guesses = first, iter(())
    else:
        guesses = itertools.chain([first], itertools.islice(model.initial_guess(), 1, None))
    for g in guesses:
        tried.append(g)
        res = newton(step, g.w, target, **opts)
        total_it += res.iterations
        path = "damped newton"
        attempts.append({"path": path, "start": g.source, "message": res.message,
                         "iterations": res.iterations, "residual_norm": res.residual_norm})
        guess = guess or g
        if res.converged:
            guess = g
            break
    if not res.converged and continuation:
        for g in (g for g in tried if g.homotopy):
            res, n_steps, it_cont, log = _continuation(step, g.w, g.p, target, **opts)
            total_it += it_cont
            path, guess = f"continuation in {g.homotopy}", g
            attempts.append({"path": path, "start": g.source, "message": res.message,
                             "steps": n_steps, "log": log})
            if res.converged:
                break
    stats = {
        "iterations": total_it,
        "residual_norm": res.residual_norm,
        "tolerance": tol,
        "wall_time": time.perf_counter() - t0,
        "compiled": fns.compiled,
        "path": path,
        "continuation_steps": n_steps,
        "start": guess.source,
        "unknowns": model.n_w,
        "terms": list(model.terms),
    }
    sol = _solution(model, fns, res, stats, packed if path == "newton" else None)
    if not res.converged:
        raise ConvergenceError(
            f"static solve of '{scene.name}' did not converge: {res.message} "
            f"(residual {res.residual_norm:.3g} N > tolerance {tol:.3g} N after {path})",
            partial=sol, diagnostics={"attempts": attempts, "history": res.history})
    return sol


def _fast_newton(fns, w0, p, tol, max_iter):
    """Plain Newton (at most FAST_MAX_ITER steps) in one call of ``static_solve``; returns
    the result and the packed outputs at its last iterate."""
    try:
        w, its, nr, packed = fns.fast("solve")(w0, p, tol)
    except RuntimeError as exc:  # the VM's QR refuses a singular Jacobian
        return NewtonResult(np.array(w0, dtype=float), False, 0, float("nan"),
                            f"plain Newton failed ({exc})"), None
    its, nr = int(its[0]), float(nr[0])
    ok = bool(np.isfinite(nr) and nr <= tol and its <= min(max_iter, FAST_MAX_ITER)
              and np.all(np.isfinite(w)))
    msg = "converged" if ok else f"plain Newton failed (residual {nr:.3g} N after {its} steps)"
    return NewtonResult(w, ok, its, nr, msg), packed


def _continuation(step, w0, p_start, p_target, **opts):
    """March p from p_start to p_target with adaptive steps and a secant predictor."""
    t, dt, w = 0.0, 0.25, np.array(w0, dtype=float)
    prev = None  # (t, w) of the previous converged point, for the predictor
    it_total, n_steps, log = 0, 0, []
    # the start is only approximately a solution at p_start: polish it there first
    res = newton(step, w, p_start, **opts)
    it_total += res.iterations
    if not res.converged:
        return res, 0, it_total, [{"t": 0.0, "message": res.message}]
    w = res.x
    while t < 1.0:
        t_new = min(1.0, t + dt)
        pred = w if prev is None else w + (w - prev[1]) * (t_new - t) / (t - prev[0])
        p = p_start + t_new * (p_target - p_start)
        res = newton(step, pred, p, **opts)
        it_total += res.iterations
        log.append({"t": t_new, "converged": res.converged, "iterations": res.iterations})
        if res.converged:
            prev, w, t = (t, w), res.x, t_new
            n_steps += 1
            dt = min(2.0 * dt, 0.5)
        else:
            dt *= 0.5
            if dt < 1e-4:
                res.message = f"continuation stalled at {t:.4g} of the way ({res.message})"
                return res, n_steps, it_total, log
    return res, n_steps, it_total, log


def _solution(model: Model, fns, res: NewtonResult, stats: dict, packed=None) -> StaticSolution:
    if packed is None:
        packed = np.concatenate(fns.fast("outputs")(res.x, model.p_target))
    out = fns.unpack(packed)
    derived = model.postprocess(out)
    s_nodes = np.asarray(model.info["s_nodes"])
    warnings = []
    sb = model.scene.seabed
    if sb is not None and sb.friction > 0:
        warnings.append("seabed friction is not applied in statics (frictionless contact)")
    if np.any(out["axial_force"] < 0):
        warnings.append("the line is in compression somewhere (axial force < 0)")
    return StaticSolution(
        scene_name=model.scene.name,
        s=s_nodes,
        positions=out["positions"],
        angle=out["angle"].ravel(),
        strain=out["strain"].ravel(),
        axial_force=out["axial_force"].ravel(),
        shear=out["shear"].ravel(),
        moment=out["moment"].ravel(),
        tension=out["tension"].ravel(),
        contact_force=out["contact_force"].ravel(),
        fairlead_force=derived["fairlead_force"],
        anchor_force=derived["anchor_force"],
        fairlead_tension=derived["fairlead_tension"],
        anchor_tension=derived["anchor_tension"],
        grounded_length=derived["grounded_length"],
        touchdown=derived["touchdown"],
        status="converged" if res.converged else "failed",
        stats=stats,
        warnings=tuple(warnings),
        unknowns=np.array(res.x),
    )
