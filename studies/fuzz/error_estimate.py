"""Fuzz study of the static discretisation-error estimate (issue 33): is every answer that
is off MoorPy by more than 1 % warned, with an estimate within a factor of 3 of its true
error?

Over random planar and 3D scenes that MoorPy solves exactly (:mod:`errest_scenes`: no
current, no bending; the 3D set weighted toward systems of 1-4 lines with buoys, clumps and
joints, 40-100 segments a line), each solved by ``sc.solve_static(scene, codegen=False)`` in a
worker process with a time limit (:mod:`fuzz_pool`), and by MoorPy (:mod:`errest_work`):

- true error: max over lines and ends of |T_symcable - T_MoorPy| over the largest end
  tension of MoorPy's answer (at least 1e-3 of the scene's weight); estimate:
  ``stats["discretisation_error"]["max_relative"]``; warned: a warning containing
  "discretisation error" (a slack-segment warning is counted apart, not as warned);
- each scene: ``correct`` (true <= 1 %), ``warned`` (true > 1 %, warned), ``silent wrong``
  (true > 1 %, not warned), ``clean error`` (SymcableError, ConvergenceError), ``crash``
  (any other exception, or the worker died), ``hang`` (over the time limit), ``no reference``
  (MoorPy failed or does not apply);
- the factor estimate / true error of every scene off by more than 1 % (and by more than
  0.3 %), false alarms (warned, true <= 1 %), and the estimate's cost (a subsample solved
  with and without ``estimate``, each in a fresh process; and on every scene the call's
  time over that time less the estimate's own ``wall_time``).

Run::

    python studies/fuzz/error_estimate.py --quick           # 20 planar + 10 3D scenes, ~1 min
    python studies/fuzz/error_estimate.py --n 1000          # 1000 planar + 1000 3D
    options: --n N (each; --n2 / --n3 apart), --seed S (33), --workers W (2), --limit S (a
             solve, 120), --cost-every K (time every K-th scene with and without the
             estimate, each in a fresh process; 20, quick 0: none), --out DIR
             (studies/fuzz/out/errest/: git-ignored, apart from run.py's outputs)
    python studies/fuzz/error_estimate.py --replay studies/fuzz/out/errest/failures.json ID
    python studies/fuzz/error_estimate.py --summarise studies/fuzz/out/errest/results.json

Writes ``records.jsonl`` (each record as its chunk of 50 scenes ends: ``--resume`` continues a
run killed midway), ``results.csv``, ``results.json``, ``failures.json`` (silent wrong answers, factors
outside [1/3, 3], crashes, hangs: each with its scene dict) and ``summary.md``; ``main(argv)``
returns the summary as a dict.
"""
from __future__ import annotations

import argparse
import json
import os
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
if str(HERE) not in sys.path:
    sys.path.insert(0, str(HERE))
if not os.environ.get("PYTHONPATH"):   # this tree's symcable (the workers inherit the path)
    sys.path.insert(1, str(HERE.parents[1]))

import errest_report as rep
import errest_scenes
import errest_work
import fuzz_pool
from fuzz_report import dump_json

# ----------------------------------------------------------------------------- running
CHUNK = 50   # scenes per pool run: records are appended to records.jsonl after each


def run(items, workers: int, limit: float, progress=None) -> list[dict]:
    """Every item in the worker pool (fuzz_pool's processes running errest_work.worker)."""
    saved = fuzz_pool._worker
    fuzz_pool._worker = errest_work.worker
    try:
        recs = fuzz_pool.run_all(items, workers=workers, solve_limit=limit, ref_limit=300.0,
                                 progress=progress)
    finally:
        fuzz_pool._worker = saved
    byid = {it["id"]: it for it in items}
    for r in recs:   # a hang or crash record from the pool: dim and segments from the item
        it = byid[r["id"]]
        r.setdefault("dim", it["dim"])
        r.setdefault("segments", errest_scenes.segments_of(it["scene"]))
    return recs


def run_checkpointed(items, args, t0: float) -> list[dict]:
    """``run`` in chunks of CHUNK scenes, each chunk's records appended to
    ``records.jsonl`` in the out dir; with ``--resume`` the scenes recorded there already
    are not run again (a long run killed midway continues where it stopped)."""
    path = args.out / "records.jsonl"
    done = {}
    if args.resume and path.is_file():
        for line in path.read_text().splitlines():
            if line.strip():
                r = json.loads(line)
                done[r["id"]] = r
    else:
        path.write_text("")
    todo = [it for it in items if it["id"] not in done]
    print(f"{len(items)} scenes, {len(done)} recorded already, {len(todo)} to run", flush=True)
    for k in range(0, len(todo), CHUNK):
        recs = run(todo[k:k + CHUNK], args.workers, args.limit)
        with open(path, "a") as fh:
            for r in recs:
                fh.write(json.dumps(r, default=rep_json) + "\n")
                done[r["id"]] = json.loads(json.dumps(r, default=rep_json))
        print(f"  {len(done)}/{len(items)} scenes, {time.perf_counter() - t0:.0f} s", flush=True)
    return [done[it["id"]] for it in items]


