"""What an offset sweep of a moored body gives (:func:`symcable.offset_sweep`): the
restoring force and moment on the body held at each prescribed offset, with its lines in
static equilibrium, and how each offset's solve went (:class:`OffsetSweep`)."""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .io import force_text
from .static import Exportable

__all__ = ["DOF_NAMES", "OffsetSweep"]

#: the six offsets' names, in the order of an offset row (m, m, m, deg, deg, deg)
DOF_NAMES = ("surge", "sway", "heave", "roll", "pitch", "yaw")
_UNITS = ("m", "m", "m", "deg", "deg", "deg")
_FORCE = ("Fx", "Fy", "Fz", "Mx", "My", "Mz")


@dataclass(frozen=True)
class OffsetSweep(Exportable):
    """The restoring force on a body over a sweep of prescribed offsets.

    An offset row (dx, dy, dz, droll, dpitch, dyaw) (m, deg) puts the body's reference
    point at ``base_pose[:3] + (dx, dy, dz)`` and turns it by R(droll, dpitch, dyaw) about
    that point in global axes, R = Rz Ry Rx (:func:`~symcable.scene.bodies.rotation_rpy`):
    its orientation is R R0, R0 the base pose's. To first order the turn is the rotation
    vector (droll, dpitch, dyaw) in global axes (radians), the coordinates of
    ``stiffness``.

    Attributes
    ----------
    scene_name, body : str
    offsets : ndarray (n, 6)
        m, m, m, deg, deg, deg (the caller's order).
    base_pose : ndarray (6,)
        The pose the offsets are taken from: position (m, global) and [roll, pitch, yaw]
        (deg); the body's static equilibrium (``about = "equilibrium"``) or where the scene
        puts it (``"scene"``).
    line_force : ndarray (n, 6)
        N and N m: the force of the lines on the body and its moment about the reference
        point, global axes.
    force : ndarray (n, 6)
        N and N m: the restoring force, ``line_force`` plus the body's own weight,
        buoyancy and drag in the current at rest (for a free body; a fixed body has none:
        then equal to ``line_force``). Zero at the equilibrium.
    stiffness : ndarray (6, 6)
        K = -d(force)/d(offset) at the base pose (N/m, N, N m/m, N m per rad; global axes),
        exact (the lines' by the implicit function theorem on the static residual): the
        tangent ``force ~ force[at 0] - K (dx, dy, dz, rad(droll), rad(dpitch), rad(dyaw))``.
        At a free body's static equilibrium it is :func:`symcable.linearize`'s
        ``body_stiffness``.
    line_names : tuple of str
        The lines attached to the body, in scene order.
    tension_a, tension_b : ndarray (n, n_lines)
        N, each of those lines' end tensions at ends A and B.
    status : tuple of str
        Per offset: "converged" or "failed".
    path : tuple of str
        Per offset: "batch" (the batched plain Newton from the neighbouring offset's
        solution) or the fallback solve's path (:func:`symcable.solve_equilibrium`), or
        the failure's message.
    iterations : ndarray (n,)
        Newton iterations of the batched solve (of the fallback's where it ran).
    residual : ndarray (n,)
        N, max |R| of the static residual at the answer, evaluated afresh.
    balance : ndarray (n,)
        The largest of the lines' global force balances, |sum of end forces - weight -
        seabed reaction| relative to the largest end tension (round-off for a solution);
        NaN in a current (the drag is not an output).
    stats : dict
        ``tolerance`` (N), ``batch_time`` (s, the batched call), ``wall_time`` (s, the
        whole sweep), ``fallbacks`` (offsets re-solved one by one), ``resets`` (offsets
        started from the base solution, not a neighbour's), ``compiled`` (bool),
        ``unknowns``.
    """

    scene_name: str
    body: str
    offsets: np.ndarray
    base_pose: np.ndarray
    line_force: np.ndarray
    force: np.ndarray
    stiffness: np.ndarray
    line_names: tuple[str, ...]
    tension_a: np.ndarray
    tension_b: np.ndarray
    status: tuple[str, ...]
    path: tuple[str, ...]
    iterations: np.ndarray
    residual: np.ndarray
    balance: np.ndarray
    stats: dict = field(default_factory=dict)

    @property
    def converged(self) -> np.ndarray:
        """(n,) bool: which offsets were solved."""
        return np.array([s == "converged" for s in self.status], bool)

    @property
    def tangent(self) -> np.ndarray:
        """(n, 6) the linear restoring force of ``stiffness`` at each offset (N, N m)."""
        d = np.array(self.offsets, float)
        d[:, 3:] = np.radians(d[:, 3:])
        return -d @ np.asarray(self.stiffness, float).T

    def dof(self) -> int:
        """The offset column that varies most (0..5, :data:`DOF_NAMES`): the plots' abscissa."""
        d = np.array(self.offsets, float)
        d[:, 3:] = np.radians(d[:, 3:]) * 10.0  # 0.1 rad weighs as 1 m
        return int(np.argmax(np.ptp(d, axis=0))) if len(d) else 0

    def summary(self) -> str:
        j = self.dof()
        n, ok = len(self.status), int(self.converged.sum())
        st = self.stats
        out = [f"scene             {self.scene_name}",
               f"body              {self.body}, base {np.round(self.base_pose, 4).tolist()}",
               f"offsets           {n} along {DOF_NAMES[j]} "
               f"{np.min(self.offsets[:, j]):.4g} .. {np.max(self.offsets[:, j]):.4g} "
               f"{_UNITS[j]}, {ok} converged",
               f"batch             {st.get('batch_time', float('nan')) * 1e3:.3g} ms "
               f"({'compiled' if st.get('compiled') else 'virtual machine'}), "
               f"{st.get('fallbacks', 0)} fallback solves"]
        for k in range(6):
            f = self.force[:, k]
            out.append(f"{_FORCE[k]:17s} "
                       f"{force_text([np.nanmin(f), np.nanmax(f)], 'N' if k < 3 else 'N m', '.5g')}")
        out.append(f"largest residual  {np.nanmax(self.residual):.3g} N "
                   f"(tolerance {st.get('tolerance', float('nan')):.3g} N)")
        return "\n".join(out)

    def plot(self, path=None, *, dof: int | str | None = None, ax=None):
        """Force and moment against the offset along ``dof`` (name or column; default the
        one that varies most), six panels, with the tangent of ``stiffness`` at the
        origin dashed (:func:`symcable.plotting.offsets.plot_offsets`); saved to ``path``
        when given; returns the figure."""
        from ..plotting.offsets import plot_offsets
        j = self.dof() if dof is None else (DOF_NAMES.index(dof) if isinstance(dof, str)
                                            else int(dof))
        return plot_offsets(self, j, path, ax=ax)
