"""Plots and a ParaView export of a 3D line's time history
(:class:`~symcable.results.line3d.LineTrajectory`): end tensions over time with the tension
envelope along the line, profile snapshots in 3D, plan and elevation, and VTK files.

Like :mod:`symcable.plotting.profiles`, each plot returns its matplotlib Figure, saved to ``path``
when given; matplotlib is imported on first use. VTK goes through meshio (the ``vtk`` extra:
``pip install symcable[vtk]``).
"""
from __future__ import annotations

from pathlib import Path
from xml.sax.saxutils import quoteattr

import numpy as np

from ..errors import SymcableError

__all__ = ["animate", "plot_modes_3d", "plot_profiles", "plot_tensions", "write_vtk"]



def _plt():
    import matplotlib.pyplot as plt
    return plt


def _finish(fig, path):
    from .profiles import finish
    return finish(fig, path, tight=True)


def plot_tensions(tr, path=None, *, title: str | None = None, t_from: float | None = None):
    """Left: the tension at end B (the fairlead of a mooring) and end A against time, spans
    where some segment of a cable is slack shaded; right: the least, mean and largest
    tension along the line over the samples from ``t_from`` s (default all) against arc
    length from end A (m). Tensions in kN, or N when every one is below 1 kN."""
    plt = _plt()
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(11.5, 4.2), gridspec_kw={"width_ratios": [1.4, 1]})
    t = tr.time
    env = tr.envelope(t_from)
    top = max(float(np.max(np.abs(tr.fairlead_tension), initial=0.0)),
              float(np.max(np.abs(tr.anchor_tension), initial=0.0)),
              float(np.max(env["max"], initial=0.0)))
    unit, scale = ("kN", 1e3) if top >= 1e3 else ("N", 1.0)
    ax.plot(t, tr.fairlead_tension / scale, color="tab:blue", lw=1.4, label="end B")
    ax.plot(t, tr.anchor_tension / scale, color="tab:orange", lw=1.4, label="end A")
    # a cable's slack (its own report in stats); a rod carries compression and is not slack
    slack = ((tr.strain <= 1e-7).any(axis=1) if "slack_fraction" in tr.stats
             else np.zeros(len(t), bool))
    if slack.any():
        edges = np.flatnonzero(np.diff(np.r_[0, slack.astype(int), 0]))
        for k, (i, j) in enumerate(zip(edges[::2], edges[1::2])):
            ax.axvspan(t[i], t[min(j, len(t) - 1)], color="0.85", zorder=0,
                       label="some segment slack" if k == 0 else None)
    ax.set_xlabel("time (s)")
    ax.set_ylabel(f"end tension ({unit})")
    ax.grid(alpha=0.3)
    ax.legend(loc="best", fontsize=8)
    from .profiles import least_span
    least_span(ax, 0.02 * top / scale)
    bx.fill_between(env["s"], env["min"] / scale, env["max"] / scale, color="tab:blue",
                    alpha=0.25, label="range")
    bx.plot(env["s"], env["mean"] / scale, color="tab:blue", lw=1.4, label="mean")
    bx.set_xlabel("arc length from end A (m)")
    bx.set_ylabel(f"tension ({unit})")
    bx.grid(alpha=0.3)
    bx.legend(loc="best", fontsize=8)
    span = f" from t = {t_from:g} s" if t_from is not None else ""
    bx.set_title(f"tension along the line{span}", fontsize=10)
    ax.set_title(f"{tr.method}, dt = {tr.dt:.3g} s", fontsize=10)
    fig.suptitle(title or f"{tr.scene_name}: tensions", fontsize=11)
    fig.tight_layout()
    return _finish(fig, path)


