"""Seed 003's drag loading functions in cable3d (``drag_law = "loading-functions"``, issue 12
item 1): the law written in the tangential and normal relative speeds (symcable.models.
cable3d_drag), its keys (symcable.scene.drag), and a statics case balanced by hand.

- Morison's coefficients as loading functions (f_n = Cd_n sin^2 psi, f_t = Cd_t cos^2 psi)
  give the element's Morison forces to round-off, moving in a current, and the same static
  line;
- a nontrivial law (up to cos 4 psi and sin 3 psi) against a hand computation at 0, 30, 90
  and 150 deg, direction and magnitude;
- the force and its Jacobian are finite at zero relative velocity and with the flow along
  the element (up to the 8th harmonic);
- a weighted line streaming from a pinned end in a current is straight at the angle where
  the normal drag balances the weight's normal part, cd R f_n(phi) = w cos(phi), and its top
  tension is L (w sin(phi) + R cd f_t(phi)) (Pode's towed-cable argument, with any law).
"""
from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import brentq

import symcable as sc
from symcable.errors import SceneError
from symcable.models.common.elements import DRAG_SPEED, element_kernel
from symcable.scene import load_scene
from symcable.scene.loading import LoadingFunctions

RHO = 1025.0
#: a Choo-Casarella-like normal law with a cos 4 psi term (f_n(0) = 0, f_n(90 deg) = 1) and
#: a tangential law with sin psi and sin 3 psi terms
LAW = LoadingFunctions(1.7, (0.48, -0.1, -0.4, 0.0, 0.02), (0.1, -0.011),
                       (0.02, 0.01, 0.005), (-0.012, 0.0, -0.003))


def _row(law: LoadingFunctions, kc: int, ks: int) -> np.ndarray:
    pad = lambda v, n: list(v) + [0.0] * (n - len(v))  # noqa: E731
    return law.cd * np.array(pad(law.normal_cos, kc) + pad(law.normal_sin, ks)
                             + pad(law.tangential_cos, kc) + pad(law.tangential_sin, ks))


def _args(xa, xb, **kw):
    args = dict(xa=xa, xb=xb, va=np.zeros(3), vb=np.zeros(3), u=np.zeros(3),
                L0=float(np.linalg.norm(xb - xa)), EA=1e6, BA=0.0, EAs=1e-3, delta=1e-9,
                wall=1.0, w=0.0, d=0.04, cdn=1.2, cdt=0.05, rho=RHO, load=1.0)
    args.update(kw)
    return args


def _total(out) -> np.ndarray:
    """The element's total external force (fa + fb: the axial force cancels)."""
    return np.asarray(out["fa"], float).ravel() + np.asarray(out["fb"], float).ravel()


def test_morison_coefficients_reproduce_morison():
    """On a stretched element whose nodes move (differently) in a current, at random
    orientations and including a flow almost along the element, the loading-function kernel
    with Morison's coefficients gives the Morison kernel's nodal forces to round-off (1e-12
    of the drag scale 0.5 rho d L0 Cd |u|^2: the two differ only in the order of the
    operations, Cd_n (Z^2 - A^2) for Cd_n B^2)."""
    cdn, cdt = 1.3, 0.07
    law = LoadingFunctions.morison(cdn, cdt)
    k0, k1 = element_kernel(), element_kernel((3, 0))
    rng = np.random.default_rng(12)
    for case in range(8):
        xa, xb = rng.normal(size=3), rng.normal(size=3)
        t = (xb - xa) / np.linalg.norm(xb - xa)
        u = rng.normal(size=3) if case < 6 else 1.5 * t + 1e-3 * rng.normal(size=3)
        args = _args(xa, xb, va=0.3 * rng.normal(size=3), vb=0.3 * rng.normal(size=3), u=u,
                     L0=0.98 * float(np.linalg.norm(xb - xa)), BA=5.0, w=3.0, cdn=cdn, cdt=cdt)
        ref, out = k0(**args), k1(law=_row(law, 3, 0), **args)
        urel = u - 0.5 * (args["va"] + args["vb"])
        scale = 0.5 * RHO * args["d"] * args["L0"] * cdn * float(urel @ urel)
        for key in ("fa", "fb"):
            np.testing.assert_allclose(np.asarray(out[key], float).ravel(),
                                       np.asarray(ref[key], float).ravel(), rtol=0,
                                       atol=1e-12 * scale + 1e-12 * abs(float(ref["T"])))


