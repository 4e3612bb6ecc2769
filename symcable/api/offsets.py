"""Offset-restoring curves of a moored body: the force and moment of its
lines (and its own weight, buoyancy and drag) on the body held at each of a sweep of
prescribed offsets, the lines in static equilibrium at each, in one batched call.

How. The scene's body is made ``kind = "fixed"`` at the base pose (its static equilibrium,
or where the scene puts it): the lines' ends on it are then held ends, whose positions are
parameters of the scene's one Mechanism (``LINE.end_b.position``). A CasADi Function maps
an offset row to those parameters (:func:`_pose_params`); one step of the sweep is the
static solve's fused plain Newton (:mod:`symcable.mechanism.static_functions`, generated C where the
static solve is) from the previous offset's solution, followed by the solve's own check
(residual evaluated afresh, finiteness, admissibility bounds); ``mapaccum`` strings the
steps into one Function over the batch, so the whole sweep is one call that reuses one
sparsity pattern, one elimination order and one compiled solve. The offsets are visited
in a nearest-neighbour order from the one nearest the base (a range from -20 to 20 m is
walked outward from 0 each way); a step starts from the base solution where the next
offset is nearer the base than the previous one, or where the previous step failed. An
offset whose batched Newton fails is re-solved alone by
:func:`~symcable.solvers.equilibrium.solve_equilibrium` (damped Newton, then continuation
in the offset from its neighbour's solution); each answer is then checked for the lines'
global force balance (:attr:`~symcable.results.offsets.OffsetSweep.balance`).
"""
from __future__ import annotations

import dataclasses
import math
import time
from types import MappingProxyType

import casadi as ca
import numpy as np

from .cable3d_static import cable3d_mechanism, static_equilibrium
from ..mechanism.bounds import bound_numbers
from ..mechanism.functions import functions
from ..mechanism.static_functions import SOLVE_MAX_ITER
from ..errors import ConvergenceError, SceneError, SymcableError
from ..limits import check as check_limit
from ..models.body.body import body_part, quaternion_rpy
from ..models.system import line_scene
from ..mechanism.mechanism import Start
from ..models.common.segments import segment_table
from ..results.offsets import DOF_NAMES, OffsetSweep
from ..scene import BodyEnd, load_scene
from ..scene.bodies import BodyKind, rotation_rpy
from ..solvers.equilibrium import solve_equilibrium

__all__ = ["ABOUT", "offset_sweep", "offsets_along"]

#: held scenes whose sweep Functions are kept on their structure's Functions
SWEEPS_KEPT = 4

#: what the offsets are taken from
ABOUT = ("equilibrium", "scene")


def offsets_along(dof, start: float, stop: float, n: int = 41) -> np.ndarray:
    """Offsets of a body evenly spaced along one degree of freedom or one direction.

    The (n, 6) rows (dx, dy, dz in m, droll, dpitch, dyaw in deg) run from ``start`` to
    ``stop`` along ``dof``, for :func:`symcable.offset_sweep`.

    Parameters
    ----------
    dof : str or array_like (6,)
        A name of :data:`~symcable.results.offsets.DOF_NAMES` (``"surge"``, ``"sway"``,
        ``"heave"`` in m, ``"roll"``, ``"pitch"``, ``"yaw"`` in deg), or a direction of 6
        finite numbers (m, m, m, deg, deg, deg), its entries scaled by the amounts.
    start, stop : float
        The first and last amount along ``dof``: m or deg for a name, a multiple of the
        direction for a direction.
    n : int
        Number of offsets (>= 1, at most the ``steps`` limit), ``start`` and ``stop``
        included. Default 41.

    Returns
    -------
    ndarray (n, 6)
        Row i is ``linspace(start, stop, n)[i]`` times the unit row of the named degree of
        freedom (or the direction): m and deg.

    Raises
    ------
    SymcableError
        An unknown name, a direction not of 6 finite numbers, ``n`` not an integer >= 1, or
        ``start`` or ``stop`` not finite.
    LimitError
        ``n`` is more than the ``steps`` limit (:func:`symcable.limits`).
    """
    if isinstance(dof, str):
        if dof not in DOF_NAMES:
            raise SymcableError(f"dof = {dof!r}: must be one of {', '.join(DOF_NAMES)} or a "
                                "direction of 6 numbers")
        direction = np.eye(6)[DOF_NAMES.index(dof)]
    else:
        direction = np.asarray(dof, float).ravel()
        if direction.size != 6 or not np.all(np.isfinite(direction)):
            raise SymcableError(f"dof = {dof!r}: a direction has 6 finite numbers (m, m, m, "
                                "deg, deg, deg)")
    if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n < 1:
        raise SymcableError(f"n = {n!r}: the number of offsets must be an integer >= 1")
    check_limit("steps", n, "n, the number of offsets", "each is a static solve")
    try:
        ends = [float(v) for v in (start, stop) if not isinstance(v, (str, bool))]
    except (TypeError, ValueError):
        ends = []
    if len(ends) != 2 or not all(math.isfinite(v) for v in ends):
        raise SymcableError(f"start, stop = {start!r}, {stop!r}: must be finite numbers "
                            "(m or deg)")
    return np.outer(np.linspace(float(start), float(stop), int(n)), direction)


