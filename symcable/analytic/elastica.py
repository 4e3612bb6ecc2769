"""Elastica oracles: the inextensible cantilever under a dead tip load (elliptic integrals)
and linear beam theory for small deflections."""
from __future__ import annotations

import math

from ..errors import ConvergenceError
from .catenary import _check_positive
from .special import _EPS, _brentq, carlson_rd, carlson_rf


# --------------------------------------------------------------------------------------------
# Elastica: cantilever with a dead tip load
# --------------------------------------------------------------------------------------------

def _tip_load_terms(y: float, t: float):
    """Elliptic terms of the tip-loaded elastica.

    ``y = sin(alpha)`` and ``t = 1 - k^2 = (1 - y)/2`` are both passed (the caller computes
    the smaller one from its root variable and the other from it) so that neither loses
    precision, as alpha -> 0 or alpha -> pi/2.

    Returns
    -------
    (kf, zc)
        ``kf = K(k) - F(phi1, k)`` (= L sqrt(P/EI) at the solution) and
        ``zc = 2 [E(k) - E(phi1, k)] - kf`` (= z_tip sqrt(P/EI) at the solution).
    """
    m = 1.0 - t
    c2 = y / (2.0 * m)  # cos^2(phi1); sin^2(phi1) = 1/(2m); 1 - m sin^2(phi1) = 1/2
    if y <= 0.5:
        # Complementary amplitude chi1 = pi/2 - phi1: K - F(phi1) = int_0^chi1 dchi /
        # sqrt(t + m sin^2 chi) = F(chi1 | -m/t)/sqrt(t), likewise for E, with
        # 1 + (m/t) sin^2 chi1 = 1/(1 - y). No difference of nearly equal integrals remains.
        rf = carlson_rf(1.0 / (1.0 + y), 1.0 / (1.0 - y), 1.0)
        rd = carlson_rd(1.0 / (1.0 + y), 1.0 / (1.0 - y), 1.0)
        root = math.sqrt(c2 / t)
        kf = root * rf
        zc = root * y * (rd / 3.0 - rf)
        return kf, zc
    # complete integrals: K = R_F(0, t, 1), E = K - m/3 R_D(0, t, 1)
    kk = carlson_rf(0.0, t, 1.0)
    ee = kk - m / 3.0 * carlson_rd(0.0, t, 1.0)
    sn = 1.0 / math.sqrt(2.0 * m)
    f1 = sn * carlson_rf(c2, 0.5, 1.0)
    e1 = f1 - m / 3.0 * sn ** 3 * carlson_rd(c2, 0.5, 1.0)
    return kk - f1, 2.0 * (ee - e1) - (kk - f1)


