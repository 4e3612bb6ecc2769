"""One ``solve_static`` call of a cable3d fuzz scene, and what came of it: the planar study's
outcomes (:mod:`fuzz_classify`: correct, wrong, other equilibrium, nan, clean error, rejected,
ugly error; hang and crash by the runner), with checks written for 3D lines and points.

Physical checks of every converged answer (independent of any reference; loads recomputed by
the study from the scene: lumped submerged weight, Morison drag on each segment from its
direction and strain, the point's weight, buoyancy, drag and applied force; the solver's axial
forces, contact forces and node positions taken as the answer):

- no segment of non-positive length (strain <= -1);
- a cable carries no compression beyond the solver's documented bound (1e-4 of the line's
  force scale, or 5 % of a segment's weight; planar.CABLE_COMPRESSION and FOLD_PUSH);
- no node deeper under the seabed than the penalty lets the heaviest section sink (3 x);
- force balance at every node that moves (interior nodes, free ends) and at every free point
  (the attached lines' end nodes with the point's own loads): this is tension continuity
  along the line, at section joints and through points;
- each held end's reported force is the pull of its segment plus the loads lumped on it, and
  a free end's is minus the force applied there;
- the whole scene in balance: what the held ends carry equals the lines' and points' weight,
  buoyancy, drag and applied forces less what the seabed carries;
- the same answer with the seabed friction and the vessel motions removed (statics apply
  neither: a difference beyond 1e-6 of the line length or the tension scale is wrong).
"""
from __future__ import annotations

import copy
import math
import time

import numpy as np

import fuzz3d_moorpy as mpsys
import fuzz3d_refs as r3
from fuzz3d_compare import deviations, largest_of, penalties
from fuzz3d_info import DRAG_SPEED, Sys3
from fuzz_classify import (BALANCE_REL, COMPRESSION_REL, FOLD_PUSH, PENETRATION_FACTOR,
                           REFINE_FACTORS, REFINE_FALL, captured_output, first_solve,
                           solve_recorded)

TWIN_REL = 1e-6      # friction and motion must change nothing beyond this (of L, of the tension)


def _solution(st) -> dict:
    """The arrays the checks need of a static solution, per line and point."""
    lines = st.lines if hasattr(st, "points") and st.points else {"line": st}
    return {
        "lines": {name: {"positions": ln.positions, "axial_force": ln.axial_force,
                         "strain": ln.strain, "contact_force": ln.contact_force,
                         "F_A": ln.anchor_force, "F_B": ln.fairlead_force,
                         "T_A": ln.anchor_tension, "T_B": ln.fairlead_tension,
                         "grounded": ln.grounded_length} for name, ln in lines.items()},
        "points": {name: {"position": p.position, "force": p.force}
                   for name, p in (getattr(st, "points", None) or {}).items()},
        "tolerance": st.stats.get("tolerance", 0.0)}


def solve(scene: dict) -> dict:
    """``solve_static`` (VM, no generated C) and the arrays the checks need, per line
    (:func:`fuzz_classify.solve_recorded`)."""
    return solve_recorded(scene, _solution)


# ----------------------------------------------------------------------------- checks
def _nodal(info: Sys3, k: int, ln_sol: dict) -> tuple[np.ndarray, np.ndarray]:
    """(nodal force sums (N+1, 3), N; the loads alone (N+1, 3)) of line k at the answer."""
    seg = info.segment_table(k)
    pos = np.asarray(ln_sol["positions"], float)
    T = np.asarray(ln_sol["axial_force"], float)
    d = np.diff(pos, axis=0)
    ell = np.linalg.norm(d, axis=1)
    t = d / np.where(ell > 0, ell, 1.0)[:, None]
    e = ell / seg["ds"] - 1.0
    load = np.zeros_like(d)
    load[:, 2] = -seg["w"] * seg["ds"]
    U = info.current
    if np.any(U != 0.0):
        ut = t @ U
        un = U[None, :] - ut[:, None] * t
        kk = 0.5 * info.rho * seg["d"] * seg["ds"] * np.sqrt(np.maximum(1.0 + e, 0.0))
        load += (kk * seg["cdt"] * np.sqrt(ut * ut + DRAG_SPEED ** 2) * ut)[:, None] * t \
            + (kk * seg["cdn"] * np.sqrt(np.sum(un * un, axis=1) + DRAG_SPEED ** 2))[:, None] * un
    nodal = np.zeros((len(pos), 3))
    loads = np.zeros((len(pos), 3))
    nodal[:-1] += T[:, None] * t + 0.5 * load
    nodal[1:] += -T[:, None] * t + 0.5 * load
    loads[:-1] += 0.5 * load
    loads[1:] += 0.5 * load
    contact = np.asarray(ln_sol["contact_force"], float)
    nodal[:, 2] += contact
    loads[:, 2] += contact
    for key, i in (("a", 0), ("b", len(pos) - 1)):
        if info.lines[k]["ends"][key]["kind"] == "free":
            nodal[i] += info.lines[k]["ends"][key]["force"]
            loads[i] += info.lines[k]["ends"][key]["force"]
    return nodal, loads


