"""The planar cable's dynamics, linearised about its static state, as a Mechanism.

A faithful re-expression of :func:`~symcable.models.planar.dynamics.build_planar_dynamics`
(read its docstring for the physics): the same CasADi expressions, split into the
Mechanism's pieces, so the equations are identical, not re-derived.

Layout
------
* ``q`` (2 N,): per segment j, ``(e_j, phi_j)``, the dynamic strain (1) and angle (rad),
  increments on the static ``eps_j``, ``phi_j``, in segment order;
* ``v`` (2 n_free,): per free node i (interior nodes, a free end), ``(u_i, v_i)``, its
  velocity in the static node frame, tangential and normal (m/s), in node order;
* ``z``: none (n_z = 0);
* kinematics ``q' = G v + w(q, t; p)``: ``de_j/dt``, ``dphi_j/dt`` linear in the node
  velocities, plus the prescribed end velocity (``w`` depends on ``t`` and the motion blocks)
  and, with both ends held, the closure stabilisation of the last segment
  (``-beta c(q, t)``, as the DynamicModel has it: see below);
* mass ``M`` = diag(m_t,i, m_n,i) per free node, kg: the lumped mass, plus the normal added
  mass in the normal direction, so ``M v' = f`` is the DynamicModel's momentum rows times
  their masses; ``f`` is the numerator of those rows, taken from the same expression graph
  (``m_t du/dt = t . R`` with ``R`` the internal-force and drag increments), so it is the
  same expression, not the rate times the mass.

The DynamicModel's state ``y`` interleaves the same symbols (``[u_0, v_0], e_0, phi_0, u_1,
v_1, ...``); :func:`state_permutation` gives the indices of ``(q, v)`` in ``y``.

The closure invariant
---------------------
With both ends held, the kinematics conserve the end-to-end closure
``c = sum ds (e t + (1 + eps) phi n) - (d_B - d_A)``; the DynamicModel stabilises it with a
Baumgarte-type term ``dc/dt = -beta c`` on the last segment (block ``beta``), and so does
this Mechanism, so its ODE is the DynamicModel's. The next step is to make ``c = 0`` an
explicit position-level constraint (two rows of ``g``, multipliers ``z`` = the force that
closes the line) and drop ``beta``.

Parameters: the DynamicModel's blocks (``phi_s``, ``eps_s``, ``amp_a``, ``phase_a``, ``amp_b``,
``phase_b``, ``omega``, ``current``, ``current_s``, ``force_a_s``, ``force_b_s``, ``ramp``,
``beta``, ``pos_a_s``, ``pos_b_s``) with its ``p_value`` (a run from rest, with the start-up
ramp); the periodic steady state is at ``ramp = 0`` (``params.with_values(ramp=0)``).
Outputs: the DynamicModel's, with units.
"""
from __future__ import annotations

import weakref

import casadi as ca
import numpy as np

from ...errors import SymcableError
from ...scene import Scene
from .dynamic import DynamicModel
from ...mechanism.mechanism import Layout, Mechanism, Output, ParamBlocks, PartLayout, Scales, Start
from .dynamics import build_planar_dynamics

__all__ = ["MECHANISMS", "OUTPUT_UNITS", "dynamics_mechanism", "mechanism_of",
           "planar_dynamics_mechanism", "state_permutation"]

#: units of the DynamicModel's outputs
OUTPUT_UNITS = {"fairlead_tension": "N", "anchor_tension": "N", "fairlead_force": "N",
                "anchor_force": "N", "tension": "N", "axial_force": "N", "strain": "1",
                "angle": "rad", "positions": "m"}


def state_permutation(model: DynamicModel) -> tuple[np.ndarray, np.ndarray]:
    """``(iq, iv)``: the indices in the DynamicModel's ``y`` of the Mechanism's ``q`` and
    ``v`` (so ``y[iq] = q``, ``y[iv] = v``)."""
    kinds = np.asarray(model.info["kinds"])
    return np.flatnonzero(np.isin(kinds, ["e", "phi"])), np.flatnonzero(np.isin(kinds, ["u", "v"]))


def _momentum_numerator(row, mass: float):
    """The numerator ``n`` of a momentum row ``n / mass`` (the same SX node), or
    ``mass * row`` when the row is not written as that division."""
    if row.is_op(ca.OP_DIV) and row.dep(1).is_constant() and float(row.dep(1)) == mass:
        return row.dep(0)
    return mass * row


