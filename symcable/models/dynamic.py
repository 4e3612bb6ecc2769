"""The interface of a semi-discrete dynamic model, as every time or periodic solver sees it.

A formulation turns a scene and its static solution into an ODE in first-order form,

    dy/dt = f(y, t; p),        y(t) in R^n_y,

with the boundary motion already inside f (a prescribed end velocity enters as a known
function of t). Its DAE form, F(y', y, t; p) = y' - f(y, t; p) = 0, is
:meth:`DynamicModel.residual`. Solvers never ask which formulation they integrate.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Mapping

import casadi as ca
import numpy as np


@dataclass(frozen=True)
class DynamicModel:
    """A semi-discrete dynamic model.

    Attributes
    ----------
    name : str
        Formulation name, e.g. ``"planar"``.
    y : casadi.SX (n_y, 1)
        State (for the planar cable: node velocities in the static node frame, m/s, then
        segment dynamic strain and angle, - and rad).
    t : casadi.SX (1, 1)
        Time, s.
    p : casadi.SX (n_p, 1)
        Parameters (static state the model is linearised about, excitation, current).
    p_value : ndarray (n_p,)
        The scene's parameter values for a run from rest (with any start-up ramp).
    p_periodic : ndarray (n_p,)
        The parameter values of the periodic steady state (no start-up ramp).
    p_undamped : ndarray (n_p,)
        Parameters of the undamped, unforced linear model about rest (no excitation, no
        current, no constraint stabilisation), for modal analysis.
    p_names : tuple of str
        Name of each block of ``p`` (see ``p_slices``).
    p_slices : Mapping[str, slice]
        Where each named block sits in ``p``.
    rhs : casadi.SX (n_y, 1)
        f(y, t; p), units of y per second.
    outputs : Mapping[str, casadi.SX]
        Named expressions of (y, t, p): at least ``fairlead_tension`` (N, scalar).
    y_scale : ndarray (n_y,)
        Typical magnitude of each state entry (for error norms and Newton steps).
    period : float or None
        Period of the excitation, s (None when nothing moves).
    y0 : ndarray (n_y,)
        The rest state (the static solution), normally zeros.
    info : Mapping
        Formulation details (layout, masses, static solution ...).
    """

    name: str
    y: ca.SX
    t: ca.SX
    p: ca.SX
    p_value: np.ndarray
    p_periodic: np.ndarray
    p_undamped: np.ndarray
    p_names: tuple
    p_slices: Mapping[str, slice]
    rhs: ca.SX
    outputs: Mapping[str, ca.SX]
    y_scale: np.ndarray
    period: float | None
    y0: np.ndarray
    info: Mapping = field(default_factory=dict)
    _cache: dict = field(default_factory=dict, repr=False, compare=False)

    @property
    def n_y(self) -> int:
        return int(self.y.numel())

    def residual(self, ydot: ca.SX) -> ca.SX:
        """DAE residual F(y', y, t; p) = y' - f(y, t; p)."""
        return ydot - self.rhs

    def functions(self, codegen: bool | None = False) -> "DynamicFunctions":
        """Named CasADi functions of this model, built once: run by the virtual machine,
        or compiled to C when ``codegen`` resolves to True
        (:func:`symcable.codegen.use_codegen`; ``dyn_rhs`` then carries its compiled
        Jacobian, so graphs built on it, such as the periodic systems, differentiate it in C)."""
        fns = self._cache.get("functions")
        if fns is None:
            y, t, p = self.y, self.t, self.p
            rhs = ca.Function("dyn_rhs", [y, t, p], [self.rhs], ["y", "t", "p"], ["ydot"])
            from ..linalg.sparse import jacobian  # O(n) with the dense closure rows
            jac = ca.Function("dyn_rhs_jac", [y, t, p], [jacobian(self.rhs, y)],
                              ["y", "t", "p"], ["dfdy"])
            names = list(self.outputs)
            out = ca.Function("dyn_outputs", [y, t, p], [self.outputs[k] for k in names],
                              ["y", "t", "p"], names)
            fns = DynamicFunctions(rhs=rhs, rhs_jacobian=jac, outputs=out)
            self._cache["functions"] = fns
        from ..codegen import compile_functions, graph_size, use_codegen
        def size():
            if "graph_size" not in self._cache:
                self._cache["graph_size"] = graph_size([fns.rhs, fns.rhs_jacobian, fns.outputs])
            return self._cache["graph_size"]
        if not use_codegen(codegen, size):
            return fns
        c = self._cache.get("functions_c")
        if c is None:
            rhs = compile_functions([fns.rhs], jacobians=True, what="the dynamics")["dyn_rhs"]
            lib = compile_functions([fns.rhs_jacobian, fns.outputs], what="the dynamics' outputs")
            c = self._cache["functions_c"] = DynamicFunctions(
                rhs=rhs, rhs_jacobian=lib["dyn_rhs_jac"], outputs=lib["dyn_outputs"], compiled=True)
        return c

    def with_params(self, **blocks) -> np.ndarray:
        """``p_value`` with named blocks replaced, e.g. ``with_params(amplitude=[1, 0])``."""
        p = np.array(self.p_value, dtype=float)
        for k, v in blocks.items():
            p[self.p_slices[k]] = v
        return p


@dataclass(frozen=True)
class DynamicFunctions:
    """``dyn_rhs(y, t, p) -> ydot``; ``dyn_rhs_jac(y, t, p) -> dfdy`` (sparse);
    ``dyn_outputs(y, t, p) -> named outputs``."""

    rhs: ca.Function
    rhs_jacobian: ca.Function
    outputs: ca.Function
    compiled: bool = False
