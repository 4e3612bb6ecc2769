"""The static configuration of a ``cable3d`` scene: its Mechanism
(:func:`~symcable.models.cable3d.line.build_cable3d`) solved by the generic
:func:`~symcable.solvers.equilibrium.solve_equilibrium`, and the outputs turned into a
:class:`~symcable.results.static.StaticSolution` with 3D positions and forces."""
from __future__ import annotations

import dataclasses
import itertools

import math
import time
from collections import OrderedDict
from types import MappingProxyType

import numpy as np

from ..errors import ConvergenceError, SymcableError
from ..models import build_mechanism
from ..models.cable3d.line import force_scale
from ..models.system import line_scene
from ..mechanism.mechanism import Mechanism, Start
from ..models.common.tow import held_motions, held_tows, moved_scene, tow_velocities
from ..models.common.segments import grounded_length, segment_table
from ..results.static import BodyState, PointState, StaticSolution, SystemStaticSolution
from ..scene import BodyEnd, Scene, load_scene
from ..solvers.equilibrium import solve_equilibrium
from ..solvers.periodic_mech import check_periodic

__all__ = ["START_MODES", "body_stiffness", "cable3d_mechanism", "check_periodic_3d",
           "dynamic_p", "node_shapes", "run_start_state", "solve_static_3d",
           "static_equilibrium"]

#: how a time run of a cable3d scene may start (:func:`run_start_state`)
START_MODES = ("steady", "rest")

#: default residual tolerance, relative to the scene's force scale (as the planar line)
RTOL = 1e-9
_CACHE: "OrderedDict[str, Mechanism]" = OrderedDict()
_CACHE_SIZE = 16
#: segments above which an error estimate's one-off scene is not kept (:func:`release`)
RELEASE_SEGMENTS = 500


def cached_mechanism(scene: Scene, build=build_mechanism) -> Mechanism:
    """``build(scene)`` (default :func:`symcable.models.build_mechanism`), built once per
    scene content: the 16 most recent Mechanisms of every formulation, in one cache."""
    key = repr(scene.to_dict())
    mech = _CACHE.get(key)
    if mech is None:
        mech = _CACHE[key] = build(scene)
        if len(_CACHE) > _CACHE_SIZE:
            _CACHE.popitem(last=False)
    else:
        _CACHE.move_to_end(key)
    return mech


def release(scene: Scene) -> None:
    """Forget the cached Mechanism of ``scene`` (and its structure's template,
    :mod:`symcable.models.structure`) when its lines have more than RELEASE_SEGMENTS
    segments in all: for the one-off scenes of an error estimate (half the segments, a
    stiffer bed), whose Mechanism and Functions of a long line take a hundred MB or more and
    serve no later analysis of the scene."""
    from ..models.structure import TEMPLATES, structure_key
    from ..scene.refine import line_segments
    if sum(line_segments(scene).values()) <= RELEASE_SEGMENTS:
        return
    mech = _CACHE.pop(repr(scene.to_dict()), None)
    key = structure_key(scene)
    if key is not None and mech is not None and TEMPLATES.get(key) is (mech.functions_of or mech):
        del TEMPLATES[key]


def cable3d_mechanism(scene: Scene) -> Mechanism:
    """The scene's cable3d Mechanism, built once per scene content.

    Built by :func:`symcable.models.build_mechanism`: one line's, or for a scene of several
    lines and points their assembly; cached by :func:`cached_mechanism` (the 16 most
    recent scenes).

    Parameters
    ----------
    scene : Scene, dict or path
        Anything :func:`symcable.load_scene` takes, ``model = "cable3d"`` (another
        formulation gets its own statics' Mechanism, as :func:`symcable.build_mechanism`).

    Returns
    -------
    Mechanism
        Its statics: the object the generic solvers take
        (:func:`symcable.solve_equilibrium`, :func:`symcable.linearize_mechanism`, ...).
    """
    return cached_mechanism(scene if isinstance(scene, Scene) else load_scene(scene))


