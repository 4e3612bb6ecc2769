"""Time stepping (explicit RK4, implicit generalized-α) of the linearised dynamics.

All runs use the seed-001 line cut to 20 segments (78 states), which keeps the file fast
and still has the current, drag, added mass and the elliptic fairlead motion.
"""
from __future__ import annotations

import numpy as np
import pytest

import symcable as sc
from symcable.api.analyses import simulate
from symcable.errors import ConvergenceError, SymcableError
from symcable.results.trajectory import Trajectory
from symcable.api.planar_time import ga_coefficients, ga_residual_function, rk4_stability_limit

from conftest import planar_rates, seed001


def _scene():
    d = seed001()
    d["sections"][0]["segments"] = 20
    return d


@pytest.fixture(scope="module")
def line():
    d = _scene()
    return d, sc.build_dynamic_model(sc.load_scene(d))


@pytest.mark.parametrize("method", ["rk4", "generalized-alpha"])
def test_static_state_stays_at_rest(line, method):
    """With the fairlead motion off, the rest state is an exact equilibrium (the rates are
    zero to round-off, 1e-12 of the state scales per second, test_planar_dynamics), so 50
    steps of 0.05 s keep every state below 1e-12 of its scale: round-off cannot grow in 2.5 s
    of a damped, stable linear system."""
    d, m = line
    tr = simulate(d, 50 * 0.05, dt=0.05, method=method, model=m,
                  params=m.with_params(amp_b=[0.0, 0.0]))
    assert tr.status == "converged" and tr.stats["steps"] == 50 and tr.n_t == 51
    assert np.max(np.abs(tr.states) / m.y_scale) < 1e-12
    np.testing.assert_allclose(tr.fairlead_tension, tr.fairlead_tension[0], rtol=1e-12)


def _errors(d, m, method, dts, ref, times, **kw):
    """Max-norm over the saved times of the state error in units of y_scale."""
    out = []
    for dt in dts:
        tr = simulate(d, times[-1], dt=dt, method=method, model=m, save_times=times, **kw)
        np.testing.assert_allclose(tr.time, times, atol=1e-12)
        out.append(np.max(np.abs(tr.states - ref.states) / m.y_scale))
    return np.array(out)


@pytest.mark.parametrize("method, dts, order, tol, kw", [
    ("rk4", [0.02, 0.01, 0.005], 4.0, 0.4, {}),
    ("generalized-alpha", [0.005, 0.0025, 0.00125], 2.0, 0.3, {"rho_inf": 0.5}),
    ("generalized-alpha", [0.005, 0.0025, 0.00125], 2.0, 0.3, {"rho_inf": 0.0}),
])
def test_measured_order_in_time(line, method, dts, order, tol, kw):
    """Error ratio under halving dt, over the first 5 s (half a period) from rest.

    The reference is RK4 at dt = 5/8000 s, whose error (about 1e-9 of the state scales,
    from its own order-4 rate) is far below the errors measured here (1e-3 .. 6e-6). The
    start from rest jolts every mode of the line, up to 31 rad/s, so the asymptotic range
    begins only at omega_max dt < 0.6 (RK4) and < 0.15 (generalized-α); the dt here are in
    it and RK4's are below its stability limit (0.091 s). Tolerances: 0.4 on 4 and 0.3 on 2
    cover the pre-asymptotic drift still seen at the coarsest pair (3.87 and 1.97 measured).
    """
    d, m = line
    times = np.linspace(0.0, 5.0, 11)[1:]
    ref = simulate(d, 5.0, dt=5.0 / 8000, method="rk4", model=m, save_times=times)
    err = _errors(d, m, method, dts, ref, times, **kw)
    rates = np.log2(err[:-1] / err[1:])
    assert np.all(np.abs(rates - order) < tol), (err, rates)


