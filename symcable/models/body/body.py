"""A rigid body (``[bodies.NAME]``, :class:`~symcable.scene.bodies.Body`) as a part of a
Mechanism: six degrees of freedom.

Coordinates. ``q = (x, y, z, e1, e2, e3, e0)``: the reference point O in global axes (m),
then a quaternion e = e0 + (e1, e2, e3), its scalar part last (the one entry past n_v: see
:mod:`.assembly`). ``v = (v_O, w)``: O's velocity in global axes (m/s) and the angular
velocity in body axes (rad/s). The kinematics ``q' = G(q) v`` are x' = v_O and
e' = e (x) (0, w) / 2 (:func:`quaternion_rate`).

Why a quaternion: it has no singular orientation (Euler angles lock at a pitch of 90
degrees; a rotation vector from a fixed orientation at a turn of 360 degrees, and a towed
body turns through that), it costs one coordinate more than the rotations, and the generic
solvers carry that coordinate without knowing it is one: in statics its ``rest`` row
``|e|^2 - 1 = 0`` (times the force scale, N) makes the static system square; in time
q' = G(q) v keeps |e| to the integrator's error, and every expression reads the rotation of
e / |e| (:func:`rotation`), so the drift of |e| changes nothing. Incremental rotations (as
in Goyal & Perkins' rod frames) would need the solvers to re-base the reference orientation
between steps. Why O and body-axis w: lines attach at body points relative to O, a scene
places O, and MoorPy and MoorDyn give a body's stiffness and forces about it; with w in body
axes the inertia is constant.

Equations (virtual work, M(q) v' = f), R = R(e / |e|) body to global, c the centre of
gravity and b the centre of buoyancy (body axes, from O), [a] the cross-product matrix:

- rigid body: M = [[m I, -m R [c]], [m [c] R^T, I_O]] with I_O = I_G + m (|c|^2 I - c c^T);
  f = (-m R (w x (w x c)), -w x I_O w) (the centripetal and gyroscopic terms);
- weight -m g e_z at c, buoyancy rho g V e_z at b (the body taken as submerged wherever
  it is), both times the parameter ``load``;
- drag at b along body axes, 0.5 rho cd_area_i |u| u_i, u = R^T (U - v_b) the water's
  velocity relative to b in body axes (|u| smoothed as the lines',
  sqrt(|u|^2 + DRAG_SPEED^2)); no rotational drag;
- in waves (``[environment.waves]``), the fluid's velocity at b joins the current in the
  drag, and Morison's inertia force acts at b: Froude-Krylov rho V a plus the added mass's
  R D R^T a on the fluid acceleration a there (:mod:`~symcable.models.common.waves`; D =
  rho diag(ca_volume), as below); the body taken as submerged wherever it is, the
  kinematics at b alone (a body small against the waves' length);
- added mass rho ca_volume_i along body axis i, at b, on b's acceleration (a uniform steady
  current U: the relative acceleration is the body's): M gains J_b^T R D R^T J_b with
  J_b = [I, -R [b]] (v_b = J_b v) and f gains -J_b^T R D R^T R (w x (w x b)). This is a
  point mass's form, not Kirchhoff's equations: with ca_volume not the same along
  every axis, the Munk moment of potential flow and the rate of the rotating added-mass
  tensor are left out (the body's energy is then conserved only for an isotropic
  ca_volume); no added inertia of rotation;
- in statics only (parameter ``hold`` = 1, 0 in time), a spring of stiffness
  :data:`HOLD_STIFFNESS` x (force scale) x 1 m per radian towards the scene's orientation
  (``hold_to``): a body on one line is free to spin about it, and the spring picks the
  scene's spin angle out of that family; its moment, at most pi x 1e-10 of the force scale
  (N m), stays below the static tolerance (1e-9 of it), so where the lines do hold the
  orientation the equilibrium is theirs;
- for a static start only (parameter ``pull``, 0 otherwise), stiff springs towards the
  scene's pose, :data:`PULL_STIFFNESS` x (force scale) per length (translation) and x
  (force scale) x (body size) per radian, times (r^pull - 1) / (r - 1) with r =
  :data:`PULL_RANGE`: from lines relaxed with the body held where the scene puts it, the
  static solve continues ``pull`` from 1 to 0, releasing the body
  (:func:`~symcable.models.system.build_system`'s starts); the factor falls
  geometrically along most of the way (1e-4 at pull = 0.5), so no part of the release is
  crowded into the last steps of the continuation.

A line's end on the body (:func:`attachment`, an :class:`~.assembly.Attached` joint) is the
body point x_O + R r, moving at v_O + R (w x r): the line's end node, its lumped mass
included, becomes a point of the body, and its force acts there (virtual work).

The static solver judges no stability of an equilibrium with a free body: the body's rest
row takes the mechanism to the solver's branch for first-order states, which needs
``stability_coordinates`` (the quaternion's entries are not the rotation's, so none are
given); an equilibrium is returned stable or not (``stats["stable"]`` None).

Periodic solves. In time |e| persists at whatever value it has, so periodic states would
form a family (every norm); the kinematics carry e' += k (1 - |e|^2) e with k the block
``norm_rate`` (1/s, 0 by default: statics, time runs and modes see none of it), under which
|e|^2 relaxes to 1 at the rate 2 k |e|^2 and nothing else changes (every expression reads
e / |e|). The periodic solvers set k (``StateNames.rate_blocks``), so the norm's Floquet
multiplier is exp(-2 k T) and the periodic state is isolated.

Parameter blocks (in waves also ``wave_scale``, ``ramp`` and ``waves``, as a free point's):
``load`` (1), ``current`` (3, m/s), ``hold`` (1), ``pull`` (1),
``hold_to`` (7: the scene's pose, the position (m) and the quaternion (e1, e2, e3, e0)),
``norm_rate`` (1, 1/s).
"""
from __future__ import annotations

