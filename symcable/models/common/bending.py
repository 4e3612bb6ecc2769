"""Optional bending of the cable3d line (line types with EI > 0): a discrete curvature
energy on node triplets, the discrete elastic rod of Bergou et al. (2008) without twist.

At a node between edges e1 = x_i - x_{i-1} and e2 = x_{i+1} - x_i, with turning angle phi,

    kb = 2 e1 x e2 / (|e1| |e2| + e1 . e2)        (|kb| = 2 tan(phi / 2), along the binormal),
    E_i = EI_i |kb|^2 / (2 lbar_i)                 (J),

lbar_i the mean of the two rest lengths. The factor 1/2 makes it the continuum energy
0.5 EI kappa^2 over the node's cell: kappa = phi / lbar, so E_i = 0.5 EI kappa^2 lbar + O(phi^4)
(EI |kb|^2 / lbar with lbar the MEAN of the rest lengths would be twice that: that is
DER's form with lbar their SUM). The forces are -grad E_i on the three nodes
(CasADi differentiates exactly), and the moment output is the vector
EI kb (1 + |kb|^2 / 4) / lbar = dE/dphi along the binormal (N m).

Where the terms are built (only where EI > 0: a line of EI = 0 gets none):

- interior nodes: EI_i the length-weighted HARMONIC mean of the two segments',
  (l1 + l2) / (l1 / EI_1 + l2 / EI_2): the turning angle is the moment times the cell's
  compliance l1 / (2 EI_1) + l2 / (2 EI_2) when the moment is continuous across a joint of
  two sections (an arithmetic mean is first order there). So a node between a segment with
  EI = 0 and one with EI > 0 gets no term: a cable cannot carry the moment, and the joint
  is a hinge;
- pinned and free ends: no term (no moment);
- a clamped end (``condition = "clamped"``, ``direction`` d, the tangent from A towards B):
  a held ghost node one first-segment length beyond the end along the clamp
  (x_0 - ds_0 d at end A, x_N + ds_N d at end B), turning with the end's translation but
  not rotating, and the end node's term with the first segment's EI and lbar = ds_0 / 2
  (half a cell lies in the line): the standard mirror-ghost clamp of finite differences,
  second order. The ghost's force goes to the clamp's reaction (the end force output).
"""
from __future__ import annotations

import casadi as ca
import numpy as np

from ...scene import EndCondition

__all__ = ["bending_kernel", "bending_nodes", "bending_terms", "linear_axial_law"]


def bending_kernel() -> ca.Function:
    """The bending term of one node triplet (module docstring): from the positions ``xp``,
    ``x``, ``xn`` (m), ``EI`` (N m^2) and ``lbar`` (m), the forces ``fp``, ``f``, ``fn`` on
    the three nodes (N), the energy ``E`` (J) and the moment vector ``M`` (N m)."""
    xp, x, xn = (ca.SX.sym(n, 3) for n in ("xp", "x", "xn"))
    EI, lbar = ca.SX.sym("EI"), ca.SX.sym("lbar")
    e1, e2 = x - xp, xn - x
    kb = 2.0 * ca.cross(e1, e2) / (ca.norm_2(e1) * ca.norm_2(e2) + ca.dot(e1, e2))
    k2 = ca.dot(kb, kb)
    E = 0.5 * EI * k2 / lbar
    g = ca.gradient(E, ca.vertcat(xp, x, xn))
    M = EI * kb * (1.0 + 0.25 * k2) / lbar
    return ca.Function("cable3d_bending", [xp, x, xn, EI, lbar],
                       [-g[0:3], -g[3:6], -g[6:9], E, M],
                       ["xp", "x", "xn", "EI", "lbar"], ["fp", "f", "fn", "E", "M"])


def bending_nodes(scene, seg: dict) -> list[tuple[int, float, float]]:
    """``(node, EI, lbar)`` of every node with a bending term (module docstring), node
    0..N; empty when the line has none."""
    ds, EI = seg["ds"], seg["EI"]
    N = len(ds)
    out = []
    for i in range(1, N):
        if EI[i - 1] > 0.0 and EI[i] > 0.0:
            ei = (ds[i - 1] + ds[i]) / (ds[i - 1] / EI[i - 1] + ds[i] / EI[i])
            out.append((i, float(ei), 0.5 * float(ds[i - 1] + ds[i])))
    for end, i, j in ((scene.end_a, 0, 0), (scene.end_b, N, N - 1)):
        if end.condition is EndCondition.CLAMPED and EI[j] > 0.0:
            out.append((i, float(EI[j]), 0.5 * float(ds[j])))
    return sorted(out)


def bending_terms(scene, seg: dict, Xm):
    """The bending of the line with node positions ``Xm`` (3, N+1): ``(nodal, ghosts,
    energy, moment)``: the forces on the nodes (3, N+1), N; those on the clamps' ghost
    nodes, {node: (3, 1)} (the clamp's reaction: add them to that end's force); the energy,
    J; the moment vectors (3, N+1), N m (zero at nodes without a term). None when the line
    has no bending term."""
    nodes = bending_nodes(scene, seg)
    if not nodes:
        return None
    N = Xm.shape[1] - 1
    ghost = {}
    for end, i, nb, j in ((scene.end_a, 0, 1, 0), (scene.end_b, N, N - 1, N - 1)):
        if end.condition is EndCondition.CLAMPED:
            sign = -1.0 if i == 0 else 1.0
            ghost[i] = Xm[:, i] + sign * float(seg["ds"][j]) * ca.DM(end.direction)
    prev, here, nxt = [], [], []
    for i, _, _ in nodes:
        prev.append(Xm[:, i - 1] if i > 0 else ghost[0])
        here.append(Xm[:, i])
        nxt.append(Xm[:, i + 1] if i < N else ghost[N])
    EI = ca.DM([e for _, e, _ in nodes]).T
    lbar = ca.DM([b for _, _, b in nodes]).T
    fp, f, fn, E, M = bending_kernel().map(len(nodes))(
        ca.horzcat(*prev), ca.horzcat(*here), ca.horzcat(*nxt), EI, lbar)
    nodal = ca.SX.zeros(3, N + 1)
    moment = ca.SX.zeros(3, N + 1)
    ghosts = {}
    for k, (i, _, _) in enumerate(nodes):
        nodal[:, i] += f[:, k]
        moment[:, i] = M[:, k]
        if i > 0:
            nodal[:, i - 1] += fp[:, k]
        else:
            ghosts[0] = fp[:, k]
        if i < N:
            nodal[:, i + 1] += fn[:, k]
        else:
            ghosts[N] = fn[:, k]
    return nodal, ghosts, ca.sum2(E), moment


def linear_axial_law(seg: dict, law: dict) -> dict:
    """The tension-only law of :func:`~symcable.models.common.segments.slack_law` with the segments
    that have EI > 0 carrying compression (the linear law EA e, as the planar line's:
    EA_slack = EA, so the smoothed corner drops out; its NaNs replaced)."""
    rod = seg["EI"] > 0.0
    if not np.any(rod):
        return law
    return dict(law, EA_slack=np.where(rod, seg["EA"], law["EA_slack"]),
                delta=np.where(rod, 1.0, law["delta"]))
