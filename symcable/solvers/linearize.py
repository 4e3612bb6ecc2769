"""Exact linearisation of any Mechanism about an equilibrium, its natural modes, and the
sensitivity of any output to any parameter block (e.g. the stiffness a line presents at an
end: the derivative of the end force with respect to the end's prescribed position).

Everything comes from CasADi's exact derivatives of the Mechanism's own force, constraint,
kinematics and output expressions: no finite differences.

- ``K = -df/dq``, ``C = -df/dv``, ``M``, ``B = dg/dq`` at (q, 0, z, 0; p), and the
  kinematics ``q' = G v + H q`` linearised (``G = I``, ``H = 0`` without kinematics). The
  constraint forces are held at their equilibrium values z, so K contains their geometric
  stiffness.
- Modes (undamped, C off): the state matrix of ``q' = H q + G v``, ``M v' = -K q`` has the
  eigenvalues ``+-i omega``. Where ``H = 0`` (at rest, ``H`` is the derivative of the part
  ``w(q, t)`` of the kinematics that does not multiply v: zero unless the formulation
  stabilises an invariant) write ``q = G u`` with ``u' = v``, the displacement in the
  velocity coordinates: ``M u'' + (K G) u = 0``. When ``K G`` is symmetric (a conservative
  system: the stiffness in any coordinates that move the nodes, as for q' = v), this is the
  symmetric generalized problem ``K G phi = omega^2 M phi`` on the velocities that keep the
  constraints (``B G u = 0``). That is the choice wherever it exists: half the size of the
  state matrix and symmetric, so about 10 times faster than the nonsymmetric eigenproblem
  of the state matrix, with
  real frequencies and shapes by construction, and none of the state matrix's zero
  eigenvalues (the invariants: directions of q that no velocity reaches) to sort out. A
  symmetric eigensolver on K G itself would lose the lowest frequencies' digits (error
  ~eps (omega_max / omega_min)^2, against ~eps omega_max / omega_min for the state
  matrix); solving its inverse keeps them (see :func:`_symmetric_modes`). Otherwise
  (H != 0, or K G not symmetric) the dense nonsymmetric eigenproblem of the state matrix
  ``[[H, G N], [-M_r^-1 N^T K, 0]]`` (N: the velocities that keep the constraints) is
  solved, and its eigenvalues' real parts are reported.
- With ``damped=True``, the damping ratios from the same system with C.
- Sensitivity (implicit function theorem): with R(x; p) = 0 the static residual,
  dx/dp = -R_x^-1 R_p and dy/dp = y_x dx/dp + y_p for an output y.
"""
from __future__ import annotations

import time

import casadi as ca
import numpy as np

from ..mechanism.functions import functions
from ..errors import SymcableError
from ..mechanism.mechanism import Mechanism
from ..results.generic import Equilibrium, Linearization, MechanismModes
from .equilibrium import constraint_null_space

__all__ = ["linearize_mechanism", "mechanism_modes", "output_sensitivity", "MAX_DENSE"]

#: largest state size n_q + n_v solved by the dense eigenproblem by default
MAX_DENSE = 3000
#: K G is taken as symmetric when |K G - (K G)^T| <= this fraction of max |K G|
SYMMETRY_TOL = 1e-10
#: symmetric problem: omega^2 <= this fraction of max omega^2 is a zero (rigid) mode, far
#: above the eigensolver's round-off (~1e-16 of max omega^2)
ZERO_TOL_SQUARED = 1e-12
#: state matrix: |lambda| <= this fraction of max |lambda| is a zero eigenvalue
ZERO_TOL = 1e-9
#: a symmetric problem of a state size up to this many times max_dense is solved by the
#: sparse eigensolver for a few modes (its tangents are still formed dense: O(n^2) memory)
SPARSE_FACTOR = 4
#: |Re lambda| / |lambda| above this: the linear model is not conservative (a warning)
REAL_PART_TOL = 1e-6


def _dense(m) -> np.ndarray:
    """A CasADi DM as a dense float array, from its nonzeros (``DM.full()`` costs ~8 ms
    for a 400 x 400 matrix, this ~0.1 ms)."""
    if not isinstance(m, ca.DM):
        return np.asarray(m, dtype=float)
    out = np.zeros(m.shape)
    if m.nnz():
        rows, cols = m.sparsity().get_triplet()
        out[np.asarray(rows, dtype=int), np.asarray(cols, dtype=int)] = np.asarray(m.nonzeros())
    return out


