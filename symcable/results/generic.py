"""Results of the generic solvers on any Mechanism: the state, its named outputs and, per part,
the outputs that part owns (``result.part("line1")["end_b_force"]``)."""
from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..errors import SymcableError
from .io import force_text, force_unit
from .static import Exportable

__all__ = ["Equilibrium", "Linearization", "MechanismModes", "MechanismTrajectory",
           "SceneLinearization"]


class _Outputs(Exportable):
    """Outputs are a dict name -> array; ``part(name)`` strips the ``name.`` prefix."""

    def part(self, name: str) -> dict:
        """The outputs of part ``name``, keyed without the ``name.`` prefix."""
        pre = name + "."
        found = {k[len(pre):]: v for k, v in self.outputs.items() if k.startswith(pre)}
        if not found:
            parts = sorted({k.split(".", 1)[0] for k in self.outputs if "." in k})
            raise SymcableError(f"part = {name!r}: no outputs (parts: {', '.join(parts) or 'none'})")
        return found

    def plot(self, path: str | Path | None = None, *, mechanism=None, **options):
        """Draw the state in space: a 3D view with plan (x-y) and elevation (x-z)
        projections (dim = 3) or the elevation (dim = 2), every part in its own colour;
        saved to ``path`` when given. ``mechanism``: the Mechanism this result belongs to
        (or its Layout), which says which coordinates are which node. ``options``: those of
        :func:`symcable.plotting.view3d.plot_mechanism` (``seabed``, ``surface``, ``title``;
        a time history also ``times``, ``snapshots``, ``envelope``: snapshots fading from
        early to late, or every node's path). Returns the matplotlib Figure."""
        from ..plotting.view3d import plot_mechanism
        if mechanism is None:
            raise SymcableError("mechanism = None: give the Mechanism this result belongs to "
                                "(or its Layout): it says which coordinates are which node")
        return plot_mechanism(self, mechanism, path, **options)

    @classmethod
    def load(cls, path: str | Path):
        obj = super().load(path)
        outs = {k: np.asarray(v, dtype=float) for k, v in (obj.outputs or {}).items()}
        object.__setattr__(obj, "outputs", outs)
        return obj


@dataclass(frozen=True)
class Equilibrium(_Outputs):
    """A static equilibrium of a Mechanism.

    Attributes
    ----------
    mechanism : str
    q : ndarray (n_q,)    coordinates, m (rad)
    z : ndarray (n_z,)    constraint forces, N
    p : ndarray (n_p,)    the parameters solved for
    outputs : dict name -> ndarray, in the units the Mechanism's outputs state
    status : str          ``"converged"`` (every check passed) or ``"failed"`` (partial result)
    stats : dict          ``iterations``, ``residual_norm`` (N), ``tolerance`` (N), ``path``,
                          ``start``, ``attempts``, ``stable``, ``min_stiffness`` (N/m: the
                          smallest eigenvalue of the reduced tangent stiffness), ``wall_time`` (s)
    warnings : tuple of str
    """

    mechanism: str
    q: np.ndarray
    z: np.ndarray
    p: np.ndarray
    outputs: dict
    status: str
    stats: dict = field(default_factory=dict)
    warnings: tuple = ()

    def __repr__(self) -> str:
        return (f"Equilibrium({self.mechanism!r}, status={self.status!r}, n_q={self.q.size}, "
                f"n_z={self.z.size}, residual={self.stats.get('residual_norm', float('nan')):.3g} N)")


