"""The starting points of the planar statics (:mod:`.model`): an elastic catenary, a straight,
bowed or hanging line, a clamped line unloaded, the minimum of the potential energy; each a
:class:`~.base.Guess` of the interleaved unknowns (node positions, segment angle and strain)
with the parameters it is (close to) a solution at and the continuation that leads on."""
from __future__ import annotations

import math

import numpy as np

from ...errors import ConvergenceError
from ...scene import EndCondition
from ..common.catenary import catenary_start
from ..common.segments import force_scale_of, slack_law
from .base import Guess


class _Layout:
    """Where node positions and segment angle/strain sit in the unknown vector."""

    def __init__(self, kinds: np.ndarray, unknown_nodes: np.ndarray):
        self.n = kinds.size
        self.nodes = unknown_nodes
        self.ix, self.iz = np.flatnonzero(kinds == "x"), np.flatnonzero(kinds == "z")
        self.iphi, self.ieps = np.flatnonzero(kinds == "phi"), np.flatnonzero(kinds == "eps")

    def pack(self, pos: np.ndarray, phi: np.ndarray, eps: np.ndarray) -> np.ndarray:
        """Unknown vector from node positions (N+1, 2) and segment angle/strain (N,)."""
        w = np.empty(self.n)
        w[self.ix], w[self.iz] = pos[self.nodes, 0], pos[self.nodes, 1]
        w[self.iphi], w[self.ieps] = phi, eps
        return w


def _from_positions(pos: np.ndarray, seg: dict, tension_mid: np.ndarray | None):
    d = np.diff(pos, axis=0)
    phi = np.unwrap(np.arctan2(d[:, 1], d[:, 0]))
    if tension_mid is None:
        eps = np.hypot(d[:, 0], d[:, 1]) / seg["ds"] - 1.0
    else:
        eps = tension_mid / seg["EA"]
    return phi, eps


def _bowed(pa, pb, seg) -> np.ndarray:
    """Node positions of a half sine between the two ends, bowed sideways until it is as
    long as the line, nodes at their arc lengths: the first buckling mode's shape, a start
    for a rod compressed between its ends (from the straight strut, the buckled branch is a
    sideways jump Newton does not make). Bowed down when the line sinks, else up (to +x
    for a vertical chord)."""
    s, L = seg["s"], float(seg["s"][-1])
    chord = pb - pa
    c = float(np.hypot(*chord))
    t = chord / c
    n = np.array([-t[1], t[0]])
    sinks = float(np.sum(seg["w"] * seg["ds"])) >= 0.0
    if n[1] != 0.0 and (n[1] > 0.0) == sinks or (n[1] == 0.0 and n[0] < 0.0):
        n = -n
    u = np.linspace(0.0, 1.0, 2001)

    def curve(a):
        return np.outer(u * c, t) + np.outer(a * np.sin(math.pi * u), n)

    def length(a):
        return float(np.sum(np.hypot(*np.diff(curve(a), axis=0).T)))

    lo, hi = 0.0, L
    for _ in range(60):  # bisection: the length grows with the amplitude
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if length(mid) < L else (lo, mid)
    pts = curve(0.5 * (lo + hi))
    arc = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(pts, axis=0).T))])
    frac = s / L * arc[-1]
    return pa + np.stack([np.interp(frac, arc, pts[:, 0]), np.interp(frac, arc, pts[:, 1])], axis=1)


def _hanging_start(scene, seg, free_a: bool):
    """Exact discrete equilibrium of a line without bending, drag or seabed that hangs from
    its fixed end: integrating F_{i-1} = F_i + P_i from the free end gives every segment
    force, hence its angle and strain, and compatibility gives the positions."""
    N = len(seg["ds"])
    fixed, free = (scene.end_b, scene.end_a) if free_a else (scene.end_a, scene.end_b)
    node_w = np.zeros(N + 1)
    node_w[:-1] += 0.5 * seg["w"] * seg["ds"]
    node_w[1:] += 0.5 * seg["w"] * seg["ds"]
    f_free = np.array(free.force or (0.0, 0.0))
    F = np.zeros((N, 2))
    if free_a:  # node 0 free: F_0 = -P_0, F_j = F_{j-1} - P_j
        acc = -(f_free + [0.0, -node_w[0]])
        for j in range(N):
            F[j] = acc
            acc = acc - [0.0, -node_w[j + 1]]
    else:       # node N free: F_{N-1} = P_N, F_{j-1} = F_j + P_j
        acc = f_free + [0.0, -node_w[N]]
        for j in range(N - 1, -1, -1):
            F[j] = acc
            acc = acc + [0.0, -node_w[j]]
    T = np.hypot(F[:, 0], F[:, 1])
    if np.any(T <= 0):
        return None
    phi = np.unwrap(np.arctan2(F[:, 1], F[:, 0]))
    eps = T / seg["EA"]
    steps = (seg["ds"] * (1 + eps))[:, None] * np.stack([np.cos(phi), np.sin(phi)], axis=1)
    origin = np.array(fixed.position)
    if free_a:
        pos = origin - np.concatenate([np.cumsum(steps[::-1], axis=0)[::-1], np.zeros((1, 2))])
    else:
        pos = origin + np.concatenate([np.zeros((1, 2)), np.cumsum(steps, axis=0)])
    return pos, phi, eps


