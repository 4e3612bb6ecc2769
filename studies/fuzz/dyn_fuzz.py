"""Dynamic fuzz study: random dynamic cable3d scenes, ``simulate`` and ``solve_periodic`` at
their defaults against a much finer time run (issue 33).

Question
--------
On random dynamic scenes (single lines taut, slack, on the seabed, in several sections, in a
current; two lines to one moving point; lines in series through a buoy or a clump; three
lines at a joint; a taut wire nearly slack at the bottom of each cycle; a harmonic motion of
period 5-20 s and amplitude 0.5-5 m in any direction; 10-40 segments a line), how many
answers of ``simulate`` (8 periods at its defaults: the step chosen for its default
tolerance, 1 % of the end tensions' range, from T/100) and ``solve_periodic``
(shooting, 100 steps a period) are correct, warned, silently wrong, clean errors, crashes
or hangs, and are their own error estimates within a factor of 3 of the true error?

The true error is measured against ``simulate`` at dt / 8 (and dt / 16 where a verdict
could depend on the reference's error, and on every ``--check16-every``-th scene; the
periodic answer against a run of 20 periods when 8 had not settled into a period), where
dt is the smaller of T/100 and 4 times the time run's own step (a reference at least 4 times
finer than the answer):
:mod:`dyn_classify` says how; the scenes: :mod:`dyn_scenes`; one scene's runs:
:mod:`dyn_work`; the worker pool with a time limit per stage: :mod:`dyn_pool`.

Run
---
    python studies/fuzz/dyn_fuzz.py --quick          # 4 small scenes, 2-3 min at load 7-10
    python studies/fuzz/dyn_fuzz.py --n 200 --budget-min 60 --check16-every 10
    options: --n N (200), --seed S (33), --workers W (2), --out DIR (studies/fuzz/out_dyn/),
             --budget-min M (no new scene after M minutes; default none),
             --check16-every K (the dt / 16 reference on every K-th scene too; 5, quick 0),
             --report (classify the --out dir's results.json again, rewrite the tables),
             --resume (keep the --out dir's records and run only the scenes it lacks: a
             200-scene run may span sessions; refused if the measured commit changed)
    python studies/fuzz/dyn_work.py studies/fuzz/out_dyn/failures.json d33-0002  # replay

Writes ``results.csv`` (one row per scene), ``results.json`` (every record with its
scene), ``failures.json`` (the scenes to look at, with their scene dicts) and
``summary.md``. ``main(argv)`` returns the same as a dict.
"""
from __future__ import annotations

import argparse
import collections
import json
import os
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
if str(HERE) not in sys.path:
    sys.path.insert(0, str(HERE))
if not os.environ.get("PYTHONPATH"):
    # measure the symcable of this tree (the worker processes inherit the path)
    sys.path.insert(1, str(HERE.parents[1]))

import dyn_classify as dc
import dyn_pool
import dyn_report
import dyn_scenes

SEED = 33
FULL_N, QUICK_N = 200, 4


def _version() -> str:
    """Where the measured symcable lives and its commit ("+changes" if its tree is dirty)."""
    import subprocess

    import symcable
    root = Path(symcable.__file__).resolve().parents[1]
    try:
        head = subprocess.run(["git", "-C", str(root), "rev-parse", "--short", "HEAD"],
                              capture_output=True, text=True, timeout=10, check=False).stdout.strip()
        dirty = subprocess.run(["git", "-C", str(root), "status", "--porcelain", "symcable"],
                               capture_output=True, text=True, timeout=10, check=False).stdout.strip()
    except (OSError, subprocess.SubprocessError):
        head, dirty = "", ""
    return f"{root} @ {head or '?'}{' +changes' if dirty else ''}"


