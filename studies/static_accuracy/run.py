"""Static accuracy and speed of symcable against the closed-form elastic catenary and MoorPy.

Question
--------
How accurate are symcable's static end tensions against the closed-form elastic catenary
(:func:`symcable.analytic.elastic_catenary`) as the number of segments grows, what order of
convergence is measured, how many Newton iterations does the solve need, and how does its run
time compare with MoorPy's catenary (``moorpy.Catenary.catenary``) on the same line?

Three single-section, pinned-pinned lines: ``taut`` (0.8 % strain, suspended), ``slack``
(deep sag, suspended) and ``seabed`` (the OC3 line on a stiff 1e8 Pa/m seabed, compared with
the closed form with a frictionless seabed), at 10 ... 320 segments. Then the headline: the
OC3 line as ``symcable/data/oc3.toml`` gives it (1e5 Pa/m seabed, 50 segments) against MoorPy (CB = 0).

Timing: median of R repeats of ``solve_static`` with a pre-built model, interleaved with the
same number of MoorPy calls on the same line (so machine noise hits both); the one-time cost
(``build_model`` plus the first solve, which builds the CasADi functions) is
measured once and reported in its own column.

Run
---
    python studies/static_accuracy/run.py            # full: 10..320 segments, R = 15
    python studies/static_accuracy/run.py --quick    # 10, 20, 40 segments, R = 3
    options: --out DIR (default studies/static_accuracy/out/), --figure PATH (extra copy)

Writes to the out dir: ``results.csv`` (one row per line x segments, units in the column
names), ``summary.md`` (the table, the observed orders and the OC3 headline) and
``convergence.png`` (error and solve time against segments).
"""
from __future__ import annotations

import copy
import math
import statistics
import sys
import time
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib import ticker  # noqa: E402
import numpy as np  # noqa: E402
from moorpy.Catenary import catenary  # noqa: E402

import symcable as sc  # noqa: E402
from symcable.analytic import elastic_catenary  # noqa: E402

HERE = Path(__file__).resolve().parent
if str(HERE.parent) not in sys.path:
    sys.path.append(str(HERE.parent))
import study_io  # noqa: E402  (studies/study_io.py)
SEGMENTS_FULL, SEGMENTS_QUICK = (10, 20, 40, 80, 160, 320), (10, 20, 40)
REPEATS_FULL, REPEATS_QUICK = 15, 3
NO_SEABED = -1e3  # MoorPy: CB < 0 means no seabed contact, seabed |CB| m below end A

# the OC3-Hywind line of symcable/data/oc3.toml (anchor on the seabed at z = -depth)
OC3 = {
    "name": "OC3 line",
    "model": "planar",
    "environment": {"water_density": 1025.0, "depth": 320.0},
    "seabed": {"stiffness": 1.0e5},
    "line_types": {"chain": {"EA": 3.84243e8, "mass": 77.7066, "diameter": 0.09,
                             "weight": 698.094, "cd_normal": 1.6, "cd_tangential": 0.1}},
    "sections": [{"type": "chain", "length": 902.2, "segments": 50}],
    "end_a": {"condition": "pinned", "position": [-853.87, -320.0]},
    "end_b": {"condition": "pinned", "position": [-5.2, -70.0]},
}
OC3_GEOM = dict(span=848.67, height=250.0, L=902.2, EA=3.84243e8, w=698.094)

# (span m, height of B above A m, unstretched length m, EA N, submerged weight N/m)
LINES = {
    "taut": dict(span=100.5, height=5.0, L=100.0, EA=3e6, w=50.0, seabed=False),
    "slack": dict(span=60.0, height=10.0, L=100.0, EA=1e8, w=100.0, seabed=False),
    "seabed": dict(**OC3_GEOM, seabed=True),
}


def scene_dict(name: str, g: dict, segments: int) -> dict:
    """Scene dict of one study line with ``segments`` segments."""
    if g["seabed"]:
        d = copy.deepcopy(OC3)
        d["seabed"]["stiffness"] = 1e8  # stiff: ~1 mm penetration, close to the rigid closed form
    else:
        d = {"environment": {"water_density": 1025.0},
             "line_types": {"rope": {"EA": g["EA"], "mass": 20.0, "diameter": 0.05,
                                     "weight": g["w"]}},
             "sections": [{"type": "rope", "length": g["L"]}],
             "end_a": {"condition": "pinned", "position": [0.0, 0.0]},
             "end_b": {"condition": "pinned", "position": [g["span"], g["height"]]}}
    d["name"] = f"static accuracy: {name}"
    d["sections"][0]["segments"] = segments
    return d


def moorpy_call(g: dict, nodes: int):
    """MoorPy's catenary on the line: (fairlead tension N, anchor tension N, info)."""
    fAH, fAV, fBH, fBV, info = catenary(g["span"], g["height"], g["L"], g["EA"], g["w"],
                                        CB=0.0 if g["seabed"] else NO_SEABED, nNodes=nodes)
    return math.hypot(fBH, fBV), math.hypot(fAH, fAV), info


