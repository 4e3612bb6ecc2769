"""Would keeping the factorised iteration matrix from one time step to the next pay on the
MoorDyn chains? A replay of the first-order generalized-alpha run on the step's own parts.

Question
--------
symcable's first-order generalized-alpha step (``symcable.solvers.galpha1``) factorises its
iteration matrix at the first Newton iteration of every step and reuses it (chord
iterations) while each iteration at least halves the residual. On WD0600 the factorisation
(the Jacobian, 344k instructions of straight-line C, and its banded LU) is 58 % of a step
(``step_profile.py``). Starting each step with the previous step's factors instead, and
refactorising only where an iteration does not contract, how many factorisations, residuals
and solves does a run take per step, how much would the parts cost, and does the run land
on the same states?

Method
------
The parts are ``step_profile.parts`` (the step's own residual, factor and solve Functions,
compiled), Newton's start is the step's own predictor (``galpha1._predictor`` with the
Taylor candidate), and the loop is the step's policy replayed in Python: converged when the
scaled residual or the scaled correction is at most the tolerance (1e-8, the chains'
``simulate`` default); the matrix refactorised at the first iteration ("fresh": the step as
it is) or only where the carried one fails to halve the residual and from the
CHORD_ITERATIONS-th iteration on ("carried"). Both runs go from the static state at t =
-10 s to ``t_end`` at fixed steps (no substeps: a step that does not converge in 40
iterations is counted as failed). The parts' cost per step is the calls times the parts'
CPU time (us) timed warm at the static state (medians of interleaved rounds, as
``step_profile.py``); the loop's own work (norms, copies, switches: 20 % of WD0600's step)
is not in it.

Run: ``python studies/performance/carried_factor.py [--quick] [--out DIR]`` (full: WD0600
under A1 at 0.1 s and under A2 at 0.05 and 0.1 s, rho_inf 0 and 0.2, and WD0050 A1 at
0.1 s; compiled, a few minutes after the step's C is cached). ``--quick``: WD0050 A1 at
0.2 s over the first 2 s, the virtual machine. Writes ``carried_factor.json`` and
``carried_factor.md``.
"""
from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

import casadi as ca
import numpy as np

from symcable.api.cable3d_static import cable3d_mechanism
from symcable.mechanism.codegen import FastCall, compile_functions
from symcable.solvers import galpha1 as ga
from symcable.solvers.equilibrium import solve_equilibrium

HERE = Path(__file__).resolve().parent
if str(HERE.parent) not in sys.path:
    sys.path.append(str(HERE.parent))
from study_io import load_module  # noqa: E402  (studies/study_io.py)

cases = load_module(HERE.parent / "chains" / "cases.py", "chains_cases")
profile = load_module(HERE / "step_profile.py", "performance_step_profile")

TOL = 1e-8  # the chains' Newton tolerance (simulate's default)
MAX_ITER = 40  # a step not converged in this many iterations counts as failed
FULL = (("WD0050", "A1", 0.1, 0.0), ("WD0600", "A1", 0.1, 0.0), ("WD0600", "A2", 0.1, 0.0),
        ("WD0600", "A2", 0.05, 0.2), ("WD0600", "A2", 0.1, 0.2))
QUICK = (("WD0050", "A1", 0.2, 0.0),)


class Parts:
    """The step's parts of one deck and rho_inf, compiled or not, and Newton's start."""

    def __init__(self, deck, motion, rho, out: Path, codegen: bool):
        self.mech = mech = cable3d_mechanism(cases.chain_scene(deck, cases.extended_table(
            motion, out)))
        self.ny = ny = mech.n_q + mech.n_v
        fns, self.kind = profile.parts(mech, ga.solver_choice(mech, codegen)[0])
        fns = {k: fns[k] for k in ("residual", "factor", "solve")}
        if codegen:
            fns = {k: compile_functions([f], what=f"the step's {k}")[f.name()]
                   for k, f in fns.items()}
        self.R, self.F, self.S = (FastCall(fns[k]) for k in ("residual", "factor", "solve"))
        x, t, h, p, st, sc = ga._symbols(mech, ca.MX)
        gamma = ga.coefficients(rho)[2]
        res = fns["residual"]
        start, _, _ = ga._predictor(
            lambda r_: ga.norm_inf(h * r_ * sc[ny:]), x, ny, mech.n_q, gamma,
            residual=lambda w_: res(w_, x, t, h, p, st), symbols=[x, t, h, p, st, sc],
            taylor=ga._taylor_rate(mech, x, t, h, p, gamma))
        self.start = FastCall(ca.Function("carried_start", [x, t, h, p, st, sc], [start]))
        self.p = np.asarray(mech.params.values, float)
        self.settings = np.array([rho, TOL])
        self.scales = ga.step_scales(mech)
        self.gamma = gamma
        eq = solve_equilibrium(mech, codegen=codegen)
        self.x0 = np.concatenate([np.ravel(eq.q), np.zeros(mech.n_v), np.zeros(ny)])

    def cost_us(self, repeats: int) -> dict:
        """CPU time (us) of each part at the static state, warm (step_profile's timing)."""
        x, ny, dt = self.x0, self.ny, 0.1
        w = x[ny:]
        f = self.F(w, x, cases.T0, dt, self.p, self.settings)[0]
        r = self.R(w, x, cases.T0, dt, self.p, self.settings)[0]
        med = profile._median_times({
            "residual": lambda: self.R(w, x, cases.T0, dt, self.p, self.settings),
            "factor": lambda: self.F(w, x, cases.T0, dt, self.p, self.settings),
            "solve": lambda: self.S(f, r)}, repeats)
        return {k: 1e6 * v for k, v in med.items()}


