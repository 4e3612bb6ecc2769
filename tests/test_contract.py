"""Solver contract suite: the generic solvers on toy mechanisms with known answers.

Toys (symcable.models.toys.toys): a pendulum written as a constrained point mass (n_z = 1), a
chain of point masses and springs assembled from parts (quadratic drag, gravity, a moving
end), and the forced Duffing oscillator. Every solver here sees only the Mechanism.
"""
from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.special import ellipk

from symcable.errors import ConvergenceError, SymcableError
from symcable.models.toys import toys
from symcable.mechanism.assembly import Prescribed, Shared, assemble
from symcable.mechanism.mechanism import Start
from symcable.solvers.equilibrium import solve_equilibrium
from symcable.solvers.integrate import integrate
from symcable.solvers.linearize import mechanism_modes, output_sensitivity
from symcable.solvers.options import RK4, GeneralizedAlpha

G = 9.80665


def _order(errors, factor=2.0):
    e = np.asarray(errors)
    return np.log(e[:-1] / e[1:]) / np.log(factor)


# ---------------------------------------------------------------------------- pendulum
def test_pendulum_statics_and_stability():
    """Hanging at (0, -L) with tension m g (to 1e-9 relative: the Newton tolerance is 1e-9 of
    the weight). The upright equilibrium satisfies the equations too, but is unstable: the
    solver must refuse it, or flag it when asked not to require stability."""
    L, m = 2.0, 3.0
    mech = toys.pendulum(L, m)
    eq = solve_equilibrium(mech)
    assert eq.status == "converged" and eq.stats["stable"]
    np.testing.assert_allclose(eq.q, [0.0, -L], atol=1e-9 * L)
    assert eq.outputs["tension"] == pytest.approx(m * G, rel=1e-9)
    up = Start(np.array([0.0, L]), np.array([-m * G / L]), mech.static_p, "upright")
    with pytest.raises(ConvergenceError, match="unstable"):
        solve_equilibrium(mech, starts=[up])
    eq_up = solve_equilibrium(mech, starts=[up], require_stable=False)
    assert not eq_up.stats["stable"] and "unstable" in eq_up.warnings[0]


def test_pendulum_mode():
    """One mode, f = sqrt(g/L)/(2 pi), exactly (to round-off: the constraint's null space and
    the Cholesky solve are exact in exact arithmetic)."""
    L = 1.5
    mech = toys.pendulum(L)
    modes = mechanism_modes(mech, solve_equilibrium(mech))
    assert modes.frequencies.size == 1
    assert modes.frequencies[0] == pytest.approx(math.sqrt(G / L) / (2 * math.pi), rel=1e-10)


def _angle_reference(theta0, L, times):
    sol = solve_ivp(lambda t, y: [y[1], -G / L * math.sin(y[0])], (0, times[-1]), [theta0, 0.0],
                    t_eval=times, rtol=1e-12, atol=1e-13, method="DOP853")
    return sol.y[0]


def _crossing_period(t, x):
    """Period from the upward zero crossings (linear interpolation), averaged."""
    i = np.flatnonzero((x[:-1] < 0) & (x[1:] >= 0))
    tc = t[i] - x[i] * (t[i + 1] - t[i]) / (x[i + 1] - x[i])
    return float(np.mean(np.diff(tc)))


@pytest.mark.parametrize("theta0", [0.01, 2.0])
def test_pendulum_period(theta0):
    """Period of the constrained pendulum released from rest at theta0, measured from zero
    crossings of a generalized-alpha run (rho_inf = 0.9, T/1600), against the complete
    elliptic integral T = 4 sqrt(L/g) K(sin^2(theta0/2)) (2 pi sqrt(L/g) for small theta0).
    The scheme's period error is second order, O((omega h)^2) = O(1.5e-5) at T/1600 (measured
    3.8e-5 at T/800 for theta0 = 2); crossing interpolation adds ~1e-6. Tolerance 2e-5."""
    L = 1.0
    mech = toys.pendulum(L)
    T = 4 * math.sqrt(L / G) * ellipk(math.sin(theta0 / 2) ** 2)
    dt = T / 1600
    tr = integrate(mech, 1600 * 4 * dt, dt, method=GeneralizedAlpha(rho_inf=0.9),
                   q0=[L * math.sin(theta0), -L * math.cos(theta0)])
    measured = _crossing_period(tr.time, tr.outputs["angle"])
    assert measured == pytest.approx(T, rel=2e-5)
    if theta0 < 0.1:
        assert T == pytest.approx(2 * math.pi * math.sqrt(L / G), rel=1e-5)


