"""The analyses of a ``cable3d`` scene, fully nonlinear: its Mechanism
(:func:`~symcable.api.cable3d_static.cable3d_mechanism`) at rest
(:func:`~symcable.api.cable3d_static.static_equilibrium`), then the generic solvers: time
stepping (:func:`~symcable.solvers.integrate.integrate`), modes
(:func:`~symcable.solvers.linearize.mechanism_modes`) and the exact linearisation.
:mod:`symcable.api.analyses` sends a cable3d scene here; the arguments are the same. Periodic
steady states: :mod:`symcable.api.cable3d_periodic`.

The same analyses run a ``model = "rod"`` (or ``"hybrid"``) scene, with the Mechanism and
static state :mod:`symcable.api.scene3d` says (the one place that dispatches on the model); a
rod's time run re-anchors its reference frames as it goes
(:func:`~symcable.models.rod.reanchor.reanchor_hook`), and its extra outputs (twist,
curvature, moments, internal force) come in ``stats["outputs"]``.
"""
from __future__ import annotations

import dataclasses
import math
import time

import numpy as np

from ..mechanism.functions import functions
from ..errors import ConvergenceError, SymcableError
from ..results.static import ModalSolution
from ..results.line3d import LineTrajectory, SystemTrajectory, line_from_outputs
from ..results.generic import SceneLinearization
from ..analytic.waves import default_band
from ..scene import End, EndCondition, Scene
from .cable3d_static import AT_REST, body_stiffness, dynamic_p, node_shapes, tows
from ..models.common.tow import held_motions
from ..models.rod.reanchor import reanchor_hook
from .scene3d import (check_moves, check_rk4_limit, dynamics_mechanism, has_twists, rod_line,
                      scene_equilibrium, start_state, twist_names, twist_shapes)
from ..solvers.integrate import (ERROR_TARGET, accurate_dt, check_steps, error_warning,
                                integrate)
from ..solvers.march import leaky_sum
from .time_tolerance import step_tolerance, tolerance_runs
from ..solvers.time_estimate import MOTION_FLOOR
from ..solvers.linearize import MAX_DENSE, mechanism_modes, output_sensitivity
from ..solvers.options import RK4, GeneralizedAlphaFirstOrder

__all__ = ["linearize_3d", "modal_analysis_3d", "simulate_3d"]

