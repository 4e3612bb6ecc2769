"""Linear waves (``[environment.waves]``): the dispersion relation, the kinematics against
their closed forms, an irregular sea's spectrum recovered from its elevation series, the
Morison loads of waves on a line and a free point, the scene contract and its errors."""
from __future__ import annotations

import math

import casadi as ca
import numpy as np
import pytest

import symcable as sc
from symcable.analytic.waves import default_band, jonswap, spectral_moment, wave_number
from symcable.errors import SceneError
from symcable.models.common.waves import wave_block, wave_function
from symcable.scene import scene_to_toml
from symcable.scene.waves import Waves

G = 9.80665


def _closed_form(c, X, t, h):
    """Airy kinematics summed over components by the textbook cosh/sinh formulas."""
    eta, u, a = 0.0, np.zeros(3), np.zeros(3)
    for A, w, k, ph, b in zip(c.amplitude, c.omega, c.k, c.phase, c.direction):
        th = k * (X[0] * math.cos(b) + X[1] * math.sin(b)) - w * t + ph
        if h is None:
            C = S = math.exp(k * min(X[2], 0.0))
        else:
            z = min(X[2], 0.0)
            C, S = (math.cosh(k * (z + h)) / math.sinh(k * h),
                    math.sinh(k * (z + h)) / math.sinh(k * h))
        eta += A * math.cos(th)
        u += A * w * np.array([C * math.cos(th) * math.cos(b), C * math.cos(th) * math.sin(b),
                               S * math.sin(th)])
        a += A * w * w * np.array([C * math.sin(th) * math.cos(b),
                                   C * math.sin(th) * math.sin(b), -S * math.cos(th)])
    return eta, u, a


def test_dispersion_to_round_off_and_its_limits():
    """omega^2 = g k tanh(k h) to 4 ulp of omega^2 over periods 2-30 s and depths 5-5000 m;
    deep water k = omega^2 / g, shallow water omega / sqrt(g h) (to 0.1 % at k h < 0.055)."""
    w = 2 * math.pi / np.linspace(2.0, 30.0, 57)
    for h in (5.0, 50.0, 320.0, 5000.0):
        k = wave_number(w, h)
        np.testing.assert_allclose(G * k * np.tanh(k * h), w * w, rtol=4e-16 * 4, atol=0)
    np.testing.assert_allclose(wave_number(w, None), w * w / G, rtol=1e-15)
    w_long = 2 * math.pi / 200.0
    assert wave_number(w_long, 5.0) * 5.0 < 0.055
    np.testing.assert_allclose(wave_number(w_long, 5.0), w_long / math.sqrt(G * 5.0), rtol=1e-3)


@pytest.mark.parametrize("depth", [60.0, None])
def test_kinematics_equal_the_closed_forms(depth):
    """Symbolic (the lines' equations) and NumPy (:func:`wave_kinematics`) kinematics of a
    three-component, three-direction sea equal the cosh/sinh closed forms to 1e-12 of
    their scale (a omega, a omega^2): the same sums in another order."""
    d = {"amplitudes": [1.0, 0.4, 0.2], "omegas": [0.5, 0.9, 1.6], "phases_deg": [10, 200, 77],
         "directions_deg": [0.0, 30.0, -120.0], "kind": "components"}
    w = Waves(**{k: tuple(v) if isinstance(v, list) else v for k, v in d.items()})
    c = w.components_in(depth, G)
    f = wave_function(w.count, depth is None, "vertical")
    block = wave_block(w, depth, G)
    pts = np.array([[0.0, 0.0, -10.0], [40.0, -15.0, -55.0], [-7.0, 3.0, -0.3],
                    [5.0, 5.0, 2.0]])  # the last above z = 0: vertical stretching
    times = [0.0, 3.7, 41.2]
    kin = sc.wave_kinematics(w if depth is None else _scene_dict(depth, d), pts, times)
    for i, t in enumerate(times):
        for j, X in enumerate(pts):
            eta, u, a = _closed_form(c, X, t, depth)
            sym = [np.ravel(np.asarray(v)) for v in f(X, t, block, 1.0, 0.0)]
            for got in ((sym[0][0], sym[1], sym[2]),
                        (kin.elevation[i, j], kin.velocity[i, j], kin.acceleration[i, j])):
                assert abs(got[0] - eta) <= 1e-12
                np.testing.assert_allclose(got[1], u, rtol=0, atol=1e-12 * 1.6)
                np.testing.assert_allclose(got[2], a, rtol=0, atol=1e-12 * 2.6)


