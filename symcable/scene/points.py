"""Points and lines of a scene of several lines (scene version 2, ``[points.NAME]`` and
``[[lines]]``; the README's "A scene file").

A version-1 scene is one line with ``[[sections]]``, ``[end_a]`` and ``[end_b]``; a version-2
scene (``model = "cable3d"``) is any number of lines, each with its own sections and line
types, whose ends are named points or inline end tables as in version 1. Points are held
(``"fixed"``), moved (``"vessel"``: a prescribed motion, as an end's) or solved for
(``"free"``: a clump weight, a buoy, a payload sphere, or a massless joint of lines).

Units are SI; vectors are (x, y, z), z up.
"""
from __future__ import annotations

import enum
import math
from dataclasses import dataclass

__all__ = ["Line", "Point", "PointKind"]


class PointKind(str, enum.Enum):
    """How a point moves."""

    FIXED = "fixed"    #: held at its position
    VESSEL = "vessel"  #: its position plus a prescribed motion (``[points.NAME.motion]``)
    FREE = "free"      #: solved for: mass, buoyancy, drag and added mass of its own


#: a sphere's drag coefficient (subcritical Reynolds number) and potential-flow added-mass
#: coefficient: the defaults of a free point given a ``diameter``
SPHERE_CD, SPHERE_CA = 0.5, 0.5


@dataclass(frozen=True)
class Point:
    """A point (``[points.NAME]``).

    Attributes
    ----------
    name : str
    kind : PointKind
    position : tuple of float
        m, (x, y, z): where a fixed point is held, about which a vessel point moves, and
        where a free point starts (its static position is solved for).
    motion : Motion or None
        Vessel points only: the prescribed motion about ``position`` (None: held there).
    mass : float
        Free points: kg (>= 0).
    volume : float
        Free points: displaced volume, m^3 (>= 0): buoyancy rho g volume, the point taken
        as submerged wherever it is.
    diameter : float or None
        Free points: a sphere's diameter, m: drag area pi d^2 / 4 (with ``cd``) in every
        direction, added-mass volume pi d^3 / 6 (with ``ca``).
    cd : float
        Drag coefficient of the sphere (with ``diameter`` only), default 0.5.
    cd_area : tuple of float or None
        Instead of a diameter: drag coefficient times area along x, y, z, m^2 (MoorDyn's
        CdA): the drag along axis i is 0.5 rho cd_area_i |u| u_i, u the water's velocity
        relative to the point.
    ca : float
        Added-mass coefficient: added mass ca rho V_a, V_a the sphere's volume with a
        ``diameter``, else ``volume`` (MoorDyn's Ca); default 0.5 with a diameter, else 0.
    force : tuple of float or None
        Free points: a constant applied force, N (MoorDyn's Fx, Fy, Fz); None: none.
    """

    name: str
    kind: PointKind
    position: tuple[float, ...]
    motion: object = None
    mass: float = 0.0
    volume: float = 0.0
    diameter: float | None = None
    cd: float = SPHERE_CD
    cd_area: tuple[float, ...] | None = None
    ca: float = 0.0
    force: tuple[float, ...] | None = None

    @property
    def is_free(self) -> bool:
        return self.kind is PointKind.FREE

    @property
    def drag_area(self) -> tuple[float, float, float]:
        """Cd times area along x, y, z, m^2 (zeros: no drag)."""
        if self.diameter is not None:
            a = self.cd * math.pi * self.diameter ** 2 / 4.0
            return (a, a, a)
        return tuple(self.cd_area) if self.cd_area is not None else (0.0, 0.0, 0.0)

    @property
    def added_volume(self) -> float:
        """The volume the added-mass coefficient multiplies, m^3."""
        return math.pi * self.diameter ** 3 / 6.0 if self.diameter is not None else self.volume


@dataclass(frozen=True)
class Line:
    """One line of a version-2 scene (``[[lines]]``).

    Attributes
    ----------
    name : str
    sections : tuple of Section
        From end A to end B.
    end_a, end_b : str, BodyEnd or End
        A point's name, a body's point (:class:`~symcable.scene.bodies.BodyEnd`), or an
        inline end (as version 1's ``[end_a]``).
    """

    name: str
    sections: tuple
    end_a: object
    end_b: object

    @property
    def length(self) -> float:
        """Total unstretched length, m."""
        return sum(s.length for s in self.sections)

    @property
    def n_segments(self) -> int:
        return sum(s.segments for s in self.sections)

    @property
    def n_nodes(self) -> int:
        return self.n_segments + 1

    def end(self, which: str):
        """``end_a`` or ``end_b`` by name (``"a"`` / ``"b"`` also accepted)."""
        return self.end_a if which in ("a", "end_a") else self.end_b
