"""Banded LU without pivoting as CasADi loops (``mapaccum``), for large banded systems in
generated C.

Generic: it sees a square sparsity pattern, nothing about cables.

Why: the iteration matrix of a long line is banded once its unknowns are ordered along the
line (half-bandwidth 5 for a cable's node velocities), but CasADi's sparse QR is slow on a
few hundred such rows (its cost does not follow the band), refactorises at every solve, and the
block LU written out in SX (:mod:`symcable.linalg.sxlu`) is fast but straight-line: its C
takes minutes to compile above a few hundred unknowns. Here the elimination is one small
kernel applied row after row (``Function.mapaccum``): generated C is a loop around a few
hundred flops, compiles in seconds whatever the size, and costs O(n l u) to factorise and
O(n (l + u)) to solve, the factors kept between solves (chord iterations reuse them).

Order: reverse Cuthill-McKee of the pattern plus its transpose (SciPy), which depends on the
pattern alone; ``l`` and ``u`` are the lower and upper bandwidths in that order. No pivot
search (as in :mod:`symcable.linalg.sxlu`): for the dominant-diagonal iteration matrices of
mechanical systems elimination in order is stable; a zero pivot gives inf/NaN, which the
caller's residual check catches.

The matrix comes as its nonzeros (``factor``) or as sums of entries of a source vector
(``factor_sum``: an element loop's blocks and the rest's nonzeros, :mod:`.gather`), gathered
straight into the band's rows; :mod:`.schur` eliminates a leading block first (the
kinematic rows) and gathers its products into the band too, without forming S.

Storage: row i of the band holds columns i - l .. i + u (``w = l + u + 1`` entries). The
elimination carries a window of the rows k .. k + l, columns k .. k + l + u, and takes in
row k + l + 1 of the band at step k; it puts out, per step, the inverse pivot, row k of U
right of the diagonal (u) and column k of L below it (l): the factors, w per row.
"""
from __future__ import annotations

import casadi as ca
import numpy as np
from scipy.sparse import csr_matrix
from scipy.sparse.csgraph import reverse_cuthill_mckee

from .gather import gather_sum

__all__ = ["BandedLU", "bandwidths", "reverse_cuthill", "with_constants"]

#: rows eliminated per call of the loop body (the body written out for this many rows):
#: fewer calls, less copying of the carried window
ROWS_PER_CALL = 8


def reverse_cuthill(sp: ca.Sparsity) -> np.ndarray:
    """Reverse Cuthill-McKee order of the square pattern ``sp`` plus its transpose."""
    n = sp.size1()
    r, c = (np.asarray(v, dtype=int) for v in sp.get_triplet())
    A = csr_matrix((np.ones(r.size), (r, c)), shape=(n, n))
    return np.asarray(reverse_cuthill_mckee(csr_matrix(A + A.T), symmetric_mode=True), int)


def bandwidths(sp: ca.Sparsity, perm=None) -> tuple[int, int]:
    """``(l, u)``: lower and upper bandwidth of the square pattern ``sp`` with rows and
    columns in the order ``perm`` (default: as given)."""
    r, c = (np.asarray(v, dtype=int) for v in sp.get_triplet())
    if perm is not None:
        inv = np.argsort(np.asarray(perm, int))
        r, c = inv[r], inv[c]
    d = c - r
    return (int(max(0, -d.min())) if d.size else 0), (int(max(0, d.max())) if d.size else 0)


