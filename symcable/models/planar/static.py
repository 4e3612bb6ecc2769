"""A static formulation (a :class:`~symcable.models.planar.base.Model`: unknowns w, residual R(w; p))
seen as a Mechanism without mass: q = w, f = R, no velocities that matter, no constraints.
The sign: the planar residual's balance rows are the net force on each node (the force of the
part beyond minus that of the part before, plus the load), which is f; its compatibility rows
(a length mismatch times EA/ds) are forces of either sign. The static residual the solvers
derive is then the model's own expression, operation for operation (no negation in the graph
that the fused Newton solve and its generated C are built from).

The planar model of Boral, Hickey & Basu is written in angles and strains, whose residual
rows mix force balances and geometric compatibility; as a Mechanism it gives the generic
static solver, the exact sensitivities of its outputs (the end stiffness) and the derived
Functions. Its residual is not the gradient of an energy, so no stability is read from its
tangent; its dynamics (linearised about the static state) carry their own mass and
stiffness.
"""
from __future__ import annotations

import casadi as ca
import numpy as np

from .base import Model
from ...mechanism.mechanism import Layout, Mechanism, Output, ParamBlocks, PartLayout, Scales, Start

__all__ = ["PLANAR_BLOCKS", "static_mechanism"]

#: the planar model's parameters as named blocks (contiguous entries of its p)
PLANAR_BLOCKS = (("load", 1), ("bending", 1), ("end_a.position", 2), ("end_b.position", 2),
                 ("end_a.angle", 1), ("end_b.angle", 1), ("current", 2), ("slack", 1))


def static_mechanism(model: Model) -> Mechanism:
    """The static Model ``model`` as a massless Mechanism (see the module docstring), built
    once per model (kept in the model's cache, so its derived Functions are too).

    ``q`` is the model's ``w`` in its own order (node and segment unknowns interleaved: the
    banded order the block LU of the fused static solve was tuned on). Outputs keep the
    model's names (``end_force_b``: (1, 2) N, the force the line exerts on its end B, ...),
    with units where the planar model documents them. ``starts()`` gives the model's initial
    guesses as Starts, each computed once (the closed-form catenary first), with the model's
    homotopy (``"bending"``, ``"load"``: the parameter block its ``p`` sets to zero); the
    line-search merit weights are the model's.
    """
    mech = model._cache.get("static_mechanism")
    if mech is None:
        mech = model._cache["static_mechanism"] = _build(model)
    return mech


def _build(model: Model) -> Mechanism:
    n = model.n_w
    names = tuple(b for b, _ in PLANAR_BLOCKS)
    sizes = tuple(s for _, s in PLANAR_BLOCKS)
    if sum(sizes) != model.p.numel():
        raise ValueError(f"static_mechanism: model {model.name!r} has {model.p.numel()} "
                         f"parameters, the planar blocks {sum(sizes)}")
    params = ParamBlocks(names, sizes, model.p_target)
    q = model.w
    v = ca.SX.sym("v", n)
    z = ca.SX.sym("z", 0)
    t = ca.SX.sym("t")
    units = {"positions": "m", "angle": "rad", "strain": "1", "axial_force": "N", "shear": "N",
             "moment": "N m", "force": "N", "tension": "N", "end_force_a": "N",
             "end_force_b": "N", "contact_force": "N"}
    outputs = {k: Output(e, units.get(k, ""), "line") for k, e in model.outputs.items()}

    def convert(g):
        return Start(np.asarray(g.w, float), np.zeros(0), np.asarray(g.p, float), g.source,
                     _BLOCK_OF.get(g.homotopy, g.homotopy))

    starts = _Memo(model.initial_guess, convert)

    s_nodes = np.asarray(model.info.get("s_nodes", np.zeros(0)), dtype=float)
    layout = Layout(2, {"line": PartLayout("line", s_nodes,
                                           np.full((s_nodes.size, 2), -1, dtype=int),
                                           np.full((s_nodes.size, 2), -1, dtype=int))})
    return Mechanism(name=f"{model.name}_static", q=q, v=v, z=z, t=t, p=model.p,
                     params=params, mass=ca.SX(n, n), force=model.residual,
                     constraint=ca.SX.zeros(0, 1),
                     scales=Scales(q=np.asarray(model.w_scale, float), v=np.ones(n),
                                   z=np.zeros(0), force=model.force_scale,
                                   residual_floor=model.residual_floor,
                                   merit=np.asarray(model.merit_weights, float)),
                     starts=starts, outputs=outputs, layout=layout, terms=model.terms,
                     bounds=dict(model.bounds), **_stability(model))


def _stability(model: Model) -> dict:
    """Where the planar line's stability is judged: in sections with bending, when one of
    their segments is in compression (a tension-only cable under conservative loads cannot
    lose stability), on the Schur complement onto the node positions, whose rows are the
    force balances (the energy's gradient); the segment angles and strains are internal."""
    seg, kinds = model.info.get("segments"), model.info.get("unknown_kinds")
    if seg is None or kinds is None or not np.any(seg["EI"] > 0) \
            or "axial_force" not in model.outputs:
        return {}
    rod = np.flatnonzero(seg["EI"] > 0).tolist()
    return {"stability_coordinates": np.flatnonzero(np.isin(np.asarray(kinds), ["x", "z"])),
            "stability_when": ca.mmin(model.outputs["axial_force"][rod])}


_BLOCK_OF = {"load": "load", "bending": "bending", "slack": "slack",
             "bending and slack": "bending and slack"}


class _Memo:
    """``starts()``: the starts of a lazy generator, each built once and then replayed (the
    first, a closed-form catenary, is asked for at every solve; the others only when it
    fails)."""

    def __init__(self, make, convert):
        self._make, self._convert = make, convert
        self._done: list = []
        self._source = None
        self._exhausted = False

    def __call__(self):
        i = 0
        while True:
            if i < len(self._done):
                yield self._done[i]
                i += 1
                continue
            if self._exhausted:
                return
            if self._source is None:
                self._source = iter(self._make())
            try:
                g = next(self._source)
            except StopIteration:
                self._exhausted = True
                return
            self._done.append(self._convert(g))
