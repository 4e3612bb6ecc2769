"""A line's segments, shared by every formulation: the segment table of a scene's sections, the
force scale, the smooth tension-only law of a cable and its compression bounds, and the
grounded length of a line on the seabed."""
from __future__ import annotations

import numpy as np

from ...scene import Scene


def segment_table(scene: Scene) -> dict[str, np.ndarray]:
    """Per-segment properties (arrays of shape (N,)) and node arc lengths (N+1,)."""
    secs = scene.sections
    counts = [sec.segments for sec in secs]
    rows = np.array([[sec.ds, sec.line_type.EA, sec.line_type.EI, sec.line_type.weight,
                      sec.line_type.diameter, sec.line_type.cd_normal,
                      sec.line_type.cd_tangential, sec.line_type.mass, sec.line_type.ca_normal]
                     for sec in secs], dtype=float).reshape(len(secs), 9)
    cols = np.repeat(rows, counts, axis=0)
    table = {k: np.ascontiguousarray(cols[:, i])
             for i, k in enumerate(("ds", "EA", "EI", "w", "d", "cdn", "cdt", "mass", "can"))}
    table["s"] = np.concatenate([[0.0], np.cumsum(table["ds"])])
    return table


#: the tension-only law of cables (EI = 0; :func:`~symcable.models.common.terms.cable_axial_force`),
#: relative to the scene's force scale F: the residual stiffness in compression is
#: SLACK_STIFFNESS F per unit strain; the corner is smoothed where the tension is about
#: SLACK_SMOOTHING F (strain width 2 SLACK_SMOOTHING F / EA); the wall that keeps segments
#: of positive length pushes with F exp(-(1 + e) / SLACK_WALL): 4.5e-5 F at e = -0.95, F at
#: e = -1. So a slack cable pushes with less than CABLE_COMPRESSION F while no segment has
#: bunched below 5 % of its length
SLACK_STIFFNESS = 1e-7


SLACK_SMOOTHING = 1e-6


SLACK_WALL = 0.005


#: the tension-only law's corner is SLACK_CONTINUATION times wider at the start of the
#: continuation in ``slack`` (the parameter sigma from 0 to 1): where Newton cannot follow
#: the sharp corner from a start (segments that go slack on the way), the solver solves
#: with the wide corner and narrows it in steps
SLACK_CONTINUATION = 1e4


def force_scale_of(scene: Scene, seg: dict) -> float:
    """A characteristic force of the scene, N: the line's total |submerged weight|, the
    largest applied end force, or 1e-6 of the smallest EA (at least 1 N)."""
    applied = [float(np.linalg.norm(e.force)) for e in (scene.end_a, scene.end_b)
               if e.force is not None]
    return max(float(np.sum(np.abs(seg["w"]) * seg["ds"])), *applied,
               1e-6 * float(np.min(seg["EA"])), 1.0)


def slack_law(seg: dict, force_scale: float) -> dict:
    """Per segment ``delta`` (strain width of the corner) and ``EA_slack`` (N) of the
    tension-only law, NaN where the segment has bending (EI > 0: compression allowed)."""
    cable = seg["EI"] <= 0.0
    delta = np.where(cable, 2.0 * SLACK_SMOOTHING * force_scale / seg["EA"], np.nan)
    return {"delta": delta, "EA_slack": np.where(cable, SLACK_STIFFNESS * force_scale, np.nan),
            "F_wall": force_scale, "w_wall": SLACK_WALL}


#: compression a cable (EI = 0) may show and still count as carrying none, relative to the
#: scene's force scale: far above the round-off of a converged solve (1e-9 of the scale)
#: and the tension-only law's residual push while segments keep 5 % of their length, far
#: below any compression that changes the answer
CABLE_COMPRESSION = 1e-4


#: ... or, where more, this fraction of the segment's own weight: a vertical line that folds
#: inside one segment (two strands side by side) bunches that segment nearly shut, and the
#: slack law's wall holds it open with a push of about SLACK_WALL times the local tension
#: (up to a few per cent of the segment's weight). The discrete line is uncertain there by
#: about a segment's weight anyway (the bunching warning says so); a compressed strut
#: pushes with many segments' weight
FOLD_PUSH = 0.05


