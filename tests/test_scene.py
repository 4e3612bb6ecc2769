"""Scene loading and validation (symcable.scene.load; the README's "A scene file").

Layer 1 (unit) tests: no solver runs. Numbers are compared exactly where the loader only copies
them, and with ``pytest.approx`` (relative 1e-12, round-off of one formula) where it computes.
"""
from __future__ import annotations

import copy
import dataclasses
import importlib.resources
import math
from types import MappingProxyType

import pytest

import symcable as sc

from symcable.errors import SceneError
from symcable.scene import End, EndCondition, LineType, Model, Scene, Seabed
from symcable.scene import load_scene, scene_to_dict, scene_to_toml

G = 9.80665


def oc3_path():
    """The built-in demo scene, found as package data (as the CLI's ``demo`` would)."""
    return importlib.resources.files("symcable.data") / "oc3.toml"


def base() -> dict:
    """A small valid planar scene (the OC3 line) as a dict, to be broken one key at a time."""
    return {
        "name": "test",
        "model": "planar",
        "environment": {"gravity": G, "water_density": 1025.0, "depth": 320.0,
                        "current": [0.0, 0.0]},
        "seabed": {"stiffness": 1.0e5, "friction": 0.0},
        "line_types": {"chain": {"EA": 3.84243e8, "EI": 0.0, "mass": 77.7066,
                                 "diameter": 0.09, "cd_normal": 1.6}},
        "sections": [{"type": "chain", "length": 902.2, "segments": 50}],
        "end_a": {"condition": "pinned", "position": [-853.87, -320.0]},
        "end_b": {"condition": "pinned", "position": [-5.2, -70.0],
                  "motion": {"kind": "harmonic", "period": 10.0, "amplitude": [2.0, 1.0],
                             "phase_deg": [0.0, -90.0]}},
    }


def multi() -> dict:
    """Two line types in three sections: chain - rope - chain, a clamped anchor on a stiff rope
    would need EI, so both ends stay pinned here."""
    d = base()
    d["line_types"]["rope"] = {"EA": 1.0e8, "mass": 8.0, "diameter": 0.16, "EI": 0.0,
                               "max_strain": 0.2}
    d["sections"] = [{"type": "chain", "length": 250.0, "segments": 10},
                     {"type": "rope", "length": 500.0, "segments": 25},
                     {"type": "chain", "length": 152.2, "segments": 8}]
    return d


def same_but_source(a: Scene, b: Scene) -> bool:
    return dataclasses.replace(a, source="") == dataclasses.replace(b, source="")


# ----------------------------------------------------------------------------- good input

def test_oc3_file_loads_with_the_published_numbers():
    """oc3.toml gives the OC3-Hywind line of NREL/TP-500-47535 and the elliptic fairlead motion of Boral et al."""
    with importlib.resources.as_file(oc3_path()) as path:
        s = load_scene(path)
        assert s.source == str(path)
    assert s.model is Model.PLANAR
    assert s.environment.depth == 320.0 and s.environment.current == (0.0, 0.0)
    assert s.environment.gravity == G and s.environment.water_density == 1025.0
    assert s.seabed == Seabed(stiffness=1.0e5, friction=0.0)
    assert s.line_types["chain"] == LineType(
        name="chain", EA=3.84243e8, EI=0.0, mass=77.7066, diameter=0.09, weight=698.094,
        cd_normal=1.6, cd_tangential=0.1, ca_normal=1.0, max_strain=0.1)
    (sec,) = s.sections
    assert sec.line_type is s.line_types["chain"]
    assert (sec.length, sec.segments, s.n_nodes) == (902.2, 50, 51)
    assert s.end_a == End(EndCondition.PINNED, position=(-853.87, -320.0))
    assert s.end_b.position == (-5.2, -70.0) and s.end_b.condition is EndCondition.PINNED
    m = s.end_b.motion
    assert (m.kind, m.period, m.amplitude, m.phase_deg) == ("harmonic", 10.0, (2.0, 1.0),
                                                            (0.0, -90.0))
    # the published weight in water agrees with the buoyancy formula to its 6 digits
    rho, d = 1025.0, 0.09
    assert (77.7066 - rho * math.pi * d**2 / 4) * G == pytest.approx(698.094, rel=1e-6)


