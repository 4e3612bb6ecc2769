"""One time step of a Mechanism as a CasADi Function: second-order generalized-alpha
(Arnold & Bruels) and classical RK4, and RK4's stability limit. Every step Function has the
signature ``step(x, t, h, p) -> (x1, err, lte)`` (see :mod:`symcable.solvers.integrate`);
the first-order generalized-alpha step is in :mod:`symcable.solvers.galpha1`.

Generalized-alpha in the form of Arnold & Bruels (2007), for M(q) a = f(q, v, z, t),
g(q, v, z, t) = 0, with a pseudo-acceleration abar:

    (1 - alpha_m) abar1 + alpha_m abar0 = (1 - alpha_f) a1 + alpha_f a0
    q1 = q0 + h v0 + h^2 (1/2 - beta) abar0 + h^2 beta abar1
    v1 = v0 + h (1 - gamma) abar0 + h gamma abar1

and the equations of motion and the constraints imposed at t1, solved by Newton on the
exact Jacobian (CasADi's rootfinder). Position-level constraints are met to the Newton
tolerance at every step (no drift). Second order for positions and velocities. It needs
q' = v (no ``kinematics``).

The Newton unknowns are the step's displacement d = q1 - q0, scaled to d / (beta h^2)
(an acceleration, so that abstolStep means what it did for a1), and z1 (a1, abar1 and v1
follow from d): q1 = q0 + d is then exact to the round-off of q, where q0 + h^2 (...) from
accelerations loses |h^2 abar| eps to cancellation (on a long step after a release enough
for a stiff axial law to turn it into a residual above the tolerance). Newton starts from
the best of three predictors (:func:`_predictor`): constant acceleration (a1 = a0, exact for
small h), constant velocity (q1 = q0 + h v0) and rest (q1 = q0), the latter two only where
the first's residual exceeds PREDICTOR_TRUST force scales and theirs is far smaller: where a
large step follows a violent start (a line released from a kink accelerates at 200 m/s^2)
the first would move the nodes by h^2 a0 / 2 ~ 100 m, whose residual (the axial law
stretched) is 1e7 N, and Newton never recovers. It iterates with CasADi's backtracking line
search, and where that fails, again from the same predictor without it (full Newton steps:
on a line the residual's norm has narrow valleys along its stiff axial rows, where the line
search's steps shrink to nothing and leave a residual; on smooth steps the line search's
Newton is the cheaper).
"""
from __future__ import annotations

import math

import casadi as ca
import numpy as np

from ..mechanism.functions import functions
from ..errors import SymcableError
from ..linalg.sparse import norm_inf, qr_solve
from ..mechanism.mechanism import Mechanism
from .newton import best_start
from .options import GeneralizedAlpha
from .stepcache import STEP_CACHE

__all__ = ["RK4_IMAG_LIMIT", "check_second_order", "galpha_step", "rk4_stability_limit", "rk4_step"]

#: RK4's stability interval on the imaginary axis: |lambda dt| <= 2 sqrt(2).
RK4_IMAG_LIMIT = 2.0 * math.sqrt(2.0)
#: largest state whose stability limit is taken from dense eigenvalues (above: power iteration)
DENSE_MAX = 800
#: largest state whose SX step is built with common subexpressions eliminated
CSE_MAX_STATES = 400


def _seg(x, i: int, j: int):
    """x[i:j] as a column (CasADi gives a 1x0 row for an empty slice of a 1x1 vector)."""
    return x[i:j] if j > i else ca.MX(0, 1)


def check_second_order(mech: Mechanism) -> None:
    """Refuse kinematics for the second-order generalized-alpha (it needs q' = v)."""
    if mech.kinematics is not None:
        raise SymcableError(f"mechanism {mech.name!r}: GeneralizedAlpha needs q' = v; its "
                            "kinematics q' = G(q) v (+ w) runs with GeneralizedAlphaFirstOrder()")


