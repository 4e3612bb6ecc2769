"""Sparse linear solves inside CasADi graphs that the code generator can write out.

Generic: it sees a square sparse matrix expression and a right-hand side, nothing else.

CasADi's sparse QR (``"qr"``) generates C, but QR fills in like the Cholesky factor of
J^T J: a single dense row (a global constraint, an integral condition) makes J^T J dense
and the factor full: an order of magnitude slower than the banded rest deserves (two dense
rows in the planar line's dynamics suffice).
:func:`sparse_solve` therefore takes the dense rows out: with ``D`` the dense rows, it
factorises the sparse matrix J_s that has unit rows e_i^T (i in D) in their place, and
restores them by the Sherman-Morrison-Woodbury formula, J = J_s + E W^T with
E = [e_i], W^T = J[D, :] - E^T:

    x = y - Z (I + W^T Z)^-1 W^T y,   y = J_s^-1 b,   Z = J_s^-1 E,

one factorisation of J_s for the k + 1 right-hand sides and a k x k solve. det J =
det J_s det(I + W^T Z), so both systems are regular when J is and the rest of J is.
"""
from __future__ import annotations

import casadi as ca
import numpy as np

__all__ = ["dense_rows", "flush_tiny", "jacobian", "norm_inf", "qr_solve", "sparse_solve",
           "to_csc"]

#: a row with more structural nonzeros than this fraction of the columns (and than
#: DENSE_MIN) counts as dense
DENSE_FRACTION = 0.25
DENSE_MIN = 16

#: CasADi's sparse QR sums a column's squared entries for its Householder reflection:
#: entries between about 1e-162 and 1e-154 square to subnormal numbers and the solution comes
#: out NaN (casadi 3.8: the 2 x 2 matrix [[2, 1e-160], [1e-160, 3]] suffices; a 3D line
#: hanging straight down has mass-matrix entries of 1e-165 and below). Entries smaller than
#: this are zeroed before a QR factorisation: in any unit, they change no digit of a solve.
TINY = 1e-150


def dense_rows(sparsity: ca.Sparsity) -> np.ndarray:
    """Indices of the rows of ``sparsity`` that count as dense."""
    rows = np.asarray(sparsity.get_triplet()[0], dtype=int)
    n = sparsity.size2()
    counts = np.bincount(rows, minlength=sparsity.size1())
    return np.flatnonzero(counts > max(DENSE_MIN, DENSE_FRACTION * n))


def flush_tiny(J):
    """``J`` (DM, SX or MX) with every nonzero of magnitude below :data:`TINY` set to zero
    (same sparsity)."""
    if isinstance(J, ca.DM):
        nz = np.array(J.nonzeros(), dtype=float)
        nz[np.abs(nz) < TINY] = 0.0
        return ca.DM(J.sparsity(), nz)
    nz = J.nz[:]
    return type(J)(J.sparsity(), ca.if_else(ca.fabs(nz) < TINY, 0, nz))


def qr_solve(J, b, linsol: str = "qr"):
    """``casadi.solve(J, b, linsol)``, the tiny entries of ``J`` flushed first for the sparse
    QR (see :data:`TINY`)."""
    return ca.solve(flush_tiny(J) if linsol == "qr" else J, b, linsol)


def sparse_solve(J: ca.MX, b: ca.MX, linsol: str = "qr") -> ca.MX:
    """``J^-1 b`` for a square sparse ``J`` (MX), with dense rows split off as described in
    the module docstring; plain ``casadi.solve`` when there are none."""
    sp = J.sparsity()
    n = sp.size1()
    D = dense_rows(sp)
    if D.size == 0 or D.size > n // 4:
        return qr_solve(J, b, linsol)
    rows, cols = (np.asarray(v, dtype=int) for v in sp.get_triplet())  # in nonzero order
    keep = np.flatnonzero(~np.isin(rows, D))
    r_s = np.concatenate([rows[keep], D])
    c_s = np.concatenate([cols[keep], D])
    order = np.lexsort((r_s, c_s))  # column-major: the nonzero order of the new pattern
    sp_s = ca.Sparsity.triplet(n, n, r_s[order].tolist(), c_s[order].tolist())
    nz = ca.vertcat(J.nz[keep.tolist()], ca.MX.ones(D.size))
    Js = ca.MX(sp_s, nz[order.tolist()])
    k = D.size
    E = ca.DM(ca.Sparsity.triplet(n, k, D.tolist(), list(range(k))), 1.0)
    Wt = J[D.tolist(), :] - E.T
    X = qr_solve(Js, ca.horzcat(b, E), linsol)
    y, Z = X[:, 0], X[:, 1:]
    C = ca.DM.eye(k) + ca.mtimes(Wt, Z)
    return y - ca.mtimes(Z, qr_solve(C, ca.mtimes(Wt, y), linsol))


