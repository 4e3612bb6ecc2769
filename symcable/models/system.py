"""Several cable3d lines, points and bodies as ONE Mechanism (scene version 2:
``[points.NAME]``, ``[bodies.NAME]``, ``[[lines]]``).

Each line is a part built by :func:`~symcable.models.cable3d.line.build_cable3d` from a one-line
scene (:func:`line_scene`): an end at a fixed or vessel point is held there by the line
itself (with the point's motion, exactly as a version-1 end), an end at a free point is a
free node of the line with no force of its own. Each free point is a small part of its own
(:func:`point_part`): one node with its mass and added mass, its weight less its buoyancy,
Morison drag on its velocity relative to the current, its applied force and, on a scene
with a seabed, its own contact with the bed (:func:`point_contact`: a clump weight rests on
the bed as the lines do, instead of sinking into it through the contact of the few line
nodes beside it). The parts are
assembled (:func:`~symcable.mechanism.assembly.assemble`) with a :class:`Shared` joint between
every free point's node and each line end attached to it, so the lines' end forces and the
point's loads add up there by virtual work. Each free body is a part of six degrees of
freedom (:func:`~symcable.models.body.body.body_part`), and a line's end on it is made a point of
the body by an :class:`~symcable.mechanism.assembly.Attached` joint named ``"LINE.end_a"`` /
``"LINE.end_b"`` (:func:`~symcable.models.body.body.attachment`); a line's end on a fixed body
is held at the body's point, as at a fixed point.

Outputs, beside each part's own (namespaced: ``"line1.axial_force"``, ``"line1.end_force_b"``,
``"buoy.own_force"``, ...):

- ``"P.position"`` (3,), m, of every point P;
- ``"P.force"`` (3,), N: the force the lines attached to P exert on it, the sum of their end
  forces there (``"LINE.end_force_a"`` / ``"_b"``). A line's end node is P's node; of the
  loads on that node, P's own (weight less buoyancy, drag, applied force, its own seabed
  contact: ``"P.own_force"``) are P's, and the line's are its end segment's axial pull
  plus the loads of its half segment lumped on the node: that half segment's weight less
  buoyancy and drag, and the seabed's contact, damper and friction under it. So a line's
  end force is its tension at the end: lying on the bed up to a point resting there, the
  bed carries the half segment (:func:`~symcable.models.common.seabed.joined_on`) and the
  force is the end segment's axial pull, whatever the segment count (as a catenary's end
  tension there); hanging from the point, it is that pull plus the half segment's weight;
- ``"P.net_force"`` (3,), N, free points only: that plus the point's own loads (zero in
  equilibrium; its mass times its acceleration in motion);
- ``"B.position"`` (3,), m, ``"B.orientation"`` (4,) (unit quaternion, scalar first),
  ``"B.roll_pitch_yaw"`` (3,), deg, ``"B.force"`` (3,), N, and ``"B.moment"`` (3,), N m, of
  every body B: the force of the lines attached to it (the sum of their end forces there)
  and its moment about B's reference point, global axes
  (:func:`~symcable.models.body.body.body_outputs`); free bodies also ``"B.velocity"``,
  ``"B.angular_velocity"`` (body axes), ``"B.own_force"``, ``"B.own_moment"`` and
  ``"B.net_force"`` (6,), the lines' force and moment plus the body's own (zero in
  equilibrium);
- ``"kinetic_energy"``, ``"potential_energy"``, J, of the whole system.

Static starts, in order: each line's closed-form elastic catenary between its end points
(free points and bodies where the scene puts them; a line with a free inline end hangs
straight from its other end), then the minimum of the whole network's potential energy from
there (:func:`~symcable.models.common.relax.relaxed_network`), the bodies held where the scene
puts them; with free bodies, that again with the bodies pulled there by stiff springs
(their parameter ``pull`` = 1), continued to their release (``pull`` = 0).
"""
from __future__ import annotations

import dataclasses

import casadi as ca
import numpy as np

