"""Stiff and extreme cases on a 3D line (cable3d): which method runs, how accurately, at what cost.

Question
--------
The 3D line of ``studies/cable3d_case.py`` (110 m of rope, a third on a frictional bed, its
fairlead moved out of plane, T = 8 s) pushed to its extremes: EA x100, 400 segments, time
steps of 10 and 30 times MoorDyn's CFL step, a near-slack and a snapping amplitude, a strong
oblique current, a line lying mostly on the bed, a buoyant section, a node landing on the
bed. For each: does each method run, with how many Newton iterations and substeps, how far
from a fine reference, at what wall time, and why does a failure fail?

Columns: generalized-alpha first order (GA1, ``simulate``, generated C) and second order
(GA2, ``integrate`` in the VM), both rho_inf = 0 at dt = T/100 (the dt rows: their dt); RK4
at its default dt (0.8 of its stability limit; the dt rows: their dt); shooting, collocation
(Newton) and harmonic balance with their defaults (VM). Time runs start from rest and last
``periods`` periods (8); each cell's error is the largest of the differences of the last
period's fairlead-tension max, min and first harmonic from the reference's same period, over
the reference's range. Reference: GA1 at T/3200 over the same periods (400 segments: T/200,
a check of the time step only). Each cell runs in a forked child with a time limit (a
blow-up, a hang or a crash is the cell's result); a cell that compiled something new into the
build cache is run again, warm, for its time.

Run
---
    python -u studies/stability/run3d.py            # full: 50 min on 2 shared cores (measured;
                                                    # mostly failing periodic solves)
    python -u studies/stability/run3d.py --quick    # base and dt = 30 x CFL rows (the test)
    options: --out DIR (default studies/stability/out/cable3d/), --timeout S (per cell)

Writes ``results.csv`` and ``summary.md``; ``main(argv)`` returns the numbers as a dict.
"""
from __future__ import annotations

import argparse
import csv
import sys
import time
from pathlib import Path

import numpy as np

import symcable as sc
from symcable.api.cable3d_static import static_equilibrium
from symcable.mechanism.codegen import cache_info
from symcable.errors import ConvergenceError
from symcable.scene import load_scene
from symcable.solvers.integrate import integrate
from symcable.solvers.options import GeneralizedAlpha

HERE = Path(__file__).resolve().parent
for _p in (HERE, HERE.parent):
    if str(_p) not in sys.path:
        sys.path.append(str(_p))
import cable3d_case as case3d  # noqa: E402
import stability3d_cases as cases  # noqa: E402
import stability3d_report as report  # noqa: E402
from study_io import load_module  # noqa: E402  (studies/study_io.py)

#: studies/stability/run.py's forked-cell runner
isolated = load_module(HERE / "run.py", "stability_planar_run").isolated
T = case3d.PERIOD
TIMEOUT_FULL, TIMEOUT_QUICK = 240.0, 120.0
SAMPLES = 256                       # tension samples per period (linear interpolation)
SLACK_FACTORS = (1.0, 2.0, 4.0)     # amplitude search, x [1, 2, 0.5] m
SLACK_BISECTIONS = 3


# --------------------------------------------------------------------------- cells
def _series_metrics(t, f, periods: int) -> list:
    tau = np.arange(SAMPLES) / SAMPLES
    return [case3d.period_metrics(np.interp((k + tau) * T, t, f)) for k in range(periods)]


def _time_cell(d: dict, scheme: str, dt, periods: int, codegen) -> dict:
    if scheme == "ga2":
        mech, eq = static_equilibrium(load_scene(d), codegen=codegen)
        tr = integrate(mech, periods * T, dt if dt is not None else T / 100,
                       method=GeneralizedAlpha(rho_inf=0.0), start=eq, p=mech.params.values,
                       codegen=False)
        f = np.linalg.norm(np.asarray(tr.outputs["end_force_b"], float).reshape(-1, 3), axis=1)
        axial = np.asarray(tr.outputs["axial_force"], float)
    else:
        tr = sc.simulate(d, periods * T, dt=(T / 100 if dt is None and scheme == "ga1" else dt),
                         method="rk4" if scheme == "rk4" else "generalized-alpha", codegen=codegen)
        f, axial = tr.fairlead_tension, tr.axial_force
    s = tr.stats
    its = s.get("newton_iterations")
    return {"status": tr.status, "per_period": _series_metrics(tr.time, f, periods),
            "dt": s["dt"], "steps": s["steps"], "iterations": its,
            "iter_per_step": None if its is None else its / s["steps"],
            "iter_max": s.get("newton_iterations_max"), "substeps": s.get("substepped_steps"),
            "max_substeps": s.get("max_substeps"), "snaps": s.get("snaps"),
            "slack_fraction": s.get("slack_fraction"), "min_axial_kN": float(np.min(axial)) / 1e3,
            "dt_stable": s.get("dt_stable"), "warnings": list(tr.warnings)}


