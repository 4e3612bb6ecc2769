"""Scaling: cost of statics and of one generalized-alpha time step against the number of
segments, 50 to 10,000.

Question: does each stage cost O(N) (near-linear), and is a 10,000-segment line solved
statically in seconds?

Every N runs in a fresh process (so peak memory is that run's alone, ``ru_maxrss``) with a
fresh build cache, in two parts:

* ``static``: the OC3 line (seabed contact) with N segments: ``build_model`` (symbolic
  build), the statics Mechanism's static solver (``static_mechanism`` and
  ``functions(mech).static_solver``: the Functions: Jacobian, Newton step, fused solve),
  generated C when the default (``codegen=None``) compiles it (compile time), the first
  ``solve_static`` on the built model and a second one (solve time), and the fairlead
  tension;
* ``step``: the seed-001 line (suspended, current, moving fairlead) with N segments: its
  static solve (the default path), ``build_dynamic_model``, the generalized-alpha step
  Function (``step_function``, default codegen) and one step from rest (first call, then a
  second call of the same step).

Which stage each N uses (block LU in SX or sparse QR, VM or C) is the library's own default
choice, recorded in the table. Writes ``scaling.csv``, ``scaling.md`` and ``scaling.png``
(log-log, with a slope-1 reference) to the output folder.

Run ``python studies/performance/scaling.py [--quick] [--out DIR] [--sizes 50,200,...]``;
``--quick`` runs N = 50 and 200 only.
"""
from __future__ import annotations

import argparse
import csv
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
SIZES = (50, 200, 500, 2000, 10000)
QUICK = (50, 200)
#: a part that runs longer than this (s) is stopped and recorded as such
TIMEOUT = 900


def _scene(name: str, n: int):
    import tomllib

    import symcable as sc
    with open(sc.demo_scene_path(name), "rb") as fh:
        d = tomllib.load(fh)
    d["sections"][0]["segments"] = n
    return sc.load_scene(d)


def _peak_mb() -> float:
    import resource
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


def run_static(n: int) -> dict:
    """One process: the static stages of the OC3 line with n segments."""
    import symcable as sc
    from symcable.mechanism.functions import functions as derived
    from symcable.models.planar.static import static_mechanism

    clock = time.perf_counter
    scene = _scene("oc3", n)
    t = clock()
    model = sc.build_model(scene)
    build = clock() - t
    t = clock()
    F = derived(static_mechanism(model))
    F.static_solver(False)
    functions = clock() - t
    t = clock()
    fns = F.static_solver(None)
    compiled = fns.compiled
    compile_s = clock() - t if compiled else 0.0
    t = clock()
    sol = sc.solve_static(scene, model=model)
    first = clock() - t
    t = clock()
    sol = sc.solve_static(scene, model=model)
    second = clock() - t
    return {"part": "static", "N": n, "unknowns": model.n_w, "build_s": build,
            "functions_s": functions, "compile_s": compile_s, "compiled": bool(fns.compiled),
            "linear_solver": "block LU (SX)" if _uses_sxlu(model) else "sparse QR",
            "solve_first_s": first, "solve_s": second, "iterations": sol.stats["iterations"],
            "path": sol.stats["path"], "fairlead_tension_N": sol.fairlead_tension,
            "peak_mb": _peak_mb()}


def _uses_sxlu(model) -> bool:
    from symcable.mechanism.static_functions import SXLU_MAX_UNKNOWNS
    return model.n_w <= SXLU_MAX_UNKNOWNS


