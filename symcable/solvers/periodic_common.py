"""What the generic periodic solvers share: the cache of their Functions, the square-system
solvers (IPOPT and CasADi's Newton), the spectral tools, and the independent check of a
claimed periodic solution.

The check
---------
A method hands over its solution as uniform samples ``(q, v, z)`` of one period, ``m`` of
them (4 times as many as the solver's own points), taken from its own interpolant. The
velocities ``q'`` and accelerations ``v'`` are the spectral (FFT) derivatives of those
samples, exact for the trigonometric interpolant and blind to how the solution was found;
collocation hands over its polynomials' own derivatives instead, so that its defect is the
DAE residual of the collocation solution itself between its points (the spectral derivative
of a piecewise polynomial would add the ringing of its derivative jumps at the mesh points).
The derived Functions ``qdot`` and ``acc_residual`` are then evaluated at every sample (one
mapped call each). The defects, scaled as the solvers scale their equations, are

- dynamic:    max |M(q) v' - f(q, v, z, t)| / scales.force
- kinematic:  max |q' - G(q) v| / v_ref          (v_ref the median velocity scale)
- constraint: max_i |g_i(q, v, z, t)| / g_scale_i  (``scales.g_scale()``: each row's typical
  magnitude in its own unit, as the time integrator judges its steps)

They are the discretisation error of the method measured in the equations (collocation
between its points, harmonic balance in the truncated harmonics, shooting in the
integrator's error), hence the error estimate; a solution is called converged only when the
solver met its tolerance, the periodicity defect is within it too, every sample is finite,
and the largest defect is below ``defect_tol``.
"""
from __future__ import annotations

import time
from dataclasses import dataclass
from typing import Callable, Mapping

import casadi as ca
import numpy as np

from ..mechanism.codegen import FastCall, compile_functions
from ..mechanism.functions import functions
from ..limits import current as current_limits, remaining_seconds
from ..progress import ProgressBar
from ..errors import ConvergenceError, SymcableError
from ..mechanism.mechanism import Mechanism
from ..results.periodic_generic import MechanismPeriodic, trig_interp
from .newton import newton
from .stepcache import StepCache, maybe_compiled

__all__ = ["PeriodicCache", "PERIODIC_CACHE", "SquareSystem", "Scaling", "spectral_derivative",
           "check_and_wrap", "StartFn", "IPOPT_DEFAULTS", "point_function"]

#: IPOPT defaults for a square system with zero objective: quiet, no NLP rescaling (the
#: residuals are already scaled, so IPOPT's constraint violation is the residual we check),
#: PORD ordering in MUMPS (steady on block-cyclic periodic Jacobians)
IPOPT_DEFAULTS = {"print_level": 0, "sb": "yes", "max_iter": 100, "mumps_pivot_order": 4,
                  "nlp_scaling_method": "none"}


#: Functions of the periodic solvers, per Mechanism and per key (method and the options that
#: shape the graph), built once: the same weak per-Mechanism cache as the integrators'
PeriodicCache = StepCache


#: the package's cache of periodic-solver Functions
PERIODIC_CACHE = PeriodicCache()


@dataclass(frozen=True)
class Scaling:
    """How the periodic solvers scale unknowns and equations (from ``mech.scales``).

    q, v, z : ndarray, the unknowns' scales; force : N (rows M a - f); v_ref : rows q' - G v;
    g : ndarray (n_z,), constraint rows g_i / g_i_scale (``scales.g_scale()``)."""

    q: np.ndarray
    v: np.ndarray
    z: np.ndarray
    force: float
    v_ref: float
    g: np.ndarray

    @classmethod
    def of(cls, mech: Mechanism) -> "Scaling":
        s = mech.scales
        pos = lambda a: np.where(np.asarray(a, float) > 0, np.asarray(a, float), 1.0)  # noqa: E731
        q, v, z = pos(s.q), pos(s.v), pos(s.z)
        return cls(q, v, z, float(s.force) if s.force > 0 else 1.0,
                   float(np.median(v)) if v.size else 1.0, pos(s.g_scale()))


#: a start: times (k,) -> (q (k, n_q), v (k, n_v), z (k, n_z))
StartFn = Callable[[np.ndarray], tuple]


def spectral_derivative(x: np.ndarray, period: float) -> np.ndarray:
    """d/dt of uniform samples ``x`` (m, n) of one period, by FFT (Nyquist term dropped)."""
    m = x.shape[0]
    if x.shape[1] == 0:
        return np.zeros_like(x)
    c = np.fft.rfft(x, axis=0)
    k = np.arange(c.shape[0], dtype=float)
    if m % 2 == 0:
        k[-1] = 0.0
    return np.fft.irfft(c * (2j * np.pi / period * k)[:, None], n=m, axis=0)


