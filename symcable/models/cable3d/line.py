"""The 3D position-vector cable (Sun, Zhu & LaRosa), ``model = "cable3d"``, as a Mechanism.

Nodes 0..N along the line (end A to end B), two-node elements between them. The unknowns q
are the positions (x, y, z) of the nodes that move (every interior node, and a free end),
v their velocities; a pinned end is held at its scene position plus its prescribed motion,
a function of t and the parameters. Per element j (unstretched length L0, current length
l, unit tangent t = (x_b - x_a) / l, strain e = l / L0 - 1), one kernel mapped over the
elements gives:

- axial force T = law(e) + BA de/dt: the tension-only law of cables
  (:func:`~symcable.models.common.terms.cable_axial_force`, as the planar line's; Sun, Zhu &
  LaRosa's secant K is not used: CasADi differentiates this law exactly, giving the tangent
  (EA/L0) t t^T + (T/l)(I - t t^T)), and Kelvin-Voigt material damping BA (N s), Sun, Zhu &
  LaRosa's C = c K;
- weight and buoyancy: the submerged weight w L0 (N), half on each node;
- Morison drag on the water's velocity relative to the element (the current minus the
  mean of its nodes' velocities), split along and across t: 0.5 rho d Cd |u| u sqrt(1+e)
  per unstretched metre (the planar law), with waves (``[environment.waves]``) their fluid
  velocity at the element's midpoint added to the current, |u| smoothed as sqrt(|u|^2 + DRAG_SPEED^2) so the
  force is differentiable at rest, half on each node; or, for a line type with ``drag_law =
  "loading-functions"``, Sun, Zhu & LaRosa's loading functions (:mod:`~symcable.models.common.drag`);
- in waves, Morison's inertia force: the displaced water's mass times (1 + Ca) the fluid
  acceleration at the element's midpoint, across and along it
  (:func:`~symcable.models.common.waves.element_wave_loads`), half on each node;
- bending where EI > 0 (:mod:`~symcable.models.common.bending`: a discrete curvature energy on node
  triplets; a clamped end's tangent held by a ghost node); such segments carry compression
  (the linear law EA e, as the planar line's), cable segments (EI = 0) do not;
- lumped mass: structural m L0 / 2 per node, and added mass rho A L0 / 2 (Ca_n (I - t t^T) +
  Ca_t t t^T) per node, rho A the displaced water per metre; or, with ``mass_matrix =
  "consistent"``, Sun, Zhu & LaRosa's L0 B / 6 [[2, 1], [1, 2]] per element (:mod:`.mass`).

Each node on a flat seabed at z = -depth gets (:mod:`~symcable.models.common.seabed`, shared with the rod) the
planar line's smooth penalty contact k d b ramp(-depth - z) (b its tributary length), a
damper into the bed (:func:`~symcable.models.common.seabed.seabed_damper`) and friction, axial
and lateral, by the scene's ``seabed.friction_law`` (:mod:`~symcable.models.common.friction`: regularised Coulomb, or an
elastic bristle per node whose deflections (m, x and y) are first-order states: the last
entries of q, node by node, their rates in the kinematics, zero at rest or, with
``seabed.static_friction = "laid"``, the static spring's deflection from the as-laid
shape). The free end carries its applied force. The lumped mass of an element next to a
moving end turns with it, so the mass matrix depends on t as well as q.

Parameters (blocks): ``line`` (the line's own numbers, :data:`SEGMENT_ROWS` per segment,
:data:`NODE_ROWS` per node and :data:`SCALARS`: every number of its sections, line types and
seabed contact that its expressions read, so that lines of one structure share one graph),
``load`` (scales weight, buoyancy and applied forces; 1),
``end_a.position``, ``end_b.position`` (3 each, m), ``current`` (3, m/s), ``slack`` (the
tension-only law's continuation, as planar), ``motion`` (scales the prescribed motions, a
tow's included; 0 in statics), ``ramp`` (1: a harmonic motion ramps in over its first
period from t = 0; 0: at full amplitude throughout, as periodic solves take it), ``bed``
(scales the seabed contact's stiffness; 1); with
static friction ``static_friction`` (1 in statics, 0 in time) and ``laid`` (the as-laid
horizontal positions of the nodes, m, node by node); with waves ``wave_scale`` (scales the
sea; 1, 0 in statics) and ``waves`` (:func:`~symcable.models.common.waves.wave_block`); an
end a host program moves (motion ``"coupled"``, :class:`symcable.Coupling`) ``end_a.coupled``
/ ``end_b.coupled`` (:func:`~symcable.models.common.elements.coupled_path`).
"""
from __future__ import annotations