def test_multi_section_dict_loads():
    """Several sections of two line types resolve to the right LineType objects, in order."""
    s = load_scene(multi())
    assert s.source == "<dict>"
    assert [x.line_type.name for x in s.sections] == ["chain", "rope", "chain"]
    assert s.sections[0].line_type is s.sections[2].line_type is s.line_types["chain"]
    assert s.line_types["rope"].max_strain == 0.2
    assert s.length == pytest.approx(902.2, rel=1e-12) and s.n_segments == 43
    assert s.sections[1].ds == 20.0


def test_returned_types_are_frozen_and_plain():
    """line_types is read-only, sections a tuple, vectors tuples of float (ints converted)."""
    d = base()
    d["end_a"]["position"] = [-853, -320]
    s = load_scene(d)
    assert isinstance(s.line_types, MappingProxyType)
    with pytest.raises(TypeError):
        s.line_types["x"] = None  # type: ignore[index]
    assert isinstance(s.sections, tuple)
    assert s.end_a.position == (-853.0, -320.0)
    assert all(type(v) is float for v in s.end_a.position + s.environment.current)
    with pytest.raises(dataclasses.FrozenInstanceError):
        s.name = "x"  # type: ignore[misc]


def test_defaults_of_a_minimal_scene():
    """Only the required keys: every default is the documented one, no depth means no seabed."""
    d = {"line_types": {"c": {"EA": 1e6, "mass": 1.0, "diameter": 0.01}},
         "sections": [{"type": "c", "length": 10.0, "segments": 5}],
         "end_a": {"condition": "pinned", "position": [0.0, 0.0]},
         "end_b": {"condition": "free"}}
    s = load_scene(d)
    assert s.name == "unnamed" and s.model is Model.PLANAR
    env = s.environment
    assert (env.gravity, env.water_density, env.depth, env.current) == (G, 1025.0, None, (0.0, 0.0))
    assert s.seabed is None
    lt = s.line_types["c"]
    assert (lt.EI, lt.cd_normal, lt.cd_tangential, lt.ca_normal, lt.max_strain) == \
        (0.0, 1.2, 0.008, 1.0, 0.1)
    assert s.end_b == End(EndCondition.FREE, force=(0.0, 0.0))
    assert s.end_a.angle_deg is None and s.end_a.force is None and s.end_a.motion is None


def test_depth_without_seabed_table_gives_default_seabed():
    """environment.depth alone gives a Seabed with the default stiffness and friction."""
    d = base()
    del d["seabed"]
    assert load_scene(d).seabed == Seabed()


def test_clamped_and_free_ends_and_motion_defaults():
    """A clamped end keeps angle_deg (radians via .angle); a free end gets its force; phase
    defaults to zero and kind to harmonic."""
    d = base()
    d["line_types"]["chain"]["EI"] = 1.0e4
    d["end_a"] = {"condition": "clamped", "position": [-853.87, -320.0], "angle_deg": 30,
                  "motion": {"period": 5.0, "amplitude": [0.5, 0.0]}}
    d["end_b"] = {"condition": "free", "force": [1.0e4, 2.0e5]}
    s = load_scene(d)
    assert s.end_a.angle_deg == 30.0 and s.end_a.angle == pytest.approx(math.pi / 6, rel=1e-12)
    assert s.end_a.motion.kind == "harmonic" and s.end_a.motion.phase_deg == (0.0, 0.0)
    assert s.end_b.force == (1.0e4, 2.0e5) and s.end_b.position is None


@pytest.mark.parametrize("rho", [1025.0, 1000.0, 0.0])
def test_computed_weight_is_the_buoyancy_formula(rho):
    """weight = (mass - rho*pi*d^2/4)*g when not given; rho = 0 (in air) gives mass*g."""
    d = base()
    d["environment"]["water_density"] = rho
    d["environment"]["gravity"] = 9.81
    lt = load_scene(d).line_types["chain"]
    assert lt.weight == pytest.approx((77.7066 - rho * math.pi * 0.09**2 / 4) * 9.81, rel=1e-12)
    if rho == 0.0:
        assert lt.weight == pytest.approx(77.7066 * 9.81, rel=1e-12)


def test_given_weight_wins_and_may_be_negative():
    """An explicit weight is kept as given, even <= 0 (a buoyant line)."""
    d = base()
    d["line_types"]["chain"]["weight"] = -12.5
    assert load_scene(d).line_types["chain"].weight == -12.5


