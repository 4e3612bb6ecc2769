"""The orchestration layer: scene -> model -> static solution -> dynamics.

Below this module each layer knows only the ones under it: formulations turn a scene into
a model (:mod:`symcable.models`) and never call a solver; solvers solve a model they are
given (:mod:`symcable.solvers`). What starts from a scene and needs a solver on the way
lives here: the dynamic model, which is linearised about the static solution, and the
analyses of a scene's dynamics, which build that model first. The package exports these
functions (``sc.simulate(scene, ...)``); their options are those of the solvers they call.
"""
from __future__ import annotations

import time
from typing import Mapping, Sequence

import numpy as np

from .models import DynamicModel, cache_dynamic_model, cached_dynamic_model, linearised_model
from .results_periodic import PeriodicSolution, PeriodicSweep
from .results_time import Trajectory
from .scene import Scene, load_scene
from .solvers import modal as _modal
from .solvers import periodic as _periodic
from .solvers.modal import MAX_DENSE, ModalSolution
from .errors import SymcableError
from .models import build_model
from .models.mechanism import Start
from .models.static_mechanism import static_mechanism
from .solvers.equilibrium import solve_equilibrium
from .solvers.linearize import output_sensitivity
from .derive import functions as _functions
from .models.planar_mechanism import dynamics_mechanism, state_permutation
from . import planar_time as _planar_time
from .results_mechanism import SceneLinearization
from .solvers.static import solve_static

__all__ = ["build_dynamic_model", "modal_analysis", "simulate", "solve_periodic", "sweep_periodic"]


def build_dynamic_model(scene: Scene, static=None) -> DynamicModel:
    """The scene's dynamics linearised about its static solution (solved here when not
    given), as CasADi expressions. Cached like :func:`symcable.build_model` when ``static``
    is not given."""
    if static is not None:
        return linearised_model(scene, static)
    model = cached_dynamic_model(scene)
    if model is None:
        model = cache_dynamic_model(scene, linearised_model(scene, solve_static(scene)))
    return model