import dataclasses
import math

import casadi as ca
import numpy as np

from ...errors import SymcableError
from ...scene import EndCondition, Scene
from ..common.bending import bending_nodes, bending_terms, linear_axial_law
from ..common.drag import law_table
from ..common.terms import fluid_term_names
from ..common.waves import WAVE_TERMS, element_wave_loads, wave_block
from .mass import added_mass_coefficients, line_mass
from .elements import CONSTANTS, FormNumbers, element_form, form_constants
from ..common.starts import force_scale, starts_of
from ..common.relax import _ramp_integral
from ...mechanism.mechanism import (Bound, Layout, Mechanism, Output, ParamBlocks, PartLayout,
                                   Scales, StateNames)
from ..common.seabed import (bristle_scale, friction_setup, lumped as _lumped, node_resolution,
                             profile_current, reaction_bound, reaction_drag, seabed_forces,
                             seabed_numbers, seabed_term_names)
from ..common.segments import (CABLE_COMPRESSION, FOLD_PUSH, SLACK_CONTINUATION, segment_table,
                              slack_law)
from ..common.elements import COUPLED_BLOCK, DRAG_SPEED, element_kernel, held_end

__all__ = ["DRAG_SPEED", "NODE_ROWS", "SCALARS", "SEGMENT_ROWS", "build_cable3d",
           "force_scale"]


P_NAMES = ("line", "load", "end_a.position", "end_b.position", "current", "slack", "motion",
           "ramp", "bed")
P_SIZES = (None, 1, 3, 3, 3, 1, 1, 1, 1)

#: the ``line`` block's rows of one entry per segment, in order: unstretched length (m), EA
#: (N), submerged weight per length (N/m), diameter (m), normal and tangential drag
#: coefficients, mass per length (kg/m), normal and tangential added-mass coefficients,
#: material damping BA (N s), the tension-only law's EA_slack (N) and corner width delta
#: (:func:`~symcable.models.common.segments.slack_law`)
SEGMENT_ROWS = ("ds", "EA", "w", "d", "cdn", "cdt", "mass", "can", "cat", "BA", "EAs", "delta")
#: ... of one entry per node: seabed contact area (m^2) and submerged weight lumped on the
#: node (N) (:func:`~symcable.models.common.seabed.seabed_numbers`; zeros without a seabed)
NODE_ROWS = ("area", "lumped")
#: ... and its scalars: the force scale F (N), the seabed contact's smoothing width and
#: sink (m) and the most a unit current's drag presses the line onto the bed (N s^2/m^2)
SCALARS = ("F", "width", "sink", "drag")


