"""The discretisation error of a static answer, and refinement until it meets a tolerance.

A static solution is exact for the discrete line (its residual is at round-off), not for the
cable: the segments cannot follow a touchdown corner, a fold or a point load within one
segment. The error of each line's end tensions is estimated by Richardson extrapolation from
a second solve of the same scene with other segment counts (half, or twice for lines of fewer
than :data:`MIN_HALVED` segments): with ``T(n) = T + C n^-p``, the user's answer is off by

    e = |T(n) - T(m)| / |1 - (n/m)^p|

where ``p`` is 2 for a smooth line and 1 past a corner (a slack line standing up from the
seabed, or folded in the water column). Such a corner's error does not fall steadily (it
depends on where the true touchdown or fold falls within a segment), so the estimate is at
least the corner's own (:func:`_corner`, :func:`_fold`: half the weight of the segment
there, times the sine of the angle turned beyond the line's smooth turning). The estimate is in N and as a fraction of the scene's largest
tension; above the accuracy asked (default 1 %) the solution carries a warning naming the
segments that would meet it, and ``accuracy=`` refines those lines until it does.
"""
from __future__ import annotations

import dataclasses
import math
import time
from typing import Callable

import numpy as np

from ..errors import SymcableError
from ..limits import current
from ..scene import Scene
from ..scene.refine import ONE_LINE, line_segments, scaled_segments

__all__ = ["ACCURACY", "force_text", "with_error_estimate"]

#: default accuracy: a solution whose estimated error exceeds this fraction of its largest
#: tension warns (and ``accuracy=`` refines to it)
ACCURACY = 0.01
#: a line of fewer segments is compared with a solve at twice its segments, not half
MIN_HALVED = 8
#: refinement rounds at most, and the largest factor of segments one round applies
MAX_ROUNDS = 4
MAX_FACTOR = 8.0
#: a touchdown is a corner (first-order convergence) when the line turns there through an
#: angle whose sine exceeds this, beyond its smooth turning
SHARP = 0.2


def _ends(sol) -> dict:
    """``{line: (anchor tension, fairlead tension, largest tension)}``, N."""
    return {name: (ln.anchor_tension, ln.fairlead_tension,
                   max(ln.anchor_tension, ln.fairlead_tension, float(np.max(np.abs(ln.tension)))))
            for name, ln in sol.lines.items()}


def _segment_weights(scene: Scene) -> dict:
    """``{line: (n - 1,) submerged weight of each segment, N}``."""
    if scene.version == 1:
        parts = {ONE_LINE: scene.sections}
    else:
        parts = {ln.name: ln.sections for ln in scene.lines}
    return {name: np.concatenate([np.full(s.segments, abs(s.line_type.weight) * s.ds)
                                  for s in secs]) for name, secs in parts.items()}


def _free_ends(scene: Scene, points: bool = False) -> dict:
    """``{line: (end A free, end B free)}``: an end with ``condition = "free"`` (and, with
    ``points``, an end at a free point)."""
    def loose(end) -> bool:
        if isinstance(end, str):
            return points and bool(scene.points[end].is_free)
        cond = getattr(end, "condition", None)
        return cond is not None and getattr(cond, "name", "") == "FREE"
    if scene.version == 1:
        return {ONE_LINE: (loose(scene.end_a), loose(scene.end_b))}
    return {ln.name: (loose(ln.end_a), loose(ln.end_b)) for ln in scene.lines}


def _turn_sines(pos: np.ndarray) -> np.ndarray:
    """Sine of the angle the line turns through at each node (n,): 1 past 90 deg, 0 at the
    ends and where a segment has no length."""
    d = np.diff(pos, axis=0)
    nd = np.linalg.norm(d, axis=1)
    u, v, nu, nv = d[:-1], d[1:], nd[:-1], nd[1:]
    out = np.zeros(len(pos))
    with np.errstate(all="ignore"):
        cos = np.einsum("ij,ij->i", u, v) / (nu * nv)
        inner = np.where(cos > 0, np.sqrt(np.maximum(0.0, 1.0 - cos * cos)), 1.0)
    out[1:-1] = np.where((nu == 0.0) | (nv == 0.0), 0.0, inner)
    return out


