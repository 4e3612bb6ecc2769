"""Harmonic balance on any Mechanism, alternating frequency/time (AFT).

Method
------
The unknowns are the real Fourier coefficients of the coordinates and of the constraint
forces over the period T (omega = 2 pi / T),

    q(t) = Q_0 + sum_{h=1..H} Q_h^c cos(h omega t) + Q_h^s sin(h omega t),  z(t) likewise,

stored as matrices (n, 2H+1) with columns ``[c_0, c_1, s_1, ..., c_H, s_H]``. The velocities
and accelerations are exact in the coefficients (v = q', a = q''). The state is sampled at
``samples`` equally spaced times (default 4H + 4: no aliasing of a cubic nonlinearity into
the balanced harmonics), the residual ``(M(q) a - f(q, v, z, t), g)`` is evaluated there by
ONE mapped call of the derived ``acc_residual``, and projected back onto the 2H + 1 harmonics
(discrete Fourier projection). The system is square; CasADi differentiates the whole map, so
Newton (CasADi's rootfinder, sparse LU) has the exact Jacobian.

Kinematics q' = G(q, t) v + w(q, t)
-----------------------------------
A mechanism with kinematics has harmonics of q AND of v as unknowns, and its rows are the
projections of the whole DAE residual (the derived ``dae_residual``, one mapped call):
``q' - G v - w`` (n_q rows per harmonic), ``M v' - f`` (n_v) and ``g`` (n_z). Eliminating v
(v = G^+ (q' - w)) would halve the unknowns only where G is square and constant, and even
then trade the sparse map for a G^-1; the planar cable, the one formulation with kinematics
today, has n_q = n_v + 2 (the end-to-end closure: G is not square) and a closure
stabilisation w that depends on q, so v stays an unknown. On an ODE y' = f(y) (the planar
cable) this is exactly the harmonic balance of y' - f(y), the momentum rows multiplied by
the constant masses. Unknowns and rows are ordered state by state (the 2H + 1 coefficients
of one state, then of the next), the states in an approximate-minimum-degree order of the
mechanism's own Jacobian (:func:`_state_order`): the system's Jacobian is then as banded as
the mechanism's, which the sparse LU, factorising in the given order, needs.

Scaling
-------
Coefficients of q and z are divided by ``scales.q`` and ``scales.z``; the force rows by
``scales.force`` and the constraint rows by ``scales.g_scale()``. The
period enters as a parameter of the one residual Function, so the graph is built once per
mechanism and (H, samples) and serves every period.

Start
-----
The last of 6 periods of generalized-alpha (64 steps each) marched from the static
equilibrium at rest (:func:`~symcable.solvers.periodic_start.transient_start`), or a given
periodic solution. Not the linear response: on Duffing at its defaults (omega = 1.2 above
the linear natural frequency 1, where the hardening response sits on its resonant branch)
the linear response is in antiphase, and Newton on the one-harmonic balance from it stalls
at a stationary point of the residual (0.33 of the force scale); the short run follows the
physics to the response the mechanism reaches from rest, at the cost of 384 cheap steps.

Checks
------
The Fourier series is sampled on 4 x ``samples`` points and checked by
:func:`~symcable.solvers.periodic_common.check_and_wrap`; the periodicity is exact by
construction.
"""
from __future__ import annotations

import math
import time

import casadi as ca
import numpy as np

from ..mechanism.functions import functions
from ..mechanism.mechanism import Mechanism
from .options import HarmonicBalance
from .periodic_common import (PERIODIC_CACHE, Scaling, SquareSystem, StartFn, check_and_wrap,
                              point_function)

__all__ = ["solve_hbalance", "HBSystem"]


def _basis(H: int, tau: np.ndarray) -> np.ndarray:
    """(len(tau), 2H+1): [1, cos(2 pi h tau), sin(2 pi h tau)] per harmonic h."""
    cols = [np.ones_like(tau)]
    for h in range(1, H + 1):
        cols += [np.cos(2 * np.pi * h * tau), np.sin(2 * np.pi * h * tau)]
    return np.stack(cols, axis=1)


def _d1(H: int) -> np.ndarray:
    """Derivative in tau/(2 pi) of the coefficients: x' = omega C D1 basis^T."""
    D = np.zeros((2 * H + 1, 2 * H + 1))
    for h in range(1, H + 1):
        c, s = 2 * h - 1, 2 * h
        D[s, c] = -h  # d/dt cos = -h omega sin: the cos coefficient feeds the sin column
        D[c, s] = h
    return D