#: steps per excitation period by default (as the planar line's generalized-alpha default)
STEPS_PER_PERIOD = 100
#: generalized-alpha's default spectral radius at infinite step for cable3d: the axial modes
#: of a stiff line sit far above any step that resolves its motion, and a kinked motion table,
#: a seabed landing or a snap excites them; rho_inf = 0 removes them in one step (against
#: 0.5: smaller fairlead errors against MoorDyn run live and against the OrcaFlex series of
#: the chain decks at their default steps; the numbers in studies/README.md)
RHO_INF = 0.0
#: generalized-alpha's Newton tolerance on a cable3d run (``newton_tol``; the scaled step
#: residual, see :class:`~symcable.solvers.options.GeneralizedAlphaFirstOrder`): the
#: tensions then move by orders of magnitude less than the step's own error from a
#: tolerance of 1e-10, in less time (fewer chord iterations)
NEWTON_TOL = 1e-8
#: ... at most this times the force scale over the stiffest segment's force per unit
#: tolerance (:func:`newton_tolerance`): a step accepts position errors up to the tolerance
#: times the position scale, worth EA / ds times that in tension, and on a stiff line these
#: feed its lightly damped axial modes, which then ring on through the run (numbers in
#: studies/README.md)
STEP_FORCE_TOL = 1e-6
#: ... and never below this: a step's residual stalls at its round-off floor
NEWTON_TOL_FLOOR = 1e-11
#: the end tensions' error estimate (:func:`tension_error_estimate`) times this: the raw
#: estimate is about half the true error, so the factor makes it a slight overestimate.
#: Not where a tow enters or leaves a turn (:func:`motion_kinks`), where the run's error
#: peaks: there the raw estimate is already about the true error (0.9 to 1.3 times it on the
#: towed body's 300 m turn and on 150 m and 600 m turns of it, against runs at 1/4 to 1/32
#: of the step), and the factor had the towed body's step of 0.54 s warn of 1.8 % of the
#: tension range for a true error of 0.85 %
TENSION_ESTIMATE_FACTOR = 2.0
#: samples on each side of a kink of the prescribed motion whose tension estimate comes
#: from across it: the third derivative of the samples (three nested central differences)
#: at a sample reaches three samples either way
KINK_REACH = 3
#: the least range an end tension's error is relative to, as a fraction of the largest end
#: tension of the run: a steady tow's tensions vary by round-off only (a free end's is zero
#: to 2e-4 N), against which any estimate is a large fraction
TENSION_RANGE_FLOOR = 1e-3
#: rad, the former default's bound on a tow's step: the turn through at most this on its
#: tightest turn (a 90 degree turn in 31 steps); too coarse, now TOW_KINK_STEP and
#: TOW_STRETCH_STEP (studies/towed_body compares against it)
TOW_TURN_STEP = 0.05
#: rad, a tow's default step turns it through at most this on its tightest turn. Why: the
#: tow path is C1, its acceleration jumps by U^2 / R where a turn begins and ends, and there
#: the tensions' error is first order in the step. The towed body (towed_body.toml, its 300 m
#: turn at 12 kn) at TOW_STRETCH_STEP's 0.54 s (0.011 rad per step) was 0.85 % of its
#: fairlead tension's range off a run at 1/32 of the step, at the 1 % target, and its
#: estimate said 0.99 %; at 0.008 rad (0.39 s) 0.6 %, estimate 0.81 %. A turn that changes
#: the tensions little against their range can need less (a 600 m turn at 3 m/s: 1 % at
#: 0.001 rad), which the run's error estimate then says
TOW_KINK_STEP = 0.008
#: a tow's default step in a turn is also at most TOW_STRETCH_STEP sqrt(T / EA) / Omega for
#: each line (T its largest tension at the start, EA its stiffest section's, Omega = U / R
#: the tightest turn's rate). Why: each step's Newton iterations start from y0 + h y'0,
#: which moves every node along its velocity; a line turning at Omega is then stretched by
#: the chord's strain (Omega h)^2 / 2, a spurious tension EA (Omega h)^2 / 2, and once that
#: is a fair part of the line's own tension the chord iterations (the matrix of the step's
#: start) diverge and the step substeps or fails. The largest steps without substeps in
#: steady turns scale as sqrt(T / EA) / Omega; 0.25 keeps the spurious tension under T / 32
#: (the measured steps: studies/README.md). The straight tow, whose predictor is exact,
#: takes any step
TOW_STRETCH_STEP = 0.25


def _motions(scene: Scene) -> list:
    """Every prescribed motion: of the ends (one line) or of the vessel points and vessels
    (version 2; a vessel's :class:`~symcable.scene.vessel.BodyMotion`, its rows t and six
    columns)."""
    ends = [e for e in (scene.end_a, scene.end_b) if e is not None]
    ends += [ln_end for ln in scene.lines for ln_end in (ln.end_a, ln.end_b)
             if isinstance(ln_end, End)]
    return [e.motion for e in ends if e.motion is not None] + [
        pt.motion for pt in scene.points.values() if pt.motion is not None] + [
        b.motion for b in scene.bodies.values() if b.motion is not None]


def run_start(scene: Scene) -> float:
    """When a run starts, s: the earliest row of a motion table when it is before 0 (MoorDyn's
    tables start at -10 s), else 0 (where a harmonic motion starts its ramp)."""
    firsts = [m.samples[0][0] for m in _motions(scene) if m.kind == "table"]
    return min([0.0] + [float(t) for t in firsts])


