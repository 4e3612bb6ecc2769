"""The admissibility bounds' limits as numbers apart from their expressions: a Mechanism's
Functions take the limits as an input, so that scenes of one structure with other limits
(:mod:`symcable.models.structure`) share them."""
from __future__ import annotations

import casadi as ca
import numpy as np

__all__ = ["bound_margins", "bound_numbers"]


def bound_numbers(mech) -> np.ndarray:
    """``mech``'s bounds' limits packed (3 k,), k the bounds' entries in order: lower limits,
    upper limits, 1 / scale (so the margin of entry i is min(value - lower, upper - value)
    / scale)."""
    lo, hi, inv = [], [], []
    for b in mech.bounds.values():
        k = int(b.expr.numel())
        lo.append(np.broadcast_to(np.asarray(b.lower, float), (k,)))
        hi.append(np.broadcast_to(np.asarray(b.upper, float), (k,)))
        inv.append(np.full(k, 1.0 / float(b.scale)))
    if not lo:
        return np.zeros(0)
    return np.concatenate(lo + hi + inv)


def bound_margins(numbers, values):
    """Each bound entry's margin (k,), in scales (negative: violated), from
    :func:`bound_numbers` and the values (numbers or CasADi expressions alike)."""
    k = values.shape[0]
    lo, hi, inv = numbers[:k], numbers[k:2 * k], numbers[2 * k:]
    if isinstance(values, np.ndarray):
        return np.fmin(values - lo, hi - values) * inv
    return ca.fmin(values - lo, hi - values) * inv
