"""Stiff and extreme cases: which method converges, how accurately and how fast.

Question
--------
On the seed-001 line pushed to its extremes (stiffer, bending-dominated, finer, a time step
above the explicit limit, lightly damped at a natural period, slack, a strong current), which
of symcable's dynamic solvers converge, how far is each from a reference answer, and what does
each cost? Methods (the columns): RK4 at its default dt (0.8 of its stability limit) and at a
given dt, generalized-alpha at dt = T/100, collocation (default mesh) solved by IPOPT and by
Newton, and harmonic balance (default H).

Every case starts from ``symcable/data/seed001.toml`` (seed-001 line, T = 10 s) coarsened to
20 segments (so that the whole table runs in a few minutes on 2 cores; the segment cases go
to 400). A time run starts from rest, runs ``periods`` excitation periods and keeps the last
one. Error: the largest of the differences in max, min and first-harmonic amplitude of the
fairlead tension over a period from the case's reference, as a fraction of the reference's
range (max - min). The reference is collocation on a twice finer mesh (80 intervals, IPOPT)
up to ``FINE_REF_MAX_SEGMENTS``, else the best converged method of the case (the order in
``REF_FALLBACK``). Time: wall time of the solve call with the dynamic model built beforehand
(the solvers' own CasADi functions are built inside the call: ``solver_build_s`` in the csv).
Every cell runs in a forked child process with a time limit, so a blow-up, a hang or
running out of memory is a cell's result, not the study's end.

Run
---
    python studies/stability/run.py            # full: 18 cases x 6 methods + slack search, ~10 min
    python studies/stability/run.py --quick    # 3 cases x 3 methods, well under a minute
    options: --out DIR (default studies/stability/out/), --timeout S (per cell)

Writes ``results.csv`` (one row per case x method, plus each case's reference) and
``summary.md`` (the case x method table, the failure messages, per-case details, the slack
search) to the out dir. ``main(argv)`` returns the same numbers as a dict.
"""

import argparse
import csv
import multiprocessing
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable

import numpy as np

import symcable as sc
from symcable.api.analyses import solve_periodic
from symcable.api.planar_time import rk4_stability_limit

HERE = Path(__file__).resolve().parent
SEGMENTS = 20             # the study's base discretisation (seed001.toml has 50)
PERIODS = 20              # time-run length, excitation periods (the last one is compared)
GIVEN_DT_PER_PERIOD = 200  # the RK4 "given dt" column: T/200 = 0.05 s at T = 10 s
SAMPLES = 200             # fairlead-tension samples per period for max/min/harmonic
FINE_INTERVALS = 80       # reference mesh (the default is 40)
FINE_REF_MAX_SEGMENTS = 200
RESONANCE_PERIODS = 300   # the lightly damped cases need many periods
CHECKPOINTS = (20, 50, 100, 150, 200, 300)  # periods at which the resonance runs' error is shown
SETTLE_TOL = 0.01         # a time run has settled when every later period is within 1 % of range
TIMEOUT_FULL, TIMEOUT_QUICK = 200.0, 120.0
SLACK_FACTORS = (1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 8.0, 10.0)  # x the seed amplitude [2, 1] m
SLACK_BISECTIONS = 4
#: the reference when the fine mesh is not run or fails: the first converged of these cells
REF_FALLBACK = ("coll_newton", "coll_ipopt", "hb", "rk4_default", "ga", "rk4_given")


@dataclass(frozen=True)
class Method:
    key: str
    label: str
    kind: str  # "time" | "periodic"


METHODS = (
    Method("rk4_default", "RK4, default dt", "time"),
    Method("rk4_given", "RK4, given dt (T/200)", "time"),
    Method("ga", "gen.-α, dt = T/100", "time"),
    Method("coll_ipopt", "collocation, IPOPT", "periodic"),
    Method("coll_newton", "collocation, Newton", "periodic"),
    Method("hb", "harmonic balance, H = 10", "periodic"),
)
BY_KEY = {m.key: m for m in METHODS}
QUICK_METHODS = ("rk4_given", "ga", "coll_newton")