def rest_start(q0, z0, n_v: int) -> StartFn:
    """A start function constant at the static state (q0, z0) at rest."""
    q0, z0 = np.asarray(q0, float), np.asarray(z0, float)
    return lambda t: (np.tile(q0, (len(t), 1)), np.zeros((len(t), n_v)),
                      np.tile(z0, (len(t), 1)))


def start_from_samples(q, v, z, period) -> StartFn:
    """A start function interpolating uniform samples of one period."""
    q, v, z = (np.asarray(a, float) for a in (q, v, z))
    return lambda t: tuple(trig_interp(a, period, np.asarray(t, float)) for a in (q, v, z))


# ---------------------------------------------------------------------------------------------
class SquareSystem:
    """r(w; P) = 0, square, in scaled unknowns; solved by IPOPT (zero objective, equality
    constraints) or by CasADi's Newton rootfinder (sparse LU). Solvers built once, kept.
    ``compiled``: the residual is built on :func:`point_function`'s generated C.

    ``order``: None, or a callable returning ``(rows, unknowns)``, two permutations of
    range(n) under which the Jacobian is to be factorised (row ``rows[i]`` pivots on unknown
    ``unknowns[i]``), called once, when a Newton solver is first built. CasADi's sparse LU
    (``csparse``) factorises in the natural order of the unknowns it is given, preferring the
    diagonal pivot, so the fill, and with it the time of every factorisation, is that of the
    order the system is written in; the Newton solvers (the rootfinder and the damped
    fallback) see the system permuted by ``order``, IPOPT the system as written (MUMPS
    orders it itself). Their Jacobian is that of the system as written, permuted
    (:meth:`_jacobian`, the rootfinder's ``jacobian_function``): CasADi differentiating
    the permuted residual itself takes longer to build and to evaluate."""

    def __init__(self, name: str, residual: ca.Function, compiled: bool = False,
                 order: Callable[[], tuple] | None = None):
        self.name = name
        self.compiled = compiled  # built on the generated-C point functions
        self.residual = residual  # (w, P) -> r
        self.n = int(residual.size1_in(0))
        self.n_par = int(residual.size1_in(1))
        self._order = order
        self._solvers: dict = {}
        self._counters: dict = {}  # IPOPT iteration callbacks, kept alive with their solvers

    def _ordered(self) -> tuple:
        """(residual, rows, unknowns): the system the Newton solvers work on, permuted by
        ``order`` (r_o(w_o) = r(w)[rows] with w_o = w[unknowns]), or as written (rows and
        unknowns None)."""
        if "ordered" not in self._solvers:
            if self._order is None:
                self._solvers["ordered"] = (self.residual, None, None)
            else:
                rows, cols = (np.asarray(a, dtype=int) for a in self._order())
                w = ca.MX.sym("w", self.n)
                P = ca.MX.sym("P", self.n_par)
                r = self.residual(w[np.argsort(cols).tolist()], P)[rows.tolist()]
                self._solvers["ordered"] = (ca.Function(f"{self.name}_residual_ordered",
                                                        [w, P], [r], ["w", "P"], ["r"]),
                                            rows, cols)
        return self._solvers["ordered"]

    def _jacobian(self) -> ca.Function:
        """(w_o, P) -> (dr_o/dw_o, r_o) of :meth:`_ordered`'s system: the Jacobian of the
        system as written (its AD graph and colouring), rows and columns permuted."""
        if "jacobian" not in self._solvers:
            _, rows, cols = self._ordered()
            w = ca.MX.sym("w", self.n)
            P = ca.MX.sym("P", self.n_par)
            r = self.residual(w, P)
            J = ca.Function(f"{self.name}_jacobian", [w, P], [ca.jacobian(r, w), r])
            if cols is not None:
                J_o, r_o = J(w[np.argsort(cols).tolist()], P)
                J = ca.Function(f"{self.name}_jacobian_ordered", [w, P],
                                [J_o[rows.tolist(), cols.tolist()], r_o[rows.tolist()]])
            self._solvers["jacobian"] = J
        return self._solvers["jacobian"]

    def _rootfinder(self, tol: float, max_iter: int) -> ca.Function:
        key = ("newton", tol, max_iter)
        if key not in self._solvers:
            res, _, cols = self._ordered()
            opts = {"abstol": tol, "abstolStep": 1e-15, "max_iter": max_iter,
                    "linear_solver": "csparse", "error_on_fail": False,
                    "show_eval_warnings": False}
            if cols is not None:  # else CasADi differentiates the system as written itself
                opts["jacobian_function"] = self._jacobian()
            self._solvers[key] = ca.rootfinder(f"{self.name}_newton", "newton", res, opts)
        return self._solvers[key]

    def _step(self) -> ca.Function:
        if "step" not in self._solvers:
            w = ca.MX.sym("w", self.n)
            P = ca.MX.sym("P", self.n_par)
            J, r = self._jacobian()(w, P)
            self._solvers["step"] = ca.Function(f"{self.name}_step", [w, P],
                                                [r, -ca.solve(J, r, "csparse")],
                                                ["w", "P"], ["r", "dw"])
        return self._solvers["step"]

    def _damped(self, w0, P, tol, max_iter):
        step = self._step()

        def call(w, pp):
            r, dw = step(w, pp)
            return np.asarray(r).ravel(), np.asarray(dw).ravel()
        res = newton(call, w0, P, tol=tol, max_iter=max_iter, x_scale=np.ones(self.n))
        return res.x, ("success" if res.converged else res.message), res.iterations

    def _newton(self, w0, P, tol, max_iter, damped_only: bool):
        """CasADi's rootfinder, then (or only) the damped Newton, on the ordered system."""
        res, _, cols = self._ordered()
        w = w0 if cols is None else w0[cols]
        if damped_only:
            w, status, iters = self._damped(w, P, tol, max_iter)
        else:
            rf = self._rootfinder(tol, max_iter)
            start = w
            try:
                w = np.asarray(rf(start, P)).ravel()
                st = rf.stats()
                status, iters = st.get("return_status", "?"), int(st.get("iter_count", -1))
            except RuntimeError as exc:  # a singular Jacobian
                w, status, iters = start, "failed: " + str(exc).strip().splitlines()[-1], 0
            r = np.asarray(res(w, P)).ravel()
            if not (r.size == 0 or np.max(np.abs(r)) <= tol):
                w, st2, it2 = self._damped(start, P, tol, max_iter)
                status, iters = f"{status}; damped Newton: {st2}", iters + it2
        if cols is not None:
            w_nat = np.empty_like(w)
            w_nat[cols] = w
            w = w_nat
        return w, status, iters

    def _ipopt(self, options: Mapping) -> ca.Function:
        key = ("ipopt", repr(sorted(options.items())))
        if key not in self._solvers:
            w = ca.MX.sym("w", self.n)
            P = ca.MX.sym("P", self.n_par)
            nlp = {"x": w, "p": P, "f": ca.MX(0), "g": self.residual(w, P)}
            # zero objective and a square nonsingular Jacobian: the primal step is the Newton
            # step whatever the Hessian, so IPOPT gets a zero Lagrangian Hessian (no second
            # derivatives of the whole system to build)
            lam_f, lam_g = ca.MX.sym("lam_f"), ca.MX.sym("lam_g", self.n)
            counter = _IpoptIterations(f"{self.name}_iterations", self.n, self.n_par)
            self._counters[key] = counter
            opts = {"ipopt": dict(options), "print_time": False, "error_on_fail": False,
                    "calc_lam_p": False, "show_eval_warnings": False,
                    "iteration_callback": counter,
                    "hess_lag": ca.Function("nlp_hess_l", [w, P, lam_f, lam_g],
                                            [ca.MX(self.n, self.n)],
                                            ["x", "p", "lam_f", "lam_g"], ["hess_gamma_x_x"])}
            try:
                self._solvers[key] = ca.nlpsol(f"{self.name}_ipopt", "ipopt", nlp, opts)
            except RuntimeError as exc:
                reason = str(exc).strip().splitlines()[-1].split(": ", 1)[-1]
                raise SymcableError(f"ipopt_options = {dict(options)}: IPOPT refused them "
                                    f"({reason})") from None
        return self._solvers[key]

    def solve(self, w0, P, *, solver: str, tol: float, max_iter: int = 50,
              ipopt_options: Mapping | None = None) -> dict:
        """Solve from ``w0``; returns dict ``w``, ``iterations``, ``residual`` (max |r|),
        ``return_status``, ``wall_time`` (s).

        ``solver``: ``"ipopt"``; ``"newton"`` (CasADi's rootfinder, full steps; when it
        fails, the damped Newton of :mod:`symcable.solvers.newton` from the same start, its
        iterations added); ``"damped"`` (that damped Newton only: each step's move limited to
        1 in scaled units, Armijo backtracking)."""
        t0 = time.perf_counter()
        w0 = np.asarray(w0, float).ravel()
        if solver in ("damped", "newton"):
            w, status, iters = self._newton(w0, P, tol, max_iter, solver == "damped")
        elif solver == "ipopt":
            opts = dict(IPOPT_DEFAULTS)
            opts.update({"tol": tol, "constr_viol_tol": tol, "max_iter": max_iter,
                         "max_wall_time": float(current_limits().solve_seconds)})
            opts.update(dict(ipopt_options or {}))
            nlp = self._ipopt(opts)
            counter = self._counters[("ipopt", repr(sorted(opts.items())))]
            with ProgressBar(int(opts["max_iter"]), None, label=f"{self.name} (IPOPT)",
                             unit="iteration") as bar:
                # the call's deadline (limits.call_deadline) by the callback, not by
                # max_wall_time: an option is fixed when the solver is built, and the one
                # IPOPT solver serves every call (a sweep's, a cached system's)
                counter.start(bar, time.perf_counter() + remaining_seconds())
                try:
                    sol = nlp(x0=w0, p=P, lbg=0.0, ubg=0.0)
                finally:
                    counter.start(None)
            st = nlp.stats()
            w = np.asarray(sol["x"]).ravel()
            status, iters = st.get("return_status", "?"), int(st.get("iter_count", -1))
        else:  # options are validated before; a programming error otherwise
            raise SymcableError(f"solver = {solver!r}: must be 'ipopt' or 'newton'")
        r = np.asarray(self.residual(w, P)).ravel()
        res = float(np.max(np.abs(r))) if r.size else 0.0
        return {"w": w, "iterations": iters, "residual": res, "return_status": status,
                "wall_time": time.perf_counter() - t0}


