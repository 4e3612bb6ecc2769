"""The spin of the rod's anchored reference frames in the twist's kinetic energy
(:mod:`symcable.models.rod.rod`).

The rod's twist theta_j is measured from the reference director d1_j = P(t0_j -> t_j) u0_j,
a function of the edge's tangent and its anchor. As the edge turns, d1_j spins about t_j at
s_j = d2_j . (d d1_j / dt) (zero while t_j = t0_j, O(|t_j - t0_j| |dt_j/dt|) elsewhere), so
the material frame spins at theta_j' + s_j, not theta_j'. The rod's Mechanism gives the twist
the kinetic energy I_j theta_j'^2 / 2 (I_j = m d^2 / 8 ds, its mass matrix's twist
entries): the frame's spin left out, an error that depends on the chart (how far each edge
has turned since its anchor).

:func:`with_reference_spin` adds it: the kinetic energy

    T = v^T M v / 2 + T_s,   T_s = sum_j I_j (theta_j' s_j + s_j^2 / 2),

with s_j = d2_j . (J_q d1_j v + d d1_j / dt) (the held ends' motion through t), which is
s_j = c_j . e_j' in closed form (:func:`spin_coefficient`: e_j the edge vector, c_j a
function of e_j and the anchor's tangent only), and its Lagrange equations: the mass
M + d^2 T_s / dv^2 (coupling each twist with its edge's two nodes; still a function of
(q, t, p)) and the force f - (d p_s / dq) v - d p_s / dt + dT_s/dq (p_s = dT_s/dv), written
out per edge (:func:`with_reference_spin`; by CasADi over the whole Mechanism they make the
step's Jacobian several times larger). T is then I_j (theta_j' + s_j)^2 / 2 per edge plus
the rest: the material frame's own spin, the same in every chart, so a run no longer depends
on when it re-anchors. Statics are unchanged (T_s = 0 at rest with the ends still); the
output ``kinetic_energy`` is T.
"""
from __future__ import annotations

import dataclasses
import weakref

import casadi as ca
import numpy as np

from ...errors import SymcableError
from ...mechanism.mechanism import Mechanism, Output

__all__ = ["edge_spins", "reference_spins", "spin_coefficient", "with_reference_spin",
           "with_reference_spin_ad"]

_CACHE: "weakref.WeakKeyDictionary[Mechanism, Mechanism]" = weakref.WeakKeyDictionary()


def _deps(expr, q, rows) -> list:
    """For each row group of ``expr`` (a list of row index lists), the q entries it depends
    on (structurally)."""
    S = ca.jacobian(expr, q).sparsity()
    r, c = S.get_triplet()
    by_row: dict = {}
    for i, j in zip(r, c):
        by_row.setdefault(i, set()).add(j)
    return [sorted(set().union(*(by_row.get(i, set()) for i in g))) for g in rows]


def twist_edges(mech: Mechanism) -> list:
    """[(index of theta_j in q and v, edge j)] of a rod or hybrid Mechanism, in edge order
    (from the structure of its ``twist_angles`` output: edge j's entry is q[k] or 0)."""
    th = ca.vec(mech.outputs["twist_angles"].expr)
    deps = _deps(th, mech.q, [[j] for j in range(th.shape[0])])
    return [(d[0], j) for j, d in enumerate(deps) if len(d) == 1]


def frame_edges(mech: Mechanism) -> list:
    """The edge of each column of the ``reference_frame`` output (6 rows per rod edge; a
    hybrid's cable3d edges have none), from the nodes its tangent depends on."""
    ref = ca.vec(mech.outputs["reference_frame"].expr)
    n_col = ref.shape[0] // 6
    node_of = {}
    for i, row in enumerate(np.asarray(mech.layout.parts["line"].node_q)):
        for k in row:
            if k >= 0:
                node_of[int(k)] = i
    N = len(mech.layout.parts["line"].s) - 1
    held = {i for i, row in enumerate(np.asarray(mech.layout.parts["line"].node_q))
            if row[0] < 0}
    out = []
    for d in _deps(ref, mech.q, [list(range(6 * c, 6 * c + 3)) for c in range(n_col)]):
        nodes = sorted({node_of[k] for k in d if k in node_of})
        if len(nodes) == 2:
            out.append(nodes[0])
        elif len(nodes) == 1 and nodes[0] == 1 and 0 in held:
            out.append(0)
        elif len(nodes) == 1 and nodes[0] == N - 1 and N in held:
            out.append(N - 1)
        else:
            raise SymcableError(f"mechanism {mech.name!r}: reference_frame column {len(out)} "
                                f"follows no single edge (nodes {nodes})")
    return out


