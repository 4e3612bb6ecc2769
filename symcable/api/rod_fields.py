"""The field variables of Goyal & Perkins' rod (their Sec. 2.2) on a discrete ``model = "rod"``
solution, and the residuals of its field equations (7)-(10) by finite differences.

Goyal & Perkins write the rod in its body frames; in world components (the body-frame
derivative ∂/∂s + kappa x is the world d/ds, and ∂/∂t + omega x the world d/dt) the
equations read

    (7)  dv/ds = omega x t                         (inextensible, unshearable)
    (8)  d omega/ds = d kappa/dt - omega x kappa    (compatibility)
    (9)  dq/ds + t x f + Q = dh/dt,  h = I omega    (moment balance)
    (10) df/ds + F = m dv/dt                        (force balance)

with v the centreline velocity (m/s), omega the angular velocity of the material frame
(rad/s), kappa its Darboux vector (curvature and twist, 1/m), f the internal force and q
the internal moment (N, N m: the part beyond s on the part before it), F and Q the
distributed force and moment (N/m, N m/m), m the mass and I the rotary inertia per metre.

Where each lives on the discrete rod (:mod:`symcable.models.rod.rod`): positions and v at the
nodes; the material frame (t, m1, m2), omega, f, tension f . t and shear |f - (f . t) t| on
the edges; kappa and q at the vertices (the interior nodes, and a clamped or guided end;
zero at a pinned or free end, which carries no moment). kappa = kb / lbar + tau t_v
(kb the discrete curvature binormal, tau = twist / lbar, t_v the vertex tangent, the
normalised mean of its edges'), in the body frame (kappa_1, kappa_2, tau) of the edge
after; q = the bending moment vector + GJ tau t_v. omega is exact on the state: the rate
of the material directors as functions of (q, t, p), t x dt/dt + (dm1/dt . m2) t, by
CasADi (it includes the spin of the anchored reference frame that the Mechanism's twist
inertia leaves out). Time derivatives in the residuals are central differences between
three samples (:func:`field_residuals`).

Layer: results (it reads a Mechanism's outputs and derived Functions; no solver).
"""
from __future__ import annotations

import weakref
from dataclasses import dataclass

import casadi as ca
import numpy as np

from ..mechanism.functions import functions
from ..errors import SymcableError
from ..mechanism.mechanism import Mechanism

__all__ = ["RodFields", "field_residuals", "rod_fields", "tension_shear", "trajectory_fields"]

_RATES: "weakref.WeakKeyDictionary[Mechanism, ca.Function]" = weakref.WeakKeyDictionary()


@dataclass(frozen=True)
class RodFields:
    """The seed's field variables on one state of a discrete rod (module docstring).

    Attributes (n = N + 1 nodes, N edges; world components unless said)
    ----------
    time : float, s
    s : ndarray (n,)  unstretched arc length of the nodes, m;  ds : ndarray (N,)
    positions, velocity : ndarray (n, 3), m and m/s
    tangent, m1, m2 : ndarray (N, 3)  each edge's material frame
    angular_velocity : ndarray (N, 3)  omega of each edge's material frame, rad/s
    curvature : ndarray (n, 3)  kappa (Darboux vector), 1/m, at the vertices (0 elsewhere)
    curvature_body : ndarray (n, 3)  (kappa_1, kappa_2, tau) in the frame of the edge after
    vertex : ndarray (n,) bool  where a vertex is (kappa and q defined)
    vertex_tangent : ndarray (n, 3)
    internal_force : ndarray (N, 3)  f, N
    moment : ndarray (n, 3)  q, N m
    tension : ndarray (N,)  f . t, N;  shear : ndarray (N,)  |f - (f . t) t|, N
    """

    time: float
    s: np.ndarray
    ds: np.ndarray
    positions: np.ndarray
    velocity: np.ndarray
    tangent: np.ndarray
    m1: np.ndarray
    m2: np.ndarray
    angular_velocity: np.ndarray
    curvature: np.ndarray
    curvature_body: np.ndarray
    vertex: np.ndarray
    vertex_tangent: np.ndarray
    internal_force: np.ndarray
    moment: np.ndarray
    tension: np.ndarray
    shear: np.ndarray


