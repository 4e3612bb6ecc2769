"""Where the time of symcable's time step goes on cable3d: the parts of one Newton iteration
of the first-order generalized-alpha step (``symcable.solvers.galpha1``), each compiled and
timed alone at a state from a real run, beside the whole compiled step.

Cases: MoorDyn's chain decks WD0050 (41 segments, 240 states) and WD0600 (170 segments,
1014 states) under the ZZP1_A1 heave (``studies/chains/cases.py`` builds the scenes), run by
``GeneralizedAlphaFirstOrder(rho_inf=0)`` (``simulate``'s scheme for cable3d) at dt = 0.1 s.

The parts are built exactly as ``galpha1._unrolled`` builds them (``galpha1.step_parts``,
so the graphs are the step's own), two ways per deck:

* ``elements`` (the step's default for a cable3d line from ELEMENT_MIN_STATES states on):
  the residual and the matrix from the Mechanism's element form
  (``symcable.solvers.element_jacobian``): a loop over the elements of the element kernel
  and of its own 6 x 12 Jacobian block, the per-node rest (kinematic rows, seabed) written
  out in SX, summed by index gathers; factorised by the banded LU (loops,
  :mod:`symcable.linalg.banded`);
* ``written``: the residual F(w; x, t, h, p) and the nonzeros of dF/dw written out
  straight-line in SX; factorised by the block LU written out in SX up to SXLU_MAX_STATES_C
  states (WD0050), above it (WD0600) by the banded LU.

The parts: ``residual``, F at the step's alpha points, evaluated at every iteration;
``jacobian``, the nonzeros of the iteration matrix; ``factor``, what the step evaluates to
refactorise (at the first iteration and from the CHORD_ITERATIONS-th on): the matrix and its
LU; ``solve``, J^-1 b from the factor's output (the LU's two triangular solves).

Per step with k linear solves (the step's ``iterations``): k + 1 residuals, k solves and
1 + max(0, k - CHORD_ITERATIONS) factors; the sum is set beside the compiled step's own time
at the same state (its remainder: the loop's norms, branches and copies).

Timing: each Function compiled to C (``symcable.mechanism.codegen``, the cache), called through
``FastCall`` at the state of a run 5 s after the start (t = -5 s: the fairlead at full heave
speed, the chain on the bed), ``repeats`` interleaved rounds of blocks of calls, medians per
call (us of CPU time). ``--quick``: WD0050 only, in the CasADi virtual machine (no
compiling), 3 rounds. With ``--tol-dt DT`` also the Newton iterations per step at tol 1e-10
and 1e-8 over the 80 s run of WD0050 at the step DT (``cable3d_moordyn.py``'s
equal-accuracy step: 0.05 s).

Run: ``python studies/performance/step_profile.py [--quick] [--out DIR]`` (full: compiling
WD0600's written-out Jacobian takes minutes, the element loops seconds). Writes
``step_profile.json`` and ``step_profile.md``.
"""
from __future__ import annotations

import argparse
import json
import statistics
import sys
import time
from pathlib import Path

import numpy as np

from symcable.models.cable3d.line import build_cable3d
from symcable.mechanism.codegen import FastCall, compile_functions
from symcable.solvers import galpha1 as ga
from symcable.solvers.equilibrium import solve_equilibrium
from symcable.solvers.integrate import integrate
from symcable.solvers.options import GeneralizedAlphaFirstOrder

HERE = Path(__file__).resolve().parent
if str(HERE.parent) not in sys.path:
    sys.path.append(str(HERE.parent))
from study_io import load_module  # noqa: E402  (studies/study_io.py)


def _load_sibling(name: str):
    return load_module(HERE / f"{name}.py", f"performance_{name}")


cases = load_module(HERE.parent / "chains" / "cases.py", "chains_cases")

DT = 0.1  # s
RHO = 0.0  # simulate's rho_inf for cable3d


