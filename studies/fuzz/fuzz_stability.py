"""An independent stability check of a returned rod shape: the Hessian of the potential
energy of a chain of the same nodes, written here from the physics, not from symcable's
equations.

A rod whose answer is off its BVP reference but passes every physical check may sit on
another branch of equilibria: a compressed rod between clamps at angles other than its
chord's is bistable (its bow can snap through), a folded or looped rod has several shapes.
Such an answer is right if it is a stable equilibrium, wrong if it is unstable (the straight
strut of issue 11, or a higher buckling mode). The solver judges stability by its own
reduced tangent stiffness; this module judges it again, by the lowest eigenvalue of the
Hessian of

    E(x) = sum_j ds_j EA_j e_j^2 / 2                          (stretching; e_j = |dx_j| / ds_j - 1,
                                                               cables only in tension)
         + sum_i EI_i a_i^2 / (2 h_i)                         (bending: a_i the turn between
                                                               segments i-1 and i, h_i the
                                                               mean of their lengths)
         + EI a_end^2 / ds_end for a clamped end               (its turn from the clamp's
                                                               direction, over half a segment)
         + sum_i W_i z_i - sum_free f . x                     (weight lumped on nodes, end loads)

over the positions of the nodes that move, evaluated at the solver's nodes. This is a
different discretisation of the rod's energy than symcable's (the clamp in particular), so
its gradient there is small but not zero; the sign of the lowest eigenvalue, far from zero
on either branch, is what counts. Not for scenes with drag (not conservative) or a seabed.
"""
from __future__ import annotations

import math

import casadi as ca
import numpy as np

#: an eigenvalue below -UNSTABLE_REL x the largest |eigenvalue| is a direction of descent
#: (an exact Hessian's eigenvalues carry a round-off of ~1e-16 of the largest)
UNSTABLE_REL = 1e-10


def lowest_eigenvalue(info, positions) -> tuple[float, float] | None:
    """(lowest eigenvalue, largest |eigenvalue|) of the energy's Hessian over the moving
    nodes, N/m; None where the check does not apply (drag, seabed, nothing moves)."""
    if info.drag or any(x["k_bed"] for x in info.secs):
        return None
    ds, EA, EI, w = (np.concatenate([np.full(x["segments"], v(x)) for x in info.secs])
                     for v in (lambda x: x["length"] / x["segments"], lambda x: x["EA"],
                               lambda x: x["EI"], lambda x: x["w"]))
    pos = np.asarray(positions, float)
    n = len(pos)
    ends = [info.ends["A"], info.ends["B"]]
    free = np.ones(n, dtype=bool)
    free[0], free[-1] = ends[0]["cond"] == "free", ends[1]["cond"] == "free"
    idx = np.flatnonzero(free)
    if idx.size == 0:
        return None
    y = ca.SX.sym("y", 2 * idx.size)
    X = [ca.SX(float(v)) for v in pos[:, 0]]
    Z = [ca.SX(float(v)) for v in pos[:, 1]]
    for k, i in enumerate(idx):
        X[i], Z[i] = y[2 * k], y[2 * k + 1]
    X, Z = ca.vertcat(*X), ca.vertcat(*Z)
    dx, dz = X[1:] - X[:-1], Z[1:] - Z[:-1]
    length = ca.sqrt(dx * dx + dz * dz)
    e = length / ca.DM(ds) - 1.0
    cable = ca.DM((EI <= 0.0).astype(float))
    e_eff = cable * ca.fmax(e, 0.0) + (1.0 - cable) * e
    energy = ca.sum1(0.5 * ca.DM(EA * ds) * e_eff * e_eff)

    def turn(ax, az, bx, bz):  # signed angle from a to b, wrap-free
        return ca.atan2(ax * bz - az * bx, ax * bx + az * bz)

    if len(ds) > 1:
        a = turn(dx[:-1], dz[:-1], dx[1:], dz[1:])
        h = 0.5 * (ds[:-1] + ds[1:])
        EI_int = 0.5 * (EI[:-1] + EI[1:])
        energy += ca.sum1(ca.DM(EI_int / h) * a * a / 2.0)
    for end, j in ((ends[0], 0), (ends[1], len(ds) - 1)):
        if end["cond"] == "clamped":
            c = math.radians(end["angle_deg"])
            a_end = turn(math.cos(c), math.sin(c), dx[j], dz[j])
            energy += EI[j] * a_end * a_end / ds[j]
    lumped = np.zeros(n)
    lumped[:-1] += 0.5 * w * ds
    lumped[1:] += 0.5 * w * ds
    energy += ca.dot(ca.DM(lumped), Z)
    for end, i in ((ends[0], 0), (ends[1], n - 1)):
        if end["cond"] == "free":
            energy -= end["force"][0] * X[i] + end["force"][1] * Z[i]
    H = ca.Function("H", [y], [ca.hessian(energy, y)[0]])
    y0 = np.ravel(np.stack([pos[idx, 0], pos[idx, 1]], axis=1))
    lam = np.linalg.eigvalsh(np.asarray(H(y0), float))
    return float(lam[0]), float(np.max(np.abs(lam)))


def is_stable(info, positions) -> bool | None:
    """True (stable), False (unstable) or None (not judged)."""
    r = lowest_eigenvalue(info, positions)
    if r is None:
        return None
    lo, big = r
    return bool(lo >= -UNSTABLE_REL * big)
