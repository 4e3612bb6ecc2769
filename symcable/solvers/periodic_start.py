"""The periodic solvers' start from a short time run (collocation and harmonic balance always;
shooting after a ramped-in first period).

The run marches ``periods`` periods of generalized-alpha (``steps`` per period, rho_inf 0.8;
first order where the mechanism has kinematics) from the static state at rest, period by
period through shooting's period map (one call each), and the last period, interpolated
trigonometrically, is the start. A period in which a step fails (its Newton iteration did
not converge: a slack segment snapping taut, a node landing on the bed, a line held by
friction) is marched again by :func:`~symcable.solvers.integrate.integrate`, whose failed
steps are retried as 2, 4, ... 16 substeps, from the state the period began at; only if that
fails too is the start the static state itself, at rest.
"""
from __future__ import annotations

import numpy as np

from ..errors import ConvergenceError
from ..mechanism.mechanism import Mechanism
from .integrate import integrate
from .options import Shooting
from .periodic_common import rest_start, start_from_samples
from .shooting_mech import period_map

__all__ = ["START_PERIODS", "START_STEPS", "transient_start"]

#: the start's time run: periods marched from the static state, steps per period
START_PERIODS = 6
START_STEPS = 64
#: the start run's scaled Newton tolerance: a start, not an answer (at the integrator's
#: default 1e-10, below the roundoff floor of many 3D lines, its every period "failed")
START_NEWTON_TOL = 1e-8


def _substepped_period(mech: Mechanism, pm, x, period: float, p, codegen) -> tuple | None:
    """One period of ``pm``'s steps from the integrator state ``x`` at t = 0 by ``integrate``
    (failed steps retried as substeps): ((q, v, z) at t = 0, h, .., T - h; the state at T
    with its rates consistent), or None if even the substeps fail."""
    nq, nv = mech.n_q, mech.n_v
    q0, v0 = x[:nq], x[nq:nq + nv]
    try:
        tr = integrate(mech, period, period / pm.steps, method=pm.method, p=p, q0=q0, v0=v0,
                       codegen=codegen, progress=False)
    except ConvergenceError:
        return None
    if tr.time.size != pm.steps + 1 or not np.all(np.isfinite(tr.q)):
        return None
    q, v, z = tr.q[-1], tr.v[-1], tr.z[-1]
    x1, _ = pm.initial_state(q, v, z, 0.0, p)
    return (tr.q[:-1], tr.v[:-1], tr.z[:-1]), x1


def transient_start(mech: Mechanism, period: float, p, q0, z0, *,
                    periods: int = START_PERIODS, steps: int = START_STEPS,
                    codegen: bool | None = False, p_first=None) -> tuple:
    """(StartFn, info): the last of ``periods`` periods of generalized-alpha (module
    docstring) marched from the static state ``(q0, z0)`` at rest; the first period with the
    parameters ``p_first`` when given (a motion ramped in from rest: a held end that starts
    displaced at full amplitude jerks the line at its first step). ``info``: ``start`` (what
    it is), ``start_periods`` and ``start_substepped_periods`` (periods marched again with
    substeps)."""
    pm = period_map(mech, Shooting(steps=steps, rho_inf=0.8, newton_tol=START_NEWTON_TOL),
                    codegen)
    nv = mech.n_v
    q0, z0 = np.asarray(q0, float), np.asarray(z0, float)
    # the rates at t = 0 from the first period's parameters: from the full motion's (an end
    # displaced by its amplitude at t = 0) the start's acceleration is the jerk the ramp is
    # there to avoid (on a stiff line the first step can fail)
    x, _ = pm.initial_state(q0, np.zeros(nv), z0, 0.0, p if p_first is None else p_first)
    substepped, samples = 0, None
    for k in range(periods):
        pk = p_first if k == 0 and p_first is not None else p
        X, E = pm.march(x, period, pk)
        X, E = np.asarray(X), np.asarray(E).ravel()
        if np.all(E <= pm.method.tol) and np.all(np.isfinite(X)):
            samples, x = pm.samples(X), X[:, -1]
            continue
        again = _substepped_period(mech, pm, x, period, pk, codegen)
        if again is None:
            return rest_start(q0, z0, nv), {
                "start": f"static state (the start's time run failed in period {k + 1}, "
                         "also with substeps)", "start_periods": k,
                "start_substepped_periods": substepped}
        substepped += 1
        samples, x = again
    q, v, zz = samples
    with_sub = f", {substepped} of them with substeps" if substepped else ""
    return start_from_samples(q, v, zz, period), {
        "start": f"{periods} periods of generalized-alpha ({steps} steps each{with_sub}) from "
                 "the static state", "start_periods": periods,
        "start_substepped_periods": substepped}