def default_dt(scene: Scene, duration: float, tensions: dict | None = None) -> float:
    """The default step, s: a harmonic motion's period / STEPS_PER_PERIOD; a table's smallest
    row spacing (the table resolves its motion no finer); a tow's time to turn through
    TOW_KINK_STEP rad on its tightest turn, and given ``tensions`` ({line name: its largest
    tension at the start, N}; a one-line scene's line is ``""``) at most TOW_STRETCH_STEP
    sqrt(T / EA) / Omega there; at most duration / 100; with no motion duration / 100."""
    dts = [duration / 100.0]
    rates = [m.speed / radius for m in _motions(scene) if m.kind == "tow"
             for _, radius, _ in m.turns]
    if rates and tensions:
        lines = {"": scene.sections} if scene.version == 1 else {
            ln.name: ln.sections for ln in scene.lines}
        for name, T in tensions.items():
            EA = max(s.line_type.EA for s in lines[name])
            if T > 0 and EA > 0:
                dts.append(TOW_STRETCH_STEP * math.sqrt(T / EA) / max(rates))
    for m in _motions(scene):
        if m.kind == "table":
            tk = np.array([r[0] for r in m.samples])
            if tk.size > 1:
                dts.append(float(np.min(np.diff(tk))))
        elif m.kind == "tow":
            dts += [TOW_KINK_STEP * radius / m.speed for _, radius, _ in m.turns]
        elif m.kind != "rao":  # (a vessel's response to the waves: the waves' period)
            dts.append(m.period / STEPS_PER_PERIOD)
    if wave_period(scene) is not None:
        dts.append(wave_period(scene) / STEPS_PER_PERIOD)
    return min(dts)


def _start_tensions(scene: Scene, eq) -> dict:
    """{line name ("" for a one-line scene): its largest axial force at the start, N}."""
    names = [""] if scene.version == 1 else [ln.name for ln in scene.lines]
    out = {}
    for n in names:
        force = eq.outputs.get(f"{n}.axial_force" if n else "axial_force")
        if force is not None:
            out[n] = float(np.max(np.asarray(force, float)))
    return out


def _line_parts(mech) -> list:
    """The names of the mechanism's line parts, in order."""
    return [n for n, part in mech.layout.parts.items() if part.kind == "line"]


def _prefixes(scene: Scene, lines) -> dict:
    """Each line's output prefix: none in a one-line scene, ``"NAME."`` in version 2."""
    return {n: ("" if scene.version == 1 else f"{n}.") for n in lines}


def _one_line(scene: Scene, what: str) -> None:
    """A SymcableError for a scene of several lines and points (version 2), which ``what``
    does not run yet."""
    if scene.version == 2:
        raise SymcableError(f"scene {scene.name!r} has several lines and points (version 2): "
                            f"{what} runs one-line cable3d scenes for now (solve_static solves "
                            "it; symcable.integrate(symcable.cable3d_mechanism(scene), ...) "
                            "steps it)")


def newton_tolerance(scene: Scene, mech) -> float:
    """The default Newton tolerance of a cable3d run's steps: NEWTON_TOL, or less on a
    stiff line: STEP_FORCE_TOL F / (q k), F the force scale (N), q the largest position scale
    (m) and k the largest EA / ds of the scene's segments (N/m), so that a step's accepted
    position error moves a segment's tension by at most about STEP_FORCE_TOL F."""
    sections = scene.sections if scene.version == 1 else [s for ln in scene.lines
                                                          for s in ln.sections]
    k = max((s.line_type.EA * s.segments / s.length for s in sections if s.length), default=0.0)
    q = float(np.max(mech.scales.q)) if np.size(mech.scales.q) else 0.0
    if k <= 0.0 or q <= 0.0:
        return NEWTON_TOL
    return max(NEWTON_TOL_FLOOR,
               min(NEWTON_TOL, STEP_FORCE_TOL * float(mech.scales.force) / (q * k)))