def build_cable3d(scene: Scene, part: str | None = None,
                  joined: tuple[bool, bool] = (False, False), *,
                  symbols: bool = True) -> Mechanism:
    """The scene's line as a cable3d Mechanism (module docstring).

    ``part``: build the line as a part of an assembly
    (:mod:`~symcable.models.system`) under that name: the Mechanism, its layout part
    and its outputs' owner take the name, and both ends may be free (joined to free points
    that other lines hold). None: the one-line scene's Mechanism ``"cable3d"``, part ``"line"``.
    ``joined``: whether end A / end B is joined to a free point of the assembly (its seabed
    contact then takes the neighbour's penetration while the point touches the bed: the
    point has its own contact, :func:`~symcable.models.system.point_contact`; this
    part of the contact is not conservative, and the potential energy output counts it at
    the node's own penetration).
    ``symbols``: False builds the numbers alone (parameter values, scales, starts, layout,
    bounds' limits, the element form's constants) on placeholder expressions, for a scene
    whose structure's expressions exist already (:mod:`symcable.models.structure`).
    """
    owner = part or "line"
    if any(e.position is not None and len(e.position) != 3 for e in (scene.end_a, scene.end_b)):
        raise SymcableError(f"build_cable3d: scene {scene.name!r} has planar end positions "
                            "(model = 'cable3d' reads [x, y, z])")
    seg = segment_table(scene)
    N = len(seg["ds"])
    env, sb = scene.environment, scene.seabed
    a, b = scene.end_a, scene.end_b
    free = [a.condition is EndCondition.FREE, b.condition is EndCondition.FREE]
    if all(free) and part is None:
        raise SymcableError(f"scene {scene.name!r}: both ends free; hold one end")
    rubs, bristle, laid = friction_setup(scene, seg)
    F = force_scale(scene, seg)
    law = linear_axial_law(seg, slack_law(seg, F))
    rho = 0.0 if env.in_air else env.water_density
    drag_law = law_table(scene)
    if drag_law is not None:
        seg["drag_law"] = dict(drag_law, eps=DRAG_SPEED)  # for the starts' frozen drag
    BA = _axial_damping(scene, seg)
    sea_numbers = seabed_numbers(scene, seg) if sb is not None else None
    cdn_bound = seg["cdn"] if drag_law is None else drag_law["normal_bound"]
    params = _param_blocks(scene, laid, _line_values(seg, law, BA, F, rho, sea_numbers,
                                                     cdn_bound, added_mass_coefficients(scene)))
    if not symbols:
        return _numbers_only(scene, seg, part, params, _moving(N, free), bristle, laid, law, F,
                             BA, rho, drag_law, cdn_bound)
    p = ca.SX.sym("p", params.n)
    L = _line_view(p[params.slice("line")], N)
    load, pa, pb = (p[params.slice(k)] for k in ("load", "end_a.position", "end_b.position"))
    current, sigma, motion, ramp_on, bed = (p[params.slice(k)] for k in (
        "current", "slack", "motion", "ramp", "bed"))
    t = ca.SX.sym("t")
    host = {k: p[params.slice(f"{k}.coupled")] for k in _coupled_ends(scene)}
    moving, q_all, v, X, V = _node_symbols(scene, N, free, bristle, pa, pb, motion, t, ramp_on,
                                           host)
    n_v = 3 * len(moving)
    state = q_all[n_v:]
    Xm, Vm = ca.horzcat(*X), ca.horzcat(*V)  # (3, N+1)

    width = ca.exp(math.log(SLACK_CONTINUATION) * (1.0 - sigma))
    sea_u = sea_f = None
    if env.waves is not None:  # the waves' velocity joins the current; their inertia force
        sea_u, sea_f = element_wave_loads(scene, Xm, t, p[params.slice("waves")],
                                          p[params.slice("wave_scale")], ramp_on, rho, L)
    fa, fb, T, e = _element_forces(scene, Xm, Vm, current, load, L, width, rho, drag_law, sea_u)
    if sea_f is not None:
        fa, fb = fa + 0.5 * sea_f, fb + 0.5 * sea_f
    elements = ca.horzcat(fa, ca.SX.zeros(3, 1)) + ca.horzcat(ca.SX.zeros(3, 1), fb)  # (3, N+1)
    nodal = ca.SX.zeros(3, N + 1)  # what the elements do not give (the element form's rest)
    contact = ca.SX.zeros(1, N + 1)
    term_names = _term_names(scene, seg, BA, rho)
    bending = bending_terms(scene, seg, Xm)
    if bending is not None:
        nodal = nodal + bending[0]
    fr = sea = None
    if sb is not None:  # contact, damper and friction on the nodes (.seabed3d)
        sea_rows = dict(sea_numbers, area=L["area"], weight=ca.fabs(L["lumped"]),
                        width=L["width"], sink=L["sink"])
        sea = seabed_forces(scene, seg, Xm, Vm, nodal, [], state=state,
                            laid=None if laid is None else p[params.slice("laid")],
                            gate=None if laid is None else p[params.slice("static_friction")],
                            joined=joined, bed=bed, numbers=sea_rows)
        nodal, contact, fr = sea.nodal, sea.contact, sea.friction
    # what the line exerts on each end (N): its element's pull and the loads lumped on the
    # end node, which the support takes (as the planar line's end forces); on a free end the
    # applied force is not the line's, and balances this. At an end joined to a free point
    # (the node is the point's too) these are the line's share of the node's loads: its end
    # segment's pull and its half segment's weight, drag and seabed contact, damper and
    # friction (resting on the bed with the point, the contact carries the half segment:
    # seabed.joined_on); the point's own loads are its own part's
    end_force_a = elements[:, 0] + nodal[:, 0] + (bending[1].get(0, 0.0) if bending else 0.0)
    end_force_b = elements[:, N] + nodal[:, N] + (bending[1].get(N, 0.0) if bending else 0.0)
    applied = _applied_forces(scene, N)
    if np.any(applied):
        nodal = nodal + load * ca.DM(applied)
    force_rest = ca.vertcat(*[nodal[:, i] for i in moving])
    nodal = elements + nodal
    force = ca.vertcat(*[nodal[:, i] for i in moving])

    mass, inertia, acc = line_mass(scene, L, Xm, V, t, rho, moving)
    if inertia is not None:
        force = force + inertia
    form = None
    if not env.current_profile and env.waves is None and part is None:  # the elements'
        # kernel as a loop (an assembly's part has none: assemble drops it)
        form = _form(scene, seg, X, V, acc, moving, drag_law, BA, law, F, rho, current, load,
                     width, force_rest, L)
    outputs = _line_outputs(owner, Xm, Vm, T, e, contact, fr if rubs else None, end_force_a,
                            end_force_b)
    _add_energies(outputs, owner, L, e, width, load, Xm, sea, bending, v, mass)
    cable = seg["EI"] <= 0.0
    bounds = _bounds(scene, seg, T, e, F, contact, applied, cdn_bound, rho, current, L["drag"])
    return Mechanism(
        name=part or "cable3d", q=q_all, v=v, z=ca.SX.sym("z", 0), t=t, p=p, params=params,
        mass=mass, force=force, constraint=ca.SX.zeros(0, 1), outputs=outputs,
        terms=tuple(term_names), bounds=bounds,
        stability_when=ca.SX(1.0) if np.all(cable) else None,
        kinematics=ca.vertcat(v, fr.rate) if bristle else None,
        rest=fr.rest if bristle else None, elements=form,
        stability_coordinates=np.arange(n_v) if bristle else None,
        **_numbers(scene, seg, part, params, moving, bristle, laid, F, int(q_all.numel()), free))