def test_pendulum_constraint_over_1000_steps_and_order():
    """The position constraint is imposed at every step: over 1000 steps |g| stays at the
    Newton tolerance (|g| <= 1e-10 L^2, g = (|q|^2 - L^2)/2), with no drift. The angle at t = 2 s converges at second order in dt (observed order within
    [1.8, 2.3] for dt from T/50 to T/400)."""
    L, theta0 = 1.0, 0.8
    mech = toys.pendulum(L)
    q0 = [L * math.sin(theta0), -L * math.cos(theta0)]
    opts = GeneralizedAlpha(rho_inf=0.8)
    dt = 2.0 / 1000
    tr = integrate(mech, 2.0, dt, method=opts, q0=q0)
    assert tr.stats["steps"] == 1000
    assert tr.stats["max_constraint"] <= 1e-10 * L ** 2
    errs = []
    for n in (50, 100, 200, 400):
        tr = integrate(mech, 2.0, 2.0 / n, method=opts, q0=q0)
        ref = _angle_reference(theta0, L, np.array([0.0, 2.0]))[-1]
        errs.append(abs(tr.outputs["angle"][-1] - ref))
    orders = _order(errs)
    assert np.all((orders > 1.8) & (orders < 2.3)), (errs, orders)


# ---------------------------------------------------------------------------- chain
def test_chain_modes_closed_form():
    """A straight chain of N masses and N + 1 springs under tension T = k (a - L0), no gravity:
    axial modes 2 sqrt(k/m) sin(j pi/(2(N+1))), transverse modes the same with k -> T/a. All
    2N frequencies to 1e-10 relative (exact up to round-off)."""
    N, m, k, span = 5, 2.0, 300.0, 6.0
    mech = toys.spring_chain(N, mass=m, stiffness=k, span=span)
    eq = solve_equilibrium(mech)
    a = span / (N + 1)
    T = k * (a - 0.8 * a)
    j = np.arange(1, N + 1)
    s = np.sin(j * np.pi / (2 * (N + 1)))
    expected = np.sort(np.concatenate([2 * np.sqrt(k / m) * s, 2 * np.sqrt(T / a / m) * s]))
    modes = mechanism_modes(mech, eq)
    np.testing.assert_allclose(modes.frequencies * 2 * np.pi, expected, rtol=1e-10)


def _chain_with_gravity(**kw):
    return toys.spring_chain(4, mass=1.0, stiffness=200.0, span=6.0, gravity=G, **kw)


def test_chain_statics_force_balance_and_relaxed_dynamics():
    """Statics of the sagging chain: the end forces carry the whole weight (global balance to
    the Newton tolerance, 1e-9 of the force scale), and the static shape is where the damped
    dynamics come to rest (generalized-alpha with rho_inf = 0 and drag smoothed at 0.1 m/s,
    i.e. linear damping 0.5 N s/m at small speed, decay e^(-0.25 t): after 100 s from the
    straight line (0.6 m of sag) less than 1e-7 m is left)."""
    mech = _chain_with_gravity(drag=5.0, drag_speed=0.1)
    eq = solve_equilibrium(mech)
    total = eq.outputs["left.force"] + eq.outputs["right.force"]
    np.testing.assert_allclose(total, [0.0, -4 * 1.0 * G], atol=1e-8 * 200.0)
    tr = integrate(mech, 100.0, 0.1, method=GeneralizedAlpha(rho_inf=0.0), save_every=100)
    np.testing.assert_allclose(tr.q[-1], eq.q, atol=1e-7)


