"""The fused static Newton solve of any Mechanism, built once and run by the CasADi virtual
machine or compiled to C (:mod:`symcable.codegen`).

``static_solve(x0, p, tol) -> (x, iterations, residual_norm, outputs)`` runs up to
:data:`SOLVE_MAX_ITER` plain Newton iterations on the static residual ``R(x; p)``,
``x = (q, z)`` (:attr:`symcable.derive.MechanismFunctions.static_residual`), in one call:
an iteration is skipped once ``max |R| <= tol`` (CasADi evaluates only the branch an
``if_else`` of Functions takes), and the loop is unrolled, so the code generator writes it
out (CasADi's rootfinder it cannot). The residual is carried from one iteration to the next:
each costs one Jacobian and one factorisation. Each Newton step is

* the block LU of :mod:`symcable.linalg.sxlu` written out in SX, when the system has at most
  :data:`SXLU_MAX_UNKNOWNS` unknowns and the Jacobian's pattern has a fixed elimination order
  (:func:`~symcable.linalg.sxlu.block_plan`: natural 2 x 2 or 1 x 1 blocks, else a matched
  block order; the unknowns keep the Mechanism's order, which formulations interleave node by
  node so the Jacobian is banded: the planar statics' order is the one the plan was tuned on);
* else the sparse QR of :func:`symcable.linalg.sparse.sparse_solve` (CasADi orders its columns
  by an approximate minimum degree of ``J^T J``, a fill-reducing order; dense rows split off).

The written-out LU pays only when compiled: its construction and its C grow faster than the
system, while the sparse QR costs O(n) to build and about as much per solve in the virtual
machine (crossover measured in ``studies/performance/scaling.py``). By default
(``codegen=None``) the solve is compiled where the written-out LU is used and its graph is
small enough to compile in seconds (:func:`symcable.codegen.use_codegen`).

The outputs come packed in one vector, the Mechanism's named outputs at ``(q, v = 0, z,
t = 0; p)`` in the order of :meth:`~symcable.derive.MechanismFunctions.unpack`. No solver
should trust the returned state without checking it (``solve_equilibrium`` does).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import casadi as ca

from . import codegen as _codegen
from .codegen import FastCall
from .linalg.sparse import sparse_solve
from .linalg.sxlu import block_lu, block_plan

__all__ = ["LINSOL", "SOLVE_MAX_ITER", "SXLU_MAX_UNKNOWNS", "StaticSolver", "static_solver"]

#: Newton iterations of the fused static solve (plain Newton from a good start converges in
#: a handful of steps or not at all; a damped Newton takes over when it does not)
SOLVE_MAX_ITER = 12
#: CasADi's sparse QR: it generates C (CSparse's LU does not) and, on the planar statics,
#: is as fast as CSparse in the virtual machine (140 against 162 us per solve on OC3)
LINSOL = "qr"
#: largest system (unknowns) whose Newton step is the block LU written out in SX; above
#: it, the sparse QR (see the module docstring)
SXLU_MAX_UNKNOWNS = 400


@dataclass(frozen=True)
class StaticSolver:
    """The Functions of a Mechanism's static solve (every one of ``(x, p)``, x = (q, z)).

    Attributes
    ----------
    residual : casadi.Function  ``<name>_static_residual(x, p) -> r``, N
    step : casadi.Function      ``<name>_static_step(x, p) -> (r, dx)``, dx = -J^-1 r by
        sparse QR: one call per iteration of a damped Newton
    solve : casadi.Function     ``<name>_static_solve(x0, p, tol) -> (x, iterations,
        residual_norm, outputs)``, the fused plain Newton of the module docstring
        (``tol`` and ``residual_norm`` max-norms of R, N)
    outputs : casadi.Function   ``<name>_static_outputs(x, p) -> y``, the named outputs at
        rest, packed as ``solve``'s
    compiled : bool             True when the four are generated C
    """

    residual: ca.Function
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


def _sym(like, name: str, n: int):
    return (ca.MX if isinstance(like, ca.MX) else ca.SX).sym(name, n)


def _newton_update(F, n: int, n_p: int) -> ca.Function:
    """``<name>_static_newton_update(x, p, r) -> dx = -J(x)^-1 r`` (r the residual at x,
    already known): the written-out block LU when it applies (module docstring), else the
    sparse-QR step (which evaluates r itself)."""
    m = F.mech
    name = f"{m.name}_static_newton_update"
    if isinstance(m.q, ca.SX) and n <= SXLU_MAX_UNKNOWNS:
        x, p = ca.SX.sym("x", n), ca.SX.sym("p", n_p)
        r_expr = F.static_residual(x, p)
        J = ca.jacobian(r_expr, x)
        plan = block_plan(J.sparsity())
        if plan is not None:
            lu = block_lu(J.sparsity(), *plan)
            r = ca.SX.sym("r", n)
            return ca.Function(name, [x, p, r], [-lu.solve(J, r)], ["x", "p", "r"], ["dx"],
                               {"cse": True})
    X, P, R = ca.MX.sym("x", n), ca.MX.sym("p", n_p), ca.MX.sym("r", n)
    return ca.Function(name, [X, P, R], [F.static_step(X, P)[1]], ["x", "p", "r"], ["dx"])


def _outputs(F) -> ca.Function:
    """``<name>_static_outputs(x, p) -> y``: the stacked outputs at v = 0, t = 0."""
    m = F.mech
    y = F.outputs(m.q, ca.DM.zeros(m.n_v), m.z, 0.0, m.p)
    x = ca.vertcat(m.q, m.z)
    return ca.Function(f"{m.name}_static_outputs", [x, m.p], [y], ["x", "p"], ["y"])


def _vm(F) -> StaticSolver:
    m = F.mech
    n, n_p = m.n_q + m.n_z, m.params.n
    residual, step = F.static_residual, F.static_step
    outputs = _outputs(F)
    update = _newton_update(F, n, n_p)

    # one plain Newton iteration, skipped once converged, unrolled SOLVE_MAX_ITER times
    P, tol = ca.MX.sym("p", n_p), ca.MX.sym("tol")
    x, rx, done, it = ca.MX.sym("x", n), ca.MX.sym("r", n), ca.MX.sym("done"), ca.MX.sym("it")
    conv = ca.norm_inf(rx) <= tol
    x_new = x + update(x, P, rx)
    args, names_in = [x, rx, done, it, P, tol], ["x", "r", "done", "it", "p", "tol"]
    names_out = ["x_out", "r_out", "done_out", "it_out"]
    iterate = ca.Function.if_else(
        f"{m.name}_static_newton_step_or_stop",
        ca.Function(f"{m.name}_static_newton_stop", args, [x, rx, conv, it], names_in, names_out),
        ca.Function(f"{m.name}_static_newton_iteration", args,
                    [x_new, residual(x_new, P), conv, it + 1], names_in, names_out))
    iterate = ca.Function(f"{m.name}_static_newton_checked", args, iterate(conv, *args),
                          names_in, names_out)
    skip = ca.Function(f"{m.name}_static_newton_skip", args, [x, rx, done, it], names_in,
                       names_out)
    body = ca.Function.if_else(f"{m.name}_static_newton_body", skip, iterate)
    X0 = ca.MX.sym("x0", n)
    z, r, d, k = X0, residual(X0, P), ca.MX(0), ca.MX(0)
    for _ in range(SOLVE_MAX_ITER):
        z, r, d, k = body(d, z, r, d, k, P, tol)
    solve = ca.Function(f"{m.name}_static_solve", [X0, P, tol],
                        [z, k, ca.norm_inf(r), outputs(z, P)],
                        ["x0", "p", "tol"], ["x", "iterations", "residual_norm", "outputs"])
    return StaticSolver(residual=residual, step=step, solve=solve, outputs=outputs)


def static_solver(F, codegen: bool | None = False) -> StaticSolver:
    """The :class:`StaticSolver` of the Mechanism of ``F`` (its
    :class:`~symcable.derive.MechanismFunctions`), built once and kept on ``F``: the virtual
    machine's, or generated C when ``codegen`` resolves to True
    (:func:`symcable.codegen.use_codegen`; ``None`` compiles only a system of at most
    :data:`SXLU_MAX_UNKNOWNS` unknowns, whose Newton step is the written-out block LU, and
    whose graph is small enough). Raises SymcableError for a ``codegen`` that is not a bool
    or None."""
    store = F.__dict__.get("_static_solver")
    if store is None:
        store = F.__dict__["_static_solver"] = {"vm": _vm(F)}
    vm = store["vm"]
    if codegen is False:
        return vm
    if not _codegen.use_codegen(codegen, lambda: _size(F, store)):
        return vm
    c = store.get("c")
    if c is None:
        group = [vm.residual, vm.step, vm.solve, vm.outputs]
        lib = _codegen.compile_functions(group, what="the static solve")
        c = store["c"] = StaticSolver(*(lib[f.name()] for f in group), compiled=True)
    return c


def _size(F, store) -> float:
    """What the default ``codegen=None`` weighs: the graph size of the four Functions, or
    infinity above SXLU_MAX_UNKNOWNS (with a sparse QR the time is the factorisation,
    compiled code in the virtual machine as well); computed once."""
    if "size" not in store:
        vm = store["vm"]
        store["size"] = (math.inf if F.mech.n_q + F.mech.n_z > SXLU_MAX_UNKNOWNS else
                         _codegen.graph_size([vm.residual, vm.step, vm.solve, vm.outputs]))
    return store["size"]
