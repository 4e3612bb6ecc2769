"""All of symcable's plots: the only module that imports matplotlib."""
from __future__ import annotations

from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np


def plot_static(sol, path: str | Path | None = None, seabed_z: float | None = None):
    """Report figure of a static solution: the profile (equal axes, seabed, touchdown,
    end tensions) above tension and bending moment against arc length.

    Parameters
    ----------
    sol : StaticSolution
    path : str or Path, optional
        Where to save the figure (PNG, PDF, SVG by suffix), at 150 dpi.
    seabed_z : float, optional
        z of the seabed to draw, m (drawn from the contact forces' nodes when not given).

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig, (ax_p, ax_t) = plt.subplots(2, 1, figsize=(8.0, 8.0), gridspec_kw={"height_ratios": [1.2, 1]})
    x, z = sol.positions[:, 0], sol.positions[:, 1]
    ax_p.plot(x, z, "-", color="C0", lw=2, label="line")
    ax_p.plot(x[[0, -1]], z[[0, -1]], "o", color="k", ms=5)
    ax_p.annotate(f"A  {sol.anchor_tension / 1e3:.1f} kN", (x[0], z[0]), textcoords="offset points",
                  xytext=(6, 6), fontsize=9)
    ax_p.annotate(f"B  {sol.fairlead_tension / 1e3:.1f} kN", (x[-1], z[-1]), textcoords="offset points",
                  xytext=(6, -12), fontsize=9)
    if seabed_z is None and np.any(sol.contact_force > 0):
        seabed_z = float(np.max(z[sol.contact_force > 0.5 * np.max(sol.contact_force)]))
    if seabed_z is not None:
        ax_p.axhline(seabed_z, color="0.5", lw=1, ls="--", label="seabed")
    if sol.touchdown is not None:
        ax_p.plot(*sol.touchdown, "v", color="C3", label=f"touchdown (grounded {sol.grounded_length:.1f} m)")
    ax_p.set_aspect("equal", adjustable="datalim")
    ax_p.set_xlabel("x (m)")
    ax_p.set_ylabel("z (m)")
    ax_p.set_title(f"{sol.scene_name}: static profile")
    ax_p.grid(True, alpha=0.3)
    ax_p.legend(loc="best", fontsize=8)

    ax_t.plot(sol.s, sol.tension / 1e3, color="C0", label="tension")
    ax_t.set_xlabel("unstretched arc length from end A, s (m)")
    ax_t.set_ylabel("tension (kN)", color="C0")
    ax_t.grid(True, alpha=0.3)
    if np.any(sol.moment != 0):
        ax_m = ax_t.twinx()
        ax_m.plot(sol.s, sol.moment / 1e3, color="C1", label="bending moment")
        ax_m.set_ylabel("bending moment (kN m)", color="C1")
    ax_t.set_title("tension and bending moment along the line")
    fig.tight_layout()
    if path is not None:
        fig.savefig(path, dpi=150)
    return fig


def close(fig) -> None:
    """Release a figure's memory."""
    plt.close(fig)


def _envelope_axis(ax, s_mid, lo, hi, static=None):
    ax.fill_between(s_mid, lo / 1e3, hi / 1e3, color="C0", alpha=0.3, label="min-max over time")
    if static is not None:
        ax.plot(s_mid, static / 1e3, color="k", lw=1, label="static")
    ax.set_xlabel("unstretched arc length from end A, s (m)")
    ax.set_ylabel("tension (kN)")
    ax.grid(True, alpha=0.3)
    ax.legend(loc="best", fontsize=8)


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
    envelope along the line (least/largest segment tension over the saved samples), kN; slack
    is marked. ``s_mid`` (n_seg,) m defaults to the trajectory's own ``s``. Returns the Figure."""
    fig, (ax_t, ax_e) = plt.subplots(2, 1, figsize=(8.0, 7.0))
    t = traj.time
    ax_t.plot(t, traj.fairlead_tension / 1e3, color="C0", lw=1.5, label="fairlead (end B)")
    ax_t.plot(t, traj.anchor_tension / 1e3, color="C1", lw=1.0, alpha=0.8, label="anchor (end A)")
    _least_axial_force(ax_t, t, getattr(traj, "axial_force", None))
    ax_t.set_xlabel("time, t (s)")
    ax_t.set_ylabel("tension, axial force (kN)")
    ax_t.set_title(f"{traj.scene_name}\n{traj.method}, dt = {traj.dt:.4g} s, status {traj.status}",
                   fontsize=10)
    ax_t.grid(True, alpha=0.3)
    ax_t.legend(loc="best", fontsize=8)
    x = getattr(traj, "s", None) if s_mid is None else s_mid
    lo, hi = traj.tension.min(axis=0), traj.tension.max(axis=0)
    ax_e.fill_between(x, lo / 1e3, hi / 1e3, color="C0", alpha=0.25, label="range over time")
    ax_e.plot(x, lo / 1e3, color="C0", lw=1.0, label="least")
    ax_e.plot(x, hi / 1e3, color="C3", lw=1.0, label="largest")
    ax_e.plot(x, traj.tension[0] / 1e3, color="k", lw=0.8, ls="--", label=f"t = {t[0]:.3g} s")
    if np.any(lo <= 0.0):
        ax_e.axhline(0.0, color="C3", lw=0.8, ls=":", label="slack")
    ax_e.set_xlabel("unstretched arc length from end A, s (m)")
    ax_e.set_ylabel("segment tension (kN)")
    ax_e.set_title("tension envelope along the line")
    ax_e.grid(True, alpha=0.3)
    ax_e.legend(loc="best", fontsize=8)
    fig.tight_layout()
    if path is not None:
        fig.savefig(path, dpi=150)
    return fig


