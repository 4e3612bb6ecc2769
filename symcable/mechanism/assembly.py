"""Assembly of several parts into one Mechanism, as finite elements share degrees of freedom.

Each part is a Mechanism with its own symbols. Its coordinates are mapped onto the assembled
ones by a selection: ``q_part = P q + E x(t; p)`` where ``P`` picks the free entries and ``E``
places prescribed ones. Then, by virtual work,

    M = sum P^T M_part P,    f = sum P^T (f_part - M_part E x''(t)),

so forces of parts that share a node add up, and a prescribed node feeds its inertia into
the rest. Joints:

- :class:`Shared`: two nodes are one node (lines meeting at a point, a line ending on a point
  mass);
- :class:`Prescribed`: a node's coordinates are a given position plus an optional harmonic
  motion, in parameter blocks ``NAME.position``, ``NAME.amplitude``, ``NAME.phase`` (rad) and
  ``NAME.omega`` (rad/s); its outputs ``NAME.force`` (N, the force the parts exert on the
  node: f_part - M_part a_part at its rows) and ``NAME.position`` (m);
- :class:`Attached`: a node is a point of another part, a rigid body (:mod:`.body`): its
  position x(q_b) and velocity x'(q_b, v_b) = J(q_b) v_b are the body's; output
  ``NAME.position`` (m). The part's velocities are then ``v_part = T(q) v`` with T the
  selection plus J, so, by virtual work, ``M += T^T M_part T`` and ``f += T^T (f_part -
  M_part (E x'' + a_c))``, a_c = (dJ/dt) v_b the attached node's acceleration at v_b' = 0
  (CasADi's directional derivative of x' along q' = G(q) v): exact, the node's mass and its
  coupling (consistent mass) carried by the body.

Parts may have kinematics q' = G(q) v (a body's quaternion) and first-order states with
``rest`` rows (the entries of q past n_v): the assembled q is every part's first n_v
entries (joined as above; entry i of q goes with entry i of v), then every part's extra
entries in part order, their rates and rest rows the parts' own.

Parameters, outputs, admissibility bounds and layout parts are namespaced ``part.name``;
stability is judged where any part's ``stability_when`` is negative (always, when a part has
none).
"""
from __future__ import annotations

import dataclasses
import functools
from collections import OrderedDict
from dataclasses import dataclass, field
from typing import Callable, Iterable

import casadi as ca
import numpy as np

from ..errors import SymcableError
from .joints import Attached, Prescribed, Shared
from .mechanism import (Layout, Mechanism, Output, ParamBlocks, PartLayout, Scales, Start,
                        StateNames)

__all__ = ["Attached", "Prescribed", "Shared", "assemble"]


def _sym(kind, name, n):
    return kind.sym(name, n)


class _DofMap:
    """Union-find over (part, local coordinate) pairs; prescribed ones are marked."""

    def __init__(self, parts: dict[str, Mechanism]):
        self.parent: dict = {}
        for name, m in parts.items():
            for j in range(m.n_v):  # the extra entries (past n_v) are each their own
                self.parent[(name, j)] = (name, j)

    def find(self, k):
        while self.parent[k] != k:
            self.parent[k] = self.parent[self.parent[k]]
            k = self.parent[k]
        return k

    def union(self, a, b):
        ra, rb = self.find(a), self.find(b)
        if ra != rb:
            self.parent[rb] = ra


def _node_dofs(parts, ref, what) -> list:
    part, node = ref
    if part not in parts:
        raise SymcableError(f"{what} = {ref!r}: no part named {part!r} (parts: "
                            f"{', '.join(parts)})")
    lay = parts[part].layout.parts.get(part)
    if lay is None:
        raise SymcableError(f"{what} = {ref!r}: part {part!r} has no layout of its nodes")
    if not -lay.n_nodes <= node < lay.n_nodes:
        raise SymcableError(f"{what} = {ref!r}: part {part!r} has {lay.n_nodes} nodes")
    idx = lay.node_q[node]
    if np.any(idx < 0):
        raise SymcableError(f"{what} = {ref!r}: that node is prescribed inside its part")
    return [(part, int(j)) for j in idx]


