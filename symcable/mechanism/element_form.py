"""An optional second description of a Mechanism's momentum rows: element kernels mapped over
elements, plus a rest, so that a solver can evaluate the iteration matrix as a loop over
elements of each kernel's own small Jacobian instead of one straight-line expression.

Written out in SX, the Jacobian of a long line is straight-line code whose size grows with the
elements (for a line of a hundred or more elements, megabytes of C, which run more slowly per
instruction than a short line's: the code no longer fits the processor's caches). The same
entries from a loop over the element kernel's 6 x 12 block and a straight-line rest cost a
fraction of that. A
formulation that can say how its momentum residual splits gives the solvers that choice; the
Mechanism's own expressions stay the definition (every solver still checks convergence on
them).

With nodes of ``dim`` coordinates, ``a = v'``, the split is

    M(q) v' - f(q, v, z, t; p) = sum_e P_e^T kernel(u_e, c_e, s) - f_rest(q, v, z, t; p),

``u_e`` the positions, velocities and accelerations of element e's ``k`` nodes (x of every
node, then v of every node, then a of every node: 3 dim k entries), ``c_e`` the element's
constants (a column of ``constants``), ``s`` values shared by every element (an expression of
``(t, p)``); ``P_e`` picks the element's moving nodes' rows. A node held by a prescribed
motion takes its position, velocity and acceleration from ``held`` (expressions of ``(t,
p)``); its rows and columns are not unknowns.
"""
from __future__ import annotations

from dataclasses import dataclass

import casadi as ca
import numpy as np

from ..errors import SymcableError

__all__ = ["ElementForm", "split_mismatch"]


@dataclass(frozen=True, eq=False)
class ElementForm:
    """The momentum rows as element kernels plus a rest (module docstring).

    Attributes
    ----------
    kernel : casadi.Function
        ``(u (3 dim k,), c (n_c,), s (n_s,)) -> r (dim k,)``: the element's share of
        M v' - f at its nodes' rows (N), in node order.
    connectivity : int array (n_el, k)
        The nodes of each element.
    constants : array (n_c, n_el)
        Each element's constants.
    shared : expression (n_s, 1) of ``(t, p)``
    node_index : int array (n_nodes, dim)
        Each node's entries in q (and the same entries of v), -1 for a held node.
    held : expression (3 dim, n_nodes) of ``(t, p)``
        Position, velocity and acceleration of every node, read at held nodes only (the
        others may hold anything: zeros).
    force_rest : expression (n_v, 1) of ``(q, v, z, t, p)``
        The force the elements do not give (contact, bending, point loads), N.
    parametric : expression (n_c, n_el) of ``p`` or None
        The constants as the parameters give them (``constants`` are its values at the
        Mechanism's parameters): what solvers build into Functions, so that scenes of one
        structure with other numbers share them (:mod:`symcable.models.structure`); None:
        ``constants`` are numbers of this Mechanism alone.
    """

    kernel: ca.Function
    connectivity: np.ndarray
    constants: np.ndarray
    shared: object
    node_index: np.ndarray
    held: object
    force_rest: object
    parametric: object = None

    def __post_init__(self):
        conn = np.asarray(self.connectivity, dtype=int)
        idx = np.asarray(self.node_index, dtype=int)
        c = np.atleast_2d(np.asarray(self.constants, dtype=float))
        object.__setattr__(self, "connectivity", conn)
        object.__setattr__(self, "node_index", idx)
        object.__setattr__(self, "constants", c)
        n_el, k = conn.shape
        dim = idx.shape[1]
        shapes = [("u", self.kernel.size1_in(0), 3 * dim * k),
                  ("c", self.kernel.size1_in(1), c.shape[0]),
                  ("s", self.kernel.size1_in(2), int(self.shared.numel())),
                  ("r", self.kernel.size1_out(0), dim * k)]
        bad = [f"{n} has {got} entries, expected {want}" for n, got, want in shapes if got != want]
        if bad or c.shape[1] != n_el or conn.min() < 0 or conn.max() >= idx.shape[0] \
                or tuple(self.held.shape) != (3 * dim, idx.shape[0]):
            raise SymcableError("ElementForm: kernel, connectivity, constants and held do not "
                                f"agree ({'; '.join(bad) or 'sizes of the arrays'})")

    @property
    def dim(self) -> int:
        return int(self.node_index.shape[1])

    def constants_at(self, mech, p):
        """The constants (n_c, n_el) at parameters ``p`` of ``mech`` (a symbol or values):
        the parametric expression where there is one, else the numbers."""
        if self.parametric is None:
            return ca.DM(self.constants)
        return ca.Function("element_constants", [mech.p], [ca.densify(self.parametric)])(p)