def _rot(rpy_deg):
    """CasADi R = Rz(yaw) Ry(pitch) Rx(roll) of ``rpy_deg`` (degrees)."""
    r, p, y = (rpy_deg[i] * (math.pi / 180.0) for i in range(3))
    cr, sr, cp, sp, cy, sy = ca.cos(r), ca.sin(r), ca.cos(p), ca.sin(p), ca.cos(y), ca.sin(y)
    return ca.vertcat(ca.horzcat(cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr),
                      ca.horzcat(sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr),
                      ca.horzcat(-sp, cp * sr, cp * cr))


def _rpy(R) -> np.ndarray:
    """(3,) [roll, pitch, yaw] (deg) of a rotation matrix (as models.body.roll_pitch_yaw)."""
    return np.degrees([math.atan2(R[2, 1], R[2, 2]),
                       math.atan2(-R[2, 0], math.hypot(R[2, 1], R[2, 2])),
                       math.atan2(R[1, 0], R[0, 0])])


def _pose_params(mech, p0, pos, R0, ends) -> ca.Function:
    """``offset_params(offset) -> p``: p0 with the held ends on the body, ``ends`` =
    [(line, key, r)], at x0 + d + R(offset) R0 r."""
    off = ca.SX.sym("offset", 6)
    R = ca.mtimes(_rot(off[3:6]), ca.DM(R0))
    p = ca.SX(ca.DM(np.asarray(p0, float)))
    for line, key, r in ends:
        sl = mech.params.slice(f"{line}.end_{key}.position")
        p[sl.start:sl.stop] = ca.DM(pos) + off[0:3] + ca.mtimes(R, ca.DM(r))
    return ca.Function("offset_params", [off], [p], ["offset"], ["p"])


#: the step of the predictor's directional difference (a fraction of the move to the next
#: offset: its relative error is of this order, far below what Newton then removes)
PREDICTOR_STEP = 1e-4


def _batch(S, pose_p, n_x: int, n_p: int, n: int, bounds: np.ndarray) -> ca.Function:
    """``offset_batch(acc0, offsets (6, n), reset (1, n), x_base, p_base, tol)``: the fused
    Newton of each offset from the previous one's solution (or ``x_base`` where ``reset`` or
    where the previous failed) moved by the tangent predictor, and its check,
    ``mapaccum``-ed over the n offsets. The predictor is the first-order change of the
    solution, dx = -J^-1 (dR/dp) dp, as the directional difference of the solve's own Newton
    step at p + h dp (h = :data:`PREDICTOR_STEP`): one more factorisation per offset, of the
    same pattern, where starting from the previous solution itself moves only the held ends
    (a taut line's end segment stretched by the whole move: plain Newton diverges from
    there). The accumulator is (x; ok; p) per offset; also returned: iterations, residual
    norm, bound margin (for the limits ``bounds``,
    :func:`~symcable.mechanism.bounds.bound_numbers`) and outputs."""
    acc, O, reset = ca.MX.sym("acc", n_x + 1 + n_p), ca.MX.sym("offset", 6), ca.MX.sym("reset")
    XB, PB, TOL = ca.MX.sym("x_base", n_x), ca.MX.sym("p_base", n_p), ca.MX.sym("tol")
    restart = ca.logic_or(reset, acc[n_x] < 0.5)
    x_from = ca.if_else(restart, XB, acc[0:n_x])
    p_from = ca.if_else(restart, PB, acc[n_x + 1:])
    p = pose_p(O)
    _, dx = S.step(x_from, p_from + PREDICTOR_STEP * (p - p_from))
    x, its, _, packed = S.solve(x_from + dx / PREDICTOR_STEP, p, TOL)
    nr, probe, margin = S.check(x, p, ca.DM(bounds))
    ok = ca.logic_and(ca.logic_and(nr <= TOL, margin >= 0), probe - probe == 0)
    step = ca.Function("offset_step", [acc, O, reset, XB, PB, TOL],
                       [ca.vertcat(x, ok, p), its, nr, margin, packed],
                       ["acc", "offset", "reset", "x_base", "p_base", "tol"],
                       ["acc_out", "iterations", "residual_norm", "bound_margin", "outputs"])
    return step.mapaccum("offset_batch", n)


