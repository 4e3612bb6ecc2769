"""Linear (Airy) waves in numbers: the dispersion relation, sea spectra and their
discretisation into components.

The kinematics of a sea of components (elevation, fluid velocity and acceleration at any
point) are written once, symbolically, in :mod:`symcable.models.common.waves`, and evaluated in
numbers by :func:`symcable.wave_kinematics`.

Conventions: angular frequencies omega in rad/s, wave numbers k in rad/m, a spectrum S(omega)
one-sided in m^2 s/rad (the elevation's variance is its integral over omega > 0), a
component's amplitude a in m (half its height), its phase in rad, the elevation
a cos(k (x cos beta + y sin beta) - omega t + phase), beta the direction the component
travels toward, counterclockwise from +x.
"""
from __future__ import annotations

import math

import numpy as np

#: the trapezoidal rule (numpy >= 2 names it trapezoid, 1.x trapz)
_trapezoid = getattr(np, "trapezoid", None) or np.trapz

__all__ = ["GRAVITY", "airy", "jonswap", "pierson_moskowitz", "spectrum_components", "wave_number",
           "spectral_moment", "default_band"]

#: standard gravity, m/s^2
GRAVITY = 9.80665


def wave_number(omega, depth: float | None = None, gravity: float = GRAVITY) -> np.ndarray:
    """The wave number k (rad/m) of each angular frequency ``omega`` (rad/s, > 0) in water
    of ``depth`` (m; None: deep water), the root of omega^2 = g k tanh(k h): Newton's
    iteration from the deep-water root omega^2 / g, to round-off.

    Parameters
    ----------
    omega : float or array
        Angular frequencies, rad/s, each > 0.
    depth : float or None
        Water depth h, m (> 0); None for deep water (k = omega^2 / g).
    gravity : float
        m/s^2.

    Returns
    -------
    numpy.ndarray
        k, rad/m, the shape of ``omega``.
    """
    w = np.asarray(omega, dtype=float)
    if np.any(~np.isfinite(w)) or np.any(w <= 0.0):
        raise ValueError(f"wave_number: omega must be finite and > 0 rad/s, got {omega!r}")
    k0 = w * w / gravity
    if depth is None:
        return k0
    h = float(depth)
    # start above the root (k tanh(k h) is increasing in k; from the larger of the deep and
    # shallow roots Newton's iteration on this concave function falls monotonically)
    k = np.maximum(k0, w / math.sqrt(gravity * h))
    for _ in range(100):
        th = np.tanh(k * h)
        f = k * th - k0
        df = th + k * h * (1.0 - th * th)
        step = f / df
        k = k - step
        if np.all(np.abs(step) <= 4.0 * np.finfo(float).eps * k):
            break
    return k


def jonswap(omega, hs: float, tp: float, gamma: float = 3.3) -> np.ndarray:
    """The JONSWAP spectrum S(omega), m^2 s/rad (one-sided), of significant wave height
    ``hs`` (m), peak period ``tp`` (s) and peak enhancement ``gamma`` (1 to 7; 1 is the
    Pierson-Moskowitz spectrum): S = (1 - 0.287 ln gamma) (5/16) hs^2 wp^4 omega^-5
    exp(-5/4 (omega/wp)^-4) gamma^exp(-(omega - wp)^2 / (2 sigma^2 wp^2)), wp = 2 pi / tp,
    sigma 0.07 below the peak and 0.09 above (DNV-RP-C205, 3.5.5); its variance is close
    to hs^2 / 16 (within 0.3 % for gamma up to 5, 2 % at 7).

    Parameters
    ----------
    omega : float or array
        rad/s (>= 0; S = 0 at omega = 0).
    hs, tp : float
        m and s (> 0).
    gamma : float
        Peak enhancement factor (>= 1).
    """
    w = np.asarray(omega, dtype=float)
    wp = 2.0 * math.pi / tp
    with np.errstate(divide="ignore", over="ignore", invalid="ignore"):
        r = np.where(w > 0.0, wp / np.where(w > 0.0, w, 1.0), 0.0)  # wp / omega
        pm = np.where(w > 0.0, 5.0 / 16.0 * hs * hs * wp ** 4
                      * np.where(w > 0.0, w, 1.0) ** -5.0 * np.exp(-1.25 * r ** 4), 0.0)
    sigma = np.where(w <= wp, 0.07, 0.09)
    peak = gamma ** np.exp(-0.5 * ((w - wp) / (sigma * wp)) ** 2)
    return (1.0 - 0.287 * math.log(gamma)) * pm * peak


def pierson_moskowitz(omega, hs: float, tp: float) -> np.ndarray:
    """The Pierson-Moskowitz spectrum S(omega), m^2 s/rad: :func:`jonswap` with gamma = 1."""
    return jonswap(omega, hs, tp, 1.0)


