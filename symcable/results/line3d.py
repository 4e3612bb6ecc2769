"""Time-domain results of a 3D line (``model = "cable3d"``): :class:`LineTrajectory`, what
:func:`symcable.simulate` returns for such a scene, with its slack and snap report, plots and
a ParaView export."""
from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..errors import SymcableError
from .io import force_text
from .static import Exportable, OneLine
from .trajectory import Trajectory

__all__ = ["LineTrajectory", "SystemTrajectory", "line_from_outputs", "slack_report", "snap_warning"]

#: a segment counts as slack when its strain is at most this (not stretched): the
#: tension-only law leaves it a tension below about EA times this
SLACK_STRAIN = 1e-7


def slack_report(time: np.ndarray, strain: np.ndarray, axial: np.ndarray) -> dict:
    """Where and when segments went slack, and the snaps that followed.

    ``time`` (n_t,) s, ``strain`` and ``axial`` (n_t, n_seg): a segment is slack at a sample
    where its strain is at most SLACK_STRAIN. Returns ``slack_fraction`` (the fraction of
    the run, by time, during which some segment was slack), ``slack_segments`` (the most
    segments slack at once), ``snaps`` (returns of a segment from slack to taut), and
    ``snap_peak`` (N, the largest axial force of a segment after its first snap; None
    without a snap) with ``snap_peak_time`` (s)."""
    slack = strain <= SLACK_STRAIN
    any_slack = slack.any(axis=1)
    dt = np.diff(time)
    frac = float(np.sum(dt * any_slack[:-1]) / max(time[-1] - time[0], 1e-300)) if dt.size else 0.0
    back = slack[:-1] & ~slack[1:]  # slack at a sample, taut at the next
    snaps = int(np.sum(back))
    out = {"slack_fraction": frac, "slack_segments": int(slack.sum(axis=1).max(initial=0)),
           "snaps": snaps, "snap_peak": None, "snap_peak_time": None}
    if snaps:
        first = int(np.argmax(back.any(axis=1))) + 1
        after = axial[first:]
        k = int(np.argmax(after.max(axis=1)))
        out.update(snap_peak=float(after[k].max()), snap_peak_time=float(time[first + k]))
    return out


