"""Rigid bodies in the 3D, plan and elevation views: each body as the box that
spans its attachment points in body axes, its local axes (x red, y green, z blue) from its
reference point, and its attachment points, at its position and orientation.

:func:`draw_bodies` adds them to existing axes (used by
:func:`symcable.plotting.view3d.plot_mechanism` for an Equilibrium or MechanismTrajectory);
:func:`plot_system` draws a scene of several lines, points and bodies from a
:class:`~symcable.results.static.SystemStaticSolution` or a
:class:`~symcable.results.line3d.SystemTrajectory` (lines, held and free points, bodies; a
trajectory's earlier snapshots fainter). :func:`body_attachments` reads the attachment
points from the scene. Axes: x, y horizontal, z up, m, true scale.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

from ..errors import SymcableError

__all__ = ["body_attachments", "body_poses", "draw_bodies", "plot_system"]

BODY_COLOR = "0.25"
AXIS_COLORS = ("tab:red", "tab:green", "tab:blue")
#: the box's half-size beyond its attachment points, and a body's least half-size, as a
#: fraction of the drawing's extent
PAD, LEAST = 0.01, 0.015


def body_attachments(scene) -> dict:
    """Body name -> (k, 3) the points (m, body axes) where the scene's lines end on it."""
    out = {name: [] for name in getattr(scene, "bodies", {})}
    for line in getattr(scene, "lines", ()):
        for key in ("a", "b"):
            end = line.end(key)
            if hasattr(end, "body") and end.body in out:
                out[end.body].append(tuple(end.offset))
    return {k: np.asarray(v, float).reshape(-1, 3) for k, v in out.items()}


def _rotation(e) -> np.ndarray:
    """(..., 3, 3) of unit quaternions (..., 4) (e0, e1, e2, e3), scalar first."""
    e = np.asarray(e, float)
    e = e / np.linalg.norm(e, axis=-1, keepdims=True)
    w, x, y, z = np.moveaxis(e, -1, 0)
    return np.stack([np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)], -1),
                     np.stack([2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)], -1),
                     np.stack([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], -1)],
                    -2)


def body_poses(outputs: dict) -> dict:
    """Body name -> (positions (n_t, 3), rotations (n_t, 3, 3)) of every body in a result's
    outputs (the pairs ``NAME.position`` and ``NAME.orientation``, a unit quaternion scalar
    first); n_t = 1 for one state."""
    out = {}
    for key in outputs:
        if key.endswith(".orientation"):
            name = key[:-len(".orientation")]
            if f"{name}.position" in outputs:
                x = np.asarray(outputs[f"{name}.position"], float).reshape(-1, 3)
                e = np.asarray(outputs[key], float).reshape(-1, 4)
                out[name] = (x, _rotation(e))
    return out


_EDGES = [(0, 1), (1, 3), (3, 2), (2, 0), (4, 5), (5, 7), (7, 6), (6, 4), (0, 4), (1, 5),
          (2, 6), (3, 7)]


def _box(offsets: np.ndarray, extent: float) -> np.ndarray:
    """(8, 3) corners (body axes) of the box around the reference point and ``offsets``."""
    pts = np.vstack([np.zeros((1, 3)), offsets])
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    mid, half = 0.5 * (lo + hi), 0.5 * (hi - lo) + PAD * extent
    half = np.maximum(half, LEAST * extent)
    return np.array([[mid[0] + sx * half[0], mid[1] + sy * half[1], mid[2] + sz * half[2]]
                     for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)])


