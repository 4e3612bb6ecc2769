"""The Kirchhoff rod (Goyal & Perkins' rod), ``model = "rod"``, as a Mechanism: the
discrete elastic rod (Bergou et al. 2008, 2010) on cable3d's nodes.

Unknowns q: the positions (x, y, z) of the moving nodes (as :mod:`~symcable.models.cable3d.line`:
every interior node and a free end), then one twist angle theta_j per edge (rad; edge j
joins nodes j and j+1); v their rates (m/s, rad/s). Terms:

- per edge, cable3d's element kernel (:func:`symcable.models.common.elements.element_kernel`):
  the axial force as the *linear* law EA e (a rod carries compression; EA stiff: the
  inextensibility is a penalty, see below), Kelvin-Voigt damping BA, the submerged weight,
  Morison drag (or the loading functions) on the relative velocity, half on each node;
- per vertex (interior nodes, and a clamped end through a ghost edge) the bending and
  twisting energy of :func:`~symcable.models.rod.frames.vertex_kernel`: B = diag(EI_1, EI_2)
  in the material frame, GJ; the forces and torques are its exact gradient (CasADi);
- lumped mass: cable3d's structural and added mass per node, and the rotary inertia of the
  twist, m d^2 / 8 per metre (a solid circular section) on each edge. The rotary inertia
  of bending (m d^2 / 16 per metre about each transverse axis) is left out (relative
  O((d / wavelength)^2)), as is the spin the anchor map gives the reference frame
  (:mod:`.frames`; second order in the edge's rotation from its anchor).

End conditions: pinned (position held, no moment, twist free), free (applied force, and
optionally a dead moment ``moment`` on its edge: :func:`~.frames.end_moment_force`, not
in the potential energy output), guided (``condition = "guided"``: free, tangent
``direction`` held: cable3d's ghost edge on the moving end node, turning with its
translation, so its force is the node's; it takes the neighbour edge's twist and anchor and
no twist term: the guide holds the tangent and the bending moment, not the twist; seed
000's benchmark right end), clamped (position held; tangent ``direction`` and the material
frame's ``twist_deg`` about it given: a held ghost edge one first-segment length beyond the
end, as cable3d's clamp, whose material director is the clamp's; the vertex at the end node
takes lbar = ds / 2, half a cell lying in the rod, so the twist angle of the ghost is the
frame at the end node and M_t = GJ (theta_0 - twist) / (ds / 2)). With no clamped end, the first
edge's twist is held at 0 (the rod's spin about itself is otherwise undetermined); a rod
needs GJ > 0 (an isotropic rod's twists are otherwise singular).

Seabed and water (:mod:`.loads`, cable3d's :mod:`~symcable.models.common.seabed` on the rod's nodes): a
flat seabed's smooth penalty contact, normal damper and friction by ``seabed.friction_law``
(regularised Coulomb; the bristle law's deflections are first-order states, the last
entries of q, node by node), static friction ``"laid"``; ``environment.current_profile``
at each element's mid-depth. Not yet: the consistent mass, natural curvature.

``model = "hybrid"`` (:mod:`.hybrid`) builds this Mechanism with a per-segment mask ``rod``
(:mod:`.hybrid_terms`): the rod's terms on its rod sections, cable3d's elsewhere.

The reference frame (its design and the alternatives weighed: studies/rod_notes): each edge's reference director is its
*anchor* (t0_j, u0_j), a parameter block ``frame`` (6 per edge, data), carried to the
current tangent by the smallest rotation. It is a smooth function of the edge's own two
nodes, so the Jacobian keeps the band of the positions-plus-twists ordering, the generic
solvers need no per-step hook, and the frame is exact for any rotation of an edge from
its anchor short of a half turn (t_j = -t0_j, where the map is singular). Re-anchoring
(``frame`` := the output ``reference_frame``, theta unchanged: the material frame does
not move) is the hook a long run or a looping rod will need; nothing calls it yet. Default
anchors: every edge along the clamp's direction (end A's first), else the chord from A to
B, else straight down, with :func:`~symcable.models.rod.frames.reference_director`.

Parameters (blocks): ``load``, ``end_a.position``, ``end_b.position``, ``current``,
``motion``, ``ramp`` (as cable3d's), ``end_a.twist``, ``end_b.twist`` (a clamp's twist,
rad; continuation and the Greenhill test move them), ``bed`` (as cable3d's), ``frame`` (6 N:
the anchors) and,
with static friction, cable3d's ``static_friction`` and ``laid``.
"""
from __future__ import annotations

