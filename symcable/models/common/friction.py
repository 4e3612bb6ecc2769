"""Seabed friction of the cable3d line (:mod:`symcable.models.cable3d.line`): the two dynamic laws
of ``seabed.friction_law`` and the static spring of ``seabed.static_friction``.

Every law acts on a node's horizontal motion, split along the line's horizontal direction
tau at the node (central difference of its neighbours) and across it (n = e_z x tau), with
the coefficients mu_a (axial) and mu_l (lateral); N is the contact's normal force (the spring,
not the damper) and k = ``friction_stiffness`` x the node's contact area (N/m). Where
mu_a = mu_l every law is the same in any horizontal frame and is written in x and y: a
node's friction then depends on its own node alone (no derivatives by the neighbours'
positions, which vanish only numerically; with the bristle law its rows form a 2 x 2 block
per node).

- ``"coulomb"`` (no state): f = -N (mu_a v_a tau + mu_l v_l n) / sqrt(|v_h|^2 + v_eps^2),
  v_eps the scene's ``friction_velocity``. Zero at rest: a node under a horizontal load F
  below mu N creeps at about v_eps F / (mu N).
- ``"bristle"``: an elastic bristle per node, its deflection b (m, 2 horizontal components,
  a first-order state of the Mechanism), force f = -k chi b, slipping at the friction limit:
  an elasto-plastic bristle regularised as Bouc and Wen's hysteresis (rate independent,
  smooth):

      b' = chi v_h - lambda (zeta_a tau + zeta_l n) - r(|zeta|) b,
      zeta = k (b . tau / mu_a, b . n / mu_l) / N_e,   chi = N / N_e,
      lambda = h(g . chi v_h) P(|zeta|) |g| / (g . zeta),   g = (zeta_a / mu_a, zeta_l / mu_l),

  N_e = sqrt(N^2 + (BRISTLE_FLOOR W)^2) (W the node's submerged weight: chi = 0.995 on the
  bed, 0 off it), |zeta| the utilisation (|f| / (mu N) in the ellipse of semi-axes mu_a N,
  mu_l N: the force never exceeds mu N where |zeta| <= 1), g the ellipse's normal,
  h(x) = (x + sqrt(x^2 + e^2)) / 2 x^2 / (x^2 + e^2) a smooth max(x, 0) that is 0 at x = 0
  (e = BRISTLE_SPEED), P(u) = u^m (m = BRISTLE_EXPONENT) up to the limit and linear beyond
  (:func:`power`). The bristle slips only while it is loaded outward (g . v_h > 0) and only
  near its limit (0.8^8 = 17 % of the motion at 80 % of mu N, 0.5^8 = 0.4 % at half);
  unloading and rest are elastic, so it holds any load below mu N at rest with no creep,
  after a displacement of about the mobilisation length mu N / k. Sliding at |v| >> e,
  |zeta| = 1: the force is mu N in the direction the Coulomb law gives (zeta parallel to
  (v_a, v_l)); at |v| ~ e a few % more (P = |v| / h(|v|): 6.5 % at e, 1 % at 3 e). The root's
  motion chi v_h and the release r (BRISTLE_RELEASE, only beyond |zeta| = 1.1: a node whose
  normal force fell below what its bristle holds, or that left the bed) keep the bristles of
  nodes off the bed at zero, where their force vanishes with N. The state at rest is b = 0
  (statics without static friction), or the static spring's deflection.
- static friction ``"laid"`` (statics only): a smooth capped spring from the as-laid shape,
  f = -k chi d / sqrt(1 + |zeta(d)|^2), d the node's horizontal displacement from the
  laid shape: at most mu N in the same ellipse (|zeta(f)| < 1). With the bristle law it is
  the bristle's state at rest (the run starts holding what statics held); with the Coulomb
  law it is a force of the static solve only (the parameter block ``static_friction``, 1 in
  statics, 0 in time), and a run from that state starts without it.
"""
from __future__ import annotations

from dataclasses import dataclass

import casadi as ca
import numpy as np