def _predictor(G, x0, t, h, p, z0, nv: int, am: float, beta: float):
    """Newton's start (d, z) for the step (module docstring): of constant acceleration
    (a1 = a0, abar1 = (a0 - alpha_m abar0) / (1 - alpha_m), d = h v0 + h^2 ((1/2 - beta)
    abar0 + beta abar1)), constant velocity (d = h v0) and rest (d = 0), the one whose
    scaled residual G is smallest (max-norm; :func:`~symcable.solvers.newton.best_start`:
    the others only where the first's exceeds PREDICTOR_TRUST)."""
    v0, a0, ab0 = _seg(x0, nv, 2 * nv), _seg(x0, 2 * nv, 3 * nv), _seg(x0, 3 * nv, 4 * nv)
    ab1 = (a0 - am * ab0) / (1 - am)
    cands = [h * v0 + h ** 2 * ((0.5 - beta) * ab0 + beta * ab1), h * v0, ca.MX.zeros(nv)]
    return best_start(lambda w_: norm_inf(G(w_, x0, t, h, p)),
                      [ca.vertcat(d / (beta * h ** 2), z0) for d in cands])


def galpha_step(mech: Mechanism, opts: GeneralizedAlpha) -> ca.Function:
    """``step(x, t, h, p) -> (x1, err, lte)`` with x = (q, v, a, abar, z): one
    generalized-alpha step of size h (s) from t (s); err is the max-norm of the residual at
    the returned state, force rows over ``scales.force`` and constraint rows over
    ``scales.g_scale()`` (the solve failed when it exceeds ``opts.tol``); lte the estimated
    local error of the positions over ``scales.q`` (max-norm)."""
    check_second_order(mech)
    F = functions(mech)
    am, af, gamma, beta = opts.coefficients
    nq, nv, nz = mech.n_q, mech.n_v, mech.n_z
    fs, ms = mech.scales.force, mech.scales.mass
    x0 = ca.MX.sym("x", nq + 3 * nv + nz)
    q0, v0 = _seg(x0, 0, nq), _seg(x0, nq, nq + nv)
    a0, ab0 = _seg(x0, nq + nv, nq + 2 * nv), _seg(x0, nq + 2 * nv, nq + 3 * nv)
    t, h, p = ca.MX.sym("t"), ca.MX.sym("h"), ca.MX.sym("p", mech.params.n)
    w = ca.MX.sym("w", nv + nz)

    def state(w_):
        # the unknown is d / (beta h^2) (an acceleration's units): d itself would shrink
        # Newton's steps by beta h^2 (6e-6 at h = 5 ms) below abstolStep, which then stops
        # Newton above tol; the product keeps d's precision (one rounding)
        d, z1 = beta * h ** 2 * _seg(w_, 0, nv), _seg(w_, nv, nv + nz)
        ab1 = (d - h * v0 - h ** 2 * (0.5 - beta) * ab0) / (beta * h ** 2)
        a1 = ((1 - am) * ab1 + am * ab0 - af * a0) / (1 - af)
        v1 = v0 + h * ((1 - gamma) * ab0 + gamma * ab1)
        return q0 + d, v1, a1, ab1, z1

    def residual(w_):
        q1, v1, a1, _, z1 = state(w_)
        r_f, r_g = F.acc_residual(q1, v1, a1, z1, t + h, p)
        return ca.vertcat(r_f / fs, r_g * (ms / (beta * h ** 2 * fs)))

    G = ca.Function("ga_res", [w, x0, t, h, p], [residual(w)])
    newton = {"abstol": opts.tol, "abstolStep": 1e-14, "max_iter": opts.max_iter,
              "error_on_fail": False, "show_eval_warnings": False}
    plain = ca.rootfinder(f"{mech.fname}_ga_newton", "newton", G, dict(newton, line_search=False))
    search = ca.rootfinder(f"{mech.fname}_ga_newton_ls", "newton", G, newton)
    z0 = _seg(x0, nq + 3 * nv, nq + 3 * nv + nz)
    w_guess = _predictor(G, x0, t, h, p, z0, nv, am, beta)
    g_scale = ca.DM(mech.scales.g_scale())

    def judged(w_):
        """(w, err): err the residual's max-norm in the rows' own units (forces over the
        force scale, constraint rows over their scale)."""
        q1_, v1_, a1_, _, z1_ = state(w_)
        r_f1, r_g1 = F.acc_residual(q1_, v1_, a1_, z1_, t + h, p)
        return w_, norm_inf(ca.vertcat(r_f1 / fs, r_g1 / g_scale))

    w_ls, err_ls = judged(search(w_guess, x0, t, h, p))
    # plain Newton only where the line search's failed (NaN counts as failed): a switch
    # between Functions of the values computed once (CasADi's short-circuiting if_else of
    # expressions would solve the line search's Newton again inside its branches)
    ws, es, gs = ca.MX.sym("w", nv + nz), ca.MX.sym("err"), ca.MX.sym("guess", nv + nz)
    args = [ws, es, gs, x0, t, h, p]
    retry = ca.Function.if_else(f"{mech.fname}_ga_retry",
                                ca.Function("kept", args, [ws, es]),
                                ca.Function("plain", args, list(judged(plain(gs, x0, t, h, p)))))
    w1, err = retry(err_ls <= opts.tol, w_ls, err_ls, w_guess, x0, t, h, p)
    q1, v1, a1, ab1, z1 = state(w1)
    # local error of the positions, Newmark's estimate (beta - 1/6) h^2 (a1 - a0) (the h^3
    # jerk term the update leaves out), relative to the coordinate scales
    lte = norm_inf(abs(beta - 1.0 / 6.0) * h ** 2 * (a1 - a0) / ca.DM(mech.scales.q))
    return ca.Function(f"{mech.fname}_ga_step", [x0, t, h, p],
                       [ca.vertcat(q1, v1, a1, ab1, z1), err, lte], ["x", "t", "h", "p"],
                       ["x1", "err", "lte"])


