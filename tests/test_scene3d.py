"""Scenes of ``model = "cable3d"`` (symcable.scene.load): 3-component vectors, what the first
3D step refuses, and the round trip.

Layer 1 (unit) tests: no solver runs. Numbers the loader only copies are compared exactly.
"""
from __future__ import annotations

import sys

import pytest

from symcable.errors import SceneError, SymcableError
from symcable.models import build_model
from symcable.scene import Model, load_scene, scene_to_toml

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover - exercised on Python 3.10 only
    import tomli as tomllib


def base3d() -> dict:
    """A small valid cable3d scene: a rope from the seabed to a fairlead off the x-z plane,
    in an oblique current, the fairlead moving in all three directions."""
    return {
        "name": "rope3d",
        "model": "cable3d",
        "environment": {"water_density": 1025.0, "depth": 50.0, "current": [0.3, -0.2, 0.0]},
        "seabed": {"stiffness": 2.0e5, "friction": 0.5},
        "line_types": {"rope": {"EA": 1.0e7, "mass": 20.0, "diameter": 0.05, "cd_normal": 1.1}},
        "sections": [{"type": "rope", "length": 100.0, "segments": 20}],
        "end_a": {"condition": "pinned", "position": [0.0, 0.0, -50.0]},
        "end_b": {"condition": "pinned", "position": [60.0, 30.0, -5.0],
                  "motion": {"period": 10.0, "amplitude": [1.0, 0.5, 0.8],
                             "phase_deg": [0.0, 45.0, -90.0]}},
    }


TOML = """
name = "rope3d"
model = "cable3d"
[environment]
water_density = 1025.0
depth = 50.0
current = [0.3, -0.2, 0.0]
[seabed]
stiffness = 2.0e5
friction = 0.5
[line_types.rope]
EA = 1.0e7
mass = 20.0
diameter = 0.05
cd_normal = 1.1
[[sections]]
type = "rope"
length = 100.0
segments = 20
[end_a]
condition = "pinned"
position = [0.0, 0.0, -50.0]
[end_b]
condition = "pinned"
position = [60.0, 30.0, -5.0]
[end_b.motion]
period = 10.0
amplitude = [1.0, 0.5, 0.8]
phase_deg = [0.0, 45.0, -90.0]
"""


def planar() -> dict:
    """The same rope in the x-z plane, ``model = "planar"``."""
    d = base3d()
    d["model"] = "planar"
    d["environment"]["current"] = [0.3, 0.0]
    d["end_a"]["position"] = [0.0, -50.0]
    d["end_b"] = {"condition": "pinned", "position": [60.0, -5.0]}
    return d


def changed(modify) -> dict:
    d = base3d()
    modify(d)
    return d


# ----------------------------------------------------------------------------- good input

def test_cable3d_dict_loads_with_three_component_vectors():
    s = load_scene(base3d())
    assert s.model is Model.CABLE3D and Model("cable3d") is Model.CABLE3D and s.dim == 3
    assert s.environment.current == (0.3, -0.2, 0.0)
    assert s.end_a.position == (0.0, 0.0, -50.0)
    assert s.end_b.position == (60.0, 30.0, -5.0)
    assert s.end_b.motion.amplitude == (1.0, 0.5, 0.8)
    assert s.end_b.motion.phase_deg == (0.0, 45.0, -90.0)
    assert (s.seabed.stiffness, s.seabed.friction) == (2.0e5, 0.5)
    assert s.line_types["rope"].cd_normal == 1.1 and s.line_types["rope"].EI == 0.0


def test_cable3d_toml_loads_as_the_dict(tmp_path):
    path = tmp_path / "rope3d.toml"
    path.write_text(TOML)
    s = load_scene(path)
    assert s == load_scene(base3d()) and s.dim == 3 and s.source == str(path)


