"""A step's iteration matrix from a Mechanism's element form
(:class:`~symcable.mechanism.element_form.ElementForm`): the elements' blocks computed by a
loop (CasADi ``map``, serial: a loop in the generated C) over the element kernel's own
Jacobian, summed onto the matrix's nonzeros by index gathers
(:mod:`symcable.linalg.gather`), plus the rest's Jacobian written out in SX (kinematic rows,
seabed contact and friction, bending: per node, and small); or, for the banded LU, the
blocks and the rest's nonzeros as the sources it gathers into its band itself
(:meth:`~symcable.linalg.banded.BandedLU.factor_sum`). The step's residual likewise
(:func:`element_residual`).

For an implicit step whose unknown is w with y'(w) = y'_0 + c_m (w - y'_0) and y(w) = y_0 +
c_y (w - y'_0) at the step's alpha point (generalized-alpha: c_m = alpha_m, c_y = alpha_f
gamma h), the momentum rows' Jacobian is c_y dR/dq, c_y dR/dv + c_m dR/dv' on the q and v
columns; the kernel returns that block per element, (dim k) x (2 dim k), with c_y and c_m
as inputs.

On a long chain (a hundred or more elements) the straight-line SX Jacobian of the
first-order generalized-alpha step is hundreds of thousands of instructions (megabytes of
C); this one is a loop of one call per element of a 6 x 12 block (about a thousand
instructions) and a rest of a small fraction of the straight-line size. The seabed as a
second loop of node kernels (each node reading its neighbours) is slightly slower than its
straight-line rest: not done.
"""
from __future__ import annotations

import casadi as ca
import numpy as np

from ..linalg.gather import gather_sum, sum_map, summed
from ..mechanism.element_form import ElementForm, gather, node_values

__all__ = ["block_kernel", "element_jacobian", "element_residual", "jacobian_inputs",
           "jacobian_loop", "residual_inputs", "residual_loop"]


def block_kernel(form: ElementForm) -> ca.Function:
    """``(u, c, s, c_y, c_m) -> B`` (dim k, 2 dim k): the element's c_y dr/dx on the q
    columns, c_y dr/dv + c_m dr/da on the v columns of its nodes (node order)."""
    u = ca.SX.sym("u", form.kernel.size1_in(0))
    c = ca.SX.sym("c", form.kernel.size1_in(1))
    s = ca.SX.sym("s", form.kernel.size1_in(2))
    cy, cm = ca.SX.sym("c_y"), ca.SX.sym("c_m")
    r = form.kernel(u, c, s)
    n = int(r.numel())  # dim k
    J = ca.jacobian(r, u)
    B = ca.horzcat(cy * J[:, :n], cy * J[:, n:2 * n] + cm * J[:, 2 * n:])
    # common subexpressions eliminated: the cable3d block from 1319 to 916 instructions
    return ca.Function(f"{form.kernel.name()}_block", [u, c, s, cy, cm], [ca.densify(B)],
                       ["u", "c", "s", "c_y", "c_m"], ["B"], {"cse": True})


def element_jacobian(mech, rest_jac: ca.SX, rest_args: list, point: ca.Function,
                     block: ca.Function | None = None):
    """``(sparsity, jac, (blocks, by, zero, one))``: the step's iteration matrix (n_y x n_y,
    y = (q, v)) as a pattern and an MX Function ``jac(*rest_args) -> nonzeros`` in that
    pattern's order; and the same as its sources: ``blocks(*rest_args)``, the elements'
    blocks, the rest's nonzeros, a 0 and a 1 in one vector (at ``zero`` and ``one``), and
    the sum map ``by`` (:mod:`symcable.linalg.gather`) whose entry m lists the positions in
    it that nonzero m sums (for a factorisation that gathers them itself,
    :meth:`~symcable.linalg.banded.BandedLU.factor_sum`).

    ``rest_jac``: the Jacobian (SX, in ``rest_args``) of the step residual of the Mechanism
    with its mass removed and its force replaced by the form's rest (kinematic rows and
    the rest's force rows); ``point``: ``(*rest_args) -> (q, v, a, t, p, c_y, c_m)``, the
    alpha point of the step, its parameters and its two coefficients (module docstring);
    ``block``: the element block kernel the loop calls (default :func:`block_kernel`; its
    generated C, for instance). Built in two parts: :func:`jacobian_inputs` (the
    straight-line SX, the costly part) and :func:`jacobian_loop`."""
    return jacobian_loop(jacobian_inputs(mech, rest_jac, rest_args, point), block)


