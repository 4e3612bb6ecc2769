"""Scenes for the error-estimate study (:mod:`error_estimate`): the fuzz study's generators,
restricted to what MoorPy solves exactly, and the 3D set weighted toward systems.

Only scenes MoorPy can answer exactly are drawn: no current, no bending, no weightless line,
no clamped end (a draw with any of them is redrawn from the next generator index). What is
used of the existing generators:

- planar (:mod:`fuzz_scenes`): the one-section classes ``taut``, ``slack``, ``vertical``,
  ``near_vertical``, ``seabed_mooring``, ``seabed_fully_slack``, ``seabed_u``,
  ``seabed_flat``, ``weight_extremes`` (reference: MoorPy's ``catenary``, through
  :func:`fuzz_refs.ref_moorpy`), and ``multi_section`` and ``free_end`` (reference: MoorPy's
  ``System`` through :mod:`fuzz3d_moorpy`, the planar scene lifted into the x-z plane);
  segment counts as the fuzz study draws them (1-60 a section);
- 3D (:mod:`fuzz3d_scenes`, :mod:`fuzz3d_systems`): ``s3_buoy``, ``s3_clump``,
  ``s3_three_lines``, the one-line ``c3_taut``, ``c3_slack``, ``c3_vertical``,
  ``c3_mooring``, ``c3_on_bed``, ``c3_multi_section``, ``c3_free_end``, and
  ``s4_four_lines`` (here: a buoy, clump or massless joint held by three anchor legs with a
  riser to a fairlead); every line re-segmented to 40-100 segments (drawn per line, shared
  over its sections by length). Reference: MoorPy's ``System`` (:mod:`fuzz3d_moorpy`).

The classes ``current``, ``bending``, ``cantilever`` (planar) and ``c3_current``,
``s3_current`` (3D) are left out: MoorPy's statics have no drag and no bending.
"""
from __future__ import annotations

import math

import fuzz3d_scenes
import fuzz_scenes
import numpy as np
from fuzz3d_draws import horizontal, seabed3
from fuzz3d_systems import _line, _line_type_for, _sec
from fuzz_draws import RHO, G, Redraw, line_type, log_uniform, weight_of
from fuzz_scenes import _plain, stratified

#: planar classes (fuzz_scenes) and their shares here
PLANAR = {"taut": 0.10, "slack": 0.12, "vertical": 0.06, "near_vertical": 0.04,
          "seabed_mooring": 0.18, "seabed_fully_slack": 0.10, "seabed_u": 0.06,
          "seabed_flat": 0.04, "weight_extremes": 0.08, "multi_section": 0.12,
          "free_end": 0.10}
#: 3D classes (fuzz3d_scenes, and s4_four_lines here) and their shares: 58 % systems
SPACE = {"s3_buoy": 0.16, "s3_clump": 0.16, "s3_three_lines": 0.14, "s4_four_lines": 0.12,
         "c3_taut": 0.05, "c3_slack": 0.06, "c3_vertical": 0.04, "c3_mooring": 0.09,
         "c3_on_bed": 0.09, "c3_multi_section": 0.06, "c3_free_end": 0.03}
SEGMENTS_3D = (40, 100)
REDRAWS = 200


def moorpy_applicable(scene: dict) -> str | None:
    """Why MoorPy cannot answer the scene exactly (None if it can), from the dict alone."""
    cur = (scene.get("environment") or {}).get("current")
    if cur is not None and any(float(v) != 0.0 for v in cur):
        return "current"
    for lt in scene["line_types"].values():
        if float(lt.get("EI", 0.0)) > 0.0:
            return "bending"
        if "weight" in lt and float(lt["weight"]) == 0.0:
            return "weightless"
    ends = [scene.get("end_a"), scene.get("end_b")] + [
        e for ln in scene.get("lines", []) for e in (ln["end_a"], ln["end_b"])]
    if any(isinstance(e, dict) and e.get("condition") == "clamped" for e in ends):
        return "clamped"
    if scene.get("model") == "cable3d" and float((scene.get("environment") or {}).get(
            "water_density", RHO)) == 0.0:
        return "in air"
    return None


