"""The planar periodic analyses on the generic periodic solvers: the glue between a scene's
DynamicModel and :func:`~symcable.solvers.periodic_mech.solve_periodic_mech`.

:func:`symcable.solve_periodic` and :func:`symcable.sweep_periodic` (in :mod:`symcable.api.analyses`)
build the scene's DynamicModel; here its Mechanism (:func:`~symcable.models.planar.mechanism.
mechanism_of`) is solved at the periodic parameters (no start-up ramp) by the method the
user names, and the generic result (:class:`~symcable.results.periodic_generic.
MechanismPeriodic`) becomes the planar one (:class:`~symcable.results.periodic.
PeriodicSolution`): the states in the DynamicModel's ``y`` order, the fairlead tension and
its harmonics, the node envelopes, the signed axial force, slack and strain-range checks.

The closure invariant
---------------------
With both ends held the planar kinematics conserve the end-to-end closure; the Mechanism
stabilises it in its formulation (``dc/dt = -beta c``, see
:mod:`symcable.models.planar.mechanism`), so its periodic problem is well posed as it stands
and the generic solvers detect nothing. With ``beta = 0`` the closure's level would be free
(a Floquet multiplier 1 of the period map, a singular collocation Jacobian): such parameters
are refused here.
"""
from __future__ import annotations

import dataclasses
import math
import time
from typing import Mapping, Sequence

import numpy as np

from ..mechanism.functions import functions
from ..errors import ConvergenceError, SceneError, SymcableError
from ..models import DynamicModel
from ..models.planar.mechanism import mechanism_of, state_permutation
from ..results.periodic import PeriodicSolution, PeriodicSweep
from ..results.periodic_generic import MechanismPeriodic
from ..results.trajectory import node_tension, range_warnings, slack_warnings
from ..scene import Scene, load_scene
from ..solvers.options import Collocation, HarmonicBalance, Shooting
from ..solvers.periodic_mech import solve_periodic_mech

__all__ = ["METHODS", "method_options", "periodic_params", "solve_model", "sweep_model",
           "DEFAULT_TOL", "REPORTED_HARMONICS"]

#: the periodic methods by name, each with its options class
METHODS = {"collocation": Collocation, "harmonic-balance": HarmonicBalance,
           "shooting": Shooting}
#: the solved system's scaled residual each method stops at, by default (the generic
#: solvers' units: collocation and harmonic balance rows over the velocity and force scales;
#: shooting the change of the scaled integrator state over one period): 1e-10 keeps
#: collocation and harmonic balance at the old planar solvers' residual; 1e-7 is the old
#: shooting's stopping rule (1e-8 per second at T = 10 s on the same scaled state), the
#: fixed point to ~1e-10 of the tension range, far below the integrator's error
DEFAULT_TOL = {"collocation": 1e-10, "harmonic-balance": 1e-10, "shooting": 1e-7}
#: harmonics of the fairlead tension reported by collocation and shooting
REPORTED_HARMONICS = 10


#: the planar dynamics' outputs with one column per segment
PER_SEGMENT = ("tension", "axial_force", "strain", "angle")


def _fields(cls) -> tuple:
    return tuple(f.name for f in dataclasses.fields(cls))


