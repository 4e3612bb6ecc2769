"""Special functions and a root finder for the closed forms, in NumPy only (so the oracles
share no code with the solvers they check): Carlson's symmetric elliptic integrals,
Legendre's incomplete integrals, Brent's bracketing method."""
from __future__ import annotations

from typing import Callable

import numpy as np

from ..errors import ConvergenceError

_EPS = np.finfo(float).eps


# --------------------------------------------------------------------------------------------
# Carlson symmetric elliptic integrals and Legendre's incomplete integrals
# --------------------------------------------------------------------------------------------

def carlson_rf(x, y, z):
    """Carlson's symmetric elliptic integral of the first kind R_F(x, y, z).

    ``R_F(x, y, z) = 1/2 * int_0^inf dt / sqrt((t+x)(t+y)(t+z))``, computed by the
    duplication algorithm of Carlson (1995, Numer. Algorithms 10, 13-26), which converges to
    machine precision.

    Parameters
    ----------
    x, y, z : array_like
        Non-negative arguments (broadcast together); at most one of them may be zero.

    Returns
    -------
    numpy.ndarray or float
        R_F, shape of the broadcast arguments (a float for scalar input).
    """
    x, y, z = np.broadcast_arrays(*(np.asarray(v, dtype=float) for v in (x, y, z)))
    scalar = x.ndim == 0
    x, y, z = (np.atleast_1d(v).astype(float, copy=True) for v in (x, y, z))
    if np.any((x < 0) | (y < 0) | (z < 0)):
        raise ValueError("carlson_rf: arguments must be >= 0")
    a0 = (x + y + z) / 3.0
    # (3 r)^(-1/6) with r = eps/4: the truncation error of the series is below r.
    q = (3.0 * _EPS / 4.0) ** (-1.0 / 6.0) * np.maximum.reduce(
        [np.abs(a0 - x), np.abs(a0 - y), np.abs(a0 - z)])
    a = a0.copy()
    x0, y0 = x.copy(), y.copy()
    f4 = 1.0  # 4^-n
    for _ in range(200):
        if np.all(q * f4 < np.abs(a)):
            break
        sx, sy, sz = np.sqrt(x), np.sqrt(y), np.sqrt(z)
        lam = sx * sy + sx * sz + sy * sz
        x, y, z = (x + lam) / 4.0, (y + lam) / 4.0, (z + lam) / 4.0
        a = (a + lam) / 4.0
        f4 /= 4.0
    else:  # pragma: no cover - needs arguments spanning more than ~1e120
        raise ConvergenceError("carlson_rf: duplication did not converge")
    big_x = (a0 - x0) * f4 / a
    big_y = (a0 - y0) * f4 / a
    big_z = -(big_x + big_y)
    e2 = big_x * big_y - big_z ** 2
    e3 = big_x * big_y * big_z
    out = (1.0 - e2 / 10.0 + e3 / 14.0 + e2 ** 2 / 24.0 - 3.0 * e2 * e3 / 44.0) / np.sqrt(a)
    return float(out[0]) if scalar else out