def test_linear_theory_boundary_conditions():
    """The kinematics satisfy linear theory: at z = 0 the vertical velocity is d(eta)/dt,
    at the seabed it is zero, and the flow has no divergence (central differences of step
    1e-3 m or s: truncation near 1e-7 of the scale)."""
    d = {"kind": "regular", "height": 3.0, "period": 9.0, "direction_deg": 25.0}
    s = _scene_dict(55.0, d)
    x = np.array([12.0, -4.0, 0.0])
    eps = 1e-3
    k = sc.wave_kinematics(s, [x, [12.0, -4.0, -55.0]], [5.0 - eps, 5.0, 5.0 + eps])
    deta = (k.elevation[2, 0] - k.elevation[0, 0]) / (2 * eps)
    assert abs(k.velocity[1, 0, 2] - deta) < 1e-6
    assert abs(k.velocity[1, 1, 2]) < 1e-12
    p = np.array([3.0, 1.0, -12.0])
    e = np.eye(3) * eps
    div = sum((sc.wave_kinematics(s, [p + e[i]], 2.0).velocity[0, 0, i]
               - sc.wave_kinematics(s, [p - e[i]], 2.0).velocity[0, 0, i]) / (2 * eps)
              for i in range(3))
    assert abs(div) < 1e-7


def test_wheeler_maps_the_surface_to_the_mean_water_level():
    """Wheeler stretching: at the instantaneous surface the kinematics are linear theory's at
    z = 0, at the seabed unchanged (exact by construction: 1e-12)."""
    d = {"kind": "regular", "height": 6.0, "period": 10.0}
    s, v = _scene_dict(50.0, dict(d, stretching="wheeler")), _scene_dict(50.0, d)
    for t in (1.0, 3.5, 7.0):
        eta = sc.wave_kinematics(v, [0.0, 0.0, 0.0], t).elevation[0, 0]
        at_surface = sc.wave_kinematics(s, [0.0, 0.0, eta], t)
        at_zero = sc.wave_kinematics(v, [0.0, 0.0, 0.0], t)
        np.testing.assert_allclose(at_surface.velocity, at_zero.velocity, atol=1e-12)
        np.testing.assert_allclose(sc.wave_kinematics(s, [0, 0, -50.0], t).velocity,
                                   sc.wave_kinematics(v, [0, 0, -50.0], t).velocity, atol=1e-12)


def test_irregular_sea_spectrum_recovered_from_its_series():
    """A JONSWAP sea (Hs 5 m, Tp 11 s, gamma 3.3, 400 components): its 3-hour elevation
    series gives Hs to 1 % and, in bands of 20 components (0.1 rad/s) holding at least 5 % of
    the largest band's energy, the spectrum's energy within 5 % (the periodogram of the whole
    record; its remaining spread is the finite record's, 3.2 % at most over seeds 0-5)."""
    w = Waves(kind="jonswap", hs=5.0, tp=11.0, gamma=3.3, components=400, seed=4)
    dt = 0.25
    t = np.arange(0.0, 3 * 3600.0, dt)
    eta = sc.wave_kinematics(w, [0.0, 0.0, 0.0], t).elevation[:, 0]
    assert abs(4.0 * eta.std() / 5.0 - 1.0) < 0.01
    E = np.abs(np.fft.rfft(eta)) ** 2 / t.size ** 2 * 2.0
    om = 2 * math.pi * np.fft.rfftfreq(t.size, dt)
    lo, hi = default_band(11.0)
    edges = lo + (hi - lo) / 400 * np.arange(0, 401, 20)
    wf = np.linspace(lo, hi, 40001)
    S = jonswap(wf, 5.0, 11.0, 3.3)
    ref = np.array([spectral_moment(wf[(wf >= a) & (wf <= b)], S[(wf >= a) & (wf <= b)])
                    for a, b in zip(edges[:-1], edges[1:])])
    got = np.array([E[(om >= a) & (om < b)].sum() for a, b in zip(edges[:-1], edges[1:])])
    big = ref > 0.05 * ref.max()
    assert big.sum() >= 6
    assert np.max(np.abs(got[big] / ref[big] - 1.0)) < 0.05


