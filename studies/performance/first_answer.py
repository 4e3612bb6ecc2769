"""The first answer: what a user waits for on a scene symcable has not solved before.

Question: how long does a static answer take when the scene is new, against MoorPy building
and solving the same system, and how long do simulate's first, second and third calls take
against a MoorDyn run? Every figure is a median of repeats taken side by side in one run.

0. **Empty build cache**: the built-in ``oc3`` line (50 segments, small enough that the
   default compiles its static solve) in a new process with an empty build cache and a C
   compiler, the default compiling in the background against waiting for the compiler
   (``SYMCABLE_CODEGEN_WAIT=1``).
1. **Cold, fresh process**: the three-line OC3 mooring (902.2 m of chain a line, 100
   segments, fixed fairleads and anchors, 320 m of water) solved by ``sc.solve_static`` with
   its defaults (the answer and its error estimate) in a new Python process, symcable and
   MoorPy imported beforehand (the import is not the answer's cost); MoorPy builds its
   ``System`` and solves it. Each process solves once; processes alternate.
2. **Changed numbers, same process**: the same mooring solved again with other numbers (line
   lengths, anchor radius, chain diameter and mass: a design loop), symcable reusing what the
   first scene of that structure built (:mod:`symcable.models.structure`), MoorPy building
   and solving each new ``System``; and the fairlead tensions of the two compared.
3. **Random systems, one after another**: scenes of the fuzz study's generators, each of a
   new structure (its own segment counts and points), solved in one process.
4. **simulate, first, second and third call** on the seed-001 line (30 periods of 10 s,
   dt = T/100, generated C) in a fresh process whose build cache an earlier process filled,
   against MoorDyn's 30-period run (RK2 at its largest stable step, its set-up included).
5. **Time runs with changed numbers**: one OC3 line (80 segments, 3D) and the mooring (3 x 40
   segments) with a harmonic fairlead motion, 60 s at dt = 0.1 s in the virtual machine: the
   first scene, then scenes of the same structure with the lines 3, 6 and 9 m longer (the
   step reused from the first).

Run ``python studies/performance/first_answer.py [--quick] [--out DIR]``; needs
``symcable[bench]``.
"""
from __future__ import annotations

import json
import math
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))
sys.path.insert(0, str(HERE.parent / "fuzz"))
import study_io  # noqa: E402

import symcable as sc  # noqa: E402

DEPTH, RADIUS, FAIR_R, FAIR_Z, LENGTH = 320.0, 853.87, 5.2, -70.0, 902.2
CHAIN = {"EA": 3.84243e8, "mass": 77.7066, "diameter": 0.09, "cd_normal": 1.6,
         "cd_tangential": 0.1, "ca_normal": 1.0}
G, RHO = 9.80665, 1025.0


def mooring(segments: int = 100, length: float = LENGTH, radius: float = RADIUS,
            diameter: float = 0.09, mass: float = 77.7066) -> dict:
    """The three-line OC3 mooring as a scene dict (fixed fairleads and anchors)."""
    points, lines = {}, []
    for i, ang in enumerate((0.0, 120.0, 240.0)):
        a = math.radians(ang)
        c, s = math.cos(a), math.sin(a)
        points[f"anchor{i}"] = {"kind": "fixed", "position": [radius * c, radius * s, -DEPTH]}
        points[f"fair{i}"] = {"kind": "fixed", "position": [FAIR_R * c, FAIR_R * s, FAIR_Z]}
        lines.append({"name": f"line{i}", "end_a": f"anchor{i}", "end_b": f"fair{i}",
                      "sections": [{"type": "chain", "length": length, "segments": segments}]})
    return {"model": "cable3d", "environment": {"gravity": G, "water_density": RHO,
                                                "depth": DEPTH},
            "seabed": {"stiffness": 1e5},
            "line_types": {"chain": dict(CHAIN, diameter=diameter, mass=mass)},
            "points": points, "lines": lines}


