"""Stiff and extreme cases on a body and a tow: which method runs, how accurately, at what cost.

Question
--------
The line rows of this study (``run.py``, ``run3d.py``, ``run_rod.py``) have no body and no
tow. Push the lifted module (``studies/systems_case.py``: a 6-DOF body on 100 m of steel
wire under a moving crane tip, T = 8 s) and seed 003's towed body (its own 9 + 3 elements)
to their extremes: a stiffer wire, more segments, a coarse step, a light module whose wire
goes slack and snaps; a tighter turn, a faster tow. For each: does each method run, how far
from a fine reference, at what wall time, and why does a failure fail?

Columns. The module: ``simulate`` (generalized-alpha) at dt = T/100 (the dt row: its dt),
RK4 at its default step, shooting, collocation (Newton) and harmonic balance with their
defaults. Time runs start from rest and last 8 periods (quick: 4); their error is the largest
of the differences of the last period's max, min and first harmonic of the top tension from
a GA1 run's at T/3200 (quick: T/800; the same start, the same period), over its range; a
periodic answer's from collocation at K = 80 (quick: 30), d = 4 (Newton). The tow:
``simulate`` at its default step (the dt row: 4 times it) and RK4 at its default; error: the
towpoint tension's largest difference over the run from GA1 at 1/8 (quick: 1/2) of the
default step, over its range. Each cell runs in a forked child
with a time limit (a blow-up, a hang or a crash is the cell's result).

Run
---
    python -u studies/stability/run_systems.py           # full: ~10 min on 2 shared cores
    python -u studies/stability/run_systems.py --quick   # two rows (the test)
    options: --out DIR (default studies/stability/out/systems/), --timeout S (per cell),
             --case module|tow (only that case's rows)

Writes ``results.csv`` and ``summary.md``; ``main(argv)`` returns the numbers as a dict.
"""
from __future__ import annotations

import argparse
import math
import os
import sys
import time
from pathlib import Path
from typing import Callable, NamedTuple

import numpy as np

import symcable as sc
from symcable.errors import ConvergenceError

HERE = Path(__file__).resolve().parent
for _p in (HERE, HERE.parent):
    if str(_p) not in sys.path:
        sys.path.append(str(_p))
import cable3d_case as case3d  # noqa: E402
import study_io  # noqa: E402
import systems_case as cases  # noqa: E402

#: studies/stability/run.py's forked-cell runner
isolated = study_io.load_module(HERE / "run.py", "stability_planar_run").isolated
T = cases.PERIOD
#: periods of the module's time runs, its references (GA1 steps per period; collocation
#: intervals at degree 4), the tow's reference (GA1 at 1/tow_ref of the default step), the
#: time limit of a cell (s)
FULL = {"periods": 8, "ref_steps": 3200, "ref_k": 80, "tow_ref": 8, "timeout": 240.0}
QUICK = {"periods": 4, "ref_steps": 800, "ref_k": 30, "tow_ref": 2, "timeout": 120.0}
SET = dict(FULL)


class Row(NamedTuple):
    """One row: ``case`` "module" or "tow", ``make()`` its scene dict, ``dt`` (s) of the time
    columns (None: T/100 for the module's GA1, the default for the rest; ``dt_factor``
    multiplies the tow's default), ``methods`` the columns run. (A NamedTuple, not a
    dataclass: the test imports this file by path.)"""

    name: str
    case: str
    make: Callable[[], dict]
    param: str = ""
    dt: float | None = None
    dt_factor: float | None = None
    methods: tuple = ()


def rows(quick: bool) -> list:
    mod = ("ga1", "rk4", "shooting", "collocation", "hb")
    tow = ("ga1", "rk4")
    if quick:
        return [Row("module", "module", cases.module_scene, "20 t on 100 m of wire",
                    methods=("ga1", "collocation")),
                Row("tow", "tow", cases.tow_scene, "9 + 3 elements, R = 300 m, 12 kn",
                    methods=("ga1",))]
    light = 6000.0
    return [
        Row("module", "module", cases.module_scene, "20 t on 100 m of wire", methods=mod),
        Row("wire EA x100", "module", lambda: cases.module_scene(ea_factor=100.0),
            "EA = 2e10 N (c = 47 km/s)", methods=mod),
        Row("40 segments", "module", lambda: cases.module_scene(segments=40), "ds = 2.5 m",
            methods=mod),
        Row("dt = T/10", "module", cases.module_scene, "0.8 s", dt=T / 10, methods=("ga1", "rk4")),
        Row("light module (snaps)", "module", lambda: cases.module_scene(mass=light),
            f"{light / 1e3:g} t: 8.6 kN submerged, the wire slack once a period", methods=mod),
        Row("tow", "tow", cases.tow_scene, "9 + 3 elements, R = 300 m, 12 kn", methods=tow),
        Row("tight turn", "tow", lambda: cases.tow_scene(radius=100.0), "R = 100 m", methods=tow),
        Row("20 knots", "tow", lambda: cases.tow_scene(speed=10.289), "10.3 m/s", methods=tow),
        Row("dt = 4 x default", "tow", cases.tow_scene, "", dt_factor=4.0, methods=("ga1",)),
        Row("48 segments", "tow", lambda: cases.tow_scene(segments=(36, 12)), "the scene's own",
            methods=tow),
    ]