def _tangents(mech: Mechanism, eq: Equilibrium):
    """K, C, M, B, G, H at ``eq`` as sparse CasADi DMs."""
    F = functions(mech)
    args = (eq.q, np.zeros(mech.n_v), eq.z, 0.0, eq.p)
    K, C, M, B, *_ = F.tangents(*args)
    if mech.kinematics is None:
        G, H = ca.DM.eye(mech.n_q), ca.DM(mech.n_q, mech.n_q)
    else:
        H, G = F.kinematics_jacobian(*args)
    return K, C, M, B, G, H


def linearize_mechanism(mech: Mechanism, eq: Equilibrium) -> Linearization:
    """K, C, M, B and the kinematics' G, H (dense arrays) about the equilibrium ``eq``.

    Exact: CasADi's derivatives of the Mechanism's force, constraint and kinematics
    expressions at (q, v = 0, z, t = 0; p) of ``eq``, the constraint forces held at z (so K
    contains their geometric stiffness); see the module docstring.

    Parameters
    ----------
    mech : Mechanism
        The system (:func:`symcable.build_mechanism`).
    eq : Equilibrium
        An equilibrium of ``mech`` (:func:`symcable.solve_equilibrium`): its q (n_q,), z
        (n_z,) and p (n_p,).

    Returns
    -------
    Linearization
        ``K`` (n_q, n_q) = -df/dq (N/m for a position coordinate), ``C`` (n_v, n_v) =
        -df/dv (N s/m), ``M`` (n_v, n_v) (kg), ``B`` (n_z, n_q) = dg/dq, ``G`` (n_q, n_v)
        and ``H`` (n_q, n_q) (1/s) of the kinematics q' = G v + H q (the identity and zero
        without kinematics), and the equilibrium's q, z, p.
    """
    K, C, M, B, G, H = (_dense(a) for a in _tangents(mech, eq))
    return Linearization(mech.name, K, C, M, B, eq.q, eq.z, eq.p,
                         {"n_q": mech.n_q, "n_z": mech.n_z}, G=G, H=H)


def _scaled(shapes: np.ndarray, *others: np.ndarray):
    """Rows of ``shapes`` scaled to max |entry| = 1 with that entry positive; ``others``
    (arrays of the same rows) scaled by the same factors."""
    if shapes.size == 0:
        return (shapes,) + others
    k = np.argmax(np.abs(shapes), axis=1)
    peak = shapes[np.arange(shapes.shape[0]), k]
    peak = np.where(peak == 0.0, 1.0, peak)[:, None]
    return (shapes / peak,) + tuple(o / peak for o in others)


def _mass_scaling(mech, Mr: np.ndarray):
    """``(apply, back)``: A = apply(Kv) = L^-1 Kv L^-T and back(Y) = L^-T Y for the Cholesky
    factor L of the reduced mass matrix (a scaling when it is diagonal, as for lumped
    masses)."""
    d = np.diag(Mr)
    if not np.any(Mr - np.diag(d)):
        if np.any(d <= 0.0):
            raise SymcableError(f"modal analysis of {mech.name!r}: the mass matrix is singular "
                                "on the free coordinates (a coordinate without mass)")
        s = 1.0 / np.sqrt(d)
        return (lambda Kv: s[:, None] * Kv * s[None, :]), (lambda Y: s[:, None] * Y)
    try:
        Li = np.linalg.inv(np.linalg.cholesky(Mr))
    except np.linalg.LinAlgError:
        raise SymcableError(f"modal analysis of {mech.name!r}: the mass matrix is singular on "
                            "the free coordinates (a coordinate without mass)") from None
    return (lambda Kv: Li @ Kv @ Li.T), (lambda Y: Li.T @ Y)