def simulate(scene, duration: float, dt: float | None = None, method: str = "generalized-alpha", *,
             rho_inf: float = 0.5, save_every: int | None = None, save_times=None,
             progress: bool | None = None, model: DynamicModel | None = None, params=None,
             newton_tol: float | None = None, codegen: bool | None = None) -> Trajectory:
    """Time response of a line from rest at t = 0 (where its excitation starts): its
    dynamics Mechanism (:func:`~symcable.models.planar_mechanism.mechanism_of`) marched by
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
        Time step, s, shortened when needed so that a whole number of steps fills
        ``duration`` (``stats['dt_requested']`` keeps the value asked for). Default:
        generalized-α ``period / 100`` (``duration / 100`` when nothing moves); RK4 0.8 times
        its stability limit (:func:`symcable.planar_time.rk4_stability_limit`), at most that
        same value.
    method : {"generalized-alpha", "rk4"}
        Implicit generalized-α (first order on the DAE residual, Jansen, Whiting & Hulbert
        2000: second order, A-stable, numerical damping set by ``rho_inf``) or explicit
        classical RK4 (fourth order, stable only below its limit).
    rho_inf : float
        Generalized-α spectral radius at infinite step, in [0, 1].
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
        y_{n+1} over y_scale (default 1e-10).
    codegen : bool, optional
        Run the step in generated C (compiled once per model structure and method, then
        loaded from the build cache); the loop over steps runs inside CasADi's ``mapaccum``,
        never in Python. Default None: generated C when a C compiler is found and the step
        is small enough for compiling to pay (see :mod:`symcable.codegen`); True without a
        compiler warns once and uses the virtual machine. Results agree with the virtual
        machine's to round-off.

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
    if model is None and scene is not None:
        scene = load_scene(scene)
        model = build_dynamic_model(scene)
    return _planar_time.simulate(scene, duration, dt, method, rho_inf=rho_inf,
                                 save_every=save_every, save_times=save_times,
                                 progress=progress, model=model, params=params,
                                 newton_tol=newton_tol, codegen=codegen, started=started)


def solve_periodic(scene, method: str = "shooting", *, intervals: int | None = None,
                   degree: int = 3, scheme: str = "radau", solver: str | None = None,
                   harmonics: int | None = None, samples: int | None = None,
                   ipopt_options: Mapping | None = None, resolution: int = 200,
                   model: DynamicModel | None = None, params: np.ndarray | None = None,
                   initial: PeriodicSolution | None = None,
                   tol: float | None = None, codegen: bool | None = None,
                   steps: int | None = None, rho_inf: float = 0.5) -> PeriodicSolution:
    """Periodic steady state of a scene's dynamics over one period of its excitation.

    ``scene`` is anything :func:`symcable.load_scene` takes, and must prescribe a motion;
    its dynamic model is built here (:func:`build_dynamic_model`) unless ``model`` is given.
    The other parameters, the result and the errors are those of
    :func:`symcable.solvers.periodic.solve_periodic`.
    """
    started = time.perf_counter()
    if model is None:
        scene = load_scene(scene)
        model = build_dynamic_model(scene)
    return _periodic.solve_periodic(
        scene, method, intervals=intervals, degree=degree, scheme=scheme, solver=solver,
        harmonics=harmonics, samples=samples, ipopt_options=ipopt_options, resolution=resolution,
        model=model, params=params, initial=initial, tol=tol, codegen=codegen, steps=steps,
        rho_inf=rho_inf, started=started)


def sweep_periodic(scene, periods: Sequence[float], method: str = "collocation", *,
                   intervals: int | None = None, degree: int = 3, scheme: str = "radau",
                   solver: str | None = None, harmonics: int | None = None,
                   samples: int | None = None, ipopt_options: Mapping | None = None,
                   resolution: int = 200, model: DynamicModel | None = None,
                   tol: float | None = None, codegen: bool | None = None,
                   steps: int | None = None, rho_inf: float = 0.5) -> PeriodicSweep:
    """Fairlead tension response over excitation periods (a tension RAO), by continuation.

    ``scene`` as in :func:`solve_periodic`; the model is built once for the whole sweep.
    The other parameters, the result and the errors are those of
    :func:`symcable.solvers.periodic.sweep_periodic`.
    """
    started = time.perf_counter()
    if model is None:
        scene = load_scene(scene)
        model = build_dynamic_model(scene)
    return _periodic.sweep_periodic(
        scene, periods, method, intervals=intervals, degree=degree, scheme=scheme, solver=solver,
        harmonics=harmonics, samples=samples, ipopt_options=ipopt_options, resolution=resolution,
        model=model, tol=tol, codegen=codegen, steps=steps, rho_inf=rho_inf, started=started)


def modal_analysis(scene, n_modes: int = 10, *, model: DynamicModel | None = None,
                   max_dense: int = MAX_DENSE, codegen: bool | None = None) -> ModalSolution:
    """The lowest undamped natural frequencies and mode shapes of a line.

    ``scene`` is anything :func:`symcable.load_scene` takes; its static state is solved and
    its dynamic model built here unless ``model`` is given (then ``scene`` may be None).
    The other parameters, the result and the errors are those of
    :func:`symcable.solvers.modal.modal_analysis`.
    """
    started = time.perf_counter()
    if model is None:
        model = build_dynamic_model(load_scene(scene))
    return _modal.modal_analysis(scene, n_modes, model=model, max_dense=max_dense, codegen=codegen,
                                 started=started)


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
    cond = getattr(scene, f"end_{end}").condition
    if str(getattr(cond, "value", cond)) != "pinned":
        raise SymcableError(f"end_{end}.condition = {getattr(cond, 'value', cond)!r}: the end "
                            "stiffness is defined for a pinned end (a prescribed position)")
    model = build_model(scene)
    mech = static_mechanism(model)
    st = solve_static(scene, model=model) if static is None else static
    p = mech.params.values
    eq = solve_equilibrium(mech, p, starts=[Start(st.unknowns, np.zeros(0), p, "static solution")])
    return -output_sensitivity(mech, eq, f"end_force_{end}", f"end_{end}.position")


def linearize(scene, *, undamped: bool = False, static=None) -> SceneLinearization:
    """The exact linearisation of a scene's dynamics about its static state: K, C, M and the
    kinematics G, H of its dynamics Mechanism (see :class:`SceneLinearization`), and the
    exact end stiffness at each pinned end. From CasADi's derivatives of the same
    expressions the solvers integrate (no finite differences).

    Parameters
    ----------
    scene : Scene, dict or path; it must have a moving end or none (its motion is switched off)
    undamped : bool
        Current, excitation and the closure stabilisation off, as ``modal_analysis`` has
        them (its frequencies are the undamped eigenvalues of the state matrix).
    static : StaticSolution, optional
    """
    scene = load_scene(scene)
    model = build_model(scene)
    st = solve_static(scene, model=model) if static is None else static
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