def wave_period(scene: Scene) -> float | None:
    """The shortest period of the scene's waves, s (None in a calm sea)."""
    waves = scene.environment.waves
    if waves is None:
        return None
    if waves.kind == "regular":
        return float(waves.period)
    if waves.kind == "components":
        return 2.0 * math.pi / max(waves.omegas)
    return 2.0 * math.pi / (waves.band[1] if waves.band else default_band(waves.tp)[1])


def _period(scene: Scene):
    per = [m.period for m in _motions(scene) if m.kind == "harmonic"]
    if wave_period(scene) is not None:
        per.append(wave_period(scene))
    return min(per) if per else None


def motion_kinks(scene: Scene) -> tuple:
    """The times (s) at which a prescribed motion's acceleration jumps: where a tow enters and
    leaves each turn (its path is C1, :mod:`symcable.models.common.tow`: the acceleration
    jumps to U^2 / R and back)."""
    out = []
    for m in _motions(scene):
        if m.kind != "tow":
            continue
        t = float(m.start)
        for after, radius, angle in m.turns:
            t += float(after)
            out.append(t)
            t += float(radius) * abs(math.radians(float(angle))) / float(m.speed)
            out.append(t)
    return tuple(sorted(out))


def tension_error_estimate(time, series, h: float, tau: float, constant: float,
                           floor: float = 0.0, kinks=()) -> float:
    """The time-stepping error of a sampled series (an end tension) relative to its range,
    by generalized-alpha's local error C h^3 |f'''| per step (``constant`` C, step ``h`` s)
    summed with a memory of ``tau`` s (one radian of the excitation), as
    :class:`~symcable.solvers.march.RunningEstimate` does on the state; the third derivative
    from the samples (``time`` s). The state's own estimate measures positions against their
    range, and a tension is EA times a small difference of positions: on a taut line the
    tension's error was 25 times the positions' (each relative to its range). Times
    TENSION_ESTIMATE_FACTOR, except within KINK_REACH samples of ``kinks`` (s, where the
    prescribed motion's acceleration jumps, :func:`motion_kinks`): across a kink the third
    derivative of the samples is the jump over the sample spacing, not a smooth
    derivative, and the raw estimate there is already about the true error. The range is
    at least ``floor`` (N): a steady tension (a steady tow, a free end's zero) has no range,
    and its round-off is no motion."""
    t, f = np.asarray(time, float), np.asarray(series, float)
    rng = max(float(np.ptp(f)), floor) if f.size else 0.0
    if t.size < 5 or not rng > 0:
        return 0.0
    f3 = np.gradient(np.gradient(np.gradient(f, t), t), t)
    H = np.diff(t)
    d = constant * h * h * 0.5 * (np.abs(f3[1:]) + np.abs(f3[:-1])) * H
    factor = np.full(d.size, TENSION_ESTIMATE_FACTOR)
    for tk in kinks:
        if t[0] < tk < t[-1]:
            # interval i takes the third derivative at samples i and i + 1, each made of
            # the samples KINK_REACH either way: those from j - 3 to j + 3 reach across
            j = int(np.searchsorted(t, tk)) - 1  # t[j] < tk <= t[j + 1]
            factor[max(0, j - KINK_REACH):j + KINK_REACH + 1] = 1.0
    E = leaky_sum(0.0, factor * d, float(np.mean(H)) / tau)
    return float(np.max(E)) / rng


