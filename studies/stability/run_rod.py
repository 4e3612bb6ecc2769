"""Stiff and extreme cases on the rod and the hybrid: does generalized-alpha run, with how many
Newton iterations per step, how accurately, and why does a failure fail?

Question
--------
The rod (``model = "rod"``) and the hybrid rod-catenary line (``model = "hybrid"``) pushed to
the extremes issue 14 names: stiff bending (EI large against the tension), near-zero tension
(a hanging line whose lower end is free), the seed's own time step (1 s) on seed 000's
benchmark relaxing from straight, and a twisted rod at 0.95 of Greenhill's buckling moment.
For each row and time step: converged or not, Newton iterations per step, substepped steps,
the error against a fine reference, the wall time, and the failure's message.

Rows (cases in ``studies/work_precision/rod_cases.py``):

* ``stiff bending``: the taut hose (140-190 N of tension, 18 segments of 0.55 m) with EI
  1000 N m^2 (bending length sqrt(EI / T) = 2.4-2.7 m, five segments; the base hose's 0.08
  m), as a hybrid (cable3d, rod, cable3d) and all rod; end B heaving 5 cm at T = 2 s;
  ``sc.simulate`` (GA1, rho_inf 0) at T/25 and T/100 for 2 periods, reference T/1600;
* ``near-zero tension``: a 5 m line hanging from its moving top, its lower end free (the
  tension falls to 2.1 N in the last segment, zero at the end), all rod and as a hybrid (rod
  on the lowest quarter); the same columns;
* ``seed dt``: seed 000's benchmark (20 segments, pure rod and hybrid with the rod on the
  last quarter) relaxing from straight (the line straight along the guide, 30 deg below the
  horizontal, at rest), through ``integrate`` on the scene's dynamics Mechanism with the
  rod's re-anchoring (what ``sc.simulate`` runs, from a given start), GA1 rho_inf 0, over
  ``SEED_DURATION`` s, at dt = 1 s (the seed's step) down to 0.01 s; reference dt = 1 ms;
  and the same line from its static state with end A moving (5 cm, T = 20 s) through
  ``sc.simulate`` at dt = 1 s and 0.1 s, reference 0.01 s;
* ``Greenhill``: the clamped-clamped twisted rod (20 segments) at 0 and 0.95 of 8.98682 B/L:
  the lowest frequency of ``sc.modal_analysis`` (the linearisation about the twisted
  state) and ``sc.simulate`` with end A moved 1 mm sideways at T = 5 s (quasi-static) for
  one period at dt = T/500: bounded or not, the mid-node's largest sideways deflection.

Every cell runs in this process (the VM functions built once per scene are then reused;
``codegen=False``); a failure is a ConvergenceError, caught and reported.

Run
---
    python -u studies/stability/run_rod.py            # full: ~15 min on 2 shared cores
    python -u studies/stability/run_rod.py --quick    # Greenhill 0.95's modes (10 segments),
                                                      # the hybrid seed at dt = 1 s (the test)
    options: --out DIR (default studies/stability/out/rod/), --groups (of GROUPS: stiff,
             slack, seed, seed-moving, greenhill; default all)

Writes ``results.csv`` and ``summary.md``; ``main(argv)`` returns the numbers as a dict.
"""
from __future__ import annotations

import argparse
import math
import sys
import time
from pathlib import Path

import numpy as np

import symcable as sc
from symcable.errors import ConvergenceError
from symcable.models.rod.reanchor import reanchor_hook
from symcable.scene import load_scene
from symcable.api.scene3d import dynamics_mechanism, scene_equilibrium
from symcable.solvers.integrate import integrate
from symcable.solvers.options import GeneralizedAlphaFirstOrder

HERE = Path(__file__).resolve().parent
for _p in (HERE.parent, HERE.parent / "work_precision"):
    if str(_p) not in sys.path:
        sys.path.append(str(_p))
import rod_cases as rc  # noqa: E402  (studies/work_precision/rod_cases.py)
import study_io  # noqa: E402

