"""The static configuration of a planar scene, on the generic equilibrium solver: the planar
Model (:mod:`symcable.models.planar.model`) seen as a Mechanism
(:func:`~symcable.models.planar.static.static_mechanism`), solved by
:func:`~symcable.solvers.equilibrium.solve_equilibrium`, and its outputs turned into the
planar :class:`~symcable.results.static.StaticSolution`. The planar glue sits here, above the
solvers, which know nothing planar.
"""
from __future__ import annotations

import time

import numpy as np

from ..mechanism.functions import functions
from ..errors import ConvergenceError, SymcableError
from ..models import build_model, formulation_of
from ..models.planar.base import Model
from ..models.planar.static import static_mechanism
from ..results.static import StaticSolution
from ..scene import Scene, load_scene
from ..solvers.equilibrium import solve_equilibrium
from ..solvers.integrate import check_positive
from .above_water import check_above_water

__all__ = ["RTOL", "solve_static"]

#: default residual tolerance, relative to the model's force scale
RTOL = 1e-9


def solve_static(scene, *, tol: float | None = None, max_iter: int = 50,
                 continuation: bool = True, model: Model | None = None,
                 codegen: bool | None = None, accuracy: float | None = None,
                 estimate: bool = True) -> StaticSolution:
    """Static configuration of a scene, with its discretisation error.

    Parameters
    ----------
    scene : Scene, dict or path
        Anything :func:`symcable.load_scene` takes. A ``model = "cable3d"`` scene is solved
        as the 3D cable (:mod:`symcable.api.cable3d_static`): the same StaticSolution, with
        positions (n, 3), end forces (3,), ``angle`` the segments' elevation, no shear, and
        ``moment`` the magnitude of the bending moment at the nodes (zero where EI = 0).
    tol : float, optional
        Residual tolerance, N (max-norm over all equations, each a force). Default
        ``1e-9`` times the scene's force scale (total submerged weight, applied forces),
        or the model's round-off floor when that is larger.
    max_iter : int
        Newton iterations allowed per solve (per continuation step).
    continuation : bool
        When Newton from the starts fails, continue from a start's own parameters (no
        bending, or no load) to the scene's, in adaptive steps (and relax by
        pseudo-transient continuation as a last resort).
    model : Model, optional
        A model already built for this scene (:func:`symcable.build_model`).
    codegen : bool, optional
        Run the solve in generated C (compiled once per model structure, then loaded from
        the build cache) rather than the CasADi virtual machine. Default None: generated C
        when a C compiler is found and the model is small enough for it to pay (see
        :mod:`symcable.mechanism.codegen`); True without a compiler warns once and uses the virtual
        machine. The results agree to round-off.
    accuracy : float, optional
        Discretisation error allowed, as a fraction of the largest tension (e.g. 0.01).
        Given, the lines whose estimated error exceeds it are solved again with more
        segments (up to four rounds) and the refined solution is returned. Default None:
        no refinement; a line whose error exceeds 1 % warns, naming the segments needed.
    estimate : bool
        Estimate the discretisation error (:mod:`symcable.api.static_error`: a second solve
        with half the segments, Richardson extrapolation) and, where a line touches the
        seabed, how far the penalty bed's sinking moves the answer from a rigid bed's
        (:mod:`symcable.api.bed_error`: Newton from the answer with a 4 times stiffer bed).
        False skips both (half the cost or less) and leaves ``stats["discretisation_error"]``
        and ``stats["seabed_error"]`` out.

    Returns
    -------
    StaticSolution
        ``stats["discretisation_error"]`` gives, per line, the estimated error of its end
        tensions (``error``, N; ``relative``, to the largest tension), the segment counts
        compared, the order assumed, and the estimate's ``wall_time`` (s);
        ``stats["seabed_error"]`` the same for the seabed's sinking (with ``sinking``, m),
        where a line touches the bed. ``stats`` also
        gives ``iterations``, ``residual_norm`` (N), ``tolerance`` (N),
        ``wall_time`` (s), ``compiled`` (generated C or not), ``path`` (``"newton"``:
        plain Newton in one CasADi call;
        ``"damped newton"``: with a line search; ``"continuation in <what>"``) and
        ``start`` (where the initial guess came from).

    Raises
    ------
    ConvergenceError
        With ``partial`` (a StaticSolution of the best iterate, status "failed") and the
        diagnostics of every attempt.
    """
    if tol is not None:
        check_positive("tol", tol, "N")
    if isinstance(max_iter, bool) or not isinstance(max_iter, (int, np.integer)) or max_iter < 1:
        raise SymcableError(f"max_iter = {max_iter!r}: must be a whole number >= 1 (Newton "
                            "iterations per solve)")
    if not isinstance(scene, Scene):
        scene = load_scene(scene)
    options = dict(tol=tol, max_iter=max_iter, continuation=continuation, codegen=codegen)
    sol = check_above_water(scene, _solve_once(scene, model=model, **options))
    if not estimate:
        if accuracy is not None:
            raise SymcableError("solve_static: accuracy needs the error estimate "
                                "(estimate=True)")
        return sol
    from .bed_error import with_bed_estimate
    from .static_error import ACCURACY, with_error_estimate
    target = ACCURACY if accuracy is None else accuracy

    # the estimate's solves (other segment counts, a stiffer bed) are one-off scenes: in the
    # virtual machine unless generated C is asked for (codegen=True), not worth a compile
    # each (1.5 s for a 25-segment planar line against 0.05 s solved)
    once = dict(options, codegen=bool(options["codegen"]))

    def solve(s, near=None):
        sol_s = _solve_once(s, model=None, near=near, **once)
        if not formulation_of(s).linearised:  # a long line's one-off scene is not kept
            from .cable3d_static import release
            release(s)
        return sol_s
    return with_error_estimate(scene, sol, solve, accuracy, after=lambda s, x: with_bed_estimate(
        s, x, solve, target, once))


