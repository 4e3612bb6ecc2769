"""Continuation of a static equilibrium along a path in one named parameter block (an end's
twist, an end's position, the load), with the stability of every point, and a way off an
unstable branch along its unstable mode: the loops and buckled shapes of a twisted rod
reached by twisting it or bringing its ends together.

Each step: a secant predictor from the last two points, damped Newton
(:func:`~symcable.solvers.newton.newton`) at the step's parameters, the step halved (at most
``max_halvings`` times) where Newton fails; every point is checked as
:func:`~symcable.solvers.equilibrium.solve_equilibrium` checks its answer (residual,
admissibility bounds, and the lowest eigenvalue of the reduced tangent stiffness). Where that
eigenvalue is negative, with ``leave_unstable`` the state is pushed both ways along its
eigenvector and relaxed by pseudo-transient continuation (which goes down the energy); a
stable equilibrium found so is the point (``left`` = True: a bifurcation or a fold was passed
and the path jumped to another branch). Without ``leave_unstable`` the unstable branch is
followed and flagged. Where Newton fails after ``max_halvings`` halvings of a step (a
fold: the branch turns back), the last state is relaxed at the step's target (the snap an
experiment would see), again with ``left`` = True. A Mechanism with anchored frames (the
rod's ``frame`` block) is re-anchored between steps when some edge has turned by more than
its hook's threshold from its anchor (the anchored frame is singular at a half turn: a loop
turns edges by nearly 180 degrees), and at every step of a relaxation.
"""
from __future__ import annotations

import time
from dataclasses import dataclass, field

import casadi as ca
import numpy as np

from ..mechanism.functions import functions
from ..errors import ConvergenceError, SymcableError
from ..mechanism.mechanism import Mechanism
from .equilibrium import (ESCAPES, _check, _ptc, _stability,
                          _unstable_direction, _x_scale, solve_equilibrium)
from .newton import newton
from .reanchor import twist_turns

__all__ = ["Branch", "BranchPoint", "trace_branch"]


@dataclass(frozen=True)
class BranchPoint:
    """One equilibrium along a branch.

    Attributes
    ----------
    value : ndarray (size of the block,)
        The block's value here, in its units (rad for a twist, m for a position, N/m for a
        load ...); with ``component`` given, (1,): that entry's value.
    p : ndarray (n_p,)
        All parameters (the ``frame`` block as re-anchored here).
    q : ndarray (n_q,)
        Coordinates, m or rad.
    z : ndarray (n_z,)
        Constraint forces, N.
    outputs : dict
        The Mechanism's outputs at the point, output name -> value (each in its own unit).
    stable : bool or None
        Whether the equilibrium is stable; None where stability is not judged (too large a
        system).
    min_stiffness : float
        Lowest eigenvalue of the reduced tangent stiffness, N/m (NaN where not judged).
    left : bool
        Reached by leaving an unstable equilibrium along its unstable mode, or by relaxing
        past a fold (default False).
    iterations : int
        Newton (and relaxation) iterations of this point (default 0).
    """

    value: np.ndarray
    p: np.ndarray
    q: np.ndarray
    z: np.ndarray
    outputs: dict
    stable: bool | None
    min_stiffness: float
    left: bool = False
    iterations: int = 0