# ----------------------------------------------------------------------------- 4 lines
def gen_four_lines(rng):
    """A buoy, a clump or a massless joint P held by three anchor legs (chain, on the bed)
    and a riser (rope or wire) up to a fairlead, fixed or a vessel point."""
    variant = str(rng.choice(["buoy", "clump", "joint"]))
    depth = log_uniform(rng, 50.0, 600.0)
    P = np.array([rng.uniform(-300.0, 300.0), rng.uniform(-300.0, 300.0),
                  -depth * rng.uniform(0.3, 0.85)])
    phi0 = rng.uniform(-math.pi, math.pi)
    ends = []
    for k in range(3):
        phi = phi0 + 2.0 * math.pi * k / 3.0 + rng.uniform(-0.4, 0.4)
        E = P + depth * rng.uniform(0.5, 2.0) * horizontal(phi)
        E[2] = -depth
        ends.append(E)
    F = P + depth * rng.uniform(0.2, 1.5) * horizontal(rng.uniform(-math.pi, math.pi))
    F[2] = -rng.uniform(2.0, 0.3 * depth)
    ends.append(F)
    lengths = [float(np.linalg.norm(E - P)) * rng.uniform(1.0, 1.6) for E in ends[:3]]
    lengths.append(float(np.linalg.norm(F - P)) * rng.uniform(1.0, 1.4))
    fams = ["chain", "chain", "chain", str(rng.choice(["rope", "wire"]))]
    drawn = [line_type(rng, fam) for fam in fams]
    w_l = sum(abs(weight_of(lt)) * L for lt, L in zip(drawn, lengths))
    if variant == "buoy":
        volume = w_l * log_uniform(rng, 0.3, 2.0) / (RHO * G)
        point = {"kind": "free", "position": list(P), "mass": 0.2 * RHO * volume, "volume": volume}
        load = 0.8 * RHO * volume * G
    elif variant == "clump":
        load = w_l * log_uniform(rng, 0.05, 1.0)
        point = {"kind": "free", "position": list(P), "mass": load / G}
    else:
        load, point = 0.0, {"kind": "free", "position": list(P), "mass": 0.0}
    types, lines = {}, []
    for k, (L, fam) in enumerate(zip(lengths, fams)):
        name = f"{fam}{k}"
        _line_type_for(rng, types, name, drawn[k], L, load)
        lines.append(_line(f"line{k}", f"end{k}", "P", [_sec(name, L, rng)]))
    points = {f"end{k}": {"kind": "fixed", "position": list(E)} for k, E in enumerate(ends)}
    if rng.uniform() < 0.5:
        points["end3"]["kind"] = "vessel"
    points["P"] = point
    return variant + ", 3 legs and a riser", {**seabed3(rng, depth), "line_types": types,
                                              "points": points, "lines": lines}


def _four_lines_item(j: int, seed: int) -> dict:
    import symcable as sc
    from symcable.errors import SceneError
    rng = np.random.default_rng([seed, 4, j])
    for _ in range(100):
        try:
            variant, scene = gen_four_lines(rng)
        except Redraw:
            continue
        scene = _plain({"name": f"errest {j:04d} s4_four_lines", "model": "cable3d", **scene})
        try:
            sc.load_scene(scene)
        except SceneError:
            continue
        return {"class": "s4_four_lines", "variant": variant, "scene": scene}
    raise RuntimeError(f"s4_four_lines {j}: no valid draw")


