"""Planar cable dynamics linearised about the static state, after S. Boral, J. Hickey and
B. Basu, "Modeling and Simulation of Periodic Cable Dynamics with Bending Stiffness Using
Time-Domain and Multi-Harmonic Balance Methods" (Algorithm S2 of its supplementary code
overview; "the paper" below).

Discretisation (the statics' own, see :mod:`symcable.models.planar.model`)
-------------------------------------------------------------------
State ``y``, interleaved like the static unknowns:

* on every node whose motion is not prescribed (interior nodes, a free end): the velocity
  in the node's static frame, tangential ``u_i`` and normal ``v_i`` (m/s). The frame angle
  ``theta_i`` is the mean of the adjacent static segment angles (an end node takes its
  segment's);
* on every segment: the dynamic strain ``e_j`` and dynamic angle ``phi_j`` (rad), increments
  on the static ``eps_j``, ``phi_j`` at the segment midpoint.

Equations (everything linear in the state except drag):

* kinematics, the time derivative of the statics' compatibility linearised at rest:
  ``de_j/dt = t_j . (V_{j+1} - V_j) / ds_j`` and
  ``dphi_j/dt = n_j . (V_{j+1} - V_j) / (ds_j (1 + eps_j))``, where ``V_i`` is the node's
  Cartesian velocity (from ``u, v``, or the prescribed end motion) and ``t_j, n_j`` the static
  segment frame. These are the paper's ``de/dt = du/ds - v dphi_s/ds`` and
  ``dphi/dt = dv/ds + u dphi_s/ds``;
* momentum per free node, projected on its static frame:
  ``m_t,i du_i/dt = t_i . R_i`` and ``m_n,i dv_i/dt = n_i . R_i`` with
  ``R_i = dF_i - dF_{i-1} + dP_i``. The lumped masses are ``m`` times the tributary length,
  plus the normal added mass ``rho Ca pi d^2/4`` in the normal direction. ``dF_j`` is the exact
  linearisation (CasADi ``jtimes``) of the statics' internal force ``T t + Q n`` in the
  direction ``(phi_j, e_j)``: the increments ``EA e t``, the rotated static tension
  ``T phi n`` and the bending shear are all in it, written out by CasADi. Weight does not
  change in Cartesian components, so it gives no increment (the paper's ``W phi`` terms are
  the rotated static tension, by the static balance);
* drag: per segment, Morison on the water's velocity relative to the segment's mean velocity,
  on the segment as it is (total angle and strain: the paper uses the static angle, which
  drops the first-order change of drag as the line turns in the current), minus the steady drag of the static balance (at the static
  state's current). So the static state is an exact rest state of the dynamics, and a
  changed current parameter loads the line.

Boundaries: a pinned or clamped end node moves with its prescribed velocity (zero for an
anchor; the derivative of the harmonic displacement ``x_i(t) = A_i cos(omega t + phase_i)``
about the static place, of the scene's ``motion``); a clamped end keeps its static angle; a
free end carries its dead load, which does not change. A run from rest (``p_value``) ramps
the displacement in over the first period so that it ends up about the scene's position,
where the paper's velocity-only start would leave it offset by ``A cos(phase)``; the periodic
steady state (``p_periodic``) has no ramp. With both ends held, the end-to-end closure that
the kinematics conserve is stabilised (``dc/dt = -beta c``; see the code), which is zero on
the physical solution.

Outputs (the paper's Algorithm S3): the force the line exerts on its ends, static plus the
increment of the end node's balance (``dP_N - dF_{N-1}`` at B, ``dP_0 + dF_0`` at A, less the
d'Alembert force of a moving end's lumped mass; the paper's ``T_static + EA e[N]`` is its
leading term), their magnitudes, the segment tension ``|F + dF|`` (a magnitude, never negative), the signed
segment axial force ``EA (eps_s + e)`` (positive = tension, negative = compression), ``e``,
``phi``, and the node positions, chained from the total angle and strain as
``r_{j+1} = r_j + ds (1 + eps_s + e) (cos, sin)(phi_s + phi)`` from a held end's place (its
static place plus its prescribed displacement; end B's when end A is free).
:func:`reconstruct_positions` does the same in NumPy from end A's static place.
"""
from __future__ import annotations

