"""Scenes: the validated, frozen description of one cable problem.

A scene comes from a TOML file or a plain dict (the layout the README documents under "A
scene file") through :func:`load_scene`, which checks every key and raises a one-line
:class:`~symcable.errors.SceneError` naming the key, the value and what is allowed.

Units are SI throughout; angles are degrees in the file and radians in the dataclasses
(attributes ending in ``_deg`` keep degrees, as the file gave them).
"""
from __future__ import annotations

import enum
import math
from dataclasses import dataclass, field
from types import MappingProxyType
from typing import TYPE_CHECKING, Any, Mapping

from .bodies import Body, BodyEnd, body_dict
from .line_types import Family, line_type_dict
from .points import Line, Point, PointKind
from .waves import Waves

if TYPE_CHECKING:  # a field's type only
    from .loading import LoadingFunctions

__all__ = [
    "EndCondition", "Model", "LineType", "Section", "Motion", "End", "Environment", "Seabed",
    "Scene", "scene_to_dict", "Point", "PointKind", "Line", "Body", "BodyEnd",
]

class EndCondition(str, enum.Enum):
    """How an end of the line is held."""

    PINNED = "pinned"    #: position given, free to rotate, no moment
    #: position and tangent given (angle_deg planar, direction cable3d); needs EI > 0 there
    CLAMPED = "clamped"
    FREE = "free"        #: external force given, position unknown, no moment


class Model(str, enum.Enum):
    """Formulations a scene can ask for (``model = ...``)."""

    PLANAR = "planar"    #: a line in the vertical x-z plane; vectors are [x, z]
    CABLE3D = "cable3d"  #: a 3D position-vector cable; vectors are [x, y, z]
    ROD = "rod"          #: a Kirchhoff rod (bending, torsion); vectors [x, y, z]
    #: sections of ``rod`` and ``cable3d`` joined by moment-free joints; [x, y, z]
    HYBRID = "hybrid"


#: space dimensions of each model: the length of every vector in its scenes (z is up)
_DIMS = {Model.PLANAR: 2, Model.CABLE3D: 3, Model.ROD: 3, Model.HYBRID: 3}


@dataclass(frozen=True)
class LineType:
    """Properties of one line type (``[line_types.NAME]``).

    Attributes
    ----------
    name : str
    EA : float
        Axial stiffness, N (> 0).
    EI : float
        Bending stiffness, N m^2 (>= 0; 0 builds no bending term). Segments with EI > 0
        carry compression (the linear law EA e); cable segments (EI = 0) are tension-only.
    mass : float
        Structural mass per unstretched length, kg/m (> 0).
    diameter : float
        Hydrodynamic (and buoyancy) diameter, m (> 0).
    weight : float
        Submerged weight per unstretched length, N/m; the file may give it, else it is
        ``(mass - water_density*pi*diameter**2/4) * gravity``. May be <= 0 (buoyant line).
    cd_normal, cd_tangential : float
        Morison drag coefficients on the normal and tangential relative velocity (>= 0).
    ca_normal : float
        Normal added-mass coefficient (>= 0).
    max_strain : float
        Largest admissible axial strain (> 0), used to decide whether a fairlead is out of
        reach; default 0.1.
    ca_tangential : float
        Tangential added-mass coefficient (>= 0; cable3d only), default 0.
    damping : float
        Axial material damping BA, N s (cable3d only; Sun, Zhu & LaRosa's C = c K,
        BA = c EA): the axial force gains BA de/dt. Negative: minus the damping ratio of the
        line's highest axial mode (adjacent nodes in opposition), BA = -damping x ds
        sqrt(EA mass), as MoorDyn's BA/-zeta. Default 0.
    drag_law : str
        cable3d: ``"morison"`` (default: ``cd_normal``, ``cd_tangential`` on the normal and
        tangential relative speeds) or ``"loading-functions"`` (``loading``; then
        ``cd_normal`` and ``cd_tangential`` are not read).
    loading : LoadingFunctions or None
        The loading functions (``[line_types.NAME.loading]``,
        :class:`~symcable.scene.loading.LoadingFunctions`), with ``drag_law =
        "loading-functions"`` only.
    EI_2 : float or None
        ``model = "rod"`` only: the second principal bending stiffness, N m^2 (the file's
        ``EI = [EI_1, EI_2]``; ``EI`` is then EI_1, about the material director m1); None:
        isotropic, EI_2 = EI.
    GJ : float
        ``model = "rod"`` only: torsional stiffness, N m^2 (>= 0), default 0.
    tension_twist : float
        ``model = "rod"`` only: the tension-torsion coupling K of a helically armoured
        cable, N m (default 0): energy K e tau per metre, so T = EA e + K tau and
        M_t = GJ tau + K e (K^2 < EA GJ).
    breaking_load : float or None
        Minimum breaking load, N (a family's, or the table's ``breaking_load``); None: not
        given.
    family : Family or None
        The catalogue family the table named (:mod:`symcable.scene.line_types`), if any.
    """

    name: str
    EA: float
    EI: float
    mass: float
    diameter: float
    weight: float
    cd_normal: float = 1.2
    cd_tangential: float = 0.008
    ca_normal: float = 1.0
    max_strain: float = 0.1
    ca_tangential: float = 0.0
    damping: float = 0.0
    drag_law: str = "morison"
    loading: LoadingFunctions | None = None
    EI_2: float | None = None
    GJ: float = 0.0
    tension_twist: float = 0.0
    breaking_load: float | None = None
    family: Family | None = None