def _scene_dict(depth, waves, **line) -> dict:
    d = {"model": "cable3d", "environment": {"depth": depth, "waves": waves},
         "line_types": {"r": dict({"mass": 30.0, "diameter": 0.1, "EA": 1e10,
                                   "cd_normal": 0.0, "cd_tangential": 0.0, "ca_normal": 1.0},
                                  **line)},
         "sections": [{"type": "r", "length": 48.5, "segments": 40}],
         "end_a": {"condition": "pinned", "position": [0.0, 0.0, -50.0]},
         "end_b": {"condition": "pinned", "position": [0.0, 0.0, -1.0]}}
    if depth is None:
        d["environment"].pop("depth")
    return d


def _harmonic(t, f, w, t0):
    """The first harmonic's sine and cosine amplitudes of f(t) over whole periods from t0."""
    m = t >= t0 - 1e-9
    span = t[m][-1] - t[m][0]
    return (np.trapezoid(f[m] * np.sin(-w * t[m]), t[m]) * 2 / span,
            np.trapezoid(f[m] * np.cos(w * t[m]), t[m]) * 2 / span)


def _inertia_sum(h, H, T, N, L0) -> float:
    """The riser's Morison inertia amplitude rho (pi/4) d^2 (1 + Ca) a_x (d 0.1 m, Ca 1)
    summed over its N elements' midpoints, on the unstretched length L0 (49 m span), N."""
    w = 2 * math.pi / T
    k = wave_number(w, h)
    zm = -h + (np.arange(N) + 0.5) * 49.0 / N
    vol = 1025.0 * math.pi / 4 * 0.01 * L0 / N
    return float(np.sum(vol * 2.0 * (H / 2) * w * w * np.cosh(k * (zm + h)) / math.sinh(k * h)))


def test_wave_inertia_on_a_taut_riser():
    """A vertical riser, 49 m from the seabed at 50 m depth, tensioned to 1e8 N (so it barely
    moves), no drag, in a regular wave (H 4 m, T 8 s): the first harmonic of the supports'
    horizontal force is the Morison inertia rho (pi/4) d^2 (1 + Ca) a_x summed over the
    elements' midpoints on the unstretched length, within 2e-4 (the line's own response,
    measured 4e-5 at this tension); its out-of-phase part below 2e-4 of it. The midpoint sum
    is the closed-form integral to 2.5e-4 here (second order in the segment)."""
    h, H, T, N, L0 = 50.0, 4.0, 8.0, 40, 48.5
    r = sc.simulate(_scene_dict(h, {"kind": "regular", "height": H, "period": T}),
                    duration=3 * T, dt=0.02)
    assert r.warnings == ()
    F = r.fairlead_force[:, 0] + r.anchor_force[:, 0]
    w = 2 * math.pi / T
    expected = _inertia_sum(h, H, T, N, L0)
    k = wave_number(w, h)
    integral = 1025.0 * math.pi / 4 * 0.01 * 2.0 * (H / 2) * w * w * math.sinh(k * 49.0) \
        / (k * math.sinh(k * h)) * L0 / 49.0
    assert abs(expected / integral - 1.0) < 3e-4
    s1, c1 = _harmonic(r.time, F, w, T)
    assert abs(s1 / expected - 1.0) < 2e-4
    assert abs(c1) < 2e-4 * expected


@pytest.mark.parametrize("model", ["rod", "hybrid"])
def test_wave_inertia_on_a_taut_rod_riser(model):
    """The same riser as a Kirchhoff rod and as the hybrid (EI = GJ = 1e3 N m^2, 20
    segments, 2 periods at T/200): the supports' first harmonic is the Morison inertia
    summed over the elements within 2e-4, as the cable's (measured 4.2e-5 and 5.2e-5 at 40
    segments, against the cable's 4.5e-5)."""
    h, H, T, N, L0 = 50.0, 4.0, 8.0, 20, 48.5
    d = _scene_dict(h, {"kind": "regular", "height": H, "period": T}, EI=1e3, GJ=1e3)
    d["model"] = model
    d["sections"][0]["segments"] = N
    r = sc.simulate(d, duration=2 * T, dt=T / 200, progress=False)
    assert r.warnings == ()
    F = r.fairlead_force[:, 0] + r.anchor_force[:, 0]
    w = 2 * math.pi / T
    expected = _inertia_sum(h, H, T, N, L0)
    s1, c1 = _harmonic(r.time, F, w, T)
    assert abs(s1 / expected - 1.0) < 2e-4
    assert abs(c1) < 2e-4 * expected