def _numbers(scene: Scene, seg: dict, part, params: ParamBlocks, moving: list, bristle: bool,
             laid, F: float, n_q: int, free: list) -> dict:
    """The line Mechanism's numeric fields: scales, starts, layout, static parameters."""
    N = len(seg["ds"])
    n_v = 3 * len(moving)
    static = {"motion": np.zeros(1)}
    if scene.environment.waves is not None:  # a calm sea in statics
        static["wave_scale"] = np.zeros(1)
    if laid is not None:
        static["static_friction"] = np.ones(1)
    p_static = params.with_values(**static)

    def starts():
        for st in starts_of(scene, seg, params, moving):
            yield dataclasses.replace(st, q=np.concatenate([st.q, np.zeros(n_q - n_v)]),
                                      p=p_static)
    return dict(scales=_scales(scene, seg, N, n_v, bristle, F),
                starts=starts if not all(free) else tuple,
                layout=_layout(part or "line", seg, N, moving, bristle), static_params=static)


def _term_names(scene: Scene, seg: dict, BA: np.ndarray, rho: float) -> list:
    """The terms the line's equations build, by name, in order."""
    names = ["elastic", "weight"] + (["material damping"] if np.any(BA) else [])
    if bending_nodes(scene, seg):
        names.append("bending")
    names += fluid_term_names(scene.sections, rho)
    if scene.environment.waves is not None:
        names += WAVE_TERMS
    if scene.seabed is not None:
        names += seabed_term_names(scene.seabed, friction_setup(scene, seg)[2] is not None)
    if np.any(_applied_forces(scene, len(seg["ds"]))):
        names.append("end force")
    return names


