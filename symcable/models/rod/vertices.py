"""The rod's vertices (:mod:`.rod`): the bending and twisting energy of
:func:`~.frames.vertex_kernel` on each interior node and on a clamp's or guide's ghost edge,
mapped over the vertices and scattered on the nodes and edges, cable3d's own bending on
the cable3d edges of a hybrid (:func:`~.hybrid_terms.cable_bending`), and the internal
force across each edge."""
from __future__ import annotations

from dataclasses import dataclass

import casadi as ca
import numpy as np

from ...scene import Scene
from .frames import reference_director, vertex_kernel
from .hybrid_terms import cable_bending, rod_vertices


def _clamp_frame(end) -> tuple[np.ndarray, np.ndarray]:
    """A clamp's (direction, reference director), numpy."""
    d = np.asarray(end.direction, float)
    return d, reference_director(d)


def _ghosts(scene: Scene, seg: dict, rod: np.ndarray, Xm, theta: list, frame, col, p, sl,
            clamped: list, guided: list) -> dict:
    """The ghost edges of clamped and guided ends, {node 0 or N: (ghost node position (3, 1),
    m; its twist, rad; its tangent and reference director (3, 1) each)}."""
    N = len(seg["ds"])
    ghost = {}
    for k, (end, i, j) in enumerate(((scene.end_a, 0, 0), (scene.end_b, N, N - 1))):
        sign = -1.0 if i == 0 else 1.0
        if clamped[k]:
            d, u = _clamp_frame(end)
            ghost[i] = (Xm[:, i] + sign * float(seg["ds"][j]) * ca.DM(d),
                        p[sl("end_a.twist" if i == 0 else "end_b.twist")], ca.DM(d), ca.DM(u))
        elif guided[k]:  # the neighbour edge's twist and anchor: no twist across the guide
            d = ca.DM(np.asarray(end.direction, float))
            ghost[i] = (Xm[:, i] + sign * float(seg["ds"][j]) * d, theta[j],
                        frame[0:3, col[j]] if rod[j] else None,
                        frame[3:6, col[j]] if rod[j] else None)
    return ghost


def _vertex_columns(seg: dict, rod: np.ndarray, verts: list, ghost: dict, Xm, theta: list,
                    frame, col, guided: list, coupled: bool) -> dict:
    """The vertex kernel's arguments, one list per argument with one entry per vertex
    (:func:`~.frames.vertex_kernel`: neighbour positions, twists, anchors, stiffnesses, GJ,
    lbar and, when ``coupled``, the tension-torsion coupling's)."""
    N = len(seg["ds"])
    stiff = lambda j: ca.DM([seg["EI"][j], seg["EI2"][j]])  # noqa: E731
    cols = {k: [] for k in ("xp", "x", "xn", "thp", "thn", "t0p", "u0p", "t0n", "u0n", "Bp",
                            "Bn", "GJ", "lbar") + (("K", "dsp", "dsn", "wp", "wn")
                                                   if coupled else ())}
    for i, jp, jn, lbar in verts:
        gp, gn = ghost.get(0) if jp < 0 else None, ghost.get(N) if jn >= N else None
        cols["xp"].append(gp[0] if gp else Xm[:, i - 1])
        cols["x"].append(Xm[:, i])
        cols["xn"].append(gn[0] if gn else Xm[:, i + 1])
        cols["thp"].append(gp[1] if gp else theta[jp])
        cols["thn"].append(gn[1] if gn else theta[jn])
        cols["t0p"].append(gp[2] if gp else frame[0:3, col[jp]])
        cols["u0p"].append(gp[3] if gp else frame[3:6, col[jp]])
        cols["t0n"].append(gn[2] if gn else frame[0:3, col[jn]])
        cols["u0n"].append(gn[3] if gn else frame[3:6, col[jn]])
        jp_, jn_ = max(jp, 0), min(jn, N - 1)
        cols["Bp"].append(stiff(jp_))
        cols["Bn"].append(stiff(jn_))
        # the joint of two sections: the harmonic mean of GJ over the cell (as cable3d's EI)
        ds_p, ds_n = seg["ds"][jp_], seg["ds"][jn_]
        at_guide = (jp < 0 and guided[0]) or (jn >= N and guided[1])
        cols["GJ"].append(0.0 if at_guide else
                          (ds_p + ds_n) / (ds_p / seg["GJ"][jp_] + ds_n / seg["GJ"][jn_]))
        cols["lbar"].append(lbar)
        if coupled:  # each edge's share of the cell (a ghost has none)
            wp, wn = (0.0 if jp < 0 else ds_p / 2), (0.0 if jn >= N else ds_n / 2)
            wp, wn = wp / (wp + wn), wn / (wp + wn)
            cols["K"].append(0.0 if at_guide else wp * seg["K"][jp_] + wn * seg["K"][jn_])
            cols["dsp"].append(ds_p)
            cols["dsn"].append(ds_n)
            cols["wp"].append(wp)
            cols["wn"].append(wn)
    return cols


