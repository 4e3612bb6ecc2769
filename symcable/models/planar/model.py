"""Planar cable with extension and bending, as CasADi expressions: the statics of S. Boral,
J. Hickey and B. Basu, "Modeling and Simulation of Periodic Cable Dynamics with Bending
Stiffness Using Time-Domain and Multi-Harmonic Balance Methods" (Algorithm S1 of its
supplementary code overview: the line in tangent angle and axial strain).

Discretisation
--------------
The unstretched line ``0 <= s <= L`` is cut into ``N`` segments (section by section, each
section uniformly) with nodes ``i = 0..N`` at arc lengths ``s_i``; segment ``j`` joins nodes
``j`` and ``j + 1`` and has unstretched length ``ds_j``.

Unknowns ``w``, interleaved node/segment so the Jacobian is banded:

* on every node whose position is not prescribed (interior nodes, and a ``free`` end):
  the position ``(x_i, z_i)``, m;
* on every segment: the tangent angle ``phi_j`` (rad, from +x towards +z) and the axial
  strain ``eps_j``, both taken at the segment midpoint.

Derived quantities:

* axial force ``T_j = EA_j eps_j`` (N) and tangent/normal ``t_j = (cos, sin) phi_j``,
  ``n_j = (-sin, cos) phi_j`` on segments;
* curvature and moment on nodes: ``kappa_i = (phi_i - phi_{i-1}) / h_i`` with
  ``h_i = (ds_{i-1} + ds_i) / 2``, ``M_i = EI_i kappa_i`` (``EI_i`` the mean of the two
  segments). Pinned and free ends carry no moment; at a clamped end the tangent angle
  ``phi_e`` is given and ``kappa`` there is the derivative at the end of the quadratic
  through ``phi_e`` and the first two segment angles (second-order one-sided);
* shear on segments from the exact moment balance of a segment,
  ``Q_j = -(M_{j+1} - M_j) / (ds_j (1 + eps_j))``;
* internal force on segments ``F_j = T_j t_j + Q_j n_j`` (the force the part beyond the
  segment's midpoint exerts on the part before it).

Residuals (every row a force, N):

* compatibility per segment, scaled by ``EA_j / ds_j``:
  ``r_{j+1} - r_j - ds_j (1 + eps_j) t_j = 0``  (the paper's geometric closure, midpoint rule);
* equilibrium per unknown node: ``F_i - F_{i-1} + P_i = 0`` with ``F_{-1} = F_N = 0`` and
  ``P_i`` the external load lumped on the node: half of each adjacent segment's weight
  and drag, the seabed contact over the node's tributary length, and at a free end its
  applied force. A held (pinned or clamped) end node cannot press into the seabed, so its
  contact is evaluated at its neighbour's penetration: an anchor lying on the seabed then
  carries the horizontal pull only, as on a rigid seabed, not its half segment's weight. These are the paper's R1 (tangential) and R2 (normal) balances in
  Cartesian components; with ``Q = -EI phi''`` R2's ``-EI phi'''`` appears exactly.

Prescribed positions and angles of the ends enter as parameters, not unknowns, so the
system is square: ``4N - 2`` unknowns for two fixed ends, ``+2`` per free end.

End values are recovered from the equilibrium of the end node: the force the line exerts
on end A is ``F_0 + P_0`` and on end B ``P_N - F_{N-1}`` (``P`` without an applied end
force), second-order accurate; fairlead/anchor tension are their magnitudes.

Parameters ``p``: ``load`` (factor on weight, drag and applied forces), ``bending`` (factor
on EI), the fixed end positions ``xa, za, xb, zb`` (m), clamped angles ``angle_a, angle_b``
(rad), the current ``ux, uz`` (m/s) and ``slack`` (1 for the scene; 0 widens the corner of
the cables' tension-only law SLACK_CONTINUATION times). ``load``, ``bending`` and ``slack``
drive continuation.
"""
from __future__ import annotations

import math
from types import MappingProxyType

import casadi as ca
import numpy as np

from ...scene import EndCondition, Scene
from ..common import terms
from .base import Model
from .model_starts import _initial_guess, _Layout
from ..common.segments import (SLACK_CONTINUATION, CABLE_COMPRESSION, FOLD_PUSH, segment_table,
                              force_scale_of, slack_law, nodal_weights, grounded_length)

P_NAMES = ("load", "bending", "xa", "za", "xb", "zb", "angle_a", "angle_b", "ux", "uz", "slack")


