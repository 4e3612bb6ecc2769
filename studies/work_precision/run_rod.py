"""Work-precision of symcable's dynamic solvers on the rod and the hybrid: error against wall time.

Question
--------
On a rod (``model = "rod"``) and a hybrid rod-catenary line (``model = "hybrid"``), how does
the error of ``sc.simulate``'s first-order generalized-alpha (GA1) fall with dt, what order
does it reach, and what does a given accuracy cost, against RK4 and the periodic solvers
(shooting, collocation) on the same case?

Cases (``rod_cases.py``): the damped rod cantilever of tests/test_rod_api.py (8 segments,
two principal stiffnesses, its clamp heaving 2 cm at T = 1 s), and tests/test_hybrid.py's
taut hose as a hybrid (cable3d, rod, cable3d sections of 6 segments, end B heaving 5 cm at
T = 2 s; full run: the same hose all rod, for the hybrid's saving). Every run starts from the
static state at rest (the motion ramped in by ``simulate``) and lasts P periods.

Error: the largest over the saved samples (every T/25) of the node positions' difference
from the reference, over the reference's largest node excursion (max over nodes of the
range of |x(t) - x(0)|). For context, the end force's (the clamp's force for the
cantilever, end B's tension for the hose) over its range: not the metric, since the force
carries the ringing of the highest bending modes (80 Hz and up at 8 segments, undamped
but for the scheme's numerical damping), which the reference resolves and keeps and the
coarse runs damp out (the reference cantilever's clamp force jitters by ~1 % of its
range at T/1600), so its error does not fall at the scheme's order until dt resolves
them. Reference: GA1 at a fine
step (full: T/3200; quick: T/400), same start, same P (so the error is the discretisation's
alone: the orders are read from it). The periodic solvers are compared with the
reference's last period (its period-to-period change is reported: the transient left).

Wall time: the whole ``sc.simulate`` / ``sc.solve_periodic`` call in the CasADi VM
(``codegen=False``: the rod's generated C takes minutes to compile, studies/rod_notes/wire14.md), after
one warm-up call per case and method (the VM functions are then built and cached in the
process: what a second call of a session costs); the warm-up's own time is the "first call"
column. Median of 3 when a call is under 2 s (full run).

Run
---
    python -u studies/work_precision/run_rod.py            # full: ~10 min on 2 shared cores
    python -u studies/work_precision/run_rod.py --quick    # GA1 at T/25-T/100 against T/400,
                                                           # 2 periods, both cases (the test)
    options: --out DIR (default studies/work_precision/out/rod/), --figure PATH,
             --cases NAME [NAME ...] (of CASES)

Writes ``results.csv``, ``summary.md`` and ``work_precision_rod.png``; ``main(argv)``
returns the numbers as a dict.
"""
from __future__ import annotations

import math
import statistics
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
import rod_cases as rc  # noqa: E402  (studies/work_precision/rod_cases.py)
import study_io  # noqa: E402

CHEAP_S = 2.0
SAMPLES_PER_PERIOD = 25


class Grid(NamedTuple):
    ga1_steps: tuple        # steps per period N (dt = T/N)
    ref_steps: int
    periods: int
    rk4: bool
    periodic: tuple         # periodic methods run
    cases: tuple            # case names
    repeats: int


FULL = Grid(ga1_steps=(25, 50, 100, 200, 400, 800), ref_steps=3200, periods=3, rk4=True,
            periodic=("shooting", "collocation"), cases=("rod cantilever", "hybrid hose", "rod hose"),
            repeats=3)
QUICK = Grid(ga1_steps=(25, 50, 100), ref_steps=400, periods=2, rk4=False, periodic=(),
             cases=("rod cantilever", "hybrid hose"), repeats=1)


class Case(NamedTuple):
    scene: dict
    period: float
    force: str          # the LineTrajectory's end-force series compared


CASES = {"rod cantilever": lambda: Case(rc.cantilever(), 1.0, "anchor_tension"),
         "hybrid hose": lambda: Case(rc.hose("hybrid"), 2.0, "fairlead_tension"),
         "rod hose": lambda: Case(rc.hose("rod"), 2.0, "fairlead_tension")}


