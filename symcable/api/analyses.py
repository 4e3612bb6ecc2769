"""The orchestration layer: scene -> model -> static solution -> dynamics.

Below this module each layer knows only the ones under it: formulations turn a scene into
a model (:mod:`symcable.models`) and never call a solver; solvers solve a model they are
given (:mod:`symcable.solvers`). What starts from a scene and needs a solver on the way
lives here: the dynamic model, which is linearised about the static solution, and the
analyses of a scene's dynamics, which build that model first. The package exports these
functions (``sc.simulate(scene, ...)``); their options are those of the solvers they call.
"""
from __future__ import annotations

import dataclasses
import math
import time
import warnings as _warnings
from collections import OrderedDict
from typing import Mapping, Sequence

import numpy as np

from ..models import DynamicModel, cache_dynamic_model, cached_dynamic_model, linearised_model
from ..results.periodic import PeriodicSolution, PeriodicSweep
from ..results.trajectory import Trajectory
from ..scene import Scene, load_scene
from ..results.static import ModalSolution
from ..errors import ModelNote, SymcableError
from ..models import build_model, formulation_of
from ..mechanism.mechanism import Start
from ..models.planar.static import static_mechanism
from ..solvers.equilibrium import solve_equilibrium
from ..solvers.linearize import MAX_DENSE, mechanism_modes, output_sensitivity
from ..solvers.integrate import check_steps
from ..mechanism.functions import functions as _functions
from ..models.planar.mechanism import dynamics_mechanism, mechanism_of, state_permutation
from . import planar_time as _planar_time
from .planar_periodic import method_options, solve_model, sweep_model
from .periodic_error import with_time_error
from ..limits import call_deadline
from ..results.generic import Equilibrium, SceneLinearization
from .planar_static import solve_static
from . import cable3d as _c3
from .time_tolerance import step_tolerance, tolerance_runs
from .builders import build_dynamic_model, build_mechanism
from . import cable3d_periodic as _c3p

__all__ = ["build_dynamic_model", "build_mechanism", "dynamics_scene", "modal_analysis", "runs_on_mechanism",
           "simulate", "solve_periodic", "sweep_periodic"]


def dynamics_scene(scene) -> Scene:
    """The scene whose dynamics the analyses of ``scene`` run: ``scene`` itself, or the
    stand-in of a linearised formulation that cannot represent them
    (:attr:`~symcable.models.Formulation.stand_in`: the planar line resting on the seabed
    as the 3D cable in its plane). Solves the static state of a linearised scene once (its
    dynamic model is then built and cached for the analyses)."""
    scene = load_scene(scene)
    form = formulation_of(scene)
    if not form.linearised or form.stand_in is None or cached_dynamic_model(scene) is not None:
        return scene
    key = repr(scene.to_dict())
    if key not in _STAND_INS:
        static = solve_static(scene, estimate=False)
        stand_in = form.stand_in(scene, static)
        if stand_in is None:  # the linearised path takes it: its model built once, here
            cache_dynamic_model(scene, linearised_model(scene, static))
            return scene
        _STAND_INS[key] = stand_in
        if len(_STAND_INS) > 16:
            _STAND_INS.popitem(last=False)
    return _STAND_INS[key]


def runs_on_mechanism(scene) -> bool:
    """Whether the dynamic analyses of ``scene`` run on its Mechanism (or its stand-in's)
    rather than on a linearised model: their results are then the Mechanism path's
    (:mod:`symcable.api.cable3d`), and their options (``start``, ``stability``) apply."""
    return not formulation_of(dynamics_scene(scene)).linearised


_STAND_INS: "OrderedDict[str, Scene]" = OrderedDict()


