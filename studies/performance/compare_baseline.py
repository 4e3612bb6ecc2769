"""Statics against the code before issue 10, side by side in one run.

Question: is the planar ``solve_static``, now the generic ``solve_equilibrium`` on the planar
statics Mechanism with the fused Newton solve carried into the functions layer
(``symcable/mechanism/static_functions.py``), as fast as the planar-specific code it replaced?

Two long-lived worker processes, one importing this tree and one a checkout of the code
before issue 10 (``--baseline DIR``, e.g. ``git worktree add ../baseline a958ce7``), time the
same calls in interleaved rounds (which side goes first alternates), each round a block of
back-to-back calls (warm, as a sweep runs them; see ``run.py``'s ``interleaved``). Reported:
the median wall time per call over the rounds, and the ratio new / old; and the same for the
process's CPU time (``time.process_time``), which leaves out the time the process waited for
a core (the machine is shared: under load the wall times swell, Python's more than C's). Cases: the OC3 line
(``demo_scene_path("oc3")``, 50 segments, on its seabed) and the seed-001 line at 50 and 200
segments (suspended, with current). Calls:

- ``fused_c``, ``fused_vm``: the fused plain-Newton call alone from the first start (us),
  generated C and the CasADi virtual machine;
- ``static_c``, ``static_vm``: ``solve_static(scene, model=model, codegen=...)`` with a
  pre-built model (ms), everything included (start, checks, outputs, result object).

Both sides must return the same fairlead tension (to 1e-9) and take the same path and Newton
iterations; the study says so when they do not. At 200 segments (798 unknowns) the Newton
step is the sparse QR, not the written-out block LU, and ``codegen=True`` compiles it anyway.

Run ``python studies/performance/compare_baseline.py --baseline DIR [--quick] [--out DIR]``
(``--quick``: OC3 only, 5 rounds). Compiling the C takes a while the first time (cached).
"""
from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parents[1]

CASES = {"oc3": ("oc3", None), "seed001_50": ("seed001", 50), "seed001_200": ("seed001", 200)}
CALLS = ("fused_c", "fused_vm", "static_c", "static_vm")
#: aim for blocks of about this many seconds
BLOCK_S = 0.02


# --------------------------------------------------------------------------- worker side

def _scene(sc, name, segments):
    scene = sc.load_scene(sc.demo_scene_path(name))
    if segments is not None:
        d = scene.to_dict()
        d["sections"] = [dict(d["sections"][0], segments=segments)]
        d["name"] = f"{d['name']} ({segments} segments)"
        scene = sc.load_scene(d)
    return scene


def _fused(sc, model, codegen):
    """The fused Newton call of either tree, from the model's first start: a callable."""
    try:  # the code before issue 10
        from symcable.functions import static_functions
        fns = static_functions(model, codegen)
        x0 = next(iter(model.initial_guess())).w
        fn = fns.fast("solve")
    except ImportError:  # this tree
        from symcable.mechanism.functions import functions
        from symcable.models.planar.static import static_mechanism
        mech = static_mechanism(model)
        fn = functions(mech).static_solver(codegen).fast("solve")
        x0 = next(iter(mech.starts())).q
    return fn, x0


def _prepare(sc, key):
    name, segments = CASES[key]
    scene = _scene(sc, name, segments)
    model = sc.build_model(scene)
    calls, info = {}, {}
    for cg, tag in ((True, "c"), (False, "vm")):
        t0 = time.perf_counter()
        st = sc.solve_static(scene, model=model, codegen=cg)  # builds (and compiles) once
        info[f"first_{tag}_s"] = time.perf_counter() - t0
        info[tag] = {"path": st.stats["path"], "iterations": st.stats["iterations"],
                     "compiled": st.stats["compiled"], "fairlead_tension": st.fairlead_tension}
        fn, x0 = _fused(sc, model, cg)
        p, tol = model.p_target, st.stats["tolerance"]
        calls[f"fused_{tag}"] = (lambda fn=fn, x0=x0, p=p, tol=tol: fn(x0, p, tol))
        calls[f"static_{tag}"] = (lambda cg=cg: sc.solve_static(scene, model=model, codegen=cg))
    info["unknowns"] = model.n_w
    return calls, info


def worker() -> None:
    """Read JSON commands from stdin, answer one JSON line each."""
    import symcable as sc

    prepared = {}
    for line in sys.stdin:
        cmd = json.loads(line)
        if cmd["op"] == "prepare":
            calls, info = _prepare(sc, cmd["case"])
            prepared[cmd["case"]] = calls
            for k, f in calls.items():  # block size: about BLOCK_S of calls (warm)
                n, t = 1, 0.0
                while t < 0.2 * BLOCK_S:
                    t0 = time.perf_counter()
                    for _ in range(n):
                        f()
                    t, n = time.perf_counter() - t0, 2 * n
                info.setdefault("number", {})[k] = max(1, int(BLOCK_S * n / 2 / t))
            out = info
        elif cmd["op"] == "time":
            f = prepared[cmd["case"]][cmd["call"]]
            n = int(cmd["number"])
            t0, c0 = time.perf_counter(), time.process_time()
            for _ in range(n):
                f()
            out = {"seconds": (time.perf_counter() - t0) / n,
                   "cpu": (time.process_time() - c0) / n}
        else:
            out = {"error": f"unknown op {cmd['op']!r}"}
        print(json.dumps(out), flush=True)