@pytest.mark.parametrize("alpha_deg", [0.0, 30.0, 90.0, 150.0])
def test_nontrivial_law_against_hand_computation(alpha_deg):
    """The relative flow at alpha from the element's tangent (psi = min(alpha, 180 - alpha)),
    2 m/s: the total drag is 0.5 rho d cd |u|^2 L0 (f_n(psi) n + f_t(psi) sign(u_t) t), n the
    unit normal part of the flow, to 1e-7 of the drag scale at 30 and 150 deg (the smoothing
    shifts psi by (DRAG_SPEED / |u|)^2 there) and to 2 (DRAG_SPEED / |u|) sum k |c_k| at 0 and
    90 deg (there the smoothed |u_t| or u_n is DRAG_SPEED, not 0: psi is off by
    DRAG_SPEED / |u|, and the law's slope is at most sum k |c_k|). Reversing the element
    changes nothing."""
    rng = np.random.default_rng(5)
    xa = rng.normal(size=3)
    t = rng.normal(size=3)
    t /= np.linalg.norm(t)
    side = np.cross(t, rng.normal(size=3))
    side /= np.linalg.norm(side)
    a, U = math.radians(alpha_deg), 2.0
    u = U * (math.cos(a) * t + math.sin(a) * side)
    xb = xa + 3.0 * t
    kc, ks = 5, 3
    k = element_kernel((kc, ks))
    args = _args(xa, xb, u=u)
    got = _total(k(law=_row(LAW, kc, ks), **args))
    psi = min(a, math.pi - a)
    scale = 0.5 * RHO * args["d"] * LAW.cd * U * U * args["L0"]
    ut = float(u @ t)
    sign = 0.0 if alpha_deg == 90.0 else math.copysign(1.0, ut)
    want = scale * (float(LAW.f_normal(psi)) * side + float(LAW.f_tangential(psi)) * sign * t)
    slope = sum(k_ * abs(c) for k_, c in enumerate(LAW.normal_cos + LAW.tangential_cos)) \
        + sum(k_ * abs(c) for k_, c in enumerate(LAW.normal_sin + LAW.tangential_sin, 1))
    tol = 1e-7 if alpha_deg in (30.0, 150.0) else 2 * DRAG_SPEED / U * slope
    np.testing.assert_allclose(got, want, rtol=0, atol=tol * scale)
    # the force does not depend on which way the element is numbered
    flipped = _total(k(law=_row(LAW, kc, ks), **_args(xb, xa, u=u)))
    np.testing.assert_allclose(flipped, got, rtol=0, atol=1e-13 * scale)


@pytest.mark.parametrize("flow", ["at rest", "along the element"])
def test_jacobian_finite_at_rest_and_in_axial_flow(flow):
    """Every entry of the Jacobian of the nodal forces in the node positions and velocities
    and in the current is finite at zero relative velocity and at u_n = 0, with harmonics up
    to k = 8 (the smoothed |u_t| and u_n are at least DRAG_SPEED)."""
    import casadi as ca
    law = LoadingFunctions(1.0, (0.5, 0.0, -0.5, 0, 0, 0, 0, 0, 0.01), (0.1,) * 8,
                           (0.05, 0.01, 0.0, 0, 0, 0, 0, 0, 0.001), (0.0,) * 7 + (0.002,))
    k = element_kernel((9, 8))
    xa, xb = np.array([0.1, -0.2, 0.3]), np.array([1.0, 0.5, -0.1])
    t = (xb - xa) / np.linalg.norm(xb - xa)
    v = np.zeros(3) if flow == "at rest" else 0.7 * t
    syms = {n: ca.SX.sym(n, 3) for n in ("xa", "xb", "va", "vb", "u")}
    args = _args(xa, xb, L0=0.9 * float(np.linalg.norm(xb - xa)), w=1.0)
    args.update(syms)
    out = k(law=_row(law, 9, 8), **args)
    x = ca.vertcat(*syms.values())
    J = ca.Function("J", [x], [ca.jacobian(ca.vertcat(out["fa"], out["fb"]), x),
                               ca.vertcat(out["fa"], out["fb"])])
    jac, f = J(np.concatenate([xa, xb, v, v, 2 * v]))  # u - (va + vb) / 2 = v
    assert np.all(np.isfinite(np.asarray(jac))) and np.all(np.isfinite(np.asarray(f)))


