"""MoorPy's ``System`` as a reference for cable3d scenes without current: fixed and vessel
points fixed, free points with their mass, volume and applied force, each section a MoorPy
line of its own joined to the next at a massless free point, a free inline end a massless
free point carrying the end's force; a flat seabed (rigid, frictionless: MoorPy's CB = 0), or
none (far below). MoorPy's lines are exact elastic catenaries; its answer is checked before
use: every free point in balance (solved again, tighter, if not), every profile ending at its
line's ends, nothing through its seabed, no line end above the water (MoorPy drops a line's
buoyancy there; symcable has no free surface).

Each line of the answer is a reference record (``F_A``, ``F_B`` (3), ``T_A``, ``T_B``,
``grounded``, ``pile``, ``profile`` (M x 3), ``s``), and ``points`` the free points'
positions.
"""
from __future__ import annotations

import contextlib
import io
import math
import os
import warnings

import numpy as np

from fuzz3d_info import Sys3

os.environ.setdefault("PYTHONBREAKPOINT", "0")   # MoorPy calls breakpoint() on some errors
NODES = 201           # profile points per MoorPy line
TOL = 1e-6            # m, MoorPy's equilibrium tolerance (its catenaries to 1e-8 m)
POINT_ZTOL = 1e-3     # m, the ramp over which MoorPy's seabed carries a point (default 2 m)


def applies(info: Sys3) -> str | None:
    """Why MoorPy's System cannot represent the scene (None if it can)."""
    if np.any(info.current != 0.0):
        return "current (MoorPy's statics have no drag on the deformed line)"
    if any(x["EI"] > 0 for ln in info.lines for x in ln["secs"]):
        return "bending"
    if any(x["w"] == 0.0 for ln in info.lines for x in ln["secs"]):
        return "a weightless section"
    if info.rho == 0.0:
        return "in air"
    return None


def _guess(info: Sys3, k: int, key: str) -> np.ndarray:
    """A start for a free end's position: the scene's point, else below the held end."""
    e = info.lines[k]["ends"][key]
    if e["kind"] == "point":
        return info.points[e["point"]]["pos"]
    other = info.lines[k]["ends"]["b" if key == "a" else "a"]
    return np.asarray(other["pos"], float) + np.array([0.0, 0.0, -0.5 * info.lines[k]["L"]])


