"""Exact design sensitivities of a static state: :func:`sensitivity`.

The static state x of a scene solves R(x; p) = 0, p the Mechanism's parameters. A number of
the scene (a line type's diameter, a section's length, an anchor's position) enters the
equations through p, p = p(theta): a line type's diameter sets every segment's diameter,
submerged weight (when the weight is not given), drag and added-mass rows. So

    dx/dtheta = -R_x^-1 R_p dp/dtheta,   dy/dtheta = y_x dx/dtheta + y_p dp/dtheta

for an output y(x; p): R_x, R_p, y_x and y_p are CasADi's exact derivatives of the same
equations the static solve solved (the implicit function theorem; no re-solve). dp/dtheta
is the derivative of the scene's own arithmetic from its numbers to the parameters (closed
forms: a length over a segment count, (m - rho pi d^2 / 4) g), taken by a central
difference of the Mechanism's numbers built afresh at theta +- h: h = ``step`` times
max(|theta|, 1 unit), the arithmetic smooth, so the difference is exact to about
``step``^2 relative (1e-12 at the default), not to the static solve's tolerance as a
difference of whole solves is; where the scene refuses one side (an anchor on the seabed
moved down) the difference is one-sided, exact for the linear arithmetic of positions and
lengths and first order (about ``step`` relative) otherwise.

A number that is compiled into the equations instead of passed as a parameter (the depth,
the water's density, a body's mass: :mod:`symcable.models.structure`) has no such
derivative yet: it is refused in one line, as is a number that changes which terms the
model builds (its sign), and a path that names no number of the scene.
"""
from __future__ import annotations

import copy
import math
import os
import re
import time

import numpy as np
from scipy.sparse.linalg import splu

from ..errors import SymcableError
from ..linalg.sparse import to_csc
from ..mechanism.functions import functions
from ..results.sensitivity import Sensitivity
from ..scene import Scene, load_scene
from ..scene.load import _read_file
from .cable3d_static import calm
from .design_slopes import breaking_loads, parameter_slope, slopes_hold
from .output_names import NO_MAGNITUDE, lines_of, requested_outputs
from .periodic_sensitivity import periodic_sensitivity, split_statistic
from .scene3d import scene_equilibrium

__all__ = ["sensitivity", "design_sensitivity", "static_values", "breaking_loads",
           "DEFAULT_STEP"]

#: the relative step of the central difference through the scene's arithmetic (module
#: docstring)
DEFAULT_STEP = 1e-6


def _raw(scene) -> tuple[dict, str | None]:
    """The scene's own data as a dict (a derived number, such as a weight left to its
    default, stays derived) and the folder its files are relative to."""
    if isinstance(scene, Scene):
        return scene.to_dict(), None
    if isinstance(scene, dict):
        return copy.deepcopy(scene), None
    if isinstance(scene, (str, os.PathLike)):
        path = os.fspath(scene)
        if not os.path.exists(path):  # a built-in scene's name, or the loader's error
            return load_scene(path).to_dict(), None
        data, _ = _read_file(path)
        return dict(data), os.path.dirname(os.path.abspath(path))
    raise SymcableError(f"scene = {type(scene).__name__}: must be a scene file's path, a dict "
                        "or a Scene")


def _split(path: str) -> list:
    """``"lines[0].sections.0.length"`` -> ["lines", 0, "sections", 0, "length"]."""
    parts = []
    for token in re.sub(r"\[(\d+)\]", r".\1", path).split("."):
        if token == "":
            raise SymcableError(f"parameter {path!r}: an empty key in the path")
        parts.append(int(token) if token.isdigit() else token)
    return parts


def _get(d, parts, path):
    x = d
    for k in parts:
        try:
            x = x[k]
        except (KeyError, IndexError, TypeError):
            raise SymcableError(f"parameter {path!r}: the scene has no {k!r} there "
                                f"(the path names keys of the scene file: "
                                f"'line_types.NAME.diameter', 'lines[0].sections[0].length', "
                                f"'points.NAME.position[0]')") from None
    return x