def draw_bodies(ax3, views, poses: dict, attachments: dict | None, extent: float, *,
                index: int = -1, alpha: float = 1.0, label: bool = True) -> list:
    """Draw each body of ``poses`` (:func:`body_poses`) at sample ``index``: on the 3D axes
    ``ax3`` (or None) and each 2D view of ``views`` = [(axes, (i, j))] (coordinate indices,
    e.g. (0, 1) the plan); ``attachments`` name -> (k, 3) body-axes points
    (:func:`body_attachments`; the box is then their span), ``extent`` (m) the drawing's
    size for the boxes' least size and the axes' length. Returns legend handles."""
    from matplotlib.lines import Line2D

    attachments = attachments or {}
    for name, (X, R) in poses.items():
        x, Rk = X[index], R[index]
        offs = np.asarray(attachments.get(name, np.zeros((0, 3))), float).reshape(-1, 3)
        corners = x + _box(offs, extent) @ Rk.T
        arms = 0.6 * max(float(np.max(np.ptp(np.vstack([np.zeros((1, 3)), offs]), axis=0))),
                         2 * LEAST * extent)
        pts = x + offs @ Rk.T
        for a, b in _EDGES:
            seg = corners[[a, b]]
            if ax3 is not None:
                ax3.plot(*seg.T, color=BODY_COLOR, lw=1.0, alpha=alpha)
            for ax, (i, j) in views:
                ax.plot(seg[:, i], seg[:, j], color=BODY_COLOR, lw=1.0, alpha=alpha)
        for k in range(3):
            seg = np.vstack([x, x + arms * Rk[:, k]])
            if ax3 is not None:
                ax3.plot(*seg.T, color=AXIS_COLORS[k], lw=1.6, alpha=alpha)
            for ax, (i, j) in views:
                ax.plot(seg[:, i], seg[:, j], color=AXIS_COLORS[k], lw=1.6, alpha=alpha)
        if len(pts):
            if ax3 is not None:
                ax3.scatter(*pts.T, marker="^", s=30, color="black", alpha=alpha, zorder=7)
            for ax, (i, j) in views:
                ax.scatter(pts[:, i], pts[:, j], marker="^", s=30, color="black", alpha=alpha,
                           zorder=7)
        if label:
            for ax, (i, j) in views:
                ax.annotate(name, (x[i], x[j]), xytext=(4, 4), textcoords="offset points",
                            fontsize=8, color=BODY_COLOR)
    if not poses or not label:
        return []
    return [Line2D([], [], color=BODY_COLOR, lw=1.0, label="body (box of its attachments)"),
            Line2D([], [], color=AXIS_COLORS[0], lw=1.6, label="body axes x, y, z"),
            Line2D([], [], ls="", marker="^", color="black", label="attachment point")]


def _system_nodes(result) -> tuple[dict, dict, np.ndarray | None]:
    """(line -> (n_t, n, 3), point -> (n_t, 3), time or None) of a system result."""
    lines, points = {}, {}
    if hasattr(result, "time"):  # SystemTrajectory
        for name, ln in result.lines.items():
            lines[name] = np.asarray(ln.positions, float)
        for name, pt in result.points.items():
            points[name] = np.asarray(pt["position"], float).reshape(-1, 3)
        return lines, points, np.asarray(result.time, float)
    for name, ln in result.lines.items():
        lines[name] = np.asarray(ln.positions, float)[None]
    for name, pt in result.points.items():
        points[name] = np.asarray(pt.position, float).reshape(1, 3)
    return lines, points, None


def _outputs(result) -> dict:
    if hasattr(result, "outputs"):
        return result.outputs
    out = {}
    for name, b in getattr(result, "bodies", {}).items():
        out[f"{name}.position"] = np.asarray(b.position, float)
        out[f"{name}.orientation"] = np.asarray(b.orientation, float)
    return out


