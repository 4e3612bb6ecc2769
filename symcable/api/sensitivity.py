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

import casadi as ca
import numpy as np
from scipy.sparse import csc_matrix
from scipy.sparse.linalg import splu

from ..errors import SymcableError
from ..mechanism.functions import functions
from ..results.sensitivity import Sensitivity
from ..scene import Scene, load_scene
from ..scene.load import _read_file
from .cable3d_static import calm
from .scene3d import scene_equilibrium, scene_mechanism

__all__ = ["sensitivity", "static_values", "DEFAULT_STEP"]

#: the relative step of the central difference through the scene's arithmetic (module
#: docstring)
DEFAULT_STEP = 1e-6
#: the largest difference (relative to the force scale) between the base Mechanism's
#: residual and a perturbed scene's own at the same state and parameters: above it the
#: number is compiled into the equations, not (only) a parameter
COMPILED_IN = 1e-9
#: derived outputs: name suffix -> the end force whose magnitude it is
_TENSIONS = {"fairlead_tension": "end_force_b", "anchor_tension": "end_force_a"}


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


def _mechanism(raw: dict, base):
    return scene_mechanism(calm(load_scene(raw, base=base)))


def _parameter_slope(raw, base, mech, x0, name, parts, value, step) -> tuple[np.ndarray, float]:
    """dp/dtheta (n_p,) by a central difference of the Mechanism's numbers (one-sided where
    the scene refuses one side: an anchor on the seabed moved down), and the signed step;
    refusing a number that changes the structure or is compiled into the equations."""
    h = step * max(abs(value), 1.0)
    ps, why = {}, None
    for sign in (1.0, -1.0):
        try:
            m = _mechanism(_set(raw, parts, value + sign * h), base)
        except SymcableError as exc:
            why = why or str(exc)
            continue
        if m.params.names != mech.params.names or m.params.sizes != mech.params.sizes \
                or (m.n_q, m.n_z) != (mech.n_q, mech.n_z):
            raise SymcableError(f"parameter {name!r}: changing it changes the model's structure "
                                "(which terms it builds), so it has no derivative here")
        p = np.asarray(m.static_p, float)
        mine = np.asarray(functions(m).static_residual(x0, p), float).ravel()
        base_r = np.asarray(functions(mech).static_residual(x0, p), float).ravel()
        if np.max(np.abs(mine - base_r), initial=0.0) > COMPILED_IN * float(mech.scales.force):
            raise SymcableError(f"parameter {name!r}: it is compiled into the equations, not "
                                "passed as a parameter (as the depth, the water's density, a "
                                "body's numbers), so it has no exact derivative yet")
        ps[sign] = p
    if len(ps) == 2:
        return (ps[1.0] - ps[-1.0]) / (2.0 * h), h
    if not ps:
        raise SymcableError(f"parameter {name!r}: the scene refuses it changed by {h:.3g} "
                            f"either way ({why})")
    sign = next(iter(ps))
    return (ps[sign] - np.asarray(mech.static_p, float)) / (sign * h), sign * h


def _outputs(mech, names) -> list:
    """[(name, output it reads, derived or None, entry or None)] of each requested output
    (``"NAME[i]"``: that entry of a vector output alone)."""
    if isinstance(names, str):
        names = [names]
    out = []
    for name in names:
        name = str(name)
        m = re.fullmatch(r"(.+)\[(\d+)\]", name)
        whole, entry = (m.group(1), int(m.group(2))) if m and m.group(1) in mech.outputs \
            else (name, None)
        head, _, tail = whole.rpartition(".")
        tension = f"{head}.{_TENSIONS[tail]}" if head and tail in _TENSIONS else \
            _TENSIONS.get(tail) if not head else None
        if whole in mech.outputs:
            size = int(mech.outputs[whole].expr.numel())
            if entry is not None and entry >= size:
                raise SymcableError(f"output {name!r}: {whole!r} has {size} entries")
            out.append((name, whole, None, entry))
        elif entry is None and tension is not None and tension in mech.outputs:
            out.append((name, tension, "norm", None))
        else:
            known = sorted(set(mech.outputs) | {
                (f"{n.rpartition('.')[0]}." if "." in n else "") + k
                for n in mech.outputs for k, v in _TENSIONS.items() if n.endswith(v)})
            raise SymcableError(f"output {name!r}: unknown; the static state's outputs: "
                                f"{', '.join(known)} (an entry of a vector one as NAME[i])")
    if not out:
        raise SymcableError("outputs: give at least one")
    return out