def check_periodic_3d(scene: Scene) -> None:
    """Refuse, before any solve, a scene whose Mechanism a periodic solve cannot take (one
    with first-order states, such as ``seabed.friction_law = "bristle"``): the
    :class:`~symcable.errors.SymcableError` of
    :func:`~symcable.solvers.periodic_mech.check_periodic`, naming the setting; or a tow
    (the towpoint travels on). A free body is taken: the periodic solvers make its
    quaternion's norm relax (:mod:`~symcable.models.body.body`)."""
    towing = [label for label, m in held_motions(scene) if m is not None and m.kind == "tow"]
    if towing:
        raise SymcableError(f"{towing[0]}.motion: kind = 'tow' is not periodic (the towpoint "
                            "travels on); run it in time (simulate)")
    check_periodic(cable3d_mechanism(scene))


def calm(scene: Scene) -> Scene:
    """``scene`` in a calm sea (its ``environment.waves`` removed): the sea the static state
    is in (a time run ramps the waves in from it), with the Mechanism and Functions of that
    structure, which do not carry the waves' expressions."""
    env = scene.environment
    if env.waves is None:
        return scene
    return dataclasses.replace(scene, environment=dataclasses.replace(env, waves=None))


def static_equilibrium(scene: Scene, *, tol: float | None = None, max_iter: int = 50,
                       continuation: bool = True, codegen: bool | None = None, start=None):
    """``(mechanism, Equilibrium)``: the scene's cable3d Mechanism at rest, solved by
    :func:`~symcable.solvers.equilibrium.solve_equilibrium` (its checks passed) to ``tol`` N
    (default RTOL times the force scale); where the dynamic analyses start. The state is in
    a calm sea: the scene's waves, if any, are left out (:func:`calm`). ``start``: (q, z) of
    a nearby scene of the same structure (a design's last iterate), tried first, before the
    Mechanism's own starts; (q, z, p) when it is that scene's equilibrium at its parameters
    p: then, where Newton from it fails, the continuation from p follows at once."""
    scene = calm(scene)
    mech = cable3d_mechanism(scene)
    if tol is None:
        F = mech.scales.force if scene.version == 2 else force_scale(scene, segment_table(scene))
        tol = mech.scales.static_tolerance(F, RTOL)
    starts = None
    if start is not None and np.size(start[0]) == mech.n_q and np.size(start[1]) == mech.n_z:
        own = len(start) > 2 and np.size(start[2]) == np.size(mech.static_p)
        first = Start(np.asarray(start[0], float), np.asarray(start[1], float),
                      np.asarray(start[2] if own else mech.static_p, float),
                      source="a nearby design's state", homotopy="the design's numbers",
                      exact=own)
        starts = itertools.chain([first], _later(mech.starts))
    eq = solve_equilibrium(mech, tol=tol, max_iter=max_iter, starts=starts,
                           continuation=None if continuation else False, codegen=codegen)
    return mech, eq