def plot_system(result, path: str | Path | None = None, *, scene=None, snapshots: int = 4,
                seabed: float | None = None, title: str | None = None):
    """A scene of several lines, points and bodies: a 3D view with the plan (x-y) and the
    elevation (x-z); lines in colour, points as dots, bodies as :func:`draw_bodies` draws
    them (their attachment points from ``scene`` when given, a scene or anything
    :func:`symcable.load_scene` takes). A trajectory: ``snapshots`` evenly spaced samples,
    earlier ones fainter. ``seabed``: its z (m), a dashed line in the elevation and a pale
    plane in the 3D view. A static solution also gets each line's tension along its
    unstretched length (kN). Saved to ``path`` when given; returns the Figure."""
    import matplotlib.pyplot as plt

    if not hasattr(result, "lines") or not hasattr(result, "points"):
        raise SymcableError(f"result = {type(result).__name__}: plot_system draws a "
                            "SystemStaticSolution or a SystemTrajectory")
    if scene is not None and not hasattr(scene, "lines"):
        from ..scene import load_scene
        scene = load_scene(scene)
    attach = body_attachments(scene) if scene is not None else {}
    lines, points, t = _system_nodes(result)
    poses = body_poses(_outputs(result))
    n_t = 1 if t is None else len(t)
    picks = np.unique(np.linspace(0, n_t - 1, max(1, min(int(snapshots), n_t))).round()
                      .astype(int))
    every = np.vstack([p.reshape(-1, 3) for p in lines.values()]
                      + [p.reshape(-1, 3) for p in points.values()]
                      + [X for X, _ in poses.values()])
    lo, hi = every.min(axis=0), every.max(axis=0)
    extent = max(float(np.max(hi - lo)), 1e-9)
    static = t is None
    fig = plt.figure(figsize=(12.0, 8.4 if static else 6.4))
    gs = fig.add_gridspec(3 if static else 2, 2, width_ratios=(1.15, 1.0), left=0.07,
                          right=0.80, bottom=0.07, top=0.9, wspace=0.18, hspace=0.45,
                          height_ratios=(1.0, 1.0, 0.8) if static else None)
    ax3 = fig.add_subplot(gs[:2, 0] if static else gs[:, 0], projection="3d")
    plan, elev = fig.add_subplot(gs[0, 1]), fig.add_subplot(gs[1, 1])
    views = [(plan, (0, 1)), (elev, (0, 2))]
    handles = []
    from matplotlib.lines import Line2D
    for k, i in enumerate(picks):
        last = k == len(picks) - 1
        alpha = 1.0 if last else 0.2 + 0.5 * k / max(1, len(picks) - 1)
        for c, (name, P) in enumerate(lines.items()):
            xyz = P[i]
            ax3.plot(*xyz.T, color=f"C{c % 10}", lw=1.6 if last else 0.9, alpha=alpha)
            for ax, (a, b) in views:
                ax.plot(xyz[:, a], xyz[:, b], color=f"C{c % 10}", lw=1.6 if last else 0.9,
                        alpha=alpha)
            if last:
                handles.append(Line2D([], [], color=f"C{c % 10}", lw=1.6, label=name))
        for name, P in points.items():
            ax3.scatter(*P[i], color="black", s=12, alpha=alpha)
            for ax, (a, b) in views:
                ax.scatter(P[i, a], P[i, b], color="black", s=12, alpha=alpha)
        handles += draw_bodies(ax3, views, poses, attach, extent, index=i, alpha=alpha,
                               label=last)
    centre, half = 0.5 * (lo + hi), 0.5 * extent * 1.05
    if seabed is not None:
        gx, gy = np.meshgrid(*(np.array([centre[j] - half, centre[j] + half]) for j in (0, 1)))
        ax3.plot_surface(gx, gy, np.full_like(gx, seabed), color="saddlebrown", alpha=0.12,
                         linewidth=0)
        elev.axhline(seabed, color="saddlebrown", lw=1.2, ls="--")
        handles.append(Line2D([], [], color="saddlebrown", lw=1.2, ls="--",
                              label=f"seabed, z = {seabed:g} m"))
    if points:
        handles.append(Line2D([], [], ls="", marker="o", ms=4, color="black", label="point"))
    for setter, j in ((ax3.set_xlim, 0), (ax3.set_ylim, 1), (ax3.set_zlim, 2)):
        setter(centre[j] - half, centre[j] + half)
    ax3.set_box_aspect((1, 1, 1))
    ax3.set_xlabel("x (m)")
    ax3.set_ylabel("y (m)")
    ax3.set_zlabel("z (m)")
    ax3.set_title("3D view")
    for ax, (a, b) in views:  # each view spans the scene's extent: round-off stays flat
        ax.set_xlim(centre[a] - half, centre[a] + half)
        lo_b, hi_b = centre[b] - half, centre[b] + half
        if b == 2 and seabed is not None:
            lo_b = min(lo_b, seabed - 0.05 * extent)
        ax.set_ylim(lo_b, hi_b)
        ax.set_aspect("equal", adjustable="datalim")
        ax.set_xlabel(f"{'xyz'[a]} (m)")
        ax.set_ylabel(f"{'xyz'[b]} (m)")
        ax.grid(True, lw=0.4, alpha=0.5)
        ax.set_title("plan (x-y)" if b == 1 else "elevation (x-z)")
    if static:
        _tension_panel(fig.add_subplot(gs[2, :]), result)
    if t is not None and len(picks) > 1:
        handles.append(Line2D([], [], color="grey", alpha=0.4, lw=1.0, label="earlier: t = "
                              + ", ".join(f"{t[i]:.3g}" for i in picks[:-1]) + " s"))
    fig.legend(handles=handles, loc="upper left", bbox_to_anchor=(0.81, 0.87), fontsize=8,
               frameon=False)
    when = "static solution" if t is None else f"t = {t[picks[-1]]:.4g} s"
    fig.suptitle(title or f"{result.scene_name}: {when}; {result.status}; true scale, m",
                 fontsize=11)
    from .profiles import finish
    return finish(fig, path)


def _tension_panel(ax, result) -> None:
    """Each line's tension (kN, or N when every tension is below 1 kN) against its
    unstretched length from end A (m)."""
    curves = []
    for name, ln in result.lines.items():
        s, T = np.ravel(np.asarray(ln.s, float)), np.ravel(np.asarray(ln.tension, float))
        if T.size == s.size - 1:  # per segment: at the segment midpoints
            s = 0.5 * (s[:-1] + s[1:])
        if T.size == s.size:
            curves.append((name, s, T))
    top = max((float(np.nanmax(np.abs(T))) for _, _, T in curves if T.size), default=0.0)
    unit, scale = ("kN", 1e3) if top >= 1e3 else ("N", 1.0)
    for c, (name, s, T) in enumerate(curves):
        ax.plot(s, T / scale, color=f"C{c % 10}", lw=1.4, label=name)
    ax.set_xlabel("unstretched length from end A (m)")
    ax.set_ylabel(f"tension ({unit})")
    ax.set_title("tension along each line")
    ax.grid(True, lw=0.4, alpha=0.5)