import functools
import math
from collections.abc import Mapping
from dataclasses import dataclass
from types import MappingProxyType

import casadi as ca
import numpy as np

from ...errors import SceneError
from ...scene import EndCondition, Scene
from ..common import terms
from .dynamic import DynamicModel
from .model import _lumping_matrix, internal_forces
from ..common.segments import force_scale_of, segment_table, slack_law


def _node_frames(phi_s):
    """Static frame angle of each node (N+1,) from the segment angles (N,)."""
    N = phi_s.numel() if hasattr(phi_s, "numel") else len(phi_s)
    if N == 1:
        return ca.vertcat(phi_s[0], phi_s[0])
    return ca.vertcat(phi_s[0], 0.5 * (phi_s[:-1] + phi_s[1:]), phi_s[N - 1])


#: Largest grounded length the dynamics accept, as a fraction of the shortest segment. The
#: penalty contact is smoothed (:func:`~symcable.models.common.terms.smooth_ramp`), so a node clear
#: of the seabed by h still carries k d delta^2 / (4 h) per metre, and a taut line whose
#: anchor sits on the seabed reports a grounded length of 1e-7..1e-3 m where no node rests on
#: it. The grounded length is the length whose weight the seabed carries: below 1 % of a
#: segment, the seabed carries less than 1 % of one segment's weight (a node must sink about
#: 0.75 delta, 1 % of its penetration under its own weight, before it does), far below what
#: the discretisation resolves (each node lumps half of each adjacent segment), so leaving
#: contact out of the dynamics changes nothing it resolves. A fraction of the segment length
#: rather than a penetration depth because the statics report a length, and the refusal
#: must agree with what they print.
GROUNDED_TOLERANCE = 0.01


def grounded_tolerance(scene: Scene) -> float:
    """Grounded length (m) up to which the dynamics treat the line as clear of the seabed."""
    return GROUNDED_TOLERANCE * min(sec.ds for sec in scene.sections)


def _check_scene(scene: Scene, static) -> None:
    if static.status != "converged":
        raise SceneError("static solution: status = %r: the dynamics needs a converged static state"
                         % static.status)
    if scene.seabed is not None and static.grounded_length > grounded_tolerance(scene):
        held = [(e.position[-1], name, other) for name, e, other in
                (("end_a", scene.end_a, "end_b"), ("end_b", scene.end_b, "end_a")) if e.is_fixed]
        _, low, other = min(held)
        raise SceneError(
            f"environment.depth = {scene.environment.depth} m: the static line rests "
            f"{static.grounded_length:.3g} m on the seabed (more than {grounded_tolerance(scene):.3g} m, "
            f"{100 * GROUNDED_TOLERANCE:g} % of a segment), and planar dynamics with seabed contact "
            f"is not supported yet: move {low}.position further from {other} along the seabed "
            "until the static line lifts off it (grounded length 0), or analyse this scene with "
            "statics only (symcable static) until seabed contact in the dynamics lands")
    periods = {e.motion.period for e in (scene.end_a, scene.end_b) if e.motion is not None}
    if len(periods) > 1:
        raise SceneError(f"end_a.motion.period, end_b.motion.period = {sorted(periods)} s: "
                         "both ends must move with the same period")


def dynamics_refusal(scene: Scene, static) -> str | None:
    """Why :func:`build_planar_dynamics` would refuse ``scene`` about ``static`` (the
    SceneError's one-line message), or None when the dynamics can be built."""
    try:
        _check_scene(scene, static)
    except SceneError as exc:
        return str(exc)
    return None


