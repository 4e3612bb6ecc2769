"""Tables and figures of studies/chains (imported by run.py): ``summary`` (markdown),
``fairlead`` and ``anchor`` (the six tension series, OrcaFlex with every code over it) and
``accuracy`` (max fairlead error against wall time)."""
from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

#: the symcable run drawn over the series (scheme, dt), the first present: the compiled
#: first-order scheme at MoorDyn's coupling step (it ran on all six; the second-order one
#: failed at 0.1 s on two)
PLOTTED = (("GA1", 0.1), ("GA2", 0.1))
#: % : the accuracy figure's top; runs above it are drawn on the edge with their value
Y_TOP = 25.0
DPI = 95
COLORS = {"OrcaFlex": "k", "symcable": "#d62728", "MoorDyn": "#1f77b4", "CableDyn": "#2ca02c"}


def _f(x, fmt="{:.1f}") -> str:
    return "-" if x is None else fmt.format(x)


def summary(res: dict) -> str:
    cfg = res["config"]
    lines = ["# MoorDyn chain decks against OrcaFlex: symcable, MoorDyn, CableDyn", "",
             f"Errors over t = 0..{cfg['t_end']:g} s, % of OrcaFlex's range (fair: the line's "
             "force on the fairlead; seg: the top segment's tension, MoorDyn's FairTen; anch: "
             "the anchor). time err: symcable against its own run at "
             f"{cfg['ref_dt']} s ({cfg['ref_scheme']}). Wall: static + run, median of "
             f"{cfg['repeats']} interleaved repeats after a first run. Peers: "
             + ", ".join(f"{k} {v or 'not installed'}" for k, v in res["peers"].items()) + ".", ""]
    head = ("| code | scheme | dt (s) | fair max | fair rms | seg max | seg rms | anch max | "
            "anch rms | time err max (seg) | wall (s) | status |")
    for case in res["series"]:
        deck, motion = case.split()
        lines += [f"## {deck}, {motion}", "", head, "|" + "---|" * 12]
        for r in (r for r in res["rows"] if (r["deck"], r["motion"]) == (deck, motion)):
            scheme = r["scheme"]
            if r["code"] == "symcable" and r["status"] == "ok":
                scheme += ", C" if r.get("compiled") else ", VM"
            scheme += " (own reference)" if r.get("reference") else ""
            terr = (f"{_f(r.get('time_err_max'))} ({_f(r.get('time_errseg_max'))})"
                    if "time_err_max" in r else "-")
            status = r["status"] + (f": {r['note']}" if r.get("note") else "")
            lines.append(f"| {r['code']} | {scheme} | {_f(r['dt_s'], '{:g}')} | "
                         f"{_f(r.get('fair_max'))} | {_f(r.get('fair_rms'))} | "
                         f"{_f(r.get('fairseg_max'))} | {_f(r.get('fairseg_rms'))} | "
                         f"{_f(r.get('anch_max'))} | {_f(r.get('anch_rms'))} | {terr} | "
                         f"{_f(r.get('wall_s'), '{:.3f}')} | {status} |")
        lines.append("")
    lines += ["## The issue's criteria", "",
              "Per scheme and tension (force on the fairlead; top segment, MoorDyn's FairTen "
              "quantity): symcable's cheapest run at dt >= 0.05 s whose max error is no larger "
              "than MoorDyn's live one (unrounded), else its most accurate run there (\"no\"); "
              "its max error (dt), wall time, and the ratios to MoorDyn's wall time (started "
              "from the deck's fileIC / from its own IC solve) and CableDyn's (dt 0.1 s).", "",
              "| case | MoorDyn max: issue / live | MoorDyn wall (s): fileIC / own IC | "
              "CableDyn 0.1 s max, wall (s) | model error (force / seg) | symcable scheme, "
              "tension | max (dt) | as accurate as MoorDyn | wall (s) | / MoorDyn: fileIC / "
              "own IC | / CableDyn |", "|" + "---|" * 11]
    for v in res["verdicts"]:
        base = (f"| {v['deck']} {v['motion']} | {v['issue_moordyn_max']} / {_f(v['moordyn_max'])} "
                f"| {_f(v['moordyn_wall'], '{:.3f}')} / {_f(v.get('moordyn_wall_own'), '{:.3f}')} "
                f"| {_f(v['cabledyn_max'])}, {_f(v['cabledyn_wall'], '{:.3f}')} | "
                f"{_f(v['model_error'])} / {_f(v['model_error_seg'])} |")
        for scheme in res["config"]["schemes"]:
            for key, label in (("fair", "force"), ("fairseg", "seg")):
                a = v.get(f"{scheme} {key}")
                if a is None:
                    lines.append(base + f" {scheme}, {label} | all failed | - | - | - | - |")
                    continue
                w = a["wall"]
                ratio = lambda d: w / d if w and d else None  # noqa: E731
                own = v.get("moordyn_wall_own")
                lines.append(base + f" {scheme}, {label} | {a['max']:.1f} ({a['dt']:g}) | "
                             f"{'yes' if a.get('meets') else 'no'} | {_f(w, '{:.3f}')} | "
                             f"{_f(ratio(v['moordyn_wall']), '{:.2f}')} / "
                             f"{_f(ratio(own), '{:.2f}')} | {_f(ratio(v['cabledyn_wall']), '{:.2f}')} |")
    return "\n".join(lines) + "\n"