def test_ga_residual_jacobian_matches_finite_differences(line):
    """dr/dydot_next of the generalized-α step residual against central differences at a
    random moving state: the residual is smooth there (a current is on, so no relative
    velocity is zero), the step 1e-6 of the scale gives a truncation error near 1e-12 and a
    round-off near 1e-10 of the Jacobian's row scale, so 1e-6 relative."""
    d, m = line
    fn = ga_residual_function(m, 0.5)
    rng = np.random.default_rng(3)
    y = 0.3 * m.y_scale * rng.standard_normal(m.n_y)
    yd = m.y_scale * rng.standard_normal(m.n_y)
    z = m.y_scale * rng.standard_normal(m.n_y)
    dt, t = 0.05, 1.3
    J = np.array(fn(z, y, yd, t, dt, m.p_value)[1].full())
    h = 1e-6 * m.y_scale
    Jfd = np.zeros_like(J)
    for k in range(m.n_y):
        e = np.zeros(m.n_y)
        e[k] = h[k]
        rp = np.array(fn(z + e, y, yd, t, dt, m.p_value)[0].full()).ravel()
        rm = np.array(fn(z - e, y, yd, t, dt, m.p_value)[0].full()).ravel()
        Jfd[:, k] = (rp - rm) / (2 * h[k])
    scale = np.max(np.abs(J), axis=1, keepdims=True)
    assert np.max(np.abs(J - Jfd) / scale) < 1e-6
    # its structure: alpha_m I - alpha_f gamma dt df/dy, df/dy at y_{n+alpha_f} (the state
    # matrix of the model's Mechanism, from its exact tangents)
    am, af, gamma = ga_coefficients(0.5)
    y_af = y + af * (dt * yd + gamma * dt * (z - yd))
    dfdy = planar_rates(m)[1](y_af, t + af * dt, m.p_value)
    np.testing.assert_allclose(J, am * np.eye(m.n_y) - af * gamma * dt * dfdy, rtol=0, atol=1e-12 * scale.max())


def test_rk4_above_its_stability_limit_raises(line):
    """RK4 at 1.2 times its stability limit amplifies the stiffest mode by about 3 per step:
    a ConvergenceError with a partial result (status "failed", finite up to the last good
    step), never NaN returned as an answer. Below the limit the same run is fine."""
    d, m = line
    lim = rk4_stability_limit(m)
    assert 0.05 < lim < 0.2  # 2 sqrt(2) / 31 rad/s for 20 segments
    with pytest.raises(ConvergenceError, match="stable") as info:
        simulate(d, 20.0, dt=1.2 * lim, method="rk4", model=m)
    part = info.value.partial
    assert isinstance(part, Trajectory) and part.status == "failed"
    assert np.all(np.isfinite(part.states))
    assert info.value.diagnostics["reason"] == "blowup"
    assert 0.0 < info.value.diagnostics["time"] <= 20.0
    ok = simulate(d, 5.0, dt=0.9 * lim, method="rk4", model=m)
    assert ok.status == "converged" and np.all(np.isfinite(ok.states))
    # the default dt is 0.8 times the limit
    assert simulate(d, 1.0, method="rk4", model=m).stats["dt"] <= 0.8 * lim


def test_newton_failure_raises_with_partial(line):
    """A Newton tolerance below round-off cannot be met: ConvergenceError naming the time,
    with the trajectory up to the last good step (here the rest state) as partial."""
    d, m = line
    with pytest.raises(ConvergenceError, match="Newton") as info:
        simulate(d, 1.0, dt=0.1, model=m, newton_tol=1e-300)
    diag = info.value.diagnostics
    assert diag["reason"] == "newton" and diag["time"] == pytest.approx(0.1)
    assert info.value.partial.status == "failed" and info.value.partial.time[-1] == 0.0


def test_slack_is_reported(line):
    """A fairlead motion of 30 m amplitude slackens the line: the trajectory says so (a
    warning with the time and arc length), never silently. It also stretches the top
    segment to a total strain of 0.126, beyond the chain's max_strain 0.1, so its status is
    "invalid" (status changed by the strain-range check: it was "slack"), with both
    warnings. At 20 m the line slackens (total strain down to -0.008) but stays within 0.078
    of stretch: status "slack"."""
    d, m = line
    tr = simulate(d, 10.0, dt=0.1, model=m, params=m.with_params(amp_b=[30.0, 30.0]))
    assert tr.status == "invalid"
    assert any("slack" in w and "s =" in w for w in tr.warnings)
    assert any("max_strain = 0.1" in w and "s =" in w for w in tr.warnings)
    tr = simulate(d, 10.0, dt=0.1, model=m, params=m.with_params(amp_b=[20.0, 20.0]))
    assert tr.status == "slack"
    assert any("slack" in w and "s =" in w for w in tr.warnings)
    assert np.min(tr.axial_force) < 0.0  # the signed force shows the compression


