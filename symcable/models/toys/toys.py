"""Small mechanisms with known answers, for the solver contract suite and as examples of
writing a formulation: a constrained pendulum, point masses and springs (assembled into a
chain), and a forced Duffing oscillator.

Every function returns a :class:`~symcable.mechanism.mechanism.Mechanism` in SI units.
"""
from __future__ import annotations

import math

import casadi as ca
import numpy as np

from ...errors import SymcableError
from ...mechanism.assembly import Prescribed, Shared, assemble
from ...mechanism.mechanism import Layout, Mechanism, Output, ParamBlocks, PartLayout, Scales, Start

__all__ = ["duffing", "hanging_chain", "pendulum", "point_mass", "spring", "spring_chain"]


def _layout(name, dim, n_nodes, kind="point"):
    idx = np.arange(n_nodes * dim).reshape(n_nodes, dim)
    return Layout(dim, {name: PartLayout(kind, np.zeros(n_nodes), idx, idx.copy())})


def pendulum(length: float = 1.0, mass: float = 1.0, gravity: float = 9.80665,
             name: str = "pendulum") -> Mechanism:
    """A point mass on a massless rod of ``length`` (m) hinged at the origin, in the vertical
    x-z plane: q = (x, z) m, one constraint (|q|^2 - L^2)/2 = 0 with multiplier z (N/m, the
    rod tension over its length), force f = (0, -m g) - q z. Parameter blocks ``length``,
    ``gravity``. Statics: hanging at (0, -L). Small-amplitude period 2 pi sqrt(L/g)."""
    q = ca.SX.sym("q", 2)
    v = ca.SX.sym("v", 2)
    z = ca.SX.sym("z", 1)
    t = ca.SX.sym("t")
    params = ParamBlocks(("length", "gravity"), (1, 1), np.array([length, gravity]))
    p = ca.SX.sym("p", params.n)
    L, g = p[0], p[1]
    M = mass * ca.SX.eye(2)
    f = ca.vertcat(0, -mass * g) - q * z
    con = 0.5 * (ca.dot(q, q) - L ** 2)
    outputs = {
        "tension": Output(z * ca.norm_2(q), "N", name, "rod tension"),
        "angle": Output(ca.atan2(q[0], -q[1]), "rad", name, "angle from the downward vertical"),
        "energy": Output(0.5 * mass * ca.dot(v, v) + mass * g * q[1], "J", name,
                         "kinetic + potential energy"),
    }
    w = mass * gravity

    def starts():
        yield Start(np.array([0.3 * length, -length * math.sqrt(1 - 0.09)]), np.array([w / length]),
                    params.values, "tilted")

    return Mechanism(name=name, q=q, v=v, z=z, t=t, p=p, params=params, mass=M, force=f,
                     constraint=ca.reshape(con, 1, 1),
                     scales=Scales(q=np.full(2, length), v=np.full(2, math.sqrt(gravity * length)),
                                   z=np.array([w / length]), force=w, mass=mass,
                                   g=np.array([length ** 2])),
                     starts=starts, outputs=outputs, layout=_layout(name, 2, 1),
                     terms=("weight", "constraint"))


def point_mass(name: str, position, mass: float, *, gravity: float = 0.0,
               drag: float = 0.0, drag_speed: float = 1e-3) -> Mechanism:
    """A point mass (kg) at ``position`` (m; its dimension is the mechanism's) with weight
    m g along -e_last and quadratic drag -c v sqrt(|v|^2 + v_eps^2) (c in N s^2/m^2; the
    square root, smoothed at ``drag_speed`` m/s, keeps the force differentiable at rest)."""
    x0 = np.asarray(position, dtype=float).ravel()
    dim = x0.size
    q, v = ca.SX.sym("q", dim), ca.SX.sym("v", dim)
    z, t = ca.SX.sym("z", 0), ca.SX.sym("t")
    params = ParamBlocks(("gravity",), (1,), np.array([gravity]))
    p = ca.SX.sym("p", 1)
    e = np.zeros(dim)
    e[-1] = 1.0
    f = -mass * p[0] * ca.DM(e) - drag * v * ca.sqrt(ca.dot(v, v) + drag_speed ** 2)
    terms = ("inertia",) + (("weight",) if gravity else ()) + (("drag",) if drag else ())

    def starts():
        yield Start(x0, np.zeros(0), params.values, "given position")

    return Mechanism(name=name, q=q, v=v, z=z, t=t, p=p, params=params,
                     mass=mass * ca.SX.eye(dim), force=f, constraint=ca.SX.zeros(0, 1),
                     scales=Scales(q=np.ones(dim), v=np.ones(dim), z=np.zeros(0),
                                   force=max(mass * abs(gravity), 1.0), mass=mass),
                     starts=starts,
                     outputs={"position": Output(q, "m", name, "position")},
                     layout=_layout(name, dim, 1), terms=terms)


