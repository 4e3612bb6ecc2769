"""Periodic steady state of any Mechanism: one entry point over three methods.

- :mod:`~symcable.solvers.collocation_mech`: direct collocation of the DAE over one period
  (Radau IIA or Gauss-Legendre), the square system solved by IPOPT or Newton;
- :mod:`~symcable.solvers.hbalance_mech`: harmonic balance, alternating frequency/time,
  Newton on the exact Jacobian;
- :mod:`~symcable.solvers.shooting_mech`: Newton with the exact monodromy on the period map
  of the generalized-alpha integrator of :func:`~symcable.solvers.integrate.integrate`.

Collocation and harmonic balance start from a short time run from the static equilibrium
(see :mod:`~symcable.solvers.hbalance_mech` for why not the linear response), shooting from
the equilibrium itself (its first periods are that run), or each from a given periodic
solution, and every answer goes through the same independent check
(:mod:`~symcable.solvers.periodic_common`) before it is called converged.
"""
from __future__ import annotations

import math
from typing import Mapping

import numpy as np

from ..mechanism.codegen import use_codegen
from ..errors import ConvergenceError, SymcableError
from ..limits import current as current_limits, past_deadline
from ..mechanism.mechanism import Mechanism
from ..results.generic import Equilibrium
from ..results.periodic_generic import MechanismPeriodic
from .collocation_mech import solve_collocation
from .equilibrium import solve_equilibrium
from .hbalance_mech import solve_hbalance
from .options import Collocation, HarmonicBalance, Shooting
from .periodic_fallback import STEP_MAX_ITER, continuation_applies, solve_by_continuation
from .periodic_common import rest_start, start_from_samples
from .periodic_start import START_PERIODS, transient_start
from .shooting_mech import solve_shooting

__all__ = ["solve_periodic_mech", "check_periodic", "with_state_rates", "DEFAULT_TOL",
           "DEFAULT_DEFECT_TOL", "STATE_RATE_PER_PERIOD"]

#: scaled residual every method solves its system to (states at their scale, forces at the
#: force scale): well above the round-off of a few hundred unknowns, well below any
#: discretisation error the methods reach
DEFAULT_TOL = 1e-9
#: the largest scaled equation defect on the check grid that is still called a solution: a
#: wrong answer (a bug, a solver stopped short, a discretisation that does not resolve the
#: response) leaves residuals of the order of the force scale between the solver's points;
#: a usable discretisation leaves a few per cent or less (Duffing, defect for state error:
#: collocation degree 2 at 20 intervals 0.086 for 5e-3; degree 3 at 40 intervals 8e-4 for
#: 2.5e-6; 5 harmonics 1.3e-3 for 2e-5; shooting at T/100 2e-3 for 9e-4)
DEFAULT_DEFECT_TOL = 0.1


#: the rate (1/s) at which the periodic solvers make first-order states with a rate block
#: (``StateNames.rate_blocks``: a free body's quaternion norm) relax, per period: 2 / T, so
#: their deviation falls by exp(-2) per period or faster (|e|^2: exp(-4)); fast enough not
#: to slow shooting's Anderson iteration (the multipliers of a cable's slow modes are larger),
#: slow against any step of the period
STATE_RATE_PER_PERIOD = 2.0


def _unrated(mech: Mechanism) -> list:
    """Indices (in the first-order states) of those without a rate block."""
    n = mech.n_q - mech.n_v
    st = mech.layout.states
    return [i for i in range(n) if st is None or not st.rate_block(i)]


def with_state_rates(mech: Mechanism, p, period: float):
    """``p`` (a copy) with every rate block of the mechanism's first-order states
    (``StateNames.rate_blocks``) that is 0 set to STATE_RATE_PER_PERIOD / ``period`` (1/s);
    None stays None."""
    st = mech.layout.states
    if p is None or st is None or not st.rate_blocks:
        return p
    out = np.array(p, dtype=float)
    for block in {b for b in st.rate_blocks if b}:
        sl = mech.params.slice(block)
        out[sl] = np.where(out[sl] == 0.0, STATE_RATE_PER_PERIOD / period, out[sl])
    return out