def parts(mech, lu: bool) -> tuple[dict, str]:
    """({name: Function} of the step's parts (module docstring), with inputs
    (w, x, t, h, p, settings) for residual / jacobian / factor and (f, b) for solve; the
    linear solver's kind: "block-lu", "banded" or "qr"), as the step builds them
    (``galpha1.step_parts``: from the element form where the Mechanism has one and ``lu``
    is off)."""
    R, factor, solve, _, kind, jac = ga.step_parts(mech, lu)
    return {"residual": R, "jacobian": jac, "factor": factor, "solve": solve}, kind


def state(mech, eq, t_run: float, codegen) -> tuple:
    """(x = (y, y'), t) after ``t_run`` s from the table's start: y from the run, y' the
    backward difference of its last two samples."""
    tr = integrate(mech, t_run, DT, t0=cases.T0, start=eq, p=mech.params.values,
                   method=GeneralizedAlphaFirstOrder(rho_inf=RHO), codegen=codegen, progress=False)
    y = np.concatenate([tr.q, tr.v], axis=1)
    return np.concatenate([y[-1], (y[-1] - y[-2]) / DT]), float(tr.time[-1])


def _median_times(calls: dict, repeats: int, block_s: float = 0.02) -> dict:
    """Median seconds per call of each callable, CPU time of this thread
    (``time.thread_time``: the machine is shared, and a descheduled process's wall time
    counts its neighbours' work): ``repeats`` interleaved rounds, each a block of
    back-to-back calls lasting about ``block_s`` s (sized from a first call)."""
    blocks = {}
    for k, f in calls.items():
        t0 = time.thread_time()
        f()
        blocks[k] = max(1, int(block_s / max(time.thread_time() - t0, 1e-6)))
    out = {k: [] for k in calls}
    for _ in range(repeats):
        for k, f in calls.items():
            t0 = time.thread_time()
            for _ in range(blocks[k]):
                f()
            out[k].append((time.thread_time() - t0) / blocks[k])
    return {k: statistics.median(v) for k, v in out.items()}


def profile(deck: str, out: Path, codegen: bool, repeats: int, way: str = "elements") -> dict:
    """The breakdown of one deck (module docstring) with the step's residual and matrix
    from the element form (``way`` "elements", the default) or written out in SX
    ("written"); times in us."""
    scene = cases.chain_scene(deck, cases.extended_table("A1", out))
    saved = ga.ELEMENT_MATRIX
    ga.ELEMENT_MATRIX = way == "elements"
    try:
        mech = build_cable3d(scene)  # not the cached Mechanism: the steps of both ways
        ny = mech.n_q + mech.n_v
        eq = solve_equilibrium(mech, codegen=codegen)
        opts = GeneralizedAlphaFirstOrder(rho_inf=RHO)
        lu, _ = ga.solver_choice(mech, codegen)
        fns, kind = parts(mech, lu)
        kern = ga.galpha1_kernel(mech, opts, lte=False, codegen=codegen)
    finally:
        ga.ELEMENT_MATRIX = saved
    # straight-line SX instructions; None for an MX graph (element loops, LU loops)
    sizes = {k: int(f.n_instructions()) if f.is_a("SXFunction") else None
             for k, f in fns.items()}
    compile_s = {}
    if codegen:
        done = {}
        for k, f in list(fns.items()):
            if f.name() not in done:
                t0 = time.perf_counter()
                done[f.name()] = compile_functions([f], what=f"the step's {k}")[f.name()]
                compile_s[k] = time.perf_counter() - t0
            fns[k] = done[f.name()]
    x, t = state(mech, eq, 5.0, codegen)
    p = np.asarray(mech.params.values, float)
    settings = np.array([opts.rho_inf, opts.tol])
    scales = ga.step_scales(mech)
    w = x[ny:]
    R, Jf, Ff, S, K = (FastCall(fns["residual"]), FastCall(fns["jacobian"]), FastCall(fns["factor"]),
                       FastCall(fns["solve"]), FastCall(kern))
    x1, err, _, its, failed = K(x, t, DT, p, settings, scales)
    z, n = newton(R, Ff, S, x, t, p, settings, scales, ny)
    gamma = ga.coefficients(RHO)[2]
    y1 = x[:ny] + DT * x[ny:] + gamma * DT * (z - x[ny:])
    agree = float(np.max(np.abs(y1 - x1[:ny]) / scales[:ny]))
    r = R(w, x, t, DT, p, settings)[0]
    f = Ff(w, x, t, DT, p, settings)[0]
    med = _median_times({
        "residual": lambda: R(w, x, t, DT, p, settings),
        "jacobian": lambda: Jf(w, x, t, DT, p, settings),
        "factor": lambda: Ff(w, x, t, DT, p, settings),
        "solve": lambda: S(f, r),
        "step": lambda: K(x, t, DT, p, settings, scales)}, repeats)
    us = {key: 1e6 * v for key, v in med.items()}
    seq = in_sequence(R, Ff, S, x, t, p, settings, scales, ny, 3 * repeats)
    spent = {key: n[key] * us[key] for key in ("residual", "factor", "solve")}
    parts_sum = sum(spent.values())
    return {"deck": deck, "way": way, "states": ny,
            "solver": {"block-lu": "block LU (SX)", "banded": "banded LU (loops)",
                       "qr": "sparse QR"}[kind],
            "compiled": bool(codegen), "instructions": sizes, "compile_s": compile_s,
            "t": t, "iterations": int(round(float(its[0]))), "failed": float(failed[0]),
            "calls": n, "replica_vs_step": agree, "us": us, "parts_sum_us": parts_sum,
            "in_sequence_us": seq,
            "shares": dict({key: v / us["step"] for key, v in spent.items()},
                           rest=1.0 - parts_sum / us["step"])}