__all__ = ["BRISTLE_EXPONENT", "BRISTLE_FLOOR", "BRISTLE_RELEASE", "BRISTLE_SPEED", "OVERLOAD",
           "Friction", "friction", "power"]

#: m/s, e: the speed below which the bristle's outward slip is smoothed to 0 at rest; far
#: below the sliding speeds that matter (the chains' grounded chain: 0.01-0.3 m/s)
BRISTLE_SPEED = 1e-3
#: m, the power of the utilisation in the slip rate; the higher, the sharper the corner
#: between stick and slip (elasto-plastic as m -> infinity) and the stiffer Newton's problem
#: (the slip rate's derivative is m |v| / (mobilisation length) while sliding)
BRISTLE_EXPONENT = 8
#: 1/s: an overloaded bristle (|zeta| beyond OVERLOAD[0], fully from OVERLOAD[1]: its node's
#: normal force fell under it, or it left the bed) returns towards zero at this rate
#: whatever its node does; never while it holds at or below the limit
BRISTLE_RELEASE = 10.0
#: the utilisations where the release starts and where it is full (C^2 step between)
OVERLOAD = (1.1, 1.3)
#: N_e = sqrt(N^2 + (this x W)^2), W the node's submerged weight: zeta stays finite off the
#: bed, and its scale there (the mobilisation length of this fraction of the weight) keeps
#: Newton's problem of a bristle above the bed mild (with N + 1e-3 W it cycled there)
BRISTLE_FLOOR = 0.1


@dataclass(frozen=True)
class Friction:
    """What :func:`friction` builds: the nodal force (2, n) horizontal, N; the bristle
    states' rates (2 n, 1) and rest rows (2 n, 1), N (None without bristles)."""

    force: object
    rate: object = None
    rest: object = None


def _frame(Xm):
    """(tau, n): the line's horizontal unit direction at each node (central difference of
    its neighbours) and the one across it, (2, n) each."""
    nxt = ca.horzcat(Xm[:, 1:], Xm[:, -1])
    prv = ca.horzcat(Xm[:, 0], Xm[:, :-1])
    tau = (nxt - prv)[0:2, :]
    tau = tau / ca.repmat(ca.sqrt(ca.sum1(tau * tau) + 1e-24), 2, 1)
    return tau, ca.vertcat(-tau[1, :], tau[0, :])


