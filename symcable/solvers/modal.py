"""Natural frequencies and mode shapes of a line about its static state.

The undamped linearised model is generic over formulations: it is the Jacobian
``A = df/dy`` of any :class:`~symcable.models.dynamic.DynamicModel` at its rest state ``y0``,
taken with the excitation amplitudes (parameter blocks ``amp_*``) and the current
(parameter block ``current``) set to zero. The static state the model is linearised about
(``phi_s``, ``eps_s`` ...) stays the scene's, current included.

Why this removes the drag: Morison drag ``|u| u`` has zero derivative at zero relative
velocity, and with no current the water's velocity relative to the line at rest is zero, so
the drag contributes nothing to ``A`` (exactly: CasADi's derivative of ``|u|`` at 0 is
``sign(0) = 0``). With a current on, the same Jacobian would hold the linear drag damping
``rho d Cd |U|`` about the current, which is not part of an undamped modal analysis.

For a conservative system the eigenvalues of ``y' = A y`` are ``+-i omega`` (and zeros for
the constraint directions of the strain/angle state, or rigid modes of a free line); each
conjugate pair gives one mode.

Cost: the eigenvalue problem is dense (LAPACK ``geev`` through :func:`numpy.linalg.eig`),
O(n_y^3) time and O(n_y^2) memory; for the planar cable n_y = 4 N - 2 for N segments
pinned at both ends. Eigen-solve alone, median on 2 cores: 0.02 s at 50 segments
(n_y = 198), 0.35 s at 200 (n_y = 798), 1.8 s at 400 (n_y = 1598); so ~15-20 s at
n_y = 3000, the default limit ``max_dense``. Building the model (static solve, symbolic
graph) adds 0.05-0.3 s at 50-200 segments the first time; the model is cached.
"""
from __future__ import annotations

import math
import time
import warnings as _warnings
from dataclasses import dataclass, field

import numpy as np

from ..errors import SymcableError
from ..models.dynamic import DynamicModel
from ..results import Exportable

__all__ = ["ModalSolution", "modal_analysis"]

#: largest state size solved by the dense eigenvalue problem by default
MAX_DENSE = 3000
#: eigenvalues with |lambda| below this fraction of max |lambda| are zero (constraint/rigid) modes
ZERO_TOL = 1e-9
#: |Re lambda| / |lambda| above this means the linear model is not conservative: a warning
REAL_PART_TOL = 1e-6


@dataclass(frozen=True)
class ModalSolution(Exportable):
    """Undamped natural modes of a line about its static state.

    ``n_modes`` is the number of modes returned, ``n`` the number of nodes.

    Attributes
    ----------
    scene_name : str
    s : ndarray (n,)
        Unstretched arc length of the nodes from end A, m.
    positions : ndarray (n, 2)
        Static node positions (x, z), m (the shape the modes oscillate about).
    frequencies : ndarray (n_modes,)
        Natural frequencies, Hz, ascending.
    periods : ndarray (n_modes,)
        Natural periods ``1 / frequencies``, s.
    real_parts : ndarray (n_modes,)
        Real part of each mode's eigenvalue, 1/s: zero for the conservative linear model,
        so its size is the round-off of the eigen-solve (see ``stats``).
    shapes : ndarray (n_modes, n, 2)
        Mode shapes as node displacement amplitudes (x, z), m, each scaled so its largest
        node displacement ``hypot(x, z)`` is 1 and that entry's largest component is
        positive. Nodes with prescribed motion (pinned ends) have zero displacement.
    status : str
        ``"converged"``.
    stats : dict
        ``n_y`` (state size), ``method`` (``"dense eig"``), ``zero_modes`` (eigenvalues
        discarded as zero: |lambda| <= ``zero_tolerance``, 1/s), ``max_relative_real_part``
        (max |Re lambda| / |lambda| over the returned modes, -), ``model_time`` (building
        the dynamic model, static solve included, when not given), ``jacobian_time``
        (evaluating A), ``eig_time`` (the eigen-solve, shapes excluded), ``wall_time`` (s).
    warnings : tuple of str
    """

    scene_name: str
    s: np.ndarray
    positions: np.ndarray
    frequencies: np.ndarray
    periods: np.ndarray
    real_parts: np.ndarray
    shapes: np.ndarray
    status: str = "converged"
    stats: dict = field(default_factory=dict)
    warnings: tuple = ()

    @property
    def n_modes(self) -> int:
        return int(len(self.frequencies))

    def summary(self) -> str:
        """One line per mode: frequency (Hz), period (s), angular frequency (rad/s)."""
        st = self.stats
        lines = [f"scene             {self.scene_name}",
                 f"modes             {self.n_modes} lowest of a {st.get('n_y', '?')}-state model "
                 f"({st.get('method', '?')}, {1e3 * st.get('wall_time', float('nan')):.1f} ms)",
                 " mode   frequency (Hz)    period (s)   omega (rad/s)"]
        for k, (f, T) in enumerate(zip(self.frequencies, self.periods), start=1):
            lines.append(f"{k:5d}   {f:14.6g}   {T:11.6g}   {2 * math.pi * f:13.6g}")
        lines.append(f"max |Re|/|lambda| {st.get('max_relative_real_part', float('nan')):.2g}")
        lines += [f"warning           {w}" for w in self.warnings]
        return "\n".join(lines)


