"""Seed 003's towed body through a 270 degree turn: tracks, depth, tension, the steady tow
against its ODE, and the time step the turn needs.

Question
--------
symcable/data/towed_body.toml is seed 003's towed-body system (355 m bare cable above 125 m
faired cable, a 9500 kg body, 12 knots, a 270 degree turn; our turn radius 300 m). What does
symcable compute for it (the ship's and the body's tracks, the body's depth and the tow
tension through the turn), how close is its steady tow to the steady-tow ODE integrated
from the body up (symcable.models.common.tow_steady), and what time step does the turn need: why
did tight tow turns need steps far below the default, and is the new default
(cable3d_api.TOW_STRETCH_STEP) enough?

Method
------
1. The steady tow (simulate's start): top tension T0, layback and depth against the ODE of
   the same cable, the body's end condition its submerged weight and its drag at the
   steady pitch symcable finds (the ODE knows no attitude).
2. The run: ``AFTER`` s straight, the turn (radius 300 m, 270 degrees, 229 s), 60 s
   straight, at the default step; the figure of ``symcable simulate --plot`` (tracks in
   plan, depth, tension / T0); the body's depth range and how far inside the ship's circle
   it cuts (its distance from the turn's centre at the turn's end).
3. The step: the same run at the old default (TOW_TURN_STEP alone: 0.05 rad of the turn per
   step, 2.43 s), at TOW_STRETCH_STEP's bound with 0.5 and 0.25 (the new default) and at half
   that: the steps that needed substeps, the Newton iterations, the run's own error estimate,
   and the body's depth at the turn's end against the finest run's.

Run
---
    python studies/towed_body/run.py            # full: 48 segments, generated C, ~10 min
    python studies/towed_body/run.py --quick    # the seed's 12 elements, VM, 10 s straight
    options: --out DIR (default studies/towed_body/out/), --figure PATH

Writes ``results.csv``, ``summary.md`` and ``towed_body.png`` to the out dir. ``main(argv)``
returns ``{"rows", "steady", "turn", "steps", "summary"}``.
"""
from __future__ import annotations

import math
import sys
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(1, str(HERE.parent))
import study_io  # noqa: E402

from symcable import demo_scene_path  # noqa: E402
from symcable.api.cable3d import (TOW_STRETCH_STEP, TOW_TURN_STEP,  # noqa: E402
                                  simulate_3d)
from symcable.errors import ConvergenceError  # noqa: E402
from symcable.models.common.tow_steady import steady_tow, tow_sections  # noqa: E402
from symcable.plotting.tows import plot_tow  # noqa: E402
from symcable.scene import load_scene  # noqa: E402
from symcable.scene.bodies import rotation_rpy  # noqa: E402

RHO, G = 1025.0, 9.80665
AFTER, AFTER_QUICK = 120.0, 10.0  # s of straight tow before the turn
TAIL = 60.0  # s after the turn


def scene(quick: bool):
    """The data scene; quick: the seed's own 9 + 3 elements and a 10 s straight start."""
    s = load_scene(demo_scene_path("towed_body"))
    if not quick:
        return s
    d = s.to_dict()
    d["lines"][0]["sections"][0]["segments"] = 9
    d["lines"][0]["sections"][1]["segments"] = 3
    d["points"]["ship"]["motion"]["turns"][0]["after"] = AFTER_QUICK
    return load_scene(d)


def steady_vs_ode(s, codegen) -> dict:
    """The steady tow (simulate's start) against the steady-tow ODE (Method 1)."""
    m, b = s.points["ship"].motion, s.bodies["fish"]
    tr = simulate_3d(s, 0.5, 0.25, codegen=codegen, progress=False)
    fish, ship = tr.bodies["fish"], tr.points["ship"]
    R = rotation_rpy(fish["roll_pitch_yaw"][0])
    u = R.T @ np.array([-m.speed, 0.0, 0.0])
    drag = R @ (0.5 * RHO * np.array(b.cd_area) * np.linalg.norm(u) * u)
    Wb = (b.mass - RHO * b.volume) * G
    ref = steady_tow(tow_sections(s.lines[0]), m.speed, Wb - drag[2], -drag[0], RHO)
    top, end = ship["position"][0], tr.lines["tow"].positions[0][-1]
    T0 = float(np.linalg.norm(ship["force"][0]))
    got = {"tension": T0, "layback": float(top[0] - end[0]), "depth": float(top[2] - end[2])}
    want = {"tension": ref.tension, "layback": ref.layback, "depth": ref.depth}
    return {"symcable": got, "ode": want, "rel": {k: got[k] / want[k] - 1 for k in got},
            "pitch_deg": float(fish["roll_pitch_yaw"][0][1]), "top_angle_deg": ref.angle,
            "body_drag": drag.tolist(), "body_weight": Wb}