def nodal_weights(seg: dict) -> tuple:
    """(tributary length (N+1,), m; submerged weight per length on each node (N+1,), N/m),
    the lumping of the residual's loads: half of each adjacent segment."""
    s = seg["s"]
    trib = np.zeros_like(s)
    trib[:-1] += 0.5 * seg["ds"]
    trib[1:] += 0.5 * seg["ds"]
    w_node = np.zeros_like(s)
    w_node[:-1] += 0.5 * seg["ds"] * seg["w"]
    w_node[1:] += 0.5 * seg["ds"] * seg["w"]
    w_node /= trib
    return trib, w_node, np.where(w_node > 0, w_node, np.inf), 0.1 * np.abs(w_node)


def seabed_sink(scene: Scene, seg: dict) -> float:
    """How far a held end may sit above the seabed and still rest on it, m: the penetration
    of the heaviest segment under its own weight (at least 1e-6 of the line's length). The
    rule of the contact models (the planar line's, and the 3D lines' in
    :func:`~symcable.models.common.seabed.seabed_forces`): a held end at most this high rests
    on the seabed, and its half segment takes its neighbour's penetration."""
    return max(abs(float(np.max(seg["w"]))) / (scene.seabed.stiffness * float(np.min(seg["d"]))),
               1e-6 * scene.length)


def grounded_length(scene: Scene, seg: dict, nodal: tuple | None, pos: np.ndarray,
                    contact: np.ndarray | None, fa: np.ndarray, fb: np.ndarray) -> tuple:
    """(grounded length, m, unstretched; its end's arc length s, m, or None; the touchdown
    point (dim,), m, or None) of a line (planar or 3D: z is the last coordinate) from its
    nodes' contact forces and its end forces; ``nodal``: :func:`nodal_weights` of ``seg``
    (None: computed here)."""
    s = seg["s"]
    if contact is None or not contact.max() > 0:
        return 0.0, None, None
    trib, w_node, w_div, w_tenth = nodal_weights(seg) if nodal is None else nodal
    # the grounded length is the length whose weight the seabed carries: the contact
    # forces, plus what a held end lying on the seabed props up of the grounded line
    # next to it (on a penalty seabed the end sits above the sunken line beside it)
    # (each node at most its tributary length: a light section between heavier ones
    # carries part of their weight where the line curves over the penalty bed, and
    # would count as more line than it is)
    grounded = float(np.sum(np.minimum(contact / w_div, trib)))
    # in contact: the seabed carries more than a tenth of the local weight per length
    in_contact = contact / trib > w_tenth
    # A held end lying on the seabed (the contact models' rule, :func:`seabed_sink`) rests
    # on the grounded line, and props up what pulls it down, where the line beside it sinks
    # into the bed without a break from the end to a node in contact. Not by the end's own
    # contact force: its half segment takes the neighbour's penetration, which on a penalty
    # seabed grows from the end over the length sqrt(T / (k d)) (9 m on the OC3 line), so
    # the neighbour is in contact only on segments longer than about a tenth of that (0.95
    # m on OC3: without this rule a fine OC3 line, 1,000 segments or more, loses 9 m of
    # its grounded length).
    # A taut line rising from its anchor does not sink beside it: the anchor then carries
    # its half segment's weight lumped on its node, which is no grounded line (and a node
    # that grazes the bed beside it, in contact by less than a tenth of its weight, none)
    rests = in_contact.copy()
    if scene.seabed is not None:
        z, floor = pos[:, -1], -scene.environment.depth
        bed = floor + seabed_sink(scene, seg)
        for node, step, force, end in ((0, 1, fa, scene.end_a), (len(s) - 1, -1, fb, scene.end_b)):
            if not (end.is_fixed and w_node[node] > 0 and float(z[node]) <= bed):
                continue
            beside = np.arange(node + step, len(s) - 1 - node, step)  # the others, from it
            sunk = z[beside] < floor
            run = beside[:int(np.argmin(sunk)) if not sunk.all() else len(beside)]
            if in_contact[node] or in_contact[run].any():
                rests[node] = True
                grounded += max(0.0, -float(force[-1])) / w_node[node]
    grounded = min(grounded, float(s[-1]))
    if not grounded > 0:
        return grounded, None, None
    if rests[0] and not rests[-1]:
        s_td = grounded
    elif rests[-1] and not rests[0]:
        s_td = float(s[-1]) - grounded
    else:
        s_td = float(s[np.argmax(in_contact)])
    return grounded, s_td, np.array([np.interp(s_td, s, pos[:, c]) for c in range(pos.shape[1])])
