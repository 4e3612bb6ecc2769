"""Fuzz study of symcable's planar statics: random scenes over the whole range a user may give,
each solve checked against independent references and physical laws.

Question
--------
Does ``solve_static`` ever return a wrong answer as "converged"? Over random planar scenes
(EA 1e5-1e10 N; chain, wire, rope, near-neutral, buoyant, weightless lines and cables in air;
taut to fully slack, exactly vertical and near-vertical; seabed or not; current; bending;
free ends; several sections; 1 to 60 segments), how many solves are correct, wrong (status
converged but physically impossible or off the reference beyond the discretisation error),
NaN, clean errors, ugly errors (an exception that is not a SymcableError) and hangs, and
how many scenes that MoorPy solves does symcable not?

What is generated, the references and the checks: ``fuzz_scenes`` (classes and proportions),
``fuzz_refs`` (closed-form catenary, the study's own piecewise closed form, MoorPy, ODE
shooting, the elastica BVP for rods, and their agreement), ``fuzz_classify`` (outcomes,
physical checks, the discretisation tolerance), ``fuzz_refine`` (the tolerance's constants,
measured by refining). Every solve runs in a worker process (``fuzz_pool``) with a time limit,
in the CasADi virtual machine (``codegen=False``: compiling generated C for each of a thousand
one-off models would dominate the run; the answers agree with the C ones to round-off).

Run
---
    python studies/fuzz/run.py            # full: 1200 scenes + 40 refined, ~17 min on 2 cores
    python studies/fuzz/run.py --quick    # 100 scenes, no refinement: about a minute
    options: --n N, --seed S, --workers W, --refine K, --out DIR (default studies/fuzz/out/),
             --cases PATH (write the curated regression cases there), --limit S (per solve),
             --n3d N (cable3d scenes: 300, quick 12; 0 none), --only3d (those alone)

Writes to the out dir: ``results.csv`` (one row per scene), ``results.json`` (every record),
``failures.json`` (every scene not solved correctly, with its scene dict, to replay),
``refine.json`` and ``summary.md`` (the tables of the README); for the cable3d scenes
(``fuzz3d_*``: 3D lines, seabed with friction, points and several lines) ``results3d.csv``,
``results3d.json``, ``failures3d.json`` and their section of ``summary.md``.
Replay one scene: ``python studies/fuzz/fuzz_classify.py studies/fuzz/out/failures.json ID``.
"""
from __future__ import annotations

import argparse
import collections
import os
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
if str(HERE) not in sys.path:
    sys.path.insert(0, str(HERE))
if not os.environ.get("PYTHONPATH"):
    # measure the symcable of this tree (not an installed copy), unless PYTHONPATH says which;
    # the worker processes inherit this path
    sys.path.insert(1, str(HERE.parents[1]))

import fuzz3d_report as rep3  # noqa: E402
import fuzz_pool  # noqa: E402
import fuzz_report as rep  # noqa: E402
import fuzz_scenes  # noqa: E402
import fuzz_tolerance  # noqa: E402

FULL = {"n": 1200, "refine": 40, "n3d": 300}
QUICK = {"n": 100, "refine": 0, "n3d": 12}
SEED = 11


def symcable_version() -> str:
    """Where the measured symcable lives, and its git commit (with "+changes" if dirty)."""
    import subprocess
    import symcable
    root = Path(symcable.__file__).resolve().parents[1]
    try:
        head = subprocess.run(["git", "-C", str(root), "rev-parse", "--short", "HEAD"],
                              capture_output=True, text=True, timeout=10).stdout.strip()
        dirty = subprocess.run(["git", "-C", str(root), "status", "--porcelain", "symcable"],
                               capture_output=True, text=True, timeout=10).stdout.strip()
    except (OSError, subprocess.SubprocessError):
        head, dirty = "", ""
    return f"{root} @ {head or '?'}{' +changes' if dirty else ''}"


