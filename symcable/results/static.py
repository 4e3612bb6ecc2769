"""Solution objects: arrays with documented units and shapes, status, stats, export."""
from __future__ import annotations

import json
import math
from abc import ABCMeta
from dataclasses import dataclass, field, fields
from pathlib import Path
from types import MappingProxyType

import numpy as np

from .io import force_text, read_tree, write_tree

__all__ = ["Exportable", "ModalSolution", "OneLine", "PointState", "StaticSolution",
           "SystemStaticSolution"]


def _jsonable(v):
    """``v`` as plain JSON: lists for arrays, and null for a number that is not finite (JSON
    has no NaN or infinity; a float array reads null back as NaN)."""
    if isinstance(v, np.ndarray):
        return _jsonable(v.tolist()) if v.dtype.kind == "f" and not np.all(np.isfinite(v)) \
            else v.tolist()
    if isinstance(v, (np.floating, np.integer)):
        v = v.item()
    if isinstance(v, float) and not math.isfinite(v):
        return None
    if isinstance(v, dict):
        return {k: _jsonable(x) for k, x in v.items()}
    if isinstance(v, (list, tuple)):
        return [_jsonable(x) for x in v]
    return v


class Exportable:
    """Save/load for frozen dataclasses of arrays and plain values: ``to_dict``,
    ``to_json``, ``save`` (``.npz`` or ``.json``) and the classmethod ``load``. Array fields
    come back as float arrays, tuple fields as tuples."""

    def short_repr(self) -> str:
        """``Class(status, name, key scalars, array shapes)`` on one line, not every array."""
        head, scalars, arrays = [], [], []
        for f in fields(self):
            v = getattr(self, f.name)
            if f.name == "status":
                head.insert(0, f"status={v!r}")
            elif isinstance(v, np.ndarray):
                arrays.append(f"{f.name}=<{'x'.join(map(str, v.shape)) or 'scalar'}>")
            elif isinstance(v, (float, np.floating)):
                scalars.append(f"{f.name}={float(v):.6g}")
            elif isinstance(v, (str, bool, int, np.integer)):
                head.append(f"{f.name}={v!r}")
        n_warn = len(getattr(self, "warnings", ()) or ())
        tail = [f"warnings=<{n_warn}>"] if n_warn else []
        return f"{type(self).__name__}({', '.join(head + scalars + arrays + tail)})"

    # ------------------------------------------------------------------ export
    def to_dict(self) -> dict:
        """Every field as plain JSON-able Python (lists for arrays), units as documented."""
        return {f.name: _jsonable(getattr(self, f.name)) for f in fields(self)}

    def to_json(self, path: str | Path | None = None) -> str:
        """JSON text of :meth:`to_dict`; also written to ``path`` when given."""
        text = json.dumps(self.to_dict(), indent=1)
        if path is not None:
            Path(path).write_text(text)
        return text

    def save(self, path: str | Path) -> Path:
        """Save to ``.npz`` or ``.json`` by suffix (:mod:`symcable.results.io`):
        :meth:`load` reads either back equal, every array and number exactly."""
        return write_tree(path, {f.name: getattr(self, f.name) for f in fields(self)})

    @classmethod
    def _decode(cls, d: dict) -> dict:
        """Undo what a subclass's :meth:`to_dict` changed from the plain fields."""
        return d

    @classmethod
    def load(cls, path: str | Path):
        """Read a solution written by :meth:`save`."""
        return cls.from_dict(read_tree(path))

    @classmethod
    def from_dict(cls, d: dict):
        """The result of :meth:`to_dict`'s dict (arrays as lists or arrays)."""
        d = cls._decode(d)
        kw = {}
        for f in fields(cls):
            v = d.get(f.name)
            if f.type in ("tuple", "tuple[str, ...]") or f.name == "warnings":
                v = tuple(v or ())
            elif isinstance(v, list):  # a plain-JSON array (to_dict, or an earlier file)
                v = np.asarray(v, dtype=float)
            kw[f.name] = v
        return cls(**kw)



