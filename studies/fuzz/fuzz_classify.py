"""One ``solve_static`` call of a fuzz scene, and what came of it.

Outcomes (``record["outcome"]``):

* ``correct`` -- status converged, every physical check passes, and within tolerance of the
  primary reference where one applies;
* ``wrong`` -- status converged but a physical check fails (``strain <= -1``; a cable, EI = 0,
  in compression beyond round-off; a node deeper under the seabed than the penalty contact
  allows; compression beyond every buckling load of a rod; global force balance off) or off
  the reference beyond the discretisation tolerance;
* ``nan`` -- a non-finite number in the returned solution;
* ``clean error`` -- ConvergenceError or another SymcableError, with a message;
* ``rejected`` -- SceneError: the scene was refused as input, with a message (the generator
  keeps to the documented checks; a weightless free end with no load, whose shape is
  undetermined, is the one scene a validation may rightly refuse);
* ``ugly error`` -- any other exception (its type and the traceback's last line);
* ``hang`` and ``crash`` are decided by the runner (time limit; worker died).

* ``other equilibrium`` -- a rod off its BVP reference with every physical check passing
  and stable by the study's own energy Hessian (:mod:`fuzz_stability`): another stable
  branch (a cantilever falling to the other side, a clamped bow snapped through); an
  unstable rod shape is ``wrong``;
* ``hang`` and ``crash`` are decided by the runner (time limit; worker died).

The comparison tolerance (discretisation error and penalty seabed) is
:mod:`fuzz_tolerance`'s.
"""
from __future__ import annotations

import math
import os
import sys
import time
import traceback
import warnings

import numpy as np

import fuzz_refs as fr
from fuzz_stability import UNSTABLE_REL, lowest_eigenvalue
from fuzz_tolerance import penalty_effect, tolerances

# cable compression allowed: the solver's documented promise (planar.CABLE_COMPRESSION and
# FOLD_PUSH), checked here: 1e-4 of the force scale, or 5 % of the segment's own weight
# where a vertical line folds inside that segment (the slack law's wall holds it open; the
# line is uncertain there by a segment's weight, which a warning says). What the push does
# to the answer is measured against the references.
COMPRESSION_REL = 1e-4
FOLD_PUSH = 0.05
PENETRATION_FACTOR = 3.0   # penetration allowed, times the one that carries the line's weight
# global force balance: of the force scale, plus the solve's own tolerance (N per equation)
# summed over the nodes (the equations hold to it, and round-off sets it for stiff lines)
BALANCE_REL = 1e-6


def solve_recorded(scene: dict, keep) -> dict:
    """Call ``solve_static`` (VM, no generated C) and record what came of it: the outcome
    ``rejected`` (SceneError), ``clean error`` (any other SymcableError; a ConvergenceError's
    path and start kept) or ``ugly error`` (anything else, with its traceback's tail) and the
    error; or, solved, ``solution = keep(static solution)`` (what the checks need), status,
    path, start, iterations and symcable's warnings. Always ``time_s`` and the Python
    warnings raised."""
    import symcable as sc
    from symcable.errors import ConvergenceError, SceneError, SymcableError
    rec = {"outcome": None}
    t0 = time.perf_counter()
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            st = sc.solve_static(scene, codegen=False)
        except SceneError as exc:
            rec.update(outcome="rejected", error=str(exc))
        except ConvergenceError as exc:
            rec.update(outcome="clean error", error=f"ConvergenceError: {exc}")
            stats = getattr(exc.partial, "stats", None) or {}
            rec["path"], rec["start"] = stats.get("path"), stats.get("start")
        except SymcableError as exc:
            rec.update(outcome="clean error", error=f"{type(exc).__name__}: {exc}")
        except Exception as exc:  # noqa: BLE001 - what we are counting
            tb = traceback.format_exception(type(exc), exc, exc.__traceback__)
            rec.update(outcome="ugly error", error=f"{type(exc).__name__}: {exc}"[:500],
                       traceback_last=tb[-2].strip().splitlines()[0] if len(tb) > 1 else "",
                       traceback=("".join(tb[-4:]))[-1500:])
        else:
            rec.update(solution=keep(st), status=st.status, path=st.stats.get("path"),
                       start=st.stats.get("start"), iterations=st.stats.get("iterations"),
                       sc_warnings=list(st.warnings))
    rec["time_s"] = time.perf_counter() - t0
    rec["py_warnings"] = sorted({f"{w.category.__name__}: {w.message}"[:200] for w in caught})
    return rec