@pytest.mark.parametrize("make", [base, multi])
def test_dict_round_trip(make):
    """load_scene(scene_to_dict(s)) == s (except source), and scene_to_dict writes every key."""
    s = load_scene(make())
    d = scene_to_dict(s)
    assert same_but_source(load_scene(d), s)
    assert set(d["line_types"]["chain"]) == {"EA", "EI", "mass", "diameter", "weight",
                                             "cd_normal", "cd_tangential", "ca_normal",
                                             "max_strain"}
    assert scene_to_dict(load_scene(d)) == d


def test_dict_round_trip_of_clamped_free_and_no_seabed():
    """Round trip also holds for angle_deg, force, motion on end A and a scene without depth."""
    d = base()
    del d["seabed"], d["environment"]["depth"]
    d["line_types"]["chain"]["EI"] = 5.0
    d["end_a"] = {"condition": "clamped", "position": [0.0, 0.0], "angle_deg": -80.0,
                  "motion": {"period": 3.0, "amplitude": [0.1, 0.2], "phase_deg": [10.0, 20.0]}}
    d["end_b"] = {"condition": "free", "force": [0.0, -1.0]}
    s = load_scene(d)
    assert same_but_source(load_scene(scene_to_dict(s)), s)


def test_toml_file_round_trip(tmp_path):
    """scene_to_toml written to a file and read back gives the same scene, for odd names too."""
    d = multi()
    d["name"] = 'quote " and \\ and é'
    d["line_types"]["my rope.v2"] = d["line_types"].pop("rope")
    d["sections"][1]["type"] = "my rope.v2"
    s = load_scene(d)
    path = tmp_path / "scene.toml"
    path.write_text(scene_to_toml(s), encoding="utf-8")
    back = load_scene(path)
    assert back.source == str(path)
    assert same_but_source(back, s)
    with importlib.resources.as_file(oc3_path()) as oc3:
        s = load_scene(str(oc3))
    path.write_text(scene_to_toml(s), encoding="utf-8")
    assert same_but_source(load_scene(path), s)


def test_scene_passes_through_and_input_dict_is_not_changed():
    """A Scene is returned as is; loading never mutates the caller's dict."""
    d = base()
    before = copy.deepcopy(d)
    s = load_scene(d)
    assert d == before
    assert load_scene(s) is s


# ----------------------------------------------------------------------------- bad input

def _set(path: str, value):
    """A modifier that sets (or, with value DELETE, removes) ``path`` in a base() dict."""
    def modify(d):
        keys = [int(k) if k.isdigit() else k for k in path.replace("[", ".").replace("]", "")
                .split(".")]
        for k in keys[:-1]:
            d = d[k]
        if value is DELETE:
            del d[keys[-1]]
        else:
            d[keys[-1]] = value
    return modify


DELETE = object()
NAN, INF = float("nan"), float("inf")