def _sx_rates(mech: Mechanism) -> ca.Function | None:
    """``rate(y, t, p) -> y'`` in SX when the mass matrix is diagonal (v' = f / diag M, the
    same expression the formulation wrote), else None."""
    m = mech
    if not isinstance(m.q, ca.SX) or m.n_z or not m.mass.sparsity().is_diag() \
            or m.mass.sparsity().nnz() != m.n_v:
        return None
    kin = m.v if m.kinematics is None else m.kinematics
    y = ca.vertcat(m.q, m.v)
    return ca.Function("rate", [y, m.t, m.p], [ca.vertcat(kin, m.force / ca.diag(m.mass))])


def rk4_step(mech: Mechanism) -> ca.Function:
    """``step(x, t, h, p) -> (x1, err, lte)`` with x = (q, v): one RK4 step (err = 0, and
    lte = NaN: no embedded estimate). SX with a diagonal mass matrix, else MX with a sparse
    solve of M at each stage. Built once per Mechanism."""
    if mech.n_z:
        raise SymcableError(f"method = 'rk4': mechanism {mech.name!r} has {mech.n_z} "
                            "constraints; use generalized-alpha")
    return STEP_CACHE.get(mech, ("rk4_step",), lambda: _rk4_step(mech))


def _rk4_step(mech):
    F = functions(mech)
    nq, nv = mech.n_q, mech.n_v
    rate = _sx_rates(mech)
    S = ca.SX if rate is not None else ca.MX
    x0 = S.sym("x", nq + nv)
    t, h, p = S.sym("t"), S.sym("h"), S.sym("p", mech.params.n)
    if rate is None:
        tan = F.tangents
        z0 = ca.MX.zeros(0)

        def rhs(x, tt):
            q, v = _seg(x, 0, nq), _seg(x, nq, nq + nv)
            M = tan(q, v, z0, tt, p)[2]
            r_f, _ = F.acc_residual(q, v, ca.MX.zeros(nv), z0, tt, p)  # = -f
            return ca.vertcat(F.qdot(q, v, z0, tt, p), qr_solve(M, -r_f))
    else:
        def rhs(x, tt):
            return rate(x, tt, p)

    k1 = rhs(x0, t)
    k2 = rhs(x0 + h / 2 * k1, t + h / 2)
    k3 = rhs(x0 + h / 2 * k2, t + h / 2)
    k4 = rhs(x0 + h * k3, t + h)
    x1 = x0 + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
    opts = {"cse": nq + nv <= CSE_MAX_STATES} if S is ca.SX else {}
    return ca.Function(f"{mech.fname}_rk4_step", [x0, t, h, p], [x1, S(0), S(np.nan)],
                       ["x", "t", "h", "p"], ["x1", "err", "lte"], opts)


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