@dataclass
class Case:
    """One row of the table. ``make()`` returns the scene dict; ``rk4_dt``/``ga_dt`` map the
    case's RK4 stability limit and period to the dt of those columns (None: the default)."""

    name: str
    group: str
    make: Callable[[], dict]
    param: str = ""
    periods: int = PERIODS
    rk4_dt: Callable | None = None
    ga_dt: Callable | None = None
    methods: tuple = tuple(m.key for m in METHODS)
    same_scene_as: str | None = None
    info: dict = field(default_factory=dict)


# ---------------------------------------------------------------------------------------------
# scenes
def base_dict(segments: int = SEGMENTS) -> dict:
    """The seed-001 scene as a dict, with ``segments`` segments."""
    d = sc.load_scene(Path(str(sc.demo_scene_path("seed001")))).to_dict()
    d["sections"][0]["segments"] = segments
    return d


def edited(segments: int, *, ea=1.0, ei=None, cd=1.0, current=None, amplitude=1.0,
           name="") -> dict:
    """The base scene with EA and Cd scaled, EI (N m^2) and the current (m/s) set, and the
    fairlead amplitude scaled."""
    d = base_dict(segments)
    lt = d["line_types"]["chain"]
    lt["EA"] *= ea
    if ei is not None:
        lt["EI"] = float(ei)
    lt["cd_normal"] *= cd
    lt["cd_tangential"] *= cd
    if current is not None:
        d["environment"]["current"] = [float(current), 0.0]
    mo = d["end_b"]["motion"]
    mo["amplitude"] = [a * amplitude for a in mo["amplitude"]]
    d["name"] = f"stability study: {name}"
    return d


def resonance_dict(segments: int, mode: int, info: dict) -> dict:
    """Light damping at a natural period: Cd x 0.01, no current, amplitude x 0.05
    ([0.1, 0.05] m), excited at the period of mode ``mode`` (1-based) of that line."""
    d = edited(segments, cd=0.01, current=0.0, amplitude=0.05, name=f"resonance, mode {mode}")
    modes = sc.modal_analysis(sc.load_scene(d), max(mode, 4))
    info.update(mode_periods=[float(p) for p in modes.periods], mode=mode)
    d["end_b"]["motion"]["period"] = float(modes.periods[mode - 1])
    return d


def slack_search(segments: int) -> dict:
    """Raise the fairlead amplitude (x the seed's [2, 1] m) until the periodic solution says
    "slack", then bisect. Collocation (Newton), each solve started from the previous one."""
    history, prev, taut, slack = [], None, None, None

    def solve(f):
        nonlocal prev
        d = edited(segments, amplitude=f, name=f"amplitude x{f:g}")
        try:
            sol = solve_periodic(d, "collocation", solver="newton", initial=prev)
        except sc.SymcableError as exc:
            history.append({"factor": f, "status": f"FAILED: {type(exc).__name__}"})
            prev = None
            return "failed"
        prev = sol
        history.append({"factor": f, "status": sol.status,
                        "fairlead_min_kN": float(np.min(sol.fairlead_tension)) / 1e3,
                        "fairlead_max_kN": float(np.max(sol.fairlead_tension)) / 1e3,
                        "segment_tension_min_kN": float(np.min(sol.tension_min)) / 1e3,
                        "warning": " / ".join(sol.warnings)})
        return sol.status

    for f in SLACK_FACTORS:
        st = solve(f)
        if st == "converged":
            taut = f
        else:
            slack = f
            break
    if slack is None or taut is None:
        return {"history": history, "taut": taut, "slack": slack}
    for _ in range(SLACK_BISECTIONS):
        mid = round(0.5 * (taut + slack), 4)
        if solve(mid) == "converged":
            taut = mid
        else:
            slack = mid
    return {"history": history, "taut": taut, "slack": slack}