# (what is wrong, modifier, fragments the message must contain: key path, value, hint)
BAD = {
    "unknown keys, with did-you-mean": [
        ("top", _set("sectoins", []), ["sectoins", "did you mean 'sections'?"]),
        ("env", _set("environment.gravty", 9.8), ["environment.gravty", "'gravity'"]),
        ("seabed", _set("seabed.stifness", 1.0), ["seabed.stifness", "'stiffness'"]),
        ("line type", _set("line_types.chain.diamter", 0.1),
         ["line_types.chain.diamter: unknown key; did you mean 'diameter'? (allowed: EA, "]),
        ("section", _set("sections[0].lenght", 1.0), ["sections[0].lenght", "'length'"]),
        ("end", _set("end_a.positon", [0, 0]), ["end_a.positon", "'position'"]),
        ("motion", _set("end_b.motion.amplitud", [0, 0]),
         ["end_b.motion.amplitud", "'amplitude'"]),
        ("far off", _set("line_types.chain.zzz", 1), ["line_types.chain.zzz: unknown key (allowed"]),
        ("non-string key", _set("end_a.3", 1), ["end_a", "key 3 must be a string"]),
    ],
    "wrong types": [
        ("string number", _set("line_types.chain.EA", "3.8e8"), ["line_types.chain.EA = '3.8e8'",
                                                                 "must be a number > 0"]),
        ("bool number", _set("line_types.chain.mass", True), ["line_types.chain.mass = True"]),
        ("float segments", _set("sections[0].segments", 50.0),
         ["sections[0].segments = 50.0", "integer"]),
        ("bool segments", _set("sections[0].segments", True), ["sections[0].segments = True"]),
        ("name", _set("name", 3), ["name = 3", "string"]),
        ("table", _set("environment", [1.0]), ["environment = [1.0]", "must be a table"]),
        ("line type table", _set("line_types.chain", 5), ["line_types.chain = 5"]),
        ("sections array", _set("sections", {"type": "chain"}),
         ["sections = {'type': 'chain'}", "array of tables"]),
        ("section table", _set("sections[0]", "chain"), ["sections[0] = 'chain'"]),
        ("vector", _set("end_a.position", "here"), ["end_a.position = 'here'", "list of 2"]),
        ("vector item", _set("end_b.motion.amplitude", [1, "2"]),
         ["end_b.motion.amplitude[1] = '2'"]),
        ("type name", _set("sections[0].type", 7), ["sections[0].type = 7", "unknown line type"]),
        ("condition", _set("end_a.condition", 1), ["end_a.condition = 1"]),
        ("angle", _set("end_a.angle_deg", "90"), ["end_a.angle_deg = '90'"]),
    ],
    "NaN and infinity": [
        ("nan length", _set("sections[0].length", NAN), ["sections[0].length = nan m",
                                                         "finite"]),
        ("inf EA", _set("line_types.chain.EA", INF), ["line_types.chain.EA = inf N", "finite"]),
        ("nan current", _set("environment.current", [NAN, 0.0]),
         ["environment.current[0] = nan m/s"]),
        ("-inf weight", _set("line_types.chain.weight", -INF), ["line_types.chain.weight = -inf"]),
        ("huge int", _set("line_types.chain.EA", 10**400), ["line_types.chain.EA = 1000", "finite"]),
    ],
    "out of range": [
        ("length", _set("sections[0].length", -3.0), ["sections[0].length = -3.0 m: must be > 0"]),
        ("zero length", _set("sections[0].length", 0), ["sections[0].length = 0 m: must be > 0"]),
        ("EA", _set("line_types.chain.EA", 0.0), ["line_types.chain.EA = 0.0 N: must be > 0"]),
        ("mass", _set("line_types.chain.mass", -1.0), ["line_types.chain.mass = -1.0 kg/m"]),
        ("diameter", _set("line_types.chain.diameter", 0.0), ["line_types.chain.diameter = 0.0 m"]),
        ("segments", _set("sections[0].segments", 0), ["sections[0].segments = 0: must be >= 1"]),
        ("EI", _set("line_types.chain.EI", -1.0), ["line_types.chain.EI = -1.0 N m^2: must be >= 0"]),
        ("cd", _set("line_types.chain.cd_normal", -0.1), ["line_types.chain.cd_normal = -0.1"]),
        ("cdt", _set("line_types.chain.cd_tangential", -1), ["line_types.chain.cd_tangential = -1"]),
        ("ca", _set("line_types.chain.ca_normal", -1.0), ["line_types.chain.ca_normal = -1.0"]),
        ("strain", _set("line_types.chain.max_strain", 0.0), ["line_types.chain.max_strain = 0.0"]),
        ("gravity", _set("environment.gravity", 0.0), ["environment.gravity = 0.0 m/s^2"]),
        ("rho", _set("environment.water_density", -1.0), ["environment.water_density = -1.0"]),
        ("depth", _set("environment.depth", -320.0), ["environment.depth = -320.0 m"]),
        ("stiffness", _set("seabed.stiffness", 0.0), ["seabed.stiffness = 0.0 Pa/m"]),
        ("friction", _set("seabed.friction", -0.5), ["seabed.friction = -0.5"]),
        ("period", _set("end_b.motion.period", 0.0), ["end_b.motion.period = 0.0 s"]),
    ],
    "unknown names": [
        ("line type", _set("sections[0].type", "chian"),
         ["sections[0].type = 'chian'", "did you mean 'chain'?", "(defined: 'chain')"]),
        ("condition", _set("end_a.condition", "fixed"),
         ["end_a.condition = 'fixed'", "'pinned', 'clamped', 'free'"]),
        ("condition typo", _set("end_b.condition", "pined"), ["did you mean 'pinned'?"]),
        ("model", _set("model", "beam"),
         ["model = 'beam'", "(allowed: 'planar', 'cable3d', 'rod', 'hybrid')"]),
        ("motion kind", _set("end_b.motion.kind", "sine"),
         ["end_b.motion.kind = 'sine'", "'harmonic'"]),
    ],
    "missing required keys": [
        ("sections", _set("sections", DELETE), ["sections: required key missing"]),
        ("empty sections", _set("sections", []), ["sections = []", "non-empty"]),
        ("line_types", _set("line_types", DELETE), ["line_types: required key missing"]),
        ("empty line_types", _set("line_types", {}), ["line_types = {}", "non-empty"]),
        ("end_a", _set("end_a", DELETE), ["end_a: required key missing"]),
        ("end_b", _set("end_b", DELETE), ["end_b: required key missing"]),
        ("condition", _set("end_a.condition", DELETE), ["end_a.condition: required key missing"]),
        ("EA", _set("line_types.chain.EA", DELETE), ["line_types.chain.EA: required key missing"]),
        ("mass", _set("line_types.chain.mass", DELETE), ["line_types.chain.mass: required"]),
        ("diameter", _set("line_types.chain.diameter", DELETE), ["line_types.chain.diameter: req"]),
        ("length", _set("sections[0].length", DELETE), ["sections[0].length: required"]),
        ("segments", _set("sections[0].segments", DELETE), ["sections[0].segments: required"]),
        ("type", _set("sections[0].type", DELETE), ["sections[0].type: required", "'chain'"]),
        ("position", _set("end_a.position", DELETE), ["end_a.position: required", "pinned"]),
        ("period", _set("end_b.motion.period", DELETE), ["end_b.motion.period: required"]),
        ("amplitude", _set("end_b.motion.amplitude", DELETE), ["end_b.motion.amplitude: req"]),
    ],
    "vectors of the wrong length": [
        ("current", _set("environment.current", [0.0, 0.0, 0.0]),
         ["environment.current = [0.0, 0.0, 0.0] m/s: must be a list of 2 numbers"]),
        ("position", _set("end_a.position", [1.0]), ["end_a.position = [1.0] m"]),
        ("amplitude", _set("end_b.motion.amplitude", [1.0]), ["end_b.motion.amplitude = [1.0]"]),
        ("phase", _set("end_b.motion.phase_deg", []), ["end_b.motion.phase_deg = [] deg"]),
    ],
    "ends that contradict their condition": [
        ("free with position", _set("end_b.condition", "free"),
         ["end_b.position = [-5.2, -70.0] m", "unknown"]),
        ("force on pinned", _set("end_a.force", [1.0, 0.0]), ["end_a.force = [1.0, 0.0] N",
                                                              "only a free end"]),
        ("angle on pinned", _set("end_a.angle_deg", 45.0), ["end_a.angle_deg = 45.0 deg",
                                                            "only a clamped end"]),
        ("clamped without angle", _set("end_a.condition", "clamped"),
         ["end_a.angle_deg: required"]),
        ("clamped without EI", lambda d: d["end_a"].update(condition="clamped", angle_deg=0.0),
         ["end_a.condition = 'clamped'", "line_types.chain.EI = 0.0", "EI > 0"]),
        ("motion on free end", lambda d: d.update(
            end_a={"condition": "free", "motion": {"period": 1.0, "amplitude": [1, 1]}}),
         ["end_a.motion = {", "only a pinned or clamped end moves"]),
        ("both free", lambda d: d.update(end_a={"condition": "free"}, end_b={"condition": "free"}),
         ["end_b.condition = 'free'", "at least one end must be pinned or clamped"]),
    ],
    "geometry": [
        ("below seabed", _set("end_a.position", [-853.87, -321.0]),
         ["end_a.position = [-853.87, -321.0] m", "below the seabed at z = -320.0"]),
        ("seabed without depth", _set("environment.depth", DELETE),
         ["seabed = {'stiffness': 100000.0, 'friction': 0.0}", "needs environment.depth"]),
        ("out of reach", _set("end_b.position", [300.0, 0.0]),
         ["end_b.position = [300.0, 0.0]", "apart but the line stretches to at most 992.4 m"]),
    ],
}
CASES = [pytest.param(mod, frags, id=f"{kind}: {name}")
         for kind, cases in BAD.items() for name, mod, frags in cases]


