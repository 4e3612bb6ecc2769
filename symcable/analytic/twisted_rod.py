"""The localized loop of an infinite twisted rod under tension (Love's homoclinic solution;
Coyne 1990, Thompson & Champneys 1996): the oracle of the looped shapes that
:func:`symcable.trace_branch` reaches.

An isotropic, inextensible, unshearable rod (bending stiffness B, N m^2) straight at both
ends along z, carrying the tension T (N) and the twisting moment M (N m) there. With the
Euler angles of the tangent (theta from the axis, psi about it), the moment about the axis
and the twisting moment are constant (B psi' sin^2 theta + M cos theta = M) and the first
integral B theta'^2 / 2 + M^2 (1 - cos theta)^2 / (2 B sin^2 theta) = T (1 - cos theta)
holds; with u = 1 - cos theta, u'^2 = (2 T / B) u^2 (a - u), a = 2 (1 - m^2 / 4),
m = M / sqrt(B T), whose orbit homoclinic to the straight state (u -> 0 at both ends) is

    1 - cos theta(s) = a sech^2(k s),   k = sqrt(T / B) sqrt(1 - m^2 / 4),

real for m < 2 (m = 2: Greenhill's criterion M^2 = 4 B T, where the infinite straight rod
turns unstable and the loop has shrunk to nothing). It takes up

- the end shortening D = int (1 - cos theta) ds = 2 a / k = 2 sqrt(4 - m^2) sqrt(B / T) (m),
- the end rotation (writhe) dR = int psi' (1 - cos theta) ds = 4 arccos(m / 2) rad beyond the
  twist M / C per metre (the twist density stays M / C: the twisting moment is constant),

m = 0 being the planar loop of the elastica (D = 4 sqrt(B / T), one full turn, 2 pi).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

__all__ = ["TwistedLoop", "twisted_loop"]


@dataclass(frozen=True)
class TwistedLoop:
    """The homoclinic loop at (B, T, M).

    m : float              M / sqrt(B T)
    k : float              1/m, the loop's inverse width
    amplitude : float      max of 1 - cos theta (2 at m = 0: the tangent turns back)
    shortening : float     m, the end shortening it takes up
    rotation : float       rad, the end rotation (writhe) it takes up beyond the twist
    """

    m: float
    k: float
    amplitude: float
    shortening: float
    rotation: float

    def one_minus_cos(self, s) -> np.ndarray:
        """1 - cos theta at arc length s (m) from the loop's middle."""
        return self.amplitude / np.cosh(self.k * np.asarray(s, float)) ** 2


def twisted_loop(B: float, T: float, M: float) -> TwistedLoop:
    """The localized loop of an infinite rod of bending stiffness B (N m^2) under tension
    T > 0 (N) and twisting moment M (N m), |M| < 2 sqrt(B T) (module docstring)."""
    if not (B > 0 and T > 0):
        raise ValueError(f"B = {B!r} N m^2 and T = {T!r} N must be > 0")
    m = abs(M) / math.sqrt(B * T)
    if not m < 2.0:
        raise ValueError(f"M / sqrt(B T) = {m:.6g}: a loop needs < 2 (Greenhill's criterion)")
    c = 1.0 - m * m / 4.0
    k = math.sqrt(T / B * c)
    return TwistedLoop(m, k, 2.0 * c, 2.0 * math.sqrt(4.0 - m * m) * math.sqrt(B / T),
                       4.0 * math.acos(m / 2.0))


def _golden_min(f, a: float, c: float, rtol: float = 1e-13) -> tuple[float, float]:
    """(x, f(x)): the minimum of ``f`` on [a, c] by golden-section search (f unimodal there)."""
    g = (math.sqrt(5.0) - 1.0) / 2.0
    x1, x2 = c - g * (c - a), a + g * (c - a)
    f1, f2 = f(x1), f(x2)
    while c - a > rtol * (abs(x1) + abs(x2)):
        if f1 < f2:
            c, x2, f2 = x2, x1, f1
            x1 = c - g * (c - a)
            f1 = f(x1)
        else:
            a, x1, f1 = x1, x2, f2
            x2 = a + g * (c - a)
            f2 = f(x2)
    return (x1, f1) if f1 < f2 else (x2, f2)


def greenhill_moment(B: float, L: float, T: float) -> float:
    """The critical twisting moment M_cr (N m) of a straight rod of length L (m) and bending
    stiffness B (N m^2) clamped at both ends and carrying the tension T > 0 (N) (Greenhill's
    problem with tension; T -> 0 gives M_cr L / B = 8.98682).

    Small lateral deflections w = u + i v obey B w'''' - i M w''' - T w'' = 0, so
    w = c1 + c2 s + c3 exp(l+ s) + c4 exp(l- s), l+- = (i M +- sqrt(4 B T - M^2)) / (2 B),
    with w = w' = 0 at s = 0 and L: M_cr is the least M above 2 sqrt(B T) (where l+ = l-
    and this basis degenerates) at which the 4 x 4 determinant vanishes, found as the first
    minimum of its modulus on a grid that is refined by golden-section search and accepted
    when it is below 1e-8 of the modulus's scale. NaN when none is found below
    max(40 B / L, 2.6 sqrt(B T))."""
    if not (B > 0 and L > 0 and T > 0):
        raise ValueError(f"greenhill_moment needs B, L, T > 0 (got {B}, {L}, {T})")

    def det(M):
        r = np.sqrt(complex(4.0 * B * T - M * M))
        lp, lm = (1j * M + r) / (2 * B), (1j * M - r) / (2 * B)
        ep, em = np.exp(lp * L), np.exp(lm * L)
        return abs(np.linalg.det(np.array([[1, 0, 1, 1], [0, 1, lp, lm], [1, L, ep, em],
                                           [0, 1, lp * ep, lm * em]], complex)))
    m0 = 2.0 * math.sqrt(B * T)
    Ms = np.unique(np.concatenate([  # fine just above 2 sqrt(B T) (long rods, high tension)
        m0 * np.linspace(1.0005, 1.3, 3000),
        np.linspace(m0 + 0.05 * B / L, max(40.0 * B / L, 1.3 * m0), 4000)]))
    a = np.array([det(m) for m in Ms])
    for k in range(1, len(Ms) - 1):
        if a[k] < a[k - 1] and a[k] < a[k + 1]:
            x, fx = _golden_min(det, Ms[k - 1], Ms[k + 1])
            if fx < 1e-8 * a.max():
                return float(x)
    return math.nan
