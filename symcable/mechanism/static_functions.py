"""The fused static Newton solve of any Mechanism, built once and run by the CasADi virtual
machine or compiled to C (:mod:`symcable.mechanism.codegen`).

``static_solve(x0, p, tol) -> (x, iterations, residual_norm, outputs)`` runs up to
:data:`SOLVE_MAX_ITER` plain Newton iterations on the static residual ``R(x; p)``,
``x = (q, z)`` (:attr:`symcable.mechanism.functions.MechanismFunctions.static_residual`), in one call:
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
  by an approximate minimum degree of ``J^T J``, a fill-reducing order; dense rows split off),
  of J evaluated alone (the residual at x is already known).

The written-out LU pays only when compiled: its construction and its C grow faster than the
system, while the sparse QR costs O(n) to build and about as much per solve in the virtual
machine (hence :data:`SXLU_MAX_UNKNOWNS`). By default
(``codegen=None``) the solve is compiled where the written-out LU is used and its graph is
small enough to compile in seconds (:func:`symcable.mechanism.codegen.use_codegen`).

The outputs come packed in one vector, the Mechanism's named outputs at ``(q, v = 0, z,
t = 0; p)`` in the order of :meth:`~symcable.mechanism.functions.MechanismFunctions.unpack`. No solver
should trust the returned state without checking it (``solve_equilibrium`` does).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import casadi as ca
import numpy as np

from . import background_build, codegen as _codegen
from .bounds import bound_margins
from .codegen import FastCall
from ..linalg.sparse import norm_inf, sparse_solve
from ..linalg.sxlu import block_lu, block_plan

__all__ = ["LINSOL", "SOLVE_MAX_ITER", "SXLU_MAX_UNKNOWNS", "StaticSolver", "static_solver"]

#: Newton iterations of the fused static solve (plain Newton from a good start converges in
#: a handful of steps or not at all; a damped Newton takes over when it does not)
SOLVE_MAX_ITER = 12
#: CasADi's sparse QR: it generates C (CSparse's LU does not) and, on the planar statics,
#: is as fast as CSparse in the virtual machine
LINSOL = "qr"
#: largest system (unknowns) whose Newton step is the block LU written out in SX; above
#: it, the sparse QR (see the module docstring)
SXLU_MAX_UNKNOWNS = 400


@dataclass(frozen=True)
class StaticSolver:
    """The Functions of a Mechanism's static solve (every one of ``(x, p)``, x = (q, z)).

    Their names are the same for every Mechanism (one library per Mechanism, so they never
    meet).

    Attributes
    ----------
    residual : casadi.Function  ``static_residual(x, p) -> r``, N
    jacobian : casadi.Function  ``static_jacobian(x, p) -> (r, J)``, J sparse (always the
        virtual machine's: for checks, analysis and the exported C, not for the solve)
    step : casadi.Function      ``static_newton_step(x, p) -> (r, dx)``, dx = -J^-1 r by
        sparse QR: one call per iteration of a damped Newton
    solve : casadi.Function     ``static_solve(x0, p, tol) -> (x, iterations, residual_norm,
        outputs)``, the fused plain Newton of the module docstring (``tol`` and
        ``residual_norm`` max-norms of R, N; ``outputs`` every output packed, see
        :meth:`~symcable.mechanism.functions.MechanismFunctions.unpack`)
    outputs : casadi.Function   ``static_outputs(x, p) -> (one output per named output of
        the Mechanism)`` at rest (v = 0, t = 0)
    check : casadi.Function     ``static_check(x, p, b) -> (residual_norm, probe,
        bound_margin)``: max |R(x)| (N) evaluated afresh, ``probe = sum(x) + sum(R)``, finite
        exactly when x and R are (CasADi's max-norm passes over a NaN; a sum does not), and
        the admissibility bounds' worst margin (scales; inf without bounds) for their limits
        ``b`` (:func:`~symcable.mechanism.functions.bound_numbers`), for a solver's
        independent check of a claimed solution in one call
    compiled : bool             True when residual, step, solve, outputs and check are
        generated C
    """

    residual: ca.Function
    jacobian: ca.Function
    step: ca.Function
    solve: ca.Function
    outputs: ca.Function
    check: ca.Function
    compiled: bool = False

    def group(self) -> list:
        """The Functions compiled together (one library)."""
        return [self.residual, self.step, self.solve, self.outputs, self.check]

    def fast(self, name: str) -> FastCall:
        """A buffered caller of one of the Functions (built once)."""
        cache = self.__dict__.setdefault("_fast", {})
        if name not in cache:
            cache[name] = FastCall(getattr(self, name))
        return cache[name]

    def packed_outputs(self, x, p) -> np.ndarray:
        """Every output at ``x`` packed as ``solve`` packs them, (n_y,)."""
        out = self.fast("outputs")(x, p)
        return np.concatenate(out) if out else np.zeros(0)


def _newton_update(m, x, p, J) -> ca.Function:
    """``static_newton_update(x, p, r) -> dx = -J(x)^-1 r`` (r the residual at x, already
    known): the written-out block LU when it applies (module docstring), else the sparse QR
    of J alone (``static_jacobian_only``: a quarter fewer operations than J with r)."""
    n = m.n_q + m.n_z
    plan = block_plan(J.sparsity()) if isinstance(J, ca.SX) and n <= SXLU_MAX_UNKNOWNS else None
    if plan is not None:
        lu = block_lu(J.sparsity(), *plan)
        r = ca.SX.sym("r", n)
        return ca.Function("static_newton_update", [x, p, r], [-lu.solve(J, r)],
                           ["x", "p", "r"], ["dx"], {"cse": True})
    jac = ca.Function("static_jacobian_only", [x, p], [J], ["x", "p"], ["J"])
    X, P, R = ca.MX.sym("x", n), ca.MX.sym("p", m.params.n), ca.MX.sym("r", n)
    return ca.Function("static_newton_update", [X, P, R], [-sparse_solve(jac(X, P), R, LINSOL)],
                       ["x", "p", "r"], ["dx"])


def _vm(F) -> StaticSolver:
    m = F.mech
    n, n_p = m.n_q + m.n_z, m.params.n
    # the static residual as an expression of fresh symbols (v = 0 and t = 0 substituted)
    x = ca.vertcat(m.q, m.z)
    r = F.static_expr()
    # common subexpressions (a segment's cos and sin, built by two terms) merged where the
    # system is small: same values, fewer operations; above SXLU_MAX_UNKNOWNS the merge
    # itself costs more than it saves (seconds at 2000 segments)
    opts = {"cse": True} if n <= SXLU_MAX_UNKNOWNS else {}
    residual = ca.Function("static_residual", [x, m.p], [r], ["x", "p"], ["r"], opts)
    J = ca.jacobian(r, x)
    jacobian = ca.Function("static_jacobian", [x, m.p], [r, J], ["x", "p"], ["r", "J"], opts)
    names = list(m.outputs)
    # dense: an output with structural zeros at rest (a friction force's components on a
    # node the substitution makes exactly zero) would otherwise come packed without them,
    # and the unpacking by shapes would misalign every later output (an IndexError on a
    # MoorDyn deck with a harmonic vessel motion)
    at_rest = ca.substitute([m.outputs[k].expr for k in names], [m.v, m.t],
                            [ca.DM.zeros(m.n_v), ca.DM(0.0)]) if names else []
    exprs = [ca.densify(e) for e in at_rest]
    # the outputs keep their names (an output may be called "x" or "p" too)
    outputs = ca.Function("static_outputs", [x, m.p], exprs, ["x", "p"], names,
                          {**opts, "allow_duplicate_io_names": True})
    # the same residual and Jacobian serve F's own (one symbolic differentiation, not two:
    # the Jacobian of a long line is most of the build)
    F.__dict__.setdefault("static_residual", residual)
    F.__dict__.setdefault("static_jacobian", jacobian)
    W, P = ca.MX.sym("x", n), ca.MX.sym("p", n_p)
    rm, Jm = jacobian(W, P)
    step = ca.Function("static_newton_step", [W, P], [rm, -sparse_solve(Jm, rm, LINSOL)],
                       ["x", "p"], ["r", "dx"])
    update = _newton_update(m, x, m.p, J)

    # one plain Newton iteration, skipped once converged (CasADi evaluates only the branch
    # an if_else of Functions takes), unrolled SOLVE_MAX_ITER times; the residual is carried
    # from one iteration to the next, so each costs one residual and one factorisation
    tol = ca.MX.sym("tol")
    z, rz, done, it = ca.MX.sym("x", n), ca.MX.sym("r", n), ca.MX.sym("done"), ca.MX.sym("it")
    conv = norm_inf(rz) <= tol
    z_new = z + update(z, P, rz)
    args, names_in = [z, rz, done, it, P, tol], ["x", "r", "done", "it", "p", "tol"]
    names_out = ["x_out", "r_out", "done_out", "it_out"]
    iterate = ca.Function.if_else(
        "static_newton_step_or_stop",
        ca.Function("static_newton_stop", args, [z, rz, conv, it], names_in, names_out),
        ca.Function("static_newton_iteration", args, [z_new, residual(z_new, P), conv, it + 1],
                    names_in, names_out))
    iterate = ca.Function("static_newton_checked", args, iterate(conv, *args), names_in,
                          names_out)
    skip = ca.Function("static_newton_skip", args, [z, rz, done, it], names_in, names_out)
    body = ca.Function.if_else("static_newton_body", skip, iterate)
    X0 = ca.MX.sym("x0", n)
    z, rz, d, k = X0, residual(X0, P), ca.MX(0), ca.MX(0)
    for _ in range(SOLVE_MAX_ITER):
        z, rz, d, k = body(d, z, rz, d, k, P, tol)
    outs = outputs.call([z, P])
    packed = ca.vertcat(*[ca.vec(o) for o in outs]) if outs else ca.MX(0, 1)
    solve = ca.Function("static_solve", [X0, P, tol], [z, k, norm_inf(rz), packed],
                        ["x0", "p", "tol"], ["x", "iterations", "residual_norm", "outputs"])
    # the admissibility bounds' worst margin at the same point (inf without bounds), their
    # limits an input (numbers of the scene: :func:`~.functions.bound_numbers`)
    values = F.bound_values(m.q, ca.DM.zeros(m.n_v), m.z, 0.0, m.p)
    b = ca.SX.sym("b", 3 * int(values.numel()))
    worst = ca.mmin(bound_margins(b, values)) if values.numel() else ca.DM(np.inf)
    # (a 0 appended: a mechanism with no unknowns, one segment between held ends, still
    # gives scalars)
    r0 = ca.vertcat(r, 0.0)
    check = ca.Function("static_check", [x, m.p, b], [norm_inf(r0), ca.sum1(ca.vertcat(x, r0)),
                                                      worst],
                        ["x", "p", "b"], ["residual_norm", "probe", "bound_margin"], opts)
    return StaticSolver(residual=residual, jacobian=jacobian, step=step, solve=solve,
                        outputs=outputs, check=check)


def static_solver(F, codegen: bool | None = False) -> StaticSolver:
    """The :class:`StaticSolver` of the Mechanism of ``F`` (its
    :class:`~symcable.mechanism.functions.MechanismFunctions`), built once and kept on ``F``: the virtual
    machine's, or generated C when ``codegen`` resolves to True
    (:func:`symcable.mechanism.codegen.use_codegen`; ``None`` compiles only a system of at most
    :data:`SXLU_MAX_UNKNOWNS` unknowns, whose Newton step is the written-out block LU, and
    whose graph is small enough). Raises SymcableError for a ``codegen`` that is not a bool
    or None."""
    if not (codegen is None or isinstance(codegen, bool)):
        _codegen.use_codegen(codegen)  # refuses it, naming the value, before any build
    store = F.__dict__.get("_static_solver")
    if store is None:
        store = F.__dict__["_static_solver"] = {"vm": _vm(F)}
    vm = store["vm"]
    if codegen is False:
        return vm
    if not _codegen.use_codegen(codegen, lambda: _size(F, store)):
        return vm
    c = store.get("c")
    if c is not None:  # (a scene of the same structure compiled it: the library in memory)
        _codegen.build_counts["memory"] += 1
    elif not background_build.finished(store.get("pending", "")):
        return vm  # (its C is being compiled in the background)
    else:
        lib = _codegen.compile_functions(vm.group(), what="the static solve",
                                         wait=background_build.waits(codegen))
        if _codegen.last_build.get("action") == "background":
            store["pending"] = _codegen.last_build["key"]
            return vm
        c = store["c"] = StaticSolver(
            residual=lib["static_residual"], jacobian=vm.jacobian, step=lib["static_newton_step"],
            solve=lib["static_solve"], outputs=lib["static_outputs"], check=lib["static_check"],
            compiled=lib["static_solve"].is_a("External"))
    return c


def _size(F, store) -> float:
    """What the default ``codegen=None`` weighs: the graph size of the compiled group, or
    infinity above SXLU_MAX_UNKNOWNS (with a sparse QR the time is the factorisation,
    compiled code in the virtual machine as well); computed once."""
    if "size" not in store:
        vm = store["vm"]
        store["size"] = (math.inf if F.mech.n_q + F.mech.n_z > SXLU_MAX_UNKNOWNS else
                         _codegen.graph_size(vm.group(), _codegen.DEFAULT_MAX_SIZE))
    return store["size"]
