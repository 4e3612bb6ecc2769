"""The banded LU as CasADi loops (symcable.linalg.banded): exact on banded patterns in any
order of their unknowns, with and without the Schur elimination of a leading block of
1 x 1 and 2 x 2 blocks (symcable.linalg.schur), in the virtual machine and the same in
generated C; and the iteration matrix of a long cable3d line takes it in the first-order
generalized-alpha step."""
from __future__ import annotations

import casadi as ca
import numpy as np
import pytest

from symcable.linalg.banded import BandedLU, bandwidths, reverse_cuthill
from symcable.linalg.schur import SchurBandedLU, diagonal_lead, lead_blocks, leading_diagonal

# Relative solve errors are bounded by (growth factor) x (condition) x eps; these matrices
# have a dominant diagonal (growth ~1, condition < 1e3), so 1e-11 leaves a wide margin
# while a wrong elimination (a missed band entry, a wrong order) gives O(1) errors.
REL = 1e-11


def _banded(n, lower, upper, rng):
    A = np.zeros((n, n))
    for k in range(-lower, upper + 1):
        A += np.diag(rng.standard_normal(n - abs(k)), k)
    return A + np.diag(np.full(n, 4.0 * (lower + upper + 1)))


def _solver_fn(solver, sp):
    a, b = ca.MX.sym("a", sp.nnz()), ca.MX.sym("b", sp.size1())
    return ca.Function("band_solve", [a, b], [solver.solve(solver.factor(a), b)])


def _nonzeros(A):
    D = ca.sparsify(ca.DM(A))
    return D.sparsity(), np.asarray(D.nonzeros())


@pytest.mark.parametrize("n, lower, upper", [(1, 0, 0), (7, 1, 1), (30, 0, 0), (50, 5, 3),
                                             (41, 2, 6), (9, 8, 8)])
def test_banded_solves_shuffled_band(n, lower, upper):
    """Any band, its unknowns shuffled: reverse Cuthill-McKee finds a band no wider than
    the original, and the solve is exact to round-off."""
    rng = np.random.default_rng(n + 10 * lower + 100 * upper)
    A = _banded(n, lower, upper, rng)
    perm = rng.permutation(n)
    A = A[np.ix_(perm, perm)]
    sp, nz = _nonzeros(A)
    lu = BandedLU(sp)
    assert lu.l + lu.u <= 2 * max(lower, upper)
    b = rng.standard_normal(n)
    x = np.asarray(_solver_fn(lu, sp)(nz, b)).ravel()
    assert np.linalg.norm(A @ x - b) <= REL * np.linalg.norm(b) * np.linalg.cond(A)


def test_schur_banded_on_a_mechanical_iteration_matrix():
    """[[d I, -c I], [C, D]] (kinematic rows q' - v on top, as the first-order
    generalized-alpha matrix has them): the Schur form solves it exactly, the leading block
    is recognised as diagonal, and the complement's band is that of D and C."""
    rng = np.random.default_rng(3)
    k = 24
    D = _banded(k, 3, 3, rng)
    C = _banded(k, 3, 3, rng) * 0.1
    A = np.block([[1.5 * np.eye(k), -0.05 * np.eye(k)], [C, D]])
    sp, nz = _nonzeros(A)
    assert leading_diagonal(sp, k) and not leading_diagonal(sp, k + 1)
    lu = SchurBandedLU(sp, k)
    assert (lu.l, lu.u) == bandwidths(ca.sparsify(ca.DM(D + C)).sparsity(), lu.lu.perm)
    b = rng.standard_normal(2 * k)
    x = np.asarray(_solver_fn(lu, sp)(nz, b)).ravel()
    assert np.linalg.norm(A @ x - b) <= REL * np.linalg.norm(b) * np.linalg.cond(A)


def test_generated_c_equals_virtual_machine(tmp_path):
    """The loops compile to C and give the virtual machine's answer to the last bits."""
    from symcable.mechanism.codegen import compile_functions, use_codegen
    if not use_codegen(True):
        pytest.fail("no C compiler on this machine: CI installs one")
    rng = np.random.default_rng(5)
    A = _banded(40, 4, 4, rng)
    sp, nz = _nonzeros(A)
    fn = _solver_fn(BandedLU(sp, "t_band"), sp)
    c = compile_functions([fn], what="a banded LU test")[fn.name()]
    b = rng.standard_normal(40)
    x_vm, x_c = (np.asarray(f(nz, b)).ravel() for f in (fn, c))
    assert np.max(np.abs(x_vm - x_c)) <= 1e-14 * np.max(np.abs(x_vm))


def test_reverse_cuthill_is_a_permutation():
    rng = np.random.default_rng(1)
    A = _banded(20, 2, 2, rng)
    sp, _ = _nonzeros(A[np.ix_(rng.permutation(20), rng.permutation(20))] + np.eye(20))
    assert sorted(reverse_cuthill(sp).tolist()) == list(range(20))


