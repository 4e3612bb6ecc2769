"""One scene of the dynamic fuzz study (:mod:`dyn_fuzz`), run in a worker process: the calls
under test and the finer reference runs, reduced to the numbers the classifier needs
(:mod:`dyn_classify`). Replay one scene: ``python studies/fuzz/dyn_work.py FAILURES.json ID``.

Stages, each announced to the parent before it starts (its own time limit there):

1. ``simulate``: ``sc.simulate(scene, PERIODS * T)`` at its defaults (its step chosen for
   its default tolerance, from T/100: ``stats["dt_runs"]``), dt its step;
2. ``reference``: ``simulate`` at the finer of dt / 4 and T/800 (dt / 8 when dt is the
   default T/100), every step saved;
3. ``periodic``: ``sc.solve_periodic(scene)`` at its defaults (shooting, 100 steps a period,
   with its time-discretisation estimate) within ``sc.limits(solve_seconds=SOLVE_SECONDS)``;
4. ``reference_long``: at dt / 8 over LONG_PERIODS, its last two periods saved, when the
   8-period reference has not settled into a period (and the periodic solve answered);
5. ``reference16``: at half the reference's step, on the scenes the parent picks (``item["check16"]``) and on
   every scene whose verdict could depend on the reference's own error
   (:func:`dyn_classify.needs_finer`).

Every call runs in the CasADi virtual machine (``codegen=False``): compiling each one-off
scene took about a minute, longer than its runs (the answers agree to round-off).
"""
from __future__ import annotations

import os
import sys
import time
import traceback

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
if HERE not in sys.path:
    sys.path.insert(0, HERE)

#: periods of each time run (the last one compared)
PERIODS = 8
#: periods of the long reference, run when the 8-period one has not settled into a period
LONG_PERIODS = 20
#: sc.limits(solve_seconds=...) for the periodic solve
SOLVE_SECONDS = 120
#: record key -> the stage the parent is told of (dyn_pool.KILL_AFTER)
STAGES = {"b": "reference", "b16": "reference16", "bL": "reference_long"}


def _ends(res) -> dict:
    """{"line/end": tension series (N)} of every line end of a result."""
    out = {}
    for name, ln in dict(res.lines).items():
        out[f"{name}/fairlead"] = np.asarray(ln.fairlead_tension, float)
        out[f"{name}/anchor"] = np.asarray(ln.anchor_tension, float)
    return out


def _call(fn) -> tuple:
    """(result or None, call record): outcome "ok", "clean error" (a SymcableError) or
    "ugly error" (anything else), the wall time and the message."""
    import symcable as sc
    t0 = time.perf_counter()
    try:
        res = fn()
        return res, {"outcome": "ok", "wall": time.perf_counter() - t0}
    except sc.SymcableError as exc:
        return None, {"outcome": "clean error", "wall": time.perf_counter() - t0,
                      "error_type": type(exc).__name__, "error": str(exc)[:600]}
    except Exception as exc:  # noqa: BLE001 - an unexpected exception is the finding
        return None, {"outcome": "ugly error", "wall": time.perf_counter() - t0,
                      "error_type": type(exc).__name__,
                      "error": traceback.format_exc()[-1500:]}


def _run_record(res, rec: dict) -> dict:
    st = res.stats
    keep = ("dt", "steps", "error_estimate", "tension_error_estimate", "error_estimate_states",
            "motion_range", "substepped_steps", "max_substeps", "newton_iterations_max",
            "static_time", "slack_fraction", "snaps", "tol", "error_measured", "dt_runs",
            "wall_time")
    rec.update(status=res.status, warnings=list(res.warnings),
               stats={k: st.get(k) for k in keep if k in st})
    lines = dict(res.lines)
    rec["stats"]["snaps"] = sum(int(ln.stats.get("snaps") or 0) for ln in lines.values())
    rec["stats"]["slack_fraction"] = max(float(ln.stats.get("slack_fraction") or 0.0)
                                         for ln in lines.values())
    return rec