def solve(info: Sys3, depth_shift: float = 0.0, start: dict | None = None) -> dict:
    """MoorPy's answer for the scene (``depth_shift``: the seabed, and every held point on it,
    that much lower; ``start``: free point positions to start from), or {"failed"/"na": why}."""
    import moorpy as mp
    why = applies(info)
    if why:
        return {"na": why}
    lengths = [ln["L"] for ln in info.lines]
    zs = [e["pos"][2] for ln in info.lines for e in ln["ends"].values() if e["pos"] is not None]
    depth = info.depth + depth_shift if info.depth is not None else \
        10.0 * (sum(lengths) + max(abs(z) for z in zs) + 1.0)
    if max(zs) > -1e-9 * max(lengths):
        return {"na": "an end at or above the water surface"}
    ms = mp.System(depth=depth, rho=info.rho, g=info.g)
    ids = {}

    def add_point(key, kind, pos, m=0.0, v=0.0, f=None):
        pos = np.array(pos, float)
        if kind == 1 and info.depth is not None and pos[2] <= -info.depth + 1e-9:
            pos[2] -= depth_shift
        p = ms.addPoint(kind, pos, m=m, v=v, fExt=np.zeros(3) if f is None else np.asarray(f, float))
        p.zSpan = [-2e9, -1e9]   # fully submerged at any z: symcable has no free surface
        p.zTol = POINT_ZTOL
        ids[key] = len(ms.pointList)
        return ids[key]

    for name, pt in info.points.items():
        if pt["free"]:
            pos = pt["pos"] if not start or name not in start else start[name]
            # MoorPy's weight is m g less rho v g: the study's net weight W
            add_point(name, 0, pos, m=max(pt["W"], 0.0) / info.g,
                      v=max(-pt["W"], 0.0) / (info.rho * info.g), f=pt["force"])
        else:
            add_point(name, 1, pt["pos"])
    pieces = {}
    for k, ln in enumerate(info.lines):
        ends = []
        for key in ("a", "b"):
            e = ln["ends"][key]
            if e["kind"] in ("held", "point") and e["point"] is not None:
                ends.append(ids[e["point"]])
            elif e["kind"] == "held":
                ends.append(add_point((k, key), 1, e["pos"]))
            else:
                pos = _guess(info, k, key) if not start or (k, key) not in start else start[(k, key)]
                ends.append(add_point((k, key), 0, pos, f=e["force"]))
        pa, pb = ms.pointList[ends[0] - 1].r, ms.pointList[ends[1] - 1].r
        s_at = np.cumsum([0.0] + [x["length"] for x in ln["secs"]]) / ln["L"]
        chain = [ends[0]]
        for j in range(1, len(ln["secs"])):
            pos = pa + s_at[j] * (pb - pa) if not start or (k, j) not in start else start[(k, j)]
            chain.append(add_point((k, j), 0, pos))
        chain.append(ends[1])
        pieces[k] = []
        for j, x in enumerate(ln["secs"]):
            tname = f"l{k}s{j}"
            # MoorPy's submerged weight is (m - rho pi d^2 / 4) g: a mass giving the study's w
            mass = x["w"] / info.g + info.rho * math.pi * x["d"] ** 2 / 4.0
            ms.setLineType(name=tname, mass=mass, d_vol=x["d"], EA=x["EA"], w=x["w"],
                           dnommm=1000.0 * x["d"])
            ms.addLine(x["length"], tname, nSegs=NODES - 1, pointA=chain[j], pointB=chain[j + 1])
            pieces[k].append(len(ms.lineList) - 1)
    try:
        with contextlib.redirect_stdout(io.StringIO()), warnings.catch_warnings():
            warnings.simplefilter("ignore")
            ms.initialize()
            ok = ms.solveEquilibrium(tol=TOL, maxIter=1000)
            if ok is not False and _worst_point(ms) > 1e-6 * max(info.force_scale, 1e-12):
                ok = ms.solveEquilibrium(tol=1e-3 * TOL, maxIter=2000)   # once more, tighter
            for line in ms.lineList:
                line.staticSolve(tol=0.01 * TOL, profiles=1)
    except Exception as exc:  # noqa: BLE001 - MoorPy failing is data
        return {"failed": f"MoorPy: {type(exc).__name__}: {exc}"[:300]}
    if ok is False:
        return {"failed": "MoorPy's solveEquilibrium did not converge"}
    out = _answer(info, ms, ids, pieces, depth)
    if start and "lines" in out:   # is it a stable equilibrium of MoorPy's? (K = -dF/dx)
        try:
            K = np.asarray(ms.getSystemStiffnessA(DOFtype="free"), float)
            out["min_stiffness"] = float(np.linalg.eigvalsh(0.5 * (K + K.T)).min()) if K.size else None
        except Exception:  # noqa: BLE001
            out["min_stiffness"] = None
    return out


def _worst_point(ms) -> float:
    """The largest net force on MoorPy's free points, N."""
    return max([float(np.linalg.norm(p.getForces(xyz=True))) for p in ms.pointList if p.type == 0]
               + [0.0])


