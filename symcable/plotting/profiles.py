"""All of symcable's plots: the only module that imports matplotlib.

Every plotting function returns its matplotlib Figure, saved to ``path`` when given (PNG,
PDF or SVG by suffix, at 150 dpi); release it with :func:`close`.
"""
from __future__ import annotations

import logging

import math
import re
from pathlib import Path

import matplotlib.pyplot as plt
from matplotlib.text import Text
import numpy as np

DPI = 150
SLACK_COLOR = "C3"
SURFACE_COLOR = "tab:cyan"
SEABED_COLOR = "saddlebrown"
# colours of the sections along the line (red is kept for touchdown and slack)
SECTION_COLORS = ("C0", "C2", "C4", "C1", "C5", "C6", "C8", "C9")
# a profile is drawn at true scale (equal axes) when its data's height/width ratio is within
# this factor of the axes box's; otherwise its axes are free and the exaggeration is stated
EQUAL_ASPECT_FACTOR = 3.0


def close(fig) -> None:
    """Release a figure's memory."""
    plt.close(fig)


def finish(fig, path: str | Path | None = None, *, tight: bool = False):
    """Make the figure's titles, labels, legends and notes plain text (their ``$`` a dollar
    sign, not mathtext: scene and line names are shown as written; tick labels keep theirs)
    and save it to ``path`` (PNG, PDF, SVG, ...) when given; returns ``fig``."""
    ticks = set()
    for ax in fig.axes:
        for axis in (ax.xaxis, ax.yaxis, getattr(ax, "zaxis", None)):
            if axis is not None:
                ticks.update(map(id, axis.get_ticklabels(which="both")))
                ticks.add(id(axis.get_offset_text()))
    for text in fig.findobj(Text):
        if id(text) not in ticks and "$" in text.get_text():
            text.set_parse_math(False)
    if path is not None:
        # equal-aspect views widen their fixed limits on purpose: not worth a log line
        log = logging.getLogger("matplotlib.axes._base")
        level = log.level
        log.setLevel(logging.ERROR)
        try:
            fig.savefig(path, dpi=DPI, **({"bbox_inches": "tight"} if tight else {}))
        finally:
            log.setLevel(level)
    return fig



def least_span(ax, span: float) -> None:
    """Widen ``ax``'s y range about its data to at least ``span`` (in the data's units), so
    that a quantity varying by round-off only is drawn flat rather than magnified into a
    full-height zig-zag; a range already wider is kept."""
    lo, hi = ax.get_ylim()
    if hi - lo < span:
        mid = 0.5 * (lo + hi)
        ax.set_ylim(mid - 0.5 * span, mid + 0.5 * span)

_save = finish


def _legend_outside(ax, **kw):
    """The axes' legend to its right, outside the data."""
    return ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0,
                     fontsize=8, **kw)


def _profile_scale(fig, ax) -> str:
    """Equal axes if the profile stays readable at true scale, else free axes: the phrase
    that says which ("true scale" or the vertical exaggeration). Call it once the layout
    and the data limits are final."""
    box = ax.get_position()
    w_in, h_in = box.width * fig.get_figwidth(), box.height * fig.get_figheight()
    (x0, x1), (z0, z1) = ax.get_xlim(), ax.get_ylim()
    exaggeration = (h_in / (z1 - z0)) / (w_in / (x1 - x0))
    if 1.0 / EQUAL_ASPECT_FACTOR <= exaggeration <= EQUAL_ASPECT_FACTOR:
        ax.set_aspect("equal", adjustable="datalim")
        return "true scale (equal axes)"
    return f"vertical exaggeration x{exaggeration:.2g}"


def _panel_height(xs, zs, width: float, lo: float, hi: float) -> float:
    """Height (in) of a profile panel ``width`` in wide that shows (xs, zs) at true scale,
    kept within [lo, hi] (beyond that the axes are not to scale and say so)."""
    dx, dz = float(np.ptp(xs)), float(np.ptp(zs))
    return float(np.clip(width * dz / dx, lo, hi)) if dx > 0 else hi


def _frame(ax, xs, zs, margin: float = 0.05) -> None:
    """Autoscale the axes to the points (xs, zs) with a margin; the limits stay automatic,
    so that equal axes can widen them (adjustable data limits)."""
    ax.update_datalim(np.column_stack([np.ravel(xs), np.ravel(zs)]))
    ax.margins(margin)
    ax.autoscale_view()


