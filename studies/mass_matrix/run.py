"""Lumped or consistent mass for cable3d: which is more accurate for what it costs?

Question
--------
Issue 12 asks for both mass matrices of the position-vector cable (seed 003 uses the
consistent one; MoorDyn lumps) and for the default to be chosen from a measurement. On a line
with seabed contact, moved out of its vertical plane (the scene of tests/test_cable3d_api.py:
110 m rope, EA 5e7 N, 60 kg/m, fairlead motion of period 8 s; its material damping fixed at
BA = 3e5 N s, the value its -0.5 gives at N = 10: MoorDyn's negative BA is a damping ratio of
the highest axial mode, BA = zeta ds sqrt(EA m), which shrinks with the segments, so a line
given that way has no converged limit), how far is the periodic
fairlead tension from the converged one at N segments with each mass matrix, and what does a
time step cost?

Method
------
For N in (5, 10, 20, 40) and each mass matrix: ``sc.simulate`` over 12 periods at dt = T/800
(generated C, first-order generalized-alpha; its time error is 0.77 % at N = 10, see
tests/test_cable3d_api.py, so the spatial errors compared are those of N <= 20) and the last
period's fairlead tension compared with the reference (N = 80, consistent and lumped averaged:
they bracket it), as max |T - T_ref| over the reference's range. Step cost: the run's
``us_per_step`` (median of 3 repeats, warm cache). ``--quick``: N = 4 and 8, 3 periods, the
reference at N = 16, dt = T/200, in CasADi's virtual machine (no compiling).

Run
---
    python studies/mass_matrix/run.py          # about 2 minutes
    python studies/mass_matrix/run.py --quick  # the test runs it

Writes results.csv, summary.md and mass_matrix.png to the out dir (default
studies/mass_matrix/out/).
"""
from __future__ import annotations

import statistics
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import symcable as sc  # noqa: E402

HERE = Path(__file__).resolve().parent
sys.path.insert(1, str(HERE.parent))
import study_io  # noqa: E402

T = 8.0


def scene(n: int, mass: str) -> dict:
    return {"model": "cable3d", "mass_matrix": mass, "environment": {"depth": 60.0},
            "line_types": {"rope": {"mass": 60.0, "diameter": 0.08, "EA": 5e7, "cd_normal": 1.2,
                                    "cd_tangential": 0.1, "ca_normal": 1.0, "damping": 3e5}},
            "seabed": {"stiffness": 1e5},
            "sections": [{"type": "rope", "length": 110.0, "segments": n}],
            "end_a": {"condition": "pinned", "position": [0.0, 0.0, -60.0]},
            "end_b": {"condition": "pinned", "position": [80.0, 30.0, -10.0],
                      "motion": {"kind": "harmonic", "period": T, "amplitude": [1.0, 0.5, 1.5],
                                 "phase_deg": [0, 30, -90]}}}


def last_period(n: int, mass: str, periods: int, repeats: int = 1, steps: int = 800,
                codegen: bool = True):
    """(times in the last period from its start, fairlead tension N, median us per step)."""
    costs = []
    for _ in range(repeats):
        tr = sc.simulate(scene(n, mass), periods * T, dt=T / steps, codegen=codegen)
        costs.append(tr.stats["us_per_step"])
    sel = tr.time >= (periods - 1) * T - 1e-9
    return tr.time[sel] - (periods - 1) * T, tr.fairlead_tension[sel], statistics.median(costs)


def main(argv=None) -> list[dict]:
    args = study_io.parse(__doc__, "N = 4 and 8, 3 periods, reference N = 16, T/200",
                          HERE / "out", argv)
    ns, periods, n_ref = ((4, 8), 3, 16) if args.quick else ((5, 10, 20, 40), 12, 80)
    kw = dict(steps=200, codegen=False) if args.quick else {}
    ref = [last_period(n_ref, m, periods, **kw) for m in ("lumped", "consistent")]
    rt = ref[0][0]
    rf = 0.5 * (ref[0][1] + np.interp(rt, ref[1][0], ref[1][1]))
    rng = float(np.ptp(rf))
    rows = []
    for mass in ("lumped", "consistent"):
        for n in ns:
            t, f, us = last_period(n, mass, periods, repeats=1 if args.quick else 3, **kw)
            err = float(np.max(np.abs(np.interp(rt, t, f) - rf)) / rng)
            rows.append({"mass_matrix": mass, "segments": n, "error_pct_range": 100 * err,
                         "max_tension_kN": float(f.max() / 1e3), "us_per_step": us})
    lines = ["| mass matrix | segments | fairlead error (% of range) | max tension (kN) | "
             "us per step |", "|---|---|---|---|---|"]
    lines += [f"| {r['mass_matrix']} | {r['segments']} | {r['error_pct_range']:.3g} | "
              f"{r['max_tension_kN']:.4g} | {r['us_per_step']:.3g} |" for r in rows]
    lines.append(f"\nreference: N = {n_ref} (lumped and consistent averaged), tension range "
                 f"{rng / 1e3:.4g} kN; dt = T/{kw.get('steps', 800)}")
    text = "\n".join(lines) + "\n"

    def plot(path):
        fig, ax = plt.subplots(figsize=(6.4, 4.2))
        for mass, mk in (("lumped", "o"), ("consistent", "s")):
            rr = [r for r in rows if r["mass_matrix"] == mass]
            ax.loglog([r["segments"] for r in rr], [r["error_pct_range"] for r in rr],
                      marker=mk, label=mass)
        ax.set_xticks(ns)
        ax.set_xticklabels([str(n) for n in ns])
        ax.minorticks_off()
        ax.set_xlabel("segments")
        ax.set_ylabel("fairlead tension error (% of range)")
        ax.set_title(f"cable3d mass matrix: error against N = {n_ref}", fontsize=10)
        ax.grid(alpha=0.3, which="both")
        ax.legend()
        fig.tight_layout()
        fig.savefig(path, dpi=150)
        plt.close(fig)

    study_io.write(args, rows, text, plot, "mass_matrix.png")
    return rows


if __name__ == "__main__":
    main()