def test_chain_order_galpha_and_rk4():
    """On the nonlinear chain (quadratic drag, gravity, a harmonically moving end, from the
    straight line), generalized-alpha converges at second order and RK4 at fourth, against
    an RK4 run at dt/32 of the coarsest. The fastest mode (28 rad/s) puts dt = 2 s/100 at
    omega h = 0.56, where both are in their asymptotic range. Orders asserted in [1.8, 2.3]
    and [3.6, 4.4]."""
    mech = _chain_with_gravity(drag=2.0, amplitude=[0.2, 0.1], omega=3.0)
    ref = integrate(mech, 2.0, 2.0 / 3200, method=RK4()).q[-1]
    e_ga, e_rk = [], []
    for n in (100, 200, 400):
        e_ga.append(np.max(np.abs(integrate(mech, 2.0, 2.0 / n, method=GeneralizedAlpha(0.8)).q[-1] - ref)))
        e_rk.append(np.max(np.abs(integrate(mech, 2.0, 2.0 / n, method=RK4()).q[-1] - ref)))
    o_ga, o_rk = _order(e_ga), _order(e_rk)
    assert np.all((o_ga > 1.8) & (o_ga < 2.3)), (e_ga, o_ga)
    assert np.all((o_rk > 3.6) & (o_rk < 4.4)), (e_rk, o_rk)


def test_end_stiffness_closed_form_and_differences():
    """The stiffness the straight chain presents at its right end: axial k/(N+1) (springs in
    series) and transverse T/span (a taut string), exact from the implicit function theorem
    (1e-9 relative), and equal to central differences of solve_equilibrium (step 1e-4 m: the
    difference error is O(h^2) ~ 1e-8 relative; tolerance 1e-6)."""
    N, k, span = 5, 300.0, 6.0
    mech = toys.spring_chain(N, stiffness=k, span=span)
    eq = solve_equilibrium(mech)
    Kend = -output_sensitivity(mech, eq, "right.force", "right.position")
    T = k * 0.2 * span / (N + 1)
    np.testing.assert_allclose(np.diag(Kend), [k / (N + 1), T / span], rtol=1e-9)
    h = 1e-4
    fd = np.zeros((2, 2))
    for j in range(2):
        fs = []
        for sgn in (1, -1):
            pos = np.array([span, 0.0])
            pos[j] += sgn * h
            p = mech.params.with_values(mech.static_p, **{"right.position": pos})
            fs.append(solve_equilibrium(mech, p, starts=[Start(eq.q, eq.z, p, "eq")]).outputs["right.force"])
        fd[:, j] = -(fs[0] - fs[1]) / (2 * h)
    np.testing.assert_allclose(Kend, fd, rtol=1e-6, atol=1e-6 * k)


# ---------------------------------------------------------------------------- assembly
def test_assembly_moving_base_equals_hand_written():
    """A mass on a spring whose other end is driven x_b(t) = A cos(w t): assembled from a
    point mass and a spring with a Prescribed joint, it must follow m x'' = -k (x - x_b - L0)
    (scipy reference at rtol 1e-11; generalized-alpha at T/2000 has an error ~1e-6 of the
    amplitude: tolerance 1e-4 m on an amplitude of ~0.1 m)."""
    m, k, L0, A, w = 2.0, 50.0, 1.0, 0.05, 3.0
    parts = [toys.point_mass("bob", [L0], m), toys.spring("s", [0.0], [L0], k, L0)]
    mech = assemble(parts, [Shared(("bob", 0), ("s", 1)),
                            Prescribed("base", ("s", 0), [0.0], amplitude=[A], omega=w)])
    assert mech.n_q == 1
    sol = solve_ivp(lambda t, y: [y[1], -k / m * (y[0] - A * math.cos(w * t) - L0)], (0, 4.0),
                    [L0 + A, 0.0], t_eval=[4.0], rtol=1e-11, atol=1e-12)
    tr = integrate(mech, 4.0, 4.0 / 4000, method=GeneralizedAlpha(1.0), q0=[L0 + A])
    assert tr.q[-1, 0] == pytest.approx(sol.y[0, -1], abs=1e-4)
    # the force the spring exerts on the base: k (x - x_b - L0), along +x
    x_b = A * math.cos(w * tr.time[-1])
    assert tr.outputs["base.force"][-1] == pytest.approx(k * (tr.q[-1, 0] - x_b - L0), rel=1e-12)