def _tour(offsets: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(order, reset): a nearest-neighbour walk through the offsets from the one nearest the
    base (distance with 0.1 rad weighing as 1 m); ``reset`` where the next offset is nearer
    the base than the last one visited (it starts from the base solution)."""
    d = np.array(offsets, float)
    d[:, 3:] = np.radians(d[:, 3:]) * 10.0
    origin = np.linalg.norm(d, axis=1)
    left = np.ones(len(d), bool)
    order, reset = [], []
    k = int(np.argmin(origin))
    while True:
        order.append(k)
        left[k] = False
        if not left.any():
            break
        dist = np.where(left, np.linalg.norm(d - d[k], axis=1), np.inf)
        nxt = int(np.argmin(dist))
        reset.append(bool(origin[nxt] < dist[nxt]))
        k = nxt
    return np.array(order, int), np.array([True] + reset, bool)


def _quat(rpy_deg):
    """CasADi (e1, e2, e3, e0) of R = Rz Ry Rx (degrees), as models.body.quaternion_rpy."""
    r, p, y = (0.5 * rpy_deg[i] * (math.pi / 180.0) for i in range(3))
    cr, sr, cp, sp, cy, sy = ca.cos(r), ca.sin(r), ca.cos(p), ca.sin(p), ca.cos(y), ca.sin(y)
    return ca.vertcat(sr * cp * cy - cr * sp * sy, cr * sp * cy + sr * cp * sy,
                      cr * cp * sy - sr * sp * cy, cr * cp * cy + sr * sp * sy)


def _qmul(a, b):
    """CasADi quaternion product a (x) b, both (e1, e2, e3, e0)."""
    av, a0, bv, b0 = a[0:3], a[3], b[0:3], b[3]
    return ca.vertcat(a0 * bv + b0 * av + ca.cross(av, bv), a0 * b0 - ca.dot(av, bv))


def _own_loads(scene, body, pos, rpy0) -> ca.Function:
    """``own(offset) -> (6,)``: the free body's weight, buoyancy and drag in the current at
    rest (force N, moment N m about the reference point, global axes) at the offset pose,
    from its own Mechanism part (:func:`~symcable.models.body.body.body_part`); zeros for a
    fixed body (it has none)."""
    off = ca.SX.sym("offset", 6)
    if not body.is_free:
        return ca.Function("own", [off], [ca.SX.zeros(6)])
    part = body_part(body, scene.environment)
    q = ca.vertcat(ca.DM(pos) + off[0:3], _qmul(_quat(off[3:6]), ca.DM(quaternion_rpy(rpy0))))
    expr = ca.vertcat(part.outputs["own_force"].expr, part.outputs["own_moment"].expr)
    # (weight, buoyancy and drag do not depend on the statics' springs' parameters)
    expr = ca.substitute(expr, ca.vertcat(part.q, part.v, part.p),
                         ca.vertcat(q, ca.DM.zeros(6), ca.DM(part.static_p)))
    return ca.Function("own", [off], [expr])


def _tangents(mech, S, body, pose_p, own, base) -> ca.Function:
    """``offset_tangents(x, offset) -> (dR/dx, dR/doffset, dY/dx, dY/doffset, dOwn/doffset)``,
    Y the lines' force and moment on the body (the moment about the moved reference point,
    ``base`` (3,) m plus the offset's translation: the output's is about the point its
    ``position`` output names); R the virtual machine's residual (generated C has no
    derivatives)."""
    off = ca.SX.sym("offset", 6)
    n_q = mech.n_q
    x = ca.SX.sym("x", n_q + mech.n_z)
    p = pose_p(off)
    force = mech.outputs[f"{body}.force"].expr
    shift = ca.DM(np.asarray(base, float)) + off[0:3] - mech.outputs[f"{body}.position"].expr
    out = ca.vertcat(force, mech.outputs[f"{body}.moment"].expr - ca.cross(shift, force))
    out = ca.substitute(out, ca.vertcat(mech.q, mech.z, mech.v, mech.t, mech.p),
                        ca.vertcat(x[:n_q], x[n_q:], ca.DM.zeros(mech.n_v), 0.0, p))
    r = S.residual(x, p)
    return ca.Function("offset_tangents", [x, off], [ca.jacobian(r, x), ca.jacobian(r, off),
                                                     ca.jacobian(out, x), ca.jacobian(out, off),
                                                     ca.jacobian(own(off), off)])


def _stiffness(tangents, eq) -> np.ndarray:
    """(6, 6) -d(restoring force)/d(offset) at the base (per m and per rad), exact: the
    lines' by the implicit function theorem on the static residual (dx = -J^-1 dR/dp dp,
    sparse LU), the body's own loads by their CasADi derivative."""
    import scipy.sparse as sp
    import scipy.sparse.linalg as spla

    Jx, Jo, Yx, Yo, Oo = tangents(np.r_[eq.q, eq.z], np.zeros(6))
    rows, cols = Jx.sparsity().get_triplet()
    J = sp.csc_matrix((np.asarray(Jx.nonzeros(), float), (rows, cols)), shape=Jx.shape)
    dx = -spla.splu(J).solve(np.asarray(Jo, float))
    dF = np.asarray(Yo, float) + np.asarray(Yx, float) @ dx + np.asarray(Oo, float)
    dF[:, 3:] *= 180.0 / math.pi  # offsets in degrees: per radian
    return -dF