def plot_profiles(tr, path=None, *, snapshots: int = 8, title: str | None = None):
    """The line at ``snapshots`` evenly spaced samples, fading from early (light) to late
    (dark): a 3D view, the plan (x-y) and the elevation (x-z), true scale, m."""
    plt = _plt()
    n_t = len(tr.time)
    idx = np.unique(np.linspace(0, n_t - 1, max(1, min(int(snapshots), n_t))).round().astype(int))
    fig = plt.figure(figsize=(12.5, 4.4))
    ax3 = fig.add_subplot(1, 3, 1, projection="3d")
    plan, elev = fig.add_subplot(1, 3, 2), fig.add_subplot(1, 3, 3)
    cmap = plt.get_cmap("Blues")
    for k, i in enumerate(idx):
        c = cmap(0.35 + 0.65 * (k + 1) / len(idx))
        P = tr.positions[i]
        lab = f"t = {tr.time[i]:.3g} s" if k in (0, len(idx) - 1) else None
        ax3.plot(P[:, 0], P[:, 1], P[:, 2], color=c, lw=1.2)
        plan.plot(P[:, 0], P[:, 1], color=c, lw=1.2, label=lab)
        elev.plot(P[:, 0], P[:, 2], color=c, lw=1.2, label=lab)
    pts = tr.positions[idx].reshape(-1, 3)
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    half = 0.5 * max(float(np.max(hi - lo)), 1e-9)
    mid = 0.5 * (lo + hi)
    for setter, j in ((ax3.set_xlim, 0), (ax3.set_ylim, 1), (ax3.set_zlim, 2)):
        setter(mid[j] - half, mid[j] + half)
    ax3.set_xlabel("x (m)")
    ax3.set_ylabel("y (m)")
    ax3.set_zlabel("z (m)")
    for ax, (a, b), name in ((plan, (0, 1), "plan"), (elev, (0, 2), "elevation")):
        ax.set_aspect("equal", adjustable="datalim")
        ax.set_xlabel("x (m)")
        ax.set_ylabel(f"{'xyz'[b]} (m)")
        ax.set_title(name, fontsize=10)
        ax.grid(alpha=0.3)
    elev.legend(loc="best", fontsize=8)
    fig.suptitle(title or f"{tr.scene_name}: {len(idx)} snapshots", fontsize=11)
    fig.tight_layout()
    return _finish(fig, path)


def write_vtk(tr, folder, stem: str = "line") -> Path:
    """One VTK XML unstructured grid (``STEM_00000.vtu`` ...) per sample, the line as one
    polyline through its nodes, with point data ``velocity`` (m/s) and ``contact_force`` (N)
    and cell data (per segment) ``tension`` (N) and ``strain``; and ``STEM.pvd``, the
    collection ParaView opens as a time series (each file at its sample's time, s).
    Returns the ``.pvd`` path."""
    try:
        import meshio
    except ImportError:
        raise SymcableError("to_vtk needs meshio: pip install 'symcable[vtk]' "
                            "(or pip install meshio)") from None
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    n = tr.positions.shape[1]
    cells = [("line", np.c_[np.arange(n - 1), np.arange(1, n)])]
    entries = []
    for i, t in enumerate(tr.time):
        name = f"{stem}_{i:05d}.vtu"
        mesh = meshio.Mesh(tr.positions[i], cells,
                           point_data={"velocity": tr.velocities[i],
                                       "contact_force": tr.contact_force[i]},
                           cell_data={"tension": [tr.tension[i]], "strain": [tr.strain[i]]})
        mesh.write(folder / name, file_format="vtu", binary=True)
        entries.append(f'    <DataSet timestep="{float(t):.9g}" part="0" file={quoteattr(name)}/>')
    pvd = folder / f"{stem}.pvd"
    pvd.write_text('<?xml version="1.0"?>\n<VTKFile type="Collection" version="0.1">\n'
                   "  <Collection>\n" + "\n".join(entries) + "\n  </Collection>\n</VTKFile>\n")
    return pvd


def animate(tr, path, *, frames: int = 60, fps: int = 15, title: str | None = None) -> Path:
    """An animated GIF of the line (plan and elevation side by side, true scale, m) at
    ``frames`` evenly spaced samples, ``fps`` frames per second, with the time and the
    fairlead tension (kN) in the title; written by matplotlib's Pillow writer. Returns the
    path."""
    plt = _plt()
    from matplotlib.animation import FuncAnimation, PillowWriter

    path = Path(path)
    if path.suffix.lower() != ".gif":
        raise SymcableError(f"path = '{path}': an animation is written as .gif")
    n_t = len(tr.time)
    idx = np.unique(np.linspace(0, n_t - 1, max(2, min(int(frames), n_t))).round().astype(int))
    fig, (plan, elev) = plt.subplots(1, 2, figsize=(11.0, 4.2))
    pts = tr.positions[idx].reshape(-1, 3)
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    pad = 0.05 * max(float(np.max(hi - lo)), 1e-9)
    for ax, (a, b), name in ((plan, (0, 1), "plan"), (elev, (0, 2), "elevation")):
        ax.set_xlim(lo[a] - pad, hi[a] + pad)
        ax.set_ylim(lo[b] - pad, hi[b] + pad)
        ax.set_aspect("equal", adjustable="box")  # the limits kept, true scale
        ax.set_xlabel(f"{'xyz'[a]} (m)")
        ax.set_ylabel(f"{'xyz'[b]} (m)")
        ax.set_title(name, fontsize=10)
        ax.grid(alpha=0.3)
    (lp,) = plan.plot([], [], "-o", color="tab:blue", ms=2.5, lw=1.4)
    (le,) = elev.plot([], [], "-o", color="tab:blue", ms=2.5, lw=1.4)
    head = fig.suptitle("", fontsize=11)
    name = title or tr.scene_name

    def draw(k):
        P = tr.positions[idx[k]]
        lp.set_data(P[:, 0], P[:, 1])
        le.set_data(P[:, 0], P[:, 2])
        head.set_text(f"{name}: t = {tr.time[idx[k]]:.2f} s, fairlead tension "
                      f"{tr.fairlead_tension[idx[k]] / 1e3:.4g} kN")
        return lp, le, head

    anim = FuncAnimation(fig, draw, frames=len(idx), blit=False)
    anim.save(path, writer=PillowWriter(fps=int(fps)))
    plt.close(fig)
    return path