def test_cable3d_defaults_have_three_components():
    """No current: (0, 0, 0); a free end's force defaults to (0, 0, 0) and reads 3 numbers;
    the motion's phases default to three zeros."""
    d = base3d()
    del d["environment"]["current"]
    del d["end_b"]["motion"]["phase_deg"]
    s = load_scene(d)
    assert s.environment.current == (0.0, 0.0, 0.0)
    assert s.end_b.motion.phase_deg == (0.0, 0.0, 0.0)
    d["end_b"] = {"condition": "free"}
    assert load_scene(d).end_b.force == (0.0, 0.0, 0.0)
    d["end_b"] = {"condition": "free", "force": [1.0, 2.0, 3.0]}
    assert load_scene(d).end_b.force == (1.0, 2.0, 3.0)


def test_planar_scene_keeps_dim_2():
    s = load_scene(planar())
    assert s.model is Model.PLANAR and s.dim == 2
    assert s.end_a.position == (0.0, -50.0) and s.environment.current == (0.3, 0.0)
    d = planar()
    del d["model"]  # planar is the default
    assert load_scene(d) == s


@pytest.mark.parametrize("make", [base3d, planar])
def test_round_trip(make):
    """load(to_dict(s)) == s, and through TOML text."""
    s = load_scene(make())
    assert load_scene(s.to_dict()) == s
    assert load_scene(tomllib.loads(scene_to_toml(s))) == s
    assert s.to_dict()["model"] == make()["model"]


# ----------------------------------------------------------------------------- refusals

def _refused(d: dict, *fragments: str) -> str:
    with pytest.raises(SceneError) as info:
        load_scene(d)
    msg = str(info.value)
    assert "\n" not in msg
    for f in fragments:
        assert f in msg, (f, msg)
    return msg


def test_clamped_end_takes_a_direction():
    """cable3d clamps an end along a tangent vector (design.md: "3D: direction"), not the
    planar angle; it needs EI > 0 in the section touching it (issue 12: bending landed, so
    the first step's refusals of EI and clamped ends became these)."""
    _refused(changed(lambda d: d["end_a"].update(condition="clamped", angle_deg=30.0)),
             "end_a.angle_deg = 30.0 deg", "direction = [t_x, t_y, t_z]")
    _refused(changed(lambda d: d["end_a"].update(condition="clamped")),
             "end_a.direction: required key missing")
    _refused(changed(lambda d: (d["end_a"].update(condition="clamped", direction=[0, 0, 0]),
                                d["line_types"]["rope"].update(EI=10.0))),
             "end_a.direction = [0, 0, 0]", "nonzero")
    _refused(changed(lambda d: d["end_a"].update(condition="clamped", direction=[1, 0, 0])),
             "end_a.condition = 'clamped'", "EI > 0")
    _refused(changed(lambda d: d["end_a"].update(direction=[1, 0, 0])),
             "end_a.direction = [1, 0, 0]", "only a clamped end")
    s = load_scene(changed(lambda d: (d["end_a"].update(condition="clamped", direction=[0, 3, 4]),
                                      d["line_types"]["rope"].update(EI=10.0))))
    assert s.end_a.direction == pytest.approx((0.0, 0.6, 0.8), abs=1e-15)
    assert load_scene(s.to_dict()) == s


def test_bending_stiffness_accepted():
    s = load_scene(changed(lambda d: d["line_types"]["rope"].update(EI=100.0)))
    assert s.line_types["rope"].EI == 100.0


def test_zero_bending_stiffness_accepted():
    d = changed(lambda d: d["line_types"]["rope"].update(EI=0.0))
    assert load_scene(d).line_types["rope"].EI == 0.0


def test_angle_refused():
    _refused(changed(lambda d: d["end_a"].update(angle_deg=10.0)),
             "end_a.angle_deg = 10.0 deg", "cable3d")


@pytest.mark.parametrize("key, value, fragments", [
    ("end_b.position", [1.0, 2.0],
     ['end_b.position = [1.0, 2.0] m: must be a list of 3 numbers [x, y, z] for model "cable3d"']),
    ("environment.current", [0.3, 0.0],
     ["environment.current = [0.3, 0.0] m/s", '[U_x, U_y, U_z] for model "cable3d"']),
    ("end_b.motion.amplitude", [1.0, 0.8], ["end_b.motion.amplitude = [1.0, 0.8] m", "[A_x, A_y, A_z]"]),
    ("end_b.motion.phase_deg", [0.0, 0.0], ["end_b.motion.phase_deg = [0.0, 0.0] deg",
                                            "[phase_x, phase_y, phase_z]"]),
])
def test_two_components_refused_in_cable3d(key, value, fragments):
    def modify(d):
        *head, last = key.split(".")
        for k in head:
            d = d[k]
        d[last] = value
    _refused(changed(modify), *fragments)


