"""The slopes dp/dtheta of a scene's arithmetic, from its numbers theta to its Mechanism's
parameters p and to the numbers the derived outputs read (breaking loads, sections), for
:mod:`symcable.api.sensitivity`: central differences of the Mechanism's numbers built
afresh, a number compiled into the equations or outputs refused, and the check that lets
one load case reuse another's slopes."""
from __future__ import annotations

import math

import numpy as np

from ..errors import SymcableError
from ..linalg.sparse import to_csc
from ..mechanism.functions import functions
from ..scene import Scene, load_scene
from .cable3d_static import calm
from .scene3d import scene_mechanism

__all__ = ["AUX_STEP", "COMPILED_IN", "breaking_loads", "outputs_differ", "parameter_slope",
           "slopes_hold"]

#: the largest difference (relative to the force scale) between the base Mechanism's
#: residual and a perturbed scene's own at the same state and parameters: above it the
#: number is compiled into the equations, not (only) a parameter
COMPILED_IN = 1e-9
#: the relative step of the scene numbers' own slopes (:func:`_aux_slope`)
AUX_STEP = 1e-3


def _mechanism(raw: dict, base):
    scene = load_scene(raw, base=base)
    return scene, scene_mechanism(calm(scene))


def breaking_loads(scene: Scene) -> np.ndarray:
    """The scene numbers the derived outputs read besides the state: each line's breaking
    load at end A and end B (its end sections' line types', N; NaN where none is given),
    then each line's sections' (length m, submerged weight N/m), end A first."""
    lines = [ln.sections for ln in scene.lines] or [scene.sections]
    out = []
    for sections in lines:
        for sec in (sections[0], sections[-1]):
            mbl = sec.line_type.breaking_load
            out.append(math.nan if mbl is None else float(mbl))
    for sections in lines:
        for sec in sections:
            out += [float(sec.length), float(sec.line_type.weight)]
    return np.array(out)

def parameter_slope(raw_at, base, mech, x0, name, value, step, rows=None, p_of=None,
                    differs=None):
    """dp/dtheta (n_p,) by a central difference of the Mechanism's numbers (one-sided where
    the scene refuses one side: an anchor on the seabed moved down), the breaking loads'
    slope alike (:func:`breaking_loads`), and the signed step; refusing a number that
    changes the structure or is compiled into the equations or into the outputs' entries
    ``rows`` (default all). ``p_of(m)``: the parameters of a built Mechanism m to
    differentiate (default its ``static_p``; a periodic solve's for the periodic state);
    ``differs(m, mech, p)``: a further check that the built Mechanism m's equations or
    outputs differ from ``mech``'s at p (the periodic state's, in motion)."""
    h = step * max(abs(value), 1.0)
    ps, why = {}, None
    for sign in (1.0, -1.0):
        try:
            scene, m = _mechanism(raw_at(value + sign * h), base)
        except SymcableError as exc:
            why = why or str(exc)
            continue
        if m.params.names != mech.params.names or m.params.sizes != mech.params.sizes \
                or (m.n_q, m.n_z) != (mech.n_q, mech.n_z):
            raise SymcableError(f"parameter {name!r}: changing it changes the model's structure "
                                "(which terms it builds), so it has no derivative here")
        p = np.asarray(m.static_p if p_of is None else p_of(m), float)
        if _compiled_in(m, mech, x0, p) or outputs_differ(m, mech, x0, p, rows) \
                or (differs is not None and differs(m, mech, p)):
            raise SymcableError(f"parameter {name!r}: it is compiled into the equations or "
                                "the outputs, not passed as a parameter (as the depth, the "
                                "water's density, a body's numbers), so it has no exact "
                                "derivative yet")
        ps[sign] = np.concatenate([p, breaking_loads(scene)])
    if len(ps) == 2:
        slope = (ps[1.0] - ps[-1.0]) / (2.0 * h)
        n_p = np.asarray(mech.static_p).size
        aux = _aux_slope(raw_at, base, value)
        if aux is not None:
            slope[n_p:] = aux
        return slope, h
    if not ps:
        raise SymcableError(f"parameter {name!r}: the scene refuses it changed by {h:.3g} "
                            f"either way ({why})")
    sign = next(iter(ps))
    base_p = np.concatenate([np.asarray(mech.static_p if p_of is None else p_of(mech), float),
                             breaking_loads(load_scene(raw_at(value), base=base))])
    return (ps[sign] - base_p) / (sign * h), sign * h


def _compiled_in(m, mech, x0, p) -> bool:
    """Whether two Mechanisms' static residuals differ at one state and one parameter
    vector (a number compiled into the equations); never for two of one structure, which
    share their Functions (:mod:`symcable.models.structure`)."""
    if m is mech or (m.functions_of or m) is (mech.functions_of or mech):
        return False
    mine = np.asarray(functions(m).static_residual(x0, p), float).ravel()
    base_r = np.asarray(functions(mech).static_residual(x0, p), float).ravel()
    return bool(np.max(np.abs(mine - base_r), initial=0.0)
                > COMPILED_IN * float(mech.scales.force))


