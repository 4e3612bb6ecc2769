"""Direct collocation of one period of any Mechanism, as a square system solved by IPOPT or
by Newton.

Method
------
The implicit DAE of the mechanism, ``F(y', y, t) = (q' - G(q) v, M(q) v' - f(q, v, z, t),
g(q, v, z, t)) = 0`` with y = (q, v, z) (the derived ``dae_residual``), is collocated on K
equal intervals of the period T. On each interval the state x = (q, v) is the polynomial of
degree d through its values at the interval start and at the d collocation points (Radau IIA
or Gauss-Legendre, ``ca.collocation_points``); z is a value per collocation point (it is
algebraic: no polynomial, no continuity). The equations are the DAE at every collocation
point (the whole period in ONE mapped call of ``dae_residual``), continuity of each
interval's end value with the next interval's start, and, closing the loop, periodicity of
(q, v): the last interval's end is the first interval's start. Unknowns and equations both
number K ((d + 1)(n_q + n_v) + d n_z): the system is square, and it is solved by IPOPT
(zero objective, a zero Lagrangian Hessian, so IPOPT takes Newton steps on the constraints
with its filter line search) or by CasADi's Newton rootfinder (sparse LU, the system
reordered for it: "Order of the unknowns and rows"), ``Collocation.solver``.

Position constraints (index 3) are imposed at the collocation points. For Radau the last
point is the interval end, so g = 0 holds at every mesh point as well, and Radau IIA being
stiffly accurate (R(inf) = 0) the multipliers z converge; Radau is the default for that
reason. For Gauss-Legendre g = 0 holds at the d interior points only; adding it at the mesh
points would make the system overdetermined (there is no further unknown to meet it), so it
is not imposed there, and the constraint's drift at the mesh points is of the order of the
discretisation error (the check reports it). Legendre has R(inf) = +-1, so on index-3
problems its multipliers are not damped: use Radau for constrained mechanisms.

Scaling
-------
Unknowns are divided by ``scales.q``, ``scales.v``, ``scales.z``; the rows ``q' - G v`` by
the median velocity scale, ``M v' - f`` by ``scales.force``, ``g`` by ``scales.g_scale()``,
and the continuity rows are differences of scaled states. The period is a parameter of the one
residual Function (built once per mechanism, K, d and scheme).

Order of the unknowns and rows
------------------------------
As written, time-point-major: the unknowns are the scaled (q, v) of every node (node after
node: an interval's start, then its d collocation points), then z of every collocation
point; the rows are the DAE at every collocation point (n_q + n_v + n_z each, point after
point), then the K continuity rows. IPOPT takes the system as written: MUMPS orders it
itself (PORD), and the order below does not make it faster.

Newton factorises the Jacobian with CasADi's sparse LU (``csparse``), which keeps the order
of the unknowns it is given and takes the diagonal pivot unless it is below 1e-8 of its
column. As written, nearly all the diagonal entries are structural zeros, the pivots are
found far away, and L + U fills in to tens of millions of entries on a line of some fifty
segments at the defaults: tens of seconds per factorisation. :meth:`CollocationSystem.lu_order`
therefore hands the Newton solvers (:class:`~symcable.solvers.periodic_common.SquareSystem`
permutes them) the system in an order of its own:

- pairs of a row and an unknown with a non-zero diagonal: the start of interval k pivots on
  the continuity row that ends interval k - 1 (coefficient 1), the (q, v, z) of a
  collocation point on that point's own DAE rows;
- the pairs ordered by nested dissection in time: the ring of K intervals is cut at the
  starts of intervals 0 and K/2, each half halved again, the cut starts (the separators)
  after the pieces they separate, down to chains of at most 10 intervals (``_LEAF``), each
  in CasADi's approximate-minimum-degree order (AMD) of the symmetrised pattern.

With it L + U is about a tenth as large, the factorisation's cost is linear in K, and a
whole ``solve_periodic`` is an order of magnitude faster than as written, on a par with
IPOPT. The orders tried beside it on the same Jacobian factorise more slowly: AMD of the
whole ring (minimum degree orders a long ring badly: its fill grows much faster than K), a
band (intervals folded 0, K-1, 1, K-2, ..., state by state inside each in the mechanism's
AMD order, as harmonic balance orders its coefficients), shorter or longer chains, MUMPS as
CasADi's ``linear_solver`` on the system as written (which also prints a banner on stdout
when the process ends) and CasADi's ``qr``. The order costs a fraction of a second once per
system, and the answer is that of the system as written to rounding (the same iterations).

Start
-----
The same as every periodic method (:mod:`symcable.solvers.hbalance_mech` says why): the
last of 6 periods of generalized-alpha from the static equilibrium, or a given periodic
solution, sampled at every node.

Checks
------
The collocation polynomials and their derivatives are sampled at 4 points per collocation
point, uniformly, and checked by :func:`~symcable.solvers.periodic_common.check_and_wrap`
(between the collocation points the DAE residual of the polynomials is the discretisation
error); the stats also report
the constraint at the collocation points (``constraint_at_nodes``, met to the solver's
tolerance) and the periodicity defect (the wrap-around continuity rows).
"""
from __future__ import annotations