def build_planar_dynamics(scene: Scene, static) -> DynamicModel:
    """Linearised planar dynamics of ``scene`` about its static solution ``static``
    (a :class:`~symcable.results.static.StaticSolution` of the same scene)."""
    _check_scene(scene, static)
    seg = segment_table(scene)
    N = len(seg["ds"])
    env = scene.environment
    a, b = scene.end_a, scene.end_b

    blocks, slices, p_value, period = _param_blocks(scene, static, N)
    p = ca.SX.sym("p", sum(n for _, n in blocks))
    P = {name: p[sl] for name, sl in slices.items()}
    t = ca.SX.sym("t")
    phi_s, eps_s = P["phi_s"], P["eps_s"]
    theta = _node_frames(phi_s)
    st = _state(scene, N, P, t)
    y, e_dyn, phi_dyn, dyn_nodes, V = st.y, st.e_dyn, st.phi_dyn, st.dyn_nodes, st.V
    # Cartesian node velocities (N+1,), by whole-vector operations (one CasADi call each,
    # not one per node): the free nodes' from their frame, the held ends' prescribed
    th_d = theta[dyn_nodes]
    c_d, s_d = ca.cos(th_d), ca.sin(th_d)
    u_d = ca.vertcat(*[st.u[i] for i in dyn_nodes])
    v_d = ca.vertcat(*[st.v[i] for i in dyn_nodes])
    Vx_d, Vz_d = u_d * c_d - v_d * s_d, u_d * s_d + v_d * c_d
    Vx = ca.vertcat(*([] if 0 in st.u else [V[0][0]]), Vx_d, *([] if N in st.u else [V[N][0]]))
    Vz = ca.vertcat(*([] if 0 in st.u else [V[0][1]]), Vz_d, *([] if N in st.u else [V[N][1]]))

    cs, sn = ca.cos(phi_s), ca.sin(phi_s)
    ds = ca.DM(seg["ds"])
    e_rate, phi_rate = _segment_rates(scene, seg, P, st, Vx, Vz, cs, sn)

    # --- internal force increments: exact linearisation of the statics' internal force
    _, _, _, Fx, Fz, bending = internal_forces(phi_s, eps_s, seg, a.condition, b.condition,
                                               1.0, a.angle or 0.0, b.angle or 0.0,
                                               slack_law(seg, force_scale_of(scene, seg)))
    F_s = ca.vertcat(Fx, Fz)
    dF = ca.jtimes(F_s, ca.vertcat(phi_s, eps_s), ca.vertcat(phi_dyn, e_dyn))
    dFx, dFz = dF[:N], dF[N:]

    # --- drag increment on segments, lumped on nodes
    lump = _lumping_matrix(N)
    term_names = ["elastic", "inertia"] + (["bending"] if bending else [])
    dPx, dPz = ca.SX.zeros(N + 1), ca.SX.zeros(N + 1)
    if not env.in_air:
        term_names += ["drag", "added mass"]
        dPx, dPz = _drag_increment(env, seg, P, st, Vx, Vz, lump)

    # --- momentum on the free nodes
    m_t = np.asarray(ca.mtimes(lump, ca.DM(seg["mass"] * seg["ds"]))).ravel()
    m_add = 0.0 if env.in_air else env.water_density * math.pi / 4.0
    m_n = m_t + np.asarray(ca.mtimes(lump, ca.DM(m_add * seg["can"] * seg["d"] ** 2 * seg["ds"]))).ravel()
    zero = ca.SX.zeros(1)
    dFx_pad, dFz_pad = ca.vertcat(zero, dFx, zero), ca.vertcat(zero, dFz, zero)
    Rx = dFx_pad[1:] - dFx_pad[:-1] + dPx
    Rz = dFz_pad[1:] - dFz_pad[:-1] + dPz

    ct, st_ = ca.cos(th_d), ca.sin(th_d)
    Rx_d, Rz_d = Rx[dyn_nodes], Rz[dyn_nodes]
    u_rate = (ct * Rx_d + st_ * Rz_d) / ca.DM(m_t[dyn_nodes])
    v_rate = (-st_ * Rx_d + ct * Rz_d) / ca.DM(m_n[dyn_nodes])
    rhs = ca.vertcat(e_rate, phi_rate, u_rate, v_rate)[_rate_order(N, dyn_nodes)]

    # --- outputs
    F_tot_x, F_tot_z = Fx + dFx, Fz + dFz
    # force on an end = static + increment of the end node's balance (as in the statics):
    # the segment force, the node's own load increment and, at a moving end, the d'Alembert
    # force of the node's lumped mass (added mass normal to the line)
    force_b = P["force_b_s"] + ca.vertcat(dPx[N] - dFx[N - 1], dPz[N] - dFz[N - 1]) \
        - _end_inertia(N, st, t, theta, m_t, m_n)
    force_a = P["force_a_s"] + ca.vertcat(dPx[0] + dFx[0], dPz[0] + dFz[0]) \
        - _end_inertia(0, st, t, theta, m_t, m_n)
    px, pz = _positions(scene, N, P, ds, st)
    outputs = {
        "fairlead_tension": ca.norm_2(force_b),
        "anchor_tension": ca.norm_2(force_a),
        "fairlead_force": force_b.T,
        "anchor_force": force_a.T,
        "tension": ca.sqrt(F_tot_x ** 2 + F_tot_z ** 2),
        "axial_force": ca.DM(seg["EA"]) * (eps_s + e_dyn),
        "strain": e_dyn,
        "angle": phi_dyn,
        "positions": ca.horzcat(ca.vertcat(*px), ca.vertcat(*pz)),
    }

    kinds = st.kinds
    y_scale = _y_scale(scene, static, np.array(kinds), period)
    # the map from the state to Cartesian node velocities (x, z) at rest, for mode shapes
    theta_s = np.asarray(_node_frames(ca.DM(np.asarray(static.angle, dtype=float)))).ravel()
    info = _LazyInfo({
        "velocity_map": functools.partial(_velocity_map, N, y.numel(), np.array(kinds),
                                          dyn_nodes, theta_s),
        "node_frames": theta_s,
        "kinds": tuple(kinds), "dynamic_nodes": tuple(dyn_nodes), "segments": seg,
        "s_nodes": seg["s"], "static": static, "terms": tuple(term_names),
        "mass_tangential": m_t, "mass_normal": m_n, "scene": scene,
        # per segment: the largest total axial strain its line type takes, the range the
        # linearised dynamics are checked against (symcable.results.trajectory.strain_warnings)
        "max_strain": np.concatenate([[sec.line_type.max_strain] * sec.segments
                                      for sec in scene.sections]),
    })
    p_periodic = np.array(p_value)
    p_periodic[slices["ramp"]] = 0.0
    p_undamped = np.array(p_periodic)
    for name in ("amp_a", "amp_b", "current", "current_s", "beta"):
        p_undamped[slices[name]] = 0.0
    return DynamicModel(name="planar", y=y, t=t, p=p, p_value=p_value, p_periodic=p_periodic,
                        p_undamped=p_undamped,
                        p_names=tuple(n for n, _ in blocks), p_slices=MappingProxyType(slices),
                        rhs=rhs, outputs=outputs, y_scale=y_scale, period=period,
                        y0=np.zeros(y.numel()), info=info)


