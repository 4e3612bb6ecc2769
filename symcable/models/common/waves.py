"""Linear (Airy) wave kinematics, symbolic: the sea's elevation, fluid velocity and fluid
acceleration at points, as CasADi expressions of the points' positions, the time and the
sea's numbers (a parameter block, so that seas of one component count share one graph).

A component of amplitude a, angular frequency omega, wave number k, phase phi and direction
beta, in water of depth h, has phase theta = k (x cos beta + y sin beta) - omega t + phi and

- elevation a cos theta (m);
- horizontal velocity a omega C(z) cos theta along beta, vertical a omega S(z) sin theta (m/s);
- their local time derivatives a omega^2 C(z) sin theta and -a omega^2 S(z) cos theta (m/s^2);

with C = cosh(k (z + h)) / sinh(k h) and S = sinh(k (z + h)) / sinh(k h), written as
(e^(k z) +- e^(-k (z + 2 h))) / (1 - e^(-2 k h)) so that they neither overflow in deep water
nor lose digits; in deep water (no depth) both are e^(k z). The sea is the sum of its
components times the ramp r(t) (:class:`~symcable.scene.waves.Waves`), the whole scaled by
the parameter ``wave_scale`` (0 in statics). Above z = 0, linear theory's own domain, the
kinematics are those at z = 0 (``stretching = "vertical"``) or, with ``"wheeler"``, at the
point mapped from [-h, eta] onto [-h, 0], h (z - eta) / (h + eta) (z - eta in deep water),
capped at 0.

The parameter block ``waves`` (:func:`wave_block`): ramp duration (s), depth h (m; unused in
deep water), then per component a, omega, k, phi, cos beta, sin beta (6 n numbers).
"""
from __future__ import annotations

import math

import casadi as ca
import numpy as np

from ...scene.waves import Waves

__all__ = ["wave_block", "wave_function", "wave_kinematics", "WAVE_TERMS"]

#: the terms a line's equations gain in waves
WAVE_TERMS = ("wave drag", "wave inertia")


def wave_block(waves: Waves, depth: float | None, gravity: float) -> np.ndarray:
    """The ``waves`` parameter block of ``waves`` in water of ``depth`` (m, None: deep) under
    ``gravity`` (m/s^2) (module docstring), 2 + 6 n numbers."""
    c = waves.components_in(depth, gravity)
    return np.concatenate([[waves.ramp_time, 0.0 if depth is None else float(depth)],
                           c.amplitude, c.omega, c.k, c.phase, np.cos(c.direction),
                           np.sin(c.direction)])


def wave_kinematics(n: int, deep: bool, stretching: str, X, t, block, scale, ramp_on):
    """The sea's elevation eta (1, m), fluid velocity u (3, m/s) and acceleration a (3,
    m/s^2) at the points ``X`` (3, m columns), as CasADi expressions (module docstring).

    Parameters
    ----------
    n : int
        The component count.
    deep : bool
        Deep water (no depth: the depth entry of ``block`` is not read).
    stretching : str
        ``"vertical"`` or ``"wheeler"``.
    X : casadi.SX
        (3, m) the points' positions, m.
    t : casadi.SX
        Time, s.
    block : casadi.SX
        The ``waves`` parameter block (2 + 6 n).
    scale, ramp_on : casadi.SX
        The ``wave_scale`` parameter (multiplies the sea) and the ``ramp`` parameter (1: the
        sea ramps in over the block's ramp duration from t = 0; 0: full throughout).

    Returns
    -------
    (eta (1, m), u (3, m), a (3, m)) : casadi.SX
    """
    f = wave_function(n, deep, stretching)
    m = X.shape[1]
    out = f.map(m)(X, t, block, scale, ramp_on)
    return out[0], out[1], out[2]


_FUNCTIONS: dict = {}