SEED_DURATION = 10.0                  # s of relaxation
SEED_DTS_FULL = (1.0, 0.3, 0.1, 0.03, 0.01)
SEED_REF_DT = 1e-3
TIME_STEPS = (25, 100)                # GA1 steps per period of the time rows
REF_STEPS = 1600
GROUPS = ("stiff", "slack", "seed", "seed-moving", "greenhill")
SEED_PERIOD = 20.0                    # s, end A's motion in the moving-seed rows


def seed_moving(hybrid: bool) -> dict:
    """Seed 000's benchmark at rest (its static state), end A moved 5 cm horizontally and
    vertically at T = 20 s: ``sc.simulate`` at the seed's 1 s (T/20) and 0.1 s."""
    d = rc.seed(20, hybrid)
    d["end_a"]["motion"] = {"kind": "harmonic", "amplitude": [0.05, 0.0, 0.05],
                            "period": SEED_PERIOD, "phase_deg": [0.0, 0.0, 90.0]}
    d["name"] += ", end A moving"
    return d


def _fail(exc: Exception, wall: float) -> dict:
    return {"ok": False, "status": "FAILED", "wall_s": wall, "exc_type": type(exc).__name__,
            "message": str(exc).strip().splitlines()[0][:300]}


def _info(tr, wall: float) -> dict:
    s = tr.stats
    its = s.get("newton_iterations")
    return {"ok": True, "status": tr.status, "wall_s": wall, "dt_s": s["dt"], "steps": s["steps"],
            "iter_per_step": None if its is None else its / s["steps"],
            "iter_max": s.get("newton_iterations_max"), "substeps": s.get("substepped_steps"),
            "reanchorings": s.get("reanchorings")}


# --------------------------------------------------------------------------- time rows
def time_row(group: str, d: dict, period: float, periods: int = 2, steps=TIME_STEPS,
             ref_steps: int | None = REF_STEPS, log=print) -> list:
    """``sc.simulate`` at T/n for n in ``steps``, each against GA1 at T/ref_steps: node
    positions over the reference's largest excursion (``error``), end-B tension over its
    range (``error_f``, context)."""
    k = math.gcd(*steps, *((ref_steps,) if ref_steps else ()))  # samples a period: on every run's steps
    ts = np.arange(1, k * periods + 1) * period / k
    runs = {}
    for n in ((ref_steps,) if ref_steps else ()) + tuple(steps):
        t0 = time.perf_counter()
        try:
            tr = sc.simulate(d, periods * period, dt=period / n, save_times=ts, codegen=False)
            c = _info(tr, time.perf_counter() - t0)
            c.update(x=np.asarray(tr.positions, float), f=np.asarray(tr.fairlead_tension, float),
                     min_axial_N=float(np.min(tr.axial_force)))
        except ConvergenceError as exc:
            c = _fail(exc, time.perf_counter() - t0)
        runs[n] = c
    ref = runs.get(ref_steps)
    cells = []
    for n in steps:
        c = runs[n]
        if c["ok"] and ref and ref["ok"]:
            x0 = ref["x"][0]
            sx = float(np.max(np.ptp(np.linalg.norm(ref["x"] - x0, axis=2), axis=0)))
            ex = float(np.max(np.linalg.norm(c["x"] - ref["x"], axis=2))) / sx
            ef = float(np.max(np.abs(c["f"] - ref["f"]))) / float(np.ptp(ref["f"]))
            c["error"], c["error_f"] = ex, ef
        cells.append(_cell(group, d["name"], f"GA1 dt=T/{n}", c, log))
    if ref is not None:
        cells.append(_cell(group, d["name"], f"reference GA1 T/{ref_steps}", ref, log))
    return cells


def _cell(group, case, config, c, log) -> dict:
    out = {"group": group, "case": case, "config": config,
           **{k: v for k, v in c.items() if k not in ("x", "f", "q")}}
    ips = c.get("iter_per_step")
    log(f"  {group:18s} {case:36s} {config:22s} {c['status']:10s} {c['wall_s']:6.1f} s"
        + ("" if ips is None else f"  N/step {ips:.2f}")
        + ("" if c.get("error") is None else f"  error {c['error']:.2e}")
        + ("" if c["ok"] else f"  {c.get('message', '')[:150]}"))
    return out