def _nonlinear(scene, **linearised_only):
    """The scene the Mechanism path runs (:mod:`symcable.api.cable3d`), or None when the
    scene takes the linearised path (:mod:`symcable.api.planar_time`,
    :mod:`symcable.api.planar_periodic`): :func:`dynamics_scene`, with a
    :class:`~symcable.errors.ModelNote` when that is a stand-in. An argument only the
    linearised path takes (``linearised_only``), given for a scene that runs on its
    Mechanism, is an error naming it; given for a linearised scene, it keeps the scene on
    its linearised path.
    """
    if scene is None:
        return None
    scene = load_scene(scene)
    given = {k: v for k, v in linearised_only.items() if v is not None}
    if formulation_of(scene).linearised:
        if given:
            return None
        run = dynamics_scene(scene)
        if run is scene:
            return None
        _warnings.warn(f"{scene.name}: the static line rests on the seabed, which the "
                       f"linearised {scene.model.value} dynamics do not model; its dynamics "
                       f"run as model = {run.model.value!r} in its plane (positions "
                       "[x, 0, z])", ModelNote, stacklevel=3)
        return run
    for key, value in given.items():
        raise SymcableError(f"{key} = <{type(value).__name__}>: not for a "
                            f"{scene.model.value} scene (its analyses build their own "
                            "Mechanism from the scene)")
    return scene


def simulate(scene, duration: float, dt: float | None = None, method: str = "generalized-alpha", *,
             rho_inf: float | None = None, save_every: int | None = None, save_times=None,
             progress: bool | None = None, model: DynamicModel | None = None, params=None,
             newton_tol: float | None = None, codegen: bool | None = None,
             start: str | None = None, tol: float | None = None) -> Trajectory:
    """Time response of a line from rest at t = 0 (where its excitation starts): its
    dynamics Mechanism (:func:`~symcable.models.planar.mechanism.mechanism_of`) marched by
    :func:`symcable.integrate`.

    Parameters
    ----------
    scene : Scene, dict or path
        Anything :func:`symcable.load_scene` takes; its dynamic model is built here
        (:func:`build_dynamic_model`, which solves the static state) unless ``model`` is
        given, and then ``scene`` may be None (its name is then the model's scene's).
    duration : float
        Simulated time, s.
    dt : float, optional
        A fixed time step, s, shortened when needed so that a whole number of steps fills
        ``duration`` (``stats['dt_requested']`` keeps the value asked for). Default:
        generalized-α the step chosen for ``tol``; RK4 0.8 times its stability limit
        (:func:`symcable.api.planar_time.rk4_stability_limit`), at most that same value.
    tol : float, optional
        Generalized-α: the error asked of the end tensions, relative to their range, in
        (0, 1); default 0.01 when neither ``dt`` nor ``save_times`` is given. Runs from the
        default step (``period / 100``, a table's or a tow's own) are compared at twice and
        half steps until two agree within ``tol`` (:mod:`symcable.api.time_tolerance`); the
        finer is returned, ``stats["error_measured"]`` its bound (None, with a warning,
        when not reached), ``stats["dt_runs"]`` each run's step (s) and difference. With
        ``save_times``, the error at those times only. Not with ``dt`` or RK4.
    method : {"generalized-alpha", "rk4"}
        Implicit generalized-α (first order on the DAE residual, Jansen, Whiting & Hulbert
        2000: second order, A-stable, numerical damping set by ``rho_inf``) or explicit
        classical RK4 (fourth order, stable only below its limit).
    rho_inf : float, optional
        Generalized-α spectral radius at infinite step, in [0, 1]; default 0.5 for the planar
        line, 0 for cable3d (:data:`symcable.api.cable3d.RHO_INF`: a stiff line's axial modes
        are far above the step and are best removed).
    save_every : int, optional
        Save every this many steps (and the last step). Default: every step when there are
        fewer than 2000 steps, else about 2000 evenly spaced samples.
    save_times : array_like, optional
        Times to save, s, each rounded to the nearest step (no interpolation); the run
        stops at the last of them.
    progress : bool, optional
        A progress bar on stderr: True always, False never, None only for a run that lasts
        over a second with stderr a terminal.
    model : DynamicModel, optional
        The model to integrate (:func:`build_dynamic_model`).
    params : array_like (n_p,), optional
        Parameter vector replacing ``model.p_value``, e.g. ``model.with_params(amp_b=[0, 0])``.
    newton_tol : float, optional
        Generalized-α Newton tolerance on the max-norm of the step residual times
        dt / y_scale (momentum rows over their masses), or of the last Newton correction of
        y_{n+1} over y_scale (default 1e-10; a cable3d scene:
        :func:`symcable.api.cable3d.newton_tolerance`, 1e-8 or less on a stiff line).
    codegen : bool, optional
        Run the step in generated C (compiled once per model structure and method, then
        loaded from the build cache); the loop over steps runs inside CasADi's ``mapaccum``,
        never in Python. Default None: generated C when a C compiler is found and the step
        is small enough for compiling to pay (see :mod:`symcable.mechanism.codegen`); True without a
        compiler warns once and uses the virtual machine. Results agree with the virtual
        machine's to round-off.
    start : {"steady", "rest"}, optional
        cable3d scenes: where the run starts. "steady" (the default for a scene whose held
        points all tow at one velocity, ``kind = "tow"``): the steady tow, the static
        solution in the frame moving with the towpoints, every node moving with them;
        "rest": the static state at rest (the default otherwise). The planar line starts
        from rest (None only).

    Returns
    -------
    Trajectory
        States in the DynamicModel's order. ``status`` "converged"; "invalid" with a
        warning when the total axial strain of a segment, or an end tension over its
        segment's EA, left the line type's ``max_strain`` (the dynamics linearised about the
        static state do not hold there: the numbers are not an answer); else "slack" with a
        warning when the total tension fell to zero somewhere (the linearised model is then
        invalid too).

    Raises
    ------
    SymcableError
        A bad argument (the message names it, its value and what is allowed).
    ConvergenceError
        A generalized-α step whose Newton iteration failed, or a state that blew up (RK4
        above its stability limit); ``partial`` is the Trajectory up to the last good step
        (status "failed"); ``diagnostics`` has ``reason`` ("newton", "blowup" or "error"),
        ``time`` (end of the failed step, s), ``time_last_good`` (s), ``step``, ``dt``,
        ``method``, and ``residual`` (max |R| dt / scale at the last Newton iterate) or
        ``state_norm`` (max |state| / scale reached) and ``worst`` (its entry of the
        Mechanism's q or v).
    """
    started = time.perf_counter()
    duration, dt = check_steps(duration, dt)  # at once, before any static solve
    s3 = _nonlinear(scene, model=model, params=params)
    if s3 is not None:
        return _c3.simulate_3d(s3, duration, dt, method,
                               rho_inf=_c3.RHO_INF if rho_inf is None else rho_inf,
                               save_every=save_every,
                               save_times=save_times, progress=progress, newton_tol=newton_tol,
                               codegen=codegen, start=start, tol=tol)
    if start is not None:
        raise SymcableError(f"start = {start!r}: the planar line's dynamics start from rest "
                            "(start applies to cable3d scenes)")
    tol = step_tolerance(tol, dt, save_times, _planar_time.Method.parse(method).value)
    if model is None and scene is not None:
        scene = load_scene(scene)
        model = build_dynamic_model(scene)

    def run(h, every, times):
        return _planar_time.simulate(scene, duration, h if h is not None else dt, method,
                                     rho_inf=0.5 if rho_inf is None else rho_inf,
                                     save_every=every, save_times=times, progress=progress,
                                     model=model, params=params, newton_tol=newton_tol,
                                     codegen=codegen, started=started)
    if tol is None:
        return run(None, save_every, save_times)
    out = tolerance_runs(run, tol, _planar_time.Method.parse(method).value, save_every,
                         save_times)
    return dataclasses.replace(out, stats=dict(out.stats,
                                               wall_time=time.perf_counter() - started))