def _lumping_matrix(n_seg: int) -> ca.DM:
    """(N+1, N) matrix giving each node half of each adjacent segment's quantity."""
    idx = np.arange(n_seg)
    rows = np.stack([idx, idx + 1], axis=1).ravel().tolist()  # column-major: (j, j), (j+1, j)
    cols = np.repeat(idx, 2).tolist()
    return ca.DM(ca.Sparsity.triplet(n_seg + 1, n_seg, rows, cols), 0.5)  # sparse: O(N), not O(N^2)


def _end_slope_weights(h0: float, h1: float | None) -> tuple[float, float, float]:
    """Weights (on phi_end, phi_first, phi_second) of d(phi)/d(sigma) at the end, sigma the
    distance from the end, for angles at sigma = 0, h0/2 and h0 + h1/2 (quadratic fit);
    a linear fit when there is only one segment (h1 None)."""
    s1 = 0.5 * h0
    if h1 is None:
        return -1.0 / s1, 1.0 / s1, 0.0
    s2 = h0 + 0.5 * h1
    return -(1.0 / s1 + 1.0 / s2), s2 / (s1 * (s2 - s1)), -s1 / (s2 * (s2 - s1))


def internal_forces(phi, eps, seg: dict, cond_a: EndCondition, cond_b: EndCondition,
                    mu=1.0, ang_a=0.0, ang_b=0.0, slack: dict | None = None):
    """Internal forces of the planar line from segment angles and strains (see the module
    docstring): axial force ``T`` (N,), shear ``Q`` (N,), nodal moments ``M`` (N+1,), the
    Cartesian internal force ``Fx, Fz`` (N,) and whether a bending term was built.

    ``mu`` scales EI (continuation); ``ang_a``, ``ang_b`` are clamped end angles, rad;
    ``slack`` (:func:`slack_law`): the tension-only law on the segments without bending
    (default: linear EA e everywhere). Works on any CasADi expressions, so the dynamics can
    linearise exactly this."""
    N = len(seg["ds"])
    ds, EA = ca.DM(seg["ds"]), ca.DM(seg["EA"])
    c, s = ca.cos(phi), ca.sin(phi)
    T = terms.axial_force(EA, eps)
    if slack is not None and np.any(np.isfinite(slack["delta"])):
        cab = np.isfinite(slack["delta"])
        law = terms.cable_axial_force(EA, eps, slack.get("width_factor", 1.0)
                                      * ca.DM(np.where(cab, slack["delta"], 1.0)),
                                      ca.DM(np.where(cab, slack["EA_slack"], 0.0)),
                                      slack["F_wall"], slack["w_wall"])
        if np.all(cab):
            T = law
        else:  # per segment the law or the linear T, picked in one indexing
            T = ca.vertcat(law, T)[[j if cab[j] else N + j for j in range(N)]]
    M = ca.SX.zeros(N + 1) if isinstance(phi, ca.SX) else ca.MX.zeros(N + 1)
    bending = bool(np.any(seg["EI"] > 0.0))
    if bending:
        if N > 1:
            h_int = 0.5 * (seg["ds"][:-1] + seg["ds"][1:])
            EI_int = 0.5 * (seg["EI"][:-1] + seg["EI"][1:])
            kappa_int = (phi[1:] - phi[:-1]) / ca.DM(h_int)
            M[1:N] = mu * terms.bending_moment(ca.DM(EI_int), kappa_int)
        second = (lambda k: phi[k]) if N > 1 else (lambda k: 0.0)
        if cond_a is EndCondition.CLAMPED:
            wa = _end_slope_weights(seg["ds"][0], seg["ds"][1] if N > 1 else None)
            kappa_a = wa[0] * ang_a + wa[1] * phi[0] + wa[2] * second(1)
            M[0] = mu * terms.bending_moment(seg["EI"][0], kappa_a)
        if cond_b is EndCondition.CLAMPED:
            wb = _end_slope_weights(seg["ds"][-1], seg["ds"][-2] if N > 1 else None)
            kappa_b = -(wb[0] * ang_b + wb[1] * phi[N - 1] + wb[2] * second(N - 2))
            M[N] = mu * terms.bending_moment(seg["EI"][-1], kappa_b)
        Q = terms.shear_from_moments(M[:-1], M[1:], ds, eps)
    else:
        Q = 0.0 * eps
    return T, Q, M, T * c - Q * s, T * s + Q * c, bending


