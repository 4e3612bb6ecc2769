"""Slack and snap of seed 003's payload sphere: time runs, periodic solutions, their stability.

The built-in scenes ``sphere`` (0.807 Hz) and ``sphere127`` (1.27 Hz): an 18.9 m steel cable
with a 12.2 kg sphere, the top moved vertically by 0.085 m. Parts (``--parts``, default all):

- ``convergence``: the top tension at 1.27 Hz against the number of segments (5, 10, 20, 40),
  from time runs (the last of 20 periods, dt = T/200);
- ``cases``: at each frequency a time run (40 periods, dt = T/200) and the periodic solution
  by collocation, harmonic balance and shooting (200 steps), each with its Floquet
  multipliers; T/T0 over one period, the slack fraction, the snap peak, and each periodic
  solution against the time run's last period (max difference / tension range);
- ``sweep``: shooting by continuation in frequency, up and then down, with stability;
- ``solvers``: Anderson shooting (with and without its stall rule), Newton shooting on the
  exact monodromy (after Anderson's first periods) and collocation on the sphere at 1.27 Hz and on a lightly damped planar line at
  resonance (tests/test_shooting.py's): periods, iterations, wall time, median of 3.

Each part writes ``out/<part>.json``; ``--plot`` (after any part) draws the figures from the
JSON files there. ``--quick``: 5 segments, 0.807 and 1.27 Hz, shooting only, a 3-point sweep
(tests/test_studies.py).
"""
from __future__ import annotations

import json
import statistics
import sys
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(1, str(HERE.parent))
import study_io  # noqa: E402

import symcable as sc  # noqa: E402
from symcable.scene import load_scene  # noqa: E402

#: slack: the top tension below this fraction of T0 (the slack law leaves a small tension in
#: a segment just slack, and the material damping of a rattling slack cable adds a little)
SLACK = 0.02
T0_NAME = "cable"


def scene(freq: float, segments: int = 20, **over):
    """The payload-sphere scene at ``freq`` Hz with ``segments`` segments."""
    d = load_scene(str(sc.demo_scene_path("sphere"))).to_dict()
    d["lines"][0]["sections"][0]["segments"] = segments
    d["points"]["top"]["motion"]["period"] = 1.0 / freq
    for k, v in over.items():
        d["points"]["top"]["motion"][k] = v
    return load_scene(d)


def t0_of(s) -> float:
    """Static top tension, N."""
    return float(sc.solve_static(s).lines[T0_NAME].fairlead_tension)


def metrics(t, T, T0, period) -> dict:
    """T/T0 min, max, mean, slack fraction and the series on 200 uniform samples of a period."""
    tau = np.arange(200) / 200
    f = np.interp(tau * period, np.r_[t, period], np.r_[T, T[0]]) / T0
    return {"min": float(f.min()), "max": float(f.max()), "mean": float(f.mean()),
            "slack": float(np.mean(f <= SLACK)), "series": f.tolist()}


def last_period(tr, period):
    """(t mod period from the start of the last full period, top tension) of a time run."""
    t = tr.time
    start = t[-1] - period
    sel = t >= start - 1e-9
    T = tr.lines[T0_NAME].fairlead_tension[sel]
    return t[sel] - start, T


def aligned_diff(a, b) -> float:
    """max |a - b| of two series over the same period, b shifted by the best whole sample
    (the time run's last period starts where it starts; both are at the same phase of the
    motion when the run lasts whole periods, so the shift found is 0 or 1 sample)."""
    a, b = np.asarray(a), np.asarray(b)
    return float(min(np.max(np.abs(a - np.roll(b, k))) for k in (-1, 0, 1)))


def lateral_share(vec, n_q):
    """Share of each Floquet eigenvector's (scaled) coordinates in x and y (the line hangs
    along z, the motion is along z: a vertical perturbation has share 0, a lateral one 1)."""
    lat = np.arange(n_q) % 3 != 2
    return np.linalg.norm(vec[lat], axis=0) ** 2


def periodic(s, method, T0, **opts):
    """One periodic solve with stability: its metrics, stats and the mode that goes unstable."""
    from symcable.api.cable3d_periodic import solve_periodic_3d_state
    from symcable.api.cable3d_static import static_equilibrium
    from symcable.solvers.floquet import floquet
    t = time.perf_counter()
    per, mp = solve_periodic_3d_state(s, method, None, False, None, dict(opts))
    wall = time.perf_counter() - t
    mech, _ = static_equilibrium(s)
    fl = floquet(mech, mp, steps=opts.get("steps", 200))
    share = lateral_share(fl.vectors, mech.n_q)
    mods = np.abs(fl.multipliers)
    vert = mods[share < 0.5]
    lat = mods[share >= 0.5]
    m = metrics(per.time, per.lines[T0_NAME].fairlead_tension, T0, per.stats["period"])
    m.update(method=method, wall=wall, floquet_max=fl.max_modulus, stable=fl.stable,
             floquet_max_vertical=float(vert.max()) if vert.size else 0.0,
             floquet_max_lateral=float(lat.max()) if lat.size else 0.0,
             floquet_time=fl.wall_time, iterations=per.stats.get("iterations"),
             periods=per.stats.get("periods"), error_estimate=per.stats.get("error_estimate"),
             warnings=list(per.warnings))
    return m