@dataclass
class Branch:
    """The points of :func:`trace_branch`, in order; ``stats``: ``wall_time`` (s),
    ``reanchored`` (points after which the anchors were renewed), ``halvings`` (failed
    steps halved), ``snaps`` ((k, value): point k reached by relaxing past a fold, value the
    last one solved before it, the fold's bracket), ``reached`` (after a stall: the last
    value at which Newton converged, the fold's bracket).

    Attributes
    ----------
    mechanism : str
        Name of the Mechanism traced.
    block : str
        The parameter block varied along the path.
    component : int or None
        The entry of ``block`` varied, or None: the whole block.
    points : list of BranchPoint
        One per value of the path, in order (after a stall, a
        :class:`~symcable.errors.ConvergenceError`'s ``partial``: those solved).
    stats : dict
        The keys above.
    """

    mechanism: str
    block: str
    component: int | None
    points: list = field(default_factory=list)
    stats: dict = field(default_factory=dict)

    @property
    def values(self) -> np.ndarray:
        """(K,) the path parameter at each point (the block's value, or its ``component``)."""
        v = np.array([pt.value for pt in self.points], float)
        return v[:, 0] if v.ndim == 2 and v.shape[1] == 1 else (
            v[:, self.component] if self.component is not None else v)

    @property
    def stable(self) -> np.ndarray:
        return np.array([pt.stable for pt in self.points], dtype=object)

    def output(self, name: str) -> np.ndarray:
        """(K, ...) the output ``name`` stacked over the points."""
        if self.points and name not in self.points[0].outputs:
            raise SymcableError(f"output {name!r} unknown; the mechanism {self.mechanism!r} "
                                f"has {', '.join(sorted(self.points[0].outputs))}")
        return np.array([np.asarray(pt.outputs[name], float) for pt in self.points])


def _path(mech: Mechanism, block: str, values, component):
    """(K, size) the block's values along the path, checked."""
    if not isinstance(block, str) or block not in mech.params.names:
        raise SymcableError(f"block = {block!r}: not a parameter block of {mech.name!r}; "
                            f"allowed: {', '.join(mech.params.names)}")
    size = mech.params.slice(block).stop - mech.params.slice(block).start
    v = np.asarray(values, dtype=float)
    if component is not None:
        if not isinstance(component, (int, np.integer)) or not 0 <= component < size:
            raise SymcableError(f"component = {component!r}: block {block!r} has {size} "
                                f"entries (0 to {size - 1})")
        if v.ndim != 1:
            raise SymcableError(f"values: a 1-D array of {block}[{component}] is needed "
                                f"(got shape {v.shape})")
    elif not (v.ndim == 2 and v.shape[1] == size) and not (v.ndim == 1 and size == 1):
        raise SymcableError(f"values: shape (K, {size}) for block {block!r} (or (K,) with "
                            f"component = i), got {v.shape}")
    if v.shape[0] < 2 or not np.all(np.isfinite(v)):
        raise SymcableError(f"values: at least two finite values along the path, got {v!r}")
    return v


class _Charts:
    """The re-anchoring of a Mechanism with anchored frames (none: every call a no-op)."""

    def __init__(self, mech, reanchor, every_step: bool = False):
        hook = reanchor or None
        self.hook, self.margin, self.update = hook, None, None
        self.every_step = every_step
        self.turns = None
        if hook is not None:
            self.margin = ca.Function("margin", [mech.q, mech.t, mech.p], [hook.margin])
            self.update = ca.Function("update", [mech.q, mech.t, mech.p], [hook.update])
            self.turns = twist_turns(mech)  # the whole turns a renewal must keep

    def ok(self, q, p) -> bool:
        """No edge within the hook's floor of the half turn from its anchor."""
        return self.hook is None or float(self.margin(q, 0.0, p)) >= self.hook.floor

    def stepwise(self) -> "_Charts":
        """The same charts renewed at every accepted step (a relaxation's)."""
        c = _Charts.__new__(_Charts)
        c.__dict__.update(self.__dict__, every_step=True)
        return c

    def renew(self, q, p):
        """(p, renewed, q): the anchors renewed at q when some edge has turned past the
        hook's threshold from its anchor (``every_step``: when any has turned), and the
        edge twists shifted by whole turns where the new chart's reference twist at a vertex
        is the old one's wrapped by 2 pi (the anchors' angle is taken afresh by atan2;
        :class:`~symcable.solvers.reanchor.TwistTurns`, as the time march does): without the
        shift the vertex's twist would jump by a turn (a coarse loop's snap can lose a turn
        of link so). Not renewed where no shift restores every vertex."""
        if self.hook is None:
            return p, False, q
        margin = float(self.margin(q, 0.0, p))
        if margin >= (2.0 - 1e-12 if self.every_step else self.hook.threshold):
            return p, False, q
        p_new = np.asarray(self.update(q, 0.0, p), float).ravel()
        q_new = q if self.turns is None else self.turns(q, p, p_new)
        if q_new is None:  # a jump no shift of the twists undoes: keep the old chart
            return p, False, q
        return p_new, True, q_new


