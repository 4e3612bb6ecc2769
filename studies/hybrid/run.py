"""Seed 000's benchmark (Goyal & Perkins, Sec. 4): the pure rod, the hybrid rod-catenary line
and a pure cable3d, statics, relaxation from straight, accuracy and speed.

Question
--------
symcable/data/seed000_rod.toml is the seed's 2 m cable (Table 1), pinned at the left, its
right end guided at 30 deg below the horizontal with 0.01 N normal to it; seed000_hybrid.toml
the same line with the rod on its last 0.5 m only. Do the pure rod and the hybrid give the
same tension (within 1 % everywhere) and shear and moment (within 5 % of their peaks in the
rod zone), as the seed's Figs. 6-8; how fast is each (the seed claims the hybrid 1.5-2x
faster) and why; what does bending add at the right end against a pure cable3d; and how
does the hybrid's advantage grow on a longer line whose low-tension zone is a small
fraction?

Method
------
1. Statics (``sc.solve_static``) of each model at several segment counts; differences of the
   profiles (tension, shear, moment along s) from the pure rod at the same count and at the
   finest; wall times (cold, and the median of interleaved warm repeats, the stability
   verdict's dense eigenvalue solve left out).
2. The relaxation from straight of each model (the hybrid's catenary with EI = 0, the
   seed's): a release of 10 steps of 0.01 s and 9 of 0.1 s, then the seed's dt = 1 s to
   rest (generalized-alpha, rho_inf = 0, the rod's frames re-anchored); the relaxed state
   against the same model's static solution; the wall times of rod and hybrid as medians
   of interleaved repeats.
3. A longer line (the same cable and right end, length 2, 4, 8 m at the same ds): the
   low-tension zone (0.5 m) a fraction 25, 12.5, 6.25 %: unknowns, Jacobian nonzeros, the
   static solve and the per-step time of each model.

The hybrid rows need model = "hybrid" (on main since hybrid14; ``bench.scene_or_none``).

Run
---
    python studies/hybrid/run.py          # full: 50-400 segments, relaxation at 80 (5
                                          # repeats), lengths 2, 4, 8 m at ds = 5 cm (~30 min)
    python studies/hybrid/run.py --quick  # 20, 40 segments, rod and hybrid relaxed at 20,
                                          # 2 m at ds = 10 cm, one repeat (~1 min)
    options: --out DIR (default studies/hybrid/out/), --figure PATH

Writes ``results.csv``, ``summary.md``, ``profiles.png`` (Figs. 5-8), ``speed.png`` and
``relaxation.png`` to the
out dir. ``main(argv)`` returns ``{"rows", "statics", "relax", "long", "summary"}``.
"""
from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

import symcable as sc

HERE = Path(__file__).resolve().parent
sys.path.insert(1, str(HERE.parent))
import study_io  # noqa: E402

bench = study_io.load_module(HERE / "bench.py", "hybrid_bench")
plots = study_io.load_module(HERE / "plots.py", "hybrid_plots")

MODELS = ("rod", "hybrid", "cable3d")


def statics(counts, repeats):
    """Per model and segment count: the profile, its differences from the finest rod, and
    the wall times; hybrid entries None while pending."""
    res, jobs = {m: {} for m in MODELS}, {}
    for m in MODELS:
        for n in counts:
            s = bench.scene_or_none(m, n)
            if s is None:
                res[m][n] = None
                continue
            sol, cold = bench.solve(s)
            jobs[(m, n)] = lambda s=s: sc.solve_static(s)
            res[m][n] = {"profile": bench.profiles(sol), "cold": cold,
                         "iterations": sol.stats["iterations"], "n_q": sol.stats["unknowns"],
                         "compiled": sol.stats["compiled"]}
    for (m, n), t in bench.interleaved(jobs, repeats).items():
        res[m][n]["warm"] = t
    ref = res["rod"][counts[-1]]["profile"]
    for m in MODELS:
        for n, r in res[m].items():
            if r is not None:  # against the rod at the same count, and the finest rod
                r["diff"] = bench.compare(r["profile"], res["rod"][n]["profile"])
                r["diff_finest"] = bench.compare(r["profile"], ref)
    return res


