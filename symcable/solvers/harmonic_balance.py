"""Periodic steady state by harmonic balance, and what every periodic solver shares.

Harmonic balance, alternating frequency/time (AFT)
--------------------------------------------------
The unknowns are the real Fourier coefficients of the scaled state ``w = y / y_scale``,

    w(t) = a_0 + sum_{h=1..H} a_h cos(h w t) + b_h sin(h w t),

stored column by column as the matrix ``[a_0, a_1, b_1, ..., a_H, b_H]`` (n_y, 2H+1). The state
is sampled at M >= 2H+1 equally spaced times of the period, the model's rate f is evaluated
there by ONE mapped CasADi function (``dyn_rhs.map(M)``), and the residual ``w' - f/y_scale``
is projected back onto the harmonics (the discrete Fourier projection; ``w'`` is exact in the
coefficients). CasADi differentiates the whole map, so Newton has the exact Jacobian.
M defaults to ``max(4H, 16)``: drag ``|v| v`` is not a polynomial, and 4H samples keep the
aliasing of its harmonics above 3H out of the balanced ones (M = 3H+1 would be exact for a
quadratic nonlinearity only).

Shared by every periodic solver
-------------------------------
* :class:`SquareSystem`: a square system r(x; p) = 0 solved by IPOPT (an NLP with zero
  objective and equality constraints: IPOPT then takes Newton steps on the constraints with a
  filter line search) or by CasADi's Newton rootfinder (sparse LU, CSparse), with the damped
  Newton of :mod:`symcable.solvers.newton` as fallback.
* :func:`linear_invariants`: rows G with ``G f(y, t)/y_scale`` independent of y (for the
  planar cable with its closure stabilisation off, ``beta = 0``: the end-to-end compatibility
  of strain and angle, whose rate is the prescribed end velocity). Periodicity leaves ``G w``
  undetermined up to a constant, so each periodic system replaces the redundant periodicity
  rows in those directions by "the mean of ``G w`` over the period is the rest state's" (the
  excitation has zero mean). A model that stabilises its invariants has none: nothing to do.
* :func:`linear_response`: the response of the model linearised at rest (the period-mean of
  ``df/dy`` at y0) to the first harmonic of ``f(y0, t)``, the start of every periodic solve.
"""
from __future__ import annotations

import enum
import math
import time
from dataclasses import dataclass, field
from typing import Mapping

import casadi as ca
import numpy as np

from ..codegen import use_codegen
from ..errors import SymcableError
from ..models.dynamic import DynamicModel
from .newton import newton

__all__ = ["SquareSolver", "SquareSystem", "Invariants", "HarmonicBalance",
           "linear_invariants", "linear_response", "solve_harmonic_balance", "period_of"]

#: residual tolerance of every periodic solve, in scaled states per second (a state at its
#: typical magnitude ``y_scale`` changing by its magnitude per second is 1); the round-off floor
#: of the residuals of the planar cable at 50 segments is about 1e-12
TOL = 1e-10
NEWTON_MAX_ITER = 50
#: IPOPT defaults. With zero objective and a square nonsingular constraint Jacobian J, the
#: primal step of IPOPT's KKT system [[W, J'], [J, 0]] is the Newton step -J^-1 g whatever W
#: is, and the multipliers are zero; so the solvers hand IPOPT a zero Lagrangian Hessian
#: (no second derivatives of the whole map to build, and one factorisation per iteration,
#: where a limited-memory W needs several solves: 0.67 s against 0.85 s at 20 segments).
#: MUMPS's automatic ordering is erratic on these block-cyclic matrices (8 s against 0.7 s
#: at 20 segments for the same system in another row order); PORD, always built into
#: MUMPS, is steady.
IPOPT_DEFAULTS = {"print_level": 0, "sb": "yes", "max_iter": 100, "mumps_pivot_order": 4}
#: Newton uses a dense LU when the Jacobian is structurally fuller than this fraction and the
#: system small enough for a dense matrix (8000^2 doubles = 0.5 GB)
DENSE_FRACTION = 0.1
DENSE_MAX_N = 8000
#: singular values of the scaled rest Jacobian below this fraction of the largest are null
NULL_RTOL = 1e-9


