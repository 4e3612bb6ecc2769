"""Work-precision of symcable's dynamic solvers on a 3D line (cable3d): error against wall time.

Question
--------
The periodic steady state of a 3D line with seabed contact and friction, its fairlead moved
out of the line's vertical plane (``studies/cable3d_case.py``: 110 m of rope in 60 m of
water, 10 segments, a third on the bed, friction 0.5, fairlead motion [1, 2, 0.5] m of period
T = 8 s), can be had by a time run from rest, read over its last period, or by a periodic
solver. To get the fairlead tension's maximum, minimum and first-harmonic amplitude to 1 %,
0.1 % or 0.01 % of its range, which method is cheapest, and what order in dt (or in the
period's resolution) does each reach on this case?

Methods (``sc.simulate`` / ``sc.solve_periodic``, each with its defaults but the swept one):

* generalized-alpha, first order (GA1, ``simulate``'s scheme, in generated C where a
  compiler is found), rho_inf = 0 (cable3d's default), over dt = T/N;
* generalized-alpha, second order (GA2, :class:`symcable.solvers.options.GeneralizedAlpha`,
  rho_inf = 0, through ``symcable.solvers.integrate.integrate`` in the CasADi VM) over dt;
* RK4 (``simulate(method="rk4")``, generated C) at dt = 0.8 and 0.4 of its stability limit;
* collocation (Radau, Newton) over K intervals and degree d; shooting (the first-order
  generalized-alpha period map at cable3d's rho_inf 0, as the ga1 rows) over its steps
  per period; harmonic balance over H. The periodic methods run in the VM (their cable3d default).

Reference: a fine run, RK4 at T/8192 (0.19 of its stability limit) for 128 periods; its last
period is the periodic state (checked against the finest collocation, an independent route).
The time runs last P periods, P the first period after which the reference's periods all
stay within 1e-4 of the range of its last one. Two errors per time run: against the
periodic state (what a user gets) and against the reference's own period P (the same
start-up transient: the time discretisation alone, from which the orders are read).

Run
---
    python -u studies/work_precision/run3d.py            # full: about 6 minutes on 2 shared cores
    python -u studies/work_precision/run3d.py --quick    # coarse grid and reference (the test)
    options: --out DIR (default studies/work_precision/out/cable3d/), --figure PATH

Writes ``results.csv``, ``summary.md`` and ``work_precision_3d.png`` to the out dir;
``main(argv)`` returns the same numbers as a dict.
"""
from __future__ import annotations

import math
import sys
import time
from pathlib import Path
from typing import NamedTuple

import numpy as np

import symcable as sc
from symcable.api.cable3d_static import static_equilibrium
from symcable.errors import ConvergenceError
from symcable.scene import load_scene
from symcable.solvers.integrate import integrate
from symcable.solvers.options import GeneralizedAlpha
from symcable.solvers.steps import rk4_stability_limit

HERE = Path(__file__).resolve().parent
for _p in (HERE, HERE.parent):
    if str(_p) not in sys.path:
        sys.path.append(str(_p))
import cable3d_case as case3d  # noqa: E402  (studies/cable3d_case.py)
import wp3d_report as report3d  # noqa: E402  (studies/work_precision/wp3d_report.py)
import study_io  # noqa: E402

CHEAP_S = 2.0            # a call faster than this is repeated, median of REPEATS
TRANSIENT_LEVEL = 1e-4   # the time runs' periods: the reference's transient below this
METHODS = ("ga1", "ga2", "rk4", "collocation", "shooting", "harmonic-balance")


class Grid(NamedTuple):
    """What one run computes (a NamedTuple: the test imports this file by path)."""

    ga1_steps: tuple      # GA1 steps per period N (dt = T/N)
    ga2_steps: tuple
    rk4_factors: tuple    # RK4 dt as a fraction of its stability limit
    collocation: tuple    # (K, d), Newton
    shoot_steps: tuple
    hb_harmonics: tuple
    ref_steps: int        # the reference's RK4 steps per period
    ref_periods: int
    repeats: int


FULL = Grid(ga1_steps=(50, 100, 200, 400, 800, 1600, 3200), ga2_steps=(50, 100, 200, 400, 800),
            rk4_factors=(0.8, 0.4),
            collocation=((20, 3), (40, 3), (80, 3), (160, 3), (20, 2), (40, 2), (80, 2),
                         (20, 4), (40, 4)),
            shoot_steps=(50, 100, 200, 400, 800), hb_harmonics=(3, 5, 10, 20),
            ref_steps=8192, ref_periods=128, repeats=3)
