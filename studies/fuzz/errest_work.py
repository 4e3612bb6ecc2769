"""One scene of the error-estimate study (:mod:`error_estimate`), in a worker process:
symcable's solve with its error estimate, MoorPy's answer, the true error, and (for some
scenes) the estimate's cost and a refined solve.

The stages, each reported to the parent (:mod:`fuzz_pool`) before it starts so each gets its
own time limit: ``solve`` (``sc.solve_static(scene, codegen=False)``, public defaults
otherwise), ``refs`` (MoorPy), ``extra`` (the cost timing and the diagnostics below). A
record's fields: ``outcome`` (solved, clean error, crash), ``sym`` ({line: [T_A, T_B]}, N),
``estimate`` (``stats["discretisation_error"]["max_relative"]`` plus, where a line touches
the bed, ``stats["seabed_error"]["max_relative"]``: the two add at worst; each is also kept,
``est_disc``, ``est_bed``, with the seabed estimate's ``t_bed``, s), ``est_lines`` ({line:
relative}, the discretisation's), ``warned`` (a warning "line '...': discretisation error
about ..." or "... the penalty seabed (stiffness ..."),
``no_estimate`` (the warning that the comparison solve failed), ``ref`` ({line: [T_A, T_B,
grounded]} or None), ``ref_kind``, ``true`` (max over lines and ends of |T - T_MoorPy| over
MoorPy's largest end tension, at least 1e-3 of the scene's weight), ``true_lines``, ``t_solve`` (s, the call with the estimate),
``t_est`` (the estimate's own ``wall_time``), ``t_cold_with`` / ``t_cold_without`` (s, the
call with and without ``estimate``, each in a fresh process: :func:`fresh_time`), and for a
scene off by more than 1 % and not warned, or warned with the estimate more than 3 times off:
``refined`` (the true error of the same scene at ``factor`` times the segments) and
``penalty`` (MoorPy's answer moved by the penalty seabed's penetration: the size of the
rigid-bed-versus-penalty-bed difference, a modelling difference, not a discretisation one).
"""
from __future__ import annotations

import contextlib
import io
import json
import os
import sys
import time
import traceback
import warnings as pywarnings

HERE = os.path.dirname(os.path.abspath(__file__))
ACCURACY = 0.01
MARK = "discretisation error about"
BED_MARK = "the penalty seabed (stiffness"
NO_ESTIMATE = "no discretisation error estimate"


def worker(conn) -> None:
    """The worker loop :func:`fuzz_pool.run_all` starts (installed as its ``_worker``)."""
    os.environ["PYTHONBREAKPOINT"] = "0"
    if HERE not in sys.path:
        sys.path.insert(0, HERE)
    while True:
        item = conn.recv()
        if item is None:
            return
        try:
            rec = run_item(item, notify=lambda *msg: conn.send(("stage", *msg)))
        except Exception:  # noqa: BLE001 - a harness bug is reported, not raised
            rec = {"id": item["id"], "cls": item["class"], "variant": item["variant"],
                   "outcome": "harness error", "error": traceback.format_exc()[-1500:]}
        conn.send(("done", rec))


def fresh_time(scene: dict, estimate: bool) -> float | None:
    """Wall time (s) of ``solve_static(scene, codegen=False, estimate=estimate)`` in a fresh
    Python process (this file run as a script): nothing built before, as a user's first
    call (symcable caches models and solver functions by scene content and by structure,
    so a second call in the same process is no measure). None if it fails."""
    import subprocess

    import symcable
    root = os.path.dirname(os.path.dirname(os.path.abspath(symcable.__file__)))
    try:
        p = subprocess.run([sys.executable, os.path.abspath(__file__), root,
                            "1" if estimate else "0"], input=json.dumps(scene),
                           capture_output=True, text=True, timeout=600, check=False)
        return float(json.loads(p.stdout.strip().splitlines()[-1])["t"])
    except (subprocess.SubprocessError, ValueError, IndexError, KeyError, OSError):
        return None


def _tensions(sol) -> dict:
    return {name: [float(ln.anchor_tension), float(ln.fairlead_tension)]
            for name, ln in sol.lines.items()}


