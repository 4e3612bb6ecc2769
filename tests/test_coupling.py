"""The coupling interface (issue 36, item 6): a host program stepping symcable's lines with the
motion of the coupled points and bodies equals ``simulate`` of that motion at the same step;
save and restore; substeps; bad calls refused in one line."""
from __future__ import annotations

import math

import numpy as np
import pytest

import symcable as sc
from symcable.errors import SymcableError

T = 10.0  # s, the motions' period
#: a vessel body's harmonic motion: surge, heave and pitch (m, m, m, deg, deg, deg)
AMP6, PH6 = [3.0, 0.0, 1.0, 0.0, 4.0, 0.0], [0.0, 0.0, 60.0, 0.0, 30.0, 0.0]
#: a fairlead's harmonic motion (m, deg)
AMP3, PH3 = [2.0, 1.0, 1.5], [0.0, 90.0, 30.0]
#: the coupling's forces against simulate's, relative to each one's range over the run: the
#: two take the same steps from the same state (the coupled end's cubic is exactly the
#: host's position and velocity where the step evaluates its forces), so they agree to the
#: round-off of the Newton iterations (measured 3e-13 on the spar); the issue asks 1e-8
SAME_RUN = 1e-8


def _chain() -> dict:
    return {"mass": 77.7, "diameter": 0.09, "weight": 698.0, "EA": 3.84e8,
            "cd_normal": 1.6, "cd_tangential": 0.1, "ca_normal": 1.0}


def spar(segments: int = 8, body_motion: bool = True) -> dict:
    """Three 250 m chains from a spar in 100 m of water, the spar moving harmonically."""
    d = {"name": "spar", "model": "cable3d", "environment": {"depth": 100.0},
         "seabed": {"stiffness": 1e5}, "line_types": {"chain": _chain()},
         "points": {}, "lines": [],
         "bodies": {"spar": {"kind": "fixed", "position": [0.0, 0.0, 0.0]}}}
    if body_motion:
        d["bodies"]["spar"]["kind"] = "vessel"
        d["bodies"]["spar"]["motion"] = {"kind": "harmonic", "period": T, "amplitude": AMP6,
                                         "phase_deg": PH6}
    for i, a in enumerate((0.0, 120.0, 240.0)):
        c, s = math.cos(math.radians(a)), math.sin(math.radians(a))
        d["points"][f"anchor{i}"] = {"kind": "fixed", "position": [230.0 * c, 230.0 * s, -100.0]}
        d["lines"].append({"name": f"line{i}", "end_a": f"anchor{i}",
                           "end_b": f"spar@[{5.0 * c}, {5.0 * s}, -20.0]",
                           "sections": [{"type": "chain", "length": 250.0,
                                         "segments": segments}]})
    return d


def one_line(segments: int = 10) -> dict:
    """One chain to a fairlead moving harmonically (version 1)."""
    return {"name": "fairlead", "model": "cable3d", "environment": {"depth": 50.0},
            "seabed": {"stiffness": 1e5}, "line_types": {"chain": _chain()},
            "sections": [{"type": "chain", "length": 150.0, "segments": segments}],
            "end_a": {"condition": "pinned", "position": [-140.0, 0.0, -50.0]},
            "end_b": {"condition": "pinned", "position": [0.0, 0.0, -5.0],
                      "motion": {"kind": "harmonic", "period": T, "amplitude": AMP3,
                                 "phase_deg": PH3}}}


def _ramp(t: float) -> tuple[float, float]:
    """The harmonic motions' ramp over their first period and its rate."""
    if t <= 0.0:
        return 0.0, 0.0
    if t >= T:
        return 1.0, 0.0
    return 0.5 * (1 - math.cos(math.pi * t / T)), 0.5 * math.pi / T * math.sin(math.pi * t / T)


def harmonic(amp, phase_deg, t: float, degrees: slice = slice(0)) -> tuple:
    """A harmonic motion with its ramp (the scene's) at t: displacement and rate, the
    entries ``degrees`` converted to rad."""
    a = np.array(amp, float)
    a[degrees] = np.radians(a[degrees])
    w, ph = 2 * math.pi / T, np.radians(phase_deg)
    r, rd = _ramp(t)
    return r * a * np.cos(w * t + ph), rd * a * np.cos(w * t + ph) - r * a * w * np.sin(w * t + ph)


