"""Schur elimination of a block-diagonal leading block before the banded LU of
:mod:`.banded`: :class:`SchurBandedLU`, and where such a lead ends (:func:`lead_blocks`,
:func:`diagonal_lead`).

Generic: it sees a square sparsity pattern, nothing about cables. Why: a mechanism's
iteration matrix in first-order form starts with its kinematic rows q' - v, structurally
diagonal in q; first-order states among q (a friction bristle's two deflections per node)
add 2 x 2 blocks coupled within their node. Eliminating that lead L,

    A = [[L, B], [C, D]],   S = D - C L^-1 B,

leaves the velocities alone to the banded LU: for a cable's nodes half the unknowns and
half-bandwidth 5 instead of 13 (with friction bristles, the velocities at half-band 5 instead
of every unknown at 7). S's band is gathered straight from the matrix's sources and from the
products C_ir G_rj, G = L^-1 B, without forming the nonzeros or S (:mod:`.gather`). L's
blocks are inverted in closed form (1 x 1 and 2 x 2), without pivoting: a singular block
gives inf/NaN, which the caller's residual check catches.
"""
from __future__ import annotations

import casadi as ca
import numpy as np

from .banded import BandedLU, with_constants
from .gather import gather_sum

__all__ = ["SchurBandedLU", "diagonal_lead", "lead_blocks", "leading_diagonal"]


def leading_diagonal(sp: ca.Sparsity, k: int) -> bool:
    """Whether the leading k x k block of ``sp`` (0 < k < n) is structurally diagonal (every
    diagonal entry present, nothing else)."""
    return 0 < k < sp.size1() and diagonal_lead(sp, k) == k


def diagonal_lead(sp: ca.Sparsity, k_max: int) -> int:
    """The largest k <= ``k_max`` (and < n) whose leading k x k block of ``sp`` is
    structurally diagonal (0 when none): a mechanism's kinematic rows q' - v lead its
    iteration matrix, and first-order states among q (a friction bristle's) end the
    diagonal part where their rows couple."""
    n = sp.size1()
    r, c = (np.asarray(v, dtype=int) for v in sp.get_triplet())
    off = r != c
    k = min(k_max, n - 1, int(np.maximum(r[off], c[off]).min()) if off.any() else n)
    present = np.zeros(n, dtype=bool)
    present[r[~off]] = True
    missing = np.flatnonzero(~present[:max(k, 0)])
    return max(0, int(missing[0]) if missing.size else k)


def lead_blocks(sp: ca.Sparsity, k_max: int) -> list[tuple[int, ...]]:
    """The blocks of the longest lead L (at most ``k_max`` rows and fewer than n) of ``sp``
    that is, up to the order of its rows, [[P, 0], [X, Q]] with P diagonal and Q block
    diagonal in pairs of consecutive rows: a row whose only entry among L's columns is its
    diagonal (a 1-block: a kinematic row q' - v), or a pair of rows whose entries among L's
    columns are in the pair's own columns and in earlier 1-blocks' (X), whose columns no
    other row of L reaches, and which is structurally invertible (both diagonal entries, or
    both off-diagonal ones): a friction bristle's two deflections, whose rates depend on
    their node's position. Anything else ends the lead (a 1 x 1 block with X, a
    triangular pair whose diagonal row is a 1-block: shorter, not wrong). The blocks'
    sizes sum to the lead's length (0: none)."""
    n = sp.size1()
    k_lim = min(k_max, n - 1)
    if k_lim <= 0:
        return []
    r, c = (np.asarray(v, dtype=int) for v in sp.get_triplet())
    present = set(zip(r.tolist(), c.tolist()))
    inside = (r < k_lim) & (c < k_lim)
    cols: list[set[int]] = [set() for _ in range(k_lim)]
    rows: list[set[int]] = [set() for _ in range(k_lim)]
    for a, b in zip(r[inside].tolist(), c[inside].tolist()):
        cols[a].add(b)
        rows[b].add(a)
    single = [cols[i] == {i} for i in range(k_lim)]
    blocks, i = [], 0
    while i < k_lim:
        if single[i]:
            blocks.append((i,))
            i += 1
            continue
        j, pair = i + 1, {i, i + 1}
        if j < k_lim and all(single[x] and x < i for x in (cols[i] | cols[j]) - pair) \
                and {i, j} <= cols[i] | cols[j] and rows[i] <= pair and rows[j] <= pair \
                and ({(i, i), (j, j)} <= present or {(i, j), (j, i)} <= present):
            blocks.append((i, j))
            i += 2
            continue
        break
    return blocks