def jacobian_inputs(mech, rest_jac: ca.SX, rest_args: list, point: ca.Function) -> dict:
    """The SX part of :func:`element_jacobian`: the Function giving every element's inputs
    and the rest's nonzeros, and the indices of the matrix's pattern (a dict, for
    :func:`jacobian_loop`)."""
    form: ElementForm = mech.elements
    n_q, ny = mech.n_q, mech.n_q + mech.n_v
    dim, conn, idx = form.dim, form.connectivity, form.node_index
    n_el, k = conn.shape
    dk = dim * k
    # (row, column, position in vec(B)) of every element entry onto moving nodes
    node_rows = idx[conn]  # (n_el, k, dim)
    coord = node_rows.reshape(n_el, dk)  # entry of q of each element row / column
    rr = np.repeat(coord[:, :, None], 2 * dk, axis=2)  # (n_el, dk rows, 2 dk cols)
    cc = np.repeat(np.concatenate([coord, coord], axis=1)[:, None, :], dk, axis=1)
    ok = (rr >= 0) & (cc >= 0)
    rows = (n_q + rr)[ok]
    cols = np.where(np.arange(2 * dk)[None, None, :] < dk, cc, n_q + cc)[ok]
    e, i, j = np.nonzero(ok)
    pos = i + dk * (e * 2 * dk + j)  # column-major vec of B (dk, 2 dk n_el)
    r_sp = rest_jac.sparsity()
    r_rows, r_cols = r_sp.get_triplet()
    sp = ca.Sparsity.triplet(ny, ny, list(r_rows) + rows.tolist(),
                             list(r_cols) + cols.tolist())
    lookup = {rc: n for n, rc in enumerate(zip(*sp.get_triplet()))}
    nz_el = [lookup[rc] for rc in zip(rows.tolist(), cols.tolist())]
    nz_rest = [lookup[rc] for rc in zip(r_rows, r_cols)]
    # the step's inputs to every element's u and the rest's Jacobian (one SX call,
    # straight-line: copies and the per-node terms), the loop over elements, and the sum
    # of both onto the matrix's nonzeros
    q, v, a, t, p, cy, cm = point(*rest_args)
    U = gather(form, node_values(mech, form, q, v, a, t, p))
    s = ca.Function("element_shared", [mech.t, mech.p], [form.shared])(t, p)
    prepare = ca.Function(f"{mech.fname}_element_inputs", rest_args,
                          [U, s, cy, cm, rest_jac.nz[:], form.constants_at(mech, p)],
                          {"cse": True})
    return {"form": form, "name": mech.fname, "prepare": prepare, "sp": sp, "n_el": n_el,
            "nz_el": nz_el, "nz_rest": nz_rest, "pos": pos,
            "args": [a.sparsity() for a in rest_args]}