def cases(quick: bool, slack: dict | None) -> list:
    n = SEGMENTS
    lim12 = lambda lim, T: 1.2 * lim  # noqa: E731
    dt_cases = [Case("dt = 1.2 x RK4 limit", "time step", lambda: edited(n, name="dt 1.2 x limit"),
                     "base scene, RK4 given and gen.-α", rk4_dt=lim12, ga_dt=lim12,
                     methods=("rk4_given", "ga"), same_scene_as="base")]
    if quick:
        return [Case("base", "base", lambda: edited(n, name="base"), "seed-001, 20 segments"),
                Case("EA x10", "stiffness", lambda: edited(n, ea=10, name="EA x10"), "EA = 3.84e8 N"),
                *dt_cases]
    w, L = 698.094, 902.2
    out = [Case("base", "base", lambda: edited(n, name="base"), "seed-001, 20 segments")]
    for k in (10, 100):
        out.append(Case(f"EA x{k}", "stiffness", lambda k=k: edited(n, ea=k, name=f"EA x{k}"),
                        f"EA = {3.84243e7 * k:.3g} N"))
    for ei in (1e6, 1e8, 1e10, 1e11):
        out.append(Case(f"EI = {ei:.0e}", "bending", lambda ei=ei: edited(n, ei=ei, name=f"EI {ei:g}"),
                        f"EI/(w L^3) = {ei / (w * L ** 3):.1e}"))
    for seg in (50, 100, 200, 400):
        out.append(Case(f"{seg} segments", "segments", lambda seg=seg: edited(seg, name=f"{seg} segments"),
                        f"n_y = {4 * seg - 2}"))
    big = lambda frac: (lambda lim, T: T * frac)  # noqa: E731
    dt_cases += [Case(f"dt = T/{q}", "time step", lambda q=q: edited(n, name=f"dt T/{q}"),
                      "base scene, RK4 given and gen.-α", rk4_dt=big(1 / q), ga_dt=big(1 / q),
                      methods=("rk4_given", "ga"), same_scene_as="base") for q in (10, 4)]
    out += dt_cases
    for mode in (1, 2):
        c = Case(f"resonance, mode {mode}", "light damping", None,
                 "Cd x0.01, no current, A = [0.1, 0.05] m", periods=RESONANCE_PERIODS)
        c.make = lambda mode=mode, c=c: resonance_dict(n, mode, c.info)
        out.append(c)
    if slack and slack.get("slack"):
        f = slack["slack"]
        out.append(Case("slack amplitude", "slack", lambda: edited(n, amplitude=f, name="slack"),
                        f"A = [{2 * f:.4g}, {f:.4g}] m (x{f:g}: first slack)"))
    out.append(Case("current 2 m/s", "current", lambda: edited(n, current=2.0, name="current 2 m/s"),
                    "U = 2 m/s (seed 0.5)"))
    return out


# ---------------------------------------------------------------------------------------------
# one cell: a solve in a forked child with a time limit
def _one_line(exc: BaseException) -> str:
    lines = str(exc).strip().splitlines()
    return lines[0] if lines else ""


def _child(fn, conn) -> None:
    try:
        res = {"ok": True, **fn()}
    except Exception as exc:  # any failure is the cell's result
        diag = getattr(exc, "diagnostics", None) or {}
        res = {"ok": False, "exc_type": type(exc).__name__, "message": _one_line(exc),
               "reason": diag.get("reason", diag.get("return_status", ""))}
    conn.send(res)
    conn.close()


def isolated(fn, timeout: float) -> dict:
    """``fn()`` in a forked child; its dict, or {"ok": False, ...} on an exception, a crash or
    the time limit (the child is then terminated by its pid)."""
    ctx = multiprocessing.get_context("fork")
    recv, send = ctx.Pipe(duplex=False)
    proc = ctx.Process(target=_child, args=(fn, send), daemon=True)
    t0 = time.perf_counter()
    proc.start()
    send.close()
    res = None
    if recv.poll(timeout):
        try:
            res = recv.recv()
        except EOFError:
            res = None
        proc.join(10)
        if res is None:
            res = {"ok": False, "exc_type": "Crash", "reason": "crash",
                   "message": f"the solver process died (exit code {proc.exitcode})"}
    else:
        proc.terminate()
        proc.join(5)
        if proc.is_alive():
            proc.kill()
            proc.join()
        res = {"ok": False, "exc_type": "Timeout", "reason": "timeout",
               "message": f"no answer within {timeout:.0f} s (stopped)"}
    res.setdefault("wall_s", time.perf_counter() - t0)
    recv.close()
    return res