def assemble(parts: Iterable[Mechanism], joints: Iterable = (), *, name: str = "assembly",
             starts: Callable[[], Iterable[Start]] | None = None,
             symbols: bool = True) -> Mechanism:
    """One Mechanism from several parts and joints (see the module docstring).

    Parameters
    ----------
    parts : iterable of Mechanism
        Each with a layout part of its own name (``mech.layout.parts[mech.name]``) listing its
        nodes; names must be unique.
    joints : iterable of Shared | Prescribed | Attached
    name : str
    starts : callable, optional
        Static starts of the whole; by default the parts' first starts, put together.
    symbols : bool
        False: the numbers of the whole alone (parameters, scales, layout, starts, bounds'
        limits) on placeholder expressions, from parts built likewise
        (:mod:`symcable.models.structure`).
    """
    parts = list(parts)
    by_name, dim, kind = _check_parts(parts)
    joints = list(joints)
    num = _number(parts, by_name, joints) if symbols else _known_number(parts, by_name, joints)
    n_v, n_q = num.n_v, num.n_q
    presc_joints = [j for j in joints if isinstance(j, Prescribed)]
    params = _param_blocks(parts, presc_joints, dim)

    n_z_total = sum(m.n_z for m in parts)
    if not symbols:  # (placeholders of the symbols' shapes)
        return _numbers_only(parts, num, params, name, kind,
                             tuple(kind(n, 1) for n in (n_q, n_v, n_z_total, 1, params.n)),
                             [m for m in parts if m.kinematics is not None], starts)
    q = _sym(kind, "q", n_q)
    v = _sym(kind, "v", n_v)
    t = _sym(kind, "t", 1)
    p = _sym(kind, "p", params.n)
    z = _sym(kind, "z", n_z_total)
    z_at, p_at, off_z, off_p = {}, {}, 0, 0
    for m in parts:
        z_at[m.name] = z[off_z:off_z + m.n_z]
        p_at[m.name] = p[off_p:off_p + m.params.n]
        off_z += m.n_z
        off_p += m.params.n

    motion = _prescribed_motion(presc_joints, params, p, t)
    kinematic = [m for m in parts if m.kinematics is not None]
    qdot, rest_rows = _kinematics(kinematic, num, kind, q, v, z_at, p_at, t)
    # a node on a body: its position, velocity and the acceleration at v' = 0
    for j in joints:
        if isinstance(j, Attached):
            qb, vb = _free_of(by_name[j.body], num, q, v)
            xd = j.velocity(qb, vb)
            motion[j.name] = (j.position(qb), xd, ca.jtimes(xd, q, qdot))

    made: dict = {}  # Functions of the parts, shared by parts of shared expressions
    M = kind(n_v, n_v)  # structurally zero: each part adds its own (sparse) block
    f = kind.zeros(n_v, 1)
    g_rows, outputs, bounds, when = [], {}, {}, []
    part_layouts = {}
    q_scale = np.zeros(n_q)
    v_scale = np.zeros(n_v)
    joint_force = {j.name: [kind(0)] * dim for j in presc_joints}
    for m in parts:
        q_loc, v_loc, a_pres, rows_free, cols_free, rows_att = _part_coords(
            m, num, motion, kind, q, v, q_scale, v_scale)
        local = (q_loc, v_loc, z_at[m.name], t, p_at[m.name])
        fn = _shared(made, ("dyn", id(m.force)), lambda: ca.Function(
            f"part_{m.fname}", [m.q, m.v, m.z, m.t, m.p], [m.mass, m.force, m.constraint]))
        Mp, fp, gp = fn(*local)
        fp_eff = fp - ca.mtimes(Mp, a_pres)  # prescribed and attached accelerations' inertia
        T = ca.DM(ca.Sparsity.triplet(m.n_v, n_v, rows_free, cols_free), 1.0)
        if rows_att:  # v_part = T(q) v: the selection plus the attached nodes' J
            S = ca.DM(ca.Sparsity.triplet(m.n_v, len(rows_att), rows_att,
                                          list(range(len(rows_att)))), 1.0)
            T = T + ca.mtimes(S, ca.jacobian(ca.vertcat(*[v_loc[i] for i in rows_att]), v))
        M = M + ca.mtimes([T.T, Mp, T])
        f = f + ca.mtimes(T.T, fp_eff)
        g_rows.append(gp)
        _add_joint_force(m, num, fp_eff, joint_force)
        outputs.update(_part_outputs(m, local, made))
        _part_bounds(m, local, bounds, when, made)
        part_layouts.update(_part_layouts(m, num))
    for j in presc_joints:
        outputs[f"{j.name}.force"] = Output(ca.vertcat(*joint_force[j.name]), "N", j.name,
                                            f"force the parts exert on {j.name}")
    for j in joints:
        if isinstance(j, (Prescribed, Attached)):
            outputs[f"{j.name}.position"] = Output(motion[j.name][0], "m", j.name,
                                                   f"position of {j.name}")
    g = ca.vertcat(*g_rows) if g_rows else kind.zeros(0, 1)
    if n_z_total == 0:
        g = kind.zeros(0, 1)

    scales = _scales(parts, q_scale, v_scale, n_z_total)
    static_params = {f"{m.name}.{k}": val for m in parts for k, val in m.static_params.items()}
    terms = tuple(dict.fromkeys(t_ for m in parts for t_ in m.terms))
    default_starts = functools.partial(_default_starts, parts, num, params, static_params)
    return Mechanism(name=name, q=q, v=v, z=z, t=t, p=p, params=params, mass=M, force=f,
                     constraint=g, scales=scales, starts=starts or default_starts,
                     outputs=outputs, layout=Layout(dim, part_layouts, _states(parts)),
                     terms=terms, static_params=static_params, bounds=bounds,
                     stability_when=_least(when) if len(when) == len(parts) else None,
                     kinematics=qdot if kinematic else None,
                     rest=ca.vertcat(*rest_rows) if rest_rows else None)


