"""What the hybrid rod-catenary line (``model = "hybrid"``, :mod:`.hybrid`) changes in the rod
Mechanism (:func:`symcable.models.rod.rod.build_rod`, which takes a per-segment mask ``rod``):

- which edges carry a twist unknown (:func:`spun_edges`): the edges of rod sections only;
  each run of rod edges is a rod of its own (the moment-free joints at its ends pass no
  twisting moment), so its spin about itself is held by its first edge's twist at 0 unless
  the run reaches a clamped end;
- which nodes carry the rod's bending-and-twisting vertex (:func:`rod_vertices`): nodes
  inside a run (both edges rod), and a clamped or guided end whose edge is rod. A node
  between a rod edge and a cable3d edge has *no* vertex term: the moment-free spherical
  joint of Goyal & Perkins (their Eqs. 12-14): shared position (so velocity continuous), the
  element forces of both sides meet there (force transmitted), no bending or twisting
  moment, and the tangent may jump;
- which nodes carry cable3d's own bending (:func:`cable_vertices`,
  :mod:`~symcable.models.common.bending`'s kernel): nodes between two cable3d edges with EI > 0 (the
  harmonic mean, as cable3d), and a clamped or guided end whose edge is cable3d with
  EI > 0 (the guide's ghost moves with its node, as the rod's);
- the axial law (:func:`axial_law`): rod edges the linear law EA e (a rod carries
  compression); cable3d edges cable3d's (the linear law where EI > 0, else tension only, at
  the sharp corner: the hybrid has no ``slack`` continuation parameter).
"""
from __future__ import annotations

import casadi as ca
import numpy as np

from ...scene import EndCondition, Scene
from ..common.bending import bending_kernel, linear_axial_law
from ..common.segments import slack_law

__all__ = ["axial_law", "cable_bending", "cable_vertices", "rod_mask", "rod_runs",
           "rod_vertices", "spun_edges"]


def rod_mask(scene: Scene) -> np.ndarray:
    """Per segment, True where it belongs to a rod section: every segment of ``model =
    "rod"``; a hybrid's sections with ``model = "rod"`` (None, the default, is cable3d)."""
    if scene.model.value == "rod":
        return np.ones(scene.n_segments, bool)
    return np.array([s.model == "rod" for s in scene.sections for _ in range(s.segments)],
                    bool)


def rod_runs(rod: np.ndarray) -> list[tuple[int, int]]:
    """The maximal runs of consecutive rod edges, [(first, last)] (inclusive)."""
    out, start = [], None
    for j, r in enumerate(list(rod) + [False]):
        if r and start is None:
            start = j
        elif not r and start is not None:
            out.append((start, j - 1))
            start = None
    return out


def spun_edges(rod: np.ndarray, clamped) -> list[int]:
    """The edges whose twist is an unknown (module docstring), in order."""
    N = len(rod)
    out = []
    for j0, j1 in rod_runs(rod):
        held = (j0 == 0 and clamped[0]) or (j1 == N - 1 and clamped[1])
        out += list(range(j0 if held else j0 + 1, j1 + 1))
    return out


def rod_vertices(rod: np.ndarray, ds: np.ndarray, held) -> list[tuple[int, int, int, float]]:
    """The rod's vertices (node, edge before, edge after, lbar), edge -1 / N an end's ghost;
    ``held`` = (end A, end B) clamped or guided."""
    N = len(rod)
    out = [(i, i - 1, i, 0.5 * (ds[i - 1] + ds[i])) for i in range(1, N) if rod[i - 1] and rod[i]]
    if held[0] and rod[0]:
        out.insert(0, (0, -1, 0, 0.5 * ds[0]))
    if held[1] and rod[-1]:
        out.append((N, N - 1, N, 0.5 * ds[-1]))
    return out