@dataclass(frozen=True)
class MechanismTrajectory(_Outputs):
    """A time history of a Mechanism.

    Attributes
    ----------
    mechanism : str
    time : ndarray (n_t,), s
    q : ndarray (n_t, n_q);  v : ndarray (n_t, n_v);  z : ndarray (n_t, n_z)
    outputs : dict name -> ndarray (n_t, ...)
    status : str     ``"converged"`` (every step's Newton iteration converged) or ``"failed"``
    stats : dict     ``method``, ``dt`` (s), ``steps``, ``newton_iterations`` (total) and
                     ``newton_iterations_max`` (per step; first-order generalized-alpha),
                     ``max_constraint`` (max |g| over the saved steps), ``wall_time`` (s),
                     ``error_estimate`` (generalized-alpha: the estimated error of the run
                     relative to the range of its motion); see :func:`symcable.integrate`
                     for the rest
    warnings : tuple of str  (with one when ``error_estimate`` exceeds 1 %)
    """

    mechanism: str
    time: np.ndarray
    q: np.ndarray
    v: np.ndarray
    z: np.ndarray
    outputs: dict
    status: str
    stats: dict = field(default_factory=dict)
    warnings: tuple = ()

    def __repr__(self) -> str:
        return (f"MechanismTrajectory({self.mechanism!r}, status={self.status!r}, "
                f"{self.time.size} samples over {self.time[-1] - self.time[0]:.4g} s)")


@dataclass(frozen=True)
class MechanismModes(Exportable):
    """Natural modes about an equilibrium (zero-frequency rigid modes left out).

    Attributes
    ----------
    frequencies : ndarray (k,)   Hz (undamped natural frequencies, ascending)
    shapes : ndarray (k, n_q)    mode shapes in q, each scaled to max |entry| = 1, that entry
                                 positive
    damping_ratios : ndarray (k,) or None (with ``damped=True``: from the complex modes)
    stats : dict                 ``method`` (``"symmetric (K G, M)"`` or ``"state matrix"``),
                                 ``state_size`` (n_q + n_v), ``free_velocities``,
                                 ``constraints``, ``zero_modes`` (rigid modes left out),
                                 ``zero_eigenvalues`` (of the undamped state matrix in q and
                                 the free velocities: invariants and rigid modes),
                                 ``zero_tolerance`` (1/s), ``max_relative_real_part``,
                                 ``linearize_time``, ``eig_time`` (s)
    velocity_shapes : ndarray (k, n_v)
        The same modes as displacements u in the velocity coordinates (u' = v, so
        ``shapes = u G^T``), scaled by the same factors as ``shapes``.
    real_parts : ndarray (k,)   1/s: the eigenvalues' real parts (zero for the symmetric
                                problem)
    warnings : tuple of str
    """

    mechanism: str
    frequencies: np.ndarray
    shapes: np.ndarray
    damping_ratios: np.ndarray | None = None
    stats: dict = field(default_factory=dict)
    velocity_shapes: np.ndarray | None = None
    real_parts: np.ndarray | None = None
    warnings: tuple = ()

    @property
    def periods(self) -> np.ndarray:
        """s"""
        return 1.0 / self.frequencies


@dataclass(frozen=True)
class Linearization(Exportable):
    """The exact linearisation about an equilibrium: dq' = G dv + H dq,
    M dv' + C dv + K dq = B_p dp.

    Attributes
    ----------
    K : ndarray (n_q, n_q)  N/m, -df/dq (constraint forces held at their equilibrium values)
    C : ndarray (n_v, n_v)  N s/m, -df/dv
    M : ndarray (n_v, n_v)  kg
    B : ndarray (n_z, n_q)  dg/dq (constraint Jacobian)
    q, z, p : the equilibrium
    G : ndarray (n_q, n_v)  d(q')/dv of the kinematics (the identity without kinematics)
    H : ndarray (n_q, n_q)  d(q')/dq at rest, 1/s (zero without kinematics)
    """

    mechanism: str
    K: np.ndarray
    C: np.ndarray
    M: np.ndarray
    B: np.ndarray
    q: np.ndarray
    z: np.ndarray
    p: np.ndarray
    stats: dict = field(default_factory=dict)
    G: np.ndarray | None = None
    H: np.ndarray | None = None