def _numbers_only(parts, num, params, name, kind, syms, kinematic, starts) -> Mechanism:
    """``assemble(symbols=False)``: the whole's numbers on placeholder expressions."""
    q, v, z, t, p = syms
    n_v, n_q = num.n_v, num.n_q
    q_scale, v_scale = np.zeros(n_q), np.zeros(n_v)
    bounds, part_layouts = {}, {}
    for m in parts:
        _part_scales(m, num, q_scale, v_scale)
        for k, b in m.bounds.items():
            bounds[f"{m.name}.{k}"] = b
        part_layouts.update(_part_layouts(m, num))
    n_z_total = sum(m.n_z for m in parts)
    static_params = {f"{m.name}.{k}": val for m in parts for k, val in m.static_params.items()}
    rest = [m for m in kinematic if m.rest is not None]
    return Mechanism(
        name=name, q=q, v=v, z=z, t=t, p=p, params=params, mass=kind(n_v, n_v),
        force=kind.zeros(n_v, 1), constraint=kind.zeros(n_z_total if n_z_total else 0, 1),
        scales=_scales(parts, q_scale, v_scale, n_z_total),
        starts=starts or functools.partial(_default_starts, parts, num, params, static_params),
        layout=Layout(parts[0].layout.dim, part_layouts, _states(parts)),
        terms=tuple(dict.fromkeys(t_ for m in parts for t_ in m.terms)),
        static_params=static_params, bounds=bounds,
        kinematics=kind.zeros(n_q, 1) if kinematic else None,
        rest=kind.zeros(sum(m.n_q - m.n_v for m in rest), 1) if rest else None)