def tension_shear(internal_force, positions) -> tuple[np.ndarray, np.ndarray]:
    """``(tension, shear)``, N, per edge: the seed's tension f . t and shear
    |f - (f . t) t| of the internal force f across each edge (``internal_force``, shape
    (..., n_seg, 3) or flat) on the edge's tangent t (from ``positions``, (..., n, 3) or
    flat; any leading sample axes are kept)."""
    X = np.asarray(positions, float)
    if X.ndim == 1 or X.shape[-1] != 3:
        X = X.reshape(X.shape[:-1] + (-1, 3))
    d = np.diff(X, axis=-2)
    t = d / np.linalg.norm(d, axis=-1, keepdims=True)
    f = np.asarray(internal_force, float).reshape(t.shape)
    ten = np.sum(f * t, axis=-1)
    return ten, np.linalg.norm(f - ten[..., None] * t, axis=-1)


def _unit(a: np.ndarray) -> np.ndarray:
    n = np.linalg.norm(a, axis=-1, keepdims=True)
    return a / np.where(n > 0, n, 1.0)


def _turn(t: np.ndarray, kb: np.ndarray, sign: float) -> np.ndarray:
    """``t`` turned by the angle 2 atan(|kb| / 2) about kb (``sign`` -1: the other way):
    the tangent across a vertex whose curvature binormal is ``kb``."""
    k = float(np.linalg.norm(kb))
    if k == 0.0:
        return t
    a, phi = kb / k, sign * 2.0 * np.arctan(0.5 * k)
    return t * np.cos(phi) + np.cross(a, t) * np.sin(phi) + a * (a @ t) * (1 - np.cos(phi))


def _rates(mech: Mechanism) -> ca.Function:
    """(q, v, t, p) -> (N, 3) the edges' t' and m1' (the material frame's rates), kept per
    Mechanism. q' = v (the rod's kinematics) and the held ends' motion through t."""
    fn = _RATES.get(mech)
    if fn is None:
        if mech.kinematics is not None:
            raise SymcableError(f"mechanism {mech.name!r}: rod_fields needs q' = v (a rod)")
        frame = ca.reshape(mech.outputs["reference_frame"].expr, 6, -1)
        theta = ca.vec(mech.outputs["twist_angles"].expr).T
        t, d1 = frame[0:3, :], frame[3:6, :]
        d2 = ca.horzcat(*[ca.cross(t[:, j], d1[:, j]) for j in range(t.shape[1])])
        m1 = d1 * ca.repmat(ca.cos(theta), 3, 1) + d2 * ca.repmat(ca.sin(theta), 3, 1)
        X = ca.vertcat(ca.vec(t), ca.vec(m1))
        rate = ca.jtimes(X, mech.q, mech.v) + ca.jacobian(X, mech.t)
        fn = _RATES[mech] = ca.Function("rod_frame_rates", [mech.q, mech.v, mech.t, mech.p],
                                        [ca.reshape(rate, 3, -1).T])
    return fn