def _answer(info: Sys3, ms, ids: dict, pieces: dict, depth: float) -> dict:
    scale = max(info.force_scale, 1e-12)
    for key, i in ids.items():
        p = ms.pointList[i - 1]
        if p.type == 0:
            f = np.asarray(p.getForces(xyz=True), float)
            if np.linalg.norm(f) > 1e-6 * scale:
                return {"failed": f"MoorPy's point {key} off balance by {np.linalg.norm(f):.3g} N"}
    for p in ms.pointList:   # MoorPy's vertical profile gets the sign of a folded end's force
        if p.type == 0 and any(ms.lineList[i - 1].info.get("ProfileType") == 6 for i in p.attached):
            return {"na": "a vertical line (MoorPy's profile 6) at a free point: MoorPy gets "
                          "the sign of a folded end's force wrong"}
    lines = {}
    for k, ln in enumerate(info.lines):
        prof, s, grounded, pile, comparable = [], [], 0.0, False, True
        s0 = 0.0
        for j in pieces[k]:
            line = ms.lineList[j]
            xyz = np.stack([line.Xs, line.Ys, line.Zs], axis=1)
            for end, r in ((xyz[0], line.rA), (xyz[-1], line.rB)):
                if np.linalg.norm(end - r) > 1e-5 * ln["L"]:
                    return {"failed": f"MoorPy's profile of line {ln['name']} misses its end by "
                                      f"{np.linalg.norm(end - r):.3g} m"}
            if xyz[:, 2].min() < -depth - 1e-6 * ln["L"]:
                return {"failed": f"MoorPy's line {ln['name']} goes through its seabed"}
            if max(line.rA[2], line.rB[2]) > 0.0:   # MoorPy then changes the line's weight
                return {"na": f"line {ln['name']} ends above the water surface"}
            ptype = line.info.get("ProfileType")
            # slack on the bed (H = 0 on the grounded part): its shape there is not unique
            pile |= ptype in (4, 5) or (line.LBot > 0 and abs(line.HF) <= 1e-9 * scale)
            comparable &= ptype not in (4, 5, 6)
            prof.append(xyz)
            s.append(s0 + np.linspace(0.0, line.L, len(xyz)))
            s0 += line.L
            grounded += float(line.LBot)
        first, last = ms.lineList[pieces[k][0]], ms.lineList[pieces[k][-1]]
        lines[ln["name"]] = {
            "F_A": [float(v) for v in first.fA], "F_B": [float(v) for v in last.fB],
            "T_A": float(np.linalg.norm(first.fA)), "T_B": float(np.linalg.norm(last.fB)),
            "grounded": grounded, "pile": pile, "shape_comparable": comparable,
            "profile": np.concatenate(prof), "s": np.concatenate(s), "regime": "moorpy system"}
    points = {name: np.asarray(ms.pointList[i - 1].r, float).tolist() for name, i in ids.items()
              if isinstance(name, str) and info.points[name]["free"]}
    return {"lines": lines, "points": points, "regime": "moorpy system"}


def penalty_effect(info: Sys3, ref: dict) -> dict:
    """The penalty seabed's difference from MoorPy's rigid one: MoorPy's answer with the bed
    (and every held point on it) lowered by the penetration that carries the heaviest line,
    per line (dT over the tension scale, dG over the length), as the planar study's
    :func:`fuzz_tolerance.penalty_effect` (its second term, the path where a stretched line
    bends down from a held end on the bed, is left out: it matters for lines stretched flat
    along the bed, which have their planar reference)."""
    from fuzz3d_info import penetration, tension_scale
    if info.depth is None or "lines" not in ref or not any(r["grounded"] > 0 for r in ref["lines"].values()):
        return {}
    pen = penetration(info)
    low = solve(info, depth_shift=pen, start=None)
    if "lines" not in low:
        return {"failed": low.get("failed") or low.get("na"), "pen": pen}
    out = {}
    for ln in info.lines:
        a, b = ref["lines"][ln["name"]], low["lines"][ln["name"]]
        sc = tension_scale(ln, a)
        out[ln["name"]] = {"pen": pen, "dT": max(abs(a["T_A"] - b["T_A"]), abs(a["T_B"] - b["T_B"])) / sc,
                           "dG": abs(a["grounded"] - b["grounded"]) / ln["L"]}
    return out