def _solution(st) -> dict:
    """What the planar checks need of a static solution."""
    return {"s": st.s, "positions": st.positions, "angle": st.angle, "strain": st.strain,
            "axial_force": st.axial_force, "contact_force": st.contact_force,
            "anchor_force": st.anchor_force, "fairlead_force": st.fairlead_force,
            "T_A": st.anchor_tension, "T_B": st.fairlead_tension,
            "grounded": st.grounded_length, "tolerance": st.stats.get("tolerance", 0.0)}


def solve(scene: dict) -> dict:
    """Call ``solve_static`` (VM, no generated C) and keep what the checks need."""
    return solve_recorded(scene, _solution)


# ----------------------------------------------------------------------------- checks
def physical_checks(info: fr.Info, sol: dict) -> list[str]:
    """What is physically impossible in a returned solution (empty list: nothing)."""
    bad = []
    seg = _segment_table(info)
    strain, axial = np.asarray(sol["strain"]), np.asarray(sol["axial_force"])
    if np.any(strain <= -1.0):
        bad.append(f"negative segment length: strain {strain.min():.3g} <= -1")
    cable = seg["EI"] == 0.0
    c_tol = np.maximum(COMPRESSION_REL * info.force_scale, FOLD_PUSH * np.abs(seg["w"]) * seg["ds"]) \
        + 1e-12 * float(seg["EA"].max())
    if np.any(cable) and np.any(axial[cable] < -c_tol[cable]):
        w_seg = float(np.max(np.abs(seg["w"]) * seg["ds"]))
        sol["compression_over_segment_weight"] = -float(axial[cable].min()) / max(w_seg, 1e-300)
        bad.append(f"cable in compression: axial force {axial[cable].min():.4g} N "
                   f"(force scale {info.force_scale:.4g} N, one segment's weight {w_seg:.4g} N)")
    if not np.all(cable):
        euler = 4.0 * math.pi ** 2 * float(seg["EI"].max()) / info.L ** 2
        limit = 2.0 * euler + info.force_scale
        if axial.min() < -limit:
            pos = np.asarray(sol["positions"])
            chord = pos[-1] - pos[0]
            nrm = np.array([-chord[1], chord[0]]) / max(np.hypot(*chord), 1e-300)
            bow = float(np.max(np.abs((pos - pos[0]) @ nrm))) / info.L
            kind = "compressed straight strut" if bow < 1e-3 else "compressed rod"
            bad.append(f"{kind}: axial force {axial.min():.4g} N, beyond twice the clamped "
                       f"Euler load {euler:.3g} N plus the load {info.force_scale:.3g} N "
                       f"(bow {bow:.2g} L)")
    if info.depth is not None:
        pen = float(np.max(-info.depth - np.asarray(sol["positions"])[:, 1]))
        k = info.secs[0]["k_bed"]
        w_max = max(abs(x["w"]) for x in info.secs)
        d_min = min(x["d"] for x in info.secs)
        allow = PENETRATION_FACTOR * max(w_max, 1e-12) / (k * d_min) + 1e-6 * info.L
        if pen > allow:
            bad.append(f"through the seabed: node {pen:.4g} m under it (contact allows "
                       f"{allow:.3g} m)")
    imbalance = force_balance(info, sol, seg)
    f_scale = max(info.force_scale, float(np.max(np.abs(axial))), 1e-300)
    n_nodes = seg["ds"].size + 1
    if imbalance > BALANCE_REL * f_scale + n_nodes * float(sol.get("tolerance", 0.0)):
        bad.append(f"global force balance off by {imbalance:.3g} N")
    return bad


def _segment_table(info: fr.Info) -> dict:
    cols = {k: [] for k in ("ds", "EA", "EI", "w", "d", "cdn", "cdt")}
    for x in info.secs:
        for _ in range(x["segments"]):
            cols["ds"].append(x["length"] / x["segments"])
            for k in ("EA", "EI", "w", "d", "cdn", "cdt"):
                cols[k].append(x[k])
    return {k: np.asarray(v, float) for k, v in cols.items()}


