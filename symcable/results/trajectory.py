"""Time-domain results: :class:`Trajectory`, what :func:`symcable.simulate` returns."""
from __future__ import annotations

from abc import ABCMeta
from dataclasses import dataclass, field
from pathlib import Path
from typing import Mapping

import numpy as np

from .io import force_text
from .static import Exportable, OneLine

__all__ = ["Trajectory", "end_force_warnings", "node_tension", "range_warnings", "slack_warnings",
           "strain_warnings"]


@dataclass(frozen=True)
class Trajectory(OneLine, Exportable, metaclass=ABCMeta):
    """A time history of a line, sampled at the saved steps: the type of every time result.
    This class is the linearised planar line's; a 3D line's and a scene's
    (:class:`~symcable.results.line3d.LineTrajectory`, ``SystemTrajectory``) are Trajectories
    too (``isinstance`` holds), with the same ``time``, ``fairlead_tension``,
    ``anchor_tension``, ``method``, ``dt``, ``status``, ``stats``, ``warnings``, ``lines``,
    ``summary()``, ``plot()``, ``save()`` and ``load()``.

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
        and dynamic angle in rad, interleaved; see :mod:`symcable.models.planar.dynamics`).
    fairlead_tension, anchor_tension : ndarray (n_t,)
        Magnitude of the force the line exerts on end B (fairlead) and end A (anchor), N.
    fairlead_force, anchor_force : ndarray (n_t, 2)
        Those forces, (F_x, F_z), N.
    tension : ndarray (n_t, n_seg)
        Magnitude of the total internal force of each segment (static plus dynamic), N:
        never negative, so it cannot show compression (see ``axial_force``).
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
        there; see ``warnings``), ``"invalid"`` (done, but the total axial strain left the
        line type's ``max_strain`` somewhere, or a result is not finite: the linearised
        dynamics do not hold there and the numbers are not an answer; see ``warnings``) or
        ``"failed"`` (only on a ConvergenceError's partial result, which ends at the last
        good step).
    stats : dict
        ``steps``, ``dt`` (s), ``dt_requested`` (s), ``dt_stable`` (s, RK4's estimated
        stability limit), ``newton_iterations`` (total), ``newton_iterations_max`` (per
        step), ``newton_tol``, ``wall_time`` (s), ``us_per_step``, ``samples``,
        ``rho_inf``, ``alpha_m``, ``alpha_f``, ``gamma`` (generalized-α), and generalized-α's
        estimate of its own time-stepping error: ``error_estimate``, the largest error of
        the response over the run relative to its range (of the states; the fairlead tension's
        error relative to its range is about the same), ``error_estimate_scaled`` (relative to the
        state's scales), ``motion_range``, ``error_memory`` (s, period / 2 pi) and
        ``dt_accurate`` (s, the dt that should bring it to 1 %); see
        :func:`symcable.solvers.integrate.integrate`.
    warnings : tuple of str
        Among them, when ``error_estimate`` exceeds 1 %: how far off the run likely is and
        which dt should meet 1 % (the status stays "converged").
    axial_force : ndarray (n_t, n_seg)
        Signed total axial force of each segment (static plus dynamic), N: positive in
        tension, negative in compression (the sign ``tension`` drops). None in files saved
        before it existed.
    positions : ndarray (n_t, n_seg + 1, 2)
        Node positions (x, z) at the samples, m, chained from the total angle and strain
        (see :mod:`symcable.models.planar.dynamics`). None in files saved before it existed.
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
    axial_force: np.ndarray | None = None
    positions: np.ndarray | None = None

    __repr__ = Exportable.short_repr

    # ------------------------------------------------------------------ building
    @classmethod
    def from_outputs(cls, model, *, scene_name: str, time: np.ndarray, states: np.ndarray,
                     outputs: Mapping[str, np.ndarray], method: str, dt: float, status: str,
                     stats: dict, warnings: tuple = ()) -> "Trajectory":
        """Assemble a trajectory from the model's named outputs at the samples (each
        ``(n_t, ...)``), checking the linearisation's range: a strain beyond the line's
        ``max_strain`` gives status ``"invalid"``, else a slack line gives ``"slack"``, each
        with a warning (a failed run stays ``"failed"``)."""
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
            total = np.asarray(static.strain) + strain
            slack, extra = slack_warnings(time, s, total, static.strain)
            bad, beyond = range_warnings(model, time, s, total, outputs)
            extra = beyond + extra
        else:
            slack, extra = slack_warnings(time, s, tension)
            bad = False
        warns = tuple(warnings) + extra
        if status == "converged" and bad:
            status = "invalid"
        elif status == "converged" and slack:
            status = "slack"
        positions = outputs.get("positions")
        if positions is not None:
            positions = np.asarray(positions, dtype=float).reshape(n_t, n_seg + 1, 2)
        return cls(scene_name=scene_name, time=np.asarray(time, dtype=float), s=s,
                   states=np.asarray(states, dtype=float).reshape(n_t, -1),
                   fairlead_tension=get("fairlead_tension", (n_t,)),
                   anchor_tension=get("anchor_tension", (n_t,)),
                   fairlead_force=get("fairlead_force", (n_t, 2)),
                   anchor_force=get("anchor_force", (n_t, 2)),
                   tension=tension, strain=strain, angle=get("angle", (n_t, n_seg)),
                   method=str(method), dt=float(dt), status=status, stats=dict(stats),
                   warnings=warns, axial_force=get("axial_force", (n_t, n_seg)),
                   positions=positions)

    # ------------------------------------------------------------------ derived
    @property
    def n_t(self) -> int:
        return int(len(self.time))

    def tension_envelope(self) -> tuple[np.ndarray, np.ndarray]:
        """Least and largest segment tension over the saved samples, each (n_seg,), N."""
        return np.min(self.tension, axis=0), np.max(self.tension, axis=0)

    # ------------------------------------------------------------------ summary
    def summary(self) -> str:
        """A few lines a person reads: tensions (N, kN or MN by their size), motion ranges,
        solver stats."""
        st = self.stats
        ft = self.fairlead_tension
        at = self.anchor_tension
        lo, hi = self.tension_envelope() if self.n_t else (np.nan, np.nan)

        def rng(a, scale=1.0):
            a = np.asarray(a) / scale
            return f"{np.min(a):.4f} .. {np.max(a):.4f}" if a.size else "-"

        def force(a):  # a force's range in the unit its size takes
            a = np.asarray(a, float)
            return force_text([np.min(a), np.max(a)], spec=".4f") if a.size else "- N"

        lines = [
            f"scene             {self.scene_name}",
            f"status            {self.status}: {self.method}, dt {self.dt:.6g} s, "
            f"{st.get('steps', '?')} steps to t = {self.time[-1] if self.n_t else 0.0:.6g} s, "
            f"{self.n_t} samples",
            f"fairlead tension  {force(ft)} (mean "
            f"{force_text(np.mean(ft) if ft.size else np.nan, spec='.4f')})",
            f"anchor tension    {force(at)}",
            f"segment tension   {force([np.min(lo), np.max(hi)] if np.size(lo) else [])} "
            "over the line",
            f"dynamic strain    {rng(self.strain)} -",
            f"axial force       {force(self.axial_force)} over the line "
            "(signed: < 0 is compression)" if self.axial_force is not None else
            "axial force       -",
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
        from ..plotting.profiles import plot_trajectory
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

def strain_warnings(time: np.ndarray, s: np.ndarray, strain: np.ndarray,
                    max_strain: np.ndarray) -> tuple[bool, tuple]:
    """Range check shared by every dynamic result: ``(invalid, warnings)``.

    The dynamics are linearised about the static state, which holds only while each
    segment's total axial strain (static plus dynamic), ``strain`` (n_t, n_seg), stays
    within what its line type takes, ``max_strain`` (n_seg,) (the scene's ``max_strain``, the
    same limit that decides whether a fairlead is out of reach). Beyond it, or where a value
    is not finite, the numbers are not an answer (an excitation far too fast or too large for
    the line). ``time`` (n_t,) s and ``s`` (n_seg,) m place the worst sample in the message.
    """
    strain = np.asarray(strain, dtype=float)
    limit = np.broadcast_to(np.asarray(max_strain, dtype=float), strain.shape[1:])
    with np.errstate(invalid="ignore"):
        bad = ~(np.abs(strain) <= limit)
    if not np.any(bad):
        return False, ()
    rows = np.flatnonzero(np.any(bad, axis=1))
    mag = np.where(np.isfinite(strain), np.abs(strain), np.inf)
    i, j = np.unravel_index(int(np.argmax(np.where(bad, mag / limit, -1.0))), strain.shape)
    value = f"{strain[i, j]:.4g}" if np.isfinite(strain[i, j]) else "not finite"
    return True, (f"invalid: the total axial strain reaches {value} at t = {time[i]:.6g} s, "
                  f"s = {s[j]:.6g} m (segment {j}; {len(rows)} of {len(time)} samples beyond), "
                  f"outside max_strain = {limit[j]:.3g} of its line type: the dynamics are "
                  "linearised about the static state and do not hold there, so these numbers "
                  "are not an answer (check the excitation's period and amplitude)",)


def end_force_warnings(time: np.ndarray, ends: dict) -> tuple[bool, tuple]:
    """The same range check on the end forces: ``ends`` maps a name (``"fairlead"``) to
    ``(tension (n_t,) N, EA of the end segment N, its max_strain)``. The force on an end is
    carried by the segment beside it, so ``|F| / EA`` beyond ``max_strain`` is a strain the
    line cannot take even where the discrete strains do not show it (a fast prescribed
    motion loads an end through the inertia of its lumped mass). Returns ``(invalid,
    warnings)``."""
    warns = []
    for name, (tension, EA, limit) in ends.items():
        t = np.asarray(tension, dtype=float)
        with np.errstate(invalid="ignore", divide="ignore"):
            eq = np.abs(t) / EA
            bad = ~(eq <= limit)
        if not np.any(bad):
            continue
        i = int(np.argmax(np.where(bad, np.where(np.isfinite(eq), eq, np.inf), -1.0)))
        value = f"{t[i]:.4g} N, a strain |T|/EA = {eq[i]:.4g}" if np.isfinite(eq[i]) else "not finite"
        warns.append(f"invalid: the {name} tension reaches {value} at t = {time[i]:.6g} s "
                     f"({int(np.sum(bad))} of {len(t)} samples beyond), outside max_strain = "
                     f"{limit:.3g} of its end segment's line type: the dynamics are linearised "
                     "about the static state and do not hold there, so these numbers are not "
                     "an answer (check the excitation's period and amplitude)")
    return bool(warns), tuple(warns)


def range_warnings(model, time: np.ndarray, s: np.ndarray, strain: np.ndarray,
                   outputs: Mapping[str, np.ndarray]) -> tuple[bool, tuple]:
    """:func:`strain_warnings` on the total segment strain (n_t, n_seg) and
    :func:`end_force_warnings` on the ``fairlead_tension``/``anchor_tension`` outputs, with the
    limits the model gives (``info["max_strain"]`` per segment, ``info["segments"]["EA"]``);
    ``(False, ())`` for a model that gives none."""
    info = model.info if model is not None else {}
    limit = info.get("max_strain")
    if limit is None:
        return False, ()
    limit = np.asarray(limit, dtype=float)
    bad, warns = strain_warnings(time, s, strain, limit)
    EA = np.asarray(info.get("segments", {}).get("EA", []), dtype=float)
    if EA.size == limit.size:
        ends = {name: (np.ravel(outputs[key]), EA[k], limit[k])
                for name, key, k in (("fairlead", "fairlead_tension", -1), ("anchor", "anchor_tension", 0))
                if outputs.get(key) is not None}
        bad_end, more = end_force_warnings(time, ends)
        bad, warns = bad or bad_end, warns + more
    return bad, warns


def node_tension(tension: np.ndarray, anchor: np.ndarray | None,
                 fairlead: np.ndarray | None) -> np.ndarray:
    """Tension on the nodes (n_t, n_seg + 1), N, as the statics give it: at the ends the end
    forces' magnitudes (``anchor``, ``fairlead``, (n_t,)), inside the mean of the two adjacent
    segments' ``tension`` (n_t, n_seg). An end without its force takes its segment's."""
    tension = np.atleast_2d(np.asarray(tension, dtype=float))
    a = tension[:, 0] if anchor is None else np.asarray(anchor, dtype=float).ravel()
    b = tension[:, -1] if fairlead is None else np.asarray(fairlead, dtype=float).ravel()
    return np.column_stack([a, 0.5 * (tension[:, :-1] + tension[:, 1:]), b])