def _relax(F, mech, x, p, tol, charts):
    """Pseudo-transient continuation from x at p, the anchors renewed at every accepted step
    and a step refused that turns an edge within the hook's floor of the half turn from
    where it was (a relaxation that swings a loop round turns edges by more than a half
    turn; a step across the anchored frame's singularity would make the reference twist
    jump by a turn, and a snap lose a turn of link): (result, p)."""
    res = _ptc(F, mech, x, p, tol, charts=charts.stepwise() if charts.hook is not None else None)
    return res, res.p


def _escape(F, mech, x, p, tol, charts):
    """From an unstable equilibrium x: pushes both ways along its most unstable mode (10 %
    of the coordinate scale), each relaxed, up to ESCAPES times: (result, p) of a stable
    equilibrium, or None."""
    its = 0
    for _ in range(ESCAPES):
        q, z = x[:mech.n_q], x[mech.n_q:]
        lam, mode = _unstable_direction(F, mech, q, z, p)
        if lam is None:
            return None
        push = 0.1 * float(np.median(mech.scales.q)) * mode / max(np.max(np.abs(mode)), 1e-300)
        found = []
        for sgn in (1.0, -1.0):
            res, pp = _relax(F, mech, np.concatenate([q + sgn * push, z]), p, tol, charts)
            its += res.iterations
            if res.converged:
                found.append((res, pp, _stability(F, mech, res.x[:mech.n_q],
                                                  res.x[mech.n_q:], pp)[0]))
        if not found:
            return None
        stable = [f for f in found if f[2]]
        if stable:
            res, pp, _ = stable[0]
            res.iterations = its
            return res, pp
        x, p = found[0][0].x, found[0][1]  # a saddle further on: escape from it in turn
    return None


def trace_branch(mech: Mechanism, block: str, values, *, component: int | None = None,
                 p=None, start=None, leave_unstable: bool = True, reanchor=None,
                 tol: float | None = None, max_iter: int = 30, max_halvings: int = 6,
                 codegen: bool | None = False) -> Branch:
    """Static continuation of ``mech`` along ``values`` of the parameter block ``block``.

    Parameters
    ----------
    mech : Mechanism
    block : str
        A parameter block of ``mech`` (a rod's ``"end_b.twist"`` in rad, ``"end_b.position"``
        in m, ``"load"`` ...).
    values : array (K,) or (K, size)
        The block's values at the K points, in its units; with ``component`` = i, (K,) the
        values of its entry i (the other entries as in ``p``).
    p : ndarray (n_p,), optional
        The other parameters (default the mechanism's static parameters).
    start : Equilibrium or BranchPoint, optional
        An equilibrium at the first value; default solved there by
        :func:`~symcable.solvers.equilibrium.solve_equilibrium` (the stable one it finds).
    leave_unstable : bool
        Where a point is unstable, leave along its unstable eigenvector to a stable
        equilibrium at the same parameters (module docstring); False: follow the branch.
    reanchor : Reanchor, optional
        Re-anchor the frames between steps by this hook
        (:class:`~symcable.mechanism.mechanism.Reanchor`); None or False: never.
        :func:`symcable.trace_branch` passes a rod's own.
    tol : float, optional
        N, as :func:`~symcable.solvers.equilibrium.solve_equilibrium`.
    max_iter, max_halvings : int
        Newton iterations per attempt; halvings of a failed step before giving up.

    Returns
    -------
    Branch
        One :class:`BranchPoint` per value.

    Raises
    ------
    SymcableError
        An unknown block, values of the wrong shape or not finite, a bad component.
    ConvergenceError
        A step failed after ``max_halvings`` halvings and no relaxation found a stable state
        there (``partial``: the branch so far; ``diagnostics["reached"]``: the last value
        solved, ``diagnostics["x"]``: its (q, z)).
    """
    t0 = time.perf_counter()
    path = _path(mech, block, values, component)
    p = np.array(mech.static_p if p is None else p, dtype=float).ravel()
    if p.size != mech.params.n:
        raise SymcableError(f"p has {p.size} entries, the mechanism {mech.name!r} {mech.params.n}")
    charts = _Charts(mech, reanchor)
    F = functions(mech)
    S = F.static_solver(codegen)
    if tol is None:
        tol = mech.scales.static_tolerance()
    opts = dict(tol=tol, max_iter=max_iter, x_scale=_x_scale(mech), merit_weights=mech.scales.merit)
    branch = Branch(mech.name, block, component,
                    stats={"reanchored": [], "halvings": 0, "snaps": []})
    tr = _Tracer(mech, F, S, S.fast("step"), opts, tol, charts,
                 mech.params.slice(block), component, leave_unstable, block, path,
                 max_halvings, branch, t0)
    branch.points.append(tr.first(p, start, codegen))
    prev = None  # (value, x) of the point before the last, for the secant
    for k in range(1, len(path)):
        pt, prev = tr.advance(k, prev)
        branch.points.append(pt)
    branch.stats["wall_time"] = time.perf_counter() - t0
    return branch


