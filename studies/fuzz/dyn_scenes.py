"""Seeded random *dynamic* cable3d scenes for the dynamic fuzz study (:mod:`dyn_fuzz`): the
3D statics generators' scenes (:mod:`fuzz3d_scenes`, :mod:`fuzz3d_systems`) with a harmonic
motion of the fairlead end or vessel point, and two kinds of their own (two lines to one
moving point; a taut wire that nearly slackens at the bottom of each cycle).

Scene ``i`` is drawn from its own generator seeded ``(seed, 33, i)``; classes by the
planar study's stratified schedule, so a scene replays from its id ``d<seed>-<i>``. Every
scene passes ``load_scene`` (a draw it refuses, e.g. an end moving faster than
max_strain x the line's axial wave speed, is redrawn and counted).

The motion: period 5-20 s (log-uniform), amplitude 0.5-5 m along a random direction (in
30 % an elliptic motion: random phases per axis), at most a tenth of the shortest line; on
a taut single line its component along the chord is kept to 2 % of the length (a taut line
moved along itself by more leaves max_strain). Segments: 10-40 per line (log-uniform; 10-16
in --quick), split over a line's sections by length (at least 2 each).
"""
from __future__ import annotations

import math

import numpy as np
from fuzz3d_draws import horizontal, seabed3, sphere
from fuzz3d_scenes import gen_current, gen_multi_section, gen_seabed, gen_two_point
from fuzz3d_systems import _line, _line_type_for, gen_buoy, gen_clump, gen_three_lines
from fuzz_draws import Redraw, line_type, log_uniform, weight_of
from fuzz_scenes import _plain, stratified

#: class -> share (sums to 1); d_ one line (scene version 1), s_ points and several lines
CLASSES = {
    "d_taut": 0.10, "d_slack": 0.09, "d_mooring": 0.13, "d_on_bed": 0.06,
    "d_multi_section": 0.08, "d_current": 0.06, "d_snatch": 0.12,
    "s_two_lines": 0.10, "s_buoy": 0.10, "s_clump": 0.09, "s_three_lines": 0.07,
}
#: the --quick set: one scene of each of these classes
QUICK_CLASSES = ["d_taut", "d_slack", "d_mooring", "d_snatch", "s_two_lines", "s_buoy",
                 "s_clump", "d_multi_section"]
PERIOD = (5.0, 20.0)
AMPLITUDE = (0.5, 5.0)
SEGMENTS = (10, 40)
QUICK_SEGMENTS = (10, 16)


# ----------------------------------------------------------------------------- motion
def motion(rng, direction=None, amplitude=None) -> dict:
    """A harmonic motion dict: period, amplitude vector (>= 0 per axis) and phases."""
    T = log_uniform(rng, *PERIOD)
    a = rng.uniform(*AMPLITUDE) if amplitude is None else amplitude
    d = sphere(rng) if direction is None else np.asarray(direction, float)
    phase = np.zeros(3)
    if rng.uniform() < 0.3:
        phase = rng.uniform(-180.0, 180.0, 3)
    amp = a * d
    phase = np.where(amp < 0, phase + 180.0, phase)
    return {"kind": "harmonic", "period": float(T), "amplitude": [float(v) for v in np.abs(amp)],
            "phase_deg": [float(v) for v in phase]}


def _taut_direction(rng, chord, a: float, L: float) -> np.ndarray:
    """A random direction whose component along ``chord`` moves the end by at most 2 % of
    ``L`` at amplitude ``a``."""
    u = np.asarray(chord, float) / np.linalg.norm(chord)
    d = sphere(rng)
    ax = float(d @ u)
    cap = min(1.0, 0.02 * L / a)
    if abs(ax) <= cap:
        return d
    perp = d - ax * u
    perp /= max(np.linalg.norm(perp), 1e-12)
    f = math.copysign(cap, ax)
    return f * u + math.sqrt(1.0 - f * f) * perp


#: the segments per line drawn (make_scene sets it: QUICK_SEGMENTS in --quick)
_seg_range = SEGMENTS


def _segments(rng, sections: list) -> None:
    """10-40 segments over ``sections`` (in place), by length, at least 2 each."""
    n = round(log_uniform(rng, *_seg_range))
    total = sum(s["length"] for s in sections)
    for s in sections:
        s["segments"] = max(2, round(n * s["length"] / total))


def _line_length(secs) -> float:
    return float(sum(s["length"] for s in secs))


