"""The study's own closed-form reference: the elastic catenary section by section (any number
of sections, weights of either sign or zero), with a flat frictionless rigid seabed, for
pinned-pinned lines and for lines with a free end. No bending, no current.

Internal force ``N(s) = (H, V(s))``: the force the part of the line beyond arc length ``s``
(unstretched, from end A) exerts on the part before it; ``dV/ds = w`` on a suspended piece,
tension ``T = |N|``, strain ``T / EA``, tangent ``N / T``. The line pulls end A with ``N(0)``
and end B with ``-N(L)``. On each piece of constant ``w`` and ``EA`` the position offsets are
closed-form (Irvine's elastic catenary), written here in forms without cancellation and
valid for ``w = 0`` (a straight bar) and ``H = 0`` (a vertical line, folded where ``V``
changes sign). The unknowns are found by root solves of one or two scalars (scipy's brentq
and hybr), each checked afterwards on the end-position residual.

Regimes:

* suspended (``H``, ``V_a``): the end B position, 2 equations; ``H = 0`` for an exactly
  vertical chord (1 equation, monotone in ``V_a``);
* grounded (anchor = the lower end on the seabed, every grounded section heavier than water):
  a grounded length ``l_g`` lies straight on the bed from the anchor with ``V = 0`` at the
  touchdown; for each ``l_g`` the height equation gives ``H`` (monotone), and the span
  equation is one bracketed scalar equation in ``l_g``; when even ``H = 0`` with a vertical
  hanging part leaves the span shorter than the grounded length, the line is fully slack
  (``H = 0``) and the grounded part's shape is not unique (it lies anywhere on the bed);
* free end: ``N(s)`` follows from the applied force, no unknown; if that hanging line would
  go through the bed and the end force has no vertical part, the free end lies on the bed and
  the suspended length is found from the height equation.
"""
from __future__ import annotations

import math

import numpy as np
from scipy.optimize import brentq, root

N_PROFILE = 2001   # samples of a reference profile


class NoReference(Exception):
    """This reference does not apply to the scene, or did not converge (message says which)."""


def piece_offsets(H: float, V0: float, w: float, EA: float, sig):
    """Offsets (dx, dz) from the start of a suspended piece to arc lengths ``sig`` in it."""
    sig = np.asarray(sig, dtype=float)
    V1 = V0 + w * sig
    T0, T1 = math.hypot(H, V0), np.hypot(H, V1)
    den = T1 + T0
    dz = np.where(den > 0, sig * (V1 + V0) / np.where(den > 0, den, 1.0), 0.0)
    dz = dz + (V0 * sig + 0.5 * w * sig * sig) / EA
    if H <= 0.0:
        return np.zeros_like(sig), dz
    same = V1 * V0 > 0
    dx = np.empty_like(sig)
    if np.any(same):
        a, s = V1[same], sig[same]
        q = s * (a + V0) / (a * T0 + V0 * T1[same])       # = asinh argument / w
        g = w * q
        small = np.abs(g) < 1e-6
        dx[same] = np.where(small, q * (1.0 - g * g / 6.0), np.arcsinh(g) / np.where(small, 1.0, w))
    other = ~same
    if np.any(other):
        if w == 0.0:  # V0 = 0 and w = 0: a horizontal bar
            dx[other] = sig[other]
        else:
            dx[other] = (np.arcsinh(V1[other] / H) - math.asinh(V0 / H)) / w
    return H * dx + H * sig / EA, dz


class Line:
    """Sections of a scene as arrays (from end A): length, w, EA; section start arc lengths."""

    def __init__(self, lengths, weights, eas):
        self.ell = np.asarray(lengths, float)
        self.w = np.asarray(weights, float)
        self.EA = np.asarray(eas, float)
        self.start = np.concatenate([[0.0], np.cumsum(self.ell)])
        self.L = float(self.start[-1])
        self.W = float(np.sum(np.abs(self.w) * self.ell))

    def reversed(self) -> "Line":
        return Line(self.ell[::-1], self.w[::-1], self.EA[::-1])

    def offsets(self, H, V_start, s, s_from=0.0):
        """Positions at arc lengths ``s`` (sorted, >= s_from) of the line suspended from
        ``s_from`` with ``N(s_from) = (H, V_start)``, relative to the point at s_from."""
        s = np.asarray(s, float)
        out = np.zeros((s.size, 2))
        x0 = z0 = 0.0
        V = V_start
        for k in range(self.ell.size):
            a, b = max(self.start[k], s_from), self.start[k + 1]
            if b <= a:
                continue
            m = (s >= a) & (s <= b)
            if np.any(m):
                dx, dz = piece_offsets(H, V, self.w[k], self.EA[k], s[m] - a)
                out[m] = np.stack([x0 + dx, z0 + dz], axis=1)
            dx, dz = piece_offsets(H, V, self.w[k], self.EA[k], np.array([b - a]))
            x0, z0, V = x0 + dx[0], z0 + dz[0], V + self.w[k] * (b - a)
        return out

    def end_offset(self, H, V_start, s_from=0.0):
        return self.offsets(H, V_start, np.array([self.L]), s_from)[0]

    def grounded_x(self, H, lg):
        """Stretched length of the grounded part [0, lg] under tension H."""
        seg = np.clip(np.minimum(self.start[1:], lg) - self.start[:-1], 0.0, None)
        return float(np.sum(seg * (1.0 + H / self.EA)))

    def profile_s(self):
        return np.unique(np.concatenate([np.linspace(0.0, self.L, N_PROFILE), self.start]))

    def V_at(self, V_start, s, s_from=0.0):
        """V(s) of the suspended line from s_from."""
        acc = np.zeros_like(np.asarray(s, float))
        for k in range(self.ell.size):
            lo = max(self.start[k], s_from)
            acc += self.w[k] * np.clip(np.minimum(s, self.start[k + 1]) - lo, 0.0, None)
        return V_start + acc


