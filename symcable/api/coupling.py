"""A coupling interface for a host program (a floating-body solver such as OpenFAST or
WEC-Sim, MoorDyn's ``Init``/``Step`` pattern): :class:`Coupling`.

The host owns the motion of the coupled points and bodies (:mod:`symcable.scene.coupled`);
symcable owns the lines (and any free points and bodies). At each of the host's steps it
gives the coupled things' positions and velocities at the step's end; symcable advances the
lines over the step by the generalized-alpha step that :func:`symcable.simulate` takes, the
coupled line ends following the cubic Hermite through the host's positions and velocities at
the step's two ends (:func:`~symcable.models.common.elements.coupled_path`), and returns the
forces the lines exert on the coupled things at the step's end. With generalized-alpha's
default rho_inf = 0 the step's forces are evaluated at its end, where the cubic is exactly
the host's state, so that a host stepping a motion equals ``simulate`` of that motion at the
same step to the Newton tolerance.
"""
from __future__ import annotations

import dataclasses
import hashlib
import math
from pathlib import Path

import casadi as ca
import numpy as np

from ..errors import ConvergenceError, SymcableError
from ..mechanism.fastcall import FastCall
from ..mechanism.functions import functions
from ..models import formulation_of
from ..scene import load_scene
from ..scene.coupled import coupled_scene, coupled_things
from ..solvers.galpha1 import galpha1_kernel, step_scales
from ..solvers.integrate import check_positive, start_rates
from ..solvers.options import GeneralizedAlphaFirstOrder
from .cable3d import RHO_INF, newton_tolerance
from .scene3d import check_moves, start_state

__all__ = ["Coupling", "CouplingState", "MAX_SUBSTEPS"]

#: a host step whose Newton iterations fail is retried as 2, 4, ... up to this many substeps
MAX_SUBSTEPS = 16


@dataclasses.dataclass(frozen=True)
class CouplingState:
    """A :class:`Coupling`'s state at one time, to restore (a host that steps back, e.g. a
    predictor-corrector): ``time`` (s), ``x`` the step's carried state (positions, velocities
    and their rates), ``ends`` the coupled ends' displacement (m) and velocity (m/s) at that
    time (n_ends, 6) from ``base`` (n_ends, 3), their positions at :meth:`Coupling.initialize`
    (m), ``positions`` the coupled things' (n_dof,), ``key`` the structure it belongs to.
    :meth:`save` and :meth:`load` keep it in a ``.npz`` file."""

    time: float
    x: np.ndarray
    ends: np.ndarray
    positions: np.ndarray
    key: str
    base: np.ndarray

    def save(self, path) -> Path:
        """Write the state to ``path`` (``.npz``); returns the path."""
        path = Path(path)
        with open(path, "wb") as fh:
            np.savez(fh, time=self.time, x=self.x, ends=self.ends, positions=self.positions,
                     key=self.key, base=self.base)
        return path

    @classmethod
    def load(cls, path) -> "CouplingState":
        """A state written by :meth:`save`."""
        try:
            with np.load(Path(path), allow_pickle=False) as d:
                return cls(float(d["time"]), np.array(d["x"], float), np.array(d["ends"], float),
                           np.array(d["positions"], float), str(d["key"]),
                           np.array(d["base"], float))
        except (OSError, KeyError, ValueError) as exc:
            raise SymcableError(f"coupling state {str(path)!r}: cannot be read ({exc})") from None


