"""Performance: generated C against the CasADi virtual machine, and symcable against its peers.

Question: how fast is each solve in generated C relative to the virtual machine (VM), and
relative to the comparison a user would make: MoorPy for statics, MoorDyn for a time run and
for reaching the periodic steady state? Every figure is a ratio taken side by side in one run,
interleaved repeats, medians (the machine is shared and noisy).

1. statics, OC3 line (51 nodes): ``solve_static`` with a pre-built model (C, VM) against
   MoorPy's catenary; also the fused Newton call alone (C, VM);
2. a 30-period time run of the seed-001 line: ``simulate``, i.e. the first-order
   generalized-alpha of ``symcable.integrate`` on the line's dynamics Mechanism (its Newton
   loop unrolled, a block LU written out in SX), dt = T/100 (C, VM), and in C
   at the fewest steps per period whose error is no larger than MoorDyn RK4's (equal
   accuracy; about T/56, from the measured second order), against MoorDyn at its largest stable step with RK4 (no
   internal damping, as symcable; the issue's comparison) and with RK2 (critical internal
   damping, MoorDyn's own advice); see moordyn_line.py. Each with its error against its own
   converged reference (max over the last period / tension range);
3. the periodic steady state: ``solve_periodic`` by collocation (IPOPT) and by shooting (the
   first-order generalized-alpha period map, Anderson-accelerated), on the generic periodic
   solvers (the virtual machine: their generalized-alpha step is a CasADi rootfinder, which
   CasADi cannot generate C for), against the wall time MoorDyn, and symcable's own time
   run, need to come within 1 % of their own steady state.

Run ``python studies/performance/run.py [--quick] [--out DIR]``; needs ``symcable[bench]``.
"""
from __future__ import annotations

import argparse
import importlib.util
import json
import math
import statistics
import time
from pathlib import Path

import numpy as np

import symcable as sc
from symcable.mechanism.functions import functions
from symcable.models.planar.static import static_mechanism

HERE = Path(__file__).resolve().parent


