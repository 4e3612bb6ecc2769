"""The periodic steady state of any Mechanism over one period, as the generic periodic solvers
(:mod:`symcable.solvers.periodic_mech`) return it."""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..errors import SymcableError
from .generic import _Outputs

__all__ = ["MechanismPeriodic"]


@dataclass(frozen=True)
class MechanismPeriodic(_Outputs):
    """A periodic response of a Mechanism, sampled on a uniform grid of one period.

    The samples are the method's own interpolant (collocation polynomials, Fourier series,
    trigonometric interpolation of the shooting steps) evaluated at ``m`` equally spaced times,
    the grid on which the solution was checked (4 times as fine as the solver's own points).

    Attributes
    ----------
    mechanism : str
    period : float, s
    time : ndarray (m,), s     t_i = i T / m, i = 0 .. m-1 (t = T is t = 0 again)
    q : ndarray (m, n_q);  v : ndarray (m, n_v);  z : ndarray (m, n_z)
    p : ndarray (n_p,)         the parameters solved for
    outputs : dict name -> ndarray (m, ...), the mechanism's named outputs
    method : str               ``"collocation"``, ``"harmonic-balance"`` or ``"shooting"``
    status : str               ``"converged"`` (solved and every check passed) or ``"failed"``
    stats : dict               ``iterations``, ``residual`` (scaled residual of the solved
                               system), ``periodicity_defect`` (scaled), ``defect`` (dict: the
                               scaled equation residuals on the fine grid: ``dynamic``
                               max |M a - f| / force scale, ``kinematic`` max |q' - G v| / v
                               scale, ``constraint`` max |g_i| / g_scale_i), ``error_estimate`` (the
                               largest of them), ``wall_time`` (s), ``start``, method details
    warnings : tuple of str
    """

    mechanism: str
    period: float
    time: np.ndarray
    q: np.ndarray
    v: np.ndarray
    z: np.ndarray
    p: np.ndarray
    outputs: dict
    method: str
    status: str
    stats: dict = field(default_factory=dict)
    warnings: tuple = ()

    def __repr__(self) -> str:
        return (f"MechanismPeriodic({self.mechanism!r}, method={self.method!r}, "
                f"status={self.status!r}, period={self.period:.6g} s, {self.time.size} samples, "
                f"error estimate {self.stats.get('error_estimate', float('nan')):.3g})")

    def at(self, t) -> tuple:
        """``(q, v, z)`` at times ``t`` (s, any shape (k,)), by trigonometric interpolation of the
        samples (the solution is periodic: any t is allowed)."""
        t = np.atleast_1d(np.asarray(t, dtype=float))
        if not np.all(np.isfinite(t)):
            raise SymcableError(f"t = {t!r}: times must be finite")
        return tuple(trig_interp(x, self.period, t) for x in (self.q, self.v, self.z))


def trig_interp(x: np.ndarray, period: float, t: np.ndarray) -> np.ndarray:
    """Trigonometric interpolation of uniform samples ``x`` (m, n) of one period at times ``t``
    (k,): (k, n). An even ``m``'s Nyquist term is split evenly between +-m/2 (real result)."""
    x = np.asarray(x, dtype=float)
    m = x.shape[0]
    if x.ndim == 1:
        return trig_interp(x[:, None], period, t)[:, 0]
    if x.shape[1] == 0:
        return np.zeros((t.size, 0))
    c = np.fft.rfft(x, axis=0) / m
    k = np.arange(c.shape[0])
    w = np.full(c.shape[0], 2.0)
    w[0] = 1.0
    if m % 2 == 0:
        w[-1] = 1.0
    ph = np.exp(2j * np.pi * np.outer(t / period, k))  # (k_t, n_k)
    return np.real(ph @ (c * w[:, None]))
