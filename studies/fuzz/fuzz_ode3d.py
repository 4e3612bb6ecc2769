"""The cable equations in 3D, integrated along the line (scipy ``solve_ivp``, DOP853) with a
root solve on the far end's position (shooting): the study's reference for a cable3d line
that leaves its vertical plane (a current oblique to it, a free end's force out of it).

As :mod:`fuzz_ode` in the plane: along the unstretched arc length s, position r (3) and
internal force N (3, the force the part beyond s exerts on the part before); T = |N|,
t = N / T, strain T / EA, and

    dr/ds = (1 + T/EA) t,        dN/ds = -f(t, T),
    f = (0, 0, -w) + 0.5 rho d sqrt(1 + T/EA) (Cd_t |u_t| u_t t + Cd_n |u_n| u_n),

u_t = U . t, u_n = U - u_t t (the Morison law of ``symcable.models.cable3d.line``: drag per
unstretched metre on the current's tangential and normal components). Pinned-pinned: N(0)
unknown (3 equations r(L) = r_B), found by continuation in the current from the line without
it (started from its elastic catenary in the ends' vertical plane, :mod:`fuzz_catenary`); a
free end: N is known there, integrated from it with no unknown. No seabed contact, no slack
fold (tension zero inside the line): such a line has no reference here.
"""
from __future__ import annotations

import math

import numpy as np
from scipy.optimize import root

from fuzz_catenary import NoReference
from fuzz_ode import Cable

RAMP = (0.25, 0.5, 0.75, 1.0)   # fractions of the current, pinned-pinned continuation


class Cable3(Cable):
    """Sections (from end A: length, w, EA, d, cdn, cdt) and the current (3, m/s); the
    integration along the line is :class:`fuzz_ode.Cable`'s."""

    DIM = 3

    def scaled(self, k: float) -> "Cable3":
        return Cable3(self.secs, self.rho, k * self.U)

    @staticmethod
    def norm(v) -> float:
        return float(np.linalg.norm(v))

    def load(self, sec: dict, t: np.ndarray, T: float) -> np.ndarray:
        f = np.array([0.0, 0.0, -sec["w"]])
        if np.any(self.U != 0.0):
            ut = float(self.U @ t)
            un = self.U - ut * t
            k = 0.5 * self.rho * sec["d"] * math.sqrt(1.0 + T / sec["EA"])
            f = f + k * (sec["cdt"] * abs(ut) * ut * t + sec["cdn"] * float(np.linalg.norm(un)) * un)
        return f


def _shoot(cable: Cable3, pa, pb, u0, scale):
    def res(u):
        try:
            y, _ = cable.integrate(u * scale, pa)
        except NoReference:
            return np.full(3, 1e3)
        return (y[:3] - pb) / cable.L
    sol = root(res, u0, method="hybr", options={"xtol": 1e-13, "maxfev": 600})
    return float(np.max(np.abs(res(sol.x)))), sol.x


def pinned(cable: Cable3, pa, pb, guesses) -> dict:
    """Shooting on N(0) for a line pinned at pa and pb, by continuation in the current from
    each of ``guesses`` (N(0) of the line without current, N) until one reaches it all."""
    pa, pb = np.asarray(pa, float), np.asarray(pb, float)
    scale = max(cable.W, 1.0)
    ramp = RAMP if np.any(cable.U != 0.0) else (1.0,)
    best = None
    for g in guesses:
        u = np.asarray(g, float) / scale
        err = math.inf
        for k in ((0.0,) + ramp if len(ramp) > 1 else ramp):
            err, u = _shoot(cable.scaled(k), pa, pb, u, scale)
            if err > 1e-8:
                break
        if best is None or err < best[0]:
            best = (err, u)
        if err <= 1e-10:
            break
    if best is None or best[0] > 1e-8:
        raise NoReference(f"3D shooting did not converge (end residual "
                          f"{best[0] if best else math.nan:.2e} L)")
    N0 = best[1] * scale
    yL, (prof, s) = cable.integrate(N0, pa, dense=True)
    return _result(N0, yL[3:], prof, s)


def free_direction(cable: Cable3, sec: dict, sign: float) -> np.ndarray:
    """Unit tangent at an unloaded free end: t = sign f(t) / |f(t)| (fixed point)."""
    t = np.array([0.0, 0.0, -sign if sec["w"] >= 0 else sign])
    for _ in range(300):
        f = cable.load(sec, t, 0.0)
        nf = float(np.linalg.norm(f))
        if nf == 0.0:
            raise NoReference("no load at the free end: direction undetermined")
        t_new = sign * f / nf
        if np.max(np.abs(t_new - t)) < 1e-14:
            return t_new
        t = t_new
    raise NoReference("free-end direction did not settle")


def free(cable: Cable3, fixed_pos, force, free_is_b: bool) -> dict:
    """A line with a free end carrying ``force`` (applied on the line): integrated from the
    free end to the held one, then translated there."""
    F = np.zeros(3) if force is None else np.asarray(force, float)
    skip = 0.0
    sec = cable.secs[-1] if free_is_b else cable.secs[0]
    sign = 1.0 if free_is_b else -1.0
    N_end = F.copy() if free_is_b else -F
    if not np.any(F):
        skip = 1e-7 * cable.L
        t = free_direction(cable, sec, sign)
        N_end = sign * skip * cable.load(sec, t, 0.0)
    y, (prof, s) = cable.integrate(N_end, np.zeros(3), forward=not free_is_b, dense=True,
                                   s_skip=skip)
    prof = prof + (np.asarray(fixed_pos, float) - y[:3])
    if free_is_b:
        N0, NL = y[3:], N_end
    else:
        N0, NL = N_end, y[3:]
    return _result(N0, NL, prof, s)


def _result(N0, NL, prof, s) -> dict:
    order = np.argsort(s, kind="stable")
    return {"F_A": [float(v) for v in N0], "F_B": [-float(v) for v in NL],
            "T_A": float(np.linalg.norm(N0)), "T_B": float(np.linalg.norm(NL)), "grounded": 0.0,
            "pile": False, "regime": "ode3d", "profile": prof[order], "s": s[order]}