def _line_loads(held) -> dict | None:
    """Line name -> its whole submerged weight (N), for :func:`_line_balance`; None in a
    current (the drag is not an output)."""
    if any(held.environment.current):
        return None
    out = {}
    for line in held.lines:
        seg = segment_table(line_scene(held, line))
        out[line.name] = float(np.sum(seg["w"] * seg["ds"]))
    return out


def _line_balance(weights, out) -> float:
    """The largest |fa + fb - W - C| of the lines (``weights``: :func:`_line_loads`) over
    the largest end tension; NaN without weights."""
    if weights is None:
        return float("nan")
    worst, top = 0.0, 0.0
    for name, w in weights.items():
        fa, fb = np.ravel(out[f"{name}.end_force_a"]), np.ravel(out[f"{name}.end_force_b"])
        load = np.array([0.0, 0.0, float(np.sum(out[f"{name}.contact_force"])) - w])
        worst = max(worst, float(np.linalg.norm(fa + fb - load)))
        top = max(top, float(np.linalg.norm(fa)), float(np.linalg.norm(fb)))
    return worst / max(top, 1e-300)


def offset_sweep(scene, body: str, offsets, *, about: str = "equilibrium",
                 tol: float | None = None, codegen: bool | None = None) -> OffsetSweep:
    """The restoring force on ``body`` held at each of ``offsets``, its lines (and every
    other free part of the scene) in static equilibrium (module docstring).

    Parameters
    ----------
    scene : anything :func:`symcable.load_scene` takes (a cable3d scene with bodies)
    body : str
        The body's name (``[bodies.NAME]``).
    offsets : array (n, 6) or (6,)
        Rows (dx, dy, dz, droll, dpitch, dyaw), m and deg, from the base pose
        (:class:`~symcable.results.offsets.OffsetSweep`); :func:`offsets_along` builds a
        range along one degree of freedom.
    about : "equilibrium" | "scene"
        The base pose: the body's static equilibrium (a free body; a fixed body's is where
        the scene holds it), or where the scene puts it.
    tol : float, optional
        N, the static residual's tolerance (default the static solve's).
    codegen : bool or None
        The static solve in generated C (as :func:`symcable.solve_static`).

    Raises
    ------
    SceneError
        No such body, or not a cable3d scene with bodies.
    SymcableError
        Offsets not (n, 6) finite numbers, ``about`` unknown.
    ConvergenceError
        The base pose's own static solve fails (a failed offset is a row with status
        "failed", not an error).
    """
    t0 = time.perf_counter()
    scene = load_scene(scene)
    if not getattr(scene, "bodies", None):
        raise SceneError(f"scene {scene.name!r}: an offset sweep needs a scene with bodies "
                         "([bodies.NAME] of a model = \"cable3d\" scene)")
    if body not in scene.bodies:
        raise SceneError(f"body = {body!r}: no such body in scene {scene.name!r}; its bodies: "
                         f"{', '.join(scene.bodies)}")
    off = np.asarray(offsets, float)
    off = off.reshape(1, 6) if off.shape == (6,) else off
    if off.ndim != 2 or off.shape[1] != 6 or len(off) == 0 or not np.all(np.isfinite(off)):
        raise SymcableError(f"offsets: shape {np.shape(offsets)}: must be (n, 6) finite rows "
                            "(dx, dy, dz in m, droll, dpitch, dyaw in deg), n >= 1")
    if about not in ABOUT:
        raise SymcableError(f"about = {about!r}: must be one of {', '.join(map(repr, ABOUT))}")
    b = scene.bodies[body]
    pos, rpy = np.asarray(b.position, float), np.asarray(b.orientation_deg, float)
    if about == "equilibrium" and b.is_free:
        _, eq0 = static_equilibrium(scene, tol=tol, codegen=codegen)
        pos = np.ravel(eq0.outputs[f"{body}.position"]).astype(float)
        e = np.ravel(eq0.outputs[f"{body}.orientation"])
        rpy = _rpy(_quat_rotation(e))
    R0 = rotation_rpy(rpy)
    fixed = dataclasses.replace(b, kind=BodyKind.FIXED, position=tuple(pos),
                                orientation_deg=tuple(rpy))
    held = dataclasses.replace(scene, bodies=MappingProxyType({**scene.bodies, body: fixed}))
    mech = cable3d_mechanism(held)
    _, eq = static_equilibrium(held, tol=tol, codegen=codegen)
    tol = float(eq.stats["tolerance"])
    ends, lines = [], []
    for line in held.lines:
        for key in ("a", "b"):
            end = line.end(key)
            if isinstance(end, BodyEnd) and end.body == body:
                ends.append((line.name, key, tuple(end.offset)))
                if line not in lines:
                    lines.append(line)
    if not ends:
        raise SceneError(f"body = {body!r}: no line is attached to it: nothing restores it")
    F = functions(mech)
    S = F.static_solver(codegen)
    # built once per held scene: F is its structure's (shared by scenes of other numbers,
    # a fixed body's pose among them), so the key holds every number built in (the pose,
    # the body's own numbers, the base parameters)
    cache = F.__dict__.setdefault("_offset_sweep", {})
    key = (body, repr(b), pos.tobytes(), rpy.tobytes(), np.asarray(eq.p, float).tobytes())
    if key not in cache:
        pose_p = _pose_params(mech, eq.p, pos, R0, ends)
        own = _own_loads(scene, b, pos, rpy)
        while len(cache) >= SWEEPS_KEPT:
            cache.pop(next(iter(cache)))
        cache[key] = {"pose_p": pose_p, "own": own, "weights": _line_loads(held),
                      "tangents": _tangents(mech, F.static_solver(False), body, pose_p, own,
                                            pos)}
    funcs = cache[key]
    pose_p, own = funcs["pose_p"], funcs["own"]
    x_base = np.concatenate([eq.q, eq.z])
    n, n_x = len(off), len(x_base)
    order, reset = _tour(off)
    if (n, S.compiled) not in funcs:
        funcs[n, S.compiled] = _batch(S, pose_p, n_x, mech.params.n, n, bound_numbers(mech))
    tb = time.perf_counter()
    acc, its, nr, _, packed = funcs[n, S.compiled](np.r_[x_base, 1.0, eq.p], off[order].T,
                                                   reset[None, :].astype(float), x_base, eq.p, tol)
    batch_time = time.perf_counter() - tb
    _, outs, status, path, iters, resid, fallbacks = _walk(
        mech, F, eq, off, order, reset, (acc, its, nr, packed), pose_p, tol, codegen)
    K = _stiffness(funcs["tangents"], eq)
    line_force, force, ta, tb_, balance = _forces(outs, off, body, lines, own,
                                                  funcs["weights"], pos)
    stats = {"tolerance": tol, "batch_time": batch_time, "wall_time": time.perf_counter() - t0,
             "fallbacks": fallbacks, "resets": int(reset.sum()), "compiled": bool(S.compiled),
             "unknowns": int(n_x)}
    return OffsetSweep(scene.name, body, off, np.r_[pos, rpy], line_force, force, K,
                       tuple(ln.name for ln in lines), ta, tb_, tuple(status), tuple(path),
                       iters, resid, balance, stats)


