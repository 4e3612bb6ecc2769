"""Figures of studies/sphere from its JSON outputs: ``draw(out)`` writes
``tension_period.png`` (T/T0 over one period at each frequency, the time run and every
periodic method) and ``response.png`` (the frequency sweep: max and min T/T0, stable solid,
unstable open markers and dashed, the slack region shaded)."""
from __future__ import annotations

import json
from pathlib import Path

import numpy as np


def _load(out: Path, part: str):
    path = out / f"{part}.json"
    return json.loads(path.read_text()) if path.exists() else None


def draw(out: Path) -> list:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    made = []
    cases = _load(out, "cases")
    if cases:
        fig, axes = plt.subplots(1, len(cases), figsize=(5.2 * len(cases), 4.0), squeeze=False)
        styles = {"shooting": ("C1", "--"), "collocation": ("C2", ":"),
                  "harmonic-balance": ("C3", "-.")}
        for ax, c in zip(axes[0], cases):
            tau = np.arange(200) / 200
            run = c["time_run"]
            ax.plot(tau, run["series"], "k-", lw=2.5, alpha=0.35,
                    label="time run, last of its periods")
            for m in c["periodic"]:
                if "series" not in m:
                    continue
                col, ls = styles.get(m["method"], ("C0", "-"))
                ax.plot(tau, m["series"], color=col, ls=ls, lw=1.3,
                        label=f"{m['method']} ({100 * m['diff_range']:.2f} % of range "
                              f"from the run; {'stable' if m['stable'] else 'unstable'}, "
                              f"|mu| {m['floquet_max']:.3g})")
            ax.axhspan(-0.05, 0.02, color="0.85", zorder=0, label="slack: T < 0.02 T0")
            ax.set_xlabel("t / T (top at its mean position, moving up, at t = 0)")
            ax.set_ylabel("top tension T / T0")
            ax.set_title(f"{c['freq']:g} Hz, T0 = {c['T0']:.2f} N: slack "
                         f"{100 * run['slack']:.0f} % of the period")
            ax.set_ylim(-0.05, 1.45 * max(2.0, run["max"]))  # room for the legend
            ax.grid(alpha=0.3)
            ax.legend(fontsize=7, loc="upper right")
        fig.suptitle("Payload sphere (seed 003, 3.1): top tension over one period, top moved "
                     "0.085 m vertically", fontsize=10)
        fig.tight_layout()
        path = out / "tension_period.png"
        fig.savefig(path, dpi=110)
        plt.close(fig)
        made.append(path)
    sweep = _load(out, "sweep")
    if sweep:
        fig, ax = plt.subplots(figsize=(10.5, 4.6))
        for direction, marker, col in (("up", "o", "C0"), ("down", "s", "C3")):
            d = sweep.get(direction)
            if not d:
                continue
            f = np.array(d["freq"], float)
            stab = np.array([bool(s) if s is not None else False for s in d["stable"]])
            ok = np.array([s == "converged" for s in d["statuses"]])
            for key in ("max", "min"):
                y = np.array(d[key], float)
                ax.plot(f[ok], y[ok], color=col, lw=0.8, alpha=0.5)
                for sel, face in ((ok & stab, col), (ok & ~stab, "none")):
                    ax.plot(f[sel], y[sel], marker, color=col, mfc=face, ms=6, ls="none")
            if (~ok).any():
                ax.plot(f[~ok], np.full((~ok).sum(), -0.04), "x", color="0.3", ms=7)
            slack = np.array([s if s is not None else 0.0 for s in d["slack"]], float)
            half = 0.5 * float(np.min(np.diff(np.sort(f)))) if f.size > 1 else 0.05
            for fi, sl in zip(f, slack):
                if sl > 0:
                    ax.axvspan(fi - half, fi + half, color="0.88", zorder=0, lw=0)
        ax.axhline(1.0, color="k", lw=0.6, ls=":")
        from matplotlib.lines import Line2D
        from matplotlib.patches import Patch
        handles = [Line2D([], [], marker="o", color="C0", ls="-", lw=0.8,
                          label="sweep up (from the previous frequency)"),
                   Line2D([], [], marker="s", color="C3", ls="-", lw=0.8, label="sweep down"),
                   Line2D([], [], marker="o", color="k", mfc="k", ls="none",
                          label="filled: stable, all Floquet |mu| < 1"),
                   Line2D([], [], marker="o", color="k", mfc="none", ls="none",
                          label="open: unstable, a multiplier |mu| > 1"),
                   Patch(color="0.88", label="slack over part of the period (T < 0.02 T0)"),
                   Line2D([], [], marker="x", color="0.3", ls="none",
                          label="no solution passed the check (the snap not resolved)")]
        cases = _load(out, "cases") or []
        lat = [m for c in cases for m in c["periodic"] if "floquet_max_lateral" in m
               and not m["stable"] and m["floquet_max_vertical"] < 1]
        if lat:
            handles.append(Line2D([], [], ls="none", label="unstable here: sideways (the slack "
                                  "line buckles);\nin the vertical plane stable"))
        ax.set_xlabel("excitation frequency, Hz")
        ax.set_ylabel("top tension over the period, T / T0  (max above, min below)")
        ax.set_title(f"Payload sphere: top tension over the period against frequency\n"
                     f"top moved 0.085 m vertically, T0 = {sweep['T0']:.2f} N, "
                     f"{sweep['segments']} segments, shooting by continuation", fontsize=9)
        ax.grid(alpha=0.3)
        ax.legend(handles=handles, fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0))
        fig.tight_layout()
        path = out / "response.png"
        fig.savefig(path, dpi=110)
        plt.close(fig)
        made.append(path)
    return made