def _param_blocks(scene: Scene, static, N: int):
    """The parameter blocks ``[(name, size)]``, where each sits in ``p`` (name -> slice),
    their values for a run from rest (n_p,) and the excitation's period (s, None when
    nothing moves)."""
    env, a, b = scene.environment, scene.end_a, scene.end_b
    blocks = [("phi_s", N), ("eps_s", N), ("amp_a", 2), ("phase_a", 2), ("amp_b", 2),
              ("phase_b", 2), ("omega", 1), ("current", 2), ("current_s", 2), ("force_a_s", 2),
              ("force_b_s", 2), ("ramp", 1), ("beta", 1), ("pos_a_s", 2), ("pos_b_s", 2)]
    slices, k = {}, 0
    for name, n in blocks:
        slices[name] = slice(k, k + n)
        k += n
    period = next((e.motion.period for e in (a, b) if e.motion is not None), None)
    values = {
        "phi_s": static.angle, "eps_s": static.strain,
        "amp_a": a.motion.amplitude if a.motion else (0.0, 0.0),
        "phase_a": a.motion.phase if a.motion else (0.0, 0.0),
        "amp_b": b.motion.amplitude if b.motion else (0.0, 0.0),
        "phase_b": b.motion.phase if b.motion else (0.0, 0.0),
        "omega": 2 * math.pi / period if period else 0.0,
        "current": env.current, "current_s": env.current,
        "force_a_s": static.anchor_force, "force_b_s": static.fairlead_force,
        "ramp": period or 0.0,
        "beta": 2 * math.pi / period if period else 1.0,
        "pos_a_s": static.positions[0], "pos_b_s": static.positions[-1],
    }
    p_value = np.concatenate([np.atleast_1d(np.asarray(values[n], dtype=float)) for n, _ in blocks])
    return blocks, slices, p_value, period


