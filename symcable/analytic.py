"""Closed-form and semi-analytic reference solutions (oracles for the tests and studies).

Everything here uses only NumPy and the standard library: the special functions (Carlson's
symmetric elliptic integrals) and the root finders (a damped 2x2 Newton, Brent's method) are
written out, so that the oracles do not share code with the solvers they check.

Contents
--------
* :func:`elastic_catenary` -- Irvine's elastic catenary between two points in a vertical
  plane, optionally touching down on a flat frictionless seabed at the level of end A.
* :func:`cantilever_tip_load` -- the inextensible elastica of a cantilever under a dead tip
  load (Bisshopp & Drucker 1945), in incomplete elliptic integrals.
* :func:`cantilever_tip_load_small`, :func:`heavy_cantilever_small` -- linear beam theory.
* :func:`carlson_rf`, :func:`carlson_rd`, :func:`elliptic_f`, :func:`elliptic_e` -- the
  special functions these need.

Conventions (``design.md``): SI units, planar (x, z) with z up, arc length ``s`` is the
unstretched length measured from end A (origin) to end B.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable

import numpy as np

from .errors import ConvergenceError

__all__ = [
    "CatenarySolution",
    "elastic_catenary",
    "cantilever_tip_load",
    "cantilever_tip_load_small",
    "heavy_cantilever_small",
    "carlson_rf",
    "carlson_rd",
    "elliptic_f",
    "elliptic_e",
]

_EPS = np.finfo(float).eps
#: spans below this fraction of the length are treated as exactly vertical lines (H = 0)
VERTICAL_SPAN_RATIO = 1e-9


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


# --------------------------------------------------------------------------------------------
# Elastic catenary
# --------------------------------------------------------------------------------------------

def _asinh_diff(v1, v0, h, dv):
    """asinh(v1/h) - asinh(v0/h) without cancellation; h >= 0, dv = v1 - v0 >= 0 (arrays).

    For v0, v1 of one sign, sinh(A - B) = a sqrt(1+b^2) - b sqrt(1+a^2) rationalised gives
    asinh(dv (v1 + v0) / (v1 S0 + v0 S1)), S = sqrt(h^2 + v^2): no difference of large
    numbers. The difference dv is passed exactly (w * sigma), because v1 - v0 recomputed from
    a large v0 would lose digits. For opposite signs the plain difference is a sum of terms
    of one sign. Where h = 0 and the signs differ the value is infinite; callers multiply it
    by h (-> 0) and never use it.
    """
    v1, v0, h, dv = np.broadcast_arrays(v1, v0, h, dv)
    s1 = np.hypot(h, v1)
    s0 = np.hypot(h, v0)
    same = v1 * v0 > 0.0
    out = np.zeros(v1.shape)
    if np.any(same):
        a, b = v1[same], v0[same]
        out[same] = np.arcsinh(dv[same] * (a + b) / (a * s0[same] + b * s1[same]))
    other = ~same & (h > 0.0)
    if np.any(other):
        out[other] = np.arcsinh(v1[other] / h[other]) - np.arcsinh(v0[other] / h[other])
    return out


def _suspended_xz(H, V0, w, EA, sigma):
    """Position of a suspended elastic catenary piece relative to its start.

    Parameters
    ----------
    H : float
        Horizontal tension, N (>= 0; H = 0 is a vertical line).
    V0 : float
        Vertical internal force at the start of the piece (along increasing s), N.
    w : float
        Weight per unstretched length, N/m.
    EA : float
        Axial stiffness, N.
    sigma : numpy.ndarray, shape (n,)
        Unstretched arc length from the start of the piece, m (>= 0).

    Returns
    -------
    x, z : numpy.ndarray, shape (n,) each
        Horizontal and vertical offsets from the start of the piece, m.
    """
    sigma = np.asarray(sigma, dtype=float)
    v1 = V0 + w * sigma
    s0 = math.hypot(H, V0)
    s1 = np.hypot(H, v1)
    # (S1 - S0)/w = sigma (V1 + V0)/(S1 + S0): stable, and continuous down to H = 0
    den = s1 + s0
    geo_z = np.where(den > 0.0, sigma * (v1 + V0) / np.where(den > 0.0, den, 1.0), 0.0)
    z = geo_z + (V0 * sigma + 0.5 * w * sigma ** 2) / EA
    if H > 0.0:
        x = H * sigma / EA + (H / w) * _asinh_diff(v1, V0, H, w * sigma)
    else:
        x = np.zeros_like(sigma)
    return x, z


@dataclass(frozen=True)
class CatenarySolution:
    """Static shape and forces of an elastic catenary between end A (origin) and end B.

    Attributes
    ----------
    span : float
        Horizontal distance from A to B, m (>= 0).
    height : float
        Height of B above A, m.
    length : float
        Unstretched length L, m.
    EA : float
        Axial stiffness, N.
    weight : float
        Submerged weight per unstretched length w, N/m.
    H : float
        Horizontal component of the line tension, N (constant along the line, >= 0).
    V_a : float
        Vertical component of the internal force at end A, taken along increasing arc length,
        N: on the suspended part V(s) = V_a + w (s - grounded_length). Negative when the line
        leaves A going down; 0 when the line touches down. Equals MoorPy's ``info['VA']``
        (and its returned ``fAV``).
    V_b : float
        The same at end B (s = L), N: ``V_b = V_a + w (L - grounded_length)``; the line pulls
        end B with (-H, -V_b). Equals MoorPy's ``info['VF']`` (= ``-fBV``).
    grounded_length : float
        Unstretched length lying on the seabed from end A, m (0 if fully suspended).
    """

    span: float
    height: float
    length: float
    EA: float
    weight: float
    H: float
    V_a: float
    V_b: float
    grounded_length: float

    @property
    def anchor_tension(self) -> float:
        """Magnitude of the line force at end A, ``sqrt(H^2 + V_a^2)``, N."""
        return math.hypot(self.H, self.V_a)

    @property
    def fairlead_tension(self) -> float:
        """Magnitude of the line force at end B, ``sqrt(H^2 + V_b^2)``, N (MoorPy's ``TB``)."""
        return math.hypot(self.H, self.V_b)

    def _arc(self, s) -> np.ndarray:
        s = np.atleast_1d(np.asarray(s, dtype=float))
        if s.ndim != 1:
            raise ValueError(f"s must be a scalar or a 1-D array, got shape {s.shape}")
        slack = 1e-12 * self.length
        if np.any(s < -slack) or np.any(s > self.length + slack):
            raise ValueError(f"s must lie in [0, L = {self.length} m]; got values in "
                             f"[{s.min()}, {s.max()}]")
        return np.clip(s, 0.0, self.length)

    def _vertical_force(self, s: np.ndarray) -> np.ndarray:
        return self.V_a + self.weight * np.maximum(s - self.grounded_length, 0.0)

    def positions(self, s) -> np.ndarray:
        """Node positions relative to end A.

        Parameters
        ----------
        s : array_like, shape (n,)
            Unstretched arc lengths from end A, m, in [0, L].

        Returns
        -------
        numpy.ndarray, shape (n, 2)
            (x, z) of each point, m. The grounded part lies on z = 0, stretched by H/EA. When
            the line is slack on the seabed (H = 0 with grounded length), the excess length is
            piled at the foot of end B (x = span), as MoorPy does. A line treated as vertical
            (span < 1e-9 L) gets x = span * s / L.
        """
        s = self._arc(s)
        lb, H, w, EA = self.grounded_length, self.H, self.weight, self.EA
        out = np.zeros((s.size, 2))
        if lb <= 0.0:
            x, z = _suspended_xz(H, self.V_a, w, EA, s)
            if H == 0.0:
                x = self.span * s / self.length
            out[:, 0], out[:, 1] = x, z
            return out
        on_ground = s <= lb
        if H > 0.0:
            x_td = lb * (1.0 + H / EA)
            out[on_ground, 0] = s[on_ground] * (1.0 + H / EA)
        else:
            x_td = self.span
            out[on_ground, 0] = np.minimum(s[on_ground], self.span)
        x, z = _suspended_xz(H, 0.0, w, EA, s[~on_ground] - lb)
        out[~on_ground, 0] = x_td + x
        out[~on_ground, 1] = z
        return out

    def tension(self, s) -> np.ndarray:
        """Magnitude of the internal force ``sqrt(H^2 + V(s)^2)``, N.

        Parameters
        ----------
        s : array_like, shape (n,)
            Unstretched arc lengths from end A, m, in [0, L].

        Returns
        -------
        numpy.ndarray, shape (n,)
        """
        s = self._arc(s)
        return np.hypot(self.H, self._vertical_force(s))

    def angle(self, s) -> np.ndarray:
        """Tangent angle ``atan2(V(s), H)`` from the +x axis, rad (0 on the seabed).

        Continuous whenever H > 0; a vertical slack line (H = 0) jumps from -pi/2 to pi/2 at
        its lowest point.

        Parameters
        ----------
        s : array_like, shape (n,)
            Unstretched arc lengths from end A, m, in [0, L].

        Returns
        -------
        numpy.ndarray, shape (n,)
        """
        s = self._arc(s)
        return np.arctan2(self._vertical_force(s), self.H)

    def strain(self, s) -> np.ndarray:
        """Axial strain ``tension(s) / EA`` (dimensionless).

        Parameters
        ----------
        s : array_like, shape (n,)
            Unstretched arc lengths from end A, m, in [0, L].

        Returns
        -------
        numpy.ndarray, shape (n,)
        """
        return self.tension(s) / self.EA


def _check_positive(name: str, value: float) -> float:
    value = float(value)
    if not math.isfinite(value) or value <= 0.0:
        raise ValueError(f"{name} = {value!r}: must be a finite number > 0")
    return value


def _vertical_va(z: float, c: float) -> float:
    """Nondimensional V_a of an exactly vertical line (H = 0) reaching height z (in units of L).

    z(L) = int sign(V) ds + (V_a L + w L^2 / 2)/EA, with V = V_a + w s: piecewise linear in
    V_a, solved branch by branch (taut upwards, U-shaped, taut downwards).
    """
    # (clamped: z - 1 carries a rounding error amplified by 1/c, and a V_a of the wrong
    # sign would fold the line and move its end by 2 |V_a| L / (w L))
    if z >= 1.0 + 0.5 * c:
        return max((z - 1.0) / c - 0.5, 0.0)
    if z <= -1.0 - 0.5 * c:
        return min((z + 1.0) / c - 0.5, -1.0)
    return (z - 1.0 - 0.5 * c) / (2.0 + c)


def _suspended_residual(u: float, va: float, x: float, z: float, c: float):
    """Residual (nondimensional, lengths / L) and Jacobian wrt (log h, va) of the free catenary."""
    h = math.exp(u)
    vb = va + 1.0
    sa, sb = math.hypot(h, va), math.hypot(h, vb)
    d = float(_asinh_diff(np.array([vb]), np.array([va]), np.array([h]), np.array([1.0]))[0])
    big_x = h * c + h * d
    big_z = c * (va + 0.5) + (vb + va) / (sa + sb)
    r = np.array([big_x - x, big_z - z])
    # 1/Sb - 1/Sa and vb/Sb - va/Sa in cancellation-free forms
    # (vb - va = 1 exactly; recomputing it from a large va would lose digits)
    inv_diff = -(va + vb) / ((sa + sb) * sa * sb)
    if va * vb > 0.0:
        ratio_diff = h * h * (vb + va) / ((vb * sa + va * sb) * sa * sb)
    else:
        ratio_diff = vb / sb - va / sa
    dx_dh = c + d - ratio_diff
    dx_dva = h * inv_diff
    dz_dh = h * inv_diff
    dz_dva = c + ratio_diff
    jac = np.array([[h * dx_dh, dx_dva], [h * dz_dh, dz_dva]])
    return r, jac


def _newton_suspended(x, z, c, guesses, tol, max_iter):
    """Damped Newton on (log h, va); tries each initial guess in turn."""
    attempts = []
    for h0, va0 in guesses:
        u, va = math.log(max(h0, 1e-300)), float(va0)
        history = []
        try:
            r, jac = _suspended_residual(u, va, x, z, c)
        except (OverflowError, ValueError):
            attempts.append({"guess": (h0, va0), "history": history, "reason": "bad guess"})
            continue
        reason = "max_iter reached"
        for it in range(max_iter + 1):
            nr = float(np.max(np.abs(r)))
            history.append(nr)
            if not math.isfinite(nr):
                reason = "non-finite residual"
                break
            if nr <= tol:
                return math.exp(u), va, it, attempts
            if it == max_iter:
                break
            try:
                step = np.linalg.solve(jac, -r)
            except np.linalg.LinAlgError:
                reason = "singular Jacobian"
                break
            if not np.all(np.isfinite(step)):
                reason = "non-finite Newton step"
                break
            # keep h within a factor e^2 per step and va within a sensible range
            scale = min(1.0, 2.0 / max(abs(step[0]), 1e-300),
                        max(1.0, 2.0 * abs(va)) / max(abs(step[1]), 1e-300))
            step = step * scale
            merit = float(np.hypot(*r))
            alpha = 1.0
            accepted = False
            while alpha > 1e-12:
                u_new, va_new = u + alpha * step[0], va + alpha * step[1]
                try:
                    r_new, jac_new = _suspended_residual(u_new, va_new, x, z, c)
                except (OverflowError, ValueError):
                    r_new = None
                if r_new is not None and np.all(np.isfinite(r_new)) and \
                        float(np.hypot(*r_new)) <= (1.0 - 1e-4 * alpha) * merit:
                    accepted = True
                    break
                alpha *= 0.5
            if not accepted:
                # At round-off level no descent is possible; accept if close enough.
                if nr <= max(tol, 1e3 * _EPS * (1.0 + abs(x) + abs(z))):
                    return math.exp(u), va, it, attempts
                reason = "line search failed"
                break
            u, va, r, jac = u_new, va_new, r_new, jac_new
        attempts.append({"guess": (h0, va0), "history": history, "reason": reason,
                         "last": (math.exp(u), va)})
    raise ConvergenceError(
        f"elastic_catenary: Newton did not converge from {len(guesses)} initial guesses "
        f"(span/L = {x:g}, height/L = {z:g}, wL/EA = {c:g})",
        diagnostics={"attempts": attempts, "units": "forces / (w L), residuals / L"})


def _free_xz(h: float, va: float, c: float) -> tuple[float, float]:
    """Nondimensional end position (X, Z) / L of a free catenary with forces (h, va) / (w L)."""
    vb = va + 1.0
    sa, sb = math.hypot(h, va), math.hypot(h, vb)
    d = float(_asinh_diff(np.array([vb]), np.array([va]), np.array([h]), np.array([1.0]))[0])
    return h * c + h * d, c * (va + 0.5) + (vb + va) / (sa + sb)


def _nested_suspended(x: float, z: float, c: float, h_start: float, max_iter: int):
    """Fallback for the free catenary: two nested bracketed scalar solves.

    For fixed h, Z is increasing in va (dZ/dva = c + vb/Sb - va/Sa > 0), bracketed by
    va = (z -+ 1)/c - 1/2 since |Z - c (va + 1/2)| < 1. With va(h) so defined, X is
    increasing in h (the flexibility matrix is symmetric positive definite, so its Schur
    complement dX/dh at fixed Z is positive). Slower than Newton but cannot wander off, which
    matters for nearly inextensible lines whose chord is close to their length, where the
    Newton iteration crawls along a narrow curved valley.
    """
    n_eval = [0]

    def va_of(h):
        def fz(va):
            n_eval[0] += 1
            return _free_xz(h, va, c)[1] - z
        lo, hi = (z - 1.0) / c - 0.5, (z + 1.0) / c - 0.5
        va, _ = _brentq(fz, lo, hi, fz(lo), fz(hi), xtol=1e-300, rtol=4.0 * _EPS,
                        max_iter=max_iter, what="elastic_catenary (va for fixed H)")
        return va

    def fx(u):
        h = math.exp(u)
        return _free_xz(h, va_of(h), c)[0] - x

    u_min, u_max = math.log(1e-300), math.log(1e300)
    u0 = min(max(math.log(h_start), u_min), u_max)
    f0 = fx(u0)
    step = 2.0 if f0 < 0.0 else -2.0
    u1, f1 = u0, f0
    while (f1 < 0.0) == (f0 < 0.0) and f1 != 0.0:
        u0, f0 = u1, f1
        u1 = min(max(u1 + step, u_min), u_max)
        if u1 == u0:
            raise ConvergenceError("elastic_catenary: could not bracket H",
                                   diagnostics={"u": u1, "f": f1})
        f1 = fx(u1)
        step *= 2.0
    u, _ = _brentq(fx, u0, u1, f0, f1, xtol=1e-300, rtol=4.0 * _EPS,
                   max_iter=max_iter, what="elastic_catenary (H)")
    h = math.exp(u)
    return h, va_of(h), n_eval[0]


def _initial_guesses(x: float, z: float, c: float) -> list[tuple[float, float]]:
    """Starting (h, va) for the free catenary, nondimensional (forces / wL, lengths / L)."""
    d = math.hypot(x, z)
    guesses = []
    # Jonkman (FAST v7) / Peyrot & Goulois (1979): lambda0 = 0.2 if taut, else from a parabola
    lam = 0.2 if d >= 1.0 else math.sqrt(3.0 * ((1.0 - z * z) / (x * x) - 1.0))
    lam = max(lam, 1e-6)
    h_j = max(0.5 * x / lam, 1e-12)
    vb_j = 0.5 * (z / math.tanh(lam) + 1.0)
    if d > 1.0:
        # straight elastic bar carrying T0 = EA (d/L - 1), half the weight at each end
        t0 = (d - 1.0) / c
        h_s, va_s = max(t0 * x / d, h_j), t0 * z / d - 0.5
        guesses.append((h_s, va_s))
    guesses.append((h_j, vb_j - 1.0))
    guesses.append((max(x, 1e-6), 0.5 * z - 0.5))
    return guesses


def _grounded_xs(l: float, z: float, c: float) -> tuple[float, float]:
    """(h, X) for suspended length l (units of L) with the touchdown at V = 0, height z exact.

    The height equation c l^2/2 + sqrt(h^2 + l^2) - h = z gives h explicitly:
    with q = z - c l^2/2 (> 0), h = (l^2 - q^2) / (2 q).
    """
    q = z - 0.5 * c * l * l
    h = max((l - q) * (l + q) / (2.0 * q), 0.0)
    geo = h * math.asinh(l / h) if h > 0.0 else 0.0
    return h, (1.0 - l) + h * c + geo


def elastic_catenary(span: float, height: float, length: float, EA: float, weight: float, *,
                     seabed: bool = False, tol: float = 1e-12,
                     max_iter: int = 100) -> CatenarySolution:
    """Elastic catenary (Irvine 1981) from end A at the origin to end B at (span, height).

    The suspended part obeys, with V(s) = V_a + w s and s the unstretched arc length,
    ``x(s) = H s/EA + (H/w)[asinh(V/H) - asinh(V_a/H)]``,
    ``z(s) = (w s^2/2 + V_a s)/EA + (H/w)[sqrt(1 + (V/H)^2) - sqrt(1 + (V_a/H)^2)]``.
    The free line solves x(L) = span, z(L) = height for (H, V_a) by a damped Newton method in
    (log H, V_a) with the analytic Jacobian, started from a straight elastic bar (taut lines)
    and from Jonkman's / Peyrot's guess, each tried in turn.

    With ``seabed=True`` a flat frictionless seabed lies at z = 0 (the level of end A). If the
    free solution has V_a >= 0 it is the answer; otherwise a grounded length L_B lies on
    z = 0 from A (stretched by H/EA) and the suspended rest starts with V = 0. The height
    equation then gives H explicitly from the suspended length, and the span equation is one
    bracketed scalar equation solved by Brent's method. If the line is longer than the "L"
    shape (along the seabed, then hanging vertically to B) it is fully slack: H = 0 and the
    excess length is piled at the foot of B (MoorPy's profile 4).

    Special cases: span < 1e-9 L is an exactly vertical line (H = 0, closed form: taut, or
    U-shaped, or piled on the seabed); height = 0 on the seabed is a line lying flat
    (H = EA (span/L - 1) if it is stretched, else 0).

    Parameters
    ----------
    span : float
        Horizontal distance from A to B, m; must be >= 0 (mirror a negative span yourself:
        x -> -x leaves H, V_a, V_b unchanged).
    height : float
        Height of B above A, m (>= 0 when ``seabed``).
    length : float
        Unstretched length L, m (> 0).
    EA : float
        Axial stiffness, N (> 0).
    weight : float
        Submerged weight per unstretched length w, N/m (> 0).
    seabed : bool, optional
        Flat frictionless seabed at the level of end A.
    tol : float, optional
        Convergence tolerance on the end-position residual divided by L.
    max_iter : int, optional
        Maximum iterations of the Newton or Brent iteration.

    Returns
    -------
    CatenarySolution

    Raises
    ------
    ValueError
        On invalid input.
    ConvergenceError
        If the iteration does not converge; ``diagnostics`` holds the residual history of
        each attempt.
    """
    length = _check_positive("length", length)
    EA = _check_positive("EA", EA)
    weight = _check_positive("weight", weight)
    span, height = float(span), float(height)
    if not (math.isfinite(span) and math.isfinite(height)):
        raise ValueError(f"span = {span!r}, height = {height!r}: must be finite")
    if span < 0.0:
        raise ValueError(f"span = {span} m: must be >= 0 (mirror the geometry: x -> -x)")
    if seabed and height < 0.0:
        raise ValueError(f"height = {height} m: must be >= 0 with seabed=True "
                         f"(the seabed is at the level of end A)")
    if int(max_iter) < 1:
        raise ValueError(f"max_iter = {max_iter!r}: must be >= 1")
    if not tol > 0.0:
        raise ValueError(f"tol = {tol!r}: must be > 0")

    wl = weight * length
    x, z, c = span / length, height / length, wl / EA

    def make(h, va, lb):
        ls = 1.0 - lb
        return CatenarySolution(span=span, height=height, length=length, EA=EA, weight=weight,
                                H=float(h * wl), V_a=float(va * wl), V_b=float((va + ls) * wl),
                                grounded_length=float(lb * length))

    def free():
        if x < VERTICAL_SPAN_RATIO:
            return make(0.0, _vertical_va(z, c), 0.0)
        guesses = _initial_guesses(x, z, c)
        try:
            h, va, _, _ = _newton_suspended(x, z, c, guesses, tol, max_iter)
            return make(h, va, 0.0)
        except ConvergenceError as err:
            newton_diag = err.diagnostics
        # Robust but slower route, then Newton again from its answer to polish it.
        try:
            h, va, _ = _nested_suspended(x, z, c, guesses[0][0], max_iter)
        except ConvergenceError as err:
            raise ConvergenceError(
                f"elastic_catenary: no convergence (span = {span} m, height = {height} m, "
                f"L = {length} m, wL/EA = {c:g}); Newton and the bracketed fallback failed",
                diagnostics={"newton": newton_diag, "fallback": err.diagnostics}) from err
        try:
            h, va, _, _ = _newton_suspended(x, z, c, [(h, va)], tol, max_iter)
        except ConvergenceError:
            big_x, big_z = _free_xz(h, va, c)
            resid = max(abs(big_x - x), abs(big_z - z))
            if resid > max(tol, 1e3 * _EPS * (1.0 + x + abs(z))):
                raise ConvergenceError(
                    f"elastic_catenary: no convergence (residual {resid * length:g} m after "
                    "the bracketed fallback)",
                    diagnostics={"newton": newton_diag,
                                 "fallback": {"H": h * wl, "V_a": va * wl,
                                              "residual_over_L": resid}}) from None
        return make(h, va, 0.0)

    if not seabed:
        return free()

    if z == 0.0:  # lying flat on the seabed
        return make(max(x - 1.0, 0.0) / c, 0.0, 1.0)
    q1 = z - 0.5 * c  # height reached by the inextensible part with V_a = 0
    if q1 >= 1.0:  # even hanging straight with V_a = 0 falls short: taut, V_a >= 0
        return free()
    # shortest suspended length: hanging vertically, c l^2/2 + l = z
    l_min = 2.0 * z / (1.0 + math.sqrt(1.0 + 2.0 * c * z))
    if x <= 1.0 - l_min:  # fully slack, longer than the "L" shape
        return make(0.0, 0.0, 1.0 - l_min)
    if q1 > 0.0:
        h1 = (1.0 - q1) * (1.0 + q1) / (2.0 * q1)
        if x >= h1 * c + h1 * math.asinh(1.0 / h1):  # touchdown at A or beyond: free line
            return free()
        l_hi = 1.0
    else:
        # h -> infinity as l -> sqrt(2 z / c) (<= 1): march towards it until X > span
        l_up = math.sqrt(2.0 * z / c)
        gap = 0.5 * (l_up - l_min)
        l_hi = l_up - gap
        for _ in range(200):
            if _grounded_xs(l_hi, z, c)[1] > x:
                break
            gap *= 0.25
            l_hi = l_up - gap
        else:  # pragma: no cover
            raise ConvergenceError("elastic_catenary: could not bracket the touchdown",
                                   diagnostics={"l_min": l_min, "l_up": l_up})

    def f(l):
        return _grounded_xs(l, z, c)[1] - x

    l_root, _ = _brentq(f, l_min, l_hi, f(l_min), f(l_hi), xtol=1e-300, rtol=4.0 * _EPS,
                        max_iter=max_iter, what="elastic_catenary (grounded)")
    resid = abs(f(l_root))
    if resid > max(tol, 1e3 * _EPS * (1.0 + x)):
        raise ConvergenceError(
            f"elastic_catenary: grounded solve stopped with span residual {resid * length:g} m",
            diagnostics={"suspended_fraction": l_root, "residual_over_L": resid})
    h, _ = _grounded_xs(l_root, z, c)
    return make(h, 0.0, 1.0 - l_root)


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