#: the most modes :func:`plot_modes_3d` draws by default (the lowest, when there are more)
MAX_MODES_DRAWN = 12
#: the three views of a 3D mode: (axes drawn, name)
_VIEWS = (((0, 1), "plan"), ((0, 2), "elevation"), ((1, 2), "end view"))


def plot_modes_3d(modal, path=None, *, modes: int | None = None, scale: float | None = None,
                  title: str | None = None, seabed: float | None = None):
    """The mode shapes of a 3D scene (a :class:`~symcable.results.static.ModalSolution` of
    a cable3d, rod or hybrid scene, or a scene of several lines): for each of the lowest
    ``modes`` (default every mode of the solution, at most :data:`MAX_MODES_DRAWN`), plan
    (x-y), elevation (x-z) and end view (y-z) of the static lines (grey) and the lines
    displaced by +/- the shape times ``scale`` m (default a tenth of the scene's extent),
    true scale, each line drawn on its own (``stats["lines"]``: its rows); the seabed at
    z = ``seabed`` m dashed when given; frequencies in the titles."""
    plt = _plt()
    n_all = len(modal.frequencies)
    k = min(MAX_MODES_DRAWN, n_all) if modes is None else min(int(modes), n_all)
    if k < 1:
        raise SymcableError(f"modes = {modes!r}: must be >= 1 (the solution has {n_all})")
    P = np.asarray(modal.positions, float)
    if P.ndim != 2 or P.shape[1] != 3:
        raise SymcableError("plot_modes_3d draws 3D modes (positions (n, 3)); planar modes: "
                            "symcable.plotting.profiles.plot_modes")
    rows = [tuple(r) for r in (modal.stats.get("lines") or {"line": [0, len(P)]}).values()]
    a = 0.1 * float(np.max(np.ptp(P, axis=0))) if scale is None else float(scale)
    fig, axes = plt.subplots(k, 3, figsize=(14.0, 2.7 * k), squeeze=False)
    for m in range(k):
        U = np.asarray(modal.shapes[m], float)
        for ax, ((i, j), name) in zip(axes[m], _VIEWS):
            for r, (r0, r1) in enumerate(rows):
                first = r == 0
                ax.plot(P[r0:r1, i], P[r0:r1, j], color="0.6", lw=1.2,
                        label="static" if first else None)
                for sgn, style in ((1, "-"), (-1, "--")):
                    Q = P[r0:r1] + sgn * a * U[r0:r1]
                    ax.plot(Q[:, i], Q[:, j], style, color="tab:blue", lw=1.3,
                            label=f"{'+' if sgn > 0 else '-'}{a:.3g} m x shape" if first
                            else None)
            if seabed is not None and j == 2:
                ax.axhline(seabed, color="tab:brown", ls=":", lw=1.2, label="seabed")
            ax.set_aspect("equal", adjustable="datalim")
            ax.set_xlabel(f"{'xyz'[i]} (m)")
            ax.set_ylabel(f"{'xyz'[j]} (m)")
            ax.grid(alpha=0.3)
            ax.set_title(f"mode {m + 1}: {modal.frequencies[m]:.4g} Hz "
                         f"({modal.periods[m]:.4g} s), {name}", fontsize=9)
        if m == 0:
            axes[m, 1].legend(loc="best", fontsize=7)
    fig.suptitle(title or f"{modal.scene_name}: {k} lowest modes", fontsize=11)
    fig.tight_layout()
    return _finish(fig, path)