@pytest.mark.parametrize("modify, fragments", CASES)
def test_bad_input_gives_one_line_scene_error(modify, fragments):
    """Each kind of bad input: a SceneError whose one-line message names the key path and the
    value received (and the did-you-mean suggestion or the allowed range)."""
    d = base()
    modify(d)
    with pytest.raises(SceneError) as info:
        load_scene(d)
    msg = str(info.value)
    assert "\n" not in msg
    for fragment in fragments:
        assert fragment in msg, f"{fragment!r} not in {msg!r}"


def test_out_of_reach_message_gives_both_numbers():
    """The reach check names end_b.position and quotes the distance and the stretched length."""
    d = base()
    d["end_a"]["position"] = [0.0, 0.0]
    d["end_b"]["position"] = [1000.0, 0.0]
    with pytest.raises(SceneError) as info:
        load_scene(d)
    assert str(info.value) == (
        "end_b.position = [1000.0, 0.0]: the ends are 1000.0 m apart but the line stretches to "
        "at most 992.4 m (length 902.2 m at max_strain 0.1)")
    d["end_b"]["position"] = [992.0, 0.0]  # just within reach: accepted
    assert load_scene(d).end_b.position == (992.0, 0.0)


def test_missing_file_and_invalid_toml_name_the_path(tmp_path):
    """A path that does not exist, a directory and a file that is not TOML each give a
    one-line SceneError naming the path."""
    for path in (tmp_path / "nope.toml", tmp_path):
        with pytest.raises(SceneError, match="^" + str(path).replace("\\", "\\\\")):
            load_scene(path)
    bad = tmp_path / "bad.toml"
    bad.write_text("name = 'x'\n[environment\ngravity = 9.8\n")
    with pytest.raises(SceneError) as info:
        load_scene(str(bad))
    assert str(bad) in str(info.value) and "invalid TOML" in str(info.value)
    assert "\n" not in str(info.value)