@dataclass
class _VertexTerms:
    """The bending and twisting of the line: the nodal forces with them added (3, N+1), N;
    the edges' twisting torques (1, N), N m; the held ends' reactions {0, N: (3, 1)}, N;
    the vertices (node, previous edge, next edge, lbar); the vertex kernel's forces on each
    vertex's previous and next node ``fp``, ``fn`` (3, n_vertices), N, and energies ``E``
    (1, n_vertices), J; per node the bending moment (3, N+1), N m, material curvatures
    (2, N+1), 1/m, twist (1, N+1), rad, and twisting moment (1, N+1), N m; cable3d's own
    bending on the cable3d edges (:func:`~.hybrid_terms.cable_bending`, or None); whether
    tension and torsion are coupled."""

    nodal: object
    torque: object
    reaction: dict
    verts: list
    fp: object
    fn: object
    E: object
    moment: object
    kap: object
    tw: object
    mt: object
    cb: dict | None
    coupled: bool


def _vertex_terms(scene: Scene, seg: dict, rod: np.ndarray, Xm, theta: list, frame, col, p,
                  sl, clamped: list, guided: list, nodal) -> _VertexTerms:
    """The vertex kernel mapped over the vertices (interior nodes, and a clamp's or guide's
    ghost edge -1 / N) and scattered on the nodes and edges, added to ``nodal`` (3, N+1)."""
    N = len(seg["ds"])
    torque = ca.SX.zeros(1, N)
    held = [clamped[k] or guided[k] for k in (0, 1)]
    verts = rod_vertices(rod, seg["ds"], held)
    ghost = _ghosts(scene, seg, rod, Xm, theta, frame, col, p, sl, clamped, guided)
    coupled = bool(np.any(seg["K"][rod] != 0.0))
    cols = _vertex_columns(seg, rod, verts, ghost, Xm, theta, frame, col, guided, coupled)
    iso = bool(np.all(seg["EI"][rod] == seg["EI2"][rod]))
    if verts:
        kernel = vertex_kernel(iso, coupled, vertices=len(verts))
        out = kernel.map(len(verts))(*[ca.horzcat(*c) for c in cols.values()])
    else:
        out = [ca.SX.zeros(n, 0) for n in (3, 3, 3, 1, 1, 1, 2, 1, 3, 1)]
    fp, f, fn, qp, qn, E, kappa, twist, M, Mt = out
    reaction = {0: ca.SX.zeros(3, 1), N: ca.SX.zeros(3, 1)}
    nv = N + 1
    moment = ca.SX.zeros(3, nv)
    kap, tw, mt = ca.SX.zeros(2, nv), ca.SX.zeros(1, nv), ca.SX.zeros(1, nv)
    for k, (i, jp, jn, _) in enumerate(verts):
        nodal[:, i] += f[:, k]
        # a clamp's ghost is held (its force is the clamp's reaction); a guide's turns with
        # its node (its force is the node's) and shares the neighbour edge's twist
        if jp >= 0:
            nodal[:, i - 1] += fp[:, k]
            torque[jp] += qp[k]
        elif guided[0]:
            nodal[:, 0] += fp[:, k]
            torque[0] += qp[k]
        else:
            reaction[0] += fp[:, k]
        if jn < N:
            nodal[:, i + 1] += fn[:, k]
            torque[jn] += qn[k]
        elif guided[1]:
            nodal[:, N] += fn[:, k]
            torque[N - 1] += qn[k]
        else:
            reaction[N] += fn[:, k]
        moment[:, i], kap[:, i], tw[i], mt[i] = M[:, k], kappa[:, k], twist[k], Mt[k]
    # cable3d's own bending on the cable3d edges (hybrid; guide and clamp ghosts as above)
    a, b = scene.end_a, scene.end_b
    cb = cable_bending(seg, rod, held, guided, Xm, (a.direction, b.direction))
    if cb is not None:
        nodal, moment = nodal + cb["nodal"], moment + cb["moment"]
        reaction = {i: reaction[i] + cb["reaction"][i] for i in (0, N)}
    return _VertexTerms(nodal, torque, reaction, verts, fp, fn, E, moment, kap, tw, mt, cb,
                        coupled)


def _internal_forces(Xm, T, vt: _VertexTerms):
    """The internal force across each edge (3, N), N, on the part before it from the part
    beyond: the axial force along the edge, and the vertex terms that straddle the cut (the
    vertex at its first node pushes the node beyond with fn, whose reaction the part before
    takes, as its forces sum to zero; the vertex at its second node pushes the node before
    with fp)."""
    N = Xm.shape[1] - 1
    internal = ca.SX.zeros(3, N)
    for j in range(N):
        dx = Xm[:, j + 1] - Xm[:, j]
        internal[:, j] = T[j] * dx / ca.norm_2(dx)
    for k, (i, _, _, _) in enumerate(vt.verts):
        if i < N:
            internal[:, i] -= vt.fn[:, k]
        if i > 0:
            internal[:, i - 1] += vt.fp[:, k]
    if vt.cb is not None:
        internal += vt.cb["straddle"]
    return internal