QUICK = Grid(ga1_steps=(100, 200, 400), ga2_steps=(100, 200), rk4_factors=(0.8,),
             collocation=((20, 3),), shoot_steps=(100,), hb_harmonics=(5,),
             ref_steps=2048, ref_periods=4, repeats=1)


# --------------------------------------------------------------------------- timing
def _timed(call, repeats: int) -> tuple:
    """(result, median wall s, n): :func:`study_io.warm_median` with CHEAP_S."""
    return study_io.warm_median(call, repeats, CHEAP_S)


# --------------------------------------------------------------------------- the runs
def save_times(periods: int, n: int, T: float) -> np.ndarray:
    """The end of every period and every step of the last (saving only the last period would
    leave one long unsaved stretch, which ``integrate`` builds into one long mapaccum)."""
    return np.concatenate([np.arange(1, periods - 1) * T, (periods - 1) * T + np.arange(n + 1) * T / n])


def time_run(d: dict, scheme: str, n: int, periods: int, T: float):
    """One time run from rest over ``periods`` periods at dt = T/n: (last period's tension
    samples, info). GA1 and RK4 through ``sc.simulate``; GA2 through ``integrate`` on the
    scene's Mechanism from its static state (the static solve is inside the time, as in
    ``simulate``)."""
    def call():
        ts = save_times(periods, n, T)
        if scheme == "ga2":
            mech, eq = static_equilibrium(load_scene(d))
            tr = integrate(mech, periods * T, T / n, method=GeneralizedAlpha(rho_inf=0.0),
                           start=eq, p=mech.params.values, save_times=ts, codegen=False)
            f = np.linalg.norm(np.asarray(tr.outputs["end_force_b"], float).reshape(-1, 3), axis=1)
        else:
            tr = sc.simulate(d, periods * T, dt=T / n, method="rk4" if scheme == "rk4" else
                             "generalized-alpha", save_times=ts)
            f = tr.fairlead_tension
        t = np.asarray(tr.time, float)
        last = t >= (periods - 1) * T - 1e-9 * T
        s = tr.stats
        if last.sum() != n + 1 or s["steps"] != periods * n:
            raise RuntimeError(f"{scheme}: {last.sum()} samples in the last period, {s['steps']} steps")
        its = s.get("newton_iterations")
        return f[last][:n], {"steps": s["steps"], "iterations": its,
                             "iter_per_step": None if its is None else its / s["steps"],
                             "substeps": s.get("substepped_steps"), "status": tr.status,
                             "code": "C" if s.get("compiled") else "VM", "dt_s": T / n}
    return call


def periodic_run(d: dict, method: str, **opts):
    def call():
        try:
            sol = sc.solve_periodic(d, method, **opts)
        except ConvergenceError as exc:
            return None, {"status": "failed: " + str(exc).splitlines()[0][:160]}
        s = sol.stats
        return np.asarray(sol.fairlead_tension, float), {
            "status": sol.status, "iterations": s.get("iterations"), "unknowns": s.get("unknowns"),
            "code": "C" if s.get("compiled") else "VM", "samples": len(sol.time)}
    return call


