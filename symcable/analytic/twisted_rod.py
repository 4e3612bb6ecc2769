"""The localized loop of an infinite twisted rod under tension (Love's homoclinic solution;
Coyne 1990, Thompson & Champneys 1996): the oracle of the looped shapes that
:func:`symcable.trace_branch` reaches (studies/hybrid/loop.py).

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