def outputs_differ(m, mech, x0, p, rows=None, v=None, t: float = 0.0) -> bool:
    """Whether two Mechanisms' outputs (their entries ``rows``, default all) differ at one
    state x0 = (q, z) (velocities ``v``, default rest; time ``t``) and one parameter vector
    (a number compiled into an output, as a free body's own numbers into its net force)."""
    if m is mech or (m.functions_of or m) is (mech.functions_of or mech):
        return False
    q, z = x0[:mech.n_q], x0[mech.n_q:]
    v = np.zeros(mech.n_v) if v is None else v
    a = np.asarray(functions(m).outputs(q, v, z, t, p), float).ravel()
    b = np.asarray(functions(mech).outputs(q, v, z, t, p), float).ravel()
    if a.shape != b.shape:
        return True
    if rows is not None:
        a, b = a[rows], b[rows]
    fin = np.isfinite(a) & np.isfinite(b)
    return bool(np.any(np.abs(a[fin] - b[fin]) > COMPILED_IN * (np.abs(a[fin]) + np.abs(b[fin]))
                       + 1e-15 * float(np.max(np.abs(a[fin]), initial=0.0))))


def _aux_slope(raw_at, base, value):
    """The slope of :func:`breaking_loads` (a scene's own arithmetic, no model built) by
    Richardson's extrapolation of central differences at relative steps AUX_STEP and twice
    it (exact to round-off for its polynomials, where the model's step of 1e-6 leaves 1e-9
    of round-off that a derived output's cancellation, the grounded length's weight
    against its fairlead's pull, magnifies); None where the scene refuses a step."""
    h = AUX_STEP * max(abs(value), 1e-3)
    try:
        f = {k: breaking_loads(load_scene(raw_at(value + k * h), base=base))
             for k in (-2, -1, 1, 2)}
    except SymcableError:
        return None
    d1, d2 = (f[1] - f[-1]) / (2 * h), (f[2] - f[-2]) / (4 * h)
    return np.where(np.isfinite(d1), (4.0 * d1 - d2) / 3.0, np.nan)

def slopes_hold(dP, raw_of, base, mech, values, step, x0, p0, rows) -> bool:
    """Whether the slopes ``dP`` (n_p + aux, n_par) predict this scene's numbers moved along
    a fixed pseudo-random direction w of its parameters (:func:`design_sensitivity`): entry
    by entry; or, where a parameter entry misses, what the entries do: the static residual
    at this state ``x0`` and the outputs' entries ``rows`` moved as their parameter slopes
    along the predicted move say (a regularisation's number such as the slack law's, which
    follows a line's stretch and so the load case, changes nothing the equations feel to
    1e-6). The breaking loads and section numbers (aux) always entry by entry."""
    h = step * np.maximum(np.abs(values), 1.0)
    w = h * np.random.default_rng(37).uniform(0.5, 1.5, values.size) \
        * np.where(np.arange(values.size) % 2, 1.0, -1.0)
    ps = []
    for sign in (1.0, -1.0):
        try:
            scene, m = _mechanism(raw_of(values + sign * w), base)
        except SymcableError:
            return False
        if m.params.names != mech.params.names or m.params.sizes != mech.params.sizes \
                or dP.shape[0] != np.asarray(m.static_p).size + breaking_loads(scene).size:
            return False
        ps.append(np.concatenate([np.asarray(m.static_p, float), breaking_loads(scene)]))
    dP = np.asarray(dP, float)
    move, predicted = ps[0] - ps[1], dP @ (2.0 * w)
    if not np.all(np.isfinite(move) == np.isfinite(predicted)):
        return False
    fin = np.isfinite(move)
    # entry by entry (their units differ): within 1e-6 of what the slopes move it by, and
    # the round-off of its own value
    bound = 1e-6 * (np.abs(np.where(np.isfinite(dP), dP, 0.0)) @ np.abs(2.0 * w)) \
        + 1e-12 * np.abs(ps[0])
    good = ~fin | (np.abs(move - np.where(fin, predicted, 0.0)) <= bound)
    n_p = np.asarray(mech.static_p).size
    if good.all():
        return True
    if not good[n_p:].all():
        return False
    F = functions(mech)
    q, z, v = x0[:mech.n_q], x0[mech.n_q:], np.zeros(mech.n_v)
    r_move = np.asarray(F.static_residual(x0, ps[0][:n_p]), float).ravel() \
        - np.asarray(F.static_residual(x0, ps[1][:n_p]), float).ravel()
    r_pred = np.asarray(F.static_parameter_slope(x0, p0, predicted[:n_p]), float).ravel()
    y_move = np.asarray(F.outputs(q, v, z, 0.0, ps[0][:n_p]), float).ravel()[rows] \
        - np.asarray(F.outputs(q, v, z, 0.0, ps[1][:n_p]), float).ravel()[rows]
    y_pred = (to_csc(F.output_parameter_jacobian(q, v, z, 0.0, p0)[2]) @ predicted[:n_p])[rows]
    scale = float(mech.scales.force)
    # row by row: a local slope error in rows that move little is not hidden by the rows
    # that move most (the round-off floor 1e-12 of the force scale)
    return bool(np.all(np.abs(r_move - r_pred) <= 1e-6 * np.abs(r_pred) + 1e-12 * scale)
                and np.all(np.abs(y_move - y_pred)
                           <= 1e-6 * np.abs(y_pred) + 1e-12 * np.abs(y_move).max(initial=0.0)))