def run(s, dt, duration, codegen):
    """One time run; (trajectory or the partial one, its stats, error message or None)."""
    t = time.perf_counter()
    try:
        tr, err = simulate_3d(s, duration, dt, codegen=codegen, progress=False), None
    except ConvergenceError as exc:
        tr, err = exc.partial, str(exc).split("\n")[0]
    return tr, time.perf_counter() - t, err


def turn_numbers(tr, s) -> dict:
    """The body's depth range, the ship's turn centre and the body's distance from it at
    the turn's end and at the run's end, m."""
    m = s.points["ship"].motion
    after, radius, angle = m.turns[0]
    t_end = m.start + after + radius * math.radians(angle) / m.speed
    centre = np.array([after * m.speed, radius])  # heading 0, to port
    p = tr.bodies["fish"]["position"]
    at = [float(np.interp(t_end, tr.time, p[:, i])) for i in range(3)]  # between samples
    depth = -p[:, 2]
    return {"depth_start": float(depth[0]), "depth_min": float(depth.min()),
            "depth_max": float(depth.max()), "depth_turn_end": -at[2], "t_turn_end": t_end,
            "body_radius_turn_end": float(np.linalg.norm(np.array(at[:2]) - centre)),
            "ship_radius": radius,
            "tension_ratio_max": float(np.max(np.linalg.norm(tr.points["ship"]["force"], axis=1))
                                       / np.linalg.norm(tr.points["ship"]["force"][0])),
            "tension_ratio_min": float(np.min(np.linalg.norm(tr.points["ship"]["force"], axis=1))
                                       / np.linalg.norm(tr.points["ship"]["force"][0]))}