def result(line: Line, H, V_a, pos, lg=0.0, pile=False, regime="suspended", s=None):
    """The reference's answer: end forces, tensions, grounded length and profile."""
    V_b = float(line.V_at(V_a, np.array([line.L]), lg)[0])
    return {"F_A": [H, V_a], "F_B": [-H, -V_b], "T_A": math.hypot(H, V_a),
            "T_B": math.hypot(H, V_b), "grounded": lg, "pile": pile, "regime": regime,
            "profile": pos, "s": s}


# ----------------------------------------------------------------------------- pinned-pinned
def suspended(line: Line, dx: float, dz: float, guesses=()):
    """(H, V_a) of the line suspended between A (origin) and B = (dx >= 0, dz)."""
    scale = max(line.W, 1e-12)
    if line.W == 0.0:  # weightless: a straight bar if stretched, else undetermined
        d = math.hypot(dx, dz)
        strain_free = float(np.sum(line.ell / line.EA))
        T = (d - line.L) / strain_free
        if T <= 0.0:
            raise NoReference("weightless slack line: the shape is not determined")
        return T * dx / d, T * dz / d
    if dx <= 1e-12 * line.L:
        def fz(v):
            return line.end_offset(0.0, v * scale)[1] - dz
        lo, hi = -2.0, 2.0
        while fz(lo) > 0:
            lo *= 2.0
        while fz(hi) < 0:
            hi *= 2.0
        return 0.0, brentq(fz, lo, hi, xtol=1e-15, rtol=1e-14, maxiter=500) * scale

    def res(u):
        H, V = math.exp(u[0]) * scale, u[1] * scale
        off = line.end_offset(H, V)
        return [(off[0] - dx) / line.L, (off[1] - dz) / line.L]

    starts = [(math.log(max(h / scale, 1e-12)), v / scale) for h, v in guesses]
    w_eq = float(np.sum(line.w * line.ell)) / scale
    for h in (0.1, 1.0, 10.0, 0.01, 100.0):
        starts.append((math.log(h), -0.5 * w_eq + h * dz / max(dx, 1e-9 * line.L)))
    best = None
    for u0 in starts:
        sol = root(res, u0, method="hybr", options={"xtol": 1e-14, "maxfev": 4000})
        err = float(np.max(np.abs(res(sol.x))))
        if best is None or err < best[0]:
            best = (err, sol.x)
        if err < 1e-11:
            break
    if best[0] > 1e-9:
        raise NoReference(f"suspended solve: residual {best[0]:.2e} L")
    return math.exp(best[1][0]) * scale, best[1][1] * scale


def grounded(line: Line, span: float, h: float):
    """Anchor A on the bed, B at (span >= 0, h > 0) above it: (H, l_g, pile) or None if the
    line does not touch down (it leaves the anchor going up)."""
    if np.any(line.w <= 0.0):
        raise NoReference("grounded regime needs every section heavier than water")

    def height(H, lg):
        return line.end_offset(H, 0.0, lg)[1]

    # shortest suspended part that reaches h hanging vertically
    if height(0.0, 0.0) < h:
        return None
    lg_max = brentq(lambda lg: height(0.0, lg) - h, 0.0, line.L, xtol=1e-14 * line.L)
    if span <= lg_max:
        return 0.0, lg_max, True

    def H_of(lg):
        f = lambda H: height(H, lg) - h  # noqa: E731  decreasing in H
        if f(0.0) <= 0.0:   # at (or, by rounding, past) the fully slack limit
            return 0.0
        hi = line.W
        for _ in range(200):
            if f(hi) < 0:
                break
            hi *= 4.0
        else:
            raise NoReference("grounded: no bracket for H")
        return brentq(f, 0.0, hi, xtol=1e-300, rtol=1e-14)

    def fx(lg):
        H = H_of(lg)
        return line.grounded_x(H, lg) + line.end_offset(H, 0.0, lg)[0] - span

    if fx(0.0) < 0.0:   # taut enough that the line lifts off at the anchor
        return None
    lg = brentq(fx, 0.0, lg_max, xtol=1e-14 * line.L, rtol=1e-14)
    return H_of(lg), lg, False