import functools
import math

import casadi as ca
import numpy as np

from ...errors import SymcableError
from ...scene import EndCondition, Scene
from ..common.elements import element_kernel, held_end
from ..common.drag import law_table
from ..common.terms import fluid_term_names
from ..common.waves import WAVE_TERMS, element_wave_loads, wave_block
from ..common.starts import force_scale, starts_of
from .hybrid_terms import axial_law, rod_mask, spun_edges
from ...mechanism.mechanism import (Bound, Layout, Mechanism, Output, ParamBlocks, PartLayout,
                                   Scales, Start)
from ..common.segments import CABLE_COMPRESSION, FOLD_PUSH, segment_table
from ..common.relax import _ramp_integral
from .frames import end_moment_force, reference_director, transport
from .vertices import _internal_forces, _vertex_terms, _VertexTerms
from .loads import rod_mass, rod_seabed, seabed_setup, water_velocity
from ..common.seabed import lumped as _lumped, node_resolution, reaction_bound

__all__ = ["build_rod", "default_anchors", "rod_table"]

P_NAMES = ("load", "end_a.position", "end_b.position", "current", "motion", "ramp",
           "end_a.twist", "end_b.twist", "bed")
P_SIZES = (1, 3, 3, 3, 1, 1, 1, 1, 1)


def rod_table(scene: Scene) -> dict:
    """cable3d's segment table (:func:`~symcable.models.common.segments.segment_table`) with the
    rod's columns: ``EI2`` (N m^2, = EI for isotropic types), ``GJ`` (N m^2) and ``K`` (the
    tension-torsion coupling, N m), per segment."""
    seg = segment_table(scene)
    lts = [s.line_type for s in scene.sections for _ in range(s.segments)]
    seg["EI2"] = np.array([lt.EI if lt.EI_2 is None else lt.EI_2 for lt in lts])
    seg["GJ"] = np.array([lt.GJ for lt in lts])
    seg["K"] = np.array([lt.tension_twist for lt in lts])
    return seg


def default_anchors(scene: Scene, N: int) -> np.ndarray:
    """The default ``frame`` block (6 N: t0 then u0 per edge; module docstring)."""
    a, b = scene.end_a, scene.end_b
    clamp = next((e.direction for e in (a, b) if e.condition is EndCondition.CLAMPED), None)
    if clamp is not None:
        t0 = np.asarray(clamp, float)
    elif a.position is not None and b.position is not None:
        t0 = np.subtract(b.position, a.position)
    else:
        t0 = np.array([0.0, 0.0, -1.0 if a.position is not None else 1.0])
    t0 = t0 / np.linalg.norm(t0)
    return np.tile(np.concatenate([t0, reference_director(t0)]), N)


def _slots(N: int, moving: list, spun: list) -> dict:
    """The order of q (and v): node by node along the rod, each moving node's (x, y, z) and
    then the twist of the edge after it, so the tangent is banded (every term couples
    neighbouring nodes and edges; the twists after all positions would couple each twist
    with far positions and fill the LU). {("x", node) or ("th", edge): index in q}, in
    order."""
    out, k = {}, 0
    for i in range(N + 1):
        if i in moving:
            out[("x", i)] = k
            k += 3
        if i in spun:
            out[("th", i)] = k
            k += 1
    return out


