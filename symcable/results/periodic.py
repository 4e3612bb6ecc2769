"""Periodic results: the steady state over one excitation period, and a sweep of them.

Both are frozen dataclasses of arrays and plain values with :class:`~symcable.results.static.Exportable`
save/load (``.npz`` or ``.json``). Harmonics are stored as two float arrays (amplitude and
phase) rather than complex numbers so that every export format keeps them.
"""
from __future__ import annotations

from abc import ABCMeta
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..errors import SymcableError
from .io import force_text, force_unit
from .static import Exportable, OneLine

__all__ = ["PeriodicSolution", "PeriodicSweep"]


@dataclass(frozen=True)
class PeriodicSolution(OneLine, Exportable, metaclass=ABCMeta):
    """Periodic steady state of a dynamic model over one excitation period: the type of
    every periodic result. This class is the linearised planar line's; a 3D scene's result
    (:class:`~symcable.results.periodic_line.PeriodicLine`, ``PeriodicSystem``) is one too
    (``isinstance`` holds), with the same ``period``, ``time``, ``fairlead_tension``,
    harmonics, ``status``, ``stats``, ``warnings``, ``summary()``, ``plot()``, ``save()``
    and ``load()``.

    ``n`` is the number of output times (``resolution``), ``n_y`` the number of states,
    ``n_seg`` the number of segments, ``H`` the number of harmonics reported.

    Attributes
    ----------
    scene_name : str
    method : str
        ``"collocation"``, ``"harmonic-balance"`` or ``"shooting"``.
    period : float
        Excitation period T, s.
    time : ndarray (n,)
        Output times ``k T / n``, k = 0 .. n-1, s (uniform over one period, end excluded:
        the value at T is the value at 0).
    states : ndarray (n, n_y)
        The state at those times, in the model's units (for the planar cable: node
        velocities m/s, dynamic strain -, dynamic angle rad): the trigonometric
        interpolant of the generic solver's uniform samples of its own representation (the
        collocation polynomials, the Fourier series of harmonic balance, the shooting's
        states at its time steps; 4 samples per collocation point, harmonic-balance time
        sample or step).
    fairlead_tension : ndarray (n,)
        Fairlead tension (static plus dynamic), N.
    fairlead_force : ndarray (n, 2)
        Force the line exerts on its fairlead, (Fx, Fz), N (empty (n, 0) if the model has
        no such output).
    tension_min, tension_max : ndarray (n_seg + 1,)
        Envelope of the tension on the nodes over the period (minimum and maximum over the
        output times), N, ends included: at end B it is the fairlead tension's, at end A the
        anchor tension's, inside the mean of the two adjacent segments' (as the statics'
        ``tension``). Empty if the model has no ``tension`` output.
    fairlead_tension_harmonics_amplitude : ndarray (H+1,)
        Amplitudes A_h of ``T_f(t) = A_0 + sum_h A_h cos(h w t + phi_h)``, N; A_0 is the mean.
    fairlead_tension_harmonics_phase : ndarray (H+1,)
        Phases phi_h, rad (phi_0 = 0).
    status : str
        ``"converged"``; ``"slack"`` (converged, but a tension reached zero somewhere over the
        period, so the linearised model is outside its range: see ``warnings``);
        ``"invalid"`` (converged, but the total axial strain left the line type's
        ``max_strain`` somewhere, or a value is not finite: the linearised dynamics do not
        hold and the numbers are not an answer; see ``warnings``); ``"failed"`` (only on a
        ConvergenceError's partial result).
    stats : dict
        ``solver`` (``"ipopt"``/``"newton"``; ``"anderson"`` for shooting, with
        ``" + newton (exact monodromy)"`` when Newton took over; shooting's ``iterations``
        are the periods marched, with ``steps``, ``rho_inf``, ``periods``,
        ``newton_iterations``), ``iterations``, ``return_status``, ``wall_time`` (s, whole
        solve), ``solve_time`` (s, the generic solver's, its start included),
        ``unknowns``, ``residual_norm`` (max-norm of the solved system's scaled residual),
        ``tolerance``, ``error_estimate`` and ``defect`` (the generic solvers' independent
        check: the scaled equation residuals between the solver's points), the
        discretisation (``intervals``, ``degree``, ``scheme`` or ``harmonics``,
        ``samples``), ``guess`` (``start``: how the start was made) and ``compiled``.
    warnings : tuple of str
    unknowns : ndarray or None
        Shooting: the integrator's state at t = 0, ``(y, y')`` with ``y = (q, v)`` of the
        dynamics Mechanism (its order, not ``states``'), from which a solve of the same
        ``steps`` restarts exactly; None for the other methods (a restart re-samples
        ``states``).
    params : ndarray (n_p,) or None
        The model parameters solved for (``omega`` among them), to evaluate the model's
        functions on this solution. ``param(name)`` gives one named block; in JSON
        (``to_dict``) they are written as named blocks, ``{"omega": 0.628, "phi_s": [...],
        ...}``.
    param_names : tuple of str
        The name of each entry of ``params``: ``"block[i]"``, or ``"block"`` for a block of one
        (e.g. ``"phi_s[3]"``, ``"omega"``; the blocks are the model's ``p_names``).
    s : ndarray (n_seg + 1,) or None
        Unstretched arc length of the nodes from end A, m: where ``tension_min`` and
        ``tension_max`` are given.
    axial_force : ndarray (n, n_seg) or None
        Signed total axial force of each segment at the output times, N: positive in
        tension, negative in compression (the envelopes, magnitudes, never show the sign).
    """

    scene_name: str
    method: str
    period: float
    time: np.ndarray
    states: np.ndarray
    fairlead_tension: np.ndarray
    fairlead_force: np.ndarray
    tension_min: np.ndarray
    tension_max: np.ndarray
    fairlead_tension_harmonics_amplitude: np.ndarray
    fairlead_tension_harmonics_phase: np.ndarray
    status: str
    stats: dict = field(default_factory=dict)
    warnings: tuple = ()
    unknowns: np.ndarray | None = None
    params: np.ndarray | None = None
    param_names: tuple = ()
    s: np.ndarray | None = None
    axial_force: np.ndarray | None = None

    __repr__ = Exportable.short_repr

    def param(self, name: str) -> np.ndarray:
        """The block ``name`` of ``params`` (e.g. ``"omega"``, ``"phi_s"``), as an array."""
        idx = [i for i, n in enumerate(self.param_names) if n == name or n.startswith(name + "[")]
        if self.params is None or not idx:
            blocks = sorted({n.split("[")[0] for n in self.param_names})
            raise SymcableError(f"param name = {name!r}: not a parameter block of this solution "
                                f"(blocks: {', '.join(blocks) or 'none recorded'})")
        return np.asarray(self.params, dtype=float)[idx]

    def to_dict(self) -> dict:
        """Every field as plain JSON-able Python; ``params`` as named blocks (a block of one
        as a number, others as lists), ``param_names`` folded into them."""
        d = super().to_dict()
        if self.params is not None and len(self.param_names) == np.size(self.params):
            blocks: dict = {}
            for name, v in zip(self.param_names, np.asarray(self.params, dtype=float).tolist()):
                base = name.split("[")[0]
                if "[" in name:
                    blocks.setdefault(base, []).append(v)
                else:
                    blocks[base] = v
            d["params"] = blocks
            d.pop("param_names", None)
        return d

    @classmethod
    def _decode(cls, d: dict) -> dict:
        params = d.get("params")
        if isinstance(params, dict):
            names, values = [], []
            for base, v in params.items():
                if isinstance(v, list):
                    names += [f"{base}[{i}]" for i in range(len(v))]
                    values += v
                else:
                    names.append(base)
                    values.append(v)
            d = {**d, "params": values, "param_names": names}
        return d

    @property
    def fairlead_tension_amplitude(self) -> float:
        """First-harmonic amplitude of the fairlead tension, N."""
        return float(self.fairlead_tension_harmonics_amplitude[1])

    def plot(self, path: str | Path | None = None):
        """The fairlead tension over the period above the tension envelope along the line
        (:func:`symcable.plotting.profiles.plot_periodic`); saved to ``path`` when given;
        returns the Figure."""
        from ..plotting.profiles import plot_periodic
        return plot_periodic(self, path)

    def summary(self) -> str:
        """A few lines a person reads: fairlead tension range and first harmonic, tension
        envelope (N, kN or MN by their size), solver stats."""
        st = self.stats
        tf = self.fairlead_tension
        amp, ph = self.fairlead_tension_harmonics_amplitude, self.fairlead_tension_harmonics_phase
        if self.method == "collocation":
            disc = (f"{st.get('intervals', '?')} intervals of degree {st.get('degree', '?')} "
                    f"({st.get('scheme', '?')})")
        elif self.method == "shooting":
            disc = (f"{st.get('steps', '?')} generalized-alpha steps per period, "
                    f"{st.get('periods', '?')} periods iterated")
        else:
            disc = f"{st.get('harmonics', '?')} harmonics, {st.get('samples', '?')} samples"
        lines = [
            f"scene             {self.scene_name}",
            f"periodic          {self.method}, {disc}, period {self.period:.4g} s",
            f"status            {self.status}",
            f"fairlead tension  mean {force_text(np.mean(tf), spec='.4f')}, min "
            f"{force_text(np.min(tf), spec='.4f')}, max {force_text(np.max(tf), spec='.4f')}",
            f"first harmonic    {force_text(amp[1], spec='.4f')} at phase "
            f"{np.degrees(ph[1]):.2f} deg"
            if amp.size > 1 else "first harmonic    -",
        ]
        if self.tension_max.size:
            lines.append(f"tension envelope  min {force_text(np.min(self.tension_min), spec='.4f')}"
                         f", max {force_text(np.max(self.tension_max), spec='.4f')} along the line "
                         "(nodes, ends included)")
        if self.axial_force is not None and np.size(self.axial_force):
            lines.append(f"axial force       min {force_text(np.min(self.axial_force), spec='.4f')}"
                         f", max {force_text(np.max(self.axial_force), spec='.4f')} along the line "
                         "(signed: < 0 is compression)")
        lines.append(
            f"solver            {st.get('solver', '?')}: {st.get('iterations', '?')} iterations "
            f"({st.get('return_status', '?')}), residual {st.get('residual_norm', float('nan')):.3g}, "
            f"{st.get('unknowns', '?')} unknowns, {1e3 * st.get('wall_time', float('nan')):.0f} ms")
        lines += [f"warning           {w}" for w in self.warnings]
        return "\n".join(lines)


