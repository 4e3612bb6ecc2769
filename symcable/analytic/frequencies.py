"""Natural frequencies of strings and shallow sagged cables (closed forms, NumPy only).

* :func:`taut_string_frequencies` -- the transverse modes of a taut string.
* :func:`sagged_cable_frequencies` -- the in-plane modes of a shallow elastic cable hung
  between level supports, from the linear theory of Irvine & Caughey (1974), as written in
  Irvine, *Cable Structures* (MIT Press 1981; Dover 1992), section 3.2.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .catenary import _check_positive
from .special import _brentq

#: sag/span above which the shallow-cable theory is out of its range (Irvine: "about 1:8")
SHALLOW_SAG_RATIO = 1.0 / 8.0


def _check_count(n) -> int:
    if isinstance(n, bool) or int(n) != n or n < 1:
        raise ValueError(f"n = {n!r}: must be an integer >= 1")
    return int(n)


def taut_string_frequencies(tension: float, length: float, mass_per_length: float,
                            n: int) -> np.ndarray:
    """Transverse natural frequencies of a taut string fixed at both ends.

    ``f_k = k / (2 L) * sqrt(T / m)`` for ``k = 1..n``.

    Parameters
    ----------
    tension : float
        Tension T, N (> 0).
    length : float
        Length L between the supports, m (> 0). For an elastic string pulled to tension T
        this is the stretched length, and ``mass_per_length`` the mass per stretched length.
    mass_per_length : float
        Mass per length m, kg/m (> 0), including any added mass of the transverse motion.
    n : int
        Number of modes (>= 1).

    Returns
    -------
    numpy.ndarray, shape (n,)
        Frequencies, Hz, ascending.
    """
    T = _check_positive("tension", tension)
    L = _check_positive("length", length)
    m = _check_positive("mass_per_length", mass_per_length)
    k = np.arange(1, _check_count(n) + 1, dtype=float)
    return k / (2.0 * L) * math.sqrt(T / m)


@dataclass(frozen=True)
class SaggedCableFrequencies:
    """In-plane natural frequencies of a shallow sagged cable (Irvine & Caughey 1974).

    Attributes
    ----------
    antisymmetric : numpy.ndarray, shape (n,)
        Frequencies of the antisymmetric modes, Hz, ascending: ``k/(2 l) sqrt(H/m)`` for
        ``k = 2, 4, ..., 2n``. They do not stretch the cable, so they do not depend on EA.
    symmetric : numpy.ndarray, shape (n,)
        Frequencies of the symmetric modes, Hz, ascending.
    symmetric_beta : numpy.ndarray, shape (n,)
        Their nondimensional roots ``beta = omega l / sqrt(H/m)``, -.
    frequencies : numpy.ndarray, shape (2n,)
        Both families merged, Hz, ascending.
    kinds : tuple of str, length 2n
        ``"symmetric"`` or ``"antisymmetric"`` for each entry of ``frequencies``.
    lambda_squared : float
        Irvine's parameter ``lambda^2 = (w l / H)^2 l / (H L_e / EA)``, -.
    sag : float
        Mid-span sag of the parabolic profile ``d = w l^2 / (8 H)``, m.
    effective_length : float
        ``L_e = l (1 + 8 (d/l)^2)``, m (the parabola's ``int (ds/dx)^3 dx`` to that order).
    """

    antisymmetric: np.ndarray
    symmetric: np.ndarray
    symmetric_beta: np.ndarray
    frequencies: np.ndarray
    kinds: tuple
    lambda_squared: float
    sag: float
    effective_length: float


def _symmetric_roots(lambda2: float, n: int) -> np.ndarray:
    """The first n positive roots beta of tan(beta/2) = beta/2 - (4/lambda^2) (beta/2)^3.

    With x = beta/2 the equation times cos x is h(x) = sin x - (x - 4 x^3/lambda^2) cos x = 0,
    which has no poles. g(x) = tan x - x + 4 x^3/lambda^2 has g' = tan^2 x + 12 x^2/lambda^2
    > 0 and g(0) = 0, so there is no root in (0, pi/2) and exactly one on each branch
    ((2k-1) pi/2, (2k+1) pi/2) of tan, where h changes sign between the ends (h = sin x there).
    """
    out = np.empty(n)
    for k in range(1, n + 1):
        a, b = (2 * k - 1) * math.pi / 2, (2 * k + 1) * math.pi / 2
        if lambda2 == 0.0:              # taut-string limit: the root tends to the branch's start
            out[k - 1] = 2 * a
            continue
        c = 0.0 if math.isinf(lambda2) else 4.0 / lambda2

        def h(x, c=c):
            return math.sin(x) - (x - c * x ** 3) * math.cos(x)

        x, _ = _brentq(h, a, b, h(a), h(b), xtol=1e-15, rtol=4e-16, max_iter=200,
                       what=f"symmetric cable mode {k}")
        out[k - 1] = 2.0 * x
    return out


def sagged_cable_frequencies(span: float, horizontal_tension: float, weight_per_length: float,
                             mass_per_length: float, EA: float, n: int) -> SaggedCableFrequencies:
    """In-plane natural frequencies of a shallow elastic cable between level supports.

    The linear theory of Irvine & Caughey (1974) (Irvine, *Cable Structures*, 1981, sec. 3.2):
    small in-plane motion about the parabolic static profile of a cable of span ``l``,
    horizontal tension ``H`` and weight ``w`` per length, sag ``d = w l^2 / (8 H)``.

    * Antisymmetric modes carry no additional tension to first order (the cable does not
      stretch): ``omega l / sqrt(H/m) = 2 k pi``, the even modes of the taut string,
      ``f = k/(2 l) sqrt(H/m)``, ``k = 2, 4, ...``.
    * Symmetric modes stretch the cable and add the tension ``h``; with
      ``beta = omega l / sqrt(H/m)`` they solve

          tan(beta/2) = beta/2 - (4/lambda^2) (beta/2)^3,
          lambda^2 = (w l / H)^2 l / (H L_e / EA),  L_e = l (1 + 8 (d/l)^2),

      so ``f = beta/(2 pi l) sqrt(H/m)``. As ``lambda^2 -> 0`` (taut string) beta -> pi, 3pi,
      ...; as ``lambda^2 -> inf`` (inextensible chain) tan(beta/2) = beta/2, beta_1 = 8.987.
      The first symmetric mode crosses the first antisymmetric one at ``lambda^2 = 4 pi^2``.

    Assumptions: level supports; a shallow profile (sag/span below about 1/8, Irvine's limit
    for the parabola), so the mass and weight per span length equal those per cable length
    and the static tension equals H everywhere -- the neglected terms are of order
    (sag/span)^2; linear elasticity; no bending stiffness; motion in the plane of the cable.

    Parameters
    ----------
    span : float
        Horizontal distance l between the supports, m (> 0).
    horizontal_tension : float
        Static horizontal tension H, N (> 0).
    weight_per_length : float
        Weight w per cable length, N/m (> 0; the submerged weight in water).
    mass_per_length : float
        Mass m per cable length, kg/m (> 0), including the added mass of the in-plane
        motion when in water (the theory has one m for both directions).
    EA : float
        Axial stiffness, N (> 0; ``math.inf`` for an inextensible cable).
    n : int
        Number of modes of each family (>= 1).

    Returns
    -------
    SaggedCableFrequencies

    Raises
    ------
    ValueError
        On a non-positive input, or a sag/span above 1/8 (out of the theory's range).
    """
    l = _check_positive("span", span)
    H = _check_positive("horizontal_tension", horizontal_tension)
    w = _check_positive("weight_per_length", weight_per_length)
    m = _check_positive("mass_per_length", mass_per_length)
    EA = float(EA)
    if math.isnan(EA) or EA <= 0.0:
        raise ValueError(f"EA = {EA!r}: must be > 0 (math.inf for an inextensible cable)")
    n = _check_count(n)
    d = w * l ** 2 / (8.0 * H)
    if d / l > SHALLOW_SAG_RATIO:
        raise ValueError(f"sag/span = {d / l:.4g} (w l / (8 H) with w = {w:g} N/m, l = {l:g} m, "
                         f"H = {H:g} N): the shallow-cable theory needs sag/span <= 1/8")
    Le = l * (1.0 + 8.0 * (d / l) ** 2)
    lam2 = (w * l / H) ** 2 * l * EA / (H * Le) if math.isfinite(EA) else math.inf
    c = math.sqrt(H / m) / l                      # rad/s per unit beta
    k = np.arange(1, n + 1, dtype=float)
    anti = 2.0 * k * math.pi * c / (2.0 * math.pi)
    beta = _symmetric_roots(lam2, n)
    sym = beta * c / (2.0 * math.pi)
    allf = np.concatenate([sym, anti])
    kinds = np.array(["symmetric"] * n + ["antisymmetric"] * n)
    order = np.argsort(allf, kind="stable")
    return SaggedCableFrequencies(antisymmetric=anti, symmetric=sym, symmetric_beta=beta,
                                  frequencies=allf[order], kinds=tuple(kinds[order].tolist()),
                                  lambda_squared=lam2, sag=d, effective_length=Le)