def _metrics(f: np.ndarray) -> dict:
    """max, min, first-harmonic amplitude (N) of uniform samples over one period."""
    c = np.fft.rfft(f) / f.size
    return {"max": float(np.max(f)), "min": float(np.min(f)), "a1": float(2.0 * abs(c[1]))}


def _time_cell(scene, model, method: str, dt, periods: int) -> dict:
    T = model.period
    dt_guess = dt if dt is not None else min(0.8 * rk4_stability_limit(model), T / 100)
    save_every = max(1, int(T / dt_guess / 100))
    t0 = time.perf_counter()
    tr = sc.simulate(scene, periods * T, dt=dt, method=method, model=model, save_every=save_every)
    wall = time.perf_counter() - t0
    tau = np.arange(SAMPLES) / SAMPLES
    per = [_metrics(np.interp((k + tau) * T, tr.time, tr.fairlead_tension)) for k in range(periods)]
    st = tr.stats
    return {"wall_s": wall, "status": tr.status, "per_period": per, **per[-1],
            "dt": st["dt"], "steps": st["steps"], "iterations": st.get("newton_iterations"),
            "warning": tr.warnings[0] if tr.warnings else ""}


def _periodic_cell(scene, model, method: str, **kw) -> dict:
    t0 = time.perf_counter()
    sol = solve_periodic(scene, method, model=model, **kw)
    wall = time.perf_counter() - t0
    st = sol.stats
    return {"wall_s": wall, "status": sol.status, **_metrics(np.asarray(sol.fairlead_tension)),
            "build_s": st.get("build_time"), "iterations": st.get("iterations"),
            "unknowns": st.get("unknowns"), "warning": sol.warnings[0] if sol.warnings else ""}


def cell_fn(key: str, scene, model, case: Case, lim: float):
    T = model.period
    if key == "rk4_default":
        return lambda: _time_cell(scene, model, "rk4", None, case.periods)
    if key == "rk4_given":
        dt = case.rk4_dt(lim, T) if case.rk4_dt else T / GIVEN_DT_PER_PERIOD
        return lambda: _time_cell(scene, model, "rk4", dt, case.periods)
    if key == "ga":
        dt = case.ga_dt(lim, T) if case.ga_dt else T / 100
        return lambda: _time_cell(scene, model, "generalized-alpha", dt, case.periods)
    if key == "coll_ipopt":
        return lambda: _periodic_cell(scene, model, "collocation", solver="ipopt")
    if key == "coll_newton":
        return lambda: _periodic_cell(scene, model, "collocation", solver="newton")
    if key == "hb":
        return lambda: _periodic_cell(scene, model, "harmonic-balance")
    if key == "reference":
        return lambda: _periodic_cell(scene, model, "collocation", solver="ipopt",
                                      intervals=FINE_INTERVALS)
    raise KeyError(key)


# ---------------------------------------------------------------------------------------------
# errors, settling
def rel_error(m: dict, ref: dict) -> float:
    rng = ref["max"] - ref["min"]
    return max(abs(m["max"] - ref["max"]), abs(m["min"] - ref["min"]), abs(m["a1"] - ref["a1"])) / rng


def settle(per: list, rng: float) -> tuple:
    """(the number of periods after which every later period's max, min and first harmonic
    stay within SETTLE_TOL x ``rng`` of the last period's, or None when the second-last
    period is already further off; that deviation of the second-last period / ``rng``)."""
    last = per[-1]
    dev = [max(abs(p["max"] - last["max"]), abs(p["min"] - last["min"]), abs(p["a1"] - last["a1"])) / rng
           for p in per]
    drift = dev[-2] if len(dev) > 1 else float("nan")
    k = len(dev) - 1  # index of the last period
    while k > 0 and dev[k - 1] <= SETTLE_TOL:
        k -= 1
    return (k + 1 if k < len(dev) - 1 else None), drift