def timed_pair(scene, model, g: dict, nodes: int, repeats: int):
    """Interleaved repeats: medians (ms) of symcable's solve and MoorPy's catenary, last results."""
    t_sc, t_mp = [], []
    for _ in range(repeats):
        t0 = time.perf_counter()
        sol = sc.solve_static(scene, model=model)
        t1 = time.perf_counter()
        mp = moorpy_call(g, nodes)
        t2 = time.perf_counter()
        t_sc.append(t1 - t0)
        t_mp.append(t2 - t1)
    return 1e3 * statistics.median(t_sc), 1e3 * statistics.median(t_mp), sol, mp


def run_line(name: str, g: dict, segments: int, repeats: int) -> dict:
    ref = elastic_catenary(g["span"], g["height"], g["L"], g["EA"], g["w"], seabed=g["seabed"])
    scene = sc.load_scene(scene_dict(name, g, segments))
    t0 = time.perf_counter()
    model = sc.build_model(scene)
    first = sc.solve_static(scene, model=model)  # builds the CasADi functions: one-time cost
    build_ms = 1e3 * (time.perf_counter() - t0)
    t_sc, t_mp, sol, (tf_mp, ta_mp, _) = timed_pair(scene, model, g, segments + 1, repeats)
    assert sol.status == "converged" and first.status == "converged"
    return {
        "line": name,
        "segments": segments,
        "unknowns": sol.stats["unknowns"],
        "fairlead_tension_ref_N": ref.fairlead_tension,
        "fairlead_tension_N": sol.fairlead_tension,
        "fairlead_rel_err": sol.fairlead_tension / ref.fairlead_tension - 1.0,
        "anchor_rel_err": sol.anchor_tension / ref.anchor_tension - 1.0,
        "moorpy_fairlead_rel_err": tf_mp / ref.fairlead_tension - 1.0,
        "moorpy_anchor_rel_err": ta_mp / ref.anchor_tension - 1.0,
        "grounded_length_err_m": sol.grounded_length - ref.grounded_length,
        "newton_iterations": sol.stats["iterations"],
        "path": sol.stats["path"],
        "build_ms": build_ms,
        "symcable_solve_ms": t_sc,
        "moorpy_ms": t_mp,
        "time_ratio": t_sc / t_mp,
    }


def observed_orders(rows: list, line: str) -> list:
    """log2(|e_n| / |e_2n|) of the fairlead-tension error between successive segment counts."""
    e = [abs(r["fairlead_rel_err"]) for r in rows if r["line"] == line]
    return [math.log2(a / b) for a, b in zip(e[:-1], e[1:])]


def oc3_headline(repeats: int) -> dict:
    """The OC3 line of symcable/data/oc3.toml (1e5 Pa/m seabed, 50 segments) against MoorPy (CB = 0)."""
    scene = sc.load_scene(OC3)
    model = sc.build_model(scene)
    sc.solve_static(scene, model=model)  # warm up: build the functions outside the timing
    g = dict(OC3_GEOM, seabed=True)
    t_sc, t_mp, sol, (tf_mp, _, info) = timed_pair(scene, model, g, 51, repeats)
    return {
        "segments": 50,
        "fairlead_tension_N": sol.fairlead_tension,
        "moorpy_fairlead_tension_N": tf_mp,
        "fairlead_rel_diff": sol.fairlead_tension / tf_mp - 1.0,
        "grounded_length_m": sol.grounded_length,
        "moorpy_grounded_length_m": float(info["LBot"]),
        "grounded_rel_diff": sol.grounded_length / float(info["LBot"]) - 1.0,
        "newton_iterations": sol.stats["iterations"],
        "symcable_solve_ms": t_sc,
        "moorpy_ms": t_mp,
        "time_ratio": t_sc / t_mp,
    }


COLUMNS = [  # (csv key, markdown header, format)
    ("line", "line", "{}"), ("segments", "segments", "{}"), ("unknowns", "unknowns", "{}"),
    ("fairlead_tension_N", "T_fair (N)", "{:.6g}"),
    ("fairlead_rel_err", "T_fair rel. err", "{:.2e}"),
    ("anchor_rel_err", "T_anch rel. err", "{:.2e}"),
    ("moorpy_fairlead_rel_err", "MoorPy T_fair rel. err", "{:.1e}"),
    ("newton_iterations", "Newton it.", "{}"), ("path", "path", "{}"),
    ("build_ms", "build (ms)", "{:.1f}"),
    ("symcable_solve_ms", "symcable solve (ms)", "{:.3f}"),
    ("moorpy_ms", "MoorPy (ms)", "{:.3f}"), ("time_ratio", "ratio symcable/MoorPy", "{:.2f}"),
]


