"""Independent references of a cable3d fuzz scene, and how well they agree.

Every reference answers with ``{"lines": {name: line record}, "points": {name: [x, y, z]},
"regime"}``; a line record as the planar study's (``F_A``, ``F_B`` now 3D: the force the line
exerts on end A / end B, ``T_A``, ``T_B``, ``grounded``, ``pile``, ``profile`` M x 3, ``s``).
``{"na": why}`` when it does not apply, ``{"failed": why}`` when it applies and fails.

* ``planar:<name>`` -- one line whose ends, current and end force lie in one vertical plane:
  the scene turned into that plane as a planar scene and given to every planar reference of
  :mod:`fuzz_refs` (the study's piecewise closed form, ``symcable.analytic.elastic_catenary``,
  MoorPy's catenary, ODE shooting), their answers turned back into 3D;
* ``ode3d`` -- one suspended line in any current, pinned-pinned or with a free end:
  :mod:`fuzz_ode3d` (3D shooting, continuation in the current);
* ``moorpy_system`` -- any scene without current (points, several lines, sections):
  :mod:`fuzz3d_moorpy`.
"""
from __future__ import annotations

import math

import numpy as np

import fuzz_ode3d as ode3
import fuzz_refs as fr
from fuzz3d_info import Sys3, compare_line
from fuzz_catenary import NoReference

ORDER = ("planar", "ode3d", "moorpy_system")
PLANAR_ORDER = ("piecewise", "catenary", "ode", "moorpy")
AGREE_T, AGREE_G, AGREE_SHAPE = fr.AGREE_T, fr.AGREE_G, fr.AGREE_SHAPE
MOORPY_AGREE_T, MOORPY_AGREE_SHAPE = 1e-5, 1e-4


# ----------------------------------------------------------------------------- the plane
def plane_of(info: Sys3):
    """(origin (3,), unit horizontal u (3,)) of the vertical plane holding a one-line
    scene's ends, current and end forces, or (None, why). The horizontal span between held
    ends, the end forces' and the current's horizontal parts must all lie along u (to 1e-12
    of their size); a vertical line with nothing horizontal lies in the x-z plane."""
    if info.version != 1:
        return None, "several lines"
    ln = info.lines[0]
    held = [e["pos"] for e in ln["ends"].values() if e["kind"] == "held"]
    vecs = [e["force"][:2] for e in ln["ends"].values()] + [info.current[:2]]
    if len(held) == 2:
        vecs.insert(0, held[1][:2] - held[0][:2])
    vecs = [v for v in vecs if np.linalg.norm(v) > 0.0]
    u = vecs[0] / np.linalg.norm(vecs[0]) if vecs else np.array([1.0, 0.0])
    for v in vecs:
        if abs(u[0] * v[1] - u[1] * v[0]) > 1e-12 * float(np.linalg.norm(v)):
            return None, "the line's ends or loads leave their vertical plane"
    return (np.asarray(held[0], float), np.array([u[0], u[1], 0.0])), None


def planar_scene(scene: dict, origin, u) -> dict:
    """The one-line cable3d scene dict as a planar one in the plane (origin, u)."""
    def to2(p):
        d = np.asarray(p, float) - origin
        return [float(d[:2] @ u[:2]), float(p[2])]
    out = {k: v for k, v in scene.items() if k not in ("seabed", "environment", "end_a", "end_b")}
    out["model"] = "planar"
    env = dict(scene.get("environment", {}))
    if "current" in env:
        c = np.asarray(env["current"], float)
        env["current"] = [float(c[:2] @ u[:2]), float(c[2])]
    out["environment"] = env
    if "seabed" in scene:
        out["seabed"] = {k: v for k, v in scene["seabed"].items() if k == "stiffness"}
    for key in ("end_a", "end_b"):
        e = dict(scene[key])
        if "position" in e:
            e["position"] = to2(e["position"])
        if "force" in e:
            f = np.asarray(e["force"], float)
            e["force"] = [float(f[:2] @ u[:2]), float(f[2])]
        out[key] = e
    return out