def build_rod(scene: Scene, rod: np.ndarray | None = None) -> Mechanism:
    """The scene's line (scene version 1, ``model = "rod"``) as a rod Mechanism (module
    docstring). ``rod``: per segment, whether it is a rod edge (default: the scene's
    sections, :func:`~symcable.models.rod.hybrid_terms.rod_mask`); the others are cable3d
    edges joined to the rod runs by moment-free joints (``model = "hybrid"``,
    :mod:`.hybrid_terms`)."""
    if scene.version == 2:
        raise SymcableError(f"scene {scene.name!r}: model = {scene.model.value!r} takes one "
                            "line ([[sections]], end_a, end_b) for now")
    seg = rod_table(scene)
    N = len(seg["ds"])
    rod = rod_mask(scene) if rod is None else np.asarray(rod, bool)
    whole = bool(np.all(rod))
    _check_rod(scene, seg, rod)
    env = scene.environment
    a, b = scene.end_a, scene.end_b
    cond = [a.condition, b.condition]
    free = [c is EndCondition.FREE for c in cond]
    clamped = [c is EndCondition.CLAMPED for c in cond]
    guided = [e.guided for e in (a, b)]
    twists = [math.radians(e.twist_deg or 0.0) for e in (a, b)]
    col = np.cumsum(rod) - 1  # each rod edge's column in the frame block
    n_rod = int(np.sum(rod))
    rubs, bristle, laid = seabed_setup(scene, seg)
    params = _param_blocks(scene, N, n_rod, twists, laid)
    p = ca.SX.sym("p", params.n)
    sl = params.slice
    load, pa, pb, current = p[0], p[sl("end_a.position")], p[sl("end_b.position")], p[7:10]
    motion, ramp_on = p[sl("motion")], p[sl("ramp")]
    frame = ca.reshape(p[sl("frame")], 6, n_rod) if n_rod else None
    t = ca.SX.sym("t")

    moving = [i for i in range(N + 1) if (i == 0 and free[0]) or (i == N and free[1]) or 0 < i < N]
    spun = spun_edges(rod, clamped)  # twists in q
    slots = _slots(N, moving, spun)
    n_v = 3 * len(moving) + len(spun)
    q_all = ca.SX.sym("q", n_v + (2 * (N + 1) if bristle else 0))  # bristles last
    q = q_all[:n_v]
    v = ca.SX.sym("v", n_v)
    X, V, theta = _node_symbols(scene, N, moving, spun, slots, q, v, pa, pb, motion, t, ramp_on)
    Xm, Vm = ca.horzcat(*X), ca.horzcat(*V)

    F = force_scale(scene, seg)
    rho = 0.0 if env.in_air else env.water_density
    drag_law = law_table(scene)
    BA = np.array([s.line_type.damping for s in scene.sections for _ in range(s.segments)])
    BA = np.where(BA < 0, -BA * np.sqrt(seg["EA"] * seg["mass"]) * seg["ds"], BA)
    EAs, delta = axial_law(seg, rod, F)
    sea_u = sea_f = None
    if env.waves is not None:  # the waves' velocity joins the current; their inertia force
        sea_u, sea_f = element_wave_loads(scene, Xm, t, p[sl("waves")], p[sl("wave_scale")],
                                          ramp_on, rho, _wave_rows(scene, seg))
    fa, fb, T, e = _element_forces(scene, seg, Xm, Vm, current, load, BA, EAs, delta, F, rho,
                                   drag_law, sea_u)
    if sea_f is not None:
        fa, fb = fa + 0.5 * sea_f, fb + 0.5 * sea_f
    nodal = ca.horzcat(fa, ca.SX.zeros(3, 1)) + ca.horzcat(ca.SX.zeros(3, 1), fb)
    vt = _vertex_terms(scene, seg, rod, Xm, theta, frame, col, p, sl, clamped, guided, nodal)
    internal = _internal_forces(Xm, T, vt)
    # the seabed (contact, damper, friction) on the nodes: a held end's goes to its support
    sea = rod_seabed(scene, seg, Xm, Vm, vt.nodal, q_all[n_v:] if bristle else None,
                     p[sl("laid")] if laid is not None else None,
                     p[sl("static_friction")] if laid is not None else None, p[sl("bed")])
    nodal = sea.nodal

    applied = np.zeros((3, N + 1))
    for end, i in ((a, 0), (b, N)):
        if end.condition is EndCondition.FREE and end.force is not None:
            applied[:, i] = end.force
    end_force = {i: nodal[:, i] + vt.reaction[i] for i in (0, N)}
    nodal = nodal + load * ca.DM(applied)
    force = ca.vertcat(*[nodal[:, i] if kind == "x" else vt.torque[i] for kind, i in slots])
    force = _add_end_moments(scene, rod, force, load, Xm, theta, frame, col, q)
    mass = rod_mass(scene, seg, Xm, rho, slots)

    slack = np.isfinite(delta) & (EAs != seg["EA"])  # tension-only cable3d edges
    potential = _potential(seg, EAs, delta, slack, e, vt, load, Xm, applied, sea)
    outputs = _outputs(N, Xm, Vm, theta, T, e, vt, internal, sea, rubs, end_force,
                       _reference_frames(Xm, rod, frame, col), v, mass, potential)
    static = {"motion": np.zeros(1), **({"static_friction": np.ones(1)} if laid is not None
                                        else {}),
              **({"wave_scale": np.zeros(1)} if env.waves is not None else {})}
    starts = functools.partial(_starts, scene, seg, params, moving, slots, twists, clamped,
                               static if laid is not None else None, q_all.numel() - n_v)
    terms = ["elastic", "weight"] + (["bending"] if vt.verts or vt.cb is not None else []) + (
        ["torsion"] if vt.verts else []) + (
        ["material damping"] if np.any(BA) else []) + (
        fluid_term_names(scene.sections, rho)) + (
        list(WAVE_TERMS) if env.waves is not None else []) + (
        sea.terms) + (
        ["end force"] if np.any(applied) else []) + (
        ["end moment"] if any(x.moment is not None and any(x.moment) for x in (a, b)) else []) + (
        ["tension-torsion coupling"] if vt.coupled else [])
    return Mechanism(
        name="rod" if whole else "hybrid", q=q_all, v=v, z=ca.SX.sym("z", 0), t=t, p=p,
        params=params, mass=mass, force=force, constraint=ca.SX.zeros(0, 1),
        scales=_scales(scene, seg, slots, q_all.numel() - n_v, sea.state_scale, F),
        starts=starts, outputs=outputs, layout=_layout(seg, N, moving, slots, sea.states),
        terms=tuple(terms), static_params=static,
        bounds=_bounds(scene, seg, T, e, slack, F, sea, applied, drag_law, rho, current),
        kinematics=ca.vertcat(v, sea.rate) if bristle else None, rest=sea.rest,
        stability_coordinates=np.arange(n_v) if bristle else None)


