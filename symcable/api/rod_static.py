"""The static configuration of a ``model = "rod"`` scene (:mod:`symcable.models.rod.rod`): its
Mechanism solved by the generic :func:`~symcable.solvers.equilibrium.solve_equilibrium`, the
outputs turned into a :class:`~symcable.results.static.StaticSolution` as cable3d's
(:func:`symcable.solve_static` sends rod scenes here)."""
from __future__ import annotations

import dataclasses
import time

import numpy as np

from .cable3d_static import (FRICTIONLESS, RTOL, _frictionless_statics, _solution,
                             cached_mechanism)
from ..errors import ConvergenceError
from ..models.common.starts import force_scale
from ..mechanism.mechanism import Mechanism
from ..models import build_mechanism
from ..models.rod.rod import rod_table
from ..models.rod.zones import probe_mechanism, zoned_scene
from ..results.static import StaticSolution
from .rod_fields import tension_shear
from ..scene import Scene
from ..solvers.equilibrium import solve_equilibrium

__all__ = ["ZONE_THRESHOLD", "hybrid_zones", "rod_mechanism", "rod_static_equilibrium",
           "solve_static_rod"]

def rod_mechanism(scene: Scene) -> Mechanism:
    """The scene's rod or hybrid Mechanism (:func:`symcable.models.build_mechanism`;
    a hybrid with ``zones = "auto"`` resolved first by :func:`hybrid_zones`), built once per
    scene content (:func:`~symcable.api.cable3d_static.cached_mechanism`)."""
    return cached_mechanism(scene, lambda s: build_mechanism(
        hybrid_zones(s)[0] if s.zones == "auto" else s))


def rod_static_equilibrium(scene: Scene, *, tol: float | None = None, max_iter: int = 50,
                           continuation: bool = True, codegen: bool | None = None):
    """``(mechanism, Equilibrium)``: the rod at rest, to ``tol`` N (default RTOL times the
    force scale, as cable3d)."""
    mech = rod_mechanism(scene)
    if tol is None:
        tol = mech.scales.static_tolerance(force_scale(scene, rod_table(scene)), RTOL)
    eq = solve_equilibrium(mech, tol=tol, max_iter=max_iter,
                           continuation=None if continuation else False, codegen=codegen)
    return mech, eq


def solve_static_rod(scene: Scene, *, tol: float | None = None, max_iter: int = 50,
                     continuation: bool = True, codegen: bool | None = None) -> StaticSolution:
    """Static configuration of a rod or hybrid scene (see :func:`symcable.solve_static`); the
    twist angles and the rod's other outputs are in ``stats["outputs"]`` (name -> array);
    with ``zones = "auto"``, ``stats["zones"]`` is :func:`hybrid_zones`'s report (the
    solution is the resolved scene's: the same nodes)."""
    t0 = time.perf_counter()
    scene, zones = hybrid_zones(scene)
    seg = rod_table(scene)
    try:
        mech, eq = rod_static_equilibrium(scene, tol=tol, max_iter=max_iter,
                                          continuation=continuation, codegen=codegen)
    except ConvergenceError as exc:
        part = exc.partial
        partial = None if part is None else _solution(scene, seg, part.outputs, part.q,
                                                      "failed", dict(part.stats), ())
        raise ConvergenceError(f"static solve of '{scene.name}' (rod) found no admissible "
                               f"equilibrium: {exc}", partial=partial,
                               diagnostics=exc.diagnostics) from None
    stats = dict(eq.stats)
    stats.update(wall_time=time.perf_counter() - t0, unknowns=mech.n_q, terms=list(mech.terms),
                 outputs=dict(eq.outputs))
    if zones["zones"] or zones["message"] != "zones given":
        stats["zones"] = zones
    warnings = tuple(eq.warnings) + ((FRICTIONLESS,) if _frictionless_statics(scene) else ())
    return _rod_forces(_solution(scene, seg, eq.outputs, eq.q, "converged", stats, warnings),
                       eq.outputs)


def _rod_forces(sol: StaticSolution, out) -> StaticSolution:
    """A rod's shear (N, per segment: the internal force across the edge minus its part along
    the edge) and the magnitude of its internal force at the interior nodes (N, the mean over
    the two edges), from the output ``internal_force`` (cable3d's solution has no shear and
    takes the axial force as the tension)."""
    f = np.asarray(out["internal_force"], float).reshape(-1, 3)
    _, shear = tension_shear(f, sol.positions)
    mag = np.linalg.norm(f, axis=1)
    tension = np.array(sol.tension, float)
    tension[1:-1] = 0.5 * (mag[:-1] + mag[1:])
    return dataclasses.replace(sol, shear=shear, tension=tension)


#: ``zones = "auto"``: a segment is a rod where the bending length sqrt(EI / T) of the
#: static line with every section cable3d exceeds this fraction of the line's length
#: (on Goyal & Perkins' benchmark the bending length away from the tension-free end is about
#: a tenth of L, so 0.15 marks only the end's low-tension zone; studies/README.md)
ZONE_THRESHOLD = 0.15
#: ... and each rod zone is grown on both sides by this many bending lengths at its edge
#: (threshold x L): the moment there, which the moment-free joint sets to zero, has decayed
#: by about exp(-1.5) = 0.22 from the zone's edge
ZONE_GROW = 1.5


def hybrid_zones(scene: Scene, threshold: float = ZONE_THRESHOLD,
                 grow: float = ZONE_GROW) -> tuple[Scene, dict]:
    """``(scene, report)``: a ``zones = "auto"`` hybrid with its rod sections chosen (any
    other scene is returned as it is, with an empty report): the line solved at rest with
    every section a cable (:func:`~symcable.models.rod.zones.probe_mechanism`), its rod
    zones and the report as :func:`~symcable.models.rod.zones.zoned_scene` gives them."""
    if scene.zones != "auto":
        return scene, {"zones": [], "threshold": threshold, "grow": grow,
                       "message": "zones given"}
    mech = probe_mechanism(scene)
    tol = mech.scales.static_tolerance(force_scale(scene, rod_table(scene)), RTOL)
    eq = solve_equilibrium(mech, tol=tol, codegen=False)
    return zoned_scene(scene, eq.outputs["positions"], eq.outputs["internal_force"],
                       threshold, grow)