def method_options(method, options: Mapping):
    """``(name, options object)`` from ``method`` (a name of :data:`METHODS` or an options
    object) and the keyword ``options`` of that method, validated by its dataclass; an option
    of another method, or of none, is one SymcableError naming it and the method's own."""
    if isinstance(method, tuple(METHODS.values())):
        name = next(k for k, c in METHODS.items() if isinstance(method, c))
        base = method
    else:
        text = str(getattr(method, "value", method)).strip().lower().replace("_", "-")
        if text not in METHODS:
            raise SymcableError(f"method = {method!r}: must be one of "
                                f"{', '.join(repr(m) for m in METHODS)}, or Collocation(...), "
                                "HarmonicBalance(...) or Shooting(...)")
        name, base = text, None
    cls = METHODS[name]
    own = _fields(cls)
    options = {k: v for k, v in options.items() if v is not None}  # None: not given
    for key, value in options.items():
        if key in own:
            continue
        owners = [m for m, c in METHODS.items() if key in _fields(c)]
        mine = ", ".join(own)
        if key == "solver" and owners:
            raise SymcableError(f"solver = {value!r}: {name} has its own solver; solver is an "
                                f"option of method = 'collocation' ({name}'s options: {mine})")
        if owners:
            raise SymcableError(f"{key} = {value!r}: an option of method = '{owners[0]}', not "
                                f"of '{name}'; pass method='{owners[0]}' ({name}'s options: "
                                f"{mine})")
        raise SymcableError(f"{key} = {value!r}: not an option of any periodic method "
                            f"({name}'s options: {mine})")
    kw = dict(options)
    if name == "collocation" and kw.get("scheme") == "gauss":
        kw["scheme"] = "legendre"
    return name, (dataclasses.replace(base, **kw) if base is not None else cls(**kw))


def periodic_params(model: DynamicModel, **blocks) -> np.ndarray:
    """The model's parameters for a periodic steady state (``p_periodic``: no start-up ramp),
    with named blocks replaced, e.g. ``omega=2*pi/T``."""
    base = getattr(model, "p_periodic", None)
    p = np.array(model.p_value if base is None else base, dtype=float)
    for name, value in blocks.items():
        if name not in model.p_slices:
            raise SymcableError(f"parameter block {name!r}: not one of the model's "
                                f"({', '.join(model.p_names)})")
        p[model.p_slices[name]] = value
    return p


def _period_of(model: DynamicModel, p: np.ndarray) -> float:
    w = float(np.asarray(p, dtype=float)[model.p_slices["omega"]][0])
    if not (math.isfinite(w) and w > 0.0):
        raise SymcableError(f"omega = {w} rad/s: a periodic solution needs omega > 0 "
                            "(a scene with a prescribed motion and its period)")
    return 2.0 * math.pi / w


def _check_model(scene, model: DynamicModel | None) -> tuple[Scene, DynamicModel]:
    if not isinstance(scene, Scene):
        scene = load_scene(scene)
    if model is None:
        raise SymcableError(f"model = None: give the dynamic model of scene '{scene.name}' "
                            "(symcable.solve_periodic and symcable.sweep_periodic build it)")
    if model.period is None:
        raise SceneError(f"scene '{scene.name}' has no prescribed motion: a periodic response "
                         "needs an excitation (add [end_b.motion] with its period, s)")
    return scene, model


def _check_params(model: DynamicModel, p: np.ndarray) -> None:
    if p.size != model.p.numel():
        raise SymcableError(f"params has {p.size} entries, the model {model.p.numel()}")
    mech = mechanism_of(model)
    if "beta" in model.p_slices and mech.n_q > mech.n_v:  # both ends held: a closure
        beta = np.asarray(p[model.p_slices["beta"]], dtype=float)
        if beta.size and not np.all(beta > 0):
            raise SymcableError(
                f"beta = {beta.tolist()}: with both ends held the closure stabilisation must be "
                "> 0 for a periodic solution (at beta = 0 the end-to-end closure is conserved "
                "at any level, so the periodic problem has no unique solution); keep the "
                "model's own beta")


# ---------------------------------------------------------------------------------------------
def _as_start(model: DynamicModel, sol: PeriodicSolution, period: float) -> MechanismPeriodic:
    """A planar periodic solution as a start of the generic solvers at ``period`` (its states
    in normalised time t/T; a shooting solution's integrator state where the period is its
    own)."""
    iq, iv = state_permutation(model)
    Y = np.asarray(sol.states, dtype=float)
    n = Y.shape[0]
    stats = {}
    if (sol.method == "shooting" and sol.unknowns is not None
            and abs(sol.period - period) <= 1e-12 * period):
        stats = {"state0": np.asarray(sol.unknowns, dtype=float),
                 "steps": sol.stats.get("steps"), "rho_inf": sol.stats.get("rho_inf")}
    mech = mechanism_of(model)
    p = np.asarray(sol.params if sol.params is not None else periodic_params(model), float)
    return MechanismPeriodic(mech.name, float(period), period * np.arange(n) / n, Y[:, iq],
                             Y[:, iv], np.zeros((n, 0)), p, {}, sol.method, "converged", stats)