def _numbers_only(scene: Scene, seg: dict, part, params: ParamBlocks, moving: list,
                  bristle: bool, laid, law: dict, F: float, BA: np.ndarray, rho: float,
                  drag_law, cdn_bound) -> Mechanism:
    """The line's Mechanism with its numbers and placeholder expressions (zeros of the
    symbols' and expressions' shapes; ``build_cable3d(symbols=False)``)."""
    N = len(seg["ds"])
    n_v = 3 * len(moving)
    n_q = n_v + (2 * (N + 1) if bristle else 0)
    free = [scene.end_a.condition is EndCondition.FREE, scene.end_b.condition is EndCondition.FREE]
    q, v, p, t = ca.SX(n_q, 1), ca.SX(n_v, 1), ca.SX(params.n, 1), ca.SX(1, 1)
    zero = ca.SX.zeros(1, N)
    bounds = _bounds(scene, seg, zero, zero, F, ca.SX.zeros(1, N + 1), _applied_forces(scene, N),
                     cdn_bound, rho, ca.SX.zeros(3, 1), 0.0)
    form = None  # (a part of an assembly has none: assemble drops it)
    if not scene.environment.current_profile and scene.environment.waves is None \
            and part is None:
        form = FormNumbers(form_constants(_form_columns(scene, seg, BA, law, F, rho),
                                          drag_law["law"].T if drag_law else None,
                                          scene.mass_matrix != "lumped"))
    return Mechanism(
        name=part or "cable3d", q=q, v=v, z=ca.SX.sym("z", 0), t=t, p=p, params=params,
        mass=ca.SX(n_v, n_v), force=ca.SX.zeros(n_v, 1), constraint=ca.SX.zeros(0, 1),
        terms=tuple(_term_names(scene, seg, BA, rho)), bounds=bounds,
        kinematics=ca.SX.zeros(n_q, 1) if bristle else None,
        rest=ca.SX.zeros(n_q - n_v, 1) if bristle else None, elements=form,
        stability_coordinates=np.arange(n_v) if bristle else None,
        **_numbers(scene, seg, part, params, moving, bristle, laid, F, n_q, free))


def _line_values(seg: dict, law: dict, BA: np.ndarray, F: float, rho: float,
                 sea: dict | None, cdn_bound, added: tuple) -> np.ndarray:
    """The ``line`` block's values (module docstring; :data:`SEGMENT_ROWS`, then
    :data:`NODE_ROWS`, then :data:`SCALARS`)."""
    N = len(seg["ds"])
    cols = dict(seg, can=added[0], cat=added[1], BA=BA, EAs=law["EA_slack"], delta=law["delta"])
    rows = [np.asarray(cols[k], float) for k in SEGMENT_ROWS]
    if sea is not None:
        rows += [sea["area"], _lumped(seg)]
        scalars = [F, sea["width"], sea["sink"], reaction_drag(seg, cdn_bound, rho)]
    else:
        rows += [np.zeros(N + 1), _lumped(seg)]
        scalars = [F, 0.0, 0.0, 0.0]
    return np.concatenate(rows + [np.asarray(scalars, float)])


def _line_view(block, N: int) -> dict:
    """The ``line`` block's entries by name: (1, N) rows, (1, N+1) rows and scalars."""
    out, i = {}, 0
    for k in SEGMENT_ROWS:
        out[k] = block[i:i + N].T
        i += N
    for k in NODE_ROWS:
        out[k] = block[i:i + N + 1].T
        i += N + 1
    for k in SCALARS:
        out[k] = block[i]
        i += 1
    return out


def _param_blocks(scene: Scene, laid: np.ndarray | None, line: np.ndarray) -> ParamBlocks:
    """The parameter blocks (module docstring) at the scene's values, ``line`` the line
    block's (:func:`_line_values`); with ``laid`` (the as-laid horizontal node positions, m)
    the static friction's two blocks too."""
    env, a, b = scene.environment, scene.end_a, scene.end_b
    sea = () if env.waves is None else (wave_block(env.waves, env.depth, env.gravity),)
    host = _coupled_ends(scene)
    names = P_NAMES + (("static_friction", "laid") if laid is not None else ()) \
        + (("wave_scale", "waves") if sea else ()) + tuple(f"{k}.coupled" for k in host)
    sizes = (line.size,) + P_SIZES[1:] + ((1, laid.size) if laid is not None else ()) \
        + ((1, sea[0].size) if sea else ()) + (COUPLED_BLOCK,) * len(host)
    return ParamBlocks(names, sizes, np.concatenate([
        line, [1.0], a.position if a.position is not None else np.zeros(3),
        b.position if b.position is not None else np.zeros(3), env.current, [1.0], [1.0], [1.0],
        [1.0]] + ([[0.0], laid] if laid is not None else []) + ([[1.0], sea[0]] if sea else [])
        + [np.zeros(COUPLED_BLOCK)] * len(host)))


def _coupled_ends(scene: Scene) -> tuple:
    """``"end_a"`` and/or ``"end_b"``: the ends a host program moves (motion ``"coupled"``)."""
    return tuple(k for k in ("end_a", "end_b") if getattr(scene, k).motion is not None
                 and getattr(scene, k).motion.kind == "coupled")