def _expand(raw: dict, names) -> list:
    """[(name, parts, value)] of each parameter, a vector key's entries one by one."""
    if isinstance(names, str):
        names = [names]
    out = []
    for name in names:
        parts = _split(str(name))
        value = _get(raw, parts, name)
        if isinstance(value, (list, tuple)) and value and all(
                isinstance(v, (int, float)) and not isinstance(v, bool) for v in value):
            out += [(f"{name}[{i}]", parts + [i], float(v)) for i, v in enumerate(value)]
        elif isinstance(value, (int, float)) and not isinstance(value, bool):
            out.append((str(name), parts, float(value)))
        else:
            raise SymcableError(f"parameter {name!r} = {value!r}: must name a number (or a "
                                "list of numbers) of the scene")
    if not out:
        raise SymcableError("parameters: give at least one")
    return out


def _set(raw: dict, parts: list, value: float) -> dict:
    d = copy.deepcopy(raw)
    x = d
    for k in parts[:-1]:
        x = x[k]
    x[parts[-1]] = value
    return d


def grounded_length(lift: float, sections, slopes: bool = False):
    """The length of line the seabed carries, m, from the vertical force ``lift`` (N) the
    line's end B needs: the sections from end B down hang until their weight is ``lift``,
    the rest lies. Negative: the anchor is lifted, by that length of the end-A section's
    weight. ``sections``: [(length m, weight N/m)] from end A; exact by vertical balance for a
    line whose suspended part no seabed or drag force holds up; smooth through the anchor's
    lift-off. With ``slopes``: (value, d/d lift, d/d sections (n, 2)), in closed form."""
    secs = np.asarray(sections, float).reshape(-1, 2)
    n = len(secs)
    rest, k = float(lift), 0
    for i in range(n - 1, -1, -1):  # from end B down: the section where the hanging ends
        if rest <= secs[i, 1] * secs[i, 0] or i == 0:
            k = i
            break
        rest -= secs[i, 1] * secs[i, 0]
    w = secs[k, 1]
    value = float(np.sum(secs[:k + 1, 0]) - rest / w)
    if not slopes:
        return value
    d = np.zeros((n, 2))
    d[:k, 0] = 1.0                                   # the lying sections' lengths
    d[k, 0] = 1.0                                    # the crossing section's
    d[k, 1] = rest / (w * w)
    d[k + 1:, 0] = secs[k + 1:, 1] / w               # a hanging section's: its weight
    d[k + 1:, 1] = secs[k + 1:, 0] / w
    return value, -1.0 / w, d


def _entries(mech, F, outs, y, dy=None, mbl=None, dmbl=None, lines=()):
    """Each requested output's entries: (names, units, values, rows of dy or None);
    ``mbl``, ``dmbl``: :func:`breaking_loads` and its slopes (n, n_par) for the derived
    outputs, ``lines`` :func:`_lines`."""
    sl = F.output_slices()
    names, units, values, rows = [], [], [], []
    for name, source, derived, entry in outs:
        block = y[sl[source]]
        dblock = None if dy is None else dy[sl[source]]
        if entry is not None:
            block = block[entry:entry + 1]
            dblock = None if dblock is None else dblock[entry:entry + 1]
        unit = str(mech.outputs[source].unit)
        if derived == "up":
            names.append(name), units.append(unit), values.append(float(block[2]))
            if dy is not None:
                rows.append(dblock[2])
            continue
        if derived == "ground":
            value, row = _grounded(name, source, lines, -float(block[2]), mbl,
                                   None if dy is None else -dblock[2], dmbl)
            names.append(name), units.append("m"), values.append(value)
            if dy is not None:
                rows.append(row)
            continue
        if derived == "horizontal":
            block, dblock = block[:2], None if dblock is None else dblock[:2]
        if derived in ("norm", "ratio", "horizontal"):
            mag = float(np.linalg.norm(block))
            if dy is not None and not mag > NO_MAGNITUDE * float(mech.scales.force):
                raise SymcableError(f"output {name!r} = {mag:.3g} N: a magnitude at zero "
                                    "has no derivative (a direction's entry, NAME[i], has)")
            row = None if dy is None else block @ dblock / mag
            if derived == "ratio":
                line = source.rpartition(".")[0]
                k = 2 * ([n[0] for n in lines].index(line) if line else 0) \
                    + source.endswith("_b")
                if not math.isfinite(mbl[k]):
                    raise SymcableError(f"output {name!r}: the line's end section has no "
                                        "breaking load (give its line type breaking_load, "
                                        "or a family)")
                unit, value = "", mag / mbl[k]
                row = None if row is None else row / mbl[k] - value / mbl[k] * dmbl[k]
                mag = value
            names.append(name), units.append(unit), values.append(mag)
            if dy is not None:
                rows.append(row)
            continue
        for i in range(block.size):
            names.append(name if block.size == 1 or entry is not None else f"{name}[{i}]")
            units.append(unit)
            values.append(float(block[i]))
            if dy is not None:
                rows.append(dblock[i])
    return names, units, values, rows