# ---------------------------------------------------------------------------------------------
# the study
def run_case(case: Case, methods: tuple, timeout: float, done: dict, skip: dict) -> dict:
    t0 = time.perf_counter()
    d = case.make()
    scene = sc.load_scene(d)
    model = sc.build_dynamic_model(scene)
    lim = rk4_stability_limit(model)  # computed here so that the children reuse it
    build_s = time.perf_counter() - t0
    T = model.period
    seg = sum(s["segments"] for s in d["sections"])
    res = {"case": case.name, "group": case.group, "segments": seg,
           "n_y": model.n_y, "period_s": T, "dt_stable_s": lim, "build_s": build_s,
           "static_fairlead_kN": model.info["static"].fairlead_tension / 1e3,
           "param": case.param + (f": dt = {case.rk4_dt(lim, T):.3g} s" if case.rk4_dt else ""),
           "info": case.info, "cells": {}}
    for key in methods:
        if key not in case.methods:
            continue
        if BY_KEY[key].kind == "periodic" and key in skip:
            res["cells"][key] = {"ok": False, "skipped": True, "exc_type": "NotRun",
                                 "message": skip[key], "reason": "skipped"}
            continue
        res["cells"][key] = isolated(cell_fn(key, scene, model, case, lim), timeout)
    # reference
    res["ref_own"] = not case.same_scene_as
    if case.same_scene_as:
        res["reference"] = done[case.same_scene_as]["reference"]
    else:
        ref = None
        if seg <= FINE_REF_MAX_SEGMENTS:
            ref = isolated(cell_fn("reference", scene, model, case, lim), timeout)
            ref["method"] = f"collocation, {FINE_INTERVALS} intervals (IPOPT)"
        if ref is None or not ref["ok"]:
            for key in REF_FALLBACK:
                c = res["cells"].get(key)
                if c and c["ok"]:
                    ref = {**c, "method": BY_KEY[key].label, "cell": key}
                    c["is_reference"] = True
                    break
        res["reference"] = ref if ref and ref["ok"] else None
    ref = res["reference"]
    for key, c in res["cells"].items():
        if c["ok"] and ref is not None:
            c["error"] = rel_error(c, ref)
            if "per_period" in c:
                c["settled_after"], c["drift"] = settle(c["per_period"], ref["max"] - ref["min"])
                c["error_after"] = {k: rel_error(c["per_period"][k - 1], ref) for k in CHECKPOINTS
                                    if k <= len(c["per_period"])}
    res["wall_s"] = time.perf_counter() - t0
    return res


def update_skips(res: dict, prev: dict | None, skip: dict, timeout: float) -> None:
    """In the segment sweep: a periodic method that timed out, or whose time extrapolated by
    its last growth factor would pass the limit, is not run at the next size."""
    for key, c in res["cells"].items():
        if BY_KEY[key].kind != "periodic" or key in skip:
            continue
        if not c["ok"] and c.get("reason") in ("timeout", "crash"):
            skip[key] = f"not run: {c['exc_type'].lower()} at {res['segments']} segments"
        elif c["ok"] and prev is not None and prev["cells"].get(key, {}).get("ok"):
            growth = c["wall_s"] / prev["cells"][key]["wall_s"]
            est = c["wall_s"] * growth
            if est > timeout:
                skip[key] = (f"not run: ~{est:.0f} s expected ({c['wall_s']:.0f} s at "
                             f"{res['segments']} segments x {growth:.1f} per doubling) > "
                             f"{timeout:.0f} s limit")


# ---------------------------------------------------------------------------------------------
# outputs
def cell_text(c: dict | None, notes: list) -> str:
    if c is None:
        return "—"
    if c.get("skipped"):
        return c["message"]
    if not c["ok"]:
        notes.append(f"{c['exc_type']}: {c['message']}")
        msg = c["message"]
        short = msg if len(msg) <= 60 else msg[:57] + "..."
        return f"FAILED: {c['exc_type']}: {short} [F{len(notes)}]"
    err = c.get("error")
    e = "(ref.)" if c.get("is_reference") else ("n/a" if err is None else f"{100 * err:.2g} %")
    word = "ok" if c["status"] == "converged" else c["status"]
    if c.get("drift", 0.0) > SETTLE_TOL:
        word += " (unsettled)"
    return f"{word} {e} {c['wall_s']:.3g} s"