def _symmetric_modes(mech, Kv, Mr, n_wanted: int):
    """(omega^2 ascending, shapes in the reduced velocity coordinates as columns) of
    ``Kv phi = omega^2 Mr phi`` (both symmetric).

    With ``A = L^-1 Kv L^-T`` (``Mr = L L^T``), a symmetric eigensolver gives each eigenvalue
    to ~eps max(omega^2) absolutely, which costs the lowest modes of a stiff line their
    digits (eps (omega_max / omega_min)^2 relative: 2e-7 on a 100-segment hanging chain with
    EA = 1e9 N). Its inverse ``(A + s I)^-1`` (the shift s = 0 unless A is singular, then
    s = the lowest non-zero eigenvalue) turns the lowest modes into the largest eigenvalues,
    to ~eps relative (2e-14 there, as the state matrix gives); the modes above the
    spectrum's geometric mean come from A itself, where they are the accurate ones.
    """
    apply, back = _mass_scaling(mech, Mr)
    A = apply(Kv)
    A = 0.5 * (A + A.T)
    if A.size == 0:
        return np.zeros(0), np.zeros((0, 0))
    direct = None
    shift = 0.0
    try:
        np.linalg.cholesky(A)               # positive definite: stable, no rigid mode
    except np.linalg.LinAlgError:
        direct = np.linalg.eigh(A)
        lam = direct[0]
        lam_max = float(np.max(np.abs(lam)))
        if lam[0] < -1e-9 * max(1.0, lam_max):
            raise SymcableError(f"modal analysis of {mech.name!r}: negative stiffness eigenvalue "
                                f"{lam[0]:.3g} (the equilibrium is unstable)") from None
        positive = lam[lam > ZERO_TOL_SQUARED * lam_max]
        if positive.size == 0:
            return lam, back(direct[1])
        shift = float(positive[0])
    Ainv = np.linalg.inv(A + shift * np.eye(A.shape[0]) if shift else A)
    mu, Y = np.linalg.eigh(0.5 * (Ainv + Ainv.T))   # 1 / (omega^2 + shift), ascending
    lam, Y = 1.0 / mu[::-1] - shift, Y[:, ::-1]
    # the top of the spectrum, where the inverse's eigenvalues 1/omega^2 are round-off (of
    # either sign), is whatever comes last: the largest eigenvalue is the largest, not the last
    top = float(np.max(lam))
    nonzero = lam[lam > ZERO_TOL_SQUARED * top]
    upper = np.flatnonzero(lam > np.sqrt(nonzero[0] * top)) if nonzero.size else []
    if len(upper) and upper[0] < n_wanted + lam.size - nonzero.size:
        if direct is None:
            direct = np.linalg.eigh(A)
        lam[upper], Y[:, upper] = direct[0][upper], direct[1][:, upper]
    return lam, back(Y)


def _sparse_symmetric_modes(mech, Kv, Mr, n_wanted: int):
    """(omega^2 ascending, shapes as columns) of the ``n_wanted`` lowest non-zero modes of
    ``Kv phi = omega^2 Mr phi`` (both symmetric, sparse in fact) and its zero modes among
    them, by shift-invert Lanczos (ARPACK through :func:`scipy.sparse.linalg.eigsh`): for a
    problem above ``max_dense``, where the dense solvers cost n^3. The shift sits just below
    zero (1e-10 of the largest eigenvalue), so the factorised ``Kv - shift Mr`` is positive
    definite with rigid modes too and the lowest modes are the best resolved ones. Returns
    also the largest ratio of the diagonals of ``Kv`` and ``Mr``, about the largest
    eigenvalue (the scale of the zero tolerance)."""
    import scipy.sparse as sps
    from scipy.sparse.linalg import ArpackNoConvergence, eigsh

    K, M = sps.csc_matrix(Kv), sps.csc_matrix(Mr)
    k = K.shape[0]
    dk, dm = K.diagonal(), M.diagonal()
    lam_max = float(np.max(dk / np.where(dm > 0, dm, np.inf)))  # ~ the largest eigenvalue
    try:
        sigma = -1e-10 * max(lam_max, 1e-300)
        n_ask = min(k - 1, n_wanted + 12)  # room for rigid modes
        lam, Y = eigsh(K, k=n_ask, M=M, sigma=sigma, which="LM")
    except (ArpackNoConvergence, RuntimeError) as exc:
        raise SymcableError(f"modal analysis of {mech.name!r}: the sparse eigensolver did not "
                            f"converge ({exc}); pass a larger max_dense for the dense one")
    order = np.argsort(lam)
    lam, Y = lam[order], Y[:, order]
    if lam[0] < -1e-9 * max(1.0, lam_max):
        raise SymcableError(f"modal analysis of {mech.name!r}: negative stiffness eigenvalue "
                            f"{lam[0]:.3g} (the equilibrium is unstable)")
    return lam, Y, lam_max