def edge_spins(mech: Mechanism) -> list:
    """[(index of theta_j in v, I_j, e_j, e_j', c_j, a_j)] per twist: the edge vector e_j (m; an
    expression of q, t, p), its rate e_j' (m/s, of v, t, p: de_j/dt, a held end's through its
    position's derivative, as the transports' spin d2 . d d1/dt takes it), the
    twist's inertia I_j (kg m^2, its mass matrix entry) and the spin's coefficient c_j
    (1/m): s_j = c_j . e_j' (module docstring), with a_j the anchor's tangent."""
    q, v = mech.q, mech.v
    frame = ca.reshape(mech.p[mech.params.slice("frame")], 6, -1)
    column = {j: c for c, j in enumerate(frame_edges(mech))}
    X = mech.outputs["positions"].expr
    # q' (v for the nodes and twists; first-order states such as friction bristles after
    # them have their own rates, which no edge depends on)
    rate = v if mech.kinematics is None else mech.kinematics
    out = []
    for i, j in twist_edges(mech):
        e = (X[j + 1, :] - X[j, :]).T
        ed = ca.jtimes(e, q, rate) + ca.jacobian(e, mech.t)  # de/dt (a held end's position rate)
        out.append((int(i), mech.mass[i, i], e, ed, spin_coefficient(e, frame[0:3, column[j]]),
                    frame[0:3, column[j]]))
    return out


def _edge_kernel() -> ca.Function:
    """``(e, e', de'/dt, a, I, theta') -> (c, f_theta, f_x)``: one edge's spin coefficient
    and the spin's generalized forces on its twist and on its edge vector
    (:func:`with_reference_spin`; e' the edge's rate, de'/dt its explicit time derivative:
    a held end's acceleration). Inlined: as a call (never_inline, like the vertex kernel's
    option) the step grows (more instructions, a slower step in C): its forward calls, one
    per direction, cost more than its few hundred operations."""
    e, ed, edd, a = (ca.SX.sym(k, 3) for k in ("e", "ed", "edd", "a"))
    I, thd = ca.SX.sym("I"), ca.SX.sym("thd")
    c = spin_coefficient(e, a)
    s = ca.dot(c, ed)
    s_p = ca.dot(ca.jtimes(c, e, ed), ed) + ca.dot(c, edd)  # ds/dt at zero acceleration
    le = ca.norm_2(e)
    P = I * (thd + s)
    return ca.Function("rod_spin_edge", [e, ed, edd, a, I, thd],
                       [c, -I * s_p, -(I * s_p) * c - P * ca.cross(ed, e) / (le * le * le)],
                       ["e", "ed", "edd", "a", "I", "thd"], ["c", "f_theta", "f_x"])


def spin_coefficient(e, a):
    """c (1/m) such that the spin of the reference director P(a -> t) u about t = e / |e|
    is s = c . e' for any u perpendicular to the anchor's tangent a:
    c = (e x a) / (|e| (|e| + a . e)), the connection of the sphere in the gauge of the
    smallest rotation from a (a Dirac monopole's vector potential, singular at t = -a like
    the map itself); its curl is -e / |e|^3, so (dc/de) w - (dc/de)^T w = (w x e) / |e|^3."""
    n = ca.norm_2(e)
    return ca.cross(e, a) / (n * (n + ca.dot(a, e)))


def reference_spins(mech: Mechanism) -> list:
    """[(index of theta_j in v, s_j)]: each twist's reference frame's spin rate s_j (rad/s,
    an expression of (q, v, t, p); module docstring), in edge order."""
    return [(i, ca.dot(c, ed)) for i, _, _, ed, c, _ in edge_spins(mech)]