def _grid(res):
    cases = list(res["series"])
    decks = sorted({c.split()[0] for c in cases})
    motions = sorted({c.split()[1] for c in cases})
    fig, axes = plt.subplots(len(decks), len(motions), figsize=(6.2 * len(motions), 3.1 * len(decks)),
                             squeeze=False, sharex=True)
    return fig, axes, decks, motions


def _plotted(series):
    for scheme, dt in PLOTTED:
        key = f"symcable {scheme} {dt}"
        if key in series:
            return key, f"symcable {scheme}, dt {dt:g} s"
    key = next((k for k in series if k.startswith("symcable")), None)
    return key, key


def _series(res, path: Path, what: str, col: str) -> None:
    fig, axes, decks, motions = _grid(res)
    t_end = res["config"]["t_end"]
    for i, deck in enumerate(decks):
        for j, motion in enumerate(motions):
            ax, s = axes[i][j], res["series"].get(f"{deck} {motion}")
            if s is None:
                ax.set_visible(False)
                continue
            o = s["orcaflex"]
            m = np.asarray(o["time"]) <= t_end + 1e-9
            ax.plot(np.asarray(o["time"])[m], np.asarray(o[col])[m], color=COLORS["OrcaFlex"],
                    lw=2.6, label="OrcaFlex (reference)", zorder=1)
            key, label = _plotted(s)
            draws = [(key, col, label, COLORS["symcable"], "-")]
            if col == "fairlead":
                draws.append((key, "fairlead_segment", label.replace("symcable", "symcable top segment"),
                              COLORS["symcable"], ":"))
            draws += [("MoorDyn", col, "MoorDyn (RK2, CFL 0.1)", COLORS["MoorDyn"], "-"),
                      ("CableDyn 0.1", col, "CableDyn, dt 0.1 s", COLORS["CableDyn"], "-")]
            for k, c, lab, color, ls in draws:
                d = s.get(k)
                if d is None or c not in d:
                    continue
                t = np.asarray(d["time"])
                keep = (t >= -1e-9) & (t <= t_end + 1e-9)
                ax.plot(t[keep], np.asarray(d[c])[keep], color=color, ls=ls, lw=1.1, label=lab,
                        zorder=2)
            ax.set_title(f"{deck}, motion {motion}", fontsize=10)
            ax.grid(alpha=0.3)
            if j == 0:
                ax.set_ylabel(f"{what} tension (kN)")
            if i == len(decks) - 1:
                ax.set_xlabel("t (s)")
    handles, labels = axes[0][0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="lower center", ncol=min(5 if len(motions) > 1 else 2, len(labels)),
               fontsize=8.5, frameon=False)
    fig.suptitle(f"{what.capitalize()} tension of the MoorDyn chain decks under heave", fontsize=12)
    fig.tight_layout(rect=(0, 0.05 if len(decks) > 1 else 0.18, 1, 0.97))
    fig.savefig(path, dpi=DPI)
    plt.close(fig)