def _on_bed(ln, weights: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``(share, on)``: each node's share of the segments' weight (N+1,), N, and whether the
    bed carries at least a tenth of it."""
    share = 0.5 * (np.concatenate([[0.0], weights]) + np.concatenate([weights, [0.0]]))
    return share, np.asarray(ln.contact_force) > 0.1 * share


def _corner(ln, weights: np.ndarray, loose: tuple = (False, False)) -> tuple[float, float]:
    """The error a touchdown corner leaves in a line's end tensions, N: where the line
    leaves the seabed at an angle (a slack line standing up from the bed), the true
    touchdown lies anywhere within the segment that leaves it, and its weight is carried by
    the bed or by the line in a proportion the nodes cannot resolve; half that segment's
    weight times the sine of the angle the line turns through there, beyond what it turns
    through a few nodes up (zero for a smooth, tangent touchdown). A node is on the bed when
    the bed carries at least a tenth of its weight. A free end or an end at a free point
    (``loose``) whose neighbour lies on the bed and whose own node the bed carries only in
    part (a tenth to nine tenths: a joint lifting off the bed; a held end's half segment
    rests where its neighbour does) has its lift-off within the end segment: the part not
    carried, first order (a joint of chains on the bed pulled up by a riser read 2.7 kN at 85 and 42 segments
    where the catenary's 0.34 m of hanging chain gives 1.35 kN). Returns
    ``(error N, that sine)``."""
    pos = np.asarray(ln.positions, float)
    n = len(pos)
    share, on = _on_bed(ln, weights)
    turn = _turn_sines(pos)
    worst, sharpest = 0.0, 0.0
    for i in np.flatnonzero(on[:-1] != on[1:]):
        up = 1 if on[i] else -1            # towards the suspended part
        far = i + (4 if up > 0 else -3)    # a node of the suspended part, past the corner
        smooth = turn[far] if 0 < far < n - 1 else 0.0
        for m in (i - 1, i, i + 1, i + 2):
            if 0 < m < n - 1:
                excess = max(0.0, turn[m] - smooth)
                worst = max(worst, 0.5 * max(weights[m - 1], weights[m]) * excess)
                sharpest = max(sharpest, excess)
    contact = np.asarray(ln.contact_force, float)
    for k, end, nb in ((0, 0, 1), (1, n - 1, n - 2)):  # a loose end half on the bed: a hinge
        frac = contact[end] / share[end] if share[end] > 0 else 0.0
        if loose[k] and n > 2 and on[nb] and 0.1 < frac < 0.9:
            worst = max(worst, (1.0 - frac) * share[end])
            sharpest = 1.0
    return worst, sharpest


def _fold(ln, weights: np.ndarray, free: tuple = (False, False)) -> tuple[float, float]:
    """The error a fold in the water column leaves in a line's end tensions, N: a line
    folded within a segment (a near-vertical line doubled back at its lower end, a slack
    loop) turns through a large angle at one node while the nodes two away on either side
    turn little; where the true fold lies within that segment the nodes cannot resolve, and
    the error falls as 1/n (first order), as at a touchdown corner. Half the weight of the
    segments beside the node times the sine of the angle turned there beyond the larger of
    those two nodes' (nodes on the seabed left to :func:`_corner`). A fold doubled back
    along the line itself (a vertical line folded at its lower end) turns no angle the nodes
    show: there the tension passes through zero within a segment, so a node in the water
    column whose tension is below the weight of a segment beside it (not within two nodes of
    a free end, ``free`` (end A, end B), where the tension falls to zero smoothly) counts as
    a fold turning through 180 degrees (sine 1), with no floor of its own. Returns
    ``(error N, that sine)``."""
    pos = np.asarray(ln.positions, float)
    n = len(pos)
    share, on = _on_bed(ln, weights)
    worst, sharpest = 0.0, 0.0
    turn = _turn_sines(pos)
    # the larger turn two nodes away on either side (-inf where there is no such interior
    # node; a node with neither is skipped)
    near = np.full(n, -np.inf)
    near[3:n - 1] = turn[1:n - 3]
    near[1:n - 3] = np.maximum(near[1:n - 3], turn[3:n - 1])
    m = np.arange(1, n - 1)
    m = m[~on[m] & np.isfinite(near[m])]
    if m.size:
        excess = np.maximum(0.0, turn[m] - near[m])
        sharp = excess > SHARP
        if np.any(sharp):
            heavy = np.maximum(weights[m - 1], weights[m])
            worst = float(np.max(0.5 * heavy[sharp] * excess[sharp]))
            sharpest = float(np.max(excess[sharp]))
    tension = np.asarray(ln.tension, float)
    for m in range(1, n - 1):
        if on[m] or (free[0] and m <= 2) or (free[1] and m >= n - 3):
            continue
        if tension[m] < max(weights[m - 1], weights[m]):
            sharpest = 1.0
            break
    return worst, sharpest


def _compare(sol, n: dict, other, m: dict, weights: dict, free: dict, loose: dict,
             before: dict | None = None) -> dict:
    """Per line the estimated error of ``sol`` (segments ``n``) from ``other`` (segments
    ``m``), at least its touchdown corner's and fold's (:func:`_corner`, :func:`_fold`;
    ``weights``, ``free`` and ``loose`` per line as :func:`_segment_weights` and
    :func:`_free_ends` give them); a line whose count did not change keeps its entry of
    ``before``."""
    mine, theirs = _ends(sol), _ends(other)
    scale = max(max(v[2] for v in mine.values()), 1e-300)
    lines = {}
    for name, (ta, tb, _) in mine.items():
        if n[name] == m[name]:
            if before and name in before:
                lines[name] = dict(before[name], relative=before[name]["error"] / scale)
            continue
        corner, sharp = max(_corner(sol.lines[name], weights[name], loose[name]),
                            _fold(sol.lines[name], weights[name], free[name]))
        # first order past a corner (the touchdown of a line standing up from the bed, a
        # fold in the water column), second order where the line is smooth
        p = 1 if sharp > SHARP else 2
        diff = max(abs(ta - theirs[name][0]), abs(tb - theirs[name][1]))
        richardson = diff / abs(1.0 - (n[name] / m[name]) ** p)
        err = max(richardson, corner)
        lines[name] = {"error": float(err), "relative": float(err / scale),
                       "segments": n[name], "compared_with": m[name], "order": p,
                       "richardson": float(richardson), "corner": float(corner)}
    return lines


def _needed(entry: dict, accuracy: float) -> int:
    """Segments that would bring ``entry``'s line under ``accuracy`` (10 % margin)."""
    ratio = max(entry["relative"] / accuracy, 1.0)
    return int(math.ceil(entry["segments"] * 1.1 * ratio ** (1.0 / entry["order"])))


def force_text(f: float) -> str:
    """A force with its unit chosen by its size."""
    for unit, scale in (("MN", 1e6), ("kN", 1e3)):
        if abs(f) >= scale:
            return f"{f / scale:.3g} {unit}"
    return f"{f:.3g} N"


def _warnings(lines: dict, accuracy: float, refining: bool) -> tuple:
    out = []
    for name, e in lines.items():
        if e["relative"] <= accuracy:
            continue
        how = ("" if refining else
               f"; solve_static(scene, accuracy={accuracy:g}) refines it")
        out.append(f"line '{name}': discretisation error about {force_text(e['error'])}, "
                   f"{e['relative']:.1%} of the largest tension, at {e['segments']} segments "
                   f"(estimated against {e['compared_with']}); about {_needed(e, accuracy)} "
                   f"segments would bring it under {100 * accuracy:g} %{how}")
    return tuple(out)


def _other(scene: Scene) -> tuple[Scene, dict]:
    n = line_segments(scene)
    other = scaled_segments(scene, {k: (0.5 if v >= MIN_HALVED else 2.0) for k, v in n.items()})
    return other, line_segments(other)


def _attach(sol, report: dict, warnings: tuple):
    stats = dict(sol.stats, discretisation_error=report)
    return dataclasses.replace(sol, stats=stats, warnings=tuple(sol.warnings) + warnings)


def with_error_estimate(scene: Scene, sol, solve: Callable, accuracy: float | None,
                        after: Callable | None = None):
    """``sol`` (the static solution of ``scene``) with its discretisation error in
    ``stats["discretisation_error"]`` and a warning per line above the accuracy; with
    ``accuracy`` given, the solution of ``scene`` refined (more segments on the lines above
    it, up to :data:`MAX_ROUNDS` rounds) until every line meets it.

    ``solve(scene, near=(scene0, sol0))`` solves a scene without estimating, where it can
    starting from ``sol0``, the solution of ``scene0`` (the answer being estimated or
    refined: the same lines at other segment counts). The report: ``lines`` (per line
    ``error`` N, ``relative`` to the largest tension, ``segments``, ``compared_with``,
    ``order``), ``max_relative``, ``accuracy``, ``segments`` (per line, of the answer
    returned), ``rounds`` (refinements made) and ``wall_time`` (s, the estimate's and the
    refinement's cost). ``after(scene, sol)``, when given, is applied to the solution
    returned and its scene (the refined one) before the report is attached (the seabed's
    estimate, :mod:`symcable.api.bed_error`).
    """
    t0 = time.perf_counter()
    target = ACCURACY if accuracy is None else float(accuracy)
    if not (0.0 < target < 1.0):
        raise SymcableError(f"solve_static: accuracy = {accuracy!r}: must be a fraction of "
                            "the largest tension between 0 and 1 (e.g. 0.01)")
    n = line_segments(scene)
    other, m = _other(scene)
    notes = ()
    try:
        ref = solve(other, near=(scene, sol))
    except SymcableError as exc:
        report = {"lines": {}, "max_relative": None, "accuracy": target, "segments": n,
                  "rounds": 0, "wall_time": time.perf_counter() - t0}
        first = str(exc).splitlines()[0][:200]
        sol = after(scene, sol) if after is not None else sol
        return _attach(sol, report, (f"no discretisation error estimate: the comparison "
                                     f"solve at {sum(m.values())} segments failed ({first})",))
    lines = _compare(sol, n, ref, m, _segment_weights(scene), _free_ends(scene),
                     _free_ends(scene, points=True))
    rounds = 0
    while accuracy is not None and rounds < MAX_ROUNDS and any(
            e["relative"] > target for e in lines.values()):
        factors = {k: min(MAX_FACTOR, max(1.5, 1.2 * (e["relative"] / target)
                                          ** (1.0 / e["order"])))
                   for k, e in lines.items() if e["relative"] > target}
        finer = scaled_segments(scene, factors)
        total = sum(line_segments(finer).values())
        if total > current().segments:
            notes = (f"refinement stopped at {sum(n.values())} segments: the next round "
                     f"needs {total}, more than the segments limit ({current().segments})",)
            break
        try:
            new = solve(finer, near=(scene, sol))
        except SymcableError as exc:
            notes = (f"refinement stopped at {sum(n.values())} segments: the solve at "
                     f"{total} failed ({str(exc).splitlines()[0][:200]})",)
            break
        n_new = line_segments(finer)
        lines = _compare(new, n_new, sol, n, _segment_weights(finer), _free_ends(finer),
                         _free_ends(finer, points=True), before=lines)
        scene, sol, n, rounds = finer, new, n_new, rounds + 1
    if after is not None:
        sol = after(scene, sol)
    report = {"lines": lines,
              "max_relative": max((e["relative"] for e in lines.values()), default=0.0),
              "accuracy": target, "segments": n, "rounds": rounds,
              "wall_time": time.perf_counter() - t0}
    return _attach(sol, report, _warnings(lines, target, accuracy is not None) + notes)
