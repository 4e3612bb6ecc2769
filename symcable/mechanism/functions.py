"""Functions derived once from any :class:`~symcable.mechanism.mechanism.Mechanism`.

Every generic solver reads a Mechanism through these CasADi Functions only:

- the static residual ``R(x; p)`` with ``x = (q, z)``: the force balance ``f(q, 0, z, t0)``
  (N) and the constraints ``g`` converted to forces by ``scales.force / q_ref``;
- the acceleration residual ``A(q, v, a, z, t; p) = [M(q) a - f(q, v, z, t); g]``, from which
  the time integrators build their steps;
- the DAE residual ``F(y', y, t; p)`` with ``y = (q, v, z)``;
- the tangent matrices ``K = -df/dq``, ``C = -df/dv``, ``M``, ``B = dg/dq``, ``-df/dz``;
- the named outputs, flattened into one vector (see :meth:`MechanismFunctions.unpack`);
- the fused static Newton solve, in the virtual machine or generated C
  (:meth:`MechanismFunctions.static_solver`, built by :mod:`symcable.mechanism.static_functions`).

Functions are built lazily, once per Mechanism, and kept by :data:`FUNCTIONS`, an explicit
cache object (a weak mapping: a Mechanism that is no longer used frees its Functions).
"""
from __future__ import annotations

import weakref
from functools import cached_property

import casadi as ca
import numpy as np

from .attached import Attached
from .static_functions import StaticSolver, static_solver
from ..linalg.sparse import qr_solve, sparse_solve
from .bounds import bound_margins, bound_numbers
from .mechanism import Mechanism

__all__ = ["FUNCTIONS", "FunctionCache", "MechanismFunctions", "bound_margins", "bound_numbers",
           "bound_violations", "functions"]


def _sym_like(x, name: str, n: int):
    """A new symbol of the same kind (SX or MX) as ``x``."""
    return (ca.MX if isinstance(x, ca.MX) else ca.SX).sym(name, n)


