"""The periodic cells of the cable3d stability study's failing rows, run again (run3d.py's
cells, one at a time, each in a forked child with a time limit).

Question
--------
On the rows where the full run (README, "The 3D line": F1-F21) saw shooting, collocation
(Newton) or harmonic balance fail or time out, which of them converge now, how close to the
reference, with how many iterations, at what wall time, and through which start (the
``warnings`` of a solve that needed a fallback say which)?

Setup: the rows of ``stability3d_cases.rows`` (the slack search's result of the full run
fixed: last taut x1.875, first slack x2, so the snap row at x4); each method with
``solve_periodic(scene, method)`` at its defaults (run3d.cell_fn); the reference the full
run's, GA1 at T/3200 over 8 periods (its last period), cached in ``periodic_refs.json``.

Run
---
    python -u studies/stability/periodic3d.py --tag after          # 8 rows x 3 methods
    options: --rows NAME [NAME ...], --methods shooting collocation hb, --timeout S (240)

Writes ``periodic_<tag>.json`` to studies/stability/out/cable3d/ and prints a table.
"""
from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
for _p in (HERE, HERE.parent):
    if str(_p) not in sys.path:
        sys.path.append(str(_p))
import cable3d_case as case3d  # noqa: E402
import stability3d_cases as cases  # noqa: E402
from study_io import load_module  # noqa: E402

run3d = load_module(HERE / "run3d.py", "stability_run3d")

ROWS = ("EA x100", "40 segments", "near-slack amplitude", "snap amplitude",
        "oblique current 2 m/s", "mostly on the seabed", "buoyant section", "touchdown landing")
METHODS = ("shooting", "collocation", "hb")
#: the full run's slack search (README): last taut and first slack amplitude factors
SLACK = {"taut": 1.875, "slack": 2.0}
OUT = HERE / "out" / "cable3d"


def rows(names=ROWS) -> list:
    every = {r.name: r for r in cases.rows(False, SLACK, case3d.moordyn_cfl_step(cases.base()))}
    return [every[n] for n in names]


def reference(row, timeout: float, cache: dict) -> dict | None:
    """The row's reference cell (GA1 at T/row.ref_steps over row.periods), from the cache."""
    if row.name not in cache:
        c = run3d.run_cell(run3d.cell_fn("reference", row.make(), row), timeout)
        cache[row.name] = {"ok": c["ok"], "per_period": c.get("per_period"),
                           "wall_s": c.get("wall_s"), "message": c.get("message")}
    ref = cache[row.name]
    return ref if ref["ok"] else None


def cell_text(c: dict) -> str:
    if not c["ok"]:
        return f"FAILED {c.get('wall_s', 0):.3g} s ({c.get('exc_type')})"
    e = "no ref." if c.get("error") is None else f"{100 * c['error']:.2g} %"
    via = f" [{c['fallback']}]" if c.get("fallback") else ""
    return f"ok {e} {c['wall_s']:.3g} s ({c.get('iterations')} it.){via}"


def main(argv=None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--tag", default="now")
    ap.add_argument("--rows", nargs="*", default=list(ROWS))
    ap.add_argument("--methods", nargs="*", default=list(METHODS))
    ap.add_argument("--timeout", type=float, default=run3d.TIMEOUT_FULL)
    args = ap.parse_args(argv)
    OUT.mkdir(parents=True, exist_ok=True)
    ref_path = OUT / "periodic_refs.json"
    refs = json.loads(ref_path.read_text()) if ref_path.exists() else {}
    out = {"tag": args.tag, "date": time.strftime("%Y-%m-%d"), "timeout_s": args.timeout,
           "rows": {}}
    path = OUT / f"periodic_{args.tag}.json"
    for row in rows(args.rows):
        ref = reference(row, args.timeout, refs)
        ref_path.write_text(json.dumps(refs, indent=1))
        d = row.make()
        res = out["rows"].setdefault(row.name, {})
        for key in args.methods:
            c = run3d.run_cell(run3d.cell_fn(key, d, row), args.timeout)
            ws = " ".join(c.get("warnings", ()))
            c["fallback"] = " + ".join(k for k, tag in (("ramped start", "ramped in over"),
                                                        ("continuation", "continuation in"))
                                       if tag in ws)
            if c["ok"] and ref is not None:
                c["error"] = case3d.rel_error(c["per_period"][-1], ref["per_period"][-1])["error"]
            res[key] = c
            print(f"{row.name:24s} {key:12s} {cell_text(c)}"
                  + ("" if c["ok"] else f"\n    {c.get('message', '')}")
                  + "".join(f"\n    warning: {w}" for w in c.get("warnings", ())), flush=True)
            path.write_text(json.dumps(out, indent=1, default=str))
    print("\n| row | " + " | ".join(args.methods) + " |\n|---|" + "---|" * len(args.methods))
    for name, res in out["rows"].items():
        print(f"| {name} | " + " | ".join(cell_text(res[k]) for k in args.methods if k in res) + " |")
    return out


if __name__ == "__main__":
    main()
