"""Design optimisation on the static state with exact gradients: :func:`optimize`.

Nested: each iterate's static state is solved, and the objective's and constraints'
gradients come from :func:`~symcable.api.sensitivity.sensitivity` (the implicit function
theorem on the equations solved: one solve and one linear solve per iterate, whatever the
number of variables), or, for comparison, from central differences of whole solves (two
solves per variable per iterate, as an optimiser around a black-box solver does). SciPy's
SLSQP drives it, in variables scaled to [0, 1] by their bounds. Load cases (a body's
prescribed offset, a steady force) are the design's scene with some numbers set; every
constraint holds in every case unless it names one (``"CASE:OUTPUT"``). A callable scene
maps the variables to the scene's dict, so one variable may move several numbers (an
anchor's radius both its coordinates); the derivatives then run through that function too. The answer is checked
independently: its constraints are evaluated again on a fresh static solve, and a design
that violates them, or an optimiser that did not converge, is a ConvergenceError, never a
result.
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass

import numpy as np

from ..errors import ConvergenceError, SceneError, SymcableError
from ..scene import load_scene
from .sensitivity import _expand, _get, _raw, _set, _split, design_sensitivity, static_values

__all__ = ["DesignResult", "optimize"]

#: a constraint counts as met within this share of its bound's magnitude, or of one unit
#: (N, m, ...) for a bound below one (a bound of zero)
FEASIBLE = 1e-6
#: an optimiser's stop it does not call success (SLSQP's "positive directional derivative
#: for linesearch" at a kink of a piecewise-smooth output, a node touching down) is taken
#: when the design is feasible and its first-order optimality residual (:func:`_kkt`) is
#: below this
KKT_TOL = 1e-3
#: a scaled constraint (or variable, from its bound) this close counts as active (a unit:
#: its largest change over the whole range of a variable, at the start)
KKT_ACTIVE = 1e-5
#: the gradient scaling's floor, over the function's magnitude (its bound's, its value's
#: or 1): a gradient of round-off does not blow the function up
SCALE_FLOOR = 1e-8
#: SLSQP's restarts from its answer, at a thousandth of the tolerance, when it stopped on the
#: objective's change just outside an active constraint's bound
POLISH = 2
#: central differences of whole solves (``gradients = "differences"``): relative step
FD_STEP = 1e-4


@dataclass(frozen=True)
class DesignResult:
    """The optimum of :func:`optimize`.

    Attributes
    ----------
    variables : dict
        {path: value} at the optimum, in the scene's units.
    objective : float
        The objective there (kg for ``"mass"``, else the output's unit).
    constraints : dict
        {"OUTPUT <= bound": value} at the optimum, from a fresh static solve (with several
        load cases ``"CASE:OUTPUT <= bound"``, one entry per case).
    stats : dict
        ``iterations`` (the optimiser's), ``evaluations`` (designs solved), ``solves``
        (static solves, the differences' included), ``wall_time`` (s), ``gradients``,
        ``message`` (the optimiser's), ``kkt_residual`` (the first-order optimality
        residual at the optimum, relative), ``worst_constraint`` (the largest violation at the
        optimum over its bound's magnitude, or 1 unit), ``history`` ([(objective, worst
        violation, solves so far)] of each design evaluated, in order).
    """

    variables: dict
    objective: float
    constraints: dict
    stats: dict


def _mass(raw: dict, base) -> float:
    """The lines' mass in air, kg: each section's length times its line type's mass per
    metre (a family's from its diameter)."""
    scene = load_scene(raw, base=base)
    sections = list(scene.sections) + [s for ln in scene.lines for s in ln.sections]
    return float(sum(s.length * s.line_type.mass for s in sections))


def _constraints(items, cases) -> list:
    """[(case or None, output, sign, bound)]: sign +1 for "<=", -1 for ">="; ``"CASE:NAME"``
    names one load case, a bare name every case."""
    out = []
    for item in items:
        try:
            name, op, bound = item
        except (TypeError, ValueError):
            raise SymcableError(f"constraint {item!r}: must be (output, '<=' or '>=', number)"
                                ) from None
        if op not in ("<=", ">=") or not isinstance(bound, (int, float)) \
                or not math.isfinite(bound):
            raise SymcableError(f"constraint {item!r}: must be (output, '<=' or '>=', a finite "
                                "number)")
        case, output = _case_of(str(name), cases)
        out.append((case, output, 1.0 if op == "<=" else -1.0, float(bound)))
    return out


def _case_of(name: str, cases) -> tuple:
    """(case or None, output) of ``"CASE:OUTPUT"`` or ``"OUTPUT"``."""
    case, sep, output = name.partition(":")
    if not sep:
        return None, name
    if case not in cases:
        raise SymcableError(f"{name!r}: no load case {case!r} (the cases: "
                            f"{', '.join(map(repr, cases))})")
    return case, output


def _apply(raw: dict, changes: dict) -> dict:
    """``raw`` with a load case's {dotted path: value} set (the last key may be new: a
    point's ``force`` where it had none)."""
    for path, value in changes.items():
        parts = _split(str(path))
        try:
            parent = _get(raw, parts[:-1], path) if len(parts) > 1 else raw
        except SymcableError:
            raise SymcableError(f"load case path {path!r}: the scene has no "
                                f"{'.'.join(map(str, parts[:-1]))!r}") from None
        if not isinstance(parent, (dict, list)) or (isinstance(parent, list)
                                                     and not (isinstance(parts[-1], int)
                                                              and parts[-1] < len(parent))):
            raise SymcableError(f"load case path {path!r}: names no key of a table")
        raw = _set(raw, parts, value)
    return raw


class _Problem:
    """The design's evaluations over its load cases, cached per point."""

    def __init__(self, make, base, names, lo, hi, objective, cons, cases, gradients):
        self.make, self.base, self.names = make, base, names
        self.lo, self.hi, self.cases = lo, hi, cases
        self.objective, self.cons, self.gradients = objective, cons, gradients
        wanted = ([] if objective == "mass" else [_case_of(objective, cases)]) + \
            [(c, n) for c, n, _, _ in cons]
        self.outputs = {case: list(dict.fromkeys(n for c, n in wanted if c in (None, case)))
                        for case in cases}
        self.cache: dict = {}
        self.solves = 0
        self.history: list = []
        #: each case's last static state (q, z, p): the next design's solves start from it
        self.state: dict = {}
        self.warm = True

    def values(self, x) -> np.ndarray:
        return self.lo + np.asarray(x, float) * (self.hi - self.lo)

    def scene(self, values, case=None) -> dict:
        """The scene's dict at the variables' ``values`` (in the load case ``case``)."""
        raw = self.make(dict(zip(self.names, (float(v) for v in values))))
        return raw if case is None else _apply(raw, self.cases[case])

    def evaluate(self, x):
        """(values {(case, output): value}, gradients {(case, output): d/dx (scaled)}, mass,
        d mass/dx)."""
        key = tuple(np.round(x, 15))
        if key not in self.cache:
            try:
                self.cache[key] = out = self._evaluate(x)
            except SceneError as exc:
                raise SymcableError(
                    f"optimize: the design {dict(zip(self.names, self.values(x).tolist()))} "
                    f"is refused by the scene ({exc}): every design within the bounds must "
                    "be one the scene takes; narrow the bounds (or make a callable scene "
                    "keep the lines long enough)") from None
            vals = out[0]
            f = out[2] if self.objective == "mass" else vals[_case_of(self.objective,
                                                                      self.cases)]
            worst = max([sg * (vals[(c, n)] - b) / max(abs(b), 1.0) for c, n, sg, b
                         in self.rows()], default=0.0)
            self.history.append((float(f), float(worst), self.solves))
        return self.cache[key]

    def _evaluate(self, x):
        v0, span = self.values(x), self.hi - self.lo
        dm = np.zeros(x.size)
        for j in range(x.size):
            up, dn, h = self._probe(v0, j, FD_STEP * 1e-2 * max(abs(v0[j]), 1e-3))
            dm[j] = (_mass(self.scene(up), self.base) - _mass(self.scene(dn), self.base)) \
                / h * span[j]
        vals, grads, slopes = {}, {}, None
        for case, names in self.outputs.items():
            if not names:
                continue
            if self.gradients == "exact":
                def at(j, v, case=case):
                    w = v0.copy()
                    w[j] = v
                    return self.scene(w, case)
                s = design_sensitivity(self.scene(v0, case), self.base, names, self.names, v0,
                                       [lambda v, j=j: at(j, v) for j in range(x.size)],
                                       reuse=slopes,
                                       raw_of=lambda w, case=case: self.scene(w, case),
                                       start=self.state.get(case))
                slopes, self.state[case] = s.stats["slopes"], s.stats["state"]
                self.solves += 1
                for i, n in enumerate(s.outputs):
                    vals[(case, n)], grads[(case, n)] = s.values[i], s.jacobian[i] * span
                continue
            here = self._values(self.scene(v0, case), names, self.state.get(case))
            self.state[case] = here.pop("state")
            for n, value in here.items():
                vals[(case, n)], grads[(case, n)] = value, np.zeros(x.size)
            for j in range(x.size):
                up, dn, h = self._probe(v0, j, FD_STEP * max(abs(v0[j]), 1.0))
                a = self._values(self.scene(up, case), names, self.state[case]) \
                    if up[j] != v0[j] else here
                b = self._values(self.scene(dn, case), names, self.state[case]) \
                    if dn[j] != v0[j] else here
                for n in here:
                    grads[(case, n)][j] = (a[n] - b[n]) / h * span[j]
        return vals, grads, _mass(self.scene(v0), self.base), dm

    def _probe(self, v0, j, h):
        """(up, down, their distance) of a difference in variable j by h that stays within
        the bounds: central inside, one-sided at a bound."""
        up, dn = v0.copy(), v0.copy()
        up[j] = min(v0[j] + h, self.hi[j])
        dn[j] = max(v0[j] - h, self.lo[j])
        if up[j] == dn[j]:
            raise SymcableError(f"variables[{self.names[j]!r}]: its bounds are closer than "
                                f"the difference step {h:.3g}")
        return up, dn, up[j] - dn[j]

    def _values(self, d, names, start=None) -> dict:
        """The outputs of one static solve (from ``start``, (q, z, p) of a nearby design's
        state, when given; its own state then as ``"state"``)."""
        self.solves += 1
        if start is None and self.warm:
            start = (np.zeros(0), np.zeros(0))  # no state yet: the Mechanism's own starts
        out = static_values(d, names, start=start) if start is not None \
            else static_values(d, names)
        return out

    def rows(self):
        """Each constraint in each case it applies to: [(case, output, sign, bound)]."""
        return [(case, n, sg, b) for c, n, sg, b in self.cons
                for case in self.cases if c in (None, case)]


def optimize(scene, variables: dict, objective="mass", constraints=(), *, cases=None,
             gradients: str = "exact", tol: float = 1e-6, max_iter: int = 100,
             start=None) -> DesignResult:
    """Minimise ``objective`` over ``variables`` subject to ``constraints`` at the scene's
    static state in each load case (module docstring).

    Parameters
    ----------
    scene : path, dict, Scene, or callable
        A 3D scene (as :func:`~symcable.api.sensitivity.sensitivity` takes it); or a
        function of the variables ({name: value}) that returns the scene's dict, for
        variables that move several numbers (an anchor's radius, one diameter for every
        line).
    variables : dict
        {name: (lower, upper)}, in the scene's units: a dotted path of a number in the scene
        (``"line_types.chain.nominal_diameter"``), or with a callable scene its argument's
        names.
    objective : str
        ``"mass"`` (the lines' mass in air, kg) or the name of a static output to minimise
        (``"CASE:OUTPUT"`` for a load case's; a bare name is the first case's).
    constraints : list of (output, "<=" | ">=", bound)
        Static outputs (:func:`~symcable.api.sensitivity.sensitivity`'s names, with
        ``"LINE.fairlead_utilisation"`` for tension over breaking load and
        ``"LINE.anchor_uplift"``) bounded: in every load case, or ``"CASE:OUTPUT"`` in one.
    cases : dict, optional
        The load cases: {name: {dotted path: value}}, each set on the design's scene (a
        body's offset ``"bodies.hull.position"``, a steady force ``"points.buoy.force"``);
        default one case, the scene as it is.
    gradients : str
        ``"exact"`` (the implicit function theorem) or ``"differences"`` (central
        differences of whole solves: two solves per variable per case per iterate).
    tol : float
        SLSQP's tolerance on the scaled problem.
    start : dict, optional
        {name: value} to start from (default: the scene's own values, or with a callable
        scene the bounds' midpoints; clipped to the bounds).
    """
    started = time.perf_counter()
    if gradients not in ("exact", "differences"):
        raise SymcableError(f"gradients = {gradients!r}: must be 'exact' or 'differences'")
    if not isinstance(variables, dict) or not variables:
        raise SymcableError("variables: give {name: (lower, upper)}, at least one")
    cases = {"base": {}} if cases is None else cases
    if not isinstance(cases, dict) or not cases or not all(
            isinstance(c, dict) for c in cases.values()):
        raise SymcableError("cases: give {name: {dotted path: value}}, at least one")
    names, lo, hi = list(variables), [], []
    for name in names:
        try:
            a, b = (float(v) for v in variables[name])
        except (TypeError, ValueError):
            raise SymcableError(f"variables[{name!r}] = {variables[name]!r}: must be (lower, "
                                "upper)") from None
        if not (math.isfinite(a) and math.isfinite(b) and a < b):
            raise SymcableError(f"variables[{name!r}] = {variables[name]!r}: must be finite "
                                "with lower < upper")
        lo.append(a), hi.append(b)
    lo, hi = np.array(lo), np.array(hi)
    make, base, own = _maker(scene, names, lo, hi)
    unknown = sorted(set(start or {}) - set(names))
    if unknown:
        raise SymcableError(f"start: {unknown[0]!r} is not a variable (the variables: "
                            f"{', '.join(map(repr, names))})")
    first = np.clip([(start or {}).get(n, own[n]) for n in names], lo, hi)
    for case in cases:  # every case's scene is valid at the start
        try:
            load_scene(_apply(make(dict(zip(names, first))), cases[case]), base=base)
        except SceneError as exc:
            raise SymcableError(f"optimize: the design {dict(zip(names, first.tolist()))} "
                                f"(the start) is refused by the scene ({exc})") from None
    cons = _constraints(constraints, cases)
    if objective != "mass":
        _case_of(str(objective), cases)
    objective = str(objective) if objective == "mass" or ":" in str(objective) \
        else f"{next(iter(cases))}:{objective}"
    prob = _Problem(make, base, names, lo, hi, objective, cons, cases, gradients)
    x0 = (first - lo) / (hi - lo)
    res = _slsqp(prob, x0, tol, max_iter)
    for _ in range(POLISH):  # stopped on the objective a hair outside an active bound
        if not FEASIBLE < _violation(prob, np.clip(res.x, 0.0, 1.0)) <= 1e-3:
            break
        again = _slsqp(prob, np.clip(res.x, 0.0, 1.0), tol * 1e-3, max_iter)
        again.nit += res.nit
        res = again
    x = np.clip(res.x, 0.0, 1.0)
    final = dict(zip(names, prob.values(x).tolist()))
    check = _Problem(make, base, names, lo, hi, objective, cons, cases, "differences")
    check.warm = False  # the answer's check solves from the Mechanism's own starts
    vals = {}
    for case, outs in check.outputs.items():
        if outs:
            vals.update({(case, n): v for n, v in
                         check._values(check.scene(prob.values(x), case), outs).items()})
    tag = (lambda c: f"{c}:") if len(cases) > 1 else (lambda c: "")
    report = {f"{tag(c)}{n} {'<=' if s > 0 else '>='} {b:g}": vals[(c, n)]
              for c, n, s, b in prob.rows()}
    worst = max([s * (vals[(c, n)] - b) / max(abs(b), 1.0) for c, n, s, b in prob.rows()],
                default=0.0)
    stats = {"iterations": int(res.nit), "evaluations": len(prob.cache),
             "solves": prob.solves + check.solves, "wall_time": time.perf_counter() - started,
             "gradients": gradients, "message": str(res.message),
             "worst_constraint": float(worst), "history": prob.history}
    stats["kkt_residual"] = res.kkt
    if worst > FEASIBLE or (not res.success and res.kkt > KKT_TOL):
        raise ConvergenceError(
            f"optimize: {'no feasible design' if worst > FEASIBLE else 'not converged'} "
            f"({res.message}; worst constraint {worst:.3g} of its bound past it; optimality "
            f"residual {res.kkt:.3g}): check the "
            "bounds and constraints", diagnostics={"reason": "optimize", **stats,
                                                   "variables": final, "constraints": report})
    value = _mass(check.scene(prob.values(x)), base) if objective == "mass" \
        else vals[_case_of(objective, cases)]
    return DesignResult(final, float(value), report, stats)


def _violation(prob: _Problem, x) -> float:
    """The largest constraint violation at ``x`` over its bound's magnitude (or one unit),
    0 when every constraint holds."""
    vals = prob.evaluate(x)[0]
    return max([max(s * (vals[(c, n)] - b) / max(abs(b), 1.0), 0.0)
                for c, n, s, b in prob.rows()], default=0.0)


def _maker(scene, names, lo, hi):
    """(make({name: value}) -> the scene's dict, the folder its files are relative to, the
    variables' own values)."""
    if callable(scene) and not isinstance(scene, (str, dict)):
        def make(values):
            raw = scene(dict(values))
            if not isinstance(raw, dict):
                raise SymcableError(f"scene(...) returned {type(raw).__name__}: a callable "
                                    "scene must return the scene's dict")
            return raw
        return make, None, dict(zip(names, (0.5 * (lo + hi)).tolist()))
    raw, base = _raw(scene)
    pars = _expand(raw, names)
    if len(pars) != len(names):
        raise SymcableError("variables: each must name one number (a list's entry as [i])")

    def make(values):
        d = raw
        for (name, parts, _) in pars:
            d = _set(d, parts, float(values[name]))
        return d
    return make, base, {n: v for n, _, v in pars}


def _slsqp(prob: _Problem, x0, tol, max_iter):
    """SciPy's SLSQP on the scaled variables; the objective and each constraint divided by
    the largest entry of its gradient at the start (gradient-based scaling, here to a
    largest entry of 1, floored at SCALE_FLOOR of the function's size), so that a force
    bounded near zero weighs as much as a utilisation."""
    from scipy.optimize import minimize
    rows = prob.rows()

    def f(x):
        vals, grads, mass, dm = prob.evaluate(x)
        key = _case_of(prob.objective, prob.cases) if prob.objective != "mass" else None
        return (mass, dm) if key is None else (vals[key], grads[key])

    vals0, grads0, _, _ = prob.evaluate(x0)
    scale = np.array([max(np.max(np.abs(grads0[(c, n)])),
                          SCALE_FLOOR * max(abs(b), abs(vals0[(c, n)]), 1.0))
                      for c, n, _, b in rows])

    def g(x):  # >= 0 when met
        vals, _, _, _ = prob.evaluate(x)
        return np.array([s * (b - vals[(c, n)]) for c, n, s, b in rows]) / scale

    def dg(x):
        _, grads, _, _ = prob.evaluate(x)
        return np.array([-s * grads[(c, n)] for c, n, s, b in rows]) / scale[:, None]

    fscale = max(np.max(np.abs(f(x0)[1])), SCALE_FLOOR * max(abs(f(x0)[0]), 1.0))
    cons = [{"type": "ineq", "fun": g, "jac": dg}] if rows else []
    res = minimize(lambda x: f(x)[0] / fscale, x0, jac=lambda x: f(x)[1] / fscale,
                   bounds=[(0.0, 1.0)] * x0.size, constraints=cons, method="SLSQP",
                   options={"ftol": tol, "maxiter": max_iter})
    x = np.clip(res.x, 0.0, 1.0)
    res.kkt = _kkt(f(x)[1] / fscale, g(x) if rows else np.zeros(0),
                   dg(x) if rows else np.zeros((0, x.size)), x)
    return res


def _kkt(gf, c, dc, x) -> float:
    """The first-order optimality residual at ``x`` (scaled variables in [0, 1]):
    |grad f - sum lambda_i grad c_i| / |grad f| with lambda >= 0 by non-negative least
    squares over the active constraints c_i >= 0 (``c``, ``dc``: the constraints and their
    gradients; the bounds added), an independent check of the optimiser's stop."""
    from scipy.optimize import nnls
    cols = [dc[i] for i in range(c.size) if c[i] <= KKT_ACTIVE]
    cols += [np.eye(x.size)[j] for j in range(x.size) if x[j] <= KKT_ACTIVE]
    cols += [-np.eye(x.size)[j] for j in range(x.size) if x[j] >= 1.0 - KKT_ACTIVE]
    norm = float(np.linalg.norm(gf)) or 1.0
    if not cols:
        return float(np.linalg.norm(gf)) / norm
    A = np.column_stack(cols)
    lam, r = nnls(A, np.asarray(gf, float))
    # complementarity: a multiplier on a constraint short of its bound counts against
    slack = np.array([c[i] for i in range(c.size) if c[i] <= KKT_ACTIVE]
                     + [x[j] for j in range(x.size) if x[j] <= KKT_ACTIVE]
                     + [1.0 - x[j] for j in range(x.size) if x[j] >= 1.0 - KKT_ACTIVE])
    return float(r + np.sum(lam * np.abs(slack) * np.linalg.norm(A, axis=0))) / norm