def _moving(N: int, free: list) -> list:
    """The nodes that move (interior nodes and free ends), in order."""
    return [i for i in range(N + 1) if (i == 0 and free[0]) or (i == N and free[1]) or 0 < i < N]


def _node_symbols(scene: Scene, N: int, free: list, bristle: bool, pa, pb, motion, t, ramp_on,
                  host: dict):
    """The moving nodes (indices), the coordinates q (3 per moving node, then 2 bristle
    deflections per node with ``bristle``), the velocities v (3 per moving node), and each
    node's position and velocity (lists of N+1 (3, 1): q and v's entries, or a held end's
    prescribed motion, m and m/s; ``host``: a coupled end's parameter block by its key)."""
    moving = _moving(N, free)
    n_v = 3 * len(moving)
    q_all = ca.SX.sym("q", n_v + (2 * (N + 1) if bristle else 0))
    q = q_all[:n_v]
    v = ca.SX.sym("v", n_v)
    X, V = [None] * (N + 1), [None] * (N + 1)
    for k, i in enumerate(moving):
        X[i], V[i] = q[3 * k:3 * k + 3], v[3 * k:3 * k + 3]
    for key, end, i, pp in (("end_a", scene.end_a, 0, pa), ("end_b", scene.end_b, N, pb)):
        if X[i] is None:
            X[i], V[i] = held_end(end, pp, motion, t, ramp_on, host.get(key))
    return moving, q_all, v, X, V


def _axial_damping(scene: Scene, seg: dict) -> np.ndarray:
    """Each segment's Kelvin-Voigt material damping BA (N,), N s."""
    BA = np.array([s.line_type.damping for s in scene.sections for _ in range(s.segments)])
    # negative: minus the damping ratio zeta of the line's highest axial mode (adjacent
    # nodes in opposition: stiffness 4 EA/ds, damping 4 BA/ds, mass m ds per node), as
    # MoorDyn reads BA/-zeta: BA = zeta ds sqrt(EA m)
    return np.where(BA < 0, -BA * np.sqrt(seg["EA"] * seg["mass"]) * seg["ds"], BA)


def _element_forces(scene: Scene, Xm, Vm, current, load, L: dict, width, rho: float,
                    drag_law: dict | None, waves=None):
    """The element kernel mapped over the N segments, its numbers the ``line`` block's
    (``L``, :func:`_line_view`), ``waves`` the waves' velocity at the elements (3, N) or
    None: the forces on each segment's first and second node (3, N),
    N; its axial force T (1, N), N, and strain e (1, N)."""
    N = Xm.shape[1] - 1
    env = scene.environment
    kernel = element_kernel(drag_law["shape"] if drag_law else None).map(N)
    water = ca.repmat(current, 1, N)
    if env.current_profile:  # the current at each element's mid-depth
        water = water + profile_current(env.current_profile,
                                        0.5 * (Xm[2, :-1] + Xm[2, 1:]))
    if waves is not None:
        water = water + waves
    return kernel(Xm[:, :-1], Xm[:, 1:], Vm[:, :-1], Vm[:, 1:], water,
                  L["ds"], L["EA"], L["BA"], L["EAs"], width * L["delta"], L["F"], L["w"],
                  L["d"], L["cdn"], L["cdt"], rho, load,
                  *([ca.DM(drag_law["law"]).T] if drag_law else []))


def _applied_forces(scene: Scene, N: int) -> np.ndarray:
    """(3, N+1) the forces applied on free ends (N, at load 1), zero elsewhere."""
    applied = np.zeros((3, N + 1))
    for end, i in ((scene.end_a, 0), (scene.end_b, N)):
        if end.condition is EndCondition.FREE and end.force is not None:
            applied[:, i] = end.force
    return applied