# --------------------------------------------------------------------------- driver side

class Worker:
    def __init__(self, tree: Path):
        env = dict(os.environ, PYTHONPATH=str(tree))
        self.proc = subprocess.Popen([sys.executable, str(Path(__file__).resolve()), "--worker"],
                                     stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True,
                                     env=env, cwd=str(HERE))

    def ask(self, **cmd) -> dict:
        self.proc.stdin.write(json.dumps(cmd) + "\n")
        self.proc.stdin.flush()
        line = self.proc.stdout.readline()
        if not line:
            raise RuntimeError(f"worker died on {cmd}")
        return json.loads(line)

    def close(self):
        self.proc.stdin.close()
        self.proc.wait(timeout=60)


def compare(baseline: Path, cases, rounds: int) -> dict:
    sides = {"old": Worker(baseline), "new": Worker(ROOT)}
    res = {}
    try:
        for case in cases:
            info = {k: w.ask(op="prepare", case=case) for k, w in sides.items()}
            number = {c: max(info["old"]["number"][c], info["new"]["number"][c]) for c in CALLS}
            times = {k: {c: [] for c in CALLS} for k in sides}
            cpu = {k: {c: [] for c in CALLS} for k in sides}
            for r in range(rounds):
                order = ("old", "new") if r % 2 == 0 else ("new", "old")
                for c in CALLS:
                    for k in order:
                        got = sides[k].ask(op="time", case=case, call=c, number=number[c])
                        times[k][c].append(got["seconds"])
                        cpu[k][c].append(got["cpu"])
            med = {k: {c: statistics.median(v) for c, v in t.items()} for k, t in times.items()}
            med_cpu = {k: {c: statistics.median(v) for c, v in t.items()} for k, t in cpu.items()}
            same = all(info["old"][t]["path"] == info["new"][t]["path"]
                       and info["old"][t]["iterations"] == info["new"][t]["iterations"]
                       and abs(info["old"][t]["fairlead_tension"] - info["new"][t]["fairlead_tension"])
                       <= 1e-9 * info["old"][t]["fairlead_tension"] for t in ("c", "vm"))
            res[case] = {"median_s": med, "ratio_new_old": {c: med["new"][c] / med["old"][c]
                                                            for c in CALLS},
                         "median_cpu_s": med_cpu,
                         "cpu_ratio_new_old": {c: med_cpu["new"][c] / med_cpu["old"][c]
                                               for c in CALLS},
                         "number": number, "rounds": rounds, "same_answer": same, "info": info}
    finally:
        for w in sides.values():
            w.close()
    return res


def table(res: dict) -> str:
    lines = ["| case | call | old | new | new / old | CPU time: old | new | new / old |",
             "|---|---|---|---|---|---|---|---|"]
    for case, r in res.items():
        for c in CALLS:
            unit, f = ("us", 1e6) if c.startswith("fused") else ("ms", 1e3)
            o, n = r["median_s"]["old"][c] * f, r["median_s"]["new"][c] * f
            co, cn = r["median_cpu_s"]["old"][c] * f, r["median_cpu_s"]["new"][c] * f
            lines.append(f"| {case} ({r['info']['new']['unknowns']} unknowns) | {c} | "
                         f"{o:.3g} {unit} | {n:.3g} {unit} | {n / o:.2f} | "
                         f"{co:.3g} {unit} | {cn:.3g} {unit} | {cn / co:.2f} |")
    for case, r in res.items():
        if not r["same_answer"]:
            lines.append(f"\n**{case}: the two sides differ** (path, iterations or tension): "
                         f"{json.dumps({k: r['info'][k] for k in ('old', 'new')})}")
    return "\n".join(lines)


def main(argv=None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--baseline", type=Path, default=os.environ.get("SYMCABLE_BASELINE"),
                    help="checkout of the code before issue 10 (or $SYMCABLE_BASELINE)")
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--rounds", type=int, default=None)
    ap.add_argument("--cases", default=None, help=f"comma-separated, of {', '.join(CASES)}")
    ap.add_argument("--out", type=Path, default=None)
    ap.add_argument("--worker", action="store_true", help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.worker:
        worker()
        return {}
    if args.baseline is None or not (Path(args.baseline) / "symcable").is_dir():
        ap.error(f"--baseline = {args.baseline}: must be a checkout of symcable before issue 10 "
                 "(a folder holding symcable/), e.g. `git worktree add ../baseline a958ce7`")
    cases = args.cases.split(",") if args.cases else ["oc3"] if args.quick else list(CASES)
    if any(c not in CASES for c in cases):
        ap.error(f"--cases = {args.cases}: each must be one of {', '.join(CASES)}")
    rounds = args.rounds or (5 if args.quick else 30)
    res = compare(Path(args.baseline).resolve(), cases, rounds)
    text = table(res)
    print(text)
    if args.out is not None:
        args.out.mkdir(parents=True, exist_ok=True)
        (args.out / "compare_baseline.json").write_text(json.dumps(res, indent=1))
        (args.out / "compare_baseline.md").write_text(text + "\n")
    return res


if __name__ == "__main__":
    main()