def test_bad_arguments():
    """One-line SymcableErrors naming the argument, the value and the allowed ones."""
    d = _scene()
    with pytest.raises(SymcableError, match="method = 'euler'.*'rk4'.*'generalized-alpha'"):
        simulate(d, 1.0, method="euler")
    with pytest.raises(SymcableError, match="rho_inf = 2.0"):
        simulate(d, 1.0, rho_inf=2.0)
    with pytest.raises(SymcableError, match="dt = -1"):
        simulate(d, 1.0, dt=-1.0)
    with pytest.raises(SymcableError, match="save_every"):
        simulate(d, 1.0, save_every=0)
    # a number written as text is refused, not read (a sweep file's "10" is a typo)
    with pytest.raises(SymcableError, match=r"^duration = '10' s: must be > 0"):
        simulate(d, "10")
    # solve_static's own options, before any build
    for kw, msg in ((dict(tol=-1.0), r"^tol = -1.0 N: must be > 0"),
                    (dict(max_iter="x"), r"^max_iter = 'x': must be a whole number >= 1"),
                    (dict(max_iter=0), r"^max_iter = 0: must be a whole number >= 1")):
        with pytest.raises(SymcableError, match=msg):
            sc.solve_static(d, **kw)


def test_saving_and_round_trip(line, tmp_path, capsys):
    """save_every and save_times pick the samples (rounded to steps); the Trajectory
    survives .npz and .json exactly (floats written by repr); no output on stderr when it
    is not a terminal."""
    d, m = line
    tr = simulate(d, 2.0, dt=0.1, model=m, save_every=4)
    np.testing.assert_allclose(tr.time, [0.0, 0.4, 0.8, 1.2, 1.6, 2.0], atol=1e-12)
    tr2 = simulate(d, 2.0, dt=0.1, model=m, save_times=[0.52, 1.0])
    np.testing.assert_allclose(tr2.time, [0.5, 1.0], atol=1e-12)
    every5 = simulate(d, 2.0, dt=0.1, model=m, save_every=5)
    np.testing.assert_allclose(tr2.states, every5.states[[1, 2]], rtol=1e-13, atol=1e-300)
    assert tr.fairlead_force.shape == (6, 2) and tr.tension.shape == (6, 20)
    # an array built with the trajectory (API change: it was a method taking the model)
    assert tr.positions.shape == (6, 21, 2) and tr.axial_force.shape == (6, 20)
    from symcable.models.planar.dynamics import reconstruct_positions
    np.testing.assert_allclose(tr.positions, reconstruct_positions(m, tr.strain, tr.angle),
                               rtol=0, atol=1e-9)
    assert "fairlead tension" in tr.summary()
    for suffix in (".npz", ".json"):
        back = Trajectory.load(tr.save(tmp_path / f"traj{suffix}"))
        for name in ("time", "states", "fairlead_tension", "fairlead_force", "tension", "angle", "s",
                     "axial_force", "positions"):
            np.testing.assert_array_equal(getattr(back, name), getattr(tr, name))
        assert (back.method, back.dt, back.status, back.warnings) == (tr.method, tr.dt, tr.status, tr.warnings)
        assert back.stats["steps"] == tr.stats["steps"]
    assert capsys.readouterr().err == ""


def test_progress_bar_only_when_asked(line, capsys):
    """progress=True draws a bar on stderr (and ends its line); progress=False and the
    default on a non-terminal stderr (pytest's capture, CI) write nothing."""
    d, m = line
    simulate(d, 0.5, dt=0.1, model=m, progress=True)
    err = capsys.readouterr().err
    assert "simulate generalized-alpha" in err and "5/5" in err and err.endswith("\n")  # tqdm
    simulate(d, 0.5, dt=0.1, model=m, progress=False)
    simulate(d, 0.5, dt=0.1, model=m)
    assert capsys.readouterr() == ("", "")