def _state_matrix_modes(mech, Hd, GN, Kq, Mr):
    """The undamped state matrix [[H, G N], [-Mr^-1 Kq, 0]]: (eigenvalues with Im > 0
    ascending, their displacements in the reduced velocities (rows), zero eigenvalues,
    zero tolerance, warnings). Refuses an unstable equilibrium (a real positive eigenvalue)."""
    k = Mr.shape[0]
    A = np.block([[Hd, GN], [-np.linalg.solve(Mr, Kq), np.zeros((k, k))]])
    ev, X = np.linalg.eig(A)
    mag = np.abs(ev)
    zero_tol = ZERO_TOL * float(mag.max()) if ev.size else 0.0
    is_zero = mag <= zero_tol
    growing = ~is_zero & (ev.real > REAL_PART_TOL * mag) & (np.abs(ev.imag) <= REAL_PART_TOL * mag)
    if np.any(growing):
        raise SymcableError(f"modal analysis of {mech.name!r}: real eigenvalue "
                            f"{ev.real[growing].max():.3g} 1/s > 0 (the equilibrium is unstable)")
    warnings = []
    nonzero = ev[~is_zero]
    rel = np.abs(nonzero.real) / np.abs(nonzero) if nonzero.size else np.zeros(0)
    if rel.size and rel.max() > REAL_PART_TOL:
        j = int(np.argmax(rel))
        warnings.append(f"the linear model is not conservative: eigenvalue {nonzero[j]:.6g} 1/s "
                        f"has |Re|/|lambda| = {rel[j]:.3g} > {REAL_PART_TOL:g}; its frequencies "
                        "are the imaginary parts")
    # oscillating: Im > 0 beyond round-off (a real double eigenvalue, such as the planar
    # closure's -beta pair, comes out of the eigensolver as a pair +-1e-15 i)
    keep = np.flatnonzero(~is_zero & (ev.imag > 1e-8 * mag))
    keep = keep[np.argsort(ev.imag[keep], kind="stable")]
    # displacement in the velocity coordinates: u = v / lambda, made real by the phase of its
    # largest entry
    u = (X[mech.n_q:, keep] / ev[keep]).T
    if u.size:
        peak = u[np.arange(u.shape[0]), np.argmax(np.abs(u), axis=1)]
        u = u * (np.abs(peak) / np.where(peak == 0, 1.0, peak))[:, None]
    return ev[keep], u.real, int(np.count_nonzero(is_zero)), zero_tol, warnings


def _damping_ratios(C, Hd, GN, Kq, Kv, Mr, N, n, zero_tol) -> np.ndarray:
    """Damping ratios -Re/|lambda| of the n lowest complex modes of the system with C: in the
    displacement of the velocity coordinates, u' = v, where H = 0, else in (q, v)."""
    Cr = C if N is None else N.T @ C @ N
    Minv = np.linalg.inv(Mr)
    k = Mr.shape[0]
    if not np.any(Hd):
        A = np.block([[np.zeros((k, k)), np.eye(k)], [-Minv @ Kv, -Minv @ Cr]])
    else:
        A = np.block([[Hd, GN], [-Minv @ Kq, -Minv @ Cr]])
    ev = np.linalg.eigvals(A)
    ev = ev[(ev.imag > 0) & (np.abs(ev) > zero_tol)]
    ev = ev[np.argsort(np.abs(ev))][:n]
    zeta = np.full(n, np.nan)
    zeta[:ev.size] = -ev.real / np.abs(ev)
    return zeta


