"""What the study knows of a cable3d scene, read with ``symcable.load_scene`` (which only
parses and validates: the weights are the ones the solver uses), in one form for one-line
(version 1) and several-line (version 2) scenes: the lines with their sections, segments and
ends, the free points with their loads; and how an answer is compared with a reference
(deviations) and how far it may be off (the discretisation tolerance in 3D).
"""
from __future__ import annotations

import math

import numpy as np

from fuzz_refs import curve_distance
from fuzz_tolerance import TOL, UNRESOLVED_TURN

#: the speed below which the model smooths |u| in its drag laws (symcable.models.cable3d.line)
DRAG_SPEED = 1e-4


class Sys3:
    """A cable3d scene as the study sees it.

    ``lines``: list of dicts ``name, secs (length, w, EA, d, cdn, cdt, segments), L, W, ends
    {"a", "b": {"kind": "held" | "point" | "free", "pos", "force", "point"}}``;
    ``points``: name -> ``kind, pos, free, W (net weight, N, down), force (3), drag_area (3),
    attached [(line index, "a" | "b")]``; environment ``rho, g, depth, current, k_bed,
    friction`` (any friction key), ``version``."""

    def __init__(self, scene: dict):
        import symcable as sc
        s = sc.load_scene(scene)
        env = s.environment
        self.version = s.version
        self.rho = 0.0 if env.in_air else env.water_density
        self.g = env.gravity
        self.depth = env.depth
        self.current = np.asarray(env.current, float) if self.rho > 0 else np.zeros(3)
        self.k_bed = s.seabed.stiffness if s.seabed is not None else None
        self.friction = bool(s.seabed is not None and (s.seabed.mu_axial > 0 or s.seabed.mu_lateral > 0))
        self.motion = False
        self.points = {}
        for name, pt in s.points.items():
            self.points[name] = {
                "kind": pt.kind.value, "pos": np.asarray(pt.position, float), "free": pt.is_free,
                "W": (pt.mass - self.rho * pt.volume) * self.g,
                "force": np.zeros(3) if pt.force is None else np.asarray(pt.force, float),
                "drag_area": np.asarray(pt.drag_area, float), "attached": []}
            self.motion |= pt.motion is not None
        raw = [("line", s.sections, s.end_a, s.end_b)] if s.version == 1 else \
            [(ln.name, ln.sections, ln.end_a, ln.end_b) for ln in s.lines]
        self.lines = []
        for k, (name, sections, ea, eb) in enumerate(raw):
            secs = [{"length": x.length, "w": x.line_type.weight, "EA": x.line_type.EA,
                     "d": x.line_type.diameter, "cdn": x.line_type.cd_normal,
                     "cdt": x.line_type.cd_tangential, "segments": x.segments, "EI": x.line_type.EI}
                    for x in sections]
            ends = {}
            for key, end in (("a", ea), ("b", eb)):
                if isinstance(end, str):
                    pt = self.points[end]
                    pt["attached"].append((k, key))
                    ends[key] = {"kind": "point" if pt["free"] else "held", "point": end,
                                 "pos": pt["pos"], "force": np.zeros(3)}
                else:
                    self.motion |= end.motion is not None
                    ends[key] = {"kind": "free" if end.condition.value == "free" else "held",
                                 "point": None,
                                 "pos": None if end.position is None else np.asarray(end.position, float),
                                 "force": np.zeros(3) if end.force is None else np.asarray(end.force, float)}
            L = sum(x["length"] for x in secs)
            self.lines.append({"name": name, "secs": secs, "L": L, "ends": ends,
                               "W": sum(abs(x["w"]) * x["length"] for x in secs),
                               "segments": sum(x["segments"] for x in secs)})
        for ln in self.lines:   # what loads a line: its weight, its free ends' forces, its points
            extra = sum(float(np.linalg.norm(e["force"])) for e in ln["ends"].values())
            for e in ln["ends"].values():
                if e["kind"] == "point":
                    pt = self.points[e["point"]]
                    extra += abs(pt["W"]) + float(np.linalg.norm(pt["force"]))
            ln["force_scale"] = ln["W"] + extra
        self.force_scale = sum(ln["W"] for ln in self.lines) + sum(
            abs(p["W"]) + float(np.linalg.norm(p["force"])) for p in self.points.values()) + sum(
            float(np.linalg.norm(e["force"])) for ln in self.lines for e in ln["ends"].values())
        self.segments = sum(ln["segments"] for ln in self.lines)

    def segment_table(self, k: int) -> dict:
        """Per segment of line k: ds, EA, w, d, cdn, cdt (arrays)."""
        cols = {c: [] for c in ("ds", "EA", "w", "d", "cdn", "cdt")}
        for x in self.lines[k]["secs"]:
            for _ in range(x["segments"]):
                cols["ds"].append(x["length"] / x["segments"])
                for c in ("EA", "w", "d", "cdn", "cdt"):
                    cols[c].append(x[c])
        return {c: np.asarray(v, float) for c, v in cols.items()}


