"""Mooring design optimisation with exact gradients (issue 37, item 4).

The mooring (``layout.py``): a floating body's three studless R4 chains (``family =
"studless_chain"``) in 200 m of water, fairleads 5.2 m from its axis at -70 m, lines heading
180, 300 and 60 degrees. Per line three design variables: its chain's nominal diameter d
(0.05-0.16 m), its anchor's radius R (350-800 m) and its length, given as its excess s over
the anchor's horizontal distance from the fairlead (30-120 m; length = R - 5.2 m + s), so
that every design within the bounds can be built. Objective: the chains' mass in air.

Four load cases, the body held at a prescribed offset (a quasi-static mooring analysis):
``mean`` (no offset) and ``off0``, ``off1``, ``off2`` (30 m, 15 % of the depth, away from
each line's anchor in turn). Constraints in every case: each fairlead's tension at most half
its breaking load (``LINE.fairlead_utilisation <= 0.5``, a safety factor of 2), at least
20 m of each chain on the seabed (``LINE.grounded_length >= 20``: no anchor uplift); in each
offset case the lines pull the body back by at least 2 MN (``hull.horizontal_force >= 2e6``:
the offset under a 2 MN steady load from that direction is then at most 30 m); in ``mean``
the lines' net horizontal force is within 10 kN of zero (the mean position is an
equilibrium).

What is measured:
1. ``sc.optimize`` with exact gradients (the implicit function theorem) from 5 starts: the
   optimum's spread over the starts, iterations, static solves and wall time.
2. The same problem with central differences of whole solves (``gradients =
   "differences"``: what an optimiser around a black-box solver does) and the same SciPy
   optimiser, from the first start: ratios of solves and wall time.
3. The optimum checked by designs around it: each variable on a grid of +-0.25, 0.5, 1 and
   2 % of its range, and random designs within +-1 % of every range: none feasible is
   lighter.
4. The sensitivities at the optimum against Richardson-extrapolated central differences
   of whole solves, with their own error estimated.
5. The grounded length (from the fairlead's vertical force) against the static solution's
   own (its nodes on the seabed).
6. The optimum's hull moved as a vessel (``WAVE_MOTION``): the sensitivities of periodic
   statistics (tension ranges, the largest utilisation, a mean tension) against central
   differences of whole periodic solves (full runs only).

``python run.py`` (20 segments a line) writes ``results.json`` and ``design.png``
(``--periodic``: item 6 alone, at the optimum already in ``results.json``);
``--quick`` (8 segments, 2 starts, a smaller neighbourhood, no differences run) writes into
``out/``.
"""
from __future__ import annotations

import argparse
import json
import math
import sys
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
import layout  # noqa: E402

import symcable as sc  # noqa: E402
from symcable.api.optimize import _apply  # noqa: E402
from symcable.api.sensitivity import design_sensitivity, static_values  # noqa: E402

OFFSET, F_REQ, UTIL, GROUNDED, BALANCE = 30.0, 2.0e6, 0.5, 20.0, 1.0e4
#: the reference differences' static solves: residual tolerance, N (the default is 1e-9 of
#: the force scale, about 2e-3 N here; its noise over a step of 1e-4 is 1e-5 of a slope;
#: 1e-6 N is below what 20 segments reach in float64)
TIGHT = 1e-5
BOUNDS = {**{f"s{k}": (30.0, 120.0) for k in range(3)},
          **{f"d{k}": (0.05, 0.16) for k in range(3)},
          **{f"R{k}": (350.0, 800.0) for k in range(3)}}
#: the load cases: the body at rest, and offset by OFFSET away from each anchor in turn
CASES = {"mean": {}, **{
    f"off{k}": {"bodies.hull.position": [-OFFSET * math.cos(math.radians(h)),
                                         -OFFSET * math.sin(math.radians(h)), 0.0]}
    for k, h in enumerate(layout.HEADINGS)}}
CONSTRAINTS = ([(f"line{k}.fairlead_utilisation", "<=", UTIL) for k in range(3)]
               + [(f"line{k}.grounded_length", ">=", GROUNDED) for k in range(3)]
               + [(f"off{k}:hull.horizontal_force", ">=", F_REQ) for k in range(3)]
               + [("mean:hull.force[0]", "<=", BALANCE), ("mean:hull.force[0]", ">=", -BALANCE),
                  ("mean:hull.force[1]", "<=", BALANCE), ("mean:hull.force[1]", ">=", -BALANCE)])


def maker(segments: int):
    """The design's scene from the variables {s0.., d0.., R0..}."""
    def make(v):
        radii = [v[f"R{k}"] for k in range(3)]
        return layout.scene([radii[k] - layout.R_FAIR + v[f"s{k}"] for k in range(3)],
                            [v[f"d{k}"] for k in range(3)], radii, segments=segments)
    return make