def cantilever_tip_load(length: float, EI: float, load: float) -> dict:
    """Large deflection of an inextensible, weightless cantilever under a dead tip load.

    The elastica is clamped at the origin with its tangent along +x and loaded at its free tip
    by a downward force P that keeps its direction. With theta(s) the tangent angle,
    ``EI theta'' = P cos(theta)``, ``theta(0) = 0``, ``theta'(L) = 0``. With alpha the tip
    rotation (theta(L) = -alpha), k^2 = (1 + sin alpha)/2 and sin(phi1) = 1/(k sqrt 2)
    (Bisshopp & Drucker 1945; Timoshenko & Gere)::

        L sqrt(P/EI) = K(k) - F(phi1, k)
        x_tip = sqrt(2 EI/P) sqrt(sin alpha)
        z_tip = -L + 2 sqrt(EI/P) [E(k) - E(phi1, k)]

    (the last from substituting 1 + sin(phi) = 2 k^2 sin^2(psi) in
    ``z_tip = -int_0^alpha sin(phi) dphi / sqrt((2P/EI)(sin alpha - sin phi))``).
    alpha is found by Brent's method on log(sin alpha) for small loads and on log(1 - k^2)
    for large ones, so the result keeps about full relative precision at both ends
    (z_tip is evaluated as sqrt(EI/P)(2[E - E(phi1)] - [K - F(phi1)]), which avoids the
    cancellation -L + (almost L) of the formula above at small loads).

    Parameters
    ----------
    length : float
        Length L, m (> 0).
    EI : float
        Bending stiffness, N m^2 (> 0).
    load : float
        Downward tip force P, N (>= 0); P L^2/EI up to about 1e5.

    Returns
    -------
    dict
        ``x_tip`` (m), ``z_tip`` (m, negative), ``angle_tip`` (rad, tangent angle at the tip,
        in (-pi/2, 0]).
    """
    length = _check_positive("length", length)
    EI = _check_positive("EI", EI)
    load = float(load)
    if not math.isfinite(load) or load < 0.0:
        raise ValueError(f"load = {load!r} N: must be a finite number >= 0 (downward)")
    lam = length * math.sqrt(load / EI)
    if lam < 1e-100:  # linear theory is exact to round-off (and y would underflow)
        return {"x_tip": length, "z_tip": -length * lam ** 2 / 3.0,
                "angle_tip": -0.5 * lam ** 2}

    if _tip_load_terms(0.5, 0.25)[0] >= lam:
        # small rotation: root variable v = log(sin alpha), sin alpha in (0, 1/2]
        def yt(v):
            y = math.exp(v)
            return y, 0.5 * (1.0 - y)
        v_hi = math.log(0.5)
        v_lo = math.log(0.25 * lam * lam)  # kf ~ sqrt(2 y) for small y
    else:
        # large rotation: root variable v = log(1 - k^2), 1 - k^2 in (0, 1/4)
        def yt(v):
            t = math.exp(v)
            return 1.0 - 2.0 * t, t
        v_hi = math.log(0.25)
        v_lo = -2.0 * lam - 4.0  # K ~ log(4/sqrt t), F(pi/4 | 1) ~ 0.88
        if v_lo < math.log(1e-300):
            raise ValueError(f"load = {load} N: P L^2/EI = {lam ** 2:g} is too large for "
                             "this implementation (limit ~1e5)")

    def g(v):
        return _tip_load_terms(*yt(v))[0] - lam

    g_lo, g_hi = g(v_lo), g(v_hi)
    if (g_lo > 0.0) == (g_hi > 0.0) and g_lo != 0.0:  # pragma: no cover - guard
        raise ConvergenceError("cantilever_tip_load: could not bracket the tip rotation",
                               diagnostics={"bracket": (v_lo, v_hi), "g": (g_lo, g_hi)})
    v, _ = _brentq(g, v_lo, v_hi, g_lo, g_hi, xtol=1e-300, rtol=4.0 * _EPS, max_iter=300,
                   what="cantilever_tip_load")
    y, t = yt(v)
    _, zc = _tip_load_terms(y, t)
    alpha = math.atan2(y, 2.0 * math.sqrt(t * (1.0 - t)))
    scale = math.sqrt(EI / load)
    return {
        "x_tip": math.sqrt(2.0) * scale * math.sqrt(y),
        "z_tip": scale * zc,
        "angle_tip": -alpha,
    }


def cantilever_tip_load_small(length: float, EI: float, load: float) -> float:
    """Linear-theory tip deflection of a cantilever under a tip load, ``P L^3 / (3 EI)``.

    Parameters
    ----------
    length : float
        Length L, m.
    EI : float
        Bending stiffness, N m^2.
    load : float
        Tip force P, N.

    Returns
    -------
    float
        Downward tip deflection (positive), m.
    """
    return float(load) * float(length) ** 3 / (3.0 * float(EI))


def heavy_cantilever_small(length: float, EI: float, weight: float) -> float:
    """Linear-theory tip deflection of a cantilever under its own weight, ``w L^4 / (8 EI)``.

    Parameters
    ----------
    length : float
        Length L, m.
    EI : float
        Bending stiffness, N m^2.
    weight : float
        Distributed load w, N/m.

    Returns
    -------
    float
        Downward tip deflection (positive), m.
    """
    return float(weight) * float(length) ** 4 / (8.0 * float(EI))
