"""The spin of the rod's anchored reference frames in the twist's kinetic energy
(:mod:`symcable.models.rod`, notes/rod14.md section 1, notes/wire14.md).

The rod's twist theta_j is measured from the reference director d1_j = P(t0_j -> t_j) u0_j,
a function of the edge's tangent and its anchor. As the edge turns, d1_j spins about t_j at
s_j = d2_j . (d d1_j / dt) (zero while t_j = t0_j, O(|t_j - t0_j| |dt_j/dt|) elsewhere), so
the material frame spins at theta_j' + s_j, not theta_j'. The rod's Mechanism gives the twist
the kinetic energy I_j theta_j'^2 / 2 (I_j = m d^2 / 8 ds, its mass matrix's twist
entries): the frame's spin left out, an error that depends on the chart (how far each edge
has turned since its anchor).

:func:`with_reference_spin` adds it: the kinetic energy

    T = v^T M v / 2 + T_s,   T_s = sum_j I_j (theta_j' s_j + s_j^2 / 2),

with s_j = d2_j . (J_q d1_j v + d d1_j / dt) (the held ends' motion through t), and its
Lagrange equations: the mass M + d^2 T_s / dv^2 (coupling each twist with its edge's two
nodes; still a function of (q, t, p)) and the force f - (d p_s / dq) v - d p_s / dt +
dT_s/dq (p_s = dT_s/dv). T is then I_j (theta_j' + s_j)^2 / 2 per edge plus the rest:
the material frame's own spin, the same in every chart, so a run no longer depends on when
it re-anchors (tests/test_rod_api_reanchor.py). Statics are unchanged (T_s = 0 at rest with
the ends still); the output ``kinetic_energy`` is T.
"""
from __future__ import annotations

import dataclasses
import weakref

import casadi as ca
import numpy as np

from ..errors import SymcableError
from .mechanism import Mechanism, Output

__all__ = ["with_reference_spin"]

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


def reference_spins(mech: Mechanism) -> list:
    """[(index of theta_j in v, s_j)]: each twist's reference frame's spin rate s_j (rad/s,
    an expression of (q, v, t, p); module docstring), in edge order."""
    q, v, t = mech.q, mech.v, mech.t
    frame = ca.reshape(mech.outputs["reference_frame"].expr, 6, -1)
    column = {j: c for c, j in enumerate(frame_edges(mech))}
    out = []
    for i, j in twist_edges(mech):
        tj, d1 = frame[0:3, column[j]], frame[3:6, column[j]]
        rate = ca.jtimes(d1, q, v) + ca.jacobian(d1, t)
        out.append((int(i), ca.dot(ca.cross(tj, d1), rate)))
    return out


def with_reference_spin(mech: Mechanism) -> Mechanism:
    """The rod Mechanism ``mech`` with the reference frames' spin in the twist's kinetic
    energy (module docstring); built once per Mechanism. The same q, v, p, outputs (the
    kinetic energy T) and everything else. A Mechanism without anchored frames (no output
    ``reference_frame``: cable3d's, a hybrid with no rod edge): itself."""
    out = _CACHE.get(mech)
    if out is not None:
        return out
    if "reference_frame" not in mech.outputs:
        return mech  # no anchored frames (a hybrid with no rod edge is cable3d's): no spin
    if mech.kinematics is not None:
        raise SymcableError(f"mechanism {mech.name!r}: not a rod (no reference_frame output, "
                            "or kinematics other than q' = v)")
    q, v, t = mech.q, mech.v, mech.t
    T_s = ca.SX(0.0)
    for i, spin in reference_spins(mech):
        T_s += mech.mass[i, i] * (v[i] * spin + 0.5 * spin * spin)
    p_s = ca.gradient(T_s, v)
    mass = mech.mass + ca.hessian(T_s, v)[0]
    force = mech.force - ca.jtimes(p_s, q, v) - ca.jacobian(p_s, t) + ca.gradient(T_s, q)
    outputs = dict(mech.outputs)
    ke = mech.outputs.get("kinetic_energy")
    if ke is not None:
        outputs["kinetic_energy"] = Output(ke.expr + T_s, ke.unit, ke.owner,
                                           ke.description + " (with the reference frames' spin)")
    out = _CACHE[mech] = dataclasses.replace(mech, mass=mass, force=force, outputs=outputs,
                                             terms=tuple(mech.terms) + ("reference spin",))
    return out
