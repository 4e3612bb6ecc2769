"""A 3D taut wire driven nearly slack at the bottom of each cycle: ``simulate`` at its
defaults against a converged reference.

Question
--------
Issue 33 holds out a taut wire whose fairlead motion leaves its plane and slackens it almost
to zero once a cycle (snap loads at the top): is ``simulate`` at its defaults within 5 % of
a converged reference at its worst point and 2 % rms (of the fairlead tension range over the
last period), or does the run's own error estimate say it is not, and by how much?

The case
--------
The steel wire rope of ``studies/moordyn_live3d`` (d = 0.09 m, 40 kg/m, EA = 600 MN, axial
damping zeta 0.8, Cd 1.2, Ca 1), 240 m from an anchor at (0, 0, -60) m to a fairlead at
(220, 60, -5) m in 100 m of water (clear of the seabed), static tension 117 kN. The fairlead
moves (5.5 cos wt, 3 cos(wt + 90 deg), 1 cos(wt - 60 deg)) m, T = 12 s: towards the anchor
and across the line's plane; the tension runs from under 1 kN to about 1.1 MN over a cycle.
Four periods from rest (the motion ramped in over the first), the last compared.

Reference: the same scene at 60 segments and dt = T/1600 (``--quick``: 30 segments, T/800;
the quick reference's own distance from the full one is given in the README). Compared:
``simulate`` at its defaults (30 segments, dt = T/100, generalized-alpha), and at
dt = 0.05 s; the true error is the largest (and rms) difference of the fairlead tension over
the last period, over the reference's range there; the estimate is the run's own
``stats["error_estimate"]`` (the time discretisation only).

Run
---
    python studies/taut_wire/run.py            # about 1 minute on 2 shared cores
    python studies/taut_wire/run.py --quick    # what tests/test_study_taut_wire.py runs
    options: --out DIR (default studies/taut_wire/out/)

Writes ``results.csv``, ``summary.md`` and ``taut_wire.png`` (the tensions over the last
period and the differences) to the out dir; ``main(argv)`` returns the rows.
"""
from __future__ import annotations

import argparse
import csv
import json
import sys
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent / "moordyn_live3d"))
import case  # noqa: E402  (studies/moordyn_live3d/case.py: the wire and its deck)

PERIOD = 12.0  # s
AMPLITUDE = (5.5, 3.0, 1.0)  # m, x y z
PHASE_DEG = (0.0, 90.0, -60.0)
FAIRLEAD = (220.0, 60.0, -5.0)  # m
DEPTH = 100.0  # m: the line hangs clear of the seabed
PERIODS = 4
#: (segments, steps per period) of the reference, full and quick
REFERENCE = {"full": (60, 1600), "quick": (30, 800)}
#: the runs compared: label -> dt (s; None: simulate's default)
RUNS = {"defaults": None, "dt = 0.05 s": 0.05}


def scene(segments: int = case.SEGMENTS) -> dict:
    """The taut wire (module docstring) as a scene dict."""
    d = case.symcable_scene(segments, motion=False, current=False)
    d["environment"]["depth"] = DEPTH
    d["end_b"]["position"] = list(FAIRLEAD)
    d["end_b"]["motion"] = {"kind": "harmonic", "period": PERIOD, "amplitude": list(AMPLITUDE),
                            "phase_deg": list(PHASE_DEG)}
    return d


def _last(tr) -> tuple:
    t = np.asarray(tr.time)
    keep = t >= t[-1] - PERIOD - 1e-9
    return t[keep], np.asarray(tr.fairlead_tension)[keep]


def main(argv=None) -> dict:
    import symcable as sc

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--out", default=str(HERE / "out"))
    args = ap.parse_args(argv)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    segs, steps = REFERENCE["quick" if args.quick else "full"]
    t0 = time.perf_counter()
    ref = sc.simulate(scene(segs), PERIODS * PERIOD, dt=PERIOD / steps, progress=False)
    ref_time = time.perf_counter() - t0
    t_ref, T_ref = _last(ref)
    span = float(T_ref.max() - T_ref.min())
    rows, series = [], {}
    for label, dt in RUNS.items():
        t0 = time.perf_counter()
        run = sc.simulate(scene(), PERIODS * PERIOD, dt=dt, progress=False)
        wall = time.perf_counter() - t0
        t, T = _last(run)
        diff = T - np.interp(t, ref.time, ref.fairlead_tension)
        est = run.stats.get("error_estimate")
        worst = float(np.max(np.abs(diff)) / span)
        rms = float(np.sqrt(np.mean(diff ** 2)) / span)
        warned = any("too coarse" in w for w in run.warnings)
        rows.append({"run": label, "dt": run.dt, "worst": worst, "rms": rms,
                     "estimate": est, "warned": warned, "within": worst <= 0.05 and rms <= 0.02,
                     "said": bool(warned and est is not None and est >= worst),
                     "wall_time": wall})
        series[label] = (t, T, diff)
    res = {"rows": rows, "reference": {"segments": segs, "steps_per_period": steps,
                                       "wall_time": ref_time, "min": float(T_ref.min()),
                                       "max": float(T_ref.max())}}
    _write(out, res)
    _plot(out / "taut_wire.png", t_ref, T_ref, series, span)
    return res


def _write(out: Path, res: dict) -> None:
    with open(out / "results.csv", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(res["rows"][0]))
        w.writeheader()
        w.writerows(res["rows"])
    ref = res["reference"]
    lines = [f"Reference: {ref['segments']} segments, T/{ref['steps_per_period']}; fairlead "
             f"tension {ref['min'] / 1e3:.3g}-{ref['max'] / 1e3:.4g} kN over the last period.", "",
             "| run | dt (s) | worst / range | rms / range | run's estimate | warned |",
             "|---|---|---|---|---|---|"]
    for r in res["rows"]:
        est = "-" if r["estimate"] is None else f"{r['estimate']:.2%}"
        lines.append(f"| {r['run']} | {r['dt']:.4g} | {r['worst']:.2%} | {r['rms']:.2%} | "
                     f"{est} | {'yes' if r['warned'] else 'no'} |")
    (out / "summary.md").write_text("\n".join(lines) + "\n")
    (out / "results.json").write_text(json.dumps(res, indent=1))


def _plot(path: Path, t_ref, T_ref, series: dict, span: float) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (a, b) = plt.subplots(2, 1, figsize=(8, 6), sharex=True, constrained_layout=True)
    a.plot(t_ref, T_ref / 1e3, "k", lw=2, label="reference")
    for label, (t, T, diff) in series.items():
        a.plot(t, T / 1e3, lw=1, label=label)
        b.plot(t, 100 * diff / span, lw=1, label=label)
    a.set_ylabel("fairlead tension (kN)")
    a.set_title("Taut wire driven nearly slack: the last of four periods")
    a.legend()
    b.set_ylabel("difference (% of range)")
    b.set_xlabel("time (s)")
    b.axhline(0, color="0.6", lw=0.5)
    b.legend()
    fig.savefig(path, dpi=120)
    plt.close(fig)


if __name__ == "__main__":
    for r in main()["rows"]:
        print(r)
