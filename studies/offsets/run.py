"""Offset-restoring curves of a moored body: symcable's batched sweep against MoorPy.

Question
--------
``sc.offset_sweep`` (symcable/api/offsets.py) gives the restoring force and moment of a body's
lines over a sweep of prescribed offsets in one batched call of the static solve's fused
Newton (one sparsity pattern, one compiled function, each offset warm-started from its
neighbour's solution by a tangent predictor). How close are its forces to MoorPy's exact
elastic catenaries, how fast is it per offset against MoorPy doing the same sweep (the body
moved, each line's ``staticSolve``, ``getForces``), and how does its cost grow with the
number of offsets and of segments?

System
------
The OC3 spar's three catenary chains (layout.py: 320 m depth, 902.2 m of chain each, part
of it on the seabed) on a body held at the origin (``about = "scene"``: the lines' force
alone, MoorPy's ``lines_only``). Sweeps: surge -20..20 m, heave -5..5 m, pitch -10..10 deg,
yaw -10..10 deg, 41 offsets each (--quick: surge and pitch, 11 offsets).

Method
------
1. Accuracy: each sweep at ``SEGMENTS`` per line (virtual machine: the answers are the
   compiled code's to round-off), the largest difference from MoorPy over the offsets,
   per force component relative to that component's largest |value| in the sweep (the
   components that are not zero by symmetry: above 1e-3 of the largest force).
2. Speed: the surge sweep ``REPEATS`` times for each segment count in ``TIMED``, in the
   generated C (cached build; the compile, once per model structure, is reported apart)
   and in the virtual machine, and MoorPy's loop, the order rotated each repeat. Per
   offset: the batched call alone (``stats["batch_time"] / n``) and the whole call
   (``stats["wall_time"] / n``: the scene read, its Mechanism looked up, the base solved,
   the stiffness, the outputs). Speed-up = median MoorPy time per offset over symcable's
   median (ratio of medians).
3. Cost against the number of offsets: the surge range with ``COUNTS`` offsets at 20
   segments (generated C), the batch time per offset.

Run
---
    python studies/offsets/run.py            # full: a few minutes once compiled
    python studies/offsets/run.py --quick    # 10 segments, virtual machine, once
    options: --out DIR (default studies/offsets/out/), --figure PATH

Writes ``results.csv`` (one row per measurement), ``summary.md`` and ``offsets.png``;
``main(argv)`` returns ``{"rows": ..., "summary": ...}``.
"""
from __future__ import annotations

import statistics
import sys
import time
from pathlib import Path
from typing import NamedTuple

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(1, str(HERE.parent))
import study_io  # noqa: E402

layout = study_io.load_module(HERE / "layout.py", "offsets_layout")


class Setup(NamedTuple):
    segments: tuple      # accuracy against MoorPy
    timed: tuple         # speed (segments)
    compiled: tuple      # of those, also in generated C
    dofs: dict           # name -> half range (m or deg)
    n: int               # offsets per sweep
    counts: tuple        # numbers of offsets for the cost
    repeats: int


FULL = Setup((10, 20, 40, 80), (10, 20, 40, 80), (10, 20, 80),
             {"surge": 20.0, "heave": 5.0, "pitch": 10.0, "yaw": 10.0}, 41, (11, 41, 161), 5)
QUICK = Setup((10,), (10,), (), {"surge": 20.0, "pitch": 10.0}, 11, (5, 11), 1)


def _moorpy(offsets) -> np.ndarray:
    ms, body = layout.moorpy_system()
    return np.array([layout.moorpy_offset(ms, body, o) for o in offsets])


def accuracy(setup: Setup) -> tuple[list, dict]:
    import symcable as sc

    rows, curves = [], {}
    for dof, half in setup.dofs.items():
        offs = sc.offsets_along(dof, -half, half, setup.n)
        ref = _moorpy(offs)
        scale = np.max(np.abs(ref), axis=0)
        big = scale > 1e-3 * np.max(scale[:3])
        for n in setup.segments:
            r = sc.offset_sweep(layout.scene(n), "spar", offs, about="scene", codegen=False)
            err = np.max(np.abs(r.line_force - ref)[:, big] / scale[big])
            rows.append({"measure": "accuracy", "dof": dof, "segments": n, "offsets": len(offs),
                         "max_rel_error": float(err), "converged": int(r.converged.sum()),
                         "fallbacks": r.stats["fallbacks"],
                         "mean_iterations": float(np.mean(r.iterations))})
            if n == setup.segments[min(1, len(setup.segments) - 1)]:
                curves[dof] = (r, ref)
    return rows, curves