def carlson_rd(x, y, z):
    """Carlson's symmetric elliptic integral of the second kind R_D(x, y, z).

    ``R_D(x, y, z) = 3/2 * int_0^inf dt / ((t+z) sqrt((t+x)(t+y)(t+z)))``, by Carlson's (1995)
    duplication algorithm.

    Parameters
    ----------
    x, y : array_like
        Non-negative arguments, at most one of them zero.
    z : array_like
        Positive argument.

    Returns
    -------
    numpy.ndarray or float
        R_D, shape of the broadcast arguments (a float for scalar input).
    """
    x, y, z = np.broadcast_arrays(*(np.asarray(v, dtype=float) for v in (x, y, z)))
    scalar = x.ndim == 0
    x, y, z = (np.atleast_1d(v).astype(float, copy=True) for v in (x, y, z))
    if np.any((x < 0) | (y < 0) | (z <= 0)):
        raise ValueError("carlson_rd: need x, y >= 0 and z > 0")
    a0 = (x + y + 3.0 * z) / 5.0
    q = (_EPS / 16.0) ** (-1.0 / 6.0) * np.maximum.reduce(
        [np.abs(a0 - x), np.abs(a0 - y), np.abs(a0 - z)])
    a = a0.copy()
    x0, y0 = x.copy(), y.copy()
    f4 = 1.0
    acc = np.zeros_like(a)
    for _ in range(200):
        if np.all(q * f4 < np.abs(a)):
            break
        sx, sy, sz = np.sqrt(x), np.sqrt(y), np.sqrt(z)
        lam = sx * sy + sx * sz + sy * sz
        acc += f4 / (sz * (z + lam))
        x, y, z = (x + lam) / 4.0, (y + lam) / 4.0, (z + lam) / 4.0
        a = (a + lam) / 4.0
        f4 /= 4.0
    else:  # pragma: no cover
        raise ConvergenceError("carlson_rd: duplication did not converge")
    big_x = (a0 - x0) * f4 / a
    big_y = (a0 - y0) * f4 / a
    big_z = -(big_x + big_y) / 3.0
    xy = big_x * big_y
    z2 = big_z ** 2
    e2 = xy - 6.0 * z2
    e3 = (3.0 * xy - 8.0 * z2) * big_z
    e4 = 3.0 * (xy - z2) * z2
    e5 = xy * z2 * big_z
    series = (1.0 - 3.0 * e2 / 14.0 + e3 / 6.0 + 9.0 * e2 ** 2 / 88.0 - 3.0 * e4 / 22.0
              - 9.0 * e2 * e3 / 52.0 + 3.0 * e5 / 26.0)
    out = f4 * a ** -1.5 * series + 3.0 * acc
    return float(out[0]) if scalar else out


def _legendre_fe(phi, m, want_e):
    """F(phi|m) and optionally E(phi|m) for any real phi, 0 <= m <= 1 (m < 1 if |phi| >= pi/2)."""
    phi, m = np.broadcast_arrays(np.asarray(phi, dtype=float), np.asarray(m, dtype=float))
    scalar = phi.ndim == 0
    phi, m = np.atleast_1d(phi), np.atleast_1d(m)
    if np.any((m < 0) | (m > 1)):
        raise ValueError("elliptic integrals: parameter m = k^2 must lie in [0, 1]")
    # phi = n*pi + r with |r| <= pi/2; F(n pi + r) = 2 n K + F(r) (same for E).
    n = np.round(phi / np.pi)
    r = phi - n * np.pi
    if np.any((n != 0) & (m >= 1)):
        raise ValueError("elliptic integrals: |phi| > pi/2 needs m < 1 (K(1) is infinite)")
    sr, cr = np.sin(r), np.cos(r)
    c2 = cr * cr
    d2 = c2 + (1.0 - m) * sr * sr  # = 1 - m sin^2, without cancellation as m -> 1
    rf = carlson_rf(c2, d2, np.ones_like(c2))
    f = sr * rf
    nz = n != 0
    kc = np.zeros_like(f)
    if np.any(nz):
        kc[nz] = carlson_rf(np.zeros(nz.sum()), 1.0 - m[nz], np.ones(nz.sum()))
    if not want_e:
        out = f + 2.0 * n * kc
        return float(out[0]) if scalar else out
    rd = carlson_rd(c2, d2, np.ones_like(c2))
    e = f - m / 3.0 * sr ** 3 * rd
    ec = np.zeros_like(f)
    if np.any(nz):
        ec[nz] = kc[nz] - m[nz] / 3.0 * carlson_rd(np.zeros(nz.sum()), 1.0 - m[nz],
                                                   np.ones(nz.sum()))
    out = e + 2.0 * n * ec
    return float(out[0]) if scalar else out