@pytest.mark.parametrize("schur", [False, True])
def test_factor_of_sources_equals_factor_of_nonzeros(schur):
    """``factor_sum`` (the nonzeros given as sums of a source vector, gathered straight into
    the band) packs the same factors as ``factor`` of the summed nonzeros, with a kinematic
    block whose B is not diagonal (two entries per row, so S_ij sums several products); the
    factors are the same operations in another order of summation: 1e-13 relative."""
    rng = np.random.default_rng(11)
    k = 15
    Bm = -0.05 * (np.eye(k) + np.eye(k, k=1))
    A = np.block([[1.5 * np.eye(k), Bm], [_banded(k, 2, 2, rng) * 0.1, _banded(k, 2, 2, rng)]])
    if not schur:
        A = _banded(2 * k, 3, 2, rng)
    sp, nz = _nonzeros(A)
    lu = SchurBandedLU(sp, k) if schur else BandedLU(sp)
    # every nonzero split into 1..3 parts scattered over a longer source vector
    parts = [rng.integers(1, 4) for _ in range(sp.nnz())]
    n_ext = int(sum(parts)) + 5
    slots = rng.permutation(n_ext)
    ext, by, at = np.zeros(n_ext), [], 0
    for m, c in enumerate(parts):
        w = rng.standard_normal(c)
        w[-1] = nz[m] - w[:-1].sum()
        idx = slots[at:at + c].tolist()
        at += c
        ext[idx] = w
        by.append(idx)
    e = ca.MX.sym("e", n_ext)
    a = ca.MX.sym("a", sp.nnz())
    f_sum = ca.Function("fs", [e], [lu.factor_sum(e, by)])(ext)
    f_nz = ca.Function("fn", [a], [lu.factor(a)])(nz)
    f_sum, f_nz = (np.asarray(f).ravel() for f in (f_sum, f_nz))
    assert np.max(np.abs(f_sum - f_nz)) <= 1e-13 * np.max(np.abs(f_nz))
    b = rng.standard_normal(2 * k)
    fa, ba = ca.MX.sym("f", lu.n_factors), ca.MX.sym("b", 2 * k)
    x = np.asarray(ca.Function("s", [fa, ba], [lu.solve(fa, ba)])(f_sum, b)).ravel()
    assert np.linalg.norm(A @ x - b) <= REL * np.linalg.norm(b) * np.linalg.cond(A)