def _check_rod(scene: Scene, seg: dict, rod: np.ndarray) -> None:
    """Raises a SymcableError for a rod section without EI > 0 and GJ > 0, both ends free,
    or a guided end on a section that cannot hold its tangent."""
    N = len(seg["ds"])
    a, b = scene.end_a, scene.end_b
    if np.any(seg["GJ"][rod] <= 0.0) or np.any(seg["EI"][rod] <= 0.0) \
            or np.any(seg["EI2"][rod] <= 0.0):
        raise SymcableError(f"scene {scene.name!r}: a rod needs EI > 0 and GJ > 0 in "
                            "every line type of its sections (a cable is model = 'cable3d')")
    if all(e.condition is EndCondition.FREE for e in (a, b)):
        raise SymcableError(f"scene {scene.name!r}: both ends free; hold one end")
    for k, (end, j) in enumerate(((a, 0), (b, N - 1))):
        if end.guided and not rod[j] and seg["EI"][j] <= 0.0:
            raise SymcableError(f"scene {scene.name!r}: end_{'ab'[k]} is guided, but its "
                                "section has EI = 0 and is not a rod: nothing holds its "
                                "tangent (give the section EI > 0, or model = 'rod')")


def _param_blocks(scene: Scene, N: int, n_rod: int, twists: list,
                  laid: np.ndarray | None) -> ParamBlocks:
    """The parameter blocks (module docstring) at the scene's values: the ``frame`` block
    (6 per rod edge) when there are rod edges, the static friction's with ``laid``."""
    env, a, b = scene.environment, scene.end_a, scene.end_b
    anchors = default_anchors(scene, N)[:6 * n_rod]
    sea = () if env.waves is None else (wave_block(env.waves, env.depth, env.gravity),)
    # no rod edge (a hybrid of cable3d sections with a guided end): no frame block
    return ParamBlocks(P_NAMES + (("frame",) if n_rod else ()) + (
        ("static_friction", "laid") if laid is not None else ()) + (
        ("wave_scale", "waves") if sea else ()),
        P_SIZES + ((6 * n_rod,) if n_rod else ()) + ((1, laid.size) if laid is not None
                                                     else ()) + ((1, sea[0].size) if sea else ()),
        np.concatenate([
            [1.0], a.position if a.position is not None else np.zeros(3),
            b.position if b.position is not None else np.zeros(3), env.current, [1.0], [1.0],
            twists, [1.0], anchors] + ([[0.0], laid] if laid is not None else [])
            + ([[1.0], sea[0]] if sea else [])))


