"""First-order generalized-alpha (Jansen, Whiting & Hulbert 2000) on a Mechanism's DAE
residual F(y', y, t; p) = 0, y = (q, v), any kinematics:

    y1 = y0 + h y'0 + gamma h (y'1 - y'0)
    F(y'0 + alpha_m (y'1 - y'0), y0 + alpha_f (y1 - y0), t0 + alpha_f h; p) = 0,

alpha_m = (3 - rho_inf) / (2 (1 + rho_inf)), alpha_f = 1 / (1 + rho_inf),
gamma = 1/2 + alpha_m - alpha_f: second order, A-stable, high-frequency damping set by
rho_inf in [0, 1]. The unknown y'1 is found by Newton's method on the exact Jacobian
alpha_m dF/dy' + alpha_f gamma h dF/dy, in one of two ways (:class:`~.options.NewtonScheme`):

* ``"unrolled"`` (the default): one CasADi Function per step with the Newton loop unrolled
  ``max_iter`` times, a converged iteration switching the rest off (CasADi evaluates only
  the taken branch of a switch; each branch a Function of values computed once, so that
  the residual, its norm and the factorisation are evaluated once per iteration). The
  residual is SX (the Mechanism's expressions inlined); the iteration matrix is factorised
  at the start of the step and reused by the next iterations (chord iterations) up to
  CHORD_ITERATIONS while they cut the residual by CHORD_CONTRACTION at least, then
  refactorised at every iteration; an iterate whose residual grew takes NEWTON_DAMPING of
  its correction (a 2-cycle broken); it starts from the best of three predictors
  (:func:`_predictor`). The factorisation is the block LU of
  :mod:`symcable.linalg.sxlu` written out in SX, on the matrix permuted to a fill-reducing
  order (approximate minimum degree of its pattern: it depends on the pattern alone), for at
  most SXLU_MAX_STATES unknowns (up to SXLU_MAX_STATES_C when generated C is asked for
  explicitly, ``codegen=True``); above, the banded LU of :mod:`symcable.linalg.banded`
  (loops whose C compiles in seconds at any size; on the Schur complement of a leading
  block of 1 x 1 and 2 x 2 blocks, the kinematic rows and a friction bristle's, where that
  costs less: :func:`_banded`) where the matrix is banded in
  reverse Cuthill-McKee order (a line's nodes: BANDED_MAX_WIDTH), else CasADi's sparse QR
  (:func:`symcable.linalg.sparse.sparse_solve`). A Mechanism with an element form
  (:class:`~symcable.mechanism.element_form.ElementForm`: the cable3d line) of at least
  ELEMENT_MIN_STATES unknowns has its residual and matrix from loops over its elements
  instead (:mod:`symcable.solvers.element_jacobian`), factorised by the banded LU (a long
  line's written-out matrix is megabytes of C). Compiled to C through
  :mod:`symcable.mechanism.codegen` when asked (or, by default, when it pays). Its derivative with
  respect to the step's inputs is that of the iterations taken: near the exact one (the
  chord iterations contract fast) but not equal to it;
* ``"rootfinder"``: CasADi's Newton rootfinder with the exact Jacobian at every iteration;
  its derivative is the exact implicit-function one (for Newton on a period map), and it
  runs in the virtual machine only.

Convergence, both ways: the step residual scaled to a change of y over the step relative to
its scales (kinematic rows h |F| / scales.q, momentum rows h |F| / (m_i scales.v) with m_i
the diagonal of a constant mass matrix, else ``scales.mass``) at most ``tol`` in the
max-norm; the unrolled loop also accepts a last Newton correction of y1 at most ``tol`` of
its scales (the iterations contract fast, so the accepted iterate is far more accurate than
that correction).
"""
from __future__ import annotations

import dataclasses
import math
import warnings

import casadi as ca
import numpy as np

from ..mechanism.codegen import use_codegen
from ..mechanism.functions import functions
from ..errors import SymcableError
from ..linalg.sparse import jacobian as _jacobian, norm_inf, qr_solve
from ..mechanism.element_form import split_mismatch
from ..mechanism.mechanism import Mechanism
from .element_jacobian import (block_kernel, jacobian_inputs, jacobian_loop, residual_inputs,
                               residual_loop)