def rod_fields(mech: Mechanism, q, v=None, t: float = 0.0, p=None) -> RodFields:
    """The field variables of the rod ``mech`` at the state (q, v) at ``t`` s with
    parameters ``p`` (default the Mechanism's; a static solution's are its ``p``; a time
    run re-anchored: the sample's, :func:`trajectory_fields`)."""
    if "reference_frame" not in mech.outputs or "internal_force" not in mech.outputs:
        raise SymcableError(f"mechanism {mech.name!r}: not a rod (no reference_frame and "
                            "internal_force outputs)")
    q = np.asarray(q, float).ravel()
    v = np.zeros(mech.n_v) if v is None else np.asarray(v, float).ravel()
    p = mech.params.values if p is None else np.asarray(p, float).ravel()
    F = functions(mech)
    y = F.outputs(q, v, np.zeros(mech.n_z), t, p)
    out = F.unpack(np.asarray(y[0] if isinstance(y, (list, tuple)) else y, float).ravel())
    get = lambda k: np.asarray(out[k], float)  # noqa: E731
    X = get("positions").reshape(-1, 3)
    N = X.shape[0] - 1
    if get("reference_frame").size != 6 * N:
        raise SymcableError(f"mechanism {mech.name!r}: rod_fields takes a rod whose every "
                            "edge is a rod edge (a hybrid's cable3d edges carry no material "
                            "frame: not yet)")
    frame = get("reference_frame").reshape(N, 6)
    tg, d1 = frame[:, :3], frame[:, 3:]
    th = get("twist_angles").ravel()[:, None]
    m1 = np.cos(th) * d1 + np.sin(th) * np.cross(tg, d1)
    m2 = np.cross(tg, m1)
    R = np.asarray(_rates(mech)(q, v, t, p), float).reshape(2, N, 3) if N else None
    tdot, m1dot = R[0], R[1]
    omega = np.cross(tg, tdot) + np.sum(m1dot * m2, axis=1)[:, None] * tg
    kap = get("curvature").reshape(-1, 2)
    tw = get("twist").ravel()
    M = get("bending_moment").reshape(-1, 3)
    Mt = get("twisting_moment").ravel()
    s = np.asarray(mech.layout.parts["line"].s, float)
    ds = np.diff(s)
    lbar = np.empty(N + 1)
    lbar[1:-1] = 0.5 * (ds[:-1] + ds[1:])
    lbar[0], lbar[-1] = 0.5 * ds[0], 0.5 * ds[-1]
    vert = np.any(kap != 0.0, axis=1) | (tw != 0.0) | np.any(M != 0.0, axis=1) | (Mt != 0.0)
    vert[1:-1] = True
    tv = np.vstack([tg[:1], _unit(tg[:-1] + tg[1:]), tg[-1:]])
    # kappa's bending part: kb / lbar at the interior vertices (from the tangents, as the
    # kernel has it), from its body components in the frame of the end edge at an end
    # vertex (a clamp's or guide's: its ghost edge's frame is not an output)
    bend = kap[:, :1] * np.vstack([m1, m1[-1:]]) + kap[:, 1:2] * np.vstack([m2, m2[-1:]])
    e1, e2 = tg[:-1], tg[1:]
    bend[1:-1] = 2.0 * np.cross(e1, e2) / (1.0 + np.sum(e1 * e2, axis=1))[:, None] \
        / lbar[1:-1, None]
    for i, j, sign in ((0, 0, -1.0), (N, N - 1, 1.0)):  # an end vertex's ghost edge
        if vert[i]:  # kb turns the ghost's tangent into the edge's (or back): t_v between
            tv[i] = _unit(_turn(tg[j], bend[i] * lbar[i], sign) + tg[j])
    tau = tw / lbar
    curv = np.where(vert[:, None], bend + tau[:, None] * tv, 0.0)
    body = np.column_stack([kap, np.where(vert, tau, 0.0)])
    f = get("internal_force").reshape(N, 3)
    ten, shear = tension_shear(f, X)
    return RodFields(
        time=float(t), s=s, ds=ds, positions=X, velocity=get("velocities").reshape(-1, 3),
        tangent=tg, m1=m1, m2=m2, angular_velocity=omega, curvature=curv,
        curvature_body=body, vertex=vert, vertex_tangent=tv, internal_force=f,
        moment=np.where(vert[:, None], M + Mt[:, None] * tv, 0.0), tension=ten,
        shear=shear)


def trajectory_fields(mech: Mechanism, traj, k: int, p=None) -> RodFields:
    """:func:`rod_fields` at sample ``k`` of a MechanismTrajectory ``traj`` (its q, v and
    time); ``p`` default the Mechanism's (a run re-anchored as it went: pass the sample's
    parameters; the run's last are ``stats["p_final"]``)."""
    return rod_fields(mech, traj.q[k], traj.v[k], float(traj.time[k]), p)


