"""The nodal seabed and current pieces of the 3D lines, shared by cable3d
(:mod:`~symcable.models.cable3d.line`) and the rod and hybrid (:mod:`~symcable.models.rod.rod`): they
act on node positions and velocities alone, whatever the line's formulation between the
nodes.

- :func:`seabed_forces`: each node on a flat seabed at z = -depth gets the planar line's
  smooth penalty contact k b ramp(-depth - z) (b its tributary contact area, half of each
  adjacent segment's diameter x length, m^2), a damper into the bed (:func:`seabed_damper`)
  and friction, axial and lateral, by ``seabed.friction_law``
  (:mod:`~symcable.models.common.friction`: regularised Coulomb, or an elastic bristle per
  node whose deflections are first-order states) with, for ``seabed.static_friction =
  "laid"``, the static spring from the as-laid shape;
- :func:`reaction_bound`: the bound ``seabed_reaction`` (the bed carries at most what
  presses the line onto it);
- :func:`friction_setup`, :func:`bristle_scale`: what the friction law adds to a Mechanism
  (states, parameters, scales);
- :func:`profile_current`: ``environment.current_profile``, the current at given depths.
"""
from __future__ import annotations

from dataclasses import dataclass

import casadi as ca
import numpy as np

from ...scene import EndCondition, Scene
from . import terms
from .starts import laid_shape
from ...mechanism.mechanism import Bound
from .relax import _ramp_integral
from .friction import Friction, friction

#: the 3D lines' contact ramp's smoothing width over the penetration under the line's own
#: weight (:func:`~symcable.models.common.terms.contact_smoothing`). The planar line keeps 1 %: its
#: linearised dynamics accept a grounded length up to 1 % of a segment, which the wider
#: ramp's tail exceeds. So do free points
#: (:data:`~symcable.models.system.POINT_CONTACT_SMOOTHING`). At 1 % Newton can cycle on a
#: heavy chain's touchdown node across the narrow smoothing (a step then retried as
#: substeps); at 10 % it does not and runs are faster, while the chains' answers against a
#: reference code and the static fairlead tension move little (the chain study, in the
#: docs). Its cost: a node at a height g above the bed carries k b delta^2 / 4 g (the
#: ramp's tail), a small fraction of its weight a few metres above the bed
CONTACT_SMOOTHING = 0.1

__all__ = ["CONTACT_SMOOTHING", "SeabedTerms", "bristle_scale", "friction_setup", "joined_on",
           "lumped", "node_resolution", "profile_current", "reaction_bound", "reaction_drag", "seabed_damper", "seabed_forces",
           "seabed_term_names",
           "seabed_numbers"]


@dataclass(frozen=True)
class SeabedTerms:
    """What :func:`seabed_forces` builds: ``nodal`` (3, n) the nodal forces given plus the
    seabed's, N; ``contact`` (1, n) the contact's normal force (the spring), N;
    ``friction`` (:class:`~symcable.models.common.friction.Friction`, or None without
    friction); ``energy`` the contact spring's potential, J."""

    nodal: object
    contact: object
    friction: Friction | None
    energy: object


def lumped(seg) -> np.ndarray:
    """Submerged weight lumped on the nodes (N+1,), N: half of each adjacent segment."""
    out = np.zeros(len(seg["ds"]) + 1)
    out[:-1] += 0.5 * seg["w"] * seg["ds"]
    out[1:] += 0.5 * seg["w"] * seg["ds"]
    return out


def node_resolution(seg) -> float:
    """The lightest node's submerged weight magnitude, N (:func:`lumped`, nodes that weigh
    nothing left out; inf when none weighs anything): the smallest load a static solve of the
    line must resolve (:attr:`~symcable.mechanism.mechanism.Scales.resolution`)."""
    w = np.abs(lumped(seg))
    w = w[w > 0]
    return float(np.min(w)) if w.size else float("inf")


def friction_setup(scene: Scene, seg: dict) -> tuple[bool, bool, np.ndarray | None]:
    """``(rubs, bristle, laid)``: whether the seabed has friction, whether by the bristle
    law (2 states per node), and the as-laid horizontal node positions (2 (N+1),), m, when
    ``seabed.static_friction = "laid"`` (else None)."""
    sb = scene.seabed
    rubs = sb is not None and (sb.mu_axial > 0 or sb.mu_lateral > 0)
    bristle = rubs and sb.friction_law == "bristle"
    laid = laid_shape(scene, seg) if rubs and sb.static_friction == "laid" else None
    return rubs, bristle, laid


def bristle_scale(sb, seg: dict) -> float:
    """The scale of a bristle's deflection, m: the median mobilisation length mu N / k."""
    mob = max(sb.mu_axial, sb.mu_lateral) * np.abs(seg["w"]) / (sb.tangential_stiffness
                                                                 * seg["d"])
    return float(np.median(mob)) or 1e-3