from .newton import best_start, best_start_residual
from .options import GeneralizedAlphaFirstOrder, NewtonScheme
from .stepcache import STEP_CACHE, maybe_compiled, structure_owner
from .step_solver import (BANDED_MAX_WIDTH, CSE_MAX_STATES, LINSOL, kernels_in_c,  # noqa: F401
                          linear_solver, linear_solver as _linear_solver)

__all__ = ["CHORD_ITERATIONS", "ELEMENT_MIN_STATES", "NEWTON_DAMPING", "SXLU_MAX_STATES",
           "SXLU_MAX_STATES_C", "coefficients", "galpha1_kernel", "galpha1_residual",
           "galpha1_step", "solver_choice", "step_parts", "step_scales"]

#: iterations of a step that reuse the matrix factorised at its start (chord iterations)
CHORD_ITERATIONS = 4
#: a chord iteration whose residual (scaled, max-norm) was not cut at least this much by
#: the last one refactorises instead: far from the solution (a long step after a violent
#: release) the start's matrix can send chord iterations off without bound, where Newton
#: with the current matrix converges
CHORD_CONTRACTION = 0.5
#: the share of its Newton correction an iteration takes when its iterate's residual (scaled,
#: max-norm) is larger than the last one's: a Newton iteration that cycles between two
#: iterates (a friction bristle's slip switching on and off across its smoothing speed)
#: converges in a few iterations with 0.5 (with 0.7 it can cycle on). It costs a few
#: iterations where a growing residual would have converged anyway (about 1 % more on an
#: undamped rope jerked taut); the first iteration after the predictor needs it too
#: (without it, a bristle's step can need substeps)
NEWTON_DAMPING = 0.5
#: largest state (entries of y) whose iteration matrix is factorised by the block LU written
#: out in SX; above it, by sparse QR (fill-reducing column order, dense rows split off),
#: whose construction is O(n)
SXLU_MAX_STATES = 400
#: the same with generated C asked for explicitly (``codegen=True``): the written-out LU in
#: C is several times faster per step than the sparse QR at a few hundred segments, but its
#: C takes minutes to compile there, which the default does not impose (the performance
#: study, in the docs)
SXLU_MAX_STATES_C = 1000
#: largest difference (relative to the force scale) between a Mechanism's residual and its
#: element form's (:func:`~symcable.mechanism.element_form.split_mismatch`) for the step to take
#: its matrix from the form: far above the round-off between the two
SPLIT_TOLERANCE = 1e-9
#: whether the step takes its matrix from a Mechanism's element form where it has one
#: (False: the written-out matrix, e.g. to time the two side by side)
ELEMENT_MATRIX = True
#: fewest states (entries of y) from which a Mechanism with an element form has its step's
#: residual and matrix from the elements' loop, factorised by the banded LU, instead of
#: written out with the block LU: compiled, the loop is slower on short lines and faster
#: from a few hundred states on (the performance study's step profile, in the docs)
ELEMENT_MIN_STATES = 200


def coefficients(rho):
    """``(alpha_m, alpha_f, gamma)`` for rho_inf ``rho`` (a number or a CasADi symbol)."""
    am = 0.5 * (3.0 - rho) / (1.0 + rho)
    af = 1.0 / (1.0 + rho)
    return am, af, 0.5 + am - af


def _error_constant(rho):
    return (rho * rho - rho + 1.0) / (3.0 * (1.0 + rho) ** 2)


def step_scales(mech: Mechanism) -> np.ndarray:
    """``(y_scale, row_scale)`` (2 n_y,): the scales of y = (q, v), and per row of F the
    factor that turns h |F| into a change of y relative to its scale (1 / scales.q on the
    kinematic rows, 1 / (m_i scales.v) on the momentum rows, m_i the diagonal of a constant
    mass matrix where it is positive, else ``scales.mass``)."""
    return STEP_CACHE.get(mech, ("step_scales",), lambda: _step_scales(mech)).copy()