def elliptic_f(phi, m):
    """Incomplete elliptic integral of the first kind F(phi | m).

    ``F(phi|m) = int_0^phi dt / sqrt(1 - m sin^2 t)``, with the *parameter* ``m = k^2`` (the
    convention of ``scipy.special.ellipkinc``), computed as ``sin(phi) R_F(cos^2, 1 - m sin^2, 1)``
    after reducing phi to [-pi/2, pi/2] by ``F(phi + n pi) = F(phi) + 2 n K(m)``.

    Parameters
    ----------
    phi : array_like
        Amplitude, rad.
    m : array_like
        Parameter k^2 in [0, 1] (m = 1 only with |phi| < pi/2).

    Returns
    -------
    numpy.ndarray or float
        F, shape of the broadcast arguments.
    """
    return _legendre_fe(phi, m, want_e=False)


def elliptic_e(phi, m):
    """Incomplete elliptic integral of the second kind E(phi | m).

    ``E(phi|m) = int_0^phi sqrt(1 - m sin^2 t) dt`` (parameter convention of
    ``scipy.special.ellipeinc``), computed as
    ``sin R_F(cos^2, Δ^2, 1) - (m/3) sin^3 R_D(cos^2, Δ^2, 1)``, ``Δ^2 = 1 - m sin^2 phi``.

    Parameters
    ----------
    phi : array_like
        Amplitude, rad.
    m : array_like
        Parameter k^2 in [0, 1] (m = 1 only with |phi| <= pi/2).

    Returns
    -------
    numpy.ndarray or float
        E, shape of the broadcast arguments.
    """
    return _legendre_fe(phi, m, want_e=True)


# --------------------------------------------------------------------------------------------
# Brent's root finder (scipy's brentq algorithm, written out)
# --------------------------------------------------------------------------------------------

def _brentq(f: Callable[[float], float], xa: float, xb: float, fa: float, fb: float, *,
            xtol: float, rtol: float, max_iter: int, what: str) -> tuple[float, int]:
    """Root of a scalar function bracketed by [xa, xb] (f(xa) f(xb) <= 0).

    Brent (1973), as in scipy's ``brentq``: inverse quadratic interpolation or secant
    steps, falling back to bisection, so the bracket always shrinks.

    Returns
    -------
    (root, iterations)
    """
    if fa * fb > 0.0:
        raise ValueError(f"{what}: root not bracketed (f(a) = {fa:g}, f(b) = {fb:g})")
    if fa == 0.0:
        return xa, 0
    if fb == 0.0:
        return xb, 0
    xpre, xcur, fpre, fcur = xa, xb, fa, fb
    xblk = fblk = spre = scur = 0.0
    for it in range(1, max_iter + 1):
        if fpre * fcur < 0.0:
            xblk, fblk = xpre, fpre
            spre = scur = xcur - xpre
        if abs(fblk) < abs(fcur):
            xpre, xcur, xblk = xcur, xblk, xcur
            fpre, fcur, fblk = fcur, fblk, fcur
        delta = 0.5 * (xtol + rtol * abs(xcur))
        sbis = 0.5 * (xblk - xcur)
        if fcur == 0.0 or abs(sbis) < delta:
            return xcur, it
        if abs(spre) > delta and abs(fcur) < abs(fpre):
            if xpre == xblk:
                stry = -fcur * (xcur - xpre) / (fcur - fpre)
            else:
                dpre = (fpre - fcur) / (xpre - xcur)
                dblk = (fblk - fcur) / (xblk - xcur)
                stry = -fcur * (fblk * dblk - fpre * dpre) / (dblk * dpre * (fblk - fpre))
            if 2.0 * abs(stry) < min(abs(spre), 3.0 * abs(sbis) - delta):
                spre, scur = scur, stry
            else:
                spre = scur = sbis
        else:
            spre = scur = sbis
        xpre, fpre = xcur, fcur
        xcur += scur if abs(scur) > delta else (delta if sbis > 0 else -delta)
        fcur = f(xcur)
    raise ConvergenceError(f"{what}: Brent's method did not converge in {max_iter} iterations",
                           diagnostics={"bracket": (xcur, xblk), "f": (fcur, fblk),
                                        "iterations": max_iter})
