"""One case of a sweep: its analysis, and the scalar outputs kept from it.

:func:`run_case` is what a Dask worker runs (and the client, for the first case): it never
raises for a case that fails, it returns a record saying so.

Outputs (SI units), by analysis
-------------------------------
``static`` (:func:`symcable.solve_static`):

* ``fairlead_tension``, ``anchor_tension`` N: the magnitude of the force the line exerts on
  its end B (fairlead) and end A (anchor);
* ``fairlead_force_x``, ``fairlead_force_y``, ``fairlead_force_z`` N: that force on end B
  by component (a planar scene has x and z only);
* ``grounded_length`` m: the length resting on the seabed.

``simulate`` (:func:`symcable.simulate`, statistics over the saved samples from
``discard`` s after the run's start) and ``periodic`` (:func:`symcable.solve_periodic`, over
one period):

* ``fairlead_tension_max``, ``_min``, ``_mean``, ``_range`` N (range = max - min), and the
  same of ``anchor_tension`` (not for a planar periodic solution, which has no anchor
  series);
* ``static_fairlead_tension``, ``static_anchor_tension`` N: of the case's static solution
  (one static solve more).

In a scene of several lines (version 2) every output is per line: ``NAME.fairlead_tension``
(end B of line NAME).
"""
from __future__ import annotations

import math
import os
import socket
import time
import traceback
from typing import Any, Mapping

import numpy as np

from ..errors import SymcableError
from ..limits import limits
from ..models import formulation_of

__all__ = ["ANALYSES", "OUTPUTS", "available_outputs", "run_case"]

ANALYSES = ("static", "simulate", "periodic")
_STATS = ("max", "min", "mean", "range")
_SERIES = ("fairlead_tension", "anchor_tension")

#: every output: name -> (unit, analyses that give it)
OUTPUTS: dict = {
    "fairlead_tension": ("N", ("static",)),
    "anchor_tension": ("N", ("static",)),
    "fairlead_force_x": ("N", ("static",)),
    "fairlead_force_y": ("N", ("static",)),
    "fairlead_force_z": ("N", ("static",)),
    "grounded_length": ("m", ("static",)),
    **{f"{q}_{s}": ("N", ("simulate", "periodic")) for q in _SERIES for s in _STATS},
    "static_fairlead_tension": ("N", ("simulate", "periodic")),
    "static_anchor_tension": ("N", ("simulate", "periodic")),
}


def available_outputs(analysis: str, scene, lines: tuple = ()) -> list:
    """The output names ``analysis`` gives on ``scene`` (a Scene): no ``fairlead_force_y``
    in the plane, no anchor tension series from a linearised periodic solve; with ``lines``
    (a scene of several lines) each prefixed by every line's name."""
    names = [n for n, (_, an) in OUTPUTS.items() if analysis in an]
    if scene.dim == 2:
        names = [n for n in names if n != "fairlead_force_y"]
    if analysis == "periodic" and formulation_of(scene).linearised:
        names = [n for n in names if not n.startswith("anchor_tension_")]
    if lines:
        return [f"{ln}.{n}" for ln in lines for n in names]
    return names


# --------------------------------------------------------------------------- the values

def _static_values(sol) -> dict:
    f = np.ravel(np.asarray(sol.fairlead_force, float))
    out = {"fairlead_tension": sol.fairlead_tension, "anchor_tension": sol.anchor_tension,
           "grounded_length": sol.grounded_length}
    for axis, value in zip(("x", "z") if f.size == 2 else ("x", "y", "z"), f):
        out[f"fairlead_force_{axis}"] = value
    return out


def _series_values(time_s, series: dict, discard: float) -> dict:
    t = np.asarray(time_s, float)
    keep = t >= t[0] + discard - 1e-9 * max(1.0, abs(discard)) if t.size else t.astype(bool)
    out = {}
    for name, x in series.items():
        x = np.asarray(x, float)
        if x.size != t.size or not keep.any():
            continue
        x = x[keep]
        out.update({f"{name}_max": np.max(x), f"{name}_min": np.min(x),
                    f"{name}_mean": np.mean(x), f"{name}_range": np.ptp(x)})
    return out