def to_3d(r: dict, origin, u) -> dict:
    """A planar reference record turned back into 3D."""
    out = dict(r)
    for key in ("F_A", "F_B"):
        out[key] = [r[key][0] * u[0], r[key][0] * u[1], r[key][1]]
    prof = np.asarray(r["profile"], float)
    out["profile"] = np.stack([origin[0] + prof[:, 0] * u[0], origin[1] + prof[:, 0] * u[1],
                               prof[:, 1]], axis=1)
    return out


def planar_refs(scene: dict, info: Sys3) -> dict:
    """Every planar reference of the scene turned into its vertical plane: {"refs": {name:
    3D record or na/failed}, "scene": the planar scene, "plane": (origin, u), "agreement":
    fuzz_refs.agreement of the planar references}; or {"na": why}."""
    from fuzz_tolerance import penalty_effect
    plane, why = plane_of(info)
    if plane is None:
        return {"na": why}
    ps = planar_scene(scene, *plane)
    res = fr.references(ps)
    refs = res["refs"]
    pen = penalty_effect(ps, refs)
    out = {name: (to_3d(r, *plane) if "T_A" in r else r) for name, r in refs.items()
           if name in PLANAR_ORDER}
    return {"refs": out, "scene": ps, "plane": plane, "agreement": res["agreement"],
            "penalty": pen}


# ----------------------------------------------------------------------------- 3D ODE
def ref_ode3d(info: Sys3) -> dict:
    if info.version != 1:
        return {"na": "several lines"}
    ln = info.lines[0]
    if any(x["EI"] > 0 for x in ln["secs"]):
        return {"na": "bending"}
    cable = ode3.Cable3(ln["secs"], info.rho, info.current)
    ea, eb = ln["ends"]["a"], ln["ends"]["b"]
    if ea["kind"] == "held" and eb["kind"] == "held":
        from fuzz_catenary import pinned_line, Line
        guesses = []
        try:   # the line without current in its ends' vertical plane: the start of the ramp
            d = eb["pos"] - ea["pos"]
            h = float(np.hypot(d[0], d[1]))
            uu = d[:2] / h if h > 0 else np.array([1.0, 0.0])
            line = Line([x["length"] for x in ln["secs"]], [x["w"] for x in ln["secs"]],
                        [x["EA"] for x in ln["secs"]])
            r = pinned_line(line, (0.0, ea["pos"][2]), (h, eb["pos"][2]), None)
            guesses.append([r["F_A"][0] * uu[0], r["F_A"][0] * uu[1], r["F_A"][1]])
        except (NoReference, ValueError, ZeroDivisionError, FloatingPointError):
            pass
        chord = (eb["pos"] - ea["pos"]) / max(float(np.linalg.norm(eb["pos"] - ea["pos"])), 1e-12)
        for k in (1.0, 0.1, 10.0):
            guesses.append(k * max(cable.W, 1.0) * chord + np.array([0.0, 0.0, 0.5 * sum(
                x["w"] * x["length"] for x in ln["secs"])]))
        r = ode3.pinned(cable, ea["pos"], eb["pos"], guesses)
    elif ea["kind"] == "held" or eb["kind"] == "held":
        free_b = eb["kind"] == "free"
        held = ea if free_b else eb
        r = ode3.free(cable, held["pos"], (eb if free_b else ea)["force"], free_b)
    else:
        return {"na": "end conditions"}
    if info.depth is not None and np.asarray(r["profile"])[:, 2].min() < -info.depth - 1e-9 * ln["L"]:
        return {"na": "touches the seabed"}
    return {"lines": {ln["name"]: r}, "points": {}, "regime": "ode3d"}