def _check_parts(parts: list) -> tuple[dict, int, type]:
    """The parts by name (unique), their common dimension (2 or 3) and the symbol kind of
    the whole (``ca.MX`` when any part is MX, else ``ca.SX``)."""
    by_name: dict[str, Mechanism] = {}
    for m in parts:
        if m.name in by_name:
            raise SymcableError(f"assemble: two parts are named {m.name!r}")
        by_name[m.name] = m
    dims = {m.layout.dim for m in parts}
    if len(dims) != 1:
        raise SymcableError(f"assemble: parts of different dimensions {sorted(dims)}")
    return by_name, dims.pop(), ca.MX if any(isinstance(m.q, ca.MX) for m in parts) else ca.SX


@dataclass
class _Numbering:
    """Where each part's local coordinates go in the assembled ``q`` (n_q,) and ``v`` (n_v,).

    ``dof`` joins shared coordinates; ``roots_prescribed`` maps a joined coordinate's root
    to the (Prescribed or Attached joint, its component k) that moves it; ``global_index``
    maps every other root to its index in q and v (< n_v); ``tail_index`` maps a part's
    entries past its n_v, ``(part, j)``, to their index in q (>= n_v)."""

    dof: _DofMap
    roots_prescribed: dict
    global_index: dict
    tail_index: dict
    n_v: int
    n_q: int
    _local: dict = field(default_factory=dict)

    def local(self, m: Mechanism) -> tuple[np.ndarray, dict]:
        """``(index, moved)`` of part ``m``'s first n_v coordinates: ``index`` (n_v,) their
        index in the assembled q and v, -1 where a joint moves them; ``moved`` maps those
        local j to the (joint, component k) that moves them. Computed once per part."""
        if m.name not in self._local:
            index, moved = np.full(m.n_v, -1, dtype=int), {}
            for jloc in range(m.n_v):
                r = self.dof.find((m.name, jloc))
                if r in self.roots_prescribed:
                    moved[jloc] = self.roots_prescribed[r]
                else:
                    index[jloc] = self.global_index[r]
            self._local[m.name] = (index, moved)
        return self._local[m.name]


def _number(parts: list, by_name: dict, joints: list) -> _Numbering:
    """The joints read into a :class:`_Numbering` of the parts' coordinates (checked: known
    parts and nodes, no node moved by two joints, no body that is itself moved)."""
    dof = _DofMap(by_name)
    prescribed: dict = {}
    for j in joints:
        if isinstance(j, Shared):
            for a, b in zip(_node_dofs(by_name, j.a, "Shared.a"), _node_dofs(by_name, j.b, "Shared.b")):
                dof.union(a, b)
        elif isinstance(j, (Prescribed, Attached)):
            if isinstance(j, Attached) and j.body not in by_name:
                raise SymcableError(f"Attached({j.name!r}).body = {j.body!r}: no such part")
            what = f"{type(j).__name__}({j.name!r}).node"
            for k, d in enumerate(_node_dofs(by_name, j.node, what)):
                prescribed[d] = (j, k)
        else:
            raise SymcableError(f"assemble: joint {j!r} is not Shared, Prescribed or Attached")
    roots_prescribed: dict = {}
    for d, jk in prescribed.items():
        r = dof.find(d)
        if r in roots_prescribed and roots_prescribed[r][0].name != jk[0].name:
            raise SymcableError(f"assemble: a node is prescribed by both "
                                f"{roots_prescribed[r][0].name!r} and {jk[0].name!r}")
        roots_prescribed[r] = jk
    global_index: dict = {}
    n_v = 0
    for m in parts:
        for jloc in range(m.n_v):
            r = dof.find((m.name, jloc))
            if r in roots_prescribed or r in global_index:
                continue
            global_index[r] = n_v
            n_v += 1
    tail_index = {}  # (part, local j >= its n_v) -> index in q
    for m in parts:
        for jloc in range(m.n_v, m.n_q):
            tail_index[(m.name, jloc)] = n_v + len(tail_index)
    n_q = n_v + len(tail_index)
    for j in joints:
        if isinstance(j, Attached) and any(dof.find((j.body, i)) in roots_prescribed
                                           for i in range(by_name[j.body].n_v)):
            raise SymcableError(f"Attached({j.name!r}): its body {j.body!r} is itself "
                                "prescribed or attached")
    return _Numbering(dof, roots_prescribed, global_index, tail_index, n_v, n_q)