class _IpoptIterations(ca.Callback):
    """IPOPT's iteration callback: counts the iterations into a progress bar (shown on a
    terminal once a solve has run a second, :class:`~symcable.progress.ProgressBar`), and
    stops IPOPT (a non-zero return: "User_Requested_Stop") once the call's deadline
    (``time.perf_counter()`` s; None: none) has passed."""

    def __init__(self, name: str, nx: int, n_par: int):
        ca.Callback.__init__(self)
        self.nx, self.n_par, self.count, self.bar, self.deadline = nx, n_par, 0, None, None
        self.construct(name, {})

    def start(self, bar, deadline: float | None = None) -> None:
        self.count, self.bar, self.deadline = 0, bar, deadline

    def get_n_in(self):
        return ca.nlpsol_n_out()

    def get_n_out(self):
        return 1

    def get_name_in(self, i):
        return ca.nlpsol_out(i)

    def get_name_out(self, i):
        return "ret"

    def get_sparsity_in(self, i):
        n = ca.nlpsol_out(i)
        if n == "f":
            return ca.Sparsity.scalar()
        if n in ("x", "lam_x", "g", "lam_g"):  # a square system: as many equations as unknowns
            return ca.Sparsity.dense(self.nx)
        if n == "lam_p":
            return ca.Sparsity.dense(self.n_par)
        return ca.Sparsity(0, 0)

    def eval(self, arg):
        self.count += 1
        if self.bar is not None:
            self.bar.update(self.count)
        late = self.deadline is not None and time.perf_counter() > self.deadline
        return [1 if late else 0]


