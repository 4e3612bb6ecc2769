"""Tables and figure of the cable3d work-precision study (run3d.py): the csv rows, the
summary in Markdown and error against wall time, log-log."""
from __future__ import annotations

import math

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib import ticker  # noqa: E402
import numpy as np  # noqa: E402

LEVELS = (1e-2, 1e-3, 1e-4)   # fractions of the reference tension range
LABELS = {"ga1": "generalized-α, first order (GA1, simulate)",
          "ga2": "generalized-α, second order (GA2, VM)", "rk4": "RK4",
          "collocation": "collocation (Radau, Newton)", "shooting": "shooting (GA2 period map)",
          "harmonic-balance": "harmonic balance"}
COLUMNS = ("method", "family", "config", "code", "status", "error", "err_t_max", "err_t_min",
           "err_a1", "error_disc", "wall_s", "repeats", "dt_s", "steps", "iterations",
           "iter_per_step", "substeps", "unknowns", "t_max_N", "t_min_N", "a1_N")


def time_to_levels(rows: list) -> dict:
    """{method: {level: the cheapest row whose error is at most the level, or None}}."""
    out = {}
    for meth in dict.fromkeys(r["method"] for r in rows):
        rs = [r for r in rows if r["method"] == meth and np.isfinite(r["error"])]
        out[meth] = {lev: min((r for r in rs if r["error"] <= lev), key=lambda r: r["wall_s"],
                              default=None) for lev in LEVELS}
    return out


def csv_rows(res: dict) -> list:
    return [{k: r.get(k) for k in COLUMNS} for r in res["rows"]]


def _pct(v, spec="{:.3g}") -> str:
    if v is None or (isinstance(v, float) and not math.isfinite(v)):
        return "-"
    return spec.format(100.0 * v)


