"""Reproducer (rows14, for the lead): GA1's order in dt on the rod cantilever of run_rod.py,
against the same cantilever as an isotropic, untwisted rod and as cable3d (the same
discrete energy: tests/test_rod_vs_cable3d.py), so that the rod's own dynamics (twist,
frames' spin) can be told from the case (clamped end, ramped start, bending undamped).

    PYTHONPATH=. python studies/work_precision/rod_order_check.py

Prints each variant's node-position errors at T/100, T/200, T/400 against T/1600 (2
periods, as run_rod.py's metric) and the orders per halving.
"""
from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

sys.path.append(str(Path(__file__).resolve().parent))
import rod_cases as rc  # noqa: E402
import run_rod as w  # noqa: E402


def variants() -> dict:
    out = {"rod (anisotropic, twisted)": rc.cantilever()}
    d = rc.cantilever()
    d["line_types"]["beam"]["EI"] = 10.0
    d["end_a"].pop("twist_deg")
    out["rod (isotropic, untwisted)"] = d
    c = rc.cantilever()
    c["model"] = "cable3d"
    c["line_types"]["beam"]["EI"] = 10.0
    c["line_types"]["beam"].pop("GJ")
    c["end_a"].pop("twist_deg")
    out["cable3d (the same line)"] = c
    return out


def main() -> None:
    for name, d in variants().items():
        case = w.Case(d, 1.0, "anchor_tension")
        ref, _ = w.time_run(case, 1600, 2)()
        errs = []
        for n in (100, 200, 400):
            res, info = w.time_run(case, n, 2)()
            errs.append(w.errors(res, ref, 1.0)["error_x"])
        orders = np.log2(np.array(errs[:-1]) / np.array(errs[1:]))
        print(f"{name:28s} errors {np.round(errs, 7)} orders {np.round(orders, 2)}", flush=True)


if __name__ == "__main__":
    main()