def test_wave_drag_on_a_taut_riser():
    """The same riser with drag (Cd 1.2) and no added mass: the supports' horizontal force
    equals Morison drag 0.5 rho d Cd |u_n| u_n plus the Froude-Krylov force rho V a_x on
    each element of the straight line (NumPy, from the wave's kinematics at the midpoints)
    within 0.5 % of its peak after the ramp (the line's own response and the drag's smoothing
    near u = 0)."""
    h, H, T, N, L0 = 50.0, 4.0, 8.0, 40, 48.5
    d = _scene_dict(h, {"kind": "regular", "height": H, "period": T}, cd_normal=1.2,
                    ca_normal=0.0)
    r = sc.simulate(d, duration=2 * T, dt=0.02)
    zm = -h + (np.arange(N) + 0.5) * 49.0 / N
    mid = np.stack([np.zeros(N), np.zeros(N), zm], axis=1)
    kin = sc.wave_kinematics(d, mid, r.time)
    ux = kin.velocity[:, :, 0]
    strain = 49.0 / L0 - 1.0
    drag = (0.5 * 1025.0 * 0.1 * 1.2 * np.abs(ux) * ux * (L0 / N) * math.sqrt(1 + strain)
            + 1025.0 * math.pi / 4 * 0.01 * (L0 / N) * kin.acceleration[:, :, 0]).sum(1)
    m = r.time >= T
    F = r.fairlead_force[:, 0] + r.anchor_force[:, 0]
    assert np.max(np.abs(F[m] - drag[m])) < 5e-3 * np.max(np.abs(drag))


def test_statics_are_in_a_calm_sea():
    """A scene in waves has the static state of its calm sea, exactly (its statics leave the
    waves out), and its run starts there without a jump (the waves ramp in)."""
    d = _scene_dict(50.0, {"kind": "jonswap", "hs": 3.0, "tp": 9.0, "components": 20})
    calm = dict(d, environment={"depth": 50.0})
    a, b = sc.solve_static(d), sc.solve_static(calm)
    np.testing.assert_array_equal(a.positions, b.positions)
    assert "wave inertia" not in a.stats["terms"]


def test_free_point_feels_the_waves():
    """A free point's own force in waves at rest: weight less buoyancy, drag 0.5 rho cd_area
    |u| u on the waves' velocity and inertia rho (V + ca V_a) a, to round-off."""
    from symcable.models.system import point_part
    pts = {"anchor": {"kind": "fixed", "position": [-100.0, 0.0, -60.0]},
           "buoy": {"kind": "free", "position": [0.0, 0.0, -20.0], "mass": 500.0,
                    "volume": 2.0, "cd_area": [1.0, 1.0, 1.5], "ca": 0.7}}
    d = {"model": "cable3d", "environment": {"depth": 60.0, "waves": {
        "kind": "regular", "height": 5.0, "period": 10.0}},
        "line_types": {"r": {"mass": 10.0, "diameter": 0.05, "EA": 1e8}},
        "points": pts, "lines": [{"name": "l", "end_a": "anchor", "end_b": "buoy",
                                  "sections": [{"type": "r", "length": 105.0, "segments": 5}]}]}
    s = sc.load_scene(d)
    pt = s.points["buoy"]
    m = point_part(pt, s.environment)
    f = ca.Function("f", [m.q, m.v, m.t, m.p], [m.force])
    X, t = np.array([3.0, 1.0, -20.0]), 2.3
    got = np.ravel(f(X, np.zeros(3), t, m.params.with_values(ramp=np.zeros(1))))
    kin = sc.wave_kinematics(s, X, t)
    u, a = kin.velocity[0, 0], kin.acceleration[0, 0]
    speed = math.sqrt(u @ u + 1e-8)  # the drag's smoothing (DRAG_SPEED 1e-4 m/s)
    want = (np.array([0, 0, -(500.0 - 1025.0 * 2.0) * s.environment.gravity])
            + 0.5 * 1025.0 * np.array(pt.drag_area) * speed * u
            + 1025.0 * (2.0 + 0.7 * pt.added_volume) * a)
    np.testing.assert_allclose(got, want, rtol=1e-12, atol=1e-9)