def _step_scales(mech: Mechanism) -> np.ndarray:
    sq, sv = np.asarray(mech.scales.q, float), np.asarray(mech.scales.v, float)
    mass = np.full(mech.n_v, float(mech.scales.mass))
    try:
        M = np.atleast_2d(np.asarray(ca.evalf(mech.mass), dtype=float))
        d = np.abs(np.diag(M)) if M.shape == (mech.n_v, mech.n_v) else np.zeros(0)
        mass = np.where(d > 0, d, mass) if d.size == mech.n_v else mass
    except (RuntimeError, NotImplementedError, TypeError):
        pass  # M depends on the state or the parameters: the mechanism's mass scale
    return np.concatenate([sq, sv, 1.0 / sq, 1.0 / (mass * sv)])


def _sx_residual(mech: Mechanism) -> ca.Function:
    """The DAE residual as an SX Function (expanded from MX when the Mechanism is MX)."""
    fn = functions(mech).dae_residual
    if fn.is_a("SXFunction"):
        return fn
    try:
        return fn.expand()
    except RuntimeError as exc:
        raise SymcableError(f"mechanism {mech.name!r}: its DAE residual cannot be written out "
                            f"in SX for the unrolled Newton loop ({str(exc).splitlines()[-1]}); "
                            "use GeneralizedAlphaFirstOrder(newton='rootfinder')") from None


def _alpha_point(w, x, t, h, rho, ny):
    """``(y', y, t)`` at the alpha points of the step from x = (y0, y'0) with y'1 = w."""
    am, af, gamma = coefficients(rho)
    y0, yd0 = x[:ny], x[ny:]
    y1 = y0 + h * yd0 + gamma * h * (w - yd0)
    return yd0 + am * (w - yd0), y0 + af * (y1 - y0), t + af * h


def _step_residual(dae, w, x, t, h, p, rho, ny):
    """F at the alpha points of the step from x = (y0, y'0) with y'1 = w."""
    return dae(*_alpha_point(w, x, t, h, rho, ny), p)


def _symbols(mech, S):
    ny = mech.n_q + mech.n_v
    return (S.sym("x", 2 * ny), S.sym("t"), S.sym("h"), S.sym("p", mech.params.n),
            S.sym("settings", 2), S.sym("scales", 2 * ny))


_IN = ["x", "t", "h", "p", "settings", "scales"]
_OUT = ["x1", "err", "lte", "iterations", "failed"]


def galpha1_residual(mech: Mechanism) -> ca.Function:
    """``ga1_residual(w, x, t, h, p, settings) -> (F, dF/dw)``: the DAE residual of the step
    from x = (y0, y'0) at t (s) of size h (s) with y'1 = w (the rows of F in their own units),
    and its exact sparse Jacobian; settings = [rho_inf, tol] (tol unused). In the
    Mechanism's order y = (q, v)."""
    def build():
        ny = mech.n_q + mech.n_v
        x, t, h, p, st, _ = _symbols(mech, ca.SX)
        w = ca.SX.sym("w", ny)
        r = _step_residual(_sx_residual(mech), w, x, t, h, p, st[0], ny)
        return ca.Function(f"{mech.fname}_ga1_residual", [w, x, t, h, p, st], [r, _jacobian(r, w)],
                           ["w", "x", "t", "h", "p", "settings"], ["F", "dF_dw"])
    return STEP_CACHE.get(mech, ("ga1_residual",), build)


def _element_parts(mech: Mechanism, args: list, ny: int) -> tuple | None:
    """``(residual inputs, jacobian inputs)``: the straight-line SX parts of the step's
    residual and iteration matrix from the Mechanism's element form
    (:func:`~symcable.solvers.element_jacobian.residual_inputs`, :func:`~symcable.solvers.
    element_jacobian.jacobian_inputs`; :func:`_element_loops` adds the loops); or None
    where it has none, is not SX, or its split does not reproduce its own residual (to
    SPLIT_TOLERANCE of its force scale at two random states: a Mechanism rebuilt with
    another force that kept its form)."""
    form = getattr(mech, "elements", None)
    if form is None or not ELEMENT_MATRIX or not isinstance(mech.q, ca.SX) or mech.n_z:
        return None
    if not split_mismatch(mech, form) <= SPLIT_TOLERANCE:
        warnings.warn(f"mechanism {mech.name!r}: its element form does not reproduce its "
                      "residual; the step's matrix is written out instead", stacklevel=3)
        return None
    rest = dataclasses.replace(mech, mass=ca.SX(mech.n_v, mech.n_v), force=form.force_rest,
                               elements=None)
    w, x, t, h, p, st = args
    am, af, gamma = coefficients(st[0])
    yda, ya, ta = _alpha_point(w, x, t, h, st[0], ny)
    nq = mech.n_q
    point = ca.Function("ga1_alpha_point", args, [ya[:nq], ya[nq:], yda[nq:], ta, p,
                                                  af * gamma * h, am])
    r = _step_residual(_sx_residual(rest), w, x, t, h, p, st[0], ny)
    return residual_inputs(mech, r, args, point), jacobian_inputs(mech, _jacobian(r, w), args,
                                                                  point)