@dataclass(frozen=True)
class PeriodicSweep(Exportable):
    """Fairlead tension response over a range of excitation periods (a tension RAO), each
    periodic solve continued from its neighbour's solution.

    ``n_p`` is the number of periods, ``n`` the number of output times per period.

    Attributes
    ----------
    scene_name : str
    method : str
    periods : ndarray (n_p,)
        Excitation periods, s, in the order solved.
    fairlead_tension_amplitude : ndarray (n_p,)
        First-harmonic amplitude of the fairlead tension, N (NaN where the solve failed).
    fairlead_tension_phase : ndarray (n_p,)
        Its phase, rad (``T_f = A_0 + A_1 cos(w t + phase) + ...``).
    fairlead_tension_mean, fairlead_tension_max, fairlead_tension_min : ndarray (n_p,)
        Mean, largest and smallest fairlead tension over each period, N.
    normalised_time : ndarray (n,)
        Output times as fractions t/T of each period, -.
    fairlead_tension : ndarray (n_p, n)
        Fairlead tension over each period at ``normalised_time``, N.
    statuses : tuple of str
        Status of each periodic solve (see :class:`PeriodicSolution`).
    status : str
        ``"converged"`` when every solve converged (``"invalid"`` when one left the line's
        strain range, else ``"slack"`` when one went slack), ``"partial"`` when some failed.
    stats : dict
        ``wall_time`` (s, whole sweep), and per period lists ``iterations``, ``solve_time``
        (s) and ``start`` (``"neighbour"``: from the previous period's solution, or ``"own
        start"``: the method's own, a short time run from rest). One set of CasADi functions,
        with the period as a parameter, serves the sweep.
    warnings : tuple of str
    """

    scene_name: str
    method: str
    periods: np.ndarray
    fairlead_tension_amplitude: np.ndarray
    fairlead_tension_phase: np.ndarray
    fairlead_tension_mean: np.ndarray
    fairlead_tension_max: np.ndarray
    fairlead_tension_min: np.ndarray
    normalised_time: np.ndarray
    fairlead_tension: np.ndarray
    statuses: tuple
    status: str
    stats: dict = field(default_factory=dict)
    warnings: tuple = ()

    def summary(self) -> str:
        """One line per period: first-harmonic amplitude, range of the fairlead tension (in
        one unit for the table, N, kN or MN by the tensions' size)."""
        k_n, u = force_unit(np.r_[self.fairlead_tension_amplitude, self.fairlead_tension_min,
                                  self.fairlead_tension_max])
        lines = [f"scene             {self.scene_name}",
                 f"sweep             {self.method}, {len(self.periods)} periods, status {self.status}, "
                 f"{self.stats.get('wall_time', float('nan')):.2f} s",
                 f"  period s   {'amplitude ' + u:13s}  {'min ' + u:11s}  {'max ' + u:11s}  "
                 "iterations  status"]
        its = self.stats.get("iterations", [None] * len(self.periods))
        for k, T in enumerate(self.periods):
            lines.append(f"  {T:8.3f}   {self.fairlead_tension_amplitude[k] / k_n:10.4f}   "
                         f"{self.fairlead_tension_min[k] / k_n:10.4f}   "
                         f"{self.fairlead_tension_max[k] / k_n:10.4f}   {str(its[k]):>10}  "
                         f"{self.statuses[k]}")
        lines += [f"warning           {w}" for w in self.warnings]
        return "\n".join(lines)