# ----------------------------------------------------------------------------- segments
def resegment(scene: dict, rng, lo: int, hi: int) -> dict:
    """Every line of ``scene`` (in place) given n segments, n drawn in [lo, hi], shared over
    its sections by length (at least 2 a section)."""
    lines = scene.get("lines", [scene])
    for ln in lines:
        n = int(rng.integers(lo, hi + 1))
        L = sum(float(s["length"]) for s in ln["sections"])
        for s in ln["sections"]:
            s["segments"] = max(2, round(n * float(s["length"]) / L))
    return scene


def segments_of(scene: dict) -> dict:
    """{line name: segments} of a scene dict (a one-line scene's line is "line")."""
    if "lines" in scene:
        return {ln["name"]: sum(int(s["segments"]) for s in ln["sections"]) for ln in scene["lines"]}
    return {"line": sum(int(s["segments"]) for s in scene["sections"])}


# ----------------------------------------------------------------------------- the sets
def _draw(i: int, cls: str, seed: int, make) -> tuple[dict, int, list]:
    """The first draw j = i, i + 100000, ... of ``make(j, cls, seed)`` that MoorPy can answer
    and ``load_scene`` takes (the planar generator draws ends up to 2 km above z = 0, which
    the free-surface rule refuses)."""
    import symcable as sc
    from symcable.errors import SceneError
    skipped = []
    for k in range(REDRAWS):
        j = i + 100000 * k
        it = make(j, cls, seed)
        why = moorpy_applicable(it["scene"])
        if why is None:
            try:
                sc.load_scene(it["scene"])
                return it, j, skipped
            except SceneError as exc:
                why = "refused: " + str(exc)[:80]
        skipped.append(why)
    raise RuntimeError(f"{cls} {i}: no scene MoorPy can answer in {REDRAWS} draws")


def planar_item(i: int, cls: str, seed: int) -> dict:
    it, j, skipped = _draw(i, cls, seed, fuzz_scenes.make_scene)
    return {"id": f"p{seed}-{i:04d}", "dim": 2, "class": cls, "variant": it["variant"],
            "draw": j, "skipped": skipped, "scene": it["scene"]}


def _make3d(j: int, cls: str, seed: int) -> dict:
    if cls == "s4_four_lines":
        return _four_lines_item(j, seed)
    return fuzz3d_scenes.make_scene(j, cls, seed)


def space_item(i: int, cls: str, seed: int) -> dict:
    it, j, skipped = _draw(i, cls, seed, _make3d)
    scene = resegment(it["scene"], np.random.default_rng([seed, 5, i]), *SEGMENTS_3D)
    return {"id": f"t{seed}-{i:04d}", "dim": 3, "class": cls, "variant": it["variant"],
            "draw": j, "skipped": skipped, "scene": scene, "model": "cable3d"}


def generate(n_planar: int, n_space: int, seed: int) -> list[dict]:
    """The planar then the 3D scenes, classes in the shares above (largest remainder,
    shuffled by seed); scene i of each set replays from (seed, i) alone."""
    p = stratified(PLANAR, n_planar, np.random.default_rng([seed, 33, 2]))
    s = stratified(SPACE, n_space, np.random.default_rng([seed, 33, 3]))
    return ([planar_item(i, c, seed) for i, c in enumerate(p)]
            + [space_item(i, c, seed) for i, c in enumerate(s)])


def lift_planar(scene: dict) -> dict:
    """A planar scene dict as a cable3d one in the x-z plane (y = 0), for MoorPy's System."""
    out = {k: v for k, v in scene.items() if k not in ("end_a", "end_b", "model", "seabed")}
    out["model"] = "cable3d"
    if "seabed" in scene:
        out["seabed"] = {k: v for k, v in scene["seabed"].items() if k == "stiffness"}
    for key in ("end_a", "end_b"):
        e = dict(scene[key])
        if "position" in e:
            e["position"] = [float(e["position"][0]), 0.0, float(e["position"][1])]
        if "force" in e:
            e["force"] = [float(e["force"][0]), 0.0, float(e["force"][1])]
        out[key] = e
    return out