from ..scene import BodyEnd, Environment, Scene
from ..scene.bodies import BodyKind
from ..scene.vessel import rigid_path
from .common.rigid import quaternion, rigid_dof
from ..scene.one_line import line_scene
from ..scene.points import Point
from .common import terms
from ..mechanism.assembly import Shared, assemble
from .body.body import attachment, body_outputs, body_part, start_q
from .common.elements import DRAG_SPEED
from .cable3d.line import _lumped, build_cable3d, force_scale
from .common.drag import law_table
from .common.starts import _catenary, _hanging
from ..mechanism.mechanism import Layout, Mechanism, Output, ParamBlocks, PartLayout, Scales, Start
from .common.segments import segment_table, slack_law
from .common.relax import _ramp_integral, drag_loads, relaxed_network
from .common.seabed import CONTACT_SMOOTHING
from .structure import rebind, structure_key
from .common.waves import wave_block, wave_kinematics

__all__ = ["build_system", "line_scene", "point_contact", "point_part"]


def _point_loads(pt: Point, env: Environment) -> tuple[float, np.ndarray, float]:
    """(net weight (m - rho V) g, N downward; applied force (3,), N; water density)."""
    rho = 0.0 if env.in_air else env.water_density
    applied = np.zeros(3) if pt.force is None else np.asarray(pt.force, float)
    return (pt.mass - rho * pt.volume) * env.gravity, applied, rho


#: a free point's contact smoothing over its penetration (:func:`point_contact`): 1 %, not
#: the lines' CONTACT_SMOOTHING. The point's stiffness carries everything that can press it
#: down, so the ramp's tail K delta^2 / 4 g is that much larger: at 10 % it holds buoys and
#: clumps up by a visible force far above the bed, enough to fail a balance check
POINT_CONTACT_SMOOTHING = 0.01


def point_contact(scene: Scene, name: str) -> tuple[float, float] | None:
    """(stiffness K, N/m; smoothing width, m) of free point ``name``'s seabed contact, or None
    when the scene has no seabed. The contact is the lines' penalty law on the point's node,
    K ramp(-depth - z) (:func:`~symcable.models.common.terms.smooth_ramp`), with K such that what
    can press the point onto the bed (its own net weight and applied force and the whole
    weight of the lines attached to it) sinks it no deeper than the most sinking section of
    those lines under its own weight, max |w| / (stiffness d); the smoothing width is
    POINT_CONTACT_SMOOTHING of that."""
    sb = scene.seabed
    if sb is None:
        return None
    pt, env = scene.points[name], scene.environment
    secs = [s for ln in scene.lines if name in (ln.end_a, ln.end_b) for s in ln.sections]
    weight, applied, _ = _point_loads(pt, env)
    press = max(weight, 0.0) + float(np.linalg.norm(applied)) \
        + sum(abs(s.line_type.weight) * s.length for s in secs)
    sink = max(max(abs(s.line_type.weight) / (sb.stiffness * s.line_type.diameter) for s in secs),
               1e-6 * min(s.length for s in secs))
    return max(press, 1e-6) / sink, max(POINT_CONTACT_SMOOTHING * sink, 1e-6)