# ----------------------------------------------------------------------------- one line
def _one_line_moving(rng, scene: dict, taut: bool = False) -> dict:
    """Move the higher pinned end of a version-1 scene (the fairlead)."""
    ends = [k for k in ("end_a", "end_b") if scene[k].get("condition") == "pinned"]
    if len(ends) < 2:
        raise Redraw("needs two pinned ends")
    k = max(ends, key=lambda e: scene[e]["position"][2])
    L = _line_length(scene["sections"])
    a = rng.uniform(*AMPLITUDE)
    if a > 0.1 * L:
        raise Redraw("line too short for the motion")
    d = None
    if taut:
        chord = np.subtract(scene["end_b"]["position"], scene["end_a"]["position"])
        d = _taut_direction(rng, chord, a, L)
    scene[k]["motion"] = motion(rng, d, a)
    _segments(rng, scene["sections"])
    return scene


def gen_single(rng, cls: str):
    if cls in ("d_taut", "d_slack"):
        variant, scene = gen_two_point(rng, "c3_" + cls[2:])
    elif cls in ("d_mooring", "d_on_bed"):
        variant, scene = gen_seabed(rng, "c3_" + cls[2:])
    elif cls == "d_multi_section":
        variant, scene = gen_multi_section(rng)
    else:
        variant, scene = gen_current(rng)
    return variant, _one_line_moving(rng, scene, taut=(cls == "d_taut"))


def gen_snatch(rng):
    """A taut wire or rope from an anchor on the bed (or a fixed point above it) up to a
    fairlead, stretched by s (0.2-2 %) at rest, moved along its chord by u (0.7-1.15) times
    its static stretch: nearly slack (u < 1) or slack for a moment (u > 1) at the bottom of
    each cycle; some transverse motion too."""
    fam = str(rng.choice(["wire", "rope"]))
    lt = line_type(rng, fam)
    a = rng.uniform(*AMPLITUDE)
    u = rng.uniform(0.7, 1.15)
    s = log_uniform(rng, 2e-3, 2e-2)
    L = a / (u * s)
    if not 20.0 <= L <= 1500.0:
        raise Redraw("length out of range")
    w_l = abs(weight_of(lt)) * L
    lo, hi = max(1e5, w_l / (0.2 * s), w_l / 0.05), min(1e10, 0.5e9 * w_l)
    if not lo < hi:
        raise Redraw("no EA")
    lt["EA"] = log_uniform(rng, lo, hi)
    theta = math.radians(rng.uniform(20.0, 90.0))
    chord_dir = math.cos(theta) * horizontal(rng.uniform(-math.pi, math.pi)) + \
        np.array([0.0, 0.0, math.sin(theta)])
    chord = L * (1.0 + s)
    top = -rng.uniform(2.0, 30.0)
    fair = np.array([rng.uniform(-500.0, 500.0), rng.uniform(-500.0, 500.0), top])
    anchor = fair - chord * chord_dir
    on_bed = rng.uniform() < 0.6
    depth = -anchor[2] if on_bed else -anchor[2] + rng.uniform(5.0, 50.0)
    d = chord_dir + rng.uniform(0.0, 0.3) * sphere(rng)
    d /= np.linalg.norm(d)
    amp = a / abs(float(d @ chord_dir))
    scene = {"line_types": {fam: lt},
             "sections": [{"type": fam, "length": float(L), "segments": 10}],
             "end_a": {"condition": "pinned", "position": [float(v) for v in anchor]},
             "end_b": {"condition": "pinned", "position": [float(v) for v in fair],
                       "motion": motion(rng, d, amp)},
             **seabed3(rng, float(depth))}
    _segments(rng, scene["sections"])
    variant = (f"{fam}, stretch {100 * s:.2g} %, motion {u:.2f} x stretch, "
               f"{math.degrees(theta):.0f} deg, anchor {'on the bed' if on_bed else 'above it'}")
    return variant, scene


# ----------------------------------------------------------------------------- systems
def _move_point(rng, scene: dict, name: str) -> dict:
    pt = scene["points"][name]
    pt["kind"] = "vessel"
    pt.pop("mass", None), pt.pop("volume", None)
    short = min(_line_length(ln["sections"]) for ln in scene["lines"])
    a = rng.uniform(*AMPLITUDE)
    if a > 0.1 * short:
        raise Redraw("a line too short for the motion")
    pt["motion"] = motion(rng, None, a)
    for ln in scene["lines"]:
        _segments(rng, ln["sections"])
    return scene