#: numberings of numbers-only builds by their structure (:func:`_known_number`), the most
#: recent last
_NUMBERINGS: "OrderedDict[tuple, _Numbering]" = OrderedDict()
_NUMBERINGS_KEPT = 32


def _known_number(parts: list, by_name: dict, joints: list) -> _Numbering:
    """:func:`_number` for a numbers-only build, kept by what it reads: each part's name,
    sizes and node layout, and each joint's kind, name and nodes. A numbering is structure
    alone, so every numbers-only build of one structure (a design loop's re-solves) shares
    the first's. Only the joints' names are read from its ``roots_prescribed`` there
    (:func:`_part_layouts`; :func:`_part_scales` reads indices), so the joint objects it
    holds, the first build's, serve any later one."""
    key = (tuple((m.name, m.n_v, m.n_q, _layout_key(m)) for m in parts),
           tuple((type(j).__name__, getattr(j, "name", None), getattr(j, "a", None),
                  getattr(j, "b", None), getattr(j, "node", None), getattr(j, "body", None))
                 for j in joints))
    num = _NUMBERINGS.get(key)
    if num is None:
        num = _NUMBERINGS[key] = _number(parts, by_name, joints)
        if len(_NUMBERINGS) > _NUMBERINGS_KEPT:
            _NUMBERINGS.popitem(last=False)
    else:
        _NUMBERINGS.move_to_end(key)
    return num


def _layout_key(m: Mechanism):
    lay = m.layout.parts.get(m.name) if m.layout is not None else None
    if lay is None:
        return None
    idx = np.asarray(lay.node_q, int)
    return idx.shape, idx.tobytes()


def _param_blocks(parts: list, presc_joints: list, dim: int) -> ParamBlocks:
    """The assembled parameters: the parts' blocks (``part.name``), then each Prescribed
    joint's ``NAME.position``, ``.amplitude`` (dim each, m), ``.phase`` (dim, rad) and
    ``.omega`` (1, rad/s)."""
    names, sizes, values = [], [], []
    for m in parts:
        for bn, bs in zip(m.params.names, m.params.sizes):
            names.append(f"{m.name}.{bn}")
            sizes.append(bs)
        values.append(m.params.values)
    for j in presc_joints:
        pos = np.asarray(j.position, dtype=float).ravel()
        if pos.size != dim:
            raise SymcableError(f"Prescribed({j.name!r}).position = {list(pos)}: needs {dim} entries")
        amp = np.zeros(dim) if j.amplitude is None else np.asarray(j.amplitude, float).ravel()
        ph = np.zeros(dim) if j.phase is None else np.asarray(j.phase, float).ravel()
        for bn, val in (("position", pos), ("amplitude", amp), ("phase", ph),
                        ("omega", np.array([float(j.omega)]))):
            if val.size != (1 if bn == "omega" else dim):
                raise SymcableError(f"Prescribed({j.name!r}).{bn} = {list(val)}: needs {dim} entries")
            names.append(f"{j.name}.{bn}")
            sizes.append(val.size)
            values.append(val)
    return ParamBlocks(tuple(names), tuple(sizes), np.concatenate(values) if values else np.zeros(0))