class MechanismFunctions:
    """The Functions of one Mechanism (see the module docstring); every attribute is built
    on first use and kept."""

    def __init__(self, mech: Mechanism):
        # weakly: FUNCTIONS maps the Mechanism to this object, and a strong reference back
        # would keep every Mechanism ever derived alive (a fuzz of 1000 scenes, 1000 graphs)
        self._mech = weakref.ref(mech)
        self.q_ref = float(np.median(mech.scales.q)) if mech.n_q else 1.0
        self.g_weight = mech.scales.force / self.q_ref
        m = mech
        self._args = [m.q, m.v, m.z, m.t, m.p]
        self._names = ["q", "v", "z", "t", "p"]
        # dense: packed outputs read by FastCall (nonzeros only) must keep every entry
        out_exprs = [ca.densify(ca.vec(o.expr)) for o in m.outputs.values()]
        self._out_shapes = {k: tuple(o.expr.shape) for k, o in m.outputs.items()}
        self._out_sizes = [int(e.numel()) for e in out_exprs]
        self._out_exprs = out_exprs

    @property
    def mech(self) -> Mechanism:
        """The Mechanism these Functions are of (alive while anyone uses it)."""
        m = self._mech()
        if m is None:
            raise ReferenceError("the Mechanism of these Functions no longer exists")
        return m

    @cached_property
    def massless(self) -> bool:
        """True when the mass matrix is structurally zero (a purely static formulation, whose
        residual rows need not be the gradient of an energy)."""
        return self.mech.mass.nnz() == 0

    # -- expressions ---------------------------------------------------------------------
    def _qdot(self):
        m = self.mech
        return m.v if m.kinematics is None else m.kinematics

    # -- static ---------------------------------------------------------------------------
    def static_expr(self):
        """The static residual as an expression of (q, z, p): (f, w_g g) at v = 0, t = 0,
        and the mechanism's ``rest`` rows when it has first-order states, N."""
        m = self.mech
        rows = [m.force, self.g_weight * m.constraint] + ([] if m.rest is None else [m.rest])
        return ca.substitute([ca.vertcat(*rows)], [m.v, m.t],
                             [ca.DM.zeros(m.n_v), ca.DM(0.0)])[0]

    @cached_property
    def static_residual(self) -> ca.Function:
        """``static_residual(x, p) -> r``: x = (q, z); r = (f(q, 0, z, 0; p), w_g g[, rest]),
        N (:meth:`static_expr`)."""
        m = self.mech
        x = ca.vertcat(m.q, m.z)
        r = self.static_expr()
        return ca.Function(f"{m.fname}_static_residual", [x, m.p], [r], ["x", "p"], ["r"])

    @cached_property
    def static_parameter_jacobian(self) -> ca.Function:
        """``static_parameter_jacobian(x, p) -> R_p``, dr/dp of the static residual, sparse."""
        m = self.mech
        x = ca.vertcat(m.q, m.z)
        return ca.Function(f"{m.fname}_static_dp", [x, m.p],
                           [ca.jacobian(self.static_expr(), m.p)], ["x", "p"], ["R_p"])

    @cached_property
    def static_parameter_slope(self) -> ca.Function:
        """``static_parameter_slope(x, p, dp) -> dR``: (dr/dp) dp, the static residual's
        directional derivative along parameter change ``dp`` (one forward sweep: the whole
        dr/dp of a long line's per-segment parameters is large)."""
        m = self.mech
        x = ca.vertcat(m.q, m.z)
        dp = _sym_like(m.p, "dp", m.params.n)
        return ca.Function(f"{m.fname}_static_dp_slope", [x, m.p, dp],
                           [ca.jtimes(self.static_expr(), m.p, dp)], ["x", "p", "dp"], ["dR"])

    @cached_property
    def static_jacobian(self) -> ca.Function:
        """``static_jacobian(x, p) -> (r, J)``, J = dr/dx sparse."""
        m = self.mech
        x = _sym_like(m.q, "x", m.n_q + m.n_z)
        p = _sym_like(m.p, "p", m.params.n)
        r = self.static_residual(x, p)
        return ca.Function(f"{m.fname}_static_jacobian", [x, p], [r, ca.jacobian(r, x)],
                           ["x", "p"], ["r", "J"])

    @cached_property
    def static_step(self) -> ca.Function:
        """``static_step(x, p) -> (r, dx)``, the full Newton step dx = -J^-1 r (sparse QR,
        dense rows split off: :func:`symcable.linalg.sparse.sparse_solve`)."""
        m = self.mech
        x = ca.MX.sym("x", m.n_q + m.n_z)
        p = ca.MX.sym("p", m.params.n)
        r, J = self.static_jacobian(x, p)
        dx = -sparse_solve(J, r, "qr")
        return ca.Function(f"{m.fname}_static_step", [x, p], [r, dx], ["x", "p"], ["r", "dx"])

    def static_solver(self, codegen: bool | None = False) -> StaticSolver:
        """The fused static Newton solve and its companions (residual, sparse-QR step,
        outputs at rest), as a :class:`~symcable.mechanism.static_functions.StaticSolver`: the virtual
        machine's, or generated C when ``codegen`` resolves to True
        (:func:`symcable.mechanism.static_functions.static_solver`); each built once."""
        return static_solver(self, codegen)

    @cached_property
    def static_ptc_step(self) -> ca.Function:
        """``static_ptc_step(x, p, c) -> (r, dx)``: a pseudo-transient step,
        dx = (diag(c) - J)^-1 r (sparse QR): c -> 0 gives Newton's step, large c a short
        step along the residual (a damped relaxation of the static problem)."""
        m = self.mech
        n = m.n_q + m.n_z
        x, p, c = ca.MX.sym("x", n), ca.MX.sym("p", m.params.n), ca.MX.sym("c", n)
        r, J = self.static_jacobian(x, p)
        dx = qr_solve(ca.diag(c) - J, r)
        return ca.Function(f"{m.fname}_static_ptc_step", [x, p, c], [r, dx], ["x", "p", "c"],
                           ["r", "dx"])

    # -- dynamics -------------------------------------------------------------------------
    @cached_property
    def acc_residual(self) -> ca.Function:
        """``acc_residual(q, v, a, z, t, p) -> (r_f, r_g)``: r_f = M(q) a - f (N), r_g = g."""
        m = self.mech
        a = _sym_like(m.v, "a", m.n_v)
        r_f = ca.mtimes(m.mass, a) - m.force
        return ca.Function(f"{m.fname}_acc_residual", [m.q, m.v, a, m.z, m.t, m.p],
                           [r_f, m.constraint], ["q", "v", "a", "z", "t", "p"], ["r_f", "r_g"])

    @cached_property
    def qdot(self) -> ca.Function:
        """``qdot(q, v, z, t, p) -> q'`` = G(q) v (the kinematics may depend on every
        argument: prescribed terms in t and p)."""
        m = self.mech
        return ca.Function(f"{m.fname}_qdot", self._args, [self._qdot()], self._names, ["qdot"])

    @cached_property
    def dae_residual(self) -> ca.Function:
        """``dae_residual(yd, y, t, p) -> F`` with y = (q, v, z):
        F = (q' - G(q) v [- w(q, z, t; p)], M(q) v' - f, g); the kinematics row is the
        mechanism's ``kinematics`` expression as it is (t- and p-dependent terms included)."""
        m = self.mech
        qd = _sym_like(m.q, "qd", m.n_q)
        vd = _sym_like(m.v, "vd", m.n_v)
        zd = _sym_like(m.z, "zd", m.n_z)
        F = ca.vertcat(qd - self._qdot(), ca.mtimes(m.mass, vd) - m.force, m.constraint)
        y = ca.vertcat(m.q, m.v, m.z)
        return ca.Function(f"{m.fname}_dae_residual", [ca.vertcat(qd, vd, zd), y, m.t, m.p], [F],
                           ["yd", "y", "t", "p"], ["F"])

    @cached_property
    def consistent_acceleration(self) -> ca.Function:
        """``consistent_acceleration(q, v, z0, t, p) -> (a, z)``: the accelerations and
        constraint forces consistent with the state: M a = f(q, v, z), and each constraint
        row differentiated in time until it involves a or z (position-level rows twice,
        velocity-level rows once, rows in z not at all). Solved by Newton (exact for the
        usual f affine in z)."""
        m = self.mech
        a = _sym_like(m.v, "a", m.n_v)
        rows = []
        qdot = self._qdot()
        for i in range(m.n_z):
            gi = m.constraint[i]
            for _ in range(3):
                if ca.depends_on(gi, ca.vertcat(m.z, a)):
                    break
                # d/dt along the motion: q' = the kinematics (with its explicit t and p
                # terms), v' = a (z is held: rows that need z' are index 1 already and left
                # the loop; kinematics that depend on z are taken at the held z)
                gi = (ca.jtimes(gi, m.q, qdot) + ca.jtimes(gi, m.v, a)
                      + ca.jacobian(gi, m.t))
            rows.append(gi)
        r = ca.vertcat(ca.mtimes(m.mass, a) - m.force, *rows)
        w = _sym_like(m.v, "w", m.n_v + m.n_z)
        r = ca.substitute([r], [ca.vertcat(a, m.z)], [w])[0]
        G = ca.Function("acc_res", [w, m.q, m.v, m.t, m.p], [r])
        rf = ca.rootfinder(f"{m.fname}_consistent", "newton", G,
                           {"abstol": 1e-12, "max_iter": 20, "error_on_fail": False,
                            "show_eval_warnings": False})
        q, v, z0 = ca.MX.sym("q", m.n_q), ca.MX.sym("v", m.n_v), ca.MX.sym("z0", m.n_z)
        t, p = ca.MX.sym("t"), ca.MX.sym("p", m.params.n)
        w_sol = rf(ca.vertcat(ca.MX.zeros(m.n_v), z0), q, v, t, p)
        return ca.Function(f"{m.fname}_consistent_acceleration", [q, v, z0, t, p],
                           [w_sol[:m.n_v], w_sol[m.n_v:]], ["q", "v", "z0", "t", "p"], ["a", "z"])

    # -- tangents -------------------------------------------------------------------------
    @cached_property
    def tangents(self) -> ca.Function:
        """``tangents(q, v, z, t, p) -> (K, C, M, B, Kz, Gv, Gz)``: K = -df/dq, C = -df/dv,
        M, B = dg/dq, Kz = -df/dz, Gv = dg/dv, Gz = dg/dz (all sparse)."""
        m = self.mech
        f, g = m.force, m.constraint
        outs = [-ca.jacobian(f, m.q), -ca.jacobian(f, m.v), m.mass, ca.jacobian(g, m.q),
                -ca.jacobian(f, m.z), ca.jacobian(g, m.v), ca.jacobian(g, m.z)]
        return ca.Function(f"{m.fname}_tangents", self._args, outs, self._names,
                           ["K", "C", "M", "B", "Kz", "Gv", "Gz"])

    @cached_property
    def kinematics_jacobian(self) -> ca.Function:
        """``(q, v, z, t, p) -> (H, G)``: H = d(q')/dq, G = d(q')/dv of the kinematics
        q' = G(q) v + w (identity G and zero H without kinematics), sparse."""
        m = self.mech
        qd = self._qdot()
        return ca.Function(f"{m.fname}_kinematics_jacobian", self._args,
                           [ca.jacobian(qd, m.q), ca.jacobian(qd, m.v)], self._names, ["H", "G"])

    @cached_property
    def force_parameter_jacobian(self) -> ca.Function:
        """``(q, v, z, t, p) -> (df/dp, dg/dp)``, sparse."""
        m = self.mech
        return ca.Function(f"{m.fname}_force_dp", self._args,
                           [ca.jacobian(m.force, m.p), ca.jacobian(m.constraint, m.p)],
                           self._names, ["f_p", "g_p"])

    @cached_property
    def stability_when(self) -> ca.Function:
        """``(q, z, p) -> s`` (v = 0, t = 0): the mechanism's ``stability_when``; stability
        is judged where s < 0."""
        m = self.mech
        e = ca.substitute([m.stability_when], [m.v, m.t], [ca.DM.zeros(m.n_v), ca.DM(0.0)])[0]
        return ca.Function(f"{m.fname}_stability_when", [m.q, m.z, m.p], [e], ["q", "z", "p"],
                           ["s"])

    # -- admissibility bounds -------------------------------------------------------------
    @cached_property
    def bound_values(self) -> ca.Function:
        """``(q, v, z, t, p) -> values``: every :class:`Bound`'s expression, stacked in the
        order of ``mech.bounds`` (their limits are numbers of the scene, not of the
        expressions: :func:`bound_numbers`)."""
        m = self.mech
        values = [ca.vec(b.expr) for b in m.bounds.values()]
        v = ca.vertcat(*values) if values else ca.DM.zeros(0)
        return ca.Function(f"{m.fname}_bound_values", self._args, [v], self._names,
                           ["values"])

    # -- outputs --------------------------------------------------------------------------
    @cached_property
    def outputs(self) -> ca.Function:
        """``outputs(q, v, z, t, p) -> y``: every named output, flattened (column-major) and
        stacked in the order of ``mech.outputs``; :meth:`unpack` splits it."""
        m = self.mech
        y = ca.vertcat(*self._out_exprs) if self._out_exprs else ca.DM.zeros(0)
        return ca.Function(f"{m.fname}_outputs", self._args, [y], self._names, ["y"])

    @cached_property
    def output_parameter_jacobian(self) -> ca.Function:
        """``(q, v, z, t, p) -> (dy/dq, dy/dz, dy/dp)`` of the stacked outputs."""
        m = self.mech
        y = ca.vertcat(*self._out_exprs) if self._out_exprs else ca.DM.zeros(0)
        return ca.Function(f"{m.fname}_outputs_dp", self._args,
                           [ca.jacobian(y, m.q), ca.jacobian(y, m.z), ca.jacobian(y, m.p)],
                           self._names, ["y_q", "y_z", "y_p"])

    def output_slices(self) -> dict:
        """name -> slice of the stacked output vector."""
        out, i = {}, 0
        for name, n in zip(self.mech.outputs, self._out_sizes):
            out[name] = slice(i, i + n)
            i += n
        return out

    @cached_property
    def _unpack_plan(self) -> list:
        """(name, start, stop, rows, cols) of each output in the stacked vector."""
        return [(name, sl.start, sl.stop, *self._out_shapes[name])
                for name, sl in self.output_slices().items()]

    def unpack(self, y) -> dict:
        """Split a stacked output vector (n_y,) into named arrays of the outputs' shapes; an
        (n_y, k) batch (columns = samples) gives arrays with a leading sample axis. Column
        vector outputs come back 1-D (per sample)."""
        y = np.asarray(y, dtype=float)
        if y.ndim == 1:  # one sample: views of y, column-major blocks
            return {name: y[a:b].reshape(cols, rows).T if cols != 1 else
                    (y[a] if rows == 1 else y[a:b])
                    for name, a, b, rows, cols in self._unpack_plan}
        batch = y.ndim == 2
        if not batch:
            y = y.reshape(-1, 1)
        k = y.shape[1]
        res = {}
        for name, sl in self.output_slices().items():
            rows, cols = self._out_shapes[name]
            block = y[sl, :].T.reshape(k, cols, rows).transpose(0, 2, 1)
            if cols == 1:
                block = block[:, :, 0]
                if rows == 1:
                    block = block[:, 0]
            res[name] = block if batch else block[0]
        return res

    def evaluate_outputs(self, q, v, z, t, p) -> dict:
        """Named outputs at one state, as NumPy arrays."""
        y = self.outputs(q, v, z, t, p)
        return self.unpack(np.asarray(y).ravel())


