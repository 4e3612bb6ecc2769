"""Periodic steady states of a ``cable3d`` scene, fully nonlinear: one period at full
amplitude (:func:`solve_periodic_3d`) and the tension response over excitation periods
(:func:`sweep_periodic_3d`), through the generic periodic solvers
(:func:`~symcable.solvers.periodic_mech.solve_periodic_mech`). :mod:`symcable.api.analyses` sends a
cable3d scene here (and a rod or hybrid scene: its own Mechanism and static state,
:mod:`symcable.api.scene3d`; a periodic solve keeps the anchors of its
start's reference frames, which holds while no edge turns by more than about 120 degrees
from its static direction over the period); the arguments are the same.
"""
from __future__ import annotations

import dataclasses
import time

import numpy as np

from .cable3d import NEWTON_TOL, RHO_INF, _line_result, _motions, _period
from .cable3d_static import cable3d_mechanism
from .scene3d import check_moves, check_periodic_scene, dynamics_mechanism, scene_equilibrium
from ..errors import ConvergenceError, SymcableError
from ..limits import current as current_limits, past_deadline
from .planar_periodic import method_options
from ..results.periodic import PeriodicSweep
from ..results.periodic_generic import MechanismPeriodic
from ..results.periodic_line import PeriodicLine, as_periodic
from ..scene import Scene
from ..solvers.floquet import floquet
from ..solvers.options import Shooting
from ..solvers.periodic_mech import solve_periodic_mech

__all__ = ["periodic_p", "solve_periodic_3d", "solve_periodic_3d_state", "sweep_periodic_3d"]


def solve_periodic_3d(scene: Scene, method="collocation", *, codegen: bool | None = None,
                      stability: bool = False, **options) -> PeriodicLine:
    """The periodic response of a cable3d line to its harmonic end motion, fully nonlinear
    (see :func:`symcable.solve_periodic`): one period, the motion at full amplitude (no
    ramp), as a :class:`~symcable.results.periodic_line.PeriodicLine` (a scene of several
    lines: ``PeriodicSystem``; both a :class:`~symcable.results.periodic.PeriodicSolution`)
    over ``[0, T)`` whose ``method`` names the periodic method and whose ``stats`` hold
    ``period`` (s), the method's iterations and its own
    ``error_estimate`` (the largest scaled equation defect on a grid 4 times the solver's).

    ``stability=True``: also the Floquet multipliers of the solution
    (:func:`~symcable.solvers.floquet.floquet`, the exact monodromy of shooting's period map
    at the solution, whatever method found it), in ``stats``: ``floquet_multipliers``,
    ``floquet_max`` (the largest modulus), ``stable`` (``floquet_max < 1 + 1e-4``) and the
    other ``floquet_*`` entries of :meth:`~symcable.solvers.floquet.Floquet.stats`.
    """
    return solve_periodic_3d_state(scene, method, codegen, stability, None, options)[0]


def periodic_p(mech) -> np.ndarray:
    """(n_p,) the parameters a periodic solve of ``mech`` runs with: its values with every
    line's ``ramp`` (namespaced in a scene of several) at 0, the motion at full amplitude
    from t = 0."""
    p = np.array(mech.params.values, float)
    for block in mech.params.names:
        if block.split(".")[-1] == "ramp":
            p[mech.params.slice(block)] = 0.0
    return p