def _streaming(law: dict | None, *, segments: int = 20) -> dict:
    """A 50 m line of submerged weight 20 N/m pinned at the origin, its end free, in a
    1.5 m/s current along x (EA 1e9 N: strain under 1e-6)."""
    lt = {"EA": 1e9, "mass": 3.0, "diameter": 0.03, "weight": 20.0, "cd_normal": 1.5,
          "cd_tangential": 0.0}
    if law is not None:
        lt.update(drag_law="loading-functions", loading=law)
    return {"model": "cable3d", "environment": {"current": [1.5, 0.0, 0.0]},
            "line_types": {"c": lt}, "sections": [{"type": "c", "length": 50.0,
                                                   "segments": segments}],
            "end_a": {"condition": "pinned", "position": [0.0, 0.0, 0.0]},
            "end_b": {"condition": "free"}}


def test_streaming_line_balanced_by_hand():
    """Statics in a current with the nontrivial law: every segment at the angle phi below
    the horizontal where cd R f_n(phi) = w cos(phi) (R = 0.5 rho d U^2), and the top tension
    L (w sin(phi) + cd R f_t(phi)): the discrete line is exactly straight (each node's normal
    loads balance), so only the strain (under 1e-6, changing each segment's drag by
    sqrt(1 + e)) and the solver's tolerance separate them: angles within 1e-5 rad (measured
    7e-8), tension within 1e-6 (measured 3e-8)."""
    law = {"cd": LAW.cd, "normal_cos": list(LAW.normal_cos), "normal_sin": list(LAW.normal_sin),
           "tangential_cos": list(LAW.tangential_cos),
           "tangential_sin": list(LAW.tangential_sin)}
    st = sc.solve_static(_streaming(law), codegen=False)
    assert st.status == "converged"
    w, L, U, d = 20.0, 50.0, 1.5, 0.03
    R = 0.5 * RHO * d * U * U * LAW.cd
    phi = brentq(lambda p: R * float(LAW.f_normal(p)) - w * math.cos(p), 1e-9, math.pi / 2)
    seg = np.diff(st.positions, axis=0)
    angle = np.arctan2(-seg[:, 2], seg[:, 0])
    np.testing.assert_allclose(angle, phi, rtol=0, atol=1e-5)
    assert np.max(np.abs(st.positions[:, 1])) < 1e-9
    top = L * (w * math.sin(phi) + R * float(LAW.f_tangential(phi)))
    assert st.anchor_tension == pytest.approx(top, rel=1e-6)


def test_morison_as_loading_functions_gives_the_same_static_line():
    """The streaming line with Morison's law and with it written as loading functions
    (Pode's law here: f_n = 1.5 sin^2 psi, no tangential drag): the same nodes to the
    solver's tolerance (a residual below 1e-9 of the force scale, 4.4e-3 N, moves a node
    by up to r ds / T, about 1e-4 m; measured 1e-10 to 2e-6 m as the two Newton paths end
    one iteration apart)."""
    law = {"cd": 1.5, "normal_cos": [0.5, 0.0, -0.5], "tangential_cos": [0.0]}
    a = sc.solve_static(_streaming(None), codegen=False)
    b = sc.solve_static(_streaming(law), codegen=False)
    np.testing.assert_allclose(b.positions, a.positions, rtol=0, atol=1e-5)
    # (the tension to the same residual: 4.4e-3 N on 564 N; measured 3e-5 N)
    assert b.anchor_tension == pytest.approx(a.anchor_tension, abs=4.4e-3)


