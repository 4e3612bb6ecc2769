"""The planar generalized-α step on a DynamicModel, kept only for the planar shooting solver
(:mod:`symcable.solvers.shooting`) until it moves onto the generic period map; ``simulate``
runs on :mod:`symcable.solvers.galpha1` through :func:`symcable.integrate`.

What remains: :func:`step_function` (the generalized-α step, first order on dy/dt = f(y, t;
p), Jansen, Whiting & Hulbert 2000, its Newton loop unrolled with chord iterations on a
block LU written out in SX), :func:`_batch` (mapaccum batches of it) and NEWTON_TOL.
"""
from __future__ import annotations

import math
from collections import OrderedDict

import casadi as ca
import numpy as np

from ..codegen import compile_functions, graph_size, use_codegen
from ..errors import SymcableError
from ..functions import FastCall
from ..linalg.sparse import jacobian as _jacobian, sparse_solve
from ..linalg.sxlu import block_lu, block_plan

__all__ = ["NEWTON_TOL", "step_function"]

#: Newton iterations per generalized-α step before the step counts as failed.
NEWTON_MAX_ITER = 10
#: iterations of a generalized-α step that reuse the matrix factorised at its start
CHORD_ITERATIONS = 4
#: Default Newton tolerance on the scaled residual and step.
NEWTON_TOL = 1e-10

# The step Function's signature:
#   (y, ydot, k, t0, dt, p, y_scale, settings)
#       -> (y_next, ydot_next, k + 1, newton_iterations, failed, measure)
# with t_n = t0 + k dt (k counts steps exactly in floating point) and
# settings = [rho_inf, newton_tol]; ``measure`` is the accepted Newton convergence measure. Everything
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


def _ga_coefficients_sym(rho):
    am = 0.5 * (3.0 - rho) / (1.0 + rho)
    af = 1.0 / (1.0 + rho)
    return am, af, 0.5 + am - af


def _ga_residual(model, z, y, yd, t, dt, p, rho):
    am, af, gamma = _ga_coefficients_sym(rho)
    y_next = y + dt * yd + gamma * dt * (z - yd)
    return yd + am * (z - yd) - model.functions().rhs(y + af * (y_next - y), t + af * dt, p)


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


def step_function(model, method="generalized-alpha", codegen: bool | None = False) -> ca.Function:
    """The generalized-α step Function of ``model`` (signature in the comment above), run by
    the virtual machine or compiled (``codegen``, see :func:`symcable.codegen.use_codegen`);
    built once per model."""
    if method != "generalized-alpha":
        raise SymcableError(f"method = {method!r}: must be 'generalized-alpha'")
    key = ("step", "generalized-alpha")
    vm = model._cache.get(key)
    if vm is None:
        vm = model._cache[key] = _ga_step(model, NEWTON_MAX_ITER)
    key = ("compiled_step", vm.name())

    def size():  # by default C only where the step is written out (block LU, small graph)
        if model.n_y > SXLU_MAX_STATES:
            return math.inf
        if ("graph_size", vm.name()) not in model._cache:
            model._cache[("graph_size", vm.name())] = graph_size([vm])
        return model._cache[("graph_size", vm.name())]
    if not use_codegen(codegen, size):
        return vm
    if key not in model._cache:
        model._cache[key] = compile_functions([vm], what="the generalized-α step")[vm.name()]
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