class HBSystem:
    """The harmonic-balance system of one mechanism for (H, M): its residual Function
    ``<name>_hb_residual(w, P) -> r`` (P = (T, p)), solvers and the packing of unknowns."""

    def __init__(self, mech: Mechanism, H: int, M: int, compiled: bool = False):
        self.mech, self.H, self.M = mech, H, M
        sc = Scaling.of(mech)
        nq, nz, nc = mech.n_q, mech.n_z, 2 * H + 1
        self.nc = nc
        self.tau = np.arange(M) / M
        self.E = _basis(H, self.tau)                       # (M, nc)
        self.D = _d1(H)
        wts = np.full(nc, 2.0 / M)
        wts[0] = 1.0 / M
        self.proj = self.E * wts                            # r (n, M) @ proj -> coefficients
        P = ca.MX.sym("P", 1 + mech.params.n)
        T, p = P[0], P[1:]
        om = 2 * math.pi / T
        Et = ca.DM(self.E.T)
        Dm = ca.DM(self.D.T)  # C @ D^T: coefficients of the derivative (columns)
        t = T * ca.DM(self.tau).T
        self.sc = sc
        self.kinematic = mech.kinematics is not None
        F = functions(mech)
        if self.kinematic:
            nv = mech.n_v
            n = nq + nv + nz
            self.scale = np.concatenate([sc.q, sc.v, sc.z])
            self.order = _state_order(F.dae_residual, n)
            inv = np.argsort(self.order)
            w = ca.MX.sym("w", n * nc)
            Cp = ca.reshape(w, nc, n).T                                # state-major unknowns
            C = ca.diag(ca.DM(self.scale)) @ Cp[inv.tolist(), :]
            Y = C @ Et
            Yd = om * (C @ Dm) @ Et
            if nz:  # no derivative of z enters the residual
                Yd = ca.vertcat(Yd[:nq + nv, :], ca.MX(nz, M))
            Fr = point_function(mech, "dae_residual", compiled).map(M)(Yd, Y, t, p)
            rows = np.concatenate([np.full(nq, 1.0 / sc.v_ref), np.full(nv, 1.0 / sc.force),
                                   1.0 / sc.g])
            Rc = (ca.diag(ca.DM(rows)) @ Fr) @ ca.DM(self.proj)
            R = ca.vec(Rc[self.order.tolist(), :].T)                   # state-major rows
        else:
            w = ca.MX.sym("w", (nq + nz) * nc)
            Qc = ca.diag(ca.DM(sc.q)) @ ca.reshape(w[:nq * nc], nq, nc)
            Zc = ca.diag(ca.DM(sc.z)) @ ca.reshape(w[nq * nc:], nz, nc) if nz else ca.MX(0, nc)
            q = Qc @ Et
            v = om * (Qc @ Dm) @ Et
            a = om ** 2 * (Qc @ Dm @ Dm) @ Et
            z = Zc @ Et
            r_f, r_g = point_function(mech, "acc_residual", compiled).map(M)(q, v, a, z, t, p)
            R = ca.vertcat(ca.vec((r_f / sc.force) @ ca.DM(self.proj)),
                           ca.vec((ca.diag(ca.DM(1.0 / sc.g)) @ r_g) @ ca.DM(self.proj)))
        self.square = SquareSystem(f"{mech.fname}_hb{H}",
                                   ca.Function(f"{mech.fname}_hb_residual", [w, P], [R],
                                               ["w", "P"], ["r"]), compiled)

    def pack(self, Qc: np.ndarray, Vc: np.ndarray, Zc: np.ndarray) -> np.ndarray:
        """Scaled unknowns from coefficients (n, 2H+1) of q, v (kinematics only) and z."""
        if self.kinematic:
            C = np.vstack([Qc, Vc, Zc]) / self.scale[:, None]
            return C[self.order].ravel(order="C")
        return np.concatenate([(Qc / self.sc.q[:, None]).ravel(order="F"),
                               (Zc / self.sc.z[:, None]).ravel(order="F")])

    def unpack(self, w: np.ndarray, period: float) -> tuple:
        """(Qc, Vc, Zc): the coefficients of q, v and z (v = q' without kinematics)."""
        nq, nz, nc = self.mech.n_q, self.mech.n_z, self.nc
        if self.kinematic:
            nv = self.mech.n_v
            C = np.empty((self.scale.size, nc))
            C[self.order] = w.reshape(-1, nc)
            C *= self.scale[:, None]
            return C[:nq], C[nq:nq + nv], C[nq + nv:]
        Qc = w[:nq * nc].reshape(nq, nc, order="F") * self.sc.q[:, None]
        Zc = w[nq * nc:].reshape(nz, nc, order="F") * self.sc.z[:, None]
        return Qc, 2 * math.pi / period * Qc @ self.D.T, Zc

    def coefficients_of(self, start: StartFn, period: float) -> np.ndarray:
        """Packed unknowns projecting a start onto the harmonics."""
        q, v, z = start(period * self.tau)
        return self.pack(*(np.asarray(a).T @ self.proj for a in (q, v, z)))