def power(s2):
    """|zeta|^m of the slip rate up to the limit (|zeta| = 1), continued beyond it by
    1 + m x + A x^2 / (1 + A x / m), x = |zeta| - 1, A = m (m - 1) / 2: C^2 at the limit and
    asymptotically linear (slope 2 m). Newton's iterates in a step that crosses many
    mobilisation lengths start far outside the limit: the bare power sends them to huge slip
    rates (the run blows up), a saturated one (bounded beyond the limit) leaves them a flat
    residual to cycle on (2-cycles at a chain's touchdown node); the linear continuation
    brings them back in one step."""
    m = BRISTLE_EXPONENT
    A = 0.5 * m * (m - 1)
    x = ca.sqrt(ca.fmax(s2, 1.0)) - 1.0
    return ca.if_else(s2 <= 1.0, s2 ** (m // 2), 1.0 + m * x + A * x * x / (1.0 + A * x / m))


def _row(x):
    """``x`` (n,) as a (1, n) row: an expression as it is (a row of parameters), numbers as
    a constant."""
    return x if isinstance(x, (ca.SX, ca.MX, ca.DM)) else ca.DM(np.asarray(x, float)).T


def friction(sb, Xm, Vm, contact, area, weight, state=None, laid=None, gate=None) -> Friction:
    """The seabed friction of ``sb`` (:class:`~symcable.scene.Seabed`) on the nodes (module
    docstring).

    ``Xm``, ``Vm`` (3, n) node positions and velocities; ``contact`` (1, n) N; ``area`` (n,) or
    (1, n) each node's contact area, m^2; ``weight`` (n,) or (1, n) its submerged weight
    magnitude, N (numbers or parameters); ``state`` (2 n, 1)
    the bristle deflections (m; the bristle law), node by node; ``laid`` (2 n, 1) the as-laid
    horizontal positions (m) and ``gate`` (the static spring's on-off, 1 in statics) when
    ``sb.static_friction`` is ``"laid"``."""
    n = Xm.shape[1]
    if sb.mu_axial == sb.mu_lateral:  # isotropic: any horizontal frame gives the same force
        # (x and y: no derivatives by the neighbours' positions, and a block per node)
        tau, nrm = ca.repmat(ca.DM([1.0, 0.0]), 1, n), ca.repmat(ca.DM([0.0, 1.0]), 1, n)
    else:
        tau, nrm = _frame(Xm)
    k = sb.tangential_stiffness * _row(area)  # (1, n), N/m
    floor = BRISTLE_FLOOR * ca.fmax(ca.fabs(_row(weight)), 1e-12)
    Ne = ca.sqrt(contact * contact + floor * floor)
    mu_a, mu_l = sb.mu_axial, sb.mu_lateral

    def along(a):
        return ca.sum1(a * tau), ca.sum1(a * nrm)

    def zeta(a):  # normalised by the limit ellipse
        a_a, a_l = along(a)
        return k * a_a / (mu_a * Ne), k * a_l / (mu_l * Ne)

    def capped(d):
        z_a, z_l = zeta(d)
        return d / ca.repmat(ca.sqrt(1.0 + z_a * z_a + z_l * z_l), 2, 1)

    share = ca.repmat(k * contact / Ne, 2, 1)  # (2, n): k N / N_e
    d = None if laid is None else Xm[0:2, :] - ca.reshape(laid, 2, n)
    if sb.friction_law == "coulomb":
        vh = Vm[0:2, :]
        speed = ca.sqrt(ca.sum1(vh * vh) + sb.friction_velocity ** 2)
        if mu_a == mu_l:  # isotropic: mu (v_a tau + v_l n) = mu v_h, without the frame
            # (whose derivatives by the neighbours' positions vanish only numerically, yet
            # are written out: most of the instructions of a long chain's step matrix rest)
            f = -ca.repmat(mu_a * contact / speed, 2, 1) * vh
        else:
            v_a, v_l = along(vh)
            f = -ca.repmat(contact / speed, 2, 1) * (ca.repmat(mu_a * v_a, 2, 1) * tau
                                                      + ca.repmat(mu_l * v_l, 2, 1) * nrm)
        if d is not None:
            f = f - gate * share * capped(d)
        return Friction(f)
    b = ca.reshape(state, 2, n)
    z_a, z_l = zeta(b)
    s2 = z_a * z_a + z_l * z_l
    g_a, g_l = z_a / mu_a, z_l / mu_l  # the limit ellipse's normal (tau, n components)
    g_norm = ca.sqrt(g_a * g_a + g_l * g_l + 1e-30)
    on = contact / Ne  # chi = N / N_e: 1 on the bed, 0 off it
    vb = ca.repmat(on, 2, 1) * Vm[0:2, :]  # what the bristle's root moves
    v_a, v_l = along(vb)
    out = (g_a * v_a + g_l * v_l) / g_norm  # outward speed, m/s
    eps = BRISTLE_SPEED
    loading = 0.5 * (out + ca.sqrt(out * out + eps * eps)) * out * out / (out * out + eps * eps)
    slip = loading * power(s2) * g_norm / (g_a * z_a + g_l * z_l + 1e-30)
    x = ca.fmin(ca.fmax((s2 - OVERLOAD[0] ** 2) / (OVERLOAD[1] ** 2 - OVERLOAD[0] ** 2), 0.0), 1.0)
    release = BRISTLE_RELEASE * x ** 3 * (10.0 - 15.0 * x + 6.0 * x * x)  # C^2 step, 1/s
    rate = (vb - ca.repmat(slip * z_a, 2, 1) * tau - ca.repmat(slip * z_l, 2, 1) * nrm
            - ca.repmat(release, 2, 1) * b)
    target = ca.DM.zeros(2, n) if d is None else capped(d)
    rest = ca.repmat(k, 2, 1) * (b - target)
    return Friction(-share * b, ca.reshape(rate, 2 * n, 1), ca.reshape(rest, 2 * n, 1))