def spring(name: str, a, b, stiffness: float, rest_length: float) -> Mechanism:
    """A massless linear spring (N/m) of ``rest_length`` (m) between two nodes, starting at
    positions ``a`` and ``b``: nodal forces +-k (l - L0) t, t the unit vector from a to b.
    Its mass matrix is zero: assemble it with point masses at both nodes."""
    a, b = (np.asarray(x, dtype=float).ravel() for x in (a, b))
    dim = a.size
    q, v = ca.SX.sym("q", 2 * dim), ca.SX.sym("v", 2 * dim)
    z, t = ca.SX.sym("z", 0), ca.SX.sym("t")
    params = ParamBlocks(("stiffness",), (1,), np.array([stiffness]))
    p = ca.SX.sym("p", 1)
    d = q[dim:] - q[:dim]
    ell = ca.sqrt(ca.dot(d, d))
    T = p[0] * (ell - rest_length)
    f = ca.vertcat(T * d / ell, -T * d / ell)

    def starts():
        yield Start(np.concatenate([a, b]), np.zeros(0), params.values, "given positions")

    return Mechanism(name=name, q=q, v=v, z=z, t=t, p=p, params=params,
                     mass=ca.SX.zeros(2 * dim, 2 * dim), force=f, constraint=ca.SX.zeros(0, 1),
                     scales=Scales(q=np.full(2 * dim, max(rest_length, 1e-3)), v=np.ones(2 * dim),
                                   z=np.zeros(0), force=max(abs(stiffness * rest_length), 1.0)),
                     starts=starts, outputs={"tension": Output(T, "N", name, "spring force")},
                     layout=_layout(name, dim, 2, kind="element"), terms=("elastic",))


def spring_chain(n_masses: int = 5, *, mass: float = 1.0, stiffness: float = 100.0,
                 span: float = 6.0, rest_length: float | None = None, gravity: float = 0.0,
                 drag: float = 0.0, drag_speed: float = 1e-3, amplitude=None,
                 omega: float = 0.0) -> Mechanism:
    """``n_masses`` point masses (kg) joined by ``n_masses + 1`` linear springs (N/m) in the
    x-z plane, between end nodes fixed at (0, 0) and (span, 0) m; the right end may move
    harmonically (``amplitude`` (2,) m at ``omega`` rad/s). Assembled from :func:`point_mass`
    and :func:`spring` parts with :class:`Shared` and :class:`Prescribed` joints.

    Without gravity the chain is straight under the spring tension T = k (a - L0),
    a = span/(N+1), and its modes are known in closed form: axial
    omega_j = 2 sqrt(k/m) sin(j pi / (2 (N+1))), transverse the same with k replaced by T/a.
    """
    N = int(n_masses)
    a = span / (N + 1)
    L0 = 0.8 * a if rest_length is None else float(rest_length)
    xs = np.linspace(0.0, span, N + 2)
    parts, joints = [], []
    for i in range(1, N + 1):
        parts.append(point_mass(f"m{i}", [xs[i], 0.0], mass, gravity=gravity, drag=drag,
                                drag_speed=drag_speed))
    for i in range(N + 1):
        parts.append(spring(f"k{i}", [xs[i], 0.0], [xs[i + 1], 0.0], stiffness, L0))
    for i in range(N + 1):
        if i >= 1:
            joints.append(Shared((f"m{i}", 0), (f"k{i}", 0)))
        if i + 1 <= N:
            joints.append(Shared((f"m{i + 1}", 0), (f"k{i}", 1)))
    joints.append(Prescribed("left", ("k0", 0), [0.0, 0.0]))
    joints.append(Prescribed("right", (f"k{N}", 1), [span, 0.0],
                             amplitude=amplitude, omega=omega))
    return assemble(parts, joints, name="chain")