def _element_loops(mech: Mechanism, args: list, ny: int, kernels_c: bool) -> tuple | None:
    """``(residual, (pattern, jacobian, sources))`` of :func:`_element_parts`, its SX part
    kept on the Mechanism, the loops calling the element kernels (their generated C with
    ``kernels_c``)."""
    parts = STEP_CACHE.get(mech, ("element_parts",), lambda: _element_parts(mech, args, ny))
    if parts is None:
        return None
    res_in, jac_in = parts
    kernel, block = res_in["form"].kernel, block_kernel(res_in["form"])
    if kernels_c:
        kernel, block = kernels_in_c([kernel, block], "the element kernels")
    return residual_loop(res_in, kernel), jacobian_loop(jac_in, block)


def _taylor_jet(mech: Mechanism) -> ca.Function:
    """``jet(q, v, a, z, t, p) -> (q'', b)`` along the motion q' = kinematics, v' = a (z
    held): q'' = d(kinematics)/dt and b = df/dt - (dM/dt) a (M may move with q and t), so
    that v'' = M^-1 b."""
    m = mech
    a = ca.SX.sym("a", m.n_v) if isinstance(m.v, ca.SX) else ca.MX.sym("a", m.n_v)
    kin = m.v if m.kinematics is None else m.kinematics

    def ddt(expr):
        return (ca.jtimes(expr, m.q, kin) + ca.jtimes(expr, m.v, a) + ca.jacobian(expr, m.t))

    Ma = ca.mtimes(m.mass, a)
    b = ddt(m.force) - ca.jtimes(Ma, m.q, kin) - ca.jacobian(Ma, m.t)
    return ca.Function(f"{m.fname}_jet", [m.q, m.v, a, m.z, m.t, m.p], [ddt(kin), b])


def _taylor_lte(mech, y0, y1, t, h, p, rho, y_scale):
    """The local error estimate of y1 over its scales (see :func:`galpha1_step`), MX."""
    F = functions(mech)
    nq, nv, ny = mech.n_q, mech.n_v, mech.n_q + mech.n_v
    z0 = ca.MX(0, 1)
    q0, v0 = y0[:nq] if nq else ca.MX(0, 1), y0[nq:ny] if nv else ca.MX(0, 1)
    M0 = F.tangents(q0, v0, z0, t, p)[2]
    r_f, _ = F.acc_residual(q0, v0, ca.MX.zeros(nv), z0, t, p)  # = -f
    a0 = qr_solve(M0, -r_f) if nv else ca.MX(0, 1)
    qd0 = F.qdot(q0, v0, z0, t, p)
    qdd0, b0 = _taylor_jet(mech)(q0, v0, a0, z0, t, p)
    ad0 = qr_solve(M0, b0) if nv else ca.MX(0, 1)
    y_pred = y0 + h * ca.vertcat(qd0, a0) + 0.5 * h ** 2 * ca.vertcat(qdd0, ad0)
    C = _error_constant(rho)
    return norm_inf(C / (C + 1.0 / 6.0) * (y1 - y_pred) / y_scale)


def _taylor_rate(mech: Mechanism, x, t, h, p, gamma):
    """The rate y'1 whose update puts q1 at the second-order Taylor step q0 + h G(q0, v0 + h
    a0 / 2) (= q0 + h v0 + h^2 a0 / 2 where q' = v) with a0 = v'0, and v1 at v0 + h a0."""
    nq, nv = mech.n_q, mech.n_v
    ny = nq + nv
    q0, v0 = x[:nq], x[nq:ny]
    qd0, a0 = x[ny:ny + nq], x[ny + nq:]
    v_mid = v0 + 0.5 * h * a0
    if mech.kinematics is None:
        rate = v_mid
    else:
        rate = functions(mech).qdot(q0, v_mid, ca.MX(0, 1), t + 0.5 * h, p)
    return ca.vertcat(qd0 + (rate - qd0) / gamma, a0)


