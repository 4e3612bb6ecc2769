"""The 3D cable's mass matrix (:mod:`.line`): structural and added mass, lumped per node or
consistent per element (Sun, Zhu & LaRosa), over the moving nodes."""
from __future__ import annotations

import math

import casadi as ca
import numpy as np

from ...scene import Scene

__all__ = ["added_mass_coefficients", "line_mass"]


def added_mass_coefficients(scene: Scene) -> tuple[np.ndarray, np.ndarray]:
    """Each segment's normal and tangential added-mass coefficients (N,) each."""
    can = np.array([s.line_type.ca_normal for s in scene.sections for _ in range(s.segments)])
    cat = np.array([s.line_type.ca_tangential for s in scene.sections for _ in range(s.segments)])
    return can, cat


def line_mass(scene: Scene, L: dict, Xm, V: list, t, rho: float, moving: list):
    """The mass matrix over the moving nodes (3 n_moving square), structural and added
    (normal, tangential), lumped (3 x 3 per node) or consistent (``scene.mass_matrix``),
    its numbers the ``line`` block's (``L``, :func:`_line_view`);
    the force of the held ends' accelerations through the consistent mass's coupling (None
    when lumped); and the held ends' accelerations ``{node: (3, 1)}``, m/s^2."""
    N = Xm.shape[1] - 1
    m_half = 0.5 * L["mass"] * L["ds"]
    ma_half = 0.5 * rho * (math.pi / 4.0) * L["d"] * L["d"] * L["ds"]
    blocks = [ca.SX.zeros(3, 3) for _ in range(N + 1)]
    halves = []  # each element's L0 B / 2
    can, cat = L["can"], L["cat"]
    for j in range(N):
        dx = Xm[:, j + 1] - Xm[:, j]
        tt = ca.mtimes(dx, dx.T) / ca.dot(dx, dx)
        blk = m_half[j] * ca.SX.eye(3) + ma_half[j] * (can[j] * (ca.SX.eye(3) - tt)
                                                       + cat[j] * tt)
        blocks[j] += blk
        blocks[j + 1] += blk
        halves.append(blk)
    # a prescribed end's acceleration reaches its neighbour through the consistent mass's
    # coupling; a table's (impulses at its rows) is left out
    acc = {i: (ca.jacobian(V[i], t) if end.motion is not None and end.motion.kind != "table"
               else ca.SX.zeros(3, 1)) for end, i in ((scene.end_a, 0), (scene.end_b, N))}
    if scene.mass_matrix == "lumped":
        return ca.diagcat(*[blocks[i] for i in moving]), None, acc
    mass, inertia = _consistent_mass(halves, acc, moving, N)
    return mass, inertia, acc


def _consistent_mass(halves, acc, moving, N):
    """The consistent mass of Sun, Zhu & LaRosa: element j's L0 B / 6 [[2, 1], [1, 2]] (B
    its mass per metre, 3 x 3, structural and added), from ``halves[j]`` = L0 B / 2 (what
    the lumped mass puts on each of its nodes): two thirds of a half on each node, one third
    coupling them.
    Returns (M over the moving nodes, sparse block-tridiagonal; the force -M_ih a_h on a
    moving node i beside a held node h, a_h = ``acc[h]`` the prescribed motion's
    acceleration)."""
    slot = {i: k for k, i in enumerate(moving)}
    M = ca.SX(3 * len(moving), 3 * len(moving))
    inertia = ca.SX.zeros(3 * len(moving), 1)
    rows = lambda i: slice(3 * slot[i], 3 * slot[i] + 3)  # noqa: E731
    for j, half in enumerate(halves):
        a, b = j, j + 1
        for i in (a, b):
            if i in slot:
                M[rows(i), rows(i)] = M[rows(i), rows(i)] + (2.0 / 3.0) * half
        if a in slot and b in slot:
            M[rows(a), rows(b)] = M[rows(a), rows(b)] + half / 3.0
            M[rows(b), rows(a)] = M[rows(b), rows(a)] + half / 3.0
        else:
            for i, h in ((a, b), (b, a)):
                if i in slot and h not in slot:
                    inertia[rows(i)] = inertia[rows(i)] - ca.mtimes(half / 3.0, acc[h])
    return M, inertia
