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
from ..models.rod.hybrid_terms import rod_runs
from ..models.rod.rod import build_rod, rod_table
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
        tol = max(RTOL * force_scale(scene, rod_table(scene)), 10 * mech.scales.residual_floor)
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
#: (studies/rod_notes/hybrid14.md: on the seed's benchmark sqrt(EI / T) is 0.087-0.112 L away from the
#: tension-free end, so 0.15 marks only the end's low-tension zone)
ZONE_THRESHOLD = 0.15
#: ... and each rod zone is grown on both sides by this many bending lengths at its edge
#: (threshold x L): the moment there, which the moment-free joint sets to zero, has decayed
#: by about exp(-1.5) = 0.22 from the zone's edge (studies/rod_notes/hybrid14.md)
ZONE_GROW = 1.5


def hybrid_zones(scene: Scene, threshold: float = ZONE_THRESHOLD,
                 grow: float = ZONE_GROW) -> tuple[Scene, dict]:
    """``(scene, report)``: a ``zones = "auto"`` hybrid with its rod sections chosen (any
    other scene is returned as it is, with an empty report).

    The line is solved at rest with every section cable3d (cable3d's own bending where
    EI > 0; a guided end held by it: :func:`~symcable.models.rod.rod.build_rod` with no rod
    edge but an end's that takes a moment), and a segment becomes a rod where its bending length sqrt(EI / T) exceeds
    ``threshold`` times the line's length L, T the tension (the internal force along the
    segment; T <= 0: a rod), among the segments whose line type has EI > 0 and GJ > 0;
    an end's segment also where the end is guided, takes a moment or a clamp gives
    ``twist_deg``. Each
    zone is grown by ``grow`` x ``threshold`` x L on both sides, to whole segments (within
    the candidates). Sections are split at the zones' ends (the segment table is
    unchanged), the rod runs marked ``model = "rod"``, the rest ``"cable3d"``. The
    report: ``zones`` [(s_start, s_end)] m of the rod runs, ``threshold``, ``grow``,
    ``bending_length`` per segment (m, inf where T <= 0), ``message`` (one line)."""
    if scene.zones != "auto":
        return scene, {"zones": [], "threshold": threshold, "grow": grow,
                       "message": "zones given"}
    given = dataclasses.replace(scene, zones="given", sections=tuple(
        dataclasses.replace(s, model=None) for s in scene.sections))
    seg = rod_table(scene)
    N = len(seg["ds"])
    first = np.zeros(N, bool)  # an end moment needs a rod edge to act on, even here
    for end, j in ((scene.end_a, 0), (scene.end_b, N - 1)):
        first[j] = end.moment is not None
    mech = build_rod(given, first)
    tol = max(RTOL * force_scale(scene, seg), 10 * mech.scales.residual_floor)
    eq = solve_equilibrium(mech, tol=tol, codegen=False)
    X, f = np.asarray(eq.outputs["positions"]), np.asarray(eq.outputs["internal_force"])
    t = np.diff(X, axis=0)
    T = np.sum(f * t, axis=1) / np.linalg.norm(t, axis=1)
    ok = (seg["EI"] > 0) & (seg["EI2"] > 0) & (seg["GJ"] > 0)
    lam = np.where(T > 0, np.sqrt(seg["EI"] / np.maximum(T, 1e-300)), np.inf)
    rod = ok & (lam > threshold * scene.length)
    a, b = scene.end_a, scene.end_b
    for end, j in ((a, 0), (b, N - 1)):
        if end.guided or end.twist_deg is not None or end.moment is not None:
            rod[j] = True
    s = seg["s"]
    mid = 0.5 * (s[:-1] + s[1:])
    width = grow * threshold * scene.length
    for j0, j1 in rod_runs(rod.copy()):
        rod |= ok & (mid > s[j0] - width) & (mid < s[j1 + 1] + width)
    sections, j0 = [], 0
    for sec in scene.sections:
        mask = rod[j0:j0 + sec.segments]
        k = 0
        while k < sec.segments:
            n = int(np.argmax(mask[k:] != mask[k])) or sec.segments - k
            sections.append(dataclasses.replace(sec, length=sec.ds * n, segments=n,
                                                model="rod" if mask[k] else "cable3d"))
            k += n
        j0 += sec.segments
    zones = [(float(s[j0]), float(s[j1 + 1])) for j0, j1 in rod_runs(rod)]
    where = ", ".join(f"{x0:.4g}-{x1:.4g} m" for x0, x1 in zones) or "none"
    msg = (f"zones = 'auto': rod on {where} of {scene.length:.4g} m (bending length "
           f"sqrt(EI/T) > {threshold:g} L = {threshold * scene.length:.4g} m, grown by "
           f"{width:.4g} m)")
    return (dataclasses.replace(scene, zones="given", sections=tuple(sections)),
            {"zones": zones, "threshold": threshold, "grow": grow, "bending_length": lam,
             "message": msg})