def tension_scale(ln: dict, ref: dict) -> float:
    return max(ref["T_A"], ref["T_B"], ln["force_scale"], 1e-12)


def compare_line(info: Sys3, k: int, ref: dict, T_A, T_B, grounded, points) -> dict:
    """Deviations of line k's answer from a reference line: tensions over the tension scale,
    grounded length and the largest distance of the nodes from the reference profile over the
    line length (a node lying on the bed counts as on a slack pile's profile, whose shape on
    the bed is not unique)."""
    ln = info.lines[k]
    scale = tension_scale(ln, ref)
    out = {"dT_A": abs(T_A - ref["T_A"]) / scale, "dT_B": abs(T_B - ref["T_B"]) / scale,
           "dG": abs(grounded - ref["grounded"]) / ln["L"], "shape": math.nan}
    if points is not None and ref.get("shape_comparable", True):
        pts = np.asarray(points, float)
        d = curve_distance(pts, np.asarray(ref["profile"], float))
        if ref.get("pile") and info.depth is not None:
            d = np.minimum(d, np.abs(pts[:, 2] + info.depth))
        out["shape"] = float(d.max()) / ln["L"]
    return out


def turn_per_segment(ln: dict, ref: dict) -> float:
    """Largest turn of the reference tangent within one segment length, rad (a fold: pi):
    the accumulated angle between successive tangents of the profile over a window of one
    segment's unstretched length."""
    prof, s = np.asarray(ref["profile"], float), np.asarray(ref["s"], float)
    d = np.diff(prof, axis=0)
    n = np.linalg.norm(d, axis=1)
    keep = n > 1e-12 * ln["L"]
    if keep.sum() < 2:
        return 0.0
    t = d[keep] / n[keep, None]
    sm = 0.5 * (s[:-1] + s[1:])[keep]
    # the tangents at the ends from the end forces (the line pulls end A along its tangent
    # there, end B against it): a fold at an end shorter than the profile's spacing (a
    # vertical line folded just below its lower end) turns there
    fa, fb = np.asarray(ref["F_A"], float), np.asarray(ref["F_B"], float)
    if np.linalg.norm(fa) > 0:
        t, sm = np.vstack([fa / np.linalg.norm(fa), t]), np.concatenate([[s[0]], sm])
    if np.linalg.norm(fb) > 0:
        t, sm = np.vstack([t, -fb / np.linalg.norm(fb)]), np.concatenate([sm, [s[-1]]])
    turn = np.concatenate([[0.0], np.cumsum(np.arccos(np.clip(np.einsum("ij,ij->i", t[:-1], t[1:]),
                                                                 -1.0, 1.0)))])
    ds = max(x["length"] / x["segments"] for x in ln["secs"])
    worst = 0.0
    for j in range(sm.size):
        hi = np.searchsorted(sm, sm[j] + ds, side="right") - 1
        worst = max(worst, float(turn[hi] - turn[j]))
    return min(worst, math.pi)