def build_planar(scene: Scene) -> Model:
    """Discretise a planar scene and write its static equations (see module docstring)."""
    seg = segment_table(scene)
    N = len(seg["ds"])
    env = scene.environment
    a, b = scene.end_a, scene.end_b
    free_a, free_b = a.condition is EndCondition.FREE, b.condition is EndCondition.FREE

    p = ca.SX.sym("p", len(P_NAMES))
    lam, mu, xa, za, xb, zb, ang_a, ang_b, ux, uz, sigma = (p[k] for k in range(len(P_NAMES)))
    X, Z, phi_l, eps_l, w_list, kinds, unknown_nodes = _unknowns(N, free_a, free_b, xa, za, xb, zb)

    Xv, Zv = ca.vertcat(*X), ca.vertcat(*Z)
    phi, eps = ca.vertcat(*phi_l), ca.vertcat(*eps_l)
    ds, EA = (ca.DM(seg[k]) for k in ("ds", "EA"))
    (c, s), _ = terms.tangent(phi)
    stretch = 1.0 + eps
    term_names = ["elastic", "weight"]

    # --- compatibility (geometric closure), in N
    comp_x = EA / ds * (Xv[1:] - Xv[:-1] - ds * stretch * c)
    comp_z = EA / ds * (Zv[1:] - Zv[:-1] - ds * stretch * s)

    # --- internal forces: axial, bending moment on nodes, shear on segments
    force_scale = force_scale_of(scene, seg)
    law = slack_law(seg, force_scale)
    # continuation parameter of the tension-only law's corner: its width is
    # SLACK_CONTINUATION times wider at sigma = 0 than at the scene's sigma = 1
    law["width_factor"] = ca.exp(math.log(SLACK_CONTINUATION) * (1.0 - sigma))
    T, Q, M, Fx, Fz, bending = internal_forces(phi, eps, seg, a.condition, b.condition, mu,
                                               ang_a, ang_b, law)
    if bending:
        term_names.append("bending")

    # --- external loads lumped on nodes (N per node)
    Px, Pz, contact = _line_loads(scene, seg, lam, ux, uz, c, s, eps, Zv, term_names)
    line_Px, line_Pz = Px, Pz
    applied = np.zeros((N + 1, 2))
    for end, node in ((a, 0), (b, N)):
        if end.condition is EndCondition.FREE and end.force is not None:
            applied[node] = end.force
    if np.any(applied):
        term_names.append("end force")
        Px = Px + lam * ca.DM(applied[:, 0])
        Pz = Pz + lam * ca.DM(applied[:, 1])

    # --- node equilibrium, in N
    zero = ca.SX.zeros(1)
    Fx_pad, Fz_pad = ca.vertcat(zero, Fx, zero), ca.vertcat(zero, Fz, zero)
    eq_x = Fx_pad[1:] - Fx_pad[:-1] + Px
    eq_z = Fz_pad[1:] - Fz_pad[:-1] + Pz

    rows, row_kind = _residual_rows(N, free_a, free_b)
    residual = ca.vertcat(comp_x, comp_z, eq_x, eq_z)[rows]
    w = ca.vertcat(*w_list)

    # --- outputs
    end_force_a = ca.horzcat(Fx[0] + line_Px[0], Fz[0] + line_Pz[0])
    end_force_b = ca.horzcat(line_Px[N] - Fx[N - 1], line_Pz[N] - Fz[N - 1])
    outputs = _outputs(Xv, Zv, phi, eps, T, Q, M, Fx, Fz, end_force_a, end_force_b, contact)
    p_target = np.array([
        1.0, 1.0,
        *(a.position if a.position is not None else (0.0, 0.0)),
        *(b.position if b.position is not None else (0.0, 0.0)),
        a.angle or 0.0, b.angle or 0.0,
        *tuple(env.current), 1.0,
    ], dtype=float)

    kinds_arr = np.array(kinds)
    w_scale, merit_weights, residual_floor = _scales(scene, seg, kinds_arr, row_kind, force_scale)
    bounds = _bounds(scene, seg, eps, T, contact, line_Px, line_Pz, Px, Pz, end_force_a,
                     end_force_b, force_scale, residual_floor)

    info = MappingProxyType({"n_segments": N, "s_nodes": seg["s"], "segments": seg,
                             "unknown_kinds": tuple(kinds), "bending": bending})

    layout = _Layout(kinds_arr, np.array(unknown_nodes, dtype=int))

    def initial_guess():
        return _initial_guess(scene, seg, layout, p_target, bending, P_NAMES)

    nodal = nodal_weights(seg)

    def postprocess(out: dict) -> dict:
        return _postprocess(scene, seg, nodal, out)

    return Model(name="planar", scene=scene, terms=tuple(term_names), w=w, p=p,
                 p_names=P_NAMES, p_target=p_target, residual=residual, outputs=outputs,
                 w_scale=w_scale, merit_weights=merit_weights, force_scale=force_scale,
                 residual_floor=residual_floor,
                 initial_guess=initial_guess,
                 postprocess=postprocess, info=info, bounds=bounds)


