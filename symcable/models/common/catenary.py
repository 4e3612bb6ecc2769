"""The closed-form elastic catenary as a line's starting shape: node positions marched
along the catenary between two held ends, segment by segment (seabed contact included)."""
from __future__ import annotations

import numpy as np


def catenary_start(pa, pb, seg, scene):
    """Node positions and midpoint tensions from the closed-form elastic catenary of an
    equivalent uniform line (total weight, series stiffness) between the two ends."""
    from ...analytic import elastic_catenary

    s, ds = seg["s"], seg["ds"]
    L = s[-1]
    w_eq = float(np.sum(seg["w"] * ds) / L)
    EA_eq = float(L / np.sum(ds / seg["EA"]))
    s_mid = s[:-1] + 0.5 * ds
    if abs(w_eq) * L < 1e-9 * EA_eq:
        return None
    depth = scene.environment.depth
    start, end, s_eval, mid_eval = pa, pb, s, s_mid
    seabed = False
    if depth is not None and w_eq > 0:
        low_first = pa[1] <= pb[1]
        low = pa if low_first else pb
        if low[1] + depth < 0.01 * L:
            seabed = True
            if not low_first:
                start, end, s_eval, mid_eval = pb, pa, L - s, L - s_mid
    dx, dz = end[0] - start[0], end[1] - start[1]
    sx = 1.0 if dx >= 0 else -1.0
    sz = 1.0 if w_eq > 0 else -1.0
    sol = elastic_catenary(abs(dx), sz * dz, L, EA_eq, abs(w_eq), seabed=seabed)
    source = "elastic catenary with seabed" if seabed else "elastic catenary"
    if sol.H == 0.0 and sol.grounded_length == 0.0 and np.hypot(dx, dz) < L:
        # a vertical fold: the catenary one segment wide instead (a narrow U, H > 0, whose
        # segments are straight and taut), its span then closed by a shear along z
        width = float(np.max(ds))
        sol = elastic_catenary(width, sz * dz, L, EA_eq, abs(w_eq))
        pos = sol.positions(s_eval) * np.array([sx, sz]) + np.asarray(start)
        pos[:, 0] -= (s_eval / L) * sx * width
        return pos, sol.tension(mid_eval), source + " (a vertical fold, one segment wide)"
    if sol.H == 0.0:  # slack: piled on the seabed (see _march)
        pos = _march(sol, seg, start, end, sx, sz, swapped=start is pb)
        if seabed:  # grounded nodes sink to where the contact carries their weight
            grounded = pos[:, 1] <= -depth + 1e-9 * L
            grounded[[0, -1]] = False  # the held ends stay where they are held
            pos[grounded, 1] -= abs(w_eq) / (scene.seabed.stiffness * float(np.mean(seg["d"])))
        return pos, None, source
    pos = sol.positions(s_eval) * np.array([sx, sz]) + np.asarray(start)
    if depth is not None:
        pos[:, 1] = np.maximum(pos[:, 1], -depth)
    return pos, sol.tension(mid_eval), source


def _march(sol, seg, start, end, sx, sz, swapped: bool) -> np.ndarray:
    """Node positions of a slack closed-form catenary (H = 0) built segment by segment, so
    that every segment is straight and keeps its length where the closed form cannot say
    how (``sol.positions`` piles the grounded excess at one point and folds a vertical line
    at a point, which a straight segment straddling it cannot follow): each segment takes
    the closed form's direction and strain at its midpoint; a grounded segment lies flat,
    shortened evenly so that the grounded length fits between the end on the seabed and
    the touchdown (the bunched pile of a slack chain); the segment in which a vertical line
    turns lies horizontal. The march's miss at the far end is spread along the line in
    proportion to arc length."""
    ds = seg["ds"][::-1] if swapped else seg["ds"]
    s = np.concatenate([[0.0], np.cumsum(ds)])
    mid = 0.5 * (s[:-1] + s[1:])
    L, lb = float(s[-1]), sol.grounded_length
    ang, eps = sol.angle(mid), sol.strain(mid)
    V = sol.V_a + sol.weight * np.maximum(s - lb, 0.0)  # vertical force at the nodes
    turn = (V[:-1] < 0.0) & (V[1:] > 0.0)
    # the turn carries the small horizontal pull that tilts the two strands by one segment
    # over their length (taut, away from the law's corner at zero strain)
    ang[turn] = 0.0
    eps[turn] = np.max(eps) * float(np.max(ds)) / L
    if lb > 0.0:
        ground = mid <= lb
        ang[ground] = 0.0
        eps[ground] = min(sol.span / lb, 1.0) - 1.0
    steps = (ds * (1.0 + eps))[:, None] * np.stack([sx * np.cos(ang), sz * np.sin(ang)], axis=1)
    pos = np.asarray(start, float) + np.concatenate([np.zeros((1, 2)), np.cumsum(steps, axis=0)])
    pos += np.outer(s / L, np.asarray(end, float) - pos[-1])
    return pos[::-1].copy() if swapped else pos
