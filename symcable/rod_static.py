"""The static configuration of a ``model = "rod"`` scene (:mod:`symcable.models.rod`): its
Mechanism solved by the generic :func:`~symcable.solvers.equilibrium.solve_equilibrium`, the
outputs turned into a :class:`~symcable.results.StaticSolution` as cable3d's
(:func:`symcable.solve_static` sends rod scenes here)."""
from __future__ import annotations

import time
from collections import OrderedDict

from .cable3d_static import RTOL, _solution
from .errors import ConvergenceError
from .models.cable3d_starts import force_scale
from .models.mechanism import Mechanism
from .models.rod import build_rod, rod_table
from .results import StaticSolution
from .scene import Scene
from .solvers.equilibrium import solve_equilibrium

__all__ = ["rod_mechanism", "rod_static_equilibrium", "solve_static_rod"]

_CACHE: "OrderedDict[str, Mechanism]" = OrderedDict()
_CACHE_SIZE = 16


def rod_mechanism(scene: Scene) -> Mechanism:
    """The scene's rod Mechanism (:func:`~symcable.models.rod.build_rod`), built once per
    scene content (the 16 most recent)."""
    key = repr(scene.to_dict())
    mech = _CACHE.get(key)
    if mech is None:
        mech = _CACHE[key] = build_rod(scene)
        if len(_CACHE) > _CACHE_SIZE:
            _CACHE.popitem(last=False)
    else:
        _CACHE.move_to_end(key)
    return mech


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
    """Static configuration of a rod scene (see :func:`symcable.solve_static`); the twist
    angles and the rod's other outputs are in ``stats["outputs"]`` (name -> array)."""
    t0 = time.perf_counter()
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
    return _solution(scene, seg, eq.outputs, eq.q, "converged", stats, tuple(eq.warnings))
