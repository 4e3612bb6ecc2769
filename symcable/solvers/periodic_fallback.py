"""Continuation in the motion amplitude: the periodic solvers' fallback where the solve from
the method's own start fails.

Why
---
Every periodic method needs a start near the periodic response. Its own (a short time run
from the static state, or for shooting the static state at rest) can be far from it when
the motion is large against what the line takes: an end held at its full displacement from
t = 0 jerks a stiff line; a slack-and-snap or a landing
response is far from the static state; a line held by friction creeps towards its periodic
position over many periods. From the static state the response at a small amplitude is
close (the static state itself is its limit), and each periodic response is a good start
for the one at a somewhat larger amplitude: the path from 0 to the full amplitude is
followed in steps.

How
---
The amplitude factor s scales every parameter block named ``motion`` (``AMPLITUDE_BLOCK``,
the last dotted part of the name: ``line1.motion`` in a scene of several lines), the
prescribed motion's own scale (cable3d: the end's displacement is ``motion`` times the
harmonic one), and every block named ``wave_scale`` (``WAVE_BLOCK``: the sea's amplitude). The periodic problem is solved at s = ``FIRST_STEP`` from the method's own
start, then at s + ds from the last solution (shooting restarts from its integrator's state,
the others from its samples), ds doubled after a success and halved after a failure, until
s = 1; it gives up when ds falls below ``MIN_STEP`` or after ``MAX_SOLVES`` solves. Each solve
is a full solve with its checks; the answer is the one at s = 1, checked like any other.

Where it applies (:func:`continuation_applies`)
-----------------------------------------------
- The method's solver did not converge (its residual above its tolerance). A solve that
  converged and was refused by the check (a defect above ``defect_tol``: the discretisation
  does not resolve the response) is not retried: the same solution would be found again.
- The mechanism has a ``motion`` or ``wave_scale`` block.
- Its first solve starts where the motion fits: a mechanism whose motion can ramp in (a
  block named ``ramp``, ``RAMP_BLOCK``) that ``p`` holds at full amplitude from t = 0
  (ramp 0) needs ``start_p``, the parameters of a ramped first period for the start's time
  run; from the static state its first solve would meet the end displaced by s A at t = 0
  (on a stiff line still a jerk at small s). The cable3d API
  solves again with ``start_p`` when the direct solve fails, so that there the order is the
  direct solve, the solve from the ramped start, then this continuation from that start.
"""
from __future__ import annotations

import dataclasses
from typing import Callable

import numpy as np

from ..errors import ConvergenceError
from ..limits import current as current_limits, past_deadline
from ..mechanism.mechanism import Mechanism

__all__ = ["AMPLITUDE_BLOCK", "WAVE_BLOCK", "RAMP_BLOCK", "FIRST_STEP", "MIN_STEP", "MAX_SOLVES",
           "STEP_MAX_ITER", "amplitude_slices", "continuation_applies", "solve_by_continuation",
           "solver_converged", "with_amplitude"]

#: the parameter block (last dotted part of its name) that scales a prescribed motion
AMPLITUDE_BLOCK = "motion"
#: ... and the one that scales the sea's waves (:mod:`symcable.models.common.waves`)
WAVE_BLOCK = "wave_scale"
#: the parameter block that ramps a prescribed motion in over the first period (1) or holds
#: it at full amplitude from t = 0 (0)
RAMP_BLOCK = "ramp"
#: the first amplitude factor, the smallest step of it, and the most solves of one path
FIRST_STEP = 0.25
MIN_STEP = 1.0 / 32.0
MAX_SOLVES = 12
#: Newton iterations of one continuation solve (collocation, harmonic balance): from the last
#: solution a step converges in a few, and one that does not is cheaper halved than iterated
STEP_MAX_ITER = 20


def _blocks(mech: Mechanism, name: str) -> list:
    return [mech.params.slice(b) for b in mech.params.names if b.split(".")[-1] == name]


def solver_converged(exc: ConvergenceError) -> bool:
    """Whether the failed solve's solver met its tolerance (the check refused it)."""
    d = getattr(exc, "diagnostics", None) or {}
    res, tol = d.get("residual"), d.get("tolerance")
    return res is not None and tol is not None and bool(np.isfinite(res)) and res <= tol