def rows_of(results: list) -> list:
    rows = []
    for r in results:
        ref = r["reference"]
        base = {"case": r["case"], "group": r["group"], "param": r["param"], "segments": r["segments"],
                "n_y": r["n_y"], "period_s": r["period_s"], "dt_stable_s": r["dt_stable_s"],
                "static_fairlead_kN": r["static_fairlead_kN"],
                "reference": ref["method"] if ref else ""}
        items = list(r["cells"].items())
        if ref is not None and "cell" not in ref and r["ref_own"]:
            items.append(("reference", ref))
        for key, c in items:
            rows.append({
                **base, "method": key, "label": BY_KEY[key].label if key in BY_KEY else ref["method"],
                "status": (c.get("status") if c["ok"] else ("not run" if c.get("skipped") else "FAILED")),
                "error_rel": c.get("error", "") if key != "reference" else 0.0,
                "wall_s": c.get("wall_s", ""), "solver_build_s": c.get("build_s", ""),
                "dt_s": c.get("dt", ""), "steps": c.get("steps", ""),
                "iterations": c.get("iterations", ""), "unknowns": c.get("unknowns", ""),
                "settled_after_periods": c.get("settled_after", ""), "drift_last_period_rel": c.get("drift", ""),
                "error_after_periods": " ".join(f"{k}:{v:.3g}" for k, v in c.get("error_after", {}).items()),
                "fairlead_max_kN": c["max"] / 1e3 if c["ok"] else "",
                "fairlead_min_kN": c["min"] / 1e3 if c["ok"] else "",
                "first_harmonic_kN": c["a1"] / 1e3 if c["ok"] else "",
                "exception": c.get("exc_type", "") if not c["ok"] else "",
                "message": c.get("message", "") if not c["ok"] else c.get("warning", ""),
            })
    return rows


def slack_why(warning: str) -> str:
    """Which slack criteria a periodic solution's warnings name."""
    why = [w for key, w in (("axial_force", "axial force <= 0"), ("tension reaches", "tension <= 0"),
                            ("reverses", "end force reverses")) if key in warning]
    return ", ".join(why) or "—"