def solve_periodic_3d_state(scene: Scene, method, codegen, stability, start, options) -> tuple:
    """(PeriodicLine or PeriodicSystem, MechanismPeriodic) of :func:`solve_periodic_3d`;
    ``start``: a periodic solution of this scene's mechanism (the second of a previous
    call's pair) at any period and resolution (its samples stretched to this period) to
    start from, the method's own start where that fails (a sweep's continuation, the error
    estimate's second solve)."""
    started = time.perf_counter()
    if not isinstance(stability, bool):
        raise SymcableError(f"stability = {stability!r}: must be True or False")
    period = _period(scene)
    motions = _motions(scene)
    other = sorted({m.kind for m in motions if m.kind not in ("harmonic", "rao")})
    waves = scene.environment.waves
    if waves is not None and waves.kind != "regular" and (waves.count > 1 or waves.kind !=
                                                          "components"):
        raise SymcableError(f"scene {scene.name!r}: a periodic response needs a regular sea "
                            f"(environment.waves.kind = 'regular'), not {waves.kind!r}: run "
                            "simulate for an irregular sea")
    if period is None or other:
        where = "[end_b.motion]" if scene.version == 1 else "[points.NAME.motion] of a vessel point"
        has = (f"its motion is {' and '.join(map(repr, other))}: run simulate instead" if other
               else "it prescribes no motion: give one")
        raise SymcableError(f"scene {scene.name!r}: a periodic response needs harmonic motion "
                            f"only ({where} kind = 'harmonic'), and {has}")
    check_periodic_scene(scene)
    tol = options.pop("tol", None)
    name, opts = method_options(method, options)
    if isinstance(opts, Shooting) and opts.rho_inf is None:
        # simulate's rho_inf (symcable.api.cable3d.RHO_INF = 0): at the generic 0.5 an under-resolved
        # axial mode of a stiff taut line rings on through the period map, and a moored body
        # pulled by a taut rope (EA 5e7 N, T/100) came out with a tension range 26 % smaller
        # than the time run's and collocation's (positions 3 mm apart); at 0 within 1 %
        opts = dataclasses.replace(opts, rho_inf=RHO_INF)
    if isinstance(opts, Shooting) and opts.newton_tol is None:
        # simulate's step tolerance: at the generic 1e-10, below the roundoff floor of many
        # lines (a step's residual stalls near 5e-9 on a 36-segment mooring), every period
        # "failed" where simulate ran the same steps
        opts = dataclasses.replace(opts, newton_tol=NEWTON_TOL)
    mech, eq = scene_equilibrium(scene, codegen=codegen)
    # in waves the static state is the calm sea's (its Mechanism without the waves): the
    # periodic solve runs the scene's own
    mech = dynamics_mechanism(scene, mech if scene.environment.waves is None
                              else cable3d_mechanism(scene))
    check_moves(scene, mech)
    p = periodic_p(mech)
    ramped = np.array(mech.params.values, float)  # the start's first period: the motion
    for block in mech.params.names:  # ramped in from rest (every line's "ramp")
        if block.split(".")[-1] == "ramp":
            ramped[mech.params.slice(block)] = 1.0
    # the virtual machine by default: compiling a collocation system of a 10-segment line
    # took minutes, longer than the solve (a few seconds) it would speed up. If the solve
    # from the method's own start fails, again from a short run whose first period ramps the
    # motion in (at full amplitude from t = 0 a fairlead moved by its amplitude jerked a 3D
    # line with seabed friction to many times its static tension at the first step, and the
    # start-up run or shooting can fail there)
    kw = dict(p=p, start=eq, codegen=False if codegen is None else codegen,
              **({} if tol is None else {"tol": float(tol)}))
    res = None
    if start is not None:  # a neighbour's solution, stretched to this period; else as below
        try:
            res = solve_periodic_mech(mech, period, opts, **dict(
                kw, start=stretched(start, period, p), fallback=False))
        except ConvergenceError:
            res = None
    try:
        if res is None:
            res = solve_periodic_mech(mech, period, opts, **kw)
    except ConvergenceError as first:
        if past_deadline():
            raise ConvergenceError(f"{str(first).splitlines()[0]}; not tried again from a "
                                   "start with the motion ramped in: the call's time limit of "
                                   f"{current_limits().solve_seconds} s (sc.limits("
                                   "solve_seconds=...), --max-solve-seconds) has passed; the "
                                   "response may have no period: run simulate to see what "
                                   "it does", diagnostics=getattr(first, "diagnostics", None)
                                   ) from None
        try:
            res = solve_periodic_mech(mech, period, opts, start_p=ramped, **kw)
        except ConvergenceError as second:
            raise ConvergenceError(f"{str(first).splitlines()[0]}; again from a start with the "
                                   f"motion ramped in: {str(second).splitlines()[0]}",
                                   diagnostics=getattr(second, "diagnostics", None)) from None
        res = dataclasses.replace(res, warnings=tuple(res.warnings) + (
            f"the solve from the method's own start failed ({str(first).splitlines()[0]}); "
            "solved from a start with the motion ramped in over its first period",))
    stats = dict(res.stats, period=period)
    if stability:  # every method's solution judged on one map: shooting's, at its rho_inf
        shoot = isinstance(opts, Shooting)
        stats.update(floquet(mech, res, rho_inf=opts.rho_inf if shoot else RHO_INF,
                             newton_tol=opts.newton_tol if shoot else NEWTON_TOL).stats())
    stats["wall_time"] = time.perf_counter() - started
    if start is not None:
        stats["start_kind"] = ("neighbour" if str(res.stats.get("start", ""))
                               .startswith("periodic solution") else "own start")
    n_t = len(res.time)
    return as_periodic(_line_result(scene, mech, res, name, period / max(n_t, 1), stats,
                                    res.warnings)), res