def newton(R, F, S, x, t, p, settings, scales, ny, spent: dict | None = None) -> tuple:
    """The step's Newton loop (``galpha1._unrolled``) replayed on the parts: the iterate y'1
    and how many times each part was called {"residual", "factor", "solve"}; with ``spent``,
    each part's CPU time (s) in this replay is added to it (the parts called in the step's
    order, each after the others: as the step meets them in the caches)."""
    tol, gamma = settings[1], ga.coefficients(settings[0])[2]
    z, f = x[ny:].copy(), None
    n = {"residual": 0, "factor": 0, "solve": 0}
    clock = time.thread_time

    def call(part, fn, *args):
        t0 = clock()
        out = fn(*args)[0]
        if spent is not None:
            spent[part] = spent.get(part, 0.0) + clock() - t0
        n[part] += 1
        return out

    for i in range(ga.CHORD_ITERATIONS + 50):
        rv = call("residual", R, z, x, t, DT, p, settings)
        if np.max(np.abs(DT * rv * scales[ny:])) <= tol:
            break
        if i == 0 or i >= ga.CHORD_ITERATIONS:
            f = call("factor", F, z, x, t, DT, p, settings)
        dz = -call("solve", S, f, rv)
        z = z + dz
        if np.max(np.abs(gamma * DT * dz / scales[:ny])) <= tol:
            break
    return z, n


def in_sequence(R, F, S, x, t, p, settings, scales, ny, repeats: int) -> dict:
    """Median CPU time (us) each part takes per step when called in the step's sequence
    (:func:`newton` replayed ``repeats`` times), and the whole replay's."""
    rounds = []
    for _ in range(repeats):
        spent = {}
        t0 = time.thread_time()
        newton(R, F, S, x, t, p, settings, scales, ny, spent)
        spent["replay"] = time.thread_time() - t0
        rounds.append(spent)
    return {k: 1e6 * statistics.median(r[k] for r in rounds) for k in rounds[0]}