def part_convergence(quick, args=None):
    rows = []
    for n in ((5, 10) if quick else (5, 10, 20, 40)):  # quick: 10 periods
        s = scene(1.27, n)
        T0 = t0_of(s)
        P = 1 / 1.27
        t = time.perf_counter()
        tr = sc.simulate(s, (10 if quick else 20) * P, P / 200)
        tt, T = last_period(tr, P)
        m = metrics(tt, T, T0, P)
        m.update(segments=n, T0=T0, wall=time.perf_counter() - t)
        rows.append(m)
        print(f"segments {n:3d}: T0 {T0:.3f} N, T/T0 {m['min']:.4f} .. {m['max']:.4f}, "
              f"slack {m['slack']:.3f}", flush=True)
    return rows


def part_cases(quick, args=None):
    out = []
    for f in (0.807, 1.27):
        s = scene(f, 5 if quick else 20)
        T0, P = t0_of(s), 1 / f
        t = time.perf_counter()
        tr = sc.simulate(s, (15 if quick else 40) * P, P / 200)
        tt, T = last_period(tr, P)
        run = metrics(tt, T, T0, P)
        run.update(method="time run", wall=time.perf_counter() - t,
                   warnings=list(tr.warnings))
        case = {"freq": f, "T0": T0, "period": P, "time_run": run, "periodic": []}
        for method in (("shooting",) if quick else ("shooting", "collocation",
                                                    "harmonic-balance")):
            opts = {"steps": 200} if method == "shooting" else {}
            try:
                m = periodic(s, method, T0, **opts)
            except sc.ConvergenceError as exc:
                m = {"method": method, "failed": str(exc).splitlines()[0]}
                print(f"{f} Hz {method}: failed: {m['failed'][:300]}", flush=True)
                case["periodic"].append(m)
                continue
            rng = run["max"] - run["min"]
            m["diff_range"] = aligned_diff(m["series"], run["series"]) / rng
            case["periodic"].append(m)
            print(f"{f} Hz {method:16s}: T/T0 {m['min']:.4f} .. {m['max']:.4f}, slack "
                  f"{m['slack']:.3f}, vs time run {100 * m['diff_range']:.2f} % of range, "
                  f"|mu| {m['floquet_max']:.4f} (vertical {m['floquet_max_vertical']:.4f}, "
                  f"lateral {m['floquet_max_lateral']:.4f}), {m['wall']:.1f} s", flush=True)
        print(f"{f} Hz time run        : T/T0 {run['min']:.4f} .. {run['max']:.4f}, slack "
              f"{run['slack']:.3f}, {run['wall']:.1f} s", flush=True)
        out.append(case)
    return out


def part_sweep(quick, args=None):
    freqs = np.array([0.8, 1.1, 1.3]) if quick else np.round(np.arange(0.6, 1.61, 0.1), 3)
    n = 5 if quick else 10  # the top tension is converged at 5 (convergence.json)
    s = scene(1.0, n)
    T0 = t0_of(s)
    res = {"T0": T0, "segments": n}
    for direction, fs in (("up", freqs), ("down", freqs[::-1])):
        t = time.perf_counter()
        sw = sc.sweep_periodic(s, 1.0 / fs, "shooting", continuation=True, stability=True,
                               steps=100)
        series = np.asarray(sw.fairlead_tension) / T0
        res[direction] = {
            "freq": fs.tolist(), "max": (np.asarray(sw.fairlead_tension_max) / T0).tolist(),
            "min": (np.asarray(sw.fairlead_tension_min) / T0).tolist(),
            "slack": [float(np.mean(r <= SLACK)) if np.all(np.isfinite(r)) else None
                      for r in series],
            "floquet_max": sw.stats["floquet_max"], "stable": sw.stats["stable"],
            "start": sw.stats["start"], "statuses": list(sw.statuses),
            "wall": time.perf_counter() - t, "warnings": list(sw.warnings)}
        print(f"sweep {direction}: {res[direction]['wall']:.0f} s; " + ", ".join(
            f"{f:g} Hz {mx:.2f}{'' if st else ' U' if st is not None else ' failed'}"
            for f, mx, st in
            zip(fs, res[direction]["max"], sw.stats["stable"])), flush=True)
    return res