class SquareSolver(str, enum.Enum):
    """How a square periodic system is solved."""

    IPOPT = "ipopt"    #: CasADi nlpsol with IPOPT (MUMPS), zero objective
    NEWTON = "newton"  #: CasADi rootfinder "newton" (CSparse LU), damped Newton as fallback


def choice(enum_cls, value, key: str):
    """``enum_cls(value)`` or a one-line SymcableError naming ``key`` and the choices."""
    try:
        return enum_cls(value.value if isinstance(value, enum.Enum) else value)
    except ValueError:
        allowed = ", ".join(repr(e.value) for e in enum_cls)
        raise SymcableError(f"{key} = {value!r}: must be one of {allowed}") from None


def period_of(model: DynamicModel, p) -> float:
    """Excitation period T for parameters ``p``, s: 2 pi / p[omega] when the model has an
    ``omega`` block, else ``model.period``."""
    if "omega" in model.p_slices:
        w = float(np.asarray(p, dtype=float)[model.p_slices["omega"]][0])
        if not w > 0.0:
            raise SymcableError(f"omega = {w} rad/s: a periodic solution needs omega > 0 "
                                "(a scene with a prescribed motion and its period)")
        return 2.0 * math.pi / w
    if model.period is None:
        raise SymcableError("model.period = None: the model has no excitation period")
    return float(model.period)


def _omega_symbol(model: DynamicModel, P: ca.MX) -> ca.MX:
    """omega as a symbol of the parameters when the model has it, so one function serves
    every period; else the model's constant."""
    if "omega" in model.p_slices:
        return P[model.p_slices["omega"].start]
    return ca.MX(2.0 * math.pi / float(model.period))


# ---------------------------------------------------------------------------------------------
# square systems
@dataclass
class SquareResult:
    """Outcome of :meth:`SquareSystem.solve` (residuals in the system's units)."""

    x: np.ndarray
    converged: bool
    iterations: int
    residual_norm: float
    return_status: str
    solver: str
    wall_time: float
    build_time: float = 0.0
    history: list = field(default_factory=list)
    compiled: bool = False