def transferred_state(scene: Scene, sol) -> tuple | None:
    """``(q, z)`` of ``scene``'s Mechanism from ``sol``, the static solution of a scene of
    the same lines, points and bodies with other segment counts or numbers (an
    error estimate's half-segment or refined scene): each line's nodes interpolated along
    its unstretched arc length from the solution's (a free point is a line's end node), a
    free body's pose from the solution's, z zero and other first-order states zero. Read
    from the solution alone (that scene's Mechanism, which a long line's estimate releases, is
    not built again). A start for :func:`static_equilibrium`, or None when ``sol`` has no
    state or names other lines."""
    if getattr(sol, "unknowns", None) is None:
        return None
    dst = cable3d_mechanism(calm(scene))
    lines = getattr(sol, "lines", None)
    bodies = getattr(sol, "bodies", None) or {}
    q = np.zeros(dst.n_q)
    for name, part in dst.layout.parts.items():
        idx = np.asarray(part.node_q, int)
        free = idx >= 0
        if part.kind == "line":
            line = sol if lines is None else lines.get(name)
            if line is None:
                return None
            s_old, pos = np.asarray(line.s, float), np.asarray(line.positions, float)
            s_new = np.asarray(part.s, float) * (s_old[-1] / part.s[-1])
            moved = np.column_stack([np.interp(s_new, s_old, pos[:, k]) for k in range(3)])
            q[idx[free]] = moved[free]
        elif part.kind == "body" and name in bodies and idx.shape == (2, 3):
            e = np.ravel(bodies[name].orientation)  # (e0, e1, e2, e3)
            q[idx[0][free[0]]] = np.ravel(bodies[name].position)[free[0]]
            q[idx[1][free[1]]] = e[1:][free[1]]
            if dst.layout.states is not None and f"{name}.e0" in dst.layout.states.names:
                q[dst.n_v + dst.layout.states.names.index(f"{name}.e0")] = e[0]
    return q, np.zeros(dst.n_z)


def _later(make_starts):
    """The starts ``make_starts()`` builds, built only when the solver asks past the ones
    before them (a relaxed network's start costs a solve of its own)."""
    yield from make_starts()


def run_start_state(scene: Scene, t0: float, start: str | None = None, *,
                    codegen: bool | None = None):
    """Where a time run of ``scene`` from ``t0`` s starts: ``(mech, eq, v0, info, warnings)``,
    ``mech`` the scene's Mechanism (the one to step), ``eq`` the static state to start from
    (its q), ``v0`` (n_v,) the start's velocities, ``info`` a dict for the run's stats
    (``start``: ``"steady tow"`` or ``"rest"``; a steady tow adds ``tow_velocity``, m/s).

    ``start``:

    - ``"steady"``: the steady tow. Every held point (pinned end, fixed or vessel point,
      fixed body) must tow (``kind = "tow"``) at one velocity u at t0; the start is the
      static solution in the frame moving at u (the water flowing past at the current
      minus u, :func:`~symcable.models.common.tow.moved_scene`), the towpoints where their paths
      put them at t0, and every free node, free point and free body moving at u (a body's
      angular velocity zero). Before any turn this is an exact solution of the dynamics
      (no acceleration anywhere): a run from it stays in it;
    - ``"rest"``: the static state in still (or the scene's) water, at rest, with each
      towpoint where its path puts it at t0 (it then sets off at full speed);
    - None: ``"steady"`` when the scene tows and the steady tow exists, else ``"rest"`` (a
      scene that tows but whose held points do not all tow at one velocity starts at rest,
      with a warning saying why).

    A scene with no tow starts as before, from :func:`static_equilibrium` at rest."""
    if start is not None and start not in START_MODES:
        raise SymcableError(f"start = {start!r}: must be one of {', '.join(map(repr, START_MODES))} "
                            "(or None: 'steady' for a scene that tows, else 'rest')")
    tows, why = held_tows(scene, t0)
    warnings = []
    if start == "steady" and why is not None:
        raise SymcableError(f"start = 'steady': scene {scene.name!r} has no steady tow at "
                            f"t = {t0:g} s: {why}; every held point must tow (kind = 'tow') at "
                            "one velocity (or start = 'rest')")
    steady = why is None and start != "rest"
    if start is None and tows and why is not None:
        warnings.append(f"started from rest, not from a steady tow: {why}")
    mech = cable3d_mechanism(scene)
    if not tows:
        _, eq = static_equilibrium(scene, codegen=codegen)
        return mech, eq, np.zeros(mech.n_v), {"start": "rest"}, warnings
    u = next(iter(tows.values()))[1]
    moved = any(np.any(st[0]) for st in tows.values())
    there = moved_scene(scene, tows, u if steady else None) if (steady or moved) else scene
    _, eq = static_equilibrium(there, codegen=codegen)
    if not steady:
        return mech, eq, np.zeros(mech.n_v), {"start": "rest"}, warnings
    if any(np.any(np.abs(st[2]) > 0) for st in tows.values()):
        warnings.append(f"the run starts inside a turn (t = {t0:g} s): its start is the "
                        "straight tow at the towpoint's velocity then, not a steady turn")
    if _frictionless_statics(scene):
        warnings.append("the steady tow's static solve has no seabed friction: the line "
                        "sliding on the bed starts without it")
    return mech, eq, tow_velocities(mech, u), {"start": "steady tow",
                                               "tow_velocity": [float(c) for c in u]}, warnings