def _with_tension_estimate(stats: dict, warnings, tr, ends, opts, period, label,
                           kinks=()) -> tuple:
    """The run's error estimate as the larger of the state's and the end tensions' (see
    :func:`tension_error_estimate`; ``kinks``: :func:`motion_kinks`), and its warning. The
    state's only when the state moves (its range at least MOTION_FLOOR of its scales): a
    line at rest still jitters by its Newton tolerance and the settling of its start, and
    the estimate of that jitter (relative to the floor) grows as the step shrinks, noise
    over noise (seed000_hybrid at rest: 1.1 % of the floor at dt = 0.005 s, against 0.06 %
    at 0.05 s); its outputs' error is the end tensions', measured against at least
    TENSION_RANGE_FLOOR of the largest tension."""
    if stats.get("error_estimate") is None or not hasattr(opts, "error_constant"):
        return stats, warnings
    h = stats["dt"]
    tau = stats.get("error_memory") or (tr.time[-1] - tr.time[0]) / (2 * math.pi)
    series = [np.linalg.norm(f, axis=1) for f in ends]
    floor = TENSION_RANGE_FLOOR * max(float(np.max(f)) if f.size else 0.0 for f in series)
    est = max(tension_error_estimate(tr.time, f, h, tau, opts.error_constant, floor, kinks)
              for f in series)
    stats = dict(stats, error_estimate_states=stats["error_estimate"], tension_error_estimate=est)
    moves = (stats.get("motion_range") or 0.0) >= MOTION_FLOOR
    stats["error_estimate"] = max(est, stats["error_estimate"] if moves else 0.0)
    stats["dt_accurate"] = accurate_dt(h, stats["error_estimate"])
    warnings = [w for w in warnings if "time step is too coarse" not in w]
    if stats["error_estimate"] > ERROR_TARGET:
        warnings.insert(0, error_warning(label, stats, "the end tensions and the motion", period))
    return stats, warnings


def _line_result(scene, mech, tr, method: str, dt: float, stats: dict, warnings,
                 opts=None, period=None):
    """The run as a LineTrajectory (one line) or a SystemTrajectory (scene version 2), its
    error estimate extended to the end tensions when ``opts`` (the stepping method) is given."""
    t = np.asarray(tr.time, float)
    warnings = list(warnings)
    lines = _line_parts(mech)
    prefix = _prefixes(scene, lines)
    if opts is not None:
        ends = [np.asarray(tr.outputs[prefix[n] + k], float).reshape(t.size, 3)
                for n in lines for k in ("end_force_a", "end_force_b")]
        stats, warnings = _with_tension_estimate(dict(stats), warnings, tr, ends, opts, period,
                                                 method, motion_kinks(scene))
    common = dict(method=method, dt=float(dt), status=tr.status, stats=stats)
    if scene.version == 1 and has_twists(scene):
        return rod_line(scene, mech, t, tr.outputs, warnings, common)
    if scene.version == 1:
        return line_from_outputs(scene.name, t, tr.outputs, mech.layout.parts["line"].s,
                                 warnings=warnings, **common)
    out = SystemTrajectory(scene.name, t, {k: np.asarray(v, float) for k, v in tr.outputs.items()},
                           tuple(lines), tuple(scene.points),
                           {n: np.asarray(mech.layout.parts[n].s, float) for n in lines},
                           warnings=tuple(warnings), body_names=tuple(scene.bodies),
                           **common)
    notes = [f"line {n}: {w}" for n, ln in out.lines.items() for w in ln.warnings]
    return dataclasses.replace(out, warnings=out.warnings + tuple(notes)) if notes else out


#: the warning of a run of a scene that nothing moves
STILL = ("the scene has no motion (no end, point or body moves): the run stays at its "
         "static state; give one a motion ([end_b.motion], [points.NAME.motion]) to run it")