class SquareSystem:
    """A square system r(x; p) = 0 in scaled unknowns; solvers built on first use, cached.

    ``residual`` is the named CasADi function ``<name>_residual(x, p) -> r``.
    """

    def __init__(self, name: str, x: ca.MX, p: ca.MX, r: ca.MX, compiled: bool = False):
        if r.numel() != x.numel():  # a programming error in a system builder, not user input
            raise SymcableError(f"{name}: {r.numel()} equations for {x.numel()} unknowns")
        self.name = name
        self.residual = ca.Function(f"{name}_residual", [x, p], [r], ["x", "p"], ["r"])
        self.n = int(x.numel())
        self.compiled = compiled  # built on the model's generated-C functions
        self._solvers: dict = {}

    def evaluate(self, x, p) -> np.ndarray:
        return self.residual(x, p).full().ravel()

    def _nlp(self, options: dict, user: Mapping | None = None) -> ca.Function:
        key = ("ipopt", repr(sorted(options.items())))
        if key not in self._solvers:
            X = ca.MX.sym("x", self.n)
            P = ca.MX.sym("p", self.residual.size1_in(1))
            nlp = {"x": X, "p": P, "f": 0, "g": self.residual(X, P)}
            # no multipliers of the parameters: not needed, and a parameter may sit where
            # the model is not differentiable (a switched-off start-up ramp)
            opts = {"ipopt": dict(options), "print_time": False, "error_on_fail": False,
                    "calc_lam_p": False}
            if options.get("hessian_approximation", "exact") == "exact":
                lam_f, lam_g = ca.MX.sym("lam_f"), ca.MX.sym("lam_g", self.n)
                opts["hess_lag"] = ca.Function(
                    "nlp_hess_l", [X, P, lam_f, lam_g], [ca.MX(self.n, self.n)],
                    ["x", "p", "lam_f", "lam_g"], ["hess_gamma_x_x"])
            try:
                self._solvers[key] = ca.nlpsol(f"{self.name}_ipopt", "ipopt", nlp, opts)
            except RuntimeError as exc:
                reason = str(exc).strip().splitlines()[-1].split(": ", 1)[-1]
                raise SymcableError(f"ipopt_options = {dict(user or {})}: IPOPT refused them "
                                    f"({reason}); see the IPOPT options reference") from None
        return self._solvers[key]

    @property
    def linear_solver(self) -> str:
        """CasADi linear solver of the Newton steps: CSparse's sparse LU, or LAPACK's dense LU
        when the Jacobian is structurally more than DENSE_FRACTION full (a model whose rate
        couples every state, like a global constraint stabilisation, makes harmonic balance
        nearly dense; there CSparse, unblocked and without a fill-reducing ordering, is 3 times
        slower than LAPACK: 51 s against 18 s on seed 001 at 50 segments, H = 10)."""
        if "linear_solver" not in self._solvers:
            nnz = self.residual.sparsity_jac(0, 0).nnz()
            dense = nnz > DENSE_FRACTION * self.n ** 2 and self.n <= DENSE_MAX_N
            self._solvers["linear_solver"] = "lapacklu" if dense else "csparse"
        return self._solvers["linear_solver"]

    def _rootfinder(self, tol: float, max_iter: int) -> ca.Function:
        key = ("newton", tol, max_iter)
        if key not in self._solvers:
            self._solvers[key] = ca.rootfinder(
                f"{self.name}_newton", "newton", self.residual,
                {"abstol": tol, "abstolStep": 1e-14, "max_iter": max_iter,
                 "linear_solver": self.linear_solver, "error_on_fail": False})
        return self._solvers[key]

    def _step(self) -> ca.Function:
        if "step" not in self._solvers:
            X = ca.MX.sym("x", self.n)
            P = ca.MX.sym("p", self.residual.size1_in(1))
            r = self.residual(X, P)
            dx = -ca.solve(ca.jacobian(r, X), r, self.linear_solver)
            self._solvers["step"] = ca.Function(f"{self.name}_step", [X, P], [r, dx],
                                                ["x", "p"], ["r", "dx"])
        return self._solvers["step"]

    def solve(self, x0, p, solver: SquareSolver, *, ipopt_options: Mapping | None = None,
              tol: float = TOL) -> SquareResult:
        """Solve from ``x0``. ``ipopt_options`` (IPOPT names) are merged over
        :data:`IPOPT_DEFAULTS` and the tolerance; converged means IPOPT's success status, or
        Newton's max-norm residual <= ``tol``."""
        tb = time.perf_counter()
        x0 = np.asarray(x0, dtype=float)
        p = np.asarray(p, dtype=float)
        history: list = []
        if solver is SquareSolver.IPOPT:
            opts = {**IPOPT_DEFAULTS, "tol": tol, "constr_viol_tol": tol, **dict(ipopt_options or {})}
            nlp = self._nlp(opts, ipopt_options)
            t0 = time.perf_counter()
            try:
                sol = nlp(x0=x0, p=p, lbg=0.0, ubg=0.0)
            except RuntimeError as exc:
                raise SymcableError(f"IPOPT failed to run: {str(exc).strip().splitlines()[-1]}") from None
            st = nlp.stats()
            x = sol["x"].full().ravel()
            status, its = str(st.get("return_status", "?")), int(st.get("iter_count", -1))
            converged = status in ("Solve_Succeeded", "Solved_To_Acceptable_Level")
            rn = _norm(self.evaluate(x, p))
        else:
            rf = self._rootfinder(tol, NEWTON_MAX_ITER)
            t0 = time.perf_counter()
            try:
                x = rf(x0, p).full().ravel()
                st = rf.stats()
            except RuntimeError as exc:  # e.g. a singular Jacobian on the way
                x, st = x0, {"return_status": str(exc).strip().splitlines()[-1], "iter_count": 0}
            status, its = str(st.get("return_status", "?")), int(st.get("iter_count", -1))
            rn = _norm(self.evaluate(x, p))
            converged = bool(st.get("success")) and rn <= tol
            history.append({"path": "newton (CasADi rootfinder)", "iterations": its,
                            "return_status": status, "residual_norm": rn})
            if not converged:  # plain Newton went astray: Newton with a line search
                res = newton(lambda xx, pp: self._step()(xx, pp), x0, p, tol=tol,
                             max_iter=NEWTON_MAX_ITER)
                x, converged, rn = res.x, res.converged, res.residual_norm
                its += res.iterations
                status = "damped newton: " + res.message
                history.append({"path": "damped newton", "iterations": res.iterations,
                                "message": res.message, "residual_norm": rn,
                                "history": res.history})
        return SquareResult(x=x, converged=converged, iterations=its, residual_norm=rn,
                            return_status=status, solver=solver.value,
                            wall_time=time.perf_counter() - t0, build_time=t0 - tb,
                            history=history, compiled=self.compiled)