def default_band(tp: float) -> tuple[float, float]:
    """The angular frequencies (rad/s) a sea of peak period ``tp`` is discretised over by
    default: 0.5 to 4 times the peak's, which hold all but 0.5 % of a
    Pierson-Moskowitz spectrum's variance (0.3 % of a JONSWAP's of gamma = 3.3)."""
    wp = 2.0 * math.pi / tp
    return 0.5 * wp, 4.0 * wp


def spectrum_components(spectrum, band: tuple[float, float], n: int,
                        seed: int = 0) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``n`` components of a sea of one-sided spectrum ``spectrum(omega)`` (m^2 s/rad) over
    ``band`` (rad/s): the band cut into n equal bins, each component's frequency drawn
    uniformly within the middle half of its bin (so the sea does not repeat after 2 pi over
    the bin width, and no two components are closer than half a bin: a record longer than
    4 pi over the bin width resolves each), its
    amplitude sqrt(2 E_i), E_i the spectrum's integral over its bin (Simpson's rule on 16
    intervals: the sea's variance is the band's to that rule's accuracy, whatever the draw),
    its phase uniform in [0, 2 pi); the draws from ``numpy.random.default_rng(seed)``.

    Returns
    -------
    omega, amplitude, phase : numpy.ndarray
        (n,) each: rad/s, m, rad.
    """
    lo, hi = (float(b) for b in band)
    if not (0.0 < lo < hi) or n < 1:
        raise ValueError(f"spectrum_components: need 0 < band[0] < band[1] and n >= 1, got "
                         f"band = {band!r}, n = {n!r}")
    rng = np.random.default_rng(seed)
    d = (hi - lo) / n
    omega = lo + d * (np.arange(n) + rng.uniform(0.25, 0.75, n))
    sub = lo + d * (np.arange(n)[:, None] + np.linspace(0.0, 1.0, 17)[None, :])
    weights = np.array([1.0] + [4.0, 2.0] * 7 + [4.0, 1.0]) * (d / 16.0 / 3.0)
    energy = np.asarray(spectrum(sub.ravel()), dtype=float).reshape(sub.shape) @ weights
    amplitude = np.sqrt(2.0 * np.maximum(energy, 0.0))
    phase = rng.uniform(0.0, 2.0 * math.pi, n)
    return omega, amplitude, phase


def spectral_moment(omega, s, order: int = 0) -> float:
    """The spectral moment m_n = integral of omega^n S(omega) d omega (trapezoidal rule over
    the samples ``omega``, rad/s, and ``s``, m^2 s/rad): m0 the variance (m^2), Hs = 4 sqrt(m0)."""
    w = np.asarray(omega, dtype=float)
    return float(_trapezoid(w ** order * np.asarray(s, dtype=float), w))


def airy(amplitude, omega, k, phase, direction, points, t, depth: float | None = None,
         stretching: str = "vertical") -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Linear (Airy) kinematics of a sea of components at ``points`` and times ``t``, in
    NumPy: the elevation (nt, m), m; the fluid velocity and local acceleration (nt, m, 3),
    m/s and m/s^2. The same sea as :mod:`symcable.models.common.waves` writes symbolically
    (its docstring has the formulas), for series and plots: components (n,) each
    (amplitude m, omega rad/s, k rad/m, phase rad, direction rad); ``points`` (m, 3), m;
    ``t`` (nt,), s; ``depth`` m (None: deep water); ``stretching`` ``"vertical"`` or
    ``"wheeler"``."""
    a, w, kk, ph, b = (np.asarray(v, float)[None, None, :] for v in
                       (amplitude, omega, k, phase, direction))
    X = np.atleast_2d(np.asarray(points, float))
    tt = np.atleast_1d(np.asarray(t, float))[:, None, None]
    x, y, z = (X[None, :, i, None] for i in range(3))
    theta = kk * (x * np.cos(b) + y * np.sin(b)) - w * tt + ph
    c, s = np.cos(theta), np.sin(theta)
    eta = np.sum(a * c, axis=-1)
    zs = np.broadcast_to(z, eta.shape + (1,)) if stretching != "wheeler" else (
        (z - eta[..., None]) if depth is None
        else depth * (z - eta[..., None]) / (depth + eta[..., None]))
    zs = np.minimum(zs, 0.0)
    e1 = np.exp(kk * zs)
    if depth is None:
        C = S = e1
    else:
        e2 = np.exp(-kk * (zs + 2.0 * depth))
        den = 1.0 - np.exp(-2.0 * kk * depth)
        C, S = (e1 + e2) / den, (e1 - e2) / den
    uh, ah = a * w * C * c, a * w * w * C * s
    u = np.stack([np.sum(uh * np.cos(b), -1), np.sum(uh * np.sin(b), -1),
                  np.sum(a * w * S * s, -1)], axis=-1)
    acc = np.stack([np.sum(ah * np.cos(b), -1), np.sum(ah * np.sin(b), -1),
                    -np.sum(a * w * w * S * c, -1)], axis=-1)
    return eta, u, acc
