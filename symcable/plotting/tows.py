"""Figures of a towed system's time run (a scene with a ``kind = "tow"`` motion; what
``symcable simulate SCENE --plot FILE`` draws for one): the ship's (towpoint's) and the
towed bodies' tracks in plan, the bodies' depth over time and the towpoint's tension over
time, normalised by the steady-tow tension T0 when the run started from its steady tow.

The towpoints are the held things that tow (a version-1 line's pinned end with the tow
motion, a version-2 vessel point); the towed things are a version-1 line's other end, and a
version-2 scene's free points and free bodies. Units: m, s, N (the tension in kN when it is
not normalised).
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

__all__ = ["tow_tracks", "turn_spans", "plot_tow"]



def _is_tow(motion) -> bool:
    return motion is not None and getattr(motion, "kind", None) == "tow"


def tow_tracks(tr, scene) -> dict:
    """The series the figure draws, from a LineTrajectory or SystemTrajectory ``tr`` of
    ``scene``: ``{"time": (n_t,), "ships": {label: (n_t, 3)}, "towed": {label: (n_t, 3)},
    "tension": {label: (n_t,) N}}``: each towpoint's position and the tension it pulls
    with, each towed thing's position (m)."""
    ships, towed, tension = {}, {}, {}
    if scene.version == 1:
        for key, node, other, top in (("end_a", 0, -1, "anchor_tension"),
                                      ("end_b", -1, 0, "fairlead_tension")):
            end = getattr(scene, key)
            if _is_tow(end.motion):
                ships[key] = tr.positions[:, node]
                tension[key] = np.asarray(getattr(tr, top), float)
                towed["end_b" if key == "end_a" else "end_a"] = tr.positions[:, other]
    else:
        pts = tr.points
        for name, pt in scene.points.items():
            if _is_tow(pt.motion):
                ships[name] = pts[name]["position"]
                tension[name] = np.linalg.norm(pts[name]["force"], axis=1)
            elif pt.is_free:
                towed[name] = pts[name]["position"]
        for name, body in scene.bodies.items():
            if body.is_free:
                towed[name] = tr.bodies[name]["position"]
    return {"time": np.asarray(tr.time, float), "ships": ships, "towed": towed,
            "tension": tension}


def turn_spans(scene) -> list[tuple[float, float]]:
    """[(start, end)] s of every turn of the scene's tow motions."""
    spans = []
    motions = ([e.motion for e in (scene.end_a, scene.end_b) if e is not None]
               if scene.version == 1 else [pt.motion for pt in scene.points.values()])
    for m in motions:
        if _is_tow(m):
            t = m.start
            for after, radius, angle in m.turns:
                t0 = t + after
                t = t0 + radius * np.radians(abs(angle)) / m.speed
                spans.append((t0, t))
    return spans


def plot_tow(tr, scene, path: str | Path | None = None, *, title: str | None = None):
    """Three panels: the tracks in plan (x, y; equal axes; start o, end s), each towed
    thing's depth below the surface over time, each towpoint's tension over time (/ T0, its
    value at the start, when the run started from its steady tow; else kN); the turns
    shaded. Returns the
    figure, saved to ``path`` when given."""
    import matplotlib.pyplot as plt
    d = tow_tracks(tr, scene)
    t = d["time"]
    fig, (ax, bx, cx) = plt.subplots(1, 3, figsize=(15, 4.6),
                                     gridspec_kw={"width_ratios": [1.2, 1, 1]})
    for k, (name, x) in enumerate(d["ships"].items()):
        ax.plot(x[:, 0], x[:, 1], color="k", lw=1.8, label=f"towpoint ({name})")
        ax.plot(*x[0, :2], "o", color="k", ms=6, mfc="white")
        ax.plot(*x[-1, :2], "s", color="k", ms=6)
    colours = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    for k, (name, x) in enumerate(d["towed"].items()):
        c = colours[k % len(colours)]
        ax.plot(x[:, 0], x[:, 1], color=c, lw=1.4, label=f"towed: {name}")
        ax.plot(*x[0, :2], "o", color=c, ms=6, mfc="white")
        ax.plot(*x[-1, :2], "s", color=c, ms=6)
        bx.plot(t, -x[:, 2], color=c, lw=1.4, label=name)
    ax.plot([], [], "o", color="0.4", mfc="white", label="start")
    ax.plot([], [], "s", color="0.4", label="end")
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.set_title("tracks in plan", fontsize=10)
    ax.legend(loc="best", fontsize=8)
    bx.invert_yaxis()
    bx.set_xlabel("time (s)")
    bx.set_ylabel("depth below the surface (m)")
    bx.set_title("towed depth", fontsize=10)
    steady = tr.stats.get("start") == "steady tow"
    for name, T in d["tension"].items():
        cx.plot(t, T / T[0] if steady and T[0] > 0 else T / 1e3, color="k", lw=1.4, label=name)
    if steady and d["tension"]:
        T0 = next(iter(d["tension"].values()))[0]
        cx.axhline(1.0, color="0.5", lw=0.8, ls="--")
        cx.set_ylabel("towpoint tension / T0")
        cx.set_title(f"towpoint tension (T0 = {T0 / 1e3:.4g} kN, the steady tow)", fontsize=10)
    else:
        cx.set_ylabel("towpoint tension (kN)")
        cx.set_title("towpoint tension", fontsize=10)
    cx.set_xlabel("time (s)")
    from .profiles import least_span
    top = max((float(np.max(np.abs(T))) for T in d["tension"].values()), default=0.0)
    least_span(cx, 0.02 if steady else 0.02 * top / 1e3)  # 2 % of the tension: flat if less
    for k, (a, b) in enumerate(turn_spans(scene)):
        if b > t[0] and a < t[-1]:
            for axis in (bx, cx):
                axis.axvspan(max(a, t[0]), min(b, t[-1]), color="0.9", zorder=0,
                             label="turn" if k == 0 else None)
    cx.legend(loc="best", fontsize=8)
    for a in (ax, bx, cx):
        a.grid(alpha=0.3)
    bx.legend(loc="best", fontsize=8)
    fig.suptitle(title or f"{scene.name}: tow (dt = {tr.dt:.3g} s)", fontsize=11)
    fig.tight_layout()
    from .profiles import finish
    return finish(fig, path, tight=True)