#: smallest expression (rows) whose Jacobian takes its dense rows apart (below it the
#: quadratic term is negligible, and the Jacobian stays the expression it always was)
SPLIT_MIN = 400


def jacobian(expr, x):
    """``casadi.jacobian(expr, x)`` for SX, with the dense rows taken apart: CasADi colours
    the columns of a Jacobian for forward sweeps, and a dense row puts every column in a
    colour of its own, so one dense row makes the sweeps, and the cost, O(n^2). The rows
    without dense ones are differentiated as usual (few colours on a banded pattern) and
    the dense rows separately (reverse sweeps, one per row); the result, put back in row
    order, has the same pattern and the same values to round-off. O(n) on the cable
    systems, whose dynamics have two dense rows (the closure of a line held at both ends)."""
    n = expr.numel()
    D = dense_rows(ca.jacobian_sparsity(expr, x)) if n >= SPLIT_MIN else np.zeros(0, dtype=int)
    if D.size == 0:
        return ca.jacobian(expr, x)
    keep = np.setdiff1d(np.arange(n), D)
    J = ca.vertcat(ca.jacobian(expr[keep.tolist()], x), ca.jacobian(expr[D.tolist()], x))
    return J[np.argsort(np.concatenate([keep, D])).tolist(), :]


def norm_inf(x):
    """max |x_i|, and infinite (or NaN) when any entry is NaN or infinite. CasADi's
    ``norm_inf`` is a chain of ``fmax``, which skips NaN: a residual with a NaN entry would
    measure 0 and pass any tolerance. Here it is divided by (-inf < sum x_i < inf), which is
    1 for a finite x and 0 (so the quotient inf or NaN) when an entry is NaN or infinite (or
    the sum overflows): one sum (a loop without calls, where ``norm_1`` calls ``fabs`` per
    entry, a cost that shows in a long line's step) and two comparisons,
    which CasADi cannot fold away (sum(x) - sum(x) it simplifies to 0)."""
    s = ca.sum1(ca.vec(x))
    return ca.norm_inf(x) / ca.logic_and(s < np.inf, s > -np.inf)


#: compressed-column patterns of the matrices :func:`to_csc` converted, by their sparsity's
#: hash (a Function's output keeps one pattern over its calls)
_PATTERNS: dict = {}


def to_csc(M: ca.DM):
    """The numeric CasADi matrix ``M`` as a SciPy ``csc_matrix`` of the same shape and
    nonzeros (its structural zeros kept as stored entries)."""
    from scipy.sparse import csc_matrix
    sp = M.sparsity()
    key = (sp.hash(), sp.size1(), sp.size2(), sp.nnz())
    pattern = _PATTERNS.get(key)
    if pattern is None or not pattern[0].is_equal(sp):  # (a hash is no proof)
        if len(_PATTERNS) > 64:
            _PATTERNS.clear()
        colind, row = sp.get_ccs()
        pattern = _PATTERNS[key] = (ca.Sparsity(sp), np.asarray(row, np.int32),
                                    np.asarray(colind, np.int32))
    values = np.fromiter(M.nonzeros(), float, count=sp.nnz())
    # (the index arrays copied: a caller pruning its matrix must not edit the kept pattern)
    return csc_matrix((values, pattern[1].copy(), pattern[2].copy()), shape=M.shape)