def seabed_numbers(scene: Scene, seg: dict) -> dict:
    """The numbers of a line's seabed terms (:func:`seabed_forces`): ``area`` (N+1,) each
    node's contact area, half of each adjacent segment's diameter x length, m^2; ``weight``
    (N+1,) its submerged weight magnitude, N (:func:`lumped`); ``width`` the contact ramp's
    smoothing width, m; ``sink`` how far a held end may sit above the bed and still rest on
    it, m (:func:`~symcable.models.common.segments.seabed_sink`); ``probe`` (N+1 ints) whose
    penetration each node's contact takes (its own, or a held end's resting on the bed its
    neighbour's): a choice, not a number."""
    sb, env = scene.seabed, scene.environment
    N = len(seg["ds"])
    area = np.zeros(N + 1)
    area[:-1] += 0.5 * seg["d"] * seg["ds"]
    area[1:] += 0.5 * seg["d"] * seg["ds"]
    width = terms.contact_smoothing(float(np.max(seg["w"])), sb.stiffness,
                                    float(np.min(seg["d"])), CONTACT_SMOOTHING)
    sink = max(abs(float(np.max(seg["w"]))) / (sb.stiffness * float(np.min(seg["d"]))),
               1e-6 * scene.length)
    probe = list(range(N + 1))
    for end, i, nb in ((scene.end_a, 0, 1), (scene.end_b, N, N - 1)):
        if end.condition is not EndCondition.FREE and end.position[2] <= -env.depth + sink:
            probe[i] = nb
    return {"area": area, "weight": np.abs(lumped(seg)), "width": width, "sink": sink,
            "probe": probe}


def seabed_forces(scene: Scene, seg: dict, Xm, Vm, nodal, term_names: list, *, state=None,
                  laid=None, gate=None, joined: tuple[bool, bool] = (False, False),
                  bed=1.0, numbers: dict | None = None) -> SeabedTerms:
    """The seabed's contact, damper and friction on the nodes (module docstring), added to
    ``nodal`` (3, N+1), N. ``Xm``, ``Vm`` (3, N+1) node positions (m) and velocities (m/s),
    held ends included; ``seg`` the segment table (``ds``, ``d``, ``w``); ``numbers`` the
    terms' numbers (:func:`seabed_numbers`; default: from ``seg``), where ``area``,
    ``weight`` ((1, N+1) rows), ``width`` and ``sink`` may be parameters; ``state`` the
    bristle deflections (2 (N+1), 1), m; ``laid`` (2 (N+1), 1) the as-laid positions and
    ``gate`` the static spring's on-off (``static_friction`` parameters); ``joined``:
    whether end A / B is joined to a free point of an assembly (its contact then takes the
    neighbour's penetration while the point touches the bed). Appends the term names.

    A held end on the seabed takes its neighbour's penetration: the half segment beside it
    rests where the neighbour does (as the planar line). An end joined to a free point: the
    point's node sits as deep as the point's own contact and the other lines put it (a
    clump pressed in, or held higher by a lighter bed load than this line's), so while the
    point lies on the bed (within the line's own penetration of it, as a held end) the half
    segment beside it rests where the neighbour does, and the bed, not the point, carries
    it; lifted off the bed, it carries none (the smooth on-off factor :func:`joined_on` of
    the point's penetration).
    This part of the contact is not conservative, and ``energy`` counts it at the node's own
    penetration. ``bed`` (the ``bed`` parameter block) scales the contact's stiffness: 1 is
    the scene's; a stiffer bed, with the smoothing kept, measures how far the penalty's
    penetration moves the answer from a rigid bed's (:mod:`symcable.api.bed_error`)."""
    sb, env = scene.seabed, scene.environment
    N = len(seg["ds"])
    rubs = sb.mu_axial > 0 or sb.mu_lateral > 0
    term_names += seabed_term_names(sb, laid is not None)
    nums = seabed_numbers(scene, seg) if numbers is None else numbers
    area, weight = (_row(nums[k]) for k in ("area", "weight"))
    dlt, sink, probe = nums["width"], nums["sink"], nums["probe"]
    pen = ca.horzcat(*[-env.depth - Xm[2, i] for i in probe])
    ramp = [terms.smooth_ramp(pen[i], dlt) for i in range(N + 1)]
    for k, (i, nb) in enumerate(((0, 1), (N, N - 1))):
        if joined[k] and N > 0:
            ramp[i] = terms.smooth_ramp(pen[nb], dlt) * joined_on(pen[i], sink, dlt)
    contact = bed * sb.stiffness * area * ca.horzcat(*ramp)
    nodal = nodal + ca.vertcat(ca.SX.zeros(2, N + 1), contact)
    nodal = nodal + seabed_damper(sb, Vm, pen, dlt, area)
    fr = None
    if rubs:
        fr = friction(sb, Xm, Vm, contact, area, weight, state, laid, gate)
        nodal = nodal + ca.vertcat(fr.force, ca.SX.zeros(1, N + 1))
    energy = bed * sb.stiffness * ca.dot(area, _ramp_integral(pen, dlt))
    return SeabedTerms(nodal, contact, fr, energy)


def _row(x):
    """``x`` (n,) numbers as a constant (1, n) row; an expression (a row of parameters) as
    it is."""
    return x if isinstance(x, (ca.SX, ca.MX, ca.DM)) else ca.DM(np.asarray(x, float)).T