def solve_periodic(scene, method="shooting", *, model: DynamicModel | None = None,
                   params: np.ndarray | None = None, initial: PeriodicSolution | None = None,
                   resolution: int = 200, tol: float | None = None, codegen: bool | None = None,
                   ipopt_options: Mapping | None = None, estimate: bool = True,
                   **options) -> PeriodicSolution:
    """Periodic steady state of a scene's dynamics over one period of its excitation, with
    the error of its time discretisation.

    The scene's dynamics Mechanism (:func:`~symcable.models.planar.mechanism.mechanism_of`)
    is solved by the generic periodic solvers
    (:func:`~symcable.solvers.periodic_mech.solve_periodic_mech`) at the periodic parameters
    (no start-up ramp); the glue is :mod:`symcable.api.planar_periodic`.

    Parameters
    ----------
    scene : Scene, dict or path
        Anything :func:`symcable.load_scene` takes; it must prescribe a motion. Its dynamic
        model is built here (:func:`build_dynamic_model`) unless ``model`` is given.
    method : {"shooting", "collocation", "harmonic-balance"} or an options object
        Shooting (default): the fixed point of the first-order generalized-alpha period map
        (the scheme of ``simulate``), Anderson-accelerated, with Newton on the exact monodromy
        as fallback; its answer carries the integrator's error at ``steps`` (about 1e-3 of
        the tension range at the default 100 on the built-in seed001 scene), and it is the
        fastest to that accuracy (the work-precision study in the docs). Collocation (Radau IIA, the most
        accurate), harmonic balance. Or :class:`~symcable.solvers.options.Collocation`,
        :class:`~symcable.solvers.options.HarmonicBalance`,
        :class:`~symcable.solvers.options.Shooting` with its options.
    **options
        The method's own options, validated by its options class: collocation
        ``intervals`` (40), ``degree`` (3), ``scheme`` ("radau" or "legendre"), ``solver``
        ("ipopt" or "newton"); harmonic balance ``harmonics`` (10), ``samples``
        (4 harmonics + 4); shooting ``steps`` per period (100, >= 8), ``rho_inf`` (0.5;
        cable3d scenes: 0, simulate's), ``newton_tol`` (each step's scaled Newton
        tolerance: 1e-10; cable3d scenes: 1e-8, simulate's). cable3d scenes also take
        ``stability=True``: the solution's Floquet multipliers in ``stats`` (``floquet_max``, ``stable``,
        :mod:`symcable.solvers.floquet`). An option of another method is an error naming
        it.
    model : DynamicModel, optional
    params : ndarray (n_p,), optional
        Model parameters (default ``model.p_periodic``: ``p_value`` without the ramp).
    initial : PeriodicSolution, optional
        Start from this solution (its states in normalised time t/T; a shooting solution of
        the same steps, its integrator state exactly) instead of the method's own start (the
        last of 6 periods of generalized-alpha from rest).
    resolution : int
        Output times per period (>= 8).
    tol : float, optional
        The scaled residual the method's system is solved to (default
        :data:`symcable.api.planar_periodic.DEFAULT_TOL`: 1e-10 for collocation and harmonic
        balance, 1e-7 for shooting, the change of its scaled state over one period).
    codegen : bool, optional
        Collocation and harmonic balance: the system's residual and Jacobian in generated C
        (compiled once per model structure and discretisation, cached; the period and every
        parameter stay inputs). Default None: generated C when a C compiler is found
        (:mod:`symcable.mechanism.codegen`). Shooting runs in the virtual machine (its
        generalized-alpha step is a CasADi rootfinder, which CasADi cannot write C for).
    ipopt_options : dict, optional
        Collocation with IPOPT: IPOPT options by their IPOPT names, over the defaults.
    estimate : bool
        Estimate the error of the time discretisation (:mod:`symcable.api.periodic_error`:
        shooting solved again at twice the steps, about twice the cost again; collocation
        and harmonic balance at half the intervals or harmonics, about half the cost
        again). False skips it.

    Returns
    -------
    PeriodicSolution
        ``status`` "converged", "slack" (a tension reached zero) or "invalid" (the strain
        left the line type's range); ``stats`` as documented there, with ``error_estimate``
        (the generic solvers' independent defect check) and ``time_discretisation_error``
        (the largest error of a line end's tension extremes, N and relative to its tension
        range; above 1 % a warning names the resolution that would meet it).

    Raises
    ------
    SceneError
        The scene prescribes no motion.
    SymcableError
        A bad method or option (one line naming it and what is allowed).
    ConvergenceError
        The solver did not converge, or its answer failed the defect check; ``partial`` is
        a PeriodicSolution with status "failed", ``diagnostics`` the solver's status.
    """
    with call_deadline():  # one deadline, limits.solve_seconds, for the whole call
        started = time.perf_counter()
        s3 = _nonlinear(scene, model=model, params=params, initial=initial,
                        ipopt_options=ipopt_options)
        state = None
        if s3 is not None:
            kw = {k: v for k, v in options.items() if k != "stability"}
            res, state = _c3p.solve_periodic_3d_state(s3, method, codegen,
                                                      options.get("stability", False), None,
                                                      dict(kw, tol=tol))
        else:
            if model is None:
                scene = load_scene(scene)
                model = build_dynamic_model(scene)
            res = solve_model(scene, model, method, params=params, initial=initial,
                              resolution=resolution, tol=tol, ipopt_options=ipopt_options,
                              codegen=codegen, options=options, started=started)
        if not estimate:
            return res
        others = {k: options[k] for k in _NOT_METHOD if k in options}
        _, opts = method_options(method, {k: v for k, v in options.items() if k not in others})
        others.pop("stability", None)
        again = dict(model=model, params=params, resolution=resolution, tol=tol, codegen=codegen,
                     ipopt_options=ipopt_options, estimate=False, **others)
        if state is not None:  # from the cycle just found: a few iterations, not a new start
            return with_time_error(res, opts, lambda o: _c3p.solve_periodic_3d_state(
                s3, o, codegen, False, state, {"tol": tol})[0])
        return with_time_error(res, opts, lambda o: solve_periodic(s3 or scene, o, **again))