def run_step(n: int) -> dict:
    """One process: one generalized-alpha step of the seed-001 line with n segments (the
    first-order step of ``simulate`` on the dynamics Mechanism)."""
    import numpy as np

    import symcable as sc
    from symcable.models.planar.mechanism import mechanism_of, state_permutation
    from symcable.api.planar_time import NEWTON_MAX_ITER
    from symcable.solvers.galpha1 import SXLU_MAX_STATES, galpha1_kernel, step_scales
    from symcable.solvers.integrate import start_rates
    from symcable.solvers.options import GeneralizedAlphaFirstOrder

    clock = time.perf_counter
    scene = _scene("seed001", n)
    t = clock()
    static = sc.solve_static(scene)
    static_s = clock() - t
    t = clock()
    dyn = sc.build_dynamic_model(scene, static=static)
    mech = mechanism_of(dyn)
    build = clock() - t
    opts = GeneralizedAlphaFirstOrder(rho_inf=0.5, max_iter=NEWTON_MAX_ITER)
    t = clock()
    vm = galpha1_kernel(mech, opts, codegen=False)
    functions = clock() - t
    t = clock()
    step = galpha1_kernel(mech, opts, codegen=None)
    compiled = bool(step.is_a("External"))
    compile_s = clock() - t if compiled else 0.0
    p = dyn.p_value
    iq, iv = state_permutation(dyn)
    y0 = np.asarray(dyn.y0, dtype=float)
    x = np.concatenate([y0[iq], y0[iv], *start_rates(mech, y0[iq], y0[iv], 0.0, p)])
    args = (x, 0.0, dyn.period / 100.0, p, [0.5, 1e-10], step_scales(mech))
    t = clock()
    out = step(*args)
    first = clock() - t
    t = clock()
    out = step(*args)
    second = clock() - t
    n_y = mech.n_q + mech.n_v
    return {"part": "step", "N": n, "unknowns": n_y, "static_s": static_s, "build_s": build,
            "functions_s": functions, "compile_s": compile_s, "compiled": compiled,
            "linear_solver": "block LU (SX)" if n_y <= SXLU_MAX_STATES else "sparse QR",
            "solve_first_s": first, "solve_s": second,
            "iterations": int(float(out[3])), "failed": bool(float(out[4])),
            "peak_mb": _peak_mb(), "vm_instructions": vm.n_instructions()}


def _child(part: str, n: int, timeout: float) -> dict:
    """Run one part for one N in a fresh process with a fresh build cache."""
    env = dict(os.environ)
    env.pop("SYMCABLE_CODEGEN", None)  # the library's own default
    with tempfile.TemporaryDirectory(prefix="symcable-scaling-") as cache:
        env["SYMCABLE_CACHE_DIR"] = cache
        cmd = [sys.executable, str(Path(__file__).resolve()), "--child", part, str(n)]
        t = time.perf_counter()
        try:
            proc = subprocess.run(cmd, capture_output=True, text=True, env=env, timeout=timeout)
        except subprocess.TimeoutExpired:
            return {"part": part, "N": n, "error": f"stopped after {timeout:.0f} s"}
        wall = time.perf_counter() - t
    lines = [ln for ln in proc.stdout.splitlines() if ln.startswith("{")]
    if proc.returncode != 0 or not lines:
        tail = " | ".join(proc.stderr.strip().splitlines()[-2:])
        return {"part": part, "N": n, "error": f"exit {proc.returncode}: {tail}"}
    row = json.loads(lines[-1])
    row["process_s"] = wall
    return row


def _slope(rows, key) -> float | None:
    """Log-log slope of ``key`` against N between the two largest N (None if not positive)."""
    import math
    pts = [(r["N"], r[key]) for r in rows if r.get(key, 0) > 0]
    if len(pts) < 2:
        return None
    (n0, v0), (n1, v1) = pts[-2], pts[-1]
    return math.log(v1 / v0) / math.log(n1 / n0)


def _fmt(v, digits=3):
    if v is None:
        return "-"
    if isinstance(v, bool):
        return "C" if v else "VM"
    if isinstance(v, float):
        return f"{v:.{digits}g}"
    return str(v)