def _unknowns(N: int, free_a: bool, free_b: bool, xa, za, xb, zb):
    """The unknowns' symbols, interleaved [node 0], seg 0, node 1, seg 1, ..., seg N-1,
    [node N]: each node's x and z (lists of N+1: a symbol, or a held end's parameter, m),
    the segment angles and strains (lists of N), all unknowns in order, each one's kind
    (``"x"``, ``"z"``, ``"phi"``, ``"eps"``) and the nodes with unknown positions."""
    X: list = [None] * (N + 1)
    Z: list = [None] * (N + 1)
    phi_l, eps_l, w_list, kinds = [], [], [], []
    unknown_nodes = []

    def add_node(i):
        X[i], Z[i] = ca.SX.sym(f"x_{i}"), ca.SX.sym(f"z_{i}")
        w_list.extend([X[i], Z[i]])
        kinds.extend(["x", "z"])
        unknown_nodes.append(i)

    if free_a:
        add_node(0)
    else:
        X[0], Z[0] = xa, za
    for j in range(N):
        ph, ep = ca.SX.sym(f"phi_{j}"), ca.SX.sym(f"eps_{j}")
        phi_l.append(ph)
        eps_l.append(ep)
        w_list.extend([ph, ep])
        kinds.extend(["phi", "eps"])
        if j + 1 < N or free_b:
            add_node(j + 1)
    X[N], Z[N] = (X[N], Z[N]) if free_b else (xb, zb)
    return X, Z, phi_l, eps_l, w_list, kinds, unknown_nodes


def _line_loads(scene: Scene, seg: dict, lam, ux, uz, c, s, eps, Zv, term_names: list):
    """The line's own loads lumped on the nodes, x and z (N+1, 1), N: weight, drag of the
    current and seabed contact; and the contact alone (N+1, 1), N. Appends the terms it
    builds to ``term_names``."""
    N = len(seg["ds"])
    env, sb = scene.environment, scene.seabed
    a, b = scene.end_a, scene.end_b
    free_a, free_b = a.condition is EndCondition.FREE, b.condition is EndCondition.FREE
    ds, wt = ca.DM(seg["ds"]), ca.DM(seg["w"])
    lump = _lumping_matrix(N)
    seg_fx = ca.SX.zeros(N)
    seg_fz = -lam * wt * ds
    current = tuple(env.current)
    if not env.in_air and any(u != 0.0 for u in current):
        term_names.append("drag")
        u_t = ux * c + uz * s
        u_n = -ux * s + uz * c
        f_t, f_n = terms.morison_drag(env.water_density, ca.DM(seg["d"]), ca.DM(seg["cdn"]),
                                      ca.DM(seg["cdt"]), u_t, u_n, eps)
        seg_fx += lam * ds * (f_t * c - f_n * s)
        seg_fz += lam * ds * (f_t * s + f_n * c)
    Px = ca.mtimes(lump, seg_fx)
    Pz = ca.mtimes(lump, seg_fz)
    contact = ca.SX.zeros(N + 1)
    if sb is not None:
        term_names.append("seabed")
        delta = terms.contact_smoothing(float(np.max(seg["w"])), sb.stiffness, float(np.min(seg["d"])))
        trib_width = np.asarray(ca.mtimes(lump, ca.DM(seg["d"] * seg["ds"]))).ravel()
        # a held end on the seabed cannot press into it; the half segment beside it rests
        # where its neighbour does, so it takes the neighbour's penetration (a held end
        # above the seabed carries its half segment itself, even when its segment reaches
        # down to the bed)
        sink = max(abs(float(np.max(seg["w"]))) / (sb.stiffness * float(np.min(seg["d"]))),
                   1e-6 * scene.length)
        probe = np.arange(N + 1)
        if not free_a and a.position[1] <= -env.depth + sink:
            probe[0] = 1
        if not free_b and b.position[1] <= -env.depth + sink:
            probe[N] = N - 1
        # whole-vector operations: one CasADi call each, not one per node
        contact = ca.DM(trib_width * sb.stiffness) * terms.smooth_ramp(
            -env.depth - Zv[probe.tolist()], delta)
        Pz = Pz + contact
    return Px, Pz, contact


