"""The periodic steady state of a 3D scene: its samples over one period as a
:class:`~symcable.results.line3d.LineTrajectory` (one line) or
:class:`~symcable.results.line3d.SystemTrajectory` (several lines, points, bodies), with the
periodic solution's own fields: the period, the fairlead tension's harmonics and the
tension envelope. Both are :class:`~symcable.results.periodic.PeriodicSolution` s
(``isinstance`` holds): what ``sc.solve_periodic`` returns, whatever the formulation.
"""
from __future__ import annotations

import math
from dataclasses import fields

import numpy as np

from .line3d import LineTrajectory, SystemTrajectory
from .io import force_text
from .periodic import PeriodicSolution

__all__ = ["PeriodicLine", "PeriodicSystem", "REPORTED_HARMONICS", "as_periodic", "harmonics"]

#: harmonics of the fairlead tension reported (as the planar solution's)
REPORTED_HARMONICS = 10


def harmonics(time, values, period: float, count: int = REPORTED_HARMONICS) -> tuple:
    """(amplitudes (H+1,), phases (H+1,) rad) of ``values(t) = A_0 + sum_h A_h cos(h w t +
    phi_h)``, w = 2 pi / period, from samples at ``time`` uniform over one period (s); A_0
    is the mean, phi_0 = 0, H = min(count, (n - 1) // 2)."""
    t, x = np.asarray(time, float), np.asarray(values, float)
    n = x.size
    H = min(int(count), (n - 1) // 2)
    h = np.arange(H + 1)
    c = np.exp(-1j * 2.0 * math.pi / period * np.outer(h, t)) @ x / n
    amp = np.concatenate([[c[0].real], 2.0 * np.abs(c[1:])])
    return amp, np.concatenate([[0.0], np.angle(c[1:])])


class _Periodic:
    """The periodic fields of a time history over one period (``stats["period"]``)."""

    @property
    def period(self) -> float:
        """The excitation period T, s."""
        return float(self.stats.get("period", np.nan))

    def _harmonics(self) -> tuple:
        return harmonics(self.time, self.fairlead_tension, self.period)

    @property
    def fairlead_tension_harmonics_amplitude(self) -> np.ndarray:
        """Amplitudes A_h of the fairlead tension's harmonics (A_0 the mean), N."""
        return self._harmonics()[0]

    @property
    def fairlead_tension_harmonics_phase(self) -> np.ndarray:
        """Phases phi_h of the fairlead tension's harmonics, rad."""
        return self._harmonics()[1]

    @property
    def fairlead_tension_amplitude(self) -> float:
        """First-harmonic amplitude of the fairlead tension, N."""
        return float(self.fairlead_tension_harmonics_amplitude[1])

    def _periodic_line(self) -> str:
        amp, ph = self._harmonics()
        first = (f", first harmonic of the fairlead tension {force_text(amp[1])} at "
                 f"{math.degrees(ph[1]):.2f} deg" if amp.size > 1 else "")
        return f"periodic          period {self.period:.4g} s{first}"


class PeriodicLine(_Periodic, LineTrajectory):
    """A 3D line's periodic steady state: its samples over one period (every field of
    :class:`~symcable.results.line3d.LineTrajectory`), with the period (s), the fairlead
    tension's harmonics and the tension envelope on the nodes."""

    @property
    def tension_min(self) -> np.ndarray:
        """(n,) N: the least tension over the period on each node, ends included (the end
        tensions at the ends, the mean of the two adjacent segments' inside)."""
        return self._node_tension().min(axis=0)

    @property
    def tension_max(self) -> np.ndarray:
        """(n,) N: the largest tension over the period on each node (as ``tension_min``)."""
        return self._node_tension().max(axis=0)

    def _node_tension(self) -> np.ndarray:
        T = np.asarray(self.tension, float)
        inner = 0.5 * (T[:, :-1] + T[:, 1:])
        return np.column_stack([self.anchor_tension, inner, self.fairlead_tension])

    def summary(self) -> str:
        """The line's summary with the period and the fairlead tension's first harmonic."""
        lines = LineTrajectory.summary(self).splitlines()
        return "\n".join(lines[:2] + [self._periodic_line()] + lines[2:])


class PeriodicSystem(_Periodic, SystemTrajectory):
    """A scene of several lines, points and bodies in its periodic steady state: its
    samples over one period (every field of :class:`~symcable.results.line3d.
    SystemTrajectory`), with the period (s) and the harmonics of the first line's tension at
    its end B (``fairlead_tension``, N)."""

    def summary(self) -> str:
        """The scene's summary with the period and the first line's first harmonic."""
        lines = SystemTrajectory.summary(self).splitlines()
        return "\n".join(lines[:2] + [self._periodic_line()] + lines[2:])


PeriodicSolution.register(PeriodicLine)
PeriodicSolution.register(PeriodicSystem)


def as_periodic(result):
    """``result`` (a LineTrajectory or SystemTrajectory over one period, its ``stats``
    holding ``period``) as a :class:`PeriodicLine` or :class:`PeriodicSystem`."""
    kind = PeriodicSystem if isinstance(result, SystemTrajectory) else PeriodicLine
    return kind(**{f.name: getattr(result, f.name) for f in fields(result)})
