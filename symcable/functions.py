"""Turning a Model into named CasADi Functions, built once per model and reused, either
run by the CasADi virtual machine or compiled to C (:mod:`symcable.codegen`)."""
from __future__ import annotations

import math
from dataclasses import dataclass

import casadi as ca
import numpy as np

from . import codegen as _codegen
from .models.base import Model
from .linalg.sparse import sparse_solve
from .linalg.sxlu import block_lu, block_plan

#: Newton iterations of the fused static solve (plain Newton from a good start converges in
#: a handful of steps or not at all; a damped Newton takes over when it does not)
SOLVE_MAX_ITER = 12
#: CasADi's sparse QR: it generates C (CSparse's LU does not) and, on the planar statics,
#: is as fast as CSparse in the virtual machine (140 against 162 us per solve on OC3)
LINSOL = "qr"
#: largest system (unknowns) whose Newton step is the block LU written out in SX; above
#: it, the step is the sparse QR (its column order fill-reducing: CasADi's QR orders
#: the columns of J by an approximate minimum degree of J^T J). The written-out LU pays
#: only when compiled; its symbolic construction (the block order by matching, the
#: elimination in Python) and its C grow faster than the system, while a sparse QR costs
#: O(n) to build and about as much as the LU per solve in the virtual machine (crossover
#: measured in studies/performance/scaling.py and its README)
SXLU_MAX_UNKNOWNS = 400


class FastCall:
    """Call a Function with dense inputs and outputs through CasADi's buffer interface:
    NumPy arrays in, NumPy arrays out, no conversion to DM (about 40 us less per call).

    ``f(*args) -> tuple of ndarray (flat, in the output's column-major order)``; an input
    given with a divisor of its length (a mapped Function's input given for one instance)
    is repeated. Raises RuntimeError when the evaluation fails, as a Function call does.
    """

    def __init__(self, fn: ca.Function):
        self.fn = fn
        self._buf, self._eval = fn.buffer()
        self._in = [np.zeros(fn.nnz_in(i)) for i in range(fn.n_in())]
        self._out = [np.zeros(fn.nnz_out(i)) for i in range(fn.n_out())]
        for i, a in enumerate(self._in):
            self._buf.set_arg(i, memoryview(a))
        for i, a in enumerate(self._out):
            self._buf.set_res(i, memoryview(a))

    def __call__(self, *args) -> tuple:
        for a, v in zip(self._in, args):
            v = np.ravel(v) if np.ndim(v) else v
            if np.ndim(v) and v.size != a.size and v.size and a.size % v.size == 0:
                a.reshape(-1, v.size)[...] = v  # a mapped input given once: repeated
            else:
                a[...] = v
        self._eval()
        if self._buf.ret() != 0:
            raise RuntimeError(f"evaluation of {self.fn.name()} failed")
        return tuple(o.copy() for o in self._out)


@dataclass(frozen=True)
class StaticFunctions:
    """The static problem's functions (every one ``(w, p) -> ...``; w unknowns, p parameters).

    Attributes
    ----------
    residual : casadi.Function  ``static_residual(w, p) -> r`` (N)
    jacobian : casadi.Function  ``static_jacobian(w, p) -> (r, J)``; J sparse, N per unit of w
        (always the virtual machine's: for checks and analysis, not for the solve)
    step : casadi.Function      ``static_newton_step(w, p) -> (r, dw)``, dw = -J^-1 r by
        sparse QR, one call per Newton iteration (the damped Newton's step)
    solve : casadi.Function     ``static_solve(w0, p, tol) -> (w, iterations,
        residual_norm, outputs)``: up to SOLVE_MAX_ITER plain Newton steps (stopping once
        max |r| <= tol, N), each solved by the block LU of :mod:`symcable.linalg.sxlu`
        written out in SX (sparse QR when the pattern has no fixed elimination order), and
        every model output packed in one vector (see ``unpack``)
    outputs : casadi.Function   ``static_outputs(w, p) -> named outputs of the model``
    compiled : bool             True when residual, step, solve and outputs are generated C
    """

    residual: ca.Function
    jacobian: ca.Function
    step: ca.Function
    solve: ca.Function
    outputs: ca.Function
    compiled: bool = False

    def fast(self, name: str) -> FastCall:
        """A buffered caller of one of the Functions (built once)."""
        cache = self.__dict__.setdefault("_fast", {})
        if name not in cache:
            cache[name] = FastCall(getattr(self, name))
        return cache[name]

    def unpack(self, packed: np.ndarray) -> dict:
        """The named outputs from ``solve``'s packed vector: {name: ndarray of its shape}."""
        shapes = self.__dict__.get("_shapes")
        if shapes is None:
            fo = self.outputs
            shapes = self.__dict__["_shapes"] = [(name, fo.size_out(i)) for i, name in enumerate(fo.name_out())]
        out, k = {}, 0
        for name, (r, c) in shapes:
            out[name] = packed[k:k + r * c].reshape(c, r).T
            k += r * c
        return out


