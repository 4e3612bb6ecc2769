"""The time-discretisation error of a periodic steady state, from a second solve at another
resolution (:func:`with_time_error`).

A periodic solve finds the exact cycle of its discrete scheme (shooting's ``steps`` per
period, collocation's ``intervals``, harmonic balance's ``harmonics``), not of the line. The
error of each line's tension extremes over the cycle is estimated by Richardson
extrapolation from the same solve at another resolution: for shooting at twice the steps
(at half them only when that fails: the coarser cycle is often not yet in the asymptotic
range, where the error falls as the steps squared, and a difference from it can be far
smaller than the error: a slack line's answer at 100 steps was 2.3 % off where 50 steps
differed from it by 0.2 %); for collocation and harmonic balance at half the resolution
(twice it when that fails). A cycle in which a segment snaps taut is compared with a finer
one too, at p = 1 (the ringing after a snap is damped by the scheme at both coarse
resolutions alike, so their difference misses it; a snap is a kink in time). With
``R(n) = R + C n^-p``, the answer is off by ``|R(n) - R(m)| / |1 - (n/m)^p|``, p = 2 for
shooting (generalized-alpha is second order), the degree + 1 for collocation (its stage
order plus one, below its superconvergent order at the mesh points: the estimate errs
large); for harmonic balance, whose error falls faster than any power, the difference
itself bounds it. The error is relative to the tension range over the cycle (or 1 % of the
largest tension when the range is smaller: a line barely moving).
"""
from __future__ import annotations

import dataclasses
import math
import time
from typing import Callable

import numpy as np

from ..errors import SymcableError
from ..solvers.options import Collocation, HarmonicBalance, Shooting
from .static_error import force_text

__all__ = ["TIME_ACCURACY", "with_time_error"]

#: a periodic answer whose estimated error exceeds this fraction of its tension range warns
TIME_ACCURACY = 0.01


def _resolution(opts):
    """``(field, value, order p or None, smallest value)`` of a method's resolution."""
    if isinstance(opts, Shooting):
        return "steps", opts.steps, 2, 8
    if isinstance(opts, Collocation):
        return "intervals", opts.intervals, opts.degree + 1, 2
    if isinstance(opts, HarmonicBalance):
        return "harmonics", opts.harmonics, None, 1
    return None


def _others(opts) -> list:
    """The options to compare with, in order: shooting twice the steps, then half; the
    others half the resolution, then (when that fails or cannot be) twice it."""
    key, n, _, least = _resolution(opts)
    extra = {"samples": None} if isinstance(opts, HarmonicBalance) else {}
    half = [dataclasses.replace(opts, **{key: n // 2}, **extra)] if n // 2 >= least else []
    double = [dataclasses.replace(opts, **{key: 2 * n}, **extra)]
    return double + half if isinstance(opts, Shooting) else half + double


def _snaps(res) -> bool:
    """Whether a segment of the cycle goes slack and snaps taut (its lines' slack reports)."""
    try:
        return any((ln.stats or {}).get("snaps") for ln in res.lines.values())
    except AttributeError:  # a planar line's cycle: no slack report
        return False


def _extremes(res) -> dict:
    """``{(line, end): (least, largest) tension over the cycle}``, N."""
    out = {}
    for name, ln in res.lines.items():
        for end in ("fairlead", "anchor"):
            t = getattr(ln, f"{end}_tension", None)  # a planar line's: its fairlead's only
            if t is not None and np.size(t):
                out[(name, end)] = (float(np.min(t)), float(np.max(t)))
    return out


def with_time_error(res, opts, solve: Callable):
    """``res`` (a PeriodicSolution solved with the options object ``opts``) with its
    time-discretisation error in ``stats["time_discretisation_error"]`` and a warning above
    :data:`TIME_ACCURACY`. ``solve(options)`` solves the same scene with other options.

    The report: ``error`` (N, the largest over the lines' end tension extremes),
    ``relative`` (to that line end's tension range, or 1 % of its largest tension when the
    range is smaller), ``where`` (line, end), ``resolution`` (the option and its value),
    ``compared_with``, ``order`` and ``wall_time`` (s)."""
    t0 = time.perf_counter()
    if _resolution(opts) is None:
        return res
    key, n, p, _ = _resolution(opts)
    failed = []
    others = _others(opts)
    if _snaps(res):  # both coarser cycles damp the ringing after a snap: compare finer;
        others = sorted(others, key=lambda o: -getattr(o, key))  # and a snap is a kink in
        p = None if p is None else 1                             # time: first order
    for other in others:
        try:
            coarse = solve(other)
            break
        except SymcableError as exc:
            failed.append(f"{key} = {getattr(other, key)}: {str(exc).splitlines()[0][:160]}")
    else:
        note = ("no time-discretisation error estimate: the solves to compare with failed ("
                + "; ".join(failed) + ")")
        return dataclasses.replace(res, warnings=tuple(res.warnings) + (note,))
    m = getattr(other, key)
    fine, rough = _extremes(res), _extremes(coarse)
    factor = 1.0 if p is None else 1.0 / abs(1.0 - (n / m) ** p)
    worst = None
    for where, (lo, hi) in fine.items():
        if where not in rough:
            continue
        err = factor * max(abs(lo - rough[where][0]), abs(hi - rough[where][1]))
        scale = max(hi - lo, 0.01 * max(abs(hi), abs(lo)), 1e-300)
        if worst is None or err / scale > worst["relative"]:
            worst = {"error": float(err), "relative": float(err / scale),
                     "where": list(where), "resolution": {key: n},
                     "compared_with": {key: m},
                     "order": p}
    if worst is None:
        return res
    worst["wall_time"] = time.perf_counter() - t0
    warnings = tuple(res.warnings)
    if worst["relative"] > TIME_ACCURACY:
        ratio = worst["relative"] / TIME_ACCURACY
        need = (int(math.ceil(n * 1.1 * ratio ** (1.0 / p))) if p is not None
                else n + max(1, n // 2))
        line, end = worst["where"]
        warnings += (f"periodic solve: time-discretisation error about "
                     f"{force_text(worst['error'])}, "
                     f"{worst['relative']:.1%} of the {end} tension range of line '{line}', "
                     f"at {key} = {n} (estimated against {m}); "
                     f"{key} = {need} would bring it under {100 * TIME_ACCURACY:g} %",)
    stats = dict(res.stats, time_discretisation_error=worst)
    return dataclasses.replace(res, stats=stats, warnings=warnings)