def check_periodic(mech: Mechanism) -> None:
    """Refuse a mechanism with first-order states fixed only by rest rows
    (``Mechanism.rest``) and without a rate block (``StateNames.rate_blocks``, which the
    periodic solvers set: :func:`with_state_rates`), with one message naming them
    (``layout.states``: what they are, the setting that adds them and the one that does
    without).

    Their rates vanish at rest whatever their value (statics fixes them by the rest rows
    alone): the seabed friction's bristle, for one, keeps any deflection while it sticks. A
    periodic motion in which such a state never slips is periodic for every value of it, so
    the periodic states form a family and each method's system is singular (near-singular
    under a smooth slip law)."""
    if mech.rest is None:
        return
    bad = _unrated(mech)
    if not bad:
        return
    n = len(bad)
    st = mech.layout.states
    what, head, instead = f"{n} first-order states", "", ("solve the periodic response of a "
                                                          "mechanism without them, or run it "
                                                          "in time")
    if st is not None:
        names = [st.names[i] for i in bad]
        shown = ", ".join(names[:2]) + (f", ..., {names[-1]}" if n > 2 else "")
        what += f" ({shown}; {st.unit})"
        head = f"{st.source}: " if st.source else ""
        instead = f"use {st.without} for periodic solves" if st.without else instead
    raise SymcableError(
        f"{head}not for a periodic solve: the {what} of mechanism {mech.name!r} are fixed at "
        "rest only by their rest rows, and one whose rate vanishes at rest (a bristle that "
        "never slips) keeps any value, so the periodic states form a family and the solve is "
        f"singular; {instead}")


def _static_base(mech: Mechanism, start) -> tuple:
    if isinstance(start, Equilibrium):
        return np.asarray(start.q, float), np.asarray(start.z, float), "given equilibrium"
    st = next(iter(mech.starts()))
    if mech.n_q != mech.n_v:
        # kinematics with n_q != n_v (the planar cable's segment coordinates against its node
        # velocities): solve_equilibrium's tangent stiffness is square in q and v, so the
        # mechanism's own static start is the base (for the planar cable, its exact rest)
        return np.asarray(st.q, float), np.asarray(st.z, float), f"static start {st.source!r}"
    try:
        eq = solve_equilibrium(mech, require_stable=False)
        return eq.q, eq.z, "static equilibrium"
    except ConvergenceError:
        return np.asarray(st.q, float), np.asarray(st.z, float), f"static start {st.source!r}"