def mechanism_modes(mech: Mechanism, eq: Equilibrium, n_modes: int | None = None, *,
                    damped: bool = False, max_dense: int = MAX_DENSE) -> MechanismModes:
    """The lowest undamped natural modes of ``mech`` about the equilibrium ``eq``.

    Frequencies in Hz, ascending; zero frequencies, the rigid modes, are left out and
    counted in ``stats["zero_modes"]``. Solved by the symmetric problem where one exists,
    else the state matrix (see the module docstring). The reduced mass matrix must be
    positive definite (every free velocity carries mass).

    Parameters
    ----------
    mech : Mechanism
        The system (:func:`symcable.build_mechanism`).
    eq : Equilibrium
        An equilibrium of ``mech`` (:func:`symcable.solve_equilibrium`).
    n_modes : int, optional
        How many modes to return (>= 1). Default None: all. Fewer come back, with a warning
        in ``.warnings``, when the mechanism has fewer.
    damped : bool
        Also return the damping ratios of the complex modes of the system with C, matched
        to the undamped modes by order. Default False.
    max_dense : int
        The largest dense eigenproblem solved: the free velocities of a symmetric problem,
        else the state size n_q + n_v (O(n^3) time, O(n^2) memory; at the default 3000 a
        symmetric problem takes about 2 s, the state matrix ~20 s). A symmetric problem up
        to SPARSE_FACTOR (4) times larger is solved for its ``n_modes`` lowest modes (fewer
        than half) by sparse shift-invert Lanczos.

    Returns
    -------
    MechanismModes
        ``frequencies`` (k,) Hz, ``shapes`` (k, n_q) in q, ``velocity_shapes`` (k, n_v),
        ``real_parts`` (k,) 1/s, ``damping_ratios`` (k,) or None, and ``stats``.

    Raises
    ------
    SymcableError
        ``n_modes`` not an integer >= 1, a problem larger than ``max_dense`` allows, a mass
        matrix singular on the free coordinates, an unstable equilibrium (a negative
        stiffness eigenvalue, or a real positive eigenvalue of the state matrix), or a
        sparse eigensolver that did not converge.
    """
    n_state = mech.n_q + mech.n_v
    if isinstance(n_modes, bool) or (n_modes is not None and (int(n_modes) != n_modes
                                                               or n_modes < 1)):
        raise SymcableError(f"n_modes = {n_modes!r}: must be an integer >= 1 (or None: all)")
    if n_state > 2 * SPARSE_FACTOR * max_dense:
        raise SymcableError(
            f"state size n_q + n_v = {n_state} > {2 * SPARSE_FACTOR} max_dense = "
            f"{2 * SPARSE_FACTOR * max_dense}: even the sparse eigensolver's dense tangents take "
            "O(n^2) memory; use a coarser discretisation or pass a larger max_dense "
            "(symcable modes --max-dense N)")
    t0 = time.perf_counter()
    K, C, M, B, G, H = _tangents(mech, eq)
    Hd = _dense(H)
    if B.size1() > 0:                         # the velocities that keep the constraints
        Gd = _dense(G)
        N = constraint_null_space(_dense(B) @ Gd, mech.n_v)
        GN = Gd @ N
        Kq = N.T @ _dense(K)
        Kv = Kq @ GN
        Mr = N.T @ _dense(M) @ N
    else:
        N, GN, Kq = None, _dense(G), _dense(K)
        Kv = _dense(ca.mtimes(K, G))
        Mr = _dense(M)
    Mr = 0.5 * (Mr + Mr.T)
    k = Mr.shape[0]
    t1 = time.perf_counter()
    scale = float(np.max(np.abs(Kv))) if Kv.size else 0.0
    symmetric = (not np.any(Hd) and
                 (Kv.size == 0 or float(np.max(np.abs(Kv - Kv.T))) <= SYMMETRY_TOL * scale))
    size = k if symmetric else n_state  # of the dense eigenproblem
    sparse = size > max_dense
    if sparse and not (symmetric and n_modes is not None and int(n_modes) < k // 2
                       and size <= SPARSE_FACTOR * max_dense):
        raise SymcableError(
            f"{'free velocities' if symmetric else 'state size n_q + n_v'} = {size} > "
            f"max_dense = {max_dense}: the dense eigenvalue problem grows as n^3 "
            f"(~{(1 if symmetric else 20) * (size / 3000) ** 3:.2g} s), and the sparse one "
            "takes a symmetric problem, fewer modes than half its size, up to "
            f"{SPARSE_FACTOR} max_dense; use a coarser discretisation, fewer modes, or pass a "
            "larger max_dense (symcable modes --max-dense N)")
    if symmetric:
        method, warnings, real = "symmetric (K G, M)", [], None
        n_wanted = k if n_modes is None else int(n_modes)
        if sparse:
            method = "symmetric (K G, M), sparse shift-invert"
            lam, U, lam_max = _sparse_symmetric_modes(mech, 0.5 * (Kv + Kv.T), Mr, n_wanted)
        else:
            lam, U = _symmetric_modes(mech, 0.5 * (Kv + Kv.T), Mr, n_wanted)
            lam_max = float(np.max(np.abs(lam))) if lam.size else 0.0
        zero = lam <= ZERO_TOL_SQUARED * lam_max
        zero_tol = float(np.sqrt(ZERO_TOL_SQUARED * lam_max))
        keep = np.flatnonzero(~zero)
        omega, u = np.sqrt(lam[keep]), U[:, keep].T
        n_rigid = int(np.count_nonzero(zero))
        n_nonzero = k - n_rigid if sparse else keep.size  # sparse: those not computed too
        n_zero_ev = mech.n_q + k - 2 * n_nonzero
    else:
        method, n_rigid = "state matrix", 0
        ev, u, n_zero_ev, zero_tol, warnings = _state_matrix_modes(mech, Hd, GN, Kq, Mr)
        omega, real = ev.imag, ev.real
    t2 = time.perf_counter()
    wanted = omega.size if n_modes is None else int(n_modes)
    if wanted > omega.size:
        warnings.append(f"n_modes = {wanted}: {mech.name!r} has only {omega.size} oscillating "
                        "modes")
    take = slice(0, min(wanted, omega.size))
    omega, u = omega[take], u[take]
    real = np.zeros(omega.size) if real is None else real[take]
    q_shapes, u_full = _scaled(u @ GN.T, u if N is None else u @ N.T)
    zeta = None
    if damped:
        zeta = _damping_ratios(_dense(C), Hd, GN, Kq, Kv, Mr, N, omega.size, zero_tol)
    return MechanismModes(mech.name, omega / (2 * np.pi), q_shapes, zeta,
                          {"method": method, "state_size": n_state, "free_velocities": k,
                           "constraints": int(B.size1()), "zero_modes": n_rigid,
                           "zero_eigenvalues": n_zero_ev, "zero_tolerance": zero_tol,
                           "max_relative_real_part":
                               float(np.max(np.abs(real) / omega)) if omega.size else 0.0,
                           "linearize_time": t1 - t0, "eig_time": t2 - t1},
                          velocity_shapes=u_full, real_parts=real, warnings=tuple(warnings))