def summary_markdown(res: dict) -> str:
    k_seabed = scene_dict("seabed", LINES["seabed"], 10)["seabed"]["stiffness"]
    lines = [f"Lines: taut, slack (suspended) and seabed (the OC3 line on a {k_seabed:.0e} Pa/m "
             "seabed; the OC3 headline below uses the built-in OC3 scene's "
             f"{OC3['seabed']['stiffness']:.0e} Pa/m).".replace("e+0", "e"), "",
             "| " + " | ".join(h for _, h, _ in COLUMNS) + " |",
             "|" + "|".join("---" for _ in COLUMNS) + "|"]
    for r in res["rows"]:
        lines.append("| " + " | ".join(f.format(r[k]) for k, _, f in COLUMNS) + " |")
    lines += ["", "Observed order of the fairlead-tension error, log2(e_n / e_2n), "
              "between successive segment counts:", ""]
    for name, orders in res["orders"].items():
        lines.append(f"- {name}: " + ", ".join(f"{o:.2f}" for o in orders))
    h = res["oc3"]
    lines += ["", "OC3 headline (symcable/data/oc3.toml: seabed 1e5 Pa/m, 50 segments = 51 nodes; "
              "MoorPy CB = 0, nNodes = 51):", "",
              "| quantity | symcable | MoorPy | difference |", "|---|---|---|---|",
              f"| fairlead tension (N) | {h['fairlead_tension_N']:.6g} | "
              f"{h['moorpy_fairlead_tension_N']:.6g} | {100 * h['fairlead_rel_diff']:+.3f} % |",
              f"| grounded length (m) | {h['grounded_length_m']:.2f} | "
              f"{h['moorpy_grounded_length_m']:.2f} | {100 * h['grounded_rel_diff']:+.2f} % |",
              f"| solve time, median of {res['repeats']} (ms) | {h['symcable_solve_ms']:.3f} | "
              f"{h['moorpy_ms']:.3f} | ratio {h['time_ratio']:.2f} |",
              "", f"Newton iterations on the OC3 line: {h['newton_iterations']}."]
    return "\n".join(lines) + "\n"


def plot(res: dict, path: Path) -> None:
    rows = res["rows"]
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 4.5), constrained_layout=True)
    colors = dict(zip(LINES, ("C0", "C1", "C2")))
    # the seabed line's stiffness as its scene has it (the OC3 headline uses the built-in OC3 scene's 1e5)
    k_seabed = scene_dict("seabed", LINES["seabed"], 10)["seabed"]["stiffness"]
    labels = {"taut": "taut (0.8 % strain)", "slack": "slack (deep sag)",
              "seabed": f"seabed: OC3 line on a {k_seabed:.0e} Pa/m seabed".replace("e+0", "e")}
    for name in LINES:
        rr = [r for r in rows if r["line"] == name]
        n = np.array([r["segments"] for r in rr])
        ax1.loglog(n, [abs(r["fairlead_rel_err"]) for r in rr], "o-", color=colors[name],
                   label=labels[name])
        ax2.loglog(n, [r["symcable_solve_ms"] for r in rr], "o-", color=colors[name],
                   label=f"symcable, {name}")
        ax2.loglog(n, [r["moorpy_ms"] for r in rr], "s--", color=colors[name], alpha=0.7,
                   label=f"MoorPy, {name}")
    n = np.array(res["segments"], dtype=float)
    e0 = max(abs(r["fairlead_rel_err"]) for r in rows if r["segments"] == n[0])
    ax1.loglog(n, 2 * e0 * (n / n[0]) ** -2.0, "k:", label="slope -2 (reference)")
    ax1.set(xlabel="segments N (-)", ylabel="|relative error| of fairlead tension (-)",
            title="Error against the closed-form elastic catenary")
    ax2.set(xlabel="segments N (-)", ylabel=f"solve time, median of {res['repeats']} (ms)",
            title="Static solve time (pre-built model) vs MoorPy catenary")
    ax2.yaxis.set_major_formatter(ticker.FormatStrFormatter("%g"))
    ax2.yaxis.set_minor_formatter(ticker.FormatStrFormatter("%g"))
    for ax in (ax1, ax2):
        ax.set_xticks(n)
        ax.xaxis.set_major_formatter(ticker.FormatStrFormatter("%d"))
        ax.xaxis.set_minor_locator(ticker.NullLocator())
        ax.grid(True, which="both", alpha=0.3)
    ax1.legend(fontsize=8, loc="lower left")  # below the slope reference, left of the data
    ax2.legend(fontsize=8, loc="upper left")
    fig.suptitle("symcable statics: accuracy and speed")
    fig.savefig(path, dpi=150)
    plt.close(fig)


def main(argv=None) -> dict:
    args = study_io.parse(__doc__, "10, 20, 40 segments and 3 repeats", HERE / "out", argv)
    segments = SEGMENTS_QUICK if args.quick else SEGMENTS_FULL
    repeats = REPEATS_QUICK if args.quick else REPEATS_FULL
    rows = [run_line(name, g, n, repeats) for name, g in LINES.items() for n in segments]
    res = {"segments": list(segments), "repeats": repeats, "rows": rows,
           "orders": {name: observed_orders(rows, name) for name in LINES},
           "oc3": oc3_headline(repeats), "out": str(args.out)}
    study_io.write(args, rows, summary_markdown(res), lambda path: plot(res, path),
                   "convergence.png")
    return res

if __name__ == "__main__":
    main()