def stretched(per: MechanismPeriodic, period: float, p) -> MechanismPeriodic:
    """``per`` (a periodic solution at another period, same mechanism layout) as a start at
    ``period``: its samples over the new period, velocities scaled by the ratio of periods,
    parameters ``p``, no integrator state (shooting then starts from the samples)."""
    r = per.period / period
    stats = {k: v for k, v in per.stats.items() if k != "state0"}
    return dataclasses.replace(per, period=float(period), time=per.time / r, v=per.v * r,
                               p=np.asarray(p, float), stats=stats)


def _with_period(scene: Scene, period: float) -> Scene:
    """The scene with every harmonic motion at ``period`` s."""
    from ..scene import load_scene
    d = scene.to_dict()
    tables = [d.get("end_a"), d.get("end_b")] + [ln.get(k) for ln in d.get("lines", [])
                                                 for k in ("end_a", "end_b")]
    tables += list(d.get("points", {}).values())
    for t in tables:
        if isinstance(t, dict) and isinstance(t.get("motion"), dict):
            t["motion"]["period"] = period
    return load_scene(d)


def _swept_end(scene: Scene, line: str | None):
    """``(pick, label)``: ``pick(periodic_result) -> tension series (N)`` of the swept end: end B of a one-line
    scene; in a scene of several lines, the end of ``line`` (default: the first line with an
    end at a point that moves) at the moving point (end B when neither end moves)."""
    if scene.version != 2:
        if line is not None:
            raise SymcableError(f"line = {line!r}: a one-line scene has no named lines; "
                                "leave it out")
        return lambda per: per.fairlead_tension, "end B"
    names = [ln.name for ln in scene.lines]
    moving = {k for k, pt in scene.points.items() if pt.motion is not None}
    if line is None:
        at = [ln.name for ln in scene.lines if {ln.end_a, ln.end_b} & moving]
        if not at:
            raise SymcableError(f"scene {scene.name!r}: no line ends at a moving point; name "
                                f"the line to sweep with line = one of {names}")
        line = at[0]
    if line not in names:
        raise SymcableError(f"line = {line!r}: not a line of scene {scene.name!r}; one of {names}")
    ln = scene.lines[names.index(line)]
    end_a = isinstance(ln.end_a, str) and ln.end_a in moving and ln.end_b not in moving
    if end_a:
        return (lambda per: per.lines[line].anchor_tension), f"line {line}, end A"
    return (lambda per: per.lines[line].fairlead_tension), f"line {line}, end B"


