"""The steady tow of a cable with a heavy, dragging body at its lower end, as the classical
two-point ODEs integrated from the body up the cable (an oracle independent of the
cable3d elements: no discretisation, no Newton; scipy's DOP853 to 1e-12).

Derivation (ours)
-----------------
In the frame moving with the towpoint at speed U along +x, the water flows past at -U x
(z up). A cable in the x-z plane trails behind and below the towpoint; s is the unstretched
arc length from the body (s = 0) up to the towpoint (s = L); phi the angle of the tangent
t = (cos phi, sin phi) (pointing up the cable, towards the ship) above the horizontal, so
the normal n = dt/dphi = (-sin phi, cos phi). The relative flow u = (-U, 0) has u . t =
-U cos phi (down the cable) and a normal part U sin phi n; the angle of attack (the acute
angle between the flow and the cable) is psi = phi for 0 < phi <= 90 deg. Per unstretched
metre the cable feels its submerged weight (0, -w), the normal drag
q d cd f_n(psi) sqrt(1 + e) n and the tangential drag q d cd f_t(psi) sqrt(1 + e) along
the flow's tangential part, -sign(cos phi) t, with q = rho U^2 / 2 and e = T / EA (the
cable3d element's drag per unstretched metre carries the same sqrt(1 + e)). The balance of
an element, d(T t)/ds + f = 0 with dt/ds = phi' n, along t and n:

    T'     = w sin phi + q d cd f_t(psi) sqrt(1 + e) sign(cos phi),
    T phi' = w cos phi - q d cd f_n(psi) sqrt(1 + e),
    x' = (1 + e) cos phi,   z' = (1 + e) sin phi.

With Morison's law (f_n = Cdn sin^2 psi, f_t = Cdt cos^2 psi, cd = 1) and R = q d Cdn,
F_t = q d Cdt these are the classical T' = w sin phi + F_t cos^2 phi, T phi' = w cos phi -
R sin^2 phi (inextensible). At the body the cable's pull T(0) t(0) balances the body's
submerged weight W_b (down) and its drag D_b (along the flow, -x): T(0) cos phi(0) = D_b,
T(0) sin phi(0) = W_b. The top tension is T(L), the layback x(L) (how far the body trails
behind the towpoint) and the depth z(L) (how far below it).
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable

import numpy as np

__all__ = ["TowSection", "SteadyTow", "steady_tow", "tow_sections"]


@dataclass(frozen=True)
class TowSection:
    """One stretch of the tow cable (SI): ``length`` m (unstretched), ``weight`` N/m
    (submerged, per unstretched metre), ``diameter`` m, ``EA`` N, ``cd`` the reference
    drag coefficient and ``f_normal``, ``f_tangential`` the loading functions of the angle
    of attack psi (rad) -> dimensionless (the drag: q d cd f per metre)."""

    length: float
    weight: float
    diameter: float
    EA: float
    cd: float
    f_normal: Callable[[float], float]
    f_tangential: Callable[[float], float]


@dataclass(frozen=True)
class SteadyTow:
    """The integrated steady tow: ``tension`` N, ``layback`` m, ``depth`` m and ``angle``
    deg (phi, above the horizontal) at the towpoint; ``s`` (n,) m from the body, and the
    profile along it: ``T`` (n,) N, ``phi`` (n,) deg, ``x`` (n,) m (behind the body,
    towards the ship), ``z`` (n,) m (above the body)."""

    tension: float
    layback: float
    depth: float
    angle: float
    s: np.ndarray
    T: np.ndarray
    phi: np.ndarray
    x: np.ndarray
    z: np.ndarray


def steady_tow(sections_from_body, speed: float, body_weight: float, body_drag: float,
               rho: float = 1025.0, *, rtol: float = 1e-12) -> SteadyTow:
    """Integrate the steady-tow ODEs (module docstring) from the body up the cable.

    ``sections_from_body``: :class:`TowSection` from the body (first) to the towpoint;
    ``speed`` U, m/s; ``body_weight`` W_b, N (submerged: weight minus buoyancy, > 0 for a
    heavy body); ``body_drag`` D_b, N (> 0); ``rho`` kg/m^3."""
    from scipy.integrate import solve_ivp
    q = 0.5 * rho * speed * speed
    T0 = math.hypot(body_weight, body_drag)
    y = [T0, math.atan2(body_weight, body_drag), 0.0, 0.0]
    s0, parts = 0.0, []
    for sec in sections_from_body:
        def rhs(_s, v, sec=sec):
            T, phi, _, _ = v
            e = T / sec.EA
            k = q * sec.diameter * sec.cd * math.sqrt(1.0 + e)
            c, sn = math.cos(phi), math.sin(phi)
            psi = math.acos(min(1.0, abs(c)))
            return [sec.weight * sn + k * sec.f_tangential(psi) * math.copysign(1.0, c),
                    (sec.weight * c - k * sec.f_normal(psi)) / T,
                    (1.0 + e) * c, (1.0 + e) * sn]
        sol = solve_ivp(rhs, (s0, s0 + sec.length), y, method="DOP853", rtol=rtol,
                        atol=rtol * max(T0, 1.0), dense_output=False,
                        t_eval=np.linspace(s0, s0 + sec.length, 201))
        if not sol.success:
            raise RuntimeError(f"steady-tow ODE: {sol.message}")
        parts.append(sol)
        s0, y = s0 + sec.length, sol.y[:, -1]
    s = np.concatenate([p.t for p in parts])
    Y = np.concatenate([p.y for p in parts], axis=1)
    return SteadyTow(float(Y[0, -1]), float(Y[2, -1]), float(Y[3, -1]),
                     math.degrees(Y[1, -1]), s, Y[0], np.degrees(Y[1]), Y[2], Y[3])


def tow_sections(line) -> list[TowSection]:
    """The :class:`TowSection` of a scene's line (``line.sections``, end A at the towpoint,
    end B at the body), reversed: from the body up; each section's line type's weight,
    diameter, EA and drag law (Morison's as f_n = Cdn sin^2, f_t = Cdt cos^2, cd = 1)."""
    out = []
    for sec in reversed(line.sections):
        lt = sec.line_type
        law = lt.loading
        if law is None:
            cdn, cdt = lt.cd_normal, lt.cd_tangential
            out.append(TowSection(sec.length, lt.weight, lt.diameter, lt.EA, 1.0,
                                  lambda p, c=cdn: c * math.sin(p) ** 2,
                                  lambda p, c=cdt: c * math.cos(p) ** 2))
        else:
            out.append(TowSection(sec.length, lt.weight, lt.diameter, lt.EA, law.cd,
                                  lambda p, f=law: float(f.f_normal(p)),
                                  lambda p, f=law: float(f.f_tangential(p))))
    return out
