"""Harmonic balance on any Mechanism, alternating frequency/time (AFT).

Method
------
The unknowns are the real Fourier coefficients of the coordinates and of the constraint
forces over the period T (omega = 2 pi / T),

    q(t) = Q_0 + sum_{h=1..H} Q_h^c cos(h omega t) + Q_h^s sin(h omega t),  z(t) likewise,

stored as matrices (n, 2H+1) with columns ``[c_0, c_1, s_1, ..., c_H, s_H]``. The velocities
and accelerations are exact in the coefficients (v = q', a = q''; mechanisms with q' = G(q) v
are refused until rigid bodies arrive). The state is sampled at ``samples`` equally spaced
times (default 4H + 4: no aliasing of a cubic nonlinearity into the balanced harmonics), the
residual ``(M(q) a - f(q, v, z, t), g)`` is evaluated there by ONE mapped call of the derived
``acc_residual``, and projected back onto the 2H + 1 harmonics (discrete Fourier projection).
The system is square; CasADi differentiates the whole map, so Newton (CasADi's rootfinder,
sparse LU) has the exact Jacobian.

Scaling
-------
Coefficients of q and z are divided by ``scales.q`` and ``scales.z``; the force rows by
``scales.force`` and the constraint rows by ``scales.g_scale()``. The
period enters as a parameter of the one residual Function, so the graph is built once per
mechanism and (H, samples) and serves every period.

Start
-----
The last of 6 periods of generalized-alpha (64 steps each) marched from the static
equilibrium at rest (:func:`~symcable.solvers.shooting_mech.transient_start`), or a given
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

from ..derive import functions
from ..errors import SymcableError
from ..models.mechanism import Mechanism
from .options import HarmonicBalance
from .periodic_common import PERIODIC_CACHE, Scaling, SquareSystem, StartFn, check_and_wrap

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

    def __init__(self, mech: Mechanism, H: int, M: int):
        self.mech, self.H, self.M = mech, H, M
        F = functions(mech)
        sc = Scaling.of(mech)
        nq, nz, nc = mech.n_q, mech.n_z, 2 * H + 1
        self.nc = nc
        self.tau = np.arange(M) / M
        self.E = _basis(H, self.tau)                       # (M, nc)
        self.D = _d1(H)
        wts = np.full(nc, 2.0 / M)
        wts[0] = 1.0 / M
        self.proj = self.E * wts                            # r (n, M) @ proj -> coefficients
        w = ca.MX.sym("w", (nq + nz) * nc)
        P = ca.MX.sym("P", 1 + mech.params.n)
        T, p = P[0], P[1:]
        Qc = ca.diag(ca.DM(sc.q)) @ ca.reshape(w[:nq * nc], nq, nc)
        Zc = ca.diag(ca.DM(sc.z)) @ ca.reshape(w[nq * nc:], nz, nc) if nz else ca.MX(0, nc)
        om = 2 * math.pi / T
        Et = ca.DM(self.E.T)
        Dm = ca.DM(self.D.T)  # C @ D^T: coefficients of the derivative (columns)
        q = Qc @ Et
        v = om * (Qc @ Dm) @ Et
        a = om ** 2 * (Qc @ Dm @ Dm) @ Et
        z = Zc @ Et
        t = T * ca.DM(self.tau).T
        r_f, r_g = F.acc_residual.map(M)(q, v, a, z, t, p)
        R = ca.vertcat(ca.vec((r_f / sc.force) @ ca.DM(self.proj)),
                       ca.vec((ca.diag(ca.DM(1.0 / sc.g)) @ r_g) @ ca.DM(self.proj)))
        self.square = SquareSystem(f"{mech.name}_hb{H}",
                                   ca.Function(f"{mech.name}_hb_residual", [w, P], [R],
                                               ["w", "P"], ["r"]))
        self.sc = sc

    def pack(self, Qc: np.ndarray, Zc: np.ndarray) -> np.ndarray:
        return np.concatenate([(Qc / self.sc.q[:, None]).ravel(order="F"),
                               (Zc / self.sc.z[:, None]).ravel(order="F")])

    def unpack(self, w: np.ndarray) -> tuple:
        nq, nz, nc = self.mech.n_q, self.mech.n_z, self.nc
        Qc = w[:nq * nc].reshape(nq, nc, order="F") * self.sc.q[:, None]
        Zc = w[nq * nc:].reshape(nz, nc, order="F") * self.sc.z[:, None]
        return Qc, Zc

    def coefficients_of(self, start: StartFn, period: float) -> np.ndarray:
        """Packed unknowns projecting a start onto the harmonics."""
        q, _, z = start(period * self.tau)
        return self.pack(np.asarray(q).T @ self.proj, np.asarray(z).T @ self.proj)


def hb_system(mech: Mechanism, H: int, M: int) -> HBSystem:
    if mech.kinematics is not None:
        raise SymcableError(f"mechanism {mech.name!r}: harmonic balance with q' = G(q) v "
                            "arrives with rigid bodies; use Collocation()")
    return PERIODIC_CACHE.get(mech, ("hb", H, M), lambda: HBSystem(mech, H, M))


def fourier_sampler(Qc, Zc, period: float) -> StartFn:
    """(q, v, z) of the Fourier series at times t."""
    H = (Qc.shape[1] - 1) // 2
    D = _d1(H)
    om = 2 * np.pi / period

    def at(t):
        E = _basis(H, np.asarray(t, float) / period)
        return E @ Qc.T, om * E @ (Qc @ D.T).T, E @ Zc.T
    return at


def default_samples(H: int) -> int:
    return 4 * H + 4


def solve_hbalance(mech: Mechanism, period: float, opts: HarmonicBalance, p, start: StartFn,
                   start_info: dict, *, tol: float, defect_tol: float, max_iter: int = 50):
    """Harmonic balance of ``mech`` from ``start`` (see the module docstring)."""
    t0 = time.perf_counter()
    H = opts.harmonics
    M = opts.samples or default_samples(H)
    sys_ = hb_system(mech, H, M)
    P = np.concatenate([[period], p])
    w0 = sys_.coefficients_of(start, period)
    sol = sys_.square.solve(w0, P, solver="newton", tol=tol, max_iter=max_iter)
    Qc, Zc = sys_.unpack(sol["w"])
    m = 4 * M
    tf = period * np.arange(m) / m
    q, v, z = fourier_sampler(Qc, Zc, period)(tf)
    solved = np.isfinite(sol["residual"]) and sol["residual"] <= tol
    stats = dict(start_info)
    stats.update({"solver": "newton", "iterations": sol["iterations"],
                  "residual": sol["residual"], "return_status": sol["return_status"],
                  "periodicity_defect": 0.0, "harmonics": H, "time_samples": M,
                  "unknowns": sys_.square.n, "tolerance": tol,
                  "wall_time": time.perf_counter() - t0,
                  "highest_harmonic": float(np.max(np.abs(Qc[:, -2:]) / sys_.sc.q[:, None]))})
    return check_and_wrap(mech, period, p, q, v, z, method="harmonic-balance", solved=solved,
                          tol=tol, defect_tol=defect_tol, stats=stats,
                          why=f"Newton stopped ({sol['return_status']}) at residual "
                              f"{sol['residual']:.3g} > tol = {tol:.3g}")
