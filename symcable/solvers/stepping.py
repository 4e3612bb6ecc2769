"""Time stepping of a :class:`~symcable.models.DynamicModel`: explicit RK4 and implicit
generalized-α, from the rest state at t = 0.

Generic: the integrators see ``dy/dt = f(y, t; p)`` (the model's ``rhs``), its Jacobian,
its named outputs, ``y_scale`` and ``period``, and nothing about cables.

Each step is one CasADi Function, and ``mapaccum`` chains many steps into one call, so a
long run pays the Python interpreter once per batch of saved samples, not once per step:

* ``rk4``: the classical four-stage Runge-Kutta method, one SX Function per step.
  Explicit, so only stable for ``dt`` below ~2.8 / (spectral radius of df/dy);
* ``generalized-alpha``: the first-order generalized-α method of Jansen, Whiting & Hulbert
  (2000) with the unknown ydot_{n+1},

      y_{n+1}        = y_n + dt ydot_n + gamma dt (ydot_{n+1} - ydot_n)
      ydot_{n+a_m}   = ydot_n + a_m (ydot_{n+1} - ydot_n)
      y_{n+a_f}      = y_n + a_f (y_{n+1} - y_n),     t_{n+a_f} = t_n + a_f dt
      R(ydot_{n+1})  = ydot_{n+a_m} - f(y_{n+a_f}, t_{n+a_f}) = 0,

  a_m = (3 - rho_inf) / (2 (1 + rho_inf)), a_f = 1 / (1 + rho_inf),
  gamma = 1/2 + a_m - a_f: second order, A-stable, with high-frequency damping set by
  rho_inf in [0, 1] (1: none; 0: annihilates the highest frequencies in one step). Each
  step solves R = 0 by Newton's method with the exact Jacobian
  a_m I - a_f gamma dt df/dy from CasADi, factorised once per step by the block LU of
  :mod:`symcable.linalg.sxlu` (written out in SX) and reused by the next iterations
  (chord iterations), inside the step Function.
"""
from __future__ import annotations

import enum
import math
import time as _time
from collections import OrderedDict

import casadi as ca
import numpy as np

from ..codegen import compile_functions, graph_size, use_codegen
from ..errors import ConvergenceError, SymcableError
from ..functions import FastCall
from ..progress import ProgressBar
from ..results_time import Trajectory
from ..linalg.sparse import jacobian as _jacobian, sparse_solve
from ..linalg.sxlu import block_lu, block_plan
from ..scene import load_scene

__all__ = ["Method", "ga_coefficients", "ga_residual_function", "rk4_stability_limit", "simulate",
           "step_function"]

#: RK4's stability interval on the imaginary axis: |lambda dt| <= 2 sqrt(2).
RK4_IMAG_LIMIT = 2.0 * math.sqrt(2.0)
#: A state beyond this multiple of ``y_scale`` (or not finite) means the run blew up.
BLOWUP = 1e6
#: Newton iterations per generalized-α step before the step counts as failed.
NEWTON_MAX_ITER = 10
#: iterations of a generalized-α step that reuse the matrix factorised at its start
CHORD_ITERATIONS = 4
#: Default Newton tolerance on the scaled residual and step (see ``simulate``).
NEWTON_TOL = 1e-10
#: Default largest number of saved samples.
MAX_SAMPLES = 2000
#: Target wall time of one batched call, s (sets the progress bar's granularity).
_CALL_TARGET = 0.2


class Method(str, enum.Enum):
    """Time integration methods."""

    RK4 = "rk4"
    GENERALIZED_ALPHA = "generalized-alpha"

    @classmethod
    def parse(cls, value) -> "Method":
        try:
            return cls(value)
        except ValueError:
            allowed = ", ".join(repr(m.value) for m in cls)
            raise SymcableError(f"method = {value!r}: must be one of {allowed}") from None


# ----------------------------------------------------------------------------- coefficients

def ga_coefficients(rho_inf: float) -> tuple[float, float, float]:
    """``(alpha_m, alpha_f, gamma)`` of first-order generalized-α for a spectral radius at
    infinity ``rho_inf`` in [0, 1] (Jansen, Whiting & Hulbert 2000, eqs. 20 and 17)."""
    alpha_m = 0.5 * (3.0 - rho_inf) / (1.0 + rho_inf)
    alpha_f = 1.0 / (1.0 + rho_inf)
    return alpha_m, alpha_f, 0.5 + alpha_m - alpha_f


# ----------------------------------------------------------------------------- RK4 stability