def moorpy_mooring(d: dict):
    """MoorPy's ``System`` of the scene dict ``d`` (its lines, points and line type), solved;
    returns the fairlead tension of each line, N."""
    import moorpy as mp
    ms = mp.System(depth=DEPTH, rho=RHO, g=G)
    lt = d["line_types"]["chain"]
    w = lt["mass"] * G - RHO * G * math.pi * lt["diameter"] ** 2 / 4.0
    ms.setLineType(name="chain", mass=lt["mass"], d_vol=lt["diameter"], EA=lt["EA"], w=w,
                   dnommm=1000.0 * lt["diameter"])
    ids = {}
    for name, pt in d["points"].items():
        ms.addPoint(1, np.array(pt["position"], float))
        ids[name] = len(ms.pointList)
    for ln in d["lines"]:
        ms.addLine(ln["sections"][0]["length"], "chain", pointA=ids[ln["end_a"]],
                   pointB=ids[ln["end_b"]])
    ms.initialize()
    ms.solveEquilibrium()
    return [float(line.TB) for line in ms.lineList]


_CHILD = r"""
import json, sys, time
sys.path.insert(0, {here!r})
import first_answer as fa
import symcable as sc, moorpy  # imported before the clock starts
d = fa.mooring({segments})
t0 = time.perf_counter()
if {which!r} == "symcable":
    st = sc.solve_static(d)
    tension = [ln.fairlead_tension for ln in st.lines.values()]
else:
    tension = fa.moorpy_mooring(d)
print(json.dumps({{"seconds": time.perf_counter() - t0, "tension": tension}}))
"""