def with_reference_spin(mech: Mechanism) -> Mechanism:
    """The rod Mechanism ``mech`` with the reference frames' spin in the twist's kinetic
    energy (module docstring); built once per Mechanism. The same q, v, p, outputs (the
    kinetic energy T) and everything else. A Mechanism without anchored frames (no output
    ``reference_frame``: cable3d's, a hybrid with no rod edge): itself.

    The Lagrange terms in closed form per edge (:func:`edge_spins`, :func:`_edge_kernel`;
    P = I (theta' + s), S = de'/dv the edge's +-1 node selection): T_s's mass
    I (g g^T - e_th e_th^T) with g = e_th + S^T c, and the force
    -(e_th + S^T c) I s_p - S^T P [(dc/de) e' - (dc/de)^T e'] with s_p = ds/dt at zero
    acceleration; the bracket is (e' x e) / |e|^3 (the curl of c). The same equations as
    CasADi's of T_s (:func:`with_reference_spin_ad`; to round-off), with far fewer operations
    in the step's Jacobian."""
    out = _CACHE.get(mech)
    if out is not None:
        return out
    if "reference_frame" not in mech.outputs:
        return mech  # no anchored frames (a hybrid with no rod edge is cable3d's): no spin
    v, t = mech.v, mech.t
    n = mech.n_v
    T_s = ca.SX(0.0)
    mass = ca.SX(mech.mass)
    force = ca.SX(mech.force)
    kernel = _edge_kernel()
    for i, I, e, ed, c, a in edge_spins(mech):
        c, f_th, f_x = kernel(e, ed, ca.jacobian(ed, t), a, I, v[i])
        s = ca.dot(c, ed)
        T_s += I * (v[i] * s + 0.5 * s * s)
        S = ca.jacobian(ed, v)  # constant: +-1 on the edge's moving nodes
        ei = ca.SX(n, 1)
        ei[i] = 1.0
        gx = ca.mtimes(S.T, c)
        mass += I * (ca.mtimes(gx, gx.T) + ca.mtimes(gx, ei.T) + ca.mtimes(ei, gx.T))
        force += ei * f_th + ca.mtimes(S.T, f_x)
    outputs = dict(mech.outputs)
    ke = mech.outputs.get("kinetic_energy")
    if ke is not None:
        outputs["kinetic_energy"] = Output(ke.expr + T_s, ke.unit, ke.owner,
                                           ke.description + " (with the reference frames' spin)")
    out = _CACHE[mech] = dataclasses.replace(mech, mass=mass, force=force, outputs=outputs,
                                             terms=tuple(mech.terms) + ("reference spin",))
    return out


def with_reference_spin_ad(mech: Mechanism) -> Mechanism:
    """:func:`with_reference_spin` with its Lagrange terms by CasADi (the first version:
    the mass d^2 T_s / dv^2 and the force -(dp_s/dq) v - dp_s/dt + dT_s/dq): the reference
    the closed form is checked against; not cached."""
    q, v, t = mech.q, mech.v, mech.t
    frame = ca.reshape(mech.outputs["reference_frame"].expr, 6, -1)
    column = {j: c for c, j in enumerate(frame_edges(mech))}
    T_s = ca.SX(0.0)
    for i, j in twist_edges(mech):  # s_j = d2_j . d1_j' by CasADi, from the transports
        tj, d1 = frame[0:3, column[j]], frame[3:6, column[j]]
        spin = ca.dot(ca.cross(tj, d1), ca.jtimes(d1, q, v) + ca.jacobian(d1, t))
        T_s += mech.mass[i, i] * (v[i] * spin + 0.5 * spin * spin)
    p_s = ca.gradient(T_s, v)
    mass = mech.mass + ca.hessian(T_s, v)[0]
    force = mech.force - ca.jtimes(p_s, q, v) - ca.jacobian(p_s, t) + ca.gradient(T_s, q)
    return dataclasses.replace(mech, mass=mass, force=force,
                               terms=tuple(mech.terms) + ("reference spin",))
