"""Statistics of a narrow-band Gaussian response from its spectral moments: zero
up-crossing period and the Rayleigh most probable maximum.

A response of variance m0 (its spectrum's integral) and second moment m2 crosses its mean
upward on average every Tz = 2 pi sqrt(m0 / m2) s; over a duration D its N = D / Tz peaks
are Rayleigh distributed (narrow band), whose most probable largest is sigma sqrt(2 ln N)
above the mean (sigma = sqrt(m0)).
"""
from __future__ import annotations

import math

import numpy as np

__all__ = ["zero_crossing_period", "rayleigh_mpm"]


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