def plot_periodic(per, path=None, s_mid=None):
    """Periodic steady state: one period of fairlead tension with the least signed axial
    force along the line (compression below the dashed zero line, shaded), its harmonic
    amplitudes, and the tension envelope on the nodes along the line (at ``per.s``, else
    ``s_mid`` when it matches, else node index). Returns the Figure."""
    fig = plt.figure(figsize=(9.0, 7.0))
    ax1 = fig.add_subplot(2, 2, 1)
    ax1.plot(per.time / per.period, per.fairlead_tension / 1e3, color="C0", label="fairlead")
    _least_axial_force(ax1, per.time / per.period, getattr(per, "axial_force", None))
    if getattr(per, "axial_force", None) is not None:
        ax1.legend(loc="best", fontsize=7)
    ax1.set_xlabel("time / period, t/T (-)")
    ax1.set_ylabel("fairlead tension, axial force (kN)")
    ax1.set_title(f"one period, T = {per.period:g} s ({per.method})")
    ax1.grid(True, alpha=0.3)
    ax2 = fig.add_subplot(2, 2, 2)
    amp = np.asarray(per.fairlead_tension_harmonics_amplitude)
    ax2.bar(np.arange(1, amp.size), amp[1:] / 1e3, color="C1")
    ax2.set_yscale("log")
    ax2.set_xlabel("harmonic k (-)")
    ax2.set_ylabel("amplitude (kN)")
    ax2.set_title("fairlead tension harmonics")
    ax2.grid(True, alpha=0.3)
    ax3 = fig.add_subplot(2, 1, 2)
    lo, hi = np.asarray(per.tension_min), np.asarray(per.tension_max)
    x = getattr(per, "s", None)
    if x is None or np.size(x) != lo.size:
        x = s_mid if s_mid is not None and np.size(s_mid) == lo.size else None
    _envelope_axis(ax3, np.arange(lo.size) if x is None else x, lo, hi)
    if x is None:
        ax3.set_xlabel("node index from end A")
    ax3.set_title("tension envelope over the period")
    fig.tight_layout()
    if path is not None:
        fig.savefig(path, dpi=150)
    return fig


def plot_modes(modal, positions, path=None, n=4, scale=None):
    """The first ``n`` mode shapes drawn on the static profile ``positions`` (n_nodes, 2),
    each scaled to a tenth of the line's extent. Returns the Figure."""
    n = min(n, len(modal.frequencies))
    fig, axes = plt.subplots(n, 1, figsize=(8.0, 2.4 * n), sharex=True)
    axes = np.atleast_1d(axes)
    extent = float(np.ptp(positions, axis=0).max())
    scale = scale or 0.1 * extent
    for k, ax in enumerate(axes):
        shape = np.asarray(modal.shapes[k])
        ax.plot(positions[:, 0], positions[:, 1], color="0.6", lw=1, label="static")
        for sign, style in ((1, "-"), (-1, "--")):
            q = positions + sign * scale * shape
            ax.plot(q[:, 0], q[:, 1], style, color="C0", lw=1.2)
        ax.set_title(f"mode {k + 1}: {modal.frequencies[k]:.4g} Hz (period {1 / modal.frequencies[k]:.4g} s)",
                     fontsize=9)
        ax.set_ylabel("z (m)")
        ax.grid(True, alpha=0.3)
    axes[-1].set_xlabel("x (m)")
    fig.suptitle(f"mode shapes (+/- {scale:.3g} m at the largest displacement; axes not to scale)",
                 fontsize=10)
    fig.tight_layout()
    if path is not None:
        fig.savefig(path, dpi=150)
    return fig
