"""A start for a cable (planar or 3D) from the minimum of its potential energy.

A line without bending, on which only its weight, the seabed's contact and the forces on its
free ends act, is in equilibrium exactly where the potential energy of its discrete chain is
stationary:

    E(x) = sum_j ds_j U(e_j) + sum_i W_i z_i + sum_i k b_i R(-depth - z_i) - sum_free f . x,

with e_j = |x_{j+1} - x_j| / ds_j - 1 the strain of segment j, U(e) the integral of the
tension-only law T(e) (:func:`~symcable.models.common.terms.cable_axial_force`), W_i the weight
lumped on node i (half of each adjacent segment, as in the residual), and R the integral of
the smoothed contact ramp with b_i the node's tributary contact width. These are the
residual's own terms, so the minimum, with each segment's angle and strain taken from its
end positions, solves the planar equations to the minimiser's tolerance. The energy is
convex up to the slack law's residual push (1e-7 of the force scale), so a minimiser with a
line search on it (IPOPT) reaches the equilibrium from far away, through the slack piles,
folds and touchdowns where Newton on the equations, whose slack directions are nearly
singular, diverges. Drag is not conservative and is left out; the solver continues in the
current from this start.
"""
from __future__ import annotations

from typing import Callable

import casadi as ca
import numpy as np

from ...scene import EndCondition
from . import terms
from .drag import law_drag_loads

__all__ = ["drag_loads", "relax_line", "relaxed_network", "relaxed_positions"]

#: IPOPT's iterations and tolerance (on the scaled energy: forces relative to the force
#: scale) for the start; Newton on the equations polishes what is left
RELAX_MAX_ITER, RELAX_TOL = 3000, 1e-10
#: the minimised energy's slack law is this much stiffer in compression and smoother at its
#: corner than the equations' (1e-4 of the force scale per unit strain; the corner where
#: the tension is 1e-3 of it): with the equations' own law the energy is nearly flat along a
#: slack pile, and IPOPT's Newton steps along it (hundreds of line lengths) fail ("Error in
#: step computation"). A pile's shape hardly depends
#: on how little it resists, and Newton on the equations polishes the rest
RELAX_WIDER = 1e3
#: minimisations with the drag frozen at the last shape (then one with the exact law)
DRAG_PASSES = 6


def _ramp_integral(x, delta):
    """The integral from 0 of max(x, 0) smoothed over ``delta``
    (:func:`~symcable.models.common.terms.smooth_ramp`), up to a constant."""
    root = ca.sqrt(x * x + delta * delta)
    return 0.25 * (x * x + x * root + delta * delta * ca.asinh(x / delta))


def _strain_energy(X, seg: dict, law: dict, wider):
    """The elastic energy of a chain of nodes X (one column per coordinate, (N+1,) each):
    sum_j ds_j U(e_j), U the integral of the tension-only law with its slack part widened by
    ``wider``."""
    d = [x[1:] - x[:-1] for x in X]
    ds, EA = ca.DM(seg["ds"]), ca.DM(seg["EA"])
    e = ca.sqrt(sum(di * di for di in d)) / ds - 1.0
    EA_s = ca.DM(law["EA_slack"]) * wider
    delta = ca.DM(law["delta"]) * wider
    U = (0.5 * EA_s * e * e + (EA - EA_s) * _ramp_integral(e, delta)
         + law["F_wall"] * law["w_wall"] * ca.exp(-(1.0 + e) / law["w_wall"]))
    return ca.sum1(ds * U)