def force_balance(info: fr.Info, sol: dict, seg: dict) -> float:
    """|sum of the forces on the line|, N: weight and drag of each segment (from its angle and
    strain), seabed contact, applied end forces, and the reactions -F_A, -F_B."""
    phi, eps = np.asarray(sol["angle"]), np.asarray(sol["strain"])
    t = np.stack([np.cos(phi), np.sin(phi)], axis=1)
    f = np.zeros((phi.size, 2))
    f[:, 1] = -seg["w"] * seg["ds"]
    U = np.asarray(info.current, float)
    if np.any(U != 0):
        n = np.stack([-t[:, 1], t[:, 0]], axis=1)
        ut, un = t @ U, n @ U
        k = 0.5 * info.rho * seg["d"] * np.sqrt(np.maximum(1.0 + eps, 0.0)) * seg["ds"]
        f += (k * seg["cdt"] * np.abs(ut) * ut)[:, None] * t + (k * seg["cdn"] * np.abs(un) * un)[:, None] * n
    total = f.sum(axis=0)
    total[1] += float(np.sum(sol["contact_force"]))
    for name, key in (("A", "anchor_force"), ("B", "fairlead_force")):
        if info.ends[name]["cond"] == "free":
            total += np.asarray(info.ends[name]["force"], float)   # applied on the line
        else:
            total -= np.asarray(sol[key], float)                    # the end's reaction
    return float(np.hypot(*total))


def classify(scene: dict, refs: dict, rec: dict) -> dict:
    """Fill in rec's outcome, checks and deviations (drops the arrays)."""
    info = fr.Info(scene)
    sol = rec.pop("solution", None)
    rec["moorpy_solved"] = ("T_A" in refs["moorpy"]) if "na" not in refs["moorpy"] else None
    name, ref = fr.primary(refs)
    rec["reference"] = name
    if sol is None:
        return rec
    arrays = [np.asarray(v, float) for k, v in sol.items()]
    if not all(np.all(np.isfinite(a)) for a in arrays):
        rec["outcome"] = "nan"
        return rec
    problems = physical_checks(info, sol)
    rec["n_segments"] = info.segments
    rec["compression_over_segment_weight"] = sol.get("compression_over_segment_weight")
    rec["min_axial_N"] = float(np.min(sol["axial_force"]))
    rec["min_strain"] = float(np.min(sol["strain"]))
    rec["T_A"], rec["T_B"], rec["grounded"] = float(sol["T_A"]), float(sol["T_B"]), float(sol["grounded"])
    if info.bending:  # the rod's stability, judged independently of the solver
        lam = lowest_eigenvalue(info, sol["positions"])
        if lam is not None:
            rec["lowest_eigenvalue"] = lam[0]
            rec["stable_independent"] = bool(lam[0] >= -UNSTABLE_REL * lam[1])
            if not rec["stable_independent"]:
                problems.append(f"unstable equilibrium (independent energy Hessian: lowest "
                                f"eigenvalue {lam[0]:.3g} N/m of {lam[1]:.3g})")
    if ref is not None:
        dev = fr.compare(info, ref, sol["T_A"], sol["T_B"], sol["grounded"], sol["positions"])
        tol = tolerances(info, ref, refs.get("penalty"))
        rec["deviation"], rec["tolerance"] = dev, tol
        off = []
        for key, lab in (("dT_A", "T_A"), ("dT_B", "T_B")):
            if dev[key] > tol["T"]:
                off.append(f"{lab} off by {100 * dev[key]:.3g} % of the tension scale")
        if dev["dG"] > tol["G"]:
            off.append(f"grounded length off by {dev['dG'] * info.L:.4g} m")
        if dev["shape"] > tol["shape"]:
            off.append(f"shape off by {dev['shape'] * info.L:.4g} m")
        if off and name == "bvp" and not problems and rec.get("stable_independent"):
            rec["problems"] = [f"another stable equilibrium than the {name} reference "
                               f"(independent energy Hessian: lowest eigenvalue "
                               f"{rec['lowest_eigenvalue']:.3g} N/m): " + "; ".join(off)]
            rec["outcome"] = "other equilibrium"
            return rec
        if off and not problems:
            refined = refined_deviations(scene, ref, refs)
            rec["refined"] = refined
            if refined and converges(dev, tol, refined):
                rec["note"] = (f"off the {name} reference at {info.segments} segments ("
                               + "; ".join(off) + "), converging to it with more: "
                               "a pre-asymptotic discretisation error")
                off = []
        if off:
            problems.append(f"off the {name} reference (tol {100 * tol['T']:.2g} % T, "
                            f"{100 * tol['shape']:.2g} % L): " + "; ".join(off))
    rec["problems"] = problems
    rec["outcome"] = "wrong" if problems else "correct"
    return rec


#: an answer off its reference counts as a discretisation error when it converges: with the
#: segments doubled and quadrupled, its largest deviation falls by at least REFINE_FALL per
#: doubling (an order of convergence above 0.58) and the last is within its tolerance
REFINE_FACTORS, REFINE_FALL = (2, 4), 1.5


