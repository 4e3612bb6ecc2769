"""How far the penalty seabed moves a static answer from a rigid bed's.

symcable's seabed is a penalty contact: a line lying on it sinks into it by w / (k d) (its
submerged weight per metre w, N/m, over the seabed stiffness k, Pa/m, times its diameter d),
while its anchors and the free points beside it stay where they are put, and a clump or a
light line sinks by its own measure. The answer is exact for that bed. A rigid-bed code
(MoorPy) puts every line at z = -depth: the suspended part is shorter by the sinking, an
anchor sits above the sunk line beside it and takes a pull down the step. On a soft bed
(k = 1e4 Pa/m: a chain sinks 2 m) that moved end tensions by 3-20 % in the fuzz study.

The estimate extrapolates to a rigid bed at first order in the sinking, which falls as 1/k:
with u = 1 / (the bed's stiffness scale), T(u) = T_rigid + C u, so the answer (u = 1) is off
by |C| = |dT/d(scale)| at scale 1. For a cable3d, rod or hybrid scene that derivative is
exact and cheap: one sparse solve with the static Jacobian at the answer against the
residual's derivative along the contact's ``bed`` parameter (every line's and point's
together), and the end forces' directional derivative along it. A planar line, whose model
has no such parameter, is solved again (rebuilt, which is cheap) with a bed :data:`STIFFER`
times stiffer:

    e = STIFFER / (STIFFER - 1) |T(k) - T(STIFFER k)|

Per line, the largest over its two end tensions, in N and as a fraction of the scene's
largest tension. Only where a line touches the bed. Above the accuracy asked (default 1 %)
the solution warns, naming the sinking and the stiffness that would bring it under.
"""
from __future__ import annotations

import dataclasses
import time

import numpy as np

from ..errors import SymcableError
from ..models import formulation_of
from ..scene import Scene

__all__ = ["STIFFER", "with_bed_estimate"]

#: the stiffer bed's factor on the seabed stiffness
STIFFER = 4.0


def _touches(sol) -> bool:
    """Whether a line rests on the bed: a node's contact above 1e-6 of the largest tension
    (the contact ramp's smooth tail puts a trace on every node above the bed)."""
    scale = max(float(np.max(ln.tension, initial=0.0)) for ln in sol.lines.values())
    return any(float(np.max(ln.contact_force, initial=0.0)) > 1e-6 * scale
               for ln in sol.lines.values())


def _ends(sol) -> dict:
    """``{line: (anchor tension, fairlead tension)}``, N, of a static solution."""
    return {name: (ln.anchor_tension, ln.fairlead_tension) for name, ln in sol.lines.items()}


def _bed_columns(mech) -> np.ndarray:
    """The indices in p of every ``bed`` block (each line's, each point's)."""
    return np.concatenate([np.arange(mech.params.n)[mech.params.slice(name)]
                           for name in mech.params.names
                           if name == "bed" or name.endswith(".bed")] or [np.zeros(0, int)])


def _end_names(scene: Scene, sol) -> dict:
    """``{line: (its end A force output, its end B force output)}``."""
    if scene.version == 1:
        return {next(iter(sol.lines)): ("end_force_a", "end_force_b")}
    return {ln.name: (f"{ln.name}.end_force_a", f"{ln.name}.end_force_b") for ln in scene.lines}


def _mechanism_slopes(scene: Scene, sol) -> dict:
    """``{line: (dT_a, dT_b)}``, N: the end tensions' derivative with respect to the bed's
    stiffness scale (every ``bed`` block together) at the answer ``sol`` (a cable3d, rod or
    hybrid solution of ``scene``), holding its equilibrium: J dx = -dR/dbed, one sparse
    solve with the exact Jacobian, and the end forces' directional derivative along it."""
    import casadi as ca
    from scipy.sparse.linalg import spsolve

    from ..linalg.sparse import to_csc
    from ..mechanism.functions import functions
    if formulation_of(scene).twists:
        from .rod_static import hybrid_zones, rod_mechanism
        mech = rod_mechanism(hybrid_zones(scene)[0])
    else:
        from .cable3d_static import cable3d_mechanism, calm
        mech = cable3d_mechanism(calm(scene))
    x = np.asarray(sol.unknowns, float)
    cols = _bed_columns(mech)
    if mech.n_z or x.size != mech.n_q or not cols.size:
        raise SymcableError("the Mechanism has constraint forces or no bed parameter")
    F = functions(mech)
    p = np.asarray(mech.static_p, float)
    Jsp = to_csc(F.static_jacobian(x, p)[1])
    along = np.zeros(mech.params.n)  # every bed block together
    along[cols] = 1.0
    r_bed = np.asarray(F.static_parameter_slope(x, p, along), float).ravel()
    with np.errstate(all="ignore"):
        dx = np.atleast_1d(spsolve(Jsp, -r_bed))
    if not np.all(np.isfinite(dx)):
        raise SymcableError("the static Jacobian is singular at the answer")
    ends = _end_names(scene, sol)
    key = "_bed_end_slopes"
    fn = F.__dict__.get(key)
    if fn is None:
        m = mech
        y = ca.vertcat(*[m.outputs[n].expr for pair in ends.values() for n in pair])
        dq, dp = ca.SX.sym("dq", m.n_q), ca.SX.sym("dp", m.params.n)
        dy = ca.jtimes(y, ca.vertcat(m.q, m.p), ca.vertcat(dq, dp))
        fn = F.__dict__[key] = ca.Function("bed_end_slopes", [m.q, m.v, m.z, m.t, m.p, dq, dp],
                                           [y, dy])
    y, dy = (np.asarray(a, float).ravel() for a in fn(x, np.zeros(mech.n_v), np.zeros(0), 0.0,
                                                        p, dx, along))
    out = {}
    for k, name in enumerate(ends):
        slopes = []
        for j in (0, 1):
            f, df = y[6 * k + 3 * j:6 * k + 3 * j + 3], dy[6 * k + 3 * j:6 * k + 3 * j + 3]
            n = float(np.linalg.norm(f))
            slopes.append(float(np.dot(f, df)) / n if n > 0 else float(np.linalg.norm(df)))
        out[name] = tuple(slopes)
    return out