def main(argv=None) -> dict:
    args = study_io.parse(__doc__, "the seed's 12 elements in the VM, 10 s straight",
                          HERE / "out", argv)
    quick = args.quick
    codegen = not quick
    s = scene(quick)
    m = s.points["ship"].motion
    after, radius, angle = m.turns[0]
    duration = after + radius * math.radians(angle) / m.speed + TAIL
    steady = steady_vs_ode(s, codegen)

    tr, wall, err = run(s, None, duration, codegen)
    if err is not None:
        raise RuntimeError(f"the default run failed: {err}")
    turn = turn_numbers(tr, s)
    turn.update(dt=tr.dt, wall=wall, substepped=tr.stats.get("substepped_steps"),
                error_estimate=tr.stats.get("error_estimate"))
    figure = lambda path: plot_tow(tr, s, path, title=(  # noqa: E731
        f"seed 003 towed body, 12 kn, 270 deg turn of radius {radius:g} m "
        f"({s.lines[0].n_segments} segments, dt = {tr.dt:.3g} s)"))

    # the step (Method 3)
    omega = m.speed / radius
    T_top = steady["symcable"]["tension"]
    EA = max(x.line_type.EA for x in s.lines[0].sections)
    bound = math.sqrt(T_top / EA) / omega
    steps = [("old default (TOW_TURN_STEP)", TOW_TURN_STEP / omega),
             ("0.5 sqrt(T/EA)/Omega", 0.5 * bound),
             (f"{TOW_STRETCH_STEP:g} sqrt(T/EA)/Omega (default)", TOW_STRETCH_STEP * bound),
             ("half the default", 0.5 * TOW_STRETCH_STEP * bound)]
    runs = []
    for label, dt in steps:
        r, w, e = run(s, dt, duration, codegen)
        st = r.stats if r is not None else {}
        runs.append({"label": label, "dt": dt, "wall": w, "failed": e,
                     "steps": st.get("steps"), "substepped": st.get("substepped_steps"),
                     "newton_max": st.get("newton_iterations_max"),
                     "newton_mean": (st["newton_iterations"] / st["steps"]
                                     if st.get("steps") else None),
                     "error_estimate": st.get("error_estimate"),
                     "depth_turn_end": (turn_numbers(r, s)["depth_turn_end"]
                                        if e is None else None),
                     "series": ((r.time, np.linalg.norm(r.points["ship"]["force"], axis=1))
                                if e is None else None)})
    finest = runs[-1]["depth_turn_end"]
    t_f, T_f = runs[-1]["series"]
    for r in runs:
        r["depth_diff"] = (r["depth_turn_end"] - finest if r["depth_turn_end"] is not None
                           and finest is not None else None)
        # the towpoint tension's largest difference from the finest run's, over its range
        # (this run's series interpolated onto the finest run's samples)
        r["tension_diff"] = (float(np.max(np.abs(np.interp(t_f, *r["series"]) - T_f))
                                   / np.ptp(T_f)) if r["series"] is not None else None)
        r.pop("series")

    rows = [{"what": f"steady {k}", "symcable": steady["symcable"][k],
             "reference": steady["ode"][k], "rel_diff": steady["rel"][k]}
            for k in ("tension", "layback", "depth")]
    rows += [{"what": f"turn {k}", "symcable": v, "reference": "", "rel_diff": ""}
             for k, v in turn.items()]
    rows += [{"what": f"step {r['label']}", "symcable": r["dt"], "reference": r["substepped"],
              "rel_diff": r["error_estimate"]} for r in runs]
    fmt = lambda v, f: "-" if v is None else format(v, f)  # noqa: E731
    lines = [f"# Seed 003's towed body ({'quick' if quick else 'full'}: "
             f"{s.lines[0].n_segments} segments, {'VM' if quick else 'generated C'})", "",
             "## Steady tow against the steady-tow ODE", "",
             "| | symcable | ODE | relative difference |", "|---|---|---|---|"]
    for k, unit, sc in (("tension", "kN", 1e-3), ("layback", "m", 1.0), ("depth", "m", 1.0)):
        lines.append(f"| {k} ({unit}) | {steady['symcable'][k] * sc:.5g} | "
                     f"{steady['ode'][k] * sc:.5g} | {steady['rel'][k]:+.1e} |")
    lines += ["", f"The body pitches {steady['pitch_deg']:.2f} deg; its drag there "
              f"({steady['body_drag'][0] / 1e3:.3g} kN along x, {steady['body_drag'][2] / 1e3:.3g}"
              f" kN up) and its submerged weight ({steady['body_weight'] / 1e3:.4g} kN) are the "
              f"ODE's end condition; the cable meets the ship at {steady['top_angle_deg']:.2f} "
              "deg below the horizontal.", "",
              "## The turn (default step)", "",
              f"dt = {turn['dt']:.3g} s, {turn['substepped']} substepped steps, error estimate "
              f"{fmt(turn['error_estimate'] and 100 * turn['error_estimate'], '.2g')} % of the "
              f"range, {turn['wall']:.1f} s wall. Body depth {turn['depth_start']:.1f} m at the "
              f"start, {turn['depth_min']:.1f}-{turn['depth_max']:.1f} m over the run, "
              f"{turn['depth_turn_end']:.1f} m at the turn's end (t = {turn['t_turn_end']:.0f} s); "
              f"there the body is {turn['body_radius_turn_end']:.1f} m from the turn's centre "
              f"(the ship's radius {turn['ship_radius']:g} m). Towpoint tension / T0: "
              f"{turn['tension_ratio_min']:.3f}-{turn['tension_ratio_max']:.3f}.", "",
              "## The time step in the turn", "",
              f"sqrt(T0/EA)/Omega = {bound:.3g} s (T0 = {T_top / 1e3:.4g} kN, EA = {EA:.4g} N, "
              f"Omega = {omega:.4g} rad/s).", "",
              "| step | dt (s) | steps | substepped | Newton max | Newton mean | error estimate "
              "(% of range) | tension - finest (% of range) | depth at turn end - finest (m) "
              "| wall (s) |", "|---|---|---|---|---|---|---|---|---|---|"]
    for r in runs:
        lines.append(f"| {r['label']} | {r['dt']:.3g} | {fmt(r['steps'], 'd')} | "
                     f"{fmt(r['substepped'], 'd')} | {fmt(r['newton_max'], 'd')} | "
                     f"{fmt(r['newton_mean'], '.2f')} | "
                     f"{fmt(r['error_estimate'] and 100 * r['error_estimate'], '.2g')} | "
                     f"{fmt(r['tension_diff'] and 100 * r['tension_diff'], '.2g')} | "
                     f"{fmt(r['depth_diff'], '+.2e')} | {r['wall']:.1f} |"
                     + (f" failed: {r['failed']}" if r["failed"] else ""))
    text = "\n".join(lines) + "\n"
    study_io.write(args, rows, text, figure, "towed_body.png")
    return {"rows": rows, "steady": steady, "turn": turn, "steps": runs, "summary": text}


if __name__ == "__main__":
    main()