import math

import casadi as ca
import numpy as np

from ...scene import Environment
from ...scene.bodies import Body
from ...mechanism.assembly import Attached
from ..common.elements import DRAG_SPEED
from ..common.waves import wave_block, wave_kinematics
from ...mechanism.mechanism import (Layout, Mechanism, Output, ParamBlocks, PartLayout, Scales,
                                   StateNames)

__all__ = ["HOLD_STIFFNESS", "PULL_STIFFNESS", "attachment", "body_outputs", "body_part",
           "quaternion_rpy", "rotation", "roll_pitch_yaw", "start_q"]

#: the statics' spring towards the scene's orientation, N m per radian per N of force scale
#: (module docstring)
HOLD_STIFFNESS = 1e-10
#: the static start's springs (module docstring): the force scale moves the body by 1e-3 of
#: the length scale, or turns it by 1e-3 rad
PULL_STIFFNESS = 1e3
#: the ratio over which the start's springs fall geometrically (module docstring)
PULL_RANGE = 1e8


def quaternion_rpy(roll_pitch_yaw_deg) -> np.ndarray:
    """(4,) the unit quaternion (e1, e2, e3, e0) of R = Rz(yaw) Ry(pitch) Rx(roll) (degrees,
    :func:`~symcable.scene.bodies.rotation_rpy`)."""
    r, p, y = (0.5 * math.radians(a) for a in roll_pitch_yaw_deg)
    cr, sr, cp, sp, cy, sy = math.cos(r), math.sin(r), math.cos(p), math.sin(p), \
        math.cos(y), math.sin(y)
    return np.array([sr * cp * cy - cr * sp * sy, cr * sp * cy + sr * cp * sy,
                     cr * cp * sy - sr * sp * cy, cr * cp * cy + sr * sp * sy])


def rotation(e):
    """(3, 3) the rotation of the quaternion ``e`` = (e1, e2, e3, e0) / |e| (any norm),
    body axes to global axes."""
    n = e / ca.sqrt(ca.dot(e, e))
    x, y, z, w = n[0], n[1], n[2], n[3]
    return ca.vertcat(
        ca.horzcat(1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)),
        ca.horzcat(2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)),
        ca.horzcat(2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)))


def quaternion_rate(e, w):
    """e' = e (x) (0, w) / 2 in the order (e1, e2, e3, e0), w in body axes (rad/s): it keeps
    |e| (e . e' = 0)."""
    ev, e0 = e[0:3], e[3]
    return 0.5 * ca.vertcat(e0 * w + ca.cross(ev, w), -ca.dot(ev, w))