def _names(model: DynamicModel, size: int) -> tuple:
    names = [""] * size
    for block, sl in (getattr(model, "p_slices", {}) or {}).items():
        idx = range(*sl.indices(size))
        for i, k in enumerate(idx):
            names[k] = block if len(idx) == 1 else f"{block}[{i}]"
    return tuple(names) if all(names) else ()


def _stats(name: str, res: MechanismPeriodic, wall: float) -> dict:
    g = res.stats
    st = {"solver": g.get("solver"), "iterations": g.get("iterations"),
          "return_status": g.get("return_status", "converged" if res.status == "converged"
                                 else "; ".join(res.warnings)),
          "residual_norm": g.get("residual"), "tolerance": g.get("tolerance"),
          "unknowns": g.get("unknowns"), "solve_time": g.get("wall_time"), "wall_time": wall,
          "guess": {"start": g.get("start")}, "compiled": bool(g.get("compiled", False)),
          "error_estimate": g.get("error_estimate"), "defect": g.get("defect"),
          "periodicity_defect": g.get("periodicity_defect")}
    keys = {"collocation": ("intervals", "degree", "scheme"),
            "harmonic-balance": ("harmonics",),
            "shooting": ("steps", "rho_inf", "periods", "newton_iterations",
                         "anderson_periods", "floquet_max", "integrator")}[name]
    st.update({k: g[k] for k in keys if k in g})
    if name == "harmonic-balance":
        st["samples"] = g.get("time_samples")
    return st