def point_part(pt: Point, env: Environment, seabed=None, contact=None) -> Mechanism:
    """A free point as a Mechanism of one node (q its position, m): mass ``mass`` plus added
    mass ``ca rho V_a`` in every direction (kg); force (N) ``load (-(mass - rho volume) g e_z
    + force)`` plus Morison drag ``0.5 rho cd_area_i |u| u_i``, u = current - v (|u| smoothed
    as the lines'). With a ``seabed`` and ``contact`` = (K, width) (:func:`point_contact`):
    the contact N = K ramp(-depth - z) upward, a damper -damping (K / stiffness) v_z while in
    contact (the lines' pressure per speed over the same footprint), and regularised Coulomb
    friction -mu N v_h / sqrt(|v_h|^2 + v_eps^2) with the isotropic ``friction`` (or, when only
    friction_axial / friction_lateral are given, the larger). Parameter blocks ``load`` (1),
    ``current`` (3, m/s), ``bed`` (1, scales K) and ``contact`` (K, N/m, and the smoothing
    width, m: numbers of the lines attached, so parameters), in waves ``wave_scale``,
    ``ramp`` and ``waves`` (:mod:`~symcable.models.common.waves`). Outputs ``position``, ``own_force`` (those loads),
    ``contact_force`` (N, upward), ``potential_energy`` (of the weight, buoyancy, applied
    force and contact, J), ``kinetic_energy`` (J)."""
    weight, applied, rho = _point_loads(pt, env)
    q, v = ca.SX.sym("q", 3), ca.SX.sym("v", 3)
    t = ca.SX.sym("t")
    sea = () if env.waves is None else (wave_block(env.waves, env.depth, env.gravity),)
    params = ParamBlocks(("load", "current", "bed", "contact")
                         + (("wave_scale", "ramp", "waves") if sea else ()),
                         (1, 3, 1, 2) + ((1, 1, sea[0].size) if sea else ()),
                         np.concatenate([[1.0], env.current, [1.0],
                                         contact if contact is not None else [0.0, 1.0]]
                                        + ([[1.0, 1.0], sea[0]] if sea else [])))
    p = ca.SX.sym("p", params.n)
    load, current, bed = p[0], p[1:4], p[4]
    u = current - v
    inertia = ca.SX.zeros(3, 1)
    if sea:  # the waves' velocity joins the current; Morison inertia rho (V + ca V_a) a
        _, u_w, a_w = wave_kinematics(env.waves.count, env.depth is None, env.waves.stretching,
                                      q, t, p[params.slice("waves")],
                                      p[params.slice("wave_scale")], p[params.slice("ramp")])
        u = u + u_w
        inertia = rho * (pt.volume + pt.ca * pt.added_volume) * a_w
    speed = ca.sqrt(ca.dot(u, u) + DRAG_SPEED ** 2)
    drag = 0.5 * rho * ca.DM(pt.drag_area) * speed * u
    own = load * (ca.vertcat(0.0, 0.0, -weight) + ca.DM(applied)) + drag + inertia
    m = pt.mass + pt.ca * rho * pt.added_volume
    mass = m * ca.SX.eye(3)
    names = ["point weight"] + (["point drag"] if rho > 0 and any(pt.drag_area) else []) \
        + (["point force"] if np.any(applied) else []) \
        + (["point wave inertia"] if sea and rho > 0 else [])
    potential = load * (weight * q[2] - ca.dot(ca.DM(applied), q))
    normal = ca.SX(0.0)
    if seabed is not None and contact is not None:
        K, width = p[5], p[6]
        pen = -env.depth - q[2]
        normal = bed * K * terms.smooth_ramp(pen, width)
        names.append("point seabed")
        own = own + ca.vertcat(0.0, 0.0, normal)
        potential = potential + bed * K * _ramp_integral(pen, width)
        on = 0.5 * (1.0 + pen / ca.sqrt(pen * pen + width * width))
        if seabed.damping > 0:
            own = own - ca.vertcat(0.0, 0.0, seabed.damping * K / seabed.stiffness * v[2] * on)
        mu = seabed.friction if seabed.friction > 0 else max(seabed.mu_axial, seabed.mu_lateral)
        if mu > 0:
            vh = v[0:2]
            slip = ca.sqrt(ca.dot(vh, vh) + seabed.friction_velocity ** 2)
            own = own + ca.vertcat(-mu * normal * vh / slip, 0.0)
    outputs = {
        "position": Output(q, "m", pt.name, "position of the point"),
        "own_force": Output(own, "N", pt.name, "weight, buoyancy, drag, applied force and "
                                               "seabed contact on the point"),
        "contact_force": Output(normal, "N", pt.name, "seabed contact force on the point"),
        "potential_energy": Output(potential, "J", pt.name, "potential of the point's weight, "
                                                            "buoyancy, applied force and contact"),
        "kinetic_energy": Output(0.5 * m * ca.dot(v, v), "J", pt.name, "kinetic energy"),
    }
    scale = max(abs(weight), float(np.linalg.norm(applied)), 1e-6)
    return Mechanism(
        name=pt.name, q=q, v=v, z=ca.SX.sym("z", 0), t=t, p=p, params=params, mass=mass,
        force=own, constraint=ca.SX.zeros(0, 1),
        scales=Scales(q=np.ones(3), v=np.ones(3), z=np.zeros(0), force=scale,
                      mass=max(m, 1e-6)),
        starts=tuple, outputs=outputs,
        layout=Layout(3, {pt.name: PartLayout("point", np.zeros(1), np.arange(3)[None, :],
                                              np.arange(3)[None, :])}),
        terms=tuple(names), stability_when=ca.SX(1.0),
        static_params={"wave_scale": np.zeros(1)} if sea else {})