def _walk(mech, F, eq, off, order, reset, batch, pose_p, tol, codegen) -> tuple:
    """Each offset's solution: the batched Newton's where it converged, else a solve from
    the neighbouring offset's solution (the walk's previous one, or the base pose after a
    reset). Returns X (n, n_x), outputs (None where failed), status, path, iterations,
    residual norms (N) and the number of fallbacks."""
    acc, its, nr, packed = batch
    acc, packed = np.asarray(acc, float), np.asarray(packed, float)
    its, nr = np.asarray(its, float).ravel(), np.asarray(nr, float).ravel()
    x_base = np.concatenate([eq.q, eq.z])
    n, n_x = len(off), len(x_base)
    X = np.full((n, n_x), np.nan)
    outs, status, path = [None] * n, ["failed"] * n, [""] * n
    iters, resid = np.zeros(n), np.full(n, np.nan)
    fallbacks = 0
    prev = None  # the last offset solved, in the walk's order
    for j, k in enumerate(order):
        if acc[n_x, j] > 0.5 and its[j] <= SOLVE_MAX_ITER:
            X[k], outs[k], status[k], path[k] = acc[:n_x, j], F.unpack(packed[:, j]), \
                "converged", "batch"
            iters[k], resid[k] = its[j], nr[j]
        else:
            fallbacks += 1
            nb = x_base if (prev is None or reset[j]) else X[prev]
            p_nb = eq.p if (prev is None or reset[j]) else \
                np.asarray(pose_p(off[prev]), float).ravel()
            start = Start(nb[:mech.n_q], nb[mech.n_q:], p_nb, "the neighbouring offset's "
                          "solution", homotopy="the offset")
            try:
                e_k = solve_equilibrium(mech, np.asarray(pose_p(off[k]), float).ravel(),
                                        tol=tol, starts=[start], codegen=codegen)
            except ConvergenceError as exc:
                path[k] = str(exc).splitlines()[0][:300]
                continue
            X[k], outs[k], status[k] = np.r_[e_k.q, e_k.z], e_k.outputs, "converged"
            path[k], iters[k] = e_k.stats["path"], e_k.stats["iterations"]
            resid[k] = e_k.stats["residual_norm"]
        prev = k
    return X, outs, status, path, iters, resid, fallbacks