def simulate_3d(scene: Scene, duration: float, dt: float | None = None,
                method: str = "generalized-alpha", *, rho_inf: float | None = None,
                save_every: int | None = None, save_times=None, progress: bool | None = None,
                newton_tol: float | None = None, codegen: bool | None = None,
                t_start: float | None = None, start: str | None = None,
                tol: float | None = None) -> LineTrajectory | SystemTrajectory:
    """Time response of a cable3d line from its static state (see :func:`symcable.simulate`).

    The run starts at ``t_start`` s (default :func:`run_start`: a motion table's first row
    when before 0, else 0) and lasts ``duration`` s; ``dt`` default :func:`default_dt`.
    ``start``: ``"steady"`` (the default when the scene tows: the steady tow, the static
    solution in the frame moving with the towpoints, everything moving with them), or
    ``"rest"`` (:func:`~symcable.api.cable3d_static.run_start_state`); ``stats["start"]`` says
    which was used (``"steady tow"`` or ``"rest"``), ``stats["tow_velocity"]`` the tow's
    velocity at the start (m/s).
    ``rho_inf`` (default :data:`RHO_INF` = 0) is generalized-alpha's numerical damping: the
    high-frequency axial waves a snap releases need it (with little damping, rho_inf near 1,
    a snap's peak can come out many times the converged one).
    ``tol`` (generalized-alpha, not with ``dt``): the step chosen for the end tensions' error
    relative to their range over the run, or at ``save_times`` when given
    (:func:`~symcable.api.time_tolerance.run_to_tolerance`);
    default :data:`~symcable.api.time_tolerance.DEFAULT_TOL` when neither ``dt`` nor
    ``save_times`` is given. Returns a :class:`LineTrajectory` (a scene of several lines and
    points: a :class:`SystemTrajectory`, ``.lines[name]`` each line's); a failed step raises
    ConvergenceError whose ``partial`` is one too.
    """
    started = time.perf_counter()
    name = str(getattr(method, "value", method)).strip().lower().replace("_", "-")
    if name not in ("generalized-alpha", "rk4"):
        raise SymcableError(f"method = {method!r}: must be 'generalized-alpha' or 'rk4'")
    rho_inf = RHO_INF if rho_inf is None else rho_inf
    if not (isinstance(rho_inf, (int, float)) and 0.0 <= rho_inf <= 1.0):
        raise SymcableError(f"rho_inf = {rho_inf!r}: must be a number in [0, 1]")
    tol = step_tolerance(tol, dt, save_times, name)
    # before the static solve: a bad duration or step is refused at once (check_steps)
    duration, dt = check_steps(duration, dt, _period(scene))
    if name == "rk4":
        opts = RK4()
    else:
        opts = GeneralizedAlphaFirstOrder(rho_inf=float(rho_inf), tol=NEWTON_TOL)
        if newton_tol is not None:
            opts = dataclasses.replace(opts, tol=float(newton_tol))
    t0 = run_start(scene) if t_start is None else float(t_start)
    mech, eq, v0, how, notes = start_state(scene, t0, start, codegen)
    if name != "rk4" and newton_tol is None:
        opts = dataclasses.replace(opts, tol=newton_tolerance(scene, mech))
    if all(m is None for _, m in held_motions(scene)) and scene.environment.waves is None:
        notes = list(notes) + [STILL]
    check_moves(scene, mech)
    t_static = time.perf_counter() - started
    if name == "rk4":  # its stable step (cached for integrate), or one line saying why not
        check_rk4_limit(scene, mech, t0, eq.q, v0)
    if dt is None and name != "rk4":
        dt = min(default_dt(scene, duration, _start_tensions(scene, eq)), duration)
    kw = dict(method=opts, t0=t0, start=eq, v0=v0, p=mech.params.values, save_every=save_every,
              save_times=save_times, progress=progress, codegen=codegen, label=name,
              period=_period(scene),
              reanchor=reanchor_hook(mech) if has_twists(scene) else None)

    def run(h, every, times):
        if h is not None:
            h = check_steps(duration, h, _period(scene))[1]
        try:
            tr = integrate(mech, duration, dt if h is None else h,
                           **dict(kw, save_every=every, save_times=times))
        except ConvergenceError as exc:
            part = exc.partial
            if part is not None and len(part.time):
                part = _line_result(scene, mech, part, name, part.stats.get("dt", h or 0.0),
                                    dict(part.stats), part.warnings)
            raise ConvergenceError(str(exc), partial=part, diagnostics=exc.diagnostics) from None
        stats = dict(tr.stats, static_time=t_static, rho_inf=float(rho_inf) if name != "rk4"
                     else None, **how)
        return _line_result(scene, mech, tr, name, tr.stats["dt"], stats,
                            tuple(notes) + tuple(tr.warnings), opts, _period(scene))

    out = run(None, save_every, save_times) if tol is None else \
        tolerance_runs(run, tol, name, save_every, save_times, t0)
    return dataclasses.replace(out, stats=dict(out.stats,
                                               wall_time=time.perf_counter() - started))