# --------------------------------------------------------------------------- the seed
def seed_row(hybrid: bool, dts, ref_dt: float | None, duration: float = SEED_DURATION,
             log=print) -> list:
    """Seed 000's relaxation from straight (module docstring) at each dt; error: the node
    positions' largest difference from the reference at the saved times (every second),
    over the line's length (2 m); also how far the last state is from the static one."""
    d = rc.seed(20, hybrid)
    scene = load_scene(d)
    mech0, eq = scene_equilibrium(scene, codegen=False)
    mech = dynamics_mechanism(scene, mech0)
    q0 = rc.straight_start(mech, eq)
    x_static = np.asarray(eq.outputs["positions"], float).reshape(-1, 3)
    ts = np.arange(1.0, duration + 0.5)
    runs = {}
    for dt in ((ref_dt,) if ref_dt else ()) + tuple(dts):
        t0 = time.perf_counter()
        try:
            tr = integrate(mech, duration, dt, method=GeneralizedAlphaFirstOrder(rho_inf=0.0),
                           q0=q0, v0=np.zeros(mech.n_v), p=mech.params.values, save_times=ts,
                           codegen=False, reanchor=reanchor_hook(mech))
            c = _info(tr, time.perf_counter() - t0)
            x = np.stack([np.asarray(o, float).reshape(-1, 3) for o in tr.outputs["positions"]])
            c.update(x=x, from_static_m=float(np.max(np.linalg.norm(x[-1] - x_static, axis=1))),
                     min_frame_margin=tr.stats.get("min_frame_margin"))
        except ConvergenceError as exc:
            c = _fail(exc, time.perf_counter() - t0)
        runs[dt] = c
    ref = runs.get(ref_dt)
    cells = []
    name = d["name"] + " from straight"
    for dt in dts:
        c = runs[dt]
        if c["ok"] and ref and ref["ok"]:
            c["error"] = float(np.max(np.linalg.norm(c["x"] - ref["x"], axis=2))) / 2.0
        cells.append(_cell("seed dt", name, f"GA1 dt={dt:g} s", c, log))
    if ref is not None:
        cells.append(_cell("seed dt", name, f"reference GA1 dt={ref_dt:g} s", ref, log))
    return cells