@dataclass(frozen=True)
class SceneLinearization(Exportable):
    """The exact linearisation of a scene's dynamics about its static state, as a first-order
    system in the coordinates q and velocities v of its dynamics Mechanism:

        dq/dt = H q + G v,        M dv/dt = -K q - C v        (+ excitation)

    For the planar line, q are the segment strain and angle increments (1, rad) and v the
    node velocities in the static node frames (m/s); ``q_kinds``/``v_kinds`` name each entry.

    Attributes
    ----------
    scene_name : str
    K : ndarray (n_v, n_q)   N per unit of q: -df/dq
    C : ndarray (n_v, n_v)   N s/m: -df/dv (drag linearised about the current, if any)
    M : ndarray (n_v, n_v)   kg (with added mass)
    G : ndarray (n_q, n_v)   d(q')/dv, 1/m or 1/s per m/s
    H : ndarray (n_q, n_q)   d(q')/dq, 1/s (the closure stabilisation, when on)
    q_kinds, v_kinds : tuple of str
    end_stiffness : dict  end ("a"/"b") -> (2, 2) N/m, -dF/dx of the force the line exerts
        on that pinned end against its position, exact (statics)
    undamped : bool  True when current, excitation and stabilisation were off (as in
        ``modal_analysis``)
    body_stiffness : dict  body name -> (6, 6): the mooring stiffness of each free body, in
        (translation of its reference point, m; small rotation about global axes, rad)
        against (force, N; moment about the reference point, N m), global axes: -d(net
        force and moment)/d(pose) with everything else in static equilibrium (the lines and
        other free parts condensed out), the body's own weight and buoyancy included; exact
        (:func:`symcable.api.cable3d_static.body_stiffness`)
    """

    scene_name: str
    K: np.ndarray
    C: np.ndarray
    M: np.ndarray
    G: np.ndarray
    H: np.ndarray
    q_kinds: tuple
    v_kinds: tuple
    end_stiffness: dict
    undamped: bool = False
    body_stiffness: dict = field(default_factory=dict)

    def summary(self) -> str:
        """The sizes, each held end's or point's stiffness matrix (rows as printed; N/m, kN/m
        or MN/m by its size) and each free body's 6 x 6 mooring stiffness diagonal."""
        out = [f"scene             {self.scene_name}",
               f"linearisation     n_q = {self.K.shape[1]}, n_v = {self.K.shape[0]}"
               + (" (undamped: current, excitation and stabilisation off)" if self.undamped
                  else "")]
        for name, k in self.end_stiffness.items():
            k = np.atleast_2d(np.asarray(k, float))
            k_n, unit = force_unit(k, "N/m")
            label = f"end {name}" if name in ("a", "b") else f"point {name}"
            rows = "; ".join(" ".join(f"{v:.5g}" for v in r) for r in k / k_n)
            out.append(f"stiffness {label:8s} [{rows}] {unit}")
        for name, k in self.body_stiffness.items():
            d = np.diag(np.asarray(k, float))
            out.append(f"body {name:12s} diagonal {force_text(d[:3], 'N/m', '.5g', ' ')}, "
                       f"{force_text(d[3:], 'N m/rad', '.5g', ' ')}")
        return "\n".join(out)

    def plot(self, path: str | Path | None = None):
        """K, C and M as maps of their entries' magnitudes
        (:func:`symcable.plotting.matrices.plot_matrices`); saved to ``path`` when given;
        returns the Figure."""
        from ..plotting.matrices import plot_matrices
        return plot_matrices(self, path)

    def state_matrix(self) -> np.ndarray:
        """A (n_q + n_v, n_q + n_v): d(q, v)/dt = A (q, v), 1/s."""
        Minv = np.linalg.inv(self.M)
        return np.block([[self.H, self.G], [-Minv @ self.K, -Minv @ self.C]])

    def __repr__(self) -> str:
        return (f"SceneLinearization({self.scene_name!r}, n_q={self.K.shape[1]}, "
                f"n_v={self.K.shape[0]}, ends={sorted(self.end_stiffness)})")