def modal_analysis_3d(scene: Scene, n_modes: int = 10, *, max_dense: int = MAX_DENSE,
                      damped: bool = False) -> ModalSolution:
    """The lowest natural modes of a cable3d line about its static state (see
    :func:`symcable.modal_analysis`): the symmetric problem K phi = omega^2 M phi in the node
    positions, K the exact tangent stiffness (tension's geometric stiffness included), M the
    lumped mass with added mass. ``shapes`` (n_modes, n, 3): node displacements (x, y, z),
    zero at held ends, scaled to a largest node displacement of 1. ``damped=True`` adds the
    damping ratios of the complex modes in ``stats["damping_ratios"]``. A scene of several
    lines: the lines' nodes stacked in scene order (a shared node once per line), with
    ``stats["lines"]`` giving each line's [start, stop) rows."""
    started = time.perf_counter()
    if isinstance(n_modes, bool) or int(n_modes) != n_modes or n_modes < 1:
        raise SymcableError(f"n_modes = {n_modes!r}: must be an integer >= 1")
    mech, eq = scene_equilibrium(scene)
    mech = dynamics_mechanism(scene, mech)
    check_moves(scene, mech)
    t_static = time.perf_counter() - started
    eq = dataclasses.replace(eq, p=dynamic_p(scene, mech, eq.p))
    modes = mechanism_modes(mech, eq, int(n_modes), damped=damped, max_dense=max_dense)
    lines = _line_parts(mech)
    shapes = np.stack([node_shapes(scene, mech, eq, lines, u)
                       for u in np.asarray(modes.velocity_shapes, float).reshape(-1, mech.n_v)])
    freq = np.asarray(modes.frequencies, float)
    st = dict(modes.stats)
    stats = {"n_y": st.get("state_size"), "method": f"dense {st.get('method')}",
             "zero_modes": st.get("zero_eigenvalues"), "zero_tolerance": st.get("zero_tolerance"),
             "max_relative_real_part": st.get("max_relative_real_part"), "model_time": t_static,
             "jacobian_time": st.get("linearize_time"), "eig_time": st.get("eig_time"),
             "wall_time": time.perf_counter() - started}
    tws = twist_shapes(mech, modes.velocity_shapes) if has_twists(scene) else None
    if tws is not None:  # each mode's twist angles (rad per unit largest node displacement)
        stats["twist_shapes"] = tws.tolist()
    if damped and modes.damping_ratios is not None:
        stats["damping_ratios"] = np.asarray(modes.damping_ratios, float).tolist()
    pre = _prefixes(scene, lines)
    if scene.version == 2:  # where each line's nodes sit in the stacked arrays
        sizes = np.cumsum([0] + [len(mech.layout.parts[n].s) for n in lines])
        stats["lines"] = {n: [int(a), int(b)] for n, a, b in zip(lines, sizes[:-1], sizes[1:])}
    return ModalSolution(
        scene_name=scene.name,
        s=np.concatenate([np.asarray(mech.layout.parts[n].s, float) for n in lines]),
        positions=np.vstack([np.asarray(eq.outputs[pre[n] + "positions"], float).reshape(-1, 3)
                             for n in lines]), frequencies=freq,
        periods=1.0 / freq, real_parts=np.asarray(modes.real_parts if modes.real_parts is not None
                                                  else np.zeros_like(freq), float),
        shapes=shapes, status="converged", stats=stats,
        warnings=tuple(modes.warnings) + ((AT_REST,) if tows(scene) else ()))


