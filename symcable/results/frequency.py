"""The result of a frequency-domain solve (:func:`symcable.solve_frequency_domain`): each
line's axial-force response to the sea, per wave component and in statistics."""
from __future__ import annotations

from dataclasses import dataclass, field, fields
from pathlib import Path
from types import MappingProxyType
from typing import Mapping

import numpy as np

from .io import force_text, read_tree, write_tree

__all__ = ["FrequencyResponse", "LineSpectrum"]


@dataclass(frozen=True)
class LineSpectrum:
    """One line's response in the frequency domain.

    Attributes
    ----------
    s : numpy.ndarray
        (N+1,) the nodes' unstretched arc length from end A, m.
    mean : numpy.ndarray
        (N,) each segment's static axial force, N (the calm sea's).
    rao : numpy.ndarray
        (n, N) complex: each segment's axial force per metre of each wave component's
        amplitude, N/m (x(t) = Re(rao a e^(-i omega t)) with the component's phase at the
        origin).
    std : numpy.ndarray
        (N,) the axial force's standard deviation in the sea, N.
    tz : numpy.ndarray
        (N,) its mean zero up-crossing period, s.
    mpm : numpy.ndarray
        (N,) the most probable largest axial force over the duration (mean plus the Rayleigh
        most probable excursion), N.
    """

    s: np.ndarray
    mean: np.ndarray
    rao: np.ndarray
    std: np.ndarray
    tz: np.ndarray
    mpm: np.ndarray

    @property
    def end_b(self) -> dict:
        """End B's segment (the fairlead's, by convention): mean, std, mpm, N."""
        return {"mean": float(self.mean[-1]), "std": float(self.std[-1]),
                "mpm": float(self.mpm[-1])}

    @property
    def end_a(self) -> dict:
        """End A's segment (the anchor's): mean, std, mpm, N."""
        return {"mean": float(self.mean[0]), "std": float(self.std[0]),
                "mpm": float(self.mpm[0])}


@dataclass(frozen=True)
class FrequencyResponse:
    """The linear response of a scene to its sea about the static state.

    Attributes
    ----------
    scene_name : str
    omega : numpy.ndarray
        (n,) the sea's components' angular frequencies, rad/s.
    amplitude : numpy.ndarray
        (n,) their amplitudes, m.
    lines : mapping str -> LineSpectrum
        Per line (a one-line scene's is ``"line"``).
    duration : float
        s, the duration the most probable maxima are over.
    status : str
        ``"converged"`` (the drag's linearisation settled to its tolerance).
    stats : dict
        ``iterations``, ``change`` (the drag's last relative change), ``linearisation``
        (``"stochastic"`` or ``"harmonic"``), ``wall_time`` (s), ``components``.
    warnings : tuple of str
    """

    scene_name: str
    omega: np.ndarray
    amplitude: np.ndarray
    lines: Mapping[str, LineSpectrum]
    duration: float
    status: str = "converged"
    stats: dict = field(default_factory=dict)
    warnings: tuple = ()

    def line(self, name: str | None = None) -> LineSpectrum:
        """A line's spectrum (the only one when ``name`` is None)."""
        if name is None:
            if len(self.lines) != 1:
                raise KeyError(f"several lines ({', '.join(self.lines)}): name one")
            return next(iter(self.lines.values()))
        return self.lines[name]

    def summary(self) -> str:
        """A few lines of text: per line, end B's mean, standard deviation and most probable
        maximum."""
        rows = [f"frequency domain  {self.scene_name}: {self.omega.size} wave components, "
                f"{self.stats.get('linearisation', '')} drag linearisation, "
                f"{self.stats.get('iterations', '?')} iterations, "
                f"{self.stats.get('wall_time', float('nan')):.3g} s"]
        for name, ln in self.lines.items():
            b = ln.end_b
            rows.append(f"{name:<16} end B axial force mean {force_text(b['mean'])}, std "
                        f"{force_text(b['std'])}, most probable max over "
                        f"{self.duration:g} s {force_text(b['mpm'])}")
        rows += [f"warning  {w}" for w in self.warnings]
        return "\n".join(rows)

    def damage(self, name: str | None = None, curve="dnv-studless-chain", *,
               diameter: float | None = None, area: float | None = None,
               breaking_load: float | None = None, duration: float | None = None,
               segment: int = -1) -> dict:
        """Fatigue damage of one segment's axial force (default end B's) over ``duration`` s
        (default the result's) by the narrow-band and Dirlik methods
        (:mod:`symcable.analytic.fatigue`), from its spectral moments over the sea's
        components (m_k = sum omega_i^k |T_i|^2 a_i^2 / 2).

        Parameters
        ----------
        name : str, optional
            The line (the only one when None).
        curve : str or TNCurve
            A T-N curve (``symcable.analytic.fatigue.TN_CURVES``: DNV-OS-E301's and API RP
            2SK's).
        diameter, area : float
            A DNV curve: the nominal diameter (m; the area from it by the curve's component)
            or the nominal area (mm^2).
        breaking_load : float
            An API curve: the reference breaking strength, N (a rope's intercept at the
            segment's static tension).
        """
        from ..analytic.fatigue import (_curve, dirlik_damage, narrow_band_damage,
                                        nominal_area)
        c = _curve(curve)
        if c.basis == "stress" and area is None:
            if diameter is None:
                raise ValueError("damage: give the nominal diameter (m) or area (mm^2)")
            area = nominal_area(diameter, c.component)
        line = self.line(name)
        T = np.abs(line.rao[:, segment]) ** 2 * self.amplitude ** 2 / 2.0
        m = {k: float(np.sum(self.omega ** k * T)) for k in (0, 1, 2, 4)}
        D = self.duration if duration is None else float(duration)
        ref = dict(area=area, breaking_load=breaking_load, mean=float(line.mean[segment]))
        return {"narrow_band": narrow_band_damage(m[0], m[2], D, c, **ref),
                "dirlik": dirlik_damage(m[0], m[1], m[2], m[4], D, c, **ref),
                "duration": D, "area": area, "breaking_load": breaking_load}

    def plot(self, path: str | Path | None = None):
        """End B's axial-force spectrum per line with the sea's, and the standard deviation
        along each line (:func:`symcable.plotting.frequency.plot_frequency`); saved to
        ``path`` when given; returns the matplotlib Figure."""
        from ..plotting.frequency import plot_frequency
        return plot_frequency(self, path)

    def save(self, path: str | Path) -> Path:
        """Save to ``.npz`` or ``.json`` (:mod:`symcable.results.io`); :meth:`load` reads it."""
        tree = {f.name: getattr(self, f.name) for f in fields(self)}
        tree["lines"] = {k: {f.name: getattr(v, f.name) for f in fields(v)}
                         for k, v in self.lines.items()}
        return write_tree(path, tree)

    @classmethod
    def load(cls, path: str | Path) -> "FrequencyResponse":
        """Read a result written by :meth:`save`."""
        d = read_tree(path)
        d["lines"] = MappingProxyType({k: LineSpectrum(**v) for k, v in d["lines"].items()})
        d["warnings"] = tuple(d.get("warnings") or ())
        return cls(**d)