def build_system(scene: Scene, *, symbols: bool = True) -> Mechanism:
    """The lines, points and bodies of a version-2 cable3d scene as one Mechanism (module
    docstring). ``symbols``: False builds the numbers alone on placeholder expressions
    (:mod:`symcable.models.structure`)."""
    env = scene.environment
    parts, joints = [], []
    built: dict = {}  # a line's structure -> the first line part of it (its template)
    for line in scene.lines:
        joined = tuple(isinstance(e, str) and scene.points[e].is_free
                       for e in (line.end_a, line.end_b))
        parts.append(_line_part(line_scene(scene, line), line.name, joined, symbols, built))
    for name, pt in scene.points.items():
        if pt.is_free:
            parts.append(point_part(pt, env, scene.seabed, point_contact(scene, name)))
    on_body: dict[str, list] = {name: [] for name in scene.bodies}
    for line in scene.lines:
        for key, node in (("a", 0), ("b", line.n_segments)):
            end = line.end(key)
            if isinstance(end, BodyEnd):
                on_body[end.body].append((line.name, key, node, end.offset))
                if scene.bodies[end.body].is_free:
                    joints.append(attachment(f"{line.name}.end_{key}", end.body,
                                             (line.name, node), end.offset))
    for name, body in scene.bodies.items():
        if body.is_free:
            length = max(ln.length for ln in scene.lines if ln.name in
                         {a[0] for a in on_body[name]})
            parts.append(body_part(body, env, length))
    attached: dict[str, list] = {name: [] for name in scene.points}
    for line in scene.lines:
        for key, node in (("a", 0), ("b", line.n_segments)):
            end = line.end(key)
            if isinstance(end, str):
                attached[end].append((line.name, key, node))
                if scene.points[end].is_free:
                    joints.append(Shared((end, 0), (line.name, node)))
    mech = assemble(parts, joints, name="cable3d_system", symbols=symbols)
    if not symbols:
        return dataclasses.replace(mech, bounds=_bounds(scene, mech, symbols=False),
                                   starts=lambda: _starts(scene, mech))
    out = dict(mech.outputs)
    for name, pt in scene.points.items():
        force = sum(out[f"{ln}.end_force_{key}"].expr for ln, key, _ in attached[name])
        if not pt.is_free:
            ln, _, node = attached[name][0]
            out[f"{name}.position"] = Output(out[f"{ln}.positions"].expr[node, :].T, "m", name,
                                             "position of the point")
        out[f"{name}.force"] = Output(force, "N", name, "force of the attached lines on the "
                                      "point: their end tensions (end segment's pull plus "
                                      "its half segment's loads), N")
        if pt.is_free:
            out[f"{name}.net_force"] = Output(force + out[f"{name}.own_force"].expr, "N", name,
                                              "net force on the point (zero in equilibrium)")
    for name, body in scene.bodies.items():
        out.update(body_outputs(body, out, on_body[name], _vessel_pose(scene, mech, name)))
    potential = sum(out[f"{p.name}.potential_energy"].expr for p in parts)
    out["kinetic_energy"] = Output(0.5 * ca.dot(mech.v, ca.mtimes(mech.mass, mech.v)), "J", "",
                                   "kinetic energy of the system")
    out["potential_energy"] = Output(potential, "J", "", "elastic, gravity, buoyancy, contact "
                                                        "and applied-force potential energy")
    return dataclasses.replace(mech, outputs=out, bounds=_bounds(scene, mech),
                               starts=lambda: _starts(scene, mech))


def _vessel_pose(scene: Scene, mech: Mechanism, name: str):
    """A vessel's pose as expressions of the assembly's t (its first line's ``motion`` and
    ``ramp`` parameters scaling and ramping it, as they do its ends), for
    :func:`~symcable.models.body.body.body_outputs`; None for another body."""
    body = scene.bodies[name]
    if body.kind is not BodyKind.VESSEL:
        return None
    env = scene.environment
    line = next(ln for ln in scene.lines for e in (ln.end_a, ln.end_b)
                if isinstance(e, BodyEnd) and e.body == name)
    sea = None if env.waves is None else env.waves.components_in(env.depth, env.gravity)
    path = rigid_path(body, (0.0, 0.0, 0.0), sea, 0.0 if env.waves is None
                      else env.waves.ramp_time)
    p = mech.p
    q, _ = rigid_dof(path, p[mech.params.slice(f"{line.name}.motion")], mech.t,
                     p[mech.params.slice(f"{line.name}.ramp")])
    o = ca.DM([np.radians(v) for v in body.orientation_deg])
    return (ca.DM(body.position) + q[:3], ca.DM(body.orientation_deg) + q[3:] * (180.0 / np.pi),
            quaternion(o + q[3:]))