def _grounded(name, source, lines, lift, aux, dlift, daux):
    """``LINE.grounded_length`` and its row (None without ``dlift``): ``lines``
    :func:`_lines`, ``aux`` and ``daux`` :func:`breaking_loads` and its slopes."""
    line = source.rpartition(".")[0]
    names = [n[0] for n in lines]
    k = names.index(line) if line else 0
    a = 2 * len(lines) + 2 * sum(n[1] for n in lines[:k])
    b = a + 2 * lines[k][1]
    own = np.asarray(aux[a:b], float)
    if not lines[k][2]:
        raise SymcableError(f"output {name!r}: the line's end A must be its anchor, a fixed "
                            "point on the seabed (the grounded length is counted from end B "
                            "down to end A)")
    if lift < 0:
        raise SymcableError(f"output {name!r}: end B pushes the line down ({lift:.3g} N "
                            "upward pull): no hanging part to count from")
    if np.any(own[1::2] <= 0):
        raise SymcableError(f"output {name!r}: needs every section of the line to sink "
                            "(weight > 0): a buoyant section's touchdown is not the seabed's")
    value, d_lift, d_own = grounded_length(lift, own.reshape(-1, 2), slopes=True)
    if dlift is None:
        return value, None
    return value, dlift * d_lift + d_own.ravel() @ daux[a:b]


def _check_state(scene, mech, F, y) -> None:
    """The static solve's own check of a free point or body floated above the surface
    (:func:`~symcable.api.above_water.check_above_water`), on the state's outputs ``y``."""
    from types import SimpleNamespace as NS
    from .above_water import _check_floating
    if scene.version == 1:
        return
    sl = F.output_slices()
    pts = {n: NS(position=y[sl[f"{n}.position"]]) for n, p in scene.points.items()
           if p.is_free and f"{n}.position" in sl}
    bodies = {n: NS(position=y[sl[f"{n}.position"]], roll_pitch_yaw=y[sl[f"{n}.roll_pitch_yaw"]])
              for n, b in scene.bodies.items() if b.is_free and f"{n}.position" in sl}
    _check_floating(scene, NS(points=pts, bodies=bodies, status="converged", warnings=()))


def static_values(scene, outputs, *, tol: float | None = None, start=None) -> dict:
    """{output entry: value} at ``scene``'s static state, by the names :func:`sensitivity`
    takes (one static solve, no derivatives); ``tol``: the solve's residual tolerance, N
    (default the static solve's, 1e-9 of the scene's force scale); ``start``: (q, z) of a
    nearby scene of the same structure to start from, or (q, z, p), its equilibrium at its
    parameters p (see :func:`~symcable.api.cable3d_static.static_equilibrium`). The state is
    ``values["state"]``, (q, z, p), when ``start`` is given."""
    raw, base = _raw(scene)
    s0 = load_scene(raw, base=base)
    mech, eq = scene_equilibrium(calm(s0), start=start,
                                 **({} if tol is None else {"tol": tol}))
    F = functions(mech)
    y = np.asarray(F.outputs(eq.q, np.zeros(mech.n_v), eq.z, 0.0, eq.p), float).ravel()
    _check_state(s0, mech, F, y)
    names, _, values, _ = _entries(mech, F, requested_outputs(mech, outputs), y, None,
                                   breaking_loads(s0), None, lines_of(s0))
    out = dict(zip(names, values))
    if start is not None:
        out["state"] = (np.asarray(eq.q, float), np.asarray(eq.z, float),
                        np.asarray(eq.p, float))
    return out