def _prescribed_motion(presc_joints: list, params: ParamBlocks, p, t) -> dict:
    """``{joint name: (x, x', x'')}``, each (dim, 1): the Prescribed joints' harmonic
    motions (m, m/s, m/s^2) as expressions of ``t`` and ``p``."""
    motion = {}
    for j in presc_joints:
        P = {bn: p[params.slice(f"{j.name}.{bn}")] for bn in ("position", "amplitude", "phase", "omega")}
        arg = P["omega"] * t + P["phase"]
        x = P["position"] + P["amplitude"] * ca.cos(arg)
        xd = -P["amplitude"] * P["omega"] * ca.sin(arg)
        xdd = -P["amplitude"] * P["omega"] ** 2 * ca.cos(arg)
        motion[j.name] = (x, xd, xdd)
    return motion


def _free_of(m: Mechanism, num: _Numbering, q, v):
    """The part's own q (m.n_q,) and v (m.n_v,) in the assembled symbols, where its entries
    are free."""
    return (ca.vertcat(*[q[num.global_index[num.dof.find((m.name, j))]] for j in range(m.n_v)],
                       *[q[num.tail_index[(m.name, j)]] for j in range(m.n_v, m.n_q)]),
            ca.vertcat(*[v[num.global_index[num.dof.find((m.name, j))]] for j in range(m.n_v)]))


def _kinematics(kinematic: list, num: _Numbering, kind, q, v, z_at, p_at, t):
    """The kinematics of the whole, q' = G(q) v (n_q, 1): each part's rows of those with
    kinematics (``kinematic``), v where it has none; and those parts' rest rows (a list)."""
    qdot = ca.vertcat(v, kind.zeros(num.n_q - num.n_v, 1))
    rest_rows = []
    for m in kinematic:
        qb, vb = _free_of(m, num, q, v)
        fn = ca.Function(f"part_{m.fname}_kin", [m.q, m.v, m.z, m.t, m.p],
                         [m.kinematics] + ([] if m.rest is None else [m.rest]))
        out = fn(qb, vb, z_at[m.name], t, p_at[m.name])
        out = list(out) if isinstance(out, (list, tuple)) else [out]
        for jloc in range(m.n_q):
            gi = (num.global_index[num.dof.find((m.name, jloc))] if jloc < m.n_v
                  else num.tail_index[(m.name, jloc)])
            qdot[gi] = out[0][jloc]
        if m.rest is not None:
            rest_rows.append(out[1])
    return qdot, rest_rows


def _part_coords(m: Mechanism, num: _Numbering, motion: dict, kind, q, v, q_scale, v_scale):
    """The part's q (m.n_q,), v (m.n_v,) and prescribed acceleration (m.n_v,) in the
    assembled symbols and motions; its local rows that are free and their global columns,
    and its rows attached to a body. Raises ``q_scale``, ``v_scale`` (assembled, in place)
    to the part's own scales where its entries are free."""
    rows_free, cols_free, rows_att = [], [], []  # local -> global for free entries
    qp, vp, ap = [], [], []
    for jloc in range(m.n_v):
        r = num.dof.find((m.name, jloc))
        if r in num.roots_prescribed:
            jt, k = num.roots_prescribed[r]
            x, xd, xdd = motion[jt.name]
            qp.append(x[k]); vp.append(xd[k]); ap.append(xdd[k])
            if isinstance(jt, Attached):
                rows_att.append(jloc)
        else:
            gi = num.global_index[r]
            rows_free.append(jloc); cols_free.append(gi)
            qp.append(q[gi]); vp.append(v[gi]); ap.append(kind(0))
            q_scale[gi] = max(q_scale[gi], m.scales.q[jloc])
            v_scale[gi] = max(v_scale[gi], m.scales.v[jloc])
    for jloc in range(m.n_v, m.n_q):
        qp.append(q[num.tail_index[(m.name, jloc)]])
        q_scale[num.tail_index[(m.name, jloc)]] = m.scales.q[jloc]
    return (ca.vertcat(*qp), ca.vertcat(*vp), ca.vertcat(*ap), rows_free, cols_free,
            rows_att)