# --------------------------------------------------------------------------- Greenhill
def greenhill_row(fractions=(0.0, 0.95), segments: int = 20, simulate: bool = True,
                  log=print) -> list:
    """Per fraction of Greenhill's moment: the lowest frequency (``sc.modal_analysis``),
    and a quasi-static sideways motion of end A (1 mm, T = 5 s) by ``sc.simulate`` at
    T/500 over one period: the mid node's largest sideways deflection over the end's."""
    cells = []
    for frac in fractions:
        d = rc.greenhill(segments, frac, kick=1e-3)
        d["end_a"]["motion"]["period"] = 5.0
        t0 = time.perf_counter()
        modal = sc.modal_analysis({k: v for k, v in d.items() if k != "end_a"} | {
            "end_a": {k: v for k, v in d["end_a"].items() if k != "motion"}}, 2)
        f1 = float(modal.frequencies[0])
        c = {"ok": True, "status": "converged", "wall_s": time.perf_counter() - t0,
             "lowest_frequency_hz": f1}
        cells.append(_cell("Greenhill", d["name"], "modal_analysis", c, log))
        if not simulate:
            continue
        t0 = time.perf_counter()
        try:
            tr = sc.simulate(d, 5.0, dt=0.01, codegen=False)
            c = _info(tr, time.perf_counter() - t0)
            mid = tr.positions[:, segments // 2, 1:]
            c["mid_over_end"] = float(np.max(np.linalg.norm(mid, axis=1)) / 1e-3)
            c["bounded"] = bool(np.all(np.isfinite(tr.positions)) and c["mid_over_end"] < 1e3)
        except ConvergenceError as exc:
            c = _fail(exc, time.perf_counter() - t0)
        cells.append(_cell("Greenhill", d["name"], "GA1 dt=T/500, 1 mm sideways", c, log))
    return cells


# --------------------------------------------------------------------------- report
def summary_markdown(res: dict) -> str:
    L = ["# Stability rows: rod and hybrid", "",
         f"Total wall time {res['wall_s']:.0f} s{' (--quick)' if res['quick'] else ''}. Cells in "
         "the VM. Error: node positions over the reference's largest excursion (seed rows from "
         "straight: over the 2 m length); the end-B tension's over its range is context (it "
         "carries the ringing of the highest bending modes, which the reference keeps).", "",
         "| group | case | run | status | wall (s) | Newton/step (max) | substepped | error (%) | "
         "other |", "|---|---|---|---|---|---|---|---|---|"]
    notes = []
    for c in res["cells"]:
        ips = "-" if c.get("iter_per_step") is None else (
            f"{c['iter_per_step']:.2f} ({c.get('iter_max')})")
        err = "-" if c.get("error") is None else f"{100 * c['error']:.3g}"
        other = []
        for k, lab, fmt in (("lowest_frequency_hz", "f1", "{:.4g} Hz"),
                            ("mid_over_end", "mid/end", "{:.3g}"),
                            ("min_axial_N", "min axial", "{:.3g} N"),
                            ("error_f", "end-B tension error", "{:.2%}"),
                            ("from_static_m", "from static at end", "{:.3g} m"),
                            ("reanchorings", "re-anchorings", "{}")):
            if c.get(k) is not None:
                other.append(f"{lab} {fmt.format(c[k])}")
        status = c["status"]
        if not c["ok"]:
            notes.append(f"{c.get('exc_type')}: {c.get('message')}")
            status = f"FAILED [F{len(notes)}]"
        L.append(f"| {c['group']} | {c['case']} | {c['config']} | {status} | {c['wall_s']:.3g} | "
                 f"{ips} | {c.get('substeps', '-')} | {err} | {', '.join(other)} |")
    if notes:
        L += ["", "Failures:", ""] + [f"- F{i + 1}: {n}" for i, n in enumerate(notes)]
    return "\n".join(L) + "\n"


def csv_rows(res: dict) -> list:
    keys = ("group", "case", "config", "status", "wall_s", "dt_s", "steps", "iter_per_step",
            "iter_max", "substeps", "reanchorings", "error", "error_f", "min_axial_N", "from_static_m",
            "lowest_frequency_hz", "mid_over_end", "bounded", "exc_type", "message")
    return [{k: c.get(k) for k in keys} for c in res["cells"]]


def main(argv=None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--quick", action="store_true",
                    help="Greenhill at 0.95 (10 segments) and the hybrid seed at dt = 1 s")
    ap.add_argument("--out", type=Path, default=HERE / "out" / "rod", help="output directory")
    ap.add_argument("--groups", nargs="*", default=list(GROUPS), choices=GROUPS,
                    help="the full run's groups to run (default all)")
    args = ap.parse_args(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    t0 = time.perf_counter()
    cells = []
    if args.quick:
        cells += greenhill_row((0.95,), segments=10, simulate=False)
        cells += seed_row(True, (1.0,), None)
    else:
        g = set(args.groups)
        for hyb in (True, False) if "stiff" in g else ():
            cells += time_row("stiff bending", rc.hose("hybrid" if hyb else "rod", EI=1000.0), 2.0)
        for hyb in (False, True) if "slack" in g else ():
            cells += time_row("near-zero tension", rc.hanging(hybrid=hyb), 2.0)
        for hyb in (False, True) if "seed" in g else ():
            cells += seed_row(hyb, SEED_DTS_FULL, SEED_REF_DT)
        for hyb in (False, True) if "seed-moving" in g else ():
            cells += time_row("seed dt", seed_moving(hyb), SEED_PERIOD, steps=(20, 200),
                              ref_steps=2000)
        if "greenhill" in g:
            cells += greenhill_row()
    res = {"quick": args.quick, "cells": cells, "wall_s": time.perf_counter() - t0,
           "out": str(args.out)}
    study_io.write_tables(args.out, csv_rows(res), summary_markdown(res))
    return res


if __name__ == "__main__":
    main()
