"""Irvine's elastic catenary between two points in a vertical plane, optionally touching
down on a flat frictionless seabed at the level of end A."""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import ConvergenceError
from .special import _EPS, _brentq

#: spans below this fraction of the length are treated as exactly vertical lines (H = 0)
VERTICAL_SPAN_RATIO = 1e-9


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
