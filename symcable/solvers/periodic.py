"""Periodic steady state over one excitation period: direct collocation, harmonic balance,
and sweeps over the excitation period by continuation.

Generic over every formulation: these solvers see a :class:`~symcable.models.dynamic.DynamicModel`
(``dy/dt = f(y, t; p)`` with named parameter blocks, ``y_scale``, ``period``) and never a cable.

Direct collocation
------------------
Time is normalised, tau = t/T with T = 2 pi / omega and omega a parameter of the model (the
``omega`` block of p), so one set of CasADi functions serves every period of a sweep. The
period is cut into K equal intervals; on each, the scaled state ``w = y/y_scale`` is the
polynomial of degree d through its value at the interval start and at the d collocation
points (Radau IIA or Gauss-Legendre, ``ca.collocation_points``). The unknowns are those
K (d+1) states; the equations are the ODE at every collocation point (one mapped call of
``dyn_rhs``), continuity of each interval's end value with the next start, and periodicity
(the last interval's end is the first start), all written as rates (scaled states per
second), so the system is square. Along the model's exact linear invariants (see
:mod:`symcable.solvers.harmonic_balance`) periodicity is redundant and is replaced by fixing
their period-mean at the rest state's (through their known value at t = 0). The square
system is solved by IPOPT (zero objective) or by CasADi's Newton rootfinder (sparse LU),
started from the one-harmonic balance (the describing-function solution with every
nonlinearity equivalently linearised), itself started from the linear response at rest.
"""
from __future__ import annotations

import enum
import math
import time
from dataclasses import dataclass
from typing import Mapping, Sequence

import casadi as ca
import numpy as np

from ..codegen import use_codegen
from ..errors import ConvergenceError, SceneError, SymcableError
from ..models.dynamic import DynamicModel
from ..results_time import node_tension, range_warnings, slack_warnings
from ..results_periodic import PeriodicSolution, PeriodicSweep
from ..scene import Scene, load_scene
from . import harmonic_balance as hbm
from . import shooting
from .harmonic_balance import SquareSolver, choice

__all__ = ["PeriodicMethod", "CollocationScheme", "periodic_params", "solve_periodic",
           "sweep_periodic"]

#: Intervals per period. Radau IIA of degree 3 is of order 5 at the mesh points on a smooth
#: solution and of order 3 in stiff components; 40 intervals (120 collocation points) resolve
#: the first harmonics of the excitation to ~1e-5 of their amplitude, and the steps T/40 are
#: short against the fastest response that matters (drag makes the solution C^2 only, which
#: caps the order near 3 anyway). Stiff axial modes above 40/T are damped by Radau's L-stability.
DEFAULT_INTERVALS = 40
#: Harmonics of harmonic balance: the drag |v| v response decays like 1/h^3, 10 harmonics
#: put the fairlead tension within 0.1 % of its range of the collocation answer on seed 001.
DEFAULT_HARMONICS = 10


class PeriodicMethod(str, enum.Enum):
    """How the periodic steady state is computed."""

    COLLOCATION = "collocation"             #: direct collocation, K intervals of degree d
    HARMONIC_BALANCE = "harmonic-balance"   #: H harmonics, alternating frequency/time
    SHOOTING = "shooting"                   #: fixed point of the generalized-α period map


class CollocationScheme(str, enum.Enum):
    """Collocation points of each interval."""

    RADAU = "radau"        #: Radau IIA: the last point is the interval end (stiffly accurate)
    LEGENDRE = "legendre"  #: Gauss-Legendre: order 2d at the mesh points, A-stable only


# ---------------------------------------------------------------------------------------------
# collocation
@dataclass(frozen=True)
class CollocationGrid:
    """K intervals of degree d on tau in [0, 1). ``tau`` (d+1,) the local nodes (0 and the
    collocation points), ``C`` (d+1, d) derivatives of the Lagrange basis at the collocation
    points, ``end`` (d+1,) the basis at 1."""

    K: int
    d: int
    scheme: CollocationScheme
    tau: np.ndarray
    C: np.ndarray
    end: np.ndarray

    @classmethod
    def build(cls, K: int, d: int, scheme: CollocationScheme) -> "CollocationGrid":
        tau = np.array([0.0] + list(ca.collocation_points(d, scheme.value)))
        C, end = np.zeros((d + 1, d)), np.zeros(d + 1)
        for j in range(d + 1):
            L = np.poly1d([1.0])
            for r in range(d + 1):
                if r != j:
                    L *= np.poly1d([1.0, -tau[r]]) / (tau[j] - tau[r])
            C[j] = np.polyder(L)(tau[1:])
            end[j] = L(1.0)
        return cls(K, d, scheme, tau, C, end)

    def node_times(self) -> np.ndarray:
        """Normalised times of every unknown state, interval by interval (K (d+1),)."""
        return ((np.arange(self.K)[:, None] + self.tau[None, :]) / self.K).ravel()

    def states(self, x: np.ndarray, tau_out: np.ndarray, scale: np.ndarray) -> np.ndarray:
        """Dense output (len(tau_out), n_y): each interval's Lagrange polynomial, model units."""
        n = scale.size
        W = np.asarray(x, dtype=float).reshape(self.K, self.d + 1, n)  # natural order
        s = np.mod(np.asarray(tau_out, dtype=float), 1.0) * self.K
        k = np.minimum(np.floor(s).astype(int), self.K - 1)
        sig = s - k
        B = np.ones((sig.size, self.d + 1))
        for j in range(self.d + 1):
            for r in range(self.d + 1):
                if r != j:
                    B[:, j] *= (sig - self.tau[r]) / (self.tau[j] - self.tau[r])
        return np.einsum("tj,tjn->tn", B, W[k]) * scale