import time

import casadi as ca
import numpy as np

from ..mechanism.mechanism import Mechanism
from .options import Collocation
from .periodic_common import (PERIODIC_CACHE, Scaling, SquareSystem, StartFn, check_and_wrap,
                              point_function)

__all__ = ["CollocationSystem", "solve_collocation"]

#: the longest chain of intervals the Newton order leaves to one AMD (module docstring):
#: of 5, 10 and 20, the fastest to factorise over K = 20 to 80, and the least fill over
#: degrees d = 2 to 4 and line lengths
_LEAF = 10


def _lagrange(tau: np.ndarray):
    """Basis of the Lagrange polynomials through ``tau`` (d+1,): (polys, C, D) with
    C[j, r] = l_j'(tau_r), D[j] = l_j(1)."""
    n = tau.size
    polys = []
    C = np.zeros((n, n))
    D = np.zeros(n)
    for j in range(n):
        L = np.poly1d([1.0])
        for r in range(n):
            if r != j:
                L *= np.poly1d([1.0, -tau[r]]) / (tau[j] - tau[r])
        polys.append(L)
        D[j] = L(1.0)
        dL = np.polyder(L)
        C[j] = [dL(tr) for tr in tau]
    return polys, C, D


class CollocationSystem:
    """The collocation system of one mechanism for (K, d, scheme): residual
    ``<name>_colloc_residual(w, P) -> r`` with P = (T, p), the grid and the packing."""

    def __init__(self, mech: Mechanism, K: int, d: int, scheme: str, compiled: bool = False):
        self.mech, self.K, self.d, self.scheme = mech, K, d, scheme
        sc = self.sc = Scaling.of(mech)
        nq, nv, nz = mech.n_q, mech.n_v, mech.n_z
        nx = self.nx = nq + nv
        self.tau = np.array([0.0] + list(ca.collocation_points(d, scheme)))
        self.polys, C, D = _lagrange(self.tau)
        self.x_scale = np.concatenate([sc.q, sc.v])
        n_nodes, n_pts = K * (d + 1), K * d
        self.n_w = nx * n_nodes + nz * n_pts
        # node times (tau units of the period) and collocation times
        self.t_nodes = (np.repeat(np.arange(K), d + 1) + np.tile(self.tau, K)) / K
        self.t_pts = (np.repeat(np.arange(K), d) + np.tile(self.tau[1:], K)) / K
        eye = np.eye(K)
        Cbig = ca.DM(ca.sparsify(ca.DM(np.kron(eye, C[:, 1:]))))         # (n_nodes, n_pts)
        Sel = np.zeros((d + 1, d))
        Sel[1:, :] = np.eye(d)
        Sbig = ca.DM(ca.sparsify(ca.DM(np.kron(eye, Sel))))
        Dbig = ca.DM(ca.sparsify(ca.DM(np.kron(eye, D[:, None]))))        # (n_nodes, K)
        first = np.zeros((d + 1, 1))
        first[0] = 1.0
        shift = np.roll(np.eye(K), -1, axis=1)  # start of interval k+1 (mod K) against end k
        Start_next = ca.DM(ca.sparsify(ca.DM(np.kron(eye, first) @ shift)))

        w = ca.MX.sym("w", self.n_w)
        P = ca.MX.sym("P", 1 + mech.params.n)
        T, p = P[0], P[1:]
        Xs = ca.reshape(w[:nx * n_nodes], nx, n_nodes)     # scaled
        Zs = ca.reshape(w[nx * n_nodes:], nz, n_pts) if nz else ca.MX(0, n_pts)
        X = ca.diag(ca.DM(self.x_scale)) @ Xs
        Z = ca.diag(ca.DM(sc.z)) @ Zs if nz else Zs
        h = T / K
        Xdot = (X @ Cbig) / h
        Xc = X @ Sbig
        yd = ca.vertcat(Xdot, ca.MX(nz, n_pts))
        y = ca.vertcat(Xc, Z)
        t = T * ca.DM(self.t_pts).T
        R = point_function(mech, "dae_residual", compiled).map(n_pts)(yd, y, t, p)
        row_scale = np.concatenate([np.full(nq, 1.0 / sc.v_ref), np.full(nv, 1.0 / sc.force),
                                    1.0 / sc.g])
        R = ca.diag(ca.DM(row_scale)) @ R
        cont = Xs @ Start_next - Xs @ Dbig                  # (nx, K), scaled
        r = ca.vertcat(ca.vec(R), ca.vec(cont))
        self.square = SquareSystem(
            f"{mech.fname}_colloc", ca.Function(f"{mech.fname}_colloc_residual", [w, P], [r],
                                               ["w", "P"], ["r"]), compiled, order=self.lu_order)
        self.n_colloc_rows = (nx + nz) * n_pts
        # where the rows of g sit in r: rows nx .. nx+nz of each column of R
        self.g_rows = (np.arange(n_pts)[:, None] * (nx + nz) + nx + np.arange(nz)[None, :]).ravel()

    def lu_order(self) -> tuple:
        """(rows, unknowns), permutations of range(n): the Newton solvers factorise the
        Jacobian with row ``rows[i]`` pivoting on unknown ``unknowns[i]``, in that order
        (module docstring, "Order of the unknowns and rows"). From the Jacobian's sparsity,
        once per system, when Newton is first used."""
        K, d, nx, nz = self.K, self.d, self.nx, self.mech.n_z
        ny, n = nx + nz, self.square.n
        n_nodes = K * (d + 1)
        k = np.arange(K)[:, None]
        # pairs: the start x_{k,0} of interval k pivots on the continuity row ending interval
        # k-1 (coefficient 1); (x, z) at a collocation point on that point's DAE rows
        start_w = k * (d + 1) * nx + np.arange(nx)
        start_r = self.n_colloc_rows + ((k - 1) % K) * nx + np.arange(nx)
        pts = (k * d + np.arange(d)).ravel()                                 # point k d + r - 1
        nodes = (k * (d + 1) + 1 + np.arange(d)).ravel()                     # its node
        pt_w = np.hstack([nodes[:, None] * nx + np.arange(nx),
                          nx * n_nodes + pts[:, None] * nz + np.arange(nz)]).reshape(K, d * ny)
        pt_r = (pts[:, None] * ny + np.arange(ny)).reshape(K, d * ny)
        w_pairs = np.hstack([start_w, pt_w]).ravel()   # interval by interval, its start first
        r_pairs = np.hstack([start_r, pt_r]).ravel()
        J = self.square.residual.sparsity_jac(0, 0).sub(r_pairs.tolist(), w_pairs.tolist())[0]
        sym = J + J.T + ca.Sparsity.diag(n)
        blk = nx + d * ny                  # interval j holds paired positions j blk ..
        groups: list = []                  # (j + 1) blk - 1, its start's nx first

        def start(j):
            return np.arange(nx) + (j % K) * blk

        def chain(a, b):  # intervals a .. b-1; the starts of a and b are separators elsewhere
            if b - a <= _LEAF:
                groups.append(np.concatenate([np.arange(j * blk + (0 if j > a else nx),
                                                        (j + 1) * blk) for j in range(a, b)]))
                return
            m = (a + b) // 2
            chain(a, m)
            chain(m, b)
            groups.append(start(m))
        if K <= _LEAF:
            groups.append(np.arange(n))    # the whole ring to one AMD
        else:
            chain(0, K // 2)
            chain(K // 2, K)
            groups += [start(K // 2), start(0)]
        perm = np.concatenate([g[np.asarray(sym.sub(g.tolist(), g.tolist())[0].amd(), dtype=int)]
                               for g in groups])
        return r_pairs[perm], w_pairs[perm]

    def pack(self, X: np.ndarray, Z: np.ndarray) -> np.ndarray:
        """X (nx, n_nodes), Z (nz, n_pts) in physical units -> scaled unknowns."""
        return np.concatenate([(X / self.x_scale[:, None]).ravel(order="F"),
                               (Z / self.sc.z[:, None]).ravel(order="F")])

    def unpack(self, w: np.ndarray) -> tuple:
        nx, nz, K, d = self.nx, self.mech.n_z, self.K, self.d
        n_nodes = K * (d + 1)
        X = w[:nx * n_nodes].reshape(nx, n_nodes, order="F") * self.x_scale[:, None]
        Z = w[nx * n_nodes:].reshape(nz, K * d, order="F") * self.sc.z[:, None]
        return X, Z

    def sample(self, X, Z, m_per: int, period: float) -> tuple:
        """States at ``m_per`` uniform points per interval: (x (K m_per, nx), x' (K m_per, nx),
        z (K m_per, nz)), x' the derivative of the collocation polynomials (1/s)."""
        K, d = self.K, self.d
        s = np.arange(m_per) / m_per
        Lx = np.stack([L(s) for L in self.polys], axis=1)          # (m_per, d+1)
        dLx = np.stack([np.polyder(L)(s) for L in self.polys], axis=1) * (K / period)
        # z: the polynomial of degree d-1 through the collocation points
        pz = []
        tz = self.tau[1:]
        for j in range(d):
            L = np.poly1d([1.0])
            for r in range(d):
                if r != j:
                    L *= np.poly1d([1.0, -tz[r]]) / (tz[j] - tz[r])
            pz.append(L(s))
        Lz = np.stack(pz, axis=1)                                   # (m_per, d)
        xs, dxs, zs = [], [], []
        for k in range(K):
            Xk = X[:, k * (d + 1):(k + 1) * (d + 1)].T
            xs.append(Lx @ Xk)
            dxs.append(dLx @ Xk)
            zs.append(Lz @ Z[:, k * d:(k + 1) * d].T)
        return np.vstack(xs), np.vstack(dxs), np.vstack(zs)


def collocation_system(mech: Mechanism, opts: Collocation,
                       compiled: bool = False) -> CollocationSystem:
    scheme = opts.scheme.value
    key = ("collocation", opts.intervals, opts.degree, scheme) + (("C",) if compiled else ())
    return PERIODIC_CACHE.get(mech, key, lambda: CollocationSystem(
        mech, opts.intervals, opts.degree, scheme, compiled))


def solve_collocation(mech: Mechanism, period: float, opts: Collocation, p, start: StartFn,
                      start_info: dict, *, tol: float, defect_tol: float, ipopt_options=None,
                      max_iter: int = 100, compiled: bool = False):
    """Collocation of ``mech`` from ``start`` (see the module docstring); ``compiled``: the
    system's residual and Jacobian in generated C."""
    t0 = time.perf_counter()
    sys_ = collocation_system(mech, opts, compiled)
    nq, nz = mech.n_q, mech.n_z
    P = np.concatenate([[period], p])
    qn, vn, _ = start(period * sys_.t_nodes)
    _, _, zp = start(period * sys_.t_pts)
    w0 = sys_.pack(np.vstack([np.asarray(qn).T, np.asarray(vn).T]), np.asarray(zp).T)
    sol = sys_.square.solve(w0, P, solver=opts.solver, tol=tol, max_iter=max_iter,
                            ipopt_options=ipopt_options)
    X, Z = sys_.unpack(sol["w"])
    r = np.asarray(sys_.square.residual(sol["w"], P)).ravel()
    per_def = float(np.max(np.abs(r[-sys_.nx:])))            # wrap-around rows: periodicity
    g_nodes = float(np.max(np.abs(r[sys_.g_rows].reshape(-1, nz)) * sys_.sc.g)) if nz else 0.0
    x, dx, z = sys_.sample(X, Z, 4 * opts.degree, period)
    solved = np.isfinite(sol["residual"]) and sol["residual"] <= tol
    stats = dict(start_info)
    stats.update({"solver": opts.solver, "iterations": sol["iterations"],
                  "residual": sol["residual"], "return_status": sol["return_status"],
                  "periodicity_defect": per_def, "constraint_at_nodes": g_nodes,
                  "intervals": opts.intervals, "degree": opts.degree,
                  "scheme": opts.scheme.value, "unknowns": sys_.square.n, "tolerance": tol,
                  "compiled": sys_.square.compiled,
                  "wall_time": time.perf_counter() - t0})
    return check_and_wrap(mech, period, p, x[:, :nq], x[:, nq:], z, method="collocation",
                          solved=solved, tol=tol, defect_tol=defect_tol, stats=stats,
                          derivatives=(dx[:, :nq], dx[:, nq:]), codegen=compiled,
                          why=_why(opts, sol, tol))


def _why(opts, sol: dict, tol: float) -> str:
    """Why a collocation solve stopped short, in a line (with the way on at a time limit)."""
    why = (f"{opts.solver} stopped ({sol['return_status']}) at residual "
           f"{sol['residual']:.3g} > tol = {tol:.3g}")
    if "WallTime" in str(sol["return_status"]) or "User_Requested" in str(sol["return_status"]):
        why += (": the time limit of one periodic solve (sc.limits(solve_seconds=...), "
                "--max-solve-seconds); method='shooting' is cheaper, or the response may have "
                "no period (simulate shows what it does)")
    return why
