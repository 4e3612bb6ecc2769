"""Vessels (``[bodies.NAME]`` with ``kind = "vessel"``): a body moved in six degrees of
freedom by a harmonic motion, a table or its response amplitude operators in the scene's
waves; the lines' ends follow its points, rotation included."""
from __future__ import annotations

import math

import numpy as np
import pytest

import symcable as sc
from symcable.errors import SceneError
from symcable.scene.bodies import rotation_rpy

FAIRLEAD = np.array([5.2, 0.0, -70.0])


def _spar(motion, waves=None, segments=8) -> dict:
    """OC3's three chains (coarse) on a vessel at the origin, fairleads at 5.2 m radius."""
    d = {"model": "cable3d", "environment": {"depth": 320.0}, "seabed": {"stiffness": 1e5},
         "line_types": {"chain": {"mass": 77.7, "diameter": 0.09, "weight": 698.1,
                                  "EA": 3.84e8, "cd_normal": 1.6, "cd_tangential": 0.1,
                                  "ca_normal": 1.0}},
         "points": {}, "bodies": {"spar": {"kind": "vessel", "position": [0.0, 0.0, 0.0],
                                           "motion": motion}}, "lines": []}
    if waves:
        d["environment"]["waves"] = waves
    for i, a in enumerate((0.0, 120.0, 240.0)):
        c, s = math.cos(math.radians(a)), math.sin(math.radians(a))
        d["points"][f"anchor{i}"] = {"kind": "fixed", "position": [853.87 * c, 853.87 * s,
                                                                   -320.0]}
        d["lines"].append({"name": f"line{i}", "end_a": f"anchor{i}",
                           "end_b": f"spar@[{5.2 * c}, {5.2 * s}, -70.0]",
                           "sections": [{"type": "chain", "length": 902.2,
                                         "segments": segments}]})
    return d


def _check_pose(r, dof, t0, body="spar"):
    """The vessel's outputs and line0's fairlead equal the rigid motion ``dof`` (n_t, 6),
    to round-off (1e-12 m, deg)."""
    b, k = r.bodies[body], r.time >= t0
    np.testing.assert_allclose(b["position"][k], dof[k, :3], atol=1e-12)
    np.testing.assert_allclose(b["roll_pitch_yaw"][k], dof[k, 3:], atol=1e-12)
    want = np.array([d[:3] + rotation_rpy(d[3:]) @ FAIRLEAD for d in dof])
    np.testing.assert_allclose(r.lines["line0"].positions[k, -1, :], want[k], atol=1e-12)


def test_harmonic_vessel_moves_its_fairleads_rigidly():
    """Surge, heave and pitch: after the first period's ramp, the reference point, the
    angles and a fairlead 70 m below follow the rigid motion exactly; the statics sit at
    the mean pose; the scene writes back equal."""
    m = {"kind": "harmonic", "period": 20.0, "amplitude": [3.0, 0.0, 1.0, 0.0, 4.0, 2.0],
         "phase_deg": [0.0, 0.0, 90.0, 0.0, 30.0, -45.0]}
    s = sc.load_scene(_spar(m))
    assert sc.load_scene(s.to_dict()) == s
    st = sc.solve_static(s)
    np.testing.assert_allclose(st.lines["line0"].positions[-1], FAIRLEAD, atol=1e-12)
    r = sc.simulate(s, duration=30.0, dt=0.1)
    assert not any("no motion" in w for w in r.warnings)
    A, ph = np.array(m["amplitude"]), np.radians(m["phase_deg"])
    _check_pose(r, A * np.cos(2 * math.pi * r.time[:, None] / 20.0 + ph), 20.0)


def test_rao_vessel_in_a_regular_wave():
    """RAOs in a regular wave between two table frequencies: each degree of freedom is
    Re(H a e^(i phi) e^(-i omega t)), H interpolated linearly in its real and imaginary
    parts (the wave's crest phase 15 deg at the reference point)."""
    w = [0.2, 0.5, 0.8, 1.2]
    amp = [[1, 0.1, 0.8, 0.3, 2, 0.5], [0.9, 0.1, 0.5, 0.2, 1.5, 0.4],
           [0.5, 0.05, 0.2, 0.1, 1, 0.2], [0.1, 0, 0.05, 0, 0.2, 0]]
    ph = [[0, 0, 0, 10, 90, 5], [10, 20, 5, 15, 100, 10], [20, 30, 10, 20, 110, 15],
          [30, 40, 20, 25, 120, 20]]
    W = 0.65
    waves = {"kind": "regular", "height": 4.0, "period": 2 * math.pi / W, "phase_deg": 15.0}
    s = sc.load_scene(_spar({"kind": "rao", "omegas": w, "amplitude": amp, "phase_deg": ph},
                            waves))
    assert sc.load_scene(s.to_dict()) == s
    r = sc.simulate(s, duration=25.0, dt=0.1)
    H = np.array(amp) * np.exp(-1j * np.radians(ph))
    Hc = np.array([np.interp(W, w, H[:, j].real) + 1j * np.interp(W, w, H[:, j].imag)
                   for j in range(6)])
    dof = np.real((Hc * 2.0 * np.exp(1j * math.radians(15.0)))[None, :]
                  * np.exp(-1j * W * r.time)[:, None])
    _check_pose(r, dof, 2 * math.pi / W)