def _load_helper(name: str):
    """Import ``HERE/<name>.py`` by its file path: studies/ is not a package, and putting
    this folder on ``sys.path`` would let its modules shadow installed ones."""
    spec = importlib.util.spec_from_file_location(f"performance_{name}", HERE / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


mdl = _load_helper("moordyn_line")

T = 10.0
#: at most this many steps per period for the equal-accuracy run (see ``equal_steps``)
N_EQUAL_MAX = 100


def interleaved(fns: dict, repeats: int, block: int = 1) -> dict:
    """Median wall time (s) of one call of each callable, interleaved so noise hits all alike:
    ``repeats`` rounds, each timing ``block`` back-to-back calls of every callable in turn.
    Blocks of microsecond calls measure them as a sweep runs them, warm in the caches; single
    interleaved calls would time each one after the others have evicted its code and data
    (the compiled static call then takes 29 us instead of 22)."""
    times = {k: [] for k in fns}
    for _ in range(repeats):
        for k, f in fns.items():
            t0 = time.perf_counter()
            for _ in range(block):
                f()
            times[k].append((time.perf_counter() - t0) / block)
    return {k: statistics.median(v) for k, v in times.items()}


def first_calls(fns: dict) -> tuple[dict, dict]:
    """``(times, results)``: one timed call of each callable, in turn (``--quick``: the
    first, cold calls, building included; their times are not the full run's medians)."""
    times, results = {}, {}
    for k, f in fns.items():
        t0 = time.perf_counter()
        results[k] = f()
        times[k] = time.perf_counter() - t0
    return times, results


def statics(repeats: int) -> dict:
    from moorpy.Catenary import catenary
    scene = sc.load_scene(sc.demo_scene_path("oc3"))
    model = sc.build_model(scene)
    t0 = time.perf_counter()
    g = next(iter(model.initial_guess()))
    start = time.perf_counter() - t0
    F = functions(static_mechanism(model))  # the statics Mechanism's fused Newton solve
    vm, c = F.static_solver(False), F.static_solver(True)
    sc.solve_static(scene, model=model, codegen=True)
    tol = sc.solve_static(scene, model=model, codegen=False).stats["tolerance"]
    a, b = scene.end_a.position, scene.end_b.position
    lt = scene.sections[0].line_type
    f_c, f_vm = c.fast("solve"), vm.fast("solve")
    med = interleaved({
        "symcable_c": lambda: sc.solve_static(scene, model=model, codegen=True),
        "symcable_vm": lambda: sc.solve_static(scene, model=model, codegen=False),
        "moorpy": lambda: catenary(b[0] - a[0], b[1] - a[1], scene.length, lt.EA, lt.weight,
                                   CB=0.0, nNodes=scene.n_segments + 1),
        "newton_call_c": lambda: f_c(g.w, model.p_target, tol),
        "newton_call_vm": lambda: f_vm(g.w, model.p_target, tol),
    }, repeats, block=50)
    med["start_guess"] = start
    return med


def equal_steps(err_100: float, err_peer: float) -> int:
    """Fewest steps per period at which generalized-α's error, second order in dt and
    ``err_100`` at T/100, is no larger than the peer's: 100 sqrt(err_100 / err_peer),
    rounded up (checked afterwards by measuring it)."""
    return int(min(N_EQUAL_MAX, math.ceil(100.0 * math.sqrt(err_100 / err_peer))))


def time_run(repeats: int, periods: int, quick: bool) -> dict:
    scene = sc.load_scene(sc.demo_scene_path("seed001"))
    model = sc.build_dynamic_model(scene)
    dur = periods * T
    runs = {}

    def sym(cg, n=100):
        runs[(cg, n)] = sc.simulate(scene, dur, dt=T / n, model=model, codegen=cg)

    def md(scheme):
        zeta = 0.0 if scheme == "RK4" else 1.0
        runs["md_" + scheme] = mdl.run(dur, mdl.DT_LIMIT[scheme], tscheme=scheme, zeta=zeta)

    # each one's error against its own converged reference, over the last period
    t = {}
    ref_sym = sc.simulate(scene, dur, dt=T / (400 if quick else 1600), model=model, codegen=True)
    tt = (periods - 1) * T + T * np.arange(100) / 100
    b = np.interp(tt, ref_sym.time, ref_sym.fairlead_tension)

    def sym_error(n):
        a = np.interp(tt, runs[(True, n)].time, runs[(True, n)].fairlead_tension)
        return float(np.max(np.abs(a - b)) / np.ptp(b))

    for scheme in ("RK2", "RK4"):
        md(scheme)
        zeta = 0.0 if scheme == "RK4" else 1.0
        ref_md = mdl.run(dur, mdl.DT_LIMIT[scheme] / (4 if quick else 32), tscheme=scheme, zeta=zeta)
        t[f"moordyn_{scheme}_error"] = mdl.tension_error(runs["md_" + scheme], ref_md)
        t[f"moordyn_{scheme}_error_as_returned"] = mdl.tension_error(runs["md_" + scheme], ref_md, shift=False)
    t["moordyn_error"] = t["moordyn_RK2_error"]
    t["moordyn_error_as_returned"] = t["moordyn_RK2_error_as_returned"]
    sym(True)
    sym(False)
    t["symcable_error"] = sym_error(100)
    # equal accuracy with MoorDyn RK4: the fewest steps per period whose measured error is
    # no larger than MoorDyn's (from the second-order estimate, raised until it holds)
    n_eq = equal_steps(t["symcable_error"], t["moordyn_RK4_error"])
    while True:
        sym(True, n_eq)
        t["symcable_error_equal"] = sym_error(n_eq)
        if t["symcable_error_equal"] <= t["moordyn_RK4_error"] or n_eq >= N_EQUAL_MAX:
            break
        n_eq = min(N_EQUAL_MAX, n_eq + 2)
    t["steps_equal"] = n_eq
    t.update(interleaved({"symcable_c": lambda: sym(True), "symcable_vm": lambda: sym(False),
                          "symcable_c_equal": lambda: sym(True, n_eq)}, repeats))
    for scheme in ("RK2", "RK4"):
        wall = []
        for _ in range(repeats):
            md(scheme)
            wall.append(runs["md_" + scheme]["wall_time"])
        t["moordyn_" + scheme] = statistics.median(wall)
    t["moordyn"] = t["moordyn_RK2"]
    t["moordyn_init"] = runs["md_RK2"]["init_time"]
    t["symcable_c_steps_s"] = runs[(True, 100)].stats["step_time"]
    t["symcable_vm_steps_s"] = runs[(False, 100)].stats["step_time"]
    t["symcable_c_us_per_step"] = runs[(True, 100)].stats["us_per_step"]
    t["symcable_newton_iterations_per_step"] = (runs[(True, 100)].stats["newton_iterations"]
                                                / runs[(True, 100)].stats["steps"])
    runs["md"] = runs["md_RK2"]
    return t, runs


def _periods_to_1pct(run: dict) -> int:
    """Periods marched until the fairlead tension is within 1 % of the last period's range."""
    return int(np.argmax(mdl.steady_state_distance(run) <= 0.01)) + 1


def periodic(repeats: int, md_run: dict, sym_run) -> dict:
    """Collocation (IPOPT) and shooting (the generic periodic solvers, in the VM) against the
    time MoorDyn (and symcable's own time run) needs to march to 1 % of its steady state:
    medians of ``repeats`` interleaved warm calls; ``repeats = 0`` (``--quick``) the first,
    cold calls' times."""
    scene = sc.load_scene(sc.demo_scene_path("seed001"))
    model = sc.build_dynamic_model(scene)
    d200 = scene.to_dict()
    d200["sections"][0]["segments"] = 200
    scene200 = sc.load_scene(d200)
    model200 = sc.build_dynamic_model(scene200)
    calls = {
        "modal_50": lambda: sc.modal_analysis(scene, 6, model=model),
        "modal_200": lambda: sc.modal_analysis(scene200, 6, model=model200),
        "collocation": lambda: sc.solve_periodic(scene, "collocation", model=model),
        "shooting": lambda: sc.solve_periodic(scene, "shooting", model=model),
    }
    out, first = first_calls(calls)
    col, shot = first["collocation"], first["shooting"]
    if repeats:  # warm medians (the first calls above built everything)
        out = interleaved(calls, repeats)
    out["collocation_solve"] = col.stats["solve_time"]
    out["iterations"] = col.stats["iterations"]
    out["shooting_periods"] = shot.stats["iterations"]
    ft = col.fairlead_tension
    out["shooting_error"] = float(np.max(np.abs(shot.fairlead_tension - ft)) / np.ptp(ft))
    n_needed = _periods_to_1pct(md_run)
    per_period = md_run["wall_time"] / (md_run["time"][-1] / T)
    out["moordyn_periods_to_1pct"] = n_needed
    out["moordyn_to_1pct"] = n_needed * per_period
    out["moordyn_to_1pct_with_init"] = n_needed * per_period + md_run["init_time"]
    n_sym = _periods_to_1pct({"time": sym_run.time, "fairlead_tension": sym_run.fairlead_tension})
    out["symcable_periods_to_1pct"] = n_sym
    out["symcable_march_to_1pct"] = n_sym * sym_run.stats["step_time"] / (sym_run.time[-1] / T)
    return out


def resonance(quick: bool) -> dict:
    """The lightly damped case of studies/stability (seed 001 at 20 segments, Cd x 0.01, no
    current, fairlead amplitude x 0.05, excited at its first natural period): the periodic
    solves (the generic solvers, VM) against the time MoorDyn (RK2 at its limit, as above)
    needs to come within 1 % of its own steady state, marching up to 300 periods (200 in
    --quick, and the periodic solves' first, cold calls timed, not warm medians)."""
    d = sc.load_scene(sc.demo_scene_path("seed001")).to_dict()
    d["sections"][0]["segments"] = 20
    d["environment"]["current"] = [0.0, 0.0]
    lt = d["line_types"]["chain"]
    lt["cd_normal"] *= 0.01
    lt["cd_tangential"] *= 0.01
    d["end_b"]["motion"]["amplitude"] = [0.05 * a for a in d["end_b"]["motion"]["amplitude"]]
    period = float(sc.modal_analysis(sc.load_scene(d), 2).periods[0])
    d["end_b"]["motion"]["period"] = period
    scene = sc.load_scene(d)
    model = sc.build_dynamic_model(scene)
    calls = {"collocation": lambda: sc.solve_periodic(scene, "collocation", model=model),
             "shooting": lambda: sc.solve_periodic(scene, "shooting", model=model)}
    out, first = first_calls(calls)
    col, shot = first["collocation"], first["shooting"]
    if not quick:  # warm medians
        out = interleaved(calls, 3)
    out.update(period=period, shooting_periods=shot.stats["iterations"],
               shooting_error=float(np.max(np.abs(shot.fairlead_tension - col.fairlead_tension))
                                    / np.ptp(col.fairlead_tension)))
    p = mdl.scene_parameters()
    p.update(cdn=p["cdn"] * 0.01, cdt=p["cdt"] * 0.01, current=(0.0, 0.0), segments=20,
             amplitude=tuple(0.05 * a for a in p["amplitude"]), period=period)
    n_per = 200 if quick else 300
    md = mdl.run(n_per * period, mdl.DT_LIMIT["RK2"], params=p)
    dist = mdl.steady_state_distance(md, period=period)
    n_needed = int(np.argmax(dist <= 0.01)) + 1
    out.update(moordyn_periods=n_per, moordyn_periods_to_1pct=n_needed,
               moordyn_to_1pct=n_needed * md["wall_time"] / n_per,
               moordyn_last_drift=float(dist[-2]))
    return out


def main(argv=None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="fewer repeats and periods (CI)")
    ap.add_argument("--out", default=str(HERE / "out"))
    args = ap.parse_args(argv)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    rep = 3 if args.quick else 7
    st = statics(5 if args.quick else 40)
    tr, runs = time_run(rep, 6 if args.quick else 30, args.quick)
    pe = periodic(0 if args.quick else 3, runs["md"], runs[(True, 100)])
    rs = resonance(args.quick)
    res = {"quick": args.quick, "statics": st, "time_run": tr, "periodic": pe, "resonance": rs}
    (out / "results.json").write_text(json.dumps(res, indent=1, default=float))
    lines = ["| comparison | ratio | detail |", "|---|---|---|",
             f"| statics, solve_static: VM / C | {st['symcable_vm'] / st['symcable_c']:.2f} | "
             f"{1e3 * st['symcable_vm']:.3f} / {1e3 * st['symcable_c']:.3f} ms |",
             f"| statics, fused Newton call: VM / C | {st['newton_call_vm'] / st['newton_call_c']:.2f} | "
             f"{1e6 * st['newton_call_vm']:.0f} / {1e6 * st['newton_call_c']:.0f} us |",
             f"| statics: symcable C / MoorPy | {st['symcable_c'] / st['moorpy']:.2f} | "
             f"MoorPy {1e3 * st['moorpy']:.3f} ms; start guess (once per model) {1e3 * st['start_guess']:.3f} ms |",
             f"| time run: VM / C | {tr['symcable_vm'] / tr['symcable_c']:.2f} | "
             f"{tr['symcable_vm']:.3f} / {tr['symcable_c']:.3f} s (step calls {tr['symcable_vm_steps_s']:.3f} / "
             f"{tr['symcable_c_steps_s']:.3f} s, {tr['symcable_c_us_per_step']:.0f} us and "
             f"{tr['symcable_newton_iterations_per_step']:.2f} iterations per step in C) |",
             f"| time run: symcable C (T/100) / MoorDyn RK4 at its limit | {tr['symcable_c'] / tr['moordyn_RK4']:.2f} | "
             f"MoorDyn RK4 (zeta 0, dtM {mdl.DT_LIMIT['RK4']} s) {tr['moordyn_RK4']:.3f} s; errors "
             f"{tr['symcable_error']:.1e} vs {tr['moordyn_RK4_error']:.1e} |",
             f"| time run: symcable C (T/{tr['steps_equal']}, equal accuracy) / MoorDyn RK4 at its limit | "
             f"{tr['symcable_c_equal'] / tr['moordyn_RK4']:.2f} | symcable {tr['symcable_c_equal']:.3f} s; errors "
             f"{tr['symcable_error_equal']:.1e} vs {tr['moordyn_RK4_error']:.1e} |",
             f"| time run: symcable C (T/100) / MoorDyn RK2 at its limit | {tr['symcable_c'] / tr['moordyn_RK2']:.2f} | "
             f"MoorDyn RK2 (zeta 1, dtM {mdl.DT_LIMIT['RK2']} s) {tr['moordyn_RK2']:.3f} s (+ init "
             f"{tr['moordyn_init']:.3f} s); errors {tr['symcable_error']:.1e} vs {tr['moordyn_RK2_error']:.1e} "
             f"({tr['moordyn_RK2_error_as_returned']:.1e} as returned) |",
             f"| modal analysis (6 modes): 200 / 50 segments | {pe['modal_200'] / pe['modal_50']:.1f} | "
             f"{1e3 * pe['modal_200']:.1f} / {1e3 * pe['modal_50']:.1f} ms (the symmetric problem in the node "
             "velocities, LAPACK's eigensolver; codegen changes nothing) |",
             f"| periodic, collocation | - | "
             f"{pe['collocation']:.2f} s, {pe['iterations']} IPOPT iterations |",
             f"| periodic, shooting | - | "
             f"{pe['shooting']:.3f} s, {pe['shooting_periods']} periods; "
             f"{pe['shooting_error']:.1e} of the range from collocation |",
             f"| periodic: collocation / MoorDyn to 1 % | {pe['collocation'] / pe['moordyn_to_1pct']:.1f} | "
             f"MoorDyn RK2 {pe['moordyn_periods_to_1pct']} periods, {pe['moordyn_to_1pct']:.3f} s |",
             f"| periodic: shooting / MoorDyn to 1 % | {pe['shooting'] / pe['moordyn_to_1pct']:.1f} | "
             f"shooting to its fixed point (default tol), {pe['shooting']:.3f} s |",
             f"| periodic: symcable C marching to 1 % / MoorDyn to 1 % | "
             f"{pe['symcable_march_to_1pct'] / pe['moordyn_to_1pct']:.2f} | symcable (T/100) "
             f"{pe['symcable_periods_to_1pct']} periods, {pe['symcable_march_to_1pct']:.3f} s |",
             f"| light damping at resonance: shooting / MoorDyn to 1 % | "
             f"{rs['shooting'] / rs['moordyn_to_1pct']:.3f} | T = {rs['period']:.2f} s, 20 segments: MoorDyn "
             f"{rs['moordyn_periods_to_1pct']} periods, {rs['moordyn_to_1pct']:.2f} s; shooting "
             f"{rs['shooting_periods']} periods, {rs['shooting']:.3f} s ({100 * rs['shooting_error']:.0f} % "
             f"of the range from collocation at T/100) |",
             f"| light damping at resonance: collocation / MoorDyn to 1 % | "
             f"{rs['collocation'] / rs['moordyn_to_1pct']:.3f} | collocation {rs['collocation']:.2f} s |"]
    if args.quick:
        lines += ["", "--quick: fewer repeats and periods; the periodic solves and modal analyses "
                  "are their first, cold calls (building included), not warm medians: the full "
                  "run's table is the answer."]
    (out / "summary.md").write_text("\n".join(lines) + "\n")
    print("\n".join(lines))
    return res


if __name__ == "__main__":
    main()