def starts(n: int) -> list:
    """The 5 starts: the bounds' midpoint, two corners' thirds, two random (seed 7)."""
    lo = np.array([b[0] for b in BOUNDS.values()])
    hi = np.array([b[1] for b in BOUNDS.values()])
    rng = np.random.default_rng(7)
    fr = [np.full(9, 0.5), np.full(9, 0.3), np.full(9, 0.7)] + [rng.uniform(0.15, 0.85, 9)
                                                                for _ in range(2)]
    return [dict(zip(BOUNDS, (lo + f * (hi - lo)).tolist())) for f in fr[:n]]


def feasible_mass(make, v, segments) -> tuple:
    """(feasible, mass kg, worst violation) of the design ``v`` by fresh static solves."""
    worst = -np.inf
    for case, change in CASES.items():
        outs = {n.partition(":")[2] or n for n, _, _ in CONSTRAINTS
                if ":" not in n or n.startswith(case + ":")}
        vals = static_values(_apply(make(v), change), sorted(outs))
        for name, op, bound in CONSTRAINTS:
            c, sep, out = name.partition(":")
            if sep and c != case:
                continue
            out = out if sep else name
            sign = 1.0 if op == "<=" else -1.0
            worst = max(worst, sign * (vals[out] - bound) / max(abs(bound), 1.0))
    scene = sc.load_scene(make(v))
    mass = sum(s.length * s.line_type.mass for ln in scene.lines for s in ln.sections)
    return worst <= 1e-6, float(mass), float(worst)


def neighbourhood(make, best, segments, quick) -> dict:
    """Designs around the optimum (module docstring, item 3)."""
    names = list(BOUNDS)
    span = np.array([b[1] - b[0] for b in BOUNDS.values()])
    x0 = np.array([best[n] for n in names])
    designs = []
    steps = (0.005, 0.02) if quick else (0.0025, 0.005, 0.01, 0.02)
    for j in range(9):
        for f in steps:
            for sign in (-1.0, 1.0):
                x = x0.copy()
                x[j] += sign * f * span[j]
                designs.append(x)
    rng = np.random.default_rng(11)
    for _ in range(10 if quick else 100):
        designs.append(x0 + rng.uniform(-0.01, 0.01, 9) * span)
    lo = np.array([b[0] for b in BOUNDS.values()])
    hi = np.array([b[1] for b in BOUNDS.values()])
    _, m0, _ = feasible_mass(make, best, segments)
    lighter, feasible = [], 0
    for x in designs:
        x = np.clip(x, lo, hi)
        ok, m, _ = feasible_mass(make, dict(zip(names, x.tolist())), segments)
        feasible += ok
        if ok and m < m0 * (1 - 1e-9):
            lighter.append(float(m))
    return {"designs": len(designs), "feasible": int(feasible), "feasible_lighter": len(lighter),
            "optimum_mass": m0, "lightest_feasible_neighbour": min(lighter) if lighter else None}


def check_sensitivities(make, best, steps) -> dict:
    """Item 4: each case's Jacobian at the optimum against central differences of whole
    solves (to a residual of TIGHT) at relative steps h, 2h and 4h (``steps``): the
    reference is the Richardson extrapolation of the first two (error O(h^4)), its own
    error estimated by its difference from the extrapolation of the last two. The step is a
    compromise: the solves' residual makes a small one noisy, and a chain whose touchdown
    sits within a segment of its anchor (the grounded length at its bound) curves within a
    large one. The mean case's horizontal force (zero there: its magnitude has no
    derivative) is left out."""
    names = list(BOUNDS)
    worst, noise, allowed = 0.0, 0.0, 0.0
    for case, change in CASES.items():
        outs = ([f"line{k}.{o}" for k in range(3) for o in ("fairlead_utilisation",
                                                               "grounded_length")]
                + ["hull.force[0]", "hull.force[1]"]
                + ([] if case == "mean" else ["hull.horizontal_force"]))

        def at(j, value, case=case):
            v = dict(best)
            v[names[j]] = value
            return _apply(make(v), CASES[case])
        s = design_sensitivity(_apply(make(best), change), None, outs, names,
                               [best[n] for n in names],
                               [lambda value, j=j: at(j, value) for j in range(9)])
        D = {}
        for step in steps:
            J = np.zeros_like(s.jacobian)
            for j, n in enumerate(names):
                h = step * abs(best[n])
                up, dn = static_values(at(j, best[n] + h), outs, tol=TIGHT), \
                    static_values(at(j, best[n] - h), outs, tol=TIGHT)
                J[:, j] = [(up[o] - dn[o]) / (2 * h) for o in s.outputs]
            D[step] = J
        ref = (4.0 * D[steps[0]] - D[steps[1]]) / 3.0
        other = (4.0 * D[steps[1]] - D[steps[2]]) / 3.0
        row = np.maximum(np.abs(s.jacobian).max(axis=1, keepdims=True), 1e-300)
        diff, err = np.abs(ref - s.jacobian) / row, np.abs(ref - other) / row
        worst, noise = max(worst, float(diff.max())), max(noise, float(err.max()))
        allowed = max(allowed, float((diff - np.maximum(1e-6, 3.0 * err)).max()))
    return {"max_relative_difference": worst, "differences_own_error": noise,
            "worst_excess_over_allowance": allowed}