def body_host(t: float) -> tuple:
    """The spar's pose (m, rad) and velocity (m/s; angular velocity, global axes, rad/s)."""
    q, qd = harmonic(AMP6, PH6, t, slice(3, 6))
    yaw, pitch = q[5], q[4]
    cy, sy, cp, sp = math.cos(yaw), math.sin(yaw), math.cos(pitch), math.sin(pitch)
    Rz = np.array([[cy, -sy, 0], [sy, cy, 0], [0, 0, 1]])
    Ry = np.array([[cp, 0, sp], [0, 1, 0], [-sp, 0, cp]])
    omega = qd[3] * (Rz @ Ry @ [1, 0, 0]) + qd[4] * (Rz @ [0, 1, 0]) + qd[5] * np.array([0, 0, 1])
    return q, np.concatenate([qd[:3], omega])


def _host_run(c: sc.Coupling, host, base, dt: float, n: int) -> np.ndarray:
    out = [c.initialize(base)]
    for k in range(n):
        x, v = host((k + 1) * dt)
        out.append(c.step(k * dt, dt, base + x, v))
    return np.array(out)


def _relative(a, b) -> np.ndarray:
    """max |a - b| over each column's range (columns whose range is round-off skipped)."""
    rng = np.ptp(b, axis=0)
    keep = rng > 1e-6 * np.max(rng)
    return np.max(np.abs(a - b), axis=0)[keep] / rng[keep]


def test_body_coupling_equals_simulate():
    """A host moving the spar by its harmonic motion gets simulate's force and moment on it,
    step for step (2 periods, 200 steps)."""
    d = spar()
    dt, n = T / 100, 200
    tr = sc.simulate(d, duration=n * dt, dt=dt)
    ref = np.hstack([np.reshape(tr.outputs["spar.force"], (-1, 3)),
                     np.reshape(tr.outputs["spar.moment"], (-1, 3))])
    c = sc.Coupling(spar(body_motion=False), coupled="spar")
    assert c.dof_names == ["spar.x", "spar.y", "spar.z", "spar.roll", "spar.pitch", "spar.yaw"]
    got = _host_run(c, body_host, np.zeros(6), dt, n)
    assert np.max(_relative(got, ref)) < SAME_RUN
    assert c.time == pytest.approx(n * dt, rel=1e-12)
    assert c.stats["host_steps"] == n and c.stats["substepped_steps"] == 0
    # the lines' outputs at the end are simulate's last sample's
    out = c.outputs()
    for name in ("line0.axial_force", "line1.positions"):
        last = np.asarray(tr.outputs[name])[-1]
        assert np.allclose(out[name], last, rtol=0, atol=1e-8 * np.max(np.abs(last)))


@pytest.mark.parametrize("version", [1, 2])
def test_point_coupling_equals_simulate(version):
    """A fairlead point moved by the host: a version-1 scene's end_b, and the same line as a
    version-2 scene's vessel point."""
    d = one_line()
    if version == 2:
        d = {k: v for k, v in d.items() if k not in ("sections", "end_a", "end_b")}
        d["points"] = {"anchor": {"kind": "fixed", "position": [-140.0, 0.0, -50.0]},
                       "fair": {"kind": "vessel", "position": [0.0, 0.0, -5.0],
                                "motion": one_line()["end_b"]["motion"]}}
        d["lines"] = [{"name": "chain", "end_a": "anchor", "end_b": "fair",
                       "sections": one_line()["sections"]}]
    dt, n = T / 50, 100
    tr = sc.simulate(d, duration=n * dt, dt=dt)
    ref = tr.fairlead_force if version == 1 else np.reshape(tr.outputs["fair.force"], (-1, 3))
    c = sc.Coupling(d)
    assert c.names == (["end_b"] if version == 1 else ["fair"])
    base = np.array([0.0, 0.0, -5.0])
    got = _host_run(c, lambda t: harmonic(AMP3, PH3, t), base, dt, n)
    assert np.max(_relative(got, ref)) < SAME_RUN