def solve_static_3d(scene: Scene, *, tol: float | None = None, max_iter: int = 50,
                    continuation: bool = True, codegen: bool | None = None,
                    near: tuple | None = None) -> StaticSolution:
    """Static configuration of a cable3d scene (see :func:`symcable.solve_static`); a scene
    of several lines and points gives a :class:`~symcable.results.static.SystemStaticSolution`.
    A scene in waves is solved in a calm sea (:func:`calm`). ``near``: ``(scene, solution)``
    of a scene like it (other segment counts or numbers), whose state, carried over by
    :func:`transferred_state`, is tried first."""
    scene = calm(scene)
    start = None if near is None else transferred_state(scene, near[1])
    if scene.version == 2:
        return _solve_system(scene, tol=tol, max_iter=max_iter, continuation=continuation,
                             codegen=codegen, start=start)
    t0 = time.perf_counter()
    mech = cable3d_mechanism(scene)
    seg = segment_table(scene)
    try:
        _, eq = static_equilibrium(scene, tol=tol, max_iter=max_iter, continuation=continuation,
                                   codegen=codegen, start=start)
    except ConvergenceError as exc:
        part = exc.partial
        partial = None if part is None else _solution(scene, seg, part.outputs, part.q, "failed",
                                                      dict(part.stats), ())
        raise ConvergenceError(f"static solve of '{scene.name}' (cable3d) found no admissible "
                               f"equilibrium: {exc}", partial=partial,
                               diagnostics=exc.diagnostics) from None
    stats = dict(eq.stats)
    stats.update(wall_time=time.perf_counter() - t0, unknowns=mech.n_q, terms=list(mech.terms))
    warnings = _static_warnings(scene, eq)
    return _solution(scene, seg, eq.outputs, eq.q, "converged", stats, warnings)


def _static_warnings(scene: Scene, eq) -> tuple:
    """The warnings of a 3D static solution: the solver's, with a seabed's friction left
    out of statics and a tow's speed left out of the state at rest."""
    return tuple(eq.warnings) + ((FRICTIONLESS,) if _frictionless_statics(scene) else ()) \
        + ((AT_REST,) if tows(scene) else ())


#: the warning of a static solve (or modes about it) of a scene that tows
AT_REST = ("the scene tows (kind = 'tow'): this is its state at rest, without the tow's "
           "speed; the steady tow is where simulate starts (start = 'steady')")


def tows(scene: Scene) -> bool:
    """Whether something held in ``scene`` moves on a tow (``kind = "tow"``)."""
    return any(m is not None and m.kind == "tow" for _, m in held_motions(scene))


#: the warning of a static solve on a seabed with friction but without static friction
FRICTIONLESS = ("seabed friction is not applied in 3D statics (seabed.static_friction = "
                "'none': frictionless contact; 'laid' holds the line from its as-laid shape)")


def _frictionless_statics(scene: Scene) -> bool:
    sb = scene.seabed
    return sb is not None and max(sb.mu_axial, sb.mu_lateral) > 0 and sb.static_friction == "none"