def gen_two_lines(rng):
    """Two anchor lines (chain or wire; suspended, touching down, or taut) from anchors on
    the bed to one vessel point near the surface, 60-180 degrees apart in azimuth."""
    depth = log_uniform(rng, 50.0, 500.0)
    V = np.array([rng.uniform(-300.0, 300.0), rng.uniform(-300.0, 300.0),
                  -rng.uniform(2.0, 0.1 * depth)])
    phi0 = rng.uniform(-math.pi, math.pi)
    apart = math.radians(rng.uniform(60.0, 180.0))
    types, lines, points, kinds = {}, [], {}, []
    for k in range(2):
        R = depth * rng.uniform(0.5, 3.0)
        A = V + R * horizontal(phi0 + k * apart)
        A[2] = -depth
        c = float(np.linalg.norm(V - A))
        h = V[2] + depth
        if rng.uniform() < 0.2:
            fam, kind = "wire", "taut"
            L = c / (1.0 + log_uniform(rng, 1e-3, 1e-2))
        else:
            fam = str(rng.choice(["chain", "chain", "wire"]))
            kind = "catenary"
            L = c + rng.uniform(0.02, 0.9) * (R + h - c)
        _line_type_for(rng, types, f"{fam}{k}", fam, L, 0.0)
        points[f"anchor{k}"] = {"kind": "fixed", "position": [float(v) for v in A]}
        lines.append(_line(f"line{k}", f"anchor{k}", "vessel",
                           [{"type": f"{fam}{k}", "length": float(L), "segments": 10}]))
        kinds.append(f"{fam} {kind}")
    points["vessel"] = {"kind": "fixed", "position": [float(v) for v in V]}
    scene = {**seabed3(rng, depth), "line_types": types, "points": points, "lines": lines}
    return ", ".join(kinds), _move_point(rng, scene, "vessel")


def gen_system(rng, cls: str):
    if cls == "s_buoy":
        variant, scene = gen_buoy(rng)
        return variant, _move_point(rng, scene, "fairlead")
    if cls == "s_clump":
        variant, scene = gen_clump(rng)
        return variant, _move_point(rng, scene, "fairlead")
    for _ in range(20):   # a buoy on three anchors has no end to move
        variant, scene = gen_three_lines(rng)
        if not variant.startswith("buoy"):
            break
    else:
        raise Redraw("three lines")
    ends = [k for k in scene["points"] if k.startswith("end")]
    top = max(ends, key=lambda k: scene["points"][k]["position"][2])
    return variant, _move_point(rng, scene, top)


def generate_one(rng, cls: str):
    if cls == "d_snatch":
        return gen_snatch(rng)
    if cls == "s_two_lines":
        return gen_two_lines(rng)
    if cls.startswith("s_"):
        return gen_system(rng, cls)
    return gen_single(rng, cls)


# ----------------------------------------------------------------------------- the set
def period_of(scene: dict) -> float:
    ends = [scene.get("end_a"), scene.get("end_b")] + list(scene.get("points", {}).values())
    return min(e["motion"]["period"] for e in ends if isinstance(e, dict) and "motion" in e)


def make_scene(i: int, cls: str, seed: int, quick: bool = False) -> dict:
    """Scene ``i`` of class ``cls`` (redrawn until the draws make a valid scene); ``quick``:
    10-16 segments a line."""
    global _seg_range
    import symcable as sc
    from symcable.errors import SceneError
    _seg_range = QUICK_SEGMENTS if quick else SEGMENTS
    rng = np.random.default_rng([seed, 33, i])
    refused = []
    for _ in range(200):
        try:
            variant, scene = generate_one(rng, cls)
        except Redraw:
            continue
        scene = _plain({"name": f"dyn {i:04d} {cls}", "model": "cable3d", **scene})
        try:
            sc.load_scene(scene)
        except SceneError as exc:
            refused.append(str(exc)[:200])
            continue
        n_seg = sum(s["segments"] for s in scene.get("sections", [])) + sum(
            s["segments"] for ln in scene.get("lines", []) for s in ln["sections"])
        return {"id": f"{'q' if quick else 'd'}{seed}-{i:04d}", "class": cls, "variant": variant, "scene": scene,
                "period": period_of(scene), "segments": n_seg, "refused_draws": refused}
    raise RuntimeError(f"scene {i} ({cls}): no valid draw in 200 tries")


def schedule(n: int, seed: int, quick: bool = False) -> list[str]:
    if quick:
        return [QUICK_CLASSES[i % len(QUICK_CLASSES)] for i in range(n)]
    return stratified(CLASSES, n, np.random.default_rng([seed, 33]))


def generate(n: int, seed: int = 33, quick: bool = False) -> list[dict]:
    """n scenes in the stated proportions (``quick``: one of each of QUICK_CLASSES)."""
    return [make_scene(i, cls, seed, quick) for i, cls in enumerate(schedule(n, seed, quick))]
