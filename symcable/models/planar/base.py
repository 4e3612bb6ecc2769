"""The interface every formulation produces, and that every solver consumes.

A solver sees only a :class:`Model`: CasADi symbols for the unknowns ``w`` and parameters
``p``, the static residual ``R(w; p)`` (every row a force, N), named outputs, scales and a
starting point. It never asks which formulation it solves.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Callable, Iterable, Mapping

import casadi as ca
import numpy as np

from ...scene import Scene


@dataclass(frozen=True)
class Guess:
    """A starting point for the static solve.

    Attributes
    ----------
    w : ndarray (n_w,)
        Unknowns.
    p : ndarray (n_p,)
        Parameters at which ``w`` is (close to) a solution. When they differ from the
        target parameters the solver may continue from ``p`` to the target.
    source : str
        Where the guess came from, e.g. ``"elastic catenary"``, for the solution's stats.
    homotopy : str
        Name of the continuation that leads from ``p`` to the target (``"bending"``,
        ``"load"``) or ``""`` when ``p`` is the target.
    """

    w: np.ndarray
    p: np.ndarray
    source: str
    homotopy: str = ""


@dataclass(frozen=True)
class Model:
    """A discretised formulation of a scene, as CasADi expressions.

    Attributes
    ----------
    name : str
        Formulation name (``"planar"``).
    scene : Scene
    terms : tuple of str
        The physics terms built for this scene, e.g. ``("elastic", "weight", "seabed")``.
    w : casadi.SX (n_w, 1)
        Static unknowns.
    p : casadi.SX (n_p, 1)
        Parameters (load factor, bending factor, end positions and angles ...).
    p_names : tuple of str
        One name per entry of ``p``.
    p_target : ndarray (n_p,)
        The parameter values of the scene itself.
    residual : casadi.SX (n_w, 1)
        Static residual, N (geometric rows are scaled by an axial stiffness over a length).
    outputs : Mapping[str, casadi.SX]
        Named expressions of ``(w, p)``; shapes are documented by the formulation.
    w_scale : ndarray (n_w,)
        Typical magnitude of each unknown, used to limit Newton steps.
    merit_weights : ndarray (n_w,)
        Row weights of the line-search merit 0.5 |diag(weights) r|^2, balancing rows whose
        units differ in meaning (geometric mismatch vs force balance).
    force_scale : float
        N, a characteristic force of the scene (weight, applied force, tension), used for
        the default residual tolerance.
    residual_floor : float
        N, the smallest residual max-norm that float64 round-off lets the equations reach;
        the default tolerance is never set below it.
    initial_guess : callable () -> iterable of Guess
        Starting points in order of preference, built lazily.
    postprocess : callable (dict of ndarray) -> dict of ndarray
        Derived quantities computed from evaluated outputs (e.g. grounded length).
    info : Mapping
        Anything else the formulation wants to expose (layout, node arc lengths, ...).
    bounds : Mapping[str, Bound]
        Admissibility conditions on ``(w, p)`` every solution is checked against
        (:class:`~symcable.mechanism.mechanism.Bound`).
    """

    name: str
    scene: Scene
    terms: tuple[str, ...]
    w: ca.SX
    p: ca.SX
    p_names: tuple[str, ...]
    p_target: np.ndarray
    residual: ca.SX
    outputs: Mapping[str, ca.SX]
    w_scale: np.ndarray
    merit_weights: np.ndarray
    force_scale: float
    residual_floor: float
    initial_guess: Callable[[], Iterable[Guess]]
    postprocess: Callable[[dict], dict]
    info: Mapping = field(default_factory=dict)
    bounds: Mapping = field(default_factory=dict)
    _cache: dict = field(default_factory=dict, repr=False, compare=False)

    @property
    def n_w(self) -> int:
        return int(self.w.numel())

    def p_with(self, **values: float) -> np.ndarray:
        """The target parameters with some entries replaced by name."""
        p = np.array(self.p_target, dtype=float)
        for k, v in values.items():
            p[self.p_names.index(k)] = v
        return p