def _form(scene: Scene, seg: dict, X: list, V: list, acc: dict, moving: list,
          drag_law: dict | None, BA: np.ndarray, law: dict, F: float, rho: float, current, load,
          width, force_rest, L: dict | None = None):
    """The elements' kernel as a loop (:func:`.elements.element_form`), the held ends'
    position, velocity and acceleration (9, N+1) fed in."""
    N = len(seg["ds"])
    held = ca.SX.zeros(9, N + 1)
    for i in (0, N):
        if i not in moving:
            held[:, i] = ca.vertcat(X[i], V[i], acc[i])
    form = element_form(
        element_kernel(drag_law["shape"] if drag_law else None),
        _form_columns(scene, seg, BA, law, F, rho),
        drag_law["law"].T if drag_law else None, ca.vertcat(current, load, width),
        _node_index(N, moving), held, force_rest, scene.mass_matrix != "lumped")
    if L is None or drag_law:  # (the loading functions' table is numbers of the scene)
        return form
    ones = ca.DM.ones(1, N)
    half = form.constants[-2:]  # the mass weights on a node's own and its neighbour's
    rows = dict(L0=L["ds"], EA=L["EA"], BA=L["BA"], EAs=L["EAs"], delta=L["delta"],
                wall=L["F"] * ones, w=L["w"], d=L["d"], cdn=L["cdn"], cdt=L["cdt"],
                rho=rho * ones, structural_half=0.5 * L["mass"] * L["ds"],
                added_half=0.5 * rho * (math.pi / 4.0) * L["d"] * L["d"] * L["ds"],
                ca_normal=L["can"], ca_tangential=L["cat"])
    parametric = ca.vertcat(*[rows[k] for k in CONSTANTS[:-2]], ca.DM(half))
    return dataclasses.replace(form, parametric=parametric)


def _form_columns(scene: Scene, seg: dict, BA: np.ndarray, law: dict, F: float,
                  rho: float) -> dict:
    """The element form's per-element constants by name (:func:`.elements.element_form`)."""
    A_w = math.pi * seg["d"] ** 2 / 4.0
    can, cat = added_mass_coefficients(scene)
    return dict(L0=seg["ds"], EA=seg["EA"], BA=BA, EAs=law["EA_slack"], delta=law["delta"],
                wall=F, w=seg["w"], d=seg["d"], cdn=seg["cdn"], cdt=seg["cdt"], rho=rho,
                structural_half=0.5 * seg["mass"] * seg["ds"],
                added_half=0.5 * rho * A_w * seg["ds"], ca_normal=can, ca_tangential=cat)


def _line_outputs(owner: str, Xm, Vm, T, e, contact, fr, end_force_a, end_force_b) -> dict:
    """The line's outputs: node positions and velocities (N+1, 3), segment axial forces and
    strains (N, 1), nodal contact (N+1, 1) and, when ``fr`` (the seabed friction) is given,
    friction forces (N+1, 2), the forces on the ends (3, 1), N."""
    return {
        "positions": Output(Xm.T, "m", owner, "node positions (x, y, z)"),
        "velocities": Output(ca.densify(Vm.T), "m/s", owner, "node velocities (x, y, z)"),
        "axial_force": Output(T.T, "N", owner, "axial force of each segment"),
        "strain": Output(e.T, "1", owner, "strain of each segment"),
        "contact_force": Output(contact.T, "N", owner, "seabed contact force on each node"),
        **({"friction_force": Output(fr.force.T, "N", owner, "seabed friction force on each "
                                     "node (x, y)")} if fr is not None else {}),
        "end_force_a": Output(end_force_a, "N", owner, "force of the line on end A: the end "
                              "segment's pull plus its half segment's loads on the end node"),
        "end_force_b": Output(end_force_b, "N", owner, "force of the line on end B: the end "
                              "segment's pull plus its half segment's loads on the end node"),
    }


def _add_energies(outputs: dict, owner: str, L: dict, e, width, load, Xm, sea, bending, v,
                  mass) -> None:
    """Adds the bending moment (where the line bends) and the energies (J) to ``outputs``:
    kinetic 0.5 v^T M v of the moving nodes; potential: the law's integral over each
    element, the submerged weight's height, the contact's integral (the conservative
    forces' potential: with no drag, damping, friction or moving end the sum is
    conserved); the numbers the ``line`` block's (``L``)."""
    ec = e.T  # (N, 1)
    EAs, EA = L["EAs"].T, L["EA"].T
    U = (0.5 * EAs * ec * ec + (EA - EAs) * _ramp_integral(ec, width * L["delta"].T)
         + L["F"] * 0.005 * ca.exp(-(1.0 + ec) / 0.005))
    potential = ca.dot(L["ds"].T, U) + load * ca.dot(L["lumped"], Xm[2, :])
    if sea is not None:
        potential += sea.energy
    if bending is not None:
        potential += bending[2]
        outputs["bending_moment"] = Output(bending[3].T, "N m", owner, "bending moment vector "
                                           "at each node (along the binormal)")
    outputs["kinetic_energy"] = Output(0.5 * ca.dot(v, ca.mtimes(mass, v)), "J", owner,
                                       "kinetic energy of the moving nodes")
    outputs["potential_energy"] = Output(potential, "J", owner, "elastic, gravity, contact "
                                         "and bending potential energy")


