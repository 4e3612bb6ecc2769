"""symcable against MoorDyn run live on a 3D line: an out-of-plane fairlead motion in an
oblique current, fairlead tension over time (issue 12; the scene and both drivers are in
``case.py`` beside this file, the test is ``tests/test_moordyn_live3d.py``).

Question
--------
With the two models made equal (one MoorDyn deck read by both, the current and the ramped
motion added alike), how far apart are their fairlead tensions, and how much of that is
each code's time step and how much the models' own discretisation (MoorDyn's nodal drag
and added mass against symcable's element ones)? The answer sets the test's tolerance.

Runs (3 periods: the ramp, then 2 periods; differences over t >= T, as fractions of the
tension's range there)
--------------------------------------------------------------------------------------
* MoorDyn 2.7.2, RK2 (its default), one ``Step`` per MoorDyn step, dtM from 2e-3 s down:
  its time error against its finest step;
* symcable, first-order generalized-alpha, dt from T/240 down, rho_inf = 0 (the test's) and
  0.5 (``simulate``'s default): its time error against its finest step;
* both at their finest steps: the model difference, at 30 segments and (full run) at 20
  and 45, to see it shrink with the segment length.

Run
---
    python studies/moordyn_live3d/run.py            # full: about 10 minutes (C compiles)
    python studies/moordyn_live3d/run.py --quick    # the test's settings and one reference
    options: --out DIR (default studies/moordyn_live3d/out/), --figure PATH (extra copy)

Writes ``results.csv`` (one row per run), ``summary.md`` and ``live3d.png`` (the tensions
over time, and the differences from MoorDyn's finest run). ``main(argv)`` returns the rows.
"""
from __future__ import annotations

import importlib.util
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

HERE = Path(__file__).resolve().parent
sys.path[1:1] = [str(HERE.parent)]
import study_io  # noqa: E402

_spec = importlib.util.spec_from_file_location("moordyn_live3d_case", HERE / "case.py")
case = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(case)

T = case.PERIOD
TEST = {"dtM": 1e-3, "dt": T / 480, "rho_inf": 0.0}  # what the test runs
FULL = {"dtM": (2e-3, 1e-3, 5e-4, 2.5e-4), "dt": (T / 240, T / 480, T / 960, T / 1920, T / 3840),
        "rho_05": (T / 240, T / 480, T / 960), "segments": (20, 45)}
QUICK = {"dtM": (1e-3, 5e-4), "dt": (T / 480, T / 960), "rho_05": (), "segments": ()}


def _row(code, segments, step, rho_inf, res, diff_own, diff_md) -> dict:
    return {"code": code, "segments": segments, "step_s": step, "rho_inf": rho_inf,
            "static_kN": res["static_tension"] / 1e3, "wall_s": res["wall_time"],
            "own_max_pct": None if diff_own is None else 100 * diff_own["max"],
            "own_rms_pct": None if diff_own is None else 100 * diff_own["rms"],
            "vs_moordyn_max_pct": None if diff_md is None else 100 * diff_md["max"],
            "vs_moordyn_rms_pct": None if diff_md is None else 100 * diff_md["rms"],
            "error_estimate_pct": 100 * res["error_estimate"] if "error_estimate" in res else None}


def _series(res) -> tuple:
    return res["time"], res["tension"]


def main(argv=None) -> dict:
    args = study_io.parse(__doc__, "the test's settings and a one-halving reference",
                          HERE / "out", argv)
    plan = QUICK if args.quick else FULL
    codegen = None if args.quick else True
    md = {h: case.run_moordyn(dtM=h) for h in plan["dtM"]}
    md_ref = md[min(md)]
    runs = {(h, 0.0): case.run_symcable(dt=h, rho_inf=0.0, codegen=codegen) for h in plan["dt"]}
    runs.update({(h, 0.5): case.run_symcable(dt=h, rho_inf=0.5, codegen=codegen)
                 for h in plan["rho_05"]})
    sc_ref = runs[(min(plan["dt"]), 0.0)]
    rows = []
    for h, r in sorted(md.items(), reverse=True):
        own = None if r is md_ref else case.difference(*_series(md_ref), *_series(r))
        rows.append(_row("MoorDyn", case.SEGMENTS, h, None, r, own, None))
    for (h, rho), r in sorted(runs.items(), key=lambda kv: (kv[0][1], -kv[0][0])):
        own = None if r is sc_ref else case.difference(*_series(sc_ref), *_series(r))
        rows.append(_row("symcable", case.SEGMENTS, h, rho, r,
                         own, case.difference(*_series(md_ref), *_series(r))))
    by_n = {}
    for n in plan["segments"]:
        # MoorDyn's stable step scales with the segment length: the finest dtM times 30 / n
        m = case.run_moordyn(segments=n, dtM=min(plan["dtM"]) * case.SEGMENTS / n)
        s = case.run_symcable(segments=n, dt=min(plan["dt"]), rho_inf=0.0, codegen=codegen)
        by_n[n] = (m, s)
        rows.append(_row("MoorDyn", n, m["dtM"], None, m, None, None))
        rows.append(_row("symcable", n, min(plan["dt"]), 0.0, s, None,
                         case.difference(*_series(m), *_series(s))))
    test = runs[(TEST["dt"], 0.0)]
    text = _summary(rows, md_ref, sc_ref, md[TEST["dtM"]], test)
    study_io.write(args, rows, text, lambda p: _plot(p, md_ref, sc_ref, test, md[TEST["dtM"]]),
                   "live3d.png")
    return {"rows": rows, "moordyn": md, "symcable": runs, "by_segments": by_n}


