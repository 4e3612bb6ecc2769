"""Prescribed paths of held points: a motion table's interpolants (:func:`table_lookup`) and
the path of a point of a vessel (:func:`rigid_end`, :mod:`symcable.scene.vessel`), as
CasADi expressions of t."""
from __future__ import annotations

import hashlib
import math

import casadi as ca
import numpy as np

__all__ = ["TABLE_VELOCITY_WIDTH", "quaternion", "rigid_dof", "rigid_end", "rotation",
           "table_lookup"]

#: the velocity of a table motion changes from one interval's slope to the next over this
#: fraction of the smallest row spacing about each row
#: (:func:`~symcable.models.common.elements.held_end`): far below any time step, far above
#: the round-off of t
TABLE_VELOCITY_WIDTH = 1e-6


def table_lookup(samples, columns: int = 3):
    """``(disp, vel)``: functions of t (SX) giving a table's displacement (``columns``,) and
    velocity as :func:`~symcable.models.common.elements.held_end` describes them, each a CasADi linear interpolant (a binary search
    per call in the graph and in its C, where the table written as a sum of ramps over its
    rows costs some ten operations per row, a large share of the residual for a long table)
    of the clamped time. The velocity is an interpolant through the slopes
    held over each interval and ramped over TABLE_VELOCITY_WIDTH of the smallest row
    spacing about each row (from zero before the first row to zero after the last)."""
    r = np.asarray(samples, float)
    tk, X = r[:, 0], r[:, 1:1 + columns]
    slopes = np.diff(X, axis=0) / np.diff(tk)[:, None]
    # at least a few units in the last place of the times, so that the grid increases
    # (rows far from t = 0: a table in seconds since some epoch)
    half = max(0.5 * TABLE_VELOCITY_WIDTH * float(np.min(np.diff(tk))),
               4.0 * float(np.spacing(np.max(np.abs(tk)))))
    grid = np.column_stack([tk - half, tk + half]).ravel()
    zero = np.zeros((1, columns))
    held = np.repeat(np.vstack([zero, slopes, zero]), 2, axis=0)[1:-1]  # (2 n, 3)
    tag = hashlib.sha1(r.tobytes()).hexdigest()[:12]  # the same in every process: one C
    d = ca.interpolant(f"table_disp_{tag}", "linear", [tk.tolist()], X.ravel().tolist())
    v = ca.interpolant(f"table_vel_{tag}", "linear", [grid.tolist()], held.ravel().tolist())

    def disp(t):
        return d(ca.fmin(ca.fmax(t, tk[0]), tk[-1]))

    def vel(t):
        return v(ca.fmin(ca.fmax(t, grid[0]), grid[-1]))
    return disp, vel


def rotation(rpy):
    """(3, 3) SX: body axes to global axes of [roll, pitch, yaw] (rad, SX),
    R = Rz(yaw) Ry(pitch) Rx(roll) (:func:`~symcable.scene.bodies.rotation_rpy`)."""
    cr, sr, cp, sp = ca.cos(rpy[0]), ca.sin(rpy[0]), ca.cos(rpy[1]), ca.sin(rpy[1])
    cy, sy = ca.cos(rpy[2]), ca.sin(rpy[2])
    return ca.vertcat(ca.horzcat(cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr),
                      ca.horzcat(sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr),
                      ca.horzcat(-sp, cp * sr, cp * cr))


def rigid_dof(path, motion_scale, t, ramp_on=1.0):
    """A vessel's six degrees of freedom at t (d, m; a, rad; SX (6,)) and their rates,
    ``motion_scale`` times the path's (a :class:`~symcable.scene.vessel.RigidPath`): its
    table's interpolants (the rates from the rows' slopes, as an end's table), or its
    components ramped in over ``path.ramp`` s from t = 0 ((1 - cos(pi t / ramp)) / 2;
    ``ramp_on`` = 0: at full amplitude)."""
    if path.samples is not None:
        disp, vel = table_lookup(path.samples, 6)
        return motion_scale * disp(t), motion_scale * vel(t)
    if not path.omega:  # still (a vessel's RAOs in a calm sea)
        return ca.SX.zeros(6), ca.SX.zeros(6)
    w = ca.DM(path.omega)
    amp, ph = ca.DM(np.asarray(path.amplitude, float)), ca.DM(np.asarray(path.phase, float))
    r = 1.0
    if path.ramp > 0:
        ramp = ca.if_else(t <= 0.0, 0.0, ca.if_else(t < path.ramp, 0.5 * (
            1.0 - ca.cos(math.pi * t / path.ramp)), 1.0))
        r = 1.0 - ramp_on * (1.0 - ramp)
    q = motion_scale * r * ca.sum1(amp * ca.cos(ph - ca.repmat(w * t, 1, 6))).T
    return q, ca.jacobian(q, t)


def rigid_end(path, pos_p, motion_scale, t, ramp_on=1.0):
    """A vessel point's position (3, m) and velocity (3, m/s) at t: ``pos_p`` (its position
    at the body's mean pose) plus d + (R(o + a) - R(o)) offset, (d, a) = :func:`rigid_dof`."""
    offset = ca.DM(path.offset)
    o = ca.DM([math.radians(v) for v in path.orientation_deg])
    R0 = rotation(o)
    q, qd = rigid_dof(path, motion_scale, t, ramp_on)
    z = ca.SX.sym("z", 6)
    placed = pos_p + z[:3] + ca.mtimes(rotation(o + z[3:]) - R0, offset)
    x = ca.substitute(placed, z, q)
    v = ca.mtimes(ca.substitute(ca.jacobian(placed, z), z, q), qd)
    return x, v


def quaternion(rpy):
    """(4,) SX: the unit quaternion (e1, e2, e3, e0) of [roll, pitch, yaw] (rad, SX)
    (:func:`~symcable.models.body.body.quaternion_rpy`'s, symbolic)."""
    r, p, y = 0.5 * rpy[0], 0.5 * rpy[1], 0.5 * rpy[2]
    cr, sr, cp, sp, cy, sy = ca.cos(r), ca.sin(r), ca.cos(p), ca.sin(p), ca.cos(y), ca.sin(y)
    return ca.vertcat(sr * cp * cy - cr * sp * sy, cr * sp * cy + sr * cp * sy,
                      cr * cp * sy - sr * sp * cy, cr * cp * cy + sr * sp * sy)