def _spectral_radius(matvec, n: int, iters: int = 300) -> float:
    """Spectral radius of a linear map by power iteration: the geometric-mean growth of
    |A^k x| over the second half of the iterations (robust to a dominant complex pair)."""
    x = np.random.default_rng(0).standard_normal(n)
    logs = []
    for _ in range(iters):
        x = matvec(x)
        nx = float(np.linalg.norm(x))
        if nx == 0.0 or not math.isfinite(nx):
            return 0.0 if nx == 0.0 else math.inf
        logs.append(math.log(nx))
        x /= nx
    return math.exp(float(np.mean(logs[iters // 2:])))


def _linear_parts(mech, q, v, t, p):
    """(H, G, K', C, M) at (q, v, t; p) as DM, K' = K + d(M a)/dq with a = M^-1 f (the
    mass matrix's change along q at the state's acceleration)."""
    F = functions(mech)
    z = np.zeros(0)
    K, C, M = (ca.DM(a) for a in F.tangents(q, v, z, t, p)[:3])
    H, G = (ca.DM(a) for a in F.kinematics_jacobian(q, v, z, t, p))
    if ca.depends_on(ca.vec(mech.mass), mech.q):
        a = qr_solve(M, -ca.DM(F.acc_residual(q, v, np.zeros(mech.n_v), z, t, p)[0]))
        dMa = STEP_CACHE.get(mech, ("dMa_dq",), lambda: _dma(mech))
        K = K + ca.DM(dMa(q, a, t, p))
    return H, G, K, C, M


def _dma(mech):
    a = (ca.SX if isinstance(mech.q, ca.SX) else ca.MX).sym("a", mech.n_v)
    return ca.Function("dMa_dq", [mech.q, a, mech.t, mech.p],
                       [ca.jacobian(ca.mtimes(mech.mass, a), mech.q)])


def rk4_stability_limit(mech: Mechanism, p=None, t: float = 0.0, q=None, v=None) -> float:
    """Largest stable RK4 step of the mechanism linearised at ``(q, v, t; p)`` (default: its
    first static start, at rest, with its own parameters), s.

    The state matrix A = d(q', v')/d(q, v) = [[H, G], [-M^-1 K, -M^-1 C]]; dense eigenvalues
    when n_q + n_v <= DENSE_MAX: the limit is the least, over the eigenvalues lambda, of the
    length of RK4's stability region along lambda's ray divided by |lambda|
    (2 sqrt 2 / |lambda| on the imaginary axis; eigenvalues with a positive real part from
    round-off count as imaginary). Larger: 2.6 / (spectral radius by power iteration), 2.6
    being the region's least radius in the left half-plane. ``inf`` when A is zero. Cached
    per Mechanism and state.
    """
    p = np.asarray(mech.params.values if p is None else p, dtype=float).ravel()
    q = np.asarray(next(iter(mech.starts())).q if q is None else q, dtype=float).ravel()
    v = np.zeros(mech.n_v) if v is None else np.asarray(v, dtype=float).ravel()
    key = ("rk4_limit", float(t), p.tobytes(), q.tobytes(), v.tobytes())
    return STEP_CACHE.get(mech, key, lambda: _rk4_limit(mech, q, v, float(t), p))


def _rk4_limit(mech, q, v, t, p) -> float:
    H, G, K, C, M = _linear_parts(mech, q, v, t, p)
    nq, n = mech.n_q, mech.n_q + mech.n_v
    if n <= DENSE_MAX:
        Md = np.atleast_2d(np.array(M.full()))
        lower = np.linalg.solve(Md, -np.hstack([np.array(K.full()), np.array(C.full())])) \
            if mech.n_v else np.zeros((0, n))
        A = np.vstack([np.hstack([np.array(H.full()), np.array(G.full())]), lower])
        lam = np.linalg.eigvals(A)
        mag = np.abs(lam)
        if not np.any(mag > 0.0):
            return math.inf
        keep = mag > 1e-9 * mag.max()
        theta = np.maximum(np.abs(np.angle(lam[keep])), 0.5 * np.pi)
        return float(np.min(_rk4_ray(theta) / mag[keep]))
    diag = M.sparsity().is_diag() and M.nnz() == mech.n_v
    m_diag = np.array(ca.diag(M).full()).ravel() if diag else None

    def matvec(x):
        xq, xv = x[:nq], x[nq:]
        top = np.array((ca.mtimes(H, xq) + ca.mtimes(G, xv)).full()).ravel()
        b = -(ca.mtimes(K, xq) + ca.mtimes(C, xv))
        low = np.array(b.full()).ravel() / m_diag if diag else np.array(qr_solve(M, b).full()).ravel()
        return np.concatenate([top, low])
    rho = _spectral_radius(matvec, n)
    return math.inf if rho == 0.0 else 2.6 / rho