def _plot_3d(result, path, scene):
    """A 3D static solution's figure: the lines, points and bodies in a 3D view with the plan
    and the elevation (:func:`symcable.plotting.bodies.plot_system`), the seabed of ``scene``
    (when given and it has one) dashed in the elevation."""
    from ..plotting.bodies import plot_system

    seabed = None
    if scene is not None:
        if not hasattr(scene, "environment"):
            from ..scene import load_scene
            scene = load_scene(scene)
        depth = scene.environment.depth
        seabed = None if depth is None else -float(depth)
    return plot_system(result, path, scene=scene, seabed=seabed)


def _components(f) -> str:
    """'Fx a, Fz b kN' (planar) or 'Fx a, Fy b, Fz c kN' (3D), in the unit the force's
    magnitude takes (:func:`~symcable.results.io.force_text`)."""
    names = ("Fx", "Fz") if len(f) == 2 else ("Fx", "Fy", "Fz")
    return force_text(f, spec=".4f", sep=", ", names=names)


def _error_lines(stats: dict) -> list:
    """The summary's lines on the discretisation error (``stats["discretisation_error"]``,
    :mod:`symcable.api.static_error`) and the seabed's (``stats["seabed_error"]``,
    :mod:`symcable.api.bed_error`): per line the end tensions' estimated error, N and
    relative to the largest tension."""
    rep = stats.get("discretisation_error")
    if not rep or not rep.get("lines"):
        return []
    out = []
    for name, e in rep["lines"].items():
        label = "discretisation" if len(rep["lines"]) == 1 else f"  error {name}"
        out.append(f"{label:17s} {e['error']:.3g} N ({e['relative']:.2%} of the largest "
                   f"tension) at {e['segments']} segments, estimated against "
                   f"{e['compared_with']}")
    if rep.get("rounds"):
        out.append(f"refined           {rep['rounds']} rounds to {rep['accuracy']:.2%}")
    bed = stats.get("seabed_error")
    for name, e in ((bed or {}).get("lines") or {}).items():
        label = "seabed" if len(bed["lines"]) == 1 else f"  seabed {name}"
        out.append(f"{label:17s} {e['error']:.3g} N ({e['relative']:.2%} of the largest "
                   f"tension) from a rigid bed's, sinking {e['sinking']:.3g} m")
    return out


class OneLine:
    """Results per part for a one-line scene: ``.lines["line"]`` is the result itself (the
    same fields), ``.points`` and ``.bodies`` are empty. Scenes of several parts give each
    line, point and body its own entry."""

    LINE_NAME = "line"

    @property
    def lines(self):
        from types import MappingProxyType
        return MappingProxyType({self.LINE_NAME: self})

    @property
    def points(self):
        from types import MappingProxyType
        return MappingProxyType({})

    @property
    def bodies(self):
        from types import MappingProxyType
        return MappingProxyType({})


