"""The linear solver of an implicit step's iteration matrix (the first-order
generalized-alpha step's, :mod:`symcable.solvers.galpha1`): the block LU written out in SX,
the banded LU of :mod:`symcable.linalg.banded` (on the Schur complement of the kinematic rows,
:mod:`symcable.linalg.schur`), or CasADi's sparse QR, chosen by the pattern
(:func:`linear_solver`); the banded LU's loops may call their kernels' generated C
(:func:`kernels_in_c`)."""
from __future__ import annotations

import casadi as ca
import numpy as np

from ..linalg.banded import BandedLU, bandwidths, reverse_cuthill
from ..linalg.schur import SchurBandedLU, lead_blocks
from ..linalg.sparse import sparse_solve
from ..linalg.sxlu import block_lu, block_plan
from ..mechanism.codegen import compile_functions

__all__ = ["BANDED_MAX_WIDTH", "CSE_MAX_STATES", "LINSOL", "banded_solver", "kernels_in_c",
           "linear_solver"]

#: largest state whose SX Functions (residual, iteration matrix) are built with common
#: subexpressions eliminated: fewer instructions and a faster step in the virtual machine,
#: but CasADi's elimination grows faster than the graph (seconds at thousands of states)
CSE_MAX_STATES = 1000
#: widest band (l + u + 1, in reverse Cuthill-McKee order) that the banded LU takes above
#: SXLU_MAX_STATES; wider patterns go to sparse QR. On a long chain (a narrow band on the
#: Schur complement) a step costs less than with the sparse QR, which refactorises at
#: every solve
BANDED_MAX_WIDTH = 40
#: the sparse linear solver above SXLU_MAX_STATES (CasADi's QR generates C; CSparse's LU does not)
LINSOL = "qr"


def _fill_order(sp: ca.Sparsity) -> np.ndarray:
    """A fill-reducing symmetric order of a square pattern: approximate minimum degree of
    the pattern plus its transpose (CSparse's AMD; dense rows go last)."""
    return np.asarray((sp + sp.T).amd(), dtype=int)


def linear_solver(J: ca.SX | None, args: list, cache: dict, lu: bool, n_lead: int = 0,
                  given: tuple | None = None, kernels_c: bool = False):
    """``(factor, solve, n_factors, kind)`` for the iteration matrix ``J`` (SX in ``args``):
    ``factor(*args) -> f``, ``solve(f, b) -> J^-1 b``, ``kind`` "block-lu", "banded" or
    "qr"; the block LU when ``lu`` and the pattern allows it, else the banded LU (Schur on
    the 1 x 1 and 2 x 2 blocks that lead the ``n_lead`` kinematic rows:
    :func:`banded_solver`) when the band is narrow enough, else sparse QR. ``given``:
    instead of ``J``, its pattern, a Function of ``args`` giving its nonzeros, and the same
    as sources and a sum map (:func:`~symcable.solvers.element_jacobian.element_jacobian`),
    which the banded LU gathers straight into its band
    (:meth:`~symcable.linalg.banded.BandedLU.factor_sum`). ``kernels_c``: the banded LU's
    loops call their kernels' generated C."""
    sp = J.sparsity() if given is None else given[0]
    n = sp.size1()
    opts = {"cse": n <= CSE_MAX_STATES}
    if lu and given is None:
        perm = _fill_order(sp)
        Jp = J[perm.tolist(), perm.tolist()]
        spp = Jp.sparsity()
        plan = (1, None) if spp.nnz_diag() == n else block_plan(spp)
        if plan is not None:
            lu = block_lu(spp, *plan, cache=cache)
            factor = ca.Function("ga1_factor", args, [lu.factor(Jp.nz[:])], opts)
            f, b = ca.SX.sym("f", lu.n_factors), ca.SX.sym("b", n)
            xp = lu.apply(f, b[perm.tolist()])
            solve = ca.Function("ga1_solve", [f, b], [xp[np.argsort(perm).tolist()]], opts)
            return factor, solve, lu.n_factors, "block-lu"
    jac = ca.Function("ga1_jacobian", args, [J.nz[:]], opts) if given is None else given[1]
    band = banded_solver(sp, n_lead, cache, kernels_c)
    if band is not None:
        margs = [ca.MX.sym(f"a{i}", a.sparsity()) for i, a in enumerate(args)]
        if given is None:
            f_band = band.factor(jac(*margs))
        else:
            blocks, by, zero, one = given[2]
            f_band = band.factor_sum(blocks(*margs), by, zero, one)
        factor = ca.Function("ga1_band_factor", margs, [f_band])
        f, b = ca.MX.sym("f", band.n_factors), ca.MX.sym("b", n)
        return factor, ca.Function("ga1_band_solve", [f, b], [band.solve(f, b)]), \
            band.n_factors, "banded"
    f, b = ca.MX.sym("f", sp.nnz()), ca.MX.sym("b", n)
    solve = ca.Function("ga1_qr_solve", [f, b], [sparse_solve(ca.MX(sp, f), b, LINSOL)])
    return jac, solve, sp.nnz(), "qr"


def kernels_in_c(fns: list, what: str) -> list:
    """The generated C of small kernel Functions (one library, cached), in their order."""
    lib = compile_functions(fns, what=what)
    return [lib[f.name()] for f in fns]


def banded_solver(sp: ca.Sparsity, n_lead: int, cache: dict, kernels_c: bool = False):
    """The banded LU of the pattern ``sp``, or None when its band is wider than
    BANDED_MAX_WIDTH; kept in ``cache``. On the Schur complement of as many of its ``n_lead``
    leading rows as form 1 x 1 or 2 x 2 diagonal blocks (:func:`~symcable.linalg.schur.
    lead_blocks`: the kinematic rows, and a friction bristle's two coupled first-order
    states per node) where that elimination costs less than the whole matrix's
    (n (l + 1) (u + 1) of each: for a cable's nodes half the unknowns at half-band 5 against
    all of them at 13, with friction bristles all at 14 or 15). ``kernels_c``: its loops
    call their kernels' generated C."""
    key = ("banded", n_lead, sp.size1(), sp.nnz(), kernels_c)
    kernels = (lambda ks: kernels_in_c(ks, "the banded LU's kernels")) if kernels_c else None
    if key not in cache:
        k = sum(len(b) for b in lead_blocks(sp, n_lead))
        l, u = bandwidths(sp, reverse_cuthill(sp))
        n = sp.size1()
        plain = l + u + 1 <= BANDED_MAX_WIDTH
        solver = None
        if k > 0:
            schur = SchurBandedLU(sp, k, "ga1", kernels)
            cost = (n - k) * (schur.l + 1) * (schur.u + 1)
            if (schur.l + schur.u + 1 <= BANDED_MAX_WIDTH
                    and (not plain or cost < n * (l + 1) * (u + 1))):
                solver = schur
        if solver is None and plain:
            solver = BandedLU(sp, "ga1", kernels=kernels)
        cache[key] = solver
    return cache[key]
