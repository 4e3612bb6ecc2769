"""Work-precision of the dynamic solvers on a body and on a tow: error against wall time.

Question
--------
The line rows of this study (``run.py``, ``run3d.py``, ``run_rod.py``) have no body and no
tow. On a 6-DOF body hanging from a moving crane tip (``studies/systems_case.py``: a 20 t
module on 100 m of steel wire, T = 8 s) and on seed 003's towed body through its 270 deg turn
(the seed's 9 + 3 elements), what does each method cost for a given error, what order does it
reach, and does ``simulate``'s own error estimate track its true error?

Methods (``sc.simulate`` / ``sc.solve_periodic`` with their defaults but the swept one):

* the module: ``simulate``'s generalized-alpha (GA1) over dt = T/N and RK4 at 0.8 of its
  stability limit (the default), each 8 periods from rest (quick: 4); shooting over its steps per
  period, collocation (Radau, Newton) over K intervals of degree 3, harmonic balance over H.
  Each time run has two errors: against the periodic state (what a user reading its last
  period gets: the module's slow beat is in it) and against a fine RK4 run's same period (the
  time discretisation alone, ``error_disc``, from which the orders are read). Periodic
  reference: collocation on the finest mesh, checked by harmonic balance and shooting.
* the tow: GA1 at multiples of ``simulate``'s default step and RK4 at its default (full mode);
  error: the towpoint tension's largest difference over the run from a GA1 run at 1/16 of the
  default step (quick: 1/8), over its range; the reference's own error from the next finer
  (full) or coarser (quick) run, first order.

Errors are fractions of the reference tension range; the metric of the module's periods is
``run3d``'s (largest of the differences of max, min and first harmonic).

Run
---
    python -u studies/work_precision/run_systems.py           # full, ~6 min on 2 shared cores
    python -u studies/work_precision/run_systems.py --quick   # coarse grids, VM (the test)
    options: --out DIR (default studies/work_precision/out/systems/), --figure PATH

Writes ``results.csv``, ``summary.md`` and ``work_precision_systems.png``; ``main(argv)``
returns the numbers as a dict.
"""
from __future__ import annotations

import math
import os
import sys
import time
from pathlib import Path
from typing import NamedTuple

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
import wp_systems_report as report  # noqa: E402

T = cases.PERIOD
_timed = study_io.warm_median  # warm-cache medians, as the 3D rows


class Grid(NamedTuple):
    """What one run computes (a NamedTuple: the test imports this file by path)."""

    ga1_steps: tuple        # the module: GA1 steps per period
    rk4: bool               # RK4 at its default step, module and tow
    shoot_steps: tuple
    collocation: tuple      # K, degree 3
    hb_harmonics: tuple
    ref_method: str         # the module's time reference: method and steps per period
    ref_steps: int          # a multiple of 512 (512 samples a period are kept)
    ref_collocation: int    # the module's periodic reference: K, degree 4
    tow_factors: tuple      # the tow: GA1 at these multiples of the default step
    tow_ref: int            # the tow's reference: GA1 at default / tow_ref
    periods: int            # the module's time runs from rest
    repeats: int
    codegen: bool | None    # None: simulate's default (generated C where a compiler is found)


FULL = Grid(ga1_steps=(25, 50, 100, 200, 400, 800), rk4=True, shoot_steps=(25, 50, 100, 200, 400),
            collocation=(10, 20, 40, 80), hb_harmonics=(3, 5, 10, 20), ref_method="rk4", ref_steps=8192,
            ref_collocation=160, tow_factors=(4.0, 2.0, 1.0, 0.5, 0.25), tow_ref=16,
            periods=8, repeats=3, codegen=None)
QUICK = Grid(ga1_steps=(50, 100, 200), rk4=False, shoot_steps=(50, 100), collocation=(20,),
             hb_harmonics=(), ref_method="generalized-alpha", ref_steps=2048, ref_collocation=30,
             tow_factors=(2.0, 1.0, 0.5), tow_ref=8, periods=4, repeats=1, codegen=False)


# --------------------------------------------------------------------------- the module
def module_time(d: dict, method: str, n: int | None, periods: int, codegen, every: int = 1):
    """A run from rest over ``periods`` periods at dt = T/n (None: the method's default):
    (per-period metrics, info)."""
    def call():
        tr = sc.simulate(d, periods * T, dt=None if n is None else T / n, method=method,
                         save_every=every, codegen=codegen)
        s = tr.stats
        series = (np.asarray(tr.time, float), np.asarray(tr.fairlead_tension, float))
        per = case3d.per_period(*series, T)
        return (per, series), {"status": tr.status, "steps": s["steps"], "dt_s": s["dt"],
                     "estimate": s.get("error_estimate"), "code": "C" if s.get("compiled") else "VM",
                     "iterations": s.get("newton_iterations")}
    return call