def output_sensitivity(mech: Mechanism, eq: Equilibrium, output: str, block: str) -> np.ndarray:
    """d(output)/d(parameter block) at the equilibrium, holding R(x; p) = 0 (exact).

    By the implicit function theorem: dx/dp = -R_x^-1 R_p and dy/dp = y_x dx/dp + y_p, from
    CasADi's derivatives (no finite differences).

    Parameters
    ----------
    mech : Mechanism
        The system (:func:`symcable.build_mechanism`).
    eq : Equilibrium
        An equilibrium of ``mech`` (:func:`symcable.solve_equilibrium`).
    output : str
        A name of ``mech.outputs`` (e.g. ``"end_force_b"``; ``"LINE.end_force_b"`` in a
        scene of several parts).
    block : str
        A parameter block of ``mech`` (e.g. ``"end_b.position"``, or
        ``"LINE.end_b.position"``).

    Returns
    -------
    ndarray (n_y, n_b)
        n_y the output's size (flattened), n_b the block's; in the output's unit per the
        block's unit, e.g. N/m for an end force against an end position.

    Raises
    ------
    SymcableError
        An unknown output or parameter block.
    """
    if output not in mech.outputs:
        raise SymcableError(f"output = {output!r}: unknown (outputs: {', '.join(mech.outputs)})")
    F = functions(mech)
    sl_p = mech.params.slice(block)
    x = np.concatenate([eq.q, eq.z])
    _, J = F.static_jacobian(x, eq.p)
    J = np.asarray(J)
    v0 = np.zeros(mech.n_v)
    R_p = np.asarray(F.static_parameter_jacobian(x, eq.p))[:, sl_p]
    try:
        dx = -np.linalg.solve(J, R_p)
    except np.linalg.LinAlgError:
        raise SymcableError("output_sensitivity: the static Jacobian is singular at this "
                            "equilibrium (a neutral mode: a mechanism, or a bifurcation), so "
                            f"{output!r} has no unique derivative in {block!r}") from None
    y_q, y_z, y_p = (np.asarray(a) for a in F.output_parameter_jacobian(eq.q, v0, eq.z, 0.0, eq.p))
    sl_y = F.output_slices()[output]
    dq, dz = dx[:mech.n_q], dx[mech.n_q:]
    return y_q[sl_y] @ dq + y_z[sl_y] @ dz + y_p[sl_y][:, sl_p]