@dataclass(frozen=True)
class Section:
    """A stretch of line of one type, from end A towards end B (``[[sections]]``).

    Attributes
    ----------
    line_type : LineType
        The resolved line type.
    length : float
        Unstretched length, m (> 0).
    segments : int
        Number of segments it is divided into (>= 1).
    model : str or None
        ``model = "hybrid"`` only: the section's formulation, ``"rod"`` or ``"cable3d"``
        (the file's ``[[sections]] model``); None when not given (a hybrid section is then
        ``"cable3d"``, or chosen by ``zones = "auto"``).
    """

    line_type: LineType
    length: float
    segments: int
    model: str | None = None

    @property
    def ds(self) -> float:
        """Unstretched segment length, m."""
        return self.length / self.segments


@dataclass(frozen=True)
class Motion:
    """Prescribed motion of an end about its position (``[end_b.motion]``).

    ``"harmonic"``: ``x_i(t) = amplitude[i] * cos(2*pi*t/period + phase[i])``.
    ``"table"`` (cable3d): the displacement read from a file of rows ``t x y z [rx ry rz]``,
    linearly interpolated, held at its first and last rows outside it (rotations ignored:
    an end is a point).
    ``"tow"`` (cable3d): a towpoint moving at constant ``speed`` in the x-y plane, straight
    on ``heading`` and through the circular ``turns`` (:mod:`symcable.scene.tow`; the path
    is :func:`symcable.models.common.tow.tow_path`).

    Attributes
    ----------
    kind : str
        ``"harmonic"``, ``"table"`` or ``"tow"``.
    period : float
        s (> 0); for a table, its time span; for a tow, the time from ``start`` to the end
        of its last turn (0 without turns): a tow has no period.
    amplitude : tuple of float
        m, one per coordinate: (x, z) planar, (x, y, z) cable3d; for a table, the largest
        |displacement| per coordinate.
    phase_deg : tuple of float
        degrees, one per coordinate (zeros for a table).
    file : str or None
        The table's file, resolved (absolute).
    samples : tuple of (t, dx, dy, dz) or None
        The table's rows, s and m.
    speed : float or None
        A tow's speed, m/s (> 0).
    heading_deg : float or None
        A tow's first heading, degrees: its direction of travel in the x-y plane from +x,
        counter-clockwise.
    start : float
        A tow: the time (s) at which the point passes its scene position; the first turn's
        ``after`` counts from it. The tow runs at ``speed`` from t = -inf.
    turns : tuple of (after, radius, angle_deg)
        A tow's turns, in order: after a straight run of ``after`` s (>= 0), a circular turn
        of ``radius`` m (> 0) through ``angle_deg`` degrees (positive: to port, i.e.
        counter-clockwise seen from above), then straight on the new heading.
    rigid : RigidPath or None
        ``"body"``: a line end at a point of a vessel (:class:`~symcable.scene.vessel.RigidPath`;
        not a file's kind: the models' one-line scenes of a vessel's lines). ``"coupled"``:
        moved by a host program (:class:`symcable.Coupling`, :mod:`symcable.scene.coupled`;
        not a file's kind either).
    """

    kind: str
    period: float
    amplitude: tuple[float, ...]
    phase_deg: tuple[float, ...]
    file: str | None = None
    samples: tuple | None = None
    speed: float | None = None
    heading_deg: float | None = None
    start: float = 0.0
    turns: tuple = ()
    rigid: Any = None

    @property
    def omega(self) -> float:
        """Angular frequency, rad/s."""
        return 2.0 * math.pi / self.period

    @property
    def phase(self) -> tuple[float, ...]:
        """Phases, rad."""
        return tuple(math.radians(p) for p in self.phase_deg)