def _sweep_time(n_seg: int, offs, codegen: bool) -> tuple[float, float]:
    import symcable as sc

    r = sc.offset_sweep(layout.scene(n_seg), "spar", offs, about="scene", codegen=codegen)
    assert r.converged.all()
    return r.stats["batch_time"] / len(offs), r.stats["wall_time"] / len(offs)


def speed(setup: Setup) -> list:
    import symcable as sc

    offs = sc.offsets_along("surge", -setup.dofs["surge"], setup.dofs["surge"], setup.n)
    rows = []
    ms, body = layout.moorpy_system()
    for n_seg in setup.timed:
        backends = ["vm"] + (["c"] if n_seg in setup.compiled else [])
        first = {}
        for b in backends:  # warm-up (and the compile, once per structure)
            t0 = time.perf_counter()
            _sweep_time(n_seg, offs, b == "c")
            first[b] = time.perf_counter() - t0
        times = {b: [] for b in backends + ["moorpy"]}
        order = backends + ["moorpy"]
        for k in range(setup.repeats):
            for who in order[k % len(order):] + order[:k % len(order)]:
                if who == "moorpy":
                    t0 = time.perf_counter()
                    for o in offs:
                        layout.moorpy_offset(ms, body, o)
                    times[who].append(((time.perf_counter() - t0) / len(offs), 0.0))
                else:
                    times[who].append(_sweep_time(n_seg, offs, who == "c"))
        mp = statistics.median(t for t, _ in times["moorpy"])
        for b in backends:
            batch = statistics.median(t for t, _ in times[b])
            whole = statistics.median(w for _, w in times[b])
            rows.append({"measure": "speed", "segments": n_seg, "backend": b,
                         "offsets": len(offs), "repeats": setup.repeats,
                         "batch_ms_per_offset": 1e3 * batch, "call_ms_per_offset": 1e3 * whole,
                         "moorpy_ms_per_offset": 1e3 * mp, "speedup_batch": mp / batch,
                         "speedup_call": mp / whole, "first_call_s": first[b]})
    return rows


def cost(setup: Setup) -> list:
    import symcable as sc

    codegen = 20 in setup.compiled
    n_seg = 20 if codegen else setup.timed[0]
    rows = []
    for count in setup.counts:
        offs = sc.offsets_along("surge", -setup.dofs["surge"], setup.dofs["surge"], count)
        _sweep_time(n_seg, offs, codegen)  # (its mapaccum built)
        ts = [_sweep_time(n_seg, offs, codegen) for _ in range(setup.repeats)]
        rows.append({"measure": "cost", "segments": n_seg, "backend": "c" if codegen else "vm",
                     "offsets": count, "batch_ms_per_offset": 1e3 * statistics.median(
                         t for t, _ in ts),
                     "call_ms_per_offset": 1e3 * statistics.median(w for _, w in ts)})
    return rows


def summary(rows: list, quick: bool) -> str:
    out = ["# Offset sweep of the OC3 lines: symcable against MoorPy" + (" (--quick)" if quick
                                                                         else ""), "",
           "## Accuracy (largest difference over the sweep, per component relative to its "
           "largest value)", "", "| dof | segments | offsets | max rel. error | fallbacks | "
           "mean Newton its |", "|---|---|---|---|---|---|"]
    for r in rows:
        if r["measure"] == "accuracy":
            out.append(f"| {r['dof']} | {r['segments']} | {r['offsets']} | "
                       f"{100 * r['max_rel_error']:.3g} % | {r['fallbacks']} | "
                       f"{r['mean_iterations']:.2f} |")
    out += ["", "## Time per offset (surge sweep; medians)", "",
            "| segments | backend | batch ms | whole call ms | MoorPy ms | MoorPy / batch | "
            "MoorPy / call | first call s |", "|---|---|---|---|---|---|---|---|"]
    for r in rows:
        if r["measure"] == "speed":
            out.append(f"| {r['segments']} | {r['backend']} | {r['batch_ms_per_offset']:.3g} | "
                       f"{r['call_ms_per_offset']:.3g} | {r['moorpy_ms_per_offset']:.3g} | "
                       f"{r['speedup_batch']:.3g} | {r['speedup_call']:.3g} | "
                       f"{r['first_call_s']:.3g} |")
    out += ["", "## Cost against the number of offsets", "",
            "| segments | backend | offsets | batch ms per offset | whole call ms per offset |",
            "|---|---|---|---|---|"]
    for r in rows:
        if r["measure"] == "cost":
            out.append(f"| {r['segments']} | {r['backend']} | {r['offsets']} | "
                       f"{r['batch_ms_per_offset']:.3g} | {r['call_ms_per_offset']:.3g} |")
    return "\n".join(out) + "\n"