def _rk4_ray(theta: np.ndarray) -> np.ndarray:
    """Length r of RK4's stability region along the rays z = r exp(i theta) of the left
    half-plane (the region is star-shaped there, and 2.61 <= r <= 2.97 on every such ray)."""
    theta = np.asarray(theta, dtype=float)

    def stable(r):
        z = r * np.exp(1j * theta)
        return np.abs(1 + z + z ** 2 / 2 + z ** 3 / 6 + z ** 4 / 24) <= 1.0 + 1e-12

    lo, hi = np.zeros_like(theta), np.full_like(theta, 4.0)
    for _ in range(50):
        mid = 0.5 * (lo + hi)
        ok = stable(mid)
        lo, hi = np.where(ok, mid, lo), np.where(ok, hi, mid)
    return lo


def _spectral_radius(J: ca.DM, iters: int = 300) -> float:
    """Spectral radius of a sparse matrix by power iteration: the geometric-mean growth of
    |J^k x| over the second half of the iterations (robust to a dominant complex pair)."""
    rows, cols = (np.asarray(v) for v in J.sparsity().get_triplet())
    vals = np.asarray(J.nonzeros(), dtype=float)
    n = J.size1()
    x = np.random.default_rng(0).standard_normal(n)
    logs = []
    for _ in range(iters):
        x = np.bincount(rows, weights=vals * x[cols], minlength=n)
        nx = float(np.linalg.norm(x))
        if nx == 0.0 or not math.isfinite(nx):
            return 0.0 if nx == 0.0 else math.inf
        logs.append(math.log(nx))
        x /= nx
    return math.exp(float(np.mean(logs[iters // 2:])))


def rk4_stability_limit(model, p: np.ndarray | None = None, t: float = 0.0) -> float:
    """Largest stable RK4 step of the model linearised at rest, s.

    Dense eigenvalues of df/dy at ``(y0, t; p)`` when n_y <= 800: the limit is the least,
    over the eigenvalues lambda, of the length of RK4's stability region along lambda's ray
    divided by |lambda| (2 sqrt 2 / |lambda| on the imaginary axis; eigenvalues with a
    positive real part from round-off count as imaginary). Larger models: 2.6 / (spectral
    radius by power iteration), 2.6 being the region's least radius in the left half-plane.
    ``inf`` when df/dy is zero.
    """
    p = np.asarray(model.p_value if p is None else p, dtype=float)
    key = ("rk4_stability_limit", float(t), p.tobytes())
    if key not in model._cache:
        model._cache[key] = _rk4_limit(model, p, t)
    return model._cache[key]


def _rk4_limit(model, p, t) -> float:
    J = model.functions().rhs_jacobian(model.y0, t, p)
    if model.n_y <= 800:
        lam = np.linalg.eigvals(np.array(J.full()))
        mag = np.abs(lam)
        if not np.any(mag > 0.0):
            return math.inf
        keep = mag > 1e-9 * mag.max()
        theta = np.abs(np.angle(lam[keep]))
        theta = np.maximum(theta, 0.5 * np.pi)
        return float(np.min(_rk4_ray(theta) / mag[keep]))
    rho = _spectral_radius(J)
    return math.inf if rho == 0.0 else 2.6 / rho


# ----------------------------------------------------------------------------- step functions
# Every step Function has the same signature, so one driver runs both methods:
#   (y, ydot, k, t0, dt, p, y_scale, settings)
#       -> (y_next, ydot_next, k + 1, newton_iterations, failed, measure)
# with t_n = t0 + k dt (k counts steps exactly in floating point) and
# settings = [rho_inf, newton_tol]. ``ydot`` is carried for generalized-α and passed through
# by RK4; ``measure`` is the accepted Newton convergence measure (0 for RK4). Everything
# that may change between runs of one model (parameters, step, scales, settings) is an
# input, so one compiled library serves every run of a model structure.

def _symbols(model, kind):
    n, n_p = model.n_y, int(model.p.numel())
    S = getattr(ca, kind)
    return (S.sym("y", n), S.sym("ydot", n), S.sym("k"), S.sym("t0"), S.sym("dt"),
            S.sym("p", n_p), S.sym("y_scale", n), S.sym("settings", 2))


_STEP_IN = ["y", "ydot", "k", "t0", "dt", "p", "y_scale", "settings"]
_STEP_OUT = ["y_next", "ydot_next", "k_next", "newton_iterations", "failed", "measure"]
#: the fallback linear solver of the Newton iterations, for a pattern with no fixed block
#: elimination order: CasADi's sparse QR, which generates C
#: (CSparse's LU does not); in the virtual machine it is as fast as CSparse here
LINSOL = "qr"
#: largest state (entries) whose iteration matrix is factorised by the block LU written
#: out in SX; above it, by the sparse QR of ``sparse_solve`` (fill-reducing column order,
#: dense rows split off), whose construction is O(n) (see functions.SXLU_MAX_UNKNOWNS)
SXLU_MAX_STATES = 400
#: largest state whose SX step Functions are built with common subexpressions eliminated:
#: CasADi's elimination grows faster than the graph (8 s for 8,000 states, 26 s for
#: 16,000) and pays only in small generated C
CSE_MAX_STATES = SXLU_MAX_STATES


def _rk4_step(model) -> ca.Function:
    """The RK4 step: one SX Function."""
    f = model.functions().rhs
    y, yd, k, t0, dt, p, sc, st = _symbols(model, "SX")
    t = t0 + k * dt
    k1 = f(y, t, p)
    k2 = f(y + 0.5 * dt * k1, t + 0.5 * dt, p)
    k3 = f(y + 0.5 * dt * k2, t + 0.5 * dt, p)
    k4 = f(y + dt * k3, t + dt, p)
    y_next = y + dt / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4)
    return ca.Function("rk4_step", [y, yd, k, t0, dt, p, sc, st],
                       [y_next, yd, k + 1, ca.SX(0), ca.SX(0), ca.SX(0)], _STEP_IN, _STEP_OUT,
                       {"cse": model.n_y <= CSE_MAX_STATES})


def _ga_coefficients_sym(rho):
    am = 0.5 * (3.0 - rho) / (1.0 + rho)
    af = 1.0 / (1.0 + rho)
    return am, af, 0.5 + am - af


def _ga_residual(model, z, y, yd, t, dt, p, rho):
    am, af, gamma = _ga_coefficients_sym(rho)
    y_next = y + dt * yd + gamma * dt * (z - yd)
    return yd + am * (z - yd) - model.functions().rhs(y + af * (y_next - y), t + af * dt, p)


def ga_residual_function(model, rho_inf: float) -> ca.Function:
    """The generalized-α step residual and its exact Jacobian.

    ``ga_residual(ydot_next, y, ydot, t, dt, p) -> (r, dr_dydot_next)``: ``y, ydot`` at
    t_n = ``t`` (s), the unknown rate ``ydot_next`` at t_n + dt; ``r`` (n_y,) in units of
    y per second, ``dr_dydot_next`` (n_y, n_y) sparse, alpha_m I - alpha_f gamma dt df/dy.
    """
    key = ("ga_residual", float(rho_inf))
    fn = model._cache.get(key)
    if fn is None:
        z = ca.SX.sym("ydot_next", model.n_y)
        y, yd, _, t, dt, p, _, _ = _symbols(model, "SX")
        r = _ga_residual(model, z, y, yd, t, dt, p, float(rho_inf))
        fn = ca.Function("ga_residual", [z, y, yd, t, dt, p], [r, _jacobian(r, z)],
                         ["ydot_next", "y", "ydot", "t", "dt", "p"], ["r", "dr_dydot_next"])
        model._cache[key] = fn
    return fn


def _ga_linear_solver(model, J: ca.SX, args: list):
    """``(factor, solve, n_factors)`` for the iteration matrix ``J`` (SX in ``args``):
    ``factor(*args) -> f`` and ``solve(f, b) -> J^-1 b``. The block LU of
    :mod:`symcable.linalg.sxlu` written out in SX when J's pattern allows a fixed
    elimination order (the generalized-α matrix alpha_m I - ... has a regular diagonal)
    and J has at most SXLU_MAX_STATES rows, else J's nonzeros and the sparse QR of
    ``sparse_solve``."""
    sp = J.sparsity()
    plan = block_plan(sp) if sp.size1() <= SXLU_MAX_STATES else None
    if plan is not None:
        lu = block_lu(sp, *plan, cache=model._cache)
        factor = ca.Function("ga_factor", args, [lu.factor(J.nz[:])])
        return factor, lu.solve_function(1), lu.n_factors
    factor = ca.Function("ga_factor", args, [J.nz[:]])
    f, b = ca.MX.sym("f", sp.nnz()), ca.MX.sym("b", sp.size1())
    solve = ca.Function("ga_qr_solve", [f, b], [sparse_solve(ca.MX(sp, f), b, LINSOL)])
    return factor, solve, sp.nnz()


def _ga_step(model, max_iter: int) -> ca.Function:
    """One generalized-α step with its Newton loop unrolled ``max_iter`` times; a converged
    iteration switches the rest off (CasADi evaluates only the taken branch of an if_else).

    The iteration matrix is factorised at the start of the step, kept for iterations
    2..CHORD_ITERATIONS (chord iterations: the model is linear in y but for drag, so the
    matrix hardly changes over a step) and refactorised at every later iteration.

    Converged when the residual scaled by dt / y_scale, or the last Newton correction of
    y_next scaled by y_scale, is <= newton_tol in the max-norm (both are changes of y over
    one step relative to the state's scale; the iterations contract fast, so the accepted
    iterate is far more accurate than the correction that was accepted)."""
    n = model.n_y
    zs = ca.SX.sym("ydot_next", n)
    y, yd, _, t, dt, p, sc, st = _symbols(model, "SX")
    r = _ga_residual(model, zs, y, yd, t, dt, p, st[0])
    args = [zs, y, yd, t, dt, p, st]
    R = ca.Function("ga_residual", args, [r], {"cse": n <= CSE_MAX_STATES})
    factor, solve, n_f = _ga_linear_solver(model, _jacobian(r, zs), args)

    # one iteration: (z, done, it, measure, f; y, ydot, t, dt, p, y_scale, settings) -> ...
    z, done, it, meas = ca.MX.sym("z", n), ca.MX.sym("done"), ca.MX.sym("it"), ca.MX.sym("measure")
    f = ca.MX.sym("f", n_f)
    y, yd, _, t, dt, p, sc, st = _symbols(model, "MX")
    tol, gamma = st[1], _ga_coefficients_sym(st[0])[2]
    r = R(z, y, yd, t, dt, p, st)
    res = ca.norm_inf(r * dt / sc)
    conv = res <= tol
    names = ["z", "done", "it", "measure", "f", "y", "ydot", "t", "dt", "p", "y_scale", "settings"]
    outs = ["z_out", "done_out", "it_out", "measure_out"]
    fargs = [z, done, it, meas, f, y, yd, t, dt, p, sc, st]
    rest = fargs[5:]
    # the loop from iteration i on, nested so that a converged step returns at once:
    # loop_i = if done: (z, done, it, measure) else loop_{i+1}(iteration_i(...))
    loop = ca.Function(f"ga_newton_done{max_iter}", fargs, [z, done, it, meas], names, outs)
    for i in range(max_iter - 1, -1, -1):
        refactor = i == 0 or i >= CHORD_ITERATIONS
        f_new = ca.if_else(conv, f, factor(z, y, yd, t, dt, p, st), True) if refactor else f
        dz = ca.if_else(conv, ca.MX.zeros(n), -solve(f_new, r), True)
        corr = ca.norm_inf(gamma * dt * dz / sc)
        nxt = loop(z + dz, ca.logic_or(conv, corr <= tol), it + 1 - conv,
                   ca.if_else(conv, res, corr), f_new, *rest)
        go_on = ca.Function(f"ga_newton_from{i}", fargs, nxt, names, outs)
        stop = ca.Function(f"ga_newton_stop{i}", fargs, [z, done, it, meas], names, outs)
        loop = ca.Function.if_else(f"ga_newton_loop{i}", stop, go_on)
        loop = ca.Function(f"ga_newton_{i}", fargs, loop(done, *fargs), names, outs)

    y, yd, k, t0, dt, p, sc, st = _symbols(model, "MX")
    gamma = _ga_coefficients_sym(st[0])[2]
    t = t0 + k * dt
    z, done, it, meas = loop(yd, 0, 0, np.inf, ca.MX.zeros(n_f), y, yd, t, dt, p, sc, st)
    y_next = y + dt * yd + gamma * dt * (z - yd)
    return ca.Function("ga_step", [y, yd, k, t0, dt, p, sc, st],
                       [y_next, z, k + 1, it, 1 - done, meas], _STEP_IN, _STEP_OUT)


def step_function(model, method, codegen: bool | None = False) -> ca.Function:
    """The step Function of ``method`` ("rk4" or "generalized-alpha") for ``model``, run by
    the virtual machine or compiled (``codegen``, see :func:`symcable.codegen.use_codegen`);
    built once per model. Signature in the comment above."""
    meth = Method.parse(method)
    key = ("step", meth.value)
    vm = model._cache.get(key)
    if vm is None:
        vm = _ga_step(model, NEWTON_MAX_ITER) if meth is Method.GENERALIZED_ALPHA else _rk4_step(model)
        model._cache[key] = vm
    key = ("compiled_step", vm.name())
    def size():  # by default C only where the step is written out (block LU, small graph)
        if meth is Method.GENERALIZED_ALPHA and model.n_y > SXLU_MAX_STATES:
            return math.inf
        if ("graph_size", vm.name()) not in model._cache:
            model._cache[("graph_size", vm.name())] = graph_size([vm])
        return model._cache[("graph_size", vm.name())]
    if not use_codegen(codegen, size):
        return vm
    if key not in model._cache:
        label = "the generalized-α step" if meth is Method.GENERALIZED_ALPHA else "the RK4 step"
        model._cache[key] = compile_functions([vm], what=label)[vm.name()]
    return model._cache[key]


def _batch(model, step: ca.Function, S: int, m: int) -> ca.Function:
    """``m`` saved samples, ``S`` steps apart, in one call:
    (y, ydot, k, t0, dt, p, y_scale, settings) -> (Y (n_y, m), YDOT (n_y, m), K (1, m),
    iterations summed, iterations max, failed steps, measure max), the last four (1, m)
    per sample."""
    cache = model._cache.setdefault("stepping_batches", OrderedDict())
    key = (step.name(), id(step), S, m)
    fn = cache.get(key)
    if fn is not None:
        cache.move_to_end(key)
        return fn
    inner = step.mapaccum(f"{step.name()}_x{S}", S, [0, 1, 2], [0, 1, 2])
    y, yd, k, t0, dt, p, sc, st = _symbols(model, "MX")
    Y, YD, K, IT, FAIL, MEAS = inner(y, yd, k, t0, dt, p, sc, st)
    save = ca.Function(f"{step.name()}_sample{S}", [y, yd, k, t0, dt, p, sc, st],
                       [Y[:, S - 1], YD[:, S - 1], K[S - 1], ca.sum2(IT), ca.mmax(IT),
                        ca.sum2(FAIL), ca.mmax(MEAS)], _STEP_IN,
                       ["y_end", "ydot_end", "k_end", "iterations", "iterations_max", "failed", "measure"])
    fn = FastCall(save.mapaccum(f"{step.name()}_sample{S}_x{m}", m, [0, 1, 2], [0, 1, 2]))
    cache[key] = fn
    if len(cache) > 64:
        cache.popitem(last=False)
    return fn


# ----------------------------------------------------------------------------- schedule

def _save_indices(n_steps: int, dt: float, duration: float, save_every, save_times) -> np.ndarray:
    """Sorted unique step indices to save."""
    if save_every is not None and save_times is not None:
        raise SymcableError("save_every and save_times: give at most one of them")
    if save_times is not None:
        st = np.atleast_1d(np.asarray(save_times, dtype=float)).ravel()
        if st.size == 0 or not np.all(np.isfinite(st)):
            raise SymcableError(f"save_times = {save_times!r}: must be a non-empty array of finite times, s")
        if st.min() < -0.5 * dt or st.max() > duration + 0.5 * dt:
            raise SymcableError(f"save_times = [{st.min():.6g} .. {st.max():.6g}] s: must lie in "
                                f"[0, duration = {duration:.6g}] s")
        return np.unique(np.clip(np.rint(st / dt).astype(np.int64), 0, n_steps))
    if save_every is None:
        save_every = 1 if n_steps < MAX_SAMPLES else math.ceil(n_steps / MAX_SAMPLES)
    elif isinstance(save_every, bool) or not isinstance(save_every, (int, np.integer)) or save_every < 1:
        raise SymcableError(f"save_every = {save_every!r}: must be a whole number of steps >= 1")
    idx = np.arange(0, n_steps + 1, int(save_every), dtype=np.int64)
    return idx if idx[-1] == n_steps else np.append(idx, n_steps)


#: longest run of steps one batched call advances between two checkpoints: a mapaccum over
#: many thousands of steps is slow to build, so long gaps between saves are cut into pieces
MAX_GAP = 256


def _with_checkpoints(idx: np.ndarray, max_gap: int = MAX_GAP) -> np.ndarray:
    """The save indices plus unsaved checkpoints, so no gap exceeds ``max_gap`` steps."""
    points = np.concatenate([[0], idx])
    extra = [np.arange(a + max_gap, b, max_gap) for a, b in zip(points[:-1], points[1:]) if b - a > max_gap]
    return np.unique(np.concatenate([idx] + extra)).astype(int) if extra else idx


def _runs(idx: np.ndarray) -> list:
    """Consecutive equal gaps between saved indices (from step 0): [(S, count), ...]."""
    gaps = np.diff(np.concatenate([[0], idx]))
    gaps = gaps[gaps > 0]
    runs: list = []
    for g in gaps:
        if runs and runs[-1][0] == g:
            runs[-1][1] += 1
        else:
            runs.append([int(g), 1])
    return runs


# ----------------------------------------------------------------------------- outputs

def _outputs(model, Y: np.ndarray, T: np.ndarray, p: np.ndarray, codegen=False) -> dict:
    """The model's named outputs at the samples: Y (n_y, n_t), T (n_t,) -> {name: (n_t, ...)}."""
    fo = model.functions(codegen).outputs
    n_t = Y.shape[1]
    cache = model._cache.setdefault("output_maps", OrderedDict())
    key = (id(fo), n_t)
    mapped = cache.get(key)
    if mapped is None:
        mapped = cache[key] = FastCall(fo.map(n_t))
        if len(cache) > 16:
            cache.popitem(last=False)
    res = mapped(np.asarray(Y, dtype=float).T, T, p)
    out = {}
    for i, name in enumerate(fo.name_out()):
        r, c = fo.size_out(i)
        a = res[i].reshape(n_t * c, r).T.reshape(r, n_t, c).transpose(1, 0, 2)
        out[name] = a.reshape(n_t) if r == c == 1 else a.reshape(n_t, r * c)
    return out


# ----------------------------------------------------------------------------- driver

def _check_positive(name, value, unit):
    try:
        v = float(value)
    except (TypeError, ValueError):
        v = float("nan")
    if not (math.isfinite(v) and v > 0.0):
        raise SymcableError(f"{name} = {value!r} {unit}: must be a finite number > 0")
    return v


def _bad_state(Y: np.ndarray, inv_scale: np.ndarray) -> np.ndarray:
    """Per column: not finite, or beyond BLOWUP times the state scale."""
    with np.errstate(invalid="ignore", over="ignore"):
        big = np.abs(Y) * inv_scale[:, None]
        return ~np.all(np.isfinite(big) & (big <= BLOWUP), axis=0)


def simulate(scene, duration: float, dt: float | None = None, method: str = "generalized-alpha", *,
             rho_inf: float = 0.5, save_every: int | None = None, save_times=None,
             progress: bool | None = None, model=None, params=None,
             newton_tol: float | None = None, codegen: bool | None = None,
             started: float | None = None) -> Trajectory:
    """Time response of a line from rest at t = 0 (where its excitation starts), for a
    dynamic model already built; :func:`symcable.simulate` builds it from a scene.

    Parameters
    ----------
    scene : Scene, dict or path, optional
        Anything :func:`symcable.load_scene` takes, for the result's name (None: the name
        of the scene the model was built for).
    duration : float
        Simulated time, s.
    dt : float, optional
        Time step, s, shortened when needed so that a whole number of steps fills
        ``duration`` (``stats['dt_requested']`` keeps the value asked for). Default:
        generalized-α ``period / 100`` (``duration / 100`` when nothing moves); RK4 0.8 times
        its stability limit (:func:`rk4_stability_limit`), at most that same value.
    method : {"generalized-alpha", "rk4"}
        Implicit generalized-α (second order, A-stable, numerical damping set by
        ``rho_inf``) or explicit classical RK4 (fourth order, stable only below its limit).
    rho_inf : float
        Generalized-α spectral radius at infinite step, in [0, 1].
    save_every : int, optional
        Save every this many steps (and the last step). Default: every step when there are
        fewer than 2000 steps, else about 2000 evenly spaced samples.
    save_times : array_like, optional
        Times to save, s, each rounded to the nearest step (no interpolation); the run
        stops at the last of them.
    progress : bool, optional
        A progress bar on stderr: True always, False never, None only for a run expected to
        take over 2 s with stderr a terminal.
    model : DynamicModel
        The model to integrate (:func:`symcable.build_dynamic_model`).
    params : array_like (n_p,), optional
        Parameter vector replacing ``model.p_value``, e.g. ``model.with_params(amp_b=[0, 0])``.
    newton_tol : float, optional
        Generalized-α Newton tolerance on the max-norm of the step residual times
        dt / y_scale, or of the last Newton correction of y_{n+1} over y_scale (default 1e-10).
    codegen : bool, optional
        Run the step in generated C (compiled once per model structure and method, then
        loaded from the build cache); the loop over steps runs inside CasADi's ``mapaccum``,
        never in Python. Default None: generated C when a C compiler is found (see
        :mod:`symcable.codegen`); True without a compiler warns once and uses the virtual
        machine. Results agree with the virtual machine's to round-off.
    started : float, optional
        ``time.perf_counter()`` when the caller began (:func:`symcable.simulate`, which
        builds the model first): ``stats["wall_time"]`` counts from it.

    Returns
    -------
    Trajectory
        ``status`` "converged"; "invalid" with a warning when the total axial strain of a
        segment, or an end tension over its segment's EA, left the line type's
        ``max_strain`` (the dynamics linearised about the static state do not hold there:
        the numbers are not an answer); else "slack" with a warning when the total tension
        fell to zero somewhere (the linearised model is then invalid too).

    Raises
    ------
    SymcableError
        A bad argument (the message names it, its value and what is allowed).
    ConvergenceError
        A generalized-α step whose Newton iteration failed, or a state that blew up (RK4
        above its stability limit); ``partial`` is the Trajectory up to the last good step
        (status "failed"); ``diagnostics`` has ``reason`` ("newton", "blowup" or "error"),
        ``time`` (end of the failed step, s), ``time_last_good`` (s), ``step``, ``dt``, and
        ``residual`` (max |R| dt / y_scale at the last Newton iterate) or ``state_norm``
        (max |y| / y_scale reached).
    """
    wall0 = _time.perf_counter() if started is None else started
    meth = Method.parse(method)
    duration = _check_positive("duration", duration, "s")
    if scene is None and model is None:
        raise SymcableError("scene = None: give a scene, or a model to integrate")
    sc = load_scene(scene) if scene is not None else None
    if model is None:
        raise SymcableError("model = None: give the dynamic model to integrate "
                            "(symcable.simulate builds it from a scene)")
    scene_name = sc.name if sc is not None else getattr(model.info.get("scene"), "name", model.name)
    p = np.array(model.p_value if params is None else params, dtype=float).ravel()
    if p.shape != np.shape(model.p_value):
        raise SymcableError(f"params: length {p.size}: must have the model's {np.size(model.p_value)} "
                            "parameters (use model.with_params(...))")
    try:
        rho_inf = float(rho_inf)
    except (TypeError, ValueError):
        rho_inf = float("nan")
    if not 0.0 <= rho_inf <= 1.0:
        raise SymcableError(f"rho_inf = {rho_inf!r}: must be in [0, 1]")
    tol = NEWTON_TOL if newton_tol is None else _check_positive("newton_tol", newton_tol, "")

    stats: dict = {"method": meth.value}
    default_dt = (model.period / 100.0) if model.period else duration / 100.0
    if meth is Method.RK4:
        stats["dt_stable"] = rk4_stability_limit(model, p)
        if dt is None:
            dt = min(0.8 * stats["dt_stable"], default_dt)
    elif dt is None:
        dt = default_dt
    dt_req = _check_positive("dt", dt, "s")
    n_steps = max(1, math.ceil(duration / dt_req * (1.0 - 1e-12)))
    dt = duration / n_steps
    idx = _save_indices(n_steps, dt, duration, save_every, save_times)
    stats.update(dt=dt, dt_requested=dt_req, newton_tol=tol if meth is Method.GENERALIZED_ALPHA else None)
    if meth is Method.GENERALIZED_ALPHA:
        am, af, gamma = ga_coefficients(rho_inf)
        stats.update(rho_inf=rho_inf, alpha_m=am, alpha_f=af, gamma=gamma)
    step = step_function(model, meth, codegen)
    stats["compiled"] = bool(step.is_a("External"))
    settings = np.array([rho_inf, tol])

    f = model.functions()
    y = np.array(model.y0, dtype=float)
    yd = np.array(f.rhs(y, 0.0, p).full()).ravel()
    y_scale = np.asarray(model.y_scale, dtype=float)
    inv_scale = 1.0 / y_scale
    saved_y, saved_k = ([y.copy()], [0]) if idx[0] == 0 else ([], [])
    k = 0
    iters, iters_max, step_time = 0, 0, 0.0
    sec_per_step = None
    failure = None
    wanted = idx
    idx = _with_checkpoints(idx)
    bar = ProgressBar(int(idx[-1]), progress, label=f"simulate {meth.value}")
    try:
        for S, count in _runs(idx):
            while count > 0 and failure is None:
                m = 1 if sec_per_step is None else max(1, int(_CALL_TARGET / (S * sec_per_step)))
                m = min(count, 1 << (m.bit_length() - 1))  # a power of two: few distinct batches
                batch = _batch(model, step, S, m)
                t0 = _time.perf_counter()
                try:
                    Y, YD, K, IT, ITM, FAIL, _ = batch(y, yd, k, 0.0, dt, p, y_scale, settings)
                    Y, YD = Y.reshape(m, -1).T, YD.reshape(m, -1).T
                    bad = ((FAIL.ravel() > 0) | _bad_state(Y, inv_scale)
                           | ~np.all(np.isfinite(YD), axis=0))
                    n_good = int(np.argmax(bad)) if np.any(bad) else m
                except RuntimeError:  # e.g. a singular Newton matrix: locate it step by step
                    n_good = 0
                elapsed = _time.perf_counter() - t0
                step_time += elapsed
                if n_good:
                    saved_y.extend(Y[:, :n_good].T)
                    saved_k.extend(int(v) for v in K.ravel()[:n_good])
                    y, yd, k = Y[:, n_good - 1].copy(), YD[:, n_good - 1].copy(), int(K.ravel()[n_good - 1])
                    iters += int(np.sum(IT.ravel()[:n_good]))
                    iters_max = max(iters_max, int(np.max(ITM.ravel()[:n_good])))
                if n_good < m:
                    failure, y, yd, k, extra, it_good = _replay(step, y, yd, k, dt, p, y_scale, settings,
                                                                (m - n_good) * S, set(idx.tolist()))
                    for kk, yy in extra:
                        saved_y.append(yy)
                        saved_k.append(kk)
                    iters += it_good
                    if failure is None:  # no step failed when replayed (not expected)
                        count -= m
                        continue
                    break
                count -= m
                sec_per_step = elapsed / (S * m)
                bar.update(k)
            if failure is not None:
                break
    finally:
        bar.close()

    stats.update(steps=k, newton_iterations=iters if meth is Method.GENERALIZED_ALPHA else None,
                 newton_iterations_max=iters_max if meth is Method.GENERALIZED_ALPHA else None,
                 step_time=step_time, us_per_step=1e6 * step_time / max(k, 1), samples=len(saved_k))
    keep = set(wanted.tolist())
    chosen = [i for i, kk in enumerate(saved_k) if kk in keep]
    saved_y, saved_k = [saved_y[i] for i in chosen], [saved_k[i] for i in chosen]
    if failure is not None and (not saved_k or saved_k[-1] != k):
        saved_y.append(y.copy())
        saved_k.append(k)
    stats["samples"] = len(saved_k)
    Ymat = np.array(saved_y).T
    times = np.array(saved_k, dtype=float) * duration / n_steps  # k dt to within one ulp
    outputs = _outputs(model, Ymat, times, p, stats["compiled"])
    stats["wall_time"] = _time.perf_counter() - wall0
    traj = Trajectory.from_outputs(model, scene_name=scene_name, time=times, states=Ymat.T,
                                   outputs=outputs, method=meth.value, dt=dt,
                                   status="failed" if failure is not None else "converged", stats=stats)
    if failure is not None:
        failure.update(dt=dt, method=meth.value)
        z = failure.pop("_ydot_next", None)
        if meth is Method.GENERALIZED_ALPHA and z is not None:
            r = np.array(ga_residual_function(model, rho_inf)(z, y, yd, k * dt, dt, p)[0].full()).ravel()
            with np.errstate(invalid="ignore", over="ignore"):
                failure["residual"] = float(np.max(np.abs(r) * dt * inv_scale))
        if failure["reason"] == "newton":
            msg = (f"{meth.value}: Newton did not converge in {NEWTON_MAX_ITER} iterations in the "
                   f"step from t = {failure['time_last_good']:.6g} to {failure['time']:.6g} s "
                   f"(scaled residual {failure['residual']:.3g}, tolerance {tol:.3g}): try a smaller dt")
        else:
            msg = (f"{meth.value}: the state blew up (not finite, or beyond {BLOWUP:g} times "
                   f"y_scale) in the step to t = {failure['time']:.6g} s with dt = {dt:.6g} s")
            if failure["reason"] == "error":
                msg = (f"{meth.value}: the step from t = {failure['time_last_good']:.6g} s failed "
                       f"({failure['message']})")
            if meth is Method.RK4:
                msg += (f"; RK4 is stable here only for dt < {stats['dt_stable']:.4g} s: use a "
                        "smaller dt or method='generalized-alpha'")
        raise ConvergenceError(msg, partial=traj, diagnostics=failure)
    return traj


def _replay(step, y, yd, k, dt, p, y_scale, settings, n_max, save_set):
    """Step one at a time from a good state to find the first bad step.

    Returns ``(failure or None, y, ydot, k, saved, iterations)`` where ``y, ydot, k`` is the
    last good step, ``saved`` the (k, y) of saved indices passed on the way, ``iterations``
    the Newton iterations of the good steps, and ``failure`` the diagnostics of the bad step
    (``time`` s, ``time_last_good`` s, ``step``, ``reason``: "newton", "blowup" or "error";
    for "newton" ``newton_iterations`` and ``newton_correction`` (the last correction of
    y_{n+1} over y_scale; the caller adds ``residual``); for "blowup" ``state_norm``, the
    largest |y| / y_scale reached)."""
    saved, good_iters = [], 0
    inv_scale = 1.0 / y_scale
    for _ in range(n_max):
        diag = {"time_last_good": k * dt, "time": (k + 1) * dt, "step": k + 1}
        try:
            yn, ydn, kn, it, fail, meas = (np.array(v.full()).ravel() for v in step(y, yd, k, 0.0, dt, p, y_scale, settings))
        except RuntimeError as exc:
            diag.update(reason="error", message=str(exc).strip().splitlines()[-1], residual=float("nan"))
            return diag, y, yd, k, saved, good_iters
        bad_state = bool(_bad_state(yn[:, None], inv_scale)[0] or not np.all(np.isfinite(ydn)))
        if bad_state:
            with np.errstate(invalid="ignore", over="ignore"):
                diag.update(reason="blowup", state_norm=float(np.max(np.abs(yn) * inv_scale)))
            return diag, y, yd, k, saved, good_iters
        if fail[0] > 0:
            diag.update(reason="newton", newton_iterations=int(it[0]), newton_correction=float(meas[0]),
                        residual=float("nan"), _ydot_next=ydn)
            return diag, y, yd, k, saved, good_iters
        y, yd, k = yn, ydn, int(kn[0])
        good_iters += int(it[0])
        if k in save_set:
            saved.append((k, y.copy()))
    return None, y, yd, k, saved, good_iters
