"""The two-node cable element of the 3D formulations (Sun, Zhu & LaRosa): its kernel (axial
force, material damping, Morison drag, weight and buoyancy on its two nodes) and the
prescribed motion of a held node."""
from __future__ import annotations

import math

import casadi as ca

from . import terms
from .drag import loading_drag
from .rigid import TABLE_VELOCITY_WIDTH, rigid_end, table_lookup  # noqa: F401 (re-exported)
from .tow import tow_path

__all__ = ["COUPLED_BLOCK", "DRAG_SPEED", "coupled_path", "element_kernel", "held_end"]


#: m/s, the speed below which |u| in the drag law is smoothed (sqrt(|u|^2 + DRAG_SPEED^2)):
#: far below any current or motion speed that matters, and a linear damping there of
#: 0.5 rho d Cd DRAG_SPEED per metre
DRAG_SPEED = 1e-4




def element_kernel(law_shape: tuple[int, int] | None = None) -> ca.Function:
    """Forces of one element on its two nodes (N, 3 each), its axial force T (N) and
    strain e, from its node positions and velocities and its properties (module docstring).
    ``law_shape`` = (Kc, Ks): the drag is the loading functions of an extra input ``law``
    (2 Kc + 2 Ks; :func:`~symcable.models.common.drag.law_table`) instead of Morison's
    law on ``cdn``, ``cdt`` (then not read).
    """
    xa, xb, va, vb, u = (ca.SX.sym(n, 3) for n in ("xa", "xb", "va", "vb", "u"))
    L0, EA, BA, EAs, delta, wall, w, d, cdn, cdt, rho, load = (
        ca.SX.sym(n) for n in ("L0", "EA", "BA", "EAs", "delta", "wall", "w", "d", "cdn", "cdt",
                               "rho", "load"))
    law = ca.SX.sym("law", 2 * sum(law_shape)) if law_shape is not None else None
    dx = xb - xa
    ell = ca.sqrt(ca.dot(dx, dx))
    t = dx / ell
    e = ell / L0 - 1.0
    edot = ca.dot(t, vb - va) / L0
    T = terms.cable_axial_force(EA, e, delta, EAs, wall, 0.005) + BA * edot
    u_rel = u - 0.5 * (va + vb)
    k = 0.5 * rho * d * L0 * ca.sqrt(ca.fmax(1.0 + e, 0.0))
    if law is None:
        ut = ca.dot(u_rel, t)
        un = u_rel - ut * t
        drag = k * (cdt * ca.sqrt(ut * ut + DRAG_SPEED ** 2) * ut * t
                    + cdn * ca.sqrt(ca.dot(un, un) + DRAG_SPEED ** 2) * un)
    else:
        drag = k * loading_drag(u_rel, t, law, law_shape, DRAG_SPEED)
    gravity = ca.vertcat(0.0, 0.0, -load * w * L0)
    half = 0.5 * (drag + gravity)
    fa = T * t + half
    fb = -T * t + half
    names = ["xa", "xb", "va", "vb", "u", "L0", "EA", "BA", "EAs", "delta", "wall", "w", "d",
             "cdn", "cdt", "rho", "load"] + (["law"] if law is not None else [])
    inputs = [xa, xb, va, vb, u, L0, EA, BA, EAs, delta, wall, w, d, cdn, cdt, rho, load]
    return ca.Function("cable3d_element", inputs + ([law] if law is not None else []),
                       [fa, fb, T, e], names, ["fa", "fb", "T", "e"])


#: entries of a coupled end's parameter block (:func:`coupled_path`): its displacement (m)
#: and velocity (m/s) at the start of the host's step, the same at its end, and the step's
#: start and end times (s)
COUPLED_BLOCK = 14


