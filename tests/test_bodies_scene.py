"""Rigid bodies in scene files (issue 13, part 1; scene version 2, ``[bodies.NAME]``): the
keys, line ends ``"NAME"`` / ``"NAME@[x, y, z]"``, the round trip through dict and TOML,
one SceneError per bad key (naming the key, the value and what is allowed), and the static
solve of the scene from a start far from its equilibrium."""
from __future__ import annotations

import numpy as np
import pytest

from symcable.errors import SceneError
from symcable.scene import BodyEnd, BodyKind, load_scene, scene_to_toml
from symcable.scene.bodies import rotation_rpy


def _scene() -> dict:
    """A free body held by two chains at two of its points and a fixed body carrying the
    anchor of a third line (a pile with a padeye)."""
    return {"model": "cable3d", "environment": {"depth": 100.0},
            "line_types": {"chain": {"mass": 50.0, "diameter": 0.08, "EA": 4e8}},
            "points": {"a1": {"kind": "fixed", "position": [-150.0, 0.0, -100.0]},
                       "a2": {"kind": "fixed", "position": [150.0, 0.0, -100.0]}},
            "bodies": {"buoy": {"mass": 3000.0, "volume": 8.0, "inertia": [2e3, 3e3, 4e3],
                                "position": [0.0, 0.0, -40.0], "orientation": [0.0, 5.0, 30.0],
                                "center_of_gravity": [0.0, 0.0, -0.5],
                                "center_of_buoyancy": [0.0, 0.0, 0.2],
                                "cd_area": [1.0, 1.2, 2.0], "ca_volume": [4.0, 4.0, 6.0]},
                       "pile": {"kind": "fixed", "position": [0.0, 150.0, -98.0],
                                "orientation": [0.0, 0.0, 90.0]}},
            "lines": [{"name": "west", "end_a": "a1", "end_b": "buoy@[-1.0, 0.0, -1.0]",
                       "sections": [{"type": "chain", "length": 170.0, "segments": 10}]},
                      {"name": "east", "end_a": "a2", "end_b": "buoy@[1.0, 0.0, -1.0]",
                       "sections": [{"type": "chain", "length": 170.0, "segments": 10}]},
                      {"name": "north", "end_a": "pile@[0.0, 0.0, 1.5]", "end_b": "buoy",
                       "sections": [{"type": "chain", "length": 160.0, "segments": 10}]}]}


def test_bodies_load_and_round_trip(tmp_path):
    s = load_scene(_scene())
    buoy, pile = s.bodies["buoy"], s.bodies["pile"]
    assert buoy.kind is BodyKind.FREE and pile.kind is BodyKind.FIXED
    assert buoy.inertia == (2e3, 3e3, 4e3) and buoy.ca_volume == (4.0, 4.0, 6.0)
    assert s.lines[0].end_b == BodyEnd("buoy", (-1.0, 0.0, -1.0))
    assert s.lines[2].end_b == BodyEnd("buoy") and s.lines[2].end_b.text == "buoy"
    # a fixed body's point in global axes: its position plus R r (yaw 90 degrees turns
    # body x to global y)
    np.testing.assert_allclose(pile.world((1.0, 0.0, 1.5)), [0.0, 151.0, -96.5], atol=1e-12)
    R = rotation_rpy((10.0, 20.0, 30.0))
    np.testing.assert_allclose(R @ R.T, np.eye(3), atol=1e-15)
    assert load_scene(s.to_dict()) == s
    path = tmp_path / "bodies.toml"
    path.write_text(scene_to_toml(s))
    assert load_scene(path) == s


def _edit(path: str, value):
    def modify(d):
        keys = path.replace("[", ".[").split(".")
        node = d
        for k in keys[:-1]:
            node = node[int(k[1:-1])] if k.startswith("[") else node[k]
        if value is DELETE:
            del node[keys[-1]]
        elif keys[-1].startswith("["):
            node[int(keys[-1][1:-1])] = value
        else:
            node[keys[-1]] = value
    return modify