def point_own(info: Sys3, name: str) -> np.ndarray:
    """Weight, buoyancy, applied force and drag (at rest in the current) on a free point, N."""
    pt = info.points[name]
    u = info.current
    speed = math.sqrt(float(u @ u) + DRAG_SPEED ** 2)
    return np.array([0.0, 0.0, -pt["W"]]) + pt["force"] + 0.5 * info.rho * pt["drag_area"] * speed * u


def sink_allowance(info: Sys3, lines: list[int]) -> float:
    """How deep under the bed a node of these lines may be, m: PENETRATION_FACTOR times the
    penetration that carries the heaviest of their sections, plus 1e-6 of the shortest."""
    secs = [x for k in lines for x in info.lines[k]["secs"]]
    return PENETRATION_FACTOR * max(max(abs(x["w"]) for x in secs), 1e-12) / (
        info.k_bed * min(x["d"] for x in secs)) + 1e-6 * min(info.lines[k]["L"] for k in lines)


def physical_checks(info: Sys3, sol: dict) -> tuple[list[str], dict]:
    """What is physically impossible in a returned solution, and the measured margins."""
    bad, m = [], {"compression_over_segment_weight": None}
    tol = float(sol.get("tolerance", 0.0))
    T_max = max(float(np.max(np.abs(s["axial_force"]))) for s in sol["lines"].values())
    f_scale = max(info.force_scale, T_max, 1e-300)
    bal = BALANCE_REL * f_scale + 2.0 * tol + 1e-13 * T_max
    at_points = {name: point_own(info, name) for name, p in info.points.items() if p["free"]}
    total = sum(at_points.values()) if at_points else np.zeros(3)
    held_sum = np.zeros(3)
    worst_node = (0.0, "")
    for k, ln in enumerate(info.lines):
        s = sol["lines"][ln["name"]]
        seg = info.segment_table(k)
        strain, axial = np.asarray(s["strain"]), np.asarray(s["axial_force"])
        pos = np.asarray(s["positions"], float)
        if np.any(strain <= -1.0):
            bad.append(f"{ln['name']}: negative segment length: strain {strain.min():.3g} <= -1")
        c_tol = np.maximum(COMPRESSION_REL * ln["force_scale"], FOLD_PUSH * np.abs(seg["w"]) * seg["ds"]) \
            + 1e-12 * float(seg["EA"].max())
        if np.any(axial < -c_tol):
            w_seg = float(np.max(np.abs(seg["w"]) * seg["ds"]))
            m["compression_over_segment_weight"] = -float(axial.min()) / max(w_seg, 1e-300)
            bad.append(f"{ln['name']}: cable in compression: axial force {axial.min():.4g} N "
                       f"(line force scale {ln['force_scale']:.4g} N, one segment's weight {w_seg:.4g} N)")
        if info.depth is not None:
            allow = np.full(len(pos), sink_allowance(info, [k]))
            for key, i in (("a", 0), ("b", len(pos) - 1)):   # a point's node: its lines' sink
                if ln["ends"][key]["kind"] == "point":
                    allow[i] = sink_allowance(info, [j for j, _ in
                                                     info.points[ln["ends"][key]["point"]]["attached"]])
            under = -info.depth - pos[:, 2] - allow
            i = int(np.argmax(under))
            if under[i] > 0:
                bad.append(f"{ln['name']}: through the seabed: node {i} {under[i] + allow[i]:.4g} m "
                           f"under it (the contact allows {allow[i]:.3g} m)")
        nodal, loads = _nodal(info, k, s)
        total = total + loads.sum(axis=0)
        n = len(pos) - 1
        for key, i, rep in (("a", 0, "F_A"), ("b", n, "F_B")):
            e = ln["ends"][key]
            if e["kind"] == "held":
                held_sum += np.asarray(s[rep], float)
                miss = float(np.linalg.norm(nodal[i] - np.asarray(s[rep], float)))
                if miss > bal:
                    bad.append(f"{ln['name']}: the force reported at end {key.upper()} is "
                               f"{miss:.3g} N off its segment's pull plus the loads on the end")
            elif e["kind"] == "point":
                at_points[e["point"]] = at_points[e["point"]] + nodal[i]
            else:   # a free end: the line pulls on it against the applied force
                miss = float(np.linalg.norm(np.asarray(s[rep], float) + e["force"]))
                if miss > bal:
                    bad.append(f"{ln['name']}: the force reported at free end {key.upper()} is "
                               f"{miss:.3g} N off minus the applied force")
        free_nodes = [i for i in range(n + 1) if 0 < i < n
                      or (i == 0 and ln["ends"]["a"]["kind"] == "free")
                      or (i == n and ln["ends"]["b"]["kind"] == "free")]
        if free_nodes:
            r = np.linalg.norm(nodal[free_nodes], axis=1)
            j = int(np.argmax(r))
            if r[j] > worst_node[0]:
                worst_node = (float(r[j]), f"{ln['name']} node {free_nodes[j]}")
    if worst_node[0] > bal:
        bad.append(f"force balance off at {worst_node[1]} by {worst_node[0]:.3g} N "
                   f"(tension continuity; allowed {bal:.3g} N)")
    for name, f in at_points.items():
        # the seabed may push a free point up where it touches the bed (the model's contact,
        # not known to the study): the rest must balance
        lift = max(-float(f[2]), 0.0) if info.depth is not None else 0.0
        if lift > bal:
            z = float(sol["points"][name]["position"][2])
            att = [k for k, _ in info.points[name]["attached"]]
            sink = sink_allowance(info, att)
            # the contact law is max(x, 0) smoothed over 1 % of the sink: its tail at a
            # height h is K width^2 / (4 h), K carrying what presses the point at the sink
            press = max(info.points[name]["W"], 0.0) + float(np.linalg.norm(info.points[name]["force"])) \
                + sum(info.lines[k]["W"] for k in att)
            h = z + info.depth
            tail = press * (0.01 * sink / PENETRATION_FACTOR) ** 2 / (4.0 * max(h, 1e-300) * sink
                                                                     / PENETRATION_FACTOR)
            if h > sink and lift > bal + tail:
                bad.append(f"point {name}: held up by {lift:.3g} N from a seabed it does not "
                           f"touch ({z + info.depth:.3g} m above it)")
            total = total + np.array([0.0, 0.0, lift])
            f = f + np.array([0.0, 0.0, lift])
            m.setdefault("point_contact", {})[name] = lift
        if np.linalg.norm(f) > bal:
            bad.append(f"point {name}: force balance off by {np.linalg.norm(f):.3g} N")
    n_nodes = sum(len(s["positions"]) for s in sol["lines"].values())
    glob = float(np.linalg.norm(total - held_sum))
    m["global_imbalance"] = glob
    m["node_imbalance"] = worst_node[0]
    if glob > BALANCE_REL * f_scale + n_nodes * tol + 1e-13 * T_max * n_nodes:
        bad.append(f"global force balance off by {glob:.3g} N (held ends against weight, "
                   "buoyancy, drag, applied forces and seabed)")
    return bad, m