#: item 6: the optimum's hull moved as a vessel, surge 2 m, heave 0.5 m and pitch 1 deg at
#: a 10 s period (heave and pitch a quarter period behind; at 3 m, 1 m and 2 deg the
#: 10-harmonic balance of the 20-segment chains found no periodic state from shooting's,
#: refused in one line); the periodic outputs and the first line's numbers they are
#: differentiated against
WAVE_MOTION = {"kind": "harmonic", "period": 10.0, "amplitude": [2.0, 0.0, 0.5, 0.0, 1.0, 0.0],
               "phase_deg": [0.0, 0.0, -90.0, 0.0, -90.0, 0.0]}
PERIODIC_OUTPUTS = ["line0.fairlead_tension.range", "line0.fairlead_tension.max",
                    "line0.fairlead_utilisation.max", "line0.anchor_tension.mean"]
PERIODIC_PARAMETERS = ["line_types.chain0.nominal_diameter", "lines[0].sections[0].length",
                       "points.anchor0.position[0]"]


def check_periodic(make, best, harmonics: int = 10) -> dict:
    """Item 6: the sensitivities of periodic statistics at the optimum, the hull moved by
    WAVE_MOTION, against central differences of whole periodic solves (the same harmonic
    balance) at relative steps 5e-6 and 1e-5, their disagreement the differences' own
    error. (Small steps: a chain on the seabed's periodic response curves within 1e-4 of
    its length, where the differences were 1.6e-3 off and converged to the exact derivative
    quadratically below 2e-5.)"""
    d = make(best)
    d["bodies"]["hull"] = {"kind": "vessel", "position": [0.0, 0.0, 0.0],
                           "motion": WAVE_MOTION}
    t = time.perf_counter()
    s = sc.sensitivity(d, PERIODIC_OUTPUTS, PERIODIC_PARAMETERS, harmonics=harmonics)
    seconds = time.perf_counter() - t
    from symcable.api.sensitivity import _expand, _set
    fd = {}
    for rel in (5e-6, 1e-5):
        J = np.zeros_like(s.jacobian)
        for j, (name, parts, value) in enumerate(_expand(d, PERIODIC_PARAMETERS)):
            h = rel * max(abs(value), 1.0)
            up, dn = (sc.sensitivity(_set(d, parts, value + k * h), PERIODIC_OUTPUTS,
                                     PERIODIC_PARAMETERS[0], harmonics=harmonics).values
                      for k in (1.0, -1.0))
            J[:, j] = (up - dn) / (2.0 * h)
        fd[rel] = J
    row = np.maximum(np.abs(s.jacobian).max(axis=1, keepdims=True), 1e-300)
    diff, err = np.abs(fd[5e-6] - s.jacobian) / row, np.abs(fd[5e-6] - fd[1e-5]) / row
    return {"outputs": dict(zip(s.outputs, s.values.tolist())),
            "relative_differences": diff.tolist(), "differences_errors": err.tolist(),
            "max_relative_difference": float(diff.max()),
            "differences_own_error": float(err.max()),
            "worst_excess_over_allowance": float((diff - np.maximum(1e-6, 3.0 * err)).max()),
            "harmonics": harmonics, "seconds": seconds}


def grounded_check(make, best) -> dict:
    """Item 5: ``LINE.grounded_length`` against the static solution's own, per case."""
    out = {}
    for case, change in CASES.items():
        d = _apply(make(best), change)
        mine = static_values(d, [f"line{k}.grounded_length" for k in range(3)])
        sol = sc.solve_static(d)
        out[case] = [(float(mine[f"line{k}.grounded_length"]),
                      float(sol.lines[f"line{k}"].grounded_length)) for k in range(3)]
    return out


