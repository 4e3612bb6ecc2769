"""Scaling of the cable3d time step against the number of segments: build, compile and
step time, the step's residual and matrix from the element loops (the default from 200
states, ``symcable.solvers.element_jacobian``) beside them written out in SX.

Question: with the element loops, do building, compiling and stepping a long line cost
O(N), where the written-out step's C grew faster than its length (WD0600, 170 segments:
79 s to build and compile, 557 us per step against 16 s and 348 us with the loops)?

Case: MoorDyn's WD0600 chain deck (``studies/chains/cases.py``) with its one section cut
into N segments, the ZZP1_A1 heave table on the fairlead, first-order generalized-alpha
(``simulate``'s scheme: rho_inf = 0, Newton tol 1e-8) at dt = 0.1 s from the static state
at t = -10 s for 10 s (100 steps). Every (N, way) runs in a fresh process with a fresh
codegen cache (so compile times are first compiles): the Mechanism's build, the step
Function's build (``galpha1_kernel``, virtual machine), its compile (``codegen=True``, at
the optimisation level ``symcable.mechanism.codegen.flags_for`` gives its graph size), and RUNS + 1
runs of the 100 steps (the last RUNS timed: the median of ``us_per_step`` of the runs'
stats; and the Newton iterations per step). The written-out way only up to
``--written-max`` segments (its compile takes minutes beyond).

Run ``python studies/performance/scaling3d.py [--quick] [--out DIR] [--sizes 50,100,...]``;
``--quick`` (the test): N = 40 (234 states) in the virtual machine (no compiling), 20
steps.
Writes ``scaling3d.csv``, ``scaling3d.md`` and ``scaling3d.png`` (the cost per Newton
iteration, and the build and compile times, against N, log-log; ``--figure PATH`` a copy).
"""
from __future__ import annotations

import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
if str(HERE.parent) not in sys.path:
    sys.path.append(str(HERE.parent))
from study_io import parse, write_tables  # noqa: E402  (studies/study_io.py)

SIZES = (50, 100, 200, 400)
QUICK = (40,)
WAYS = ("elements", "written")
#: timed runs of the 100 steps per (N, way), after an untimed one (median)
RUNS = 5
#: a part that runs longer than this (s) is stopped and recorded as such
TIMEOUT = 1200


def _one(n: int, way: str, codegen: bool, steps: int) -> dict:
    """One (N, way) measurement in this process (module docstring)."""
    from study_io import load_module

    from symcable.mechanism.codegen import flags_for, graph_size
    from symcable.models.cable3d.line import build_cable3d
    from symcable.scene import load_scene
    from symcable.solvers import galpha1 as ga
    from symcable.solvers.equilibrium import solve_equilibrium
    from symcable.solvers.integrate import integrate
    from symcable.solvers.options import GeneralizedAlphaFirstOrder

    cases = load_module(HERE.parent / "chains" / "cases.py", "chains_cases")
    ga.ELEMENT_MATRIX = way == "elements"
    d = cases.chain_scene("WD0600", cases.extended_table("A1", Path(tempfile.mkdtemp()))
                          ).to_dict()
    d["sections"][0]["segments"] = n
    scene = load_scene(d)
    t0 = time.perf_counter()
    mech = build_cable3d(scene)
    t1 = time.perf_counter()
    opts = GeneralizedAlphaFirstOrder(rho_inf=0.0, tol=1e-8)
    lu, by_elements = ga.solver_choice(mech, codegen)
    vm = ga.galpha1_kernel(mech, opts, codegen=False)
    t2 = time.perf_counter()
    level = flags_for(graph_size([vm]))[0]
    if codegen:
        ga.galpha1_kernel(mech, opts, codegen=True)
    t3 = time.perf_counter()
    eq = solve_equilibrium(mech, codegen=codegen)

    def run():
        return integrate(mech, 0.1 * steps, 0.1, t0=cases.T0, start=eq, p=mech.params.values,
                         method=opts, codegen=codegen, progress=False)
    run()
    runs = [run() for _ in range(RUNS)]
    tr = runs[0]
    return {"segments": n, "way": way, "states": mech.n_q + mech.n_v,
            "solver": "block LU (SX)" if lu else "banded LU", "elements": by_elements,
            "compiled": bool(codegen), "build_s": t1 - t0, "step_build_s": t2 - t1,
            "compile_s": t3 - t2 if codegen else float("nan"),
            "level": level if codegen else "",
            "us_per_step": statistics.median(r.stats["us_per_step"] for r in runs),
            "newton_per_step": tr.stats["newton_iterations"] / tr.stats["steps"]}