def twin_scene(scene: dict) -> dict | None:
    """The scene without seabed friction and vessel motions (statics apply neither), or None
    when it has neither."""
    twin = copy.deepcopy(scene)
    changed = False
    sb = twin.get("seabed") or {}
    for key in ("friction", "friction_axial", "friction_lateral"):
        changed |= sb.pop(key, None) is not None
    for holder in [twin.get("end_a"), twin.get("end_b")] + list((twin.get("points") or {}).values()) \
            + [ln.get(k) for ln in twin.get("lines") or [] for k in ("end_a", "end_b")]:
        if isinstance(holder, dict) and holder.pop("motion", None) is not None:
            changed = True
    return twin if changed else None


def twin_check(info: Sys3, scene: dict, sol: dict) -> tuple[list[str], dict | None]:
    twin = twin_scene(scene)
    if twin is None:
        return [], None
    rec = solve(twin)
    if rec.get("solution") is None:
        return [], {"outcome": rec["outcome"], "error": (rec.get("error") or "")[:300]}
    worst = 0.0
    for ln in info.lines:
        a, b = sol["lines"][ln["name"]], rec["solution"]["lines"][ln["name"]]
        scale = max(ln["force_scale"], a["T_A"], a["T_B"])
        worst = max(worst, float(np.max(np.linalg.norm(np.asarray(a["positions"]) - b["positions"], axis=1))) / ln["L"],
                    abs(a["T_A"] - b["T_A"]) / scale, abs(a["T_B"] - b["T_B"]) / scale)
    out = {"outcome": "converged", "deviation": worst}
    if worst > TWIN_REL:
        return [f"the answer changes by {worst:.3g} (of L or the tension scale) when the seabed "
                "friction and vessel motions are removed (statics apply neither)"], out
    return [], out