DELETE = object()


def _loose(d):
    """The free body held only by a line whose other end is free: nothing holds it."""
    d["lines"] = [{"name": "tail", "end_a": {"condition": "free"}, "end_b": "buoy",
                   "sections": [{"type": "chain", "length": 50.0, "segments": 5}]},
                  {"name": "pin", "end_a": "a1", "end_b": "pile",
                   "sections": [{"type": "chain", "length": 250.0, "segments": 5}]},
                  {"name": "pin2", "end_a": "a2", "end_b": "pile",
                   "sections": [{"type": "chain", "length": 250.0, "segments": 5}]}]


#: (modifier, fragments of the one-line message: key path, value, what is allowed)
BAD = {
    "mass negative": (_edit("bodies.buoy.mass", -1.0), ["bodies.buoy.mass = -1.0 kg", "> 0"]),
    "mass missing": (_edit("bodies.buoy.mass", DELETE),
                     ["bodies.buoy.mass: required key missing", "kg"]),
    "inertia missing": (_edit("bodies.buoy.inertia", DELETE),
                        ["bodies.buoy.inertia: required key missing", "Ixx"]),
    "inertia length": (_edit("bodies.buoy.inertia", [1.0, 2.0]),
                       ["bodies.buoy.inertia = [1.0, 2.0] kg m^2", "list of 3"]),
    "inertia zero": (_edit("bodies.buoy.inertia", [1.0, 0.0, 2.0]),
                     ["bodies.buoy.inertia[1] = 0.0 kg m^2", "> 0"]),
    "volume negative": (_edit("bodies.buoy.volume", -2.0), ["bodies.buoy.volume = -2.0 m^3",
                                                            ">= 0"]),
    "position missing": (_edit("bodies.buoy.position", DELETE),
                         ["bodies.buoy.position: required key missing"]),
    "orientation": (_edit("bodies.buoy.orientation", [0.0, 1.0]),
                    ["bodies.buoy.orientation = [0.0, 1.0] deg", "[roll, pitch, yaw]"]),
    "centre of gravity": (_edit("bodies.buoy.center_of_gravity", "middle"),
                          ["bodies.buoy.center_of_gravity = 'middle' m", "list of 3"]),
    "cd_area negative": (_edit("bodies.buoy.cd_area", [1.0, -1.0, 0.0]),
                         ["bodies.buoy.cd_area[1] = -1.0 m^2", ">= 0"]),
    "ca_volume negative": (_edit("bodies.buoy.ca_volume", [1.0, 1.0, -3.0]),
                           ["bodies.buoy.ca_volume[2] = -3.0 m^3", ">= 0"]),
    "kind": (_edit("bodies.buoy.kind", "floating"),
             ["bodies.buoy.kind = 'floating'", "unknown body kind", "'free', 'fixed'"]),
    "key": (_edit("bodies.buoy.inertial", [1.0, 1.0, 1.0]),
            ["bodies.buoy.inertial", "did you mean 'inertia'?"]),
    "fixed body with mass": (_edit("bodies.pile.mass", 10.0),
                             ["bodies.pile.mass = 10.0", "only a free body takes mass"]),
    "unknown body": (_edit("lines[0].end_b", "bouy@[1, 0, 0]"),
                     ["lines[0].end_b = 'bouy@[1, 0, 0]'", "unknown body", "did you mean 'buoy'?"]),
    "unknown end": (_edit("lines[0].end_b", "buoi"),
                    ["lines[0].end_b = 'buoi'", "unknown point", "did you mean 'buoy'?"]),
    "body point": (_edit("lines[0].end_b", "buoy@[1, 0]"),
                   ["lines[0].end_b = 'buoy@[1, 0]'", "NAME@[x, y, z]"]),
    "body point text": (_edit("lines[0].end_b", "buoy@front"),
                        ["lines[0].end_b = 'buoy@front'", "three numbers"]),
    "unused body": (_edit("bodies.spare", {"kind": "fixed", "position": [0.0, 0.0, -50.0]}),
                    ["bodies.spare", "no line attaches to this body"]),
    "body named as a point": (_edit("bodies.a1", {"kind": "fixed", "position": [0, 0, -9]}),
                              ["bodies.a1 = 'a1'", "point's name"]),
    "line named as a body": (_edit("lines[1].name", "buoy"),
                             ["lines[1].name = 'buoy'", "body's name"]),
    "bodies without lines": (_edit("lines", DELETE), ["points"]),
    "fixed body point below the seabed": (_edit("bodies.pile.position", [0.0, 150.0, -102.0]),
                                          ["lines[2].end_a = 'pile@[0.0, 0.0, 1.5]'",
                                           "below the seabed"]),
    "nothing holds": (_loose, ["lines[0].end_a", "nothing holds them"]),
    "out of reach": (_edit("lines[1].sections[0].length", 100.0),
                     ["points.a2.position", "the ends are", "stretch to at most"]),
}


