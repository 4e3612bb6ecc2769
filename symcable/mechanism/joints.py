"""The joints of an assembly (:func:`.assembly.assemble`): nodes shared by two parts, nodes
moved by a prescribed motion, and nodes attached to a part that is a rigid body."""
from __future__ import annotations

from dataclasses import dataclass
from typing import Sequence

__all__ = ["Attached", "Prescribed", "Shared"]


@dataclass(frozen=True)
class Shared:
    """Node ``b`` (part name, node index) is the same node as node ``a``.

    Parameters
    ----------
    a, b : (str, int)
        Part name and node index (negative: counted from the part's last node); every
        coordinate of node ``b`` is node ``a``'s. Neither may be prescribed inside its part.
    """

    a: tuple[str, int]
    b: tuple[str, int]


@dataclass(frozen=True)
class Prescribed:
    """Node ``node`` (part name, node index) moves as
    ``x_i(t) = position_i + amplitude_i cos(omega t + phase_i)`` (m, rad/s, rad).

    Parameters
    ----------
    name : str
        The joint's name: its parameter blocks are ``NAME.position``, ``NAME.amplitude``,
        ``NAME.phase`` and ``NAME.omega``, its outputs ``NAME.force`` (N, the force the
        parts exert on the node) and ``NAME.position`` (m).
    node : (str, int)
        Part name and node index (negative: counted from the part's last node).
    position : sequence of float
        m, the node's mean position, one entry per coordinate (the parts' dimension, 2 or 3).
    amplitude : sequence of float or None, default None
        m, per coordinate; None: zeros (the node held at ``position``).
    phase : sequence of float or None, default None
        rad, per coordinate; None: zeros.
    omega : float, default 0.0
        rad/s, the angular frequency of the motion.
    """

    name: str
    node: tuple[str, int]
    position: Sequence[float]
    amplitude: Sequence[float] | None = None
    phase: Sequence[float] | None = None
    omega: float = 0.0


@dataclass(frozen=True)
class Attached:
    """Node ``node`` (part name, node index) is a point of part ``body``: its position is
    ``position(q_body)`` (m) and its velocity ``velocity(q_body, v_body)`` (m/s, linear in
    v_body), CasADi Functions of that part's own q and v (:func:`.body.attachment`)."""

    name: str
    node: tuple[str, int]
    body: str
    position: object
    velocity: object