@dataclass
class _State:
    """The state's symbols: ``y`` (n_y, 1) interleaved [node 0], seg 0, node 1, ..., seg N-1,
    [node N]; each entry's kind (``"u"``, ``"v"``, ``"e"``, ``"phi"``); the free nodes'
    tangential and normal velocities (node -> SX, m/s) in node order ``dyn_nodes``; the
    dynamic strains and angles (N, 1); the held ends' prescribed velocities ``V`` (N+1 list,
    (2, 1) m/s at a held end, else None) and displacements ``disp`` (end A, end B: (2, 1), m)."""

    y: ca.SX
    kinds: list
    u: dict
    v: dict
    dyn_nodes: list
    e_dyn: ca.SX
    phi_dyn: ca.SX
    V: list
    disp: list


def _state(scene: Scene, N: int, P: dict, t) -> _State:
    """The state's symbols and the held ends' prescribed motion (:class:`_State`)."""
    a, b = scene.end_a, scene.end_b
    omega = P["omega"]
    y_list, kinds, V = [], [], [None] * (N + 1)
    u_l, v_l, dyn_nodes = {}, {}, []

    def add_node(i):
        u, v = ca.SX.sym(f"u_{i}"), ca.SX.sym(f"v_{i}")
        u_l[i], v_l[i] = u, v
        y_list.extend([u, v])
        kinds.extend(["u", "v"])
        dyn_nodes.append(i)

    # prescribed end displacement d(t) = r(t) A cos(omega t + phase) about the static place,
    # with r a smooth start-up ramp over the first `ramp` seconds (r = 1 when ramp = 0), so a
    # run from rest ends up oscillating about the scene's position; V = dd/dt exactly
    T_r = P["ramp"][0]
    on = T_r > 0
    T_safe = ca.if_else(on, T_r, 1.0)  # no division by zero, so derivatives stay finite
    tau = ca.fmin(t / T_safe, 1.0)
    r = ca.if_else(on, 0.5 * (1 - ca.cos(math.pi * tau)), 1.0)
    r_dot = ca.if_else(ca.logic_and(on, t < T_r), 0.5 * math.pi / T_safe * ca.sin(math.pi * tau), 0.0)
    disp = [ca.SX.zeros(2, 1), ca.SX.zeros(2, 1)]

    def prescribed(i, tag):
        amp, ph = P[f"amp_{tag}"], P[f"phase_{tag}"]
        d = ca.vertcat(*[amp[c] * ca.cos(omega * t + ph[c]) for c in range(2)])
        v = ca.vertcat(*[-amp[c] * omega * ca.sin(omega * t + ph[c]) for c in range(2)])
        disp[0 if i == 0 else 1] = r * d
        V[i] = r_dot * d + r * v

    e_sym, ph_sym = [], []
    if a.condition is EndCondition.FREE:
        add_node(0)
    else:
        prescribed(0, "a")
    for j in range(N):
        e, ph = ca.SX.sym(f"e_{j}"), ca.SX.sym(f"phi_{j}")
        e_sym.append(e)
        ph_sym.append(ph)
        y_list.extend([e, ph])
        kinds.extend(["e", "phi"])
        if j + 1 < N or b.condition is EndCondition.FREE:
            add_node(j + 1)
    if b.condition is not EndCondition.FREE:
        prescribed(N, "b")
    return _State(ca.vertcat(*y_list), kinds, u_l, v_l, dyn_nodes, ca.vertcat(*e_sym),
                  ca.vertcat(*ph_sym), V, disp)