def _largest(dev: dict) -> float:
    return max(v for v in dev.values() if not math.isnan(v))


def _within(dev: dict, tol: dict) -> bool:
    return (max(dev["dT_A"], dev["dT_B"]) <= tol["T"] and dev["dG"] <= tol["G"]
            and (math.isnan(dev["shape"]) or dev["shape"] <= tol["shape"]))


def refined_deviations(scene: dict, ref: dict, refs: dict) -> list | None:
    """(segments, deviation, tolerance) of the scene solved with REFINE_FACTORS times the
    segments of every section; None when a refined solve does not converge or fails a
    physical check."""
    import copy
    out = []
    for factor in REFINE_FACTORS:
        fine = copy.deepcopy(scene)
        for sec in fine["sections"]:
            sec["segments"] = int(sec["segments"]) * factor
        r = solve(fine)
        sol = r.get("solution")
        if sol is None:
            return None
        info = fr.Info(fine)
        if physical_checks(info, sol):
            return None
        dev = fr.compare(info, ref, sol["T_A"], sol["T_B"], sol["grounded"], sol["positions"])
        out.append({"segments": info.segments, "deviation": dev,
                    "tolerance": tolerances(info, ref, refs.get("penalty"))})
    return out


def converges(dev: dict, tol: dict, refined: list) -> bool:
    """Whether the refined answers close in on the reference (see REFINE_FALL)."""
    largest = [_largest(dev)] + [_largest(r["deviation"]) for r in refined]
    falling = all(b <= a / REFINE_FALL for a, b in zip(largest[:-1], largest[1:]))
    return falling and _within(refined[-1]["deviation"], refined[-1]["tolerance"])


def first_solve(item: dict, notify, solve_scene) -> dict:
    """The record of ``solve_scene(item["scene"])`` (what C code printed captured), with the
    item's id, class and variant, ``notify("refs", partial)`` after it (for the runner's time
    limits); a scene refused as input has nothing to compare: its record is final, with no
    references (and no solution)."""
    with captured_output() as printed:
        rec = solve_scene(item["scene"])
    rec["printed"] = printed.text[-500:]
    if notify:
        notify("refs", {k: v for k, v in rec.items() if k != "solution"})
    rec.update(id=item["id"], cls=item["class"], variant=item["variant"])
    if rec["outcome"] == "rejected":
        rec.pop("solution", None)
        rec.update(refs={}, agreement={"names": [], "pairs": [], "ok": True})
    return rec


def run_scene(item: dict, notify=None) -> dict:
    """The solve, then the references, then the classification of one generated scene
    (``notify("refs", partial)`` between the two, for the runner's time limits)."""
    rec = first_solve(item, notify, solve)
    if rec["outcome"] == "rejected":
        return rec
    t0 = time.perf_counter()
    refs = fr.references(item["scene"])
    refs["refs"]["penalty"] = penalty_effect(item["scene"], refs["refs"])
    t_ref = time.perf_counter() - t0
    rec = classify(item["scene"], refs["refs"], rec)
    rec.update(ref_time_s=t_ref, refs=fr.strip(refs["refs"]), agreement=refs["agreement"])
    return rec


class captured_output:
    """Capture what C/C++ code prints on file descriptors 1 and 2 (CasADi's own warnings)."""

    def __enter__(self):
        import tempfile
        self.tmp = tempfile.TemporaryFile(mode="w+b")
        sys.stdout.flush()
        sys.stderr.flush()
        self.saved = [os.dup(1), os.dup(2)]
        os.dup2(self.tmp.fileno(), 1)
        os.dup2(self.tmp.fileno(), 2)
        self.text = ""
        return self

    def __exit__(self, *exc):
        sys.stdout.flush()
        sys.stderr.flush()
        os.dup2(self.saved[0], 1)
        os.dup2(self.saved[1], 2)
        for fd in self.saved:
            os.close(fd)
        self.tmp.seek(0)
        self.text = self.tmp.read().decode(errors="replace")
        self.tmp.close()
        return False


if __name__ == "__main__":  # replay one scene from a JSON file: python fuzz_classify.py f.json id
    import json
    from pathlib import Path
    if not os.environ.get("PYTHONPATH"):   # this tree's symcable, as run.py measures it
        sys.path.insert(1, str(Path(__file__).resolve().parents[2]))
    items = json.load(open(sys.argv[1]))
    items = items if isinstance(items, list) else items["scenes"]
    for it in items:
        if len(sys.argv) < 3 or it["id"] == sys.argv[2]:
            print(json.dumps(run_scene(it), indent=1, default=float)[:3000])