def _in_fresh_process(n: int, way: str, codegen: bool, steps: int) -> dict:
    """:func:`_one` in a child process with a fresh codegen cache."""
    with tempfile.TemporaryDirectory() as cache:
        env = dict(os.environ, SYMCABLE_CACHE_DIR=cache)
        code = (f"import json, sys; sys.path.insert(0, {str(HERE)!r}); import scaling3d; "
                f"print(json.dumps(scaling3d._one({n}, {way!r}, {codegen}, {steps})))")
        try:
            out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True,
                                 text=True, timeout=TIMEOUT)
        except subprocess.TimeoutExpired:
            return {"segments": n, "way": way, "status": f"stopped after {TIMEOUT} s"}
    if out.returncode != 0:
        return {"segments": n, "way": way,
                "status": "failed: " + (out.stderr.strip().splitlines() or ["?"])[-1]}
    return dict(json.loads(out.stdout.strip().splitlines()[-1]), status="ok")


def table(rows: list) -> str:
    lines = ["| segments | states | residual and matrix | solver | build s | step build s | "
             "compile s (level) | us per step | Newton per step |",
             "|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        if r["status"] != "ok":
            lines.append(f"| {r['segments']} | | {r['way']} | {r['status']} | | | | | |")
            continue
        way = "element loops" if r["elements"] else "written out (SX)"
        comp = f"{r['compile_s']:.1f} ({r['level']})" if r["compiled"] else "(VM)"
        lines.append(f"| {r['segments']} | {r['states']} | {way} | {r['solver']} | "
                     f"{r['build_s']:.2f} | {r['step_build_s']:.2f} | {comp} | "
                     f"{r['us_per_step']:.0f} | {r['newton_per_step']:.2f} |")
    return "\n".join(lines) + "\n"


def plot(rows: list, path: Path) -> None:
    """Two log-log panels against the segments, both ways: the step's cost per Newton
    iteration (us) and its build and compile time (s), each with a slope-1 reference."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np

    fig, axes = plt.subplots(1, 2, figsize=(11, 4.5))
    for way, style in (("elements", "o-"), ("written", "s--")):
        rs = [r for r in rows if r["way"] == way and r["status"] == "ok"]
        if not rs:
            continue
        name = "element loops" if way == "elements" else "written out (SX)"
        N = np.array([r["segments"] for r in rs], float)
        per_it = np.array([r["us_per_step"] / r["newton_per_step"] for r in rs])
        axes[0].loglog(N, per_it, style, label=name)
        for key, what in (("compile_s", "compile"), ("step_build_s", "step build")):
            v = np.array([r[key] for r in rs], float)
            if np.all(np.isfinite(v)):
                axes[1].loglog(N, v, style, label=f"{what}, {name}")
        if way == "elements":
            axes[0].loglog(N, per_it[0] * N / N[0], ":", color="k", label="slope 1")
    axes[0].set_ylabel("CPU us per Newton iteration (C)")
    axes[0].set_title("the step's cost (WD0600 chain, A1 heave, dt 0.1 s)")
    axes[1].set_ylabel("s (written out: block LU in SX to 1000 states, banded above)")
    axes[1].set_title("building and compiling the step (fresh cache)")
    for ax in axes:
        ax.set_xlabel("segments N")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8, loc="upper left")
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def main(argv=None) -> dict:
    def extra(ap):
        ap.add_argument("--sizes", type=str, default=None, help="comma-separated segment counts")
        ap.add_argument("--written-max", type=int, default=200,
                        help="largest N run with the matrix written out (its compile grows fast)")
    args = parse(__doc__, "N = 40 in the VM, 20 steps", HERE / "out", argv, extra)
    sizes = QUICK if args.quick else SIZES
    if args.sizes:
        sizes = tuple(int(s) for s in args.sizes.split(","))
    rows = []
    for n in sizes:
        for way in WAYS:
            if way == "written" and n > args.written_max:
                continue
            rows.append(_in_fresh_process(n, way, not args.quick, 20 if args.quick else 100))
            print(table(rows[-1:]).splitlines()[-1], flush=True)
    keys = sorted({k for r in rows for k in r})  # a stopped or failed row has fewer
    rows = [{k: r.get(k) for k in keys} for r in rows]
    plot(rows, args.out / "scaling3d.png")
    if args.figure is not None:
        plot(rows, args.figure)
    # named after the study: studies/performance/out holds the other scripts' tables too
    write_tables(args.out, rows, table(rows), ("scaling3d", "scaling3d"))
    return {"quick": args.quick, "rows": rows}


if __name__ == "__main__":
    main()
