"""Time-domain results: :class:`Trajectory`, what :func:`symcable.simulate` returns."""
from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Mapping

import numpy as np

from .results import Exportable

__all__ = ["Trajectory", "slack_warnings"]


@dataclass(frozen=True)
class Trajectory(Exportable):
    """A time history of a line, sampled at the saved steps.

    ``n_t`` is the number of saved samples, ``n_y`` the number of states, ``n_seg`` the
    number of segments.

    Attributes
    ----------
    scene_name : str
    time : ndarray (n_t,)
        Sample times, s (t = 0 is the rest state, where the excitation starts).
    s : ndarray (n_seg,)
        Unstretched arc length of each segment's midpoint from end A, m.
    states : ndarray (n_t, n_y)
        The model's state (for the planar model: node velocities in m/s, dynamic strain
        and dynamic angle in rad, interleaved; see :mod:`symcable.models.planar_dynamics`).
    fairlead_tension, anchor_tension : ndarray (n_t,)
        Magnitude of the force the line exerts on end B (fairlead) and end A (anchor), N.
    fairlead_force, anchor_force : ndarray (n_t, 2)
        Those forces, (F_x, F_z), N.
    tension : ndarray (n_t, n_seg)
        Magnitude of the total internal force of each segment (static plus dynamic), N.
    strain : ndarray (n_t, n_seg)
        Dynamic strain of each segment (increment on the static strain), -.
    angle : ndarray (n_t, n_seg)
        Dynamic angle of each segment (increment on the static angle), rad.
    method : str
        ``"rk4"`` or ``"generalized-alpha"``.
    dt : float
        Time step used, s.
    status : str
        ``"converged"`` (every step done), ``"slack"`` (done, but the total axial tension
        fell to zero or below somewhere: the model linearised about a taut state is invalid
        there; see ``warnings``) or ``"failed"`` (only on a ConvergenceError's partial
        result, which ends at the last good step).
    stats : dict
        ``steps``, ``dt`` (s), ``dt_requested`` (s), ``dt_stable`` (s, RK4's estimated
        stability limit), ``newton_iterations`` (total), ``newton_iterations_max`` (per
        step), ``newton_tol``, ``wall_time`` (s), ``us_per_step``, ``samples``,
        ``rho_inf``, ``alpha_m``, ``alpha_f``, ``gamma`` (generalized-α).
    warnings : tuple of str
    """

    scene_name: str
    time: np.ndarray
    s: np.ndarray
    states: np.ndarray
    fairlead_tension: np.ndarray
    anchor_tension: np.ndarray
    fairlead_force: np.ndarray
    anchor_force: np.ndarray
    tension: np.ndarray
    strain: np.ndarray
    angle: np.ndarray
    method: str
    dt: float
    status: str
    stats: dict = field(default_factory=dict)
    warnings: tuple = ()

    # ------------------------------------------------------------------ building
    @classmethod
    def from_outputs(cls, model, *, scene_name: str, time: np.ndarray, states: np.ndarray,
                     outputs: Mapping[str, np.ndarray], method: str, dt: float, status: str,
                     stats: dict, warnings: tuple = ()) -> "Trajectory":
        """Assemble a trajectory from the model's named outputs at the samples (each
        ``(n_t, ...)``), checking for slack: a slack line gets a warning and status
        ``"slack"`` (a failed run stays ``"failed"``)."""
        n_t = len(time)
        n_seg = np.asarray(outputs["tension"]).reshape(n_t, -1).shape[1]
        s_nodes = model.info.get("s_nodes") if model is not None else None
        s = (0.5 * (np.asarray(s_nodes)[:-1] + np.asarray(s_nodes)[1:]) if s_nodes is not None
             and len(s_nodes) == n_seg + 1 else np.arange(n_seg, dtype=float))

        def get(name, shape):
            v = outputs.get(name)
            return np.full(shape, np.nan) if v is None else np.asarray(v, dtype=float).reshape(shape)

        tension = get("tension", (n_t, n_seg))
        strain = get("strain", (n_t, n_seg))
        static = model.info.get("static") if model is not None else None
        if static is not None and np.shape(static.strain) == (n_seg,):
            slack, extra = slack_warnings(time, s, np.asarray(static.strain) + strain, static.strain)
        else:
            slack, extra = slack_warnings(time, s, tension)
        warns = tuple(warnings) + extra
        if status == "converged" and slack:
            status = "slack"
        return cls(scene_name=scene_name, time=np.asarray(time, dtype=float), s=s,
                   states=np.asarray(states, dtype=float).reshape(n_t, -1),
                   fairlead_tension=get("fairlead_tension", (n_t,)),
                   anchor_tension=get("anchor_tension", (n_t,)),
                   fairlead_force=get("fairlead_force", (n_t, 2)),
                   anchor_force=get("anchor_force", (n_t, 2)),
                   tension=tension, strain=strain, angle=get("angle", (n_t, n_seg)),
                   method=str(method), dt=float(dt), status=status, stats=dict(stats),
                   warnings=warns)

    # ------------------------------------------------------------------ derived
    @property
    def n_t(self) -> int:
        return int(len(self.time))

    def positions(self, model) -> np.ndarray:
        """Node positions (n_t, n_seg + 1, 2), m, reconstructed from the total angle and
        strain (seed S3). ``model`` is the :class:`~symcable.models.DynamicModel` the run used
        (``symcable.build_dynamic_model(scene)``)."""
        from .models.planar_dynamics import reconstruct_positions
        return reconstruct_positions(model, self.strain, self.angle)

    def tension_envelope(self) -> tuple[np.ndarray, np.ndarray]:
        """Least and largest segment tension over the saved samples, each (n_seg,), N."""
        return np.min(self.tension, axis=0), np.max(self.tension, axis=0)

    # ------------------------------------------------------------------ summary
    def summary(self) -> str:
        """A few lines a person reads: tensions (kN), motion ranges, solver stats."""
        st = self.stats
        ft = self.fairlead_tension
        at = self.anchor_tension
        lo, hi = self.tension_envelope() if self.n_t else (np.nan, np.nan)

        def rng(a, scale=1.0):
            a = np.asarray(a) / scale
            return f"{np.min(a):.4f} .. {np.max(a):.4f}" if a.size else "-"

        lines = [
            f"scene             {self.scene_name}",
            f"status            {self.status}: {self.method}, dt {self.dt:.6g} s, "
            f"{st.get('steps', '?')} steps to t = {self.time[-1] if self.n_t else 0.0:.6g} s, "
            f"{self.n_t} samples",
            f"fairlead tension  {rng(ft, 1e3)} kN (mean {np.mean(ft) / 1e3 if ft.size else np.nan:.4f} kN)",
            f"anchor tension    {rng(at, 1e3)} kN",
            f"segment tension   {np.min(lo) / 1e3 if np.size(lo) else np.nan:.4f} .. "
            f"{np.max(hi) / 1e3 if np.size(hi) else np.nan:.4f} kN over the line",
            f"dynamic strain    {rng(self.strain)} -",
            f"dynamic angle     {rng(np.degrees(self.angle))} deg",
        ]
        solver = (f"solver            {1e3 * st.get('wall_time', float('nan')):.1f} ms, "
                  f"{st.get('us_per_step', float('nan')):.1f} us/step")
        if st.get("newton_iterations") is not None:
            solver += (f", {st['newton_iterations']} Newton iterations "
                       f"(max {st.get('newton_iterations_max', '?')} per step)")
        if st.get("dt_stable") is not None:
            solver += f", RK4 stability limit {st['dt_stable']:.4g} s"
        lines.append(solver)
        lines += [f"warning           {w}" for w in self.warnings]
        return "\n".join(lines)

    # ------------------------------------------------------------------ plots
    def plot(self, path: str | Path | None = None):
        """Fairlead tension against time (kN) above the tension envelope (least and largest
        over time) along the line; saved to ``path`` when given. Returns the Figure."""
        from .plotting import plot_trajectory
        return plot_trajectory(self, path, s_mid=self.s)