class Coupling:
    """symcable's lines stepped by a host program (module docstring).

    ``scene``: a cable3d scene (a path, dict or Scene). ``coupled``: the names of the points
    and bodies the host moves (a version-1 scene's ``"end_a"`` / ``"end_b"``); default every
    vessel point and vessel body (version 1: the ends with a motion, else ``end_b``); their
    own motions in the scene are replaced by the host's. ``rho_inf`` (default 0, as
    ``simulate``), ``newton_tol`` (default ``simulate``'s for the scene), ``max_step`` (s:
    a host step longer than this is taken as equal substeps; default none, the host's step),
    ``codegen`` (the step in generated C: None where it pays, True, False).

    The degrees of freedom (:attr:`dof_names`), in the order of ``coupled``: a point's
    x, y, z (m), a body's x, y, z (m), roll, pitch, yaw (rad); velocities m/s and, for a
    body, its angular velocity in global axes (rad/s). Forces: on a point (3,), N; on a body
    the force (N) and its moment about the reference point (N m), global axes: what the
    lines exert on it.

    Use: ``f = c.initialize(x0)`` (the static state with the coupled things at x0), then
    ``f = c.step(t, dt, x, v)`` for each host step from t to t + dt (x, v at t + dt);
    :meth:`state` / :meth:`restore` to step back; :meth:`outputs` for every named output
    (tensions, node positions) at the current time.
    """

    def __init__(self, scene, coupled=None, *, rho_inf: float | None = None,
                 newton_tol: float | None = None, max_step: float | None = None,
                 codegen: bool | None = None):
        self.scene = load_scene(scene)
        form = formulation_of(self.scene)
        if form.linearised or form.twists:
            raise SymcableError(f"scene {self.scene.name!r}: model = "
                                f"{self.scene.model.value!r}; the coupling steps cable3d "
                                "scenes (model = 'cable3d') for now")
        self.things = coupled_things(self.scene, coupled)
        rho = RHO_INF if rho_inf is None else rho_inf
        if isinstance(rho, bool) or not isinstance(rho, (int, float)) or not 0.0 <= rho <= 1.0:
            raise SymcableError(f"rho_inf = {rho_inf!r}: must be a number in [0, 1]")
        self.rho_inf = float(rho)
        self.newton_tol = None if newton_tol is None else check_positive("newton_tol", newton_tol)
        self.max_step = None if max_step is None else check_positive("max_step", max_step, "s")
        self.codegen = codegen
        self._ends = [(th, e) for th in self.things for e in th.ends]
        self.stats = {"steps": 0, "host_steps": 0, "newton_iterations": 0,
                      "substepped_steps": 0}
        self._mech = None

    # -- what the host sees -------------------------------------------------------------
    @property
    def names(self) -> list:
        """The coupled things' names, in order."""
        return [th.name for th in self.things]

    @property
    def dof_names(self) -> list:
        """Each degree of freedom's name (``"fair1.x"``, ``"spar.pitch"``), in order."""
        return [n for th in self.things for n in th.dof_names()]

    @property
    def n_dof(self) -> int:
        """Degrees of freedom (3 per point, 6 per body)."""
        return sum(th.dofs for th in self.things)

    @property
    def time(self) -> float:
        """The time the coupling has reached, s."""
        self._need_start("time")
        return self._time

    @property
    def forces(self) -> np.ndarray:
        """The forces (and bodies' moments) on the coupled things at :attr:`time`, (n_dof,)."""
        self._need_start("forces")
        return self._forces.copy()

    def initialize(self, positions=None, velocities=None, t: float = 0.0) -> np.ndarray:
        """The lines' static state with the coupled things at ``positions`` (n_dof,; default
        their scene poses), at rest, at time ``t`` (s); the things' velocities
        ``velocities`` (default zero) start the first step's path. Returns the forces
        (n_dof,)."""
        t = self._finite("t", t)
        poses = self._split("positions", self._default_positions() if positions is None
                            else positions)
        rates = self._split("velocities", np.zeros(self.n_dof) if velocities is None
                            else velocities)
        scene = coupled_scene(self.scene, self.things, poses)
        mech, eq, _, _, _ = start_state(scene, t, "rest", self.codegen)
        check_moves(scene, mech)
        tol = newton_tolerance(scene, mech) if self.newton_tol is None else self.newton_tol
        opts = GeneralizedAlphaFirstOrder(rho_inf=self.rho_inf, tol=tol)
        self._mech, self._opts, self._eq = mech, opts, eq
        self._kern = FastCall(galpha1_kernel(mech, opts, lte=False, codegen=self.codegen))
        self._consts = (np.array([opts.rho_inf, opts.tol]), np.asarray(step_scales(mech), float))
        self._slices = [mech.params.slice(self._block(e)) for _, e in self._ends]
        self._position_slices = [mech.params.slice(self._block(e).replace(".coupled",
                                                                           ".position"))
                                 for _, e in self._ends]
        self._base = np.vstack([th.end_kinematics(pose, np.zeros(th.dofs))[0]
                                for th, pose in zip(self.things, poses)])
        self._end_out = self._end_forces(mech)
        self._key = _structure_key(mech, self.names)
        self._p = np.asarray(mech.params.values, float).copy()
        self._now = self._end_state(poses, rates)
        self._set_path(self._now, self._now, t, t)
        q0, v0 = np.asarray(eq.q, float), np.zeros(mech.n_v)
        qd, vd = start_rates(mech, q0, v0, t, self._p)
        self._x = np.concatenate([q0, v0, qd, vd])
        self._time, self._poses = t, poses
        self._forces = self._loads(poses)
        self.stats.update(newton_tol=tol, rho_inf=self.rho_inf, n_states=int(q0.size + v0.size),
                          compiled=bool(self._kern.fn.is_a("External")))
        return self._forces.copy()

    def step(self, t: float, dt: float, positions, velocities) -> np.ndarray:
        """Advance from ``t`` (s, the coupling's :attr:`time`) to ``t + dt`` with the coupled
        things at ``positions`` moving at ``velocities`` (each (n_dof,)) at t + dt; returns
        the forces (n_dof,) there. A step whose Newton iterations fail is retried as 2, 4,
        ... MAX_SUBSTEPS substeps; past that a ConvergenceError leaves the state at t."""
        self._need_start("step")
        t, dt = self._finite("t", t), check_positive("dt", dt, "s")
        if abs(t - self._time) > 1e-9 * max(1.0, abs(t), dt):
            raise SymcableError(f"t = {t!r} s: the coupling is at t = {self._time!r} s; step "
                                "from there (restore() a saved state to step from another time)")
        poses = self._split("positions", positions)
        new = self._end_state(poses, self._split("velocities", velocities))
        self._set_path(self._now, new, t, t + dt)
        base = 1 if self.max_step is None else max(1, math.ceil(dt / self.max_step - 1e-9))
        n, last = base, None
        while n <= base * MAX_SUBSTEPS:
            x, last = self._substeps(t, dt, n)
            if x is not None:
                break
            n *= 2
        else:
            self._set_path(self._now, self._now, t, t)
            raise ConvergenceError(
                f"coupling: Newton did not converge in the step from t = {t:.6g} to "
                f"{t + dt:.6g} s, not even as {base * MAX_SUBSTEPS} substeps (scaled residual "
                f"{last:.3g}, tolerance {self._opts.tol:.3g}): a smaller host step, or check the "
                "positions given", diagnostics={"reason": "newton", "time": t + dt,
                                                "time_last_good": t, "residual": last})
        self.stats["host_steps"] += 1
        self.stats["substepped_steps"] += int(n > base)
        self._x, self._time, self._now, self._poses = x, t + dt, new, poses
        self._forces = self._loads(poses)
        return self._forces.copy()

    def outputs(self) -> dict:
        """Every named output of the lines at :attr:`time` (``"LINE.axial_force"``, N;
        ``"LINE.positions"``, m; ...: the Mechanism's, as ``simulate`` reports them)."""
        self._need_start("outputs")
        mech = self._mech
        F = functions(mech)
        ny = mech.n_q + mech.n_v
        y = F.outputs(self._x[:mech.n_q], self._x[mech.n_q:ny], np.zeros(0), self._time,
                      self._p)
        return F.unpack(np.asarray(y, float).ravel())

    def state(self) -> CouplingState:
        """The state at :attr:`time` (:class:`CouplingState`)."""
        self._need_start("state")
        return CouplingState(self._time, self._x.copy(), self._now.copy(),
                             np.concatenate(self._poses), self._key, self._base.copy())

    def restore(self, state: CouplingState) -> np.ndarray:
        """Return to a :meth:`state` of this coupling (the same scene and coupled things);
        returns the forces there."""
        self._need_start("restore")
        if not isinstance(state, CouplingState) or state.key != self._key \
                or state.x.shape != self._x.shape or state.ends.shape != self._now.shape \
                or state.positions.shape != (self.n_dof,) or state.base.shape != self._base.shape:
            raise SymcableError("restore: the state is not one of this coupling's (another "
                                "scene or other coupled things)")
        self._x, self._now, self._time = state.x.copy(), state.ends.copy(), float(state.time)
        self._base = state.base.copy()  # the ends' start, and so their held positions
        for sl, b in zip(self._position_slices, self._base):
            self._p[sl] = b
        self._set_path(self._now, self._now, self._time, self._time)
        self._poses = self._split("positions", state.positions)
        self._forces = self._loads(self._poses)
        return self._forces.copy()

    # -- inside --------------------------------------------------------------------------
    def _need_start(self, what: str) -> None:
        if self._mech is None:
            raise SymcableError(f"coupling: {what} before initialize(); call "
                                "initialize(positions) first")

    @staticmethod
    def _finite(name: str, value) -> float:
        try:
            v = float("nan") if isinstance(value, (str, bool)) else float(value)
        except (TypeError, ValueError):
            v = float("nan")
        if not math.isfinite(v):
            raise SymcableError(f"{name} = {value!r}: must be a finite number (s)")
        return v

    def _default_positions(self) -> np.ndarray:
        return np.concatenate([np.asarray(th.pose, float) for th in self.things])

    def _split(self, name: str, values) -> list:
        """``values`` (n_dof,) split per thing, checked."""
        try:
            a = np.asarray(values, dtype=float).ravel()
        except (TypeError, ValueError):
            a = np.full(0, np.nan)
        if a.size != self.n_dof or not np.all(np.isfinite(a)):
            raise SymcableError(f"{name}: {a.size} value(s): must be {self.n_dof} finite numbers, "
                                f"one per degree of freedom ({', '.join(self.dof_names)})")
        cuts = np.cumsum([0] + [th.dofs for th in self.things])
        return [a[i:j] for i, j in zip(cuts[:-1], cuts[1:])]

    def _block(self, end) -> str:
        return f"{end.end}.coupled" if self.scene.version == 1 else \
            f"{end.line}.{end.end}.coupled"

    def _end_forces(self, mech) -> FastCall:
        names = [f"end_force_{e.end[-1]}" if self.scene.version == 1 else
                 f"{e.line}.end_force_{e.end[-1]}" for _, e in self._ends]
        expr = ca.vertcat(*[ca.vec(mech.outputs[n].expr) for n in names])
        return FastCall(ca.Function("coupling_end_forces",
                                    [mech.q, mech.v, mech.z, mech.t, mech.p], [expr]))

    def _end_state(self, poses, rates) -> np.ndarray:
        """Each coupled end's displacement from its start (m) and velocity (m/s), (n_ends, 6)."""
        rows = [np.hstack(th.end_kinematics(pose, rate))
                for th, pose, rate in zip(self.things, poses, rates)]
        out = np.vstack(rows)
        out[:, :3] -= self._base
        return out

    def _set_path(self, a: np.ndarray, b: np.ndarray, t0: float, t1: float) -> None:
        for sl, ra, rb in zip(self._slices, a, b):
            self._p[sl] = np.concatenate([ra[:3], ra[3:], rb[:3], rb[3:], [t0, t1]])

    def _substeps(self, t: float, dt: float, n: int):
        """``(x at t + dt, None)`` after n equal steps, or ``(None, scaled residual)``."""
        x, h = self._x, dt / n
        iterations = 0.0
        for k in range(n):
            x1, err, _, its, failed = self._kern(x, t + k * h if k else t, h, self._p,
                                                 *self._consts)
            if failed[0] or not np.all(np.isfinite(x1)):
                return None, float(err[0])
            x, iterations = x1.copy(), iterations + float(its[0])
        self.stats["steps"] += n
        self.stats["newton_iterations"] += int(iterations)
        return x, None

    def _loads(self, poses) -> np.ndarray:
        mech = self._mech
        ny = mech.n_q + mech.n_v
        f = self._end_out(self._x[:mech.n_q], self._x[mech.n_q:ny], np.zeros(0), self._time,
                          self._p)[0].reshape(-1, 3)
        out, k = [], 0
        for th, pose in zip(self.things, poses):
            out.append(th.load(pose, f[k:k + len(th.ends)]))
            k += len(th.ends)
        return np.concatenate(out)


def _structure_key(mech, names) -> str:
    text = repr((mech.fname, mech.n_q, mech.n_v, mech.params.names, mech.params.sizes, names))
    return hashlib.sha256(text.encode()).hexdigest()[:16]