def _solve_once(scene: Scene, *, tol, max_iter, continuation, model, codegen, near=None):
    """:func:`solve_static` without the error estimate; ``near`` (a similar scene and its
    solution, whose state is tried first) where the formulation takes one (cable3d)."""
    form = formulation_of(scene)
    if not form.linearised:
        if model is not None:
            raise SymcableError(f"solve_static(model=...): a planar Model; a "
                                f"{scene.model.value} scene builds its own Mechanism (leave "
                                "model out)")
        if form.twists:
            from .rod_static import solve_static_rod
            return solve_static_rod(scene, tol=tol, max_iter=max_iter,
                                    continuation=continuation, codegen=codegen)
        from .cable3d_static import solve_static_3d
        return solve_static_3d(scene, tol=tol, max_iter=max_iter, continuation=continuation,
                               codegen=codegen, near=near)
    t0 = time.perf_counter()
    model = model or build_model(scene)
    mech = static_mechanism(model)
    if tol is None:
        tol = max(RTOL * model.force_scale, model.residual_floor)
    tol = float(tol)
    try:
        eq = solve_equilibrium(mech, model.p_target, tol=tol, max_iter=max_iter,
                               continuation=None if continuation else False, codegen=codegen)
    except ConvergenceError as exc:
        raise _failure(scene, model, mech, exc, tol, t0) from None
    st = eq.stats
    stats = {
        "iterations": st["iterations"],
        "residual_norm": st["residual_norm"],
        "tolerance": tol,
        "wall_time": time.perf_counter() - t0,
        "compiled": st["compiled"],
        "path": st["path"],
        "continuation_steps": st["continuation_steps"],
        "start": st["start"],
        "unknowns": mech.n_q,
        "terms": list(model.terms),
    }
    return _solution(model, eq.q, eq.outputs, "converged", stats)


