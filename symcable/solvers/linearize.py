"""Exact linearisation of any Mechanism about an equilibrium, its natural modes, and the
sensitivity of any output to any parameter block (e.g. the stiffness a line presents at an
end: the derivative of the end force with respect to the end's prescribed position).

Everything comes from CasADi's exact derivatives of the Mechanism's own force, constraint
and output expressions: no finite differences.

- ``K = -df/dq``, ``C = -df/dv``, ``M``, ``B = dg/dq`` at (q, 0, z, 0; p). The constraint
  forces are held at their equilibrium values z, so K contains their geometric stiffness.
- Modes: the generalized eigenproblem K phi = omega^2 M phi on the null space of B
  (coordinates that keep the constraints), by a dense symmetric solve (Cholesky of the
  reduced M); with ``damped=True`` the complex modes of the first-order system with C.
- Sensitivity (implicit function theorem): with R(x; p) = 0 the static residual,
  dx/dp = -R_x^-1 R_p and dy/dp = y_x dx/dp + y_p for an output y.
"""
from __future__ import annotations

import numpy as np

from ..derive import functions
from ..errors import SymcableError
from ..models.mechanism import Mechanism
from ..results_mechanism import Equilibrium, Linearization, MechanismModes
from .equilibrium import constraint_null_space

__all__ = ["linearize_mechanism", "mechanism_modes", "output_sensitivity"]

#: largest reduced system solved densely
DENSE_MAX_N = 4000


def linearize_mechanism(mech: Mechanism, eq: Equilibrium) -> Linearization:
    """K, C, M, B (dense arrays) about the equilibrium ``eq``."""
    F = functions(mech)
    K, C, M, B, *_ = F.tangents(eq.q, np.zeros(mech.n_v), eq.z, 0.0, eq.p)
    return Linearization(mech.name, np.asarray(K), np.asarray(C), np.asarray(M), np.asarray(B),
                         eq.q, eq.z, eq.p, {"n_q": mech.n_q, "n_z": mech.n_z})


def mechanism_modes(mech: Mechanism, eq: Equilibrium, n_modes: int | None = None, *,
                    damped: bool = False) -> MechanismModes:
    """Natural modes about ``eq``: frequencies (Hz, ascending) and shapes in q.

    The reduced mass matrix must be positive definite (every free coordinate carries mass);
    a SymcableError says so otherwise. With ``damped=True`` the damping ratios of the complex
    modes (from C) are returned too, matched to the undamped modes by frequency order.
    """
    lin = linearize_mechanism(mech, eq)
    n = mech.n_q
    N = constraint_null_space(lin.B, n)
    k = N.shape[1]
    if k > DENSE_MAX_N:
        raise SymcableError(f"modal analysis: {k} free coordinates exceed the dense limit "
                            f"{DENSE_MAX_N}")
    Kr = N.T @ (0.5 * (lin.K + lin.K.T)) @ N
    Mr = N.T @ (0.5 * (lin.M + lin.M.T)) @ N
    try:
        L = np.linalg.cholesky(Mr)
    except np.linalg.LinAlgError:
        raise SymcableError(f"modal analysis of {mech.name!r}: the mass matrix is singular on "
                            "the free coordinates (a coordinate without mass)") from None
    Li = np.linalg.inv(L)
    A = Li @ Kr @ Li.T
    lam, Y = np.linalg.eigh(0.5 * (A + A.T))
    shapes_r = np.linalg.solve(L.T, Y)
    shapes = (N @ shapes_r).T
    n_modes = k if n_modes is None else int(n_modes)
    if not 1 <= n_modes <= k:
        raise SymcableError(f"n_modes = {n_modes}: must be in [1, {k}]")
    lam, shapes = lam[:n_modes], shapes[:n_modes]
    if np.any(lam < -1e-9 * max(1.0, np.max(np.abs(lam)))):
        raise SymcableError(f"modal analysis of {mech.name!r}: negative stiffness eigenvalue "
                            f"{lam.min():.3g} (the equilibrium is unstable)")
    shapes = shapes / np.max(np.abs(shapes), axis=1, keepdims=True)
    freqs = np.sqrt(np.clip(lam, 0.0, None)) / (2 * np.pi)
    zeta = None
    if damped:
        Cr = N.T @ lin.C @ N
        Minv = np.linalg.inv(Mr)
        Aft = np.block([[np.zeros((k, k)), np.eye(k)], [-Minv @ (N.T @ lin.K @ N), -Minv @ Cr]])
        ev = np.linalg.eigvals(Aft)
        ev = ev[ev.imag > 0]
        ev = ev[np.argsort(np.abs(ev))][:n_modes]
        zeta = np.full(n_modes, np.nan)
        zeta[:ev.size] = -ev.real / np.abs(ev)
    return MechanismModes(mech.name, freqs, shapes, zeta,
                          {"free_coordinates": k, "constraints": int(lin.B.shape[0])})


def output_sensitivity(mech: Mechanism, eq: Equilibrium, output: str, block: str) -> np.ndarray:
    """d(output)/d(parameter block) at the equilibrium, holding R(x; p) = 0 (exact).

    Returns an (n_y, n_b) array in the output's unit per the block's unit, e.g. N/m for an
    end force against an end position.
    """
    if output not in mech.outputs:
        raise SymcableError(f"output = {output!r}: unknown (outputs: {', '.join(mech.outputs)})")
    F = functions(mech)
    sl_p = mech.params.slice(block)
    x = np.concatenate([eq.q, eq.z])
    _, J = F.static_jacobian(x, eq.p)
    J = np.asarray(J)
    v0 = np.zeros(mech.n_v)
    f_p, g_p = F.force_parameter_jacobian(eq.q, v0, eq.z, 0.0, eq.p)
    R_p = np.vstack([np.asarray(f_p), F.g_weight * np.asarray(g_p)])[:, sl_p]
    dx = -np.linalg.solve(J, R_p)
    y_q, y_z, y_p = (np.asarray(a) for a in F.output_parameter_jacobian(eq.q, v0, eq.z, 0.0, eq.p))
    sl_y = F.output_slices()[output]
    dq, dz = dx[:mech.n_q], dx[mech.n_q:]
    return y_q[sl_y] @ dq + y_z[sl_y] @ dz + y_p[sl_y][:, sl_p]

