"""The lowest eigenpair by the band (symcable.linalg.eigen) is the dense solver's: on a
shuffled banded symmetric matrix with negative eigenvalues (the band found by reverse
Cuthill-McKee) and on one without a band (the dense fallback). Tolerances: round-off of a
symmetric eigensolver on entries of order 1 (1e-10)."""
import numpy as np
import pytest

from symcable.linalg.eigen import lowest_eigenpair


def _banded(n, b, rng):
    A = np.zeros((n, n))
    for k in range(b + 1):
        d = rng.normal(size=n - k)
        A += np.diag(d, k) + (np.diag(d, -k) if k else 0)
    return A


@pytest.mark.parametrize("n, b", [(400, 3), (600, 12)])
def test_banded_lowest_eigenpair_is_the_dense_one(n, b):
    rng = np.random.default_rng(n)
    perm = rng.permutation(n)
    A = _banded(n, b, rng)[np.ix_(perm, perm)]  # no band in this order
    lam, v = lowest_eigenpair(A)
    ref = np.linalg.eigvalsh(A)[0]
    assert ref < 0 and abs(lam - ref) < 1e-10 * max(1.0, abs(ref))
    assert abs(np.linalg.norm(v) - 1.0) < 1e-10
    assert np.linalg.norm(A @ v - lam * v) < 1e-9


def test_a_matrix_without_a_band_takes_the_dense_solver():
    rng = np.random.default_rng(1)
    M = rng.normal(size=(300, 300))
    A = M + M.T
    lam, v = lowest_eigenpair(A)
    assert abs(lam - np.linalg.eigvalsh(A)[0]) < 1e-9 * abs(lam)
    assert np.linalg.norm(A @ v - lam * v) < 1e-8 * abs(lam)