def test_assembly_errors():
    """Bad assemblies are one-line SymcableErrors naming the offending value."""
    a = toys.point_mass("a", [0.0, 0.0], 1.0)
    with pytest.raises(SymcableError, match="two parts are named 'a'"):
        assemble([a, toys.point_mass("a", [1.0, 0.0], 1.0)])
    with pytest.raises(SymcableError, match="no part named 'b'"):
        assemble([a], [Shared(("a", 0), ("b", 0))])
    with pytest.raises(SymcableError, match="has 1 nodes"):
        assemble([a], [Prescribed("x", ("a", 3), [0.0, 0.0])])
    with pytest.raises(SymcableError, match="needs 2 entries"):
        assemble([a], [Prescribed("x", ("a", 0), [0.0])])
    with pytest.raises(SymcableError, match="rk4"):
        integrate(toys.pendulum(), 1.0, 0.1, method=RK4())
    with pytest.raises(SymcableError, match="needs rho_inf < 1"):
        integrate(toys.pendulum(), 1.0, 0.1, method=GeneralizedAlpha(1.0))


# ---------------------------------------------------------------------------- duffing
def test_duffing_orders():
    """Forced Duffing oscillator from rest over 5 s: generalized-alpha second order, RK4
    fourth order, against scipy's DOP853 at rtol 1e-12."""
    mech = toys.duffing()
    c, k, k3, F0, w = 0.2, 1.0, 1.0, 0.5, 1.2
    ref = solve_ivp(lambda t, y: [y[1], -c * y[1] - k * y[0] - k3 * y[0] ** 3 + F0 * math.cos(w * t)],
                    (0, 5.0), [0.0, 0.0], t_eval=[5.0], rtol=1e-12, atol=1e-13, method="DOP853").y[0, -1]
    e_ga, e_rk = [], []
    for n in (40, 80, 160):
        e_ga.append(abs(integrate(mech, 5.0, 5.0 / n, method=GeneralizedAlpha(0.8), q0=[0.0]).q[-1, 0] - ref))
        e_rk.append(abs(integrate(mech, 5.0, 5.0 / n, method=RK4(), q0=[0.0]).q[-1, 0] - ref))
    o_ga, o_rk = _order(e_ga), _order(e_rk)
    assert np.all((o_ga > 1.8) & (o_ga < 2.3)), (e_ga, o_ga)
    assert np.all((o_rk > 3.6) & (o_rk < 4.4)), (e_rk, o_rk)


def test_options_are_validated():
    """Options are validated once, with one-line messages."""
    with pytest.raises(SymcableError, match=r"rho_inf = 1.5: must be in \[0.0, 1.0\]"):
        GeneralizedAlpha(rho_inf=1.5)
    with pytest.raises(SymcableError, match="must be > 0"):
        integrate(toys.duffing(), -1.0, 0.1)


def _duffing_ref(t_end, x0):
    c, k, k3, F0, w = 0.2, 1.0, 1.0, 0.5, 1.2
    return solve_ivp(lambda t, y: [y[1], -c * y[1] - k * y[0] - k3 * y[0] ** 3 + F0 * math.cos(w * t)],
                     (0, t_end), [x0, 0.0], t_eval=[t_end], rtol=1e-13, atol=1e-14,
                     method="DOP853").y[0, -1]