def _solution(scene, seg, out, q, status, stats, warnings) -> StaticSolution:
    pos = np.asarray(out["positions"], float)
    axial = np.ravel(out["axial_force"])
    contact = np.ravel(out["contact_force"])
    fa, fb = np.ravel(out["end_force_a"]), np.ravel(out["end_force_b"])
    d = np.diff(pos, axis=0)
    elevation = np.arctan2(d[:, 2], np.hypot(d[:, 0], d[:, 1]))
    tension = np.concatenate([[np.linalg.norm(fa)], 0.5 * (np.abs(axial[:-1]) + np.abs(axial[1:])),
                              [np.linalg.norm(fb)]])
    grounded, _, touchdown = grounded_length(scene, seg, None, pos,
                                             contact if scene.seabed is not None else None, fa, fb)
    n = len(pos)
    # |bending moment| at the nodes (N m; zero without bending: EI = 0)
    moment = (np.linalg.norm(np.asarray(out["bending_moment"], float), axis=1)
              if "bending_moment" in out else np.zeros(n))
    return StaticSolution(
        scene_name=scene.name, s=np.asarray(seg["s"]), positions=pos, angle=elevation,
        strain=np.ravel(out["strain"]), axial_force=axial, shear=np.zeros(n - 1),
        moment=moment, tension=tension, contact_force=contact, fairlead_force=fb,
        anchor_force=fa, fairlead_tension=float(np.linalg.norm(fb)),
        anchor_tension=float(np.linalg.norm(fa)), grounded_length=grounded,
        touchdown=touchdown, status=status, stats=stats, warnings=warnings,
        unknowns=np.array(q, float))


def _solve_system(scene: Scene, *, tol, max_iter, continuation, codegen,
                  start=None) -> SystemStaticSolution:
    """:func:`solve_static_3d` of a scene of several lines and points."""
    t0 = time.perf_counter()
    try:
        mech, eq = static_equilibrium(scene, tol=tol, max_iter=max_iter,
                                      continuation=continuation, codegen=codegen, start=start)
    except ConvergenceError as exc:
        part = exc.partial
        partial = None if part is None else _system(scene, part.outputs, part.q, "failed",
                                                    dict(part.stats), ())
        raise ConvergenceError(f"static solve of '{scene.name}' (cable3d, {len(scene.lines)} "
                               f"lines, {len(scene.points)} points) found no admissible "
                               f"equilibrium: {exc}", partial=partial,
                               diagnostics=exc.diagnostics) from None
    stats = dict(eq.stats)
    stats.update(wall_time=time.perf_counter() - t0, unknowns=mech.n_q, terms=list(mech.terms))
    warnings = _static_warnings(scene, eq)
    return _system(scene, eq.outputs, eq.q, "converged", stats, warnings)


def _system(scene, out, q, status, stats, warnings) -> SystemStaticSolution:
    lines = {}
    for line in scene.lines:
        ls = line_scene(scene, line)
        mine = {k.split(".", 1)[1]: v for k, v in out.items() if k.startswith(line.name + ".")}
        lines[line.name] = _solution(ls, segment_table(ls), mine, q, status, stats, warnings)
    points = {}
    for name, pt in scene.points.items():
        net = out.get(f"{name}.net_force")
        points[name] = PointState(name, pt.kind.value, np.ravel(out[f"{name}.position"]),
                                  np.ravel(out[f"{name}.force"]),
                                  None if net is None else np.ravel(net))
    bodies = {}
    for name, body in scene.bodies.items():
        get = lambda key: np.ravel(out[f"{name}.{key}"])  # noqa: E731
        bodies[name] = BodyState(name, body.kind.value, get("position"), get("orientation"),
                                 get("roll_pitch_yaw"), get("force"), get("moment"),
                                 get("net_force") if body.is_free else None)
    return SystemStaticSolution(scene.name, MappingProxyType(lines), MappingProxyType(points),
                                status, stats, warnings, np.array(q, float),
                                MappingProxyType(bodies))


def dynamic_p(scene: Scene, mech: Mechanism, p) -> np.ndarray:
    """``p`` with every free body's statics-only spring off (``NAME.hold`` = 0,
    :mod:`~symcable.models.body.body`): the parameters a linearisation about a static state
    takes."""
    p = np.array(p, float)
    for name, body in scene.bodies.items():
        if body.is_free:
            p[mech.params.slice(f"{name}.hold")] = 0.0
    return p


