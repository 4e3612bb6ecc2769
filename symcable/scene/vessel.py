"""A vessel: a body moved in six degrees of freedom (``[bodies.NAME]`` with ``kind =
"vessel"`` and a ``motion``), and the path of a point of it.

The body's pose at time t is its reference point ``position + d(t)`` and its orientation
``orientation + a(t)`` ([roll, pitch, yaw] added, degrees; the rotation
:func:`~symcable.scene.bodies.rotation_rpy`), d (m) and a (deg) the motion's six degrees of
freedom. A line's end at the body point ``offset`` (body axes) is held at
``position + d(t) + R(orientation + a(t)) offset``: it follows the body's rotation. The
motion is

- ``"harmonic"``: DOF_j(t) = amplitude_j cos(2 pi t / period + phase_j), ramped in over its
  first period as an end's harmonic motion;
- ``"table"``: rows t x y z roll pitch yaw (s, m, deg) from a file, linear between rows and
  held beyond them;
- ``"rao"``: the response to the scene's waves (``[environment.waves]``): for each wave
  component of amplitude a and frequency omega, DOF_j = |H_j(omega)| a cos(theta_ref + phi -
  omega t - psi_j(omega)) with theta_ref + phi the component's phase at the reference point
  (its mean position), |H_j| (m/m, deg/m) and the lag psi_j (deg) of the table interpolated
  linearly in omega in their real and imaginary parts (held beyond the table's ends),
  ramped in with the waves.

The reader is :func:`read_body_motion`; :func:`rigid_path` gives a line end's path.
"""
from __future__ import annotations

import hashlib
import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from .waves import WaveComponents

__all__ = ["BODY_MOTION_KINDS", "BodyMotion", "RigidPath", "rigid_path"]

#: ``kind`` of a vessel's motion
BODY_MOTION_KINDS = ("harmonic", "table", "rao")
DOF = ("x", "y", "z", "roll", "pitch", "yaw")


@dataclass(frozen=True)
class BodyMotion:
    """A vessel's motion in six degrees of freedom (module docstring).

    Attributes
    ----------
    kind : str
        ``"harmonic"``, ``"table"`` or ``"rao"``.
    period : float
        Harmonic: s; a table: its time span; RAOs: 0.
    amplitude, phase_deg : tuple of float
        Harmonic: six amplitudes (m, m, m, deg, deg, deg) and phases (deg).
    file : str or None
        A table's file, resolved.
    samples : tuple of tuple or None
        A table's rows (t, x, y, z, roll, pitch, yaw), s, m, deg.
    omegas : tuple of float
        RAOs: the table's angular frequencies, rad/s, increasing.
    rao_amplitude, rao_phase_deg : tuple of tuple
        RAOs: per frequency six amplitudes (m/m, m/m, m/m, deg/m, deg/m, deg/m) and lags
        behind the wave elevation at the reference point (deg).
    """

    kind: str
    period: float = 0.0
    amplitude: tuple[float, ...] = (0.0,) * 6
    phase_deg: tuple[float, ...] = (0.0,) * 6
    file: str | None = None
    samples: tuple | None = None
    omegas: tuple[float, ...] = ()
    rao_amplitude: tuple = ()
    rao_phase_deg: tuple = ()

    def to_dict(self) -> dict:
        """The motion's table in the file's layout."""
        if self.kind == "table":
            return {"kind": "table", "file": self.file}
        if self.kind == "rao":
            return {"kind": "rao", "omegas": list(self.omegas),
                    "amplitude": [list(r) for r in self.rao_amplitude],
                    "phase_deg": [list(r) for r in self.rao_phase_deg]}
        return {"kind": "harmonic", "period": self.period, "amplitude": list(self.amplitude),
                "phase_deg": list(self.phase_deg)}

    def response(self, sea: WaveComponents, reference) -> tuple[np.ndarray, np.ndarray]:
        """RAOs: each wave component's motion amplitude (n, 6) (m and deg) and phase (n, 6),
        rad, such that DOF_j(t) = sum_i amplitude_ij cos(phase_ij - omega_i t), for the sea's
        components ``sea`` at the body's reference point ``reference`` (x, y), m."""
        w = np.asarray(self.omegas, float)
        H = np.asarray(self.rao_amplitude, float) * np.exp(
            -1j * np.radians(np.asarray(self.rao_phase_deg, float)))
        Hc = np.stack([np.interp(sea.omega, w, H[:, j].real)
                       + 1j * np.interp(sea.omega, w, H[:, j].imag) for j in range(6)], axis=1)
        theta = (sea.k * (reference[0] * np.cos(sea.direction)
                          + reference[1] * np.sin(sea.direction)) + sea.phase)
        z = Hc * (sea.amplitude * np.exp(1j * theta))[:, None]
        return np.abs(z), np.angle(z)


@dataclass(frozen=True)
class RigidPath:
    """The path of a point of a vessel: its body's mean pose, the point (``offset``, m, body
    axes), and the six degrees of freedom as components (``omega`` (n,), rad/s; ``amplitude``
    and ``phase`` (n, 6): m or rad, and rad; DOF_j = sum_i amplitude_ij cos(phase_ij -
    omega_i t)) ramped in over ``ramp`` s (0: not ramped), or a table's ``samples`` (rows t
    and six columns, s, m, rad)."""

    position: tuple[float, ...]
    orientation_deg: tuple[float, ...]
    offset: tuple[float, ...]
    omega: tuple[float, ...] = ()
    amplitude: tuple = ()
    phase: tuple = ()
    ramp: float = 0.0
    samples: tuple | None = None

    def key(self) -> str:
        """A digest of the path's numbers (they are constants of a line's expressions)."""
        return hashlib.sha256(repr(self).encode()).hexdigest()[:16]


def rigid_path(body: Any, offset, sea: WaveComponents | None, ramp: float) -> RigidPath:
    """The path of the point ``offset`` (m, body axes) of the vessel ``body`` (its motion a
    :class:`BodyMotion`); ``sea`` the scene's wave components (RAOs need them: None, a calm
    sea, leaves the vessel still) and ``ramp`` (s) the waves' ramp time."""
    m: BodyMotion = body.motion
    deg = np.array([1.0, 1.0, 1.0, math.pi / 180.0, math.pi / 180.0, math.pi / 180.0])
    common = dict(position=tuple(body.position), orientation_deg=tuple(body.orientation_deg),
                  offset=tuple(float(v) for v in offset))
    if m.kind == "table":
        rows = np.asarray(m.samples, float)
        rows = np.column_stack([rows[:, :1], rows[:, 1:7] * deg])
        return RigidPath(samples=tuple(map(tuple, rows)), **common)
    if m.kind == "harmonic":
        w = np.array([2.0 * math.pi / m.period])
        amp = (np.asarray(m.amplitude, float) * deg)[None, :]
        ph = -np.radians(np.asarray(m.phase_deg, float))[None, :]
        r = m.period
    elif sea is None:  # RAOs in a calm sea (statics): the vessel at its mean pose
        return RigidPath(**common)
    else:
        amp, ph = m.response(sea, body.position)
        amp, w, r = amp * deg[None, :], sea.omega, ramp
    return RigidPath(omega=tuple(map(float, w)), amplitude=tuple(map(tuple, amp)),
                     phase=tuple(map(tuple, ph)), ramp=float(r), **common)