def plot(rows: list, curves: dict, path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(2, 2, figsize=(11, 8))
    for a, (dof, k, unit) in zip(ax[0], (("surge", 0, "kN"), ("pitch", 4, "MN m"))):
        if dof not in curves:
            continue
        r, ref = curves[dof]
        j = r.dof()
        s = 1e3 if k < 3 else 1e6
        x = r.offsets[:, j]
        a.plot(x, r.line_force[:, k] / s, "-", label="symcable (batched static solves)")
        a.plot(x, ref[:, k] / s, "o", ms=3, mfc="none", label="MoorPy")
        a.plot(x, (r.line_force[np.argmin(np.abs(x)), k] + r.tangent[:, k]) / s, "--",
               color="0.4", label="linear stiffness (exact, at 0)")
        a.set_xlabel(f"{dof} ({'m' if j < 3 else 'deg'})")
        a.set_ylabel(f"{'Fx' if k == 0 else 'My'} of the lines ({unit})")
        a.grid(alpha=0.3)
        a.legend(fontsize=8)
    acc = [r for r in rows if r["measure"] == "accuracy"]
    for dof in dict.fromkeys(r["dof"] for r in acc):
        sub = [r for r in acc if r["dof"] == dof]
        ax[1, 0].loglog([r["segments"] for r in sub], [r["max_rel_error"] for r in sub], "o-",
                        label=dof)
    ax[1, 0].set_xlabel("segments per line")
    ax[1, 0].set_ylabel("largest difference from MoorPy (relative)")
    ax[1, 0].grid(alpha=0.3, which="both")
    ax[1, 0].legend(fontsize=8)
    sp = [r for r in rows if r["measure"] == "speed"]
    for b, style in (("c", "o-"), ("vm", "s--")):
        sub = [r for r in sp if r["backend"] == b]
        if sub:
            ax[1, 1].loglog([r["segments"] for r in sub], [r["batch_ms_per_offset"] for r in sub],
                            style, label=f"symcable {b.upper()}, batched call")
            ax[1, 1].loglog([r["segments"] for r in sub], [r["call_ms_per_offset"] for r in sub],
                            style, alpha=0.4, label=f"symcable {b.upper()}, whole call")
    vm = [r for r in sp if r["backend"] == "vm"]
    ax[1, 1].loglog([r["segments"] for r in vm], [r["moorpy_ms_per_offset"] for r in vm], "k^-",
                    label="MoorPy (catenaries)")
    ax[1, 1].set_xlabel("segments per line")
    ax[1, 1].set_ylabel("time per offset (ms, median)")
    ax[1, 1].grid(alpha=0.3, which="both")
    ax[1, 1].legend(fontsize=8)
    fig.suptitle("OC3 lines: restoring force over offsets, symcable vs MoorPy")
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def main(argv=None) -> dict:
    args = study_io.parse(__doc__, "10 segments, virtual machine, once", HERE / "out", argv)
    setup = QUICK if args.quick else FULL
    rows, curves = accuracy(setup)
    rows += speed(setup)
    rows += cost(setup)
    text = summary(rows, args.quick)
    keys = list(dict.fromkeys(k for r in rows for k in r))
    table = [{k: r.get(k, "") for k in keys} for r in rows]
    study_io.write(args, table, text, lambda path: plot(rows, curves, path), "offsets.png")
    return {"rows": rows, "summary": text}


if __name__ == "__main__":
    main()
