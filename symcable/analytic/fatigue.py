"""Fatigue of mooring lines from tension: T-N (S-N) curves, rainflow counting of a tension
history (the ``rainflow`` package, ASTM E1049's four-point method) with Miner's sum, and
spectral damage from a tension spectrum (narrow band, Dirlik).

A curve N = a_D S^-m gives the cycles to failure N at a range S: for DNV-OS-E301's curves
(Position Mooring, Ch. 2 Sec. 2) the nominal stress range in MPa, the tension range over the
component's nominal area (``area``, mm^2); for API RP 2SK's (3rd edition, Sec. 6: N R^M =
K) the tension range over the component's reference breaking strength R (``breaking_load``,
N), a rope's K falling with the mean tension's share of it, log10 K = log10 a_D - c L_m.
Miner's damage of n_i cycles of ranges S_i is sum n_i / N_i = sum n_i S_i^m / a_D. Both
standards' curves are :data:`TN_CURVES`; any other is given by its a_D and m.
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
    """N = a_D S^-m (module docstring).

    Attributes
    ----------
    a_D : float
        The curve's intercept: cycles at a unit range (1 MPa; or, ``basis = "breaking"``, a
        range equal to the breaking strength).
    m : float
        Its slope (> 0).
    component : str
        ``"chain"`` (the load carried by two bars: nominal area 2 pi d^2 / 4) or ``"rope"``
        (pi d^2 / 4), for :func:`nominal_area`.
    basis : str
        ``"stress"`` (S in MPa over the nominal area) or ``"breaking"`` (S the range over
        the reference breaking strength).
    mean_slope : float
        ``"breaking"`` only: c in log10 a_D(L_m) = log10 a_D - c L_m, L_m the mean tension
        over the breaking strength (API's ropes; 0 for chain).
    """

    a_D: float
    m: float
    component: str = "chain"
    basis: str = "stress"
    mean_slope: float = 0.0

    def intercept(self, mean_ratio: float = 0.0) -> float:
        """a_D at the mean tension's share ``mean_ratio`` of the breaking strength."""
        return self.a_D * 10.0 ** (-self.mean_slope * mean_ratio)

    def cycles(self, stress_range) -> np.ndarray:
        """Cycles to failure at each stress range (MPa)."""
        s = np.asarray(stress_range, float)
        with np.errstate(divide="ignore"):
            return self.a_D * s ** -self.m


#: DNV-OS-E301's curves (stress in MPa) and API RP 2SK's (the range over the breaking
#: strength; a rope's K = 10^(a - c L_m))
TN_CURVES = {
    "dnv-studless-chain": TNCurve(6.0e10, 3.0, "chain"),
    "dnv-studlink-chain": TNCurve(1.2e11, 3.0, "chain"),
    "dnv-stranded-rope": TNCurve(3.4e14, 4.0, "rope"),
    "dnv-spiral-rope": TNCurve(1.7e17, 4.8, "rope"),
    "api-studlink-chain": TNCurve(1000.0, 3.0, "chain", "breaking"),
    "api-studless-chain": TNCurve(316.0, 3.0, "chain", "breaking"),
    "api-connecting-link": TNCurve(178.0, 3.0, "chain", "breaking"),
    "api-stranded-rope": TNCurve(10.0 ** 3.20, 4.09, "rope", "breaking", 2.79),
    "api-spiral-rope": TNCurve(10.0 ** 3.25, 5.05, "rope", "breaking", 3.43),
}


def nominal_area(diameter: float, component: str = "chain") -> float:
    """The nominal area (mm^2) of a chain (two bars of ``diameter`` m: 2 pi d^2 / 4) or a
    rope (pi d^2 / 4)."""
    a = math.pi / 4.0 * (1000.0 * diameter) ** 2
    return 2.0 * a if component == "chain" else a


def _scale(c: TNCurve, area, breaking_load, mean) -> tuple[float, float]:
    """``(divisor of a tension range, a_D)`` for curve ``c``: the nominal ``area`` (mm^2)
    and a_D for a stress curve; the ``breaking_load`` (N) and a_D at the ``mean`` tension's
    share of it (N; required where the curve's intercept falls with it) for a
    breaking-strength curve."""
    if c.basis == "breaking":
        if breaking_load is None or not breaking_load > 0:
            raise ValueError(f"breaking_load = {breaking_load!r}: an API curve needs the "
                             "reference breaking strength, N (> 0)")
        if mean is None and c.mean_slope:
            raise ValueError("mean: this rope curve's intercept falls with the mean tension: "
                             "give the mean tension, N")
        return float(breaking_load), c.intercept((mean or 0.0) / breaking_load)
    if area is None or not area > 0:
        raise ValueError(f"area = {area!r}: a stress curve needs the nominal area, mm^2 (> 0)")
    return float(area), c.a_D


def _curve(curve) -> TNCurve:
    if isinstance(curve, TNCurve):
        return curve
    if curve not in TN_CURVES:
        raise ValueError(f"curve = {curve!r}: one of {', '.join(map(repr, TN_CURVES))} or a "
                         "TNCurve(a_D, m)")
    return TN_CURVES[curve]


def rainflow_damage(tension, curve="dnv-studless-chain", *, area: float | None = None,
                    breaking_load: float | None = None, mean: float | None = None) -> dict:
    """Miner's damage of a tension history (N, any sampling: its reversals are what count)
    by rainflow counting (half cycles counted as half), at the nominal ``area`` (mm^2; a
    stress curve) or the ``breaking_load`` (N; an API curve, a rope's intercept at the
    ``mean`` tension, N: default the samples' mean, which is the time mean only for evenly
    sampled histories).

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
    div, a_D = _scale(c, area, breaking_load, float(np.mean(x)) if mean is None else mean)
    damage = float(np.sum(counts * (ranges / div) ** c.m) / a_D) if ranges.size else 0.0
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
                       area: float | None = None, breaking_load: float | None = None,
                       mean: float | None = None) -> float:
    """Damage over ``duration`` s of a narrow-band Gaussian tension of variance ``m0``
    (N^2) and second moment ``m2`` (N^2 rad^2/s^2): nu0 T (2 sqrt(2 m0))^m Gamma(1 + m/2) /
    a_D at the nominal ``area`` (mm^2) or the ``breaking_load`` (N; an API rope's a_D at the
    ``mean`` tension, N), nu0 = sqrt(m2 / m0) / 2 pi. An upper bound for a broad-band
    response."""
    c = _curve(curve)
    div, a_D = _scale(c, area, breaking_load, mean)
    if m0 <= 0.0:
        return 0.0
    nu0 = math.sqrt(m2 / m0) / (2.0 * math.pi)
    sigma = math.sqrt(m0) / div
    return nu0 * duration * (2.0 * math.sqrt(2.0) * sigma) ** c.m * math.gamma(
        1.0 + c.m / 2.0) / a_D


def dirlik_damage(m0: float, m1: float, m2: float, m4: float, duration: float,
                  curve="dnv-studless-chain", *, area: float | None = None,
                  breaking_load: float | None = None, mean: float | None = None) -> float:
    """Damage over ``duration`` s of a Gaussian tension of spectral moments m0, m1, m2, m4
    (N^2 (rad/s)^k; :func:`moments`) by Dirlik's empirical distribution of rainflow ranges
    (Dirlik 1985), at the nominal ``area`` (mm^2) or the ``breaking_load`` (N; an API
    rope's a_D at the ``mean`` tension, N)."""
    c = _curve(curve)
    div, a_D = _scale(c, area, breaking_load, mean)
    if m0 <= 0.0:
        return 0.0
    xm = m1 / m0 * math.sqrt(m2 / m4)
    gam = m2 / math.sqrt(m0 * m4)
    D1 = 2.0 * (xm - gam * gam) / (1.0 + gam * gam)
    R = (gam - xm - D1 * D1) / (1.0 - gam - D1 + D1 * D1)
    D2 = (1.0 - gam - D1 + D1 * D1) / (1.0 - R)
    D3 = 1.0 - D1 - D2
    Q = 1.25 * (gam - D3 - D2 * R) / D1
    s0 = math.sqrt(m0) / div  # MPa, or a share of the breaking strength
    m = c.m
    # E[S^m] with S = 2 s0 Z and Dirlik's density of Z: an exponential, two Rayleighs
    ez = (D1 * Q ** m * math.gamma(1.0 + m) + math.sqrt(2.0) ** m * math.gamma(1.0 + m / 2.0)
          * (D2 * abs(R) ** m + D3))
    peaks = math.sqrt(m4 / m2) / (2.0 * math.pi)
    return peaks * duration * (2.0 * s0) ** m * ez / a_D
