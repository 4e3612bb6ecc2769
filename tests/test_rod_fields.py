"""The seed's field variables and its field equations (7)-(10) on the discrete rod
(:mod:`symcable.api.rod_fields`; issue 14: "the seed's field equations (7)-(10) hold on the
discrete solution, with the residual shrinking at second order as segments are refined").

Statics: a heavy cantilever with two principal stiffnesses whose clamp's frame is turned
30 deg (bending and twist coupled: the moment q has a twisting part), sagging far
(w L^3 / EI = 10). Time: the frame's angular velocity against the rate of the material
directors between samples.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

from symcable.api.rod_fields import field_residuals, rod_fields, trajectory_fields
from test_rod_statics import EI, L, cantilever, solve

W = 10.0 * EI / L**3  # N/m


def _static(segments: int):
    d = cantilever(weight=W, segments=segments, twist=30.0)
    d["line_types"]["beam"]["EI"] = [EI, 2 * EI]
    mech, eq = solve(d)
    fl = rod_fields(mech, eq.q, None, 0.0, eq.p)
    return fl, field_residuals(fl, mass=1.0, force=(0.0, 0.0, -W))


@pytest.fixture(scope="module")
def refined():
    return {n: _static(n) for n in (10, 20, 40)}


def _worst(r, sl=slice(None)):
    return float(np.max(np.linalg.norm(r[sl], axis=1)))


def test_moment_balance_second_order(refined):
    """Eq. (9), dq/ds + t x f = 0, across the edges: measured max |residual| over the
    interior edges 0.53, 0.21, 0.065, 0.0175 N m/m at 10, 20, 40, 80 segments (orders 1.3,
    1.7, 1.9: second order once resolved), against a moment gradient of up to 25 N m/m.
    The edge at the clamp is first order (0.47, 0.46, 0.30, 0.17: the clamp's vertex has
    half a cell, ds / 2, so its moment sits off the node by O(ds)); the free end's edge
    holds to the solve's tolerance (q = 0 beyond it). (w = 12.5 N/m.) Asserted: the interior order from 20
    to 40 within 0.3 of 2, the clamp's edge below 2 % of the scale at 40 segments and
    falling."""
    r9 = {n: refined[n][1]["9"] for n in refined}
    inner = {n: _worst(r9[n], slice(1, -1)) for n in r9}
    assert abs(math.log2(inner[20] / inner[40]) - 2.0) < 0.3, inner
    clamp = {n: _worst(r9[n][:1]) for n in r9}
    assert clamp[40] < 0.02 * W * L and clamp[40] < clamp[20], clamp
    assert _worst(r9[40][-1:]) < 1e-6 * W * L


def test_force_balance_exact(refined):
    """Eq. (10), df/ds + F = 0, across the interior nodes: the discrete rod's internal force
    (the axial force and the vertex terms straddling the cut) balances the lumped weight
    exactly, so the residual is the static solve's (measured 7e-7, 7e-7, 2.4e-6 N/m at 10,
    20, 40 segments, against w = 12.5 N/m: the solve's force tolerance over lbar). Asserted
    below 1e-5 w."""
    for n, (_, r) in refined.items():
        assert _worst(r["10"]) < 1e-5 * W, n


def _weight_moment(fl) -> np.ndarray:
    """The moment of the lumped weight about the clamp (node 0), N m: the moment the rod
    beyond the clamp exerts on it, q at s = 0."""
    X, ds = fl.positions, fl.ds
    lump = np.r_[ds[0] / 2, 0.5 * (ds[:-1] + ds[1:]), ds[-1] / 2]
    F = np.zeros_like(X)
    F[:, 2] = -W * lump
    return np.sum(np.cross(X - X[0], F), axis=0)


def test_static_fields(refined):
    """At rest v, omega and Eqs. (7)-(8) vanish; the tension f . t and shear |f - (f . t) t|
    split f; the moment q at the clamp is the moment of the weight about it (the root
    moment: measured relative errors 4.8e-3, 1.2e-3, 3.0e-4 at 10, 20, 40 segments, second
    order: asserted 1e-3 at 40 and the order within 0.3 of 2); a free end has no vertex and
    no moment; the material frames are orthonormal."""
    fl, r = refined[40]
    assert np.max(np.abs(fl.velocity)) == 0 and np.max(np.abs(fl.angular_velocity)) < 1e-12
    assert _worst(r["7"]) < 1e-12 and _worst(r["8"]) < 1e-12
    f = fl.internal_force
    assert np.allclose(fl.tension**2 + fl.shear**2, np.sum(f * f, axis=1))
    err = {}
    for n, (g, _) in refined.items():
        M = _weight_moment(g)
        err[n] = np.linalg.norm(g.moment[0] - M) / np.linalg.norm(M)
    assert err[40] < 1e-3 and abs(math.log2(err[20] / err[40]) - 2.0) < 0.3, err
    assert fl.vertex[0] and not fl.vertex[-1] and np.all(fl.moment[-1] == 0)
    assert np.allclose(np.linalg.norm(fl.m1, axis=1), 1) and np.allclose(
        np.sum(fl.m1 * fl.tangent, axis=1), 0, atol=1e-12)


def test_angular_velocity_is_the_frames_rate():
    """omega (exact on the state, CasADi) against the material directors' rate between
    samples of a run (central differences, dt = 0.5 ms): dm1/dt = omega x m1 and dt/dt =
    omega x t to 1e-4 of |omega| (the differences' O(dt^2) error: measured 1.5e-6 and 9.5e-6
    at 0.5 ms, 5.8e-6 and 4.1e-5 at 1 ms); the tumbling, anisotropic rod of
    tests/test_rod_api_reanchor.py. The dynamic residuals of Eqs. (7)-(10) are computed
    (shapes checked) but not asserted: module note in studies/rod_notes/wire14.md (they are dominated by
    the unresolved axial and twist modes a start off equilibrium rings, and do not shrink
    with the segments at a fixed step)."""
    from test_rod_api_reanchor import _spinning
    from symcable.solvers.integrate import integrate
    from symcable.solvers.options import GeneralizedAlphaFirstOrder
    mech, q0, v0, p = _spinning(EI=[1.0, 1.5], axis=[0.0, 1.0, 0.3])
    tr = integrate(mech, 0.1, 5e-4, method=GeneralizedAlphaFirstOrder(rho_inf=0.5, tol=1e-12),
                   q0=q0, v0=v0, p=p, codegen=False)
    k = tr.time.size // 2
    a, b, c = (trajectory_fields(mech, tr, kk, p) for kk in (k - 1, k, k + 1))
    dt = c.time - a.time
    w = b.angular_velocity
    for x_a, x_b, x_c in ((a.m1, b.m1, c.m1), (a.tangent, b.tangent, c.tangent)):
        err = np.max(np.abs((x_c - x_a) / dt - np.cross(w, x_b)))
        assert err < 1e-4 * np.max(np.linalg.norm(w, axis=1)), err
    r = field_residuals([a, b, c], mass=1.0, force=(0.0, 0.0, -1.0),
                        twist_inertia=1.0 * 0.02**2 / 8)
    assert set(r) == {"7", "8", "9", "10"} and r["8"].shape == (7, 3)