def _lightly_damped_line():
    """tests/test_shooting.py's resonance case: the seed-001 line (planar, 20 segments), drag
    x 0.01, no current, fairlead amplitude x 0.05, excited at its first natural period."""
    d = load_scene(str(sc.demo_scene_path("seed001"))).to_dict()
    d["sections"][0]["segments"] = 20
    d["environment"]["current"] = [0.0, 0.0]
    lt = d["line_types"]["chain"]
    lt["cd_normal"], lt["cd_tangential"] = 0.016, 0.016
    d["end_b"]["motion"]["amplitude"] = [0.1, 0.05]
    d["end_b"]["motion"]["period"] = float(sc.modal_analysis(load_scene(d), 2).periods[0])
    return load_scene(d)


def part_solvers(quick, args=None):
    from symcable.solvers import shooting_mech
    which = (args.solver_cases if args is not None else "sphere,line").split(",")
    cases = [("sphere, 1.27 Hz", scene(1.27, 5 if quick else 20))] if "sphere" in which else []
    if not quick and "line" in which:
        cases.append(("lightly damped line at resonance", _lightly_damped_line()))
    variants = ["anderson", "anderson-nostall", "newton"] + (
        ["collocation"] if args is None or not args.no_collocation else [])
    if quick:
        variants = ["anderson", "newton"]
    if args is not None and args.variants:
        variants = args.variants.split(",")
    default, stall = shooting_mech.ANDERSON_PERIODS, shooting_mech.ANDERSON_STALL_PERIODS
    rows = []
    for label, s in cases:
        for variant in variants:
            walls, st = [], {}
            for _ in range(1 if quick else 3):
                # newton: Anderson's budget 1 period (5 on a state of 240: anderson_budget);
                # anderson-nostall: without the stall rule (Anderson's whole budget)
                shooting_mech.ANDERSON_PERIODS = 1 if variant == "newton" else default
                shooting_mech.ANDERSON_STALL_PERIODS = (10 ** 9 if variant == "anderson-nostall"
                                                        else stall)
                t = time.perf_counter()
                try:
                    per = sc.solve_periodic(s, "collocation" if variant == "collocation"
                                            else "shooting")
                    st = per.stats
                except sc.ConvergenceError as exc:
                    st = {"failed": str(exc).splitlines()[0]}
                finally:
                    shooting_mech.ANDERSON_PERIODS = default
                    shooting_mech.ANDERSON_STALL_PERIODS = stall
                walls.append(time.perf_counter() - t)
            row = {"case": label, "variant": variant, "wall_median": statistics.median(walls),
                   "walls": walls, "periods": st.get("periods"),
                   "anderson_periods": st.get("anderson_periods"),
                   "newton_iterations": st.get("newton_iterations"),
                   "iterations": st.get("iterations"), "failed": st.get("failed"),
                   "start": st.get("start"), "unknowns": st.get("unknowns")}
            rows.append(row)
            print(f"{label:34s} {variant:12s} periods {row['periods']} (Anderson "
                  f"{row['anderson_periods']}, Newton {row['newton_iterations']}), iterations "
                  f"{row['iterations']}, {row['wall_median']:.1f} s (median of "
                  f"{len(walls)}){' FAILED ' + row['failed'][:200] if row['failed'] else ''}",
                  flush=True)
    return rows


PARTS = {"convergence": part_convergence, "cases": part_cases, "sweep": part_sweep,
         "solvers": part_solvers}


def main(argv=None):
    def extra(ap):
        ap.add_argument("--parts", default=",".join(PARTS), help="comma-separated: "
                        + ", ".join(PARTS) + " (default all)")
        ap.add_argument("--plot", action="store_true", help="draw the figures from out/*.json")
        ap.add_argument("--solver-cases", default="sphere,line", help="solvers part: sphere, line")
        ap.add_argument("--variants", help="solvers part: a comma-separated subset of anderson, "
                        "anderson-nostall, newton, collocation")
        ap.add_argument("--no-collocation", action="store_true", help="solvers part: shooting "
                        "only (collocation's time is in cases.json)")
    args = study_io.parse(__doc__, "5 segments, shooting only, a 3-point sweep",
                          HERE / "out", argv, extra)
    parts = [p for p in args.parts.split(",") if p]
    for p in parts:
        if p not in PARTS:
            raise SystemExit(f"--parts: {p!r} is not one of {', '.join(PARTS)}")
    results = {}
    for p in parts:
        results[p] = PARTS[p](args.quick, args)
        name = p if p != "solvers" or (args.solver_cases == "sphere,line"
                                       and not args.variants) else \
            f"solvers_{args.solver_cases.replace(',', '_')}" + (
                f"_{args.variants.replace(',', '_')}" if args.variants else "")
        (args.out / f"{name}.json").write_text(json.dumps(results[p], indent=1))
    if args.plot or args.quick:
        study_io.load_module(HERE / "plots.py", "sphere_plots").draw(args.out)
    return results


if __name__ == "__main__":
    main()