def _segment_rates(scene: Scene, seg: dict, P: dict, st: _State, Vx, Vz, cs, sn):
    """The kinematics on the segments: the rates of the dynamic strain and angle (N, 1), 1/s
    and rad/s, from the Cartesian node velocities ``Vx``, ``Vz`` (N+1, 1) and the static
    segment frame ``cs``, ``sn`` (cos, sin of the static angle); with both ends held, the
    end-to-end closure stabilised."""
    N = len(seg["ds"])
    eps_s = P["eps_s"]
    ds = ca.DM(seg["ds"])
    dVx = Vx[1:] - Vx[:-1]
    dVz = Vz[1:] - Vz[:-1]
    e_rate = (cs * dVx + sn * dVz) / ds
    phi_rate = (-sn * dVx + cs * dVz) / (ds * (1.0 + eps_s))
    # The kinematics conserve the closure c = sum ds (e t + (1 + eps) phi n) - (d_B - d_A)
    # (it telescopes to V_N - V_0 - dd_B/dt + dd_A/dt = 0), so with both ends held the state
    # has two more kinematic entries than displacements and a periodic solution would be
    # fixed only up to c. Baumgarte-type stabilisation makes dc/dt = -beta c: zero on the
    # physical manifold c = 0, which it makes attracting (and the periodic problem regular).
    # The correction acts on the last segment only: dc/dt = -beta c just the same, and only
    # two rows of the Jacobian become dense (spread over every segment, all of them would).
    if scene.end_a.condition is not EndCondition.FREE and scene.end_b.condition is not EndCondition.FREE:
        e_dyn, phi_dyn, disp = st.e_dyn, st.phi_dyn, st.disp
        cx = ca.sum1(ds * (e_dyn * cs - (1.0 + eps_s) * phi_dyn * sn)) - (disp[1][0] - disp[0][0])
        cz = ca.sum1(ds * (e_dyn * sn + (1.0 + eps_s) * phi_dyn * cs)) - (disp[1][1] - disp[0][1])
        beta, k = P["beta"][0], N - 1
        e_rate[k] = e_rate[k] - beta / seg["ds"][k] * (cs[k] * cx + sn[k] * cz)
        phi_rate[k] = phi_rate[k] - beta / seg["ds"][k] * (-sn[k] * cx + cs[k] * cz) / (1.0 + eps_s[k])
    return e_rate, phi_rate


def _drag_increment(env, seg: dict, P: dict, st: _State, Vx, Vz, lump):
    """The drag's increment lumped on the nodes, x and z (N+1, 1), N: on the segment as it is
    now (total angle and strain), minus the steady drag of the static balance at the static
    state's own current (block current_s): rest is exact, and a changed current (block
    current) loads the line as the statics would."""
    phi_s, eps_s = P["phi_s"], P["eps_s"]
    ds = ca.DM(seg["ds"])
    U = P["current"]
    Vmx = 0.5 * (Vx[:-1] + Vx[1:])
    Vmz = 0.5 * (Vz[:-1] + Vz[1:])

    def drag_xz(rx, rz, ang, strain):
        c_, s_ = ca.cos(ang), ca.sin(ang)
        ut, un = c_ * rx + s_ * rz, -s_ * rx + c_ * rz
        ft, fn = terms.morison_drag(env.water_density, ca.DM(seg["d"]), ca.DM(seg["cdn"]),
                                    ca.DM(seg["cdt"]), ut, un, strain)
        return ds * (ft * c_ - fn * s_), ds * (ft * s_ + fn * c_)

    fx, fz = drag_xz(U[0] - Vmx, U[1] - Vmz, phi_s + st.phi_dyn, eps_s + st.e_dyn)
    fx0, fz0 = drag_xz(P["current_s"][0], P["current_s"][1], phi_s, eps_s)
    return ca.mtimes(lump, fx - fx0), ca.mtimes(lump, fz - fz0)


def _rate_order(N: int, dyn_nodes: list) -> list:
    """Where each state entry's rate sits in [e; phi; u; v] (interleaved like the state)."""
    n_d = len(dyn_nodes)
    where = {i: k for k, i in enumerate(dyn_nodes)}
    order = []
    if 0 in where:
        order += [2 * N, 2 * N + n_d]
    for j in range(N):
        order += [j, N + j]
        if j + 1 in where:
            order += [2 * N + where[j + 1], 2 * N + n_d + where[j + 1]]
    return order


def _end_inertia(i: int, st: _State, t, theta, m_t: np.ndarray, m_n: np.ndarray):
    """The d'Alembert force (2, 1), N, of end node ``i``'s lumped mass when it moves (added
    mass normal to the line); zero for a free end."""
    if i in st.u:
        return ca.SX.zeros(2, 1)
    acc = ca.jacobian(st.V[i], t)
    ct, st_ = ca.cos(theta[i]), ca.sin(theta[i])
    a_t, a_n = ct * acc[0] + st_ * acc[1], -st_ * acc[0] + ct * acc[1]
    return ca.vertcat(m_t[i] * a_t * ct - m_n[i] * a_n * st_, m_t[i] * a_t * st_ + m_n[i] * a_n * ct)