def jacobian_loop(inputs: dict, block: ca.Function | None = None):
    """:func:`element_jacobian`'s result from its :func:`jacobian_inputs`, the loop over
    the elements calling ``block`` (default :func:`block_kernel` of the form)."""
    block = block_kernel(inputs["form"]) if block is None else block
    sp, nz_el, nz_rest, name = inputs["sp"], inputs["nz_el"], inputs["nz_rest"], inputs["name"]
    margs = [ca.MX.sym(f"a{n}", a) for n, a in enumerate(inputs["args"])]
    U, s, cy, cm, jr, C = inputs["prepare"](*margs)
    B = block.map(inputs["n_el"], "serial")(U, C, s, cy, cm)
    by = sum_map(sp.nnz(), nz_el + nz_rest,
                 inputs["pos"].tolist() + [B.numel() + i for i in range(len(nz_rest))])
    # the sources end with a 0 and a 1, for the gathers' padding and the band's padding
    # rows, so that no gather copies them to append its own
    n_src = int(B.numel()) + len(nz_rest)
    blocks = ca.Function(f"{name}_element_blocks", margs,
                         [ca.vertcat(ca.vec(B), jr, ca.DM([0.0, 1.0]))])
    jac = ca.Function(f"{name}_element_jacobian", margs,
                      [gather_sum(blocks(*margs), by, n_src)])
    return sp, jac, (blocks, by, n_src, n_src + 1)


def element_residual(mech, rest_res: ca.SX, rest_args: list, point: ca.Function,
                     kernel: ca.Function | None = None) -> ca.Function:
    """An MX Function ``res(*rest_args) -> r`` (n_y,): the step residual, the elements'
    kernel evaluated by a loop over elements, scattered onto their nodes' momentum rows and
    added to ``rest_res`` (SX in ``rest_args``: the step residual of the Mechanism with its
    mass removed and its force replaced by the form's rest); ``point`` as for
    :func:`element_jacobian`; ``kernel`` the element kernel the loop calls (default the
    form's). In two parts, as :func:`element_jacobian`: :func:`residual_inputs` and
    :func:`residual_loop`."""
    return residual_loop(residual_inputs(mech, rest_res, rest_args, point), kernel)


def residual_inputs(mech, rest_res: ca.SX, rest_args: list, point: ca.Function) -> dict:
    """The SX part of :func:`element_residual` (a dict, for :func:`residual_loop`)."""
    form: ElementForm = mech.elements
    n_q, ny = mech.n_q, mech.n_q + mech.n_v
    dim, conn, idx = form.dim, form.connectivity, form.node_index
    n_el, k = conn.shape
    coord = idx[conn].reshape(n_el, dim * k)  # entry of q of each element row
    e, i = np.nonzero(coord >= 0)
    rows = (n_q + coord[e, i]).tolist()
    pos = (i + dim * k * e).tolist()  # column-major vec of R (dim k, n_el)
    q, v, a, t, p, _, _ = point(*rest_args)
    U = gather(form, node_values(mech, form, q, v, a, t, p))
    s = ca.Function("element_shared", [mech.t, mech.p], [form.shared])(t, p)
    prepare = ca.Function(f"{mech.fname}_element_res_inputs", rest_args,
                          [U, s, rest_res, form.constants_at(mech, p)], {"cse": True})
    return {"form": form, "name": mech.fname, "prepare": prepare, "n_el": n_el, "ny": ny,
            "rows": rows, "pos": pos, "args": [a_.sparsity() for a_ in rest_args]}


def residual_loop(inputs: dict, kernel: ca.Function | None = None) -> ca.Function:
    """:func:`element_residual`'s Function from its :func:`residual_inputs`, the loop over
    the elements calling ``kernel`` (default the form's)."""
    kernel = inputs["form"].kernel if kernel is None else kernel
    ny, rows, pos = inputs["ny"], inputs["rows"], inputs["pos"]
    margs = [ca.MX.sym(f"a{n}", a_) for n, a_ in enumerate(inputs["args"])]
    U, s, rr, C = inputs["prepare"](*margs)
    R = kernel.map(inputs["n_el"], "serial")(U, C, s)
    n_r = R.numel()
    r = summed(ca.vertcat(ca.vec(R), rr), ny, rows + list(range(ny)),
               pos + [n_r + j for j in range(ny)])
    return ca.Function(f"{inputs['name']}_element_residual", margs, [r])