@dataclass(frozen=True)
class LineTrajectory(OneLine, Exportable):
    """The time history of a 3D line, fully nonlinear (large motion, slack and snap), at the
    saved steps.

    ``n_t`` samples, ``n`` nodes (end A to end B), ``n_seg = n - 1`` segments.

    Attributes
    ----------
    scene_name : str
    time : ndarray (n_t,)
        Sample times, s (the excitation starts at t = 0; a motion table at its first row).
    s : ndarray (n,)
        Unstretched arc length of the nodes from end A, m.
    positions, velocities : ndarray (n_t, n, 3)
        Node positions (x, y, z), m, and velocities, m/s (z up).
    axial_force : ndarray (n_t, n_seg)
        Axial force of each segment, N (tension positive; a cable's is never below zero
        by more than round-off: it goes slack instead).
    strain : ndarray (n_t, n_seg)
        Axial strain of each segment, -.
    contact_force : ndarray (n_t, n)
        Seabed reaction on each node, N (zeros without a seabed).
    fairlead_force, anchor_force : ndarray (n_t, 3)
        Force the line exerts on end B (the fairlead) and end A (the anchor), N.
    fairlead_tension, anchor_tension : ndarray (n_t,)
        Their magnitudes, N.
    method : str
        ``"generalized-alpha"`` or ``"rk4"``.
    dt : float
        Time step, s.
    status : str
        ``"converged"`` (every step done; see ``warnings`` for a coarse step or a snap that
        needed substeps) or ``"failed"`` (a ConvergenceError's partial result).
    stats : dict
        The integrator's (:func:`symcable.integrate`: steps, Newton iterations,
        ``error_estimate``, ``substepped_steps``, wall time, ...), ``static_time`` (s), and
        the slack report (:func:`slack_report`): ``slack_fraction``, ``slack_segments``,
        ``snaps``, ``snap_peak`` (N), ``snap_peak_time`` (s).
    warnings : tuple of str
    """

    scene_name: str
    time: np.ndarray
    s: np.ndarray
    positions: np.ndarray
    velocities: np.ndarray
    axial_force: np.ndarray
    strain: np.ndarray
    contact_force: np.ndarray
    fairlead_force: np.ndarray
    anchor_force: np.ndarray
    fairlead_tension: np.ndarray
    anchor_tension: np.ndarray
    method: str
    dt: float
    status: str
    stats: dict = field(default_factory=dict)
    warnings: tuple = ()

    __repr__ = Exportable.short_repr

    @property
    def tension(self) -> np.ndarray:
        """(n_t, n_seg) N: the axial force floored at zero (a cable's tension)."""
        return np.maximum(self.axial_force, 0.0)

    def envelope(self, t_from: float | None = None) -> dict:
        """Least, mean and largest tension along the line over the samples from ``t_from`` s
        (default all): ``s`` (segment midpoints, m) and ``min``, ``mean``, ``max`` (N)."""
        sel = slice(None) if t_from is None else self.time >= t_from - 1e-12
        T = self.tension[sel]
        if not len(T):
            raise SymcableError(f"t_from = {t_from!r} s: after the last sample "
                                f"({self.time[-1]:.6g} s)")
        mid = 0.5 * (self.s[:-1] + self.s[1:])
        return {"s": mid, "min": T.min(axis=0), "mean": T.mean(axis=0), "max": T.max(axis=0)}

    def summary(self) -> str:
        """A few lines: run, end tensions (range), slack and snap, warnings."""
        st = self.stats
        kn = lambda a: force_text([np.min(a), np.max(a)])  # noqa: E731 (N, kN, MN by size)
        lines = [f"scene             {self.scene_name}",
                 f"run               {self.method}, dt {self.dt:.4g} s, {len(self.time)} samples "
                 f"over {self.time[-1] - self.time[0]:.4g} s, status {self.status}",
                 f"fairlead tension  {kn(self.fairlead_tension)}",
                 f"anchor tension    {kn(self.anchor_tension)}"]
        lines += _error_lines(st)
        if st.get("slack_fraction"):
            lines.append(f"slack             {100 * st['slack_fraction']:.3g} % of the time, up to "
                         f"{st['slack_segments']} segments; {st['snaps']} snap(s)"
                         + (f", peak {force_text(st['snap_peak'])} at t = "
                            f"{st['snap_peak_time']:.4g} s" if st.get("snap_peak") else ""))
        lines.append(f"wall time         {st.get('wall_time', float('nan')):.3g} s")
        lines += [f"warning           {w}" for w in self.warnings]
        return "\n".join(lines)

    def plot(self, path: str | Path | None = None, *, kind: str = "tensions", **options):
        """``kind = "tensions"``: end tensions against time and the tension envelope along the
        line; ``"profile"``: snapshots of the line in 3D, plan and elevation
        (:func:`symcable.plotting.line3d.plot_profiles`; ``snapshots``, ``title``). Saved
        to ``path`` when given; returns the matplotlib Figure."""
        from ..plotting.line3d import plot_profiles, plot_tensions
        if kind == "tensions":
            return plot_tensions(self, path, **options)
        if kind == "profile":
            return plot_profiles(self, path, **options)
        raise SymcableError(f"kind = {kind!r}: must be 'tensions' or 'profile'")

    def animate(self, path: str | Path, **options) -> Path:
        """An animated GIF of the line in plan and elevation
        (:func:`symcable.plotting.line3d.animate`: ``frames``, ``fps``, ``title``)."""
        from ..plotting.line3d import animate
        return animate(self, path, **options)

    def to_vtk(self, folder: str | Path, stem: str = "line") -> Path:
        """Write the run for ParaView (:func:`symcable.plotting.line3d.write_vtk`): one
        ``.vtu`` per sample (the line as a polyline, with tension, strain, velocity and
        seabed contact) and a ``.pvd`` collection with their times; returns the ``.pvd``."""
        from ..plotting.line3d import write_vtk
        return write_vtk(self, folder, stem)


def snap_warning(stats: dict) -> str | None:
    """The warning of a run in which segments went slack and snapped taut (None if none)."""
    if not stats.get("snaps"):
        return None
    return (f"segments went slack ({100 * stats['slack_fraction']:.3g} % of the time, up to "
            f"{stats['slack_segments']} at once) and snapped taut {stats['snaps']} time(s); "
            f"largest tension after a snap {force_text(stats['snap_peak'])} at t = "
            f"{stats['snap_peak_time']:.4g} s: snap peaks converge slowly in dt, check them at "
            "dt / 2")