class BandedLU:
    """Banded LU of square matrices with the pattern ``sp`` (see the module docstring).

    Attributes: ``n``, ``perm`` (the order), ``l``, ``u``, ``n_factors`` (= n (l + u + 1)).
    Methods: ``factor(a) -> f`` (MX: ``a`` the matrix's nonzeros in CasADi's column-major
    order), ``solve(f, b) -> x`` (MX, ``b`` an n-vector). ``kernels``: optional, a callable
    that maps the list of the three row kernels (elimination, forward, backward
    substitution) to the Functions the loops call instead (their generated C)."""

    def __init__(self, sp: ca.Sparsity, name: str = "band", rows: int | None = None,
                 kernels=None):
        self.n = n = sp.size1()
        self.perm = reverse_cuthill(sp)
        self.l, self.u = bandwidths(sp, self.perm)
        l, u = self.l, self.u
        self.w = w = l + u + 1
        self.rows = R = int(rows or ROWS_PER_CALL)
        self.calls = -(-n // R)
        self.n_pad = N = self.calls * R  # padded with identity rows
        self.n_factors = N * w
        inv = np.argsort(self.perm)
        r, c = (np.asarray(v, dtype=int) for v in sp.get_triplet())
        pr, pc = inv[r], inv[c]
        self._band_index = (pr * w + pc - pr + l).tolist()
        self._pad_index = (np.arange(n, N) * w + l).tolist()
        # the first window (rows 0..l, columns 0..l+u) gathered from the band; N w + l + 1
        # rows of zeros follow the band (incoming rows past the end)
        idx = np.full((l + 1, w), N * w, dtype=int)
        for row in range(min(l + 1, N)):
            for col in range(w):
                j = col - row + l
                if 0 <= j < w:
                    idx[row, col] = row * w + j
        self._window0 = idx.ravel().tolist()
        # CasADi's default nesting of the loop (a loop of loops): one flat loop of all the
        # calls ("base" = calls) took 13 s and 2.4 GB to build for 6,000 unknowns, against
        # 0.05 s and 0.1 GB nested, and was slower to call
        # ``kernels``: a callable taking the three kernels and returning their replacements
        # (the same Functions compiled: the loops stay in the caller's graph)
        ks = [self._elimination_kernel(name), self._forward_kernel(name),
              self._backward_kernel(name)]
        if kernels is not None:
            ks = list(kernels(ks))
        self._eliminate = ks[0].mapaccum(f"{name}_factor", self.calls, 1, {})
        self._forward = ks[1].mapaccum(f"{name}_forward", self.calls, 1, {})
        self._backward = ks[2].mapaccum(f"{name}_backward", self.calls, 1, {})

    # kernels (SX, small: ``rows`` rows per call) ------------------------------------------
    def _elimination_kernel(self, name):
        l, u, w, R = self.l, self.u, self.w, self.rows
        W = ca.SX.sym("W", (l + 1) * w)
        inc = ca.SX.sym("inc", w, R)
        rows = [[W[r * w + c] for c in range(w)] for r in range(l + 1)]
        out = []
        for k in range(R):
            inv_piv = 1.0 / rows[0][0]
            mult = [rows[r][0] * inv_piv for r in range(1, l + 1)]
            new = []
            for r in range(1, l + 1):
                new.append([rows[r][c] - mult[r - 1] * rows[0][c] if c <= u else rows[r][c]
                            for c in range(1, w)] + [ca.SX(0)])
            new.append([inc[c, k] for c in range(w)])
            out += [inv_piv] + [rows[0][c] for c in range(1, u + 1)] + mult
            rows = new
        flat = [e for row in rows for e in row]
        return ca.Function(f"{name}_eliminate", [W, inc],
                           [ca.vertcat(*flat), ca.reshape(ca.vertcat(*out), w, R)])

    def _forward_kernel(self, name):
        l, u, R = self.l, self.u, self.rows
        s = ca.SX.sym("s", l + 1)
        f = ca.SX.sym("f", self.w, R)
        b_in = ca.SX.sym("b_in", 1, R)
        st, ys = [s[r] for r in range(l + 1)], []
        for k in range(R):
            y = st[0]
            st = [st[r] - f[1 + u + r - 1, k] * y for r in range(1, l + 1)] + [b_in[k]]
            ys.append(y)
        return ca.Function(f"{name}_fwd", [s, f, b_in], [ca.vertcat(*st), ca.horzcat(*ys)])

    def _backward_kernel(self, name):
        u, R = self.u, self.rows
        s = ca.SX.sym("s", max(u, 1))
        f = ca.SX.sym("f", self.w, R)  # rows in reverse order
        y = ca.SX.sym("y", 1, R)
        st, xs = [s[c] for c in range(max(u, 1))], []
        for k in range(R):
            acc = y[k]
            for c in range(1, u + 1):
                acc = acc - f[c, k] * st[c - 1]
            x = acc * f[0, k]
            st = ([x] + st[:u - 1]) if u else st
            xs.append(x)
        return ca.Function(f"{name}_bwd", [s, f, y], [ca.vertcat(*st), ca.horzcat(*xs)])

    # expressions --------------------------------------------------------------------------
    def factor(self, a):
        """The packed factors (MX, n_pad w) of the matrix with nonzeros ``a``."""
        return self.factor_sum(a, [[m] for m in range(len(self._band_index))])

    def factor_sum(self, ext, by: list[list[int]], zero: int | None = None,
                   one: int | None = None):
        """:meth:`factor` of the matrix whose nonzero m is the sum of ``ext`` (an MX column)
        at the positions ``by[m]`` (:mod:`symcable.linalg.gather`), gathered straight into
        the band's rows without forming the nonzeros; ``zero`` and ``one``: positions where
        ``ext`` is 0 and 1 (else both are appended to a copy of ``ext``)."""
        ext, zero, one = with_constants(ext, zero, one)
        return self.factor_rows(*self.band_gather(ext, by, zero, one))

    def band_gather(self, ext, by: list[list[int]], zero: int, one: int | None = None):
        """``(W0, rows)``: the first window and the incoming rows of the band (MX) of the
        matrix whose nonzero m sums ``ext`` at ``by[m]``; ``ext[zero]`` = 0, and the padding
        rows' pivots ``ext[one]`` (= 1), or 0 with ``one`` None (a part to add to another)."""
        N, w, l = self.n_pad, self.w, self.l
        band: list[list[int]] = [[] for _ in range(N * w + (l + 1) * w + 1)]
        for m, p in enumerate(self._band_index):
            band[p] = by[m]
        if one is not None:
            for p in self._pad_index:
                band[p] = [one]
        return (gather_sum(ext, [band[p] for p in self._window0], zero),
                gather_sum(ext, band[(l + 1) * w:(l + 1) * w + N * w], zero))

    def factor_rows(self, W0, rows):
        """The packed factors from the band's first window and incoming rows
        (:meth:`band_gather`)."""
        _, F = self._eliminate(W0, ca.reshape(rows, self.w, self.n_pad))
        return ca.vec(F)

    def solve(self, f, b):
        """x = A^-1 b for the factors ``f`` of A (MX) and the n-vector ``b``."""
        n, N, w, l, u = self.n, self.n_pad, self.w, self.l, self.u
        F = ca.reshape(f, w, N)
        bp = ca.vertcat(b[self.perm.tolist()], ca.MX.zeros(N - n + l + 1, 1))
        _, y = self._forward(bp[:l + 1], F, ca.reshape(bp[l + 1:l + 1 + N], 1, N))
        rev = list(range(N - 1, -1, -1))
        _, xr = self._backward(ca.MX.zeros(max(u, 1), 1), F[:, rev], y[:, rev])
        x = ca.reshape(xr[:, rev], N, 1)
        return x[np.argsort(self.perm).tolist()]


def with_constants(ext, zero: int | None, one: int | None):
    """``(ext, zero, one)``: ``ext`` with the positions of a 0 and a 1 in it, appended to a
    copy where not given."""
    if zero is not None and one is not None:
        return ext, zero, one
    n = int(ext.numel())
    return ca.vertcat(ext, ca.DM([0.0, 1.0])), n, n + 1

