"""Forced toy mechanisms for the periodic solvers' contract tests: a pendulum with a
constraint whose pivot is driven horizontally.

Every function returns a :class:`~symcable.mechanism.mechanism.Mechanism` in SI units.
"""
from __future__ import annotations

import math

import casadi as ca
import numpy as np

from ...mechanism.mechanism import Layout, Mechanism, Output, ParamBlocks, PartLayout, Scales, Start

__all__ = ["driven_pendulum"]


def driven_pendulum(length: float = 1.0, mass: float = 1.0, gravity: float = 9.80665, *,
                    damping: float = 0.5, pivot_amplitude: float = 0.05, omega: float = 2.0,
                    name: str = "driven_pendulum") -> Mechanism:
    """A point mass (kg) on a massless rod of ``length`` (m) whose pivot moves horizontally,
    x_p(t) = A cos(omega t) (A = ``pivot_amplitude`` m, ``omega`` rad/s), in the vertical x-z
    plane, with viscous damping ``damping`` (N s/m) on the absolute velocity.

    q = (x, z) m, the mass's position; one rheonomic constraint
    g = (|q - x_p(t) e_x|^2 - L^2)/2 = 0 with multiplier z (N/m, the rod tension over its
    length); force f = (0, -m g) - (q - x_p e_x) z - c v. Parameter block ``drive`` =
    (A, omega), ``length``, ``gravity``. Statics (A = 0): hanging at (0, -L). Period of the
    response 2 pi / omega; for small A the angle responds linearly with the gain
    omega^2 / (omega_0^2 - omega^2 + i omega c/m) (omega_0^2 = g/L) on A/L.
    """
    q = ca.SX.sym("q", 2)
    v = ca.SX.sym("v", 2)
    z = ca.SX.sym("z", 1)
    t = ca.SX.sym("t")
    params = ParamBlocks(("length", "gravity", "drive"), (1, 1, 2),
                         np.array([length, gravity, pivot_amplitude, omega]))
    p = ca.SX.sym("p", params.n)
    L, g, A, w = p[0], p[1], p[2], p[3]
    pivot = ca.vertcat(A * ca.cos(w * t), 0)
    r = q - pivot
    f = ca.vertcat(0, -mass * g) - r * z - damping * v
    con = 0.5 * (ca.dot(r, r) - L ** 2)
    outputs = {
        "tension": Output(z * ca.norm_2(r), "N", name, "rod tension"),
        "angle": Output(ca.atan2(r[0], -r[1]), "rad", name, "rod angle from the downward vertical"),
        "pivot": Output(pivot, "m", name, "pivot position"),
    }
    wgt = mass * gravity

    def starts():
        yield Start(np.array([0.0, -length]), np.array([wgt / length]),
                    params.with_values(drive=[0.0, omega]), "hanging")

    idx = np.arange(2).reshape(1, 2)
    return Mechanism(name=name, q=q, v=v, z=z, t=t, p=p, params=params, mass=mass * ca.SX.eye(2),
                     force=f, constraint=ca.reshape(con, 1, 1),
                     scales=Scales(q=np.full(2, length),
                                   v=np.full(2, math.sqrt(gravity * length)),
                                   z=np.array([wgt / length]), force=wgt, mass=mass,
                                   g=np.array([length ** 2])),
                     starts=starts, outputs=outputs,
                     layout=Layout(2, {name: PartLayout("point", np.zeros(1), idx, idx.copy())}),
                     terms=("weight", "constraint", "damping", "prescribed motion"),
                     static_params={"drive": [0.0, omega]})
