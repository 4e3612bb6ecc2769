"""Sums of gathered entries as loops, for assembling vectors (residuals, a matrix's
nonzeros, a band) from many small contributions in generated C.

Generic: a *sum map* ``by`` is a list with, for each entry of the result, the list of the
positions of a source vector ``ext`` summed into it (empty: zero). :func:`gather_sum`
evaluates it as one gather per depth (the most contributions an entry has): loops with an
index array in the generated C, where the same sum written out in SX is straight-line code
whose length grows with the line (a sizeable share of a long chain's step). Written instead
as the product of a constant sparse 0/1 matrix with ``ext`` (CasADi's sparse product), the
factorisation of a long chain's step is slower.
"""
from __future__ import annotations

import casadi as ca

__all__ = ["gather_sum", "sum_map", "summed"]


def sum_map(n: int, targets, sources) -> list[list[int]]:
    """The sum map of ``n`` entries, entry ``targets[m]`` receiving ``ext[sources[m]]``."""
    by: list[list[int]] = [[] for _ in range(n)]
    for j, m in zip(targets, sources):
        by[int(j)].append(int(m))
    return by


def gather_sum(ext, by: list[list[int]], zero: int | None = None):
    """(len(by),) MX: entry j the sum of ``ext`` (an MX column) at the positions ``by[j]``;
    ``zero``: a position where ``ext`` is 0 (pads the shorter lists), else a zero is
    appended to a copy of ``ext``."""
    if zero is None:
        zero = int(ext.numel())
        ext = ca.vertcat(ext, ca.MX.zeros(1, 1))
    depth = max((len(x) for x in by), default=0)
    out = ca.MX.zeros(len(by), 1)
    for d in range(depth):
        pick = ext[[x[d] if d < len(x) else zero for x in by]]
        out = pick if d == 0 else out + pick
    return ca.densify(out)


def summed(ext, n: int, targets, sources):
    """(n,): entry j the sum of ``ext``'s entries ``sources[m]`` over every m with
    ``targets[m]`` = j (zero where none): :func:`gather_sum` of :func:`sum_map`."""
    return gather_sum(ext, sum_map(n, targets, sources))
