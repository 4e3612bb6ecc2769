"""The rod's (and the hybrid's) mass and its loads from the water and the seabed
(:mod:`~symcable.models.rod.rod`): what acts on the nodes alone, whatever the formulation
between them, so cable3d's (:mod:`~symcable.models.common.seabed`) on the rod's nodes.

- :func:`water_velocity`: the uniform current plus ``environment.current_profile`` at each
  element's mid-depth (as cable3d);
- :func:`rod_seabed`: cable3d's seabed on the rod's nodes (contact, damper, friction by
  ``seabed.friction_law``, static friction ``"laid"``), with what the bristle law adds to
  the Mechanism (its states after the rod's unknowns, their rates and rest rows);
- :func:`rod_mass`: cable3d's lumped mass per node and the twist's rotary inertia per edge.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import casadi as ca
import numpy as np

from ...scene import Scene
from ...mechanism.mechanism import StateNames
from ..common.seabed import bristle_scale, friction_setup, profile_current, seabed_forces

__all__ = ["RodSeabed", "rod_mass", "rod_seabed", "seabed_setup", "water_velocity"]


def water_velocity(scene: Scene, current, Xm):
    """The water's velocity at each element (3, N), m/s: the uniform ``current`` parameter
    (3, 1) plus the profile at the element's mid-depth (:func:`~symcable.models.common.seabed.profile_current`)."""
    N = Xm.shape[1] - 1
    water = ca.repmat(current, 1, N)
    if scene.environment.current_profile:
        water = water + profile_current(scene.environment.current_profile,
                                        0.5 * (Xm[2, :-1] + Xm[2, 1:]))
    return water


def seabed_setup(scene: Scene, seg: dict) -> tuple[bool, bool, np.ndarray | None]:
    """``(rubs, bristle, laid)`` of :func:`~symcable.models.common.seabed.friction_setup`, (False, False, None)
    without a seabed."""
    if scene.seabed is None:
        return False, False, None
    return friction_setup(scene, seg)


@dataclass
class RodSeabed:
    """What :func:`rod_seabed` builds: ``nodal`` (3, N+1) N, the nodal forces with the
    seabed's; ``contact`` (1, N+1) N; ``friction`` (or None); ``energy`` J (the contact's);
    ``terms`` the term names; with the bristle law
    ``rate``, ``rest`` (2 (N+1), 1) and ``states`` (StateNames), ``state_scale`` m."""

    nodal: object
    contact: object
    friction: object = None
    energy: object = 0.0
    terms: list = field(default_factory=list)
    rate: object = None
    rest: object = None
    states: StateNames | None = None
    state_scale: float = 0.0


def rod_seabed(scene: Scene, seg: dict, Xm, Vm, nodal, state, laid, gate, bed=1.0) -> RodSeabed:
    """The seabed on the rod's nodes (:func:`~symcable.models.common.seabed.seabed_forces`), added to ``nodal``
    (3, N+1), N. ``state``: the bristle deflections (2 (N+1), 1), m, the last entries of
    q (None without the bristle law); ``laid``, ``gate``: the static friction parameters
    (None without); ``bed`` the contact stiffness's scale (the ``bed`` block). No seabed:
    ``nodal`` unchanged, zero contact."""
    N = Xm.shape[1] - 1
    sb = scene.seabed
    if sb is None:
        return RodSeabed(nodal, ca.SX.zeros(1, N + 1))
    names: list = []
    sea = seabed_forces(scene, seg, Xm, Vm, nodal, names, state=state, laid=laid, gate=gate,
                        bed=bed)
    out = RodSeabed(sea.nodal, sea.contact, sea.friction, sea.energy, names)
    if state is not None and sea.friction is not None and sea.friction.rate is not None:
        out.rate, out.rest = sea.friction.rate, sea.friction.rest
        out.states = StateNames(tuple(f"node{i}.bristle.{c}" for i in range(N + 1)
                                      for c in "xy"), "m", 'seabed.friction_law = "bristle"',
                                'seabed.friction_law = "coulomb"')
        out.state_scale = bristle_scale(sb, seg)
    return out


def rod_mass(scene: Scene, seg: dict, Xm, rho: float, slots: dict):
    """The lumped mass over the rod's unknowns in ``slots``' order (kg, kg m^2): per node
    cable3d's structural m L0 / 2 and added rho A L0 / 2 (Ca_n (I - t t^T) + Ca_t t t^T)
    from each adjacent element, per twisted edge the rotary inertia m d^2 / 8 L0 (a solid
    circular section)."""
    N = len(seg["ds"])
    A_w = math.pi * seg["d"] ** 2 / 4.0
    blocks = [ca.SX.zeros(3, 3) for _ in range(N + 1)]
    can = np.array([s.line_type.ca_normal for s in scene.sections for _ in range(s.segments)])
    cat = np.array([s.line_type.ca_tangential for s in scene.sections for _ in range(s.segments)])
    for j in range(N):
        dx = Xm[:, j + 1] - Xm[:, j]
        tt = ca.mtimes(dx, dx.T) / ca.dot(dx, dx)
        blk = 0.5 * seg["mass"][j] * seg["ds"][j] * ca.SX.eye(3) + 0.5 * rho * A_w[j] * \
            seg["ds"][j] * (can[j] * (ca.SX.eye(3) - tt) + cat[j] * tt)
        blocks[j] += blk
        blocks[j + 1] += blk
    spin = seg["mass"] * seg["d"] ** 2 / 8.0 * seg["ds"]  # kg m^2 per edge
    return ca.diagcat(*[blocks[i] if kind == "x" else ca.SX(spin[i]) for kind, i in slots])