class Collocation:
    """The square collocation system of ``model`` on ``grid`` (see the module docstring).

    ``system.residual(x, p)``: x the scaled states at the nodes; r the collocation equations
    and the continuity equations (the last interval's wrap onto the first start carries the
    invariants' gauge, last). Both are ordered for the sparse LU, which CasADi's CSparse runs
    in the given order (no fill-reducing permutation): first the collocation points of each
    interval, state by state inside it (a band as narrow as the model's), paired with that
    interval's collocation equations; then the starts of intervals 1 .. K-1 and 0, paired
    with the continuity equations of intervals 0 .. K-1 (whose pivots are then exactly
    ``K/T I``). Eliminating an interval's points only couples its start to the next one, and
    the dense fill is confined to the column of the first start (the monodromy products):
    2.5 times faster than the natural interval-by-interval order on seed 001.
    ``natural[k, l, i]``: the position in x of state i at node l of interval k.
    """

    def __init__(self, model: DynamicModel, grid: CollocationGrid, inv: hbm.Invariants,
                 compiled: bool = False):
        self.model, self.grid, self.invariants = model, grid, inv
        n, S = model.n_y, model.y_scale
        K, d = grid.K, grid.d
        N = n * K * (d + 1)
        nat = np.arange(N).reshape(K, d + 1, n)  # natural index of (interval, node, state)
        last = np.setdiff1d(np.arange(n), inv.keep_states)
        order = np.concatenate([nat[:, 1:, :].transpose(0, 2, 1).ravel(), nat[1:, 0, :].ravel(),
                                nat[0, 0, inv.keep_states], nat[0, 0, last]])
        self.natural = np.argsort(order).reshape(K, d + 1, n)
        X = ca.MX.sym("w", N)
        P = ca.MX.sym("p", model.p.numel())
        omega = hbm._omega_symbol(model, P)
        T = 2.0 * math.pi / omega
        W = ca.reshape(X[self.natural.ravel().tolist()], n, K * (d + 1))
        eye = np.eye(K)
        Cblk = ca.DM(ca.sparsify(ca.DM(np.kron(eye, grid.C))))           # (K(d+1), K d)
        Eblk = ca.DM(ca.sparsify(ca.DM(np.kron(eye, grid.end[:, None]))))  # (K(d+1), K)
        start = np.zeros((d + 1, 1))
        start[0] = 1.0
        nxt = np.roll(eye, 1, axis=0)  # nxt[k+1, k] = 1: column k picks start k+1 (mod K)
        Sblk = ca.DM(ca.sparsify(ca.DM(np.kron(nxt, start))))
        sel = np.zeros((d + 1, d))
        sel[1:] = np.eye(d)
        Pblk = ca.DM(ca.sparsify(ca.DM(np.kron(eye, sel))))              # collocation columns
        tc = ((np.arange(K)[:, None] + grid.tau[None, 1:]) / K).ravel()
        Sd, Sinv = ca.diag(ca.DM(S)), ca.diag(ca.DM(1.0 / S))
        Wc = ca.mtimes(W, Pblk)
        F = model.functions(compiled).rhs.map(K * d)(ca.mtimes(Sd, Wc), ca.DM(tc).T * T, P)
        rate = K / T
        coll = rate * ca.mtimes(W, Cblk) - ca.mtimes(Sinv, F)           # (n, K d)
        cont = rate * (ca.mtimes(W, Sblk) - ca.mtimes(W, Eblk))          # (n, K)
        if inv.r:
            gauge = omega * (ca.mtimes(ca.DM(inv.G), W[:, 0] - ca.DM(inv.w0))
                             + _invariant_mean_offset(model, inv, P, omega))
            last = cont[:, K - 1]
            cont = ca.horzcat(cont[:, :K - 1], ca.vertcat(last[inv.keep.tolist()], gauge))
        # rows: the collocation equations interval by interval, state-major inside, then continuity
        coll_rows = ca.vertcat(*[ca.vec(coll[:, k * d:(k + 1) * d].T) for k in range(K)])
        self.system = hbm.SquareSystem(f"periodic_collocation_{K}x{d}{scheme_tag(grid.scheme)}",
                                       X, P, ca.vertcat(coll_rows, ca.vec(cont)), compiled)

    def to_natural(self, x: np.ndarray) -> np.ndarray:
        """Scaled states (K, d+1, n_y) by interval, node and state, from the unknown vector."""
        return np.asarray(x, dtype=float)[self.natural]

    def from_natural(self, W: np.ndarray) -> np.ndarray:
        """The unknown vector from scaled states (K, d+1, n_y) (or flattened)."""
        x = np.empty(self.natural.size)
        x[self.natural.ravel()] = np.asarray(W, dtype=float).ravel()
        return x

    def guess_from(self, states_of_tau) -> np.ndarray:
        """Unknown vector sampled from a callable tau -> states (len(tau), n_y)."""
        return self.from_natural(states_of_tau(self.grid.node_times()) / self.model.y_scale)

    def states(self, x: np.ndarray, tau: np.ndarray) -> np.ndarray:
        return self.grid.states(self.to_natural(x), tau, self.model.y_scale)