def joined_on(pen, sink, width):
    """The on-off factor of a joined end's contact (:func:`seabed_forces`): whether the free
    point's node lies within the line's own penetration under its weight, ``sink`` (m), of the
    bed (the rule of a held end, which rests on the bed within ``sink`` of it), smoothed over
    ``width`` (m) about pen = -sink: 0.5 (1 + tanh((pen + sink) / width)), ``pen`` the node's
    penetration (m, negative above the bed).

    Not a step about pen = 0 on the line's smoothing width: a point's own contact is far
    stiffer than the line's (:func:`~symcable.models.system.point_contact`), so a point at
    rest presses in anywhere from 0 to ``sink``, and such a step took from the line's contact
    up to half of its end half segment's weight (13 % at 0.1 ``sink``), which the point's
    contact carried instead and the line reported as its pull on the point (at a clump
    weight, far more than the chain's actual pull). The tanh's tail is exponential: at
    pen >= 0, with width = CONTACT_SMOOTHING ``sink``, the factor is 1 to 4e-9."""
    return 0.5 * (1.0 + ca.tanh((pen + sink) / width))


def reaction_drag(seg: dict, cdn: np.ndarray, rho: float) -> float:
    """The most a unit current's drag presses a line onto the bed, N s^2/m^2: the sum of
    0.5 rho Cd_n d L0 over its segments (normal drag coefficients ``cdn``)."""
    return float(np.sum(0.5 * rho * cdn * seg["d"] * seg["ds"]))


def reaction_bound(scene: Scene, seg: dict, contact, applied: np.ndarray, cdn: np.ndarray,
                   rho: float, current, F: float, drag=None) -> Bound:
    """The bound ``seabed_reaction``: the bed's reaction (the sum of ``contact``, N) is at
    most the line's submerged weight, the applied end forces (``applied`` (3, N+1), N) and
    the most the current's drag presses (normal drag coefficients ``cdn`` per segment, water
    density ``rho``; the profile's fastest row, and the uniform ``current`` parameter (3,),
    m/s), with 1 % margin. The uniform current's share is on the expression's side, in the
    parameter, not a constant of the bound: scenes that differ only in their current then
    share one graph, and one compiled library (a sweep of current speeds compiles once).
    ``drag``: the :func:`reaction_drag` that expression reads (default: the number; a
    parameter, for graphs shared by scenes of other line properties)."""
    env = scene.environment
    press = float(np.sum(np.maximum(seg["w"], 0.0) * seg["ds"])) + float(np.abs(applied).sum())
    u2 = max((float(np.dot(r[1:], r[1:])) for r in env.current_profile), default=0.0) * 2.0
    press_drag = reaction_drag(seg, cdn, rho)
    press += press_drag * u2
    return Bound(
        ca.sum2(contact) - 1.01 * (press_drag if drag is None else drag)
        * ca.dot(current, current),
        upper=1.01 * press + 1e-6 * F, unit="N", scale=F,
        what="the seabed carries at most what presses the line onto it (the value: its "
             "reaction less 1.01 times the most the uniform current's drag presses)")


def seabed_term_names(sb, laid: bool) -> list:
    """The terms :func:`seabed_forces` builds for seabed ``sb``, by name, in order (``laid``:
    with the static spring of ``seabed.static_friction = "laid"``)."""
    names = ["seabed"] + (["seabed damping"] if sb.damping > 0 else [])
    if sb.mu_axial > 0 or sb.mu_lateral > 0:
        names += ["seabed friction"] + (["friction bristles"] if sb.friction_law == "bristle"
                                        else []) + (["static friction"] if laid else [])
    return names


def seabed_damper(sb, Vm, pen, dlt, area):
    """Nodal forces (3, N+1) of the seabed's normal damper, N: -damping b v_z times the
    contact's smooth on-off factor 0.5 (1 + g / sqrt(g^2 + delta^2)) (b = ``area``, the node's
    contact width x length, m^2; g the penetration, m); zero at rest, built only where the
    scene asks."""
    out = ca.SX.zeros(3, Vm.shape[1])
    if sb.damping > 0:
        on = 0.5 * (1.0 + pen / ca.sqrt(pen * pen + dlt * dlt))
        out[2, :] = -sb.damping * _row(area) * Vm[2, :] * on
    return out


def profile_current(rows, z):
    """The current (3, N) at depths ``z`` (1, N), m: linear between the profile's rows (z
    ascending), held beyond the first and the last, written as a sum of ramps."""
    r = np.asarray(rows, float)
    zk, U = r[:, 0], r[:, 1:4]
    slopes = np.diff(U, axis=0) / np.diff(zk)[:, None]
    kinks = np.vstack([slopes[:1], np.diff(slopes, axis=0), -slopes[-1:]])  # (n, 3)
    out = ca.repmat(ca.DM(U[0]), 1, z.shape[1])
    for k in range(len(zk)):
        out = out + ca.mtimes(ca.DM(kinks[k]), ca.fmax(z - zk[k], 0.0))
    return out
