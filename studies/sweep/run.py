"""Sweeps on Dask: the speed-up from 1 to 2 local workers, and what limits it.

Question
--------
``symcable sweep`` (:func:`symcable.run_sweep`) runs each case of a sweep as an independent
task on a local Dask cluster (worker processes, one thread each). On this machine's 2 cores,
how much faster are 2 workers than 1 on a sweep whose cases take long enough to matter, and
what takes the rest: the cluster's start-up, the first case (run in the client, where it
compiles the generated C the workers then load from the build cache), each case's own
set-up (its scene's Mechanism and Functions are built per case), the tasks' serialisation,
and the two cores shared with the client, the scheduler and whatever else runs?

Sweep
-----
The OC3 line as a ``cable3d`` line of ``SEGMENTS`` segments on its seabed, its fairlead on
the elliptic orbit of the built-in scene (period 10 s, amplitudes 2 m and 1 m), under a
uniform current of 8 speeds (0.1 to 0.8 m/s) from 5 headings (0 to 90 degrees): 40 cases of
``simulate`` (``DURATION`` s at dt = ``DT`` s, statistics of the fairlead tension after
``DISCARD`` s). The current is a parameter of the compiled functions: every case shares the
first case's library. The sweep file and the scene are written to the out folder
(``CASES.toml``, ``line.toml``).

Method
------
1. Compile: the first case in this process with an empty build cache (a folder of the out
   dir), then again (loaded from memory): the difference is the compile time.
2. The tasks: the pickled size of one task (its scene included) and the time to pickle and
   unpickle it (Dask pickles each task it sends to a worker).
3. Start-up: a local cluster of 1 and of 2 workers started and closed (median of repeats).
4. The sweep ``REPEATS`` times with 0 (in this process, no Dask), 1 and 2 workers, the order
   rotated each repeat, into a fresh results folder each time (nothing skipped): its wall
   time and the median of its cases' own times (on their workers' clocks). Speed-up = the
   median wall time on 1 worker over that on 2.
5. The results of every run against those of the first: the same cases on the same compiled
   library (a case solved again in one process may start its static solve from the cached
   solution: round-off).

Run
---
    python studies/sweep/run.py            # full: about 10 minutes on 2 shared cores
    python studies/sweep/run.py --quick    # 4 short cases in the virtual machine, once
    options: --out DIR (default studies/sweep/out/)

Writes ``results.csv`` (one row per measurement) and ``summary.md`` (the tables) to the out
dir. ``main(argv)`` returns ``{"rows": ..., "summary": ...}``.
"""
from __future__ import annotations

import importlib
import math
import os
import pickle
import shutil
import statistics
import sys
import time
from pathlib import Path
from typing import NamedTuple

HERE = Path(__file__).resolve().parent
sys.path.insert(1, str(HERE.parent))
import study_io  # noqa: E402


class Setup(NamedTuple):
    segments: int
    duration: float
    dt: float
    discard: float
    speeds: tuple
    headings: tuple
    repeats: int
    codegen: bool | None


FULL = Setup(10, 120.0, 0.02, 20.0, tuple(0.1 * k for k in range(1, 9)),
             (0.0, 22.5, 45.0, 67.5, 90.0), 3, None)
#: the test's: 4 short cases in the virtual machine (no compile), once, the cluster's own
#: costs not measured
QUICK = Setup(5, 2.0, 0.1, 0.5, (0.25, 1.0), (0.0, 90.0), 1, False)


def write_sweep(folder: Path, setup: Setup) -> Path:
    """The scene (``line.toml``) and the sweep file (``CASES.toml``) in ``folder``."""
    import tomli_w

    import symcable as sc

    d = sc.load_scene(sc.demo_scene_path("oc3")).to_dict()
    d.update(name="OC3 line, cable3d", model="cable3d")
    for end in ("end_a", "end_b"):
        x, z = d[end]["position"]
        d[end]["position"] = [x, 0.0, z]
    d["end_b"]["motion"] = {"kind": "harmonic", "period": 10.0, "amplitude": [2.0, 0.0, 1.0],
                            "phase_deg": [0.0, 0.0, -90.0]}
    d["environment"]["current"] = [0.0, 0.0, 0.0]
    d["sections"][0]["segments"] = setup.segments
    (folder / "line.toml").write_text(tomli_w.dumps(d))
    currents = [[round(u * math.cos(math.radians(h)), 12), round(u * math.sin(math.radians(h)), 12),
                 0.0] for u in setup.speeds for h in setup.headings]
    sweep = {"name": "OC3 cable3d, current speed and heading", "scene": "line.toml",
             "analysis": "simulate",
             "outputs": ["fairlead_tension_max", "fairlead_tension_min", "fairlead_tension_mean"],
             "simulate": {"duration": setup.duration, "dt": setup.dt, "discard": setup.discard},
             "grid": {"environment.current": currents}}
    if setup.codegen is not None:
        sweep["codegen"] = setup.codegen
    path = folder / "CASES.toml"
    path.write_text(tomli_w.dumps(sweep))
    return path