@dataclass(frozen=True)
class End:
    """One end of the line (``[end_a]``, the anchor; ``[end_b]``, the fairlead).

    Attributes
    ----------
    condition : EndCondition
    position : tuple of float or None
        m, (x, z) planar or (x, y, z) cable3d, z up; given for pinned and clamped ends,
        None for a free end.
    angle_deg : float or None
        Clamped ends only (planar): angle of the line's tangent (direction of increasing arc length,
        i.e. pointing from A towards B) from +x, counter-clockwise, degrees.
    direction : tuple of float or None
        Clamped ends only (cable3d): the line's unit tangent at the end, pointing from A
        towards B (the file's vector, normalised); it keeps its direction while the end
        moves. ``model = "rod"``: also a guided end's (``condition = "guided"``, read as a
        free end with a direction: position unknown, tangent held; :attr:`guided`).
    force : tuple of float or None
        Free ends only: external force applied to the end, N, one component per coordinate
        (zero vector if not given).
    motion : Motion or None
        Prescribed motion about ``position`` (pinned/clamped ends only).
    twist_deg : float or None
        Clamped ends of ``model = "rod"`` only: the angle of the clamp's material director
        m1 about ``direction`` from the reference director
        (:func:`symcable.models.rod.frames.reference_director` of the direction), degrees;
        None: 0.
    moment : tuple of float or None
        Free (not guided) ends of ``model = "rod"``, or of a rod section of ``"hybrid"``:
        a dead moment applied to the end, [M_x, M_y, M_z] N m (None: none).
    """

    condition: EndCondition
    position: tuple[float, ...] | None = None
    angle_deg: float | None = None
    force: tuple[float, ...] | None = None
    motion: Motion | None = None
    direction: tuple[float, ...] | None = None
    twist_deg: float | None = None
    moment: tuple[float, ...] | None = None

    @property
    def angle(self) -> float | None:
        """Clamped tangent angle, rad (None unless clamped)."""
        return None if self.angle_deg is None else math.radians(self.angle_deg)

    @property
    def guided(self) -> bool:
        """True for a guided end (rod): free, with its tangent ``direction`` held."""
        return self.condition is EndCondition.FREE and self.direction is not None

    @property
    def is_fixed(self) -> bool:
        """True when the position is given (pinned or clamped)."""
        return self.condition is not EndCondition.FREE