def _predictor(res, x, ny: int, nq: int, gamma, residual=None, symbols=None, taylor=None):
    """Newton's start y'1 for the step from x = (y0, y'0): of the Taylor step ``taylor``
    (:func:`_taylor_rate`, when given), the constant rate y'1 = y'0, constant velocity (q1 =
    q0 + h q'0, v1 = v0) and rest (y1 = y0), the one whose scaled residual ``res(w)``
    (max-norm) is smallest (the first on a tie; a residual that is not finite is never
    chosen). The Taylor step and the constant rate are both evaluated and the better stands
    first. The constant rate moves q by h q'0 only: on a stiff chain its missing h^2 a / 2 of
    a heaving fairlead can exceed the top segment's stretch, which leaves the segment slack
    at Newton's start, and the first iterate overshoots; from the Taylor step such runs need
    about half the factorisations. The constant rate is exact on a steady tow, where the
    Taylor step carries the start's round-off accelerations into the positions. After a
    violent start (a line released from a kink) both put v1 = h v'0, hundreds of m/s at a
    1 s step, into the drag, and Newton runs off from there. Rest is y'1 = (1 - 1 / gamma)
    y'0 (the update y1 = y0 + h y'0 + gamma h (y'1 - y'0) = y0). The others are tried only
    where the first's residual exceeds PREDICTOR_TRUST
    (:func:`~symcable.solvers.newton.best_start`). With ``residual`` (w -> the residual
    vector, whose scaled norm is ``res``) and ``symbols`` (the MX inputs the expressions are
    of), ``(start, residual(start), res(residual(start)))``."""
    yd0 = x[ny:]
    stay = (1 - 1 / gamma) * yd0
    cands = ([] if taylor is None else [taylor]) + [yd0, ca.vertcat(yd0[:nq], stay[nq:]), stay]
    lead = 1 if taylor is None else 2
    if residual is None:
        return best_start(res, cands, lead)
    return best_start_residual(residual, res, cands, symbols, lead)


def solver_choice(mech: Mechanism, codegen: bool | None) -> tuple[bool, bool]:
    """``(lu, by_elements)``: whether the step's matrix is factorised by the block LU
    written out in SX, and whether its residual and matrix come from the Mechanism's
    element form (then factorised by the banded LU): see the module docstring,
    SXLU_MAX_STATES, SXLU_MAX_STATES_C and ELEMENT_MIN_STATES."""
    ny = mech.n_q + mech.n_v
    explicit_c = codegen is True and ny <= SXLU_MAX_STATES_C and use_codegen(True)
    by_elements = (ELEMENT_MATRIX and getattr(mech, "elements", None) is not None
                   and ny >= ELEMENT_MIN_STATES)
    return (ny <= SXLU_MAX_STATES or explicit_c) and not by_elements, by_elements


def step_parts(mech: Mechanism, lu: bool, kernels_c: bool = False) -> tuple:
    """``(residual, factor, solve, n_factors, kind, jacobian)``: the parts of one Newton
    iteration of the unrolled step as :func:`_unrolled` builds them, Functions of (w, x, t,
    h, p, settings) but ``solve(f, b)`` (:func:`~symcable.solvers.step_solver.
    linear_solver`); from the element form where the Mechanism has one (and ``lu`` is
    off), else written out in SX. ``kind``: "block-lu", "banded" or "qr"; ``jacobian``:
    the matrix's nonzeros alone. ``kernels_c``: the element and banded LU loops call their
    kernels' generated C."""
    ny = mech.n_q + mech.n_v
    x, t, h, p, st, _ = _symbols(mech, ca.SX)
    w = ca.SX.sym("w", ny)
    args = [w, x, t, h, p, st]
    cache = STEP_CACHE.get(mech, ("block_lu",), dict)
    elements = None if lu else _element_loops(mech, args, ny, kernels_c)
    if elements is None:
        r = _step_residual(_sx_residual(mech), w, x, t, h, p, st[0], ny)
        opts = {"cse": ny <= CSE_MAX_STATES}
        R = ca.Function(f"{mech.fname}_ga1_res", args, [r], opts)
        J = _jacobian(r, w)
        factor, solve, n_f, kind = linear_solver(J, args, cache, lu, mech.n_q)
        jac = factor if kind == "qr" else ca.Function("ga1_jacobian", args, [J.nz[:]], opts)
    else:
        R, given = elements
        factor, solve, n_f, kind = linear_solver(None, args, cache, lu, mech.n_q, given,
                                                  kernels_c)
        jac = given[1]
    return R, factor, solve, n_f, kind, jac