def reference(d: dict, T: float, grid: Grid, log=print) -> dict:
    """RK4 at T/ref_steps over ref_periods: every period's metrics; the last is the periodic
    state (checked in the tables by the finest collocation, an independent route)."""
    n, P = grid.ref_steps, grid.ref_periods
    every = max(1, n // 512)  # 512 samples a period
    t0 = time.perf_counter()
    tr = sc.simulate(d, P * T, dt=T / n, method="rk4", save_every=every)
    wall = time.perf_counter() - t0
    per = case3d.per_period(tr.time, tr.fairlead_tension, T)
    ref = {"method": f"RK4, dt = T/{n}", "periods": per, "wall_s": wall,
           "dt_stable_s": tr.stats.get("dt_stable"), "state": per[-1]}
    rng = per[-1]["t_max_N"] - per[-1]["t_min_N"]
    ref["range_N"] = rng
    ref["transient"] = [case3d.rel_error(p, per[-1])["error"] for p in per[:-1]]
    k = len(ref["transient"])
    while k > 0 and ref["transient"][k - 1] < TRANSIENT_LEVEL:
        k -= 1
    ref["P"] = min(max(k + 1, 2), P)
    log(f"reference {ref['method']} x {P} periods: {wall:.1f} s, range {rng:.0f} N, P = {ref['P']}")
    return ref


def _row(method, family, resolution, config, tension, info, wall, reps, ref, P=None) -> dict:
    r = {"method": method, "family": family, "resolution": resolution, "config": config,
         "wall_s": wall, "repeats": reps, **{k: info.get(k) for k in (
             "status", "code", "dt_s", "steps", "iterations", "iter_per_step", "substeps",
             "unknowns")}}
    if tension is None:
        r.update(error=math.nan, error_disc=math.nan)
        return r
    m = case3d.period_metrics(tension)
    r.update(m)
    r.update(case3d.rel_error(m, ref["state"]))
    if P is not None:  # against the reference's own period P: the discretisation alone
        r["error_disc"] = case3d.rel_error(m, ref["periods"][P - 1])["error"]
    else:
        r["error_disc"] = r["error"]
    return r


def run_study(grid: Grid, log=print) -> dict:
    t_start = time.perf_counter()
    d = case3d.scene_dict("smooth")
    T = case3d.PERIOD
    mech, eq = static_equilibrium(load_scene(d))
    lim = rk4_stability_limit(mech, q=eq.q)  # at the static state, as simulate computes it
    ref = reference(d, T, grid, log)
    P = ref["P"]
    rows = []

    def add(r):
        rows.append(r)
        log(f"  {r['method']:17s} {r['config']:16s} {r.get('code') or '':2s} error "
            f"{r['error']:.3e} (disc. {r['error_disc']:.3e})  wall {r['wall_s']:8.3f} s  {r['status']}")

    for scheme, steps in (("ga1", grid.ga1_steps), ("ga2", grid.ga2_steps)):
        for n in steps:
            (f, info), wall, reps = _timed(time_run(d, scheme, n, P, T), grid.repeats)
            add(_row(scheme, scheme, n, f"dt=T/{n}", f, info, wall, reps, ref, P))
    for fac in grid.rk4_factors:
        n = int(math.ceil(T / (fac * lim)))
        (f, info), wall, reps = _timed(time_run(d, "rk4", n, P, T), grid.repeats)
        add(_row("rk4", "rk4", n, f"dt=T/{n} ({fac:g} lim)", f, info, wall, reps, ref, P))
    for K, deg in grid.collocation:
        (f, info), wall, reps = _timed(periodic_run(d, "collocation", intervals=K, degree=deg,
                                                    solver="newton"), grid.repeats)
        add(_row("collocation", f"collocation d={deg}", K, f"K={K}, d={deg}", f, info, wall, reps, ref))
    for n in grid.shoot_steps:
        (f, info), wall, reps = _timed(periodic_run(d, "shooting", steps=n), grid.repeats)
        add(_row("shooting", "shooting", n, f"dt=T/{n}", f, info, wall, reps, ref))
    for H in grid.hb_harmonics:
        (f, info), wall, reps = _timed(periodic_run(d, "harmonic-balance", harmonics=H), grid.repeats)
        add(_row("harmonic-balance", "harmonic-balance", H, f"H={H}", f, info, wall, reps, ref))
    cfl = case3d.moordyn_cfl_step(d)
    return {"scene": d["name"], "period_s": T, "reference": ref, "P": P, "rows": rows,
            "rk4_limit_s": lim, "moordyn_cfl_dt_s": cfl, "orders": orders(rows),
            "time_to_level": report3d.time_to_levels(rows), "wall_s": time.perf_counter() - t_start}


def orders(rows: list) -> dict:
    """Each family's observed orders, successive pairs of its resolutions (the time runs on
    their discretisation error, the periodic methods on their error against the reference),
    and the least-squares slope over the last three points."""
    out = {}
    for fam in dict.fromkeys(r["family"] for r in rows):
        rs = sorted((r for r in rows if r["family"] == fam and np.isfinite(r["error_disc"])),
                    key=lambda r: r["resolution"])
        pairs = case3d.observed_orders(rs, "error_disc")
        tail = rs[-3:]
        slope = None
        if len(tail) >= 2 and all(r["error_disc"] > 0 for r in tail):
            x = np.log([r["resolution"] for r in tail])
            y = np.log([r["error_disc"] for r in tail])
            slope = float(-np.polyfit(x, y, 1)[0])
        out[fam] = {"pairs": pairs, "slope_last3": slope}
    return out


def main(argv=None) -> dict:
    args = study_io.parse(__doc__, "coarse grid and reference (the test; about 30 s)",
                          HERE / "out" / "cable3d", argv)
    res = run_study(QUICK if args.quick else FULL)
    res["quick"], res["out"] = bool(args.quick), str(args.out)
    study_io.write(args, report3d.csv_rows(res), report3d.summary_markdown(res),
                   lambda path: report3d.plot(res, path), "work_precision_3d.png")
    return res


if __name__ == "__main__":
    main()