def _bounds(scene: Scene, seg: dict, T, e, F: float, contact, applied: np.ndarray,
            cdn, rho: float, current, drag) -> dict:
    """The admissibility bounds: positive segment lengths, no compression in cable segments
    (EI = 0), and with a seabed its reaction
    (:func:`~symcable.models.common.seabed.reaction_bound`, ``cdn`` the normal drag
    coefficients it reads, ``drag`` its expression's
    :func:`~symcable.models.common.seabed.reaction_drag`)."""
    N = len(seg["ds"])
    cable = seg["EI"] <= 0.0
    push = np.maximum(CABLE_COMPRESSION * F, FOLD_PUSH * np.abs(seg["w"]) * seg["ds"])
    bounds = {"strain": Bound(e.T, lower=-1.0 + 1e-9, unit="1", scale=1.0,
                              what="segments of positive length")}
    cab = np.flatnonzero(cable)
    if cab.size:  # segments with EI > 0 carry compression
        bounds["cable_axial_force"] = Bound(T.T if cab.size == N else T.T[cab.tolist()],
                                            lower=-push[cab], unit="N", scale=F,
                                            what="a cable (EI = 0) carries no compression")
    if scene.seabed is not None:
        bounds["seabed_reaction"] = reaction_bound(scene, seg, contact, applied, cdn, rho,
                                                   current, F, drag)
    return bounds


def _scales(scene: Scene, seg: dict, N: int, n_v: int, bristle: bool, F: float) -> Scales:
    """The scales: a tenth of the line's length per coordinate (m), a bristle's mobilisation
    length per deflection (m), sqrt(g L) per velocity (m/s), the force scale ``F`` (N), the
    line's mass (kg), the round-off floor of the stiffest segment's force (N) and the lightest
    node's weight (N, :func:`~symcable.models.common.seabed.node_resolution`)."""
    env, a, b = scene.environment, scene.end_a, scene.end_b
    L = scene.length
    coord = L + max((float(np.max(np.abs(e_.position))) for e_ in (a, b)
                     if e_.position is not None), default=0.0)
    floor = 100.0 * np.finfo(float).eps * float(np.max(seg["EA"] / seg["ds"])) * coord
    total_mass = float(np.sum(seg["mass"] * seg["ds"]))
    q_scale = np.full(n_v, 0.1 * L)
    if bristle:  # a bristle's deflection: up to its mobilisation length mu N / k
        q_scale = np.concatenate([q_scale, np.full(2 * (N + 1), bristle_scale(scene.seabed, seg))])
    return Scales(q=q_scale, v=np.full(n_v, math.sqrt(env.gravity * L)),
                  z=np.zeros(0), force=F, mass=max(total_mass, 1e-6), residual_floor=floor,
                  resolution=node_resolution(seg))


def _layout(owner: str, seg: dict, N: int, moving: list, bristle: bool) -> Layout:
    """The layout: the line's nodes (held ends moved by ``end_a`` / ``end_b``) and, with
    bristles, the names of their deflections."""
    states = None
    if bristle:  # node by node, x then y (see seabed_friction.friction)
        states = StateNames(tuple(f"node{i}.bristle.{c}" for i in range(N + 1) for c in "xy"),
                            "m", 'seabed.friction_law = "bristle"',
                            'seabed.friction_law = "coulomb"')
    index = _node_index(N, moving)
    return Layout(3, {owner: PartLayout(
        "line", seg["s"], index, index.copy(),
        {i: name for i, name in ((0, "end_a"), (N, "end_b")) if i not in moving})}, states)




def _node_index(N, moving) -> np.ndarray:
    """(N+1, 3) index of each node's coordinates in q (-1 for a held end)."""
    idx = -np.ones((N + 1, 3), dtype=int)
    idx[np.asarray(moving, dtype=int)] = np.arange(3 * len(moving)).reshape(-1, 3)
    return idx