def relaxation(n, duration, models=MODELS, repeats=1):
    """Each model's relaxation from straight (the hybrid with the seed's catenary, EI = 0)
    against its own static state; with ``repeats`` > 1 the whole relaxation is rerun,
    the models interleaved, and the wall times are the medians."""
    out, walls = {}, {m: [] for m in models}
    for k in range(repeats):
        for m in models:
            if "failed" in out.get(m, {}):
                continue
            s = bench.scene(m, n)
            try:
                run = bench.relax(s, duration)
            except sc.ConvergenceError as exc:
                out[m] = {"failed": str(exc)}
                continue
            walls[m].append(run["wall"] + run["release_wall"])
            if k == 0:
                out[m] = run
    for m, run in out.items():
        if "failed" in run:
            continue
        run["wall_runs"] = walls[m]
        run["wall_median"] = float(np.median(walls[m]))
        s = bench.scene(m, n)
        with bench.no_stability_check():
            sol = sc.solve_static(s)
        prof_run, prof_sta = bench.profiles(run["last"]), bench.profiles(sol)
        run["profile"], run["static"] = prof_run, prof_sta
        run["diff"] = bench.compare(prof_run, prof_sta)
        run["pos_err"] = float(np.max(np.abs(prof_run["X"] - prof_sta["X"])))
    return out


def long_lines(lengths, ds, repeats):
    """Rod and cable3d and hybrid on lines of several lengths at the same ds: sizes, the
    warm static solve and the 1 s step (medians of interleaved repeats)."""
    rows, jobs = [], {}
    for L in lengths:
        n = int(round(L / ds))
        for m in MODELS:
            s = bench.scene(m, n, length=L)
            row = {"length": L, "zone_fraction": bench.ROD_ZONE / L, "model": m, "segments": n,
                   "status": "ok"}
            bench.solve(s)
            sizes, step = bench.step_runner(s)
            row.update(sizes)
            jobs[(L, m, "static")] = lambda s=s: sc.solve_static(s)
            jobs[(L, m, "step")] = step
            rows.append(row)
    t = bench.interleaved(jobs, repeats)
    for row in rows:
        row["static_warm"] = t[(row["length"], row["model"], "static")]
        row["us_per_step"] = 1e5 * t[(row["length"], row["model"], "step")]  # 10 steps
    return rows