def sensitivity(scene, outputs, parameters, *, step: float = DEFAULT_STEP,
                harmonics: int = 10) -> Sensitivity:
    """Exact derivatives of named outputs of ``scene``'s static state, or of statistics
    over its periodic steady state, with respect to named numbers of the scene (module
    docstring; :mod:`symcable.api.periodic_sensitivity`).

    Parameters
    ----------
    scene : path, dict or Scene
        A 3D scene (``model = "cable3d"``, ``"rod"`` or ``"hybrid"``). From a path or a
        dict, a number the scene derives (a line type's weight from its mass and diameter)
        follows the parameters; a Scene's numbers are taken as it writes them
        (:meth:`~symcable.scene.Scene.to_dict`: such a weight then stays as it is).
    outputs : str or list of str
        Names of the static state's outputs (``"line0.end_force_b"``, ``"spar.force"``,
        ``"positions"``), or ``"LINE.fairlead_tension"`` / ``"LINE.anchor_tension"`` (one
        line: ``"fairlead_tension"``), the magnitudes of end B's and end A's forces, N;
        ``"LINE.fairlead_utilisation"`` / ``"LINE.anchor_utilisation"``, those over the end
        section's breaking load (its line type's ``breaking_load`` or family's: the
        breaking load's own slope included); ``"LINE.anchor_uplift"``, the vertical pull of
        the line on its end A, N (> 0 lifts the anchor); ``"LINE.grounded_length"``, the
        length of line the seabed carries from the vertical balance of the line (m;
        negative: the anchor lifted by that length's weight; smooth through the lift-off);
        ``"NAME.horizontal_force"``, the horizontal magnitude of a point's or body's
        ``force`` (the lines' restoring force on a body at an offset), N.
        Periodic: any of these scalars (not the grounded length) followed by
        ``.range``, ``.max``, ``.min`` or ``.mean``, its statistic over one period of the
        steady state under the scene's harmonic motion (``"line0.fairlead_tension.range"``,
        N), the state by harmonic balance; static and periodic outputs in separate calls.
    parameters : str or list of str
        Dotted paths of numbers in the scene file's layout: ``"line_types.chain.diameter"``,
        ``"lines[0].sections[0].length"``, ``"points.anchor0.position"`` (a list: each
        entry a parameter, ``"...position[0]"`` ...), ``"environment.current[0]"``.
    step : float
        The central difference's relative step through the scene's arithmetic.
    harmonics : int
        Periodic outputs: the harmonic balance's harmonics (default 10, the periodic
        solve's).

    Returns
    -------
    Sensitivity
        The outputs' values and the Jacobian (n_out, n_par).
    """
    if not (isinstance(step, float) and 0.0 < step < 1e-2):
        raise SymcableError(f"step = {step!r}: must be a float in (0, 0.01)")
    raw, base = _raw(scene)
    pars = _expand(raw, parameters)
    names = [outputs] if isinstance(outputs, str) else list(outputs)
    periodic = [n for n in names if split_statistic(str(n))]
    if periodic:
        if len(periodic) != len(names):
            raise SymcableError(f"outputs: {periodic[0]!r} is a periodic statistic and "
                                f"{next(n for n in names if n not in periodic)!r} a static "
                                "output: ask for them in two calls (two states)")
        return periodic_sensitivity(raw, base, names, [n for n, _, _ in pars],
                                    [v for _, _, v in pars],
                                    [lambda v, parts=parts: _set(raw, parts, v)
                                     for _, parts, _ in pars], step, harmonics)
    return design_sensitivity(raw, base, outputs, [n for n, _, _ in pars],
                              [v for _, _, v in pars],
                              [lambda v, parts=parts: _set(raw, parts, v) for _, parts, _ in pars],
                              step)


