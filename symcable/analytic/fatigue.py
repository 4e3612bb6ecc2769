"""Fatigue of mooring lines from tension: T-N (S-N) curves, rainflow counting of a tension
history (the ``rainflow`` package, ASTM E1049's four-point method) with Miner's sum, and
spectral damage from a tension spectrum (narrow band, Dirlik).

A curve N = a_D S^-m gives the cycles to failure N at a nominal stress range S (MPa): the
tension range over the component's nominal area. Miner's damage of n_i cycles of ranges S_i
is sum n_i / N_i = sum n_i S_i^m / a_D. The curves of DNV-OS-E301 (Position Mooring,
Ch. 2 Sec. 2) are :data:`TN_CURVES`; any other is given by its a_D and m.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

#: the trapezoidal rule (numpy >= 2 names it trapezoid, 1.x trapz)
_trapezoid = getattr(np, "trapezoid", None) or np.trapz

__all__ = ["TNCurve", "TN_CURVES", "nominal_area", "rainflow_damage", "narrow_band_damage",
           "dirlik_damage", "equivalent_range", "moments"]


@dataclass(frozen=True)
class TNCurve:
    """N = a_D S^-m, S the nominal stress range in MPa.

    Attributes
    ----------
    a_D : float
        The curve's intercept (cycles at 1 MPa).
    m : float
        Its slope (> 0).
    component : str
        ``"chain"`` (the load carried by two bars: nominal area 2 pi d^2 / 4) or ``"rope"``
        (pi d^2 / 4), for :func:`nominal_area`.
    """

    a_D: float
    m: float
    component: str = "chain"

    def cycles(self, stress_range) -> np.ndarray:
        """Cycles to failure at each stress range (MPa)."""
        s = np.asarray(stress_range, float)
        with np.errstate(divide="ignore"):
            return self.a_D * s ** -self.m


#: DNV-OS-E301's curves (stress in MPa)
TN_CURVES = {
    "dnv-studless-chain": TNCurve(6.0e10, 3.0, "chain"),
    "dnv-studlink-chain": TNCurve(1.2e11, 3.0, "chain"),
    "dnv-stranded-rope": TNCurve(3.4e14, 4.0, "rope"),
    "dnv-spiral-rope": TNCurve(1.7e17, 4.8, "rope"),
}


def nominal_area(diameter: float, component: str = "chain") -> float:
    """The nominal area (mm^2) of a chain (two bars of ``diameter`` m: 2 pi d^2 / 4) or a
    rope (pi d^2 / 4)."""
    a = math.pi / 4.0 * (1000.0 * diameter) ** 2
    return 2.0 * a if component == "chain" else a


def _curve(curve) -> TNCurve:
    if isinstance(curve, TNCurve):
        return curve
    if curve not in TN_CURVES:
        raise ValueError(f"curve = {curve!r}: one of {', '.join(map(repr, TN_CURVES))} or a "
                         "TNCurve(a_D, m)")
    return TN_CURVES[curve]


def rainflow_damage(tension, curve="dnv-studless-chain", *, area: float) -> dict:
    """Miner's damage of a tension history (N, any sampling: its reversals are what count)
    by rainflow counting (half cycles counted as half), at the nominal ``area`` (mm^2).

    Returns
    -------
    dict
        ``ranges`` (N) and ``counts`` of the cycles (half cycles 0.5), ``damage`` (1),
        ``cycles`` (their total count).
    """
    import rainflow
    c = _curve(curve)
    x = np.asarray(tension, float)
    if x.ndim != 1 or x.size < 2 or not np.all(np.isfinite(x)):
        raise ValueError("tension: a finite 1D history of at least two samples")
    pairs = rainflow.count_cycles(x)
    ranges = np.array([r for r, _ in pairs], float)
    counts = np.array([n for _, n in pairs], float)
    damage = float(np.sum(counts * (ranges / area) ** c.m) / c.a_D) if ranges.size else 0.0
    return {"ranges": ranges, "counts": counts, "damage": damage,
            "cycles": float(counts.sum())}


def equivalent_range(ranges, counts, m: float, n_ref: float) -> float:
    """The damage-equivalent range: the one range whose ``n_ref`` cycles do the damage of
    the given cycles under a curve of slope ``m``, (sum n_i R_i^m / n_ref)^(1/m)."""
    r, n = np.asarray(ranges, float), np.asarray(counts, float)
    return float((np.sum(n * r ** m) / n_ref) ** (1.0 / m))


def moments(omega, S, orders=(0, 1, 2, 4)) -> dict:
    """Spectral moments {k: m_k} of a one-sided spectrum ``S`` sampled at ``omega`` (rad/s;
    the trapezoidal rule): m_k = integral of omega^k S."""
    w, s = np.asarray(omega, float), np.asarray(S, float)
    order = np.argsort(w)
    w, s = w[order], s[order]
    return {k: float(_trapezoid(w ** k * s, w)) for k in orders}


def narrow_band_damage(m0: float, m2: float, duration: float, curve="dnv-studless-chain", *,
                       area: float) -> float:
    """Damage over ``duration`` s of a narrow-band Gaussian tension of variance ``m0``
    (N^2) and second moment ``m2`` (N^2 rad^2/s^2): nu0 T (2 sqrt(2 m0))^m Gamma(1 + m/2) /
    a_D at the nominal ``area`` (mm^2), nu0 = sqrt(m2 / m0) / 2 pi. An upper bound for a
    broad-band response."""
    c = _curve(curve)
    if m0 <= 0.0:
        return 0.0
    nu0 = math.sqrt(m2 / m0) / (2.0 * math.pi)
    sigma = math.sqrt(m0) / area
    return nu0 * duration * (2.0 * math.sqrt(2.0) * sigma) ** c.m * math.gamma(
        1.0 + c.m / 2.0) / c.a_D


def dirlik_damage(m0: float, m1: float, m2: float, m4: float, duration: float,
                  curve="dnv-studless-chain", *, area: float) -> float:
    """Damage over ``duration`` s of a Gaussian tension of spectral moments m0, m1, m2, m4
    (N^2 (rad/s)^k; :func:`moments`) by Dirlik's empirical distribution of rainflow ranges
    (Dirlik 1985), at the nominal ``area`` (mm^2)."""
    c = _curve(curve)
    if m0 <= 0.0:
        return 0.0
    xm = m1 / m0 * math.sqrt(m2 / m4)
    gam = m2 / math.sqrt(m0 * m4)
    D1 = 2.0 * (xm - gam * gam) / (1.0 + gam * gam)
    R = (gam - xm - D1 * D1) / (1.0 - gam - D1 + D1 * D1)
    D2 = (1.0 - gam - D1 + D1 * D1) / (1.0 - R)
    D3 = 1.0 - D1 - D2
    Q = 1.25 * (gam - D3 - D2 * R) / D1
    s0 = math.sqrt(m0) / area  # MPa
    m = c.m
    # E[S^m] with S = 2 s0 Z and Dirlik's density of Z: an exponential, two Rayleighs
    ez = (D1 * Q ** m * math.gamma(1.0 + m) + math.sqrt(2.0) ** m * math.gamma(1.0 + m / 2.0)
          * (D2 * abs(R) ** m + D3))
    peaks = math.sqrt(m4 / m2) / (2.0 * math.pi)
    return peaks * duration * (2.0 * s0) ** m * ez / c.a_D
