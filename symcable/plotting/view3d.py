"""Plots of any Mechanism's state in space: its parts' nodes in 3D (a 3D view with plan and
elevation projections) or in the vertical plane (dim = 2).

Works from a result (:class:`~symcable.results.generic.Equilibrium` or
:class:`~symcable.results.generic.MechanismTrajectory`) and the mechanism's
:class:`~symcable.mechanism.mechanism.Layout`: a node's coordinates are its entries of ``q``
(``node_q``); a prescribed node's are the output ``NAME.position`` of what moves it
(``PartLayout.prescribed``); a part whose nodes are not in ``q`` (the planar statics, whose
unknowns are angles and strains) is drawn from its ``positions`` output. Axes: x, y
horizontal, z up, m.

Like :mod:`symcable.plotting.profiles`, each function returns its matplotlib Figure, saved to ``path``
when given; matplotlib is imported on first use.
"""
from __future__ import annotations

import re
from pathlib import Path

import numpy as np

from ..errors import SymcableError

__all__ = ["node_positions", "plot_mechanism"]

SURFACE_COLOR = "tab:cyan"
SEABED_COLOR = "saddlebrown"
PRESCRIBED_STYLE = dict(marker="s", s=46, facecolors="white", edgecolors="black",
                        linewidths=1.4, zorder=6)
#: more parts than this are coloured and listed by name family (``k0`` ... ``k12`` -> ``k*``)
MAX_LEGEND_PARTS = 10
#: snapshots drawn of a trajectory by default
SNAPSHOTS = 4


def _layout_of(layout):
    lay = getattr(layout, "layout", layout)  # a Mechanism or its Layout
    if not hasattr(lay, "parts") or not hasattr(lay, "dim"):
        raise SymcableError(f"layout = {type(layout).__name__}: give the Mechanism the result "
                            "belongs to, or its Layout")
    if lay.dim not in (2, 3):
        raise SymcableError(f"layout.dim = {lay.dim}: only 2 (x, z) and 3 (x, y, z) are drawn")
    return lay


def node_positions(result, layout) -> dict:
    """Node positions of every part that has nodes, m: part name -> array (n_t, n_nodes, dim)
    (n_t = 1 for an Equilibrium), from ``result.q``, the prescribed nodes' ``NAME.position``
    outputs and, for parts without node coordinates in q, a ``positions`` output.

    Raises SymcableError when a node's position cannot be found."""
    lay = _layout_of(layout)
    q = np.atleast_2d(np.asarray(result.q, dtype=float))
    outs = result.outputs or {}
    n_t, dim = q.shape[0], lay.dim
    found = {}
    for name, part in lay.parts.items():
        if part.n_nodes == 0:
            continue
        idx = np.asarray(part.node_q, dtype=int)
        pos = np.full((n_t, part.n_nodes, dim), np.nan)
        free = idx >= 0
        pos[:, free] = q[:, idx[free]]
        for i, joint in part.prescribed.items():
            key = f"{joint}.position"
            if key in outs:
                pos[:, i] = np.asarray(outs[key], dtype=float).reshape(n_t, dim)
        missing = np.isnan(pos).any(axis=(0, 2))
        if missing.any():
            keys = [f"{name}.positions"] + (["positions"] if len(lay.parts) == 1 else [])
            key = next((k for k in keys if k in outs), None)
            if key is None:
                raise SymcableError(
                    f"part {name!r}: nodes {np.flatnonzero(missing).tolist()} have no "
                    "coordinates in q, no prescribed position output and the result has no "
                    f"{keys[0]!r} output")
            pos = np.asarray(outs[key], dtype=float).reshape(n_t, part.n_nodes, dim)
        found[name] = pos
    if not found:
        raise SymcableError("the layout has no part with nodes: nothing to draw")
    return found


def dim_of(layout) -> int:
    """The layout's dimension (2 or 3)."""
    return _layout_of(layout).dim


def _colours(lay, names) -> dict:
    """Part -> (colour, legend label or None): one colour per part, or per name family
    (``m1`` ... ``m12`` -> "m1-m12 (12 points)") when there are many parts."""
    if len(names) <= MAX_LEGEND_PARTS:
        return {n: (f"C{k % 10}", n if n == lay.parts[n].kind else f"{n} ({lay.parts[n].kind})")
                for k, n in enumerate(names)}
    family = {n: re.sub(r"\d+$", "", n) for n in names}
    members = {}
    for n in names:
        members.setdefault(family[n], []).append(n)
    out = {}
    for k, (fam, group) in enumerate(members.items()):
        kind = lay.parts[group[0]].kind
        label = (f"{group[0]}-{group[-1]} ({len(group)} {kind}s)" if len(group) > 1
                 else f"{group[0]} ({kind})")
        for j, n in enumerate(group):
            out[n] = (f"C{k % 10}", label if j == 0 else None)
    return out