#: solve_periodic's keyword options that are not the method's own
_NOT_METHOD = ("stability", "start")


def sweep_periodic(scene, periods: Sequence[float], method="shooting", *,
                   model: DynamicModel | None = None, resolution: int = 200,
                   tol: float | None = None, codegen: bool | None = None,
                   ipopt_options: Mapping | None = None, **options) -> PeriodicSweep:
    """Fairlead tension response over excitation periods (a tension RAO), by continuation.

    Each period sets the ``omega`` block of the periodic parameters to 2 pi / T (one set of
    CasADi functions serves the sweep) and starts from the previous period's solution,
    falling back to the method's own start if that fails; the model is built once for the
    whole sweep. A cable3d scene: each period solved from its own start.

    Parameters
    ----------
    scene : Scene, dict or path
        As in :func:`solve_periodic`; it must prescribe a motion.
    periods : sequence of float
        Excitation periods, s (a non-empty list of finite values > 0), solved in order.
    method : str or options object
        As in :func:`solve_periodic` (and the same default, ``"shooting"``).
    model, resolution, tol, codegen, ipopt_options
        As in :func:`solve_periodic` (``resolution``: output times per period, default 200).
    **options
        The method's options, as in :func:`solve_periodic`. With several lines and points,
        ``line="NAME"`` picks the line whose tension at its moving end is swept (default:
        the first line ending at a moving point; ``stats["swept"]`` says which).

    Returns
    -------
    PeriodicSweep
        Per period (n_p,): tension amplitude, phase (rad), mean, max, min (N), and the
        tension over each period (n_p, resolution). A failed period has NaN results and
        status "failed" (and a warning); ``stats["start"]`` says per period "neighbour" or
        "own start".

    Raises
    ------
    SymcableError
        Bad periods, method or option (the message names it).
    ConvergenceError
        When every period fails.
    """
    started = time.perf_counter()
    s3 = _nonlinear(scene, model=model, ipopt_options=ipopt_options)
    if s3 is not None:
        return _c3p.sweep_periodic_3d(s3, periods, method, resolution=resolution, codegen=codegen,
                                     tol=tol, **options)
    if model is None:
        scene = load_scene(scene)
        model = build_dynamic_model(scene)
    return sweep_model(scene, model, periods, method, resolution=resolution, tol=tol,
                       ipopt_options=ipopt_options, codegen=codegen, options=options,
                       started=started)