def _compile(sweep) -> dict:
    """The first case with an empty build cache, then again from memory, s."""
    from symcable.mechanism import codegen
    from symcable.sweep.case import run_case
    from symcable.sweep.run import _task

    codegen.clear_cache()
    cold = run_case(_task(sweep, sweep.cases[0], first=True))
    warm = run_case(_task(sweep, sweep.cases[0], first=True))
    return {"cold": cold["wall_time"], "warm": warm["wall_time"],
            "compiled": cold["builds"].get("compiled", 0)}


def _task_cost(sweep) -> dict:
    """Pickled size of one task (bytes) and the time to pickle and unpickle it (s, median)."""
    import cloudpickle

    from symcable.sweep.run import _task

    task = _task(sweep, sweep.cases[1])
    times = []
    for _ in range(20):
        t = time.perf_counter()
        blob = cloudpickle.dumps(task)
        pickle.loads(blob)
        times.append(time.perf_counter() - t)
    return {"bytes": len(blob), "seconds": statistics.median(times)}


def _import_symcable() -> float:
    """Seconds a worker takes to import symcable (its sweep included), run on each worker."""
    t = time.perf_counter()
    importlib.import_module("symcable")
    return time.perf_counter() - t


def _startup(n: int) -> dict:
    """Seconds to start a local cluster of ``n`` workers with its client (``start``), for its
    fresh workers to import symcable, all at once (``import``: what each worker's first task
    pays), and to close both (``close``)."""
    import logging

    import distributed

    t0 = time.perf_counter()
    cluster = distributed.LocalCluster(n_workers=n, threads_per_worker=1, processes=True,
                                       dashboard_address=":0", silence_logs=logging.ERROR)
    client = distributed.Client(cluster)
    t1 = time.perf_counter()
    client.run(_import_symcable)
    t2 = time.perf_counter()
    client.close()
    cluster.close()
    return {"start": t1 - t0, "import": t2 - t1, "close": time.perf_counter() - t2}


def _median_startup(n: int, repeats: int) -> dict:
    runs = [_startup(n) for _ in range(repeats)]
    return {k: statistics.median(r[k] for r in runs) for k in runs[0]}


def _values(result) -> dict:
    return {c.name: c.values for c in result.cases}


def _difference(values: dict, reference: dict) -> float:
    """Largest relative difference of any output of any case from the reference run's (inf
    when a case has values in one run only)."""
    worst = 0.0
    for name, ref in reference.items():
        got = values.get(name, {})
        if set(got) != set(ref):
            return math.inf
        for k, r in ref.items():
            worst = max(worst, abs(got[k] - r) / max(abs(r), 1e-300))
    return worst