def solve(scene: dict, **kw):
    """``(solution or None, record)`` of ``sc.solve_static(scene, codegen=False, **kw)``."""
    from fuzz_classify import captured_output

    import symcable as sc
    from symcable.errors import SymcableError
    t0 = time.perf_counter()
    try:
        with captured_output(), pywarnings.catch_warnings():
            pywarnings.simplefilter("ignore")
            sol = sc.solve_static(scene, codegen=False, **kw)
    except SymcableError as exc:
        return None, {"outcome": "clean error", "error_type": type(exc).__name__,
                      "error": str(exc)[:600], "t_solve": time.perf_counter() - t0}
    except Exception as exc:  # noqa: BLE001 - the point of the study
        return None, {"outcome": "crash", "error_type": type(exc).__name__,
                      "error": traceback.format_exc()[-1500:], "t_solve": time.perf_counter() - t0}
    return sol, {"outcome": "solved", "t_solve": time.perf_counter() - t0}


def reference(item: dict) -> dict:
    """MoorPy's answer: {"kind", "lines": {line: [T_A, T_B, grounded]}, "full"} or {"na"/"failed"}.
    One planar section between two pinned ends: MoorPy's catenary
    (:func:`fuzz_refs.ref_moorpy`; its vertical profile at a span under 1e-4 of the height,
    "approximate" there, is accepted: it is off by about the span over the length, far under
    the 1 % judged); anything else: MoorPy's System (:mod:`fuzz3d_moorpy`), a planar scene
    lifted into the x-z plane."""
    import fuzz3d_moorpy as mpsys
    import fuzz_refs as fr
    from errest_scenes import lift_planar
    from fuzz3d_info import Sys3
    scene = item["scene"]
    with contextlib.redirect_stdout(io.StringIO()):
        if item["dim"] == 2:
            info = fr.Info(scene)
            if len(info.secs) == 1 and info.pinned_pinned():
                r = fr.guard(fr.ref_moorpy, info)
                if "T_A" not in r:
                    return r
                return {"kind": "moorpy catenary" + (" (vertical)" if r.get("approximate") else ""),
                        "lines": {"line": [r["T_A"], r["T_B"], r["grounded"]]}, "full": r,
                        "force_scale": info.force_scale}
            scene = lift_planar(scene)
        info = Sys3(scene)
        r = fr.guard(mpsys.solve, info)
    if "lines" not in r:
        return r
    return {"kind": "moorpy system", "lines": {k: [v["T_A"], v["T_B"], v["grounded"]]
                                               for k, v in r["lines"].items()}, "full": r,
            "force_scale": info.force_scale}


#: the true error's scale is MoorPy's largest end tension, but at least this fraction of the
#: scene's force scale (submerged weights and applied forces): a slack line lying flat on the
#: bed has zero tension in MoorPy's answer and a few hundredths of a newton in symcable's
#: (its penalty contact), which is no error
SCALE_FLOOR = 1e-3


def true_error(sym: dict, ref: dict, force_scale: float = 0.0) -> tuple[float, dict]:
    """max over lines and ends of |T_sym - T_ref| over MoorPy's largest end tension (at
    least SCALE_FLOOR x the force scale), and per line."""
    scale = max(max(max(v[0], v[1]) for v in ref.values()), SCALE_FLOOR * force_scale)
    scale = scale if scale > 0 else 1.0
    per = {k: max(abs(sym[k][0] - ref[k][0]), abs(sym[k][1] - ref[k][1])) / scale for k in ref}
    return max(per.values()), per


def penalty(item: dict, ref: dict) -> float | None:
    """The penalty seabed's effect on MoorPy's answer, over its tension scale (None: none)."""
    import fuzz3d_moorpy as mpsys
    import fuzz_refs as fr
    import fuzz_tolerance as ftol
    from errest_scenes import lift_planar
    from fuzz3d_info import Sys3
    if not any(v[2] > 0 for v in ref["lines"].values()):
        return None
    with contextlib.redirect_stdout(io.StringIO()):
        if ref["kind"].startswith("moorpy catenary"):
            full = dict(ref["full"], approximate=None)
            p = fr.guard(ftol.penalty_effect, item["scene"], {"moorpy": full})
            return p.get("dT")
        scene = item["scene"] if item["dim"] == 3 else lift_planar(item["scene"])
        p = fr.guard(mpsys.penalty_effect, Sys3(scene), ref["full"])
    vals = [v["dT"] for v in p.values() if isinstance(v, dict) and "dT" in v]
    return max(vals) if vals else None


