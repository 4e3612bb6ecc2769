"""Sparse block LU factorisation written out as scalar CasADi expressions (SX), for generated C.

Generic: it sees a square sparsity pattern and a block size, nothing about cables.

Why: CasADi's sparse QR (:mod:`symcable.linalg.sparse`) is compiled C++ in the virtual
machine and generic index-driven C in generated code, so generating code cannot make it
faster, and it dominates a Newton iteration of the banded cable systems (most of an
iteration of a mooring line's statics). Written out as straight-line arithmetic on the
nonzeros, with the fill computed once from the pattern, the same elimination is a few
thousand flops with no index logic: the C compiler turns it into a tight instruction stream.

Elimination is by ``b x b`` blocks in their natural order, each diagonal block inverted in
closed form (``b = 1``: the reciprocal; ``b = 2``: adjugate over determinant). There is no
pivot search, so the expressions, and a library compiled from them, depend on the pattern
alone: every scene of one structure shares them. Within a block every entry may be zero
(the inverse is exact whatever the block's pattern), which is what the cable systems need:

* the planar statics interleave 2-vectors of unknowns (segment angle and strain, node
  position) with 2-vectors of residuals, and several diagonal *entries* are structurally
  zero while the 2 x 2 diagonal *blocks* are regular (a segment's compatibility fixes its
  angle and strain; a node's balance its position);
* the generalized-α iteration matrix ``alpha_m I - alpha_f gamma dt df/dy`` of a mechanical
  system has a dominant, or positive-real, diagonal, for which elimination without
  pivoting is stable.

A matrix whose diagonal blocks are singular, or nearly, gives infinite or inaccurate
results; callers check what they solve (a Newton iteration checks its residual, and
:func:`block_lu_check` measures the pivots and the growth of a numeric matrix).

``BlockLU(sparsity, block)`` builds

* ``factor``, the Function ``lu_factor(a) -> f``: ``a`` the matrix's nonzeros (CasADi's
  column-major order), ``f`` the packed factors (blocks of L, of U, inverse pivot blocks);
* ``solve_function(n_rhs)``, the Function ``lu_solve(f, b) -> x``, ``b`` n x n_rhs;
* ``apply(f, b)``, the same as expressions, to inline in a larger SX graph.
"""
from __future__ import annotations

import casadi as ca
import numpy as np

__all__ = ["BlockLU", "block_lu", "block_lu_check", "block_matching", "block_plan"]


def _inverse(P: ca.SX) -> ca.SX:
    """Closed-form inverse of a 1 x 1 or 2 x 2 SX block."""
    if P.size1() == 1:
        return 1.0 / P
    a, b, c, d = P[0, 0], P[0, 1], P[1, 0], P[1, 1]
    inv_det = 1.0 / (a * d - b * c)
    return ca.vertcat(ca.horzcat(d * inv_det, -b * inv_det), ca.horzcat(-c * inv_det, a * inv_det))


