"""The sea's waves (``[environment.waves]``): linear (Airy) waves, regular or irregular,
as a set of components.

A sea is a sum of components, each a x cos(k (x cos beta + y sin beta) - omega t + phase) of
the elevation (m), with k from the dispersion relation in the scene's depth
(:func:`~symcable.analytic.waves.wave_number`). Its kinematics at the nodes are
:mod:`symcable.models.common.waves`'s; the table's reader is :mod:`.wave_table`.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..analytic.waves import (default_band, jonswap, spectrum_components, wave_number)

__all__ = ["WAVE_KINDS", "STRETCHING", "Waves", "WaveComponents"]

#: ``kind`` of a sea
WAVE_KINDS = ("regular", "jonswap", "pierson-moskowitz", "components")
#: ``stretching``: the kinematics above the mean water level
STRETCHING = ("vertical", "wheeler")


@dataclass(frozen=True)
class WaveComponents:
    """A sea as components, arrays of one length n (the component count).

    Attributes
    ----------
    amplitude : numpy.ndarray
        m (half the component's height).
    omega : numpy.ndarray
        Angular frequency, rad/s.
    k : numpy.ndarray
        Wave number, rad/m (from the dispersion relation in the scene's depth).
    phase : numpy.ndarray
        rad.
    direction : numpy.ndarray
        The direction each component travels toward, rad counterclockwise from +x.
    """

    amplitude: np.ndarray
    omega: np.ndarray
    k: np.ndarray
    phase: np.ndarray
    direction: np.ndarray

    @property
    def n(self) -> int:
        return int(self.amplitude.size)


@dataclass(frozen=True)
class Waves:
    """Linear waves (``[environment.waves]``).

    Attributes
    ----------
    kind : str
        ``"regular"`` (one component of ``height`` and ``period``), ``"jonswap"`` or
        ``"pierson-moskowitz"`` (an irregular sea of ``hs``, ``tp`` and, for JONSWAP,
        ``gamma``, discretised into ``components`` by ``seed``), or ``"components"``
        (given ``amplitudes``, ``omegas``, ``phases_deg`` and optional ``directions_deg``).
    height, period : float or None
        Regular waves: the height H (m, crest to trough; the amplitude is H / 2) and period
        (s).
    phase_deg : float
        Regular waves: the phase, deg (0: a crest at x = y = 0 at t = 0).
    hs, tp, gamma : float or None
        Irregular seas: significant wave height (m), peak period (s) and JONSWAP peak
        enhancement (1 to 7, default 3.3; Pierson-Moskowitz is 1).
    components : int
        Irregular seas: the component count (default 200), over ``band``.
    band : tuple of float or None
        Irregular seas: the angular frequencies (rad/s) discretised, [low, high]; None:
        0.5 to 4 times the peak's (:func:`~symcable.analytic.waves.default_band`).
    seed : int
        Irregular seas: the random frequencies within the bins and the phases
        (:func:`~symcable.analytic.waves.spectrum_components`).
    amplitudes, omegas, phases_deg, directions_deg : tuple of float
        ``kind = "components"``: per component, m, rad/s, deg, deg (directions default
        ``direction_deg``).
    direction_deg : float
        The direction the waves travel toward, deg counterclockwise from +x (default 0).
    stretching : str
        The kinematics above the mean water level z = 0 (linear theory's own domain ends
        there): ``"vertical"`` (default: those at z = 0, up to any height) or ``"wheeler"``
        (the water column from the seabed to the instantaneous surface mapped onto the one
        to z = 0: the kinematics at h (z - eta) / (h + eta), or z - eta in deep water).
    ramp : float or None
        s: the waves ramp in over this time from t = 0, (1 - cos(pi t / ramp)) / 2, so a run
        from the static state starts without a jump (periodic solves take them at full
        amplitude throughout); None: the regular period or the peak period.
    """

    kind: str = "regular"
    height: float | None = None
    period: float | None = None
    phase_deg: float = 0.0
    hs: float | None = None
    tp: float | None = None
    gamma: float = 3.3
    components: int = 200
    band: tuple[float, float] | None = None
    seed: int = 0
    amplitudes: tuple[float, ...] = ()
    omegas: tuple[float, ...] = ()
    phases_deg: tuple[float, ...] = ()
    directions_deg: tuple[float, ...] = ()
    direction_deg: float = 0.0
    stretching: str = "vertical"
    ramp: float | None = None

    @property
    def count(self) -> int:
        """The component count."""
        if self.kind == "regular":
            return 1
        if self.kind == "components":
            return len(self.amplitudes)
        return self.components

    @property
    def ramp_time(self) -> float:
        """The ramp's duration, s (``ramp``, or the regular or peak period)."""
        if self.ramp is not None:
            return self.ramp
        return float(self.period if self.kind == "regular" else
                     self.tp if self.tp is not None else 2.0 * math.pi / max(self.omegas))

    def spectrum(self, omega) -> np.ndarray:
        """The one-sided spectrum S(omega), m^2 s/rad, of an irregular sea (JONSWAP or
        Pierson-Moskowitz); ``ValueError`` for the other kinds."""
        if self.kind not in ("jonswap", "pierson-moskowitz"):
            raise ValueError(f"waves of kind {self.kind!r} have no spectrum")
        return jonswap(omega, self.hs, self.tp,
                       self.gamma if self.kind == "jonswap" else 1.0)

    def components_in(self, depth: float | None, gravity: float) -> WaveComponents:
        """The sea's components in water of ``depth`` (m; None: deep) under ``gravity``
        (m/s^2)."""
        beta = math.radians(self.direction_deg)
        if self.kind == "regular":
            w = np.array([2.0 * math.pi / self.period])
            a = np.array([0.5 * self.height])
            ph = np.array([math.radians(self.phase_deg)])
            dirs = np.array([beta])
        elif self.kind == "components":
            a, w = np.array(self.amplitudes, float), np.array(self.omegas, float)
            ph = np.radians(np.array(self.phases_deg, float))
            dirs = (np.radians(np.array(self.directions_deg, float)) if self.directions_deg
                    else np.full(a.size, beta))
        else:
            band = self.band if self.band is not None else default_band(self.tp)
            w, a, ph = spectrum_components(self.spectrum, band, self.components, self.seed)
            dirs = np.full(w.size, beta)
        return WaveComponents(a, w, wave_number(w, depth, gravity), ph, dirs)

    def to_dict(self) -> dict:
        """The table in the file's layout (keys of this kind only)."""
        out: dict = {"kind": self.kind}
        if self.kind == "regular":
            out.update(height=self.height, period=self.period, phase_deg=self.phase_deg)
        elif self.kind == "components":
            out.update(amplitudes=list(self.amplitudes), omegas=list(self.omegas),
                       phases_deg=list(self.phases_deg))
            if self.directions_deg:
                out["directions_deg"] = list(self.directions_deg)
        else:
            out.update(hs=self.hs, tp=self.tp, components=self.components, seed=self.seed)
            if self.kind == "jonswap":
                out["gamma"] = self.gamma
            if self.band is not None:
                out["band"] = list(self.band)
        out.update(direction_deg=self.direction_deg, stretching=self.stretching)
        if self.ramp is not None:
            out["ramp"] = self.ramp
        return out