def summary_markdown(res: dict) -> str:
    ref, T = res["reference"], res["period_s"]
    st = ref["state"]
    L = [f"# Work-precision on the {res['scene']}", "",
         f"T = {T:g} s. Errors in % of the reference tension range ({ref['range_N']:.0f} N). "
         f"Study wall time {res['wall_s']:.0f} s.", "",
         "## Reference", "",
         f"{ref['method']} for {len(ref['periods'])} periods ({ref['wall_s']:.1f} s); its last "
         f"period: T_max {st['t_max_N']:.1f} N, T_min {st['t_min_N']:.1f} N, A_1 {st['a1_N']:.1f} N. "
         f"RK4's stability limit {res['rk4_limit_s']:.4g} s (T/{T / res['rk4_limit_s']:.0f}); "
         f"MoorDyn's CFL-0.1 step {res['moordyn_cfl_dt_s']:.4g} s.", ""]
    tr = ref["transient"]
    shown = [k for k in range(len(tr)) if k < 10 or (k + 1) in (12, 16, 20, 24, 32, 48, 64, 96)
             or k == len(tr) - 1]
    L += ["Start-up transient (the reference's periods against its last, %):", "",
          "| period | " + " | ".join(str(k + 1) for k in shown) + " |",
          "|---|" + "---|" * len(shown),
          "| change (%) | " + " | ".join(_pct(tr[k], "{:.2g}") for k in shown) + " |", "",
          f"Time runs last **P = {res['P']} periods** (the first after which every period is within "
          "0.01 % of the last).", "",
          "## Runs", "",
          "\"error\": against the periodic state; \"disc.\": against the reference's own period P "
          "(the same transient; the time discretisation alone).", "",
          "| method | config | code | error (%) | T_max (%) | T_min (%) | A_1 (%) | disc. (%) | "
          "wall (s) | repeats | Newton/step | substeps | iterations | status |",
          "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in res["rows"]:
        ips = "-" if r.get("iter_per_step") is None else f"{r['iter_per_step']:.2f}"
        L.append(f"| {r['method']} | {r['config']} | {r.get('code') or '-'} | {_pct(r['error'])} | "
                 f"{_pct(r.get('err_t_max'), '{:+.2g}')} | {_pct(r.get('err_t_min'), '{:+.2g}')} | "
                 f"{_pct(r.get('err_a1'), '{:+.2g}')} | {_pct(r['error_disc'])} | {r['wall_s']:.3g} | "
                 f"{r['repeats']} | {ips} | {r.get('substeps') if r.get('substeps') is not None else '-'} | "
                 f"{r.get('iterations') if r.get('iterations') is not None else '-'} | {r['status']} |")
    L += ["", "## Observed orders", "",
          "Time runs: from the discretisation error (disc.); periodic methods: from the error "
          "against the reference. Order p in error ~ resolution^-p (resolution: steps per "
          "period, intervals K, harmonics H).", "",
          "| family | successive pairs | slope, last three |", "|---|---|---|"]
    for fam, o in res["orders"].items():
        pairs = ", ".join(f"{lab}: {p:.2f}" for lab, p in o["pairs"]) or "-"
        s = "-" if o["slope_last3"] is None else f"{o['slope_last3']:.2f}"
        L.append(f"| {fam} | {pairs} | {s} |")
    L += ["", "## Cheapest run to each level", "",
          "| method | " + " | ".join(f"{100 * v:g} %" for v in LEVELS) + " |",
          "|---|" + "---|" * len(LEVELS)]
    for meth, v in res["time_to_level"].items():
        L.append(f"| {meth} | " + " | ".join(
            f"{r['wall_s']:.3g} s ({r['config']})" if r else "not reached" for r in v.values()) + " |")
    return "\n".join(L) + "\n"


def _resolutions(meth: str, rs: list) -> str:
    """A line's resolutions in order, for its legend entry: "T/50 ... T/3200", "K = 20, 40"."""
    v = [r["resolution"] for r in rs]
    if meth in ("ga1", "ga2", "rk4", "shooting"):
        return "dt = " + ", ".join(f"T/{n}" for n in v)
    return ("K" if meth == "collocation" else "H") + " = " + ", ".join(str(n) for n in v)


def plot(res: dict, path) -> None:
    """Error (% of the range) against wall time, one line per family in order of resolution."""
    markers = {"ga1": "s", "ga2": "D", "rk4": "o", "collocation": "v", "shooting": "P",
               "harmonic-balance": "^"}
    cmaps = {"ga1": plt.cm.Greens, "ga2": plt.cm.Blues, "rk4": plt.cm.Greys,
             "collocation": plt.cm.Oranges, "shooting": plt.cm.Purples,
             "harmonic-balance": plt.cm.Reds}
    fig, ax = plt.subplots(figsize=(12, 6.5), constrained_layout=True)
    for meth in LABELS:
        fams = list(dict.fromkeys(r["family"] for r in res["rows"] if r["method"] == meth))
        for i, fam in enumerate(fams):
            rs = sorted((r for r in res["rows"] if r["family"] == fam and np.isfinite(r["error"])
                         and r["error"] > 0), key=lambda r: r["resolution"])
            if not rs:
                continue
            col = cmaps[meth](0.6 + 0.35 * i / max(len(fams) - 1, 1))
            name = LABELS[meth] + (f" ({fam.split(' ', 1)[1]})" if " " in fam else "")
            ax.loglog([r["wall_s"] for r in rs], [100 * r["error"] for r in rs], marker=markers[meth],
                      color=col, ms=5, lw=1.2, label=f"{name}: {_resolutions(meth, rs)}")
    for lev in LEVELS:
        ax.axhline(100 * lev, color="0.5", lw=0.8, ls=":")
    ax.yaxis.set_major_formatter(ticker.FuncFormatter(lambda v, _: f"{v:g} %"))
    ax.set_xlabel("wall time of one call (static solve, build, run; warm cache), s")
    ax.set_ylabel("largest error of T_max, T_min, A_1, % of the tension range")
    quick = " (--quick)" if res.get("quick") else ""
    ax.set_title(f"Work-precision, 3D line with seabed friction{quick}: periodic fairlead tension\n"
                 f"(reference: {res['reference']['method']}, {len(res['reference']['periods'])} periods)")
    ax.grid(True, which="both", alpha=0.25)
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    fig.savefig(path, dpi=130)
    plt.close(fig)
