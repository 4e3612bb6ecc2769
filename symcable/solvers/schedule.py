"""Which steps of a fixed-step run are saved, and how they are batched: saved samples
``save_every`` steps apart or at ``save_times``, with unsaved checkpoints so no batched call
advances too many steps at once."""
from __future__ import annotations

import math

import numpy as np

from ..errors import SymcableError

__all__ = ["MAX_GAP", "runs", "save_indices", "unaliased_every", "with_checkpoints"]

#: longest run of steps one batched call advances between two checkpoints: a mapaccum over
#: many thousands of steps is slow to build, so long gaps between saves are cut into pieces
MAX_GAP = 256


def unaliased_every(every: int, dt: float, period: float | None) -> int:
    """The least whole number of steps >= ``every`` between saved samples that is not in step
    with a motion of ``period`` s: where a period is a whole number P of steps (dt s), one
    whose greatest common divisor with P is 1, so that P successive samples fall at P
    different phases of the motion (every 50th step of a run at T/100 would sample two
    phases only, and show a flat response); ``every`` itself otherwise."""
    if period is None or not period > 0 or every <= 1:
        return every
    steps = period / dt
    P = round(steps)
    if P < 2 or abs(steps - P) > 1e-6 * steps:
        return every
    while math.gcd(every, P) != 1:
        every += 1
    return every


def save_indices(n_steps: int, dt: float, duration: float, save_every, save_times,
                 max_samples: int | None = None, period: float | None = None) -> np.ndarray:
    """Sorted unique step indices to save (0 is the start): every ``save_every`` steps and
    the last (None: every step, or about ``max_samples`` evenly spaced when there are more
    steps than that, their spacing not in step with a motion of ``period`` s:
    :func:`unaliased_every`), or the steps nearest ``save_times`` (s, from the start)."""
    if save_every is not None and save_times is not None:
        raise SymcableError("save_every and save_times: give at most one of them")
    if save_times is not None:
        st = np.atleast_1d(np.asarray(save_times, dtype=float)).ravel()
        if st.size == 0 or not np.all(np.isfinite(st)):
            raise SymcableError(f"save_times = {save_times!r}: must be a non-empty array of finite times, s")
        if st.min() < -0.5 * dt or st.max() > duration + 0.5 * dt:
            raise SymcableError(f"save_times = [{st.min():.6g} .. {st.max():.6g}] s: must lie in "
                                f"[0, duration = {duration:.6g}] s")
        return np.unique(np.clip(np.rint(st / dt).astype(np.int64), 0, n_steps))
    if save_every is None:
        save_every = 1 if max_samples is None or n_steps < max_samples else \
            unaliased_every(math.ceil(n_steps / max_samples), dt, period)
    elif isinstance(save_every, bool) or not isinstance(save_every, (int, np.integer)) or save_every < 1:
        raise SymcableError(f"save_every = {save_every!r}: must be a whole number of steps >= 1")
    idx = np.arange(0, n_steps + 1, int(save_every), dtype=np.int64)
    return idx if idx[-1] == n_steps else np.append(idx, n_steps)


def with_checkpoints(idx: np.ndarray, max_gap: int = MAX_GAP) -> np.ndarray:
    """The save indices plus unsaved checkpoints, so no gap exceeds ``max_gap`` steps."""
    points = np.concatenate([[0], idx])
    long = np.flatnonzero(np.diff(points) > max_gap)
    extra = [np.arange(points[i] + max_gap, points[i + 1], max_gap) for i in long]
    return np.unique(np.concatenate([idx] + extra)).astype(int) if extra else idx


def runs(idx: np.ndarray) -> list:
    """Consecutive equal gaps between saved indices (from step 0): [(S, count), ...]."""
    gaps = np.diff(np.concatenate([[0], idx]))
    gaps = gaps[gaps > 0]
    if not gaps.size:
        return []
    starts = np.concatenate([[0], np.flatnonzero(np.diff(gaps)) + 1])
    counts = np.diff(np.concatenate([starts, [gaps.size]]))
    return [[int(gaps[a]), int(c)] for a, c in zip(starts, counts)]