def _part_scales(m: Mechanism, num: _Numbering, q_scale, v_scale) -> None:
    """What :func:`_part_coords` does to ``q_scale``, ``v_scale``, alone (numbers only)."""
    index, _ = num.local(m)
    free = index >= 0
    np.maximum.at(q_scale, index[free], np.asarray(m.scales.q, float)[:m.n_v][free])
    np.maximum.at(v_scale, index[free], np.asarray(m.scales.v, float)[:m.n_v][free])
    for jloc in range(m.n_v, m.n_q):
        q_scale[num.tail_index[(m.name, jloc)]] = m.scales.q[jloc]


def _add_joint_force(m: Mechanism, num: _Numbering, fp_eff, joint_force: dict) -> None:
    """Adds to ``joint_force`` (joint name -> dim entries, N, in place) the force this part
    exerts on each prescribed node, ``fp_eff`` = f_part - M_part a_part at its rows, with the
    prescribed accelerations only: exact in statics, and in dynamics for a mass matrix that
    does not couple the node to free ones (lumped mass)."""
    for jloc in range(m.n_v):
        r = num.dof.find((m.name, jloc))
        if r in num.roots_prescribed and isinstance(num.roots_prescribed[r][0], Prescribed):
            jt, k = num.roots_prescribed[r]
            joint_force[jt.name][k] = joint_force[jt.name][k] + fp_eff[jloc]


def _shared(made: dict, key: tuple, build):
    """``made[key]``, built once: parts that share their expressions (a mooring's identical
    lines, :mod:`symcable.models.structure`) share the Functions that evaluate them."""
    if key not in made:
        made[key] = build()
    return made[key]


def _part_outputs(m: Mechanism, local: tuple, made: dict) -> dict:
    """The part's outputs, namespaced ``part.name``, at ``local`` = its (q, v, z, t, p) in
    the assembled symbols."""
    outputs = {}
    if m.outputs:
        names_o = list(m.outputs)
        fo = _shared(made, ("out", id(m.force)), lambda: ca.Function(
            f"part_{m.fname}_out", [m.q, m.v, m.z, m.t, m.p], [m.outputs[k].expr for k in names_o]))
        vals = fo(*local)
        vals = vals if isinstance(vals, (list, tuple)) else [vals]
        for k, val in zip(names_o, vals):
            o = m.outputs[k]
            outputs[f"{m.name}.{k}"] = Output(val, o.unit, o.owner or m.name, o.description)
    return outputs


def _part_bounds(m: Mechanism, local: tuple, bounds: dict, when: list, made: dict) -> None:
    """Adds the part's admissibility bounds, namespaced, to ``bounds`` and its
    ``stability_when`` to ``when`` (in place), at ``local`` = its (q, v, z, t, p) in the
    assembled symbols."""
    if m.bounds or m.stability_when is not None:
        names_b = list(m.bounds)
        exprs = [m.bounds[k].expr for k in names_b]
        if m.stability_when is not None:
            exprs.append(m.stability_when)
        vals = _shared(made, ("bounds", id(m.force)), lambda: ca.Function(
            f"part_{m.fname}_bounds", [m.q, m.v, m.z, m.t, m.p], exprs))(*local)
        vals = list(vals) if isinstance(vals, (list, tuple)) else [vals]
        for k, val in zip(names_b, vals):
            bounds[f"{m.name}.{k}"] = dataclasses.replace(m.bounds[k], expr=val)
        if m.stability_when is not None:
            when.append(vals[-1])


def _part_layouts(m: Mechanism, num: _Numbering) -> dict:
    """The part's layout parts in assembled indices (-1 where a node is prescribed or
    attached; ``moved_by`` names the joint or the part's own prescribed motion)."""
    index, moved = num.local(m)
    part_layouts = {}
    for pname, lay in m.layout.parts.items():
        local = np.asarray(lay.node_q, dtype=int)
        node_q = np.where(local >= 0, index[np.maximum(local, 0)], -1) if index.size else \
            np.full(local.shape, -1, dtype=int)
        moved_by = {i: f"{m.name}.{j}" for i, j in lay.prescribed.items()}
        for ii in zip(*np.nonzero((local >= 0) & (node_q < 0))):
            moved_by[int(ii[0])] = moved[int(local[ii])][0].name
        part_layouts[pname] = PartLayout(lay.kind, lay.s, node_q, node_q.copy(), moved_by)
    return part_layouts