def _per_record(res, rec: dict) -> dict:
    st = res.stats
    keep = ("iterations", "periods", "residual", "error_estimate", "time_discretisation_error",
            "solver", "start", "wall_time")
    rec.update(status=res.status, warnings=list(res.warnings),
               stats={k: st.get(k) for k in keep if k in st})
    rec["stats"]["start"] = str(rec["stats"].get("start"))[:120]
    return rec


def _reference(scene, duration, dt, key, factor, rec, series, T, notify) -> None:
    """A reference run at dt / factor into ``rec[key]`` and ``series[key]`` (``"bL"``: over
    LONG_PERIODS, its last two periods saved)."""
    import dyn_classify as dc

    import symcable as sc
    notify(STAGES[key], dict(rec))
    kw = {"save_every": 1}
    if key == "bL":
        duration = LONG_PERIODS * T
        n = round(2 * T / (dt / factor))
        kw = {"save_times": duration - 2 * T + (dt / factor) * np.arange(n + 1)}
    ref, rec[key] = _call(lambda: sc.simulate(scene, duration, dt / factor, codegen=False, **kw))
    if ref is not None:
        _run_record(ref, rec[key])
        series[key] = (np.asarray(ref.time, float), _ends(ref))
        rec["numbers"] = dc.numbers(series, T)


def run_scene(item: dict, notify=lambda *a: None) -> dict:
    """Every stage of one scene; returns its record (the classifier's numbers in
    ``record["numbers"]``)."""
    import dyn_classify as dc

    import symcable as sc
    scene, T = item["scene"], float(item["period"])
    duration = PERIODS * T
    rec = {"id": item["id"], "cls": item["class"], "variant": item["variant"],
           "period": T, "segments": item["segments"]}
    series = {}

    notify("simulate", dict(rec))
    res, rec["sim"] = _call(lambda: sc.simulate(scene, duration, codegen=False))
    dt = T / 100.0
    if res is not None:
        _run_record(res, rec["sim"])
        series["a"] = (np.asarray(res.time, float), _ends(res))
        # the references' "dt": 8 times their step, which is at most a quarter of the
        # answer's and at most T/800 (the default step's eighth)
        dt = min(4.0 * float(res.stats["dt"]), dt)
    del res

    _reference(scene, duration, dt, "b", 8, rec, series, T, notify)
    notify("periodic", dict(rec))
    with sc.limits(solve_seconds=SOLVE_SECONDS):
        per, rec["per"] = _call(lambda: sc.solve_periodic(scene, codegen=False))
    if per is not None:
        _per_record(per, rec["per"])
        series["c"] = (np.asarray(per.time, float), _ends(per))
    del per
    if "b" in series:
        rec["numbers"] = dc.numbers(series, T)
        if "c" in series and (dc.errors(rec["numbers"]).get("settle") or 0.0) > dc.SETTLE:
            _reference(scene, duration, dt, "bL", 8, rec, series, T, notify)
        if item.get("check16") or dc.needs_finer(rec, series, T):
            _reference(scene, duration, dt, "b16", 16, rec, series, T, notify)
    return rec


def replay(path: str, scene_id: str) -> dict:
    """Run one saved scene again (from failures.json or results.json) and print its verdict."""
    import json

    import dyn_classify as dc
    with open(path) as fh:
        items = json.load(fh)
    items = items["records"] if isinstance(items, dict) else items
    item = next(x for x in items if x["id"] == scene_id)
    item = {"id": item["id"], "class": item.get("class", item.get("cls")),
            "variant": item["variant"], "scene": item["scene"], "period": item["period"],
            "segments": item["segments"], "check16": True}
    rec = run_scene(item)
    dc.classify(rec)
    print(json.dumps({k: rec.get(k) for k in ("id", "sim_class", "per_class", "true_sim",
                                              "est_sim", "true_per", "est_per")}, indent=1))
    return rec


if __name__ == "__main__":
    os.environ.setdefault("SYMCABLE_CODEGEN", "0")
    sys.path.insert(1, os.path.dirname(os.path.dirname(HERE)))
    replay(sys.argv[1], sys.argv[2])
