"""Tables and figure of the body-and-tow work-precision study (run_systems.py)."""
from __future__ import annotations

import math

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib import ticker  # noqa: E402
import numpy as np  # noqa: E402

LABELS = {"ga1": "generalized-α (simulate's default)", "rk4": "RK4 (its default step)",
          "shooting": "shooting", "collocation": "collocation (Radau d=3, Newton)",
          "harmonic-balance": "harmonic balance"}
MARKERS = {"ga1": "s", "rk4": "o", "shooting": "P", "collocation": "v", "harmonic-balance": "^"}
COLOURS = {"ga1": "tab:green", "rk4": "0.3", "shooting": "tab:purple", "collocation": "tab:orange",
           "harmonic-balance": "tab:red"}
COLUMNS = ("case", "method", "config", "code", "status", "error", "error_disc",
           "error_est_metric", "estimate",
           "err_t_max", "err_t_min", "err_a1", "depth_end_m", "wall_s", "repeats", "dt_s",
           "steps", "iterations", "unknowns")


def csv_rows(res: dict) -> list:
    return [{k: r.get(k) for k in COLUMNS} for r in res["rows"]]


def _pct(v) -> str:
    if v is None or (isinstance(v, float) and not math.isfinite(v)):
        return "-"
    return f"{100.0 * v:.3g}"


def _factor(r) -> str:
    e, est = r.get("error_est_metric"), r.get("estimate")
    if not est or not e or not math.isfinite(e) or e <= 0:
        return "-"
    return f"{est / e:.2g}"


def _table(rows, tow: bool) -> list:
    head = ("| method | configuration | code | error (%) | "
            + ("depth at the end (m) | " if tow else "time discretisation alone (%) | ")
            + "what the estimate measures (%) | its estimate (%) | estimate / true | wall (s) | "
            "steps or unknowns | status |")
    out = [head, "|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        mid = (f"{r['depth_end_m']:+.3f}" if tow and "depth_end_m" in r else _pct(r.get("error_disc")))
        size = r.get("steps") or r.get("unknowns") or "-"
        out.append(f"| {r['method']} | {r['config']} | {r.get('code') or '-'} | {_pct(r['error'])} | "
                   f"{mid} | {_pct(r.get('error_est_metric'))} | {_pct(r.get('estimate'))} | {_factor(r)} | {r['wall_s']:.3g} | {size} | "
                   f"{r.get('status')} |")
    return out


def summary_markdown(res: dict) -> str:
    mod, tow = res["module"], res["tow"]
    st = mod["state"]
    L = [f"# Work-precision on a body and a tow{' (--quick)' if res['quick'] else ''}", "",
         f"Study wall time {res['wall_s']:.0f} s.", "",
         "## The lifted module (body, T = 8 s)", "",
         f"Periodic reference: collocation K = {mod['ref_collocation']}, d = 4 (Newton): "
         f"T_max {st['t_max_N'] / 1e3:.3f} kN, T_min {st['t_min_N'] / 1e3:.3f} kN, A_1 "
         f"{st['a1_N'] / 1e3:.3f} kN; range {mod['range_N'] / 1e3:.2f} kN. Time reference: {mod['ref_method']} at "
         f"T/{mod['ref_steps']} over {mod['periods']} periods ({mod['ref_wall_s']:.1f} s); its "
         f"periods {mod['periods'] // 2 + 1}-{mod['periods']} stay up to {100 * mod['beat']:.2f} % of the range from the periodic state (the "
         "module's lightly damped swing): a time run's last period is that far from the "
         "periodic state whatever its step (the column 'time discretisation alone' compares "
         "it with the time reference's same period instead).", "",
         "Errors in % of the range. The run's own estimate and what it estimates: `simulate`'s "
         "`stats[\"error_estimate\"]` is of the tension sample by sample over the whole run "
         "(against the time reference at the same times, phase included); a periodic solve's "
         "`stats[\"time_discretisation_error\"][\"relative\"]` is of the cycle's extremes "
         "(the larger of the T_max and T_min errors against the periodic reference).", ""]
    L += _table(mod["rows"], tow=False)
    L += ["", f"## The tow (seed 003's towed body, 9 + 3 elements, {tow['duration_s']:.0f} s)", "",
          f"simulate's default step {tow['dt0_s']:.4g} s. Reference: GA1 at 1/{tow['tow_ref']} of "
          f"it ({tow['ref_wall_s']:.1f} s), whose own error is about {100 * tow['ref_error']:.2g} % "
          f"of the towpoint tension range ({tow['range_N'] / 1e3:.2f} kN). Error: the towpoint "
          "tension's largest difference over the run, % of that range; the body's depth at the "
          "end against the reference's.", ""]
    L += _table(tow["rows"], tow=True)
    L += ["", "## Observed orders (time discretisation error, successive refinements)", ""]
    for key, pairs in res["orders"].items():
        if pairs:
            L.append(f"- {key}: " + ", ".join(f"{p:.2f}" for _, p in pairs))
    return "\n".join(L) + "\n"


def plot(res: dict, path) -> None:
    """Error (% of range) against wall time: the module (left), the tow (right)."""
    fig, axes = plt.subplots(1, 2, figsize=(13, 5.5), constrained_layout=True)
    for ax, case, title in ((axes[0], "module", "Lifted module (6-DOF body), periodic tension"),
                            (axes[1], "tow", "Towed body through a 270° turn")):
        for meth in LABELS:
            rs = sorted((r for r in res["rows"] if r["case"] == case and r["method"] == meth
                         and np.isfinite(r["error"]) and r["error"] > 0), key=lambda r: r["resolution"])
            if rs:
                ax.loglog([r["wall_s"] for r in rs], [100 * r["error"] for r in rs],
                          marker=MARKERS[meth], color=COLOURS[meth], ms=5, lw=1.2, label=LABELS[meth])
        if case == "tow":
            ax.axhline(100 * res["tow"]["ref_error"], color="0.3", lw=0.8, ls="--",
                       label="the reference's own error (below it, a reading is a bound)")
        for lev in (1e-2, 1e-3):
            ax.axhline(100 * lev, color="0.5", lw=0.8, ls=":")
        ax.yaxis.set_major_formatter(ticker.FuncFormatter(lambda v, _: f"{v:g} %"))
        ax.set_xlabel("wall time of one call (warm cache), s")
        ax.set_ylabel("error, % of the tension range")
        ax.set_title(title + (" (--quick)" if res["quick"] else ""))
        ax.grid(True, which="both", alpha=0.25)
        ax.legend(fontsize=8)
    fig.savefig(path, dpi=130)
    plt.close(fig)