def bound_violations(mech: Mechanism, q, v, z, t, p, slack: float = 0.0) -> list:
    """One line per violated :class:`Bound` of ``mech`` at the state (its worst entry, value,
    allowed range and meaning); ``slack`` (in scales) tolerated below a bound."""
    values = np.asarray(functions(mech).bound_values(q, v, z, t, p), float).ravel()
    margins = bound_margins(bound_numbers(mech), values)
    out, i = [], 0
    for name, b in mech.bounds.items():
        k = int(b.expr.numel())
        mk = margins[i:i + k]
        i += k
        if not k or np.all(mk >= -slack):
            continue
        worst = int(np.argmin(np.where(np.isnan(mk), -np.inf, mk)))
        val = values[i - k + worst]
        lo = np.broadcast_to(np.asarray(b.lower, float), (k,))[worst]
        hi = np.broadcast_to(np.asarray(b.upper, float), (k,))[worst]
        rng = (f">= {lo:.4g}" if np.isinf(hi) else f"<= {hi:.4g}" if np.isinf(lo)
               else f"in [{lo:.4g}, {hi:.4g}]")
        n_bad = int(np.sum(~(mk >= -slack)))
        unit = "" if b.unit in ("", "1", "-") else f" {b.unit}"  # (a ratio has none)
        out.append(f"{name} = {val:.4g}{unit} at entry {worst} (must be {rng}: "
                   f"{b.what}; {n_bad} of {k} entries violate it)")
    return out


class FunctionCache:
    """Functions per Mechanism, built once and kept on the Mechanism
    (:class:`~symcable.mechanism.attached.Attached`), so they go with it."""

    def __init__(self):
        self._store = Attached("functions")

    def get(self, mech: Mechanism) -> MechanismFunctions:
        """The Functions of ``mech``: those of the Mechanism whose expressions it shares
        (``mech.functions_of``), else its own."""
        owner = mech.functions_of or mech
        return self._store.setdefault(owner, lambda: MechanismFunctions(owner))

    def __len__(self) -> int:
        return len(self._store)

    def clear(self) -> None:
        self._store.clear()


#: the package's cache of derived Functions
FUNCTIONS = FunctionCache()


def functions(mech: Mechanism) -> MechanismFunctions:
    """The derived Functions of ``mech`` (built on first use, then reused)."""
    return FUNCTIONS.get(mech)