def _slack_where(warnings) -> tuple[str, float | None]:
    """Where the result first went slack, from its ``"slack: ..."`` warning: a phrase, and
    the arc length s (m) when the warning gives it."""
    for w in warnings:
        m = re.search(r"at t = (\S+) s, s = (\S+) m", w) if w.startswith("slack") else None
        if m:
            return f"total tension <= 0 first at t = {m[1]} s, s = {m[2]} m", float(m[2])
    return "total tension <= 0 somewhere", None


def _mark_slack(ax, s_first: float | None = None) -> None:
    """The zero-tension line in the slack colour (the y axis is made to include it), and
    the first slack point at arc length ``s_first`` when given."""
    ax.axhline(0.0, color=SLACK_COLOR, lw=1.0, ls="--", label="zero tension (slack)")
    if s_first is not None:
        ax.plot(s_first, 0.0, "X", color=SLACK_COLOR, ms=9, label="first slack point (axial force <= 0)")
    lo, hi = ax.get_ylim()
    if lo > 0.0:
        ax.set_ylim(-0.03 * hi, hi)


# ---------------------------------------------------------------------------- statics
def _sections(scene, sol):
    """[(s_start, s_end, line type name, EI)] from end A, m; one unnamed section without
    a scene."""
    if scene is None:
        return [(float(sol.s[0]), float(sol.s[-1]), None, None)]
    out, s0 = [], 0.0
    for sec in scene.sections:
        out.append((s0, s0 + sec.length, sec.line_type.name, sec.line_type.EI))
        s0 += sec.length
    return out


def _mark_sections(ax, sections, label_names: bool) -> None:
    """Section boundaries (dotted) and shaded spans on an axes against arc length."""
    if len(sections) < 2:
        return
    for k, (s0, s1, name, _) in enumerate(sections):
        ax.axvspan(s0, s1, color=SECTION_COLORS[k % len(SECTION_COLORS)], alpha=0.07, lw=0)
        if k:
            ax.axvline(s0, color="0.3", lw=0.8, ls=":")
        if label_names:
            ax.text(0.5 * (s0 + s1), 0.96, name, transform=ax.get_xaxis_transform(), ha="center",
                    va="top", fontsize=7, color="0.2",
                    bbox=dict(boxstyle="round,pad=0.15", fc="white", ec="none", alpha=0.7))