def cable_vertices(seg: dict, rod: np.ndarray, held) -> list[tuple[int, float, float]]:
    """cable3d's bending nodes (node, EI, lbar) on the cable3d edges (module docstring);
    ``held`` = (end A, end B) clamped or guided."""
    ds, EI = seg["ds"], np.where(rod, 0.0, seg["EI"])
    N = len(ds)
    out = [(i, float((ds[i - 1] + ds[i]) / (ds[i - 1] / EI[i - 1] + ds[i] / EI[i])),
            0.5 * float(ds[i - 1] + ds[i])) for i in range(1, N) if EI[i - 1] > 0 and EI[i] > 0]
    for k, (i, j) in enumerate(((0, 0), (N, N - 1))):
        if held[k] and EI[j] > 0:
            out.append((i, float(EI[j]), 0.5 * float(ds[j])))
    return sorted(out)


def cable_bending(seg: dict, rod: np.ndarray, held, guided, Xm, directions) -> dict | None:
    """cable3d's bending at :func:`cable_vertices` for node positions ``Xm`` (3, N+1), or None
    where there is none: ``nodal`` forces (3, N+1), N (a guide's ghost turns with its node,
    so its force is the node's); ``reaction`` {0, N: (3, 1)} (a clamp's ghost's force: the
    clamp takes it); ``moment`` (3, N+1), N m; ``straddle`` (3, N), the vertex terms across
    each edge's cut (the internal force's share, as the rod's); ``energy``, J.
    ``directions``: the ends' tangents (a held end's)."""
    verts = cable_vertices(seg, rod, held)
    if not verts:
        return None
    N = Xm.shape[1] - 1
    ghost = {0: Xm[:, 0] - float(seg["ds"][0]) * ca.DM(directions[0]) if held[0] else None,
             N: Xm[:, N] + float(seg["ds"][-1]) * ca.DM(directions[1]) if held[1] else None}
    fp, f, fn, E, M = bending_kernel().map(len(verts))(
        ca.horzcat(*[Xm[:, i - 1] if i > 0 else ghost[0] for i, _, _ in verts]),
        ca.horzcat(*[Xm[:, i] for i, _, _ in verts]),
        ca.horzcat(*[Xm[:, i + 1] if i < N else ghost[N] for i, _, _ in verts]),
        ca.DM([c[1] for c in verts]).T, ca.DM([c[2] for c in verts]).T)
    nodal, moment = ca.SX.zeros(3, N + 1), ca.SX.zeros(3, N + 1)
    straddle = ca.SX.zeros(3, N)
    reaction = {0: ca.SX.zeros(3, 1), N: ca.SX.zeros(3, 1)}
    for k, (i, _, _) in enumerate(verts):
        nodal[:, i] += f[:, k]
        moment[:, i] = M[:, k]
        for nb, fk in ((i - 1, fp[:, k]), (i + 1, fn[:, k])):
            if 0 <= nb <= N:
                nodal[:, nb] += fk
            elif guided[0 if nb < 0 else 1]:
                nodal[:, i] += fk
            else:
                reaction[i] += fk
        if i < N:
            straddle[:, i] -= fn[:, k]
        if i > 0:
            straddle[:, i - 1] += fp[:, k]
    return {"nodal": nodal, "reaction": reaction, "moment": moment, "straddle": straddle,
            "energy": ca.sum2(E)}


def axial_law(seg: dict, rod: np.ndarray, F: float) -> tuple[np.ndarray, np.ndarray]:
    """(EA_slack, delta) per segment for cable3d's element kernel (module docstring): on
    rod edges (EA, 1), the linear law."""
    law = linear_axial_law(seg, slack_law(seg, F))
    return (np.where(rod, seg["EA"], law["EA_slack"]), np.where(rod, 1.0, law["delta"]))


def clamped_ends(scene: Scene) -> list[bool]:
    """[end A clamped, end B clamped]."""
    return [e.condition is EndCondition.CLAMPED for e in (scene.end_a, scene.end_b)]