# ----------------------------------------------------------------------------- references
def other_equilibrium(info: Sys3, sol: dict, pens: dict) -> dict:
    """MoorPy's System started from the answer (its free points, section joints and free
    ends where the answer puts them): {"same": True, "why"} when it converges there, to
    within the tolerance, and is stable there (the lowest eigenvalue of its stiffness > 0)."""
    start = {}
    for name, p in sol["points"].items():
        if info.points[name]["free"]:
            start[name] = np.asarray(p["position"], float)
    for k, ln in enumerate(info.lines):
        pos = np.asarray(sol["lines"][ln["name"]]["positions"], float)
        node = np.cumsum([0] + [x["segments"] for x in ln["secs"]])
        for j in range(1, len(ln["secs"])):
            start[(k, j)] = pos[node[j]]
        start[(k, "a")], start[(k, "b")] = pos[0], pos[-1]
    r = mpsys.solve(info, start=start)
    if "lines" not in r:
        return {"same": False, "why": r.get("failed") or r.get("na")}
    dev = deviations(info, r, sol, pens)
    lam = r.get("min_stiffness")
    out = {"same": not dev["off"] and (lam is None or lam > 0), "largest": dev["largest"],
           "min_stiffness": lam, "off": dev["off"]}
    out["why"] = (f"deviation {dev['largest']:.3g}, lowest stiffness eigenvalue "
                  f"{lam if lam is None else format(lam, '.3g')} N/m")
    return out


def refined(scene: dict, ref: dict, pens: dict, keys: list) -> list | None:
    """The scene with REFINE_FACTORS times the segments of every section: (segments, the
    largest of the deviations that were off (``keys``), within tolerance) each; None when a
    refined solve fails or fails a check."""
    out = []
    for factor in REFINE_FACTORS:
        fine = copy.deepcopy(scene)
        for sec in [s for s in fine.get("sections", [])] + [
                s for ln in fine.get("lines", []) for s in ln["sections"]]:
            sec["segments"] = int(sec["segments"]) * factor
        r = solve(fine)
        sol = r.get("solution")
        if sol is None:
            return None
        info = Sys3(fine)
        if physical_checks(info, sol)[0]:
            return None
        dev = deviations(info, ref, sol, pens)
        out.append({"segments": info.segments, "largest": largest_of(dev, keys),
                    "within": not dev["off"]})
    return out


def converges(largest: float, ref_rows: list) -> bool:
    seq = [largest] + [r["largest"] for r in ref_rows]
    return all(b <= a / REFINE_FALL for a, b in zip(seq[:-1], seq[1:])) and ref_rows[-1]["within"]