def refined(item: dict, ref: dict, factor: float) -> dict:
    """The true error of the scene solved at ``factor`` times the segments (no estimate)."""
    import symcable as sc
    from symcable.scene.refine import scaled_segments
    scene = scaled_segments(sc.load_scene(item["scene"]), factor)
    sol, rec = solve(scene, estimate=False)
    if sol is None:
        return {"factor": factor, "outcome": rec["outcome"], "error": rec.get("error", "")[:300]}
    true, per = true_error(_tensions(sol), ref["lines"], ref["force_scale"])
    return {"factor": factor, "true": true, "true_lines": per, "t": rec["t_solve"]}


def run_item(item: dict, notify=None, extra: bool = True) -> dict:
    """The record of one scene (see the module's docstring)."""
    notify = notify or (lambda *a: None)
    rec = {"id": item["id"], "cls": item["class"], "variant": item["variant"],
           "dim": item["dim"], "segments": _segments(item["scene"])}
    sol, out = solve(item["scene"])
    rec.update(out)
    if sol is not None:
        de = sol.stats.get("discretisation_error") or {}
        be = sol.stats.get("seabed_error") or {}
        disc, bed = de.get("max_relative"), be.get("max_relative")
        rec.update(sym=_tensions(sol),
                   estimate=None if disc is None else disc + (bed or 0.0),
                   est_disc=disc, est_bed=bed, t_bed=be.get("wall_time"),
                   est_lines={k: v.get("relative") for k, v in (de.get("lines") or {}).items()},
                   est_orders={k: v.get("order") for k, v in (de.get("lines") or {}).items()},
                   t_est=de.get("wall_time"), path=sol.stats.get("path"),
                   warnings=[w[:300] for w in sol.warnings],
                   warned=any(MARK in w or BED_MARK in w for w in sol.warnings),
                   slack_warning=any("hang slack" in w for w in sol.warnings),
                   no_estimate=any(NO_ESTIMATE in w for w in sol.warnings))
    notify("refs", dict(rec))
    t0 = time.perf_counter()
    ref = reference(item)
    rec["t_ref"] = time.perf_counter() - t0
    if "lines" in ref:
        rec.update(ref={k: v for k, v in ref["lines"].items()}, ref_kind=ref["kind"],
                   force_scale=ref["force_scale"])
        if sol is not None:
            rec["true"], rec["true_lines"] = true_error(rec["sym"], ref["lines"], ref["force_scale"])
    else:
        rec["ref_why"] = str(ref.get("na") or ref.get("failed"))[:300]
        rec["ref_failed"] = "failed" in ref
    if not extra:
        return rec
    notify("extra", dict(rec))
    if item.get("cost") and sol is not None:
        rec.update(t_cold_without=fresh_time(item["scene"], False),
                   t_cold_with=fresh_time(item["scene"], True))
    if rec.get("true") is not None and rec["true"] > ACCURACY and suspicious(rec):
        n = sum(rec["segments"].values())
        rec["refined"] = refined(item, ref, 4.0 if n <= 150 else 2.0)
        rec["penalty"] = penalty(item, ref)
    return rec


def suspicious(rec: dict) -> bool:
    """Off by more than 1 % and not warned, or warned with an estimate 3 times off."""
    if not rec.get("warned"):
        return True
    est = rec.get("estimate")
    return est is None or not (1.0 / 3.0 <= est / rec["true"] <= 3.0)


def _segments(scene: dict) -> dict:
    from errest_scenes import segments_of
    return segments_of(scene)


if __name__ == "__main__":   # fresh_time's child: scene JSON on stdin, root and estimate as args
    sys.path.insert(0, sys.argv[1])
    _scene = json.loads(sys.stdin.read())
    _sol, _rec = solve(_scene, estimate=sys.argv[2] == "1")
    print(json.dumps({"t": _rec["t_solve"] if _sol is not None else None}))