def continuation_applies(mech: Mechanism, p, start_p, first: ConvergenceError) -> bool:
    """Whether :func:`solve_by_continuation` is tried after ``first`` (module docstring)."""
    if solver_converged(first) or not amplitude_slices(mech):
        return False
    held = any(np.all(np.asarray(p, float)[sl] == 0.0) for sl in _blocks(mech, RAMP_BLOCK))
    return start_p is not None or not held


def amplitude_slices(mech: Mechanism) -> list:
    """Where the ``motion`` and ``wave_scale`` blocks sit in ``p`` (empty: no continuation
    in amplitude)."""
    return _blocks(mech, AMPLITUDE_BLOCK) + _blocks(mech, WAVE_BLOCK)


def with_amplitude(p, slices, s: float) -> np.ndarray:
    """``p`` with its motion blocks times ``s``."""
    out = np.array(p, dtype=float)
    for sl in slices:
        out[sl] *= s
    return out


def _line(exc: BaseException) -> str:
    lines = str(exc).strip().splitlines()
    return lines[0] if lines else type(exc).__name__


def solve_by_continuation(solve: Callable, mech: Mechanism, p, first: ConvergenceError, *,
                          start_p=None, first_step: float = FIRST_STEP,
                          min_step: float = MIN_STEP, max_solves: int = MAX_SOLVES):
    """The periodic solution at ``p`` by continuation in the motion amplitude (module
    docstring), after the direct solve failed with ``first``.

    ``solve(p, start, start_p)`` is one full periodic solve (its checks included) at the
    parameters ``p`` from ``start`` (None: the method's own start; else a periodic solution);
    ``start_p`` the parameters of the own start's first period (scaled alike), or None.
    Returns the solution at ``p``, its warnings extended by what was done and its stats by
    ``continuation`` (the factors solved at, in order) and ``continuation_solves``. Raises
    ``first`` (no motion block) or a ConvergenceError naming both failures."""
    slices = amplitude_slices(mech)
    if not slices:
        raise first
    s, ds, prev, path, solves, last = 0.0, float(first_step), None, [], 0, None
    while s < 1.0 and solves < max_solves and ds >= min_step:
        if past_deadline():
            last = ConvergenceError(f"stopped at the call's time limit of "
                                    f"{current_limits().solve_seconds} s (sc.limits("
                                    "solve_seconds=...), --max-solve-seconds)")
            break
        s_try = min(1.0, s + ds)
        sp = None if start_p is None or prev is not None else with_amplitude(start_p, slices, s_try)
        solves += 1
        try:
            sol = solve(with_amplitude(p, slices, s_try), prev, sp)
        except ConvergenceError as exc:
            last = exc
            if s_try == 1.0 and solver_converged(exc):
                break  # solved at full amplitude and refused by the check: that is the answer
            if not (solver_converged(exc) and exc.partial is not None):
                ds /= 2.0
                continue
            # solved at s_try but not resolved on the check grid: a start all the same (the
            # check at s = 1 decides)
            sol = exc.partial
        s, prev = s_try, sol
        path.append(s)
        ds *= 2.0
    if s < 1.0:
        why = (f"reached amplitude factor {s:.3g} in {solves} solves" +
               (f" (the last: {_line(last)})" if last is not None else ""))
        raise ConvergenceError(f"{_line(first)}; again by continuation in the motion amplitude: "
                               f"{why}", partial=getattr(last, "partial", None),
                               diagnostics=getattr(last, "diagnostics", None)) from None
    stats = dict(prev.stats, continuation=tuple(path), continuation_solves=solves)
    where = (getattr(first, "diagnostics", None) or {}).get("start") or "the method's own start"
    note = (f"the solve from its start ({where}) failed ({_line(first)}); solved by "
            f"continuation in the motion amplitude, the first solve from that start "
            f"(factors {', '.join(f'{x:.3g}' for x in path)}; {solves} solves)")
    return dataclasses.replace(prev, stats=stats, warnings=tuple(prev.warnings) + (note,))
