"""A time run whose step is chosen for a tolerance on what a user reads: the end tensions.

The run at the default step is compared with a run at twice its step; while the two differ
by more than the tolerance, the step is halved and the new run compared with the one before.
The difference between runs at steps 2h and h is the error of the run at 2h less that at h;
for a scheme that converges with order p >= 1 (generalized-alpha: 2 on smooth motion, about
1 where a line lands on the seabed) it is at least the error of the run at h, so a run whose
difference to its coarser partner is within the tolerance is within it itself. With three
runs the observed order ``p = log2(d_prev / d)`` is known, and below 1 the error of the finer
run is taken as ``d / (2^p - 1)``, larger than d; an observed order near zero (the runs not
converging: a snap, axial waves the finer step starts to resolve) verifies nothing.

The comparison is on the coarser run's sample times (the finer run's samples there, or
linear interpolation between its samples where its saved grid is not a refinement of the
other's), each end tension relative to its range over the run (at least
TENSION_RANGE_FLOOR of the largest end tension). A run saved at given times (``save_times``:
the window a user reads, such as the span after a start-up) is compared at those times only:
the caller saves every run at the first run's sample times, which every finer run's steps
contain, and no coarser partner is run (its steps would not contain them). So too when the
first run did not keep every step (a long run thinned to a number of samples): later runs
keep its samples, and the comparison reads no interpolated value (:func:`tolerance_runs`).

Two coarse runs can agree and both be far off: when both damp (generalized-alpha's rho_inf)
a response that only much finer steps resolve, such as the stick-slip axial vibration of a
very stiff chain on a rough bed. The first comparison assumes the runs are in their
asymptotic range; ``studies/fuzz/README.md`` gives the measured case.

This module is generic over formulations: it sees a ``run(dt) -> trajectory`` and the
trajectories' end tensions.
"""
from __future__ import annotations

import dataclasses
import math
import time

import numpy as np

from ..errors import ConvergenceError, SymcableError

__all__ = ["DEFAULT_TOL", "MAX_HALVINGS", "check_tol", "end_tensions", "every_step",
           "run_to_tolerance", "step_tolerance", "tension_difference", "tolerance_runs"]

#: the end tensions' error a run at simulate's default asks for (no dt, no tol), relative to
#: their range
DEFAULT_TOL = 0.01
#: the finest step tried is the default step / 2^MAX_HALVINGS
MAX_HALVINGS = 5
#: an observed order of convergence below this verifies nothing (module docstring)
MIN_ORDER = 0.3
#: halving stops after this many comparisons in a row whose observed order is below
#: MIN_ORDER (the runs do not converge with the step: more halvings only cost)
STALLED = 2
#: the least range an end tension's difference is relative to, as a fraction of the largest
#: end tension of the run (a steady tension's round-off is no motion)
TENSION_RANGE_FLOOR = 1e-3
#: warnings of a run's own step-error estimate, superseded by a verified comparison
OWN_ESTIMATE_MARK = "the time step is too coarse"


def check_tol(tol) -> float:
    """``tol`` as a float in (0, 1), or a one-line SymcableError naming it."""
    try:
        value = float(tol)
    except (TypeError, ValueError):
        value = float("nan")
    if isinstance(tol, bool) or not 0.0 < value < 1.0:
        raise SymcableError(f"tol = {tol!r}: must be a number in (0, 1), the error asked of the "
                            "run's end tensions relative to their range (e.g. 0.01)")
    return value


def step_tolerance(tol, dt, save_times, method: str) -> float | None:
    """The tolerance a run is stepped for: ``tol`` checked (:func:`check_tol`), refused with
    ``dt`` (a fixed step) or a method other than generalized-alpha (RK4's step is its
    stability limit); DEFAULT_TOL when none of ``tol``, ``dt`` and ``save_times`` is given and
    the method is generalized-alpha; else None (a fixed step)."""
    ga = method == "generalized-alpha"
    if tol is None:
        return DEFAULT_TOL if ga and dt is None and save_times is None else None
    if dt is not None:
        raise SymcableError(f"tol = {tol!r} with dt = {dt!r}: give dt (a fixed step) or tol (the "
                            "step chosen for it), not both")
    if not ga:
        raise SymcableError(f"tol = {tol!r}: not with method = {method!r} (its step is its "
                            "stability limit); use method = 'generalized-alpha'")
    return check_tol(tol)


def end_tensions(traj) -> tuple[np.ndarray, list[np.ndarray]]:
    """``(time (n_t,) s, [series (n_t,) N])``: the fairlead and anchor tension of every line
    of a trajectory (one line's, or each of ``traj.lines``)."""
    lines = list(traj.lines.values()) if hasattr(traj, "lines") else [traj]
    series = []
    for ln in lines:
        for name in ("fairlead_tension", "anchor_tension"):
            f = getattr(ln, name, None)
            if f is not None:
                series.append(np.asarray(f, float).ravel())
    return np.asarray(traj.time, float), series


def tension_difference(coarse, fine) -> float:
    """The largest difference of the end tensions of two runs of one scene (module docstring)
    at the coarser run's sample times, relative to each tension's range in the finer run."""
    tc, sc_ = end_tensions(coarse)
    tf, sf = end_tensions(fine)
    if len(sc_) != len(sf) or tc.size < 2 or tf.size < 2:
        raise SymcableError("the runs compared for tol have different end tensions")
    keep = (tc >= tf[0] - 1e-9) & (tc <= tf[-1] + 1e-9)
    largest = max((float(np.max(np.abs(f))) for f in sf if f.size), default=0.0)
    floor = TENSION_RANGE_FLOOR * largest
    worst = 0.0
    for c, f in zip(sc_, sf):
        rng = max(float(np.ptp(f)), floor)
        if not rng > 0:
            continue
        at = np.interp(tc[keep], tf, f)
        d = float(np.max(np.abs(at - c[keep]))) if at.size else 0.0
        worst = max(worst, d / rng)
    return worst


