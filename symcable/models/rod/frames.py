"""Frames and the elastic kernel of the discrete elastic rod (``model = "rod"``,
:mod:`symcable.models.rod.rod`): Bergou et al. 2008 ("Discrete elastic rods"), with the
reference frame carried as a smooth function of the positions (the choice is argued in
:mod:`symcable.models.rod.rod`).

Edge j (nodes j, j+1) has the unit tangent t_j, an *anchor* (t0_j, u0_j) stored as data (the
parameter block ``frame``: a unit tangent and a unit director perpendicular to it), and a
twist angle theta_j (rad, an unknown). Its reference director is the anchor's director
carried to the current tangent by the smallest rotation,

    d1_j = P(t0_j -> t_j) u0_j,   d2_j = t_j x d1_j,

(:func:`transport`; the "time-parallel transport" of DER done in one step from the anchor,
so it is a function of t_j alone: defined and smooth except at t_j = -t0_j), and the material
directors are d1, d2 turned by theta_j about t_j:

    m1_j = cos(theta_j) d1_j + sin(theta_j) d2_j,   m2_j = t_j x m1_j.

At the node between edges j-1 and j (a *vertex*; rest lengths lbar = the mean of theirs):

    kb = 2 e_{j-1} x e_j / (|e_{j-1}| |e_j| + e_{j-1} . e_j)   (|kb| = 2 tan(phi/2))
    kappa_1^k = kb . m1_k,  kappa_2^k = kb . m2_k               (k = j-1, j: each edge's frame)
    twist = theta_j - theta_{j-1} + ref,  ref = the angle from P(t_{j-1} -> t_j) d1_{j-1}
            to d1_j about t_j (the reference twist)
    E = [ 1/2 sum_k (EI_1^k (kappa_1^k)^2 + EI_2^k (kappa_2^k)^2) + GJ twist^2 ] / (2 lbar)

so an isotropic rod's bending is cable3d's EI |kb|^2 / (2 lbar)
(:mod:`~symcable.models.common.bending`) and the twist energy is 0.5 GJ tau^2 over the
vertex's cell with tau = twist / lbar. EI_1 resists bending *about* m1 (kappa_1 = kb . m1),
EI_2 about m2. The rest shape is straight and untwisted (no natural curvature yet).
"""
from __future__ import annotations

import math

import casadi as ca
import numpy as np

__all__ = ["CALL_MIN_VERTICES", "end_moment_force", "reference_director", "reference_twist",
           "transport", "vertex_kernel"]


def reference_director(t) -> np.ndarray:
    """A unit vector perpendicular to the unit vector ``t`` (numpy, data only): the global
    axis least aligned with t (z first on ties), with its t component removed. A clamp's
    ``twist_deg`` is measured from it about the clamp's direction, and the default anchors
    use it, so a straight rod along a clamp starts with zero reference twist."""
    t = np.asarray(t, float) / np.linalg.norm(t)
    axis = np.eye(3)[[2, 0, 1][int(np.argmin(np.abs(t[[2, 0, 1]])))]]
    u = axis - (axis @ t) * t
    return u / np.linalg.norm(u)


def transport(a, b, u):
    """``u`` (perpendicular to the unit vector ``a``) turned by the smallest rotation that
    takes ``a`` to the unit vector ``b`` (about a x b; CasADi or numpy):
    u - (u . b) / (1 + a . b) (a + b) (Rodrigues' formula for u . a = 0, without the angle
    or the axis: the cheapest form to differentiate twice); smooth except at b = -a."""
    return u - ca.dot(u, b) / (1.0 + ca.dot(a, b)) * (a + b)


def _solid_angle(a, b, c):
    """The signed solid angle of the spherical triangle of unit vectors a, b, c (sr):
    2 atan2(a . b x c, 1 + a.b + b.c + c.a) (Van Oosterom and Strackee)."""
    return 2.0 * ca.atan2(ca.dot(a, ca.cross(b, c)),
                          1.0 + ca.dot(a, b) + ca.dot(b, c) + ca.dot(c, a))


def reference_twist(t1, t2, t0p, u0p, t0n, u0n):
    """The reference twist at a vertex (rad): the angle about t2 from the edge before's
    reference director d1p = P(t0p -> t1) u0p, carried to t2 by P(t1 -> t2), to the edge
    after's d1n = P(t0n -> t2) u0n. Written without the transports: carried back to t0n,
    the two differ by the holonomy of the loop t0p -> t1 -> t2 -> t0n -> t0p (minus its solid
    angle, two triangles) and the anchors' own angle c0 (from P(t0p -> t0n) u0p to u0n about
    t0n: a function of the parameters only, 0 for equal anchors):

        ref = c0 - Omega(t0p, t1, t2) - Omega(t0p, t2, t0n)

    The same value as the transports' (to round-off), at a third of the cost of the tangent;
    like them, smooth while the loop stays well inside a hemisphere."""
    moved = transport(t0p, t0n, u0p)
    c0 = ca.atan2(ca.dot(ca.cross(moved, u0n), t0n), ca.dot(moved, u0n))
    return c0 - _solid_angle(t0p, t1, t2) - _solid_angle(t0p, t2, t0n)