def test_time_run_and_periodic_solution_agree_on_slack():
    """One slack test for every dynamic result: at 5.3 x the seed-001 amplitude (20
    segments) a time run and the periodic solution both report "slack"; at 5.0 x both are
    "converged" (the signed axial force first reaches zero between 5.125 x and 5.25 x)."""
    import symcable as sc
    d = sc.load_scene(sc.demo_scene_path("seed001")).to_dict()
    d["sections"][0]["segments"] = 20
    for factor, expected in ((5.0, "converged"), (5.3, "slack")):
        d["end_b"]["motion"]["amplitude"] = [2.0 * factor, 1.0 * factor]
        scene = sc.load_scene(d)
        assert sc.solve_periodic(scene).status == expected
        assert sc.simulate(scene, 60.0, dt=0.05).status == expected


def test_sparse_save_times_match_a_dense_run():
    """Saving only a few samples late in a long run (long gaps between saves are cut into
    unsaved checkpoints) gives exactly the states of a run that saves every step: the same
    arithmetic, so equal to round-off (1e-12 of the state scale)."""
    import symcable as sc
    d = sc.load_scene(sc.demo_scene_path("seed001")).to_dict()
    d["sections"][0]["segments"] = 10
    scene = sc.load_scene(d)
    model = sc.build_dynamic_model(scene)
    dt, n = 0.1, 1200
    sparse = sc.simulate(scene, n * dt, dt=dt, model=model, save_times=[100.0, 110.0, 120.0])
    dense = sc.simulate(scene, n * dt, dt=dt, model=model, save_every=1)
    assert sparse.stats["samples"] == 3
    rows = [int(round(t / dt)) for t in sparse.time]
    np.testing.assert_allclose(sparse.states, dense.states[rows], rtol=0,
                               atol=1e-12 * np.max(model.y_scale))


def test_start_rates_with_a_badly_scaled_mass_matrix():
    """v' = M^-1 f at the start for a coupled mass matrix of entries near 1e-13 (a rod's
    rotary inertia): CasADi's sparse QR alone refused it ('nfact' failed: its pivots fall
    under an absolute threshold); scaled by the diagonal it is solved to round-off, and a
    singular one is a ConvergenceError naming the mass matrix."""
    import casadi as ca

    from symcable.mechanism.mechanism import Layout, Mechanism, ParamBlocks, PartLayout, Scales
    from symcable.solvers.integrate import start_rates

    def mech(m):
        q, v, t = ca.SX.sym("q", 2), ca.SX.sym("v", 2), ca.SX.sym("t")
        params = ParamBlocks(("k",), (1,), np.array([1e-9]))
        p = ca.SX.sym("p", 1)
        idx = np.arange(2).reshape(1, 2)
        return Mechanism(name="tiny", q=q, v=v, z=ca.SX.sym("z", 0), t=t, p=p, params=params,
                         mass=ca.SX(ca.DM(m)), force=-p[0] * q, constraint=ca.SX.zeros(0, 1),
                         scales=Scales(q=np.ones(2), v=np.ones(2), z=np.zeros(0), force=1e-9),
                         starts=tuple, layout=Layout(2, {"tiny": PartLayout(
                             "point", np.zeros(1), idx, idx.copy())}))

    M = np.array([[2e-13, 1e-13], [1e-13, 3e-13]])
    q0 = np.array([1.0, -2.0])
    with pytest.raises(RuntimeError, match="nfact"):  # the unscaled solve
        ca.solve(ca.DM(M), ca.DM(-1e-9 * q0), "qr")
    _, a = start_rates(mech(M), q0, np.zeros(2), 0.0, np.array([1e-9]))
    assert np.allclose(M @ a, -1e-9 * q0, rtol=1e-12, atol=0.0)
    with pytest.raises(ConvergenceError, match="the mass matrix is singular"):
        start_rates(mech(np.array([[1.0, 1.0], [1.0, 1.0]])), q0, np.zeros(2), 0.0,
                    np.array([1e-9]))