def _wave_rows(scene: Scene, seg: dict) -> dict:
    """The per-segment rows the waves' inertia force reads (1, N): diameter ``d`` (m),
    length ``ds`` (m) and the added-mass coefficients ``can``, ``cat``."""
    cat = [s.line_type.ca_tangential for s in scene.sections for _ in range(s.segments)]
    return {"d": ca.DM(seg["d"]).T, "ds": ca.DM(seg["ds"]).T, "can": ca.DM(seg["can"]).T,
            "cat": ca.DM(cat).T}


def _node_symbols(scene: Scene, N: int, moving: list, spun: list, slots: dict, q, v, pa, pb,
                  motion, t, ramp_on):
    """Each node's position and velocity (lists of N+1 (3, 1), m and m/s: q and v's
    entries, or a held end's prescribed motion) and each edge's twist angle (list of N, rad:
    q's entry, or 0 where the twist is not an unknown)."""
    X, V = [None] * (N + 1), [None] * (N + 1)
    for i in moving:
        k = slots[("x", i)]
        X[i], V[i] = q[k:k + 3], v[k:k + 3]
    for end, i, pp in ((scene.end_a, 0, pa), (scene.end_b, N, pb)):
        if X[i] is None:
            X[i], V[i] = held_end(end, pp, motion, t, ramp_on)
    theta = [ca.SX(0.0)] * N
    for j in spun:
        theta[j] = q[slots[("th", j)]]
    return X, V, theta


def _element_forces(scene: Scene, seg: dict, Xm, Vm, current, load, BA: np.ndarray,
                    EAs: np.ndarray, delta: np.ndarray, F: float, rho: float,
                    drag_law: dict | None, waves=None):
    """cable3d's element kernel mapped over the N edges: the forces on each edge's first and
    second node (3, N), N; its axial force T (1, N), N, and strain e (1, N). ``waves``: the
    waves' velocity at the edges' midpoints (3, N), m/s, added to the water's, or None."""
    N = len(seg["ds"])
    row = lambda key: ca.DM(seg[key]).T  # noqa: E731
    water = water_velocity(scene, current, Xm)
    return element_kernel(drag_law["shape"] if drag_law else None).map(N)(
        Xm[:, :-1], Xm[:, 1:], Vm[:, :-1], Vm[:, 1:], water if waves is None else water + waves,
        row("ds"), row("EA"), ca.DM(BA).T, ca.DM(EAs).T, ca.DM(delta).T, F, row("w"),
        row("d"), row("cdn"), row("cdt"), rho, load,
        *([ca.DM(drag_law["law"]).T] if drag_law else []))


def _add_end_moments(scene: Scene, rod: np.ndarray, force, load, Xm, theta: list, frame, col,
                     q):
    """``force`` (n_v, 1) plus the free ends' applied moments (each on its rod edge,
    :func:`~.frames.end_moment_force`)."""
    N = Xm.shape[1] - 1
    for end, j in ((scene.end_a, 0), (scene.end_b, N - 1)):
        if end.moment is not None and any(end.moment):
            if not rod[j]:
                raise SymcableError(f"scene {scene.name!r}: an end moment needs a rod section "
                                    "at its end (model = 'rod' there)")
            force = force + load * end_moment_force(
                Xm[:, j], Xm[:, j + 1], theta[j], frame[0:3, col[j]], frame[3:6, col[j]],
                ca.DM(end.moment), q)
    return force