def plot_static(sol, path: str | Path | None = None, seabed_z: float | None = None, scene=None):
    """Report figure of a static solution: the profile above the tension and, when the line
    has bending stiffness (EI > 0 on some section), the bending moment against arc length.

    The profile shows the ends with their tensions, the free surface (z = 0, when the scene
    is in water), the seabed (z = -depth), the touchdown point and, on a line of several
    sections, each section in its own colour with its line type and the boundaries marked
    (also on the arc-length panels). It is drawn at true scale when that is readable, else
    with its vertical exaggeration stated in its title.

    Parameters
    ----------
    sol : StaticSolution
    path : str or Path, optional
        Where to save the figure (PNG, PDF, SVG by suffix), at 150 dpi.
    seabed_z : float, optional
        z of the seabed to draw, m (default: ``-depth`` of the scene, else from the contact
        forces' nodes).
    scene : Scene, optional
        The scene solved: its sections (boundaries, line type names, EI), water and seabed.
        Without it the plot has no section marks or free surface, and draws the bending
        moment when the solution's model built a bending term.

    Returns
    -------
    matplotlib.figure.Figure
    """
    sections = _sections(scene, sol)
    if scene is not None:
        bending = any(EI > 0 for *_, EI in sections)
        water = not scene.environment.in_air
        if seabed_z is None and scene.seabed is not None:
            seabed_z = -float(scene.environment.depth)
    else:
        bending = "bending" in sol.stats.get("terms", ()) or bool(np.any(sol.moment != 0))
        water = False
    if seabed_z is None and np.any(sol.contact_force > 0):
        seabed_z = float(np.max(sol.positions[sol.contact_force > 0.5 * np.max(sol.contact_force), 1]))

    x, z = sol.positions[:, 0], sol.positions[:, 1]
    z_all = [float(np.min(z)), float(np.max(z))]
    if water:
        z_all.append(0.0)
    if seabed_z is not None:
        z_all.append(seabed_z)
    rows = 3 if bending else 2
    h_profile = _panel_height(x, z_all, 7.0, 2.0, 4.5)
    fig = plt.figure(figsize=(10.0, h_profile + 1.0 + 2.9 * (rows - 1)))
    gs = fig.add_gridspec(rows, 1, height_ratios=[h_profile + 0.3] + [2.4] * (rows - 1))
    ax_p = fig.add_subplot(gs[0])
    ax_t = fig.add_subplot(gs[1])
    ax_m = fig.add_subplot(gs[2], sharex=ax_t) if bending else None

    # ---- profile
    for k, (s0, s1, name, _) in enumerate(sections):
        on = (sol.s >= s0 - 1e-9 * sol.s[-1]) & (sol.s <= s1 + 1e-9 * sol.s[-1])
        label = ("line" if name is None else
                 f"line: '{name}', {s1 - s0:g} m" if len(sections) == 1 else
                 f"section {k + 1}: '{name}', {s1 - s0:g} m")
        ax_p.plot(x[on], z[on], "-", color=SECTION_COLORS[k % len(SECTION_COLORS)], lw=2,
                  label=label)
    for k, (s_b, _, name, _) in enumerate(sections[1:], start=1):
        xb, zb = np.interp(s_b, sol.s, x), np.interp(s_b, sol.s, z)
        ax_p.plot(xb, zb, "D", color="k", ms=5, label="section boundary" if k == 1 else None)
        ax_p.annotate(f"{sections[k - 1][2]} | {name}", (xb, zb), textcoords="offset points",
                      xytext=(6, -12), fontsize=7)
    ax_p.plot(x[[0, -1]], z[[0, -1]], "o", color="k", ms=5)
    x_mid, z_top = 0.5 * (np.min(x) + np.max(x)), max(z_all) - 0.05 * (max(z_all) - min(z_all))
    for i, label, tension in ((0, "A", sol.anchor_tension), (-1, "B", sol.fairlead_tension)):
        inward = -1 if x[i] > x_mid else 1  # the label towards the middle, below an end at the top
        ax_p.annotate(f"{label}  {tension / 1e3:.1f} kN", (x[i], z[i]), textcoords="offset points",
                      xytext=(6 * inward, -8 if z[i] > z_top else 6), fontsize=9,
                      ha="left" if inward > 0 else "right", va="top" if z[i] > z_top else "bottom")
    if water:
        ax_p.axhline(0.0, color=SURFACE_COLOR, lw=1.2, label="free surface, z = 0 m")
    if seabed_z is not None:
        ax_p.axhline(seabed_z, color=SEABED_COLOR, lw=1.2, label=f"seabed, z = {seabed_z:g} m")
    if sol.touchdown is not None:
        ax_p.plot(*sol.touchdown, "v", color="C3", label=f"touchdown (grounded {sol.grounded_length:.1f} m)")
    _frame(ax_p, [np.min(x), np.max(x)], [min(z_all), max(z_all)])
    ax_p.set_xlabel("x (m)")
    ax_p.set_ylabel("z (m)")
    ax_p.set_title(f"{sol.scene_name}: static profile", fontsize=10)
    ax_p.grid(True, alpha=0.3)
    _legend_outside(ax_p)

    # ---- tension and moment against arc length
    ax_t.plot(sol.s, sol.tension / 1e3, color="C0")
    ax_t.set_ylabel("tension (kN)")
    ax_t.set_title("tension along the line", fontsize=10)
    for ax in (ax_t, ax_m):
        if ax is None:
            continue
        ax.set_xlabel("unstretched arc length from end A, s (m)")
        ax.grid(True, alpha=0.3)
        _mark_sections(ax, sections, label_names=ax is ax_t)
    if ax_m is not None:
        ax_m.plot(sol.s, sol.moment / 1e3, color="C1")
        ax_m.set_ylabel("bending moment (kN m)")
        ax_m.set_title("bending moment along the line", fontsize=10)
        ax_t.set_xlabel("")
        ax_t.tick_params(labelbottom=False)

    fig.tight_layout()
    ax_p.set_title(f"{sol.scene_name}: static profile, {_profile_scale(fig, ax_p)}", fontsize=10)
    return _save(fig, path)


# ---------------------------------------------------------------------------- dynamics
def _least_axial_force(ax, t, axial_force):
    """The least signed axial force along the line at each time (kN; < 0 is compression,
    which the tension magnitudes hide), a dashed zero line, and the compressive part shaded."""
    if axial_force is None or not np.size(axial_force):
        return
    least = np.min(np.asarray(axial_force), axis=1) / 1e3
    ax.plot(t, least, color="C2", lw=1.0, label="least axial force along the line (+ tension)")
    ax.axhline(0.0, color="k", lw=0.8, ls="--")
    if np.any(least < 0.0):
        ax.fill_between(t, least, 0.0, where=least < 0.0, color="C3", alpha=0.35,
                        label="compression")