def _forces(outs, off, body: str, lines, own, weights, base) -> tuple:
    """Per offset (n rows; NaN where it failed): the lines' force and moment on the body
    (n, 6) N, N m about its displaced reference point (``base`` (3,) m, the reference point
    at the base pose, plus the offset's translation); with the body's own loads (n, 6);
    each line's end tensions at A and B (n, n_lines) N; the lines' force balance (n,)."""
    n = len(off)
    line_force = np.full((n, 6), np.nan)
    force = np.full((n, 6), np.nan)
    ta, tb_ = np.full((n, len(lines)), np.nan), np.full((n, len(lines)), np.nan)
    balance = np.full(n, np.nan)
    for k in range(n):
        o = outs[k]
        if o is None:
            continue
        # the output's moment is about the point its ``position`` output names (the held
        # body's first line end less that end's offset at the base orientation): moved to
        # the displaced reference point
        f = np.ravel(o[f"{body}.force"])
        shift = base + off[k, :3] - np.ravel(o[f"{body}.position"])
        line_force[k] = np.r_[f, np.ravel(o[f"{body}.moment"]) - np.cross(shift, f)]
        force[k] = line_force[k] + np.asarray(own(off[k]), float).ravel()
        for i, line in enumerate(lines):
            ta[k, i] = np.linalg.norm(np.ravel(o[f"{line.name}.end_force_a"]))
            tb_[k, i] = np.linalg.norm(np.ravel(o[f"{line.name}.end_force_b"]))
        balance[k] = _line_balance(weights, o)
    return line_force, force, ta, tb_, balance


def _quat_rotation(e) -> np.ndarray:
    """(3, 3) body to global axes of the unit quaternion (e0, e1, e2, e3), scalar first."""
    w, x, y, z = np.asarray(e, float) / np.linalg.norm(e)
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])
