"""Steps chosen by a tolerance: ``simulate`` at its defaults against the true error, on the
built-in moving scenes.

Question
--------
``simulate(scene, duration)`` chooses its step for a tolerance on the end tensions (0.01 of
their range by default; :mod:`symcable.api.time_tolerance`): the run at the default step
against one at twice it, then halvings until two runs agree. On every built-in scene that
moves, is the answer within its tolerance of a converged run, is its reported bound
(``stats["error_measured"]``) at least its true error, and what does it cost against one run
at the default step (the former default), whose own error is shown beside?

Each scene runs ``PERIODS`` excitation periods (the towed body
its turns and a minute more, as the command line's default) in the CasADi virtual
machine. True error: the largest
difference of any end tension (fairlead and anchor of every line) from the reference, at
the answer's samples, relative to that tension's range in the reference (at least 1e-3 of
the largest end tension); the reference is the same run at an eighth of the answer's step
(``--quick``: a quarter). Times are medians of ``--repeats`` calls after a first (warm
caches), the two calls of one scene side by side.

Run ``python studies/time_error/tolerance.py [--quick] [--repeats 3] [--scenes NAME ...]
[--out DIR]``;
writes ``tolerance.md`` and ``tolerance.json``. ``--quick``: seed001, two periods, one
repeat (the test runs it).
"""
from __future__ import annotations

import argparse
import json
import statistics
import time
import warnings
from pathlib import Path

import symcable as sc
from symcable.api.time_tolerance import tension_difference

HERE = Path(__file__).resolve().parent
#: the built-in scenes that move (seed000_rod and seed000_hybrid have no motion)
SCENES = ("seed001", "oc3", "sphere", "sphere127", "towed_body")
PERIODS = 6
TOW_EXTRA_S = 60.0


def _duration(scene, periods: int) -> float:
    """``periods`` periods of the scene's harmonic motion (an end's or a point's); a tow's
    turns and TOW_EXTRA_S more."""
    held = [scene.end_a, scene.end_b] + list((scene.points or {}).values())
    for end in held:
        m = getattr(end, "motion", None)
        if m is not None and m.kind == "harmonic":
            return periods * float(m.period)
        if m is not None and m.kind == "tow":  # its turns and a minute more (the CLI's)
            return float(m.period) + TOW_EXTRA_S
    raise ValueError(f"{scene.name}: no motion")


def _call(scene, duration, **kw):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        t0 = time.perf_counter()
        tr = sc.simulate(scene, duration, codegen=False, progress=False, **kw)
        return tr, time.perf_counter() - t0


def case(name: str, periods: int, repeats: int, ref_factor: int) -> dict:
    scene = sc.load_scene(sc.demo_scene_path(name))
    duration = _duration(scene, periods)
    out, _ = _call(scene, duration)  # warm
    fixed, _ = _call(scene, duration, dt=out.stats["dt_default"])
    t_tol, t_fixed = [], []
    for _ in range(repeats):
        t_tol.append(_call(scene, duration)[1])
        t_fixed.append(_call(scene, duration, dt=fixed.dt)[1])
    ref, _ = _call(scene, duration, dt=out.dt / ref_factor)
    st = out.stats
    return {"scene": name, "duration_s": duration, "dt_default_s": float(fixed.dt),
            "dt_s": float(out.dt), "runs": len(st["dt_runs"]), "dt_runs": st["dt_runs"],
            "error_measured": st["error_measured"], "true_error": tension_difference(out, ref),
            "default_true_error": tension_difference(fixed, ref),
            "default_own_estimate": fixed.stats.get("error_estimate"),
            "wall_tol_s": statistics.median(t_tol), "wall_default_s": statistics.median(t_fixed),
            "warned": [w for w in out.warnings if "tol = " in w]}


def table(rows) -> str:
    out = ["| scene | duration (s) | default dt (s) | chosen dt (s) | runs | bound | true error "
           "| default step's true error (its own estimate) | wall (s) | one run at the default "
           "(s) | ratio |", "|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        b = r["error_measured"]
        est = r["default_own_estimate"]
        out.append(
            f"| {r['scene']} | {r['duration_s']:g} | {r['dt_default_s']:.4g} | {r['dt_s']:.4g} | "
            f"{r['runs']} | {'not reached' if b is None else f'{100 * b:.2g} %'} | "
            f"{100 * r['true_error']:.2g} % | {100 * r['default_true_error']:.2g} % "
            f"({'-' if est is None else f'{100 * est:.2g} %'}) | {r['wall_tol_s']:.2f} | "
            f"{r['wall_default_s']:.2f} | {r['wall_tol_s'] / r['wall_default_s']:.2f} |")
    return "\n".join(out)


def main(argv=None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--out", type=Path, default=HERE / "out")
    ap.add_argument("--scenes", nargs="+", choices=SCENES, default=None)
    a = ap.parse_args(argv)
    a.out.mkdir(parents=True, exist_ok=True)
    names = ("seed001",) if a.quick else tuple(a.scenes or SCENES)
    rows = []
    for name in names:
        rows.append(case(name, 2 if a.quick else PERIODS, 1 if a.quick else a.repeats,
                         4 if a.quick else 8))
        print(table(rows[-1:]).splitlines()[-1], flush=True)
    text = table(rows)
    (a.out / "tolerance.md").write_text(text + "\n")
    (a.out / "tolerance.json").write_text(json.dumps({"rows": rows, "quick": a.quick}, indent=1))
    print(text)
    return {"rows": rows}


if __name__ == "__main__":
    main()