def test_source_of_the_wrong_type():
    """Something that is neither a path, a dict nor a Scene is a SceneError too."""
    with pytest.raises(SceneError, match=r"scene = 42: must be a path"):
        load_scene(42)  # type: ignore[arg-type]


JUNK = [None, "x", True, 0, -1.0, NAN, [], [1.0, 2.0, 3.0], {}, {"zz": 1}, ["a", None]]


def _leaf_paths(d, prefix=""):
    """Every key path of a nested dict/list, tables included."""
    items = d.items() if isinstance(d, dict) else enumerate(d)
    for k, v in items:
        path = f"{prefix}[{k}]" if isinstance(k, int) else (f"{prefix}.{k}" if prefix else k)
        yield path
        if isinstance(v, (dict, list)):
            yield from _leaf_paths(v, path)


@pytest.mark.parametrize("junk", JUNK, ids=repr)
def test_junk_anywhere_gives_a_purpose_built_scene_error(junk):
    """Any junk value at any key of a valid scene either loads or raises a SceneError from a
    specific check (never a KeyError/TypeError, nor the loader's catch-all message)."""
    for path in _leaf_paths(multi()):
        d = multi()
        _set(path, junk)(d)
        try:
            load_scene(d)
        except SceneError as exc:
            msg = str(exc)
            assert "\n" not in msg and "invalid scene (" not in msg, (path, msg)


def test_several_lines_only_in_cable3d_and_guided_only_on_rods():
    """[[lines]] with model = "rod" or "hybrid" (which solve one line) and a guided end on the
    planar line (which has no tangent to hold on a free end) are refused when the scene is
    read, naming the key, not later in a solve."""
    d = sc.load_scene("sphere").to_dict()
    for model in ("rod", "hybrid"):
        d["model"] = model
        with pytest.raises(sc.SceneError, match=r"^lines = .*model = \"cable3d\" only"):
            sc.load_scene(d)
    d = sc.load_scene("seed001").to_dict()
    d["end_b"] = {"condition": "guided"}
    with pytest.raises(sc.SceneError, match=r"^end_b.condition = 'guided': .*\"rod\""):
        sc.load_scene(d)


def test_a_mistyped_builtin_name_gets_the_closest():
    """A scene name that is neither a file nor a built-in scene: the closest built-in name
    is suggested, or all of them when none is close."""
    with pytest.raises(sc.SceneError, match=r"^seed01: scene file not found \(nor a built-in "
                       r"scene; did you mean 'seed001'\?\)$"):
        sc.load_scene("seed01")
    with pytest.raises(sc.SceneError, match=r"nor a built-in scene: oc3, .*towed_body\)$"):
        sc.load_scene("zzzz")