def main(argv=None) -> dict:
    args = study_io.parse(__doc__, "4 short cases in the virtual machine, once",
                          HERE / "out", argv)
    setup = QUICK if args.quick else FULL
    if not args.quick:  # generated C as a user gets it, into a cache of its own
        os.environ.pop("SYMCABLE_CODEGEN", None)
        os.environ["SYMCABLE_CACHE_DIR"] = str(args.out / "build-cache")  # workers inherit it
    import symcable as sc

    path = write_sweep(args.out, setup)
    sweep = sc.read_sweep(path)
    load0 = os.getloadavg()[0]
    comp = _compile(sweep) if setup.codegen is not False else None
    task = _task_cost(sweep)
    # the cluster's own costs (--quick: not measured, the test needs no model)
    startup = {} if args.quick else {n: _median_startup(n, setup.repeats) for n in (1, 2)}
    rows, runs, reference = [], {0: [], 1: [], 2: []}, None
    for rep in range(setup.repeats):
        order = [0, 1, 2][rep % 3:] + [0, 1, 2][:rep % 3]
        for w in order:
            folder = args.out / f"results-w{w}"
            shutil.rmtree(folder, ignore_errors=True)
            t = time.perf_counter()
            res = sc.run_sweep(path, out=folder, workers=w, progress=False)
            wall = time.perf_counter() - t
            case_times = [c.wall_time for c in res.cases if c.ok]
            if reference is None:
                reference = _values(res)
            diff = _difference(_values(res), reference)
            runs[w].append(wall)
            rows.append({"measure": "sweep", "workers": w, "repeat": rep, "seconds": wall,
                         "cases": len(res), "failed": res.stats["failed"],
                         "case_median": statistics.median(case_times),
                         "case_sum": sum(case_times), "first_case": res.cases[0].wall_time,
                         "vm_fallback": res.stats["vm_fallback"], "max_rel_difference": diff})
    med = {w: statistics.median(v) for w, v in runs.items()}
    case_med = {w: statistics.median(r["case_median"] for r in rows if r["workers"] == w)
                for w in (0, 1, 2)}
    rows += [{"measure": f"cluster of {n} workers: {k}", "seconds": v}
             for n, st in startup.items() for k, v in st.items()]
    rows.append({"measure": "task pickle+unpickle", "seconds": task["seconds"],
                 "bytes": task["bytes"]})
    if comp is not None:
        rows.append({"measure": "compile (first case cold - warm)",
                     "seconds": comp["cold"] - comp["warm"], "libraries": comp["compiled"]})
    speedup = med[1] / med[2]
    n = len(sweep.cases)
    lines = [
        f"# Sweeps on Dask: 1 and 2 local workers ({'quick' if args.quick else 'full'})", "",
        f"{n} cases of `simulate` ({setup.segments} segments, {setup.duration:g} s at dt = "
        f"{setup.dt:g} s), {setup.repeats} repeat(s), order rotated; load average "
        f"{load0:.2f} at the start, {os.getloadavg()[0]:.2f} at the end (2 cores).", "",
        "| workers | wall time s (median) | fastest s | per case s (median, own clock) | "
        "all runs s |", "|---|---|---|---|---|"]
    for w in (0, 1, 2):
        label = "0 (in process, no Dask)" if w == 0 else str(w)
        lines.append(f"| {label} | {med[w]:.2f} | {min(runs[w]):.2f} | {case_med[w]:.3f} | "
                     f"{', '.join(f'{x:.2f}' for x in runs[w])} |")
    worst = max(r["max_rel_difference"] for r in rows if "max_rel_difference" in r)
    lines += ["", f"**Speed-up from 1 to 2 workers: {speedup:.2f}** (medians; fastest runs: "
              f"{min(runs[1]) / min(runs[2]):.2f}; ideal 2). Largest relative difference of any "
              f"output of any run from the first run's: {worst:.1e}.",
              "", "| what | s |", "|---|---|",
              *(f"| local cluster of {n} worker{'s' if n > 1 else ''}: start {st['start']:.2f}, "
                f"its workers import symcable {st['import']:.2f}, close {st['close']:.2f} | "
                f"{sum(st.values()):.2f} |" for n, st in startup.items()),
              f"| pickle + unpickle one task ({task['bytes'] / 1e3:.1f} kB, its scene "
              f"included) | {task['seconds'] * 1e3:.2f} ms |"]
    if comp is not None:
        lines.append(f"| compile the first case's generated C ({comp['compiled']} libraries; "
                     f"once, in the client) | {comp['cold'] - comp['warm']:.1f} |")
    # what 2 workers could do at best: the start-up and the first case (in the client) are
    # serial; the other cases split over the workers at the 1-worker case time
    if not startup:
        text = "\n".join(lines) + "\n"
        keys = list(dict.fromkeys(k for r in rows for k in r))
        study_io.write_tables(args.out, [{k: r.get(k, "") for k in keys} for r in rows], text)
        return {"rows": rows, "summary": text, "speedup": speedup}
    first = statistics.median(r["first_case"] for r in rows if r.get("workers") == 2)
    fixed = {w: sum(startup[w].values()) + first for w in (1, 2)}
    model = {w: fixed[w] + (n - 1) * case_med[w] / w for w in (1, 2)}
    lines += ["", "Model of the wall time on w workers: the cluster (start, its workers' import "
              "of symcable, close) + the first case in the client + the other cases x their "
              "median time on w workers / w:", "",
              "| workers | fixed s | cases s | model s | measured s |", "|---|---|---|---|---|",
              *(f"| {w} | {fixed[w]:.2f} | {model[w] - fixed[w]:.2f} | {model[w]:.2f} | "
                f"{med[w]:.2f} |" for w in (1, 2)), "",
              f"A case takes {case_med[2] / case_med[1]:.2f} times as long on each of 2 workers "
              "as on 1: the two cores are shared with the client, the scheduler, the nannies and "
              "the machine's other load. With no fixed cost and cases as fast on 2 workers as "
              f"on 1, the speed-up would be 2; with the fixed cost measured, at most "
              f"{(fixed[1] + (n - 1) * case_med[1]) / (fixed[2] + (n - 1) * case_med[1] / 2):.2f}."]
    text = "\n".join(lines) + "\n"
    keys = list(dict.fromkeys(k for r in rows for k in r))
    study_io.write_tables(args.out, [{k: r.get(k, "") for k in keys} for r in rows], text)
    return {"rows": rows, "summary": text, "speedup": speedup}


if __name__ == "__main__":
    main()