def _failure(scene, model, mech, exc: ConvergenceError, tol: float, t0: float):
    """The ConvergenceError of solve_static: the best attempt's message and a partial
    StaticSolution (of the first start when no attempt left a finite iterate)."""
    best = exc.diagnostics.get("best") or {}
    nr = float(best.get("residual_norm", float("nan")))
    path = best.get("path", "no attempt")
    eq = exc.partial
    stats = {"iterations": exc.diagnostics.get("iterations", 0), "residual_norm": nr,
             "tolerance": tol, "wall_time": time.perf_counter() - t0,
             "compiled": bool(eq is not None and eq.stats.get("compiled")), "path": path,
             "continuation_steps": 0, "start": best.get("start"), "unknowns": model.n_w,
             "terms": list(model.terms)}
    if eq is not None:
        partial = _solution(model, eq.q, eq.outputs, "failed", stats)
    else:
        F = functions(mech)
        q = np.asarray(next(iter(mech.starts())).q, float)
        out = F.unpack(F.static_solver().packed_outputs(q, model.p_target))
        partial = _solution(model, q, out, "failed", stats)
    attempts = exc.diagnostics.get("attempts", [])
    return ConvergenceError(
        f"static solve of '{scene.name}' found no admissible equilibrium in {len(attempts)} "
        f"attempts (diagnostics['attempts'] has one line each); the best ({path} from "
        f"{best.get('start', 'no start')}, residual {nr:.3g} N, tolerance {tol:.3g} N): "
        f"{best.get('message', 'no start')}",
        partial=partial, diagnostics=exc.diagnostics)


#: a cable segment shorter than this strain is slack (its tension-only law near zero)
BUNCHED_STRAIN = -0.01


def _bunching_warnings(model: Model, out: dict, seg: dict) -> list:
    """A warning where cable segments in the water column are slack and shortened: the line
    folds or sags within one segment there, which a straight segment represents only as a
    shorter chord; the tension near it is uncertain by about that segment's weight."""
    strain = np.asarray(out["strain"], float).ravel()
    if not strain.min() < BUNCHED_STRAIN:  # the usual case, at the cost of one min
        return []
    contact = np.asarray(out["contact_force"], float).ravel()
    cable = seg["EI"] <= 0.0
    free = (contact[:-1] <= 0.1 * np.abs(seg["w"]) * seg["ds"] / 2) & \
        (contact[1:] <= 0.1 * np.abs(seg["w"]) * seg["ds"] / 2)
    bunched = cable & free & (strain < BUNCHED_STRAIN)
    if not np.any(bunched):
        return []
    j = int(np.argmin(np.where(bunched, strain, np.inf)))
    s_mid = 0.5 * (seg["s"][:-1] + seg["s"][1:])
    weight = float(np.max(np.abs(seg["w"][bunched]) * seg["ds"][bunched]))
    return [f"{int(bunched.sum())} cable segment(s) hang slack in the water column, shortened to "
            f"{100 * (1 + strain[j]):.0f} % of their length at s = {s_mid[j]:.4g} m: the line "
            f"folds or sags within a segment there, and the tension near it is uncertain by "
            f"about a segment's weight ({weight:.4g} N); more segments resolve it"]


def _solution(model: Model, w, out: dict, status: str, stats: dict) -> StaticSolution:
    derived = model.postprocess(out)
    s_nodes = np.asarray(model.info["s_nodes"])
    warnings = []
    sb = model.scene.seabed
    if sb is not None and sb.friction > 0:
        warnings.append("seabed friction is not applied in statics (frictionless contact)")
    seg = model.info["segments"]
    axial = np.asarray(out["axial_force"], float).ravel()
    rod = seg["EI"] > 0.0
    if np.any(rod) and axial[rod].min() < 0:
        warnings.append(f"the line is in compression where it has bending stiffness (axial "
                        f"force down to {axial[rod].min():.4g} N)")
    warnings += _bunching_warnings(model, out, seg)

    def col(name):
        v = out[name]
        return v if v.__class__ is np.ndarray and v.ndim == 1 else np.asarray(v, float).ravel()

    return StaticSolution(
        scene_name=model.scene.name,
        s=s_nodes,
        positions=np.asarray(out["positions"], dtype=float),
        angle=col("angle"),
        strain=col("strain"),
        axial_force=col("axial_force"),
        shear=col("shear"),
        moment=col("moment"),
        tension=col("tension"),
        contact_force=col("contact_force"),
        fairlead_force=derived["fairlead_force"],
        anchor_force=derived["anchor_force"],
        fairlead_tension=derived["fairlead_tension"],
        anchor_tension=derived["anchor_tension"],
        grounded_length=derived["grounded_length"],
        touchdown=derived["touchdown"],
        status=status,
        stats=stats,
        warnings=tuple(warnings),
        unknowns=np.array(w, dtype=float),
    )