def _frame(e, theta, t0, u0):
    """(t, d1, m1, m2) of an edge vector ``e`` with twist ``theta`` and anchor (t0, u0)."""
    t = e / ca.norm_2(e)
    d1 = transport(t0, t, u0)
    d2 = ca.cross(t, d1)
    m1 = ca.cos(theta) * d1 + ca.sin(theta) * d2
    return t, d1, m1, ca.cross(t, m1)


#: a rod with at least this many vertices gets the vertex kernel as a call
#: (:func:`vertex_kernel`'s ``call``; ``vertices`` given). Default: never (the straight-line
#: step is faster in the virtual machine, which runs large steps by default); in generated C
#: the call makes the step faster, the more so the longer the rod. Set it (e.g. to 16)
#: before the scene's Mechanism is first built
#: (:func:`symcable.api.rod_static.rod_mechanism` keeps it per scene content) for runs in
#: generated C (``codegen=True``) of long rods.
CALL_MIN_VERTICES: float = math.inf


def vertex_kernel(isotropic: bool = False, coupled: bool = False,
                  call: bool | None = None, vertices: int = 0) -> ca.Function:
    """The elastic term of one vertex (module docstring). ``isotropic``: EI_1 = EI_2 on both
    edges (only ``Bp[0]``, ``Bn[0]`` read), the bending energy written without the frames,
    (EI_p + EI_n) |kb|^2 / 4 per 2 lbar (the same value: kb is perpendicular to both
    tangents, so kappa_1^2 + kappa_2^2 = |kb|^2), which cuts the kernel's exact Hessian, the
    cost of every tangent, from 9.3 k to 5.0 k operations (the twist term keeps the rest).
    Inputs: node positions ``xp``,
    ``x``, ``xn`` (m), twists ``thp``, ``thn`` of the edges before and after (rad), their
    anchors ``t0p``, ``u0p``, ``t0n``, ``u0n``, their bending stiffnesses ``Bp``, ``Bn``
    ([EI_1, EI_2], N m^2), the vertex's ``GJ`` (N m^2) and ``lbar`` (m). Outputs: the forces
    ``fp``, ``f``, ``fn`` on the three nodes (N), the torques ``qp``, ``qn`` on the two twists
    (N m; minus the energy's gradient), the energy ``E`` (J), the material curvatures
    ``kappa`` = [kappa_1, kappa_2] in the frame of the edge after (1/m: kb . m / lbar), the
    ``twist`` (rad), the bending moment vector ``M`` (N m, world frame: the mean over the two
    edges of (EI_1 kappa_1 m1 + EI_2 kappa_2 m2), kappa = kb . m / lbar) and the twisting
    moment ``Mt`` = GJ twist / lbar (N m).

    ``coupled``: the tension-torsion coupling of helically armoured cables (Knapp 1979,
    "Derivation of a new stiffness matrix for helically armoured cables considering tension
    and torsion"; Costello, "Theory of wire rope"): the linear law [T, M_t] = [[EA, K],
    [K, GJ]] [e, tau], i.e. the energy K e tau per metre, here K ebar twist at the vertex
    (twist = tau lbar), ebar = wp e_p + wn e_n the strains of the two edges (e = |edge| /
    ds - 1) weighted by their shares of the cell (0 for a ghost). Extra inputs ``K`` (N m),
    ``dsp``, ``dsn`` (the edges' rest lengths, m), ``wp``, ``wn``; ``Mt`` is then
    GJ twist / lbar + K ebar.

    ``call``: a Function that is never inlined: an SX expression that calls it (mapped over
    the vertices) holds one call node per vertex, its derivatives calls of the kernel's
    forward derivative (one per direction: 11 per vertex), so generated C holds the kernel
    and its derivative once, at some cost per evaluation. The same values."""
    call = _call(call, vertices)
    xp, x, xn, t0p, u0p, t0n, u0n = (ca.SX.sym(n, 3) for n in
                                     ("xp", "x", "xn", "t0p", "u0p", "t0n", "u0n"))
    Bp, Bn = ca.SX.sym("Bp", 2), ca.SX.sym("Bn", 2)
    thp, thn, GJ, lbar = (ca.SX.sym(n) for n in ("thp", "thn", "GJ", "lbar"))
    e1, e2 = x - xp, xn - x
    t1, d1p, m1p, m2p = _frame(e1, thp, t0p, u0p)
    t2, d1n, m1n, m2n = _frame(e2, thn, t0n, u0n)
    kb = 2.0 * ca.cross(e1, e2) / (ca.norm_2(e1) * ca.norm_2(e2) + ca.dot(e1, e2))
    kp = ca.vertcat(ca.dot(kb, m1p), ca.dot(kb, m2p))
    kn = ca.vertcat(ca.dot(kb, m1n), ca.dot(kb, m2n))
    twist = thn - thp + reference_twist(t1, t2, t0p, u0p, t0n, u0n)
    if isotropic:
        bend = 0.5 * (Bp[0] + Bn[0]) * ca.dot(kb, kb)
    else:  # EI_1 k1^2 + EI_2 k2^2 = EI_1 |kb|^2 + (EI_2 - EI_1) k2^2 (kb is perpendicular
        # to both tangents): one projection per edge, a fifth fewer operations in the Hessian
        k2p = ca.cos(thp) * ca.dot(kb, ca.cross(t1, d1p)) - ca.sin(thp) * ca.dot(kb, d1p)
        k2n = ca.cos(thn) * ca.dot(kb, ca.cross(t2, d1n)) - ca.sin(thn) * ca.dot(kb, d1n)
        bend = 0.5 * ((Bp[0] + Bn[0]) * ca.dot(kb, kb) + (Bp[1] - Bp[0]) * k2p * k2p
                      + (Bn[1] - Bn[0]) * k2n * k2n)
    E = (0.5 * bend + 0.5 * GJ * twist * twist) / lbar
    Mt = GJ * twist / lbar
    extra = []
    if coupled:
        K, dsp, dsn, wp, wn = (ca.SX.sym(n) for n in ("K", "dsp", "dsn", "wp", "wn"))
        ebar = wp * (ca.norm_2(e1) / dsp - 1.0) + wn * (ca.norm_2(e2) / dsn - 1.0)
        E = E + K * ebar * twist
        Mt = Mt + K * ebar
        extra = [K, dsp, dsn, wp, wn]
    g = ca.gradient(E, ca.vertcat(xp, x, xn, thp, thn))
    M = 0.5 * (Bp[0] * kp[0] * m1p + Bp[1] * kp[1] * m2p
               + Bn[0] * kn[0] * m1n + Bn[1] * kn[1] * m2n) / lbar
    names_in = ["xp", "x", "xn", "thp", "thn", "t0p", "u0p", "t0n", "u0n", "Bp", "Bn", "GJ",
                "lbar"] + (["K", "dsp", "dsn", "wp", "wn"] if coupled else [])
    return ca.Function("rod_vertex", [xp, x, xn, thp, thn, t0p, u0p, t0n, u0n, Bp, Bn, GJ,
                                      lbar] + extra,
                       [-g[0:3], -g[3:6], -g[6:9], -g[9], -g[10], E, kn / lbar, twist, M, Mt],
                       names_in, ["fp", "f", "fn", "qp", "qn", "E", "kappa", "twist", "M", "Mt"],
                       {"never_inline": True} if call else {})