def _unrolled(mech: Mechanism, max_iter: int, with_lte: bool, lu: bool,
              kernels_c: bool = False) -> ca.Function:
    """The kernel of the unrolled Newton loop (see :func:`galpha1_kernel`)."""
    ny = mech.n_q + mech.n_v
    name = f"{mech.fname}_ga1"
    R, factor, solve, n_f, _, _ = step_parts(mech, lu, kernels_c)

    # the loop's state: z (y'1), rz = F(z) and res its scaled norm (evaluated where the loop
    # goes on, zero where it stops), done, it (linear solves), measure, f (the factors), the
    # previous scaled residual; then the step's inputs. Every branch is a Function of values
    # computed once (``Function.if_else``): CasADi's short-circuiting ``if_else`` of
    # expressions builds its branches from the symbols and computes again, inside each,
    # what the expression shares with the rest of the graph (the matrix would be factorised
    # twice per refactorisation and the residual's norm taken several times)
    z, rz, res = ca.MX.sym("z", ny), ca.MX.sym("rz", ny), ca.MX.sym("res")
    done, it, meas = ca.MX.sym("done"), ca.MX.sym("it"), ca.MX.sym("measure")
    f, prev = ca.MX.sym("f", n_f), ca.MX.sym("previous")
    x, t, h, p, st, sc = _symbols(mech, ca.MX)
    step_in = [x, t, h, p, st]
    tol, gamma = st[1], coefficients(st[0])[2]
    names = ["z", "rz", "res", "done", "it", "measure", "f", "previous"] + _IN
    outs = ["z_out", "done_out", "it_out", "measure_out"]
    fargs = [z, rz, res, done, it, meas, f, prev, x, t, h, p, st, sc]
    rest = fargs[8:]
    r_z = R(z, *step_in)
    refactor_or_keep = ca.Function.if_else(
        f"{name}_refactor",
        ca.Function(f"{name}_factorise", [z, f] + step_in, [factor(z, *step_in)]),
        ca.Function(f"{name}_keep", [z, f] + step_in, [f]))
    residual_unless = ca.Function.if_else(
        f"{name}_next_residual",
        ca.Function(f"{name}_no_residual", [z, sc] + step_in, [ca.MX.zeros(ny), 0]),
        ca.Function(f"{name}_residual", [z, sc] + step_in,
                    [r_z, norm_inf(h * r_z * sc[ny:])]))
    # the loop from iteration i on, nested so that a converged step returns at once:
    # loop_i = if done: (z, ...) else if F(z) converged: (z, ...) else loop_{i+1}(...)
    # after the last iteration: its iterate judged by its own residual (a step whose last
    # correction was too large may still have landed on the solution)
    loop = ca.Function(f"{name}_done{max_iter}", fargs,
                       [z, ca.logic_or(done, res <= tol), it,
                        ca.if_else(done, meas, res)], names, outs)
    stop = ca.Function(f"{name}_stop", fargs, [z, done, it, meas], names, outs)
    converged = ca.Function(f"{name}_converged", fargs, [z, 1, it, res], names, outs)
    for i in range(max_iter - 1, -1, -1):
        if 0 < i < CHORD_ITERATIONS:
            # a chord iteration, unless the last one did not contract the residual
            f_new = refactor_or_keep(ca.logic_not(res <= CHORD_CONTRACTION * prev), z, f,
                                     *step_in)
        else:
            f_new = factor(z, *step_in)
        dz = -solve(f_new, rz)
        corr = norm_inf(gamma * h * dz / sc[:ny])
        done_new = corr <= tol
        # a correction from an iterate whose residual grew is damped (breaks 2-cycles),
        # unless it is the last one (converged: taken whole)
        damp = ca.logic_and(res > prev, ca.logic_not(done_new))
        z_new = z + ca.if_else(damp, NEWTON_DAMPING, 1.0) * dz
        r_new, res_new = residual_unless(done_new, z_new, sc, *step_in)
        body = ca.Function(f"{name}_iterate{i}", fargs,
                           loop(z_new, r_new, res_new, done_new, it + 1, corr, f_new, res,
                                *rest), names, outs)
        test = ca.Function.if_else(f"{name}_test{i}", converged, body)
        go_on = ca.Function(f"{name}_from{i}", fargs, test(res <= tol, *fargs), names, outs)
        branch = ca.Function.if_else(f"{name}_loop{i}", stop, go_on)
        loop = ca.Function(f"{name}_newton{i}", fargs, branch(done, *fargs), names, outs)

    x, t, h, p, st, sc = _symbols(mech, ca.MX)
    y0, yd0 = x[:ny], x[ny:]
    gamma = coefficients(st[0])[2]
    start, r_start, res_start = _predictor(
        lambda r_: norm_inf(h * r_ * sc[ny:]), x, ny, mech.n_q, gamma,
        residual=lambda w_: R(w_, x, t, h, p, st), symbols=[x, t, h, p, st, sc],
        taylor=_taylor_rate(mech, x, t, h, p, gamma))
    z, done, it, meas = loop(start, r_start, res_start, 0, 0, np.inf, ca.MX.zeros(n_f),
                             np.inf, x, t, h, p, st, sc)
    y1 = y0 + h * yd0 + gamma * h * (z - yd0)
    lte = _taylor_lte(mech, y0, y1, t, h, p, st[0], sc[:ny]) if with_lte else ca.MX(np.nan)
    return ca.Function(f"{name}_kernel{max_iter}{'_lte' if with_lte else ''}",
                       [x, t, h, p, st, sc], [ca.vertcat(y1, z), meas, lte, it, 1 - done],
                       _IN, _OUT)