def module_periodic(d: dict, method: str, **opts):
    def call():
        try:
            sol = sc.solve_periodic(d, method, **opts)
        except ConvergenceError as exc:
            return None, {"status": "failed: " + str(exc).splitlines()[0][:160]}
        s = sol.stats
        est = (s.get("time_discretisation_error") or {}).get("relative")
        return case3d.period_metrics(np.asarray(sol.fairlead_tension, float)), {
            "status": sol.status, "iterations": s.get("iterations"), "unknowns": s.get("unknowns"),
            "estimate": est, "code": "C" if s.get("compiled") else "VM"}
    return call


def module_study(grid: Grid, log=print) -> dict:
    d = cases.module_scene()
    t0 = time.perf_counter()
    ((ref_per, ref_series), _), ref_wall, _ = _timed(module_time(d, grid.ref_method, grid.ref_steps, grid.periods,
                                                   grid.codegen, every=grid.ref_steps // 512), 1)
    (state, sinfo), _, _ = _timed(module_periodic(d, "collocation", intervals=grid.ref_collocation,
                                                  degree=4, solver="newton"), 1)
    if state is None:
        raise RuntimeError(f"the periodic reference failed: {sinfo['status']}")
    rng = state["t_max_N"] - state["t_min_N"]
    log(f"module: references in {time.perf_counter() - t0:.1f} s, range {rng / 1e3:.1f} kN")
    rows = []

    def add(method, resolution, config, m, info, wall, reps, series=None):
        r = {"case": "module", "method": method, "resolution": resolution, "config": config,
             "wall_s": wall, "repeats": reps, **info}
        if m is None:
            r.update(error=math.nan, error_disc=math.nan, error_est_metric=math.nan)
        else:
            r.update(m, **case3d.rel_error(m, state))
            if series is None:  # a periodic answer: its estimate is of the extremes
                r["error_disc"] = r["error"]
                r["error_est_metric"] = max(abs(r["err_t_max"]), abs(r["err_t_min"]))
            else:  # a time run: against the reference's same period, and sample by sample
                r["error_disc"] = case3d.rel_error(m, ref_per[-1])["error"]
                f_ref = np.interp(series[0], *ref_series)
                r["error_est_metric"] = float(np.max(np.abs(series[1] - f_ref))
                                              / np.ptp(ref_series[1]))
        rows.append(r)
        log(f"  module {method:16s} {config:14s} error {r['error']:.3e} disc {r['error_disc']:.3e}"
            f"  est {r.get('estimate') or math.nan:.2e}  {wall:7.3f} s  {r.get('status')}")

    for n in grid.ga1_steps:
        ((per, series), info), wall, reps = _timed(
            module_time(d, "generalized-alpha", n, grid.periods, grid.codegen), grid.repeats)
        add("ga1", n, f"dt=T/{n}", per[-1], info, wall, reps, series)
    if grid.rk4:
        ((per, series), info), wall, reps = _timed(module_time(d, "rk4", None, grid.periods, grid.codegen),
                                                   grid.repeats)
        n = round(T / info["dt_s"])
        add("rk4", n, f"dt=T/{n} (default)", per[-1], info, wall, reps, series)
    for n in grid.shoot_steps:
        (m, info), wall, reps = _timed(module_periodic(d, "shooting", steps=n), grid.repeats)
        add("shooting", n, f"dt=T/{n}", m, info, wall, reps)
    for K in grid.collocation:
        (m, info), wall, reps = _timed(module_periodic(d, "collocation", intervals=K, degree=3,
                                                       solver="newton"), grid.repeats)
        add("collocation", K, f"K={K}, d=3", m, info, wall, reps)
    for H in grid.hb_harmonics:
        (m, info), wall, reps = _timed(module_periodic(d, "harmonic-balance", harmonics=H),
                                       grid.repeats)
        add("harmonic-balance", H, f"H={H}", m, info, wall, reps)
    beat = max(case3d.rel_error(p, state)["error"] for p in ref_per[grid.periods // 2:])
    return {"rows": rows, "state": state, "range_N": rng, "ref_wall_s": ref_wall,
            "periods": grid.periods, "ref_method": grid.ref_method, "ref_steps": grid.ref_steps, "ref_collocation": grid.ref_collocation,
            "beat": beat, "ref_per": ref_per}


# --------------------------------------------------------------------------- the tow
def tow_time(d: dict, method: str, dt, codegen):
    def call():
        tr = sc.simulate(d, cases.tow_duration(d), dt=dt, method=method, save_every=1,
                         codegen=codegen)
        s = tr.stats
        return cases.tow_series(tr), {"status": tr.status, "steps": s["steps"], "dt_s": s["dt"],
                                      "estimate": s.get("error_estimate"),
                                      "code": "C" if s.get("compiled") else "VM",
                                      "iterations": s.get("newton_iterations")}
    return call


def tow_study(grid: Grid, log=print) -> dict:
    d = cases.tow_scene()
    (_, info0), _, _ = _timed(tow_time(d, "generalized-alpha", None, grid.codegen), 1)
    dt0 = info0["dt_s"]
    t0 = time.perf_counter()
    (ref, _), ref_wall, _ = _timed(tow_time(d, "generalized-alpha", dt0 / grid.tow_ref, grid.codegen), 1)
    # the reference's own error, first order in dt: e(h) - e(h/2) = e(h)/2 against a finer
    # run (full), e(2h) - e(h) = e(h) against a coarser one (quick)
    k = 2 * grid.tow_ref if grid.tow_ref >= 16 else grid.tow_ref // 2
    (chk, _), _, _ = _timed(tow_time(d, "generalized-alpha", dt0 / k, grid.codegen), 1)
    diff = cases.tow_error(chk, ref)["error"]
    ref_error = 2.0 * diff if k > grid.tow_ref else diff
    log(f"tow: reference dt0/{grid.tow_ref} in {time.perf_counter() - t0:.1f} s, its error ~{ref_error:.1e}")
    rows = []

    def add(method, resolution, config, series, info, wall, reps):
        r = {"case": "tow", "method": method, "resolution": resolution, "config": config,
             "wall_s": wall, "repeats": reps, **info, **cases.tow_error(series, ref)}
        r["error_disc"] = r["error_est_metric"] = r["error"]
        rows.append(r)
        log(f"  tow {method:6s} {config:16s} error {r['error']:.3e}  est "
            f"{r.get('estimate') or math.nan:.2e}  depth {r['depth_end_m']:+.3f} m  {wall:7.3f} s")

    for f in grid.tow_factors:
        (s, info), wall, reps = _timed(tow_time(d, "generalized-alpha", dt0 * f, grid.codegen),
                                       grid.repeats)
        add("ga1", 1.0 / f, f"dt={f:g} x default", s, info, wall, reps)
    if grid.rk4:
        (s, info), wall, reps = _timed(tow_time(d, "rk4", None, grid.codegen), grid.repeats)
        add("rk4", dt0 / info["dt_s"], f"dt={info['dt_s']:.3g} s (default)", s, info, wall, reps)
    return {"rows": rows, "dt0_s": dt0, "ref_wall_s": ref_wall, "ref_error": ref_error,
            "tow_ref": grid.tow_ref, "range_N": float(np.ptp(ref["tension"])),
            "duration_s": cases.tow_duration(d)}


def orders(rows: list) -> dict:
    """log2 of successive error_disc ratios of each (case, method) over its resolutions."""
    out = {}
    for key in dict.fromkeys((r["case"], r["method"]) for r in rows):
        rs = sorted((r for r in rows if (r["case"], r["method"]) == key
                     and np.isfinite(r["error_disc"]) and r["error_disc"] > 0),
                    key=lambda r: r["resolution"])
        out[f"{key[0]} {key[1]}"] = [
            (f"{a['config']} -> {b['config']}",
             math.log(a["error_disc"] / b["error_disc"]) / math.log(b["resolution"] / a["resolution"]))
            for a, b in zip(rs, rs[1:])]
    return out


def main(argv=None) -> dict:
    args = study_io.parse(__doc__, "coarse grids in the VM (the test; about a minute)",
                          HERE / "out" / "systems", argv)
    if args.quick:
        os.environ.setdefault("SYMCABLE_CODEGEN", "0")
    grid = QUICK if args.quick else FULL
    t0 = time.perf_counter()
    mod = module_study(grid)
    tow = tow_study(grid)
    res = {"quick": bool(args.quick), "module": mod, "tow": tow,
           "rows": mod["rows"] + tow["rows"], "wall_s": time.perf_counter() - t0}
    res["orders"] = orders(res["rows"])
    study_io.write(args, report.csv_rows(res), report.summary_markdown(res),
                   lambda path: report.plot(res, path), "work_precision_systems.png")
    return res


if __name__ == "__main__":
    main()