def _periodic_cell(d: dict, method: str, **kw) -> dict:
    try:
        sol = sc.solve_periodic(d, method, **kw)
    except ConvergenceError as exc:  # a failed cell, with where the solver started from
        diag = exc.diagnostics or {}
        return {"ok": False, "exc_type": type(exc).__name__,
                "message": str(exc).strip().splitlines()[0], "reason": "convergence",
                "start": diag.get("start"), "iterations": diag.get("iterations")}
    s = sol.stats
    m = case3d.period_metrics(np.interp(np.arange(SAMPLES) / SAMPLES * T, np.r_[sol.time, T],
                                        np.r_[sol.fairlead_tension, sol.fairlead_tension[0]]))
    return {"status": sol.status, "per_period": [m], "iterations": s.get("iterations"),
            "unknowns": s.get("unknowns"), "warnings": list(sol.warnings),
            "min_axial_kN": float(np.min(sol.axial_force)) / 1e3}


def cell_fn(key: str, d: dict, row):
    def timed(fn):
        def run():
            before = cache_info()["entries"]
            t0 = time.perf_counter()
            out = fn()
            out["wall_s"] = time.perf_counter() - t0
            out["compiled_new"] = cache_info()["entries"] != before
            return out
        return run
    if key in ("ga1", "ga2", "rk4"):
        return timed(lambda: _time_cell(d, key, row.dt, row.periods, row.codegen))
    if key == "reference":
        return timed(lambda: _time_cell(d, "ga1", T / row.ref_steps, row.periods, row.codegen))
    method, kw = {"shooting": ("shooting", {}), "collocation": ("collocation", {"solver": "newton"}),
                  "hb": ("harmonic-balance", {})}[key]
    return timed(lambda: _periodic_cell(d, method, **kw))


def run_cell(fn, timeout: float) -> dict:
    """``isolated(fn)``, once more when the first call compiled into the build cache."""
    c = isolated(fn, timeout)
    if c.get("ok") and c.get("compiled_new"):
        c = isolated(fn, timeout)
    return c


# --------------------------------------------------------------------------- rows
def estimates(row, segments: int, done: dict) -> dict:
    """{method: "not run" cell} for the methods of the rows ``row.estimate_from`` that this
    row leaves out: the wall time extrapolated as segments^a, a from those two rows."""
    if not row.estimate_from:
        return {}
    a, b = (done.get(n) for n in row.estimate_from)
    out = {}
    for key in (b or {}).get("cells", {}):
        if key in row.methods:
            continue
        ca, cb = a["cells"].get(key), b["cells"].get(key)
        if not (ca and cb and ca.get("ok") and cb.get("ok")):
            continue
        alpha = np.log(cb["wall_s"] / ca["wall_s"]) / np.log(b["segments"] / a["segments"])
        est = cb["wall_s"] * (segments / b["segments"]) ** alpha
        out[key] = {"ok": False, "skipped": True, "exc_type": "NotRun", "estimate_s": est,
                    "message": f"not run: ~{est:.0f} s expected ({ca['wall_s']:.3g} s at "
                               f"{a['segments']}, {cb['wall_s']:.3g} s at {b['segments']} "
                               f"segments: ~segments^{alpha:.2f})"}
    return out