def rep_json(o):
    import numpy as np
    if isinstance(o, (np.floating, np.integer, np.bool_)):
        return o.item()
    if isinstance(o, np.ndarray):
        return o.tolist()
    raise TypeError(type(o))


def symcable_version() -> str:
    """Where the measured symcable lives, and its git commit (+changes if its tree is dirty),
    as run.py says it (loaded by path: another study's run.py may be importable as "run")."""
    import importlib.util
    spec = importlib.util.spec_from_file_location("fuzz_study_run", HERE / "run.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module.symcable_version()


def main(argv=None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--quick", action="store_true", help="20 planar + 10 3D scenes")
    ap.add_argument("--n", type=int, help="scenes of each kind (default 1000)")
    ap.add_argument("--n2", type=int, help="planar scenes")
    ap.add_argument("--n3", type=int, help="3D scenes")
    ap.add_argument("--seed", type=int, default=33)
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--limit", type=float, default=120.0, help="time limit of a solve, s")
    ap.add_argument("--cost-every", type=int, help="time every K-th scene with and without "
                    "the estimate, each in a fresh process (default 20; quick 0: none)")
    ap.add_argument("--out", type=Path, default=HERE / "out" / "errest")
    ap.add_argument("--resume", action="store_true",
                    help="keep the scenes already in OUT/records.jsonl, run the rest")
    ap.add_argument("--replay", nargs=2, metavar=("FILE", "ID"), help="rerun one scene")
    ap.add_argument("--summarise", type=Path, metavar="RESULTS_JSON",
                    help="write the summary.md of a results.json again (next to it)")
    args = ap.parse_args(argv)
    if args.replay:
        return replay(*args.replay)
    if args.summarise:
        data = json.loads(args.summarise.read_text())
        s = rep.summarise(data["records"], data["summary"]["meta"])
        (args.summarise.parent / "summary.md").write_text(rep.markdown(s, data["records"]))
        print(rep.markdown(s, data["records"]))
        return s
    n = args.n or 1000
    n2 = args.n2 if args.n2 is not None else (20 if args.quick and not args.n else n)
    n3 = args.n3 if args.n3 is not None else (10 if args.quick and not args.n else n)
    every = args.cost_every if args.cost_every is not None else (0 if args.quick else 20)
    args.out.mkdir(parents=True, exist_ok=True)
    t0 = time.perf_counter()
    items = errest_scenes.generate(n2, n3, args.seed)
    for it in items:
        it["cost"] = bool(every) and int(it["id"].rsplit("-", 1)[1]) % every == 0
    recs = run_checkpointed(items, args, t0)
    meta = {"symcable": symcable_version(), "seed": args.seed, "n2": n2, "n3": n3,
            "workers": args.workers, "limit": args.limit, "cost_every": every,
            "wall_s": time.perf_counter() - t0, "out": str(args.out), "resumed": args.resume}
    s = rep.summarise(recs, meta)
    scenes = {it["id"]: it for it in items}
    fails = [{"kind": rep.failure_kind(r), "record": r, "id": r["id"], "class": r["cls"],
              "dim": scenes[r["id"]]["dim"], "variant": r.get("variant"),
              "scene": scenes[r["id"]]["scene"]} for r in recs if rep.failure_kind(r)]
    dump_json(fails, args.out / "failures.json")
    dump_json({"summary": s, "records": recs}, args.out / "results.json")
    rep.write_csv(recs, args.out / "results.csv")
    text = rep.markdown(s, recs)
    (args.out / "summary.md").write_text(text)
    print(text)
    return s


def replay(path: str, ident: str) -> dict:
    """Run one scene of a failures.json or results.json again, in this process."""
    with open(path) as fh:
        data = json.load(fh)
    entries = data if isinstance(data, list) else []
    for e in entries:
        if e["id"] == ident:
            item = {"id": e["id"], "class": e["class"], "variant": e.get("variant"),
                    "dim": e["dim"], "scene": e["scene"], "cost": False}
            rec = errest_work.run_item(item, extra=True)
            rec["category"] = rep.category(rec)
            print(json.dumps(rec, indent=1, default=str))
            return rec
    raise SystemExit(f"{ident} not in {path} (replay reads failures.json, which holds the scenes)")


if __name__ == "__main__":
    main()