@dataclass(frozen=True)
class StaticSolution(OneLine, Exportable, metaclass=ABCMeta):
    """Static configuration of a line. ``n`` is the number of nodes, ``n - 1`` of segments.
    The type of every static result: a scene of several lines, points and bodies gives a
    :class:`SystemStaticSolution`, a StaticSolution too (``isinstance`` holds), whose
    ``lines[name]`` are this class.

    Attributes
    ----------
    scene_name : str
    s : ndarray (n,)
        Unstretched arc length of the nodes from end A, m.
    positions : ndarray (n, 2) or (n, 3)
        Node positions (x, z), m; (x, y, z) for a cable3d scene.
    angle : ndarray (n-1,)
        Tangent angle of each segment from +x towards +z, rad (cable3d: its elevation above
        the horizontal).
    strain : ndarray (n-1,)
        Axial strain of each segment, -.
    axial_force : ndarray (n-1,)
        Axial force EA * strain of each segment, N.
    shear : ndarray (n-1,)
        Shear force of each segment, N (0 without bending).
    moment : ndarray (n,)
        Bending moment at the nodes, N m (0 without bending).
    tension : ndarray (n,)
        Magnitude of the internal force at the nodes, N (at the ends: the end forces).
    contact_force : ndarray (n,)
        Seabed contact force carried by each node, N.
    fairlead_force, anchor_force : ndarray (2,) or (3,)
        Force the line exerts on its end B (fairlead) and end A (anchor), N.
    fairlead_tension, anchor_tension : float
        Their magnitudes, N.
    grounded_length : float
        Unstretched length resting on the seabed, m.
    touchdown : ndarray (2,) or (3,), or None
        Position of the touchdown point, m (None without seabed contact).
    status : str
        ``"converged"`` or ``"failed"`` (only on a ConvergenceError's partial result).
    stats : dict
        ``iterations``, ``residual_norm`` (N), ``tolerance`` (N), ``wall_time`` (s),
        ``path``, ``start``, ``continuation_steps``, ``unknowns``, ``terms``.
    warnings : tuple of str
    unknowns : ndarray
        The solver's unknown vector (to restart from).
    """

    scene_name: str
    s: np.ndarray
    positions: np.ndarray
    angle: np.ndarray
    strain: np.ndarray
    axial_force: np.ndarray
    shear: np.ndarray
    moment: np.ndarray
    tension: np.ndarray
    contact_force: np.ndarray
    fairlead_force: np.ndarray
    anchor_force: np.ndarray
    fairlead_tension: float
    anchor_tension: float
    grounded_length: float
    touchdown: np.ndarray | None
    status: str
    stats: dict = field(default_factory=dict)
    warnings: tuple = ()
    unknowns: np.ndarray | None = None

    __repr__ = Exportable.short_repr

    # ------------------------------------------------------------------ summary
    def summary(self) -> str:
        """A few lines a person reads: end tensions (kN), grounded length (m), solver stats."""
        st = self.stats
        lines = [
            f"scene             {self.scene_name}",
            f"status            {self.status} via {st.get('path', '?')} from {st.get('start', '?')}",
            f"fairlead tension  {force_text(self.fairlead_tension, spec='.4f')}  "
            f"({_components(self.fairlead_force)})",
            f"anchor tension    {force_text(self.anchor_tension, spec='.4f')}  "
            f"({_components(self.anchor_force)})",
            f"grounded length   {self.grounded_length:.3f} m",
            f"max |moment|      {force_text(np.max(np.abs(self.moment)), 'N m', '.4f')}",
            f"solver            {st.get('iterations', '?')} iterations, residual "
            f"{st.get('residual_norm', float('nan')):.3g} N (tol {st.get('tolerance', float('nan')):.3g} N), "
            f"{1e3 * st.get('wall_time', float('nan')):.1f} ms",
        ]
        lines += _error_lines(st)
        lines += [f"warning           {w}" for w in self.warnings]
        return "\n".join(lines)

    # ------------------------------------------------------------------ plots
    def plot(self, path: str | Path | None = None, scene=None):
        """Profile, and tension (and bending moment, when EI > 0) along the line, in one
        figure (saved to ``path`` when given). Give the ``scene`` solved to mark its sections,
        free surface and seabed (see :func:`symcable.plotting.profiles.plot_static`). Returns the
        matplotlib Figure."""
        if self.positions.shape[1] != 2:
            return _plot_3d(self, path, scene)
        from ..plotting.profiles import plot_static
        return plot_static(self, path, scene=scene)