def _reference_frames(Xm, rod: np.ndarray, frame, col) -> list:
    """The current reference directors of the rod edges (the re-anchoring output): per rod
    edge its tangent and transported reference director, (6, 1)."""
    d1 = []
    for j in np.flatnonzero(rod):
        tj = (Xm[:, j + 1] - Xm[:, j]) / ca.norm_2(Xm[:, j + 1] - Xm[:, j])
        d1.append(ca.vertcat(tj, transport(frame[0:3, col[j]], tj, frame[3:6, col[j]])))
    return d1


def _potential(seg: dict, EAs: np.ndarray, delta: np.ndarray, slack: np.ndarray, e,
               vt: _VertexTerms, load, Xm, applied: np.ndarray, sea):
    """The potential energy, J: bending and twisting, axial (cable3d's integral of the
    tension-only law on its slack edges, the wall left out), gravity, applied forces,
    cable3d's bending and the seabed's."""
    U = 0.5 * ca.DM(EAs) * e.T * e.T
    if np.any(slack):  # cable3d's integral of the tension-only law (its wall left out)
        U = U + ca.DM(seg["EA"] - EAs) * _ramp_integral(e.T, ca.DM(delta))
    potential = ca.sum2(vt.E) + ca.dot(ca.DM(seg["ds"]), U) \
        + load * ca.dot(ca.DM(_lumped(seg)), Xm[2, :].T) \
        - load * ca.dot(ca.DM(applied.T.ravel()), ca.vec(Xm))
    if vt.cb is not None:
        potential += vt.cb["energy"]
    potential += sea.energy
    return potential


def _outputs(N: int, Xm, Vm, theta: list, T, e, vt: _VertexTerms, internal, sea, rubs: bool,
             end_force: dict, d1: list, v, mass, potential) -> dict:
    """The rod's outputs (owner ``"line"``): node and edge fields, the end forces, the
    re-anchored frames (with rod edges) and the energies."""
    owner = "line"
    return {
        "positions": Output(Xm.T, "m", owner, "node positions (x, y, z)"),
        "velocities": Output(ca.densify(Vm.T), "m/s", owner, "node velocities (x, y, z)"),
        "twist_angles": Output(ca.vertcat(*theta), "rad", owner, "twist angle of each edge "
                               "(material frame from the reference frame; 0 on cable3d "
                               "edges)"),
        "axial_force": Output(T.T, "N", owner, "axial force of each segment"),
        "strain": Output(e.T, "1", owner, "strain of each segment"),
        "curvature": Output(vt.kap.T, "1/m", owner, "material curvatures kappa_1, kappa_2 at "
                            "each node (the next edge's frame; 0 where no vertex)"),
        "twist": Output(vt.tw.T, "rad", owner, "discrete twist at each node"),
        "bending_moment": Output(vt.moment.T, "N m", owner, "bending moment vector at each node"),
        "twisting_moment": Output(vt.mt.T, "N m", owner, "twisting moment GJ tau at each node"),
        "internal_force": Output(internal.T, "N", owner, "internal force across each edge "
                                 "(on the part towards end A; Goyal & Perkins' f): tension and shear"),
        "contact_force": Output(sea.contact.T, "N", owner, "seabed contact force on each "
                                "node"),
        **({"friction_force": Output(sea.friction.force.T, "N", owner, "seabed friction force "
                                     "on each node (x, y)")} if rubs else {}),
        "end_force_a": Output(end_force[0], "N", owner, "force of the rod on end A"),
        "end_force_b": Output(end_force[N], "N", owner, "force of the rod on end B"),
        **({"reference_frame": Output(ca.vertcat(*d1), "1", owner, "each rod edge's tangent "
                                      "and reference director (the re-anchored frame "
                                      "block)")} if d1 else {}),
        "kinetic_energy": Output(0.5 * ca.dot(v, ca.mtimes(mass, v)), "J", owner,
                                 "kinetic energy"),
        "potential_energy": Output(potential, "J", owner, "bending, twisting, axial, gravity, "
                                   "contact and applied-force potential energy (the axial "
                                   "term without the wall's)"),
    }


