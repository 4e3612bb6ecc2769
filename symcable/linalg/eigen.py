"""The lowest eigenpair of a symmetric matrix, by its band where it has one.

A static solve judges stability by the lowest eigenvalue of its tangent stiffness. The dense
symmetric eigensolver costs n^3, most of a warm static solve of a rod of a few hundred
segments. A line's stiffness is banded once its unknowns are ordered along
the line (reverse Cuthill-McKee finds the order), and LAPACK's banded solver (dsbevx, through
:func:`scipy.linalg.eig_banded`) gives the lowest eigenpair alone in n b^2, b the half
bandwidth: the same number, exactly, not an iterative estimate. Matrices without a narrow
band (b > n / 8), or small ones, take the dense solver.
"""
from __future__ import annotations

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sps
from scipy.sparse.csgraph import reverse_cuthill_mckee

__all__ = ["lowest_eigenpair", "DENSE_BELOW"]

#: below this size the dense solver is as fast (no band to find)
DENSE_BELOW = 160


def lowest_eigenpair(A: np.ndarray) -> tuple[float, np.ndarray]:
    """``(lambda_min, v)``: the lowest eigenvalue of the symmetric matrix ``A`` (n, n) and a
    unit eigenvector (n,). Only ``A``'s upper triangle and its pattern are read (pass the
    symmetric part of a tangent)."""
    A = np.asarray(A, dtype=float)
    n = A.shape[0]
    if n < DENSE_BELOW:
        return _dense(A)
    S = sps.csr_matrix(np.triu(A))
    S = S + S.T  # the pattern, symmetric (values unused here)
    perm = reverse_cuthill_mckee(S.tocsr(), symmetric_mode=True)
    P = A[np.ix_(perm, perm)]
    rows, cols = np.nonzero(np.triu(P))
    b = int(np.max(cols - rows)) if rows.size else 0
    if b > n // 8:
        return _dense(A)
    ab = np.zeros((b + 1, n))
    ab[b + rows - cols, cols] = P[rows, cols]  # LAPACK's upper band storage
    w, v = sla.eig_banded(ab, lower=False, select="i", select_range=(0, 0))
    vec = np.empty(n)
    vec[perm] = v[:, 0]
    return float(w[0]), vec


def _dense(A: np.ndarray) -> tuple[float, np.ndarray]:
    lam, vec = np.linalg.eigh(A)
    return float(lam[0]), vec[:, 0]