def _rootfinder(mech: Mechanism, tol: float, max_iter: int, with_lte: bool) -> ca.Function:
    """The kernel on CasADi's Newton rootfinder (exact derivatives; tol fixed at build)."""
    ny = mech.n_q + mech.n_v
    R = galpha1_residual(mech)
    x, t, h, p, st, sc = _symbols(mech, ca.MX)
    w = ca.MX.sym("w", ny)

    def scaled(w_):
        return h * R(w_, x, t, h, p, st)[0] * sc[ny:]

    G = ca.Function("ga1_res", [w, x, t, h, p, st, sc], [scaled(w)])
    rf = ca.rootfinder(f"{mech.fname}_ga1_newton", "newton", G,
                       {"abstol": tol, "abstolStep": 1e-14, "max_iter": max_iter,
                        "error_on_fail": False, "show_eval_warnings": False})
    y0, yd0 = x[:ny], x[ny:]
    gamma = coefficients(st[0])[2]
    start = _predictor(lambda w_: norm_inf(scaled(w_)), x, ny, mech.n_q, gamma,
                       taylor=_taylor_rate(mech, x, t, h, p, gamma))
    w1 = rf(start, x, t, h, p, st, sc)
    y1 = y0 + h * yd0 + gamma * h * (w1 - yd0)
    err = norm_inf(scaled(w1))
    lte = _taylor_lte(mech, y0, y1, t, h, p, st[0], sc[:ny]) if with_lte else ca.MX(np.nan)
    return ca.Function(f"{mech.fname}_ga1_rootfinder", [x, t, h, p, st, sc],
                       [ca.vertcat(y1, w1), err, lte, ca.MX(np.nan), 1 - (err <= tol)], _IN, _OUT)