def _timed(call, repeats: int):
    runs = []
    while True:
        t0 = time.perf_counter()
        out = call()
        runs.append((time.perf_counter() - t0, out))
        if len(runs) >= repeats or runs[0][0] >= CHEAP_S:
            break
    return runs[-1][1], statistics.median(w for w, _ in runs), len(runs)


def _series(tr, force: str) -> dict:
    return {"t": np.asarray(tr.time, float), "x": np.asarray(tr.positions, float),
            "f": np.asarray(getattr(tr, force), float)}


def time_run(case: Case, n: int | None, periods: int, method: str = "generalized-alpha"):
    """One ``sc.simulate`` over ``periods`` periods at dt = T/n (RK4: n None, its default
    dt), saved every T/25: (series, info)."""
    T = case.period
    ts = np.arange(1, SAMPLES_PER_PERIOD * periods + 1) * T / SAMPLES_PER_PERIOD

    def call():
        try:
            tr = sc.simulate(case.scene, periods * T, dt=None if n is None else T / n,
                             method=method, save_times=ts, codegen=False)
        except ConvergenceError as exc:
            return None, {"status": "failed: " + str(exc).splitlines()[0][:200]}
        s = tr.stats
        its = s.get("newton_iterations")
        return _series(tr, case.force), {
            "status": tr.status, "steps": s["steps"], "dt_s": s["dt"],
            "iter_per_step": None if its is None else its / s["steps"],
            "substeps": s.get("substepped_steps"), "reanchorings": s.get("reanchorings"),
            "dt_stable_s": s.get("dt_stable")}
    return call


def periodic_run(case: Case, method: str):
    def call():
        try:
            sol = sc.solve_periodic(case.scene, method, codegen=False)
        except ConvergenceError as exc:
            return None, {"status": "failed: " + str(exc).splitlines()[0][:200]}
        return _series(sol, case.force), {"status": sol.status,
                                          "iterations": sol.stats.get("iterations")}
    return call


def errors(run: dict, ref: dict, T: float, last_period: bool = False) -> dict:
    """Position and force errors over the reference's scales (module docstring); a periodic
    run is compared with the reference's last period, at the reference's samples (t mod T)."""
    x0 = ref["x"][0]
    scale_x = float(np.max(np.ptp(np.linalg.norm(ref["x"] - x0, axis=2), axis=0)))
    scale_f = float(np.ptp(ref["f"]))
    if last_period:
        last = ref["t"] >= ref["t"][-1] - T + 1e-9 * T
        tr, xr, fr = ref["t"][last], ref["x"][last], ref["f"][last]
        ph = np.mod(run["t"] - run["t"][0], T)
        tt = np.mod(tr, T)
        x = np.stack([np.stack([np.interp(tt, ph, run["x"][:, i, k], period=T)
                                for k in range(3)], axis=1) for i in range(xr.shape[1])], axis=1)
        f = np.interp(tt, ph, run["f"], period=T)
    elif run["t"].shape == ref["t"].shape and np.max(np.abs(run["t"] - ref["t"])) < 1e-9 * T:
        x, f, xr, fr = run["x"], run["f"], ref["x"], ref["f"]
    else:  # RK4's steps do not fall on the saved times: linear interpolation (its dt ~T/1000)
        xr, fr = ref["x"], ref["f"]
        x = np.stack([np.stack([np.interp(ref["t"], run["t"], run["x"][:, i, k]) for k in range(3)],
                               axis=1) for i in range(xr.shape[1])], axis=1)
        f = np.interp(ref["t"], run["t"], run["f"])
    ex = float(np.max(np.linalg.norm(x - xr, axis=2))) / scale_x
    ef = float(np.max(np.abs(f - fr))) / scale_f
    return {"error": ex, "error_x": ex, "error_f": ef, "scale_x_m": scale_x,
            "scale_f_N": scale_f}