class BlockLU:
    """Symbolic block LU of one sparsity pattern (see the module docstring).

    Attributes
    ----------
    n : int            order of the matrix
    block : int        block size (1 or 2)
    n_factors : int    length of the packed factors
    factor : casadi.Function  ``lu_factor(a[nnz]) -> f[n_factors]``
    """

    def __init__(self, sparsity: ca.Sparsity, block: int = 2, order=None):
        n = sparsity.size1()
        if sparsity.size2() != n:
            raise ValueError(f"block LU: the matrix must be square, got {n}x{sparsity.size2()}")
        if block not in (1, 2) or n % block:
            raise ValueError(f"block LU: block = {block!r} must be 1 or 2 and divide the order {n}")
        self.n, self.block = n, block
        nb = n // block
        order = np.arange(nb) if order is None else np.asarray(order, dtype=int)
        if sorted(order.tolist()) != list(range(nb)):
            raise ValueError("block LU: order must be a permutation of the block rows")
        self.order = order
        step = np.empty(nb, dtype=int)
        step[order] = np.arange(nb)  # the step at which each block row is eliminated
        a = ca.SX.sym("a", sparsity.nnz())
        A = ca.SX(sparsity, a)
        r_idx, c_idx = (np.asarray(v, dtype=int) // block for v in sparsity.get_triplet())
        pattern = sorted(set(zip(r_idx.tolist(), c_idx.tolist())))
        rows = [dict() for _ in range(nb)]  # block row -> {block column: SX b x b}
        col_rows = [set() for _ in range(nb)]
        for I, Jb in pattern:
            rows[step[I]][Jb] = A[I * block:(I + 1) * block, Jb * block:(Jb + 1) * block]
            col_rows[Jb].add(step[I])
        lower, inv_piv = [], []
        for k in range(nb):
            if k not in rows[k]:
                raise ValueError(f"block LU: pivot block {k} (block row {order[k]}) is structurally "
                                 "zero; choose the order with block_plan")
            Pi = _inverse(ca.densify(rows[k][k]))
            inv_piv.append(Pi)
            upper = [(j, v) for j, v in rows[k].items() if j > k]
            mult = []
            for i in sorted(col_rows[k]):
                if i <= k:
                    continue
                L = ca.mtimes(rows[i].pop(k), Pi)
                mult.append((i, L))
                for j, v in upper:
                    upd = ca.mtimes(L, v)
                    if j in rows[i]:
                        rows[i][j] = rows[i][j] - upd
                    else:
                        rows[i][j] = -upd
                        col_rows[j].add(i)
            lower.append(mult)
        self._lower = [[i for i, _ in m] for m in lower]
        self._upper = [sorted(j for j in rows[k] if j > k) for k in range(nb)]
        packed, self._loc, k0 = [], [], 0
        bb = block * block
        for k in range(nb):
            loc = {}
            for i, L in lower[k]:
                loc[("L", i)] = k0
                packed.append(ca.vec(ca.densify(L)))
                k0 += bb
            for j in self._upper[k]:
                loc[("U", j)] = k0
                packed.append(ca.vec(ca.densify(rows[k][j])))
                k0 += bb
            loc["P"] = k0
            packed.append(ca.vec(inv_piv[k]))
            k0 += bb
            self._loc.append(loc)
        self.n_factors = k0
        self.factor = ca.Function("lu_factor", [a], [ca.vertcat(*packed)], ["a"], ["f"])
        self._solves = {}

    def _blk(self, f, at):
        b = self.block
        return ca.reshape(f[at:at + b * b], b, b)

    def apply(self, f, rhs):
        """``A^-1 rhs`` as SX expressions of the packed factors ``f`` and of ``rhs`` (n x m)."""
        b, nb = self.block, self.n // self.block
        y = [rhs[int(k) * b:(int(k) + 1) * b, :] for k in self.order]
        for k in range(nb):  # forward: L y = rhs (unit block diagonal)
            for i in self._lower[k]:
                y[i] = y[i] - ca.mtimes(self._blk(f, self._loc[k][("L", i)]), y[k])
        x = [None] * nb
        for k in range(nb - 1, -1, -1):  # back: U x = y
            acc = y[k]
            for j in self._upper[k]:
                acc = acc - ca.mtimes(self._blk(f, self._loc[k][("U", j)]), x[j])
            x[k] = ca.mtimes(self._blk(f, self._loc[k]["P"]), acc)
        return ca.vertcat(*x)

    def solve_function(self, n_rhs: int = 1) -> ca.Function:
        """``lu_solve(f, b[n x n_rhs]) -> x``."""
        fn = self._solves.get(n_rhs)
        if fn is None:
            f = ca.SX.sym("f", self.n_factors)
            rhs = ca.SX.sym("b", self.n, n_rhs)
            fn = ca.Function("lu_solve", [f, rhs], [self.apply(f, rhs)], ["f", "b"], ["x"])
            self._solves[n_rhs] = fn
        return fn

    def solve(self, A: ca.SX, rhs):
        """``A^-1 rhs`` for an SX matrix ``A`` of this pattern, as SX expressions."""
        return self.apply(self.factor(A.nz[:]), rhs)


def block_lu(sparsity: ca.Sparsity, block: int = 2, order=None,
             cache: dict | None = None) -> BlockLU:
    """The :class:`BlockLU` of ``sparsity``, reused from ``cache`` (a dict) when given."""
    key = ("block_lu", sparsity.serialize(), int(block),
           None if order is None else tuple(int(i) for i in order))
    if cache is not None and key in cache:
        return cache[key]
    lu = BlockLU(sparsity, block, order)
    if cache is not None:
        cache[key] = lu
    return lu


def block_lu_check(A, block: int = 2, order=None) -> dict:
    """Numeric block LU of ``A`` (ndarray or DM) as :class:`BlockLU` does it:
    ``max_pivot_condition``, the largest condition number of a pivot block, and ``growth``,
    max |U| / max |A|. Large values mean the elimination loses accuracy on ``A``."""
    M = np.array(A.full() if hasattr(A, "full") else A, dtype=float)
    if order is not None:
        M = M[np.concatenate([np.arange(i * block, (i + 1) * block) for i in order])]
    n, scale, worst = M.shape[0], np.abs(M).max(), 1.0
    with np.errstate(all="ignore"):
        for k in range(0, n, block):
            P = M[k:k + block, k:k + block]
            worst = max(worst, float(np.linalg.cond(P)))
            if k + block < n:
                L = M[k + block:, k:k + block] @ np.linalg.inv(P)
                M[k + block:, k + block:] -= L @ M[k:k + block, k + block:]
                M[k + block:, k:k + block] = 0.0
        growth = float(np.abs(np.triu(M)).max() / scale)
    return {"max_pivot_condition": worst, "growth": growth}


def _block_edges(sparsity: ca.Sparsity, block: int) -> dict:
    """Block row -> block columns whose block can be regular (for block 2: both diagonal or
    both anti-diagonal entries present)."""
    nz = set(zip(*(np.asarray(v, dtype=int).tolist() for v in sparsity.get_triplet())))
    nb = sparsity.size1() // block
    edges = {I: [] for I in range(nb)}
    for r, c in nz:
        I, J = r // block, c // block
        if J in edges[I]:
            continue
        i0, j0 = I * block, J * block
        if block == 1 or ((i0, j0) in nz and (i0 + 1, j0 + 1) in nz) or \
                ((i0, j0 + 1) in nz and (i0 + 1, j0) in nz):
            edges[I].append(J)
    return edges


def block_matching(sparsity: ca.Sparsity, block: int) -> np.ndarray | None:
    """A row order by blocks that puts a possibly regular block on every diagonal position:
    ``order[k]`` is the block row eliminated at step k (a maximum bipartite matching of block
    rows to block columns by augmenting paths, trying the natural pairing first); None when
    no perfect matching exists. Depends on the pattern alone."""
    n = sparsity.size1()
    if n % block:
        return None
    edges = _block_edges(sparsity, block)
    nb = n // block
    for I in edges:
        edges[I].sort(key=lambda J: (J != I, abs(J - I)))
    owner = [-1] * nb  # block column -> block row
    for root in range(nb):  # augmenting path from each block row, depth-first, iteratively
        seen, parent = set(), {}  # parent: block column -> block column it was reached from
        stack = [(root, iter(edges[root]), None)]
        found = None
        while stack and found is None:
            I, it, via = stack[-1]
            J = next((j for j in it if j not in seen), None)
            if J is None:
                stack.pop()
                continue
            seen.add(J)
            parent[J] = via
            if owner[J] < 0:
                found = J
            else:
                stack.append((owner[J], iter(edges[owner[J]]), J))
        if found is None:
            return None
        # flip the path back to the root: each column on it goes to the row that reached it
        # (columns nearer the root still hold their old rows when their successor is set)
        J, I = found, stack[-1][0]
        while True:
            owner[J] = I
            J = parent[J]
            if J is None:
                break
            I = root if parent[J] is None else owner[parent[J]]
    return np.asarray(owner, dtype=int)


def block_plan(sparsity: ca.Sparsity):
    """``(block, order)`` for :class:`BlockLU` on ``sparsity``, from the pattern alone: the
    first of 2 x 2 blocks in natural order, 2 x 2 blocks in a matched order
    (:func:`block_matching`), entries in natural order, entries in a matched order whose
    pivots can all be nonzero; None when there is none (the matrix is structurally
    singular)."""
    for block in (2, 1):
        if sparsity.size1() % block:
            continue
        edges = _block_edges(sparsity, block)
        if all(I in edges[I] for I in edges):
            return block, None
        order = block_matching(sparsity, block)
        if order is not None:
            return block, order
    return None