def _norm(r: np.ndarray) -> float:
    return float(np.max(np.abs(r))) if r.size else 0.0


# ---------------------------------------------------------------------------------------------
# invariants and the linear response at rest
@dataclass(frozen=True)
class Invariants:
    """Exact linear invariants of the scaled rate (see the module docstring).

    Attributes
    ----------
    G : ndarray (r, n_y)   orthonormal rows, scaled coordinates (r may be 0)
    keep : ndarray (n_y - r,) int   rows of a periodicity condition c = 0 to keep; the r others
        (where ``G[:, dropped]`` is best conditioned) follow from ``G c = 0``
    keep_states : ndarray (n_y - r,) int   states whose mean (or start) the square systems
        order first; the r others (where the right null vectors V of the rest Jacobian are best
        conditioned) are ordered last, with the gauge rows. Then the leading block, rows
        ``keep`` by states ``keep_states`` of the rest Jacobian, is nonsingular, and a
        natural-order LU finds its pivots on the diagonal.
    w0 : ndarray (n_y,)    the scaled rest state
    """

    G: np.ndarray
    keep: np.ndarray
    keep_states: np.ndarray
    w0: np.ndarray

    @property
    def r(self) -> int:
        return int(self.G.shape[0])

    def same_as(self, other: "Invariants") -> bool:
        if (self.G.shape != other.G.shape or not np.array_equal(self.keep, other.keep)
                or not np.array_equal(self.keep_states, other.keep_states)):
            return False
        return bool(np.max(np.abs(self.G.T @ self.G - other.G.T @ other.G), initial=0.0) < 1e-8)


def _pivots(B: np.ndarray) -> np.ndarray:
    """Columns of B (r, n) kept after greedy column pivoting drops the r best conditioned."""
    R, drop = B.copy(), []
    for _ in range(B.shape[0]):
        j = int(np.argmax(np.linalg.norm(R, axis=0)))
        q = R[:, j] / np.linalg.norm(R[:, j])
        R = R - np.outer(q, q @ R)
        drop.append(j)
    return np.setdiff1d(np.arange(B.shape[1]), np.array(drop, dtype=int))


def _sample_times(M: int) -> np.ndarray:
    return np.arange(M) / M


def rest_jacobian(model: DynamicModel, p, samples: int = 16) -> np.ndarray:
    """Period-mean of the scaled Jacobian ``S^-1 df/dy S`` at the rest state (n_y, n_y)."""
    S, T = model.y_scale, period_of(model, p)
    J = np.asarray(_rest_jacobian_function(model, samples)(p, T).full())
    return J * S[None, :] / S[:, None]


def _rest_jacobian_function(model: DynamicModel, samples: int) -> ca.Function:
    """``(p, T) -> mean_k df/dy(y0, k T / samples; p)``, built once per model and samples
    (one call, one sparse result: converting the mapped samples side by side to a dense
    array cost more than the evaluation)."""
    key = ("rest_jacobian_mean", samples)
    fn = model._cache.get(key)
    if fn is None:
        n = model.n_y
        P, T = ca.MX.sym("p", model.p.numel()), ca.MX.sym("T")
        J = model.functions().rhs_jacobian.map(samples)(
            ca.DM(np.tile(model.y0[:, None], samples)), ca.DM(_sample_times(samples)).T * T, P)
        mean = sum(J[:, k * n:(k + 1) * n] for k in range(samples)) / samples
        fn = model._cache[key] = ca.Function("rest_jacobian_mean", [P, T], [mean])
    return fn


