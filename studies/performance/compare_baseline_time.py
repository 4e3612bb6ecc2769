"""Side by side: ``simulate`` (generalized-alpha, seed 001) on this checkout against the code
before issue 10 (a worktree of commit a958ce7), timed in one run.

Question: is the time step on the generic integrator (the first-order generalized-alpha on
the dynamics Mechanism) as fast as the old planar stepper, in generated C and in the
virtual machine, with as many Newton iterations per step?

Two long-lived worker processes, one per code base (``PYTHONPATH`` set to each checkout),
each with its models built and its code compiled once; the parent asks them in turn for
the same run, ``repeats`` interleaved rounds, and reports medians and the ratio new/old of

* the wall time of ``sc.simulate`` with the model given (what studies/performance/run.py's
  time run measures: 30 periods of seed 001 at T/100),
* µs per step in the step calls (``stats["us_per_step"]``),
* Newton iterations per step,

on seed 001 (50 segments) in C and in the VM, and at 200 segments (798 states) in C, in the
VM, and with the default ``codegen=None``: the code before issue 10 compiled every step by
default (its written-out LU at 200 segments takes minutes to compile), the present default
compiles only up to 400 states and runs larger steps in the VM on sparse QR (the scaling
work of issue 10, studies/performance/README.md). The fairlead tensions of the two code
bases are compared too (max difference over the range). Compiled libraries are kept in
``--cache`` (default: a folder in the system's temporary directory) across runs.

Run ``python studies/performance/compare_baseline_time.py [--quick] [--baseline DIR]``;
the machine is shared and noisy, so only medians of interleaved rounds mean anything (the
two workers are pinned to one core, ``--cpu``; the ratio of the fastest rounds is given too).
"""
from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

HERE = Path(__file__).resolve().parent
NEW = HERE.parents[1]
BASELINE = Path("/work/baseline")
T = 10.0


def worker() -> None:
    """Answer JSON requests on stdin: {"segments", "periods", "codegen"} -> timings."""
    import time

    import numpy as np

    import symcable as sc

    models = {}
    cpu = os.environ.get("COMPARE_CPU")
    if cpu:  # both workers on one core: the same cache and the same neighbours
        os.sched_setaffinity(0, {int(cpu)})
    for line in sys.stdin:
        req = json.loads(line)
        n, periods, cg = req["segments"], req["periods"], req["codegen"]
        if n not in models:
            d = sc.load_scene(sc.demo_scene_path("seed001")).to_dict()
            d["sections"][0]["segments"] = n
            scene = sc.load_scene(d)
            models[n] = (scene, sc.build_dynamic_model(scene))
        scene, model = models[n]
        t0 = time.perf_counter()
        tr = sc.simulate(scene, periods * T, dt=T / 100, model=model, codegen=cg)
        wall = time.perf_counter() - t0
        st = tr.stats
        out = {"wall": wall, "us_per_step": st["us_per_step"], "compiled": bool(st["compiled"]),
               "iterations": st["newton_iterations"] / st["steps"],
               "tension": np.asarray(tr.fairlead_tension).tolist()}
        print(json.dumps(out), flush=True)


class Worker:
    def __init__(self, path: Path, cache: str, cpu: int | None):
        env = dict(os.environ, PYTHONPATH=str(path), SYMCABLE_CACHE_DIR=cache,
                   COMPARE_CPU="" if cpu is None else str(cpu))
        env.pop("SYMCABLE_CODEGEN", None)
        self.proc = subprocess.Popen([sys.executable, str(Path(__file__).resolve()), "--worker"],
                                     stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True,
                                     env=env, cwd=str(path))

    def ask(self, **req) -> dict:
        self.proc.stdin.write(json.dumps(req) + "\n")
        self.proc.stdin.flush()
        line = self.proc.stdout.readline()
        if not line:
            raise RuntimeError("worker died")
        return json.loads(line)

    def close(self):
        self.proc.stdin.close()
        self.proc.wait(timeout=60)