def test_free_end_force_needs_three_components():
    _refused(changed(lambda d: d.update(end_b={"condition": "free", "force": [1.0, 0.0]})),
             "end_b.force = [1.0, 0.0] N", "[F_x, F_y, F_z]")


def test_three_components_refused_in_planar():
    d = planar()
    d["end_b"]["position"] = [60.0, 0.0, -5.0]
    _refused(d, 'end_b.position = [60.0, 0.0, -5.0] m: must be a list of 2 numbers [x, z] '
                'for model "planar"')


def test_missing_position_names_the_3d_layout():
    _refused(changed(lambda d: d["end_a"].pop("position")),
             "end_a.position: required key missing ([x, y, z], m")


# ----------------------------------------------------------------------------- geometry

def test_reach_uses_all_three_components():
    """In the x-z plane the ends are 75 m apart (within the 110 m reach); with y = 100 m
    they are 125 m apart."""
    _refused(changed(lambda d: d["end_b"].update(position=[60.0, 100.0, -5.0])),
             "end_b.position = [60.0, 100.0, -5.0]", "ends are 125.0 m apart")


def test_below_seabed_reads_z_last():
    _refused(changed(lambda d: d["end_a"].update(position=[0.0, -80.0, -51.0])),
             "end_a.position = [0.0, -80.0, -51.0] m", "below the seabed at z = -50.0")
    # y below -depth is not a depth
    assert load_scene(changed(lambda d: d["end_b"].update(position=[60.0, -55.0, -5.0])))


def test_motion_speed_counts_the_y_component():
    """5 m in y at 0.1 s: 314 m/s, above max_strain * sqrt(EA / mass) = 70.7 m/s."""
    _refused(changed(lambda d: d["end_b"]["motion"].update(
        period=0.1, amplitude=[0.0, 5.0, 0.0], phase_deg=[0.0, 0.0, 0.0])),
        "end_b.motion.period = 0.1 s", "314 m/s")


# ----------------------------------------------------------------------------- no Model record

def test_build_model_refuses_cable3d_cleanly():
    """cable3d is a Mechanism, not a planar-style Model record: build_model says where it is."""
    with pytest.raises(SymcableError, match="cable3d is a Mechanism"):
        build_model(base3d())


def test_cli_check_cable3d(tmp_path, capsys):
    from symcable.cli.main import main

    path = tmp_path / "rope3d.toml"
    path.write_text(TOML)
    assert main(["check", str(path)]) == 0
    out = capsys.readouterr().out
    assert "cable3d" in out and "unknowns" in out and out.strip().endswith("ok")


def test_cable3d_only_line_keys():
    """``damping`` (axial material damping, N s; negative = -zeta) and ``ca_tangential``
    load in cable3d and round-trip; a planar scene refuses them when nonzero (the planar
    line has neither), naming the key."""
    d = base3d()
    lt = next(iter(d["line_types"].values()))
    lt.update(damping=-0.8, ca_tangential=0.5)
    s = load_scene(d)
    t = next(iter(s.line_types.values()))
    assert (t.damping, t.ca_tangential) == (-0.8, 0.5)
    assert next(iter(load_scene(s.to_dict()).line_types.values())) == t
    planar = {"line_types": {"c": {"mass": 50.0, "diameter": 0.1, "EA": 1e8, "damping": 1e4}},
              "sections": [{"type": "c", "length": 100.0, "segments": 10}],
              "end_a": {"condition": "pinned", "position": [0.0, 0.0]},
              "end_b": {"condition": "pinned", "position": [90.0, 0.0]}}
    _refused(planar, "line_types.c.damping", "cable3d")