def linear_invariants(model: DynamicModel, p, Jw: np.ndarray | None = None) -> Invariants:
    """Rows G (scaled coordinates) with ``G S^-1 f(y, t; p)`` independent of y: the left null
    space of the scaled rest Jacobian, kept only if it also annihilates the Jacobian at a
    random moving state (so it is exact, not a near-singularity). Cached on the model per
    parameter vector."""
    n, S = model.n_y, model.y_scale
    w0 = model.y0 / S
    cache = model._cache.setdefault("linear_invariants", {})
    key = np.asarray(p, dtype=float).tobytes()
    if key in cache:
        return cache[key]
    if len(cache) > 32:
        cache.clear()
    if Jw is None:
        Jw = rest_jacobian(model, p)
    U, s, Vt = np.linalg.svd(Jw)
    null = s <= NULL_RTOL * (s[0] if s.size and s[0] > 0 else 1.0)
    G, V = U[:, null].T, Vt[null]
    if G.shape[0]:
        rng = np.random.default_rng(12345)
        y = model.y0 + 0.5 * S * rng.standard_normal(n)
        t = rng.uniform(0.0, period_of(model, p))
        Jr = model.functions().rhs_jacobian(y, t, p).full() * S[None, :] / S[:, None]
        if np.max(np.abs(G @ Jr)) > 1e-8 * max(np.max(np.abs(Jr)), 1e-300):
            G, V = np.zeros((0, n)), np.zeros((0, n))
    inv = cache[key] = Invariants(G=G, keep=_pivots(G), keep_states=_pivots(V), w0=w0)
    return inv


@dataclass(frozen=True)
class LinearResponse:
    """First-harmonic response of the model linearised at rest, scaled coefficients
    ``[a_0, a_1, b_1]`` (n_y, 3); ``damping`` added to keep it finite at resonance (1/s)."""

    coefficients: np.ndarray
    damping: float
    invariants: Invariants


def linear_response(model: DynamicModel, p, samples: int = 16) -> LinearResponse:
    """Solve ``(i w I - A) Y = F_1`` with A the period-mean scaled Jacobian at rest and F_1 the
    projection of ``f(y0, t)`` on ``e^{i w t}``; the mean part from ``A a_0 = -F_0`` with the
    invariants' gauge. A small damping (1 % of w) is added when an eigenvalue of A lies within
    1 % of ``i w`` (an undamped resonance)."""
    n, S = model.n_y, model.y_scale
    T = period_of(model, p)
    w = 2.0 * math.pi / T
    Jw = rest_jacobian(model, p, samples)
    inv = linear_invariants(model, p, Jw)
    tau = _sample_times(samples)
    F = model.functions().rhs.map(samples)(np.tile(model.y0[:, None], samples),
                                           tau * T, p).full() / S[:, None]
    F0 = F.mean(axis=1)
    Fa = 2.0 / samples * F @ np.cos(2 * math.pi * tau)
    Fb = 2.0 / samples * F @ np.sin(2 * math.pi * tau)
    lam = np.linalg.eigvals(Jw)
    damping = 0.01 * w if np.min(np.abs(1j * w - lam)) < 0.01 * w else 0.0
    Y = np.linalg.solve((1j * w + damping) * np.eye(n) - Jw, Fa - 1j * Fb)
    a0 = np.linalg.lstsq(np.vstack([Jw, inv.G]), np.concatenate([-F0, np.zeros(inv.r)]),
                         rcond=None)[0]
    coef = np.column_stack([inv.w0 + a0, Y.real, -Y.imag])
    return LinearResponse(coefficients=coef, damping=damping, invariants=inv)


# ---------------------------------------------------------------------------------------------
# harmonic balance
def fourier_matrix(H: int, tau: np.ndarray) -> np.ndarray:
    """E (len(tau), 2H+1): w(tau) = C @ E.T for coefficients C = [a_0, a_1, b_1, ...]."""
    tau = np.asarray(tau, dtype=float)
    E = np.ones((tau.size, 2 * H + 1))
    for h in range(1, H + 1):
        E[:, 2 * h - 1] = np.cos(2 * math.pi * h * tau)
        E[:, 2 * h] = np.sin(2 * math.pi * h * tau)
    return E