def test_scene_round_trip_and_defaults():
    law = {"cd": 1.7, "normal_cos": [0.5, 0.0, -0.5], "tangential_sin": [0.01]}
    s = load_scene(_streaming(law))
    lt = s.line_types["c"]
    assert lt.drag_law == "loading-functions"
    assert lt.loading == LoadingFunctions(1.7, (0.5, 0.0, -0.5), (), (), (0.01,))
    assert s.to_dict()["line_types"]["c"]["loading"] == law
    assert load_scene(s.to_dict()) == s
    assert load_scene(_streaming(None)).line_types["c"].drag_law == "morison"
    assert "drag_law" not in load_scene(_streaming(None)).to_dict()["line_types"]["c"]


@pytest.mark.parametrize("change, fragments", [
    (lambda lt: lt.update(drag_law="loading"),
     ["line_types.c.drag_law = 'loading'", "'morison', 'loading-functions'"]),
    (lambda lt: lt.update(drag_law="loading-functions"),
     ["line_types.c.loading: required key missing", "cd, normal_cos"]),
    (lambda lt: lt.update(loading={"cd": 1.0, "normal_cos": [1.0], "tangential_cos": [0.0]}),
     ["line_types.c.loading = ", 'read only with drag_law = "loading-functions"']),
    (lambda lt: lt.update(drag_law="loading-functions",
                          loading={"normal_cos": [0.5, 0, -0.5], "tangential_cos": [0.0]}),
     ["line_types.c.loading.cd: required key missing", "reference drag coefficient"]),
    (lambda lt: lt.update(drag_law="loading-functions",
                          loading={"cd": -1.0, "normal_cos": [0.5], "tangential_cos": [0.0]}),
     ["line_types.c.loading.cd = -1.0", ">= 0"]),
    (lambda lt: lt.update(drag_law="loading-functions",
                          loading={"cd": 1.0, "tangential_cos": [0.0]}),
     ["line_types.c.loading.normal_cos: required key missing", "normal_sin"]),
    (lambda lt: lt.update(drag_law="loading-functions",
                          loading={"cd": 1.0, "normal_cos": [0.5, "x"], "tangential_cos": [0.0]}),
     ["line_types.c.loading.normal_cos = [0.5, 'x']", "at most 9 numbers", "k = 0, 1"]),
    (lambda lt: lt.update(drag_law="loading-functions",
                          loading={"cd": 1.0, "normal_cos": [0.5], "tangential_sin": [0.1] * 9}),
     ["line_types.c.loading.tangential_sin = ", "at most 8 numbers", "up to k = 8"]),
    (lambda lt: lt.update(drag_law="loading-functions",
                          loading={"cd": 1.0, "normal_cos": [0.5],
                                   "tangential_cos": [0.019, -0.0239, -0.001]}),
     ["line_types.c.loading.tangential_cos = [0.019, -0.0239, -0.001]", "f_t(0 deg) = -0.0059",
      "must not drive the line"]),
    (lambda lt: lt.update(drag_law="loading-functions",
                          loading={"cd": 1.0, "normal_cos": [0.5], "tangential": [0.0]}),
     ["line_types.c.loading.tangential: unknown key", "did you mean"]),
])
def test_bad_drag_law_keys_are_one_line_errors(change, fragments):
    d = _streaming(None)
    change(d["line_types"]["c"])
    with pytest.raises(SceneError) as info:
        load_scene(d)
    msg = str(info.value)
    assert "\n" not in msg
    for f in fragments:
        assert f in msg, (f, msg)


def test_loading_functions_are_refused_in_planar():
    d = {"model": "planar", "line_types": {"c": {"EA": 1e9, "mass": 3.0, "diameter": 0.03,
                                                 "drag_law": "loading-functions"}},
         "sections": [{"type": "c", "length": 50.0, "segments": 5}],
         "end_a": {"condition": "pinned", "position": [0.0, 0.0]},
         "end_b": {"condition": "pinned", "position": [40.0, 10.0]}}
    with pytest.raises(SceneError, match=r"line_types\.c\.drag_law = 'loading-functions'.*"
                                         "cable3d option"):
        load_scene(d)