# Every gathered vector is taken through ca.vec: a 1 x 1 MX indexed by a list turns into a
# row, and the products below need columns.


class SchurBandedLU:
    """``A = [[L, B], [C, D]]`` with the leading k x k block L = [[P, 0], [X, Q]] up to its
    rows' order (:func:`lead_blocks`: P diagonal, Q in 2 x 2 blocks), solved by eliminating
    L, S = D - C L^-1 B, and :class:`~symcable.linalg.banded.BandedLU` on S (module
    docstring). G = L^-1 B by blocks: G_P = P^-1 B_P, G_Q = Q^-1 (B_Q - X G_P).

    ``factor(a) -> f`` packs S's banded factors, P^-1 and Q^-1's blocks, and the nonzeros
    of X, B and C; ``factor_sum`` the same from a source vector; ``solve(f, b) -> x``.
    ``kernels``: as :class:`~symcable.linalg.banded.BandedLU`'s, for S's."""

    def __init__(self, sp: ca.Sparsity, k: int, name: str = "band", kernels=None):
        self.k, self.n, self.sp = k, sp.size1(), sp
        if not 0 < k < self.n:
            raise ValueError(f"SchurBandedLU: the lead k = {k} must be in 1 .. n - 1 = "
                             f"{self.n - 1}")
        blocks = lead_blocks(sp, k)
        if sum(len(b) for b in blocks) != k:
            raise ValueError(f"SchurBandedLU: the leading {k} x {k} block is not [[P, 0], "
                             "[X, Q]] (P diagonal, Q in pairs of rows)")
        M = ca.DM(sp, np.arange(1, sp.nnz() + 1, dtype=float))  # nonzero m + 1 at its place

        def at(i, j):
            return int(M[i, j]) - 1  # -1: structurally zero

        def where(X):
            return np.asarray(X.nonzeros(), dtype=int) - 1

        B, C, D = M[:k, k:], M[k:, :k], M[k:, k:]
        self.sp_B, self.sp_C = B.sparsity(), C.sparsity()
        self._B, self._C = where(B), where(C)
        self._ones = [b[0] for b in blocks if len(b) == 1]
        self._twos = [b for b in blocks if len(b) == 2]
        self._L1 = [at(i, i) for i in self._ones]
        self._L2 = [[at(i, i), at(i, j), at(j, i), at(j, j)] for i, j in self._twos]
        # X: the pairs' rows (in the order of _twos, two each) by the 1-blocks' columns
        q_rows = [i for pair in self._twos for i in pair]
        Xm = M[q_rows, self._ones] if q_rows and self._ones else ca.DM(len(q_rows),
                                                                       len(self._ones))
        self.sp_X = Xm.sparsity()
        self._X = where(Xm)
        n1 = len(self._ones)
        self.n_inv = n1 + 4 * len(self._twos)
        self._index(D)
        self.lu = BandedLU(self._sp_S, name, kernels=kernels)
        self.l, self.u = self.lu.l, self.lu.u
        self.n_factors = self.lu.n_factors + self.n_inv + len(self._X) + B.nnz() + C.nnz()

    def _index(self, D):
        """G's entries, each a sum of products of gathered vectors (``_GP``, ``_H``,
        ``_GQ``: index lists), S's pattern, and the products C_ir G_rj that S_ij subtracts:
        ``_prods`` (S entry, C entry, G entry)."""
        k, n1 = self.k, len(self._ones)
        b_rows, b_cols = self.sp_B.get_triplet()
        b_in: list[dict[int, int]] = [{} for _ in range(k)]  # row -> {column: B entry}
        for t, (r, c) in enumerate(zip(b_rows, b_cols)):
            b_in[r][c] = t
        g_in: list[dict[int, int]] = [{} for _ in range(k)]  # row -> {column: G entry}
        # G_P = P^-1 B_P: entry (r, j) = inv[p] * B[t]
        self._GP = ([], [])
        for p, r in enumerate(self._ones):
            for j, t in sorted(b_in[r].items()):
                g_in[r][j] = len(self._GP[0])
                self._GP[0].append(p)
                self._GP[1].append(t)
        n_gp = len(self._GP[0])
        # H = B_Q - X G_P (per pair row): sources [B; -X G_P products], gathered
        x_rows, x_cols = self.sp_X.get_triplet()
        x_in: list[list[tuple[int, int]]] = [[] for _ in range(2 * len(self._twos))]
        for t, (a, p) in enumerate(zip(x_rows, x_cols)):
            x_in[a].append((p, t))
        nb = self.sp_B.nnz()
        self._XG = ([], [])  # (X entry, G_P entry) per product
        h_in: list[dict[int, list[int]]] = []
        for a, r in enumerate(i for pair in self._twos for i in pair):
            row = {j: [t] for j, t in b_in[r].items()}
            for p, tx in x_in[a]:
                for j, g in g_in[self._ones[p]].items():
                    row.setdefault(j, []).append(nb + len(self._XG[0]))
                    self._XG[0].append(tx)
                    self._XG[1].append(g)
            h_in.append(row)
        self._H: list[list[int]] = []
        h_at: list[dict[int, int]] = []
        for row in h_in:
            h_at.append({})
            for j, src in sorted(row.items()):
                h_at[-1][j] = len(self._H)
                self._H.append(src)
        # G_Q = Q^-1 H: entry (r, j) = sum over the pair's rows s of inv[r, s] * H[s, j]
        self._GQ: list[list[tuple[int, int]]] = []
        for t, pair in enumerate(self._twos):
            for a, r in enumerate(pair):
                for j in sorted(set(h_at[2 * t]) | set(h_at[2 * t + 1])):
                    g_in[r][j] = n_gp + len(self._GQ)
                    self._GQ.append([(n1 + 4 * t + 2 * a + b, h_at[2 * t + b][j])
                                     for b in range(2) if j in h_at[2 * t + b]])
        d_rows, d_cols = D.sparsity().get_triplet()
        d_where = np.asarray(D.nonzeros(), dtype=int) - 1
        prods = [((i, j), tc, g) for tc, (i, r) in enumerate(zip(*self.sp_C.get_triplet()))
                 for j, g in sorted(g_in[r].items())]
        entries = sorted(set(zip(d_rows, d_cols)) | {ij for ij, _, _ in prods},
                         key=lambda ij: (ij[1], ij[0]))
        m = self.n - k
        self._sp_S = ca.Sparsity.triplet(m, m, [i for i, _ in entries], [j for _, j in entries])
        s_rows, s_cols = self._sp_S.get_triplet()
        s_at = {rc: s for s, rc in enumerate(zip(s_rows, s_cols))}
        self._S_from_D = [(s_at[rc], int(mm)) for rc, mm in zip(zip(d_rows, d_cols), d_where)]
        self._prods = [(s_at[ij], tc, g) for ij, tc, g in prods]
        self._n_S = self._sp_S.nnz()

    def _inverse(self, pick):
        """P^-1 and Q^-1's entries (MX column): the 1 x 1 blocks' 1 / d, then per 2 x 2 block
        [[a, b], [c, e]] its inverse [e, -b, -c, a] / (a e - b c), row by row."""
        parts = []
        if self._ones:
            parts.append(1.0 / ca.vec(pick(self._L1)))
        if self._twos:
            a, b, c, e = (ca.vec(pick([blk[q] for blk in self._L2])) for q in range(4))
            det = a * e - b * c
            parts.append(ca.vec(ca.horzcat(e / det, -b / det, -c / det, a / det).T))
        return ca.vertcat(*parts)

    def _G(self, inv, X, B):
        """G = L^-1 B's entries (MX column): G_P's, then G_Q's."""
        G = ca.vec(inv[self._GP[0]]) * ca.vec(B[self._GP[1]]) if self._GP[0] else ca.MX(0, 1)
        if not self._GQ:
            return G
        src = ca.vertcat(B, -(ca.vec(X[self._XG[0]]) * ca.vec(G[self._XG[1]]))) \
            if self._XG[0] else B
        H = gather_sum(src, self._H)
        flat = [pair for pairs in self._GQ for pair in pairs]
        terms = ca.vec(inv[[p[0] for p in flat]]) * ca.vec(H[[p[1] for p in flat]])
        at, by = 0, []
        for pairs in self._GQ:
            by.append(list(range(at, at + len(pairs))))
            at += len(pairs)
        return ca.vertcat(G, gather_sum(terms, by))

    def _lead_solve(self, inv, X, y):
        """L^-1 y for a k-vector ``y``: y_P / d, then Q^-1 (y_Q - X (y_P / d))."""
        n1, outs, order = len(self._ones), [], []
        yp = ca.vec(inv[:n1]) * ca.vec(y[self._ones]) if self._ones else ca.MX(0, 1)
        outs.append(yp)
        order += self._ones
        if self._twos:
            first, second = [i for i, _ in self._twos], [j for _, j in self._twos]
            t = ca.vec(ca.reshape(y[first + second], len(first), 2).T)  # pair by pair
            if self.sp_X.nnz():
                t = t - ca.mtimes(X, yp)
            t0, t1 = t[0::2], t[1::2]
            base = n1 + 4 * np.arange(len(self._twos))
            g = [ca.vec(inv[(base + q).tolist()]) for q in range(4)]
            outs += [g[0] * t0 + g[1] * t1, g[2] * t0 + g[3] * t1]
            order += first + second
        x = ca.vertcat(*outs)
        if order != list(range(self.k)):
            x = x[np.argsort(order).tolist()]
        return x

    def factor(self, a):
        return self.factor_sum(a, [[m] for m in range(self.sp.nnz())])

    def factor_sum(self, ext, by: list[list[int]], zero: int | None = None,
                   one: int | None = None):
        """:meth:`factor` of the matrix whose nonzero m is the sum of ``ext`` at the
        positions ``by[m]`` (:meth:`BandedLU.factor_sum`, ``zero`` and ``one`` as there):
        S's band gathered from ``ext`` and from the products C_ir G_rj, without forming the
        nonzeros or S."""
        ext, zero, one = with_constants(ext, zero, one)

        def pick(index):
            return gather_sum(ext, [by[m] if m >= 0 else [] for m in index], zero)

        B, C, X = pick(self._B), pick(self._C), pick(self._X)
        inv = self._inverse(pick)
        S_by: list[list[int]] = [[] for _ in range(self._n_S)]
        for s, m in self._S_from_D:
            S_by[s] = by[m]
        W0, rows = self.lu.band_gather(ext, S_by, zero, one)
        if self._prods:
            G = self._G(inv, X, B)
            s_i, c_i, g_i = (list(c) for c in zip(*self._prods))
            prods: list[list[int]] = [[] for _ in range(self._n_S)]
            for t, s in enumerate(s_i):
                prods[s].append(t)
            minus = ca.vertcat(-(ca.vec(C[c_i]) * ca.vec(G[g_i])), 0.0)
            W1, rows1 = self.lu.band_gather(minus, prods, len(s_i))
            W0, rows = W0 + W1, rows + rows1
        return ca.vertcat(self.lu.factor_rows(W0, rows), inv, X, B, C)

    def solve(self, f, b):
        k, at = self.k, self.lu.n_factors
        parts = []
        for size in (self.n_inv, self.sp_X.nnz(), self.sp_B.nnz()):
            parts.append(f[at:at + size])
            at += size
        inv = parts[0]
        X = ca.MX(self.sp_X, parts[1])
        B = ca.MX(self.sp_B, parts[2])
        C = ca.MX(self.sp_C, f[at:])
        bq, bv = b[:k], b[k:]
        xv = self.lu.solve(f[:self.lu.n_factors], bv - ca.mtimes(C, self._lead_solve(inv, X, bq)))
        return ca.vertcat(self._lead_solve(inv, X, bq - ca.mtimes(B, xv)), xv)