@dataclass(frozen=True)
class ModalSolution(Exportable):
    """Undamped natural modes of a line about its static state
    (:func:`symcable.modal_analysis`).

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
        Real part of each mode's eigenvalue, 1/s: zero for the conservative linear model
        (exactly, when it is solved as a symmetric problem; see ``stats["method"]``).
    shapes : ndarray (n_modes, n, 2)
        Mode shapes as node displacement amplitudes (x, z), m, each scaled so its largest
        node displacement ``hypot(x, z)`` is 1 and that entry's largest component is
        positive. Nodes with prescribed motion (pinned ends) have zero displacement.
    status : str
        ``"converged"``.
    stats : dict
        ``n_y`` (state size), ``method`` (the eigenproblem solved), ``zero_modes``
        (eigenvalues of the state matrix that are zero: invariants such as the closure of a
        line held at both ends, and rigid modes), ``zero_tolerance`` (1/s: smaller
        frequencies count as zero), ``max_relative_real_part`` (max |Re lambda| / |lambda|
        over the returned modes, -), ``model_time`` (building the dynamic model, static
        solve included, when not given), ``jacobian_time`` (the exact tangents K, M and
        kinematics G), ``eig_time`` (the eigen-solve), ``wall_time`` (s).
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

    def plot(self, path: str | Path | None = None, *, seabed: float | None = None):
        """The mode shapes on the static state: a planar line's in its plane
        (:func:`symcable.plotting.profiles.plot_modes`), a 3D scene's in plan, elevation and
        end view with each line apart (:func:`symcable.plotting.line3d.plot_modes_3d`; the
        seabed at z = ``seabed`` m when given); saved to ``path`` when given; returns the
        Figure."""
        if np.asarray(self.positions).shape[-1] == 3:
            from ..plotting.line3d import plot_modes_3d
            return plot_modes_3d(self, path, seabed=seabed)
        from ..plotting.profiles import plot_modes
        return plot_modes(self, self.positions, path)

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


@dataclass(frozen=True)
class PointState:
    """A point of a scene of several lines, in a solution (:class:`SystemStaticSolution`).

    Attributes
    ----------
    name : str
    kind : str
        ``"fixed"``, ``"vessel"`` or ``"free"``.
    position : ndarray (3,)
        m.
    force : ndarray (3,)
        The force the attached lines exert on the point, N (on a fixed or vessel point: what
        holds it must take its opposite).
    net_force : ndarray (3,) or None
        Free points: ``force`` plus the point's own weight, buoyancy, drag and applied
        force, N (zero in equilibrium, to the solver's tolerance); None for held points.
    """

    name: str
    kind: str
    position: np.ndarray
    force: np.ndarray
    net_force: np.ndarray | None = None

    @property
    def tension(self) -> float:
        """|force|, N."""
        return float(np.linalg.norm(self.force))


@dataclass(frozen=True)
class BodyState:
    """A rigid body of a scene of several lines, in a solution (:class:`SystemStaticSolution`).

    Attributes
    ----------
    name, kind : str  (``"free"`` or ``"fixed"``)
    position : ndarray (3,)  m, the reference point
    orientation : ndarray (4,)  unit quaternion (e0, e1, e2, e3), body to global axes
    roll_pitch_yaw : ndarray (3,)  deg, R = Rz(yaw) Ry(pitch) Rx(roll)
    force, moment : ndarray (3,)
        N and N m: the force of the attached lines on the body and its moment about the
        reference point, global axes (on a fixed body: what holds it takes their opposite).
    net_force : ndarray (6,) or None
        Free bodies: ``force``, ``moment`` plus the body's weight, buoyancy and drag (zero in
        equilibrium, to the solver's tolerance); None for fixed bodies.
    """

    name: str
    kind: str
    position: np.ndarray
    orientation: np.ndarray
    roll_pitch_yaw: np.ndarray
    force: np.ndarray
    moment: np.ndarray
    net_force: np.ndarray | None = None


@dataclass(frozen=True)
class SystemStaticSolution:
    """Static configuration of a scene of several lines and points (scene version 2).

    Attributes
    ----------
    scene_name : str
    lines : Mapping[str, StaticSolution]
        Each line's own static solution (positions (n, 3), tension, fairlead_tension =
        |force on its end B|, anchor_tension, grounded_length, ...), by line name; their
        ``status`` and ``stats`` are the system's.
    points : Mapping[str, PointState]
        Every point's position and forces, by point name.
    status : str
        ``"converged"`` or ``"failed"`` (only on a ConvergenceError's partial result).
    stats : dict
        As :class:`StaticSolution`'s.
    warnings : tuple of str
    unknowns : ndarray
        The solver's unknown vector (to restart from).
    bodies : Mapping[str, BodyState]
        Every body's pose and the lines' force and moment on it, by body name.
    """

    scene_name: str
    lines: object
    points: object
    status: str
    stats: dict = field(default_factory=dict)
    warnings: tuple = ()
    unknowns: np.ndarray | None = None
    bodies: object = field(default_factory=lambda: MappingProxyType({}))

    def __repr__(self) -> str:
        return (f"SystemStaticSolution(status={self.status!r}, scene_name={self.scene_name!r}, "
                f"lines={list(self.lines)}, points={list(self.points)})")

    def summary(self) -> str:
        """Per line its end tensions (kN) and grounded length (m), per point its position
        (m) and the lines' force on it (kN), then the solver's stats."""
        st = self.stats
        out = [f"scene             {self.scene_name}",
               f"status            {self.status} via {st.get('path', '?')} from "
               f"{st.get('start', '?')}"]
        for name, ln in self.lines.items():
            out.append(f"line {name:12s} fairlead {force_text(ln.fairlead_tension, spec='.4f')}, "
                       f"anchor {force_text(ln.anchor_tension, spec='.4f')}, grounded "
                       f"{ln.grounded_length:.3f} m")
        for name, pt in self.points.items():
            x = ", ".join(f"{v:.3f}" for v in pt.position)
            out.append(f"point {name:11s} {pt.kind:6s} at ({x}) m, lines' force "
                       f"{_components(pt.force)}")
        for name, b in self.bodies.items():
            x = ", ".join(f"{v:.3f}" for v in b.position)
            a = ", ".join(f"{v:.3f}" for v in b.roll_pitch_yaw)
            out.append(f"body {name:12s} {b.kind:6s} at ({x}) m, roll/pitch/yaw ({a}) deg, "
                       f"lines' force {_components(b.force)}")
        out.append(f"solver            {st.get('iterations', '?')} iterations, residual "
                   f"{st.get('residual_norm', float('nan')):.3g} N (tol "
                   f"{st.get('tolerance', float('nan')):.3g} N)")
        out += _error_lines(st)
        out += [f"warning           {w}" for w in self.warnings]
        return "\n".join(out)

    def to_dict(self) -> dict:
        """Plain JSON-able Python: each line's :meth:`StaticSolution.to_dict`, each point's
        fields, the status, stats and warnings."""
        return {"scene_name": self.scene_name,
                "lines": {k: v.to_dict() for k, v in self.lines.items()},
                "points": {k: {f.name: _jsonable(getattr(v, f.name)) for f in fields(v)}
                           for k, v in self.points.items()},
                "bodies": {k: {f.name: _jsonable(getattr(v, f.name)) for f in fields(v)}
                           for k, v in self.bodies.items()},
                "status": self.status, "stats": _jsonable(self.stats),
                "warnings": list(self.warnings),
                "unknowns": _jsonable(self.unknowns)}

    def to_json(self, path: str | Path | None = None) -> str:
        """JSON text of :meth:`to_dict`; also written to ``path`` when given."""
        text = json.dumps(self.to_dict(), indent=1)
        if path is not None:
            Path(path).write_text(text)
        return text

    def plot(self, path: str | Path | None = None, scene=None):
        """The lines, points and bodies in a 3D view with the plan and the elevation (the
        seabed of ``scene``, when given, dashed), saved to ``path`` when given; returns the
        matplotlib Figure."""
        return _plot_3d(self, path, scene)

    def save(self, path: str | Path) -> Path:
        """Save to ``.npz`` or ``.json`` by suffix (:mod:`symcable.results.io`): every
        line's, point's and body's fields, the status, stats and warnings; :meth:`load` reads
        either back equal, every number exactly."""
        def part(v):
            return {f.name: getattr(v, f.name) for f in fields(v)}
        return write_tree(path, {
            "scene_name": self.scene_name, "lines": {k: part(v) for k, v in self.lines.items()},
            "points": {k: part(v) for k, v in self.points.items()},
            "bodies": {k: part(v) for k, v in self.bodies.items()}, "status": self.status,
            "stats": self.stats, "warnings": tuple(self.warnings), "unknowns": self.unknowns})

    @classmethod
    def load(cls, path: str | Path) -> "SystemStaticSolution":
        """Read a solution written by :meth:`save`."""
        d = read_tree(path)

        def state(kind, v):
            return kind(**{f.name: (np.asarray(v[f.name], dtype=float)
                                    if isinstance(v.get(f.name), (list, np.ndarray)) else
                                    v.get(f.name)) for f in fields(kind)})

        lines = {k: StaticSolution.from_dict(v) for k, v in d["lines"].items()}
        unknowns = d.get("unknowns")
        return cls(scene_name=d["scene_name"], lines=MappingProxyType(lines),
                   points=MappingProxyType({k: state(PointState, v)
                                            for k, v in d["points"].items()}),
                   status=d["status"], stats=d.get("stats") or {},
                   warnings=tuple(d.get("warnings") or ()),
                   unknowns=None if unknowns is None else np.asarray(unknowns, dtype=float),
                   bodies=MappingProxyType({k: state(BodyState, v)
                                            for k, v in d.get("bodies", {}).items()}))


StaticSolution.register(SystemStaticSolution)  # a scene of several lines: a StaticSolution too