def plot_trajectory(traj, path=None, s_mid=None):
    """Time response: fairlead and anchor tension against time, with the least signed axial
    force along the line (compression below the dashed zero line, shaded), above the tension
    envelope along the line (least/largest segment tension over the saved samples), kN. The title
    gives the scene, method, time step and status; a slack result is marked in red (where it
    went slack, and the zero-tension line). ``s_mid`` (n_seg,) m defaults to the
    trajectory's own ``s``. Returns the Figure."""
    slack = traj.status == "slack"
    fig, (ax_t, ax_e) = plt.subplots(2, 1, figsize=(10.0, 7.5))
    t = traj.time
    ax_t.plot(t, traj.fairlead_tension / 1e3, color="C0", lw=1.5, label="fairlead (end B)")
    ax_t.plot(t, traj.anchor_tension / 1e3, color="C1", lw=1.0, alpha=0.8, label="anchor (end A)")
    _least_axial_force(ax_t, t, getattr(traj, "axial_force", None))
    ax_t.set_xlabel("time, t (s)")
    ax_t.set_ylabel("tension, axial force (kN)")
    ax_t.set_title(f"{traj.scene_name}\ntime response: {traj.method}, dt = {traj.dt:.4g} s, "
                   f"status {traj.status}", fontsize=10)
    ax_t.grid(True, alpha=0.3)
    x = getattr(traj, "s", None) if s_mid is None else s_mid
    lo, hi = traj.tension.min(axis=0), traj.tension.max(axis=0)
    ax_e.fill_between(x, lo / 1e3, hi / 1e3, color="C0", alpha=0.25, label="range over time")
    ax_e.plot(x, lo / 1e3, color="C0", lw=1.0, label="least")
    ax_e.plot(x, hi / 1e3, color="C3" if not slack else "C4", lw=1.0, label="largest")
    ax_e.plot(x, traj.tension[0] / 1e3, color="k", lw=0.8, ls="--", label=f"t = {t[0]:.3g} s")
    ax_e.set_xlabel("unstretched arc length from end A, s (m)")
    ax_e.set_ylabel("segment tension (kN)")
    ax_e.set_title("tension envelope along the line", fontsize=10)
    ax_e.grid(True, alpha=0.3)
    if slack or np.any(lo <= 0.0):
        where, s_first = _slack_where(traj.warnings)
        _mark_slack(ax_t)
        _mark_slack(ax_e, s_first)
        ax_e.set_title(f"tension envelope along the line\nSLACK: {where} "
                       "(linearised model invalid there)", fontsize=10, color=SLACK_COLOR)
    for ax in (ax_t, ax_e):
        _legend_outside(ax)
    fig.tight_layout()
    return _save(fig, path)


def plot_periodic(per, path=None, s_mid=None):
    """Periodic steady state: one period of fairlead tension with the least signed axial
    force along the line (compression below the dashed zero line, shaded), its harmonic
    amplitudes, and the tension envelope on the nodes along the line (at ``per.s``, else
    ``s_mid`` when it matches, else node index). The title gives the scene, method, period
    and status; a slack result is marked in red (where it went slack, and the zero-tension
    line). Returns the Figure."""
    slack = per.status == "slack"
    fig = plt.figure(figsize=(10.0, 7.5))
    fig.suptitle(f"{per.scene_name}\nperiodic steady state: {per.method}, period T = "
                 f"{per.period:g} s, status {per.status}", fontsize=11,
                 color=SLACK_COLOR if slack else "k")
    ax1 = fig.add_subplot(2, 2, 1)
    ax1.plot(per.time / per.period, per.fairlead_tension / 1e3, color="C0", label="fairlead")
    _least_axial_force(ax1, per.time / per.period, getattr(per, "axial_force", None))
    if getattr(per, "axial_force", None) is not None:
        ax1.legend(loc="best", fontsize=7)
    ax1.set_xlabel("time / period, t/T (-)")
    ax1.set_ylabel("fairlead tension, axial force (kN)")
    ax1.set_title(f"fairlead tension over one period (T = {per.period:g} s)", fontsize=10)
    ax1.grid(True, alpha=0.3)
    ax2 = fig.add_subplot(2, 2, 2)
    amp = np.asarray(per.fairlead_tension_harmonics_amplitude)
    ax2.bar(np.arange(1, amp.size), amp[1:] / 1e3, color="C1")
    ax2.set_yscale("log")
    ax2.set_xlabel("harmonic k (-)")
    ax2.set_ylabel("amplitude (kN)")
    ax2.set_title(f"fairlead tension harmonics (mean {amp[0] / 1e3:.4g} kN)", fontsize=10)
    ax2.grid(True, alpha=0.3)
    ax3 = fig.add_subplot(2, 1, 2)
    lo, hi = np.asarray(per.tension_min), np.asarray(per.tension_max)
    x = getattr(per, "s", None)
    if x is None or np.size(x) != lo.size:
        x = s_mid if s_mid is not None and np.size(s_mid) == lo.size else None
    xs = np.arange(lo.size) if x is None else np.asarray(x)
    ax3.fill_between(xs, lo / 1e3, hi / 1e3, color="C0", alpha=0.3, label="min-max over the period")
    ax3.plot(xs, lo / 1e3, color="C0", lw=1.0, label="least")
    ax3.plot(xs, hi / 1e3, color="C4", lw=1.0, label="largest")
    ax3.set_xlabel("node index from end A (-)" if x is None else
                   "unstretched arc length from end A, s (m)")
    ax3.set_ylabel("tension on the nodes (kN)")
    ax3.set_title("tension envelope over the period", fontsize=10)
    ax3.grid(True, alpha=0.3)
    if slack:
        where, s_first = _slack_where(per.warnings)
        _mark_slack(ax1)
        _mark_slack(ax3, s_first if x is not None else None)
        ax1.legend(loc="best", fontsize=8)
        ax3.set_title(f"tension envelope over the period\nSLACK: {where} "
                      "(linearised model invalid there)", fontsize=10, color=SLACK_COLOR)
    _legend_outside(ax3)
    fig.tight_layout()
    return _save(fig, path)


