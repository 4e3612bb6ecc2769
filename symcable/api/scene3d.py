"""Which Mechanism and which static state the Mechanism path's analyses take: the cable's,
or for a formulation with twists (:attr:`~symcable.models.Formulation.twists`, a rod) the
rod's (:mod:`symcable.api.rod_static`): the one place that asks (:mod:`symcable.api.cable3d`
and :mod:`symcable.api.cable3d_periodic` run every scene through it), and the twists' extras
in the results (the rod's series, twist mode shapes, twist coordinate names).
"""
from __future__ import annotations

import dataclasses
import math
import re

import numpy as np

from .cable3d_static import (cable3d_mechanism, check_periodic_3d, run_start_state,
                             static_equilibrium)
from ..errors import SymcableError
from ..models import formulation_of
from ..models.rod.spin import with_reference_spin
from ..models.common.tow import held_tows
from ..results.line3d import LineTrajectory, line_from_outputs
from .rod_fields import tension_shear
from .rod_static import rod_mechanism, rod_static_equilibrium
from ..scene import Scene

__all__ = ["ROD_SERIES", "check_moves", "check_periodic_scene", "check_rk4_limit",
           "dynamics_mechanism", "has_twists", "rod_line", "scene_equilibrium", "scene_mechanism",
           "start_state", "twist_names", "twist_shapes"]

#: the rod's outputs a time or periodic result carries in ``stats["outputs"]`` (name ->
#: array (n_t, ...)), beyond the cable's series (see :mod:`symcable.models.rod.rod`)
ROD_SERIES = ("twist_angles", "curvature", "twist", "bending_moment", "twisting_moment",
              "internal_force", "reference_frame", "kinetic_energy", "potential_energy")

def has_twists(scene: Scene) -> bool:
    """Whether the scene's formulation carries twists and material frames (a rod's
    Mechanism, :mod:`symcable.api.rod_static`)."""
    return formulation_of(scene).twists


def scene_mechanism(scene: Scene):
    """The scene's Mechanism: the rod's for a rod or hybrid scene, else cable3d's (each
    built once per scene content)."""
    return rod_mechanism(scene) if has_twists(scene) else cable3d_mechanism(scene)


def scene_equilibrium(scene: Scene, **options):
    """``(mechanism, Equilibrium)``: the scene at rest, by the rod's static solve for a rod
    or hybrid scene, else cable3d's (``options``: ``tol``, ``max_iter``, ``continuation``,
    ``codegen``, as :func:`~symcable.api.cable3d_static.static_equilibrium`)."""
    if has_twists(scene):
        options.pop("start", None)  # the rod's statics take no outside start
        return rod_static_equilibrium(scene, **options)
    return static_equilibrium(scene, **options)


def check_moves(scene: Scene, mech) -> None:
    """A dynamic analysis needs something that moves: a SymcableError naming the scene when
    ``mech`` has no velocity unknowns (every node held, e.g. one segment between two held
    ends)."""
    if mech.n_v == 0:
        raise SymcableError(f"scene {scene.name!r}: nothing moves (every node is held, e.g. a "
                            "single segment between two held ends): its dynamics have no "
                            "unknowns; give the line more segments")


def check_rk4_limit(scene: Scene, mech, t0: float, q, v) -> float:
    """RK4's stable step at the run's start, s
    (:func:`~symcable.solvers.steps.rk4_stability_limit` with the run's own arguments, so that
    :func:`~symcable.solvers.integrate.integrate` finds it cached), or one SymcableError
    naming the method and the fix where it cannot be computed. Past DENSE_MAX states it is a
    power iteration with sparse QR solves of the mass matrix, which CasADi's QR refuses
    (``Linsol::solve: 'nfact' failed``) when a pivot is below its absolute threshold: a rod's
    twist inertia (m D^2 ds / 8: 4.9e-13 kg m^2 on 5 mm cells of Goyal & Perkins' cable,
    beside node masses of 4e-6 kg) fails at 6.5e-13 and passes at 9.8e-13 (seed000_rod at
    300 and 200 segments), and the run would stop on a CasADi RuntimeError."""
    from ..solvers.steps import rk4_stability_limit
    try:
        return rk4_stability_limit(mech, mech.params.values, t0, q, v)
    except RuntimeError as exc:
        # CasADi's "<path>/linsol.cpp:91: Linsol::solve: 'nfact' failed", in one line
        why = re.sub(r"^\S*:\d+:\s*", "", " ".join(str(exc).split())) or type(exc).__name__
        sections = scene.sections if scene.version == 1 else [
            sec for ln in scene.lines for sec in ln.sections]
        ds = min((sec.ds for sec in sections), default=None)
        rod = (f"; a rod's twist inertia on segments of {ds * 1e3:.3g} mm is below the sparse "
               "solver's pivot threshold" if has_twists(scene) and ds else "")
        raise SymcableError(f"method = 'rk4': its stable step cannot be computed for scene "
                            f"{scene.name!r} ({mech.n_q + mech.n_v} states): the sparse solve "
                            f"with its mass matrix failed ({why}){rod}; use "
                            "method='generalized-alpha' (the default) or fewer, longer "
                            "segments") from None