def newton_tolerance(out: Path, dt: float) -> dict:
    """Newton iterations per step and the top-segment tension's change over WD0050's 80 s
    run at ``dt`` s: tol 1e-10 (the default) against 1e-8."""
    import symcable as sc
    cm = _load_sibling("cable3d_moordyn")
    scene = cases.chain_scene("WD0050", cm.periodic_table(out, 90.0))
    res = {}
    sc.simulate(scene, 90.0, dt=dt, codegen=True, progress=False)  # builds, loads: untimed
    for tol in (1e-10, 1e-8):
        c0 = time.process_time()
        tr = sc.simulate(scene, 90.0, dt=dt, codegen=True, progress=False, newton_tol=tol)
        res[tol] = (tr.stats["newton_iterations"] / tr.stats["steps"], time.process_time() - c0,
                    np.asarray(tr.axial_force)[:, -1])
    (i10, s10, T10), (i8, s8, T8) = res[1e-10], res[1e-8]
    return {"dt": dt, "iterations_1e-10": i10, "iterations_1e-8": i8, "cpu_1e-10": s10,
            "cpu_1e-8": s8, "tension_change_of_range": float(np.max(np.abs(T8 - T10)) / np.ptp(T10))}


#: how each row's step has its residual and matrix
WAYS = {"elements": "element loops", "written": "written out (SX)"}


def _count(n) -> str:
    return "loops" if n is None else f"{n:,}"


def table(rows: list) -> str:
    lines = ["| case | residual and matrix | states | solver | calls R / F / S | residual us "
             "(instr.) | Jacobian us (instr.) | factor us | solve us | parts summed us | "
             "in the step's order us: R / F / S | step us | residual / factor / solve / rest |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        u, n, s, c, q = r["us"], r["instructions"], r["shares"], r["calls"], r["in_sequence_us"]
        lines.append(
            f"| {r['deck']}{'' if r['compiled'] else ' (VM)'} | {WAYS[r['way']]} | "
            f"{r['states']} | {r['solver']} | "
            f"{c['residual']} / {c['factor']} / {c['solve']} | {u['residual']:.0f} "
            f"({_count(n['residual'])}) | {u['jacobian']:.0f} ({_count(n['jacobian'])}) | "
            f"{u['factor']:.0f} | {u['solve']:.0f} | {r['parts_sum_us']:.0f} | "
            f"{q['residual']:.0f} / {q['factor']:.0f} / {q['solve']:.0f} | "
            f"{u['step']:.0f} | {100 * s['residual']:.0f} / {100 * s['factor']:.0f} / "
            f"{100 * s['solve']:.0f} / {100 * s['rest']:.0f} % |")
    return "\n".join(lines) + "\n"


def main(argv=None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--quick", action="store_true", help="WD0050 in the virtual machine, 3 rounds")
    ap.add_argument("--out", type=Path, default=HERE / "out")
    ap.add_argument("--tol-dt", type=float, default=None,
                    help="also compare Newton tol 1e-10 and 1e-8 on WD0050's 80 s run at this dt (s)")
    args = ap.parse_args(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    decks = ("WD0050",) if args.quick else ("WD0050", "WD0600")
    rows = [profile(d, args.out, not args.quick, 3 if args.quick else 15, way)
            for d in decks for way in ("elements", "written")]
    res = {"quick": args.quick, "rows": rows}
    text = table(rows)
    if args.tol_dt:
        res["newton_tol"] = nt = newton_tolerance(args.out, args.tol_dt)
        text += (f"\nWD0050, 80 s at dt = {nt['dt']} s: Newton iterations per step "
                 f"{nt['iterations_1e-10']:.2f} at tol 1e-10, {nt['iterations_1e-8']:.2f} at 1e-8; "
                 f"CPU time of the run {nt['cpu_1e-10']:.2f} / {nt['cpu_1e-8']:.2f} s; top-segment "
                 f"tension changed by {nt['tension_change_of_range']:.1e} of its range.\n")
    (args.out / "step_profile.json").write_text(json.dumps(res, indent=1, default=float))
    (args.out / "step_profile.md").write_text(text)
    print(text)
    return res


if __name__ == "__main__":
    main()