def measure(workers: dict, cases: list, repeats: int) -> list:
    """One row per case: medians over ``repeats`` interleaved rounds (the order of the two
    workers alternates from round to round), after a first call that builds and compiles."""
    import numpy as np

    rows = []
    for label, n, periods, cg in cases:
        req = dict(segments=n, periods=periods, codegen=cg)
        first = {k: w.ask(**req) for k, w in workers.items()}
        a, b = np.array(first["old"]["tension"]), np.array(first["new"]["tension"])
        diff = float(np.max(np.abs(a - b)) / np.ptp(a)) if a.shape == b.shape else float("nan")
        res = {k: [] for k in workers}
        for r in range(repeats):
            for k in (list(workers) if r % 2 == 0 else list(workers)[::-1]):
                res[k].append(workers[k].ask(**req))
        row = {"case": label, "segments": n, "periods": periods, "tension_diff": diff,
               "compiled": {k: res[k][0]["compiled"] for k in workers}}
        for key in ("wall", "us_per_step", "iterations"):
            for k in workers:
                row[f"{key}_{k}"] = statistics.median(x[key] for x in res[k])
                row[f"{key}_{k}_min"] = min(x[key] for x in res[k])
            row[f"{key}_ratio"] = row[f"{key}_new"] / row[f"{key}_old"]
            row[f"{key}_ratio_min"] = row[f"{key}_new_min"] / row[f"{key}_old_min"]
        rows.append(row)
        print(json.dumps(row), flush=True)
    return rows


def main(argv=None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="3 rounds, 6 periods at 50 segments")
    ap.add_argument("--baseline", default=str(BASELINE))
    ap.add_argument("--repeats", type=int, default=None)
    ap.add_argument("--cache", default=os.path.join(tempfile.gettempdir(), "symcable-compare-cache"))
    ap.add_argument("--no-200", action="store_true", help="seed 001 (50 segments) only")
    ap.add_argument("--cpu", type=int, default=os.cpu_count() - 1,
                    help="pin both workers to this core (-1: no pinning)")
    args = ap.parse_args(argv)
    repeats = args.repeats or (3 if args.quick else 9)
    p50, p200 = (6, 2) if args.quick else (30, 5)
    cases = [("seed 001, C", 50, p50, True), ("seed 001, VM", 50, p50, False)]
    if not args.no_200:
        cases += [("200 segments, C", 200, p200, True), ("200 segments, VM", 200, p200, False),
                  ("200 segments, default", 200, p200, None)]
    os.makedirs(args.cache, exist_ok=True)
    cpu = None if args.cpu < 0 else args.cpu
    workers = {"old": Worker(Path(args.baseline), args.cache, cpu),
               "new": Worker(NEW, args.cache, cpu)}
    try:
        rows = measure(workers, cases, repeats)
    finally:
        for w in workers.values():
            w.close()
    lines = ["| case | wall old / new (s) | ratio | µs/step old / new | ratio (of minima) | "
             "iterations/step old / new | compiled old/new | tension diff |",
             "|---|---|---|---|---|---|---|---|"]
    for r in rows:
        lines.append(f"| {r['case']}, {r['periods']} periods at T/100 | {r['wall_old']:.3f} / "
                     f"{r['wall_new']:.3f} | {r['wall_ratio']:.2f} | {r['us_per_step_old']:.1f} / "
                     f"{r['us_per_step_new']:.1f} | {r['us_per_step_ratio']:.2f} "
                     f"({r['us_per_step_ratio_min']:.2f}) | "
                     f"{r['iterations_old']:.3f} / {r['iterations_new']:.3f} | "
                     f"{r['compiled']['old']}/{r['compiled']['new']} | {r['tension_diff']:.1e} |")
    print("\n".join(lines))
    return {"rows": rows, "repeats": repeats}


if __name__ == "__main__":
    if "--worker" in sys.argv:
        worker()
    else:
        main()