def _line_part(ls: Scene, name: str, joined: tuple, symbols: bool, built: dict) -> Mechanism:
    """The line part ``name`` of one-line scene ``ls`` (:func:`line_scene`): built, or, when
    a line of the same structure is in ``built`` (the mooring's identical lines), that
    part's expressions with this line's numbers and name (:mod:`symcable.models.structure`:
    the lines of a system share one graph as scenes do)."""
    if not symbols:
        return build_cable3d(ls, part=name, joined=joined, symbols=False)
    key = structure_key(ls)
    key = None if key is None else (key, joined)
    first = built.get(key)
    if first is not None:
        part = rebind(first, build_cable3d(ls, part=name, joined=joined, symbols=False))
        if part is not None:
            return dataclasses.replace(
                part, name=name, functions_of=None,
                outputs={k: dataclasses.replace(o, owner=name) for k, o in part.outputs.items()})
    part = build_cable3d(ls, part=name, joined=joined)
    if key is not None:
        built[key] = part
    return part


def _bounds(scene: Scene, mech: Mechanism, symbols: bool = True) -> dict:
    """The parts' bounds, with the lines' seabed reactions summed into one: the seabed
    carries at most what presses on it, and a line's share of that includes the free points
    (a clump on the bed) and whatever else hangs from them."""
    bounds = {k: b for k, b in mech.bounds.items() if not k.endswith(".seabed_reaction")}
    parts = [b for k, b in mech.bounds.items() if k.endswith(".seabed_reaction")]
    if parts:
        points = [mech.outputs[f"{n}.contact_force"].expr for n, p in scene.points.items()
                  if p.is_free] if symbols else []
        env = scene.environment
        press = 0.0
        for pt in scene.points.values():
            if pt.is_free:
                w, applied, rho = _point_loads(pt, env)
                u = float(np.linalg.norm(env.current))
                press += max(w, 0.0) + float(np.linalg.norm(applied)) \
                    + 0.5 * rho * float(np.max(pt.drag_area)) * u * u
        for body in scene.bodies.values():  # a free body hanging on lines that rest on it
            if body.is_free:
                rho = 0.0 if env.in_air else env.water_density
                u = float(np.linalg.norm(env.current))
                press += max((body.mass - rho * body.volume) * env.gravity, 0.0) \
                    + 0.5 * rho * float(np.max(body.cd_area)) * u * u
        bounds["seabed_reaction"] = dataclasses.replace(
            parts[0], expr=sum(b.expr for b in parts) + sum(points) if symbols else parts[0].expr,
            upper=sum(float(b.upper) for b in parts) + 1.01 * press,
            scale=max(b.scale for b in parts))
    return bounds


def _node_q(mech: Mechanism, part: str) -> np.ndarray:
    return np.asarray(mech.layout.parts[part].node_q, int)


def _first_shapes(scene: Scene) -> dict[str, tuple[np.ndarray, str]]:
    """Each line's first shape (N+1, 3), m: its elastic catenary (or the straight line)
    between its end points, free points where the scene puts them; or hanging straight from
    its held end when its other end is a free inline end."""
    out = {}
    for line in scene.lines:
        ls = line_scene(scene, line, pinned_free=True)
        seg = segment_table(ls)
        if ls.end_a.is_fixed and ls.end_b.is_fixed:
            cat = _catenary(ls, seg)
            if cat is None:
                pa, pb = np.asarray(ls.end_a.position), np.asarray(ls.end_b.position)
                cat = pa + np.outer(seg["s"] / seg["s"][-1], pb - pa), "straight line"
            out[line.name] = cat
        else:
            out[line.name] = _hanging(ls, seg), "hanging straight along its load"
    return out


