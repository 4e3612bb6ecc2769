"""Comparing a cable3d answer with a reference: each line's deviations (tensions, grounded
length, shape) against its discretisation tolerance (:func:`fuzz3d_info.tolerances_3d`, with
the penalty seabed's effect on the reference), widened by what the lines sharing a free point
may be off by; the free points' places (only the height of a point resting on the bed among
slack lines, whose place there is not unique)."""
from __future__ import annotations

import math

import numpy as np

import fuzz3d_moorpy as mpsys
from fuzz3d_info import Sys3, compare_line, tolerances_3d


def penalties(info: Sys3, name: str, ref: dict, bundle: dict) -> dict:
    """Per line, the penalty seabed's effect on the primary reference ({} where none)."""
    if name == "planar":
        pen = bundle["planar"].get("penalty") or {}
        return {info.lines[0]["name"]: pen} if "dT" in pen else {}
    if name == "moorpy_system":
        return mpsys.penalty_effect(info, ref)
    return {}


def deviations(info: Sys3, ref: dict, sol: dict, pens: dict) -> dict:
    """Each line's deviations and tolerances, the free points' distances, what is off, and
    the worst line (largest deviation over tolerance)."""
    per, off, keys, worst = {}, [], [], (-1.0, None)
    for k, ln in enumerate(info.lines):
        r, s = ref["lines"][ln["name"]], sol["lines"][ln["name"]]
        dev = compare_line(info, k, r, s["T_A"], s["T_B"], s["grounded"], s["positions"])
        per[ln["name"]] = {"deviation": dev, "tolerance": tolerances_3d(info, k, r, pens.get(ln["name"]))}
    coupled(info, ref, per)
    for k, ln in enumerate(info.lines):
        dev, tol = per[ln["name"]]["deviation"], per[ln["name"]]["tolerance"]
        tag = "" if info.version == 1 else f"{ln['name']}: "
        for key, lab in (("dT_A", "T_A"), ("dT_B", "T_B")):
            if dev[key] > tol["T"]:
                off.append(f"{tag}{lab} off by {100 * dev[key]:.3g} % of the tension scale")
                keys.append((ln["name"], key))
        if dev["dG"] > tol["G"]:
            off.append(f"{tag}grounded length off by {dev['dG'] * ln['L']:.4g} m")
            keys.append((ln["name"], "dG"))
        if dev["shape"] > tol["shape"]:
            off.append(f"{tag}shape off by {dev['shape'] * ln['L']:.4g} m")
            keys.append((ln["name"], "shape"))
        ratio = max(dev["dT_A"] / tol["T"], dev["dT_B"] / tol["T"], dev["dG"] / tol["G"],
                    0.0 if math.isnan(dev["shape"]) else dev["shape"] / tol["shape"])
        if ratio > worst[0]:
            worst = (ratio, ln["name"])
    points = {}
    for name, p in ref.get("points", {}).items():
        att = info.points[name]["attached"]
        Lmin = min(info.lines[k]["L"] for k, _ in att)
        diff = np.subtract(p, sol["points"][name]["position"])
        if loose_on_bed(info, ref, name):   # only its height is determined
            diff[:2] = 0.0
        d = float(np.linalg.norm(diff)) / Lmin
        t = max(per[info.lines[k]["name"]]["tolerance"]["shape"] for k, _ in att)
        points[name] = {"deviation": d, "tolerance": t}
        if d > t:
            off.append(f"point {name} off by {d * Lmin:.4g} m")
            keys.append(("point", name))
    largest = max([v for x in per.values() for v in x["deviation"].values() if not math.isnan(v)]
                  + [x["deviation"] for x in points.values()])
    return {"lines": per, "points": points, "off": off, "keys": keys, "worst": worst[1],
            "largest": largest}


def largest_of(dev: dict, keys: list) -> float:
    """The largest of the deviations named by ``keys`` ((line, quantity) or ("point", name))."""
    return max(dev["points"][k]["deviation"] if line == "point"
               else dev["lines"][line]["deviation"][k] for line, k in keys)


def loose_on_bed(info: Sys3, ref: dict, name: str) -> bool:
    """Whether free point ``name`` lies on the bed with every attached line slack there in
    the reference (a pile at it: its place on the bed is not unique)."""
    p = ref["points"][name]
    if info.depth is None or p[2] > -info.depth + 1e-3:
        return False
    for k, key in info.points[name]["attached"]:
        r = ref["lines"][info.lines[k]["name"]]
        if r["T_B" if key == "b" else "T_A"] > 1e-9 * info.lines[k]["force_scale"]:
            return False
    return True


def coupled(info: Sys3, ref: dict, per: dict) -> None:
    """Add to each line's tolerance (in place) what the lines sharing a free point with it may
    be off by: a neighbour's end force errs by up to its tension tolerance (times its tension
    scale), and the point balances it with this line's end force; the point moves by up to the
    neighbour's shape tolerance (times its length), and this line's shape and grounded length
    with it. (A clump between a coarse chain on the bed and a fine riser: the riser's tension
    is off by what the chain's touchdown, resolved to a segment, is off.)"""
    from fuzz3d_info import tension_scale
    own = {ln["name"]: dict(per[ln["name"]]["tolerance"]) for ln in info.lines}
    for k, ln in enumerate(info.lines):
        t = per[ln["name"]]["tolerance"]
        scale = tension_scale(ln, ref["lines"][ln["name"]])
        seen = {k}
        for e in ln["ends"].values():
            if e["kind"] != "point":
                continue
            for j, _ in info.points[e["point"]]["attached"]:
                if j in seen:
                    continue
                seen.add(j)
                other = info.lines[j]
                tj = own[other["name"]]
                t["T"] += tj["T"] * tension_scale(other, ref["lines"][other["name"]]) / scale
                t["shape"] += tj["shape"] * other["L"] / ln["L"]
                t["G"] += tj["shape"] * other["L"] / ln["L"]