def wave_function(n: int, deep: bool, stretching: str) -> ca.Function:
    """The kinematics at one point as a CasADi Function ``(X (3), t, block, scale, ramp_on)
    -> (eta, u (3), a (3))`` (module docstring); one per (n, deep, stretching), kept."""
    key = (n, deep, stretching)
    if key in _FUNCTIONS:
        return _FUNCTIONS[key]
    X, t = ca.SX.sym("X", 3), ca.SX.sym("t")
    block, scale, ramp_on = ca.SX.sym("waves", 2 + 6 * n), ca.SX.sym("scale"), ca.SX.sym("ramp")
    T_ramp, h = block[0], block[1]
    a, w, k, phi, cb, sb = (block[2 + i * n:2 + (i + 1) * n] for i in range(6))
    ramp = ca.if_else(t <= 0.0, 0.0,
                      ca.if_else(t < T_ramp, 0.5 * (1.0 - ca.cos(math.pi * t / T_ramp)), 1.0))
    r = scale * (1.0 - ramp_on * (1.0 - ramp))
    amp = r * a
    x, y, z = X[0], X[1], X[2]

    def theta_at(px, py):
        return k * (px * cb + py * sb) - w * t + phi

    theta = theta_at(x, y)
    eta = ca.dot(amp, ca.cos(theta))
    if stretching == "wheeler":
        zs = (z - eta) if deep else h * (z - eta) / (h + eta)
    else:
        zs = z
    zs = ca.fmin(zs, 0.0)
    e1 = ca.exp(k * zs)
    if deep:
        C = S = e1
    else:
        e2 = ca.exp(-k * (zs + 2.0 * h))
        den = 1.0 - ca.exp(-2.0 * k * h)
        C, S = (e1 + e2) / den, (e1 - e2) / den
    c, s = ca.cos(theta), ca.sin(theta)
    aw, aww = amp * w, amp * w * w
    uh = aw * C * c  # along each component's direction
    u = ca.vertcat(ca.dot(uh, cb), ca.dot(uh, sb), ca.dot(aw * S, s))
    ah = aww * C * s
    acc = ca.vertcat(ca.dot(ah, cb), ca.dot(ah, sb), -ca.dot(aww * S, c))
    f = ca.Function(f"airy{n}", [X, t, block, scale, ramp_on], [eta, u, acc],
                    ["X", "t", "waves", "scale", "ramp"], ["eta", "u", "a"])
    _FUNCTIONS[key] = f
    return f


def element_wave_loads(scene, X, t, block, scale, ramp_on, rho: float, L: dict):
    """The sea's loads on a line's elements from its nodes ``X`` (3, N+1), m: the fluid
    velocity at each element's midpoint (3, N), m/s, added to the current for the drag, and
    each element's Morison inertia force (3, N), N: the displaced water's mass rho (pi/4)
    d^2 L0 (unstretched, as the added mass's) times (1 + Ca_n) the fluid acceleration's
    component across the element plus (1 + Ca_t) its component along it. ``L``: the line's
    per-segment rows ``d``, ``ds``, ``can``, ``cat`` (1, N); ``block``, ``scale``,
    ``ramp_on``: the ``waves``, ``wave_scale`` and ``ramp`` parameters (module docstring)."""
    env = scene.environment
    n = X.shape[1] - 1
    mid = 0.5 * (X[:, :-1] + X[:, 1:])
    _, u, a = wave_kinematics(env.waves.count, env.depth is None, env.waves.stretching, mid, t,
                              block, scale, ramp_on)
    dx = X[:, 1:] - X[:, :-1]
    tt = dx / ca.repmat(ca.sqrt(ca.sum1(dx * dx)), 3, 1)
    at = ca.repmat(ca.sum1(a * tt), 3, 1) * tt
    vol = rho * (math.pi / 4.0) * L["d"] * L["d"] * L["ds"]
    force = (ca.repmat(vol * (1.0 + L["can"]), 3, 1) * (a - at)
             + ca.repmat(vol * (1.0 + L["cat"]), 3, 1) * at)
    assert force.shape == (3, n)
    return u, force