def _residual_rows(N: int, free_a: bool, free_b: bool) -> tuple[list, list]:
    """The residual's rows, interleaved like the unknowns, as indices into the stacked
    [comp_x; comp_z; eq_x; eq_z] (one CasADi indexing, not one call per row); and each row's
    segment (compatibility rows) or -1 (equilibrium rows)."""
    rows, row_kind = [], []
    if free_a:
        rows += [2 * N, 3 * N + 1]
        row_kind += [-1, -1]
    for j in range(N):
        rows += [j, N + j]
        row_kind += [j, j]
        if j + 1 < N or free_b:
            rows += [2 * N + j + 1, 3 * N + 1 + j + 1]
            row_kind += [-1, -1]
    return rows, row_kind


def _outputs(Xv, Zv, phi, eps, T, Q, M, Fx, Fz, end_force_a, end_force_b, contact) -> dict:
    """The named outputs of ``(w, p)``: node positions (N+1, 2), m; segment angle (rad),
    strain, axial force, shear (N, 1); nodal moments (N+1, 1), N m; segment internal force
    (N, 2), N; node tension (N+1, 1), N; the end forces (1, 2), N; the contact (N+1, 1), N."""
    N = phi.numel()
    Fmag = ca.sqrt(Fx * Fx + Fz * Fz)
    # interior nodes: the mean of the two segments' (none with one segment: a 1 x 1 SX
    # sliced [:-1] is 1 x 0, a row, which vertcat would count wrongly)
    inner = 0.5 * (Fmag[:-1] + Fmag[1:]) if N > 1 else ca.SX(0, 1)
    tension_nodes = ca.vertcat(ca.norm_2(end_force_a), inner, ca.norm_2(end_force_b))
    return {
        "positions": ca.horzcat(Xv, Zv),
        "angle": phi,
        "strain": eps,
        "axial_force": T,
        "shear": Q,
        "moment": M,
        "force": ca.horzcat(Fx, Fz),
        "tension": tension_nodes,
        "end_force_a": end_force_a,
        "end_force_b": end_force_b,
        "contact_force": contact,
    }


def _scales(scene: Scene, seg: dict, kinds_arr: np.ndarray, row_kind: list,
            force_scale: float) -> tuple[np.ndarray, np.ndarray, float]:
    """The unknowns' scales (n_w,: m, rad, strain), the residual rows' merit weights (n_w,)
    and the residual's round-off floor (N)."""
    a, b = scene.end_a, scene.end_b
    L = scene.length
    max_strain = max(sec.line_type.max_strain for sec in scene.sections)
    w_scale = np.select([kinds_arr == "phi", kinds_arr == "eps"], [0.5, 0.5 * max_strain], 0.1 * L)

    # merit weights: a compatibility row measures a length mismatch times EA/ds; weigh it
    # as that mismatch relative to the line length times the force scale, so a rotation
    # whose second-order stretch error the next Newton step removes is not rejected
    row_kind = np.array(row_kind)
    geo = row_kind >= 0
    merit_weights = np.ones(len(row_kind))
    merit_weights[geo] = (force_scale / L) / (seg["EA"][row_kind[geo]] / seg["ds"][row_kind[geo]])

    # round-off floor of the residual: compatibility rows amplify a coordinate's last bit
    # by EA/ds, moment rows an angle's by EI/ds^2
    coord = L + max(abs(v) for e in (a, b) if e.position is not None for v in e.position)
    residual_floor = 100.0 * np.finfo(float).eps * float(
        np.max(seg["EA"] / seg["ds"]) * coord + np.max(seg["EI"] / seg["ds"] ** 2) * 2.0 * math.pi)
    return w_scale, merit_weights, residual_floor