def fairlead(res: dict, path: Path) -> None:
    _series(res, path, "fairlead", "fairlead")


def anchor(res: dict, path: Path) -> None:
    _series(res, path, "anchor", "anchor")


def _clip(ax, pts, color, marker, ls, label, dy):
    """Draw (wall, error, dt) points, those above Y_TOP on the edge (open) with their value."""
    if not pts:
        return
    x, y, dts = zip(*pts)
    yc = [min(v, Y_TOP) for v in y]
    ax.plot(x, yc, marker=marker, ls=ls, color=color, label=label)
    for xx, yy, v, dt in zip(x, yc, y, dts):
        text = f"{dt:g}" if v <= Y_TOP else f"{dt:g}: {v:.0f} %"
        ax.annotate(text, (xx, yy), fontsize=7, xytext=(3, dy), textcoords="offset points")
        if v > Y_TOP:
            ax.plot([xx], [yy], marker="^", color=color, ms=9, mfc="white")


def accuracy(res: dict, path: Path) -> None:
    """Per case: max fairlead error (force on the fairlead) against wall time, each symcable
    scheme through its steps, CableDyn through its steps, MoorDyn a point; the dotted line is
    symcable's converged error (the model against OrcaFlex)."""
    fig, axes, decks, motions = _grid(res)
    markers = {"GA2": ("o", "-"), "GA1": ("s", "--"), "GA1-rho0.2": ("^", ":")}
    for i, deck in enumerate(decks):
        for j, motion in enumerate(motions):
            ax = axes[i][j]
            rs = [r for r in res["rows"] if (r["deck"], r["motion"]) == (deck, motion)
                  and r["status"] == "ok"]
            if not rs:
                ax.set_visible(False)
                continue
            own = next((r for r in rs if r.get("reference")), None)
            for scheme, (mk, ls) in markers.items():
                pts = sorted((r["wall_s"], r["fair_max"], r["dt_s"]) for r in rs
                             if r["code"] == "symcable" and r["scheme"] == scheme
                             and not r.get("reference") and r.get("wall_s"))
                _clip(ax, pts, COLORS["symcable"], mk, ls,
                      f"symcable {scheme} ({'C' if scheme.startswith('GA1') else 'VM'})", 3)
            pts = sorted((r["wall_s"], r["fair_max"], r["dt_s"]) for r in rs
                         if r["code"] == "CableDyn" and r.get("wall_s"))
            _clip(ax, pts, COLORS["CableDyn"], "v", "-", "CableDyn", -9)
            mds = [r for r in rs if r["code"] == "MoorDyn" and r.get("wall_s")]
            for k, md in enumerate(mds):
                ax.plot([md["wall_s"]], [md["fair_max"]], "D", color=COLORS["MoorDyn"], ms=7,
                        mfc=COLORS["MoorDyn"] if k == 0 else "none",
                        label="MoorDyn" + ("" if k == 0 else f" (start: {md['start']})"))
            if own:
                ax.axhline(own["fair_max"], color=COLORS["symcable"], ls=":", lw=1,
                           label="symcable converged (dt 0.0025 s)")
            ax.set_xscale("log")
            ax.set_ylim(0.0, Y_TOP * 1.08)
            ax.set_title(f"{deck}, motion {motion}", fontsize=10)
            ax.grid(alpha=0.3, which="both")
            if j == 0:
                ax.set_ylabel("max fairlead error (% of range)")
            if i == len(decks) - 1:
                ax.set_xlabel("wall time, static + run (s)")
    handles, labels = axes[0][0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="lower center", ncol=min(len(labels), 5 if len(motions) > 1 else 2),
               fontsize=8.5, frameon=False)
    fig.suptitle("Max fairlead-tension error against OrcaFlex (% of its range) and wall time "
                 "(labels: dt in s; MoorDyn: CFL 0.1)", fontsize=12)
    fig.tight_layout(rect=(0, 0.05 if len(decks) > 1 else 0.18, 1, 0.97))
    fig.savefig(path, dpi=DPI)
    plt.close(fig)