def summary(st, rx, lg, counts) -> tuple[list[dict], str]:
    rows, lines = [], ["# Seed 000 benchmark: rod, hybrid, cable3d", "",
                       "## Statics: differences from the pure rod at the same segments (and "
                       f"from the rod at {counts[-1]}); times: generated C where compiled", "",
                       "| model | segments | unknowns | tension diff / peak | shear diff / peak "
                       "(rod zone) | moment diff / peak (rod zone) | end position diff (m) | "
                       f"tension, moment vs rod {counts[-1]} | Newton it. | cold (s) | warm "
                       "median (s) |", "|---|---|---|---|---|---|---|---|---|---|---|"]
    for m in MODELS:
        for n, r in st[m].items():
            if r is None:
                lines.append(f"| {m} | {n} | {bench.HYBRID_PENDING} ||||||||")
                rows.append({"part": "statics", "model": m, "segments": n,
                             "status": "pending"})
                continue
            d = r["diff"]
            lines.append(f"| {m} | {n} | {r['n_q']} | {d['tension_err']:.2e} | "
                         f"{d['shear_err']:.2e} | {d['moment_err']:.2e} | {d['end_err']:.2e} | "
                         f"{r['diff_finest']['tension_err']:.2e}, "
                         f"{r['diff_finest']['moment_err']:.2e} | "
                         f"{r['iterations']} | {r['cold']:.2f} | {r['warm']:.3f} |")
            rows.append({"part": "statics", "model": m, "segments": n, "status": "ok",
                         "unknowns": r["n_q"], **d,
                         **{f"finest_{k}": v for k, v in r["diff_finest"].items()},
                         "cold_s": r["cold"], "warm_s": r["warm"],
                         "iterations": r["iterations"], "compiled": r["compiled"]})
    lines += ["", "## Relaxation from straight (the release: 10 steps of 0.01 s, 9 of 0.1 s; "
              "then the seed's dt = 1 s; rho_inf = 0; the hybrid's catenary EI = 0)", "",
              "| model | unknowns | release (steps, substepped, wall s) | "
              "1 s steps | substepped (max substeps) | wall (s, median) | us/step | "
              "max |x - x_static| (m) | tension diff | moment diff | final kinetic energy (J) |",
              "|---|---|---|---|---|---|---|---|---|---|---|"]
    for m, r in rx.items():
        if "failed" in r:
            lines.append(f"| {m} | failed: {r['failed'][:160]} ||||||||||")
            rows.append({"part": "relaxation", "model": m, "status": r["failed"]})
            continue
        d = r["diff"]
        snap = f"{r['release_steps']}, {r['release_substepped']}, {r['release_wall']:.1f}"
        lines.append(f"| {m} | {r['n_q']} | {snap} | {r['steps']} | {r['substepped']} "
                     f"({r['max_substeps']}) | {r['wall_median']:.2f} | "
                     f"{r['us_per_step']:.0f} | {r['pos_err']:.2e} | "
                     f"{d['tension_err']:.2e} | {d['moment_err']:.2e} | {r['K'][-1]:.2e} |")
        rows.append({"part": "relaxation", "model": m, "unknowns": r["n_q"],
                     "wall_s": r["wall_median"], "steps": r["steps"],
                     "substepped": r["substepped"], "us_per_step": r["us_per_step"],
                     "pos_err": r["pos_err"], **{f"relax_{k}": v for k, v in d.items()}})
    if "rod" in rx and "hybrid" in rx and "wall_median" in rx["rod"] \
            and "wall_median" in rx["hybrid"]:
        lines += ["", f"Relaxation wall time, rod / hybrid (medians): "
                  f"{rx['rod']['wall_median'] / rx['hybrid']['wall_median']:.2f} (release "
                  f"and 1 s steps, {len(rx['rod']['wall_runs'])} interleaved runs)"]
    lines += ["", "## Longer lines (the same right end; the rod zone 0.5 m)", "",
              "| length (m) | zone fraction | model | segments | unknowns | Jacobian nnz | "
              "static warm (s) | us per 1 s step (VM) |", "|---|---|---|---|---|---|---|---|"]
    for r in lg:
        if r["status"] != "ok":
            lines.append(f"| {r['length']:g} | {r['zone_fraction']:.3f} | {r['model']} | "
                         f"{r['segments']} | {r['status']} ||||")
        else:
            lines.append(f"| {r['length']:g} | {r['zone_fraction']:.3f} | {r['model']} | "
                         f"{r['segments']} | {r['n_q']} | {r['jac_nnz']} | "
                         f"{r['static_warm']:.3f} | {r['us_per_step']:.0f} |")
        rows.append({"part": "long", **r})
    keys = list(dict.fromkeys(k for r in rows for k in r))  # one header for every part
    return [{k: r.get(k, "") for k in keys} for r in rows], "\n".join(lines) + "\n"


def main(argv=None) -> dict:
    args = study_io.parse(__doc__, "20 and 40 segments, rod and hybrid relaxed at 20, 2 m "
                          "at ds = 10 cm", HERE / "out", argv, extra=lambda ap: ap.add_argument(
                              "--parts", default="statics,relax,long",
                              help="comma-separated: statics (always), relax, long"))
    relaxed = MODELS
    if args.quick:  # the tests: every part runs, on the smallest cases (the timings are not
        # the answer: one repeat; the pure cable3d's relaxation, which fails, left out)
        counts, repeats, n_rel, dur, lengths, ds = (20, 40), 1, 20, 60.0, (2.0,), 0.1
        relaxed = ("rod", "hybrid")
    else:
        counts, repeats, n_rel, dur, lengths, ds = (50, 100, 200, 400), 7, 80, 60.0, \
            (2.0, 4.0, 8.0), 0.05
    parts = args.parts.split(",")
    st = statics(counts, repeats)
    rx = relaxation(n_rel, dur, relaxed, 1 if args.quick else 5) if "relax" in parts else {}
    lg = long_lines(lengths, ds, repeats) if "long" in parts else []
    rows, text = summary(st, rx, lg, counts)
    study_io.write(args, rows, text, lambda p: plots.profiles_figure(st, counts, rx, p),
                   "profiles.png")
    plots.speed_figure(st, lg, args.out / "speed.png")
    if rx:
        plots.relaxation_figure(rx, args.out / "relaxation.png")
    return {"rows": rows, "statics": st, "relax": rx, "long": lg, "summary": text}


if __name__ == "__main__":
    main()