def _snapshot_indices(n_t: int, times, t, snapshots: int) -> np.ndarray:
    if n_t == 1:
        return np.array([0])
    if times is not None:
        return np.unique([int(np.argmin(np.abs(t - float(x)))) for x in np.ravel(times)])
    return np.unique(np.linspace(0, n_t - 1, max(1, int(snapshots))).round().astype(int))


def _views(dim: int) -> list:
    """(axes key, coordinate indices, axis labels) of each 2D view."""
    if dim == 2:
        return [("elevation", (0, 1), ("x (m)", "z (m)"))]
    return [("plan", (0, 1), ("x (m)", "y (m)")), ("elevation", (0, 2), ("x (m)", "z (m)"))]


def _equal_3d(ax, pts: np.ndarray) -> None:
    """Limits around the points with equal scales on x, y and z."""
    lo, hi = np.nanmin(pts, axis=0), np.nanmax(pts, axis=0)
    centre, half = 0.5 * (lo + hi), 0.5 * max(float(np.max(hi - lo)), 1e-9) * 1.05
    ax.set_xlim(centre[0] - half, centre[0] + half)
    ax.set_ylim(centre[1] - half, centre[1] + half)
    ax.set_zlim(centre[2] - half, centre[2] + half)
    ax.set_box_aspect((1, 1, 1))


def plot_mechanism(result, layout, path: str | Path | None = None, *, times=None,
                   snapshots: int = SNAPSHOTS, envelope: bool = False,
                   seabed: float | None = None, surface: bool = False, title: str | None = None,
                   bodies: dict | None = None):
    """Draw a mechanism's state: for dim = 3 a 3D view with the plan (x-y) and elevation
    (x-z) projections beside it, for dim = 2 the elevation (x-z).

    Each part (a line, a point mass, a spring) in its own colour, named in the legend (by
    name family beyond ten parts); nodes as dots; prescribed nodes (whose position is given,
    e.g. fixed or moved ends) as open squares. Axes in m at true scale (equal axes).

    Parameters
    ----------
    result : Equilibrium or MechanismTrajectory
    layout : Mechanism or Layout
        The mechanism the result belongs to (its layout says which q are which node).
    path : str or Path, optional
        Save the figure there (PNG, PDF or SVG by suffix, at 150 dpi).
    times : sequence of float, optional
        Trajectory only: the times (s) to draw, nearest saved samples; default ``snapshots``
        evenly spaced samples from the first to the last. Earlier snapshots are drawn
        fainter, the last one solid.
    snapshots : int
        Number of snapshots when ``times`` is not given.
    envelope : bool
        Trajectory only: instead of snapshots, every node's path over the whole run (thin
        lines: the region the mechanism sweeps), with the last state solid.
    seabed : float, optional
        Depth of a flat seabed, as its z (m, negative below the free surface): a brown plane
        in 3D and a line in the elevation.
    surface : bool
        Draw the free surface z = 0 (a cyan plane in 3D, a line in the elevation).
    title : str, optional
        Replaces the default title (the mechanism, and the time or "equilibrium").
    bodies : dict, optional
        Rigid bodies (every pair of outputs ``NAME.position``, ``NAME.orientation``) are
        drawn by :func:`symcable.plotting.bodies.draw_bodies` (a box, their axes, their
        attachment points); ``bodies`` gives those points, name -> (k, 3) in body axes
        (:func:`symcable.plotting.bodies.body_attachments` of the scene).

    Returns
    -------
    matplotlib.figure.Figure
    """
    import matplotlib.pyplot as plt

    from .bodies import body_poses

    lay = _layout_of(layout)
    # a body part's "nodes" are its position and quaternion: drawn as a body instead
    pos = {n: p for n, p in node_positions(result, lay).items() if lay.parts[n].kind != "body"}
    poses = body_poses(result.outputs or {}) if dim_of(lay) == 3 else {}
    dim = lay.dim
    is_traj = np.ndim(result.q) == 2
    t = np.atleast_1d(np.asarray(getattr(result, "time", [0.0]), dtype=float))
    n_t = next(iter(pos.values())).shape[0]
    if (times is not None or envelope) and not is_traj:
        raise SymcableError("times / envelope: only for a MechanismTrajectory (an Equilibrium "
                            "is one state)")
    picks = np.array([n_t - 1]) if envelope else _snapshot_indices(n_t, times, t, snapshots)
    colours = _colours(lay, list(pos))

    if dim == 3:
        fig = plt.figure(figsize=(12.0, 6.4))
        gs = fig.add_gridspec(2, 2, width_ratios=(1.15, 1.0), left=0.02, right=0.80,
                              bottom=0.09, top=0.87, wspace=0.18, hspace=0.35)
        ax3 = fig.add_subplot(gs[:, 0], projection="3d")
        axes2 = {"plan": fig.add_subplot(gs[0, 1]), "elevation": fig.add_subplot(gs[1, 1])}
    else:
        fig = plt.figure(figsize=(10.0, 5.0))
        ax3 = None
        axes2 = {"elevation": fig.add_axes((0.09, 0.12, 0.68, 0.72))}

    every = np.concatenate([p.reshape(-1, dim) for p in pos.values()]
                           + [X for X, _ in poses.values()])
    every = every[np.all(np.isfinite(every), axis=1)]
    body_handles = _draw_snapshots(ax3, axes2, lay, pos, poses, bodies, picks, colours, every)
    if envelope:
        _draw_envelope(ax3, axes2, lay, pos, colours)
    levels = _draw_levels(ax3, axes2, dim, every, seabed, surface)
    handles = _legend_handles(lay, pos, colours, body_handles, levels, t, picks,
                              is_traj and not envelope and len(picks) > 1, envelope)
    fig.legend(handles=handles, loc="upper left", bbox_to_anchor=(0.81 if dim == 3 else 0.79, 0.87),
               fontsize=8, frameon=False)
    if title is None:
        if not is_traj:
            when = "equilibrium"
        elif envelope:
            when = f"node paths over t = {t[0]:.4g}-{t[-1]:.4g} s, the state at {t[-1]:.4g} s solid"
        else:
            when = f"t = {t[picks[-1]]:.4g} s" + (f" (and {len(picks) - 1} earlier, fainter)"
                                                  if len(picks) > 1 else "")
        title = f"{result.mechanism}: {when}; {result.status}; true scale, m"
    fig.suptitle(title, fontsize=11)
    from .profiles import finish
    return finish(fig, path)