def solve_periodic_mech(mech: Mechanism, period: float, method=None, *, p=None, start=None,
                        ipopt_options: Mapping | None = None, tol: float = DEFAULT_TOL,
                        defect_tol: float = DEFAULT_DEFECT_TOL,
                        max_iter: int | None = None,
                        codegen: bool | None = False, start_p=None,
                        fallback: bool = True) -> MechanismPeriodic:
    """The periodic response of ``mech`` with period ``period``.

    Parameters
    ----------
    mech : Mechanism
        Its forcing (explicit in t, or prescribed motion) must have period ``period``.
    period : float, s, > 0
    method : Collocation | HarmonicBalance | Shooting, default Collocation()
    p : ndarray (n_p,), optional
        Parameters; default the mechanism's own (with its motion and forcing).
    start : MechanismPeriodic | Equilibrium | None
        A periodic solution of the same period to start from, or the static state the
        start's short time run begins at (default: solved by ``solve_equilibrium``).
    start_p : ndarray (n_p,), optional
        With a static start: the parameters of that time run's first period (the motion
        ramped in from rest, where ``p`` holds it at full amplitude from t = 0); shooting
        then also starts from that run (two periods) instead of from rest.
    ipopt_options : mapping, optional
        Passed to IPOPT (collocation with ``solver="ipopt"``), over the defaults.
    tol : float
        Scaled residual the method's system is solved to (see the method modules).
    defect_tol : float
        Largest scaled equation defect on the check grid accepted as converged.
    max_iter : int, optional
        Newton / IPOPT iterations (defaults: collocation 100, harmonic balance 50,
        shooting 30).
    fallback : bool
        With a static start (``start`` None or an Equilibrium): where the method's solver
        does not converge from that start, solve again by continuation in the motion
        amplitude (:mod:`~symcable.solvers.periodic_fallback`, which says where it applies),
        with a warning saying so; every solve on the way is checked as the direct one.
        False: the direct solve only.
    codegen : bool or None
        Collocation and harmonic balance: the per-point residual and its Jacobian in
        generated C; shooting: the first-order step kernel (:func:`symcable.mechanism.codegen.
        use_codegen`: None is C where it pays; default False, the virtual machine); all
        three: the check's functions on its grid. Shooting's second-order step and the
        exact-monodromy step of its Newton fallback are CasADi rootfinders and stay in the
        virtual machine.

    Returns
    -------
    MechanismPeriodic (status ``"converged"``)

    Raises
    ------
    SymcableError
        Bad arguments (period <= 0, unknown method, wrong sizes); a mechanism with
        first-order states held only by rest rows (:func:`check_periodic`).
    ConvergenceError
        The solver failed or the solution failed the checks; ``partial`` is the result with
        status ``"failed"``, ``diagnostics`` its stats.
    """
    method = Collocation() if method is None else method
    if not isinstance(method, (Collocation, HarmonicBalance, Shooting)):
        raise SymcableError(f"method = {method!r}: must be Collocation(...), "
                            "HarmonicBalance(...) or Shooting(...)")
    try:
        period = float(period)
    except (TypeError, ValueError):
        raise SymcableError(f"period = {period!r}: must be a number of seconds > 0") from None
    if not (math.isfinite(period) and period > 0):
        raise SymcableError(f"period = {period!r} s: must be finite and > 0")
    for key, val in (("tol", tol), ("defect_tol", defect_tol)):
        if not (isinstance(val, (int, float)) and math.isfinite(val) and val > 0):
            raise SymcableError(f"{key} = {val!r}: must be a number > 0")
    if max_iter is not None and not (isinstance(max_iter, int) and max_iter >= 1):
        raise SymcableError(f"max_iter = {max_iter!r}: must be an integer >= 1")
    if ipopt_options is not None and not isinstance(ipopt_options, Mapping):
        raise SymcableError(f"ipopt_options = {ipopt_options!r}: must be a mapping of IPOPT "
                            "option names to values")
    check_periodic(mech)
    p = mech.params.values if p is None else np.asarray(p, dtype=float).ravel()
    if p.size != mech.params.n:
        raise SymcableError(f"p has {p.size} entries, the mechanism {mech.name!r} "
                            f"{mech.params.n}")
    # first-order states that relax at a rate set here (a free body's quaternion norm)
    p = with_state_rates(mech, p, period)
    if start_p is not None:
        start_p = with_state_rates(mech, np.asarray(start_p, dtype=float).ravel(), period)

    if not (start is None or isinstance(start, (Equilibrium, MechanismPeriodic))):
        raise SymcableError(f"start = {type(start).__name__}: must be a MechanismPeriodic, an "
                            "Equilibrium or None")
    kw = {"tol": tol, "defect_tol": defect_tol, "ipopt_options": ipopt_options,
          "max_iter": max_iter, "codegen": codegen}
    static = None if isinstance(start, MechanismPeriodic) else _static_base(mech, start)
    try:
        return _solve(mech, period, method, p, start, start_p, static, **kw)
    except ConvergenceError as first:
        if not (fallback and static is not None and continuation_applies(mech, p, start_p, first)):
            raise
        if past_deadline():  # the call's time is spent: no continuation
            raise ConvergenceError(f"{str(first).strip().splitlines()[0]}; no continuation "
                                   f"in the motion amplitude: the call's time limit of "
                                   f"{current_limits().solve_seconds} s (sc.limits("
                                   "solve_seconds=...), --max-solve-seconds) has passed",
                                   partial=first.partial,
                                   diagnostics=first.diagnostics) from None

        # a continuation step that Newton does not close within STEP_MAX_ITER iterations is
        # halved rather than iterated on (shooting's periods are capped by their own budget)
        kw_step = kw if isinstance(method, Shooting) else dict(
            kw, max_iter=min(max_iter or STEP_MAX_ITER, STEP_MAX_ITER))

        def again(pp, prev, sp):  # one solve of the continuation: from prev, or as above
            return _solve(mech, period, method, pp, start if prev is None else prev, sp, static,
                          **kw_step)
        return solve_by_continuation(again, mech, p, first, start_p=start_p)