def pinned_line(line: Line, pa, pb, depth: float | None):
    """Reference of a pinned-pinned line (pa, pb: global end positions; depth: seabed at
    z = -depth or None)."""
    pa, pb = np.asarray(pa, float), np.asarray(pb, float)
    sx = 1.0 if pb[0] >= pa[0] else -1.0
    mirror = np.array([sx, 1.0])
    dx, dz = abs(pb[0] - pa[0]), pb[1] - pa[1]
    bed_tol = 1e-9 * max(line.L, 1.0)
    if depth is not None:
        on_a, on_b = pa[1] + depth < bed_tol, pb[1] + depth < bed_tol
        if (on_a or on_b) and not (on_a and on_b):
            if on_b:  # the anchor is end B: solve the reversed line and map back
                r = pinned_line(line.reversed(), pb, pa, depth)
                return _reverse(r, line)
            g = grounded(line, dx, dz)
            if g is not None:
                H, lg, pile = g
                s = line.profile_s()
                pos = np.zeros((s.size, 2))
                on = s <= lg
                pos[on, 0] = [line.grounded_x(H, v) for v in s[on]] if not pile else np.minimum(s[on], dx)
                x_td = line.grounded_x(H, lg) if not pile else dx
                pos[~on] = line.offsets(H, 0.0, s[~on], lg) + [x_td, 0.0]
                pos = pos * mirror + pa
                r = result(line, H, 0.0, pos, lg, pile, "fully slack" if pile else "grounded", s)
                r["F_A"][0] *= sx
                r["F_B"][0] *= sx
                return r
        elif on_a and on_b and dz == 0.0:
            raise NoReference("both ends on the bed: left to the analytic catenary")
    H, V = suspended(line, dx, dz)
    s = line.profile_s()
    pos = line.offsets(H, V, s) * mirror + pa
    if depth is not None and pos[:, 1].min() < -depth - bed_tol:
        raise NoReference("suspended solution goes through the seabed (touchdown between "
                          "two ends above it: not covered)")
    r = result(line, H, V, pos, s=s, regime="vertical" if H == 0 else "suspended")
    r["F_A"][0] *= sx
    r["F_B"][0] *= sx
    return r


def _reverse(r: dict, line: Line) -> dict:
    """A result computed on the reversed line, seen from the original end A."""
    out = dict(r)
    out["F_A"], out["F_B"] = list(r["F_B"]), list(r["F_A"])
    out["T_A"], out["T_B"] = r["T_B"], r["T_A"]
    out["profile"] = r["profile"][::-1]
    out["s"] = line.L - r["s"][::-1]
    return out


# ----------------------------------------------------------------------------- free end
def free_line(line: Line, fixed_pos, free_force, free_is_b: bool, depth: float | None):
    """Reference of a line with one free end carrying ``free_force`` (N, applied on the line)."""
    if not free_is_b:
        r = free_line(line.reversed(), fixed_pos, free_force, True, depth)
        return _reverse(r, line)
    F = np.asarray(free_force, float)
    # N(L) = F; V(s) = F_z - (weight of the line beyond s); H = F_x
    H, V_a = float(F[0]), float(F[1] - np.sum(line.w * line.ell))
    sx = 1.0 if H >= 0 else -1.0
    s = line.profile_s()
    pos = line.offsets(abs(H), V_a, s) * [sx, 1.0] + np.asarray(fixed_pos, float)
    if abs(H) == 0.0 and abs(V_a) == 0.0 and line.W == 0.0:
        raise NoReference("weightless line without end force: the shape is not determined")
    if depth is None or pos[:, 1].min() >= -depth - 1e-9 * line.L:
        r = result(line, abs(H), V_a, pos, s=s, regime="hanging")
        r["F_A"][0] *= sx
        r["F_B"][0] *= sx
        return r
    if F[1] != 0.0 or np.any(line.w <= 0.0):
        raise NoReference("free end through the seabed with a vertical end force (not covered)")
    # the free end B lies on the bed: the reversed line has its anchor there with H known
    rev = line.reversed()
    h = fixed_pos[1] + depth

    def fz(lg):
        return rev.end_offset(abs(H), 0.0, lg)[1] - h
    if fz(0.0) < 0:
        raise NoReference("free end on the bed: no suspended length reaches the fixed end")
    lg = brentq(fz, 0.0, rev.L, xtol=1e-14 * rev.L)
    pile = abs(H) == 0.0
    s_rev = rev.profile_s()
    on = s_rev <= lg
    pos = np.zeros((s_rev.size, 2))
    pos[on, 0] = [rev.grounded_x(abs(H), v) for v in s_rev[on]]
    x_td = rev.grounded_x(abs(H), lg)
    pos[~on] = rev.offsets(abs(H), 0.0, s_rev[~on], lg) + [x_td, 0.0]
    # place it: the fixed end (last point) at fixed_pos, the free end on the +x side when H>0
    pos[:, 0] = -pos[:, 0]
    pos = pos * [sx, 1.0]
    pos += np.asarray(fixed_pos, float) - pos[-1]
    r = result(rev, abs(H), 0.0, pos, lg, pile, "free end on the bed", s_rev)
    r["F_A"][0] *= -sx
    r["F_B"][0] *= -sx
    return _reverse(r, line)