class HarmonicBalance:
    """The AFT harmonic-balance system of ``model`` with H harmonics and M samples.

    ``system.residual(x, p)``: x = the scaled coefficients (n_y, 2H+1) state by state (the
    2H+1 coefficients of state 0, then of state 1 ...; see :meth:`pack`); r the projected
    residual ``w' - f/y_scale`` in the same layout (scaled states per second), except that the
    mean rows made redundant by the invariants are dropped and the gauge rows
    ``w G (a_0 - w0)`` come last, with the means they fix last among the unknowns.
    CasADi's CSparse factorises in the given order (no fill-reducing permutation), and this
    order keeps the Jacobian banded like the model's (each state couples to its neighbours in
    all harmonics) with the dense gauge rows at the end: in harmonic-major order the LU of
    the same matrix is ten times slower, and with the gauge rows in the middle eight.
    """

    def __init__(self, model: DynamicModel, H: int, M: int, inv: Invariants, compiled: bool = False):
        if M < 2 * H + 1:
            raise SymcableError(f"samples = {M}: harmonic balance with harmonics = {H} needs "
                                f"samples >= 2*harmonics+1 = {2 * H + 1}")
        self.H, self.M, self.invariants, self.model = H, M, inv, model
        n, S, m = model.n_y, model.y_scale, 2 * H + 1
        # unknown order: state-major, the mean of the gauged states last (they pair with the
        # dense gauge rows, which come last too)
        nat = np.arange(n * m).reshape(n, m)
        gauged = np.zeros((n, m), dtype=bool)
        gauged[np.setdiff1d(np.arange(n), inv.keep_states), 0] = True
        order = np.concatenate([nat[~gauged], nat[gauged]])
        self.position = np.argsort(order).reshape(n, m)  # position in x of coefficient (i, j)
        dropped_rows = np.zeros((n, m), dtype=bool)
        dropped_rows[np.setdiff1d(np.arange(n), inv.keep), 0] = True
        X = ca.MX.sym("c", n * m)
        P = ca.MX.sym("p", model.p.numel())
        C = ca.reshape(X[self.position.ravel().tolist()], m, n).T
        omega = _omega_symbol(model, P)
        tau = _sample_times(M)
        E = fourier_matrix(H, tau)
        proj = E.T * (2.0 / M)
        proj[0] *= 0.5
        D = np.zeros((m, m))
        for h in range(1, H + 1):
            D[2 * h - 1, 2 * h], D[2 * h, 2 * h - 1] = h, -h
        Sd, Sinv = ca.diag(ca.DM(S)), ca.diag(ca.DM(1.0 / S))
        Ys = ca.mtimes(Sd, ca.mtimes(C, ca.DM(E.T)))
        t = ca.DM(tau).T * (2.0 * math.pi / omega)
        Fw = ca.mtimes(Sinv, model.functions(compiled).rhs.map(M)(Ys, t, P))
        R = omega * ca.mtimes(C, ca.DM(D.T)) - ca.mtimes(Fw, ca.DM(proj.T))
        r = ca.vec(R.T)[nat[~dropped_rows].tolist()]
        if inv.r:
            r = ca.vertcat(r, omega * ca.mtimes(ca.DM(inv.G), C[:, 0] - ca.DM(inv.w0)))
        self.system = SquareSystem(f"periodic_hb{H}", X, P, r, compiled)

    def pack(self, C: np.ndarray) -> np.ndarray:
        """Unknown vector from scaled coefficients C (n_y, 2H+1)."""
        x = np.empty(self.position.size)
        x[self.position.ravel()] = np.asarray(C, dtype=float).ravel()
        return x

    def unpack(self, x: np.ndarray) -> np.ndarray:
        """Scaled coefficients (n_y, 2H+1) from the unknown vector."""
        return np.asarray(x, dtype=float)[self.position]

    def states(self, x: np.ndarray, tau: np.ndarray) -> np.ndarray:
        """States (len(tau), n_y) at normalised times tau = t/T, model units."""
        return coefficient_states(self.unpack(x), tau, self.model.y_scale)


def coefficient_states(C: np.ndarray, tau: np.ndarray, scale: np.ndarray) -> np.ndarray:
    """States (len(tau), n_y) of scaled Fourier coefficients C (n_y, 2H+1)."""
    H = (C.shape[1] - 1) // 2
    return (C @ fourier_matrix(H, tau).T).T * scale