def modal_analysis(scene, n_modes: int = 10, *, model: DynamicModel | None = None,
                   max_dense: int = MAX_DENSE, codegen: bool | None = None) -> ModalSolution:
    """The lowest undamped natural frequencies and mode shapes of a line about its static
    state.

    The line's dynamics Mechanism (:func:`symcable.models.planar.mechanism.mechanism_of`) is
    linearised at rest with its undamped parameters (``model.p_undamped``: the static state
    kept, current included; excitation, current and the closure stabilisation off) and its
    modes solved by :func:`symcable.solvers.linearize.mechanism_modes`: with no
    stabilisation the kinematics are ``q' = G v``, ``K G`` is symmetric, and the modes are
    the symmetric problem ``K G phi = omega^2 M phi`` in the node velocities (the node
    frames' tangential and normal displacements), one mode per frequency; the state
    matrix's zero eigenvalues (the closure of a line held at both ends) never enter.

    Why the drag is out: Morison drag ``|u| u`` has zero derivative at zero relative
    velocity, and with no current the water's velocity relative to the line at rest is zero,
    so C = 0 exactly (CasADi's derivative of ``|u|`` at 0 is ``sign(0) = 0``).

    Parameters
    ----------
    scene : Scene, dict, path or None
        Anything :func:`symcable.load_scene` takes; its static state is solved and its
        dynamic model built here unless ``model`` is given (then ``scene`` may be None).
    n_modes : int
        Number of modes (>= 1): the lowest, zero modes skipped. Fewer are returned, with a
        warning, when the model has fewer.
    model : DynamicModel, optional
        A dynamic model already built (:func:`build_dynamic_model`).
    max_dense : int
        Largest state size n_y = n_q + n_v solved (dense eigenproblem, O(n^3); the symmetric
        problem is of size n_v ~ n_y / 2: a few seconds at n_y = 3000, the default).
    codegen : bool, optional
        Accepted for uniformity with the other analyses and checked; the tangents are
        evaluated once, in CasADi's virtual machine (about a tenth of the time at 200
        segments, the rest is LAPACK's eigen-solve), so generated C would not pay for its
        compilation.

    Returns
    -------
    ModalSolution

    Raises
    ------
    SymcableError
        On ``n_modes < 1``, a bad ``codegen``, a model larger than ``max_dense``, or an
        unstable static state.
    """
    started = time.perf_counter()
    if isinstance(n_modes, bool) or int(n_modes) != n_modes or n_modes < 1:
        raise SymcableError(f"n_modes = {n_modes!r}: must be an integer >= 1")
    if codegen is not None and not isinstance(codegen, bool):
        raise SymcableError(f"codegen = {codegen!r}: must be True, False or None (automatic)")
    s3 = _nonlinear(scene, model=model)
    if s3 is not None:
        return _c3.modal_analysis_3d(s3, n_modes, max_dense=max_dense)
    if model is None:
        model = build_dynamic_model(load_scene(scene))
    t_model = time.perf_counter()
    mech = mechanism_of(model)
    p = np.array(model.p_undamped, dtype=float)
    rest = Equilibrium(mech.name, np.zeros(mech.n_q), np.zeros(0), p, {}, "converged",
                       {"start": "the static state (rest of the linearised dynamics)"})
    modes = mechanism_modes(mech, rest, int(n_modes), max_dense=max_dense)
    for w in modes.warnings:
        _warnings.warn(w, RuntimeWarning, stacklevel=2)

    # node displacements (x, z) from the displacements in the node frames
    _, iv = state_permutation(model)
    D = np.asarray(model.info["velocity_map"], dtype=float)[:, iv]
    n_nodes = D.shape[0] // 2
    disp = (modes.velocity_shapes @ D.T).reshape(-1, n_nodes, 2)
    shapes = np.array([_node_shape(d) for d in disp]).reshape(-1, n_nodes, 2)
    info, st = model.info, modes.stats
    static, sc = info.get("static"), info.get("scene")
    freq = np.asarray(modes.frequencies, dtype=float)
    return ModalSolution(
        scene_name=getattr(sc, "name", model.name),
        s=np.asarray(info.get("s_nodes", np.arange(n_nodes)), dtype=float),
        positions=(np.asarray(static.positions, dtype=float) if static is not None
                   else np.full((n_nodes, 2), np.nan)),
        frequencies=freq, periods=1.0 / freq, real_parts=np.asarray(modes.real_parts, float),
        shapes=shapes, status="converged",
        stats={"n_y": st["state_size"], "method": f"dense {st['method']}",
               "zero_modes": st["zero_eigenvalues"], "zero_tolerance": st["zero_tolerance"],
               "max_relative_real_part": st["max_relative_real_part"],
               "model_time": t_model - started, "jacobian_time": st["linearize_time"],
               "eig_time": st["eig_time"], "wall_time": time.perf_counter() - started},
        warnings=modes.warnings)