def _solve(mech: Mechanism, period: float, method, p, start, start_p, static, *, tol,
           defect_tol, ipopt_options, max_iter, codegen) -> MechanismPeriodic:
    """One periodic solve of :func:`solve_periodic_mech` (arguments checked there) from
    ``start`` (a MechanismPeriodic), or from ``static`` = (q0, z0, what) by the method's own
    start."""
    if isinstance(start, MechanismPeriodic):
        if abs(start.period - period) > 1e-12 * period:
            raise SymcableError(f"start.period = {start.period} s: the start must have the "
                                f"period solved for, {period} s")
        start_fn = start_from_samples(start.q, start.v, start.z, period)
        info = {"start": f"periodic solution by {start.method}", "start_iterations": 0}
    else:
        q0, z0, base = static
        if start_p is not None:  # a first period with the motion ramped in from rest
            p_first = np.asarray(start_p, dtype=float).ravel()
            if p_first.size != mech.params.n:
                raise SymcableError(f"start_p has {p_first.size} entries, the mechanism "
                                    f"{mech.name!r} {mech.params.n}")
            n = 2 if isinstance(method, Shooting) else START_PERIODS
            start_fn, info = transient_start(mech, period, p, q0, z0, codegen=codegen,
                                             periods=n, p_first=p_first)
            info["start"] = f"{info['start']} about the {base}, the first period ramped"
        elif isinstance(method, Shooting):  # its own first periods are the transient
            start_fn = rest_start(q0, z0, mech.n_v)
            info = {"start": f"the {base} at rest", "start_periods": 0}
        else:
            start_fn, info = transient_start(mech, period, p, q0, z0, codegen=codegen)
            info["start"] = f"{info['start']} about the {base}"

    kw = {"tol": tol, "defect_tol": defect_tol}
    if max_iter is not None:
        kw["max_iter"] = max_iter
    if isinstance(method, Collocation):
        return solve_collocation(mech, period, method, p, start_fn, info,
                                 ipopt_options=ipopt_options, compiled=use_codegen(codegen),
                                 **kw)
    if isinstance(method, HarmonicBalance):
        return solve_hbalance(mech, period, method, p, start_fn, info,
                              compiled=use_codegen(codegen), **kw)
    state0 = None
    if (isinstance(start, MechanismPeriodic) and start.method == "shooting"
            and start.stats.get("state0") is not None
            and start.stats.get("steps") == method.steps
            and (method.rho_inf is None or start.stats.get("rho_inf") == method.rho_inf)):
        # the integrator's own state at t = 0, rates included: a shooting solution of the same
        # discretisation restarts exactly (one period confirms it)
        state0 = start.stats["state0"]
        info["start"] = "shooting solution (its integrator state at t = 0)"
    return solve_shooting(mech, period, method, p, start_fn, info, state0=state0,
                          codegen=codegen, **kw)