def refine_items(items: list[dict], k: int) -> list[dict]:
    """k scenes to refine, spread over the set (every class)."""
    pool = list(items)
    step = max(1, len(pool) // max(k, 1))
    return [dict(it, job="refine") for it in pool[::step][:k]]


def main(argv=None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--quick", action="store_true", help="100 scenes, no refinement")
    ap.add_argument("--n", type=int, help="number of scenes")
    ap.add_argument("--seed", type=int, default=SEED)
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--refine", type=int, help="scenes to refine for the tolerance check")
    ap.add_argument("--limit", type=float, default=30.0, help="time limit per solve, s")
    ap.add_argument("--out", type=Path, default=HERE / "out")
    ap.add_argument("--cases", type=Path, help="write the curated regression cases here")
    ap.add_argument("--n3d", type=int, help="number of cable3d scenes (0: none)")
    ap.add_argument("--only3d", action="store_true", help="the cable3d scenes only")
    args = ap.parse_args(argv)
    if args.only3d:
        return main3d(args, QUICK if args.quick else FULL)
    mode = QUICK if args.quick else FULL
    n = args.n or mode["n"]
    k_refine = mode["refine"] if args.refine is None else args.refine
    args.out.mkdir(parents=True, exist_ok=True)

    t0 = time.perf_counter()
    items = fuzz_scenes.generate(n, args.seed)
    scenes = {it["id"]: it["scene"] for it in items}

    shown = set()

    def progress(done, total):
        if (done % 100 == 0 or done == total) and done not in shown:
            shown.add(done)
            print(f"  {done}/{total} scenes, {time.perf_counter() - t0:.0f} s", flush=True)

    records = fuzz_pool.run_all(items, workers=args.workers, solve_limit=args.limit,
                                progress=progress)
    refine = None
    if k_refine:
        print(f"refining {k_refine} scenes", flush=True)
        ref_results = fuzz_pool.run_all(refine_items(items, k_refine), workers=args.workers,
                                        solve_limit=600.0, ref_limit=600.0)
        refine = {"scenes": len(ref_results),
                  "converging": sum(1 for r in ref_results if r.get("converges")),
                  "constants": rep.refine_constants(ref_results, fuzz_tolerance.TOL),
                  "results": ref_results}
        rep.dump_json(refine, args.out / "refine.json")
    wall = time.perf_counter() - t0

    table, bad = rep.agreement_table(records)
    applies = [r for r in records if r.get("moorpy_solved") is not None]
    solved = [r for r in applies if r["moorpy_solved"]]
    res = {
        "symcable": symcable_version(),
        "mode": "quick" if args.quick else "full", "seed": args.seed, "n": n,
        "workers": args.workers, "solve_limit": args.limit, "wall_s": wall,
        "records": records, "counts": rep.counts(records),
        "by_class": {k: dict(v) for k, v in rep.by_class(records).items()},
        "agreement": {"table": table, "disagreeing": bad},
        "ref_counts": dict(sorted(collections.Counter(
            len((r.get("agreement") or {}).get("names", [])) + (1 if r.get("reference") == "bvp" else 0)
            for r in records).items())),
        "moorpy": {"applies": len(applies), "solved": len(solved),
                   "sym_correct": sum(1 for r in solved if r["outcome"] == "correct"),
                   "sym_clean": sum(1 for r in solved if r["outcome"] == "clean error"),
                   "sym_other": sum(1 for r in solved if r["outcome"] not in ("correct", "clean error"))},
        "refine": refine, "out": str(args.out),
    }
    rep.write_csv(records, args.out / "results.csv")
    rep.dump_json(records, args.out / "results.json")
    fails = rep.failures(records, scenes)
    rep.dump_json(fails, args.out / "failures.json")
    res["failures"] = len(fails)
    if args.cases:
        rep.dump_json(rep.curate(fails), args.cases)
    n3d = mode["n3d"] if args.n3d is None else args.n3d
    text = rep.summary_markdown(res)
    if n3d:
        print(f"{n3d} cable3d scenes", flush=True)
        res["cable3d"] = run3d(n3d, args)
        res["wall_s"] = time.perf_counter() - t0
        text += "\n" + rep3.summary_markdown(res["cable3d"])
    (args.out / "summary.md").write_text(text)
    print(text)
    return res


def run3d(n3d: int, args) -> dict:
    """The cable3d scenes (fuzz3d_scenes, fuzz3d_classify): results3d.csv, results3d.json,
    failures3d.json in the out dir."""
    t0 = time.perf_counter()
    shown = set()

    def progress(done, total):
        if (done % 50 == 0 or done == total) and done not in shown:
            shown.add(done)
            print(f"  cable3d {done}/{total} scenes, {time.perf_counter() - t0:.0f} s", flush=True)

    res = rep3.run(n3d, args.seed, args.workers, args.limit, args.out, progress)
    res["symcable"] = symcable_version()
    return res


def main3d(args, mode) -> dict:
    """--only3d: the cable3d scenes alone, their summary in summary3d.md."""
    args.out.mkdir(parents=True, exist_ok=True)
    res = run3d(mode["n3d"] if args.n3d is None else args.n3d, args)
    text = rep3.summary_markdown(res)
    (args.out / "summary3d.md").write_text(text)
    print(text)
    return {"cable3d": res}


if __name__ == "__main__":
    main()