@dataclass(frozen=True)
class Environment:
    """Gravity, water and current (``[environment]``).

    Attributes
    ----------
    gravity : float
        m/s^2 (> 0), default 9.80665.
    water_density : float
        kg/m^3 (>= 0), default 1025; 0 means the cable is in air (no buoyancy, drag or
        added mass).
    depth : float or None
        m (> 0); a flat seabed at z = -depth, or None for no seabed.
    current : tuple of float
        Uniform current velocity, m/s: [U_x, U_z] planar, [U_x, U_y, U_z] cable3d; default
        zero (the loader gives the scene's dimension; the dataclass default is planar).
    current_profile : tuple of (z, U_x, U_y, U_z)
        cable3d: a current varying with depth, rows by ascending z (m, up), linear between
        them and held beyond (added to ``current``); empty: none.
    waves : Waves or None
        Linear waves (``[environment.waves]``, :class:`~symcable.scene.waves.Waves`; 3D
        scenes in water); None: a calm sea.
    """

    gravity: float = 9.80665
    water_density: float = 1025.0
    depth: float | None = None
    current: tuple[float, ...] = (0.0, 0.0)
    current_profile: tuple = ()
    waves: Waves | None = None

    @property
    def in_air(self) -> bool:
        return self.water_density == 0.0


@dataclass(frozen=True)
class Seabed:
    """Seabed contact (``[seabed]``; present whenever ``environment.depth`` is given).

    Attributes
    ----------
    stiffness : float
        Pa/m (> 0): vertical contact pressure per metre of penetration; the contact force per
        unstretched length is ``stiffness * diameter * penetration``. Default 1e5.
    friction : float
        Coulomb coefficient (>= 0). Statics treat the seabed as frictionless (friction is
        statically indeterminate) unless ``static_friction`` says otherwise; the cable3d
        dynamics apply it by ``friction_law``.
    damping : float
        Pa s/m (>= 0): the normal damper of the contact, pressure per m/s of the node's
        vertical speed while it is in contact (cable3d dynamics).
    friction_axial, friction_lateral : float or None
        Coulomb coefficients along and across the line (cable3d dynamics); None: ``friction``.
    friction_velocity : float
        m/s (> 0): the speed over which the Coulomb law is regularised,
        -mu N v / sqrt(|v|^2 + friction_velocity^2). Default 0.01. Not used by the bristle law.
    friction_law : str
        cable3d dynamics (:mod:`symcable.models.common.friction`): ``"coulomb"`` (default,
        the law above) or ``"bristle"`` (an elastic bristle per node that slips at mu N:
        holds force at rest; in a scene of several lines on every line's nodes, a free
        point on the bed keeping the Coulomb law).
    friction_stiffness : float or None
        Pa/m (> 0): tangential stiffness per unit contact area, of the bristle and of the
        static spring (mobilisation length mu N / (stiffness x area)); None: ``stiffness``.
    static_friction : str
        cable3d statics: ``"none"`` (default, frictionless) or ``"laid"`` (a smooth capped
        spring, at most mu N, from the as-laid shape: the catenary in the ends' vertical
        plane). One-line scenes with both ends held.
    """

    stiffness: float = 1.0e5
    friction: float = 0.0
    damping: float = 0.0
    friction_axial: float | None = None
    friction_lateral: float | None = None
    friction_velocity: float = 0.01
    friction_law: str = "coulomb"
    friction_stiffness: float | None = None
    static_friction: str = "none"

    @property
    def tangential_stiffness(self) -> float:
        """Pa/m: ``friction_stiffness``, or ``stiffness`` when not given."""
        return self.stiffness if self.friction_stiffness is None else self.friction_stiffness

    @property
    def mu_axial(self) -> float:
        return self.friction if self.friction_axial is None else self.friction_axial

    @property
    def mu_lateral(self) -> float:
        return self.friction if self.friction_lateral is None else self.friction_lateral