def _invariant_mean_offset(model: DynamicModel, inv: hbm.Invariants, P: ca.MX, omega: ca.MX,
                           samples: int = 32) -> ca.MX:
    """``mean(G w) - G w(0)`` over a period (r,), known in advance: ``G w' = g(t)`` with
    ``g = G f(y0, t)/y_scale`` whatever the state, so with ``g = sum a_h cos + b_h sin`` (zero
    mean) it is ``sum_h b_h / (h omega)``. Fixing ``G w(0)`` by it, rather than the mean of
    ``G w`` over every node, keeps each gauge row local (one start, not a dense row over all
    nodes of the Jacobian)."""
    tau = np.arange(samples) / samples
    Y0 = ca.DM(np.tile(model.y0[:, None], samples))
    g = ca.mtimes(ca.DM(inv.G / model.y_scale[None, :]),
                  model.functions().rhs.map(samples)(Y0, ca.DM(tau).T * (2.0 * math.pi / omega), P))
    h = np.arange(1, samples // 2)
    weights = (2.0 / samples) * np.sin(2.0 * math.pi * np.outer(tau, h)) / h[None, :]  # (M, H)
    return ca.mtimes(g, ca.DM(weights.sum(axis=1))) / omega


def scheme_tag(scheme: CollocationScheme) -> str:
    return "r" if scheme is CollocationScheme.RADAU else "g"


def _collocation(model: DynamicModel, grid: CollocationGrid, inv: hbm.Invariants,
                 compiled: bool = False) -> Collocation:
    """The collocation system, built once per (K, d, scheme, invariants, compiled), cached on
    the model; ``compiled``: on the model's generated-C right-hand side and its Jacobian."""
    cache = model._cache.setdefault("periodic_collocation", {})
    key = (grid.K, grid.d, grid.scheme.value, compiled)
    for col in cache.get(key, []):
        if col.invariants.same_as(inv):
            return col
    col = Collocation(model, grid, inv, compiled)
    cache.setdefault(key, []).append(col)
    return col


# ---------------------------------------------------------------------------------------------
# configuration
@dataclass(frozen=True)
class _Config:
    method: PeriodicMethod
    solver: SquareSolver
    intervals: int
    degree: int
    scheme: CollocationScheme
    harmonics: int
    samples: int | None
    ipopt_options: Mapping
    resolution: int
    tol: float
    codegen: bool | None = None
    steps: int = shooting.DEFAULT_STEPS
    rho_inf: float = 0.5


def _config(method, intervals, degree, scheme, solver, harmonics, samples, ipopt_options,
            resolution, tol, codegen=None, steps=None, rho_inf=0.5) -> _Config:
    method = choice(PeriodicMethod, method, "method")
    # an option of another method is a mistake, not something to ignore silently (the
    # default method is shooting, so intervals=... alone would otherwise do nothing)
    colloc, hb, shoot = (PeriodicMethod.COLLOCATION, PeriodicMethod.HARMONIC_BALANCE,
                         PeriodicMethod.SHOOTING)
    owners = {"intervals": (intervals, (colloc,)), "ipopt_options": (ipopt_options, (colloc, hb)),
              "harmonics": (harmonics, (hb,)), "samples": (samples, (hb,)),
              "steps": (steps, (shoot,))}
    for key, (value, allowed) in owners.items():
        if value is not None and method not in allowed:
            names = " or ".join(f"'{m.value}'" for m in allowed)
            raise SymcableError(f"{key} = {value!r}: an option of method = {names}, not of "
                                f"'{method.value}'; pass method={names.split(' or ')[0]}")
    default_solver = SquareSolver.IPOPT if method is PeriodicMethod.COLLOCATION else SquareSolver.NEWTON
    if method is PeriodicMethod.SHOOTING and solver is not None:
        raise SymcableError(f"solver = {solver!r}: shooting has its own solver (Anderson-accelerated "
                            "periods); give solver only with collocation or harmonic-balance")
    solver = default_solver if solver is None else choice(SquareSolver, solver, "solver")
    steps, rho_inf = shooting.check_shooting_args(steps, rho_inf)
    scheme = choice(CollocationScheme, "legendre" if scheme == "gauss" else scheme, "scheme")
    intervals = DEFAULT_INTERVALS if intervals is None else intervals
    harmonics = DEFAULT_HARMONICS if harmonics is None else harmonics
    for key, v, lo in (("intervals", intervals, 2), ("degree", degree, 1), ("harmonics", harmonics, 1),
                       ("resolution", resolution, 8)):
        if not isinstance(v, (int, np.integer)) or v < lo:
            raise SymcableError(f"{key} = {v!r}: must be an integer >= {lo}")
    if degree > 9:
        raise SymcableError(f"degree = {degree}: must be <= 9 (use more intervals instead)")
    if samples is not None and (not isinstance(samples, (int, np.integer)) or samples < 2 * harmonics + 1):
        raise SymcableError(f"samples = {samples!r}: must be an integer >= 2*harmonics+1 = "
                            f"{2 * harmonics + 1}")
    if ipopt_options is not None and not isinstance(ipopt_options, Mapping):
        raise SymcableError(f"ipopt_options = {ipopt_options!r}: must be a dict of IPOPT options")
    tol = (shooting.TOL if method is PeriodicMethod.SHOOTING else hbm.TOL) if tol is None else float(tol)
    if not tol > 0:
        raise SymcableError(f"tol = {tol}: must be > 0 (scaled states per second)")
    return _Config(method, solver, int(intervals), int(degree), scheme, int(harmonics),
                   None if samples is None else int(samples), dict(ipopt_options or {}),
                   int(resolution), tol, codegen, steps, rho_inf)


def periodic_params(model: DynamicModel, **blocks) -> np.ndarray:
    """The model's parameters for a periodic steady state (``p_periodic`` when the model has
    it: no start-up ramp), with named blocks replaced, e.g. ``omega=2*pi/T``."""
    base = getattr(model, "p_periodic", None)
    p = np.array(model.p_value if base is None else base, dtype=float)
    for name, value in blocks.items():
        p[model.p_slices[name]] = value
    return p


def _model_for(scene, model: DynamicModel | None) -> tuple[Scene, DynamicModel]:
    if not isinstance(scene, Scene):
        scene = load_scene(scene)
    if model is None:
        raise SymcableError(f"model = None: give the dynamic model of scene '{scene.name}' "
                            "(symcable.solve_periodic and symcable.sweep_periodic build it)")
    if model.period is None:
        raise SceneError(f"scene '{scene.name}' has no prescribed motion: a periodic response needs "
                         "an excitation (add [end_b.motion] with its period, s)")
    return scene, model


# ---------------------------------------------------------------------------------------------
# public API
def solve_periodic(scene, method: str = "shooting", *, intervals: int | None = None,
                   degree: int = 3, scheme: str = "radau", solver: str | None = None,
                   harmonics: int | None = None, samples: int | None = None,
                   ipopt_options: Mapping | None = None, resolution: int = 200,
                   model: DynamicModel | None = None, params: np.ndarray | None = None,
                   initial: PeriodicSolution | None = None,
                   tol: float | None = None, codegen: bool | None = None,
                   steps: int | None = None, rho_inf: float = 0.5,
                   started: float | None = None) -> PeriodicSolution:
    """Periodic steady state of a scene's dynamics over one period of its excitation, for a
    dynamic model already built; :func:`symcable.solve_periodic` builds it from a scene.

    Parameters
    ----------
    scene : Scene, dict or path
        Anything :func:`symcable.load_scene` takes; it must prescribe a motion.
    method : {"shooting", "collocation", "harmonic-balance"}
        Shooting (default): the fixed point of one period of ``simulate``'s generalized-α
        integrator, found by Anderson-accelerated marching, every period one call of
        generated C; the fastest periodic method to 1e-3 of the tension range on seed 001
        (studies/work_precision: 16-25 times faster than collocation), its answer carrying
        the integrator's error at ``steps`` (3.3e-4 of the range in max, min and first
        harmonic at the default 100; see :mod:`symcable.solvers.shooting`). Direct
        collocation (the most accurate), or harmonic balance.
    intervals : int, optional
        Collocation intervals K per period (default 40, see :data:`DEFAULT_INTERVALS`).
    degree : int
        Collocation degree d (points per interval), default 3.
    scheme : {"radau", "legendre"}
        Collocation points: Radau IIA (default) or Gauss-Legendre (``"gauss"`` also accepted).
    solver : {"ipopt", "newton"}, optional
        IPOPT on a zero-objective NLP (default for collocation), or CasADi's Newton rootfinder
        with a sparse LU (default for harmonic balance; usually faster).
    harmonics : int, optional
        Harmonics H of harmonic balance (default 10); for collocation, how many harmonics of
        the fairlead tension to report (default 10).
    samples : int, optional
        Time samples M of harmonic balance per period (default ``max(4H, 16)``, >= 2H+1).
    ipopt_options : dict, optional
        IPOPT options by their IPOPT names (``{"max_iter": 50, "print_level": 5}``), merged
        over the defaults ``print_level 0, sb yes, max_iter 100, tol and constr_viol_tol =
        tol, hessian_approximation limited-memory``.
    resolution : int
        Output times per period.
    model : DynamicModel
        The model built for this scene (:func:`symcable.build_dynamic_model`).
    params : ndarray (n_p,), optional
        Model parameters (default: the model's periodic steady-state parameters,
        ``model.p_periodic``, i.e. ``p_value`` without a start-up ramp).
    initial : PeriodicSolution, optional
        Start from this solution (its unknowns when the discretisation matches, else its
        states re-sampled in normalised time t/T) instead of the frequency-domain guess.
    tol : float, optional
        Residual tolerance, scaled states per second (default 1e-10). For shooting, the
        change of the scaled state over one period divided by the period (default 1e-8:
        the fixed point to ~1e-10 of the tension range, see :data:`shooting.TOL`).
    codegen : bool, optional
        The system's residual and Jacobian in generated C, which IPOPT or the Newton
        rootfinder call (compiled once per model structure and discretisation, then loaded
        from the build cache; parameters such as the period stay inputs); for shooting, the
        integrator's step. Default None: generated C when a C compiler is found
        (:mod:`symcable.codegen`). The small one-harmonic start is always solved in the
        virtual machine.
    steps : int, optional
        Shooting only: generalized-α steps per period (default 100, at least 8).
    rho_inf : float
        Shooting only: generalized-α spectral radius at infinite step, in [0, 1] (default
        0.5, as ``simulate``).
    started : float, optional
        ``time.perf_counter()`` when the caller began (:func:`symcable.solve_periodic`,
        which builds the model first): ``stats["wall_time"]`` counts from it.

    Returns
    -------
    PeriodicSolution
        ``status`` "converged"; "invalid" (with a warning naming the quantity and the limit)
        when the total axial strain of a segment, or an end tension over its segment's EA,
        leaves the line type's ``max_strain`` over the period: the dynamics are linearised
        about the static state and the numbers are then not an answer; else "slack" when the
        total tension reaches zero somewhere.

    Raises
    ------
    SceneError
        The scene prescribes no motion.
    ConvergenceError
        The solver did not converge; ``partial`` is the last iterate as a PeriodicSolution
        with status "failed", ``diagnostics`` the solver's return status and history.
    """
    t0 = time.perf_counter() if started is None else started
    cfg = _config(method, intervals, degree, scheme, solver, harmonics, samples, ipopt_options,
                  resolution, tol, codegen, steps, rho_inf)
    scene, model = _model_for(scene, model)
    p = periodic_params(model) if params is None else np.asarray(params, dtype=float)
    sol, _ = _solve(scene.name, model, p, cfg, initial=initial, t0=t0)
    return sol


def sweep_periodic(scene, periods: Sequence[float], method: str = "collocation", *,
                   intervals: int | None = None, degree: int = 3, scheme: str = "radau",
                   solver: str | None = None, harmonics: int | None = None,
                   samples: int | None = None, ipopt_options: Mapping | None = None,
                   resolution: int = 200, model: DynamicModel | None = None,
                   tol: float | None = None, codegen: bool | None = None,
                   steps: int | None = None, rho_inf: float = 0.5,
                   started: float | None = None) -> PeriodicSweep:
    """Fairlead tension response over excitation periods (a tension RAO), by continuation.

    Each period sets the ``omega`` block of the model's periodic parameters to 2 pi / T,
    so one set of CasADi functions serves the whole sweep; each solve starts from the previous
    period's solution (same normalised-time grid), and falls back to its own frequency-domain
    guess if that fails. The arguments are those of :func:`solve_periodic`.

    Returns
    -------
    PeriodicSweep
        A failed period has NaN results and status "failed" (and a warning).

    Raises
    ------
    ConvergenceError
        When every period fails.
    """
    t0 = time.perf_counter() if started is None else started
    cfg = _config(method, intervals, degree, scheme, solver, harmonics, samples, ipopt_options,
                  resolution, tol, codegen, steps, rho_inf)
    scene, model = _model_for(scene, model)
    if "omega" not in model.p_slices:
        raise SymcableError(f"model '{model.name}' has no omega parameter block: it cannot be swept "
                            "over the excitation period")
    periods = np.asarray(periods, dtype=float).ravel()
    if periods.size == 0 or not np.all(periods > 0):
        raise SymcableError(f"periods = {periods.tolist()} s: must be a non-empty list of values > 0")
    n = cfg.resolution
    rows = {k: np.full(periods.size, np.nan) for k in ("amp", "phase", "mean", "max", "min")}
    curves = np.full((periods.size, n), np.nan)
    statuses, warnings = [], []
    stats = {"iterations": [], "solve_time": [], "build_time": [], "start": []}
    prev = None
    for i, T in enumerate(periods):
        p = periodic_params(model, omega=2.0 * math.pi / T)
        sol, start = None, None
        own = "rest state" if cfg.method is PeriodicMethod.SHOOTING else "frequency-domain guess"
        for start in (["neighbour"] if prev is not None else []) + [own]:
            try:
                sol, build = _solve(scene.name, model, p, cfg,
                                    initial=prev if start == "neighbour" else None, t0=time.perf_counter())
                stats["build_time"].append(build)
                break
            except ConvergenceError as exc:
                warnings.append(f"period {T:g} s from the {start}: {exc}")
        if sol is None:
            statuses.append("failed")
            for key in ("iterations", "solve_time", "build_time"):
                stats[key].append(None)
            stats["start"].append(start)
            continue
        prev = sol
        ft = sol.fairlead_tension
        rows["amp"][i] = sol.fairlead_tension_harmonics_amplitude[1]
        rows["phase"][i] = sol.fairlead_tension_harmonics_phase[1]
        rows["mean"][i], rows["max"][i], rows["min"][i] = np.mean(ft), np.max(ft), np.min(ft)
        curves[i] = ft
        statuses.append(sol.status)
        warnings += [f"period {T:g} s: {w}" for w in sol.warnings]
        stats["iterations"].append(sol.stats["iterations"])
        stats["solve_time"].append(sol.stats["solve_time"])
        stats["start"].append(start)
    if all(s == "failed" for s in statuses):
        raise ConvergenceError(f"periodic sweep: no period converged ({warnings[-1]})", partial=None,
                               diagnostics={"warnings": warnings, "stats": stats})
    status = ("partial" if "failed" in statuses else "invalid" if "invalid" in statuses
              else "slack" if "slack" in statuses else "converged")
    stats["wall_time"] = time.perf_counter() - t0
    return PeriodicSweep(
        scene_name=scene.name, method=cfg.method.value, periods=periods,
        fairlead_tension_amplitude=rows["amp"], fairlead_tension_phase=rows["phase"],
        fairlead_tension_mean=rows["mean"], fairlead_tension_max=rows["max"],
        fairlead_tension_min=rows["min"], normalised_time=np.arange(n) / n,
        fairlead_tension=curves, statuses=tuple(statuses), status=status, stats=stats,
        warnings=tuple(warnings))


# ---------------------------------------------------------------------------------------------
# the solve
def _fourier_resample(states: np.ndarray, tau: np.ndarray) -> np.ndarray:
    """Trigonometric interpolation of uniform samples over a period (n, n_y) at tau (m,)."""
    n = states.shape[0]
    c = np.fft.rfft(states, axis=0) / n
    h = np.arange(c.shape[0])
    wgt = np.where((h == 0) | ((n % 2 == 0) & (h == n // 2)), 1.0, 2.0)
    ph = np.exp(2j * math.pi * np.outer(np.asarray(tau, dtype=float), h))
    return np.real(ph @ (wgt[:, None] * c))


def _solve(scene_name: str, model: DynamicModel, p: np.ndarray, cfg: _Config, *,
           initial: PeriodicSolution | None, t0: float) -> tuple[PeriodicSolution, float]:
    """One periodic solve; returns the solution and the time spent building its solver."""
    T = hbm.period_of(model, p)
    stats: dict = {"solver": cfg.solver.value}
    n = model.n_y
    if cfg.method is PeriodicMethod.SHOOTING:
        res, samples, guess = _shoot(model, p, cfg, initial)
        stats.update(solver="anderson", steps=cfg.steps, rho_inf=cfg.rho_inf, periods=res.iterations,
                     newton_iterations=guess.pop("newton_iterations"))
        natural = res.x

        def states_of(tau, Y=samples):
            return _fourier_resample(Y, tau)
    elif cfg.method is PeriodicMethod.HARMONIC_BALANCE:
        H, M = cfg.harmonics, cfg.samples or hbm.default_samples(cfg.harmonics)
        stats.update(harmonics=H, samples=M)
        C0 = None
        if initial is not None:
            same = (initial.method == cfg.method.value and initial.unknowns is not None
                    and initial.unknowns.size % n == 0 and initial.unknowns.size // n % 2 == 1)
            C0 = (np.asarray(initial.unknowns, dtype=float).reshape(n, -1) if same else
                  _fit_harmonics(initial, H, model.y_scale))
        out = hbm.solve_harmonic_balance(model, p, harmonics=H, samples=M, solver=cfg.solver,
                                         ipopt_options=cfg.ipopt_options, tol=cfg.tol, initial=C0,
                                         codegen=cfg.codegen)
        res, guess, natural = out.result, dict(out.guess), out.coefficients

        def states_of(tau, C=natural):
            return hbm.coefficient_states(C, tau, model.y_scale)
    else:
        grid = CollocationGrid.build(cfg.intervals, cfg.degree, cfg.scheme)
        stats.update(intervals=grid.K, degree=grid.d, scheme=grid.scheme.value)
        if initial is not None:
            col = _collocation(model, grid, hbm.linear_invariants(model, p), use_codegen(cfg.codegen))
            same = (initial.method == cfg.method.value and initial.unknowns is not None
                    and initial.unknowns.size == col.system.n
                    and initial.stats.get("scheme") == grid.scheme.value
                    and initial.stats.get("degree") == grid.d)
            x0 = (col.from_natural(initial.unknowns) if same else
                  col.guess_from(lambda tau: _fourier_resample(initial.states, tau)))
            guess = {"start": "given solution" + ("" if same else " (re-sampled)")}
        else:
            g1 = hbm.solve_harmonic_balance(model, p, harmonics=1, solver=SquareSolver.NEWTON,
                                            tol=cfg.tol)
            col = _collocation(model, grid, g1.hb.invariants, use_codegen(cfg.codegen))
            ok = g1.result.converged
            guess = {"start": "one-harmonic balance (describing function)" if ok
                     else "linear response at rest (one-harmonic balance failed)",
                     "iterations": g1.result.iterations, "residual_norm": g1.result.residual_norm,
                     "wall_time": g1.result.wall_time + g1.guess.get("wall_time", 0.0)}
            C1 = g1.coefficients if ok else hbm.linear_response(model, p).coefficients
            x0 = col.guess_from(lambda tau: hbm.coefficient_states(C1, tau, model.y_scale))
        res = col.system.solve(x0, p, cfg.solver, ipopt_options=cfg.ipopt_options, tol=cfg.tol)
        natural = col.to_natural(res.x)

        def states_of(tau, c=col, x=res.x):
            return c.states(x, tau)
    stats.update(iterations=res.iterations, return_status=res.return_status,
                 residual_norm=res.residual_norm, tolerance=cfg.tol, unknowns=int(res.x.size),
                 solve_time=res.wall_time, build_time=res.build_time, guess=guess, compiled=res.compiled,
                 wall_time=time.perf_counter() - t0)
    status = "converged" if res.converged else "failed"
    sol = _solution(scene_name, model, p, T, cfg, states_of, natural.ravel(), status, stats,
                    cfg.harmonics)
    if not res.converged:
        raise ConvergenceError(
            f"periodic {cfg.method.value} ({stats['solver']}): {res.return_status} after "
            f"{res.iterations} {'periods' if cfg.method is PeriodicMethod.SHOOTING else 'iterations'}, "
            f"residual {res.residual_norm:.3g} (tol {cfg.tol:.3g} "
            "scaled states per second)", partial=sol,
            diagnostics={"return_status": res.return_status, "iterations": res.iterations,
                         "residual_norm": res.residual_norm, "tolerance": cfg.tol,
                         "history": res.history, "guess": guess})
    return sol, res.build_time


def _shoot(model: DynamicModel, p: np.ndarray, cfg: _Config, initial: PeriodicSolution | None):
    """The shooting solve: ``(result, states over the period or None, guess description)``.
    The start is ``initial``'s state at t = 0 (its own unknowns when it is a shooting
    solution of the same steps), else the rest state; the invariants' level as collocation's."""
    tb = time.perf_counter()
    pm = shooting.period_map(model, p, cfg.steps, cfg.rho_inf, cfg.codegen)
    build = time.perf_counter() - tb
    inv = hbm.linear_invariants(model, p)
    gauge = _invariant_start(model, inv, p) if inv.r else None
    if (initial is not None and initial.method == PeriodicMethod.SHOOTING.value
            and initial.unknowns is not None and initial.unknowns.size == 2 * model.n_y
            and initial.stats.get("steps") == cfg.steps):
        z0, guess = np.asarray(initial.unknowns, dtype=float), {"start": "given solution"}
    elif initial is not None:
        z0 = shooting.start_state(pm, np.asarray(initial.states, dtype=float)[0], inv, gauge)
        guess = {"start": "given solution (its state at t = 0)"}
    else:
        z0 = shooting.start_state(pm, model.y0, inv, gauge)
        guess = {"start": "rest state"}
    res, samples, newton_its = shooting.solve_shooting(pm, z0, tol=cfg.tol)
    if samples is None:  # the very first period failed: nothing to show
        raise ConvergenceError(f"periodic shooting: {res.return_status} with dt = T/{cfg.steps}: try "
                               "more steps per period", partial=None,
                               diagnostics={"return_status": res.return_status, "history": res.history})
    res.build_time = build
    guess["newton_iterations"] = newton_its
    return res, samples, guess


def _invariant_start(model: DynamicModel, inv: hbm.Invariants, p: np.ndarray) -> np.ndarray:
    """Scaled level ``G w(0)`` of the invariants that puts their period-mean at the rest
    state's (the collocation's gauge, see :func:`_invariant_mean_offset`), (r,)."""
    cache = model._cache.setdefault("invariant_offset", {})
    off = cache.get(inv.G.tobytes())
    if off is None:
        P = ca.MX.sym("p", model.p.numel())
        omega = hbm._omega_symbol(model, P)
        off = cache[inv.G.tobytes()] = ca.Function(
            "invariant_offset", [P], [_invariant_mean_offset(model, inv, P, omega)])
    return inv.G @ inv.w0 - np.asarray(off(p).full()).ravel()


def _fit_harmonics(initial: PeriodicSolution, H: int, scale: np.ndarray) -> np.ndarray:
    """Scaled Fourier coefficients (n_y, 2H+1) of a solution's uniform states."""
    Y = np.asarray(initial.states, dtype=float) / scale
    n = Y.shape[0]
    c = np.fft.rfft(Y, axis=0) / n
    out = np.zeros((Y.shape[1], 2 * H + 1))
    out[:, 0] = c[0].real
    for h in range(1, min(H, (n - 1) // 2) + 1):
        out[:, 2 * h - 1], out[:, 2 * h] = 2 * c[h].real, -2 * c[h].imag
    return out


def _solution(scene_name, model, p, T, cfg, states_of, x, status, stats, n_harm) -> PeriodicSolution:
    """Dense output at ``resolution`` times, outputs, envelopes, harmonics, slack check."""
    n = cfg.resolution
    tau = np.arange(n) / n
    Y = states_of(tau)
    fns = model.functions()
    outs = fns.outputs.map(n)(Y.T, tau * T, p)
    outs = dict(zip(fns.outputs.name_out(), [o.full() for o in outs]))
    ft = outs["fairlead_tension"].ravel()
    force = outs["fairlead_force"].reshape(n, -1) if "fairlead_force" in outs else np.zeros((n, 0))
    tension = outs["tension"].T if "tension" in outs else np.zeros((n, 0))
    if tension.size:  # on the nodes, ends included: the end forces' magnitudes at the ends
        anchor = outs["anchor_tension"].ravel() if "anchor_tension" in outs else None
        tension = node_tension(tension, anchor, ft)
    axial_force = outs["axial_force"].reshape(-1, n).T if "axial_force" in outs else None
    c = np.fft.rfft(ft) / n
    H = min(n_harm, (n - 1) // 2)
    amp = np.concatenate([[c[0].real], 2.0 * np.abs(c[1:H + 1])])
    phase = np.concatenate([[0.0], np.angle(c[1:H + 1])])
    warnings = ()
    s_nodes = np.asarray(model.info["s_nodes"], dtype=float) if "s_nodes" in model.info else None
    if status == "converged":
        static = model.info.get("static")
        axial = outs.get("axial_force", outs.get("tension")).reshape(-1, n).T
        s_mid = s_nodes
        s_mid = 0.5 * (s_mid[:-1] + s_mid[1:]) if s_mid is not None and s_mid.size == axial.shape[1] + 1 \
            else np.arange(axial.shape[1])
        slack, warnings = slack_warnings(tau * T, s_mid, axial,
                                         None if static is None else static.axial_force)
        invalid = False
        if static is not None and "strain" in outs:
            total = np.asarray(static.strain) + outs["strain"].reshape(-1, n).T
            invalid, beyond = range_warnings(model, tau * T, s_mid, total, outs)
            warnings = beyond + warnings
        if invalid:
            status = "invalid"
        elif slack:
            status = "slack"
    slices = getattr(model, "p_slices", {}) or {}
    names = [""] * np.size(p)
    for block, sl in slices.items():
        idx = range(*sl.indices(np.size(p)))
        for i, k in enumerate(idx):
            names[k] = block if len(idx) == 1 else f"{block}[{i}]"
    return PeriodicSolution(
        scene_name=scene_name, method=cfg.method.value, period=float(T), time=tau * T, states=Y,
        fairlead_tension=ft, fairlead_force=force,
        tension_min=tension.min(axis=0) if tension.size else np.zeros(0),
        tension_max=tension.max(axis=0) if tension.size else np.zeros(0),
        fairlead_tension_harmonics_amplitude=amp, fairlead_tension_harmonics_phase=phase,
        status=status, stats=stats, warnings=tuple(warnings), unknowns=np.asarray(x, dtype=float),
        params=np.asarray(p, dtype=float), param_names=tuple(names) if all(names) else (),
        s=s_nodes if s_nodes is not None and s_nodes.size == tension.shape[1] else None,
        axial_force=axial_force)