@dataclass
class _Tracer:
    """One continuation's working set: the mechanism, its Functions ``F`` and static solver
    ``S`` (``step`` its Newton step), the Newton options, the tolerance (N), the charts,
    where the block sits in p (``sl``, ``component``), the path (K, size) in the block's
    units, and the Branch being built (``t0`` its start, ``time.perf_counter``, s)."""

    mech: Mechanism
    F: object
    S: object
    step: object
    opts: dict
    tol: float
    charts: _Charts
    sl: slice
    component: int | None
    leave_unstable: bool
    block: str
    path: np.ndarray
    max_halvings: int
    branch: Branch
    t0: float

    def at(self, v, base):
        """The parameters ``base`` (n_p,) with the block (or its component) set to ``v``."""
        out = base.copy()
        if self.component is None:
            out[self.sl] = np.ravel(v)
        else:
            out[self.sl.start + self.component] = float(np.ravel(v)[0])
        return out

    def point(self, x, pp, v, left, its):
        """(BranchPoint or None, why): the point at x (q, z) converged at pp, checked."""
        mech, F, S = self.mech, self.F, self.S
        ok, why, info = _check(S, F, mech, x, pp, self.tol, False)
        if not ok:
            return None, why
        out = F.unpack(S.packed_outputs(x, pp))
        return BranchPoint(np.atleast_1d(np.array(v, float)), pp.copy(), x[:mech.n_q].copy(),
                           x[mech.n_q:].copy(), out, info["stable"],
                           float(info["min_stiffness"]), left, its), ""

    def settle(self, x, pp, v, its, left=False):
        """(point, why): the point at x (converged at pp), left along its unstable mode to
        a stable equilibrium where asked and found."""
        pt, why = self.point(x, pp, v, left, its)
        if pt is None or pt.stable is not False or not self.leave_unstable:
            return pt, why
        out = _escape(self.F, self.mech, x, pp, self.tol, self.charts)
        if out is not None:
            new, _ = self.point(out[0].x, out[1], v, True, its + out[0].iterations)
            if new is not None and new.stable:
                return new, ""
        return pt, why  # no stable state found from it: the unstable one, flagged

    def first(self, p, start, codegen) -> BranchPoint:
        """The point at the path's first value: ``start`` (an equilibrium there) corrected
        by Newton, or solved by :func:`~symcable.solvers.equilibrium.solve_equilibrium`."""
        path, block = self.path, self.block
        p_cur = self.at(path[0], p)
        if start is None:
            eq = solve_equilibrium(self.mech, p_cur, tol=self.tol, codegen=codegen)
            x0, its = np.concatenate([eq.q, eq.z]), int(eq.stats.get("iterations", 0))
        else:
            x0, its = np.concatenate([np.asarray(start.q, float), np.asarray(start.z, float)]), 0
            if start.p is not None:
                p_cur = self.at(path[0], np.asarray(start.p, float))
            res = newton(self.step, x0, p_cur, **self.opts)
            if not res.converged:
                raise ConvergenceError(f"the start is not an equilibrium at {block} = {path[0]}: "
                                       f"{res.message}", partial=self.branch)
            x0, its = res.x, res.iterations
        pt, why = self.settle(x0, p_cur, path[0], its)
        if pt is None:
            raise ConvergenceError(f"the start at {block} = {path[0]} failed its check: {why}",
                                   partial=self.branch)
        return pt

    def advance(self, k: int, prev):
        """(point at path[k], prev): the step from the last point to value k, by secant
        predictor (from ``prev``, the (value, x) before the last point, or None) and Newton,
        halved where it fails, a fold's snap relaxed; ``prev`` for the next step."""
        branch, path, block, opts, at = self.branch, self.path, self.block, self.opts, self.at
        last = branch.points[-1]
        p_base, renewed, q_last = self.charts.renew(last.q, last.p)
        x_last = np.concatenate([q_last, last.z])
        if renewed:
            branch.stats["reanchored"].append(k - 1)
            if q_last is not last.q:
                prev = None  # twists shifted by turns: no secant across them
        v0 = np.atleast_1d(np.array(path[k - 1], float))
        v1 = np.atleast_1d(np.array(path[k], float))
        frac, its = 0.0, 0
        x_cur, v_cur, jumped = x_last, v0, False
        h, halvings = 1.0, 0
        while frac < 1.0:
            f_new = min(1.0, frac + h)
            v_new = v0 + f_new * (v1 - v0)
            pred = x_cur
            if prev is not None and not last.left:
                dv = v_cur - prev[0]
                den = float(dv @ dv)
                if den > 0:
                    pred = x_cur + (x_cur - prev[1]) * float((v_new - v_cur) @ dv) / den
            res = newton(self.step, pred, at(v_new, p_base), **opts)
            if not res.converged and pred is not x_cur:
                res = newton(self.step, x_cur, at(v_new, p_base), **opts)
            its += res.iterations
            if res.converged:
                prev, x_cur, v_cur, frac = (v_cur, x_cur), res.x, v_new, f_new
                h = min(2.0 * h, 1.0 - frac) if frac < 1.0 else h
            else:
                halvings += 1
                branch.stats["halvings"] += 1
                h *= 0.5
                if halvings > self.max_halvings:
                    if self.leave_unstable:  # a fold: the branch ends; snap to where it relaxes
                        snap, p_snap = _relax(self.F, self.mech, x_cur, at(v1, p_base), self.tol,
                                              self.charts)
                        its += snap.iterations
                        if snap.converged:
                            branch.stats["snaps"].append((k, np.array(v_cur)))
                            x_cur, v_cur, frac, jumped = snap.x, v1, 1.0, True
                            p_base = p_snap
                            break
                    branch.stats["wall_time"] = time.perf_counter() - self.t0
                    branch.stats["reached"] = v_cur
                    raise ConvergenceError(
                        f"continuation in {block} stalled between {path[k - 1]} and "
                        f"{path[k]} after {self.max_halvings} halvings, at {v_cur} ({res.message})",
                        partial=branch, diagnostics={"reached": v_cur, "x": x_cur})
        pt, why = self.settle(x_cur, at(v1, p_base), path[k], its, jumped)
        if pt is None:
            branch.stats["wall_time"] = time.perf_counter() - self.t0
            raise ConvergenceError(f"the point at {block} = {path[k]} failed its check: {why}",
                                   partial=branch)
        if pt.left:
            prev = None
        return pt, prev