def _per_edge(value, N: int, width: int = 0) -> np.ndarray:
    """``value`` (one, or one per edge) as (N,) or, with ``width``, (N, width)."""
    a = np.asarray(value, float)
    return np.array(np.broadcast_to(a, (N, width) if width else (N,)))


def field_residuals(fields, *, mass=0.0, force=(0.0, 0.0, 0.0), twist_inertia=0.0,
                    bending_inertia=0.0) -> dict:
    """The residuals of the seed's Eqs. (7)-(10) (module docstring) on a discrete rod, by
    finite differences: ``fields`` one :class:`RodFields` (a static state: v, omega and the
    time derivatives zero) or three at equally spaced times (central differences in time,
    at the middle one). Per metre as the equations: (7) 1/s per edge (m/s per m), (8)
    1/s^2... per interior vertex, (9) N m/m per edge, (10) N/m per interior node.

    ``mass`` kg/m, ``force`` N/m (the distributed force F: the submerged weight
    (0, 0, -w) in air or still water; (N, 3) per edge, or one (3,)), ``twist_inertia`` and
    ``bending_inertia`` kg m (the rotary inertia per metre about the tangent and about a
    transverse axis: the rod Mechanism has m d^2 / 8 and 0), scalars or per edge. The
    distributed moment Q is zero. Differences: (7) and (9) across each edge,
    (v_{j+1} - v_j) / ds_j and (q_{j+1} - q_j) / ds_j with the edge's t, f, omega; (8) and
    (10) across each interior node, (omega_j - omega_{j-1}) / lbar and (f_j - f_{j-1}) /
    lbar with the node's kappa and the mean of its edges' omega, m and F.

    Returns {"7": (N, 3), "8": (N - 1, 3), "9": (N, 3), "10": (N - 1, 3)}."""
    seq = list(fields) if isinstance(fields, (list, tuple)) else [fields]
    if len(seq) not in (1, 3):
        raise SymcableError(f"fields: {len(seq)} states: give one (static) or three equally "
                            "spaced in time")
    now = seq[len(seq) // 2]
    N = now.tangent.shape[0]
    tg, f, w, q = now.tangent, now.internal_force, now.angular_velocity, now.moment
    ds = now.ds
    lbar = 0.5 * (ds[:-1] + ds[1:])
    m = _per_edge(mass, N)
    F = _per_edge(force, N, 3)
    It, Ib = _per_edge(twist_inertia, N), _per_edge(bending_inertia, N)

    def h(fl):  # angular momentum per metre of each edge
        wt = np.sum(fl.angular_velocity * fl.tangent, axis=1)[:, None]
        return It[:, None] * wt * fl.tangent + Ib[:, None] * (fl.angular_velocity - wt * fl.tangent)

    if len(seq) == 3:
        dt = seq[2].time - seq[0].time
        if not dt > 0 or abs((seq[1].time - seq[0].time) - (seq[2].time - seq[1].time)) > 1e-9 * dt:
            raise SymcableError("fields: three states at equally spaced, increasing times")
        rate = lambda a, b: (a - b) / dt  # noqa: E731
        dv = rate(seq[2].velocity, seq[0].velocity)
        dkap = rate(seq[2].curvature, seq[0].curvature)
        dh = rate(h(seq[2]), h(seq[0]))
    else:
        dv, dkap, dh = (np.zeros_like(now.velocity), np.zeros_like(now.curvature),
                        np.zeros((N, 3)))
    r7 = np.diff(now.velocity, axis=0) / ds[:, None] - np.cross(w, tg)
    wbar = 0.5 * (w[:-1] + w[1:])
    kap = now.curvature[1:-1]
    r8 = np.diff(w, axis=0) / lbar[:, None] - dkap[1:-1] + np.cross(wbar, kap)
    r9 = np.diff(q, axis=0) / ds[:, None] + np.cross(tg, f) - dh
    mbar = 0.5 * (m[:-1] + m[1:])[:, None]
    Fbar = 0.5 * (F[:-1] + F[1:])
    r10 = np.diff(f, axis=0) / lbar[:, None] + Fbar - mbar * dv[1:-1]
    return {"7": r7, "8": r8, "9": r9, "10": r10}