def split_mismatch(mech, form: ElementForm, points: int = 2, seed: int = 0) -> float:
    """The largest difference (relative to the force scale) between the Mechanism's own
    momentum residual M v' - f and the split's, at ``points`` random states about its first
    start (positions moved by 1 % of their scale, velocities and accelerations of the order
    of their scales): 0 up to round-off when the split is the Mechanism's."""
    n_v = mech.n_v
    S = ca.SX if isinstance(mech.q, ca.SX) else ca.MX
    a = S.sym("a", n_v)
    full = ca.Function("full", [mech.q, mech.v, a, mech.t, mech.p],
                       [ca.mtimes(mech.mass, a) - mech.force]) if mech.n_z == 0 else None
    if full is None:
        return np.inf
    split = ca.Function("split", [mech.q, mech.v, a, mech.t, mech.p],
                        [split_residual(mech, form, mech.q, mech.v, a, mech.t, mech.p)])
    rng = np.random.default_rng(seed)
    try:
        q0 = next(iter(mech.starts())).q
    except StopIteration:
        q0 = np.zeros(mech.n_q)
    sq, sv = np.asarray(mech.scales.q), np.asarray(mech.scales.v)
    worst = 0.0
    for _ in range(points):
        q = q0 + 0.01 * sq * rng.standard_normal(mech.n_q)
        v = sv * rng.standard_normal(n_v) * 0.1
        acc = sv * rng.standard_normal(n_v) * 0.1
        t = float(rng.uniform(0.0, 10.0))
        args = (q, v, acc, t, mech.params.values)
        d = np.asarray(full(*args) - split(*args), float)
        if not np.all(np.isfinite(d)):
            return np.inf
        worst = max(worst, float(np.max(np.abs(d), initial=0.0)) / float(mech.scales.force))
    return worst


def split_residual(mech, form: ElementForm, q, v, a, t, p):
    """The split's M v' - f at ``(q, v, a, t, p)`` (symbols or values): the elements' kernel
    evaluated element by element (a loop, ``map``), scattered onto the rows, less the rest."""
    X = node_values(mech, form, q, v, a, t, p)
    U = gather(form, X)
    s = ca.Function("shared", [mech.t, mech.p], [form.shared])(t, p)
    R = form.kernel.map(form.connectivity.shape[0], "serial")(U, form.constants_at(mech, p), s)
    rest = ca.Function("rest", list(mech.symbols), [form.force_rest])(
        q, v, ca.DM.zeros(mech.n_z), t, p)
    return ca.mtimes(ca.DM(scatter_matrix(form, mech.n_v)), ca.vec(R)) - rest


def node_values(mech, form: ElementForm, q, v, a, t, p):
    """(3 dim, n_nodes): every node's position, velocity and acceleration, from (q, v, a) at
    moving nodes and from ``held`` at held ones."""
    dim, idx = form.dim, form.node_index
    n_nodes = idx.shape[0]
    moving = np.flatnonzero(idx[:, 0] >= 0)
    still = ca.DM((idx[:, 0] < 0).astype(float)).T
    held = ca.Function("held", [mech.t, mech.p], [form.held])(t, p)
    out = []
    for blk, vec in enumerate((q, v, a)):
        n = int(vec.numel())
        for c in range(dim):
            sel = ca.DM(ca.Sparsity.triplet(n_nodes, n, moving.tolist(), idx[moving, c].tolist()),
                        np.ones(moving.size))
            out.append(ca.mtimes(sel, vec).T + still * held[blk * dim + c, :])
    return ca.vertcat(*out)


def gather(form: ElementForm, X):
    """(3 dim k, n_el): each element's u from the node values X (3 dim, n_nodes)."""
    dim = form.dim
    conn = form.connectivity
    k = conn.shape[1]
    rows = []
    for blk in range(3):
        for j in range(k):
            rows.append(X[blk * dim:(blk + 1) * dim, conn[:, j].tolist()])
    return ca.vertcat(*rows)


def scatter_matrix(form: ElementForm, n_v: int) -> ca.DM:
    """The sparse (n_v, dim k n_el) 0/1 matrix that adds each element's r onto the momentum
    rows of its moving nodes."""
    dim, conn, idx = form.dim, form.connectivity, form.node_index
    n_el, k = conn.shape
    rows, cols = [], []
    for e in range(n_el):
        for j in range(k):
            for c in range(dim):
                r = idx[conn[e, j], c]
                if r >= 0:
                    rows.append(int(r))
                    cols.append(e * dim * k + j * dim + c)
    sp = ca.Sparsity.triplet(n_v, dim * k * n_el, rows, cols)
    return ca.DM(sp, np.ones(len(rows)))
