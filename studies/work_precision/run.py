"""Work-precision of symcable's dynamic solvers on the seed-001 line: error against wall time.

Question
--------
The periodic steady state of the seed-001 line (``symcable/data/seed001.toml``: OC3 geometry,
suspended, 0.5 m/s current, elliptic fairlead motion of period T = 10 s, 50 segments) can be
had five ways: run RK4 or generalized-alpha from rest until the start-up transient has gone and
read the last period, or solve for the periodic state directly by harmonic balance, by
collocation (IPOPT or Newton) or by shooting (the fixed point of generalized-alpha's period
map). To get the fairlead tension's max, min and first-harmonic amplitude to 1 %, 0.1 % or
0.01 % of its range, which is cheapest, and by how much? And which periodic method reaches
0.1 % first, to be ``solve_periodic``'s default?

Grids (full run; ``--quick`` takes a few cheap points of each and a coarse reference):

* RK4 over the periods simulated P (2, 3, 4, 6, 8, 16) at dt = 0.8, 0.4 and 0.2 times its
  stability limit (rounded down to a whole number of steps per period), reading period P;
* generalized-alpha (rho_inf = 0.5) over dt = T/25 ... T/400, reading the last of P_GA
  periods, where P_GA is measured first: the transient of a long run at the finest dt must
  have decayed to a tenth of that run's error;
* harmonic balance over H (1, 2, 3, 5, 8, 12, 16 harmonics), Newton;
* collocation (Radau) over K (10, 20, 40, 80 intervals) and d (2, 3, 4), with Newton and with
  IPOPT;
* shooting over its steps per period N (dt = T/25 ... T/400), in generated C and in the VM,
  interleaved;
* then (full run) the periodic methods side by side, interleaved: each one's cheapest run to
  0.1 % and its defaults.

Reference: collocation K = 160, d = 4 (Newton), checked against the largest-H harmonic balance
and the K = 80, d = 4 collocation. Error of a run: the largest of |T_max - T_max,ref|,
|T_min - T_min,ref| and |A_1 - A_1,ref|, over the reference's tension range T_max,ref -
T_min,ref. Each quantity comes from one period of fairlead tension sampled uniformly (time
runs: the steps of the last period; periodic solvers: 1000 output samples); A_1 is the FFT's
first harmonic, max and min are those of the trigonometric interpolant on 4096 points.

Timing: the wall time of the whole call (a time run from rest to its end, or a periodic solve
with its initial guess), with the dynamic model and its Mechanism (and RK4's stability limit)
built beforehand; each repeat uses a freshly built model, so the time includes building
the solver of that discretisation (collocation or harmonic-balance system, IPOPT or rootfinder,
integrator step and batch), which a user waits for too. Median of 3 repeats when the first
takes under 2 s, else that single run. The one-time model build is measured once, apart.
Code: each analysis' default (generated C when a compiler is found, as for a user), shooting
also in the VM. A call that compiles something new into the build cache (cold cache) is not
timed but made again, warm; point ``SYMCABLE_CACHE_DIR`` at a cache of its own to keep it.

Run
---
    python studies/work_precision/run.py            # full: about 10 minutes on 2 shared cores
    python studies/work_precision/run.py --quick    # cheap points, coarse reference: < 1 minute
    options: --out DIR (default studies/work_precision/out/), --figure PATH (extra copy)

Writes to the out dir: ``results.csv`` (one row per run, units in the column names),
``summary.md`` (tables: reference, transient, runs, time to each error level, measured and
interpolated in log-log, the periodic methods side by side) and ``work_precision.png`` (error
against wall time, log-log).
"""
from __future__ import annotations

import math
import sys
import statistics
import time
from pathlib import Path
from typing import NamedTuple

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib import ticker  # noqa: E402
import numpy as np  # noqa: E402

import symcable as sc  # noqa: E402
from symcable.api.analyses import solve_periodic  # noqa: E402
from symcable.mechanism.codegen import cache_info  # noqa: E402
from symcable.errors import ConvergenceError  # noqa: E402
from symcable.models.planar.mechanism import mechanism_of  # noqa: E402
from symcable.api.planar_time import rk4_stability_limit  # noqa: E402

HERE = Path(__file__).resolve().parent
if str(HERE.parent) not in sys.path:
    sys.path.append(str(HERE.parent))
import study_io  # noqa: E402  (studies/study_io.py)
LEVELS = (1e-2, 1e-3, 1e-4)          # error levels, fraction of the reference tension range
CHEAP_S = 2.0                        # a run faster than this is repeated, median of REPEATS
REPEATS = 3
RESOLUTION = 1000                    # output samples per period of the periodic solvers
FINE = 4096                          # trigonometric interpolation for the max and min
TRANSIENT_FRACTION = 0.1             # GA transient must fall below this part of its error
METHODS = ("rk4", "generalized-alpha", "harmonic-balance", "collocation-newton",
           "collocation-ipopt", "shooting")