def _state_order(dae: ca.Function, n: int) -> np.ndarray:
    """The states in an approximate-minimum-degree order of the symmetrised sparsity of
    dF/dy' + dF/dy (CasADi's AMD): each state's harmonics and rows are kept together and the
    states ordered so that the sparse LU, which factorises in the given order, meets the
    mechanism's couplings as a narrow band and its dense rows (a global constraint, such as
    the planar cable's closure stabilisation) last. In the order q, v, z a momentum row sits
    a whole q-block from the coordinates it couples to, and the LU is several times slower
    (the planar cable, tens of segments, ten harmonics)."""
    sp = dae.sparsity_jac(0, 0) + dae.sparsity_jac(1, 0)
    sym = sp + sp.T + ca.Sparsity.diag(n)
    return np.asarray(sym.amd(), dtype=int)


def hb_system(mech: Mechanism, H: int, M: int, compiled: bool = False) -> HBSystem:
    key = ("hb", H, M) + (("C",) if compiled else ())
    return PERIODIC_CACHE.get(mech, key, lambda: HBSystem(mech, H, M, compiled))


def fourier_sampler(Qc, Vc, Zc, period: float) -> StartFn:
    """(q, v, z) of the Fourier series at times t."""
    H = (Qc.shape[1] - 1) // 2

    def at(t):
        E = _basis(H, np.asarray(t, float) / period)
        return E @ Qc.T, E @ Vc.T, E @ Zc.T
    return at


def default_samples(H: int) -> int:
    return 4 * H + 4


def solve_hbalance(mech: Mechanism, period: float, opts: HarmonicBalance, p, start: StartFn,
                   start_info: dict, *, tol: float, defect_tol: float, max_iter: int = 50,
                   compiled: bool = False):
    """Harmonic balance of ``mech`` from ``start`` (see the module docstring); ``compiled``:
    the system's residual and Jacobian in generated C."""
    t0 = time.perf_counter()
    H = opts.harmonics
    M = opts.samples or default_samples(H)
    sys_ = hb_system(mech, H, M, compiled)
    P = np.concatenate([[period], p])
    w0 = sys_.coefficients_of(start, period)
    sol = sys_.square.solve(w0, P, solver="newton", tol=tol, max_iter=max_iter)
    Qc, Vc, Zc = sys_.unpack(sol["w"], period)
    m = 4 * M
    tf = period * np.arange(m) / m
    q, v, z = fourier_sampler(Qc, Vc, Zc, period)(tf)
    solved = np.isfinite(sol["residual"]) and sol["residual"] <= tol
    stats = dict(start_info)
    stats.update({"solver": "newton", "iterations": sol["iterations"],
                  "residual": sol["residual"], "return_status": sol["return_status"],
                  "periodicity_defect": 0.0, "harmonics": H, "time_samples": M,
                  "unknowns": sys_.square.n, "tolerance": tol, "compiled": sys_.square.compiled,
                  "wall_time": time.perf_counter() - t0,
                  "highest_harmonic": float(np.max(np.abs(Qc[:, -2:]) / sys_.sc.q[:, None]))})
    return check_and_wrap(mech, period, p, q, v, z, method="harmonic-balance", solved=solved,
                          tol=tol, defect_tol=defect_tol, stats=stats, codegen=compiled,
                          why=f"Newton stopped at residual {sol['residual']:.3g} > tol = "
                              f"{tol:.3g} (its solver said: {sol['return_status']})")