def point_function(mech: Mechanism, name: str, compiled: bool) -> ca.Function:
    """The derived Function ``name`` (``"dae_residual"``, ``"acc_residual"``) of ``mech``, or,
    ``compiled``, it and its Jacobian in generated C (:mod:`symcable.mechanism.codegen`, cached): the
    periodic systems map it over their points, so the C is one point's, small, and the
    whole system's graph, its map and its sparse Jacobian stay in CasADi (compiling the
    mapped system itself writes out every point's Jacobian: minutes of C compiler)."""
    fn = getattr(functions(mech), name)
    if not compiled:
        return fn
    return PERIODIC_CACHE.get(mech, ("compiled", name), lambda: compile_functions(
        [fn], jacobians=True, what=f"the {name} of {mech.name}")[fn.name()])


# ---------------------------------------------------------------------------------------------
def _check_functions(mech: Mechanism, m: int, codegen: bool | None = False) -> tuple:
    """(acc_residual, qdot, outputs), each mapped over ``m`` samples and called through
    :class:`~symcable.mechanism.codegen.FastCall` (samples as rows in, flat column-major out); each in
    generated C where ``codegen`` resolves to True (:func:`~symcable.solvers.stepcache.
    maybe_compiled`: compiled once per Mechanism, the outputs shared with the integrators)."""
    F = functions(mech)

    def build():
        fns = [maybe_compiled(mech, (name,), getattr(F, name), codegen, f"the {name}")
               for name in ("acc_residual", "qdot", "outputs")]
        return tuple(FastCall(f.map(m)) for f in fns)
    return PERIODIC_CACHE.get(mech, ("check", m, codegen), build)