def _draw_snapshots(ax3, axes2: dict, lay, pos: dict, poses: dict, bodies: dict | None,
                    picks: np.ndarray, colours: dict, every: np.ndarray) -> list:
    """Draws each part at the sample indices ``picks`` (earlier ones fainter; points last,
    on top of the lines that meet at them; prescribed nodes of the last as open squares)
    on the 3D axes ``ax3`` (None in 2D) and the 2D views ``axes2``, and the bodies
    ``poses``; returns the bodies' legend handles. ``every``: all drawn points (k, dim), m."""
    from .bodies import draw_bodies

    dim = lay.dim
    order = sorted(pos, key=lambda n: lay.parts[n].kind == "point")
    body_handles = []
    for k_snap, i in enumerate(picks):
        last = k_snap == len(picks) - 1
        alpha = 1.0 if last else 0.25 + 0.5 * k_snap / max(1, len(picks) - 1)
        for name in order:
            colour, _ = colours[name]
            part = lay.parts[name]
            xyz = pos[name][i]
            pres = np.zeros(part.n_nodes, dtype=bool)
            pres[list(part.prescribed)] = True
            style = dict(color=colour, alpha=alpha, gid=f"{name}@{i}", marker="o")
            if part.kind == "point":
                style.update(ls="", ms=5.5 if last else 3.0, zorder=4)
            else:
                style.update(lw=1.8 if last else 1.0, ms=2.5 if last else 1.5)
            if ax3 is not None:
                ax3.plot(xyz[:, 0], xyz[:, 1], xyz[:, 2], **style)
                if last and pres.any():
                    ax3.scatter(*xyz[pres].T, **PRESCRIBED_STYLE)
            for key, (a, b), _ in _views(dim):
                ax = axes2[key]
                ax.plot(xyz[:, a], xyz[:, b], **style)
                if last and pres.any():
                    ax.scatter(xyz[pres, a], xyz[pres, b], **PRESCRIBED_STYLE)
        if poses:
            body_handles = draw_bodies(
                ax3, [(axes2[key], ab) for key, ab, _ in _views(dim)], poses, bodies,
                float(np.max(np.ptp(every, axis=0))), index=min(i, len(next(iter(
                    poses.values()))[0]) - 1), alpha=alpha, label=last)
    return body_handles


