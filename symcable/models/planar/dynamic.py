"""The planar linearised dynamics as a plain record of its formulation.

:func:`~symcable.models.planar.dynamics.build_planar_dynamics` writes the planar cable's
dynamics, linearised about its static state, as a first-order ODE

    dy/dt = f(y, t; p),        y(t) in R^n_y,

with the boundary motion already inside f (a prescribed end velocity enters as a known
function of t). This record keeps those expressions, the parameter blocks and their values,
the scales and the formulation's details; it derives and compiles nothing. Solvers never see
it: :func:`~symcable.models.planar.mechanism.mechanism_of` re-expresses it as a
:class:`~symcable.mechanism.mechanism.Mechanism` (q' = G v + w, M v' = f), and every Function a
solver calls is derived from that Mechanism, once, by :func:`symcable.mechanism.functions.functions`.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Mapping

import casadi as ca
import numpy as np


@dataclass(frozen=True, eq=False)
class DynamicModel:
    """The planar linearised dynamics (see the module docstring). Compared and hashed by
    identity (its arrays have no single truth value), so it can key a weak cache such as
    :data:`~symcable.models.planar.mechanism.MECHANISMS`.

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

    @property
    def n_y(self) -> int:
        """Number of states."""
        return int(self.y.numel())

    def with_params(self, **blocks) -> np.ndarray:
        """``p_value`` with named blocks replaced, e.g. ``with_params(amp_b=[1, 0])``."""
        p = np.array(self.p_value, dtype=float)
        for k, v in blocks.items():
            p[self.p_slices[k]] = v
        return p