def relaxed_positions(seg: dict, pos0: np.ndarray, free: np.ndarray, law: dict,
                      node_weight: np.ndarray, end_forces: np.ndarray,
                      contact: tuple | None, force_scale: float,
                      loads: Callable[[np.ndarray], np.ndarray] | None = None
                      ) -> np.ndarray | None:
    """Node positions (N+1, dim), m, at the minimum of the line's potential energy (module
    docstring), from ``pos0`` (N+1, dim: planar (x, z) or 3D (x, y, z), the last coordinate
    up); None when the minimiser ends on non-finite numbers.

    ``free``: (N+1,) bool, the nodes that move (held ends keep ``pos0``); ``law``: the
    tension-only law (:func:`~symcable.models.common.segments.slack_law`, every segment a cable);
    ``node_weight``: (N+1,) N, downward; ``end_forces``: (N+1, dim) N applied on free nodes;
    ``contact``: (depth, stiffness Pa, smoothing m, tributary widths (N+1,) m) or None;
    ``loads``: position-dependent nodal loads (N+1, dim), N, that are not conservative (drag):
    held fixed while the energy is minimised, then evaluated at the minimum and the minimum
    sought again (DRAG_PASSES times, each load the mean of the last two)."""
    pos0 = np.asarray(pos0, float)
    n, dim = pos0.shape
    idx = np.flatnonzero(free)
    L = float(np.sum(seg["ds"]))
    y = ca.SX.sym("y", dim * idx.size)
    cols = [[ca.SX(float(v)) for v in pos0[:, c]] for c in range(dim)]
    for k, i in enumerate(idx):  # unknowns: displacement from pos0 relative to the length
        for c in range(dim):
            cols[c][i] = pos0[i, c] + L * y[dim * k + c]
    X = [ca.vertcat(*col) for col in cols]
    Z = X[-1]  # up
    wider = ca.SX.sym("wider")  # the law's regularisation (RELAX_WIDER, then 1)
    energy = _strain_energy(X, seg, law, wider) + ca.dot(ca.DM(node_weight), Z)
    applied = ca.SX.sym("applied", dim * n)  # nodal loads, frozen: (x, [y,] z) per node
    energy -= sum(ca.dot(applied[c::dim], X[c]) for c in range(dim))
    if contact is not None:
        depth, k, width, trib = contact
        on = ca.DM(np.where(free, k * np.asarray(trib, float), 0.0))
        energy += ca.dot(on, _ramp_integral(-depth - Z, width))
    nlp = {"x": y, "p": ca.vertcat(wider, applied), "f": energy / (force_scale * L)}
    opts = {"ipopt.print_level": 0, "print_time": False, "ipopt.sb": "yes",
            "ipopt.max_iter": RELAX_MAX_ITER, "ipopt.tol": RELAX_TOL,
            "show_eval_warnings": False}

    def positions(yv):
        pos = pos0.copy()
        pos[idx] += L * yv.reshape(-1, dim)
        return pos

    fixed = np.asarray(end_forces, float)
    f = fixed + (loads(pos0) if loads is not None else 0.0)
    yv = np.zeros(dim * idx.size)
    passes = [RELAX_WIDER] * (DRAG_PASSES if loads is not None else 1) + [1.0]
    try:
        solver = ca.nlpsol("relax", "ipopt", nlp, opts)
        # regularised, then with the equations' own law from there (kept only when it ends
        # well: on a pile the exact law's flat energy may stall it)
        for k, factor in enumerate(passes):
            sol = solver(x0=yv, p=np.concatenate([[factor], f.ravel()]))
            y_new = np.asarray(sol["x"], float).ravel()
            if factor != 1.0 or (solver.stats()["success"] and np.all(np.isfinite(y_new))):
                yv = y_new
            if loads is not None and k + 2 < len(passes) and np.all(np.isfinite(yv)):
                f = 0.5 * f + 0.5 * (fixed + loads(positions(yv)))
    except RuntimeError:
        return None
    if not np.all(np.isfinite(yv)):
        return None
    return positions(yv)


