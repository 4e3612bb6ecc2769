"""Statistics of a narrow-band Gaussian response from its spectral moments: zero
up-crossing period and the Rayleigh most probable maximum.

A response of variance m0 (its spectrum's integral) and second moment m2 crosses its mean
upward on average every Tz = 2 pi sqrt(m0 / m2) s; over a duration D its N = D / Tz peaks
are Rayleigh distributed (narrow band), whose most probable largest is sigma sqrt(2 ln N)
above the mean (sigma = sqrt(m0)). From time runs, the largest values of several records (or
of equal windows of one) are fitted with a Gumbel distribution (:func:`gumbel_mpm`).
"""
from __future__ import annotations

import math

import numpy as np

__all__ = ["zero_crossing_period", "rayleigh_mpm", "gumbel_mpm"]


def zero_crossing_period(m0, m2) -> np.ndarray:
    """Tz = 2 pi sqrt(m0 / m2), s (m0 in units^2, m2 in units^2 rad^2/s^2); inf where m2 = 0."""
    m0, m2 = np.asarray(m0, float), np.asarray(m2, float)
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(m2 > 0.0, 2.0 * math.pi * np.sqrt(m0 / np.where(m2 > 0.0, m2, 1.0)),
                        np.inf)


def rayleigh_mpm(m0, m2, duration: float) -> np.ndarray:
    """The most probable maximum excursion above the mean over ``duration`` s of a
    narrow-band Gaussian response: sigma sqrt(2 ln N), N = duration / Tz peaks (none when N
    <= 1: zero)."""
    n = duration / zero_crossing_period(m0, m2)
    return np.sqrt(np.asarray(m0, float)) * np.sqrt(2.0 * np.log(np.maximum(n, 1.0)))


#: Euler-Mascheroni constant
_EULER = 0.5772156649015329


def gumbel_mpm(maxima, records: float = 1.0) -> dict:
    """The Gumbel distribution of the largest value of a record, fitted by moments to
    ``maxima`` (one per record of equal duration, at least two): scale beta = s sqrt(6) / pi,
    location mu = mean - 0.5772 beta (s the sample standard deviation); its most probable
    maximum (the mode) over ``records`` records' duration, mu + beta ln(records).

    Returns
    -------
    dict
        ``mpm``, ``mu``, ``beta`` (the maxima's units).
    """
    x = np.asarray(maxima, float).ravel()
    if x.size < 2 or not np.all(np.isfinite(x)) or records <= 0:
        raise ValueError("gumbel_mpm: at least two finite maxima and records > 0")
    beta = float(np.std(x, ddof=1)) * math.sqrt(6.0) / math.pi
    mu = float(np.mean(x)) - _EULER * beta
    return {"mpm": mu + beta * math.log(records), "mu": mu, "beta": beta}