def dynamics_mechanism(scene: Scene, mech):
    """The Mechanism the dynamic analyses of ``scene`` run: a rod's with its reference
    frames' spin in the twist's kinetic energy
    (:func:`~symcable.models.rod.spin.with_reference_spin`: the motion then independent of
    when the frames are re-anchored), else ``mech`` itself. The same q, v and p: a static
    state of ``mech`` is one of it."""
    return with_reference_spin(mech) if has_twists(scene) else mech


def check_periodic_scene(scene: Scene) -> None:
    """:func:`~symcable.api.cable3d_static.check_periodic_3d`, for the scene's own Mechanism."""
    if has_twists(scene):
        from ..solvers.periodic_mech import check_periodic
        check_periodic(rod_mechanism(scene))
    else:
        check_periodic_3d(scene)


def start_state(scene: Scene, t0: float, start: str | None, codegen):
    """:func:`~symcable.api.cable3d_static.run_start_state`; a rod or hybrid scene starts from
    its static state at rest (a tow is refused: its steady start is cable3d's for now)."""
    if not has_twists(scene):
        return run_start_state(scene, t0, start, codegen=codegen)
    tows, _ = held_tows(scene, t0)
    if tows or start == "steady":
        raise SymcableError(f"start = {start!r}: a {scene.model.value} scene runs from rest "
                            "(start = 'rest' or None); a tow (kind = 'tow') is not taken by "
                            "the rod yet")
    if start is not None and start != "rest":
        raise SymcableError(f"start = {start!r}: must be 'rest' or None for a "
                            f"{scene.model.value} scene")
    mech, eq = rod_static_equilibrium(scene, codegen=codegen)
    return dynamics_mechanism(scene, mech), eq, np.zeros(mech.n_v), {"start": "rest"}, []


def rod_line(scene, mech, t, outputs, warnings, common) -> LineTrajectory:
    """A rod's run as a LineTrajectory: the cable's series, and the rod's own
    (:data:`ROD_SERIES`, and the seed's ``tension`` f . t and ``shear``, N, (n_t, n_seg),
    from the internal force f) in ``stats["outputs"]``; without the cable's slack report (a rod
    carries compression: a segment at or below zero strain is not slack)."""
    line = line_from_outputs(scene.name, t, outputs, mech.layout.parts["line"].s,
                             warnings=warnings, **common)
    n_t = np.asarray(t).size
    stats = {k: v for k, v in line.stats.items()
             if k not in ("slack_fraction", "slack_segments", "snaps", "snap_peak",
                          "snap_peak_time")}
    stats["outputs"] = {k: np.asarray(outputs[k], float).reshape(n_t, -1)
                        for k in ROD_SERIES if k in outputs}
    if "internal_force" in outputs:  # the seed's tension f . t and shear, not EA e
        stats["outputs"]["tension"], stats["outputs"]["shear"] = tension_shear(
            stats["outputs"]["internal_force"], line.positions)
    return dataclasses.replace(line, stats=stats, warnings=tuple(warnings))


def twist_shapes(mech, velocity_shapes) -> np.ndarray | None:
    """(n_modes, N) each mode's edge twist angles (rad; 0 on an edge whose twist is held or
    a hybrid's cable3d edge), with the scale of its node shape
    (:func:`~symcable.api.cable3d_static.node_shapes`: a largest node displacement of 1, its
    largest entry positive); a mode that moves no node (pure torsion) to a largest twist of
    1. None for a Mechanism without twists."""
    from ..models.rod.spin import twist_edges
    if "twist_angles" not in mech.outputs:
        return None
    pairs = twist_edges(mech)
    if not pairs:
        return None
    U = np.asarray(velocity_shapes, float).reshape(-1, mech.n_v)
    idx = np.asarray(mech.layout.parts["line"].node_v)
    tw, edges = (np.array(c, int) for c in zip(*pairs))
    N = len(mech.layout.parts["line"].s) - 1
    out = np.zeros((U.shape[0], N))
    for r, u in enumerate(U):
        x, part = np.where(idx < 0, 0.0, u[np.where(idx < 0, 0, idx)]), u[tw]
        peak, top = float(np.max(np.linalg.norm(x, axis=1))), float(np.max(np.abs(part)))
        if peak > 1e-9 * top:
            c = math.copysign(1.0, x.flat[int(np.argmax(np.abs(x)))]) / peak
        else:
            c = math.copysign(1.0, part[int(np.argmax(np.abs(part)))]) / max(top, 1e-300)
        out[r, edges] = part * c
    return out


def twist_names(kinds, mech) -> tuple:
    """``kinds`` (the Mechanism's coordinate names) with its twists named
    ``"edge{j}.twist"``."""
    from ..models.rod.spin import twist_edges
    names = list(kinds)
    if "twist_angles" in mech.outputs:
        for i, j in twist_edges(mech):
            names[i] = f"edge{j}.twist"
    return tuple(names)