#: the methods of ``solve_periodic`` (the others march ``simulate`` from rest)
PERIODIC = ("harmonic-balance", "collocation-newton", "collocation-ipopt", "shooting")
LABELS = {"rk4": "RK4 (from rest)", "generalized-alpha": "generalized-α (from rest)",
          "harmonic-balance": "harmonic balance (Newton)",
          "collocation-newton": "collocation, Newton", "collocation-ipopt": "collocation, IPOPT",
          "shooting": "shooting (generalized-α period map)"}
#: the level the default periodic method is chosen at (the issue: 1e-3 of the tension range)
DEFAULT_LEVEL = 1e-3


class Grid(NamedTuple):
    """What one run of the study computes (a NamedTuple, not a dataclass: the test imports
    this file by path, outside sys.modules)."""

    rk4_periods: tuple        # periods simulated from rest, P
    rk4_factors: tuple        # dt as a fraction of RK4's stability limit
    ga_steps: tuple           # steps per period N (dt = T/N)
    ga_transient_periods: int  # length of the run at the finest N that measures the transient
    hb_harmonics: tuple
    col_newton: tuple         # (K, d) solved by Newton
    col_ipopt: tuple          # (K, d) solved by IPOPT
    shoot_steps: tuple        # shooting: generalized-alpha steps per period N (dt = T/N)
    shoot_codegen: tuple      # shooting: codegen values, each a line (None: the default)
    reference: tuple          # (K, d) of the reference collocation (Newton)
    head_to_head: bool        # re-time the periodic methods side by side at DEFAULT_LEVEL


FULL = Grid(rk4_periods=(2, 3, 4, 6, 8, 16), rk4_factors=(0.8, 0.4, 0.2),
            ga_steps=(25, 50, 100, 200, 400), ga_transient_periods=12,
            hb_harmonics=(1, 2, 3, 5, 8, 12, 16),
            col_newton=tuple((K, d) for d in (2, 3, 4) for K in (10, 20, 40, 80)),
            col_ipopt=tuple((K, d) for d in (2, 3, 4) for K in (10, 20, 40, 80)),
            shoot_steps=(25, 50, 100, 200, 400), shoot_codegen=(True, False),
            reference=(160, 4), head_to_head=True)
QUICK = Grid(rk4_periods=(1, 2, 3), rk4_factors=(0.8,), ga_steps=(25, 50),
             ga_transient_periods=6, hb_harmonics=(1, 3, 5),
             col_newton=((5, 3), (10, 3)), col_ipopt=((5, 3), (10, 3)),
             shoot_steps=(25, 50, 100), shoot_codegen=(None,), reference=(20, 4),
             head_to_head=False)


# --------------------------------------------------------------------------- measuring
QUANTITIES = ("t_max_N", "t_min_N", "a1_N")


def metrics(series) -> dict:
    """Max, min (of the interpolant on FINE points) and first-harmonic amplitude, N, of one
    period of fairlead tension sampled uniformly from t = 0 (mod T); ``fine`` is that
    interpolant (for the waveform error, not written out)."""
    x = np.asarray(series, dtype=float)
    fine = study_io.trig_interp(x, FINE) if x.size != FINE else x
    return {"t_max_N": float(fine.max()), "t_min_N": float(fine.min()),
            "a1_N": float(2.0 * abs(np.fft.rfft(x)[1]) / x.size), "fine": fine}


def errors(m: dict, ref: dict) -> dict:
    """Signed errors over the reference range, and their largest magnitude (``error``, the
    study's metric); ``err_wave``, for context, is the largest difference of the whole
    waveform over the period, max_t |T(t) - T_ref(t)|, which also counts phase errors."""
    rng = ref["t_max_N"] - ref["t_min_N"]
    e = {f"err_{k}": (m[f"{k}_N"] - ref[f"{k}_N"]) / rng for k in ("t_max", "t_min", "a1")}
    e["error"] = max(abs(v) for v in e.values())
    e["err_wave"] = (float(np.max(np.abs(m["fine"] - ref["fine"]))) / rng
                     if m.get("fine") is not None else math.nan)
    return e


def fresh_model(scene):
    """A newly built model with its Mechanism (``mechanism_of``, what every solver reads) and
    RK4's stability limit (the one-time cost, kept out of the solve times); the Functions the
    solvers derive from the Mechanism, and their caches, are built by the timed call."""
    model = sc.build_dynamic_model(scene)
    mechanism_of(model)
    rk4_stability_limit(model)
    return model


def _cache_entries() -> int:
    return cache_info()["entries"]