def galpha1_kernel(mech: Mechanism, opts: GeneralizedAlphaFirstOrder, *, lte: bool = False,
                   codegen: bool | None = False) -> ca.Function:
    """The step as integrators run it: ``kernel(x, t, h, p, settings, scales) ->
    (x1, err, lte, iterations, failed)`` with settings = [rho_inf, tol] and scales =
    :func:`step_scales` (inputs, so one compiled library serves every rho_inf, tolerance and
    scale); ``iterations`` the linear solves of the unrolled loop (NaN with the rootfinder),
    ``failed`` 1 when Newton did not converge. ``lte`` NaN unless ``lte=True``. Built once per
    Mechanism; in generated C when ``codegen`` resolves to True
    (:func:`symcable.mechanism.codegen.use_codegen`: by default where the step is written out, up to
    SXLU_MAX_STATES, and small enough to compile; with ``codegen=True`` written out up to
    SXLU_MAX_STATES_C), with a one-line notice while compiling."""
    if mech.n_z:
        raise SymcableError(f"mechanism {mech.name!r} has {mech.n_z} constraints: "
                            "GeneralizedAlphaFirstOrder takes n_z = 0 only for now; use "
                            "GeneralizedAlpha()")
    # (built from the expressions alone: kept for every scene of the structure)
    owner = structure_owner(mech)
    if opts.newton is NewtonScheme.ROOTFINDER:
        return STEP_CACHE.get(owner, ("ga1_rootfinder", opts.tol, opts.max_iter, lte),
                              lambda: _rootfinder(owner, opts.tol, opts.max_iter, lte))
    lu, by_elements = solver_choice(owner, codegen)
    key = ("ga1_unrolled", opts.max_iter, lte, lu)
    vm = STEP_CACHE.get(owner, key, lambda: _unrolled(owner, opts.max_iter, lte, lu))
    # sparse QR is C++ in the virtual machine already: C does not pay by default
    size = (lambda: math.inf) if not lu and not by_elements else None
    step = maybe_compiled(owner, key, vm, codegen, "the generalized-α step", size)
    if step is vm and by_elements and codegen is not False and use_codegen(codegen):
        # too large to compile whole (a long line): its loops stay in the virtual machine
        # and call their kernels' generated C, small and compiled in about a second
        step = STEP_CACHE.get(owner, key + ("kernels_c",),
                              lambda: _unrolled(owner, opts.max_iter, lte, lu, True))
    return step


def galpha1_step(mech: Mechanism, opts: GeneralizedAlphaFirstOrder,
                 codegen: bool | None = False, *, lte: bool = True) -> ca.Function:
    """``step(x, t, h, p) -> (x1, err, lte)`` with x = (y, y'), y = (q, v): one first-order
    generalized-alpha step (see the module docstring) of size h (s) from t (s).

    ``err`` is the Newton convergence measure the step accepted (the scaled residual, or
    with the unrolled loop possibly the last correction of y1 over its scales): at most
    ``opts.tol`` when the step converged, above it (or NaN) when it failed.

    ``lte`` estimates the local error of y over its scales (max-norm) by the difference from
    the second-order Taylor predictor y0 + h y'(t0) + h^2/2 y''(t0), whose local error is
    h^3/6 y^(3) (y', y'' exact, from the equations, not the carried y'): on the principal
    root of y' = A y the step's error is C h^3 y^(3) (C = ``opts.error_constant``, 1/9 at
    rho_inf = 1/2), so the error is C / (C + 1/6) times that difference. Where the solution
    is driven by an explicit forcing rather than by its own dynamics (pure quadrature
    y' = g(t)) the step's h^3 error vanishes and the estimate overstates it.

    ``opts.newton`` chooses the Newton loop (module docstring): "unrolled" (fast, compiled
    with ``codegen``), or "rootfinder" (derivatives exact by the implicit function theorem).
    ``lte=False`` leaves the error estimate out (NaN; it costs a Taylor predictor per step,
    which shooting does not use).
    """
    kern = galpha1_kernel(mech, opts, lte=lte, codegen=codegen)

    def build():
        x, t, h, p, _, _ = _symbols(mech, ca.MX)
        consts = (ca.DM([opts.rho_inf, opts.tol]), ca.DM(step_scales(mech)))
        x1, err, lte, _, _ = kern(x, t, h, p, *consts)
        return ca.Function(f"{mech.fname}_ga1_step", [x, t, h, p], [x1, err, lte],
                           ["x", "t", "h", "p"], ["x1", "err", "lte"])
    return STEP_CACHE.get(mech, ("ga1_step", kern.name(), id(kern), opts.rho_inf, opts.tol), build)
