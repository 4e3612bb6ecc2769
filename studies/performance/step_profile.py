"""Where the time of symcable's time step goes on cable3d: the parts of one Newton iteration
of the first-order generalized-alpha step (``symcable.solvers.galpha1``), each compiled and
timed alone at a state from a real run, beside the whole compiled step.

Cases: MoorDyn's chain decks WD0050 (41 segments, 240 states) and WD0600 (170 segments,
1014 states) under the ZZP1_A1 heave (``studies/chains/cases.py`` builds the scenes), run by
``GeneralizedAlphaFirstOrder(rho_inf=0)`` (``simulate``'s scheme for cable3d) at dt = 0.1 s.

The parts are built exactly as ``galpha1._unrolled`` builds them (its private helpers are
called, so the graphs are the step's own):

* ``residual``: F(w; x, t, h, p), the DAE residual at the step's alpha points (SX, written
  out straight-line), evaluated at every iteration;
* ``jacobian``: the nonzeros of dF/dw (SX), the iteration matrix;
* ``factor``: what the step evaluates to refactorise (at the first iteration and from the
  CHORD_ITERATIONS-th on): the Jacobian and its block LU written out in SX up to
  SXLU_MAX_STATES_C states (WD0050), above it (WD0600) the Jacobian and its banded LU (loops,
  :mod:`symcable.linalg.banded`), or the Jacobian alone where the solve is sparse QR (a
  pattern with no narrow band);
* ``solve``: J^-1 b from the factor's output: the two triangular solves of the LU, or the
  sparse QR (CasADi's, with dense rows split off), which factorises at each call.

Per step with k linear solves (the step's ``iterations``): k + 1 residuals, k solves and
1 + max(0, k - CHORD_ITERATIONS) factors; the sum is set beside the compiled step's own time
at the same state (its remainder: the loop's norms, branches and copies).

Timing: each Function compiled to C (``symcable.codegen``, the cache), called through
``FastCall`` at the state of a run 5 s after the start (t = -5 s: the fairlead at full heave
speed, the chain on the bed), ``repeats`` interleaved rounds of blocks of calls, medians per
call (us of CPU time). ``--quick``: WD0050 only, in the CasADi virtual machine (no
compiling), 3 rounds. Also measured: the element forces and their Jacobian written out
straight-line (as now) against the element kernel kept as a loop (:func:`kernel_loops`),
and with ``--tol-dt DT`` the Newton iterations per step at tol 1e-10 (the default) and 1e-8
over the 80 s run of WD0050 at the step DT (``cable3d_moordyn.py``'s equal-accuracy step:
0.05 s).

Run: ``python studies/performance/step_profile.py [--quick] [--out DIR]`` (full: compiling
WD0600's Jacobian takes minutes). Writes ``step_profile.json`` and ``step_profile.md``.
"""
from __future__ import annotations

import argparse
import json
import math
import statistics
import sys
import time
from pathlib import Path

import casadi as ca
import numpy as np

from symcable.cable3d_static import cable3d_mechanism
from symcable.codegen import FastCall, compile_functions
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
    linear solver's kind: "block-lu", "banded" or "qr")."""
    ny = mech.n_q + mech.n_v
    x, t, h, p, st, _ = ga._symbols(mech, ca.SX)
    w = ca.SX.sym("w", ny)
    r = ga._step_residual(ga._sx_residual(mech), w, x, t, h, p, st[0], ny)
    args = [w, x, t, h, p, st]
    opts = {"cse": ny <= ga.CSE_MAX_STATES}
    J = ga._jacobian(r, w)
    factor, solve, _, kind = ga._linear_solver(J, args, {}, lu, mech.n_q)
    # with sparse QR the factor is the Jacobian's nonzeros: the same graph, timed once
    jac = factor if kind == "qr" else ca.Function("prof_jacobian", args, [J.nz[:]], opts)
    return {"residual": ca.Function("prof_residual", args, [r], opts), "jacobian": jac,
            "factor": factor, "solve": solve}, kind


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


