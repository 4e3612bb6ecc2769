"""Where a hybrid line (``zones = "auto"``) is a rod: from the static line solved with every
section a cable, a segment is a rod where its bending length is long against the line.

The solve itself is the caller's (:func:`symcable.api.rod_static.hybrid_zones`): this module
gives the Mechanism to solve (:func:`probe_mechanism`) and turns its solution into the zoned
scene (:func:`zoned_scene`).
"""
from __future__ import annotations

import dataclasses

import numpy as np

from ...scene import Scene
from .hybrid_terms import rod_runs
from .rod import build_rod, rod_table

__all__ = ["probe_mechanism", "zoned_scene"]

#: the section kinds a zoned hybrid's sections take
_ROD, _CABLE = "rod", "cable3d"


def probe_mechanism(scene: Scene):
    """The Mechanism of ``scene`` with every section a cable (its own bending where EI > 0;
    a guided end held, an end's rod edge where the end takes a moment), whose static state
    :func:`zoned_scene` reads."""
    given = dataclasses.replace(scene, zones="given", sections=tuple(
        dataclasses.replace(s, model=None) for s in scene.sections))
    N = len(rod_table(scene)["ds"])
    first = np.zeros(N, bool)  # an end moment needs a rod edge to act on, even here
    for end, j in ((scene.end_a, 0), (scene.end_b, N - 1)):
        first[j] = end.moment is not None
    return build_rod(given, first)


def _rod_mask(scene: Scene, seg, X, f, threshold: float, grow: float):
    """(rod (N,) bool, bending length (N,) m): the segments that are rods, from the probe's
    node positions X (N+1, 3) m and internal forces f (N, 3) N."""
    t = np.diff(X, axis=0)
    T = np.sum(f * t, axis=1) / np.linalg.norm(t, axis=1)
    ok = (seg["EI"] > 0) & (seg["EI2"] > 0) & (seg["GJ"] > 0)
    lam = np.where(T > 0, np.sqrt(seg["EI"] / np.maximum(T, 1e-300)), np.inf)
    rod = ok & (lam > threshold * scene.length)
    N = len(seg["ds"])
    for end, j in ((scene.end_a, 0), (scene.end_b, N - 1)):
        if end.guided or end.twist_deg is not None or end.moment is not None:
            rod[j] = True
    s = seg["s"]
    mid = 0.5 * (s[:-1] + s[1:])
    width = grow * threshold * scene.length
    for j0, j1 in rod_runs(rod.copy()):
        rod |= ok & (mid > s[j0] - width) & (mid < s[j1 + 1] + width)
    return rod, lam


def zoned_scene(scene: Scene, X, f, threshold: float, grow: float) -> tuple[Scene, dict]:
    """``(scene, report)``: ``scene`` with its sections split at the rod zones' ends (the
    segment table unchanged), the rod runs marked as rods and the rest as cables, from the
    probe's static node positions ``X`` (N+1, 3) m and internal forces ``f`` (N, 3) N.

    A segment is a rod where its bending length sqrt(EI / T) exceeds ``threshold`` times the
    line's length L (T <= 0: a rod), among the segments whose line type has EI > 0 and
    GJ > 0; an end's segment also where the end is guided, takes a moment or a clamp gives
    ``twist_deg``. Each zone is grown by ``grow`` x ``threshold`` x L on both sides, to
    whole segments (within the candidates). The report: ``zones`` [(s_start, s_end)] m of
    the rod runs, ``threshold``, ``grow``, ``bending_length`` per segment (m, inf where
    T <= 0), ``message`` (one line)."""
    seg = rod_table(scene)
    rod, lam = _rod_mask(scene, seg, np.asarray(X, float), np.asarray(f, float), threshold, grow)
    sections, j0 = [], 0
    for sec in scene.sections:
        mask = rod[j0:j0 + sec.segments]
        k = 0
        while k < sec.segments:
            n = int(np.argmax(mask[k:] != mask[k])) or sec.segments - k
            sections.append(dataclasses.replace(sec, length=sec.ds * n, segments=n,
                                                model=_ROD if mask[k] else _CABLE))
            k += n
        j0 += sec.segments
    s = seg["s"]
    zones = [(float(s[j0]), float(s[j1 + 1])) for j0, j1 in rod_runs(rod)]
    where = ", ".join(f"{x0:.4g}-{x1:.4g} m" for x0, x1 in zones) or "none"
    msg = (f"zones = 'auto': rod on {where} of {scene.length:.4g} m (bending length "
           f"sqrt(EI/T) > {threshold:g} L = {threshold * scene.length:.4g} m, grown by "
           f"{grow * threshold * scene.length:.4g} m)")
    return (dataclasses.replace(scene, zones="given", sections=tuple(sections)),
            {"zones": zones, "threshold": threshold, "grow": grow, "bending_length": lam,
             "message": msg})