def _scales(scene: Scene, seg: dict, slots: dict, n_states: int, state_scale: float,
            F: float) -> Scales:
    """The scales: a tenth of the line's length per position (m), 1 rad per twist, the
    bristle scale per state (m); sqrt(g L) per velocity (m/s), over L per twist rate; the
    force scale ``F`` (N), the line's mass (kg), the stiffest edge's round-off floor (N), the
    lightest node's weight (N)."""
    env, a, b = scene.environment, scene.end_a, scene.end_b
    L = scene.length
    coord = L + max((float(np.max(np.abs(x.position))) for x in (a, b)
                     if x.position is not None), default=0.0)
    floor = 100.0 * np.finfo(float).eps * float(np.max(seg["EA"] / seg["ds"])) * coord
    vx = math.sqrt(env.gravity * L)
    is_x = np.concatenate([[kind == "x"] * (3 if kind == "x" else 1) for kind, _ in slots])
    return Scales(q=np.concatenate([np.where(is_x, 0.1 * L, 1.0),
                                    np.full(n_states, state_scale)]),
                  v=np.where(is_x, vx, vx / L),
                  z=np.zeros(0), force=F, mass=max(float(np.sum(seg["mass"] * seg["ds"])),
                                                   1e-6), residual_floor=floor,
                  resolution=node_resolution(seg))


def _starts(scene: Scene, seg: dict, params: ParamBlocks, moving: list, slots: dict,
            twists: list, clamped: list, static: dict | None, n_states: int):
    """The static starts (a generator of Start): cable3d's node positions
    (:func:`~symcable.models.common.starts.starts_of`), the twists interpolated between
    the clamps' (or a clamp's throughout), zero first-order states; with static friction
    (``static``: its static parameter values) the start's parameters set to them."""
    N = len(seg["ds"])
    lo, hi = twists
    s = seg["s"] / seg["s"][-1]
    th = lo + (hi - lo) * 0.5 * (s[:-1] + s[1:]) if all(clamped) else \
        np.full(N, hi if clamped[1] and not clamped[0] else lo)
    for st in starts_of(scene, seg, params, moving):
        x = st.q.reshape(-1, 3)
        yield Start(np.concatenate([x[moving.index(i)] if kind == "x" else th[i:i + 1]
                                    for kind, i in slots] + [np.zeros(n_states)]),
                    st.z, params.with_values(st.p, **static) if static is not None else st.p,
                    st.source, st.homotopy)


def _layout(seg: dict, N: int, moving: list, slots: dict, states) -> Layout:
    """The layout: the line's nodes in q (held ends moved by ``end_a`` / ``end_b``) and the
    first-order states' names."""
    node_q = -np.ones((N + 1, 3), dtype=int)
    for i in moving:
        node_q[i] = slots[("x", i)] + np.arange(3)
    return Layout(3, {"line": PartLayout(
        "line", seg["s"], node_q, node_q,
        {i: name for i, name in ((0, "end_a"), (N, "end_b")) if i not in moving})}, states)


def _bounds(scene: Scene, seg: dict, T, e, slack: np.ndarray, F: float, sea,
            applied: np.ndarray, drag_law: dict | None, rho: float, current) -> dict:
    """The admissibility bounds: positive edge lengths, no compression in the tension-only
    cable3d edges, and with a seabed its reaction."""
    bounds = {"strain": Bound(e.T, lower=-1.0 + 1e-9, unit="1", scale=1.0,
                              what="segments of positive length")}
    cab = np.flatnonzero(slack)
    if cab.size:  # as cable3d: a cable (EI = 0) carries no compression
        push = np.maximum(CABLE_COMPRESSION * F, FOLD_PUSH * np.abs(seg["w"]) * seg["ds"])
        bounds["cable_axial_force"] = Bound(T.T[cab.tolist()], lower=-push[cab], unit="N",
                                            scale=F, what="a cable (EI = 0) carries no "
                                            "compression")
    if scene.seabed is not None:
        bounds["seabed_reaction"] = reaction_bound(
            scene, seg, sea.contact, applied,
            seg["cdn"] if drag_law is None else drag_law["normal_bound"], rho, current, F)
    return bounds