def body_stiffness(scene: Scene, mech: Mechanism, eq, name: str, p=None) -> np.ndarray:
    """(6, 6) the mooring stiffness of free body ``name`` about the equilibrium ``eq`` (see
    :class:`~symcable.results.generic.SceneLinearization`): K_v = (-df/dq) G in the
    velocity coordinates (translation, rotation in body axes), every coordinate but the
    body's condensed out (K_bb - K_bi K_ii^-1 K_ib: the rest in static equilibrium as the
    body moves, sparse LU), then turned to global axes, T K T^T with T = diag(I, R). Exact
    at an equilibrium (there the turn of the moment with R adds nothing). ``p`` default the
    equilibrium's, with the statics-only spring off (:func:`dynamic_p`)."""
    import scipy.sparse.linalg as spla

    from ..mechanism.functions import functions

    F = functions(mech)
    p = dynamic_p(scene, mech, eq.p) if p is None else np.asarray(p, float)
    args = (eq.q, np.zeros(mech.n_v), eq.z, 0.0, p)
    K = _csc(F.tangents(*args)[0])
    G = _csc(F.kinematics_jacobian(*args)[1])
    Kv = (K @ G).tocsc()
    b = np.asarray(mech.layout.parts[name].node_v, int).ravel()
    i = np.setdiff1d(np.arange(mech.n_v), b)
    Kbb = Kv[b][:, b].toarray()
    if i.size:
        try:
            X = spla.splu(Kv[i][:, i].tocsc()).solve(Kv[i][:, b].toarray())
        except RuntimeError as exc:
            raise SymcableError(f"bodies.{name}: no mooring stiffness: the rest of the system "
                                f"is not held when the body is ({exc})") from None
        Kbb = Kbb - Kv[b][:, i] @ X
    e = np.ravel(eq.outputs[f"{name}.orientation"])  # (e0, e1, e2, e3)
    T = np.eye(6)
    T[3:, 3:] = _rotation(e)
    return T @ np.asarray(Kbb) @ T.T


def _csc(m):
    import scipy.sparse as sp
    rows, cols = m.sparsity().get_triplet()
    return sp.csc_matrix((np.asarray(m.nonzeros(), float), (rows, cols)), shape=m.shape)


def _rotation(e) -> np.ndarray:
    """(3, 3) body to global axes of the unit quaternion (e0, e1, e2, e3)."""
    w, x, y, z = e / np.linalg.norm(e)
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])


def node_shapes(scene: Scene, mech, eq, lines, u) -> np.ndarray:
    """(n, 3) the lines' node displacements of a mode whose velocity-coordinate shape is
    ``u`` (n_v,), scaled to a largest node displacement of 1 (its largest entry positive):
    zero at held ends; a node on a free body moves with it, u_O + R (theta x r) (u_O, theta
    the body's entries of u, theta in body axes)."""
    rows = []
    for n in lines:
        part = mech.layout.parts[n]
        idx = np.asarray(part.node_v)
        rows.append(np.where(idx < 0, 0.0, u[np.where(idx < 0, 0, idx)]))
        line = next((ln for ln in scene.lines if ln.name == n), None)
        for key, i in (() if line is None else (("a", 0), ("b", len(part.s) - 1))):
            end = line.end(key)
            if isinstance(end, BodyEnd) and scene.bodies[end.body].is_free:
                b = np.asarray(mech.layout.parts[end.body].node_v)
                e = np.ravel(eq.outputs[f"{end.body}.orientation"])
                rows[-1][i] = u[b[0]] + _rotation(e) @ np.cross(u[b[1]], end.offset)
    out = np.vstack(rows)
    peak = np.max(np.linalg.norm(out, axis=1))
    j = int(np.argmax(np.abs(out)))
    return out * (math.copysign(1.0, out.flat[j]) / peak if peak > 0 else 1.0)