def _once(scene, run) -> tuple:
    """``run`` on a fresh model, timed: (wall_s, (metrics, info)). A call that compiled
    something new into the build cache (a cold cache: 2-10 s of C compiler) is not timed:
    it is discarded and the call made again, now warm, as every later solve of that model
    structure is."""
    while True:
        model = fresh_model(scene)
        before = _cache_entries()
        t0 = time.perf_counter()
        out = run(model)
        wall = time.perf_counter() - t0
        if _cache_entries() == before:
            return wall, out


def _median_run(runs: list) -> tuple:
    """(metrics, info, median wall_s, repeats) of a list of (wall_s, (metrics, info))."""
    wall, (m, info) = sorted(runs, key=lambda w: w[0])[(len(runs) - 1) // 2]  # the median run
    return m, info, statistics.median(w for w, _ in runs), len(runs)


def timed(scene, run, repeats: int) -> tuple:
    """``run(model) -> (metrics, info)`` on a fresh model, timed; repeated (median) when cheap.
    Returns (metrics, info, wall_s, n_repeats)."""
    runs = []
    while True:
        runs.append(_once(scene, run))
        if len(runs) >= repeats or runs[0][0] >= CHEAP_S:
            break
    return _median_run(runs)


def timed_interleaved(scene, runs: dict, repeats: int) -> dict:
    """``timed`` for several runs at once, interleaved: round r makes the r-th call of every
    run still cheap (first call under CHEAP_S), so a slow spell of the shared machine falls
    on all of them alike. Returns {key: (metrics, info, wall_s, n_repeats)}."""
    done = {k: [] for k in runs}
    for r in range(repeats):
        for k, run in runs.items():
            if r == 0 or done[k][0][0] < CHEAP_S:
                done[k].append(_once(scene, run))
    return {k: _median_run(v) for k, v in done.items()}


# --------------------------------------------------------------------------- the runs
def time_run(scene, method: str, periods: int, n: int, T: float):
    """A run from rest over ``periods`` periods with n steps per period, saving the end of
    each period and every step of the last one. (Saving only the last period would leave one
    unsaved stretch of (P-1) n steps, which ``simulate`` runs as one ``mapaccum`` of that
    length; building that for ~10^4 steps takes seconds, against a fraction of a second for
    the period-long batches used here.)"""
    dt = T / n
    t_save = np.concatenate([np.arange(1, periods - 1) * T,
                             (periods - 1) * T + np.arange(n + 1) * dt])

    def run(model):
        tr = sc.simulate(scene, periods * T, dt=dt, method=method, model=model, save_times=t_save)
        last = tr.time >= (periods - 1) * T - 1e-9 * T
        if last.sum() != n + 1 or tr.stats["steps"] != periods * n:
            raise RuntimeError(f"{method}: {last.sum()} samples in the last period, "
                               f"{tr.stats['steps']} steps")
        s = tr.stats
        its = s.get("newton_iterations")
        return metrics(tr.fairlead_tension[last][:n]), {
            "status": tr.status, "steps": s["steps"], "iterations": its,
            "iter_per_step": None if its is None else its / s["steps"], "core_s": s["step_time"],
            "code": "C" if s.get("compiled") else "VM"}
    return run


def periodic_run(scene, method: str, **kw):
    def run(model):
        try:
            sol = solve_periodic(scene, method, model=model, resolution=RESOLUTION, **kw)
        except ConvergenceError as exc:
            nan = {"t_max_N": math.nan, "t_min_N": math.nan, "a1_N": math.nan, "fine": None}
            return nan, {"status": "failed: " + str(exc)[:80]}
        s = sol.stats
        guess = s.get("guess", {})
        info = {"status": sol.status, "iterations": s["iterations"],
                "guess_iterations": guess.get("iterations"), "core_s": s["solve_time"],
                "unknowns": s.get("unknowns"), "code": "C" if s.get("compiled") else "VM"}
        if method == "shooting":  # iterations: periods marched, each of `steps` steps
            info.update(steps=s["steps"] * s["iterations"], iter_per_step=None,
                        newton_iterations=s["newton_iterations"])
        m = metrics(sol.fairlead_tension)
        # the solution's own FFT must give the same first harmonic (one period, uniform)
        if abs(sol.fairlead_tension_harmonics_amplitude[1] - m["a1_N"]) > 1e-9 * m["a1_N"]:
            raise RuntimeError(f"{method}: A_1 {m['a1_N']} N from the samples, "
                               f"{sol.fairlead_tension_harmonics_amplitude[1]} N from the solution")
        return m, info
    return run


def row(method, family, resolution, label, m, info, wall, reps, **cfg) -> dict:
    r = {"method": method, "family": family, "resolution": resolution, "config": label,
         "periods": None, "dt_s": None, "K": None, "d": None, "H": None, **cfg,
         "wall_s": wall, "repeats": reps, "core_s": info.get("core_s"),
         "iterations": info.get("iterations"), "iter_per_step": info.get("iter_per_step"),
         "guess_iterations": info.get("guess_iterations"), "steps": info.get("steps"),
         "unknowns": info.get("unknowns"), "code": info.get("code"), "status": info["status"], **m}
    return r


def ga_transient(scene, model, n: int, periods: int, T: float, ref: dict) -> dict:
    """Per-period metrics of a long generalized-alpha run at n steps per period: how fast
    the start-up transient decays (each period against the last), and the error at the end."""
    dt = T / n
    tr = sc.simulate(scene, periods * T, dt=dt, method="generalized-alpha", model=model,
                     save_times=np.arange(periods * n + 1) * dt)
    ft = tr.fairlead_tension
    per = [metrics(ft[p * n:(p + 1) * n]) for p in range(periods)]
    rng = ref["t_max_N"] - ref["t_min_N"]
    dev = [max(abs(q[k] - per[-1][k]) for k in QUANTITIES) / rng for q in per]
    final_error = errors(per[-1], ref)["error"]
    need = TRANSIENT_FRACTION * final_error
    P = next(p + 1 for p, v in enumerate(dev) if v <= need or p + 1 == periods - 1)
    return {"n": n, "periods_run": periods, "deviation": dev, "final_error": final_error,
            "threshold": need, "periods_needed": P, "converged": dev[P - 1] <= need}


# --------------------------------------------------------------------------- the study
def one_time_build(scene) -> dict:
    t0 = time.perf_counter()
    model = sc.build_dynamic_model(scene)
    t1 = time.perf_counter()
    mechanism_of(model)
    t2 = time.perf_counter()
    rk4_stability_limit(model)
    t3 = time.perf_counter()
    return {"build_dynamic_model_s": t1 - t0, "mechanism_s": t2 - t1, "rk4_limit_s": t3 - t2,
            "n_y": int(model.n_y)}


def time_to_levels(rows: list) -> dict:
    """Per method and level, the cheapest run whose error is at most the level."""
    out = {}
    for meth in METHODS:
        mine = [r for r in rows if r["method"] == meth and np.isfinite(r["error"])]
        out[meth] = {}
        for lev in LEVELS:
            ok = [r for r in mine if r["error"] <= lev]
            out[meth][lev] = min(ok, key=lambda r: r["wall_s"]) if ok else None
    return out


def interpolate_line(rs: list, lev: float) -> float | None:
    """Wall time at which one line (rows of one family, in order of resolution) first reaches
    error ``lev``: linear in log(time) against log(error) between the last point above the
    level and the first at or below it, and never more than the time of a point that reaches
    it (the times of a line need not grow with its resolution: a noisy or slow first call);
    the first point's own time when it is already below (an upper bound); None when no point
    reaches it."""
    reached = [r["wall_s"] for r in rs if r["error"] <= lev]
    for k, r in enumerate(rs):
        if r["error"] <= lev:
            if k == 0:
                return min(reached)
            a = rs[k - 1]
            f = math.log(lev / a["error"]) / math.log(r["error"] / a["error"])
            t = math.exp(math.log(a["wall_s"]) + f * math.log(r["wall_s"] / a["wall_s"]))
            return min([t] + reached)
    return None


def interpolated_times(rows: list) -> dict:
    """{method: {level: (wall_s, family) or None}}: the fastest of that method's lines at each
    level, interpolated in log-log (:func:`interpolate_line`)."""
    out = {}
    for meth in METHODS:
        out[meth] = {}
        fams = dict.fromkeys(r["family"] for r in rows if r["method"] == meth)
        for lev in LEVELS:
            best = None
            for fam in fams:
                rs = sorted((r for r in rows if r["family"] == fam and np.isfinite(r["error"])),
                            key=lambda r: r["resolution"])
                t = interpolate_line(rs, lev)
                if t is not None and (best is None or t < best[0]):
                    best = (t, fam)
            out[meth][lev] = best
    return out


def periodic_winner(interp: dict, level: float = DEFAULT_LEVEL) -> dict:
    """The periodic method fastest to ``level`` (interpolated), and every periodic method's
    time over the winner's."""
    cands = {m: interp[m][level][0] for m in PERIODIC if interp.get(m, {}).get(level)}
    if not cands:
        return {"level": level, "method": None, "ratios": {}}
    win = min(cands, key=cands.get)
    return {"level": level, "method": win, "wall_s": cands[win],
            "ratios": {m: t / cands[win] for m, t in cands.items()}}


def winners(ttl: dict) -> dict:
    win = {}
    for lev in LEVELS:
        cands = [(v[lev]["wall_s"], m) for m, v in ttl.items() if v[lev] is not None]
        win[lev] = min(cands)[1] if cands else None
    return win


def run_study(grid: Grid, repeats: int, log=print) -> dict:
    scene = sc.load_scene(sc.demo_scene_path("seed001"))
    T = scene.end_b.motion.period
    build = one_time_build(scene)
    t_start = time.perf_counter()

    # the reference, and the largest-H harmonic balance as its check (in the HB sweep)
    K, d = grid.reference
    ref_m, ref_info, ref_wall, _ = timed(scene, periodic_run(scene, "collocation", intervals=K,
                                                              degree=d, solver="newton"), 1)
    if not ref_info["status"] in ("converged", "slack"):
        raise RuntimeError(f"reference collocation K={K}, d={d}: {ref_info['status']}")
    ref = dict(ref_m, range_N=ref_m["t_max_N"] - ref_m["t_min_N"], K=K, d=d, wall_s=ref_wall,
               iterations=ref_info["iterations"], unknowns=ref_info["unknowns"])
    log(f"reference K={K} d={d}: {ref_wall:.1f} s, range {ref['range_N']:.1f} N")
    rows = []

    def add(r):
        r.update(errors(r, ref))
        r.pop("fine")
        rows.append(r)
        log(f"  {r['method']:19s} {r['config']:24s} err {r['error']:.3e}  wall {r['wall_s']:8.3f} s"
            f"  x{r['repeats']}  {r['code']}  {r['status']}")

    # RK4: over periods and dt
    dt_stable = rk4_stability_limit(fresh_model(scene))
    for f in grid.rk4_factors:
        n = math.ceil(T / (f * dt_stable))
        for P in grid.rk4_periods:
            m, info, wall, reps = timed(scene, time_run(scene, "rk4", P, n, T), repeats)
            add(row("rk4", f"RK4, dt = {f:g} x limit", P, f"P={P}, dt=T/{n}", m, info, wall, reps,
                    periods=P, dt_s=T / n))
    # generalized-alpha: periods needed from a long run at the finest dt, then over dt
    trans = ga_transient(scene, fresh_model(scene), max(grid.ga_steps), grid.ga_transient_periods,
                         T, ref)
    P = trans["periods_needed"]
    log(f"generalized-alpha: {P} periods (transient {trans['deviation'][P - 1]:.2e} <= "
        f"{trans['threshold']:.2e})")
    for n in grid.ga_steps:
        m, info, wall, reps = timed(scene, time_run(scene, "generalized-alpha", P, n, T), repeats)
        add(row("generalized-alpha", "generalized-α", n, f"P={P}, dt=T/{n}", m, info, wall, reps,
                periods=P, dt_s=T / n))
    # harmonic balance over H
    for H in grid.hb_harmonics:
        m, info, wall, reps = timed(scene, periodic_run(scene, "harmonic-balance", harmonics=H),
                                    repeats)
        add(row("harmonic-balance", "harmonic balance", H, f"H={H}", m, info, wall, reps, H=H))
    # collocation over K and d
    for solver, cfgs in (("newton", grid.col_newton), ("ipopt", grid.col_ipopt)):
        solver_name = {"newton": "Newton", "ipopt": "IPOPT"}[solver]
        for K, d in cfgs:
            m, info, wall, reps = timed(scene, periodic_run(scene, "collocation", intervals=K,
                                                            degree=d, solver=solver), repeats)
            add(row(f"collocation-{solver}", f"collocation d={d}, {solver_name}", K,
                    f"K={K}, d={d}", m, info, wall, reps, K=K, d=d))

    # shooting over its steps per period, in generated C and in the VM, interleaved
    shots = {(cg, n): periodic_run(scene, "shooting", steps=n, codegen=cg)
             for cg in grid.shoot_codegen for n in grid.shoot_steps}
    for (cg, n), (m, info, wall, reps) in timed_interleaved(scene, shots, repeats).items():
        add(row("shooting", f"shooting, {CODE_NAMES[info['code']]}", n, f"dt=T/{n}", m, info,
                wall, reps, dt_s=T / n, periods=info.get("iterations")))

    hb_top = max((r for r in rows if r["method"] == "harmonic-balance"), key=lambda r: r["H"])
    ttl = time_to_levels(rows)
    interp = interpolated_times(rows)
    h2h = head_to_head(scene, rows, ttl, ref, repeats, log) if grid.head_to_head else None
    return {"scene": scene.name, "period_s": T, "build": build, "reference": ref,
            "reference_check": hb_top, "dt_stable_s": dt_stable, "ga_transient": trans,
            "ga_periods": P, "rows": rows, "time_to_level": ttl, "winners": winners(ttl),
            "interpolated": interp, "periodic_winner": periodic_winner(interp), "head_to_head": h2h,
            "repeats": repeats, "study_wall_s": time.perf_counter() - t_start}


#: each periodic method with its defaults (``solve_periodic(scene, method)``, output
#: resolution aside), by the study's name for it (collocation's default solver is IPOPT)
DEFAULTS = {"harmonic-balance": "harmonic-balance", "collocation-ipopt": "collocation",
            "shooting": "shooting"}


def _kwargs(r: dict) -> tuple:
    """(solve_periodic method, keyword arguments) that reproduce a periodic row."""
    if r["method"] == "harmonic-balance":
        return "harmonic-balance", {"harmonics": r["H"]}
    if r["method"] == "shooting":
        return "shooting", {"steps": r["resolution"], "codegen": r["code"] == "C"}
    return "collocation", {"intervals": r["K"], "degree": r["d"],
                           "solver": r["method"].split("-")[1]}


def head_to_head(scene, rows, ttl, ref, repeats: int, log=print) -> list:
    """The periodic methods side by side, interleaved, ``repeats`` rounds for every entry
    (slow ones too): each method's cheapest run to DEFAULT_LEVEL in the sweep, and each
    method's defaults (``solve_periodic(scene, method)``). The sweep above runs the methods
    one after another, minutes apart on a shared machine; this puts their times to the
    level on the same footing."""
    entries = {}
    for meth in PERIODIC:
        r = ttl[meth][DEFAULT_LEVEL]
        if r is not None:
            m, kw = _kwargs(r)
            entries[(meth, "cheapest to level", r["config"] + ("" if m != "shooting" else
                                                               f", {r['code']}"))] = (m, kw)
    for meth, m in DEFAULTS.items():
        entries[(meth, "defaults", f"solve_periodic(scene, {m!r})")] = (m, {})
    runs = {k: periodic_run(scene, m, **kw) for k, (m, kw) in entries.items()}
    done = {k: [] for k in runs}
    for _ in range(repeats):
        for k, run in runs.items():
            done[k].append(_once(scene, run))
    out = []
    for (meth, kind, label), v in done.items():
        m, info, wall, reps = _median_run(v)
        e = errors(m, ref)
        out.append({"method": meth, "kind": kind, "config": label, "wall_s": wall,
                    "repeats": reps, "error": e["error"], "err_wave": e["err_wave"],
                    "code": info.get("code"), "iterations": info.get("iterations"),
                    "status": info["status"]})
        log(f"  head-to-head {meth:19s} {kind:18s} {label:40s} err {e['error']:.3e}  "
            f"wall {wall:8.3f} s")
    return out


# --------------------------------------------------------------------------- outputs
def _fmt(v, spec="{:.3g}"):
    if v is None or (isinstance(v, float) and not np.isfinite(v)):
        return "-"
    return spec.format(v) if isinstance(v, float) else str(v)


def _pct(v, spec: str) -> str:
    """A fraction of the reference range as a percentage ("-" when missing)."""
    return _fmt(None if v is None else 100.0 * v, spec)


def summary_markdown(res: dict) -> str:
    ref, chk, tr, b = res["reference"], res["reference_check"], res["ga_transient"], res["build"]
    L = [f"# Work-precision on the {res['scene']}", "",
         f"Period T = {res['period_s']:g} s, {b['n_y']} states. Error = max of |error| of T_max, "
         f"T_min and A_1, in % of the reference range (as in the figure). Study wall time "
         f"{res['study_wall_s']:.0f} s.",
         "",
         "## Reference", "",
         "| quantity | reference (collocation K={K}, d={d}) | harmonic balance H={H} | "
         "difference (% of range) |".format(K=ref["K"], d=ref["d"], H=chk["H"]),
         "|---|---|---|---|"]
    for k, name in (("t_max", "T_max (N)"), ("t_min", "T_min (N)"), ("a1", "A_1 (N)")):
        L.append(f"| {name} | {ref[k + '_N']:.2f} | {chk[k + '_N']:.2f} | {_pct(chk['err_' + k], '{:+.2g}')} |")
    L += [f"| range (N) | {ref['range_N']:.2f} | | |", ""]
    for r in res["rows"]:  # the next-finest collocation as a second check
        if r["method"] == "collocation-newton" and (r["K"], r["d"]) == (ref["K"] // 2, ref["d"]):
            L += [f"Collocation K={r['K']}, d={r['d']} against the reference: "
                  f"{_pct(r['error'], '{:.3g}')} % of the range (T_max {_pct(r['err_t_max'], '{:+.2g}')} %, "
                  f"T_min {_pct(r['err_t_min'], '{:+.2g}')} %, A_1 {_pct(r['err_a1'], '{:+.2g}')} %).", ""]
    L += [
          f"Reference solve: {ref['wall_s']:.1f} s, {ref['iterations']} Newton iterations, "
          f"{ref['unknowns']} unknowns.", "",
          "One-time build (not in the times below): `build_dynamic_model` "
          f"{1e3 * b['build_dynamic_model_s']:.0f} ms, its Mechanism "
          f"{1e3 * b['mechanism_s']:.0f} ms, RK4 stability limit {1e3 * b['rk4_limit_s']:.0f} ms "
          f"(limit {res['dt_stable_s']:.4g} s).", "",
          "## Generalized-α transient", "",
          f"Run from rest at dt = T/{tr['n']} for {tr['periods_run']} periods; change of the "
          "period's (T_max, T_min, A_1) against the last period, in % of the range:", "",
          "| period | " + " | ".join(str(p + 1) for p in range(tr["periods_run"])) + " |",
          "|---|" + "---|" * tr["periods_run"],
          "| change (%) | " + " | ".join(_pct(v, "{:.2g}") for v in tr["deviation"]) + " |", "",
          f"Error of that run's last period: {_pct(tr['final_error'], '{:.2g}')} %; needed: a transient "
          f"below {TRANSIENT_FRACTION:g} of it ({_pct(tr['threshold'], '{:.2g}')} %): "
          f"**{res['ga_periods']} periods**"
          + ("" if tr["converged"] else " (NOT reached within the run)") + ".", "",
          "## Runs", "",
          "Errors in % of the reference tension range (signed: run minus reference; \"error\" is "
          "the largest magnitude).", "",
          "| method | config | code | error (%) | err T_max (%) | err T_min (%) | err A_1 (%) | "
          "waveform (%) | wall (s) | repeats | solver core (s) | iterations | status |",
          "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in res["rows"]:
        its = r["iterations"]
        if r["method"] == "rk4":
            its = f"{r['steps']} steps"
        elif r["method"] == "generalized-alpha":
            its = f"{its} ({r['iter_per_step']:.2f}/step)"
        elif r["method"] == "shooting":
            its = f"{its} periods"
        elif r["guess_iterations"] is not None:
            its = f"{its} (+{r['guess_iterations']} guess)"
        L.append(f"| {r['method']} | {r['config']} | {r['code']} | {_pct(r['error'], '{:.3g}')} | "
                 f"{_pct(r['err_t_max'], '{:+.2g}')} | {_pct(r['err_t_min'], '{:+.2g}')} | "
                 f"{_pct(r['err_a1'], '{:+.2g}')} | {_pct(r['err_wave'], '{:.2g}')} | "
                 f"{r['wall_s']:.3g} | {r['repeats']} | {_fmt(r['core_s'])} | {its} | {r['status']} |")
    L += ["", "## Time to reach each error level", "",
          "Cheapest run (wall time, s) whose error is at most the level (in % of the reference "
          "tension range); its configuration.", "",
          "| method | " + " | ".join(f"{100 * lev:g} %" for lev in LEVELS) + " |",
          "|---|" + "---|" * len(LEVELS)]
    for meth, v in res["time_to_level"].items():
        cells = [f"{r['wall_s']:.3g} ({r['config']})" if r else "not reached"
                 for r in (v[lev] for lev in LEVELS)]
        L.append(f"| {meth} | " + " | ".join(cells) + " |")
    L.append("| **winner** | " + " | ".join(res["winners"][lev] or "no method reached it"
                                             for lev in LEVELS) + " |")
    L += ["", "## Time to each level, interpolated", "",
          "Wall time (s) at which each method's fastest line reaches the level, linear in "
          "log(time) against log(error) between its two points either side of the level (a "
          "line whose coarsest point is already below it: that point's time, an upper bound).",
          "", "| method | " + " | ".join(f"{100 * lev:g} %" for lev in LEVELS) + " |",
          "|---|" + "---|" * len(LEVELS)]
    for meth, v in res["interpolated"].items():
        cells = [f"{v[lev][0]:.3g} ({v[lev][1]})" if v[lev] else "not reached" for lev in LEVELS]
        L.append(f"| {meth} | " + " | ".join(cells) + " |")
    h2h = res.get("head_to_head")
    if h2h:
        L += ["", "## Periodic methods side by side", "",
              f"Interleaved, median of {res['repeats']} for every entry: each periodic method's "
              f"cheapest run to {100 * DEFAULT_LEVEL:g} % of the range in the sweep above, and its "
              "defaults (resolution 1000 as everywhere here).", "",
              "| method | which | config | code | error (%) | waveform (%) | wall (s) | "
              "time over shooting's |", "|---|---|---|---|---|---|---|---|"]
        base = next((h["wall_s"] for h in h2h if h["method"] == "shooting"
                     and h["kind"] == "cheapest to level"), None)
        for h in h2h:
            L.append(f"| {h['method']} | {h['kind']} | {h['config']} | {h['code']} | "
                     f"{_pct(h['error'], '{:.3g}')} | {_pct(h['err_wave'], '{:.2g}')} | "
                     f"{h['wall_s']:.3g} | {_fmt(None if base is None else h['wall_s'] / base, '{:.1f}')} |")
    pw = res["periodic_winner"]
    if pw["method"] is not None:
        L += ["", f"**Fastest periodic method to {100 * pw['level']:g} % of the range: "
              f"{pw['method']}** ({pw['wall_s']:.3g} s); time over the winner's: "
              + ", ".join(f"{m} {v:.1f}" for m, v in sorted(pw["ratios"].items(), key=lambda kv: kv[1]))
              + "."]
    return "\n".join(L) + "\n"


CODE_NAMES = {"C": "generated C", "VM": "CasADi VM"}
RESOLUTION_NAMES = {"rk4": "P", "harmonic-balance": "H", "collocation-newton": "K",
                    "collocation-ipopt": "K"}  # generalized-alpha and shooting: dt, T/N


def _resolutions(meth: str, values: list) -> str:
    """The resolutions of one line, for its legend entry: "P = 2, 3, 4", "dt = T/25, T/50"."""
    if meth in ("generalized-alpha", "shooting"):
        return "dt = " + ", ".join(f"T/{v}" for v in values)
    return f"{RESOLUTION_NAMES[meth]} = " + ", ".join(str(v) for v in values)


def plot(res: dict, path: Path) -> None:
    """Error (% of the reference range) against wall time, log-log: one line per method at
    fixed settings, its points joined in order of resolution, which the legend lists (no
    labels on the points: they overlapped where the lines cross). Every line's error falls
    (or levels off) as its resolution grows, so its points read from top to bottom."""
    markers = {"rk4": "o", "generalized-alpha": "s", "harmonic-balance": "^",
               "collocation-newton": "D", "collocation-ipopt": "v", "shooting": "P"}
    cmaps = {"rk4": plt.cm.Blues, "generalized-alpha": plt.cm.Greens,
             "harmonic-balance": plt.cm.Purples, "collocation-newton": plt.cm.Reds,
             "collocation-ipopt": plt.cm.Oranges, "shooting": plt.cm.Greys}
    fig, ax = plt.subplots(figsize=(13, 7), constrained_layout=True)
    for meth in METHODS:
        fams = list(dict.fromkeys(r["family"] for r in res["rows"] if r["method"] == meth))
        for i, fam in enumerate(fams):
            rs = sorted((r for r in res["rows"] if r["family"] == fam and np.isfinite(r["error"])),
                        key=lambda r: r["resolution"])
            if not rs:
                continue
            col = cmaps[meth](0.55 + 0.4 * i / max(len(fams) - 1, 1))
            if meth == "shooting":  # black (generated C) to grey (VM, dashed)
                col = cmaps[meth](0.95 - 0.35 * i / max(len(fams) - 1, 1))
            if meth == "rk4":
                name = f"{fam} (from rest)"
            else:
                name = fam if len(fams) > 1 or meth == "shooting" else LABELS[meth]
            ax.loglog([r["wall_s"] for r in rs], [100 * r["error"] for r in rs],
                      marker=markers[meth], color=col, ms=5, lw=1.2,
                      ls="--" if meth == "collocation-ipopt" or fam.endswith("VM") else "-",
                      label=f"{name}: {_resolutions(meth, [r['resolution'] for r in rs])}")
    for k, lev in enumerate(LEVELS):
        ax.axhline(100 * lev, color="0.4", lw=0.8, ls=":",
                   label="error levels: " + ", ".join(f"{100 * v:g} %" for v in LEVELS) if k == 0 else None)
    ax.yaxis.set_major_formatter(ticker.FuncFormatter(lambda v, _: f"{v:g} %"))
    ax.xaxis.set_major_formatter(ticker.FuncFormatter(lambda v, _: f"{v:g}"))
    ax.set_xlabel("wall time of one solve from scratch (model built), s")
    ax.set_ylabel("error of T_max, T_min, A_1 (largest), % of the reference tension range")
    ref = res["reference"]
    quick = " (--quick: coarse grid and reference)" if res.get("quick") else ""
    ax.set_title(f"Work-precision, seed-001 line: periodic fairlead tension{quick}\n(reference: "
                 f"collocation K={ref['K']}, d={ref['d']}; range {ref['range_N'] / 1e3:.1f} kN)")
    ax.grid(True, which="both", alpha=0.25)
    ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0,
              title="method: its resolutions, in order along its line (error falls as they grow)",
              title_fontsize=8)
    fig.savefig(path, dpi=150)
    plt.close(fig)


def main(argv=None) -> dict:
    args = study_io.parse(__doc__, "a few cheap points per method, coarse reference (under a minute)",
                          HERE / "out", argv)
    res = run_study(QUICK if args.quick else FULL, REPEATS)
    res["quick"], res["out"] = bool(args.quick), str(args.out)
    study_io.write(args, res["rows"], summary_markdown(res), lambda path: plot(res, path),
                   "work_precision.png")
    return res

if __name__ == "__main__":
    main()