def hb_system(model: DynamicModel, H: int, M: int, inv: Invariants,
              compiled: bool = False) -> HarmonicBalance:
    """The HB system, built once per (H, M, invariants, compiled) and cached on the model;
    ``compiled``: on the model's generated-C right-hand side and its Jacobian."""
    cache = model._cache.setdefault("periodic_hb", {})
    for hb in cache.get((H, M, compiled), []):
        if hb.invariants.same_as(inv):
            return hb
    hb = HarmonicBalance(model, H, M, inv, compiled)
    cache.setdefault((H, M, compiled), []).append(hb)
    return hb


def pad_coefficients(C: np.ndarray, H_to: int) -> np.ndarray:
    """Coefficients (n_y, 2H+1) as those of H_to harmonics (zeros added, or truncated)."""
    C = np.asarray(C, dtype=float)
    out = np.zeros((C.shape[0], 2 * H_to + 1))
    k = min(C.shape[1], 2 * H_to + 1)
    out[:, :k] = C[:, :k]
    return out


def default_samples(H: int) -> int:
    return max(4 * H, 16)


@dataclass
class HBResult:
    """Outcome of :func:`solve_harmonic_balance`: ``hb`` the system, ``result`` its solve,
    ``coefficients`` the scaled Fourier coefficients (n_y, 2H+1) of its last iterate,
    ``guess`` stats of how the start was made."""

    hb: HarmonicBalance
    result: SquareResult
    coefficients: np.ndarray
    guess: dict


def solve_harmonic_balance(model: DynamicModel, p, *, harmonics: int, samples: int | None = None,
                           solver: SquareSolver = SquareSolver.NEWTON,
                           ipopt_options: Mapping | None = None, tol: float = TOL,
                           initial: np.ndarray | None = None,
                           codegen: bool | None = False) -> HBResult:
    """Harmonic balance with ``harmonics`` harmonics from ``initial`` (scaled coefficients
    (n_y, 2H'+1), padded or truncated to H), or else from the one-harmonic balance, itself
    started from the linear response at rest. The one-harmonic balance is always solved by
    Newton (it is small) in the virtual machine; ``codegen`` applies to the H-harmonic
    system (see :func:`symcable.codegen.use_codegen`)."""
    compiled = use_codegen(codegen)
    t0 = time.perf_counter()
    H = int(harmonics)
    M = int(samples) if samples is not None else default_samples(H)

    def done(hb, res, guess):
        return HBResult(hb, res, hb.unpack(res.x), guess)

    if initial is not None:
        hb = hb_system(model, H, M, linear_invariants(model, p), compiled)
        guess = {"start": "given", "wall_time": time.perf_counter() - t0}
        return done(hb, hb.system.solve(hb.pack(pad_coefficients(initial, H)), p, solver,
                                        ipopt_options=ipopt_options, tol=tol), guess)
    lin = linear_response(model, p)
    inv = lin.invariants
    guess = {"start": "linear response at rest", "damping_added": lin.damping}
    if H == 1 and M == default_samples(1):
        hb = hb_system(model, 1, M, inv, compiled)
        res = hb.system.solve(hb.pack(lin.coefficients), p, solver, ipopt_options=ipopt_options,
                              tol=tol)
        guess["wall_time"] = time.perf_counter() - t0 - res.wall_time
        return done(hb, res, guess)
    hb1 = hb_system(model, 1, default_samples(1), inv)
    r1 = hb1.system.solve(hb1.pack(lin.coefficients), p, SquareSolver.NEWTON, tol=tol)
    guess.update(start="one-harmonic balance (describing function)", iterations=r1.iterations,
                 converged=r1.converged, residual_norm=r1.residual_norm)
    C1 = hb1.unpack(r1.x) if r1.converged else lin.coefficients
    hb = hb_system(model, H, M, inv, compiled)
    guess["wall_time"] = time.perf_counter() - t0
    res = hb.system.solve(hb.pack(pad_coefficients(C1, H)), p, solver,
                          ipopt_options=ipopt_options, tol=tol)
    return done(hb, res, guess)