#: constants of the terms the 3D tolerance adds to the planar study's (README, "cable3d
#: scenes"): second order in the turn per segment (a line turned sharply by a strong current
#: errs by ~0.05 dphi^2 of its tension, measured on c11-0271 at 9, 18 and 36 segments)
TOL3 = {"T2c": 0.1}


def tolerances_3d(info: Sys3, k: int, ref: dict, pen: dict | None = None) -> dict:
    """The comparison tolerance of line k against a 3D reference: the planar study's terms
    and constants (:mod:`fuzz_tolerance`: second order; first order where the reference turns
    more than 1 rad within a segment or lies on the bed; the penalty seabed's effect ``pen``
    measured on the reference, {"dT", "dG", "pen"}), with the turn measured in 3D, and:

    - the first-order term takes a segment's whole load, weight and drag
      (|w| + 0.5 rho d Cd |U|^2 per metre), not its weight alone;
    - second order in the turn per segment, ``T2c dphi^2`` (a sharply turned line);
    - on a penalty bed, a held end resting on it lifts the line out of contact over the
      length sqrt(H / (k d)) where it bends down into the bed: that much less grounded length
      per such end (the planar study's extra path, as a length)."""
    ln = info.lines[k]
    ds = max(x["length"] / x["segments"] for x in ln["secs"])
    n_eff = ln["L"] / ds
    dphi = turn_per_segment(ln, ref)
    unresolved = ref["grounded"] > 0.0 or dphi > UNRESOLVED_TURN
    on_bed = [key for key, e in ln["ends"].items() if info.depth is not None and e["pos"] is not None
              and e["pos"][2] <= -info.depth + 1e-9 * ln["L"]]
    u2 = float(info.current @ info.current)
    q = max(abs(x["w"]) + 0.5 * info.rho * x["d"] * max(x["cdn"], x["cdt"]) * u2 for x in ln["secs"])
    scale = tension_scale(ln, ref)
    pen = pen or {}
    lift = 0.0
    for key in on_bed:
        f = np.asarray(ref["F_A" if key == "a" else "F_B"], float)
        sec = ln["secs"][0 if key == "a" else -1]
        lift += math.sqrt(float(np.hypot(f[0], f[1])) / (info.k_bed * sec["d"]))
    t = {"dphi": dphi, "n_eff": n_eff, "e2": n_eff ** -2, "eb": 0.0, "ec": 0.0,
         "e2c": dphi ** 2 if dphi <= UNRESOLVED_TURN else 0.0, "e1_T": q * ds / scale if unresolved else 0.0,
         "e1_L": 1.0 / n_eff if unresolved else 0.0,
         "g1": 1.0 / n_eff if ref["grounded"] > 0.0 or on_bed else 0.0,
         "pen_T": pen.get("dT", 0.0), "pen_G": pen.get("dG", 0.0) + lift / ln["L"],
         "pen_L": pen.get("pen", 0.0) / ln["L"]}
    c = TOL
    t["T"] = (c["T2"] * t["e2"] + TOL3["T2c"] * t["e2c"] + c["T1"] * t["e1_T"]
              + c["Tpen"] * t["pen_T"] + c["floor"])
    t["shape"] = c["S2"] * t["e2"] + c["S1"] * t["e1_L"] + c["Spen"] * t["pen_L"] + c["floor"]
    t["G"] = c["G1"] * t["g1"] + c["Gpen"] * t["pen_G"] + c["floor"]
    return t


def penetration(info: Sys3) -> float:
    """How far the penalty seabed lets the lines sink under their own weight, m:
    max |w| / (stiffness * min diameter) over the lines."""
    secs = [x for ln in info.lines for x in ln["secs"]]
    return max(abs(x["w"]) for x in secs) / (info.k_bed * min(x["d"] for x in secs))