def design_sensitivity(raw: dict, base, outputs, names, values, raw_at, step=DEFAULT_STEP,
                       reuse=None, raw_of=None, start=None):
    """:func:`sensitivity` with each parameter j given by its name, its value and
    ``raw_at[j](v)``: the scene's dict with that parameter at v (the others as in ``raw``),
    so that a parameter may move several numbers of the scene (an anchor's radius both its
    coordinates).

    ``reuse``: the parameters' slopes through the scene's arithmetic from another scene
    (``stats["slopes"]`` of its result: another load case of the same design), taken when
    they predict this scene's own numbers moved along one pseudo-random direction of the
    parameters (``raw_of(values)``: the scene's dict at those values) to within 1e-6 of the
    move (two builds instead of two per parameter); else the slopes are taken afresh.
    ``start``: (q, z) or (q, z, p) of a nearby design's state to start the static solve
    from (as :func:`static_values`); the state solved is ``stats["state"]``, (q, z, p)."""
    started = time.perf_counter()
    s0 = load_scene(raw, base=base)
    if s0.dim != 3:
        raise SymcableError(f"scene {s0.name!r}: sensitivities are of 3D scenes (model = "
                            "'cable3d', 'rod' or 'hybrid') for now")
    mech, eq = scene_equilibrium(calm(s0), start=start)
    outs = requested_outputs(mech, outputs)
    F = functions(mech)
    x0 = np.concatenate([np.asarray(eq.q, float), np.asarray(eq.z, float)])
    p0 = np.asarray(eq.p, float)
    sl = F.output_slices()
    rows = np.concatenate([np.arange(sl[src].start, sl[src].stop) for _, src, _, _ in outs])
    reused = reuse is not None and raw_of is not None and slopes_hold(
        reuse, raw_of, base, mech, np.asarray(values, float), step, x0, p0, rows)
    if reused:
        dP, steps = np.asarray(reuse, float), [step * max(abs(float(v)), 1.0) for v in values]
    else:
        slopes, steps = [], []
        for name, value, at in zip(names, values, raw_at):
            dp, h = parameter_slope(at, base, mech, x0, name, float(value), step, rows)
            slopes.append(dp)
            steps.append(h)
        dP = np.column_stack(slopes)  # (n_p + the breaking loads, n_par)
    slopes_all = dP
    n_p = np.asarray(mech.static_p).size
    dP, dmbl = dP[:n_p], dP[n_p:]
    J = F.static_jacobian(x0, p0)[1]
    Rp = np.column_stack([np.asarray(F.static_parameter_slope(x0, p0, dP[:, j]), float).ravel()
                          for j in range(dP.shape[1])])
    if x0.size:
        try:
            lu = splu(to_csc(J))
            dx = -lu.solve(Rp)
        except RuntimeError:
            raise SymcableError(f"scene {s0.name!r}: the static Jacobian is singular at its "
                                "state (a neutral mode, a bifurcation): no unique derivative "
                                "there") from None
    else:
        dx = np.zeros((0, dP.shape[1]))
    q, z, v0 = eq.q, eq.z, np.zeros(mech.n_v)
    # (sparse: the outputs read few unknowns and parameters; dense, y_p alone took 40 ms)
    y_q, y_z, y_p = (to_csc(a) for a in F.output_parameter_jacobian(q, v0, z, 0.0, p0))
    dy = y_q @ dx[:mech.n_q] + y_z @ dx[mech.n_q:] + y_p @ dP
    y = np.asarray(F.outputs(q, v0, z, 0.0, p0), float).ravel()
    _check_state(s0, mech, F, y)
    onames, units, ovalues, rows = _entries(mech, F, outs, y, dy, breaking_loads(s0), dmbl,
                                            lines_of(s0))
    return Sensitivity(s0.name, tuple(onames), tuple(units), tuple(names),
                       np.array(ovalues), np.array(values, float), np.array(rows),
                       {"parameter_steps": steps, "slopes": slopes_all, "slopes_reused": reused,
                        "state": (np.asarray(eq.q, float), np.asarray(eq.z, float),
                                  np.asarray(eq.p, float)),
                        "residual_norm": float(eq.stats.get("residual_norm", math.nan)),
                        "wall_time": time.perf_counter() - started})