# ----------------------------------------------------------------------------- all
def references(scene: dict) -> dict:
    """Every reference of the scene: {"refs": {name: answer}, "planar": the planar bundle or
    na, "agreement"}. The planar references count as one, ``planar``, answered by the first
    usable of PLANAR_ORDER (the others are compared with it in ``agreement``)."""
    import fuzz3d_moorpy as mpsys
    info = Sys3(scene)
    refs, planar = {}, fr.guard(planar_refs, scene, info)
    if "refs" in planar:
        for name in PLANAR_ORDER:
            r = planar["refs"].get(name, {})
            if fr.usable(r):
                refs["planar"] = {"lines": {info.lines[0]["name"]: r}, "points": {},
                                  "regime": f"planar {name}", "name": name}
                break
        else:
            refs["planar"] = {"failed": "; ".join(f"{n}: {planar['refs'][n].get('na') or planar['refs'][n].get('failed')}"
                                                  for n in PLANAR_ORDER if n in planar["refs"])[:300]}
    else:
        refs["planar"] = planar
    refs["ode3d"] = fr.guard(ref_ode3d, info)
    refs["moorpy_system"] = fr.guard(mpsys.solve, info)
    return {"refs": refs, "planar": planar, "agreement": agreement(info, refs, planar)}


def usable(r: dict) -> bool:
    return "lines" in r


def primary(refs: dict):
    for name in ORDER:
        if usable(refs.get(name, {})):
            return name, refs[name]
    return None, None


def agreement(info: Sys3, refs: dict, planar: dict) -> dict:
    """Pairwise agreement of the references that answered (each planar one on its own, the
    3D ones), per line and at the free points: the largest deviations, and whether each pair
    is within AGREE_* (tensions over the tension scale, grounded length and shape over the
    line length, points over the shortest attached line)."""
    answers = {}
    if "refs" in planar:
        for n in PLANAR_ORDER:
            r = planar["refs"].get(n, {})
            if fr.usable(r):
                answers[f"planar:{n}"] = {"lines": {info.lines[0]["name"]: r}, "points": {}}
    for n in ("ode3d", "moorpy_system"):
        if usable(refs.get(n, {})):
            answers[n] = refs[n]
    names = list(answers)
    pairs = []
    for i, a in enumerate(names):
        for b in names[i + 1:]:
            worst = {"dT": 0.0, "dG": 0.0, "shape": 0.0, "points": 0.0}
            for k, ln in enumerate(info.lines):
                ra, rb = answers[a]["lines"][ln["name"]], answers[b]["lines"][ln["name"]]
                comparable = ra.get("shape_comparable", True) and rb.get("shape_comparable", True)
                if len(ra["profile"]) < len(rb["profile"]):   # the denser profile as the curve
                    ra, rb = rb, ra
                sub = np.asarray(rb["profile"])[:: max(1, len(rb["profile"]) // 200)]
                c = compare_line(info, k, ra, rb["T_A"], rb["T_B"], rb["grounded"],
                                 sub if comparable else None)
                worst["dT"] = max(worst["dT"], c["dT_A"], c["dT_B"])
                worst["dG"] = max(worst["dG"], c["dG"])
                if c["shape"] == c["shape"]:
                    worst["shape"] = max(worst["shape"], c["shape"])
            for name, pa in answers[a]["points"].items():
                pb = answers[b]["points"].get(name)
                if pb is not None:
                    Lmin = min(info.lines[k]["L"] for k, _ in info.points[name]["attached"])
                    worst["points"] = max(worst["points"], math.dist(pa, pb) / Lmin)
            ok = (worst["dT"] <= AGREE_T and worst["dG"] <= AGREE_G
                  and worst["shape"] <= AGREE_SHAPE and worst["points"] <= AGREE_SHAPE)
            pairs.append({"pair": f"{a}-{b}", **worst, "ok": ok})
    return {"names": names, "pairs": pairs, "ok": all(p["ok"] for p in pairs)}


def strip(refs: dict) -> dict:
    """The references without their profiles (for JSON)."""
    out = {}
    for name, r in refs.items():
        if "lines" in r:
            out[name] = {"regime": r.get("regime"), "points": r.get("points"), "lines": {
                k: {kk: v for kk, v in x.items() if kk not in ("profile", "s")}
                for k, x in r["lines"].items()}}
        else:
            out[name] = {k: v for k, v in r.items() if k not in ("profile", "s")}
    return out