def replay(parts: Parts, dt: float, t_end: float, carry: bool) -> tuple[np.ndarray, dict]:
    """(the state at t_end, calls per step {"residual", "factor", "solve"} and "failed" steps)
    of the run from the static state at T0 with fresh or carried factors (module docstring)."""
    ny, sc, p, st = parts.ny, parts.scales, parts.p, parts.settings
    x, t, f = parts.x0.copy(), cases.T0, None
    n = {"residual": 0, "factor": 0, "solve": 0, "failed": 0}
    steps = int(round((t_end - cases.T0) / dt))
    for _ in range(steps):
        z = np.ravel(parts.start(x, t, dt, p, st, sc)[0])
        f = f if carry else None
        prev, ok = np.inf, False
        for i in range(MAX_ITER):
            rv = np.ravel(parts.R(z, x, t, dt, p, st)[0])
            n["residual"] += 1
            res = float(np.max(np.abs(dt * rv * sc[ny:])))
            if res <= TOL:
                ok = True
                break
            stalled = i > 0 and res > ga.CHORD_CONTRACTION * prev
            if f is None or i >= ga.CHORD_ITERATIONS or stalled:
                f = parts.F(z, x, t, dt, p, st)[0]
                n["factor"] += 1
            dz = -np.ravel(parts.S(f, rv)[0])
            n["solve"] += 1
            z, prev = z + dz, res
            if np.max(np.abs(parts.gamma * dt * dz / sc[:ny])) <= TOL:
                ok = True
                break
        n["failed"] += 0 if ok else 1
        y1 = x[:ny] + dt * x[ny:] + parts.gamma * dt * (z - x[ny:])
        x, t = np.concatenate([y1, z]), t + dt
    return x, {k: v / steps for k, v in n.items()} | {"steps": steps}


def study(runs, out: Path, codegen: bool, t_end: float, repeats: int) -> list:
    rows, built = [], {}
    for deck, motion, dt, rho in runs:
        key = (deck, motion, rho)
        if key not in built:
            built[key] = Parts(deck, motion, rho, out, codegen)
        parts = built[key]
        us = parts.cost_us(repeats)
        row = {"deck": deck, "motion": motion, "dt": dt, "rho_inf": rho, "states": parts.ny,
               "solver": parts.kind, "compiled": codegen, "part_us": us}
        states = {}
        for way in ("fresh", "carried"):
            states[way], calls = replay(parts, dt, t_end, way == "carried")
            calls["parts_us_per_step"] = sum(calls[k] * us[k] for k in us)
            row[way] = calls
        ny = parts.ny
        row["state_difference"] = float(np.max(np.abs(states["carried"][:ny] - states["fresh"][:ny])
                                               / parts.scales[:ny]))
        rows.append(row)
        print(f"{deck} {motion} dt {dt} rho_inf {rho}: fresh {row['fresh']}, carried "
              f"{row['carried']}", flush=True)
    return rows


def table(rows: list) -> str:
    lines = ["| case | dt (s) | rho_inf | states | parts us: residual / factor / solve | fresh: "
             "residual / factor / solve per step | carried: the same | failed steps: fresh / "
             "carried | parts us per step: fresh / carried (ratio) | state difference (scaled) |",
             "|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        u, a, b = r["part_us"], r["fresh"], r["carried"]
        lines.append(
            f"| {r['deck']} {r['motion']}{'' if r['compiled'] else ' (VM)'} | {r['dt']:g} | "
            f"{r['rho_inf']:g} | {r['states']} | {u['residual']:.0f} / {u['factor']:.0f} / "
            f"{u['solve']:.0f} | {a['residual']:.2f} / {a['factor']:.2f} / {a['solve']:.2f} | "
            f"{b['residual']:.2f} / {b['factor']:.2f} / {b['solve']:.2f} | "
            f"{a['failed']:.3f} / {b['failed']:.3f} | {a['parts_us_per_step']:.0f} / "
            f"{b['parts_us_per_step']:.0f} ({b['parts_us_per_step'] / a['parts_us_per_step']:.2f})"
            f" | {r['state_difference']:.1e} |")
    return "\n".join(lines) + "\n"


def main(argv=None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--quick", action="store_true",
                    help="WD0050 A1 at 0.2 s over 2 s, the virtual machine")
    ap.add_argument("--out", type=Path, default=HERE / "out")
    args = ap.parse_args(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    runs, t_end = (QUICK, cases.T0 + 2.0) if args.quick else (FULL, 20.0)
    rows = study(runs, args.out, not args.quick, t_end, 3 if args.quick else 15)
    res = {"quick": args.quick, "t_end": t_end, "tol": TOL, "rows": rows}
    text = table(rows)
    (args.out / "carried_factor.json").write_text(json.dumps(res, indent=1, default=float))
    (args.out / "carried_factor.md").write_text(text)
    print(text)
    return res


if __name__ == "__main__":
    main()