def _fmt(x, spec=".3g") -> str:
    return "" if x is None else format(x, spec)


def _summary(rows, md_ref, sc_ref, md_test, sc_test) -> str:
    lines = ["# symcable against MoorDyn, live, on a 3D line", "",
             f"Static fairlead tension in the current: MoorDyn (settled after "
             f"{md_ref['settled_after']:.0f} s) {md_ref['static_tension'] / 1e3:.4f} kN, its Init "
             f"(no current) {md_ref['ic_tension'] / 1e3:.4f} kN; symcable "
             f"{sc_ref['static_tension'] / 1e3:.4f} kN (difference "
             f"{sc_ref['static_tension'] - md_ref['static_tension']:+.3g} N).", "",
             "Differences over t >= T as % of the range; 'own' against the code's finest step, "
             "'vs MoorDyn' against MoorDyn's finest run at the same segments.", "",
             "| code | segments | step (s) | rho_inf | own max | own rms | vs MoorDyn max | "
             "vs MoorDyn rms | estimate | wall (s) |", "|---" * 10 + "|"]
    for r in rows:
        lines.append(f"| {r['code']} | {r['segments']} | {r['step_s']:.4g} | {_fmt(r['rho_inf'])} | "
                     f"{_fmt(r['own_max_pct'])} | {_fmt(r['own_rms_pct'])} | "
                     f"{_fmt(r['vs_moordyn_max_pct'])} | {_fmt(r['vs_moordyn_rms_pct'])} | "
                     f"{_fmt(r['error_estimate_pct'])} | {r['wall_s']:.3g} |")
    d = case.difference(*_series(md_test), *_series(sc_test))
    lines += ["", f"The test's pair (MoorDyn dtM {TEST['dtM']:g} s, symcable dt {TEST['dt']:g} s, "
              f"rho_inf {TEST['rho_inf']:g}): max {100 * d['max']:.3g} %, rms {100 * d['rms']:.3g} % "
              f"of {d['range'] / 1e3:.4g} kN; wall MoorDyn {md_test['wall_time']:.3g} s "
              f"(run {md_test['run_time']:.3g} s), symcable {sc_test['wall_time']:.3g} s "
              f"(static {sc_test['static_time']:.3g} s).", ""]
    return "\n".join(lines)


def _plot(path, md_ref, sc_ref, sc_test, md_test) -> None:
    fig, (ax, bx) = plt.subplots(2, 1, figsize=(11, 7), sharex=True,
                                 gridspec_kw={"height_ratios": [3, 2]})
    ax.plot(md_ref["time"], md_ref["tension"] / 1e3, "k-", lw=1.6,
            label=f"MoorDyn, dtM = {md_ref['dtM']:g} s")
    ax.plot(sc_ref["time"], sc_ref["tension"] / 1e3, "C1--", lw=1.2,
            label=f"symcable, dt = {sc_ref['time'][1]:.3g} s")
    ax.plot(sc_test["time"], sc_test["tension"] / 1e3, "C0:", lw=1.2,
            label=f"symcable, dt = {sc_test['time'][1]:.3g} s (the test's)")
    ax.set_ylabel("fairlead tension (kN)")
    ax.set_title("Wire rope, fairlead moved in x, y, z, 0.5 m/s current at 30 deg: 30 segments")
    ax.legend(loc="upper left", fontsize=8)
    ax.grid(alpha=0.3)
    for res, style, label in ((sc_ref, "C1-", "symcable finest"), (sc_test, "C0-", "symcable, test's dt"),
                              (md_test, "k-", "MoorDyn, test's dtM")):
        t = res["time"]
        d = res["tension"] - np.interp(t, md_ref["time"], md_ref["tension"])
        bx.plot(t, d / 1e3, style, lw=0.8, label=label)
    bx.axvline(T, color="0.5", lw=0.8)
    bx.set_ylabel("minus MoorDyn finest (kN)")
    bx.set_xlabel("time (s); the motion ramps in over the first period")
    bx.legend(loc="upper left", fontsize=8)
    bx.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


if __name__ == "__main__":
    main()