def _solution(scene_name: str, model: DynamicModel, name: str, res: MechanismPeriodic,
              resolution: int, stats: dict, n_harm: int) -> PeriodicSolution:
    """The planar result of a generic one: dense output at ``resolution`` times (the
    method's samples interpolated trigonometrically), outputs, envelopes, harmonics, checks."""
    mech = mechanism_of(model)
    T, n, p = res.period, resolution, res.p
    t = T * np.arange(n) / n
    q, v, z = res.at(t)
    iq, iv = state_permutation(model)
    Y = np.zeros((n, model.n_y))
    Y[:, iq], Y[:, iv] = q, v
    F = functions(mech)
    outs = F.unpack(np.asarray(F.outputs.map(n)(q.T, v.T, z.T, t[None, :], p)))
    for key in PER_SEGMENT:  # one segment: unpack cannot tell (n, 1) from a scalar series
        if key in outs:
            outs[key] = np.asarray(outs[key]).reshape(n, -1)
    ft = np.ravel(outs["fairlead_tension"])
    force = outs["fairlead_force"].reshape(n, -1) if "fairlead_force" in outs else np.zeros((n, 0))
    tension = outs["tension"] if "tension" in outs else np.zeros((n, 0))
    if tension.size:  # on the nodes, ends included: the end forces' magnitudes at the ends
        tension = node_tension(tension, outs.get("anchor_tension"), ft)
    axial_force = outs.get("axial_force")
    c = np.fft.rfft(ft) / n
    H = min(n_harm, (n - 1) // 2)
    amp = np.concatenate([[c[0].real], 2.0 * np.abs(c[1:H + 1])])
    phase = np.concatenate([[0.0], np.angle(c[1:H + 1])])
    status, warnings = ("converged" if res.status == "converged" else "failed"), ()
    s_nodes = np.asarray(model.info["s_nodes"], dtype=float) if "s_nodes" in model.info else None
    if status == "converged":
        static = model.info.get("static")
        axial = outs.get("axial_force", outs.get("tension"))
        s_mid = s_nodes
        s_mid = 0.5 * (s_mid[:-1] + s_mid[1:]) if s_mid is not None and \
            s_mid.size == axial.shape[1] + 1 else np.arange(axial.shape[1])
        slack, warnings = slack_warnings(t, s_mid, axial,
                                         None if static is None else static.axial_force)
        invalid = False
        if static is not None and "strain" in outs:
            total = np.asarray(static.strain) + outs["strain"]
            invalid, beyond = range_warnings(model, t, s_mid, total, outs)
            warnings = beyond + warnings
        status = "invalid" if invalid else "slack" if slack else status
    return PeriodicSolution(
        scene_name=scene_name, method=name, period=float(T), time=t, states=Y,
        fairlead_tension=ft, fairlead_force=force,
        tension_min=tension.min(axis=0) if tension.size else np.zeros(0),
        tension_max=tension.max(axis=0) if tension.size else np.zeros(0),
        fairlead_tension_harmonics_amplitude=amp, fairlead_tension_harmonics_phase=phase,
        status=status, stats=stats, warnings=tuple(warnings) + tuple(res.warnings),
        unknowns=(np.asarray(res.stats["state0"], dtype=float)
                  if res.stats.get("state0") is not None else None),
        params=np.asarray(p, dtype=float), param_names=_names(model, np.size(p)),
        s=s_nodes if s_nodes is not None and s_nodes.size == tension.shape[1] else None,
        axial_force=axial_force)


def _solve(scene_name: str, model: DynamicModel, name: str, opts, p: np.ndarray, *,
           initial: PeriodicSolution | None, tol: float | None, ipopt_options, resolution: int,
           codegen: bool | None, t0: float) -> PeriodicSolution:
    """One periodic solve of the model's Mechanism, as a PeriodicSolution."""
    _check_params(model, p)
    T = _period_of(model, p)
    mech = mechanism_of(model)
    start = None if initial is None else _as_start(model, initial, T)
    n_harm = opts.harmonics if name == "harmonic-balance" else REPORTED_HARMONICS
    try:
        res = solve_periodic_mech(mech, T, opts, p=p, start=start,
                                  ipopt_options=ipopt_options, codegen=codegen,
                                  tol=DEFAULT_TOL[name] if tol is None else tol)
    except ConvergenceError as exc:
        part = exc.partial
        if not isinstance(part, MechanismPeriodic):
            raise
        stats = _stats(name, part, time.perf_counter() - t0)
        sol = _solution(scene_name, model, name, part, resolution, stats, n_harm)
        raise ConvergenceError(
            f"periodic {name} ({stats['solver']}): {str(exc).split(': ', 1)[-1]}", partial=sol,
            diagnostics={"return_status": stats["return_status"],
                         "iterations": stats["iterations"],
                         "residual_norm": stats["residual_norm"], "tolerance": stats["tolerance"],
                         "history": part.stats.get("history"), "guess": stats["guess"],
                         "defect": stats["defect"]}) from None
    if initial is not None:
        res.stats["start"] = ("given solution" if initial.method == name and
                              res.stats.get("start", "").startswith("shooting solution")
                              else "given solution (re-sampled)")
    stats = _stats(name, res, time.perf_counter() - t0)
    return _solution(scene_name, model, name, res, resolution, stats, n_harm)


def solve_model(scene, model: DynamicModel | None, method, *, params=None, initial=None,
                resolution: int = 200, tol: float | None = None, ipopt_options=None,
                codegen: bool | None = None, options: Mapping, started: float | None = None
                ) -> PeriodicSolution:
    """:func:`symcable.solve_periodic` on a built model (see there)."""
    t0 = time.perf_counter() if started is None else started
    name, opts = method_options(method, options)
    _check_common(name, resolution, tol, ipopt_options, codegen)
    scene, model = _check_model(scene, model)
    p = periodic_params(model) if params is None else np.asarray(params, dtype=float).ravel()
    return _solve(scene.name, model, name, opts, p, initial=initial, tol=tol,
                  ipopt_options=ipopt_options, resolution=resolution, codegen=codegen, t0=t0)


def _check_common(name, resolution, tol, ipopt_options, codegen) -> None:
    if not isinstance(resolution, (int, np.integer)) or resolution < 8:
        raise SymcableError(f"resolution = {resolution!r}: must be an integer >= 8 (output "
                            "times per period)")
    if tol is not None and not (isinstance(tol, (int, float)) and tol > 0):
        raise SymcableError(f"tol = {tol!r}: must be a number > 0")
    if ipopt_options is not None and name != "collocation":
        raise SymcableError(f"ipopt_options = {ipopt_options!r}: an option of method = "
                            f"'collocation' (IPOPT), not of '{name}'")
    if ipopt_options is not None and not isinstance(ipopt_options, Mapping):
        raise SymcableError(f"ipopt_options = {ipopt_options!r}: must be a dict of IPOPT options")
    if codegen not in (None, True, False):
        raise SymcableError(f"codegen = {codegen!r}: must be True, False or None (automatic)")


def sweep_model(scene, model: DynamicModel | None, periods: Sequence[float], method, *,
                resolution: int = 200, tol: float | None = None, ipopt_options=None,
                codegen: bool | None = None, options: Mapping,
                started: float | None = None) -> PeriodicSweep:
    """:func:`symcable.sweep_periodic` on a built model (see there)."""
    t0 = time.perf_counter() if started is None else started
    name, opts = method_options(method, options)
    _check_common(name, resolution, tol, ipopt_options, codegen)
    scene, model = _check_model(scene, model)
    if "omega" not in model.p_slices:
        raise SymcableError(f"model '{model.name}' has no omega parameter block: it cannot be "
                            "swept over the excitation period")
    periods = np.asarray(periods, dtype=float).ravel()
    if periods.size == 0 or not np.all(np.isfinite(periods) & (periods > 0)):
        raise SymcableError(f"periods = {periods.tolist()} s: must be a non-empty list of "
                            "values > 0")
    n = resolution
    rows = {k: np.full(periods.size, np.nan) for k in ("amp", "phase", "mean", "max", "min")}
    curves = np.full((periods.size, n), np.nan)
    statuses, warnings = [], []
    stats = {"iterations": [], "solve_time": [], "start": []}
    prev = None
    for i, T in enumerate(periods):
        p = periodic_params(model, omega=2.0 * math.pi / T)
        sol, start = None, None
        for start in (["neighbour"] if prev is not None else []) + ["own start"]:
            try:
                sol = _solve(scene.name, model, name, opts, p,
                             initial=prev if start == "neighbour" else None, tol=tol,
                             ipopt_options=ipopt_options, resolution=resolution,
                             codegen=codegen, t0=time.perf_counter())
                break
            except ConvergenceError as exc:
                warnings.append(f"period {T:g} s from the {start}: {exc}")
        stats["start"].append(start)
        if sol is None:
            statuses.append("failed")
            stats["iterations"].append(None)
            stats["solve_time"].append(None)
            continue
        prev = sol
        ft = sol.fairlead_tension
        rows["amp"][i] = sol.fairlead_tension_harmonics_amplitude[1]
        rows["phase"][i] = sol.fairlead_tension_harmonics_phase[1]
        rows["mean"][i], rows["max"][i], rows["min"][i] = np.mean(ft), np.max(ft), np.min(ft)
        curves[i] = ft
        statuses.append(sol.status)
        warnings += [f"period {T:g} s: {w}" for w in sol.warnings]
        stats["iterations"].append(sol.stats["iterations"])
        stats["solve_time"].append(sol.stats["solve_time"])
    if all(s == "failed" for s in statuses):
        raise ConvergenceError(f"periodic sweep: no period converged ({warnings[-1]})",
                               partial=None, diagnostics={"warnings": warnings, "stats": stats})
    status = ("partial" if "failed" in statuses else "invalid" if "invalid" in statuses
              else "slack" if "slack" in statuses else "converged")
    stats["wall_time"] = time.perf_counter() - t0
    return PeriodicSweep(
        scene_name=scene.name, method=name, periods=periods,
        fairlead_tension_amplitude=rows["amp"], fairlead_tension_phase=rows["phase"],
        fairlead_tension_mean=rows["mean"], fairlead_tension_max=rows["max"],
        fairlead_tension_min=rows["min"], normalised_time=np.arange(n) / n,
        fairlead_tension=curves, statuses=tuple(statuses), status=status, stats=stats,
        warnings=tuple(warnings))
