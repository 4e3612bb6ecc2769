"""The rod with exact inextensibility: the rod Mechanism of :mod:`symcable.models.rod.rod` with its
stiff axial energy taken out and one constraint per edge put in its place (study code).

    g_j(q) = |x_{j+1} - x_j| - ds_j = 0            (m, one row per edge)

The multiplier z_j (N) is the edge's tension: the force of the constraint on the nodes is
-B^T z (B = dg/dq), i.e. +z_j t_j on node j and -z_j t_j on node j+1, exactly the axial force
T_j t_j of cable3d's element kernel with T_j = z_j. The rod's own force keeps everything
else (bending, twist, weight, drag, end force); its axial term (+T_j t_j, -T_j t_j with
T_j = EA e_j + BA e_j', the element kernel's ``axial_force``) is cancelled by adding B^T T:

    f_c(q, v, z) = f_rod(q, v) + B^T T(q, v) - B^T z

so f_c does not contain EA at all (the cancellation is exact algebra; numerically it leaves
round-off of EA e t, which is ~EA eps on the constraint manifold). No library change: the
Mechanism's generic pieces (derive.functions: the static residual, the acceleration residual,
the tangents) read it as they read any constrained Mechanism.

Outputs changed: ``axial_force`` is z (N) and ``internal_force`` carries z_j t_j in place of
T_j t_j; the others are the rod's (``strain`` is then the constraint's violation / ds).
"""
from __future__ import annotations

import dataclasses

import casadi as ca
import numpy as np

from symcable.mechanism.mechanism import Mechanism, Output, Scales, Start


def constrained(rod: Mechanism, ds: np.ndarray) -> Mechanism:
    """The exact-constraint variant of a rod Mechanism (module docstring). ``ds``: the rest
    length of each edge (m), in order along the line."""
    out = rod.outputs
    X = out["positions"].expr.T          # (3, N + 1), m: held ends as expressions of t, p
    T = out["axial_force"].expr          # (N, 1), N: EA e + BA e' (the element kernel's)
    N = int(T.numel())
    dx = X[:, 1:] - X[:, :-1]
    ell = ca.sqrt(ca.sum1(dx * dx)).T    # (N, 1), m
    g = ell - ca.DM(np.asarray(ds, float))
    z = ca.SX.sym("z", N)
    B = ca.jacobian(g, rod.q)            # (N, n_q)
    force = rod.force + ca.mtimes(B.T, T - z)
    tangent = dx / ca.repmat(ell.T, 3, 1)
    internal = out["internal_force"].expr + ((z - T) * tangent.T)
    outputs = dict(out)
    outputs["axial_force"] = Output(z, "N", out["axial_force"].owner,
                                    "tension of each edge (the constraint's multiplier)")
    outputs["internal_force"] = Output(internal, "N", out["internal_force"].owner,
                                       out["internal_force"].description)
    outputs["constraint"] = Output(g, "m", "", "edge length minus its rest length")
    sc = rod.scales
    scales = Scales(q=sc.q, v=sc.v, z=np.full(N, sc.force), force=sc.force, mass=sc.mass,
                    residual_floor=sc.residual_floor, g=np.full(N, float(np.min(ds))),
                    merit=None)

    def starts():
        for st in rod.starts():
            yield Start(st.q, np.zeros(N), st.p, st.source, st.homotopy)

    return dataclasses.replace(rod, name=rod.name + "_constrained", z=z, force=force,
                               constraint=g, scales=scales, starts=starts, outputs=outputs)