def undamped_parameters(model: DynamicModel) -> np.ndarray:
    """The formulation's parameters of the undamped, unforced linear model about rest
    (``model.p_undamped``: the static state kept, excitation and current off)."""
    return np.asarray(model.p_undamped, dtype=float)


def _velocity_map(model: DynamicModel) -> np.ndarray:
    """Real matrix (2 n, n_y) from the state to the Cartesian node velocities (x, z), m/s,
    which every formulation gives as ``info["velocity_map"]``."""
    if "velocity_map" not in model.info:
        raise SymcableError(f"model {model.name!r} gives no info['velocity_map']: modal shapes "
                            "need the map from its state to node velocities")
    return np.asarray(model.info["velocity_map"], dtype=float)


def _shape(disp: np.ndarray) -> np.ndarray:
    """Real mode shape (n, 2) from a complex displacement (n, 2): rotated so its largest
    entry is real and positive, then scaled to a largest node displacement of 1."""
    k = np.argmax(np.abs(disp))
    z = disp.flat[k]
    if z == 0:
        return np.zeros(disp.shape)
    real = (disp * (abs(z) / z)).real
    return real / np.max(np.hypot(real[:, 0], real[:, 1]))


def modal_analysis(scene, n_modes: int = 10, *, model: DynamicModel | None = None,
                   max_dense: int = MAX_DENSE, codegen: bool | None = None,
                   started: float | None = None) -> ModalSolution:
    """The lowest undamped natural frequencies and mode shapes of a line, for a dynamic
    model already built; :func:`symcable.modal_analysis` builds it from a scene.

    Parameters
    ----------
    scene : Scene, dict, path or None
        Not used here (the model is given): :func:`symcable.modal_analysis` builds the
        model of a scene, solving its static state.
    n_modes : int
        Number of modes (>= 1): the lowest, each conjugate pair once, zero modes skipped.
        Fewer are returned, with a warning, when the model has fewer.
    model : DynamicModel
        A dynamic model already built (:func:`symcable.build_dynamic_model`).
    max_dense : int
        Largest state size n_y solved (dense eigenvalue problem, O(n_y^3): ~20 s at 3000).
    codegen : bool, optional
        Evaluate the state matrix in generated C (:mod:`symcable.codegen`; default None:
        when a compiler is found). The time here is the dense eigenvalue solve (LAPACK),
        which generated C does not change; the option is for uniformity and for models
        whose Jacobian is costly.
    started : float, optional
        ``time.perf_counter()`` when the caller began (:func:`symcable.modal_analysis`,
        which builds the model first): ``stats["model_time"]`` and ``stats["wall_time"]``
        count from it.

    Returns
    -------
    ModalSolution

    Raises
    ------
    SymcableError
        On ``n_modes < 1`` or a model larger than ``max_dense``.
    """
    t_start = time.perf_counter() if started is None else started
    if isinstance(n_modes, bool) or int(n_modes) != n_modes or n_modes < 1:
        raise SymcableError(f"n_modes = {n_modes!r}: must be an integer >= 1")
    n_modes = int(n_modes)
    if model is None:
        raise SymcableError("model = None: give the dynamic model "
                            "(symcable.modal_analysis builds it from a scene)")
    t_model = time.perf_counter()
    n_y = model.n_y
    if n_y > max_dense:
        raise SymcableError(
            f"state size n_y = {n_y} > max_dense = {max_dense}: the dense eigenvalue problem "
            f"would take ~{20 * (n_y / 3000) ** 3:.0f} s; use fewer segments or pass a larger "
            "max_dense")

    p0 = undamped_parameters(model)
    A = np.array(model.functions(codegen).rhs_jacobian(model.y0, 0.0, p0).full(), dtype=float)
    t_jac = time.perf_counter()
    lam, X = np.linalg.eig(A)
    t_eig = time.perf_counter()

    scale = float(np.max(np.abs(lam))) if lam.size else 0.0
    zero_tol = ZERO_TOL * scale
    is_zero = np.abs(lam) <= zero_tol
    pick = np.flatnonzero(~is_zero & (lam.imag > 0.0))
    pick = pick[np.argsort(lam.imag[pick], kind="stable")]

    warnings = []
    nonzero = lam[~is_zero]
    rel_all = np.abs(nonzero.real) / np.abs(nonzero) if nonzero.size else np.zeros(0)
    if rel_all.size and rel_all.max() > REAL_PART_TOL:
        k = np.argmax(rel_all)
        warnings.append(f"the linear model is not conservative: eigenvalue {nonzero[k]:.6g} 1/s "
                        f"has |Re|/|lambda| = {rel_all[k]:.3g} > {REAL_PART_TOL:g}; its "
                        "frequencies are the imaginary parts")
    if len(pick) < n_modes:
        warnings.append(f"n_modes = {n_modes}: the model has only {len(pick)} oscillating modes")
    pick = pick[:n_modes]

    D = _velocity_map(model)
    n_nodes = D.shape[0] // 2
    shapes = np.zeros((len(pick), n_nodes, 2))
    for row, k in enumerate(pick):
        disp = (D @ X[:, k]) / lam[k]            # velocity = lambda * displacement
        shapes[row] = _shape(disp.reshape(n_nodes, 2))

    omega = lam.imag[pick]
    freq = omega / (2.0 * math.pi)
    rel = np.abs(lam[pick].real) / np.abs(lam[pick]) if len(pick) else np.zeros(0)
    for w in warnings:
        _warnings.warn(w, RuntimeWarning, stacklevel=2)

    info = model.info
    static = info.get("static")
    sc = info.get("scene")
    t_end = time.perf_counter()
    return ModalSolution(
        scene_name=getattr(sc, "name", model.name),
        s=np.asarray(info.get("s_nodes", np.arange(n_nodes)), dtype=float),
        positions=(np.asarray(static.positions, dtype=float) if static is not None
                   else np.full((n_nodes, 2), np.nan)),
        frequencies=freq,
        periods=1.0 / freq,
        real_parts=lam.real[pick].copy(),
        shapes=shapes,
        status="converged",
        stats={"n_y": n_y, "method": "dense eig", "zero_modes": int(np.count_nonzero(is_zero)),
               "zero_tolerance": zero_tol,
               "max_relative_real_part": float(rel.max()) if rel.size else 0.0,
               "model_time": t_model - t_start, "jacobian_time": t_jac - t_model,
               "eig_time": t_eig - t_jac,
               "wall_time": t_end - t_start},
        warnings=tuple(warnings),
    )