def profile(deck: str, out: Path, codegen: bool, repeats: int) -> dict:
    """The breakdown of one deck (module docstring); times in us."""
    scene = cases.chain_scene(deck, cases.extended_table("A1", out))
    mech = cable3d_mechanism(scene)
    ny = mech.n_q + mech.n_v
    eq = solve_equilibrium(mech, codegen=codegen)
    opts = GeneralizedAlphaFirstOrder(rho_inf=RHO)
    lu = ny <= ga.SXLU_MAX_STATES or (codegen and ny <= ga.SXLU_MAX_STATES_C)
    fns, kind = parts(mech, lu)
    sizes = {k: int(f.n_instructions()) for k, f in fns.items()}
    compile_s = {}
    if codegen:
        done = {}
        for k, f in list(fns.items()):
            if f.name() not in done:
                t0 = time.perf_counter()
                done[f.name()] = compile_functions([f], what=f"the step's {k}")[f.name()]
                compile_s[k] = time.perf_counter() - t0
            fns[k] = done[f.name()]
    kern = ga.galpha1_kernel(mech, opts, lte=False, codegen=codegen)
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
    return {"deck": deck, "states": ny, "solver": {"block-lu": "block LU (SX)", "banded": "banded LU (loops)",
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


def kernel_loops(N: int, codegen: bool, repeats: int) -> dict:
    """The element forces of N elements of WD0050's chain (cable3d's element kernel, Morison
    drag, no contact) and their Jacobian with respect to the node positions and velocities,
    two ways, each compiled and timed like the parts: ``straight`` as the model builds them
    (the kernel mapped over the elements on SX symbols, so written out element by element,
    and the Jacobian taken by CasADi on that expression) and ``loops`` (the kernel mapped
    ``serial`` on MX: one loop over the elements in the generated C; the Jacobian as each
    element's own 6 x 12 block, the kernel's Jacobian in a loop, left unassembled). Times
    in us, compile times in s."""
    from symcable.models.cable3d import _element_kernel
    kern = _element_kernel()
    ds, w, rho, d = 10.0, 390 * 9.80665 * (1 - 1025 / 7850), 1025.0, 0.252
    const = [ds, 1.674e9, 8.1e6, 1e3, 1e-4, 1e6, w, d, 1.37, 0.64 * math.pi, rho, 1.0]
    args = [ca.DM.ones(1, N) * c for c in const]
    water = ca.DM.zeros(3, N)
    rng = np.random.default_rng(1)
    X0 = np.vstack([np.linspace(400.0, 0.0, N + 1), np.zeros(N + 1), np.linspace(-50.0, 0.0, N + 1)])
    xv = np.concatenate([(X0 * (1 + 1e-3 * rng.standard_normal(X0.shape))).ravel("F"),
                         0.1 * rng.standard_normal(3 * (N + 1))])
    out = {"N": N}
    fns = {}
    for way, S in (("straight", ca.SX), ("loops", ca.MX)):
        z = S.sym("xv", 6 * (N + 1))
        X, V = ca.reshape(z[:3 * (N + 1)], 3, N + 1), ca.reshape(z[3 * (N + 1):], 3, N + 1)
        mapped = kern.map(N) if way == "straight" else kern.map(N, "serial")
        fa, fb, _, _ = mapped(X[:, :-1], X[:, 1:], V[:, :-1], V[:, 1:], water, *args)
        nodal = ca.horzcat(fa, S.zeros(3, 1)) + ca.horzcat(S.zeros(3, 1), fb)
        if way == "straight":
            jac = ca.jacobian(ca.vec(nodal), z).nz[:]
        else:
            e = [ca.SX.sym(n, 3) for n in ("xa", "xb", "va", "vb")]
            ins = kern.sx_in()  # one element written out in SX, its Jacobian too
            fa1, fb1, _, _ = kern(*e, *ins[4:])
            ej = ca.Function("elem_jac", [*e, *ins[4:]],
                             [ca.jacobian(ca.vertcat(fa1, fb1), ca.vertcat(*e))])
            jac = ej.map(N, "serial")(X[:, :-1], X[:, 1:], V[:, :-1], V[:, 1:], water, *args)
        fns[f"{way}_forces"] = ca.Function(f"kl_{way}_f{N}", [z], [ca.vec(nodal)], {"cse": True})
        fns[f"{way}_jacobian"] = ca.Function(f"kl_{way}_j{N}", [z], [ca.vec(jac)], {"cse": True})
    out["instructions"] = {k: int(f.n_instructions()) for k, f in fns.items()}
    out["compile_s"] = {}
    if codegen:
        for k, f in list(fns.items()):
            t0 = time.perf_counter()
            fns[k] = compile_functions([f], what=f"an element-kernel experiment ({k})")[f.name()]
            out["compile_s"][k] = time.perf_counter() - t0
    calls = {k: FastCall(f) for k, f in fns.items()}
    a = calls["straight_forces"](xv)[0]
    b = calls["loops_forces"](xv)[0]
    out["forces_agree"] = float(np.max(np.abs(a - b)) / np.max(np.abs(a)))
    med = _median_times({k: (lambda c=c: c(xv)) for k, c in calls.items()}, repeats)
    out["us"] = {k: 1e6 * v for k, v in med.items()}
    return out


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


def table(rows: list) -> str:
    lines = ["| case | states | solver | calls R / F / S | residual us (instr.) | "
             "Jacobian us (instr.) | factor us | solve us | parts summed us | in the step's "
             "order us: R / F / S | step us | residual / factor / solve / rest |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        u, n, s, c, q = r["us"], r["instructions"], r["shares"], r["calls"], r["in_sequence_us"]
        lines.append(
            f"| {r['deck']}{'' if r['compiled'] else ' (VM)'} | {r['states']} | {r['solver']} | "
            f"{c['residual']} / {c['factor']} / {c['solve']} | {u['residual']:.0f} ({n['residual']:,}) | {u['jacobian']:.0f} "
            f"({n['jacobian']:,}) | {u['factor']:.0f} | {u['solve']:.0f} | {r['parts_sum_us']:.0f} | "
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
    rows = [profile(d, args.out, not args.quick, 3 if args.quick else 15) for d in decks]
    res = {"quick": args.quick, "rows": rows}
    text = table(rows)
    res["kernel_loops"] = kl = [kernel_loops(n, not args.quick, 3 if args.quick else 15)
                                for n in ((41,) if args.quick else (41, 170))]
    text += ("\n| elements | forces: straight-line / loop us | Jacobian: straight-line / loop "
             "(element blocks) us | instructions straight-line: forces / Jacobian | compile s: "
             "straight-line / loop |\n|---|---|---|---|---|\n")
    for k in kl:
        u, n, c = k["us"], k["instructions"], k["compile_s"]
        cs = (f"{c['straight_forces'] + c['straight_jacobian']:.1f} / "
              f"{c['loops_forces'] + c['loops_jacobian']:.1f}") if c else "-"
        text += (f"| {k['N']} | {u['straight_forces']:.1f} / {u['loops_forces']:.1f} | "
                 f"{u['straight_jacobian']:.1f} / {u['loops_jacobian']:.1f} | "
                 f"{n['straight_forces']:,} / {n['straight_jacobian']:,} | {cs} |\n")
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
