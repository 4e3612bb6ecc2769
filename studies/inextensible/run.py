"""Inextensibility of the rod: a stiff axial energy (EA, on main) or an exact constraint
|x_{j+1} - x_j| = ds per edge carried in z (its multiplier the tension)? Issue 14, item 1.

Question
--------
The rod on main (symcable/models/rod/rod.py) is inextensible through cable3d's axial law EA e
with a stiff EA. The exact alternative is one length constraint per edge with a Lagrange
multiplier (the tension), solved on the KKT system in statics and as an index-3 DAE by the
generalized-alpha step of Arnold & Bruels (2007) in time. Which is better, measured: in
statics the tension and tip differences (they should scale like T/EA), Newton iterations,
the Jacobian's condition number, time per solve; in time, Newton iterations per step,
whether the stiff rod's axial frequency sqrt(EA/m)/ds shows in the step (tension noise),
time per step, at dt = 1, 0.1, 0.01 s.

Method
------
The constrained rod is the rod Mechanism with its axial term cancelled and the constraint
added (``inext_constrained.py``; no library change). Both run through the same code:
1. Closed form (``inext_statics.closed_form``): the benchmark's cable hanging straight from a pin
   with a 0.05 N tip force: T_j = P + w (L - s_j) for both, the constrained tip at exactly
   -L, the stiff one (P L + w L^2 / 2) / EA lower.
2. Statics of seed 000's benchmark (symcable/data/seed000_rod.toml, Table 1) at several
   segment counts: the constrained rod against the stiff rod at EA x 0.01, 1, 100
   (``inext_statics.compare``: plain Newton on the Mechanism's static residual with its exact
   Jacobian; iterations from the straight start and from each model's solution at 0.9 x
   the loads; condition numbers at the solution).
3. Dynamics (``inext_dynamics.py``: the library's generalized-alpha step, Newton written out):
   the benchmark from rest with a vertical velocity 0.01 sin(pi s/L) m/s, and a pendulum
   (one edge, pinned, in air, released at 60 deg; the elliptic closed form), at several dt
   and rho_inf.

Run
---
    python studies/inextensible/run.py          # full: statics at 20, 80, 400 segments,
                                                # dynamics at 40 (~15 min)
    python studies/inextensible/run.py --quick  # statics at 10, dynamics at 10 over 2 s at
                                                # dt = 1, 0.1; the pendulum at 0.1, 0.01 s
    options: --out DIR (default studies/inextensible/out/)

Writes ``results.csv`` and ``summary.md`` to the out dir. ``main(argv)`` returns
``{"rows", "closed_form", "statics", "perturbed", "pendulum", "summary"}``.
"""
from __future__ import annotations

import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
sys.path.insert(1, str(HERE.parent))
import study_io  # noqa: E402
import inext_dynamics as dynamics  # noqa: E402
import inext_statics as statics  # noqa: E402

EA_FACTORS = (0.01, 1.0, 100.0)


def _fmt(v):
    if isinstance(v, bool) or isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        return f"{v:.3g}"
    return str(v)


def _table(rows, keys) -> str:
    out = ["| " + " | ".join(keys) + " |", "|" + "---|" * len(keys)]
    out += ["| " + " | ".join(_fmt(r.get(k, "")) for k in keys) + " |" for r in rows]
    return "\n".join(out)


def main(argv=None) -> dict:
    args = study_io.parse(__doc__, "statics at 10 segments, dynamics at 10 over 2 s",
                          HERE / "out", argv)
    quick = args.quick
    seg_static = (10,) if quick else (20, 80, 400)
    cf_rows = []
    for fac in EA_FACTORS:
        c = statics.closed_form(10 if quick else 40, 3926.990816987241 * fac)
        cf_rows.append({"case": "closed form", "segments": c["segments"], "EA": c["EA"],
                        "stretch_exact": c["stretch_exact"],
                        "stiff_stretch_err": c["stiff"]["stretch"] - c["stretch_exact"],
                        "stiff_T_err": c["stiff"]["T_err"],
                        "constrained_tip_err": c["constrained"]["tip_err"],
                        "constrained_T_err": c["constrained"]["T_err"],
                        "constrained_length_err": c["constrained"]["length_err"],
                        "T_max": c["T_exact_max"]})
    st_rows = []
    for n in seg_static:
        st_rows += statics.compare(n, EA_FACTORS, damped=not quick)
    pert = dynamics.perturbed(10 if quick else 40, 2.0 if quick else 5.0,
                              (1.0, 0.1) if quick else (1.0, 0.1, 0.01),
                              (0.8,) if quick else (0.0, 0.8, 1.0),
                              ea_factors=(1.0,) if quick else EA_FACTORS)
    pend = dynamics.pendulum((0.1, 0.01) if quick else (0.1, 0.01, 0.001),
                             (0.8,) if quick else (0.0, 0.8, 1.0))
    rows = cf_rows + st_rows + pert + pend
    keys = list(dict.fromkeys(k for r in rows for k in r))
    rows = [{k: r.get(k, "") for k in keys} for r in rows]
    text = "\n\n".join([
        "# Inextensibility: stiff EA against the exact constraint (studies/inextensible)",
        "## Closed form: the hanging rod (m, N)",
        _table(cf_rows, ["segments", "EA", "stretch_exact", "stiff_stretch_err", "stiff_T_err",
                         "constrained_tip_err", "constrained_T_err", "constrained_length_err"]),
        "## Statics, seed 000's benchmark (dT, dX against the constrained rod)",
        _table(st_rows, ["segments", "model", "EA", "unknowns", "cold_iterations",
                         "cold_converged", "damped_iterations", "damped_converged",
                         "iterations", "residual", "time", "time_per_iteration", "cond",
                         "cond_eq", "T_over_EA", "dT", "dX", "tip_dX", "strain_max"]),
        "## Dynamics, the benchmark perturbed from rest",
        _table(pert, ["segments", "model", "rho_inf", "dt", "tol", "steps", "converged", "its_mean",
                      "its_max", "time_per_step", "cond", "cond_eq", "cond_unscaled",
                      "omega_axial_dt", "roughness", "dT"]),
        "## Dynamics, the pendulum (closed form; errors over m g, angle in rad)",
        _table(pend, ["model", "rho_inf", "dt", "steps", "converged", "theta_err", "T_err",
                      "T_noise", "T_noise_late", "its_mean", "its_max", "time_per_step", "cond",
                      "cond_eq", "omega_axial_dt"]),
    ])
    study_io.write_tables(args.out, rows, text)
    return {"rows": rows, "closed_form": cf_rows, "statics": st_rows, "perturbed": pert,
            "pendulum": pend, "summary": text}


if __name__ == "__main__":
    main()
