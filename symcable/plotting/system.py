"""End tensions of a scene of several lines and points over time (a
:class:`~symcable.results.line3d.SystemTrajectory`, from ``simulate`` or a periodic solve):
each line's end tensions normalised by their static values T0 when given (the report's T/T0,
as in Sun, Zhu & LaRosa's Figs. 2-3), else in kN, the spans where some segment of a line is
slack shaded. ``SystemTrajectory.plot`` draws it; the CLI passes T0 from the scene's static
solution.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

__all__ = ["plot_system_tensions"]

#: a segment whose strain is at most this is counted slack (the line results' own test)
SLACK_STRAIN = 1e-7


def _slack_spans(t: np.ndarray, slack: np.ndarray) -> list:
    edges = np.flatnonzero(np.diff(np.r_[0, slack.astype(int), 0]))
    return [(t[i], t[min(j, len(t) - 1)]) for i, j in zip(edges[::2], edges[1::2])]


def plot_system_tensions(tr, path: str | Path | None = None, *, t0: dict | None = None,
                         title: str | None = None):
    """One axes: for each line (colour), its end-B tension (solid) and end-A tension
    (dashed) against time (s), divided by that end's static tension ``t0[line] = (T0_a,
    T0_b)`` (N) when given (a dotted line at 1), else in kN; spans where any segment of any
    line is slack shaded grey. Saved to ``path`` when given (PNG, 150 dpi); returns the
    Figure."""
    import matplotlib
    if path is not None:
        matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(9.5, 4.4))
    t = np.asarray(tr.time, float)
    slack = np.zeros(t.size, bool)
    normed = t0 is not None
    colors = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    for k, name in enumerate(tr.line_names):
        ln = tr.lines[name]
        c = colors[k % len(colors)]
        ta, tb = (t0.get(name, (np.nan, np.nan)) if normed else (1e3, 1e3))
        for ten, t_ref, style, end in ((ln.fairlead_tension, tb, "-", "B"),
                                       (ln.anchor_tension, ta, "--", "A")):
            ok = np.isfinite(t_ref) and t_ref > 0
            if normed and not ok:
                continue
            label = (f"{name}, end {end}" + (f" (T0 = {t_ref:.4g} N)" if normed else ""))
            ax.plot(t, np.asarray(ten) / t_ref, style, color=c, lw=1.3, label=label)
        slack |= (np.asarray(ln.strain) <= SLACK_STRAIN).any(axis=1)
    for k, (a, b) in enumerate(_slack_spans(t, slack)):
        ax.axvspan(a, b, color="0.88", zorder=0, label="some segment slack" if k == 0 else None)
    if normed:
        ax.axhline(1.0, color="0.4", lw=0.8, ls=":")
    from .profiles import least_span
    top = max((float(np.nanmax(np.abs(line.get_ydata()))) for line in ax.get_lines()
               if len(line.get_ydata())), default=0.0)
    least_span(ax, 0.02 * top)  # a tension steady to round-off is drawn flat
    ax.set_xlabel("time (s)")
    ax.set_ylabel("end tension / static tension T0" if normed else "end tension (kN)")
    ax.grid(alpha=0.3)
    ax.legend(loc="center left", bbox_to_anchor=(1.01, 0.5), fontsize=8, frameon=False)
    ax.set_title(f"{tr.method}, dt = {tr.dt:.3g} s", fontsize=10)
    fig.suptitle(title or f"{tr.scene_name}: end tensions", fontsize=11)
    fig.tight_layout()
    from .profiles import finish
    return finish(fig, path, tight=True)