def run_case(name: str, grid: Grid, log=print) -> dict:
    case = CASES[name]()
    T, P = case.period, grid.periods
    t0 = time.perf_counter()
    warm = time_run(case, grid.ga1_steps[0], 1)()   # builds the VM functions (first call)
    first = time.perf_counter() - t0
    t0 = time.perf_counter()
    ref, rinfo = time_run(case, grid.ref_steps, P)()
    if ref is None:
        raise RuntimeError(f"{name}: the reference failed: {rinfo['status']}")
    ref_wall = time.perf_counter() - t0
    k = SAMPLES_PER_PERIOD  # the last period's positions against the one before
    scale = float(np.max(np.ptp(np.linalg.norm(ref["x"] - ref["x"][0], axis=2), axis=0)))
    drift = float(np.max(np.linalg.norm(ref["x"][-k:] - ref["x"][-2 * k:-k], axis=2))
                  ) / scale if len(ref["t"]) >= 2 * k else None
    log(f"{name}: first call {first:.1f} s ({warm[1]['status']}), reference T/{grid.ref_steps} "
        f"{ref_wall:.1f} s, last-period change {drift}")
    rows = []

    def add(method, config, resolution, res, info, wall, reps):
        r = {"case": name, "method": method, "config": config, "resolution": resolution,
             "wall_s": wall, "repeats": reps, **info}
        r.update(errors(res, ref, T, last_period=method not in ("ga1", "rk4"))
                 if res is not None else {"error": math.nan})
        rows.append(r)
        log(f"  {method:12s} {config:14s} error {r['error']:.3e}  wall {wall:7.2f} s  "
            f"{info.get('status')}  N/step {info.get('iter_per_step')}")

    for n in grid.ga1_steps:
        (res, info), wall, reps = _timed(time_run(case, n, P), grid.repeats)
        add("ga1", f"dt=T/{n}", n, res, info, wall, reps)
    if grid.rk4:
        time_run(case, None, 1, "rk4")()  # warm-up
        (res, info), wall, reps = _timed(time_run(case, None, P, "rk4"), grid.repeats)
        add("rk4", f"dt={info.get('dt_s', 0):.3g} s", None, res, info, wall, reps)
    periodic = {}
    for meth in grid.periodic:
        t0 = time.perf_counter()
        periodic_run(case, meth)()  # warm-up (its first call builds the discretisation)
        pfirst = time.perf_counter() - t0
        (res, info), wall, reps = _timed(periodic_run(case, meth), grid.repeats)
        info["first_call_s"] = pfirst
        add(meth, "defaults", None, res, info, wall, reps)
        periodic[meth] = res
    if len(periodic) == 2 and None not in periodic.values():
        a, b = periodic.values()  # shooting against collocation: two routes to one state
        rows[-2]["vs_other_periodic"] = errors(a, b, T, last_period=True)["error_x"]
    return {"case": name, "scene": case.scene["name"], "period_s": T, "periods": P,
            "first_call_s": first, "reference": f"GA1, dt = T/{grid.ref_steps}",
            "reference_wall_s": ref_wall, "reference_drift": drift,
            "n_dof": int(ref["x"].shape[1]), "rows": rows, "orders": orders(rows)}


def orders(rows: list) -> list:
    """GA1's observed order between successive halvings of dt: log2(e(dt) / e(dt/2))."""
    rs = [r for r in rows if r["method"] == "ga1" and np.isfinite(r["error"])]
    return [(f"T/{a['resolution']}->T/{b['resolution']}", math.log2(a["error"] / b["error"]))
            for a, b in zip(rs, rs[1:]) if a["error"] > 0 and b["error"] > 0]