def _table(rows, part) -> list[str]:
    rows = [r for r in rows if r["part"] == part and "error" not in r]
    head = ("| N | unknowns | build s | functions s | compile s | VM/C | linear solver | "
            "first solve s | solve s | peak MB |")
    if part == "step":
        head = head.replace("first solve s | solve s", "static s | first step s | step s")
    out = [head, "|" + "---|" * (head.count("|") - 1)]
    for r in rows:
        cells = [r["N"], r["unknowns"], r["build_s"], r["functions_s"], r["compile_s"],
                 r["compiled"], r["linear_solver"]]
        if part == "step":
            cells.append(r["static_s"])
        cells += [r["solve_first_s"], r["solve_s"], r["peak_mb"]]
        out.append("| " + " | ".join(_fmt(c) for c in cells) + " |")
    slopes = {k: _slope(rows, k) for k in ("build_s", "functions_s", "solve_s", "peak_mb")}
    out.append("")
    out.append("log-log slope between the two largest N: " + ", ".join(
        f"{k} {v:.2f}" for k, v in slopes.items() if v is not None))
    return out


def _plot(rows, path: Path) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np

    fig, axes = plt.subplots(1, 2, figsize=(11, 4.5), sharey=True)
    for ax, part, title in ((axes[0], "static", "statics (OC3 line)"),
                            (axes[1], "step", "one generalized-alpha step (seed-001 line)")):
        rs = [r for r in rows if r["part"] == part and "error" not in r]
        if not rs:
            continue
        N = np.array([r["N"] for r in rs], dtype=float)
        for key, label in (("build_s", "symbolic build"), ("functions_s", "Functions"),
                           ("compile_s", "compile (default)"), ("solve_first_s", "first solve"),
                           ("solve_s", "solve")):
            v = np.array([r.get(key, 0.0) for r in rs], dtype=float)
            ok = v > 0
            if np.any(ok):
                ax.loglog(N[ok], v[ok], "o-", label=label)
        mem = np.array([r["peak_mb"] for r in rs]) / 1000.0
        ax.loglog(N, mem, "s--", color="0.4", label="peak memory, GB")
        ref = N / N[0] * max(r["build_s"] for r in rs[:1])
        ax.loglog(N, ref, ":", color="k", label="slope 1")
        ax.set_xlabel("segments N")
        ax.set_title(title)
        ax.grid(True, which="both", alpha=0.3)
    axes[0].set_ylabel("s (memory: GB)")
    axes[1].legend(fontsize=8, loc="upper left")
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def main(argv=None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="N = 50 and 200 only")
    ap.add_argument("--sizes", help="comma-separated N (default 50,200,500,2000,10000)")
    ap.add_argument("--parts", default="static,step")
    ap.add_argument("--out", default=str(HERE / "out"))
    ap.add_argument("--timeout", type=float, default=TIMEOUT)
    ap.add_argument("--child", nargs=2, metavar=("PART", "N"), help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.child:
        part, n = args.child[0], int(args.child[1])
        row = run_static(n) if part == "static" else run_step(n)
        print(json.dumps(row))
        return row
    sizes = QUICK if args.quick else SIZES
    if args.sizes:
        sizes = tuple(int(s) for s in args.sizes.split(","))
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    rows = []
    for part in args.parts.split(","):
        for n in sizes:  # one process at a time: the machine is shared
            rows.append(_child(part, n, args.timeout))
    keys = sorted({k for r in rows for k in r})
    with open(out / "scaling.csv", "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=keys)
        w.writeheader()
        w.writerows(rows)
    md = ["# Scaling against segments", ""]
    for part, title in (("static", "Statics, OC3 line"), ("step", "One generalized-alpha step, seed-001 line")):
        if any(r["part"] == part for r in rows):
            md += [f"## {title}", ""] + _table(rows, part) + [""]
    errors = [r for r in rows if "error" in r]
    if errors:
        md += ["Not finished: " + "; ".join(f"{r['part']} N={r['N']}: {r['error']}" for r in errors), ""]
    (out / "scaling.md").write_text("\n".join(md) + "\n")
    _plot(rows, out / "scaling.png")
    return {"rows": rows, "out": out}


if __name__ == "__main__":
    main()