def test_diagonal_lead_stops_where_first_order_states_couple():
    """Positions' kinematic rows (diagonal) then a bristle's two coupled first-order states
    per node, then the momentum rows: the diagonal lead is the positions and the first
    bristle row (its coupling is to the next row, outside the leading block); a missing
    diagonal entry ends it there; a fully diagonal matrix leaves one row for the complement.
    The Schur form on that lead solves the matrix exactly."""
    rng = np.random.default_rng(4)
    k, nb, nv = 6, 4, 6
    n = k + nb + nv
    A = np.zeros((n, n))
    A[:k, :k] = np.diag(1.5 + rng.random(k))
    A[:k, k + nb:] = -0.05 * np.eye(k)
    A[k:k + nb, k:k + nb] = np.kron(np.eye(nb // 2), [[2.0, 0.3], [0.2, 2.0]])
    A[k:k + nb, k + nb:k + nb + nb] = 0.1 * rng.standard_normal((nb, nb))
    A[k + nb:, :k] = 0.1 * _banded(nv, 1, 1, rng)
    A[k + nb:, k + nb:] = _banded(nv, 2, 2, rng)
    A[k + nb:, k:k + nb] = 0.05 * rng.standard_normal((nv, nb))
    sp, nz = _nonzeros(A)
    assert diagonal_lead(sp, k + nb) == k + 1
    assert diagonal_lead(sp, 3) == 3
    lu = SchurBandedLU(sp, diagonal_lead(sp, k + nb))
    b = rng.standard_normal(n)
    x = np.asarray(_solver_fn(lu, sp)(nz, b)).ravel()
    assert np.linalg.norm(A @ x - b) <= REL * np.linalg.norm(b) * np.linalg.cond(A)
    B = A.copy()
    B[2, 2] = 0.0
    assert diagonal_lead(_nonzeros(B)[0], k + nb) == 2
    assert diagonal_lead(_nonzeros(np.diag(np.arange(1.0, 6.0)))[0], 10) == 4


@pytest.mark.parametrize("k, b_per_row", [(1, 3), (2, 1), (2, 2)])
def test_schur_with_one_entry_blocks(k, b_per_row):
    """A diagonal lead of one or two rows, B with one or several entries per row, C with
    one or several per column (where a 1 x 1 vector indexed by a list turns into a row):
    the Schur form still solves exactly."""
    rng = np.random.default_rng(10 * k + b_per_row)
    n = 7
    A = _banded(n, 2, 2, rng)
    A[:k, :k] = np.diag(2.0 + rng.random(k))
    A[:k, k:] = 0.0
    for r in range(k if b_per_row > 1 else 1):  # one B entry in all where b_per_row = 1
        A[r, k + r:k + r + b_per_row] = 0.1 * rng.standard_normal(b_per_row)
    A[k:, :k] = 0.0
    A[k, 0] = 0.2
    if k == 2:
        A[k + 1, 1] = -0.3
        A[k + 2, 0] = 0.15  # two entries in C's first column
    sp, nz = _nonzeros(A)
    assert diagonal_lead(sp, k) == k
    lu = SchurBandedLU(sp, k)
    b = rng.standard_normal(n)
    x = np.asarray(_solver_fn(lu, sp)(nz, b)).ravel()
    assert np.linalg.norm(A @ x - b) <= REL * np.linalg.norm(b) * np.linalg.cond(A)


def _bristle_like(rng, k, nb, nv, pair=True):
    """Positions' kinematic rows (k, diagonal), then nb first-order states coupled in pairs
    (a bristle's two deflections per node; with ``pair`` False the pairs' diagonals are
    missing and their off-diagonals carry them) and to their node's positions (X), then nv
    momentum rows, banded."""
    n = k + nb + nv
    A = np.zeros((n, n))
    A[:k, :k] = np.diag(1.5 + rng.random(k))
    A[:k, k + nb:] = -0.05 * np.eye(k, nv)
    blk = [[2.0, 0.3], [0.2, 2.0]] if pair else [[0.0, 1.7], [-1.9, 0.0]]
    A[k:k + nb, k:k + nb] = np.kron(np.eye(nb // 2), blk)
    A[k:k + nb, :k] = 0.3 * rng.standard_normal((nb, k)) * (  # X: the node's position
        np.abs(np.subtract.outer(np.arange(nb) // 2, np.arange(k) // 3)) == 0)
    A[k:k + nb, k + nb:] = 0.1 * rng.standard_normal((nb, nv)) * (
        np.abs(np.subtract.outer(np.arange(nb) // 2, np.arange(nv) // 3)) <= 1)
    A[k + nb:, :k] = 0.1 * _banded(nv, 1, 1, rng)[:, :k]
    A[k + nb:, k + nb:] = _banded(nv, 2, 2, rng)
    A[k + nb:, k:k + nb] = 0.05 * rng.standard_normal((nv, nb)) * (
        np.abs(np.subtract.outer(np.arange(nv) // 3, np.arange(nb) // 2)) <= 1)
    return A


@pytest.mark.parametrize("pair, nb", [(True, 6), (False, 6), (True, 2)])
def test_schur_eliminates_two_by_two_blocks(pair, nb):
    """A lead [[P, 0], [X, Q]]: 1 x 1 blocks (the kinematic rows) and 2 x 2 blocks (a
    bristle's coupled pairs, with their diagonal or with their off-diagonal entries,
    depending on their node's positions through X): lead_blocks finds every block, the
    complement is the momentum rows alone, and the Schur form (from the nonzeros, and from
    sources split over a longer vector) solves exactly; a pair that couples to a third row
    ends the lead before it."""
    rng = np.random.default_rng(20 + nb + pair)
    k, nv = 6, 6
    A = _bristle_like(rng, k, nb, nv, pair)
    sp, nz = _nonzeros(A)
    blocks = lead_blocks(sp, k + nb)
    assert blocks == [(i,) for i in range(k)] + [(k + i, k + i + 1) for i in range(0, nb, 2)]
    lu = SchurBandedLU(sp, k + nb)
    assert lu.lu.n == nv
    b = rng.standard_normal(A.shape[0])
    x = np.asarray(_solver_fn(lu, sp)(nz, b)).ravel()
    assert np.linalg.norm(A @ x - b) <= REL * np.linalg.norm(b) * np.linalg.cond(A)
    ext = np.concatenate([0.5 * nz, 0.5 * nz, [7.0]])
    by = [[m, m + sp.nnz()] for m in range(sp.nnz())]
    e, bb = ca.MX.sym("e", ext.size), ca.MX.sym("b", A.shape[0])
    fs = ca.Function("fs", [e, bb], [lu.solve(lu.factor_sum(e, by), bb)])
    x2 = np.asarray(fs(ext, b)).ravel()
    assert np.linalg.norm(A @ x2 - b) <= REL * np.linalg.norm(b) * np.linalg.cond(A)
    if nb < 4:
        return
    C = A.copy()
    C[k + 1, k + 2] = 0.1  # the first pair's second row couples to the next pair
    assert sum(len(bl) for bl in lead_blocks(_nonzeros(C)[0], k + nb)) == k
    with pytest.raises(ValueError, match=r"is not \[\[P, 0\], \[X, Q\]\]"):
        SchurBandedLU(_nonzeros(C)[0], k + nb)


def test_the_loops_graph_does_not_grow_with_the_unknowns():
    """The factor loop is CasADi's nested mapaccum, whose graph grows with log n: one flat
    loop of n / ROWS_PER_CALL calls is a graph of one node per two calls (3,001 nodes at 6,000
    unknowns, 13 s and 2.4 GB to build where the nested one takes 0.05 s; measured 55 and 60
    nodes nested at 600 and 6,000). At most 2x over 10x the unknowns."""
    small, big = (BandedLU(ca.Sparsity.banded(n, 5)) for n in (600, 6000))
    for name in ("_eliminate", "_forward", "_backward"):
        a, b = getattr(small, name).n_nodes(), getattr(big, name).n_nodes()
        assert b <= 2 * a, (name, a, b)