def planar_dynamics_mechanism(scene: Scene, static) -> Mechanism:
    """The linearised planar dynamics of ``scene`` about its static solution ``static``
    (a :class:`~symcable.results.static.StaticSolution` of the same scene), as a Mechanism (see the
    module docstring)."""
    return dynamics_mechanism(build_planar_dynamics(scene, static))


#: DynamicModel -> its Mechanism, built once by :func:`mechanism_of`; a weak mapping, so the
#: entry goes with the model (the Mechanism holds the model's symbols, not the model)
MECHANISMS: "weakref.WeakKeyDictionary[DynamicModel, Mechanism]" = weakref.WeakKeyDictionary()


def mechanism_of(model: DynamicModel) -> Mechanism:
    """:func:`dynamics_mechanism` of ``model``, built once per DynamicModel and kept in
    :data:`MECHANISMS`, so that the Functions derived from it (and their compiled code) are
    derived once."""
    mech = MECHANISMS.get(model)
    if mech is None:
        mech = MECHANISMS[model] = dynamics_mechanism(model)
    return mech


def dynamics_mechanism(model: DynamicModel) -> Mechanism:
    """The planar DynamicModel ``model`` re-expressed as a Mechanism, on its own symbols."""
    if model.name != "planar":
        raise SymcableError(f"dynamics_mechanism: model {model.name!r} is not the planar "
                            "linearised dynamics")
    info = model.info
    iq, iv = state_permutation(model)
    y, rhs = model.y, model.rhs
    q = ca.vertcat(*[y[int(k)] for k in iq])
    v = ca.vertcat(*[y[int(k)] for k in iv])
    z = ca.SX.sym("z", 0)
    nodes = list(info["dynamic_nodes"])
    m_t, m_n = np.asarray(info["mass_tangential"]), np.asarray(info["mass_normal"])
    masses = np.ravel(np.column_stack([m_t[nodes], m_n[nodes]])) if nodes else np.zeros(0)
    force = ca.vertcat(*[_momentum_numerator(rhs[int(k)], float(mk))
                         for k, mk in zip(iv, masses)]) if iv.size else ca.SX(0, 1)
    kinematics = ca.vertcat(*[rhs[int(k)] for k in iq])
    sizes = tuple(model.p_slices[n].stop - model.p_slices[n].start for n in model.p_names)
    params = ParamBlocks(tuple(model.p_names), sizes, model.p_value)
    outputs = {k: Output(e, OUTPUT_UNITS.get(k, ""), "line") for k, e in model.outputs.items()}

    static = info["static"]
    s_nodes = np.asarray(info["s_nodes"], dtype=float)
    node_v = np.full((s_nodes.size, 2), -1, dtype=int)
    for k, i in enumerate(nodes):
        node_v[i] = (2 * k, 2 * k + 1)
    # q holds segment increments, not node coordinates: no node has coordinates in q
    layout = Layout(2, {"line": PartLayout("line", s_nodes,
                                           np.full((s_nodes.size, 2), -1, dtype=int), node_v)})
    force_scale = float(np.hypot(*np.asarray(static.fairlead_force, dtype=float)))
    scales = Scales(q=np.asarray(model.y_scale, float)[iq], v=np.asarray(model.y_scale, float)[iv],
                    z=np.zeros(0), force=force_scale,
                    mass=float(np.median(masses)) if masses.size else 1.0)
    # the static state is the rest state q = 0 with the motion off
    static_params = {"amp_a": 0.0, "amp_b": 0.0}
    p_rest = params.with_values(**static_params)

    def starts():
        yield Start(np.zeros(q.numel()), np.zeros(0), p_rest, "static state")

    mass = ca.SX(ca.DM(ca.Sparsity.diag(masses.size), masses))
    return Mechanism(name="planar_dynamics", q=q, v=v, z=z, t=model.t, p=model.p,
                     params=params, mass=mass, force=force, constraint=ca.SX.zeros(0, 1),
                     scales=scales, starts=starts, outputs=outputs, layout=layout,
                     kinematics=kinematics, terms=tuple(info["terms"]),
                     static_params=static_params)