def _rows(a: np.ndarray) -> np.ndarray:
    """(m, n) samples as the flat column-major (n, m) a mapped Function takes."""
    return np.ascontiguousarray(a, dtype=float).ravel()


def defects(mech: Mechanism, period: float, p, q, v, z, qd=None, a=None, *,
            codegen: bool | None = False) -> dict:
    """The scaled equation residuals of uniform samples (see the module docstring);
    ``qd``, ``a``: the derivatives of q and v from the method's own interpolant (default:
    spectral); ``codegen``: the Functions in generated C (:func:`_check_functions`)."""
    sc = Scaling.of(mech)
    m = q.shape[0]
    t = period * np.arange(m) / m
    acc, qdot, _ = _check_functions(mech, m, codegen)
    qd = spectral_derivative(q, period) if qd is None else qd
    a = spectral_derivative(v, period) if a is None else a
    r_f, r_g = acc(_rows(q), _rows(v), _rows(a), _rows(z), t, p)
    G = qdot(_rows(q), _rows(v), _rows(z), t, p)[0]
    kin = np.max(np.abs(_rows(qd) - G)) / sc.v_ref if G.size else 0.0
    dyn = np.max(np.abs(r_f)) / sc.force if mech.n_v else 0.0
    con = np.max(np.abs(r_g.reshape(m, -1)) / sc.g[None, :]) if mech.n_z else 0.0
    return {"dynamic": float(dyn), "kinematic": float(kin), "constraint": float(con)}


def check_and_wrap(mech: Mechanism, period: float, p, q, v, z, *, method: str, solved: bool,
                   tol: float, defect_tol: float, stats: dict, why: str = "",
                   warnings: tuple = (), derivatives: tuple | None = None,
                   codegen: bool | None = False) -> MechanismPeriodic:
    """Check a claimed solution independently and return it, or raise ConvergenceError
    carrying it (status ``"failed"``) and the diagnostics. ``derivatives`` = (q', v') from
    the method's own interpolant where it is only piecewise smooth (collocation);
    ``codegen``: the check's Functions in generated C (:func:`_check_functions`)."""
    q, v, z = (np.asarray(a, float) for a in (q, v, z))
    m = q.shape[0]
    t = period * np.arange(m) / m
    finite = all(np.all(np.isfinite(a)) for a in (q, v, z))
    if finite:
        d = defects(mech, period, p, q, v, z, *(derivatives or ()), codegen=codegen)
        err = max(d.values())
    else:
        d, err = {}, float("nan")
    stats = dict(stats)
    stats.update({"defect": d, "error_estimate": err, "samples": m, "defect_tol": defect_tol})
    reasons = []
    if not solved:
        reasons.append(why or "the solver did not converge")
    if not finite:
        reasons.append("the solution is not finite")
    elif not err <= defect_tol:
        worst = max(d, key=d.get)
        reasons.append(f"{worst} defect {err:.3g} > defect_tol = {defect_tol:.3g} on the "
                       f"{m}-sample check grid (refine the discretisation)")
    pd = stats.get("periodicity_defect", 0.0)
    if not pd <= max(tol, 1e-13) * 10:
        reasons.append(f"periodicity defect {pd:.3g} > 10 tol = {10 * tol:.3g}")
    outputs = {}
    if finite:
        out = _check_functions(mech, m, codegen)[2]
        outputs = functions(mech).unpack(out(_rows(q), _rows(v), _rows(z), t, p)[0]
                                         .reshape(m, -1).T)
    status = "failed" if reasons else "converged"
    res = MechanismPeriodic(mech.name, float(period), t, q, v, z, np.asarray(p, float), outputs,
                            method, status, stats, tuple(warnings) + tuple(reasons))
    if reasons:
        raise ConvergenceError(f"periodic solution of {mech.name!r} by {method} failed: "
                               + "; ".join(reasons), partial=res, diagnostics=stats)
    return res