def run_row(row, timeout: float, done: dict | None = None, log=print) -> dict:
    t0 = time.perf_counter()
    d = row.make()
    out = {"row": row.name, "group": row.group, "param": row.param, "periods": row.periods,
           "segments": sum(s["segments"] for s in d["sections"]),
           "cfl_dt_s": case3d.moordyn_cfl_step(d), "cells": {}}
    out["cells"].update(estimates(row, out["segments"], done or {}))
    for key in row.methods:
        c = run_cell(cell_fn(key, d, row), timeout)
        out["cells"][key] = c
        log(f"  {row.name:24s} {key:12s} {'ok' if c['ok'] else 'FAILED'} {c.get('wall_s', 0):7.1f} s"
            + ("" if c["ok"] else f"  {c.get('exc_type')}: {c.get('message', '')[:120]}"))
    ref = None
    if row.ref_steps:
        ref = run_cell(cell_fn("reference", d, row), timeout)
        ref["method"] = f"GA1, dt = T/{row.ref_steps}"
    out["reference"] = ref if ref and ref["ok"] else None
    if ref is not None and not ref["ok"]:
        out["reference_failure"] = f"{ref.get('exc_type')}: {ref.get('message')}"
    if out["reference"] is not None:
        per = out["reference"]["per_period"]
        out["ref_drift"] = case3d.rel_error(per[-2], per[-1])["error"] if len(per) > 1 else None
        for c in out["cells"].values():
            if c["ok"]:
                c["error"] = case3d.rel_error(c["per_period"][-1], per[-1])["error"]
    out["wall_s"] = time.perf_counter() - t0
    return out


def slack_search(log=print) -> dict:
    """Raise the fairlead amplitude (x [1, 2, 0.5] m) until a GA1 run at T/200 over 4 periods
    reports a slack segment, then bisect: the last taut and the first slack factors."""
    hist, taut, slack = [], None, None

    def probe(f):
        tr = sc.simulate(cases.scaled_amplitude(f), 4 * T, dt=T / 200)
        s = tr.stats
        h = {"factor": f, "snaps": s.get("snaps"), "slack_fraction": s.get("slack_fraction"),
             "min_axial_kN": float(tr.axial_force.min()) / 1e3,
             "fairlead_max_kN": float(tr.fairlead_tension.max()) / 1e3,
             "fairlead_min_kN": float(tr.fairlead_tension.min()) / 1e3}
        hist.append(h)
        log(f"  slack search x{f:g}: slack fraction {h['slack_fraction']}, snaps {h['snaps']}")
        return (s.get("slack_fraction") or 0.0) > 0
    for f in SLACK_FACTORS:
        if probe(f):
            slack = f
            break
        taut = f
    if taut is not None and slack is not None:
        for _ in range(SLACK_BISECTIONS):
            mid = round(0.5 * (taut + slack), 4)
            taut, slack = (taut, mid) if probe(mid) else (mid, slack)
    return {"history": hist, "taut": taut, "slack": slack}


def main(argv=None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--quick", action="store_true", help="base and dt = 30 x CFL rows")
    ap.add_argument("--out", type=Path, default=HERE / "out" / "cable3d", help="output directory")
    ap.add_argument("--timeout", type=float, help="time limit per cell, s")
    args = ap.parse_args(argv)
    timeout = args.timeout or (TIMEOUT_QUICK if args.quick else TIMEOUT_FULL)
    args.out.mkdir(parents=True, exist_ok=True)
    t0 = time.perf_counter()
    slack = None if args.quick else slack_search()
    cfl = case3d.moordyn_cfl_step(cases.base())
    results, done = [], {}
    for row in cases.rows(args.quick, slack, cfl):
        results.append(run_row(row, timeout, done))
        done[row.name] = results[-1]
        print(f"{row.name}: {results[-1]['wall_s']:.1f} s", flush=True)
    res = {"quick": args.quick, "rows": results, "slack": slack, "cfl_dt_s": cfl,
           "timeout_s": timeout, "wall_s": time.perf_counter() - t0, "out": str(args.out)}
    res["csv"] = report.csv_rows(res)
    with open(args.out / "results.csv", "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(res["csv"][0]))
        w.writeheader()
        w.writerows(res["csv"])
    text = report.summary_markdown(res)
    (args.out / "summary.md").write_text(text)
    print(text)
    return res


if __name__ == "__main__":
    main()