# --------------------------------------------------------------------------- cells
def _time_cell(d: dict, case: str, method: str, dt) -> dict:
    periods = SET["periods"]
    duration = periods * T if case == "module" else cases.tow_duration(d)
    tr = sc.simulate(d, duration, dt=dt, method=method, save_every=1)
    s = tr.stats
    out = {"status": tr.status, "dt": s["dt"], "steps": s["steps"],
           "iterations": s.get("newton_iterations"), "substeps": s.get("substepped_steps"),
           "snaps": s.get("snaps"), "estimate": s.get("error_estimate"),
           "warnings": list(tr.warnings)}
    if case == "module":
        tau = (np.arange(512) + 0.5) / 512
        f = np.interp((periods - 1 + tau) * T, tr.time, tr.fairlead_tension)
        out["metrics"] = case3d.period_metrics(f)
    else:
        out["series"] = {k: v.tolist() for k, v in cases.tow_series(tr).items()}
    return out


def _periodic_cell(d: dict, method: str, **kw) -> dict:
    try:
        sol = sc.solve_periodic(d, method, **kw)
    except ConvergenceError as exc:
        return {"ok": False, "exc_type": type(exc).__name__,
                "message": str(exc).strip().splitlines()[0], "reason": "convergence"}
    s = sol.stats
    return {"status": sol.status, "iterations": s.get("iterations"), "unknowns": s.get("unknowns"),
            "estimate": (s.get("time_discretisation_error") or {}).get("relative"),
            "warnings": list(sol.warnings),
            "metrics": case3d.period_metrics(np.asarray(sol.fairlead_tension, float))}


def cell_fn(key: str, d: dict, row: Row, dt0: float | None):
    def timed(fn):
        def run():
            t0 = time.perf_counter()
            out = fn()
            out["wall_s"] = time.perf_counter() - t0
            return out
        return run
    if key in ("ga1", "rk4", "ref"):
        method = "rk4" if key == "rk4" else "generalized-alpha"
        if key == "ref":
            dt = T / SET["ref_steps"] if row.case == "module" else dt0 / SET["tow_ref"]
        elif key == "ga1" and row.case == "module":
            dt = row.dt or T / 100
        elif key == "ga1" and row.dt_factor:
            dt = dt0 * row.dt_factor
        else:
            dt = row.dt
        return timed(lambda: _time_cell(d, row.case, method, dt))
    if key == "pref":
        return timed(lambda: _periodic_cell(d, "collocation", intervals=SET["ref_k"], degree=4,
                                            solver="newton"))
    method, kw = {"shooting": ("shooting", {}), "collocation": ("collocation", {"solver": "newton"}),
                  "hb": ("harmonic-balance", {})}[key]
    return timed(lambda: _periodic_cell(d, method, **kw))


def _error(c: dict, row: Row, refs: dict):
    if row.case == "tow":
        ref = refs.get("ref")
        if ref is None:
            return None
        run = {k: np.asarray(v) for k, v in c["series"].items()}
        return cases.tow_error(run, {k: np.asarray(v) for k, v in ref["series"].items()})["error"]
    ref = refs.get("pref" if "metrics" in c and "dt" not in c else "ref")
    return None if ref is None else case3d.rel_error(c["metrics"], ref["metrics"])["error"]


def run_row(row: Row, timeout: float, log=print) -> dict:
    t0 = time.perf_counter()
    d = row.make()
    dt0 = None
    if row.case == "tow":  # simulate's default step for the whole run (it depends on the turns)
        dt0 = sc.simulate(d, cases.tow_duration(d)).stats["dt"]
    out = {"row": row.name, "case": row.case, "param": row.param, "segments": cases.segments(d),
           "cfl_dt_s": cases.moordyn_cfl_step(d), "cells": {}, "refs": {}}
    for key in row.methods:
        c = isolated(cell_fn(key, d, row, dt0), timeout)
        out["cells"][key] = c
        log(f"  {row.name:22s} {key:12s} {'ok' if c.get('ok') else 'FAILED'} {c.get('wall_s', 0):7.1f} s"
            + ("" if c.get("ok") else f"  {c.get('exc_type')}: {c.get('message', '')[:120]}"))
    periodic = any(k in row.methods for k in ("shooting", "collocation", "hb"))
    for key in ("ref",) + (("pref",) if periodic else ()):
        c = isolated(cell_fn(key, d, row, dt0), 2 * timeout)
        out["refs"][key] = c if c.get("ok") else None
        if not c.get("ok"):
            out[f"{key}_failure"] = f"{c.get('exc_type')}: {c.get('message')}"
    for c in out["cells"].values():
        if c.get("ok"):
            c["error"] = _error(c, row, out["refs"])
            c.pop("series", None)
    for c in out["refs"].values():
        if c is not None:
            c.pop("series", None)
    out["wall_s"] = time.perf_counter() - t0
    return out