def _per_line(result, pick, several: bool) -> dict:
    """The values of a one-line result, or with ``several`` lines (a scene of version 2)
    ``NAME.``-prefixed of each line's."""
    if several:
        return {f"{name}.{k}": v for name, ln in result.lines.items() for k, v in pick(ln).items()}
    return pick(result)


def _analyse(scene, analysis: str, options: Mapping, codegen) -> tuple:
    """``(values, status)`` of one case's analysis."""
    from ..api.analyses import simulate, solve_periodic
    from ..api.planar_static import solve_static

    several = scene.version == 2
    if analysis == "static":
        sol = solve_static(scene, codegen=codegen)
        return _per_line(sol, _static_values, several), sol.status
    if analysis == "simulate":
        res = simulate(scene, options["duration"], dt=options.get("dt"), tol=options.get("tol"),
                       method=options.get("method", "generalized-alpha"), progress=False,
                       codegen=codegen)
        discard = float(options.get("discard", 0.0))
    else:
        res = solve_periodic(scene, options.get("method", "shooting"), codegen=codegen)
        discard = 0.0
    values = _per_line(res, lambda r: _series_values(
        r.time, {k: getattr(r, k) for k in _SERIES if hasattr(r, k)}, discard), several)
    static = solve_static(scene, codegen=codegen, estimate=False)
    values.update(_per_line(static, lambda s: {"static_fairlead_tension": s.fairlead_tension,
                                               "static_anchor_tension": s.anchor_tension},
                            several))
    return values, res.status


def _one_line(exc: BaseException) -> str:
    text = " ".join(str(exc).split())
    return f"{type(exc).__name__}: {text}" if text else type(exc).__name__


def run_case(task: Mapping) -> dict:
    """Run one case and return its record (a JSON-ready dict); never raises for a failed case.

    ``task``: ``name``, ``hash``, ``scene`` (a loaded :class:`~symcable.scene.Scene`),
    ``analysis``, ``options`` (of the analysis), ``codegen`` (None, True or False; the
    analysis' argument), ``cached_only`` (compile nothing: generated C only from the build
    cache, else the virtual machine, :func:`symcable.mechanism.codegen.cached_only`), ``limits`` (the
    client's :class:`~symcable.limits.Limits`, in force on the worker too; absent: the
    worker's own).

    The record: ``name``, ``hash``, ``status`` (the result's own, e.g. "converged", "slack",
    "invalid"; or "failed"), ``message`` (one line: the error of a failed case, else ""),
    ``values`` (every output the analysis gives, float; empty when failed: a failed case never
    reports a number), ``wall_time`` s, ``worker`` (host:pid), ``builds`` (this case's
    compile_functions calls by what they did: memory, cache, compiled, vm).
    """
    from ..mechanism import background_build, codegen as _cg

    started = time.perf_counter()
    before = dict(_cg.build_counts)
    record: dict[str, Any] = {"name": task["name"], "hash": task["hash"]}
    try:
        # a case that may compile (the first) waits for the compiler: the rest load its C
        with _cg.cached_only() if task.get("cached_only") else background_build.waiting(), \
                limits(task.get("limits")):
            values, status = _analyse(task["scene"], task["analysis"], task["options"],
                                      task.get("codegen"))
        values = {k: float(v) for k, v in values.items()}
        bad = next((k for k, v in values.items() if not math.isfinite(v)), None)
        if bad is not None:
            raise SymcableError(f"output {bad} = {values[bad]}: not finite (the analysis "
                                "returned no usable number)")
        record.update(status=str(status), message="", values=values)
    except SymcableError as exc:
        record.update(status="failed", message=_one_line(exc), values={})
    except Exception as exc:  # a case must not stop the sweep: recorded, with where it broke
        where = traceback.extract_tb(exc.__traceback__)[-1]
        record.update(status="failed", values={}, message=_one_line(exc) + f" (unexpected, at "
                      f"{os.path.basename(where.filename)}:{where.lineno})")
    record.update(wall_time=time.perf_counter() - started,
                  worker=f"{socket.gethostname()}:{os.getpid()}",
                  builds={k: _cg.build_counts[k] - before.get(k, 0) for k in _cg.build_counts})
    return record