def summary_markdown(res: dict) -> str:
    L = ["# Work-precision on the rod and the hybrid", "",
         f"Study wall time {res['wall_s']:.0f} s{' (--quick)' if res['quick'] else ''}. Errors "
         "in % (the error: node positions, of the largest node excursion; the end force, context: of its range); wall times of "
         "warm calls in the VM.", ""]
    for c in res["cases"]:
        drift = "-" if c["reference_drift"] is None else f"{100 * c['reference_drift']:.2g} %"
        L += [f"## {c['scene']}", "",
              f"T = {c['period_s']:g} s, {c['periods']} periods from rest. Reference "
              f"{c['reference']} ({c['reference_wall_s']:.1f} s); its last period against the one "
              f"before: {drift} "
              f"of the largest excursion (the transient left: the periodic rows' floor). First call "
              f"(builds the VM functions): {c['first_call_s']:.1f} s.", "",
              "| method | config | error (%) | force (%, context) | wall (s) | Newton/step "
              "| substeps | re-anchorings | status |", "|---|---|---|---|---|---|---|---|---|"]
        for r in c["rows"]:
            def pct(k):
                v = r.get(k)
                return "-" if v is None or not np.isfinite(v) else f"{100 * v:.3g}"
            ips = "-" if r.get("iter_per_step") is None else f"{r['iter_per_step']:.2f}"
            L.append(f"| {r['method']} | {r['config']} | {pct('error')} | "
                     f"{pct('error_f')} | {r['wall_s']:.3g} | {ips} | {r.get('substeps', '-')} | "
                     f"{r.get('reanchorings', '-')} | {r['status']} |")
        pr = [r for r in c["rows"] if r.get("vs_other_periodic") is not None]
        if pr:
            L += ["", f"Shooting against collocation (node positions, % of the excursion): "
                  f"{100 * pr[0]['vs_other_periodic']:.3g}."]
        L += ["", "GA1's observed orders: " + (", ".join(f"{k}: {p:.2f}" for k, p in c["orders"])
                                               or "-"), ""]
    return "\n".join(L) + "\n"


def csv_rows(res: dict) -> list:
    keys = ("case", "method", "config", "resolution", "status", "error", "error_x", "error_f",
            "scale_x_m", "scale_f_N", "wall_s", "repeats", "steps", "dt_s", "iter_per_step",
            "substeps", "reanchorings", "dt_stable_s", "iterations", "first_call_s",
            "vs_other_periodic")
    return [{k: r.get(k) for k in keys} for c in res["cases"] for r in c["rows"]]


def plot(res: dict, path) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(9, 5.5), constrained_layout=True)
    marks = {"ga1": "s", "rk4": "o", "shooting": "P", "collocation": "v"}
    for i, c in enumerate(res["cases"]):
        col = f"C{i}"
        ga = [r for r in c["rows"] if r["method"] == "ga1" and np.isfinite(r["error"])]
        ax.loglog([r["wall_s"] for r in ga], [100 * r["error"] for r in ga], "-s", color=col,
                  label=f"{c['case']}: GA1 " + ", ".join(r["config"][3:] for r in ga))
        for r in c["rows"]:
            if r["method"] != "ga1" and np.isfinite(r["error"]):
                ax.loglog(r["wall_s"], 100 * r["error"], marks[r["method"]], color=col, ms=8,
                          label=f"{c['case']}: {r['method']}")
    ax.set_xlabel("wall time of one warm call (VM), s")
    ax.set_ylabel("largest node-position error, % of the largest excursion")
    ax.set_title("Work-precision, rod and hybrid" + (" (--quick)" if res["quick"] else ""))
    ax.grid(True, which="both", alpha=0.25)
    ax.legend(fontsize=7)
    fig.savefig(path, dpi=120)
    plt.close(fig)


def main(argv=None) -> dict:
    args = study_io.parse(__doc__, "GA1 T/25-T/100 against T/400, 2 periods (the test)",
                          HERE / "out" / "rod", argv,
                          extra=lambda ap: ap.add_argument("--cases", nargs="*", choices=list(CASES),
                                                           help="the cases run (default the grid's)"))
    grid = QUICK if args.quick else FULL
    if args.cases:
        grid = grid._replace(cases=tuple(args.cases))
    t0 = time.perf_counter()
    res = {"quick": bool(args.quick), "cases": [run_case(n, grid) for n in grid.cases]}
    res["wall_s"] = time.perf_counter() - t0
    study_io.write(args, csv_rows(res), summary_markdown(res), lambda p: plot(res, p),
                   "work_precision_rod.png")
    return res


if __name__ == "__main__":
    main()