def _scales(parts: list, q_scale: np.ndarray, v_scale: np.ndarray, n_z_total: int) -> Scales:
    """The assembled scales: ``q_scale`` (n_q,) and ``v_scale`` (n_v,) with non-positive
    entries set to 1 (in place), the parts' z scales in order, the largest of their force
    (N), mass (kg) and residual floor (N), the smallest of their resolutions (N)."""
    q_scale[q_scale <= 0] = 1.0
    v_scale[v_scale <= 0] = 1.0
    return Scales(q=q_scale, v=v_scale,
                  z=np.concatenate([m.scales.z for m in parts]) if n_z_total else np.zeros(0),
                  force=max(m.scales.force for m in parts),
                  mass=max(m.scales.mass for m in parts),
                  residual_floor=max(m.scales.residual_floor for m in parts),
                  resolution=min(m.scales.resolution for m in parts))


def _default_starts(parts: list, num: _Numbering, params: ParamBlocks, static_params: dict):
    """The default static start of the whole (a generator of one Start): each part's first
    start, a shared coordinate taken from the first part that has it."""
    q0 = np.zeros(num.n_q)
    seen = np.zeros(num.n_q, dtype=bool)
    z0 = []
    for m in parts:
        st = next(iter(m.starts()), None)
        ql = np.zeros(m.n_q) if st is None else np.asarray(st.q, float)
        z0.append(np.zeros(m.n_z) if st is None else np.asarray(st.z, float))
        for jloc in range(m.n_q):
            if jloc >= m.n_v:
                q0[num.tail_index[(m.name, jloc)]] = ql[jloc]
                continue
            r = num.dof.find((m.name, jloc))
            if r in num.roots_prescribed:
                continue
            gi = num.global_index[r]
            if not seen[gi]:
                q0[gi], seen[gi] = ql[jloc], True
    zz = np.concatenate(z0) if z0 else np.zeros(0)
    yield Start(q0, zz, params.with_values(**static_params), "parts' own starts")


def _states(parts) -> StateNames | None:
    """The names of the assembled first-order states (every part's entries past its n_v),
    in part order: each part's own (``layout.states``), prefixed ``"{part}."`` where it is
    not already (a line's ``"a.node3.bristle.x"``), or ``"{part}.state{i}"``; the unit,
    source and the setting without them of the first part that names its own."""
    named = [m.layout.states for m in parts if m.n_q > m.n_v and m.layout.states is not None]
    if not any(m.n_q > m.n_v for m in parts):
        return None
    names, rates = [], []
    for m in parts:
        if m.n_q > m.n_v:
            own = m.layout.states
            names += [n if n.startswith(f"{m.name}.") else f"{m.name}.{n}" for n in own.names] \
                if own is not None else [f"{m.name}.state{i}" for i in range(m.n_q - m.n_v)]
            rates += [f"{m.name}.{own.rate_block(i)}" if own is not None and own.rate_block(i)
                      else "" for i in range(m.n_q - m.n_v)]
    # the unit, source and setting of the first part whose states have no rate block (the
    # ones a periodic solve refuses), else of the first that names its own
    plain = [s for s in named if not all(s.rate_block(i) for i in range(len(s.names)))]
    first = (plain or named or [StateNames((), "")])[0]
    return StateNames(tuple(names), first.unit, first.source, first.without,
                      tuple(rates) if any(rates) else ())


def _least(exprs):
    """The least of the parts' ``stability_when``: stability is judged where any part's is
    negative (a part without one is always judged, so the whole then has none)."""
    out = exprs[0]
    for e in exprs[1:]:
        out = ca.fmin(out, e)
    return out