def line_from_outputs(scene_name: str, time, outputs: dict, s, *, prefix: str = "",
                      method: str, dt: float, status: str, stats: dict,
                      warnings=()) -> LineTrajectory:
    """A LineTrajectory from a mechanism's outputs at the samples (``prefix``: a line's
    ``"NAME."`` in a scene of several lines), with its slack report in ``stats`` and a
    warning when it snapped."""
    t = np.asarray(time, float)
    n_t = t.size
    get = lambda key: np.asarray(outputs[prefix + key], float)  # noqa: E731
    pos = get("positions").reshape(n_t, -1, 3)
    n = pos.shape[1]
    axial = get("axial_force").reshape(n_t, n - 1)
    strain = get("strain").reshape(n_t, n - 1)
    fa, fb = (get(k).reshape(n_t, 3) for k in ("end_force_a", "end_force_b"))
    stats = dict(stats, **slack_report(t, strain, axial))
    note = snap_warning(stats)
    return LineTrajectory(
        scene_name=scene_name, time=t, s=np.asarray(s, float), positions=pos,
        velocities=get("velocities").reshape(n_t, n, 3), axial_force=axial, strain=strain,
        contact_force=get("contact_force").reshape(n_t, n), fairlead_force=fb,
        anchor_force=fa, fairlead_tension=np.linalg.norm(fb, axis=1),
        anchor_tension=np.linalg.norm(fa, axis=1), method=method, dt=float(dt), status=status,
        stats=stats, warnings=tuple(warnings) + ((note,) if note else ()))