def _entries(mech, F, outs, y, dy=None):
    """Each requested output's entries: (names, units, values, rows of dy or None)."""
    sl = F.output_slices()
    names, units, values, rows = [], [], [], []
    for name, source, derived, entry in outs:
        block = y[sl[source]]
        dblock = None if dy is None else dy[sl[source]]
        if entry is not None:
            block = block[entry:entry + 1]
            dblock = None if dblock is None else dblock[entry:entry + 1]
        unit = str(mech.outputs[source].unit)
        if derived == "norm":
            mag = float(np.linalg.norm(block))
            names.append(name), units.append(unit), values.append(mag)
            if dy is not None:
                rows.append(block @ dblock / mag if mag > 0 else np.full(dy.shape[1], math.nan))
            continue
        for i in range(block.size):
            names.append(name if block.size == 1 or entry is not None else f"{name}[{i}]")
            units.append(unit)
            values.append(float(block[i]))
            if dy is not None:
                rows.append(dblock[i])
    return names, units, values, rows


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


def static_values(scene, outputs) -> dict:
    """{output entry: value} at ``scene``'s static state, by the names :func:`sensitivity`
    takes (one static solve, no derivatives)."""
    raw, base = _raw(scene)
    s0 = load_scene(raw, base=base)
    mech, eq = scene_equilibrium(calm(s0))
    F = functions(mech)
    y = np.asarray(F.outputs(eq.q, np.zeros(mech.n_v), eq.z, 0.0, eq.p), float).ravel()
    _check_state(s0, mech, F, y)
    names, _, values, _ = _entries(mech, F, _outputs(mech, outputs), y)
    return dict(zip(names, values))


def sensitivity(scene, outputs, parameters, *, step: float = DEFAULT_STEP) -> Sensitivity:
    """Exact derivatives of named outputs of ``scene``'s static state with respect to named
    numbers of the scene (module docstring).

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
        line: ``"fairlead_tension"``), the magnitudes of end B's and end A's forces.
    parameters : str or list of str
        Dotted paths of numbers in the scene file's layout: ``"line_types.chain.diameter"``,
        ``"lines[0].sections[0].length"``, ``"points.anchor0.position"`` (a list: each
        entry a parameter, ``"...position[0]"`` ...), ``"environment.current[0]"``.
    step : float
        The central difference's relative step through the scene's arithmetic.

    Returns
    -------
    Sensitivity
        The outputs' values and the Jacobian (n_out, n_par).
    """
    started = time.perf_counter()
    if not (isinstance(step, float) and 0.0 < step < 1e-2):
        raise SymcableError(f"step = {step!r}: must be a float in (0, 0.01)")
    raw, base = _raw(scene)
    s0 = load_scene(raw, base=base)
    if s0.dim != 3:
        raise SymcableError(f"scene {s0.name!r}: sensitivities are of 3D scenes (model = "
                            "'cable3d', 'rod' or 'hybrid') for now")
    pars = _expand(raw, parameters)
    mech, eq = scene_equilibrium(calm(s0))
    outs = _outputs(mech, outputs)
    F = functions(mech)
    x0 = np.concatenate([np.asarray(eq.q, float), np.asarray(eq.z, float)])
    p0 = np.asarray(eq.p, float)
    slopes, steps = [], []
    for name, parts, value in pars:
        dp, h = _parameter_slope(raw, base, mech, x0, name, parts, value, step)
        slopes.append(dp)
        steps.append(h)
    dP = np.column_stack(slopes)  # (n_p, n_par)
    J = F.static_jacobian(x0, p0)[1]
    Rp = np.column_stack([np.asarray(F.static_parameter_slope(x0, p0, dP[:, j]), float).ravel()
                          for j in range(dP.shape[1])])
    if x0.size:
        try:
            lu = splu(csc_matrix(_sparse(J)))
            dx = -lu.solve(Rp)
        except RuntimeError:
            raise SymcableError(f"scene {s0.name!r}: the static Jacobian is singular at its "
                                "state (a neutral mode, a bifurcation): no unique derivative "
                                "there") from None
    else:
        dx = np.zeros((0, dP.shape[1]))
    q, z, v0 = eq.q, eq.z, np.zeros(mech.n_v)
    y_q, y_z, y_p = (np.asarray(a) for a in F.output_parameter_jacobian(q, v0, z, 0.0, p0))
    dy = y_q @ dx[:mech.n_q] + y_z @ dx[mech.n_q:] + y_p @ dP
    y = np.asarray(F.outputs(q, v0, z, 0.0, p0), float).ravel()
    _check_state(s0, mech, F, y)
    names, units, values, rows = _entries(mech, F, outs, y, dy)
    return Sensitivity(s0.name, tuple(names), tuple(units), tuple(n for n, _, _ in pars),
                       np.array(values), np.array([v for _, _, v in pars]), np.array(rows),
                       {"parameter_steps": steps,
                        "residual_norm": float(eq.stats.get("residual_norm", math.nan)),
                        "wall_time": time.perf_counter() - started})


def _sparse(J) -> "csc_matrix":
    """A CasADi sparse matrix as SciPy's."""
    J = ca.DM(J)
    sp = J.sparsity()
    return csc_matrix((np.asarray(J.nonzeros(), float), np.asarray(sp.row(), int),
                       np.asarray(sp.colind(), int)), shape=J.shape)