def _node_shape(disp: np.ndarray) -> np.ndarray:
    """A mode shape (n, 2) scaled to a largest node displacement ``hypot(x, z)`` of 1, its
    largest entry positive (zeros stay zeros)."""
    peak = disp.flat[int(np.argmax(np.abs(disp)))]
    if peak == 0:
        return np.zeros(disp.shape)
    out = disp * math.copysign(1.0, peak)
    return out / np.max(np.hypot(out[:, 0], out[:, 1]))


def end_stiffness(scene, end: str = "b", *, static=None) -> np.ndarray:
    """The stiffness a line presents at its end ``"a"`` or ``"b"``: K = -dF/dx, (dim, dim)
    N/m, with F the force the line exerts on that end and x the end's prescribed position,
    the rest of the line in equilibrium. Exact: CasADi's derivatives of the static residual
    and of the end force, by the implicit function theorem (no finite differences). The end
    must be pinned (have a prescribed position).

    Parameters
    ----------
    scene : Scene, dict or path
    end : ``"a"`` or ``"b"``
    static : StaticSolution, optional
        The static state of the same scene (solved here when not given).
    """
    if end not in ("a", "b"):
        raise SymcableError(f"end = {end!r}: must be 'a' or 'b'")
    scene = load_scene(scene)
    held = getattr(scene, f"end_{end}")
    if held is None:
        raise SymcableError(f"end = {end!r}: scene {scene.name!r} has several lines, points or "
                            "bodies and no end_a/end_b of its own: its stiffness at each fixed "
                            "or vessel point is sc.linearize(scene).end_stiffness[point name]")
    cond = held.condition
    if str(getattr(cond, "value", cond)) != "pinned":
        raise SymcableError(f"end_{end}.condition = {getattr(cond, 'value', cond)!r}: the end "
                            "stiffness is defined for a pinned end (a prescribed position)")
    if not formulation_of(scene).linearised:
        if static is not None:
            raise SymcableError("static = <StaticSolution>: not for a cable3d scene (its "
                                "equilibrium is solved here)")
        return _c3.end_stiffness_3d(scene, end)
    model = build_model(scene)
    mech = static_mechanism(model)
    st = solve_static(scene, model=model, estimate=False) if static is None else static
    p = mech.params.values
    eq = solve_equilibrium(mech, p, starts=[Start(st.unknowns, np.zeros(0), p, "static solution")])
    return -output_sensitivity(mech, eq, f"end_force_{end}", f"end_{end}.position")