@dataclass(frozen=True)
class Scene:
    """A validated scene. Build it with :func:`load_scene`, not by hand.

    Attributes
    ----------
    name : str
    model : Model
    environment : Environment
    seabed : Seabed or None
        None when the scene has no seabed (no ``environment.depth``).
    line_types : Mapping[str, LineType]
        Read-only mapping, name -> type.
    sections : tuple of Section
        From end A to end B (a version-1 scene, one line); empty in a scene of several
        lines (version 2).
    end_a, end_b : End or None
        The ends of a version-1 scene's line; None in version 2.
    source : str
        Where the scene came from (file path or ``"<dict>"``), for messages.
    points : Mapping[str, Point]
        Version 2 (``[points.NAME]``): read-only mapping, name -> point; empty in version 1.
    lines : tuple of Line
        Version 2 (``[[lines]]``): the lines, each with its sections and ends (a point's
        name or an inline End); empty in version 1.
    mass_matrix : str
        cable3d: ``"lumped"`` (default: half of each element's mass, structural and added,
        on each of its nodes) or ``"consistent"`` (Sun, Zhu & LaRosa's linear-interpolation
        mass, L0/6 [[2, 1], [1, 2]] per element, coupling neighbours).
    bodies : Mapping[str, Body]
        Version 2 (``[bodies.NAME]``, :mod:`.bodies`): read-only mapping, name -> rigid
        body; lines attach to them (a line end :class:`BodyEnd`); empty without.
    zones : str
        ``model = "hybrid"``: ``"given"`` (default: each section's ``model``, cable3d when
        not given) or ``"auto"`` (the rod sections chosen from the line's static tension,
        :func:`symcable.api.rod_static.hybrid_zones`).
    """

    name: str
    model: Model
    environment: Environment
    seabed: Seabed | None
    line_types: Mapping[str, LineType]
    sections: tuple[Section, ...]
    end_a: End | None
    end_b: End | None
    source: str = field(default="<dict>", compare=False)
    points: Mapping[str, Point] = field(default_factory=lambda: MappingProxyType({}))
    lines: tuple[Line, ...] = ()
    mass_matrix: str = "lumped"
    bodies: Mapping[str, Body] = field(default_factory=lambda: MappingProxyType({}))
    zones: str = "given"

    @property
    def version(self) -> int:
        """1: one line (``[[sections]]``, ``[end_a]``, ``[end_b]``); 2: ``[[lines]]`` and
        ``[points.NAME]``."""
        return 2 if self.lines else 1

    @property
    def dim(self) -> int:
        """Number of space dimensions, the length of every vector in the scene: 2 for
        ``planar`` (x, z), 3 for ``cable3d`` (x, y, z); z is up in both."""
        return _DIMS[Model(self.model)]

    @property
    def length(self) -> float:
        """Total unstretched length, m (of every line, in version 2)."""
        return sum(s.length for s in self.sections) + sum(ln.length for ln in self.lines)

    @property
    def n_segments(self) -> int:
        """Number of segments (of every line, in version 2)."""
        return sum(s.segments for s in self.sections) + sum(ln.n_segments for ln in self.lines)

    @property
    def n_nodes(self) -> int:
        """Number of nodes (of every line, in version 2: each line has its own end nodes)."""
        return self.n_segments + max(1, len(self.lines))

    def to_dict(self) -> dict:
        """The scene as a plain dict in the file's layout (angles in degrees), such that
        ``load_scene(scene.to_dict())`` gives an equal scene."""
        return scene_to_dict(self)