def test_scene_contract_round_trip_and_errors(tmp_path):
    """[environment.waves] loads from TOML, writes back equal, and each bad input is one
    SceneError naming the key."""
    d = _scene_dict(50.0, {"kind": "jonswap", "hs": 3.0, "tp": 9.0, "gamma": 2.0,
                           "components": 30, "seed": 7, "direction_deg": 45.0,
                           "stretching": "wheeler"})
    s = sc.load_scene(d)
    assert sc.load_scene(s.to_dict()) == s
    path = tmp_path / "s.toml"
    path.write_text(scene_to_toml(s))
    assert sc.load_scene(path) == s
    assert s.environment.waves.count == 30
    bad = [({"kind": "jonswop"}, "environment.waves.kind"),
           ({"kind": "regular", "height": 2.0}, "environment.waves.period"),
           ({"kind": "jonswap", "hs": 2.0, "tp": 8.0, "period": 3.0}, "environment.waves.period"),
           ({"kind": "jonswap", "hs": 2.0, "tp": 8.0, "components": 5000},
            "environment.waves.components"),
           ({"kind": "components", "amplitudes": [1.0, 2.0], "omegas": [1.0],
             "phases_deg": [0.0, 0.0]}, "environment.waves.omegas"),
           ({"kind": "regular", "height": 2.0, "period": 8.0, "stretching": "linear"},
            "environment.waves.stretching")]
    for waves, key in bad:
        with pytest.raises(SceneError, match=key.replace(".", r"\.")):
            sc.load_scene(_scene_dict(50.0, waves))
    planar = {"model": "planar", "environment": {"waves": {"kind": "regular", "height": 1.0,
                                                           "period": 5.0}}}
    with pytest.raises(SceneError, match="environment.waves"):
        sc.load_scene(planar)
    air = _scene_dict(50.0, {"kind": "regular", "height": 1.0, "period": 5.0})
    air["environment"]["water_density"] = 0.0
    with pytest.raises(SceneError, match="air"):
        sc.load_scene(air)


def test_a_free_body_feels_the_waves():
    """A moored free body in a regular wave (H 4 m, T 8 s): its own force
    at every sample of a 12 s run is its weight, buoyancy, drag on the water's velocity
    relative to its centre of buoyancy (current and waves) and Morison's inertia rho (V +
    R diag(ca_volume) R^T) a there, recomputed in NumPy from the run's pose and velocities
    and sc.wave_kinematics, to round-off, where the waves' inertia force reaches about 0.7 %
    of the body's weight (it rests 68 m down, where the wave's acceleration is a
    seventieth of the surface's)."""
    import sys
    from pathlib import Path
    sys.path.insert(0, str(Path(__file__).parent))
    from symcable.scene.bodies import rotation_rpy
    from test_bodies_scene import _scene
    d = _scene()
    d["environment"]["current"] = [0.3, 0.1, 0.0]
    d["environment"]["waves"] = {"kind": "regular", "height": 4.0, "period": 8.0,
                                 "direction_deg": 20.0}
    s = sc.load_scene(d)
    tr = sc.simulate(s, duration=12.0, dt=0.05, progress=False)
    b = s.bodies["buoy"]
    rho, g = s.environment.water_density, s.environment.gravity
    out = tr.outputs
    x, rpy = np.reshape(out["buoy.position"], (-1, 3)), np.reshape(out["buoy.roll_pitch_yaw"], (-1, 3))
    vO, w = np.reshape(out["buoy.velocity"], (-1, 3)), np.reshape(out["buoy.angular_velocity"], (-1, 3))
    own = np.reshape(out["buoy.own_force"], (-1, 3))
    cb, D = np.asarray(b.center_of_buoyancy), rho * np.diag(b.ca_volume)
    worst, wave = 0.0, 0.0
    for k, t in enumerate(tr.time):
        R = rotation_rpy(rpy[k])
        xB = x[k] + R @ cb
        kin = sc.wave_kinematics(s, xB[None, :], t, ramp=True)
        u_w, a_w = kin.velocity[0][0], kin.acceleration[0][0]
        u = R.T @ (np.asarray(s.environment.current) + u_w - (vO[k] + R @ np.cross(w[k], cb)))
        drag = 0.5 * rho * np.asarray(b.cd_area) * np.sqrt(u @ u + 1e-8) * u
        want = (np.array([0.0, 0.0, -b.mass * g + rho * g * b.volume]) + R @ drag
                + rho * b.volume * a_w + R @ D @ R.T @ a_w)
        worst = max(worst, float(np.max(np.abs(own[k] - want))))
        wave = max(wave, float(np.linalg.norm(rho * b.volume * a_w + R @ D @ R.T @ a_w)))
    assert worst < 1e-8 * b.mass * g
    assert wave > 1e-3 * b.mass * g
