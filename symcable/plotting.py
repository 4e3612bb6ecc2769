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
