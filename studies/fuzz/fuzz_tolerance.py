"""The comparison tolerance of a fuzz answer against a reference: the planar model's
discretisation error, and the modelling difference of its penalty seabed.

The planar model is second order in the segment length; where the reference turns by more
than ``UNRESOLVED_TURN`` within one segment (a fold, a sharp bend) or lies on the seabed (the
touchdown falls between nodes) its error is first order, and so it is for a rod whose
bending boundary layer a segment does not resolve. A penalty seabed lets the line sink into
it, and where a held end rests on the bed the line bends down from it, which adds path length.
A comparison allows the sum of these error scales times constants measured by refining
(``fuzz_refine``; README, "Tolerance"), plus a floor.
"""
from __future__ import annotations

import math

import numpy as np

import fuzz_refs as fr

#: comparison tolerance = sum of constants times the error scales of ``tolerance_terms``,
#: plus a floor; the constants are about twice the largest measured by refining scenes that
#: converge to their reference (README, "Tolerance")
TOL = {"T2": 4.0, "T1": 0.6, "TB": 5.0, "TC": 1.0, "Tpen": 1.0,
       "S2": 4.0, "S1": 1.0, "SB": 4.0, "Spen": 2.0,
       "G1": 3.0, "Gpen": 1.0, "floor": 1e-3}
UNRESOLVED_TURN = 1.0      # rad within one segment


def _on_bed(info: fr.Info, name: str) -> bool:
    e = info.ends[name]
    return e["cond"] != "free" and abs(e["pos"][1] + info.depth) <= 1e-9 * info.L


def penetration(info: fr.Info) -> float:
    """How far the penalty seabed lets the line sink under its own weight, m:
    max |w| / (stiffness * min diameter)."""
    w_max = max(abs(x["w"]) for x in info.secs)
    return w_max / (info.secs[0]["k_bed"] * min(x["d"] for x in info.secs))


def penalty_effect(scene: dict, refs: dict) -> dict:
    """The modelling difference of the penalty seabed against the references' rigid one, as
    the change of the primary reference (in the units of ``fuzz_refs.compare``) under two
    perturbations, added: (1) the bed and every end resting on it lowered by the penetration;
    (2) the extra path where the sunken line bends down from a held end resting on the bed,
    ``pen^2 / (4 l)`` per such end with ``l = sqrt(H / (k d))`` (a line under horizontal
    tension H on an elastic foundation of stiffness k d), given to the reference as that much
    more span."""
    info = fr.Info(scene)
    name, ref = fr.primary(refs)
    if info.depth is None or ref is None or ref["grounded"] <= 0.0:
        return {"na": "no contact"}
    pen = penetration(info)
    low = dict(scene, environment=dict(scene["environment"], depth=info.depth + pen))
    for end, key in (("A", "end_a"), ("B", "end_b")):
        if _on_bed(info, end):
            low[key] = dict(scene[key], position=[scene[key]["position"][0],
                                                  scene[key]["position"][1] - pen])
    out = {"pen": pen, "dT": 0.0, "dG": 0.0, "extra_path": 0.0}
    wide = dict(scene)
    k = info.secs[0]["k_bed"]
    for end, key, sec, sign in (("A", "end_a", info.secs[0], -1.0), ("B", "end_b", info.secs[-1], 1.0)):
        H = abs(ref["F_A"][0] if end == "A" else ref["F_B"][0])
        if _on_bed(info, end) and H > 0.0:
            p_end = abs(sec["w"]) / (k * sec["d"])
            extra = p_end ** 2 / (4.0 * math.sqrt(H / (k * sec["d"])))
            other = info.ends["B" if end == "A" else "A"]["pos"]
            away = math.copysign(1.0, scene[key]["position"][0] - other[0]) if \
                scene[key]["position"][0] != other[0] else sign
            wide[key] = dict(scene[key], position=[scene[key]["position"][0] + away * extra,
                                                   scene[key]["position"][1]])
            out["extra_path"] += extra
    for changed in (low, wide) if out["extra_path"] > 0 else (low,):
        r = fr.guard(fr.FUNCTIONS[name], fr.Info(changed))
        if "T_A" not in r:
            return {"failed": r.get("failed") or r.get("na"), "pen": pen}
        c = fr.compare(info, ref, r["T_A"], r["T_B"], r["grounded"], None)
        out["dT"] += max(c["dT_A"], c["dT_B"])
        out["dG"] += c["dG"]
    return out