def roll_pitch_yaw(R):
    """(3,) [roll, pitch, yaw], degrees, of R = Rz(yaw) Ry(pitch) Rx(roll); pitch in
    [-90, 90]."""
    deg = 180.0 / math.pi
    return deg * ca.vertcat(ca.atan2(R[2, 1], R[2, 2]),
                            ca.atan2(-R[2, 0], ca.sqrt(R[2, 1] ** 2 + R[2, 2] ** 2)),
                            ca.atan2(R[1, 0], R[0, 0]))


def _skew(a):
    return ca.vertcat(ca.horzcat(0, -a[2], a[1]), ca.horzcat(a[2], 0, -a[0]),
                      ca.horzcat(-a[1], a[0], 0))


def body_part(body: Body, env: Environment, length: float = 1.0) -> Mechanism:
    """A free body as a Mechanism of six degrees of freedom (module docstring).

    ``length`` (m): a length of the system it sits in (its longest line), for the scales
    of its position (0.1 of it) and velocity (sqrt(g length)). Layout part ``body`` with
    two rows: the position's entries of q and v, and the quaternion's vector part with w.
    Outputs: ``position`` (m), ``orientation`` (the unit quaternion (e0, e1, e2, e3), scalar
    first), ``roll_pitch_yaw`` (deg), ``velocity`` (m/s, of O), ``angular_velocity`` (rad/s,
    body axes), ``own_force`` and ``own_moment`` (N, N m: weight, buoyancy and drag, global
    axes, the moment about O), ``potential_energy``, ``kinetic_energy`` (J).
    """
    rho = 0.0 if env.in_air else env.water_density
    g = env.gravity
    m, V = body.mass, body.volume
    c, b = ca.DM(body.center_of_gravity), ca.DM(body.center_of_buoyancy)
    sea = () if env.waves is None or rho == 0 else (
        wave_block(env.waves, env.depth, env.gravity),)
    params = ParamBlocks(("load", "current", "hold", "pull", "hold_to", "norm_rate")
                         + (("wave_scale", "ramp", "waves") if sea else ()),
                         (1, 3, 1, 1, 7, 1) + ((1, 1, sea[0].size) if sea else ()),
                         np.concatenate([[1.0], env.current, [0.0, 0.0], start_q(body), [0.0]]
                                        + ([[1.0, 1.0], sea[0]] if sea else [])))
    q, v, t, p = ca.SX.sym("q", 7), ca.SX.sym("v", 6), ca.SX.sym("t"), ca.SX.sym("p", params.n)
    load, current, hold, pull, x_to, e_to = p[0], p[1:4], p[4], p[5], p[6:9], p[9:13]
    norm_rate = p[13]
    x, e, vO, w = q[0:3], q[3:7], v[0:3], v[3:6]
    R = rotation(e)
    I3 = ca.DM.eye(3)

    cx = _skew(c)
    IO = ca.DM(np.diag(body.inertia)) + m * (ca.dot(c, c) * I3 - ca.mtimes(c, c.T))
    mass = ca.vertcat(ca.horzcat(m * I3, -m * ca.mtimes(R, cx)),
                      ca.horzcat(m * ca.mtimes(cx, R.T), IO))
    force = ca.vertcat(-m * ca.mtimes(R, ca.cross(w, ca.cross(w, c))),
                       -ca.cross(w, ca.mtimes(IO, w)))
    Jb = ca.horzcat(I3, -ca.mtimes(R, _skew(b)))  # v_b = Jb v
    D = ca.DM(np.diag(rho * np.asarray(body.ca_volume, float)))
    terms = ["body inertia"]
    if rho > 0 and any(body.ca_volume):
        terms.append("body added mass")
        A = ca.mtimes([R, D, R.T])
        mass = mass + ca.mtimes([Jb.T, A, Jb])
        force = force - ca.mtimes([Jb.T, A, R, ca.cross(w, ca.cross(w, b))])
    weight = load * ca.vertcat(0.0, 0.0, -m * g)
    buoyancy = load * ca.vertcat(0.0, 0.0, rho * g * V)
    water = current
    inertia = ca.SX.zeros(3, 1)
    if sea:  # at b: the waves' velocity joins the current; Froude-Krylov and added mass
        _, u_w, a_w = wave_kinematics(env.waves.count, env.depth is None, env.waves.stretching,
                                      x + ca.mtimes(R, b), t, p[params.slice("waves")],
                                      p[params.slice("wave_scale")], p[params.slice("ramp")])
        water = water + u_w
        inertia = rho * V * a_w + ca.mtimes([R, D, R.T, a_w])
        terms.append("body wave inertia")
    u = ca.mtimes(R.T, water - ca.mtimes(Jb, v))  # the water past b, body axes
    drag = 0.5 * rho * ca.DM(body.cd_area) * ca.sqrt(ca.dot(u, u) + DRAG_SPEED ** 2) * u
    at_b = buoyancy + ca.mtimes(R, drag) + inertia
    own_moment_body = ca.cross(c, ca.mtimes(R.T, weight)) + ca.cross(b, ca.mtimes(R.T, at_b))
    terms += ["body weight"] + (["body drag"] if rho > 0 and any(body.cd_area) else [])
    F_scale = max(m * g, rho * g * V, 1e-6)
    size = max(1.0, float(np.max(np.abs(np.r_[body.center_of_gravity,
                                              body.center_of_buoyancy]))))
    released = (ca.exp(pull * math.log(PULL_RANGE)) - 1.0) / (PULL_RANGE - 1.0)
    k_turn = hold * HOLD_STIFFNESS * F_scale * 1.0 + released * PULL_STIFFNESS * F_scale * size
    k_move = released * PULL_STIFFNESS * F_scale / max(length, 1.0)
    n_to = e_to / ca.sqrt(ca.dot(e_to, e_to))
    n = e / ca.sqrt(ca.dot(e, e))
    # the rotation from hold_to to e in body axes, delta = conj(hold_to) (x) n
    d0 = ca.dot(n_to, n)
    dv = n_to[3] * n[0:3] - n[3] * n_to[0:3] - ca.cross(n_to[0:3], n[0:3])
    force = force + ca.vertcat(weight + at_b - k_move * (x - x_to),
                               own_moment_body - 2.0 * k_turn * d0 * dv)

    xG, xB = x + ca.mtimes(R, c), x + ca.mtimes(R, b)
    potential = -ca.dot(weight, xG) - ca.dot(buoyancy, xB) + 2.0 * k_turn * (1 - d0 * d0) \
        + 0.5 * k_move * ca.dot(x - x_to, x - x_to)
    outputs = {
        "position": Output(x, "m", body.name, "position of the reference point"),
        "orientation": Output(ca.vertcat(n[3], n[0:3]), "1", body.name,
                              "unit quaternion (e0, e1, e2, e3), body to global axes"),
        "roll_pitch_yaw": Output(roll_pitch_yaw(R), "deg", body.name,
                                 "[roll, pitch, yaw] of R = Rz(yaw) Ry(pitch) Rx(roll)"),
        "velocity": Output(vO, "m/s", body.name, "velocity of the reference point"),
        "angular_velocity": Output(w, "rad/s", body.name, "angular velocity, body axes"),
        "own_force": Output(weight + at_b, "N", body.name, "weight, buoyancy and drag"),
        "own_moment": Output(ca.mtimes(R, own_moment_body), "N m", body.name,
                             "moment of weight, buoyancy and drag about the reference point, "
                             "global axes"),
        "potential_energy": Output(potential, "J", body.name, "potential of weight and "
                                                              "buoyancy"),
        "kinetic_energy": Output(0.5 * ca.dot(v, ca.mtimes(mass, v)), "J", body.name,
                                 "kinetic energy, added mass included"),
    }
    rest = F_scale * (ca.dot(e, e) - 1.0)
    vel = math.sqrt(g * max(length, 1.0))
    scales = Scales(q=np.r_[np.full(3, 0.1 * max(length, 1.0)), np.full(4, 0.25)],
                    v=np.r_[np.full(3, vel), np.full(3, vel / size)], z=np.zeros(0),
                    force=F_scale, mass=m)
    layout = Layout(3, {body.name: PartLayout("body", np.zeros(2), np.arange(6).reshape(2, 3),
                                              np.arange(6).reshape(2, 3))},
                    StateNames((f"{body.name}.e0",), "1", f"[bodies.{body.name}] (the scalar "
                               "part of its orientation quaternion)", "", ("norm_rate",)))
    return Mechanism(
        name=body.name, q=q, v=v, z=ca.SX.sym("z", 0), t=t, p=p, params=params, mass=mass,
        force=force, constraint=ca.SX.zeros(0, 1), scales=scales, starts=tuple,
        outputs=outputs, layout=layout, kinematics=ca.vertcat(vO, quaternion_rate(e, w) + norm_rate * (1.0 - ca.dot(e, e)) * e),
        rest=rest, terms=tuple(terms),
        static_params={"hold": np.ones(1), **({"wave_scale": np.zeros(1)} if sea else {})},
        stability_when=ca.SX(1.0))


