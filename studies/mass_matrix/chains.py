"""Lumped or consistent mass on MoorDyn's chain decks against OrcaFlex (issue 12).

Question
--------
``run.py`` found the consistent mass 1.3-1.8 times more accurate per segment than the lumped
one on a line with seabed contact, against symcable's own converged solution; the default
stayed lumped until the chain decks said whether the consistent mass also brings symcable
closer to an external reference. Here: the six chain cases of ``studies/chains`` (WD0050,
WD0200, WD0600 under the heave tables A1 and A2), symcable's ``simulate`` scheme and defaults
(first-order generalized-alpha, rho_inf = 0, generated C) at dt = 0.1 and 0.05 s with each
mass matrix: the max and rms error of the top segment's tension (MoorDyn's FairTen quantity)
against OrcaFlex's fairlead series over t = 0..20 s, % of OrcaFlex's range, and the run's
wall time (static solve plus run, median of ``repeats`` interleaved rounds after a first
untimed one).

Run
---
    python studies/mass_matrix/chains.py            # about 15 minutes (compiling included)
    python studies/mass_matrix/chains.py --quick    # WD0050 A1 at 0.1 s, the VM

Writes ``out/chains.csv`` (one row per run) and ``out/chains.md`` (the table).
"""
from __future__ import annotations

import sys
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
if str(HERE.parent) not in sys.path:
    sys.path.append(str(HERE.parent))
from study_io import load_module, parse, write_tables  # noqa: E402  (studies/study_io.py)

from symcable.api.cable3d_static import cable3d_mechanism  # noqa: E402
from symcable.scene import load_scene  # noqa: E402

cases = load_module(HERE.parent / "chains" / "cases.py", "chains_cases")

T_END = 20.0  # s: the end of OrcaFlex's series
FULL = dict(decks=cases.DECKS, motions=cases.MOTIONS, dts=(0.1, 0.05), repeats=3, codegen=True)
QUICK = dict(decks=("WD0050",), motions=("A1",), dts=(0.1,), repeats=1, codegen=False)


def _scene(deck: str, motion: str, mass: str, out: Path):
    d = cases.chain_scene(deck, cases.extended_table(motion, out)).to_dict()
    d["mass_matrix"] = mass
    return load_scene(d)


def run(cfg: dict, out: Path) -> list[dict]:
    rows = []
    for deck in cfg["decks"]:
        for motion in cfg["motions"]:
            ref = cases.reference(deck, motion)
            rng = float(np.ptp(ref[:, 3]))
            runs = {}
            for mass in ("lumped", "consistent"):
                scene = _scene(deck, motion, mass, out)
                for dt in cfg["dts"]:
                    r = cases.SymcableRun(scene, dt, T_END, "GA1", codegen=cfg["codegen"])
                    r.mech = cable3d_mechanism(scene)
                    tr, _, _ = r.once()  # warms the caches (generated C, batches)
                    T = cases.tensions(tr)
                    e = cases.errors(T["time"], T["fairlead_segment"], ref[:, 0], ref[:, 3], rng)
                    runs[(mass, dt)] = (r, {"deck": deck, "motion": motion, "mass_matrix": mass,
                                            "dt_s": dt, "max_pct": e["max"], "rms_pct": e["rms"],
                                            "iterations": tr.stats.get("newton_iterations"),
                                            "substepped": tr.stats.get("substepped_steps")})
            walls = {k: [] for k in runs}
            for _ in range(cfg["repeats"]):
                for k, (r, _) in runs.items():
                    t0 = time.perf_counter()
                    r.once()
                    walls[k].append(time.perf_counter() - t0)
            for k, (_, row) in runs.items():
                row["wall_s"] = float(np.median(walls[k]))
                lumped = runs[("lumped", row["dt_s"])][1]
                row["wall_vs_lumped"] = row["wall_s"] / max(float(np.median(walls[("lumped", row["dt_s"])])), 1e-12)
                rows.append(row)
                print(f"{deck} {motion} {row['mass_matrix']:10s} dt {row['dt_s']}: max "
                      f"{row['max_pct']:.2f} % (lumped {lumped['max_pct']:.2f}), rms "
                      f"{row['rms_pct']:.2f} %, wall {row['wall_s']:.3f} s", flush=True)
    return rows


def table(rows: list[dict]) -> str:
    lines = ["| case | dt (s) | max %: lumped / consistent | rms %: lumped / consistent | "
             "wall s: lumped / consistent |", "|---|---|---|---|---|"]
    key = {(r["deck"], r["motion"], r["dt_s"], r["mass_matrix"]): r for r in rows}
    for (deck, motion, dt, mass), r in key.items():
        if mass != "lumped":
            continue
        c = key[(deck, motion, dt, "consistent")]
        lines.append(f"| {deck} {motion} | {dt:g} | {r['max_pct']:.1f} / {c['max_pct']:.1f} | "
                     f"{r['rms_pct']:.1f} / {c['rms_pct']:.1f} | {r['wall_s']:.3f} / "
                     f"{c['wall_s']:.3f} |")
    return "\n".join(lines) + "\n"


def main(argv=None) -> list[dict]:
    args = parse(__doc__, "WD0050 A1 at 0.1 s, the virtual machine", HERE / "out", argv)
    rows = run(QUICK if args.quick else FULL, args.out)
    write_tables(args.out, rows, table(rows), ("chains", "chains"))
    return rows


if __name__ == "__main__":
    main()