def hanging_chain(n_masses: int, a, b, *, mass: float = 1.0, stiffness: float = 1e4,
                  length: float | None = None, gravity: float = 9.80665, drag: float = 0.0,
                  drag_speed: float = 1e-3, amplitude=None, omega: float = 0.0,
                  name: str = "chain") -> Mechanism:
    """``n_masses`` point masses (kg) joined by ``n_masses + 1`` linear springs (N/m) between
    two prescribed end nodes at ``a`` and ``b`` (m; 2 or 3 coordinates, z last and up):
    a catenary-like chain hanging under gravity in 2D or 3D. ``length`` (m) is the total
    unstretched length (default 1.2 times the distance between the ends), shared equally by
    the springs. End ``b`` may move as ``b + amplitude sin(omega t)`` (m per coordinate,
    rad/s: at ``b`` at t = 0); the end joints are ``end_a`` and ``end_b`` (outputs ``end_a.force``,
    ``end_b.position`` ...). Parts ``m1`` ... ``mN`` and ``k0`` ... ``kN``; the static start
    is the straight line between the ends."""
    a, b = (np.asarray(x, dtype=float).ravel() for x in (a, b))
    if a.size != b.size or a.size not in (2, 3):
        raise SymcableError(f"hanging_chain: a = {a.tolist()}, b = {b.tolist()}: need two "
                            "points of 2 or 3 coordinates each")
    N = int(n_masses)
    L0 = (1.2 * float(np.linalg.norm(b - a)) if length is None else float(length)) / (N + 1)
    xs = a + np.linspace(0.0, 1.0, N + 2)[:, None] * (b - a)
    parts = [point_mass(f"m{i}", xs[i], mass, gravity=gravity, drag=drag, drag_speed=drag_speed)
             for i in range(1, N + 1)]
    parts += [spring(f"k{i}", xs[i], xs[i + 1], stiffness, L0) for i in range(N + 1)]
    joints = [Shared((f"m{i}", 0), (f"k{i}", 0)) for i in range(1, N + 1)]
    joints += [Shared((f"m{i + 1}", 0), (f"k{i}", 1)) for i in range(N)]
    joints += [Prescribed("end_a", ("k0", 0), a),
               Prescribed("end_b", (f"k{N}", 1), b, amplitude=amplitude,
                          phase=np.full(a.size, -0.5 * math.pi), omega=omega)]
    return assemble(parts, joints, name=name)


def duffing(*, mass: float = 1.0, damping: float = 0.2, stiffness: float = 1.0,
            cubic: float = 1.0, force: float = 0.5, omega: float = 1.2,
            name: str = "duffing") -> Mechanism:
    """The forced Duffing oscillator m x'' + c x' + k x + k3 x^3 = F cos(omega t) (SI:
    kg, N s/m, N/m, N/m^3, N, rad/s); q = x (m). Parameter blocks ``forcing`` = (F, omega).
    Its periodic response has period 2 pi / omega."""
    q, v = ca.SX.sym("q", 1), ca.SX.sym("v", 1)
    z, t = ca.SX.sym("z", 0), ca.SX.sym("t")
    params = ParamBlocks(("forcing",), (2,), np.array([force, omega]))
    p = ca.SX.sym("p", 2)
    f = -damping * v - stiffness * q - cubic * q ** 3 + p[0] * ca.cos(p[1] * t)

    def starts():
        yield Start(np.zeros(1), np.zeros(0), params.values, "rest")

    return Mechanism(name=name, q=q, v=v, z=z, t=t, p=p, params=params,
                     mass=mass * ca.SX.eye(1), force=f, constraint=ca.SX.zeros(0, 1),
                     scales=Scales(q=np.ones(1), v=np.ones(1), z=np.zeros(0),
                                   force=max(abs(force), stiffness), mass=mass),
                     starts=starts, outputs={"x": Output(q, "m", name, "displacement")},
                     layout=_layout(name, 1, 1), terms=("elastic", "damping", "forcing"),
                     static_params={"forcing": [0.0, omega]})