@dataclass(frozen=True)
class SystemTrajectory(Exportable):
    """The time history of a scene of several lines and points (scene version 2).

    Attributes
    ----------
    scene_name : str
    time : ndarray (n_t,), s
    outputs : dict name -> ndarray (n_t, ...)
        The mechanism's outputs at the samples, namespaced (``"upper.axial_force"``,
        ``"buoy.position"``; see :mod:`symcable.models.system`).
    line_names, point_names : tuple of str
    line_s : dict line name -> ndarray (n,)  unstretched arc length of its nodes, m
    method : str;  dt : float, s;  status : str;  stats : dict;  warnings : tuple of str

    ``lines[name]`` is each line's :class:`LineTrajectory` (with its own slack report);
    ``points[name]`` a dict of ``position`` (n_t, 3) m and ``force`` (n_t, 3) N, the force
    the lines exert on the point; ``bodies[name]`` (``body_names``) a dict of ``position``
    (n_t, 3) m, ``orientation`` (n_t, 4) (unit quaternion, scalar first),
    ``roll_pitch_yaw`` (n_t, 3) deg, ``force`` (n_t, 3) N and ``moment`` (n_t, 3) N m (the
    lines' on the body, global axes, about its reference point), and for a free body
    ``velocity`` (n_t, 3) m/s and ``angular_velocity`` (n_t, 3) rad/s (body axes).
    """

    scene_name: str
    time: np.ndarray
    outputs: dict
    line_names: tuple
    point_names: tuple
    line_s: dict
    method: str
    dt: float
    status: str
    stats: dict = field(default_factory=dict)
    warnings: tuple = ()
    body_names: tuple = ()

    def __repr__(self) -> str:
        return (f"SystemTrajectory(status={self.status!r}, scene_name={self.scene_name!r}, "
                f"lines={list(self.line_names)}, points={list(self.point_names)}, "
                + (f"bodies={list(self.body_names)}, " if self.body_names else "")
                + f"{self.time.size} samples)")

    @property
    def lines(self):
        from types import MappingProxyType
        return MappingProxyType({
            name: line_from_outputs(f"{self.scene_name}:{name}", self.time, self.outputs,
                                    self.line_s[name], prefix=f"{name}.", method=self.method,
                                    dt=self.dt, status=self.status, stats={})
            for name in self.line_names})

    @property
    def fairlead_tension(self) -> np.ndarray:
        """(n_t,) N: the tension at end B of the scene's first line (the one-line shortcut;
        every line's: ``lines[name].fairlead_tension``)."""
        return self.lines[self.line_names[0]].fairlead_tension

    @property
    def anchor_tension(self) -> np.ndarray:
        """(n_t,) N: the tension at end A of the scene's first line."""
        return self.lines[self.line_names[0]].anchor_tension

    @property
    def points(self):
        from types import MappingProxyType
        n_t = self.time.size
        return MappingProxyType({
            name: {k: np.asarray(self.outputs[f"{name}.{k}"], float).reshape(n_t, 3)
                   for k in ("position", "force") if f"{name}.{k}" in self.outputs}
            for name in self.point_names})

    @property
    def bodies(self):
        from types import MappingProxyType
        n_t = self.time.size
        keys = {"position": 3, "orientation": 4, "roll_pitch_yaw": 3, "velocity": 3,
                "angular_velocity": 3, "force": 3, "moment": 3}
        return MappingProxyType({
            name: {k: np.asarray(self.outputs[f"{name}.{k}"], float).reshape(n_t, n)
                   for k, n in keys.items() if f"{name}.{k}" in self.outputs}
            for name in self.body_names})

    def plot(self, path: str | Path | None = None, *, kind: str = "tensions", t0=None,
             scene=None, **options):
        """``kind = "tensions"``: every line's end tensions against time, divided by their
        static tensions ``t0`` = {line: (T0_a, T0_b)} (N) when given, else in kN
        (:func:`symcable.plotting.system.plot_system_tensions`); ``"system"``: the lines,
        points and bodies in 3D, plan and elevation at a few samples
        (:func:`symcable.plotting.bodies.plot_system`; ``scene`` for the bodies'
        attachment points, ``snapshots``). Saved to ``path`` when given; returns the
        matplotlib Figure."""
        if kind == "tensions":
            from ..plotting.system import plot_system_tensions
            return plot_system_tensions(self, path, t0=t0, **options)
        if kind == "system":
            from ..plotting.bodies import plot_system
            return plot_system(self, path, scene=scene, **options)
        raise SymcableError(f"kind = {kind!r}: must be 'tensions' or 'system'")

    def summary(self) -> str:
        """The run, each line's end tensions (range; N, kN or MN by their size) and each
        point's excursion (m)."""
        st = self.stats
        out = [f"scene             {self.scene_name}",
               f"run               {self.method}, dt {self.dt:.4g} s, {self.time.size} samples "
               f"over {self.time[-1] - self.time[0]:.4g} s, status {self.status}"]
        for name, ln in self.lines.items():
            out.append(f"line {name:12s} fairlead "
                       f"{force_text([ln.fairlead_tension.min(), ln.fairlead_tension.max()])}, "
                       f"anchor {force_text([ln.anchor_tension.min(), ln.anchor_tension.max()])}")
        for name, pt in self.points.items():
            x = pt["position"]
            out.append(f"point {name:11s} excursion {np.max(np.linalg.norm(x - x[0], axis=1)):.4g} m")
        for name, b in self.bodies.items():
            x, a = b["position"], b["roll_pitch_yaw"]
            out.append(f"body {name:12s} excursion {np.max(np.linalg.norm(x - x[0], axis=1)):.4g} "
                       f"m, largest roll/pitch/yaw change {np.max(np.abs(a - a[0])):.4g} deg")
        out += _error_lines(st)
        out.append(f"wall time         {st.get('wall_time', float('nan')):.3g} s")
        out += [f"warning           {w}" for w in self.warnings]
        return "\n".join(out)

    @classmethod
    def load(cls, path):
        obj = super().load(path)
        object.__setattr__(obj, "outputs", {k: np.asarray(v, float) for k, v in obj.outputs.items()})
        object.__setattr__(obj, "line_s", {k: np.asarray(v, float) for k, v in obj.line_s.items()})
        object.__setattr__(obj, "line_names", tuple(obj.line_names))
        object.__setattr__(obj, "point_names", tuple(obj.point_names))
        object.__setattr__(obj, "body_names", tuple(obj.body_names))
        return obj


Trajectory.register(LineTrajectory)  # a 3D line's and a scene's time histories are
Trajectory.register(SystemTrajectory)  # Trajectories too (isinstance holds)


def _error_lines(st: dict) -> list:
    """The summary's line on a run's time-stepping error: the bound verified against a run
    at twice the step when its step was chosen for a tolerance, else the run's own estimate."""
    if st.get("error_measured") is not None:
        return [f"error             {100 * st['error_measured']:.2g} % of the range (against a "
                f"run at twice the step; tol {100 * st['tol']:.2g} %)"]
    if st.get("error_estimate") is not None:
        return [f"error estimate    {100 * st['error_estimate']:.2g} % of the range"]
    return []