def _positions(scene: Scene, N: int, P: dict, ds, st: _State):
    """The node positions (the paper's S3), x and z (lists of N+1), m, from the total angle
    and strain, chained from a held end's place (static, plus its prescribed displacement);
    from end B when end A is free."""
    disp = st.disp
    ang, stretch = P["phi_s"] + st.phi_dyn, ds * (1.0 + P["eps_s"] + st.e_dyn)
    step_x, step_z = stretch * ca.cos(ang), stretch * ca.sin(ang)
    if scene.end_a.condition is not EndCondition.FREE:
        px, pz = [P["pos_a_s"][0] + disp[0][0]], [P["pos_a_s"][1] + disp[0][1]]
        for j in range(N):
            px.append(px[-1] + step_x[j])
            pz.append(pz[-1] + step_z[j])
    else:
        px, pz = [P["pos_b_s"][0] + disp[1][0]], [P["pos_b_s"][1] + disp[1][1]]
        for j in range(N - 1, -1, -1):
            px.append(px[-1] - step_x[j])
            pz.append(pz[-1] - step_z[j])
        px, pz = px[::-1], pz[::-1]
    return px, pz


def _y_scale(scene: Scene, static, kinds: np.ndarray, period) -> np.ndarray:
    """Typical magnitude of each state entry (n_y,): a velocity scale (m/s) for u and v, the
    static strain's for e, 0.01 rad for phi."""
    env, a, b = scene.environment, scene.end_a, scene.end_b
    amp = max([np.max(np.abs(e.motion.amplitude)) for e in (a, b) if e.motion] + [0.0])
    v_scale = max(amp * (2 * math.pi / period if period else 0.0), float(np.hypot(*env.current)), 0.1)
    e_scale = max(float(np.max(np.abs(static.strain))), 1e-6)
    return np.select([np.isin(kinds, ["u", "v"]), kinds == "e"], [v_scale, e_scale], 0.01)


def _velocity_map(N: int, n_y: int, kinds: np.ndarray, dyn_nodes: list,
                  theta_s: np.ndarray) -> np.ndarray:
    """The map from the state to Cartesian node velocities (x, z) at rest, for mode shapes:
    dense, (2 (N+1), n_y), so built when first asked for (by modal analysis)."""
    vmap = np.zeros((2 * (N + 1), n_y))
    iu, iv = np.flatnonzero(kinds == "u"), np.flatnonzero(kinds == "v")
    rows = 2 * np.asarray(dyn_nodes, dtype=int)
    cth, sth = np.cos(theta_s[dyn_nodes]), np.sin(theta_s[dyn_nodes])
    vmap[rows, iu], vmap[rows, iv] = cth, -sth
    vmap[rows + 1, iu], vmap[rows + 1, iv] = sth, cth
    return vmap


class _LazyInfo(Mapping):
    """A read-only mapping whose callable values are computed on first access."""

    def __init__(self, data: dict, lazy=("velocity_map",)):
        self._data, self._lazy = dict(data), set(lazy)

    def __getitem__(self, key):
        if key in self._lazy:
            self._data[key] = self._data[key]()
            self._lazy.discard(key)
        return self._data[key]

    def __contains__(self, key):
        return key in self._data

    def __iter__(self):
        return iter(self._data)

    def __len__(self):
        return len(self._data)


def reconstruct_positions(model: DynamicModel, e: np.ndarray, phi: np.ndarray) -> np.ndarray:
    """Node positions (n_times, N+1, 2), m, from dynamic strain and angle (n_times, N):
    ``r_{j+1} = r_j + ds (1 + eps_s + e) (cos, sin)(phi_s + phi)`` from end A's static place."""
    st = model.info["static"]
    ds = model.info["segments"]["ds"]
    e, phi = np.atleast_2d(e), np.atleast_2d(phi)
    ang = st.angle + phi
    step = (ds * (1.0 + st.strain + e))[..., None] * np.stack([np.cos(ang), np.sin(ang)], axis=-1)
    start = np.broadcast_to(st.positions[0], (e.shape[0], 1, 2))
    return np.concatenate([start, start + np.cumsum(step, axis=1)], axis=1)