def turn_per_segment(info: fr.Info, ref: dict) -> float:
    """Largest turn of the reference tangent over one segment length, rad (a fold: pi)."""
    prof, s = np.asarray(ref["profile"]), np.asarray(ref["s"])
    d = np.diff(prof, axis=0)
    keep = np.hypot(d[:, 0], d[:, 1]) > 1e-12 * info.L
    if keep.sum() < 2:
        return 0.0
    phi = np.unwrap(np.arctan2(d[keep, 1], d[keep, 0]))
    sm = 0.5 * (s[:-1] + s[1:])[keep]
    ds_of = np.interp(sm, np.concatenate([[0.0], np.cumsum([x["length"] for x in info.secs])])[1:],
                      [x["length"] / x["segments"] for x in info.secs], left=np.nan)
    ds_of = np.where(np.isnan(ds_of), info.secs[0]["length"] / info.secs[0]["segments"], ds_of)
    worst = 0.0
    for j in range(sm.size):
        window = np.abs(sm - sm[j]) <= 0.5 * ds_of[j]
        worst = max(worst, float(np.ptp(phi[window])))
    return min(worst, math.pi)


def tolerance_terms(info: fr.Info, ref: dict, penalty: dict | None) -> dict:
    """The error scales a comparison with a reference must allow (see TOL): second order in
    the segment length; first order (a segment's weight, a segment length) where the
    reference turns more than ``UNRESOLVED_TURN`` within one segment (a fold, a sharp bend)
    or lies on the seabed (the touchdown falls between nodes), more so for a rod folded
    within a segment; a clamped rod whose bending length sqrt(EI / T) is shorter than a
    segment (the clamp's boundary layer unresolved: its end tensions are then not judged,
    ``ec`` = 1 with constant 1); the penalty seabed's effect."""
    ds = max(x["length"] / x["segments"] for x in info.secs)
    n_eff = info.L / ds
    dphi = turn_per_segment(info, ref)
    unresolved = ref["grounded"] > 0.0 or dphi > UNRESOLVED_TURN
    # a held end on the seabed: a touchdown at it (reference grounded length 0) is resolved
    # to a segment too (the discrete line may rest part of its first segment)
    on_bed = info.depth is not None and any(
        e["cond"] != "free" and e["pos"][1] <= -info.depth + 1e-9 * info.L
        for e in info.ends.values())
    w = max(abs(x["w"]) for x in info.secs)
    pen = penalty if penalty and "dT" in penalty else {"pen": 0.0, "dT": 0.0, "dG": 0.0}
    rod = 1.0 / n_eff if info.bending and dphi > UNRESOLVED_TURN else 0.0
    clamp = 0.0
    if info.bending and any(e["cond"] == "clamped" for e in info.ends.values()):
        ei = max(x["EI"] for x in info.secs)
        if ds > math.sqrt(ei / fr.tension_scale(info, ref)):
            clamp = 1.0
    return {"dphi": dphi, "n_eff": n_eff, "e2": n_eff ** -2, "eb": rod, "ec": clamp,
            "e1_T": w * ds / fr.tension_scale(info, ref) if unresolved else 0.0,
            "e1_L": 1.0 / n_eff if unresolved else 0.0,
            "g1": 1.0 / n_eff if ref["grounded"] > 0.0 or on_bed else 0.0,
            "pen_T": pen["dT"], "pen_G": pen["dG"], "pen_L": pen["pen"] / info.L}


def tolerances(info: fr.Info, ref: dict, penalty: dict | None = None) -> dict:
    t = tolerance_terms(info, ref, penalty)
    c = TOL
    t["T"] = (c["T2"] * t["e2"] + c["T1"] * t["e1_T"] + c["TB"] * t["eb"] + c["TC"] * t["ec"]
              + c["Tpen"] * t["pen_T"] + c["floor"])
    t["shape"] = (c["S2"] * t["e2"] + c["S1"] * t["e1_L"] + c["SB"] * t["eb"]
                  + c["Spen"] * t["pen_L"] + c["floor"])
    t["G"] = c["G1"] * t["g1"] + c["Gpen"] * t["pen_G"] + c["floor"]
    return t