@pytest.mark.parametrize("case", sorted(BAD))
def test_each_bad_key_is_one_scene_error(case):
    edit, fragments = BAD[case]
    d = _scene()
    edit(d)
    with pytest.raises(SceneError) as info:
        load_scene(d)
    msg = str(info.value)
    assert "\n" not in msg
    for fragment in fragments:
        assert fragment in msg, msg


def test_bodies_in_a_one_line_scene_are_refused():
    d = {"model": "cable3d", "line_types": _scene()["line_types"],
         "sections": [{"type": "chain", "length": 100.0, "segments": 4}],
         "end_a": {"condition": "pinned", "position": [0.0, 0.0, 0.0]},
         "end_b": {"condition": "free"},
         "bodies": {"b": {"mass": 1.0, "inertia": [1, 1, 1], "position": [0, 0, -1]}}}
    with pytest.raises(SceneError, match=r"bodies = .*attached to \[\[lines\]\]"):
        load_scene(d)


def test_a_body_started_far_from_its_equilibrium():
    """The scene above puts the buoy 28 m above its equilibrium and turned 30 degrees in yaw
    and 5 in pitch from it: Newton from the lines' starts fails (the out-of-plane stiffness of
    slack catenaries is zero), and the static solve gets there by releasing the body from
    stiff springs at the scene's pose (models/body.py, ``pull``); started at zero
    orientation it reaches the same equilibrium (position within 1e-6 m, roll, pitch and yaw
    within 1e-6 degree: the static tolerance over the body's softest stiffness), where its
    net force and moment vanish (to 10 times the tolerance)."""
    import symcable as sc

    a = sc.solve_static(_scene(), codegen=False)
    d = _scene()
    d["bodies"]["buoy"]["orientation"] = [0.0, 0.0, 0.0]
    b = sc.solve_static(d, codegen=False)
    assert a.stats["path"] == "continuation in the bodies' pull"
    for st in (a, b):
        assert np.max(np.abs(st.bodies["buoy"].net_force)) < 10 * st.stats["tolerance"]
    np.testing.assert_allclose(a.bodies["buoy"].position, b.bodies["buoy"].position, atol=1e-6)
    np.testing.assert_allclose(a.bodies["buoy"].roll_pitch_yaw, b.bodies["buoy"].roll_pitch_yaw,
                               atol=1e-6)
    assert a.bodies["buoy"].position[2] < -60.0 and abs(a.bodies["buoy"].roll_pitch_yaw[2]) < 1e-6
    # the fixed pile carries the north line's pull at its padeye
    np.testing.assert_allclose(a.bodies["pile"].force, a.lines["north"].anchor_force)
    arm = a.lines["north"].positions[0] - a.bodies["pile"].position
    pull = a.lines["north"].anchor_force
    np.testing.assert_allclose(a.bodies["pile"].moment, np.cross(arm, pull),
                               atol=1e-9 * np.linalg.norm(pull))