def coupled_path(block, t):
    """A coupled end's displacement (m, (3,)) and velocity (m/s) at t (s): the cubic Hermite
    through the host's displacement x0 and velocity v0 at t0 and x1, v1 at t1 (``block`` =
    [x0, v0, x1, v1, t0, t1], :data:`COUPLED_BLOCK`), held at x1, v1 outside [t0, t1] (and
    at t1 <= t0). Exact at the step's ends, so that a step whose forces are evaluated at its
    end (generalized-alpha at rho_inf = 0) sees exactly the host's end state; in between (a
    substep, rho_inf > 0's alpha point) the cubic matching both ends' positions and
    velocities."""
    x0, v0, x1, v1 = (block[3 * i:3 * i + 3] for i in range(4))
    t0, t1 = block[12], block[13]
    h = t1 - t0
    hs = ca.if_else(h > 0, h, 1.0)
    s = ca.if_else(h > 0, ca.fmin(ca.fmax((t - t0) / hs, 0.0), 1.0), 1.0)
    s2, s3 = s * s, s * s * s
    x = (2 * s3 - 3 * s2 + 1) * x0 + (3 * s2 - 2 * s3) * x1 \
        + h * ((s3 - 2 * s2 + s) * v0 + (s3 - s2) * v1)
    v = (6 * s2 - 6 * s) * (x0 - x1) / hs + (3 * s2 - 4 * s + 1) * v0 + (3 * s2 - 2 * s) * v1
    return x, v


def held_end(end, pos_p, motion_scale, t, ramp_on=1.0, coupled=None):
    """A pinned end's position (m) and velocity (m/s): its parameter position plus the scaled
    prescribed motion:

    - a table's displacement, linearly interpolated (held at its first and last rows). Its
      velocity is the interval's slope, and at a row the mean of the slopes either side,
      changing linearly over :data:`TABLE_VELOCITY_WIDTH` of the smallest row spacing about
      each row: continuous in t, so a time step that ends on a row (up to round-off in t)
      sees one velocity, not the slope of whichever side the rounding of t falls on (with
      the derivative of the interpolant, a step ending on a row sees the left slope, the
      right one or their mean depending on how the run is batched, so that runs of one
      scene batched differently disagree);
    - or x_i = r(t) A_i cos(2 pi t / period + phase_i), ramped in over the first period by
      r = (1 - cos(pi t / period)) / 2 (0 before t = 0, 1 after one period), so that a run
      from the static state at any t <= 0 starts without a jump in the end's position or
      velocity; ``ramp_on`` = 0 (the parameter ``ramp``: periodic solves) takes r = 1
      throughout. Its velocity is the derivative;
    - or a tow's path (:func:`~symcable.models.common.tow.tow_path`), neither ramped nor changed by
      ``ramp_on`` (scaled by ``motion_scale``: held at its scene position in statics);
    - or, ``"coupled"`` (a host program's, :class:`symcable.Coupling`), the Hermite cubic of
      its parameter block ``coupled`` (:func:`coupled_path`), scaled by ``motion_scale``."""
    m = end.motion
    if m is None:
        return pos_p, ca.SX.zeros(3, 1)
    if m.kind == "coupled":
        x, v = coupled_path(coupled, t)
        return pos_p + motion_scale * x, motion_scale * v
    if m.kind == "body":  # a point of a vessel (.rigid)
        return rigid_end(m.rigid, pos_p, motion_scale, t, ramp_on)
    if m.kind == "tow":
        x, v = tow_path(m, t)
        return pos_p + motion_scale * x, motion_scale * v
    if m.kind == "table":  # piecewise linear through the rows, held outside them
        disp, vel = table_lookup(m.samples)
        return pos_p + motion_scale * disp(t), motion_scale * vel(t)
    A = ca.DM(m.amplitude)
    ph = ca.DM([math.radians(v) for v in m.phase_deg])
    ramp = ca.if_else(t <= 0.0, 0.0,
                      ca.if_else(t < m.period, 0.5 * (1.0 - ca.cos(math.pi * t / m.period)), 1.0))
    ramp = 1.0 - ramp_on * (1.0 - ramp)
    x = pos_p + motion_scale * ramp * A * ca.cos(2.0 * math.pi * t / m.period + ph)
    return x, ca.jacobian(x, t)