def main(argv=None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--n", type=int, default=None)
    ap.add_argument("--seed", type=int, default=SEED)
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--out", default=str(HERE / "out_dyn"))
    ap.add_argument("--budget-min", type=float, default=None)
    ap.add_argument("--check16-every", type=int, default=None)
    ap.add_argument("--report", action="store_true",
                    help="classify the --out dir's results.json again and rewrite its tables")
    ap.add_argument("--resume", action="store_true",
                    help="keep the --out dir's records, run only the scenes they lack")
    args = ap.parse_args(argv)
    if args.report:
        return report(Path(args.out))
    n = args.n or (QUICK_N if args.quick else FULL_N)
    every = args.check16_every if args.check16_every is not None else (0 if args.quick else 5)
    os.environ.setdefault("SYMCABLE_CODEGEN", "0")
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    t0 = time.perf_counter()
    version = _version()   # at the start: the tree may change while the study runs
    items = dyn_scenes.generate(n, args.seed, quick=args.quick)
    for i, it in enumerate(items):
        it["check16"] = bool(every) and i % every == 0
    old, wall0 = _previous(out, n, args.seed, version) if args.resume else ([], 0.0)
    have = {r["id"] for r in old}
    todo = [it for it in items if it["id"] not in have]
    log = open(out / "progress.log", "a" if args.resume else "w")  # noqa: SIM115 - closed after the run

    def progress(done, total):
        if len(done) != getattr(progress, "last", -1):
            progress.last = len(done)
            c = collections.Counter()
            for r in done.values():
                dc.classify(r)
                c[f"sim {r['sim_class']}"] += 1
                c[f"per {r['per_class']}"] += 1
            print(f"{time.perf_counter() - t0:7.0f} s  {len(done)}/{total}  {dict(c)}",
                  file=log, flush=True)

    try:
        load = os.getloadavg()[0]
    except OSError:
        load = None
    recs = dyn_pool.run_all(todo, workers=args.workers, progress=progress,
                            budget_s=None if args.budget_min is None else 60 * args.budget_min)
    log.close()
    res = {"n": len(old) + len(recs), "n_asked": n, "seed": args.seed, "workers": args.workers,
           "quick": args.quick, "version": version,
           "command": "python studies/fuzz/dyn_fuzz.py " + " ".join(argv if argv is not None
                                                                    else sys.argv[1:]),
           "wall_min": wall0 + (time.perf_counter() - t0) / 60, "load": load}
    scenes = {it["id"]: it for it in items}
    new = [dict(r, scene=scenes[r["id"]]["scene"], **{"class": scenes[r["id"]]["class"]})
           for r in recs]
    order = {it["id"]: i for i, it in enumerate(items)}
    res["records"] = sorted(old + new, key=lambda r: order[r["id"]])
    return _write(out, res)


def _previous(out: Path, n: int, seed: int, version: str) -> tuple[list, float]:
    """The records and wall minutes of an earlier run in ``out`` of the same scenes and code."""
    path = out / "results.json"
    if not path.exists():
        return [], 0.0
    with open(path) as fh:
        res = json.load(fh)
    if (res.get("n_asked"), res.get("seed")) != (n, seed):
        raise SystemExit(f"--resume: {path} holds --n {res.get('n_asked')} --seed "
                         f"{res.get('seed')}, not --n {n} --seed {seed}")
    if str(res.get("version")).split(" @ ")[-1] != version.split(" @ ")[-1]:
        raise SystemExit(f"--resume: {path} measured {res.get('version')}, this run would "
                         f"measure {version}; start a new --out")
    return res["records"], float(res.get("wall_min", 0.0))


def report(out: Path) -> dict:
    """The tables again from ``out/results.json`` (after a change of the classifier)."""
    with open(out / "results.json") as fh:
        res = json.load(fh)
    return _write(out, res)


def _write(out: Path, res: dict) -> dict:
    recs = res["records"]
    for r in recs:
        dc.classify(r)
    with open(out / "results.json", "w") as fh:
        json.dump(res, fh, indent=1, default=float)
    dyn_report.write_csv(out / "results.csv", recs)
    res["failures"] = dyn_report.write_failures(out / "failures.json", recs)
    (out / "summary.md").write_text(dyn_report.summary(res))
    res["sim_counts"] = collections.Counter(r["sim_class"] for r in recs)
    res["per_counts"] = collections.Counter(r["per_class"] for r in recs)
    print(f"{len(recs)} scenes in {res['wall_min']:.1f} min: simulate "
          f"{dict(res['sim_counts'])}; solve_periodic {dict(res['per_counts'])}; "
          f"outputs in {out}")
    return res


if __name__ == "__main__":
    main()