# --------------------------------------------------------------------------- report
COLS = {"ga1": "simulate (gen.-α)", "rk4": "RK4, default dt", "shooting": "shooting",
        "collocation": "collocation, Newton", "hb": "harmonic balance"}


def _cell_text(c, notes: list) -> str:
    if c is None:
        return ""
    if not c.get("ok"):
        notes.append(f"{c.get('exc_type')}: {c.get('message', '')}")
        return f"FAILED [{len(notes)}]"
    err = c.get("error")
    e = "-" if err is None or not math.isfinite(err) else f"{100 * err:.3g} %"
    est = c.get("estimate")
    est = "" if est is None else f", est. {100 * est:.2g} %"
    return f"{e}{est}, {c['wall_s']:.2g} s"


def summary_markdown(res: dict) -> str:
    L = [f"# Stiff and extreme cases on a body and a tow{' (--quick)' if res['quick'] else ''}", "",
         f"{len(res['rows'])} rows in {res['wall_s']:.0f} s; time limit {res['timeout_s']:.0f} s a "
         "cell. Each cell: error (% of the reference tension range), the answer's own estimate "
         "(simulate: sample by sample over the run; periodic: the cycle's extremes), wall time.", "",
         "| row | what | segments | " + " | ".join(COLS.values()) + " |",
         "|---|---|---|" + "---|" * len(COLS)]
    notes: list = []
    for r in res["rows"]:
        cells = " | ".join(_cell_text(r["cells"].get(k), notes) for k in COLS)
        L.append(f"| {r['row']} | {r['param']} | {r['segments']} | {cells} |")
    L += ["", f"References: the module's time columns ({SET['periods']} periods) against GA1 at "
          f"T/{SET['ref_steps']}, its periodic columns against collocation K = {SET['ref_k']}, "
          f"d = 4; the tow's against GA1 at 1/{SET['tow_ref']} of the default step.", ""]
    for r in res["rows"]:
        for key in ("ref", "pref"):
            if f"{key}_failure" in r:
                L.append(f"- {r['row']}: the reference {key} failed: {r[f'{key}_failure']}")
    L += [""] + [f"{i}. {n}" for i, n in enumerate(notes, 1)]
    return "\n".join(L) + "\n"


def csv_rows(res: dict) -> list:
    out = []
    for r in res["rows"]:
        for key, c in r["cells"].items():
            out.append({"row": r["row"], "case": r["case"], "method": key, "ok": c.get("ok"),
                        "error": c.get("error"), "estimate": c.get("estimate"),
                        "wall_s": c.get("wall_s"), "steps": c.get("steps"), "dt": c.get("dt"),
                        "iterations": c.get("iterations"), "unknowns": c.get("unknowns"),
                        "snaps": c.get("snaps"), "status": c.get("status"),
                        "failure": None if c.get("ok") else c.get("message")})
    return out


def main(argv=None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--quick", action="store_true", help="two rows in the VM (the test)")
    ap.add_argument("--out", type=Path, default=HERE / "out" / "systems", help="output directory")
    ap.add_argument("--timeout", type=float, help="time limit per cell, s")
    ap.add_argument("--case", choices=("module", "tow"), help="only this case's rows")
    args = ap.parse_args(argv)
    if args.quick:
        os.environ.setdefault("SYMCABLE_CODEGEN", "0")
    SET.clear()
    SET.update(QUICK if args.quick else FULL)
    timeout = args.timeout or SET["timeout"]
    args.out.mkdir(parents=True, exist_ok=True)
    t0 = time.perf_counter()
    results = []
    for row in rows(args.quick):
        if args.case and row.case != args.case:
            continue
        results.append(run_row(row, timeout))
        print(f"{row.name}: {results[-1]['wall_s']:.1f} s", flush=True)
    res = {"quick": args.quick, "rows": results, "timeout_s": timeout,
           "wall_s": time.perf_counter() - t0, "out": str(args.out)}
    study_io.write_tables(args.out, csv_rows(res), summary_markdown(res))
    return res


if __name__ == "__main__":
    main()
