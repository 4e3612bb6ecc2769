"""Design optimisation on the static state with exact gradients: :func:`optimize`.

Nested: each iterate's static state is solved, and the objective's and constraints'
gradients come from :func:`~symcable.api.sensitivity.sensitivity` (the implicit function
theorem on the equations solved: one solve and one linear solve per iterate, whatever the
number of variables), or, for comparison, from central differences of whole solves (two
solves per variable per iterate, as an optimiser around a black-box solver does). SciPy's
SLSQP drives it, in variables scaled to [0, 1] by their bounds. The answer is checked
independently: its constraints are evaluated again on a fresh static solve, and a design
that violates them, or an optimiser that did not converge, is a ConvergenceError, never a
result.
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass

import numpy as np

from ..errors import ConvergenceError, SymcableError
from ..scene import load_scene
from .sensitivity import _expand, _raw, _set, sensitivity, static_values

__all__ = ["DesignResult", "optimize"]

#: a constraint counts as met within this share of its bound's magnitude (and 1e-9)
FEASIBLE = 1e-6
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
        {"OUTPUT <= bound": value} at the optimum, from a fresh static solve.
    stats : dict
        ``iterations`` (the optimiser's), ``evaluations`` (designs solved), ``solves``
        (static solves, the differences' included), ``wall_time`` (s), ``gradients``,
        ``message`` (the optimiser's).
    """

    variables: dict
    objective: float
    constraints: dict
    stats: dict


def _mass(raw: dict) -> float:
    """The lines' mass in air, kg: each section's length times its line type's mass per
    metre."""
    types = raw.get("line_types", {})
    sections = list(raw.get("sections", [])) + [s for ln in raw.get("lines", [])
                                                for s in ln.get("sections", [])]
    return float(sum(float(s["length"]) * float(types[s["type"]]["mass"]) for s in sections))


def _constraints(items) -> list:
    """[(output, sign, bound)]: sign +1 for "<=", -1 for ">="."""
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
        out.append((str(name), 1.0 if op == "<=" else -1.0, float(bound)))
    return out


class _Problem:
    """The design's evaluations, cached per point."""

    def __init__(self, raw, base, pars, lo, hi, objective, cons, gradients):
        self.raw, self.base, self.pars = raw, base, pars
        self.lo, self.hi = lo, hi
        self.objective, self.cons, self.gradients = objective, cons, gradients
        self.outputs = ([] if objective == "mass" else [objective]) + [c[0] for c in cons]
        self.cache: dict = {}
        self.solves = 0

    def scene(self, x) -> dict:
        d = self.raw
        for (_, parts, _), v in zip(self.pars, self.lo + x * (self.hi - self.lo)):
            d = _set(d, parts, float(v))
        return d

    def evaluate(self, x):
        """(values {output: value}, gradients {output: d/dx (scaled)}, mass, d mass/dx)."""
        key = tuple(np.round(x, 15))
        if key in self.cache:
            return self.cache[key]
        d = self.scene(x)
        span = self.hi - self.lo
        dm = np.array([(_mass(_set(d, p, v + 0.5)) - _mass(_set(d, p, v - 0.5))) for (_, p, _), v
                       in zip(self.pars, self.lo + x * span)]) * span
        names = list(dict.fromkeys(self.outputs))
        if self.gradients == "exact":
            s = sensitivity(d, names, [n for n, _, _ in self.pars]) if names else None
            self.solves += 1
            vals = {n: s.values[s.outputs.index(n)] for n in names} if s else {}
            grads = {n: s.jacobian[s.outputs.index(n)] * span for n in names} if s else {}
        else:
            vals = self._values(d, names)
            grads = {n: np.zeros(x.size) for n in names}
            for j, (_, parts, _) in enumerate(self.pars):
                v = self.lo[j] + x[j] * span[j]
                h = FD_STEP * max(abs(v), 1.0)
                up, dn = self._values(_set(d, parts, v + h), names), \
                    self._values(_set(d, parts, v - h), names)
                for n in names:
                    grads[n][j] = (up[n] - dn[n]) / (2 * h) * span[j]
        out = (vals, grads, _mass(d), dm)
        self.cache[key] = out
        return out

    def _values(self, d, names) -> dict:
        """The outputs of one static solve."""
        self.solves += 1
        return static_values(d, names)