def classify(scene: dict, bundle: dict, rec: dict) -> dict:
    """Fill in rec's outcome, checks and deviations (drops the arrays)."""
    info = Sys3(scene)
    refs = bundle["refs"]
    sol = rec.pop("solution", None)
    mp = refs.get("moorpy_system", {})
    rec["moorpy_solved"] = None if "na" in mp else "lines" in mp
    name, ref = r3.primary(refs)
    rec["reference"] = name if name != "planar" else f"planar {refs['planar'].get('name')}"
    if sol is None:
        return rec
    arrays = [np.asarray(v, float) for ln in sol["lines"].values() for v in ln.values()] + \
        [np.asarray(v, float) for p in sol["points"].values() for v in p.values()]
    if not all(np.all(np.isfinite(a)) for a in arrays):
        rec["outcome"] = "nan"
        return rec
    problems, margins = physical_checks(info, sol)
    rec.update(margins)
    rec["n_segments"] = info.segments
    rec["min_axial_N"] = min(float(np.min(s["axial_force"])) for s in sol["lines"].values())
    rec["min_strain"] = min(float(np.min(s["strain"])) for s in sol["lines"].values())
    first = sol["lines"][info.lines[0]["name"]]
    rec["T_A"], rec["T_B"], rec["grounded"] = float(first["T_A"]), float(first["T_B"]), float(first["grounded"])
    twin_problems, rec["twin"] = twin_check(info, scene, sol)
    problems += twin_problems
    if ref is not None:
        pens = penalties(info, name, ref, bundle)
        dev = deviations(info, ref, sol, pens)
        w = dev["lines"][dev["worst"]]
        rec["deviation"], rec["tolerance"] = w["deviation"], w["tolerance"]
        rec["points_deviation"] = dev["points"]
        off = dev["off"]
        if off and not problems:
            rows = refined(scene, ref, pens, dev["keys"])
            rec["refined"] = rows
            if rows and converges(largest_of(dev, dev["keys"]), rows):
                rec["note"] = (f"off the {rec['reference']} reference at {info.segments} segments ("
                               + "; ".join(off) + "), converging to it with more: "
                               "a pre-asymptotic discretisation error")
                off = []
        if off and not problems and name == "moorpy_system":
            other = other_equilibrium(info, sol, pens)
            rec["other"] = other
            if other.get("same"):
                rec["problems"] = [f"another equilibrium than the {rec['reference']} reference's "
                                   f"(MoorPy started from this answer stays there: "
                                   f"{other['why']}): " + "; ".join(off)]
                rec["outcome"] = "other equilibrium"
                return rec
        if off:
            problems.append(f"off the {rec['reference']} reference (tol "
                            f"{100 * w['tolerance']['T']:.2g} % T, "
                            f"{100 * w['tolerance']['shape']:.2g} % L): " + "; ".join(off))
    rec["problems"] = problems
    rec["outcome"] = "wrong" if problems else "correct"
    return rec


def run_scene(item: dict, notify=None) -> dict:
    """The solve, then the references, then the classification of one cable3d scene
    (:func:`fuzz_classify.first_solve`)."""
    rec = first_solve(item, notify, solve)
    if rec["outcome"] == "rejected":
        return rec
    t0 = time.perf_counter()
    with captured_output():
        bundle = r3.references(item["scene"])
    t_ref = time.perf_counter() - t0
    with captured_output():
        rec = classify(item["scene"], bundle, rec)
    rec.update(ref_time_s=t_ref, refs=r3.strip(bundle["refs"]), agreement=bundle["agreement"])
    return rec


if __name__ == "__main__":  # replay: python fuzz3d_classify.py out/failures3d.json c11-0007
    import json
    import os
    import sys
    from pathlib import Path
    if not os.environ.get("PYTHONPATH"):   # this tree's symcable, as run.py measures it
        sys.path.insert(1, str(Path(__file__).resolve().parents[2]))
    for it in json.load(open(sys.argv[1])):
        if len(sys.argv) < 3 or it["id"] == sys.argv[2]:
            item = {"id": it["id"], "class": it.get("class") or it.get("cls"),
                    "variant": it.get("variant"), "scene": it["scene"]}
            print(json.dumps(run_scene(item), indent=1, default=str)[:4000])
