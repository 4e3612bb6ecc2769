"""Turning a Model into named CasADi Functions, built once per model and reused."""
from __future__ import annotations

from dataclasses import dataclass, field

import casadi as ca

from .models.base import Model


@dataclass(frozen=True)
class StaticFunctions:
    """The static problem's functions.

    Attributes
    ----------
    residual : casadi.Function  ``static_residual(w, p) -> r`` (N)
    jacobian : casadi.Function  ``static_jacobian(w, p) -> (r, J)``; J sparse, N per unit of w
    step : casadi.Function      ``static_newton_step(w, p) -> (r, dw)``, dw = -J^-1 r by
        sparse LU (CSparse) inside CasADi, so one call per Newton iteration
    outputs : casadi.Function   ``static_outputs(w, p) -> named outputs of the model``
    """

    def rootfinder(self, tol: float, max_iter: int) -> ca.Function:
        """Plain Newton inside CasADi (no globalisation): ``static_rootfinder(w0, p) -> w``,
        one call for the whole iteration. Built once per (tol, max_iter)."""
        key = (tol, max_iter)
        if key not in self._rootfinders:
            self._rootfinders[key] = ca.rootfinder(
                "static_rootfinder", "newton", self.residual,
                {"abstol": tol, "max_iter": max_iter, "linear_solver": "csparse",
                 "error_on_fail": False})
        return self._rootfinders[key]

    residual: ca.Function
    jacobian: ca.Function
    step: ca.Function
    outputs: ca.Function
    _rootfinders: dict = field(default_factory=dict, repr=False, compare=False)


def static_functions(model: Model) -> StaticFunctions:
    """Build (once, then cached on the model) the named static functions of ``model``."""
    cached = model._cache.get("static")
    if cached is not None:
        return cached
    w, p, r = model.w, model.p, model.residual
    residual = ca.Function("static_residual", [w, p], [r], ["w", "p"], ["r"])
    J = ca.jacobian(r, w)
    jacobian = ca.Function("static_jacobian", [w, p], [r, J], ["w", "p"], ["r", "J"])
    W = ca.MX.sym("w", w.sparsity())
    P = ca.MX.sym("p", p.sparsity())
    rm, Jm = jacobian(W, P)
    dw = -ca.solve(Jm, rm, "csparse")
    step = ca.Function("static_newton_step", [W, P], [rm, dw], ["w", "p"], ["r", "dw"])
    names = list(model.outputs)
    outputs = ca.Function("static_outputs", [w, p], [model.outputs[k] for k in names],
                          ["w", "p"], names)
    fns = StaticFunctions(residual=residual, jacobian=jacobian, step=step, outputs=outputs)
    model._cache["static"] = fns
    return fns
