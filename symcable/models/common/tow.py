"""The tow path (``kind = "tow"``, :mod:`symcable.scene.tow`) as CasADi expressions of t,
and what a run needs to start on it: where every held point is and how fast it moves at
the start, and the scene in the frame moving with the tow (:func:`moved_scene`).

The path, the displacement from the point's scene position (m; z stays 0): pieces in
time, each a closed form valid for every t, chosen by ``if_else`` on t (so Newton, the
Jacobians and the generated C see one smooth expression per piece):

- straight, from t = -inf to the first turn: P_k + U e(psi_k) (t - t_k), e(psi) =
  (cos psi, sin psi, 0), psi_0 the heading, P_0 = 0 at t_0 = ``start``;
- a turn of radius R through angle a (sign s = sign a: +1 to port) entered at t_k, P_k,
  psi_k: psi(t) = psi_k + s (U / R) (t - t_k), x = C + s R (sin psi, -cos psi, 0) with the
  centre C = P_k + s R (-sin psi_k, cos psi_k, 0), lasting R |a| / U;
- then straight on psi_k + a, and so on; the last straight runs to t = +inf.

Position and velocity are continuous at every joint (the arcs are tangent to the straights,
entered at their ends): the path is C1, its speed U everywhere; the acceleration jumps to
U^2 / R entering a turn.
"""
from __future__ import annotations

import math

import casadi as ca
import numpy as np

__all__ = ["held_motions", "held_tows", "moved_scene", "tow_path", "tow_state", "tow_velocities"]


def _pieces(m):
    """[(t_k, kind, P_k (2,), psi_k, extra)] of the path: kind "line" or "arc" (extra =
    (s, R, C (2,)))."""
    U, psi, t, P = m.speed, math.radians(m.heading_deg), m.start, np.zeros(2)
    out = []
    for after, R, angle in m.turns:
        out.append((t, "line", P.copy(), psi, None))
        t, P = t + after, P + U * after * np.array([math.cos(psi), math.sin(psi)])
        s = 1.0 if angle > 0 else -1.0
        C = P + s * R * np.array([-math.sin(psi), math.cos(psi)])
        out.append((t, "arc", P.copy(), psi, (s, R, C)))
        a = math.radians(angle)
        t, psi = t + R * abs(a) / U, psi + a
        P = C + s * R * np.array([math.sin(psi), -math.cos(psi)])
    out.append((t, "line", P.copy(), psi, None))
    return out


def tow_path(m, t):
    """(displacement (3, 1), velocity (3, 1)) of tow motion ``m`` at ``t`` (an SX/MX
    expression or a number): m and m/s (module docstring)."""
    U = m.speed
    xs, vs = [], []
    for tk, kind, P, psi, extra in _pieces(m):
        if kind == "line":
            e = np.array([math.cos(psi), math.sin(psi)])
            xs.append(ca.vertcat(P[0] + U * e[0] * (t - tk), P[1] + U * e[1] * (t - tk), 0.0))
            vs.append(ca.vertcat(U * e[0], U * e[1], 0.0) + 0.0 * t)
        else:
            s, R, C = extra
            ang = psi + s * (U / R) * (t - tk)
            xs.append(ca.vertcat(C[0] + s * R * ca.sin(ang), C[1] - s * R * ca.cos(ang), 0.0))
            vs.append(ca.vertcat(U * ca.cos(ang), U * ca.sin(ang), 0.0))
    starts = [p[0] for p in _pieces(m)]
    x, v = xs[-1], vs[-1]
    for k in range(len(xs) - 2, -1, -1):
        x = ca.if_else(t < starts[k + 1], xs[k], x)
        v = ca.if_else(t < starts[k + 1], vs[k], v)
    return x, v


