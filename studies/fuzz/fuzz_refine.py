"""The discretisation error of the planar model against the references, by refining: one
scene solved at a ladder of segment counts (each section gets segments in proportion to its
length, at least one), the deviations from the primary reference at each, and the constants
``C = deviation * N_eff^2`` (``N_eff = L / ds_max``) that the comparison tolerance of
:mod:`fuzz_classify` must cover. A scene counts only if it converges towards its reference
(deviation below ``CONVERGED`` and ``CONVERGED_SHAPE`` at the finest level), and a level
counts only if its answer passes the physical checks, so that a wrong answer does not pass for
discretisation error.
"""
from __future__ import annotations

import copy

import fuzz_classify as fc
import fuzz_refs as fr
from fuzz_tolerance import penalty_effect, tolerances

LEVELS = (2, 3, 4, 6, 8, 12, 16, 24, 32, 48, 64, 96)
CONVERGED = 1e-3          # end tensions, of the tension scale, at the finest level
CONVERGED_SHAPE = 1e-2    # shape, of the length (a rod on another branch stays off)


def scaled(scene: dict, n_total: int) -> dict:
    """The scene with about n_total segments, shared among sections by length."""
    out = copy.deepcopy(scene)
    L = sum(s["length"] for s in out["sections"])
    for s in out["sections"]:
        s["segments"] = max(1, int(round(n_total * s["length"] / L)))
    return out


def run(item: dict, levels=LEVELS) -> dict:
    """Deviations at each level of one scene (``rows``), and whether it converges."""
    refs = fr.references(item["scene"])["refs"]
    refs["penalty"] = penalty_effect(item["scene"], refs)
    name, ref = fr.primary(refs)
    rows = []
    if ref is None:
        return {"id": item["id"], "cls": item["class"], "rows": rows, "reference": None,
                "converges": False}
    for n in levels:
        scene = scaled(item["scene"], n)
        info = fr.Info(scene)
        rec = fc.solve(scene)
        sol = rec.get("solution")
        if sol is None:
            rows.append({"n": n, "outcome": rec["outcome"]})
            continue
        dev = fr.compare(info, ref, sol["T_A"], sol["T_B"], sol["grounded"], sol["positions"])
        tol = tolerances(info, ref, refs.get("penalty"))
        rows.append({"n": n, "outcome": "solved", **dev, **{f"tol_{k}": v for k, v in tol.items()},
                     "physical": fc.physical_checks(info, sol)})
    solved = [r for r in rows if r["outcome"] == "solved"]
    finest = solved[-1] if solved else None
    converges = bool(finest and finest["n"] == levels[-1] and not finest["physical"]
                     and max(finest["dT_A"], finest["dT_B"]) < CONVERGED
                     and not finest["shape"] > CONVERGED_SHAPE)
    return {"id": item["id"], "cls": item["class"], "variant": item["variant"],
            "reference": name, "rows": rows, "converges": converges}