def end_stiffness_3d(scene: Scene, end: str = "b", *, equilibrium=None) -> np.ndarray:
    """(3, 3) N/m: K = -dF/dx of the force the line exerts on pinned end ``end`` against that
    end's position, the line in static equilibrium; exact (implicit function theorem on the
    static residual's CasADi derivatives)."""
    mech, eq = scene_equilibrium(scene) if equilibrium is None else equilibrium
    return -output_sensitivity(mech, eq, f"end_force_{end}", f"end_{end}.position")


def linearize_3d(scene: Scene, *, undamped: bool = False) -> SceneLinearization:
    """K, C, M, G, H of a cable3d line about its static state (see :func:`symcable.linearize`):
    q and v are the positions and velocities of the moving nodes (``q_kinds`` names each,
    e.g. ``"node3.y"``); K includes the geometric stiffness of the static tension; C the
    material damping and the drag linearised about the current (none with ``undamped``,
    which also switches the current off); and the exact (3, 3) stiffness of each pinned
    end (a scene of several lines: of each fixed or vessel point, by name, every line
    attached to it moved with it; q named ``"line.node3.y"``, a free point's ``"buoy.x"``),
    and the (6, 6) mooring stiffness of each free body (``body_stiffness``, global axes:
    :func:`~symcable.api.cable3d_static.body_stiffness`; its q named ``"tow.x"``, ``"tow.e1"``,
    its v ``"tow.rx"`` ...). A free body's statics-only spring is off (K of the lines and
    bodies alone)."""
    mech0, eq = scene_equilibrium(scene)
    mech = dynamics_mechanism(scene, mech0)
    p = dynamic_p(scene, mech, eq.p)
    if undamped:
        for block in mech.params.names:
            if block.split(".")[-1] == "current":
                p[mech.params.slice(block)] = 0.0
    F = functions(mech)
    z0 = np.zeros(0)
    q0, v0 = np.asarray(eq.q, float), np.zeros(mech.n_v)
    K, C, M, *_ = (np.asarray(a) for a in F.tangents(q0, v0, z0, 0.0, p))
    H, G = (np.asarray(a) for a in F.kinematics_jacobian(q0, v0, z0, 0.0, p))
    if undamped:
        C = np.zeros_like(C)
    q_kinds, v_kinds = mech.coordinate_names(tagged=scene.version == 2)
    if has_twists(scene):  # the twists: "edge{j}.twist"
        q_kinds, v_kinds = (twist_names(k, mech) for k in (q_kinds, v_kinds))
    ends = {}
    if scene.version == 1:
        for end in ("a", "b"):
            if getattr(scene, f"end_{end}").condition is EndCondition.PINNED:
                ends[end] = end_stiffness_3d(scene, end, equilibrium=(mech0, eq))
    else:  # each held point: -d(lines' force on it)/d(its position), every attached end
        for pname, pt in scene.points.items():
            if pt.is_free:
                continue
            K_pt = np.zeros((3, 3))
            for ln in scene.lines:
                for end in ("a", "b"):
                    if getattr(ln, f"end_{end}") == pname:
                        K_pt -= output_sensitivity(mech, eq, f"{pname}.force",
                                                   f"{ln.name}.end_{end}.position")
            ends[pname] = K_pt
    bodies = {name: body_stiffness(scene, mech, eq, name, p)
              for name, b in scene.bodies.items() if b.is_free}
    return SceneLinearization(scene.name, K, C, M, G, H, q_kinds, v_kinds, ends, undamped,
                              bodies)