def drag_loads(env, seg: dict) -> Callable[[np.ndarray], np.ndarray]:
    """Nodal drag of the environment's uniform current on a line at rest, as a function of
    the node positions (N+1, dim) -> (N+1, dim), N: the Morison law of the residuals
    (:func:`~symcable.models.common.terms.morison_drag`: 0.5 rho d Cd |u| u sqrt(1 + e) per
    unstretched metre, split along and across each segment) in numbers, each segment's half
    on each of its nodes. Planar or 3D (the current has the positions' dimension)."""
    if "drag_law" in seg:  # a cable3d line with loading functions
        return law_drag_loads(env, seg, seg["drag_law"])
    u = np.asarray(env.current, float)
    k = 0.5 * env.water_density * seg["d"] * seg["ds"]

    def loads(pos):
        d = np.diff(pos, axis=0)
        length = np.maximum(np.linalg.norm(d, axis=1), 1e-300)
        t = d / length[:, None]
        ut = t @ u
        un = u[None, :] - ut[:, None] * t  # the normal part, a vector
        un_abs = np.linalg.norm(un, axis=1)
        stretch = np.sqrt(length / seg["ds"])
        f = (k * stretch)[:, None] * ((seg["cdt"] * np.abs(ut) * ut)[:, None] * t
                                      + (seg["cdn"] * un_abs)[:, None] * un)
        out = np.zeros_like(pos, dtype=float)
        out[:-1] += 0.5 * f
        out[1:] += 0.5 * f
        return out

    return loads


def relax_line(scene, seg: dict, pos0: np.ndarray, law: dict,
               force_scale: float) -> np.ndarray | None:
    """:func:`relaxed_positions` of a one-line scene (planar or 3D: the dimension of
    ``pos0``): its held ends at their positions, the weight lumped on the nodes, the free
    ends' forces, the seabed's contact and the current's drag as the residuals have them;
    ``law`` the tension-only law (:func:`~symcable.models.common.segments.slack_law`)."""
    a, b = scene.end_a, scene.end_b
    N = len(seg["ds"])
    free = np.ones(N + 1, dtype=bool)
    free[0], free[N] = a.condition is EndCondition.FREE, b.condition is EndCondition.FREE
    pos0 = np.array(pos0, dtype=float)
    forces = np.zeros_like(pos0)
    for end, node in ((a, 0), (b, N)):
        if free[node]:
            if end.force is not None:
                forces[node] = end.force
        else:
            pos0[node] = end.position
    lumped = np.zeros(N + 1)
    lumped[:-1] += 0.5 * seg["w"] * seg["ds"]
    lumped[1:] += 0.5 * seg["w"] * seg["ds"]
    contact = None
    if scene.seabed is not None:
        width = np.zeros(N + 1)
        width[:-1] += 0.5 * seg["d"] * seg["ds"]
        width[1:] += 0.5 * seg["d"] * seg["ds"]
        k = scene.seabed.stiffness
        contact = (scene.environment.depth, k,
                   terms.contact_smoothing(float(np.max(seg["w"])), k, float(np.min(seg["d"]))),
                   width)
    env = scene.environment
    drag = None if env.in_air or not any(env.current) else drag_loads(env, seg)
    return relaxed_positions(seg, pos0, free, law, lumped, forces, contact, force_scale, drag)