def scene_to_dict(scene: Scene) -> dict:
    """The scene as a plain dict in the file's layout, every key written out.

    Angles are in degrees, vectors are lists, the (possibly computed) ``weight`` is explicit,
    ``environment.depth`` and ``[seabed]`` are omitted when there is no seabed.
    ``load_scene(scene_to_dict(s))`` equals ``s`` except for ``source``.
    """
    env = scene.environment
    environment: dict[str, Any] = {"gravity": env.gravity, "water_density": env.water_density}
    if env.depth is not None:
        environment["depth"] = env.depth
    environment["current"] = list(env.current)
    if env.current_profile:
        environment["current_profile"] = [list(r) for r in env.current_profile]
    if env.waves is not None:
        environment["waves"] = env.waves.to_dict()
    out: dict[str, Any] = {"name": scene.name, "model": Model(scene.model).value,
                           "environment": environment}
    if scene.mass_matrix != "lumped":
        out["mass_matrix"] = scene.mass_matrix
    if scene.zones != "given":
        out["zones"] = scene.zones
    if scene.seabed is not None:
        sb = scene.seabed
        out["seabed"] = {"stiffness": sb.stiffness, "friction": sb.friction}
        if sb.damping:
            out["seabed"]["damping"] = sb.damping
        for key in ("friction_axial", "friction_lateral"):
            if getattr(sb, key) is not None:
                out["seabed"][key] = getattr(sb, key)
        if sb.friction_velocity != Seabed.friction_velocity:
            out["seabed"]["friction_velocity"] = sb.friction_velocity
        for key in ("friction_law", "friction_stiffness", "static_friction"):
            if getattr(sb, key) != getattr(Seabed, key):
                out["seabed"][key] = getattr(sb, key)
    types = dict(scene.line_types)
    for s in scene.sections + tuple(x for ln in scene.lines for x in ln.sections):
        types.setdefault(s.line_type.name, s.line_type)  # a hand-built Scene may miss some
    out["line_types"] = {name: line_type_dict(lt) for name, lt in types.items()}
    if scene.lines:
        out["points"] = {name: _point_dict(pt) for name, pt in scene.points.items()}
        if scene.bodies:
            out["bodies"] = {name: body_dict(b) for name, b in scene.bodies.items()}
        out["lines"] = [{"name": ln.name, "end_a": _end_ref(ln.end_a), "end_b": _end_ref(ln.end_b),
                         "sections": _sections_list(ln.sections)} for ln in scene.lines]
        return out
    out["sections"] = _sections_list(scene.sections)
    for key, end in (("end_a", scene.end_a), ("end_b", scene.end_b)):
        out[key] = _end_dict(end)
    return out


def _sections_list(sections) -> list:
    return [{"type": s.line_type.name, "length": s.length, "segments": s.segments,
             **({"model": s.model} if s.model is not None else {})} for s in sections]


def _motion_dict(m: Motion) -> dict:
    if m.kind == "coupled":
        return {"kind": "coupled"}
    if m.kind == "body":
        return {"kind": "body", "path": m.rigid.key()}
    if m.kind == "tow":
        return {"kind": "tow", "speed": m.speed, "heading": m.heading_deg, "start": m.start,
                "turns": [{"after": a, "radius": r, "angle": g} for a, r, g in m.turns]}
    return ({"kind": "table", "file": m.file} if m.kind == "table" else
            {"kind": m.kind, "period": m.period, "amplitude": list(m.amplitude),
             "phase_deg": list(m.phase_deg)})


def _end_dict(end: End) -> dict:
    e: dict[str, Any] = {"condition": EndCondition(end.condition).value}
    if end.position is not None:
        e["position"] = list(end.position)
    if end.angle_deg is not None:
        e["angle_deg"] = end.angle_deg
    if end.direction is not None:
        e["direction"] = list(end.direction)
    if end.force is not None:
        e["force"] = list(end.force)
    if end.motion is not None:
        e["motion"] = _motion_dict(end.motion)
    if end.twist_deg is not None:
        e["twist_deg"] = end.twist_deg
    if end.moment is not None:
        e["moment"] = list(end.moment)
    return e


def _end_ref(end) -> str | dict:
    """A line's end: a point's name, a body's point, or an inline end table."""
    if isinstance(end, BodyEnd):
        return end.text
    return end if isinstance(end, str) else _end_dict(end)


def _point_dict(pt: Point) -> dict:
    """A point's table, every key that applies written out (so it loads back equal)."""
    out: dict[str, Any] = {"kind": PointKind(pt.kind).value, "position": list(pt.position)}
    if pt.motion is not None:
        out["motion"] = _motion_dict(pt.motion)
    if pt.kind is PointKind.FREE:
        out["mass"], out["volume"] = pt.mass, pt.volume
        if pt.diameter is not None:
            out["diameter"], out["cd"] = pt.diameter, pt.cd
        if pt.cd_area is not None:
            out["cd_area"] = list(pt.cd_area)
        out["ca"] = pt.ca
        if pt.force is not None:
            out["force"] = list(pt.force)
    return out