def linearize(scene, *, undamped: bool = False, static=None) -> SceneLinearization:
    """The exact linearisation of a scene's dynamics about its static state: K, C, M and the
    kinematics G, H of its dynamics Mechanism (see :class:`SceneLinearization`), the
    exact end stiffness at each pinned end, and (cable3d scenes with free bodies) each
    body's 6 x 6 mooring stiffness, ``body_stiffness``. From CasADi's derivatives of the
    same expressions the solvers integrate (no finite differences).

    Parameters
    ----------
    scene : Scene, dict or path; it must have a moving end or none (its motion is switched off)
    undamped : bool
        Current, excitation and the closure stabilisation off, as ``modal_analysis`` has
        them (its frequencies are the undamped eigenvalues of the state matrix).
    static : StaticSolution, optional
    """
    s3 = _nonlinear(scene, static=static)
    if s3 is not None:
        return _c3.linearize_3d(s3, undamped=undamped)
    scene = load_scene(scene)
    model = build_model(scene)
    st = solve_static(scene, model=model, estimate=False) if static is None else static
    dyn = build_dynamic_model(scene, static=st)
    mech = dynamics_mechanism(dyn)
    # at rest: the periodic parameters (no start-up ramp) with the end motion off
    p = np.array(dyn.p_undamped if undamped else dyn.p_periodic, dtype=float)
    for block in ("amp_a", "amp_b"):
        p[dyn.p_slices[block]] = 0.0
    F = _functions(mech)
    q0, v0, z0 = np.zeros(mech.n_q), np.zeros(mech.n_v), np.zeros(0)
    K, C, M, *_ = (np.asarray(a) for a in F.tangents(q0, v0, z0, 0.0, p))
    H, G = (np.asarray(a) for a in F.kinematics_jacobian(q0, v0, z0, 0.0, p))
    kinds = dyn.info["kinds"]
    iq, iv = state_permutation(dyn)
    ends = {}
    for end in ("a", "b"):
        cond = getattr(scene, f"end_{end}").condition
        if str(getattr(cond, "value", cond)) == "pinned":
            ends[end] = end_stiffness(scene, end, static=st)
    return SceneLinearization(scene.name, K, C, M, G, H, tuple(kinds[int(k)] for k in iq),
                              tuple(kinds[int(k)] for k in iv), ends, undamped)