def sweep_periodic_3d(scene: Scene, periods, method="collocation", *, resolution: int = 200,
                      codegen: bool | None = None, line: str | None = None,
                      continuation: bool = False, stability: bool = False,
                      **options) -> PeriodicSweep:
    """The periodic tension at the moving end of a cable3d line over excitation periods (a
    tension RAO; see :func:`symcable.sweep_periodic`): the scene's harmonic motion at each
    period, each solved by :func:`solve_periodic_3d` from its own start (the period is part
    of the line's Mechanism, so each period builds its own). A one-line scene: end B's
    tension (N); several lines and points: the tension of ``line`` (default the first line
    ending at a moving point) at its moving end. A period that fails gives NaN and a
    warning; every one failing raises.

    ``continuation=True``: each period starts from the previous period's solution (its
    samples stretched to the new period), and from its own start where that fails; in the
    order given, so a sweep up and a sweep down can follow two branches of a hysteretic
    response. ``stats["start"]`` says per period "neighbour" or "own start".
    ``stability=True``: per period the Floquet multipliers' largest modulus and whether the
    solution is stable (:func:`solve_periodic_3d`), as ``stats["floquet_max"]`` and
    ``stats["stable"]`` (lists; None for a failed period)."""
    for key, val in (("continuation", continuation), ("stability", stability)):
        if not isinstance(val, bool):
            raise SymcableError(f"{key} = {val!r}: must be True or False")
    started = time.perf_counter()
    check_periodic_scene(scene)
    pick, swept = _swept_end(scene, line)
    periods = np.asarray(periods, dtype=float).ravel()
    if periods.size == 0 or not np.all(np.isfinite(periods)) or np.any(periods <= 0):
        raise SymcableError(f"periods = {periods.tolist()!r}: must be a non-empty list of "
                            "periods > 0 s")
    if isinstance(resolution, bool) or int(resolution) != resolution or resolution < 8:
        raise SymcableError(f"resolution = {resolution!r}: must be an integer >= 8")
    tau = np.arange(int(resolution)) / int(resolution)
    rows = {k: np.full(periods.size, np.nan) for k in ("amp", "phase", "mean", "max", "min")}
    series = np.full((periods.size, tau.size), np.nan)
    statuses, warnings, its, times = [], [], [], []
    starts, fmax, stable = [], [], []
    prev = None
    name = method if isinstance(method, str) else type(method).__name__
    for i, T in enumerate(periods):
        t0 = time.perf_counter()
        try:
            per, mp = solve_periodic_3d_state(_with_period(scene, float(T)), method, codegen,
                                              stability, prev if continuation else None,
                                              dict(options))
        except (ConvergenceError, SymcableError) as exc:
            statuses.append("failed")
            warnings.append(f"period {T:g} s: {str(exc).splitlines()[0]}")
            its.append(None)
            times.append(time.perf_counter() - t0)
            starts.append("own start")
            fmax.append(None)
            stable.append(None)
            continue
        prev = mp
        starts.append(per.stats.get("start_kind", "own start"))
        fmax.append(per.stats.get("floquet_max"))
        stable.append(per.stats.get("stable"))
        name = per.method
        ten = pick(per)
        f = np.interp(tau * T, np.r_[per.time, T], np.r_[ten, ten[0]])
        c = np.fft.rfft(f) / f.size
        series[i] = f
        rows["amp"][i], rows["phase"][i] = 2 * abs(c[1]), float(np.angle(c[1]))
        rows["mean"][i], rows["max"][i], rows["min"][i] = f.mean(), f.max(), f.min()
        statuses.append(per.status)
        its.append(per.stats.get("iterations"))
        times.append(time.perf_counter() - t0)
    if all(st == "failed" for st in statuses):
        raise ConvergenceError(f"sweep_periodic of {scene.name!r}: every period failed; first: "
                               f"{warnings[0]}", diagnostics={"warnings": warnings})
    status = "converged" if all(st == "converged" for st in statuses) else "partial"
    return PeriodicSweep(
        scene_name=scene.name, method=name, periods=periods,
        fairlead_tension_amplitude=rows["amp"], fairlead_tension_phase=rows["phase"],
        fairlead_tension_mean=rows["mean"], fairlead_tension_max=rows["max"],
        fairlead_tension_min=rows["min"], normalised_time=tau, fairlead_tension=series,
        statuses=tuple(statuses), status=status,
        stats={"wall_time": time.perf_counter() - started, "iterations": its,
               "solve_time": times, "start": starts, "swept": swept,
               **({"floquet_max": fmax, "stable": stable} if stability else {})},
        warnings=tuple(warnings))