def test_state_restore_and_file(tmp_path):
    """Restoring a saved state (in memory or from its file) and stepping again repeats the
    same forces exactly; a state of another coupling is refused."""
    d = one_line(6)
    c = sc.Coupling(d)
    base = np.array([0.0, 0.0, -5.0])
    c.initialize(base)
    dt = 0.1
    for k in range(10):
        c.step(k * dt, dt, base + harmonic(AMP3, PH3, (k + 1) * dt)[0],
               harmonic(AMP3, PH3, (k + 1) * dt)[1])
    saved = c.state()
    path = saved.save(tmp_path / "state.npz")

    def ten_more():
        out = []
        for k in range(10, 20):
            x, v = harmonic(AMP3, PH3, (k + 1) * dt)
            out.append(c.step(k * dt, dt, base + x, v))
        return np.array(out)
    first = ten_more()
    c.restore(saved)
    assert c.time == pytest.approx(1.0)
    assert np.array_equal(ten_more(), first)
    c.restore(sc.CouplingState.load(path))
    assert np.array_equal(ten_more(), first)
    # a restart: a new coupling, started elsewhere, restores the file and goes on alike, to
    # the Newton tolerance (its scales and tolerance come from its own start: measured
    # 3e-7 of the largest force; before the ends' start was saved, 10 times the force)
    c = sc.Coupling(d)
    c.initialize(base + [5.0, 0.0, 0.0])
    c.restore(sc.CouplingState.load(path))
    assert np.array_equal(c.state().positions, saved.positions)
    assert np.allclose(ten_more(), first, rtol=0, atol=1e-5 * np.max(np.abs(first)))
    other = sc.Coupling(one_line(7))
    other.initialize()
    with pytest.raises(SymcableError, match="not one of this coupling's"):
        other.restore(saved)


def test_substeps_follow_the_host_path():
    """A host step of four of simulate's, taken as four substeps along the cubic through the
    host's states, stays within a small part of the range of simulate's run at the
    substep (the cubic's position error over a step of T/25 is about (h/T)^4 of the
    amplitude)."""
    d = one_line(6)
    h, n = T / 100, 100
    ref = sc.simulate(d, duration=n * h, dt=h).fairlead_force
    c = sc.Coupling(d, max_step=h)
    base = np.array([0.0, 0.0, -5.0])
    got = _host_run(c, lambda t: harmonic(AMP3, PH3, t), base, 4 * h, n // 4)
    assert c.stats["steps"] == n
    # 1e-3: four times the measured (substeps along the cubic against the exact motion)
    assert np.max(_relative(got, ref[::4])) < 1e-3


def test_forces_at_initialize_are_the_static_state():
    """The forces at the start are the static solution's force on the spar."""
    d = spar(body_motion=False)
    st = sc.solve_static(d)
    c = sc.Coupling(d, coupled=["spar"])
    f = c.initialize()
    assert np.allclose(f[:3], st.bodies["spar"].force, rtol=1e-6, atol=1e-3)


def test_bad_calls_get_one_line():
    d = spar(body_motion=False)
    with pytest.raises(SymcableError, match="is free"):
        sc.Coupling({**d, "bodies": {"spar": {"kind": "free", "position": [0, 0, 0],
                                              "mass": 1e6, "inertia": [1e8] * 3,
                                              "volume": 1e3}}}, coupled="spar")
    with pytest.raises(SymcableError, match="not in the scene"):
        sc.Coupling(d, coupled="ship")
    with pytest.raises(SymcableError, match="no vessel point or body"):
        sc.Coupling(d)
    c = sc.Coupling(d, coupled="spar")
    with pytest.raises(SymcableError, match="before initialize"):
        c.step(0.0, 0.1, np.zeros(6), np.zeros(6))
    with pytest.raises(SymcableError, match="must be 6 finite numbers"):
        c.initialize(np.zeros(3))
    c.initialize()
    with pytest.raises(SymcableError, match="must be 6 finite numbers"):
        c.step(0.0, 0.1, [0, 0, 0, 0, 0, float("nan")], np.zeros(6))
    with pytest.raises(SymcableError, match="the coupling is at t = 0"):
        c.step(1.0, 0.1, np.zeros(6), np.zeros(6))
    with pytest.raises(SymcableError, match="dt = -0.1"):
        c.step(0.0, -0.1, np.zeros(6), np.zeros(6))
    with pytest.raises(SymcableError, match="model = 'planar'"):
        sc.Coupling(sc.demo_scene_path("seed001"))
