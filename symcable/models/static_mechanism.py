"""A static formulation (a :class:`~symcable.models.base.Model`: unknowns w, residual R(w; p))
seen as a Mechanism without mass: q = w, f = -R, no velocities that matter, no constraints.

The planar model of seed 001 is written in angles and strains, whose residual rows mix force
balances and geometric compatibility; as a Mechanism it gives the generic static solver,
the exact sensitivities of its outputs (the end stiffness) and the derived Functions. Its
residual is not the gradient of an energy, so no stability is read from its tangent; its
dynamics (linearised about the static state) carry their own mass and stiffness.
"""
from __future__ import annotations

import casadi as ca
import numpy as np

from .base import Model
from .mechanism import Layout, Mechanism, Output, ParamBlocks, PartLayout, Scales, Start

__all__ = ["PLANAR_BLOCKS", "static_mechanism"]

#: the planar model's parameters as named blocks (contiguous entries of its p)
PLANAR_BLOCKS = (("load", 1), ("bending", 1), ("end_a.position", 2), ("end_b.position", 2),
                 ("end_a.angle", 1), ("end_b.angle", 1), ("current", 2))


def static_mechanism(model: Model) -> Mechanism:
    """The static Model ``model`` as a massless Mechanism (see the module docstring).

    Outputs keep the model's names (``end_force_b``: (1, 2) N, the force the line exerts on
    its end B, ...), with units where the planar model documents them.
    """
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

    def starts():
        for g in model.initial_guess():
            yield Start(np.asarray(g.w, float), np.zeros(0), np.asarray(g.p, float), g.source,
                        _BLOCK_OF.get(g.homotopy, g.homotopy))

    s_nodes = np.asarray(model.info.get("s_nodes", np.zeros(0)), dtype=float)
    layout = Layout(2, {"line": PartLayout("line", s_nodes,
                                           np.full((s_nodes.size, 2), -1, dtype=int),
                                           np.full((s_nodes.size, 2), -1, dtype=int))})
    return Mechanism(name=f"{model.name}_static", q=q, v=v, z=z, t=t, p=model.p,
                     params=params, mass=ca.SX(n, n), force=-model.residual,
                     constraint=ca.SX.zeros(0, 1),
                     scales=Scales(q=np.asarray(model.w_scale, float), v=np.ones(n),
                                   z=np.zeros(0), force=model.force_scale,
                                   residual_floor=model.residual_floor),
                     starts=starts, outputs=outputs, layout=layout, terms=model.terms)


_BLOCK_OF = {"load": "load", "bending": "bending"}