def tow_state(m, t: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(displacement (3,), m; velocity (3,), m/s; acceleration (3,), m/s^2) of tow motion
    ``m`` at time ``t`` s, as numbers."""
    ts = ca.SX.sym("t")
    x, v = tow_path(m, ts)
    f = ca.Function("tow", [ts], [x, v, ca.jacobian(v, ts)])
    return tuple(np.asarray(a, float).ravel() for a in f(float(t)))


def held_motions(scene):
    """[(label, motion or None)] of everything the scene holds (pinned or clamped ends,
    fixed and vessel points, inline ends, fixed bodies and vessels), labelled by its key path
    (``"end_b"``, ``"points.ship"``, ``"lines.L1.end_a"``, ``"bodies.frame"``)."""
    out = []
    if scene.version == 1:
        for key in ("end_a", "end_b"):
            end = getattr(scene, key)
            if end.is_fixed:
                out.append((key, end.motion))
        return out
    for name, pt in scene.points.items():
        if not pt.is_free:
            out.append((f"points.{name}", pt.motion))
    for ln in scene.lines:
        for key in ("end_a", "end_b"):
            end = getattr(ln, key)
            if hasattr(end, "condition") and end.is_fixed:
                out.append((f"lines.{ln.name}.{key}", end.motion))
    for name, body in scene.bodies.items():
        if not body.is_free:  # a fixed body's None, a vessel's BodyMotion
            out.append((f"bodies.{name}", body.motion))
    return out


def held_tows(scene, t0: float) -> tuple[dict, str | None]:
    """``({label: (displacement (3,), velocity (3,), acceleration (3,))} of every held
    thing that tows, at t0; why not steady)``: the second is None when every held thing tows
    at one velocity at t0 (to 1e-9 of the speed), so that the steady tow exists; else the
    reason, naming a held thing."""
    tows, why = {}, None
    for label, m in held_motions(scene):
        if m is None or m.kind != "tow":
            why = why or (f"{label} is held {'still' if m is None else 'on a ' + m.kind + ' motion'}"
                          " while another point tows")
            continue
        tows[label] = tow_state(m, t0)
    if not tows:
        return tows, "nothing tows"
    u = [st[1] for st in tows.values()]
    if why is None and any(np.linalg.norm(w - u[0]) > 1e-9 * np.linalg.norm(u[0]) for w in u):
        why = "the towed points move at different velocities at the start"
    return tows, why


def moved_scene(scene, tows: dict, velocity=None):
    """The scene (a new, re-validated Scene) with every towed held thing at its position at
    the start (its scene position plus the displacement in ``tows``, :func:`held_tows`), the
    free points and bodies moved with them when they all move by one displacement, and,
    given the tow ``velocity`` (3,), m/s, the current (and current profile) seen from the
    frame moving at it: the water's velocity minus the tow's."""
    from ...scene import load_scene
    d = scene.to_dict()
    shifts = [st[0] for st in tows.values()]
    common = shifts[0] if shifts and all(np.allclose(s, shifts[0], rtol=0, atol=1e-12)
                                         for s in shifts) else None
    add = lambda pos, dx: [float(a + b) for a, b in zip(pos, dx)]  # noqa: E731
    if scene.version == 1:
        for key in ("end_a", "end_b"):
            if key in tows:
                d[key]["position"] = add(d[key]["position"], tows[key][0])
    else:
        for name, pt in d["points"].items():
            label = f"points.{name}"
            if label in tows:
                pt["position"] = add(pt["position"], tows[label][0])
            elif common is not None and scene.points[name].is_free:
                pt["position"] = add(pt["position"], common)
        for ln in d["lines"]:
            for key in ("end_a", "end_b"):
                label = f"lines.{ln['name']}.{key}"
                if label in tows:
                    ln[key]["position"] = add(ln[key]["position"], tows[label][0])
        for name, body in d.get("bodies", {}).items():
            if common is not None and scene.bodies[name].is_free:
                body["position"] = add(body["position"], common)
    if velocity is not None:
        env = d["environment"]
        # (a current profile is added to the uniform current: it stays as it is)
        env["current"] = [float(c - u) for c, u in zip(env["current"], velocity)]
    return load_scene(d)


def tow_velocities(mech, velocity) -> np.ndarray:
    """(n_v,) every translational velocity of the mechanism (a line's node, a free point,
    a body's reference point: the entries its coordinate names end in ``.x``, ``.y``,
    ``.z``) at ``velocity`` (3,), m/s; every other (a body's angular velocity) zero."""
    _, names = mech.coordinate_names()
    v0 = np.zeros(mech.n_v)
    for i, n in enumerate(names):
        axis = n.rsplit(".", 1)[-1]
        if axis in ("x", "y", "z"):
            v0[i] = velocity["xyz".index(axis)]
    return v0