def _laid_on_seabed(scene, seg, pos: np.ndarray, free_a: bool) -> np.ndarray:
    """A hanging line that reaches below the seabed, lowered onto it: the nodes above the
    seabed stay; from the first node below it on, the line lies flat on the bed (at the
    depth where the contact carries its weight), each segment at its unstretched length,
    away from the held end (in the direction of the free end's horizontal force, else +x)."""
    depth = scene.environment.depth
    order = np.arange(len(pos))[::-1] if free_a else np.arange(len(pos))
    ds = seg["ds"][::-1] if free_a else seg["ds"]
    p = pos[order].copy()
    below = np.flatnonzero(p[:, 1] < -depth)
    k = int(below[0])
    free = scene.end_a if free_a else scene.end_b
    fx = (free.force or (0.0, 0.0))[0]
    direction = 1.0 if fx >= 0.0 else -1.0
    pen = max(float(np.mean(seg["w"])), 0.0) / (scene.seabed.stiffness * float(np.mean(seg["d"])))
    p[k, 1] = -depth - pen
    for i in range(k + 1, len(p)):
        p[i] = p[i - 1] + np.array([direction * ds[i - 1], 0.0])
    out = np.empty_like(p)
    out[order] = p
    return out


def _initial_guess(scene, seg, layout: _Layout, p_target, bending, p_names: tuple):
    """Starting points in order of preference (the solver tries each), built lazily: a
    generator, so a start is only computed when the ones before it have failed;
    ``p_names`` names the entries of ``p_target``."""
    a, b = scene.end_a, scene.end_b
    free_a, free_b = a.condition is EndCondition.FREE, b.condition is EndCondition.FREE
    s, L = seg["s"], seg["s"][-1]
    no_bending = np.array(p_target)
    no_bending[p_names.index("bending")] = 0.0
    cable_p, cable_h = (no_bending, "bending") if bending else (np.array(p_target), "")
    if np.any(seg["EI"] <= 0.0):  # cables: continuation from the tension-only law's wide corner
        cable_p = np.array(cable_p)
        cable_p[p_names.index("slack")] = 0.0
        cable_h = "bending and slack" if cable_h else "slack"

    def make(pos, phi, eps, p0, source, homotopy):
        return Guess(w=layout.pack(pos, phi, eps), p=p0, source=source, homotopy=homotopy)

    if not free_a and not free_b:
        pa, pb = np.array(a.position), np.array(b.position)
        try:
            start = catenary_start(pa, pb, seg, scene)
        except (ConvergenceError, ValueError, FloatingPointError):
            start = None
        if start is not None:
            pos, ten, source = start
            yield make(pos, *_from_positions(pos, seg, ten), cable_p, source, cable_h)
        straight = pa + np.outer(s / L, pb - pa)
        phi, eps = _from_positions(straight, seg, None)
        yield make(straight, phi, np.maximum(eps, 0.0), cable_p, "straight line", cable_h)
        if bending and np.hypot(*(pb - pa)) < L:
            bowed = _bowed(pa, pb, seg)
            yield make(bowed, *_from_positions(bowed, seg, None), np.array(p_target),
                       "bowed line (half sine)", "")
        relaxed = _relaxed(scene, seg, straight if start is None else start[0], p_target, make)
        if relaxed is not None:
            yield relaxed
        return

    fixed, free = (b, a) if free_a else (a, b)

    def hanging():
        start = _hanging_start(scene, seg, free_a)
        if start is None:
            return None
        pos, phi, eps = start
        if scene.seabed is not None and np.min(pos[:, 1]) < -scene.environment.depth:
            pos = _laid_on_seabed(scene, seg, pos, free_a)
            phi, eps = _from_positions(pos, seg, None)
            return make(pos, phi, eps, cable_p, "hanging line laid on the seabed", cable_h)
        return make(pos, phi, eps, cable_p, "hanging line", cable_h)

    def unloaded():
        t = np.array([math.cos(fixed.angle), math.sin(fixed.angle)])
        pos = np.array(fixed.position) + np.outer(s - (0.0 if free_b else L), t)
        p0 = np.array(p_target)
        p0[p_names.index("load")] = 0.0
        return make(pos, np.full(len(seg["ds"]), math.atan2(t[1], t[0])), np.zeros(len(seg["ds"])),
                    p0, "straight clamped line, unloaded", "load")

    order = [hanging]
    if fixed.condition is EndCondition.CLAMPED:
        load = float(np.hypot(*(free.force or (0.0, 0.0))) + np.sum(np.abs(seg["w"]) * seg["ds"]))
        # when bending dominates a cantilever is best reached from its unloaded state
        order = [unloaded, hanging] if np.max(seg["EI"]) > 0.1 * load * L**2 else [hanging, unloaded]
    first = None
    for build in order:
        g = build()
        if g is not None:
            first = g if first is None else first
            yield g
    if first is not None:
        pos = np.zeros((len(s), 2))
        pos[layout.nodes, 0], pos[layout.nodes, 1] = first.w[layout.ix], first.w[layout.iz]
        relaxed = _relaxed(scene, seg, pos, p_target, make)
        if relaxed is not None:
            yield relaxed


def _relaxed(scene, seg, pos0, p_target, make):
    """The start at the minimum of the line's potential energy
    (:func:`~symcable.models.common.relax.relaxed_positions`) from ``pos0``, for lines
    without bending, the drag of a current frozen at the last shape in a few passes. None
    for a line with bending or when the minimiser fails."""
    from ..common.relax import relax_line

    if np.any(seg["EI"] > 0.0):
        return None
    force_scale = force_scale_of(scene, seg)
    pos = relax_line(scene, seg, pos0, slack_law(seg, force_scale), force_scale)
    if pos is None:
        return None
    return make(pos, *_from_positions(pos, seg, None), np.array(p_target),
                "minimum of the potential energy", "")