def test_galpha_error_estimate_tracks_local_error():
    """One generalized-alpha step from an exact state: the estimate (beta - 1/6) h^2 |a1 - a0|
    matches the true local error of the position within a factor 1.5 for h from 0.05 to
    0.2 s on Duffing (measured within 10 %; the estimate omits higher-order terms that grow
    with h)."""
    mech = toys.duffing()
    for h in (0.05, 0.1, 0.2):
        tr = integrate(mech, h, h, q0=[1.5])
        true = abs(tr.q[-1, 0] - _duffing_ref(h, 1.5))
        assert true / 1.5 <= tr.stats["max_error_estimate"] <= 1.5 * true, (h, true)


def test_adaptive_steps_follow_the_tolerance():
    """With tol, steps adapt: the global error at 20 s falls with tol (at tol = 1e-6 below
    1e-4 m, measured 8.5e-5), the step count grows like tol^(-1/3) for a second-order
    method with local error control (ratio per decade in [1.6, 2.6], measured 1.9-2.1), and
    stats report the steps taken."""
    mech = toys.duffing()
    ref = _duffing_ref(20.0, 1.5)
    runs = {tol: integrate(mech, 20.0, tol=tol, q0=[1.5]) for tol in (1e-4, 1e-5, 1e-6)}
    errs = [abs(tr.q[-1, 0] - ref) for tr in runs.values()]
    steps = [tr.stats["steps"] for tr in runs.values()]
    assert errs[0] > errs[1] > errs[2] and errs[2] < 1e-4
    ratios = np.array(steps[1:]) / np.array(steps[:-1])
    assert np.all((ratios > 1.6) & (ratios < 2.6)), steps
    st = runs[1e-6].stats
    assert st["dt_min"] <= st["dt_max"] and st["max_error_estimate"] <= 1e-6
    assert runs[1e-6].time[-1] == pytest.approx(20.0, rel=1e-12)
    with pytest.raises(SymcableError, match="adaptive steps need generalized-alpha"):
        integrate(mech, 1.0, tol=1e-6, method=RK4())


# ---------------------------------------------------------------------------- planar
@pytest.mark.parametrize("name", ["oc3", "seed001"])
def test_planar_statics_through_the_generic_solver(name):
    """The planar formulation's statics as a Mechanism (models/static_mechanism.py), solved by
    the generic solve_equilibrium from the formulation's own starts (closed-form catenary with
    seabed): the same state as the planar solve_static to its tolerance (end forces within
    1e-9 relative: both converge Newton to ~1e-12 of the tension from the same start)."""
    import symcable as sc
    from symcable.models import build_model
    from symcable.models.planar.static import static_mechanism

    scene = sc.load_scene(sc.demo_scene_path(name))
    st = sc.solve_static(scene, codegen=False)
    mech = static_mechanism(build_model(scene))
    eq = solve_equilibrium(mech)
    assert eq.status == "converged" and eq.stats["stable"] is None  # no mass: not judged
    np.testing.assert_allclose(np.ravel(eq.outputs["end_force_b"]), st.fairlead_force, rtol=1e-9)
    np.testing.assert_allclose(np.ravel(eq.outputs["end_force_a"]), st.anchor_force, rtol=1e-9,
                               atol=1e-9 * st.fairlead_tension)


def test_output_sensitivity_at_a_singular_jacobian_says_so(monkeypatch):
    """Where the static Jacobian is singular (a neutral mode), the derivative is not unique:
    one SymcableError naming the output and the block, not numpy's LinAlgError."""
    from symcable.mechanism.functions import functions
    mech = toys.spring_chain(3, stiffness=300.0, span=4.0)
    eq = solve_equilibrium(mech)
    F = functions(mech)
    jac = F.static_jacobian
    monkeypatch.setattr(type(F), "static_jacobian", property(
        lambda self: (lambda x, p: (jac(x, p)[0], 0.0 * jac(x, p)[1]))), raising=False)
    with pytest.raises(SymcableError, match="singular.*'right.force'.*'right.position'"):
        output_sensitivity(mech, eq, "right.force", "right.position")