def _bounds(scene, seg, eps, T, contact, line_Px, line_Pz, Px, Pz, end_force_a, end_force_b,
            force_scale, residual_floor) -> dict:
    """The planar line's admissibility bounds (:class:`~symcable.mechanism.mechanism.Bound`):

    - ``strain`` > -1: every segment has a positive length;
    - ``cable_axial_force`` >= -max(CABLE_COMPRESSION x force scale, FOLD_PUSH x the
      segment's weight) on segments without bending (EI = 0): a cable does not push;
    - ``seabed_reaction``, the sum of the contact forces, at most what can press the line
      onto the bed: its submerged weight, the applied end forces and the largest drag of the
      current (1 % over): a line pushed through the seabed by a compressed strut reacts far
      more;
    - ``force_balance``: the loads on the line (weight, drag, contact, applied forces) and
      the forces of the held ends sum to zero (x and z, N), to 1e-6 of the force scale plus
      the round-off floor per node: a check of the end-force outputs against the
      equations."""
    from ...mechanism.mechanism import Bound

    N = len(seg["ds"])
    out = {"strain": Bound(eps, lower=-1.0 + 1e-9, unit="1", scale=1.0,
                           what="segments of positive length")}
    cable = np.flatnonzero(seg["EI"] <= 0.0)
    if cable.size:
        push = np.maximum(CABLE_COMPRESSION * force_scale,
                          FOLD_PUSH * np.abs(seg["w"][cable]) * seg["ds"][cable])
        out["cable_axial_force"] = Bound(T[cable.tolist()], lower=-push, unit="N",
                                         scale=force_scale,
                                         what="a cable (EI = 0) carries no compression")
    rod = np.flatnonzero(seg["EI"] > 0.0)
    if N == 1 and rod.size and all(e.is_fixed for e in (scene.end_a, scene.end_b)):
        # one segment held at both ends has no node that could move: its stability cannot
        # be judged, and past Euler's load (pinned, the lowest) the straight bar it returns
        # is not the rod's shape
        euler = math.pi ** 2 * float(seg["EI"][0]) / float(seg["ds"][0]) ** 2
        out["one_segment_buckling"] = Bound(T, lower=-euler, unit="N", scale=force_scale,
                                            what="a one-segment rod compressed past Euler's "
                                                 "load pi^2 EI / L^2 cannot bend: give it "
                                                 "more segments")
    env = scene.environment
    if scene.seabed is not None:
        press = float(np.sum(np.maximum(seg["w"], 0.0) * seg["ds"]))
        press += sum(math.hypot(*e.force) for e in (scene.end_a, scene.end_b)
                     if e.force is not None)
        if not env.in_air:
            u2 = sum(u * u for u in env.current)
            press += float(np.sum(0.5 * env.water_density * seg["cdn"] * seg["d"] * seg["ds"])) * u2
        out["seabed_reaction"] = Bound(ca.sum1(contact), upper=1.01 * press + 1e-6 * force_scale,
                                       unit="N", scale=force_scale,
                                       what="the seabed carries at most what presses the line "
                                            "onto it")
    bal_x, bal_z = ca.sum1(Px), ca.sum1(Pz)
    for end, f in ((scene.end_a, end_force_a), (scene.end_b, end_force_b)):
        if end.condition is not EndCondition.FREE:
            bal_x, bal_z = bal_x - f[0], bal_z - f[1]
    slack = 1e-6 * force_scale + (N + 1) * residual_floor
    out["force_balance"] = Bound(ca.vertcat(bal_x, bal_z), lower=-slack, upper=slack, unit="N",
                                 scale=force_scale, what="the line's loads and end forces in "
                                                         "balance")
    return out


# --------------------------------------------------------------------------- results


def _postprocess(scene: Scene, seg: dict, nodal: tuple, out: dict) -> dict:
    """Fairlead/anchor tension, grounded length (m, unstretched) and touchdown point
    (``nodal``: :func:`nodal_weights` of ``seg``)."""
    fa = np.ravel(out["end_force_a"])
    fb = np.ravel(out["end_force_b"])
    res = {"anchor_force": fa, "fairlead_force": fb,
           "anchor_tension": float(np.hypot(fa[0], fa[1])),
           "fairlead_tension": float(np.hypot(fb[0], fb[1]))}
    contact = np.ravel(out["contact_force"]) if scene.seabed is not None else None
    grounded, s_td, touchdown = grounded_length(scene, seg, nodal, np.asarray(out["positions"]),
                                                contact, fa, fb)
    res.update(grounded_length=grounded, touchdown_arclength=s_td, touchdown=touchdown)
    return res