def _draw_envelope(ax3, axes2: dict, lay, pos: dict, colours: dict) -> None:
    """Draws every node's path over the whole run, each distinct node once (parts share
    nodes), as thin lines."""
    seen = set()
    for name, p in pos.items():
        colour, _ = colours[name]
        part = lay.parts[name]
        for node in range(p.shape[1]):
            key = (tuple(part.node_q[node]) if np.all(part.node_q[node] >= 0)
                   else part.prescribed.get(node, (name, node)))
            if key in seen:
                continue
            seen.add(key)
            path_ = p[:, node]
            if ax3 is not None:
                ax3.plot(*path_.T, color=colour, lw=0.6, alpha=0.35)
            for key, (a, b), _ in _views(lay.dim):
                axes2[key].plot(path_[:, a], path_[:, b], color=colour, lw=0.6, alpha=0.35)


def _draw_levels(ax3, axes2: dict, dim: int, every: np.ndarray, seabed: float | None,
                 surface: bool) -> list:
    """Draws the seabed and free surface (planes in 3D, lines in the elevation), sets the
    axes' labels, titles and true-scale limits around ``every`` (k, dim) and the levels;
    returns the levels drawn, [(z (m), colour, label)]."""
    lo, hi = every.min(axis=0), every.max(axis=0)
    levels = [(z, c, lab) for z, c, lab in ((seabed, SEABED_COLOR, f"seabed, z = {seabed:g} m"
                                             if seabed is not None else ""),
                                            (0.0 if surface else None, SURFACE_COLOR,
                                             "free surface, z = 0"))
              if z is not None]
    centre, half = 0.5 * (lo + hi), 0.5 * max(float(np.max(hi - lo)), 1e-9)
    if ax3 is not None and levels:  # the planes span the scene's extent on x and y
        X, Y = np.meshgrid(*([centre[j] - 1.05 * half, centre[j] + 1.05 * half] for j in (0, 1)))
        for z, c, _ in levels:
            ax3.plot_surface(X, Y, np.full_like(X, z), color=c, alpha=0.15, linewidth=0)
    for z, c, _ in levels:
        axes2["elevation"].axhline(z, color=c, lw=1.2, ls="--")
    if ax3 is not None:
        pts = every if not levels else np.vstack([every] + [np.r_[lo[:2], z][None] for z, _, _ in levels])
        _equal_3d(ax3, pts)
        ax3.set_xlabel("x (m)")
        ax3.set_ylabel("y (m)")
        ax3.set_zlabel("z (m)")
        ax3.set_title("3D view")
    for key, (a, b), (xl, yl) in _views(dim):
        ax = axes2[key]
        # each view spans at least a tenth of the scene's extent: a coordinate that varies
        # by round-off only (a plan of a line in its vertical plane) is drawn flat
        ax.update_datalim([[centre[a] - 0.1 * half, centre[b] - 0.1 * half],
                           [centre[a] + 0.1 * half, centre[b] + 0.1 * half]])
        ax.autoscale_view()
        ax.set_xlabel(xl)
        ax.set_ylabel(yl)
        ax.set_aspect("equal", adjustable="datalim")
        ax.grid(True, lw=0.4, alpha=0.5)
        ax.set_title("plan (x-y)" if key == "plan" else "elevation (x-z)")
        if key == "elevation" and levels:
            zs = [z for z, _, _ in levels]
            ax.update_datalim([[lo[0], min(zs)], [hi[0], max(zs)]])
            ax.autoscale_view()
    return levels


def _legend_handles(lay, pos: dict, colours: dict, body_handles: list, levels: list,
                    t: np.ndarray, picks: np.ndarray, earlier: bool, envelope: bool) -> list:
    """The legend's handles: parts, the prescribed-node marker, bodies, levels and, with
    ``earlier``, the earlier snapshots' times or, with ``envelope``, the node paths' (``t``
    the samples' times, s; ``picks`` the snapshots' sample indices)."""
    from matplotlib.lines import Line2D

    handles = [Line2D([], [], color=colours[n][0], label=colours[n][1], marker="o",
                      **(dict(ls="", ms=5.5) if lay.parts[n].kind == "point" else dict(lw=1.8, ms=2.5)))
               for n in pos if colours[n][1] is not None]
    if any(lay.parts[n].prescribed for n in pos):
        handles.append(Line2D([], [], ls="", marker="s", mfc="white", mec="black", ms=7,
                              label="prescribed node"))
    handles += body_handles
    handles += [Line2D([], [], color=c, lw=1.2, ls="--", label=lab) for _, c, lab in levels]
    if earlier:
        handles.append(Line2D([], [], color="grey", alpha=0.4, lw=1.0,
                              label="earlier: t = " + ", ".join(f"{t[i]:.3g}" for i in picks[:-1])
                              + " s"))
    if envelope:
        handles.append(Line2D([], [], color="grey", alpha=0.4, lw=0.6,
                              label=f"node paths, t = {t[0]:.3g}-{t[-1]:.3g} s"))
    return handles
