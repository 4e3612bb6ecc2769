"""The study's numerical reference: the cable equations integrated along the line by scipy's
``solve_ivp`` (DOP853), with a root solve (``scipy.optimize.root``, hybr) on the end
conditions (shooting). Covers what the closed forms do not: a steady current (Morison drag on
the line at rest, the law of ``symcable.models.common.terms.morison_drag``: per unstretched length
``0.5 rho d Cd |u| u sqrt(1 + strain)`` on the tangential and normal components of the
current), any number of sections, and free ends. No bending, no seabed contact: a solution
that goes through the seabed, or whose tension vanishes somewhere (a slack fold, where the
tangent is undefined), is not a reference.

State along the unstretched arc length s: position r = (x, z) and internal force N (the
force the part beyond s exerts on the part before); tension T = |N|, tangent t = N / T,
strain T / EA, and

    dr/ds = (1 + T/EA) t,        dN/ds = -f(t, T),   f = (0, -w) + drag.

Pinned-pinned: unknown N(0), 2 equations r(L) = r_B. A free end: N is known there (the
applied force), so the line is integrated from the free end to the fixed one, no unknown;
with no end force the tangent at the free end is the direction of the distributed load there
(found by a fixed-point iteration), and the integration starts a small distance in.
"""
from __future__ import annotations

import math

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import root

from fuzz_catenary import N_PROFILE, NoReference

RTOL, ATOL_REL = 1e-11, 1e-12


class Cable:
    """Sections (from end A) with weight, stiffness and drag, and the current; in the plane
    (``DIM`` = 2: x, z), or in 3D by :class:`fuzz_ode3d.Cable3`, which gives its own
    :meth:`load` and :meth:`norm`."""

    DIM = 2

    def __init__(self, secs: list[dict], rho: float, current):
        self.secs = secs          # each: length, w, EA, d, cdn, cdt
        self.rho = rho
        self.U = np.asarray(current, float) if rho > 0 else np.zeros(self.DIM)
        self.start = np.concatenate([[0.0], np.cumsum([s["length"] for s in secs])])
        self.L = float(self.start[-1])
        self.W = float(sum(abs(s["w"]) * s["length"] for s in secs))
        self.drag = bool(np.any(self.U != 0.0))

    def load(self, sec: dict, t: np.ndarray, T: float) -> np.ndarray:
        """Distributed load per unstretched length on a piece with unit tangent t, N/m."""
        f = np.array([0.0, -sec["w"]])
        if self.drag:
            n = np.array([-t[1], t[0]])
            ut, un = self.U @ t, self.U @ n
            k = 0.5 * self.rho * sec["d"] * math.sqrt(1.0 + T / sec["EA"])
            f = f + k * (sec["cdt"] * abs(ut) * ut * t + sec["cdn"] * abs(un) * un * n)
        return f

    @staticmethod
    def norm(v) -> float:
        """|v| of a vector of DIM entries."""
        return math.hypot(v[0], v[1])

    def rhs(self, sec: dict):
        def f(_s, y):
            N = y[self.DIM:]
            T = self.norm(N)
            if T <= 0.0:
                raise NoReference("zero tension inside the line")
            t = N / T
            return np.concatenate([(1.0 + T / sec["EA"]) * t, -self.load(sec, t, T)])
        return f

    def integrate(self, N0, r0=None, forward=True, dense=False, s_skip=0.0):
        """Integrate from end A (forward) or end B (backward) with the given internal force
        there; returns (r, N) at the other end ((x, z, Nx, Nz) in the plane), and the profile
        (points, s) if ``dense``."""
        n = self.DIM
        r0 = np.zeros(n) if r0 is None else r0
        y = np.concatenate([np.asarray(r0, float), np.asarray(N0, float)])
        order = range(len(self.secs)) if forward else range(len(self.secs) - 1, -1, -1)
        scale = max(self.W, self.norm(N0), 1.0)
        atol = np.array([ATOL_REL * self.L] * n + [ATOL_REL * scale] * n)
        pts, ss = [], []
        for k in order:
            a, b = self.start[k], self.start[k + 1]
            if forward:
                a = max(a, s_skip)
            else:
                b = min(b, self.L - s_skip)
            if b <= a:
                continue
            span = (a, b) if forward else (b, a)   # solve_ivp runs backwards when b < a
            sol = solve_ivp(self.rhs(self.secs[k]), span, y, method="DOP853", rtol=RTOL, atol=atol,
                            dense_output=dense)
            if not sol.success:
                raise NoReference(f"solve_ivp: {sol.message}")
            if dense:
                grid = np.linspace(span[0], span[1], max(3, int(N_PROFILE * abs(b - a) / self.L)))
                pts.append(sol.sol(grid)[:n].T)
                ss.append(grid)
            y = sol.y[:, -1]
        prof = (np.concatenate(pts), np.concatenate(ss)) if dense else None
        return y, prof