def _starts(scene: Scene, mech: Mechanism):
    """Static starts of the system (module docstring), lazily."""
    p0 = mech.static_p
    shapes = _first_shapes(scene)

    def start(positions: dict[str, np.ndarray], source: str) -> Start:
        q = np.zeros(mech.n_q)
        for line in scene.lines:
            idx = _node_q(mech, line.name)
            held = idx[:, 0] < 0
            q[idx[~held].ravel()] = positions[line.name][~held].ravel()
        # every free point is some line's end node: placed with that line; every free body
        # where the scene puts it
        for name, body in scene.bodies.items():
            if body.is_free:
                q0 = start_q(body)
                q[_node_q(mech, name).ravel()] = q0[:6]
                q[mech.n_v + mech.layout.states.names.index(f"{name}.e0")] = q0[6]
        return Start(q, np.zeros(0), p0, source)

    sources = sorted({src.split(" (")[0] for _, src in shapes.values()})
    yield start({k: v[0] for k, v in shapes.items()},
                f"each line's {' / '.join(sources)} between its end points")
    bent = any(s.line_type.EI > 0 for ln in scene.lines for s in ln.sections)
    relaxed = None if bent else _relaxed(scene, mech, {k: v[0] for k, v in shapes.items()})
    if relaxed is not None:  # (the relaxation's energy is a cable's: no bending)
        yield start(relaxed, "minimum of the potential energy")
    free = [name for name, b in scene.bodies.items() if b.is_free]
    if free:  # the lines there hold the bodies pulled to the scene's pose, then release them
        st = start(relaxed if relaxed is not None else {k: v[0] for k, v in shapes.items()},
                   "the lines relaxed with the bodies pulled to where the scene puts them")
        pulled = mech.params.with_values(p0, **{f"{name}.pull": 1.0 for name in free})
        yield dataclasses.replace(st, p=pulled, homotopy="the bodies' pull")


def _relaxed(scene: Scene, mech: Mechanism, shapes: dict[str, np.ndarray]) -> dict | None:
    """The lines' shapes at the minimum of the network's potential energy, from
    ``shapes`` (:func:`~symcable.models.common.relax.relaxed_network`), or None."""
    env, sb = scene.environment, scene.seabed
    ids: dict[int, int] = {}
    chains, scales = [], []
    for line in scene.lines:
        idx = _node_q(mech, line.name)
        node_ids = np.array([-1 if i[0] < 0 else ids.setdefault(int(i[0]), len(ids))
                             for i in idx])
        ls = line_scene(scene, line)
        seg = segment_table(ls)
        table = law_table(ls)
        if table is not None:  # loading functions: the frozen drag in their law
            seg["drag_law"] = dict(table, eps=DRAG_SPEED)
        F = force_scale(ls, seg)
        scales.append(F)
        contact = None
        if sb is not None:
            trib = np.zeros(len(seg["s"]))
            trib[:-1] += 0.5 * seg["d"] * seg["ds"]
            trib[1:] += 0.5 * seg["d"] * seg["ds"]
            contact = (env.depth, sb.stiffness, terms.contact_smoothing(
                float(np.max(seg["w"])), sb.stiffness, float(np.min(seg["d"])),
                CONTACT_SMOOTHING), trib)
        drag = None if env.in_air or not any(env.current) else drag_loads(env, seg)
        chains.append({"seg": seg, "law": slack_law(seg, F), "pos0": shapes[line.name],
                       "ids": node_ids, "node_weight": _lumped(seg), "contact": contact,
                       "loads": drag})
    weight, force = np.zeros(len(ids)), np.zeros((len(ids), 3))
    stiff, width = np.zeros(len(ids)), np.ones(len(ids))
    for name, pt in scene.points.items():
        if pt.is_free:
            w, applied, rho = _point_loads(pt, env)
            u = np.asarray(env.current, float)
            k = ids[int(_node_q(mech, name)[0, 0])]
            weight[k] = w
            force[k] = applied + 0.5 * rho * np.asarray(pt.drag_area) * np.linalg.norm(u) * u
            contact = point_contact(scene, name)
            if contact is not None:
                stiff[k], width[k] = contact
    rel = relaxed_network(chains, weight, force, max(scales),
                          point_contact=None if sb is None else (env.depth, stiff, width))
    if rel is None:
        return None
    return {line.name: pos for line, pos in zip(scene.lines, rel)}