def slack_warnings(time: np.ndarray, s: np.ndarray, axial: np.ndarray,
                   axial_static: np.ndarray | None = None) -> tuple[bool, tuple]:
    """Slack check shared by every dynamic result: ``(slack, warnings)``.

    Slack is a total axial force (or strain: only its sign matters) at or below zero on a
    segment that is in tension at rest: ``axial`` (n_t, n_seg) static plus dynamic,
    ``axial_static`` (n_seg,). NaN counts as slack, never passed silently. A segment already
    in compression at rest (a bending-stiff line) is not slack; it gets a warning of its own.
    ``s`` (n_seg,) m and ``time`` (n_t,) s place the first slack sample in the message.
    """
    axial = np.asarray(axial, dtype=float)
    taut = np.ones(axial.shape[1], dtype=bool) if axial_static is None else np.asarray(axial_static) > 0
    warns = []
    if not np.all(taut):
        warns.append(f"{int(np.sum(~taut))} segment(s) are in compression at rest (from s = "
                     f"{s[np.argmin(taut)]:.6g} m): a bending-stiff line; they are not checked for slack")
    bad = ~(axial > 0.0) & taut
    if not np.any(bad):
        return False, tuple(warns)
    rows = np.flatnonzero(np.any(bad, axis=1))
    i = rows[0]
    j = int(np.flatnonzero(bad[i])[0])
    warns.insert(0, f"slack: the total tension is <= 0 at t = {time[i]:.6g} s, s = {s[j]:.6g} m "
                    f"(segment {j}; {len(rows)} of {len(time)} samples slack, from t = {time[i]:.6g} "
                    f"to {time[rows[-1]]:.6g} s): the dynamics linearised about the taut static "
                    "state is invalid there")
    return True, tuple(warns)