def plot_modes(modal, positions=None, path=None, n=None, scale=None):
    """Mode shapes on the static profile, one panel per mode: static profile (grey) and
    static profile plus and minus ``scale`` times the shape (solid, dashed), ``scale``
    defaulting to a tenth of the line's extent. ``positions`` (n_nodes, 2) m defaults to
    ``modal.positions``; ``n`` (default: every mode of ``modal``) says how many of the lowest
    modes to draw. The figure's legend gives each mode's number, frequency (Hz) and period
    (s). Returns the Figure."""
    positions = np.asarray(modal.positions if positions is None else positions, dtype=float)
    n_all = len(modal.frequencies)
    n = n_all if n is None else max(1, min(int(n), n_all))
    ncols = 1 if n <= 3 else 2
    nrows = math.ceil(n / ncols)
    extent = float(np.ptp(positions, axis=0).max())
    scale = scale or 0.1 * extent
    shapes = [np.asarray(modal.shapes[k]) for k in range(n)]
    pts = np.concatenate([positions] + [positions + sg * scale * sh for sh in shapes for sg in (1, -1)])
    width = 5.3 if ncols > 1 else 8.0
    legend_rows = math.ceil(n / 3)
    top, bottom = 0.75, 0.3 + 0.2 * legend_rows  # in: suptitle, legend
    fig_h = nrows * (_panel_height(pts[:, 0], pts[:, 1], width, 1.4, 3.2) + 0.75) + top + bottom
    fig, axes = plt.subplots(nrows, ncols, figsize=(width * ncols + 1.0 * ncols, fig_h),
                             squeeze=False)
    handles = []
    for k, ax in enumerate(axes.flat):
        if k >= n:
            ax.set_axis_off()
            continue
        f = float(modal.frequencies[k])
        col = f"C{k % 10}" if k % 10 != 7 else "C9"  # C7 is grey, the static profile's colour
        ax.plot(positions[:, 0], positions[:, 1], color="0.6", lw=1)
        h, = ax.plot(*(positions + scale * shapes[k]).T, "-", color=col, lw=1.3,
                     label=f"mode {k + 1}: {f:.4g} Hz, period {1 / f:.4g} s")
        ax.plot(*(positions - scale * shapes[k]).T, "--", color=col, lw=1.0)
        handles.append(h)
        _frame(ax, pts[:, 0], pts[:, 1], 0.04)
        ax.set_title(f"mode {k + 1}", fontsize=9)
        if k + ncols >= n:
            ax.set_xlabel("x (m)")
        if k % ncols == 0:
            ax.set_ylabel("z (m)")
        ax.grid(True, alpha=0.3)
    which = (f"all {n} modes computed" if n == n_all else f"modes 1-{n} of the {n_all} computed")
    fig.legend(handles=handles, loc="lower center", ncol=min(n, 3), fontsize=8, frameon=False)
    fig.tight_layout(rect=(0.0, bottom / fig_h, 1.0, 1.0 - top / fig_h))
    scales = {_profile_scale(fig, ax) for ax in axes.flat[:n]}
    fig.suptitle(f"{modal.scene_name}: {which}\ngrey: static profile; solid / dashed: plus / minus "
                 f"{scale:.3g} m x the mode shape (largest displacement 1); {', '.join(sorted(scales))}",
                 fontsize=9)
    return _save(fig, path)