def summary_markdown(res: dict) -> str:
    methods = res["methods"]
    notes: list = []
    head = ["case", "parameter", "RK4 limit (s)", "reference"] + [BY_KEY[k].label for k in methods]
    lines = ["Cells: status, error (max of the max/min/first-harmonic differences of the fairlead "
             "tension over a period, as a % of the reference's range), wall time of the solve. "
             f"RK4 given dt = T/{GIVEN_DT_PER_PERIOD} unless the case says otherwise; time runs: "
             f"{PERIODS} periods from rest (resonance: {RESONANCE_PERIODS}), the last one compared; "
             f"\"unsettled\": its last two periods still differ by more than {100 * SETTLE_TOL:g} % "
             "of the range.", "",
             "| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for r in res["cases"]:
        ref = r["reference"]
        cells = [cell_text(r["cells"].get(k), notes) for k in methods]
        lines.append(f"| {r['case']} | {r['param']} | {r['dt_stable_s']:.3g} | "
                     f"{ref['method'] if ref else 'none'} | " + " | ".join(cells) + " |")
    if notes:
        lines += ["", "Failures:", ""] + [f"- F{i + 1}: {n}" for i, n in enumerate(notes)]
    lines += ["", "Details (dt of the time runs; periods after which every later period stays "
              f"within {100 * SETTLE_TOL:g} % of the range of the last one; periodic iterations):", "",
              "| case | segments | n_y | T (s) | static T_f (kN) | RK4 limit / base | dt used (s): "
              "RK4 default, given, gen.-α | settled after (periods): RK4 default, given, gen.-α | "
              "periodic iterations: IPOPT, Newton, HB |", "|---|---|---|---|---|---|---|---|---|"]
    lim0 = res["cases"][0]["dt_stable_s"]

    def f(r, k, field, fmt):
        c = r["cells"].get(k)
        if not c or not c["ok"] or c.get(field) in (None, ""):
            return "—"
        return fmt.format(c[field])

    for r in res["cases"]:
        tk, pk = ("rk4_default", "rk4_given", "ga"), ("coll_ipopt", "coll_newton", "hb")
        lines.append(
            f"| {r['case']} | {r['segments']} | {r['n_y']} | {r['period_s']:.4g} | "
            f"{r['static_fairlead_kN']:.1f} | {r['dt_stable_s'] / lim0:.3g} | "
            + ", ".join(f(r, k, "dt", "{:.3g}") for k in tk) + " | "
            + ", ".join(f(r, k, "settled_after", "{}") for k in tk) + " | "
            + ", ".join(f(r, k, "iterations", "{}") for k in pk) + " |")
    sl = res.get("slack")
    if sl:
        lines += ["", "Slack search (collocation, Newton; amplitude = factor x [2, 1] m):", "",
                  "| factor | status | why slack | fairlead T min (kN) | fairlead T max (kN) | "
                  "segment tension min (kN) |", "|---|---|---|---|---|---|"]
        for h in sl["history"]:
            lines.append(f"| {h['factor']:g} | {h['status']} | {slack_why(h.get('warning', ''))} | "
                         f"{h.get('fairlead_min_kN', float('nan')):.1f} | "
                         f"{h.get('fairlead_max_kN', float('nan')):.1f} | "
                         f"{h.get('segment_tension_min_kN', float('nan')):.1f} |")
        lines += ["", f"Last taut factor {sl['taut']}, first slack factor {sl['slack']}."]
    for r in res["cases"]:
        if r["info"].get("mode_periods"):
            lines.append(f"\n{r['case']}: natural periods of that line (s) "
                         + ", ".join(f"{p:.3f}" for p in r["info"]["mode_periods"])
                         + f"; excited at mode {r['info']['mode']}. Error of the time runs after "
                         "k periods: " + "; ".join(
                             f"{BY_KEY[k].label}: " + ", ".join(
                                 f"{n}: {100 * e:.2g} %" for n, e in c.get("error_after", {}).items())
                             for k, c in r["cells"].items() if c["ok"] and "error_after" in c) + ".")
    lines += ["", f"Total wall time {res['wall_s']:.0f} s."]
    return "\n".join(lines) + "\n"


def main(argv=None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--quick", action="store_true", help="3 cases x 3 methods at 20 segments")
    ap.add_argument("--out", type=Path, default=HERE / "out", help="output directory")
    ap.add_argument("--timeout", type=float, help="time limit per cell, s")
    args = ap.parse_args(argv)
    timeout = args.timeout or (TIMEOUT_QUICK if args.quick else TIMEOUT_FULL)
    methods = QUICK_METHODS if args.quick else tuple(m.key for m in METHODS)
    args.out.mkdir(parents=True, exist_ok=True)
    t0 = time.perf_counter()

    slack = None if args.quick else slack_search(SEGMENTS)
    done, results, skip, prev_seg = {}, [], {}, None
    for case in cases(args.quick, slack):
        r = run_case(case, methods, timeout, done, skip if case.group == "segments" else {})
        if case.group == "segments":
            update_skips(r, prev_seg, skip, timeout)
            prev_seg = r
        done[case.name] = r
        results.append(r)
        print(f"{case.name}: {r['wall_s']:.1f} s", flush=True)

    res = {"quick": args.quick, "methods": list(methods), "cases": results, "slack": slack,
           "timeout_s": timeout, "wall_s": time.perf_counter() - t0, "out": str(args.out)}
    res["rows"] = rows_of(results)
    with open(args.out / "results.csv", "w", newline="") as fh:
        writer = csv.DictWriter(fh, fieldnames=list(res["rows"][0]))
        writer.writeheader()
        writer.writerows(res["rows"])
    text = summary_markdown(res)
    (args.out / "summary.md").write_text(text)
    print(text)
    return res


if __name__ == "__main__":
    main()