def optimize(scene, variables: dict, objective="mass", constraints=(), *,
             gradients: str = "exact", tol: float = 1e-6, max_iter: int = 100,
             start=None) -> DesignResult:
    """Minimise ``objective`` over ``variables`` subject to ``constraints`` at the scene's
    static state (module docstring).

    Parameters
    ----------
    scene : path or dict
        A 3D scene (as :func:`~symcable.api.sensitivity.sensitivity` takes it).
    variables : dict
        {dotted path of a number in the scene: (lower, upper)}, in the scene's units.
    objective : str
        ``"mass"`` (the lines' mass in air, kg) or the name of a static output to minimise.
    constraints : list of (output, "<=" | ">=", bound)
        Static outputs (:func:`~symcable.api.sensitivity.sensitivity`'s names) bounded.
    gradients : str
        ``"exact"`` (the implicit function theorem) or ``"differences"`` (central
        differences of whole solves: two solves per variable per iterate).
    tol : float
        SLSQP's tolerance on the scaled problem.
    start : dict, optional
        {path: value} to start from (default: the scene's own values, clipped to the
        bounds).
    """
    started = time.perf_counter()
    if gradients not in ("exact", "differences"):
        raise SymcableError(f"gradients = {gradients!r}: must be 'exact' or 'differences'")
    if not isinstance(variables, dict) or not variables:
        raise SymcableError("variables: give {path: (lower, upper)}, at least one")
    raw, base = _raw(scene)
    pars = _expand(raw, list(variables))
    if len(pars) != len(variables):
        raise SymcableError("variables: each must name one number (a list's entry as [i])")
    lo, hi = [], []
    for name, _, _ in pars:
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
    cons = _constraints(constraints)
    load_scene(raw, base=base)  # the scene itself is valid
    prob = _Problem(raw, base, pars, lo, hi, str(objective), cons, gradients)
    first = np.array([(start or {}).get(n, v) for n, _, v in pars], float)
    x0 = np.clip((first - lo) / (hi - lo), 0.0, 1.0)
    res = _slsqp(prob, x0, tol, max_iter)
    x = np.clip(res.x, 0.0, 1.0)
    final = dict(zip([n for n, _, _ in pars], (lo + x * (hi - lo)).tolist()))
    check = _Problem(raw, base, pars, lo, hi, str(objective), cons, "differences")
    d = check.scene(x)
    vals = check._values(d, [c[0] for c in cons] + ([] if objective == "mass"
                                                    else [str(objective)]))
    report = {f"{n} {'<=' if s > 0 else '>='} {b:g}": vals[n] for n, s, b in cons}
    worst = max([s * (vals[n] - b) / max(abs(b), 1e-9) for n, s, b in cons], default=0.0)
    stats = {"iterations": int(res.nit), "evaluations": len(prob.cache),
             "solves": prob.solves + check.solves, "wall_time": time.perf_counter() - started,
             "gradients": gradients, "message": str(res.message),
             "worst_constraint": float(worst)}
    if not res.success or worst > FEASIBLE:
        raise ConvergenceError(
            f"optimize: {'no feasible design' if worst > FEASIBLE else 'not converged'} "
            f"({res.message}; worst constraint {worst:.3g} of its bound past it): check the "
            "bounds and constraints", diagnostics={"reason": "optimize", **stats,
                                                   "variables": final, "constraints": report})
    value = _mass(d) if objective == "mass" else vals[str(objective)]
    return DesignResult(final, float(value), report, stats)


def _slsqp(prob: _Problem, x0, tol, max_iter):
    from scipy.optimize import minimize

    def f(x):
        vals, grads, mass, dm = prob.evaluate(x)
        return (mass, dm) if prob.objective == "mass" else (vals[prob.objective],
                                                             grads[prob.objective])

    def g(x):  # >= 0 when met, scaled by the bound
        vals, _, _, _ = prob.evaluate(x)
        return np.array([s * (b - vals[n]) / max(abs(b), 1e-9) for n, s, b in prob.cons])

    def dg(x):
        _, grads, _, _ = prob.evaluate(x)
        return np.array([-s * grads[n] / max(abs(b), 1e-9) for n, s, b in prob.cons])

    scale = abs(f(x0)[0]) or 1.0
    cons = [{"type": "ineq", "fun": g, "jac": dg}] if prob.cons else []
    return minimize(lambda x: f(x)[0] / scale, x0, jac=lambda x: f(x)[1] / scale,
                    bounds=[(0.0, 1.0)] * x0.size, constraints=cons, method="SLSQP",
                    options={"ftol": tol, "maxiter": max_iter})