def plot(make, best, runs, path: Path) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(11, 4.6))
    for case, style in (("mean", "-"), ("off0", "--"), ("off1", ":")):
        sol = sc.solve_static(_apply(make(best), CASES[case]))
        for k in range(3):
            p = np.asarray(sol.lines[f"line{k}"].positions)
            ax.plot(p[:, 0], p[:, 1], style, color=f"C{k}",
                    label=f"line{k}" if case == "mean" else None)
    ax.plot([], [], "k-", label="mean")
    ax.plot([], [], "k--", label="off0 (30 m)")
    ax.plot([], [], "k:", label="off1 (30 m)")
    ax.set_aspect("equal")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.set_title("optimum: plan view of the chains")
    ax.legend(fontsize=8)
    for label, run in runs.items():
        h = np.array(run["history"])
        if len(h):
            bx.plot(h[:, 2], h[:, 0] / 1e3, "-" if "exact" in label else "--", label=label)
    bx.set_xlabel("static solves so far")
    bx.set_ylabel("chain mass (t)")
    bx.set_xscale("log")
    bx.set_title("optimiser history (each design evaluated)")
    bx.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def main(argv=None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--periodic", action="store_true",
                    help="item 6 alone, at the optimum of results.json (written back there)")
    args = ap.parse_args(argv)
    if args.periodic:
        results = json.loads((HERE / "results.json").read_text())
        results["periodic"] = check_periodic(maker(results["segments"]), results["optimum"])
        (HERE / "results.json").write_text(json.dumps(results, indent=1, default=float))
        print(json.dumps(results["periodic"], indent=1, default=float))
        return results
    segments, n_starts = (8, 2) if args.quick else (20, 5)
    out_dir = HERE / "out" if args.quick else HERE
    out_dir.mkdir(exist_ok=True)
    make = maker(segments)
    for case, change in CASES.items():  # every case's model built once, before any timing
        static_values(_apply(make(starts(1)[0]), change), ["hull.force"])
    runs = {}
    for i, start in enumerate(starts(n_starts)):
        t = time.perf_counter()
        r = sc.optimize(make, BOUNDS, "mass", CONSTRAINTS, cases=CASES, start=start)
        runs[f"exact, start {i}"] = {"variables": r.variables, "mass": r.objective,
                                     "iterations": r.stats["iterations"],
                                     "solves": r.stats["solves"],
                                     "wall_time": time.perf_counter() - t,
                                     "history": r.stats["history"]}
        print(f"exact start {i}: {r.objective:.1f} kg, {r.stats['iterations']} iterations, "
              f"{r.stats['solves']} solves, {runs[f'exact, start {i}']['wall_time']:.1f} s",
              flush=True)
    if not args.quick:
        t = time.perf_counter()
        r = sc.optimize(make, BOUNDS, "mass", CONSTRAINTS, cases=CASES, start=starts(1)[0],
                        gradients="differences")
        runs["differences, start 0"] = {"variables": r.variables, "mass": r.objective,
                                        "iterations": r.stats["iterations"],
                                        "solves": r.stats["solves"],
                                        "wall_time": time.perf_counter() - t,
                                        "history": r.stats["history"]}
        print(f"differences start 0: {r.objective:.1f} kg, {r.stats['iterations']} "
              f"iterations, {r.stats['solves']} solves, "
              f"{runs['differences, start 0']['wall_time']:.1f} s", flush=True)
    exact = [v for k, v in runs.items() if k.startswith("exact")]
    best = min(exact, key=lambda v: v["mass"])["variables"]
    span = {n: b[1] - b[0] for n, b in BOUNDS.items()}
    spread = max(abs(v["variables"][n] - best[n]) / span[n] for v in runs.values() for n in best)
    mass_spread = max(abs(v["mass"] / min(e["mass"] for e in exact) - 1) for v in runs.values())
    results = {
        "segments": segments, "bounds": BOUNDS, "cases": CASES,
        "constraints": [list(c) for c in CONSTRAINTS],
        "runs": {k: {kk: vv for kk, vv in v.items() if kk != "history"} for k, v in runs.items()},
        "optimum": best,
        "optimum_lengths": {f"L{k}": best[f"R{k}"] - layout.R_FAIR + best[f"s{k}"]
                            for k in range(3)},
        "spread_over_starts_of_range": spread, "mass_spread": mass_spread,
        "exact_over_differences": None if args.quick else {
            "solves": runs["exact, start 0"]["solves"] / runs["differences, start 0"]["solves"],
            "wall_time": runs["exact, start 0"]["wall_time"]
            / runs["differences, start 0"]["wall_time"]},
        "neighbourhood": neighbourhood(make, best, segments, args.quick),
        "sensitivities": check_sensitivities(make, best, (5e-3, 1e-2, 2e-2) if args.quick
                                             else (1e-4, 2e-4, 4e-4)),
        "grounded_length": grounded_check(make, best),
        "periodic": None if args.quick else check_periodic(make, best),
    }
    plot(make, best, runs, out_dir / "design.png")
    (out_dir / "results.json").write_text(json.dumps(results, indent=1, default=float))
    print(json.dumps({k: results[k] for k in ("optimum", "spread_over_starts_of_range",
                                              "mass_spread", "exact_over_differences",
                                              "neighbourhood", "sensitivities", "periodic")},
                     indent=1, default=float))
    return results


if __name__ == "__main__":
    main()