def test_table_vessel(tmp_path):
    """A table of t x y z roll pitch yaw: between rows the pose is linear in each degree of
    freedom (the rows here lie on a line, so the rigid motion is the table's exactly)."""
    t = np.linspace(0.0, 20.0, 11)
    rows = np.column_stack([t, 0.2 * t, -0.1 * t, 0.05 * t, 0.1 * t, -0.2 * t, 0.3 * t])
    path = tmp_path / "motion.txt"
    np.savetxt(path, rows)
    d = _spar({"kind": "table", "file": str(path)})
    r = sc.simulate(d, duration=20.0, dt=0.25)
    dof = np.interp(r.time, t, rows[:, 1])[:, None] * np.array([1, -0.5, 0.25, 0.5, -1, 1.5])
    _check_pose(r, dof, 0.0)


@pytest.mark.parametrize("motion, key", [
    ({"kind": "rao", "omegas": [0.1, 0.5], "amplitude": [[1] * 6] * 2,
      "phase_deg": [[0] * 6] * 2}, r"bodies\.spar\.motion\.kind"),
    ({"kind": "harmonic", "period": 10.0, "amplitude": [1, 0, 0]}, r"bodies\.spar\.motion\.amplitude"),
    ({"kind": "harmonic", "period": 10.0, "amplitude": [0] * 6, "file": "x"}, r"bodies\.spar\.motion\.file"),
    ({"kind": "spin"}, r"bodies\.spar\.motion\.kind"),
])
def test_vessel_motion_errors(motion, key):
    """Each bad vessel motion is one SceneError naming the key (RAOs without waves, a short
    amplitude, a key of another kind, an unknown kind)."""
    with pytest.raises(SceneError, match=key):
        sc.load_scene(_spar(motion))


def test_motion_only_on_a_vessel():
    d = _spar({"kind": "harmonic", "period": 10.0, "amplitude": [1, 0, 0, 0, 0, 0]})
    d["bodies"]["spar"]["kind"] = "fixed"
    with pytest.raises(SceneError, match=r"bodies\.spar\.motion.*vessel"):
        sc.load_scene(d)
    d["bodies"]["spar"]["kind"] = "vessel"
    d["bodies"]["spar"].pop("motion")
    with pytest.raises(SceneError, match=r"bodies\.spar\.motion: required"):
        sc.load_scene(d)


def test_motion_table_given_on_the_command_line(tmp_path):
    """``simulate SCENE --motion FILE``: a scene's vessel points become one vessel about their
    centroid at z = 0, moved rigidly by the table (the fairlead of line0 follows the rigid
    motion of its point); a one-line deck's end B takes the translations; a bad target is
    one clear message."""
    from symcable.scene.moving import with_motion
    d = _spar({"kind": "harmonic", "period": 10.0, "amplitude": [0.0] * 6})
    d["bodies"] = {}
    for i, line in enumerate(d["lines"]):
        a = math.radians(120.0 * i)
        d["points"][f"f{i}"] = {"kind": "vessel", "position": [5.2 * math.cos(a),
                                                               5.2 * math.sin(a), -70.0]}
        line["end_b"] = f"f{i}"
    t = np.linspace(0.0, 10.0, 6)
    rows = np.column_stack([t, 0.3 * t, 0 * t, 0.1 * t, 0 * t, 0.2 * t, 0.5 * t])
    path = tmp_path / "m.txt"
    np.savetxt(path, rows)
    s = with_motion(sc.load_scene(d), str(path))
    assert list(s.bodies) == ["vessel"] and not any(p.startswith("f") for p in s.points)
    r = sc.simulate(s, duration=10.0, dt=0.25)
    dof = np.interp(r.time, t, rows[:, 1])[:, None] * np.array([1, 0, 1 / 3, 0, 2 / 3, 5 / 3])
    _check_pose(r, dof, 0.0, "vessel")
    with pytest.raises(SceneError, match="--moving 'nowhere'"):
        with_motion(sc.load_scene(d), str(path), "nowhere")
    one = {"model": "cable3d", "line_types": {"r": {"mass": 10.0, "diameter": 0.05, "EA": 1e8}},
           "sections": [{"type": "r", "length": 110.0, "segments": 5}],
           "end_a": {"condition": "pinned", "position": [0.0, 0.0, -100.0]},
           "end_b": {"condition": "pinned", "position": [40.0, 0.0, -10.0]}}
    m = with_motion(sc.load_scene(one), str(path)).end_b.motion
    assert m.kind == "table" and m.samples[-1][1:] == tuple(rows[-1, 1:4])


def test_check_names_the_sea_and_the_vessel(tmp_path):
    """``symcable check`` says what the sea is and how the vessel moves."""
    import subprocess
    import sys
    from symcable.scene import scene_to_toml
    w = {"kind": "jonswap", "hs": 4.0, "tp": 9.0, "components": 20, "seed": 2}
    rao = {"kind": "rao", "omegas": [0.2, 1.0], "amplitude": [[1, 0, 1, 0, 1, 0]] * 2,
           "phase_deg": [[0] * 6] * 2}
    path = tmp_path / "spar.toml"
    path.write_text(scene_to_toml(sc.load_scene(_spar(rao, w, segments=4))))
    out = subprocess.run([sys.executable, "-m", "symcable", "check", str(path)],
                         capture_output=True, text=True, timeout=300).stdout
    assert "waves      jonswap, Hs 4 m, Tp 9 s, gamma 3.3, 20 components (seed 2)" in out
    assert "moved by its RAOs at 2 frequencies (0.2-1 rad/s)" in out