def start_q(body: Body) -> np.ndarray:
    """(7,) the body's q where the scene puts it."""
    return np.r_[np.asarray(body.position, float), quaternion_rpy(body.orientation_deg)]


def attachment(name: str, body: str, node: tuple[str, int], offset) -> Attached:
    """The joint that makes ``node`` (part, index) the point ``offset`` (m, body axes) of
    the body part ``body``: at x_O + R r, moving at v_O + R (w x r)."""
    qb, vb = ca.SX.sym("q", 7), ca.SX.sym("v", 6)
    r = ca.DM(np.asarray(offset, float))
    R = rotation(qb[3:7])
    pos = ca.Function("attached_position", [qb], [qb[0:3] + ca.mtimes(R, r)])
    vel = ca.Function("attached_velocity", [qb, vb], [vb[0:3] + ca.mtimes(R, ca.cross(vb[3:6], r))])
    return Attached(name, node, body, pos, vel)


def body_outputs(body: Body, out: dict, ends: list, pose=None) -> dict:
    """The system outputs of ``body`` from the assembled ones ``out`` (namespaced) and the
    line ends on it, ``ends`` = [(line, "a" | "b", node index, offset)]: ``position``,
    ``orientation``, ``roll_pitch_yaw`` (a fixed body's constant), ``force`` (N, the sum of
    the lines' end forces there) and ``moment`` (N m, their moment about the reference point,
    global axes), and for a free body ``net_force`` (6,): those plus its own weight,
    buoyancy and drag (N, N m; zero in equilibrium). Keys ``"NAME.*"``. A vessel's pose
    ``pose`` = (position (3, m), [roll, pitch, yaw] (3, deg), quaternion (4, e1 e2 e3 e0)),
    expressions of t (:func:`~symcable.models.common.rigid.rigid_dof`)."""
    name = body.name
    new = {}
    if pose is not None:
        x, rpy, e = pose
        new[f"{name}.position"] = Output(x, "m", name, "position of the reference point")
        new[f"{name}.orientation"] = Output(ca.vertcat(e[3], e[:3]), "1", name,
                                            "unit quaternion (e0, e1, e2, e3)")
        new[f"{name}.roll_pitch_yaw"] = Output(rpy, "deg", name, "[roll, pitch, yaw]")
    elif not body.is_free:
        e = quaternion_rpy(body.orientation_deg)
        # a fixed body's reference point from its first line end, held at the body point
        # ``offset`` (a parameter of the line): the body's position is then a number of the
        # parameters, not of the expressions (:mod:`symcable.models.structure`)
        x = ca.DM(body.position)
        if ends:
            line, _, node, offset = ends[0]
            x = out[f"{line}.positions"].expr[node, :].T \
                - ca.DM(body.rotation @ np.asarray(offset, float))
        new[f"{name}.position"] = Output(x, "m", name, "position of the reference point")
        new[f"{name}.orientation"] = Output(ca.DM(np.r_[e[3], e[:3]]), "1", name,
                                            "unit quaternion (e0, e1, e2, e3)")
        new[f"{name}.roll_pitch_yaw"] = Output(ca.DM(body.orientation_deg), "deg", name,
                                               "[roll, pitch, yaw]")
    x = (out.get(f"{name}.position") or new[f"{name}.position"]).expr
    force, moment = ca.DM.zeros(3), ca.DM.zeros(3)
    for line, key, node, _ in ends:
        f = out[f"{line}.end_force_{key}"].expr
        at = out[f"{line}.positions"].expr[node, :].T
        force = force + f
        moment = moment + ca.cross(at - x, f)
    new[f"{name}.force"] = Output(force, "N", name, "force of the attached lines on the body")
    new[f"{name}.moment"] = Output(moment, "N m", name, "moment of the attached lines about "
                                                        "the reference point, global axes")
    if body.is_free:
        new[f"{name}.net_force"] = Output(
            ca.vertcat(force + out[f"{name}.own_force"].expr,
                       moment + out[f"{name}.own_moment"].expr), "N", name,
            "net force and moment (N m, about the reference point) on the body: zero in "
            "equilibrium")
    return new
