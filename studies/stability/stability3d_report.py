"""Tables of the cable3d stability study (run3d.py): csv rows and the Markdown summary."""
from __future__ import annotations

LABELS = {"ga1": "GA1 (C), T/100", "ga2": "GA2 (VM), T/100", "rk4": "RK4, default dt",
          "shooting": "shooting", "collocation": "collocation (Newton)", "hb": "harmonic balance"}


def _num(v, spec="{:.3g}") -> str:
    return "-" if v is None else spec.format(v)


def cell_text(c: dict | None, notes: list) -> str:
    if c is None:
        return "—"
    if c.get("skipped"):
        return c["message"]
    if not c["ok"]:
        start = f" [started from: {c['start']}]" if c.get("start") else ""
        notes.append(f"{c.get('exc_type')}: {c.get('message')}{start}")
        return f"FAILED [F{len(notes)}] {c.get('wall_s', 0):.3g} s"
    err = c.get("error")
    word = "ok" if c["status"] == "converged" else c["status"]
    e = "no ref." if err is None else f"{100 * err:.2g} %"
    extra = []
    if c.get("iter_per_step") is not None:
        extra.append(f"{c['iter_per_step']:.2f} N/step")
    if c.get("substeps"):
        extra.append(f"{c['substeps']} substepped (x{c['max_substeps']})")
    if c.get("snaps"):
        extra.append(f"{c['snaps']} snaps")
    if c.get("iterations") is not None and c.get("iter_per_step") is None and "steps" not in c:
        extra.append(f"{c['iterations']} it.")
    return f"{word} {e} {c['wall_s']:.3g} s" + (f" ({', '.join(extra)})" if extra else "")


def summary_markdown(res: dict) -> str:
    keys = list(LABELS)
    notes: list = []
    L = ["Cells: status, error (largest of the fairlead-tension max, min, first-harmonic "
         "differences from the reference's same period, % of its range), wall time; GA1: "
         "Newton iterations per step (N/step); time runs: steps that converged only as substeps, "
         "snaps (a slack segment pulled taut). "
         f"MoorDyn's CFL-0.1 step of the base line: {res['cfl_dt_s']:.4g} s.", "",
         "| row | parameter | reference | " + " | ".join(LABELS.values()) + " |",
         "|---|---|---|" + "---|" * len(keys)]
    for r in res["rows"]:
        ref = r["reference"]
        refs = ref["method"] if ref else ("FAILED: " + r.get("reference_failure", "")[:60]
                                          if r.get("reference_failure") else "none")
        cells = [cell_text(r["cells"].get(k), notes) for k in keys]
        L.append(f"| {r['row']} | {r['param']} | {refs} | " + " | ".join(cells) + " |")
    if notes:
        L += ["", "Failures (each cell's exception, one line):", ""]
        L += [f"- F{i + 1}: {n}" for i, n in enumerate(notes)]
    L += ["", "Details: segments; MoorDyn's CFL-0.1 step of the row (s); GA1: dt, Newton "
          "iterations (per step, largest in a step); time runs' smallest axial force (kN, < 0: "
          "a compressed segment's damping force) and slack fraction; RK4's stability limit; "
          "the reference's last-period drift (% of range) and wall time.", "",
          "| row | segments | CFL dt (s) | GA1 dt (s) | GA1 Newton (per step, max) | "
          "GA1 min axial (kN) | GA1 slack fraction | RK4 limit (s) | ref. drift (%) | ref. wall (s) |",
          "|---|---|---|---|---|---|---|---|---|---|"]
    for r in res["rows"]:
        g, rk, ref = r["cells"].get("ga1") or {}, r["cells"].get("rk4") or {}, r["reference"] or {}
        L.append(f"| {r['row']} | {r['segments']} | {r['cfl_dt_s']:.3g} | {_num(g.get('dt'))} | "
                 f"{_num(g.get('iter_per_step'), '{:.2f}')}, {_num(g.get('iter_max'), '{}')} | "
                 f"{_num(g.get('min_axial_kN'), '{:.1f}')} | {_num(g.get('slack_fraction'), '{:.3f}')} | "
                 f"{_num(rk.get('dt_stable'), '{:.3g}')} | "
                 f"{_num(None if r.get('ref_drift') is None else 100 * r['ref_drift'], '{:.2g}')} | "
                 f"{_num(ref.get('wall_s'), '{:.3g}')} |")
    sl = res.get("slack")
    if sl:
        L += ["", "Slack search (GA1, T/200, 4 periods; amplitude = factor x [1, 2, 0.5] m):", "",
              "| factor | slack fraction | snaps | min axial (kN) | fairlead min (kN) | fairlead max (kN) |",
              "|---|---|---|---|---|---|"]
        for h in sl["history"]:
            L.append(f"| {h['factor']:g} | {h['slack_fraction']:.4f} | {h['snaps']} | "
                     f"{h['min_axial_kN']:.1f} | {h['fairlead_min_kN']:.1f} | {h['fairlead_max_kN']:.1f} |")
        L += ["", f"Last taut factor {sl['taut']}, first slack factor {sl['slack']}."]
    warn = [(r["row"], k, w) for r in res["rows"] for k, c in r["cells"].items()
            if c.get("ok") for w in c.get("warnings", []) if "too coarse" not in w]
    if warn:
        L += ["", "Warnings of the cells (other than the time-step estimate):", ""]
        L += [f"- {row} / {k}: {w}" for row, k, w in warn]
    L += ["", f"Total wall time {res['wall_s']:.0f} s."]
    return "\n".join(L) + "\n"


def csv_rows(res: dict) -> list:
    out = []
    for r in res["rows"]:
        items = list(r["cells"].items()) + ([("reference", r["reference"])] if r["reference"] else [])
        for key, c in items:
            last = c["per_period"][-1] if c.get("ok") else {}
            status = c.get("status") if c.get("ok") else ("not run" if c.get("skipped") else "FAILED")
            out.append({"row": r["row"], "group": r["group"], "param": r["param"],
                        "segments": r["segments"], "cfl_dt_s": r["cfl_dt_s"], "method": key,
                        "status": status,
                        "error_rel": c.get("error"), "wall_s": c.get("wall_s"),
                        "dt_s": c.get("dt"), "steps": c.get("steps"),
                        "newton_iterations": c.get("iterations"), "newton_max": c.get("iter_max"),
                        "substepped_steps": c.get("substeps"), "max_substeps": c.get("max_substeps"),
                        "snaps": c.get("snaps"), "slack_fraction": c.get("slack_fraction"),
                        "min_axial_kN": c.get("min_axial_kN"), "dt_stable_s": c.get("dt_stable"),
                        "fairlead_max_N": last.get("t_max_N"), "fairlead_min_N": last.get("t_min_N"),
                        "first_harmonic_N": last.get("a1_N"),
                        "exception": c.get("exc_type") if not c.get("ok") else "",
                        "message": c.get("message") if not c.get("ok") else "; ".join(c.get("warnings", []))})
    return out
