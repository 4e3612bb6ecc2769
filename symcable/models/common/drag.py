"""The drag loading functions of Sun, Zhu & LaRosa in the cable3d element (``drag_law =
"loading-functions"``; the law and its keys: :mod:`symcable.scene.loading`).

Written in the tangential and normal relative speeds, never in the angle itself: with u the
water's velocity relative to the element, t its unit tangent, u_t = u . t and u_perp =
u - u_t t, the two |.| of the law are smoothed as the Morison law's |u| is, with
:data:`~symcable.models.common.elements.DRAG_SPEED` = eps:

    A = sqrt(u_t^2 + eps^2)       (|u_t|),      B = sqrt(|u_perp|^2 + eps^2)   (u_n),
    Z^2 = A^2 + B^2               (|u|^2),      cos psi = A / Z,   sin psi = B / Z,

cos k psi and sin k psi by the Chebyshev recurrences g_k = 2 cos(psi) g_{k-1} - g_{k-2}
(g_0, g_1 = 1, cos psi and 0, sin psi), and per unit length, per 0.5 rho d (the element
kernel multiplies by 0.5 rho d L0 sqrt(1 + e)):

    Z^2 [cd f_n(psi) u_perp / B + cd f_t(psi) (u_t / A) t].

Everything is smooth (A, B >= eps), so the force and its Jacobian are finite at zero
relative velocity and with the flow along the element (u_perp = 0). Morison's law in this
form (:meth:`~symcable.scene.loading.LoadingFunctions.morison`: f_n = Cd_n sin^2 psi,
f_t = Cd_t cos^2 psi) is Z^2 f_n = Cd_n (Z^2 - A^2) = Cd_n B^2 and Z^2 f_t = Cd_t A^2: the
force Cd_n B u_perp + Cd_t A u_t t, the element's Morison expression, to round-off. A law
with f_n(0) != 0 (or f_t(90 deg) != 0) has its normal (tangential) force faded out within
eps of axial (normal) flow, where its direction is undefined.
"""
from __future__ import annotations

import casadi as ca
import numpy as np

from ...scene import Scene
from ...scene.loading import LoadingFunctions

__all__ = ["law_table", "loading_drag", "law_drag_loads"]


def _pad(values, n) -> list[float]:
    return list(values) + [0.0] * (n - len(values))


def law_table(scene: Scene) -> dict | None:
    """Per-segment loading functions of a one-line scene, or None when every section's
    line type has Morison's law (the element then keeps its Morison expression):

    - ``"law"`` (N, 2 Kc + 2 Ks): cd times [normal cos (Kc), normal sin (Ks), tangential
      cos (Kc), tangential sin (Ks)], zero-padded; Morison sections as
      :meth:`LoadingFunctions.morison`;
    - ``"shape"`` (Kc, Ks): Kc cosine (from k = 0) and Ks sine (from k = 1) coefficients;
    - ``"normal_bound"`` (N,): cd times the sum of |f_n's coefficients|, an upper bound of
      cd f_n (for the seabed-reaction bound, as Cd_n is for Morison's law)."""
    types = [s.line_type for s in scene.sections for _ in range(s.segments)]
    if all(lt.drag_law == "morison" for lt in types):
        return None
    laws = [lt.loading if lt.drag_law != "morison"
            else LoadingFunctions.morison(lt.cd_normal, lt.cd_tangential) for lt in types]
    kc = max(max(len(f.normal_cos), len(f.tangential_cos)) for f in laws)
    ks = max(max(len(f.normal_sin), len(f.tangential_sin)) for f in laws)
    rows = np.array([f.cd * np.array(_pad(f.normal_cos, kc) + _pad(f.normal_sin, ks)
                                     + _pad(f.tangential_cos, kc) + _pad(f.tangential_sin, ks))
                     for f in laws], float).reshape(len(laws), 2 * (kc + ks))
    bound = np.array([f.cd * (np.sum(np.abs(f.normal_cos)) + np.sum(np.abs(f.normal_sin)))
                      for f in laws])
    return {"law": rows, "shape": (kc, ks), "normal_bound": bound}


def _harmonics(c, s, kc, ks):
    """cos k psi (k = 0..kc-1) and sin k psi (k = 1..ks) from cos psi = c, sin psi = s."""
    cos = [1.0, c][:kc]
    while len(cos) < kc:
        cos.append(2.0 * c * cos[-1] - cos[-2])
    sin = [0.0, s]
    while len(sin) < ks + 1:
        sin.append(2.0 * c * sin[-1] - sin[-2])
    return cos, sin[1:ks + 1]


def loading_drag(u_rel, t, law, shape, eps: float):
    """The loading-function drag per unit length per 0.5 rho d (module docstring), a (3, 1)
    expression, from the relative velocity ``u_rel`` (3, 1), m/s, the unit tangent ``t``
    (3, 1), ``law`` (2 Kc + 2 Ks, 1: a row of :func:`law_table`), ``shape`` = (Kc, Ks) and
    the smoothing speed ``eps`` (m/s). Unit: m^2/s^2."""
    kc, ks = shape
    ut = ca.dot(u_rel, t)
    perp = u_rel - ut * t
    A = ca.sqrt(ut * ut + eps * eps)
    B = ca.sqrt(ca.dot(perp, perp) + eps * eps)
    Z2 = A * A + B * B
    Z = ca.sqrt(Z2)
    cos, sin = _harmonics(A / Z, B / Z, kc, ks)
    n_cos, n_sin = law[0:kc], law[kc:kc + ks]
    t_cos, t_sin = law[kc + ks:2 * kc + ks], law[2 * kc + ks:]
    fn = sum(n_cos[k] * cos[k] for k in range(kc)) + sum(n_sin[k] * sin[k] for k in range(ks))
    ft = sum(t_cos[k] * cos[k] for k in range(kc)) + sum(t_sin[k] * sin[k] for k in range(ks))
    return Z2 * (fn / B) * perp + Z2 * ft * (ut / A) * t


def law_drag_loads(env, seg: dict, table: dict):
    """Nodal drag of the environment's uniform current on a line at rest (the loading
    functions of ``table``, :func:`law_table`, with its smoothing speed ``"eps"``), as a function of the node positions
    (N+1, 3) -> (N+1, 3), N: each segment's half on each of its nodes, as
    :func:`~symcable.models.common.relax.drag_loads` does for Morison's law (for the starts)."""
    u, tt = ca.SX.sym("u", 3), ca.SX.sym("t", 3)
    law = ca.SX.sym("law", table["law"].shape[1])
    f = ca.Function("drag", [u, tt, law],
                    [loading_drag(u, tt, law, table["shape"], table["eps"])])
    n = len(seg["ds"])
    fmap = f.map(n)
    k = 0.5 * env.water_density * seg["d"] * seg["ds"]
    cur = np.repeat(np.asarray(env.current, float)[:, None], n, axis=1)

    def loads(pos):
        d = np.diff(pos, axis=0)
        length = np.maximum(np.linalg.norm(d, axis=1), 1e-300)
        t = (d / length[:, None]).T
        per = np.asarray(fmap(cur, t, table["law"].T), float).T  # (N, 3)
        per = per * (k * np.sqrt(length / seg["ds"]))[:, None]
        out = np.zeros_like(pos, dtype=float)
        out[:-1] += 0.5 * per
        out[1:] += 0.5 * per
        return out

    return loads