def _sinking(scene: Scene) -> dict:
    """``{line: m}``, how far each line sinks into the bed under its own weight, w / (k d)
    (its heaviest section's)."""
    k = scene.seabed.stiffness
    lines = ({"line": scene.sections} if scene.version == 1
             else {ln.name: ln.sections for ln in scene.lines})
    return {name: max(max(s.line_type.weight, 0.0) / (k * s.line_type.diameter) for s in secs)
            for name, secs in lines.items()}


def _warnings(scene: Scene, lines: dict, accuracy: float) -> tuple:
    k = scene.seabed.stiffness
    out = []
    for name, e in lines.items():
        if e["relative"] <= accuracy:
            continue
        need = k * e["relative"] / accuracy * 1.1
        out.append(f"line '{name}': the penalty seabed (stiffness {k:.3g} Pa/m) lets it sink "
                   f"{e['sinking']:.3g} m into the bed; a rigid bed would move its end "
                   f"tensions by about {e['error']:.3g} N ({e['relative']:.1%} of the largest "
                   f"tension); seabed.stiffness = {need:.2g} Pa/m would bring that under "
                   f"{100 * accuracy:g} % (if the bed is that firm)")
    return tuple(out)


def with_bed_estimate(scene: Scene, sol, solve, accuracy: float, options: dict):
    """``sol`` (the static solution of ``scene``) with the seabed's estimated effect in
    ``stats["seabed_error"]`` (module docstring) and a warning per line above ``accuracy``;
    unchanged for a scene without a seabed or whose lines do not touch it. ``solve(scene)``
    solves a scene without estimating (the planar line's stiffer bed); ``options`` the
    solve's (``codegen``). The report: ``lines`` (per line ``error`` N, ``relative`` to the
    largest tension, ``sinking`` m), ``max_relative``, ``stiffness`` (Pa/m), ``method`` and
    ``wall_time`` (s)."""
    if scene.seabed is None or sol.status != "converged" or not _touches(sol):
        return sol
    t0 = time.perf_counter()
    mine = _ends(sol)
    try:
        if formulation_of(scene).linearised:  # the planar line: its own Model, no bed block
            stiff = dataclasses.replace(scene, seabed=dataclasses.replace(
                scene.seabed, stiffness=STIFFER * scene.seabed.stiffness))
            theirs = _ends(solve(stiff))
            errors = {name: STIFFER / (STIFFER - 1.0) * max(abs(ta - theirs[name][0]),
                                                            abs(tb - theirs[name][1]))
                      for name, (ta, tb) in mine.items()}
            how = f"against a {STIFFER:g} times stiffer bed"
        else:
            errors = {name: max(abs(da), abs(db))
                      for name, (da, db) in _mechanism_slopes(scene, sol).items()}
            how = "from the sensitivity to the bed's stiffness"
    except (SymcableError, RuntimeError) as exc:
        first = str(exc).splitlines()[0][:200]
        stats = dict(sol.stats, seabed_error={"lines": {}, "max_relative": None,
                                              "wall_time": time.perf_counter() - t0})
        return dataclasses.replace(sol, stats=stats, warnings=tuple(sol.warnings) + (
            f"no seabed estimate: {first}",))
    scale = max(max(max(v) for v in mine.values()),
                max((float(np.max(ln.tension)) for ln in sol.lines.values()), default=0.0),
                1e-300)
    sink = _sinking(scene)
    lines = {}
    for name, err in errors.items():
        lines[name] = {"error": float(err), "relative": float(err / scale),
                       "sinking": float(sink.get(name, next(iter(sink.values()))))}
    report = {"lines": lines, "max_relative": max(e["relative"] for e in lines.values()),
              "stiffness": scene.seabed.stiffness, "method": how,
              "wall_time": time.perf_counter() - t0}
    stats = dict(sol.stats, seabed_error=report)
    return dataclasses.replace(sol, stats=stats,
                               warnings=tuple(sol.warnings) + _warnings(scene, lines, accuracy))