def relaxed_network(chains: list[dict], point_weight: np.ndarray, point_force: np.ndarray,
                    force_scale: float, point_contact: tuple | None = None
                    ) -> list[np.ndarray] | None:
    """Node positions of several lines joined at shared nodes (points), m, at the minimum of
    their potential energy: :func:`relaxed_positions` for a network (each line's strain
    energy, lumped weight, contact and frozen drag as there) plus the points' own loads.

    ``chains``: one dict per line: ``seg``, ``law`` (its tension-only law), ``pos0`` (N+1, 3)
    m, ``ids`` (N+1,) int (-1: held at ``pos0``; else the index of the free node, shared by
    the lines that meet there), ``node_weight`` (N+1,) N, ``contact`` (as
    :func:`relaxed_positions`, or None), ``loads`` (the drag, or None).
    ``point_weight`` (n_free,) N downward and ``point_force`` (n_free, 3) N: constant loads on
    the free nodes (a point's weight less its buoyancy, its applied force and its drag in the
    current). ``point_contact``: (depth m, stiffness (n_free,) N/m, smoothing width (n_free,)
    m) of the free nodes' own seabed contact (a point's: K ramp(-depth - z)), or None.
    Returns the positions (N+1, 3) of each line, or None when the minimiser ends on
    non-finite numbers."""
    n_free = len(point_weight)
    x0 = np.zeros((n_free, 3))
    for c in chains:
        for i, k in enumerate(c["ids"]):
            if k >= 0:
                x0[k] = c["pos0"][i]
    L = max(float(np.sum(c["seg"]["ds"])) for c in chains)
    y = ca.SX.sym("y", 3 * n_free)
    nodes = [ca.DM(x0[k]) + L * y[3 * k:3 * k + 3] for k in range(n_free)]
    wider = ca.SX.sym("wider")
    energy = ca.dot(ca.DM(point_weight), ca.vertcat(*[nd[2] for nd in nodes])) \
        - ca.dot(ca.DM(np.asarray(point_force, float).ravel()), ca.vertcat(*nodes))
    if point_contact is not None:
        depth, stiff, width = point_contact
        energy += sum(float(stiff[k]) * _ramp_integral(-depth - nodes[k][2], float(width[k]))
                      for k in range(n_free) if stiff[k] > 0)
    frozen = []
    for c in chains:
        cols = [[nodes[k][j] if k >= 0 else ca.SX(float(c["pos0"][i, j]))
                 for i, k in enumerate(c["ids"])] for j in range(3)]
        X = [ca.vertcat(*col) for col in cols]
        energy += _strain_energy(X, c["seg"], c["law"], wider) + ca.dot(ca.DM(c["node_weight"]), X[2])
        applied = ca.SX.sym("applied", 3 * len(c["ids"]))
        frozen.append(applied)
        energy -= sum(ca.dot(applied[j::3], X[j]) for j in range(3))
        if c["contact"] is not None:
            depth, k, width, trib = c["contact"]
            on = ca.DM(np.where(np.asarray(c["ids"]) >= 0, k * np.asarray(trib, float), 0.0))
            energy += ca.dot(on, _ramp_integral(-depth - X[2], width))
    nlp = {"x": y, "p": ca.vertcat(wider, *frozen), "f": energy / (force_scale * L)}
    opts = {"ipopt.print_level": 0, "print_time": False, "ipopt.sb": "yes",
            "ipopt.max_iter": RELAX_MAX_ITER, "ipopt.tol": RELAX_TOL, "show_eval_warnings": False}

    def positions(yv):
        xs = x0 + L * yv.reshape(-1, 3)
        out = []
        for c in chains:
            pos = np.array(c["pos0"], float)
            ids = np.asarray(c["ids"])
            pos[ids >= 0] = xs[ids[ids >= 0]]
            out.append(pos)
        return out

    def loads(yv):
        return np.concatenate([(c["loads"](pos) if c["loads"] is not None
                                else np.zeros_like(pos)).ravel()
                               for c, pos in zip(chains, positions(yv))])

    dragged = any(c["loads"] is not None for c in chains)
    yv = np.zeros(3 * n_free)
    f = loads(yv)
    passes = [RELAX_WIDER] * (DRAG_PASSES if dragged else 1) + [1.0]
    try:
        solver = ca.nlpsol("relax_network", "ipopt", nlp, opts)
        for k, factor in enumerate(passes):
            sol = solver(x0=yv, p=np.concatenate([[factor], f]))
            y_new = np.asarray(sol["x"], float).ravel()
            if factor != 1.0 or (solver.stats()["success"] and np.all(np.isfinite(y_new))):
                yv = y_new
            if dragged and k + 2 < len(passes) and np.all(np.isfinite(yv)):
                f = 0.5 * f + 0.5 * loads(yv)
    except RuntimeError:
        return None
    if not np.all(np.isfinite(yv)):
        return None
    return positions(yv)