def _call(call: bool | None, vertices: int) -> bool:
    return bool(call) if call is not None else vertices >= CALL_MIN_VERTICES


def end_moment_force(xa, xb, theta, t0, u0, M, q):
    """The generalized force (on the unknowns ``q``, CasADi column) of a dead moment ``M``
    (3, N m) applied to the edge from ``xa`` to ``xb`` with twist ``theta`` and anchor
    (``t0``, ``u0``): the virtual work of M on the edge's rotation,
    M . (t x dt) + (M . t) (dtheta + d2 . dd1), where d1 = P(t0 -> t) u0 is the reference
    director, d2 = t x d1 (its spin about t beyond the smallest rotation, which the anchor
    map gives as t moves), so the force is J_t^T (M x t) + (M . t) (J_theta^T + J_d1^T d2).
    Exact for a dead moment in any configuration; not the gradient of a potential (a dead
    moment has none in 3D)."""
    e = xb - xa
    t = e / ca.norm_2(e)
    d1 = transport(t0, t, u0)
    d2 = ca.cross(t, d1)
    mt = ca.dot(M, t)
    return ca.mtimes(ca.jacobian(t, q).T, ca.cross(M, t)) \
        + mt * (ca.jacobian(theta, q).T + ca.mtimes(ca.jacobian(d1, q).T, d2))