def pinned(cable: Cable, pa, pb, guess=None):
    """Shooting on N(0) for a line pinned at pa and pb (global positions)."""
    pa, pb = np.asarray(pa, float), np.asarray(pb, float)
    scale = max(cable.W, 1.0)

    def res(u):
        try:
            y, _ = cable.integrate(u * scale, pa)
        except NoReference:
            return np.full(2, 1e3)
        return (y[:2] - pb) / cable.L

    starts = [] if guess is None else [np.asarray(guess, float) / scale]
    d = pb - pa
    chord = d / max(np.hypot(*d), 1e-12)
    for h in (1.0, 0.1, 10.0, 100.0):
        starts.append(h * chord + np.array([0.0, -0.5 * sum(s["w"] * s["length"] for s in cable.secs) / scale]))
    best = None
    for u0 in starts:
        sol = root(res, u0, method="hybr", options={"xtol": 1e-13, "maxfev": 400})
        err = float(np.max(np.abs(res(sol.x))))
        if best is None or err < best[0]:
            best = (err, sol.x)
        if err < 1e-10:
            break
    if best[0] > 1e-8:
        raise NoReference(f"shooting did not converge (end residual {best[0]:.2e} L)")
    N0 = best[1] * scale
    yL, (prof, s) = cable.integrate(N0, pa, dense=True)
    return _result(N0, yL[2:], prof, s)


def free_direction(cable: Cable, sec: dict, sign: float):
    """Unit tangent at an unloaded free end: t = sign * f(t) / |f(t)| (fixed point)."""
    t = np.array([0.0, -1.0]) * sign if sec["w"] >= 0 else np.array([0.0, 1.0]) * sign
    for _ in range(200):
        f = cable.load(sec, t, 0.0)
        nf = math.hypot(*f)
        if nf == 0.0:
            raise NoReference("no load at the free end: direction undetermined")
        t_new = sign * f / nf
        if np.max(np.abs(t_new - t)) < 1e-14:
            return t_new
        t = t_new
    raise NoReference("free-end direction did not settle")


def free(cable: Cable, fixed_pos, force, free_is_b: bool):
    """Line with a free end carrying ``force`` (applied on the line): integrate from the free
    end to the fixed one, then translate."""
    F = np.asarray(force, float)
    skip = 0.0
    if free_is_b:          # N(L) = F, integrate backwards
        N_end = F.copy()
        if not np.any(F):
            skip = 1e-7 * cable.L
            t = free_direction(cable, cable.secs[-1], 1.0)
            N_end = skip * cable.load(cable.secs[-1], t, 0.0)
            if N_end @ t < 0:
                raise NoReference("free end: load not along the tangent")
    else:                  # N(0) = -F, integrate forwards
        N_end = -F
        if not np.any(F):
            skip = 1e-7 * cable.L
            t = free_direction(cable, cable.secs[0], -1.0)
            N_end = -skip * cable.load(cable.secs[0], t, 0.0)
    y, (prof, s) = cable.integrate(N_end, (0.0, 0.0), forward=not free_is_b, dense=True,
                                   s_skip=skip)
    prof = prof + (np.asarray(fixed_pos, float) - y[:2])
    if free_is_b:
        prof, s = prof[::-1], s[::-1]
        N0, NL = y[2:], N_end
    else:
        N0, NL = N_end, y[2:]
    return _result(N0, NL, prof, s)


def _result(N0, NL, prof, s):
    order = np.argsort(s, kind="stable")
    return {"F_A": [float(N0[0]), float(N0[1])], "F_B": [-float(NL[0]), -float(NL[1])],
            "T_A": float(np.hypot(*N0)), "T_B": float(np.hypot(*NL)), "grounded": 0.0,
            "pile": False, "regime": "ode", "profile": prof[order], "s": s[order]}