def cold(which: str, segments: int, cache: str) -> dict:
    """One solve in a new process (``which``: "symcable" or "moorpy")."""
    env = dict(os.environ, SYMCABLE_CACHE_DIR=cache)
    out = subprocess.run([sys.executable, "-c", _CHILD.format(here=str(HERE), which=which,
                                                              segments=segments)],
                         capture_output=True, text=True, env=env, check=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


_CHILD_EMPTY = r"""
import json, sys, time
import symcable as sc
from symcable.mechanism import background_build
t0 = time.perf_counter()
st = sc.solve_static("oc3")
seconds = time.perf_counter() - t0
background_build.wait(900)  # (not timed: the build goes on after the answer)
print(json.dumps({"seconds": seconds, "compiled": bool(st.stats["compiled"])}))
"""


def empty_cache_first(wait: bool) -> dict:
    """The built-in ``oc3`` line solved at the defaults in a new process with an empty build
    cache and a C compiler: the default compiling in the background (``wait`` False) or
    waiting for the compiler (``SYMCABLE_CODEGEN_WAIT=1``, the default before the background
    build)."""
    with tempfile.TemporaryDirectory() as cache:
        env = dict(os.environ, SYMCABLE_CACHE_DIR=cache, SYMCABLE_CODEGEN_WAIT="1" if wait else "0")
        env.pop("SYMCABLE_CODEGEN", None)
        out = subprocess.run([sys.executable, "-c", _CHILD_EMPTY], capture_output=True,
                             text=True, env=env, check=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


def designs(n: int, rng) -> list[dict]:
    """``n`` variants of the mooring: line length 880-960 m, anchor radius 830-870 m, chain
    diameter 0.08-0.10 m with its mass per metre scaled by d^2."""
    out = []
    for _ in range(n):
        dia = float(rng.uniform(0.08, 0.10))
        out.append(mooring(length=float(rng.uniform(880.0, 960.0)),
                           radius=float(rng.uniform(830.0, 870.0)), diameter=dia,
                           mass=77.7066 * (dia / 0.09) ** 2))
    return out


def changed_numbers(n: int, repeats: int) -> dict:
    """Section 2: the design loop, symcable and MoorPy, medians per solve."""
    rng = np.random.default_rng(34)
    cases = designs(n, rng)
    sc.solve_static(mooring())  # the structure's first scene (its template)
    sym, mp_, diff = [], [], []
    for _ in range(repeats):
        for d in cases:
            t0 = time.perf_counter()
            st = sc.solve_static(d)
            t1 = time.perf_counter()
            ref = moorpy_mooring(d)
            t2 = time.perf_counter()
            sym.append(t1 - t0)
            mp_.append(t2 - t1)
            got = [ln.fairlead_tension for ln in st.lines.values()]
            diff.append(max(abs(a - b) / b for a, b in zip(got, ref)))
    return {"resolve_symcable_s": statistics.median(sym), "resolve_moorpy_s": statistics.median(mp_),
            "resolve_ratio": statistics.median(sym) / statistics.median(mp_),
            "resolve_tension_diff_max": max(diff), "resolve_cases": len(sym)}


def random_systems(n: int) -> dict:
    """Section 3: ``n`` random systems of the fuzz study's generators, one after another."""
    import fuzz3d_systems as gen
    rng = np.random.default_rng(7)
    makers = [gen.gen_three_lines, gen.gen_buoy, gen.gen_clump]
    times, done = [], 0
    while done < n:
        try:
            _, d = makers[done % len(makers)](rng)
        except gen.Redraw:
            continue
        d = {"model": "cable3d", **d}
        t0 = time.perf_counter()
        try:
            sc.solve_static(d)
        except sc.SymcableError:
            pass
        times.append(time.perf_counter() - t0)
        done += 1
    return {"random_median_s": statistics.median(times), "random_n": n}


_SIMULATE = r"""
import json, time
import symcable as sc
scene = sc.load_scene(sc.demo_scene_path("seed001"))
out = []
for _ in range(3):
    t0 = time.perf_counter()
    sc.simulate(scene, 300.0, dt=0.1, codegen={codegen})
    out.append(time.perf_counter() - t0)
print(json.dumps(out))
"""


def simulate_calls(cache: str, repeats: int, codegen: bool | None = True) -> dict:
    """Section 4: simulate's first, second and third call in a fresh process (the build
    cache filled by an earlier process, as on any run after the first), against MoorDyn's
    run (its set-up and settling included). ``codegen`` as simulate's (``--quick``: the
    default, so that the tests' virtual machine setting holds)."""
    mdl = study_io.load_module(HERE / "moordyn_line.py", "performance_moordyn_line")
    env = dict(os.environ, SYMCABLE_CACHE_DIR=cache)

    def calls():
        res = subprocess.run([sys.executable, "-c", _SIMULATE.format(codegen=codegen)],
                             capture_output=True, text=True, env=env, check=True)
        return json.loads(res.stdout.strip().splitlines()[-1])
    calls()  # fills the cache
    runs, md = [], []
    for _ in range(repeats):
        runs.append(calls())
        r = mdl.run(300.0, mdl.DT_LIMIT["RK2"], tscheme="RK2", zeta=1.0)
        md.append(r["wall_time"] + r["init_time"])
    out = {f"simulate_{k}_s": statistics.median(r[i] for r in runs)
           for i, k in enumerate(("first", "second", "third"))}
    out["moordyn_s"] = statistics.median(md)
    return out


MOTION = {"kind": "harmonic", "period": 10.0, "amplitude": [2.0, 0.0, 1.0],
          "phase_deg": [0.0, 0.0, -90.0]}


def moving_line(extra: float) -> dict:
    """One OC3 line, 80 segments, its fairlead moving; ``extra`` m longer."""
    return {"model": "cable3d", "environment": {"gravity": G, "water_density": RHO, "depth": DEPTH},
            "seabed": {"stiffness": 1e5}, "line_types": {"chain": dict(CHAIN)},
            "sections": [{"type": "chain", "length": LENGTH + extra, "segments": 80}],
            "end_a": {"condition": "pinned", "position": [-RADIUS, 0.0, -DEPTH]},
            "end_b": {"condition": "pinned", "position": [-FAIR_R, 0.0, FAIR_Z], "motion": MOTION}}


def moving_mooring(extra: float) -> dict:
    """The mooring at 40 segments a line, fairlead 0 moving; its lines ``extra`` m longer."""
    d = mooring(segments=40, length=LENGTH + extra)
    d["points"]["fair0"].update(kind="vessel", motion=MOTION)
    return d


def changed_runs(scenes: dict) -> dict:
    """Section 5: each scene maker's first run, then the median of three with other numbers."""
    out = {}
    for name, make in scenes.items():
        t0 = time.perf_counter()
        sc.simulate(make(0.0), 60.0, dt=0.1, codegen=False)
        out[f"run_{name}_first_s"] = time.perf_counter() - t0
        later = []
        for extra in (3.0, 6.0, 9.0):
            t0 = time.perf_counter()
            sc.simulate(make(extra), 60.0, dt=0.1, codegen=False)
            later.append(time.perf_counter() - t0)
        out[f"run_{name}_changed_s"] = statistics.median(later)
    return out


def main(argv=None) -> dict:
    args = study_io.parse(__doc__, "fewer repeats and designs (a minute)",
                          HERE / "out_first_answer", argv)
    quick = args.quick
    rows = {}
    with tempfile.TemporaryDirectory() as cache:
        runs = {"symcable": [], "moorpy": []}
        for _ in range(1 if quick else 7):
            for which in runs:
                runs[which].append(cold(which, 100, cache))
        rows["cold_symcable_s"] = statistics.median(r["seconds"] for r in runs["symcable"])
        rows["cold_moorpy_s"] = statistics.median(r["seconds"] for r in runs["moorpy"])
        rows["cold_ratio"] = rows["cold_symcable_s"] / rows["cold_moorpy_s"]
        a, b = runs["symcable"][0]["tension"], runs["moorpy"][0]["tension"]
        rows["cold_tension_diff"] = max(abs(x - y) / y for x, y in zip(a, b))
        rows.update(simulate_calls(cache, 1 if quick else 5, None if quick else True))
    empty = {"background": [], "waiting": []}
    for _ in range(1 if quick else 3):
        for mode in empty:
            empty[mode].append(empty_cache_first(mode == "waiting"))
    for mode, got in empty.items():
        rows[f"empty_{mode}_s"] = statistics.median(r["seconds"] for r in got)
        rows[f"empty_{mode}_compiled"] = any(r["compiled"] for r in got)
    rows.update(changed_numbers(3 if quick else 30, 1 if quick else 3))
    rows.update(random_systems(2 if quick else 30))
    rows.update(changed_runs({"line": moving_line} if quick
                             else {"line": moving_line, "mooring": moving_mooring}))
    rows["second_over_third"] = rows["simulate_second_s"] / rows["simulate_third_s"]
    text = "\n".join([
        "| measurement | symcable | peer | ratio |", "|---|---|---|---|",
        f"| cold first static solve, fresh process (3 x 100 segments) | "
        f"{rows['cold_symcable_s']:.3f} s | MoorPy {rows['cold_moorpy_s']:.3f} s | "
        f"{rows['cold_ratio']:.1f} |",
        f"| first static solve of `oc3` (50 segments), fresh process, empty build cache, "
        f"a C compiler: compiling in the background / waiting for it | "
        f"{rows['empty_background_s']:.2f} / {rows['empty_waiting_s']:.2f} s | - | "
        f"{rows['empty_background_s'] / rows['empty_waiting_s']:.2f} |",
        f"| re-solve with changed numbers ({rows['resolve_cases']} designs) | "
        f"{rows['resolve_symcable_s'] * 1e3:.1f} ms | MoorPy {rows['resolve_moorpy_s'] * 1e3:.1f} ms"
        f" | {rows['resolve_ratio']:.2f} |",
        f"| random systems, each a new structure ({rows['random_n']}) | "
        f"{rows['random_median_s']:.3f} s | - | - |",
        f"| simulate seed 001, 300 s: first / second / third call | "
        f"{rows['simulate_first_s']:.2f} / {rows['simulate_second_s']:.2f} / "
        f"{rows['simulate_third_s']:.2f} s | MoorDyn {rows['moordyn_s']:.2f} s | "
        f"{rows['simulate_first_s'] / rows['moordyn_s']:.2f} / "
        f"{rows['simulate_second_s'] / rows['moordyn_s']:.2f} / "
        f"{rows['simulate_third_s'] / rows['moordyn_s']:.2f} |",
        *[f"| 60 s time run, {name}: first scene / later ones of other numbers | "
          f"{rows[f'run_{name}_first_s']:.2f} / {rows[f'run_{name}_changed_s']:.2f} s | - | - |"
          for name in ("line", "mooring") if f"run_{name}_first_s" in rows],
        "",
        f"Fairlead tensions against MoorPy's: largest difference "
        f"{rows['resolve_tension_diff_max']:.2e} (relative; 100 segments against its exact "
        f"catenary). Second simulate call / third: {rows['second_over_third']:.2f}."])
    study_io.write_tables(args.out, [rows], text)
    return rows


if __name__ == "__main__":
    main()