def run_to_tolerance(run, tol: float, label: str = "simulate", partner: bool = True):
    """The run of ``run(dt)`` (None: the default step) whose end tensions are within ``tol``
    of their range, verified against a run at twice its step (module docstring): the default
    step first, compared with twice it (``partner``, when the first run kept every step:
    :func:`every_step`; else with half it), then halving while
    the difference exceeds ``tol``, at
    most MAX_HALVINGS times, and no more once STALLED comparisons in a row show no
    convergence. ``run`` raises ConvergenceError for a step that fails and
    SymcableError for a step it refuses (twice the default past half the motion's period);
    such a partner is skipped. Returns the accepted run, or the finest with a warning when
    none is verified; its ``stats`` add ``tol``, ``error_measured`` (the accepted run's error
    bound, relative; None when not verified), ``dt_runs`` ([dt s, difference to the run
    before or None] for each run, coarsest first), ``dt_default`` (s, the first run's) and
    ``tol_wall_time`` (s, all runs)."""
    started = time.perf_counter()
    first = run(None)
    h0 = float(first.dt)
    tried = []
    d_prev, coarse = None, None
    try:
        coarse = run(2.0 * h0) if partner and every_step(first) else None
    except (ConvergenceError, SymcableError):
        pass
    if coarse is not None:
        d_prev = tension_difference(coarse, first)
        tried.append([float(coarse.dt), None])
    tried.append([h0, d_prev])
    if d_prev is not None and d_prev <= tol:
        return _accepted(first, tol, d_prev, tried, started, h0, None)
    prev, error, stalled = first, None, 0
    for _ in range(MAX_HALVINGS):
        h = 0.5 * float(prev.dt)
        try:
            fine = run(h)
        except ConvergenceError as exc:
            note = (f"{label}: tol = {tol:g} not verified: the run at dt = {h:.4g} s failed "
                    f"({exc}); the run at dt = {float(prev.dt):.4g} s is returned")
            return _accepted(prev, tol, None, tried, started, h0, note)
        d = tension_difference(prev, fine)
        tried.append([float(fine.dt), d])
        error = _bound(d, d_prev)
        if error <= tol:
            return _accepted(fine, tol, error, tried, started, h0, None)
        stalled = stalled + 1 if not math.isfinite(error) else 0
        prev, d_prev = fine, d
        if stalled >= STALLED:
            break
    last = tried[-1][1]
    why = ("" if error is None else
           f", which bounds its error at {100 * error:.2g} % (the difference falls slowly "
           "with the step)" if math.isfinite(error) else
           ", and the difference does not fall with the step (a snap, a contact or axial "
           "waves the steps resolve only in part)")
    note = (f"{label}: tol = {tol:g} not reached by dt = {float(prev.dt):.4g} s: its end "
            f"tensions differ from the run at twice its step by {100 * last:.2g} % of their "
            "range" + why)
    return _accepted(prev, tol, None, tried, started, h0, note)


def every_step(traj) -> bool:
    """Whether a run kept every step (its samples one step apart), so that a run at twice
    its step has its samples among them."""
    t = np.asarray(traj.time, float)
    return t.size > 1 and bool(np.allclose(np.diff(t), float(traj.dt), rtol=1e-6, atol=0.0))


def tolerance_runs(run, tol: float, label: str, save_every=None, save_times=None,
                   t0: float = 0.0):
    """:func:`run_to_tolerance` of ``run(dt, save_every, save_times)`` (dt None: the default
    step; ``save_times`` s from the start ``t0``): the first run saved as the user asked,
    later ones at the first run's samples when it was given ``save_times`` or did not keep
    every step (module docstring), else as the user asked."""
    grid = {}

    def at(h):
        same = h is not None and (save_times is not None or not grid["every"])
        tr = run(h, None, grid["times"]) if same else run(h, save_every, save_times)
        if not grid:
            grid.update(times=np.asarray(tr.time, float) - t0, every=every_step(tr))
        return tr
    return run_to_tolerance(at, tol, label, partner=save_times is None)


def _bound(d: float, d_prev: float | None) -> float:
    """The error of the finer of two runs differing by ``d`` (module docstring), given the
    difference ``d_prev`` of the pair before (None: order at least 1 assumed)."""
    if d_prev is None or d <= 0.0 or d_prev <= 0.0:
        return d
    order = math.log2(d_prev / d)
    if order >= 1.0:
        return d
    if order < MIN_ORDER:
        return math.inf
    return d / (2.0 ** order - 1.0)


def _accepted(traj, tol, error, tried, started, h0, note):
    """``traj`` with the tolerance's stats, its own step-error warning dropped when runs
    were compared (their difference is the better evidence, and ``note`` says it), and
    ``note`` added."""
    warnings = tuple(traj.warnings)
    if error is not None or any(d is not None for _, d in tried):
        warnings = tuple(w for w in warnings if OWN_ESTIMATE_MARK not in w)
    if note:
        warnings = (note,) + warnings
    stats = dict(traj.stats, tol=tol, error_measured=error, dt_runs=tried, dt_default=h0,
                 tol_wall_time=time.perf_counter() - started)
    return dataclasses.replace(traj, stats=stats, warnings=warnings)