def _vm_static(model: Model) -> StaticFunctions:
    w, p, r = model.w, model.p, model.residual
    residual = ca.Function("static_residual", [w, p], [r], ["w", "p"], ["r"])
    J = ca.jacobian(r, w)
    jacobian = ca.Function("static_jacobian", [w, p], [r, J], ["w", "p"], ["r", "J"])
    names = list(model.outputs)
    outputs = ca.Function("static_outputs", [w, p], [model.outputs[k] for k in names],
                          ["w", "p"], names)
    n, n_p = model.n_w, int(p.numel())

    W, P = ca.MX.sym("w", n), ca.MX.sym("p", n_p)
    rm, Jm = jacobian(W, P)
    step = ca.Function("static_newton_step", [W, P], [rm, -sparse_solve(Jm, rm, LINSOL)],
                       ["w", "p"], ["r", "dw"])

    # one plain Newton iteration, skipped once converged (CasADi evaluates only the branch
    # taken by an if_else of Functions), unrolled SOLVE_MAX_ITER times: a loop that the code
    # generator can write out, unlike CasADi's rootfinder. The residual is carried from one
    # iteration to the next, so each costs one residual and one factorisation.
    update = _newton_update(model, J, step)
    z, rz, done, it = ca.MX.sym("w", n), ca.MX.sym("r", n), ca.MX.sym("done"), ca.MX.sym("it")
    tol = ca.MX.sym("tol")
    conv = ca.norm_inf(rz) <= tol
    z_new = z + update(z, P, rz)
    args, names_in = [z, rz, done, it, P, tol], ["w", "r", "done", "it", "p", "tol"]
    names_out = ["w_out", "r_out", "done_out", "it_out"]
    iterate = ca.Function.if_else(
        "static_newton_step_or_stop",
        ca.Function("static_newton_stop", args, [z, rz, conv, it], names_in, names_out),
        ca.Function("static_newton_iteration", args, [z_new, residual(z_new, P), conv, it + 1],
                    names_in, names_out))
    iterate = ca.Function("static_newton_checked", args, iterate(conv, *args), names_in, names_out)
    skip = ca.Function("static_newton_skip", args, [z, rz, done, it], names_in, names_out)
    body = ca.Function.if_else("static_newton_body", skip, iterate)
    W0 = ca.MX.sym("w0", n)
    z, r, d, k = W0, residual(W0, P), ca.MX(0), ca.MX(0)
    for _ in range(SOLVE_MAX_ITER):
        z, r, d, k = body(d, z, r, d, k, P, tol)
    packed = ca.vertcat(*[ca.vec(o) for o in outputs.call([z, P])])
    solve = ca.Function("static_solve", [W0, P, tol], [z, k, ca.norm_inf(r), packed],
                        ["w0", "p", "tol"], ["w", "iterations", "residual_norm", "outputs"])
    return StaticFunctions(residual=residual, jacobian=jacobian, step=step, solve=solve,
                           outputs=outputs)


def _newton_update(model: Model, J: ca.SX, step: ca.Function) -> ca.Function:
    """``static_newton_update(w, p, r) -> dw = -J(w)^-1 r`` (r the residual at w, already
    known), the fused solve's Newton step: the block LU of :mod:`symcable.linalg.sxlu`
    written out in SX when the system has at most SXLU_MAX_UNKNOWNS unknowns and the
    Jacobian's pattern allows a fixed elimination order, else ``step``'s (sparse QR, which
    evaluates r itself)."""
    w, p = model.w, model.p
    plan = block_plan(J.sparsity()) if model.n_w <= SXLU_MAX_UNKNOWNS else None
    if plan is not None:
        lu = block_lu(J.sparsity(), *plan, cache=model._cache)
        r = ca.SX.sym("r", model.n_w)
        return ca.Function("static_newton_update", [w, p, r], [-lu.solve(J, r)], ["w", "p", "r"],
                           ["dw"], {"cse": True})
    W, P, R = ca.MX.sym("w", model.n_w), ca.MX.sym("p", int(p.numel())), ca.MX.sym("r", model.n_w)
    return ca.Function("static_newton_update", [W, P, R], [step(W, P)[1]], ["w", "p", "r"], ["dw"])


def _size(model, name: str, functions) -> int:
    """:func:`symcable.codegen.graph_size` of a model's Functions, computed once."""
    key = ("graph_size", name)
    if key not in model._cache:
        model._cache[key] = _codegen.graph_size(functions)
    return model._cache[key]


def static_functions(model: Model, codegen: bool | None = False) -> StaticFunctions:
    """Build (once, then cached on the model) the named static functions of ``model``:
    run by the virtual machine, or compiled to C when ``codegen`` resolves to True
    (see :func:`symcable.codegen.use_codegen`; the default ``None`` compiles only a model
    of at most SXLU_MAX_UNKNOWNS unknowns, whose Newton step is the written-out block LU)."""
    vm = model._cache.get("static")
    if vm is None:
        vm = model._cache["static"] = _vm_static(model)
    group = [vm.residual, vm.step, vm.solve, vm.outputs]
    # by default C only where it pays: where the Newton step is the written-out block LU
    # (with a sparse QR the time is the factorisation, compiled code in the VM as well)
    # and the graph is small enough to compile in seconds
    if not _codegen.use_codegen(codegen, lambda: _size(model, "static", group)
                                if model.n_w <= SXLU_MAX_UNKNOWNS else math.inf):
        return vm
    c = model._cache.get("static_c")
    if c is None:
        lib = _codegen.compile_functions(group, what="the static solve")
        c = model._cache["static_c"] = StaticFunctions(
            residual=lib["static_residual"], jacobian=vm.jacobian, step=lib["static_newton_step"],
            solve=lib["static_solve"], outputs=lib["static_outputs"], compiled=True)
    return c
