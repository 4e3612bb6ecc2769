"""Above the water (issue 33): symcable has no free surface (z = 0), so what is loaded as
submerged must be in the water.

- a line that its held ends put mostly out of the water (an anchor 20 m above the surface)
  is refused when the scene is read, in one line naming the key and the value, and
  ``symcable check`` does not say "ok" (symcable.scene.checks._check_free_surface);
- a free body or free buoy that the static solve floats above the surface, its buoyancy
  still counted in full, or a buoyant section of a line floated above it, is refused after
  the solve (symcable.api.above_water), and a line the solve leaves mostly in air is
  warned about;
- a fairlead a few metres above the surface, and a scene in air, solve as before, with no
  such message.
"""
from __future__ import annotations

import copy
import math

import numpy as np
import pytest

import symcable as sc
from symcable.cli.main import main
from symcable.errors import SceneError, SymcableError
from symcable.scene import load_scene

from conftest import OC3, two_point

# ----------------------------------------------------------------------------- scenes

#: an anchor 20 m above the free surface, its line rising from a fairlead 2 m above it:
#: 36 m of chain, at least (20 + 2) / 1.1 = 20 m of it in air whatever its shape
ANCHOR_UP = """
name = "anchor in the air"
model = "cable3d"
[environment]
water_density = 1025.0
depth = 50.0
[line_types.chain]
EA = 3.84e8
mass = 77.7
diameter = 0.09
[[sections]]
type = "chain"
length = 36.0
segments = 12
[end_a]
condition = "pinned"
position = [30.0, 0.0, 20.0]
[end_b]
condition = "pinned"
position = [0.0, 0.0, 2.0]
"""

#: the same chain, its anchor on the seabed and its fairlead 3 m above the surface
FAIRLEAD_UP = ANCHOR_UP.replace("length = 36.0", "length = 95.0").replace(
    "[30.0, 0.0, 20.0]", "[70.0, 0.0, -50.0]").replace("[0.0, 0.0, 2.0]", "[0.0, 0.0, 3.0]")


def _write(tmp_path, text, name="scene.toml"):
    path = tmp_path / name
    path.write_text(text)
    return path


#: a free body moored by three chains to the seabed (test_moordyn_bodies's deck, its chains
#: 223 m instead of 215 m and its volume 300 m^3 instead of 250 m^3): its buoyancy,
#: 3.0 MN, lifts it until the chains are nearly taut, its reference point (MoorDyn's centre
#: of buoyancy) at z = +4.4 m
DEPTH, R_ANCHOR, R_FAIR = 80.0, 213.5, 5.0


def body_deck(length: float = 223.0, volume: float = 300.0) -> str:
    points = "\n".join(
        f"{2 * k + 1}  Fixed  {R_ANCHOR * math.cos(math.radians(120 * k)):.10f} "
        f"{R_ANCHOR * math.sin(math.radians(120 * k)):.10f} {-DEPTH}  0 0 0 0\n"
        f"{2 * k + 2}  Body1  {R_FAIR * math.cos(math.radians(120 * k)):.10f} "
        f"{R_FAIR * math.sin(math.radians(120 * k)):.10f} -5.0  0 0 0 0" for k in range(3))
    lines = "\n".join(f"{k + 1}  chain  {2 * k + 1}  {2 * k + 2}  {length}  10  -"
                      for k in range(3))
    return f"""MoorDyn v2 input file: a buoyant body moored by three chains
---------------------- LINE TYPES -----------------------------------
TypeName   Diam    Mass/m   EA        BA/-zeta  EI  Cd   Ca   CdAx  CaAx
(name)     (m)     (kg/m)   (N)       (N-s/-)   (-) (-)  (-)  (-)   (-)
chain      0.09    77.7     3.84e8    -1.0      0   1.2  1.0  0.4   0.5
---------------------- BODIES ---------------------------------------
ID  Attachment  X0  Y0  Z0     r0  p0  y0  Mass    CG     I                 Volume   CdA  Ca
(#) (word)      (m) (m) (m)    (deg)(deg)(deg)(kg) (m)    (kg-m^2)          (m^3)    (m^2) (-)
1   Free        0   0   -30.0  0   0   0   2.0e5   -3.0   4e6|4e6|1e6       {volume}  0    0
---------------------- POINTS ---------------------------------------
ID  Attachment  X  Y  Z  M  V  CdA  Ca
(#) (word)      (m) (m) (m) (kg) (m^3) (m^2) (-)
{points}
---------------------- LINES ----------------------------------------
ID  LineType  AttachA  AttachB  UnstrLen  NumSegs  LineOutputs
(#) (name)    (ID)     (ID)     (m)       (-)      (-)
{lines}
---------------------- OPTIONS --------------------------------------
{DEPTH}   WtrDpth
1025.0    WtrDnsty
9.80665   g
1e8       kBot
------------------------- need this line -------------------------------------
"""


def buoy_scene(volume: float) -> dict:
    """A buoy (a free point) held down by a 60 m rope from an anchor 50 m deep and tied by
    a 40 m rope to a vessel point at the surface 60 m away: with 2 m^3 it floats up to the
    ropes' reach, above the surface."""
    return {"model": "cable3d", "environment": {"depth": 50.0},
            "line_types": {"rope": {"EA": 1e7, "mass": 5.0, "diameter": 0.08}},
            "points": {"anchor": {"kind": "fixed", "position": [0.0, 0.0, -50.0]},
                       "buoy": {"kind": "free", "position": [10.0, 0.0, -20.0], "mass": 200.0,
                                "volume": volume, "diameter": 1.2},
                       "ship": {"kind": "vessel", "position": [60.0, 0.0, 0.0]}},
            "lines": [{"name": "riser", "end_a": "anchor", "end_b": "buoy",
                       "sections": [{"type": "rope", "length": 60.0, "segments": 12}]},
                      {"name": "tether", "end_a": "buoy", "end_b": "ship",
                       "sections": [{"type": "rope", "length": 40.0, "segments": 8}]}]}


def _one_line(msg: str) -> str:
    assert "\n" not in msg and "Traceback" not in msg
    return msg


def _solve_checked(scene):
    """The static solution checked against the surface, whether solve_static does it
    already or not (check_above_water adds each warning once)."""
    from symcable.api.above_water import check_above_water
    scene = load_scene(scene)
    return check_above_water(scene, sc.solve_static(scene, codegen=False))


# ----------------------------------------------------------------------------- at load

def test_anchor_above_the_surface_is_refused_in_one_line(tmp_path):
    """The anchor 20 m up: one SceneError naming the key, the value, how much of the line is
    in air and what is allowed."""
    with pytest.raises(SceneError) as info:
        load_scene(_write(tmp_path, ANCHOR_UP))
    msg = _one_line(str(info.value))
    assert msg.startswith("end_a.position = [30.0, 0.0, 20.0] m: 20.00 m above the free "
                          "surface (z = 0)"), msg
    assert "end_b.position at z = 2.000 m" in msg and "mostly out of the water" in msg
    assert "at least 20.00 m of its 36.00 m (56 %)" in msg
    assert "environment.water_density = 0" in msg


def test_check_does_not_say_ok_on_an_anchor_above_the_surface(tmp_path, capsys):
    """``symcable check`` refuses it: exit status 2, one line on stderr, no "ok"."""
    path = _write(tmp_path, ANCHOR_UP)
    assert main(["check", str(path)]) == 2
    out, err = capsys.readouterr()
    assert "ok" not in out.split()
    err = _one_line(err.strip())
    assert err.startswith("symcable: SceneError: end_a.position = [30.0, 0.0, 20.0] m"), err


def test_refusals_name_points_inline_ends_fixed_bodies_and_deck_lines(tmp_path):
    """Every kind of held end is named by its key: a line between two vessel points on a
    deck that it cannot leave even stretched to max_strain; a fixed body's point; a
    MoorDyn deck's anchor, prefixed with its deck line."""
    base = {"model": "cable3d", "environment": {"depth": 30.0},
            "line_types": {"rope": {"EA": 1e7, "mass": 5.0, "diameter": 0.08}},
            "lines": [{"name": "span", "end_a": "a", "end_b": "b",
                       "sections": [{"type": "rope", "length": 40.5, "segments": 10}]}]}
    d = copy.deepcopy(base)
    d["points"] = {"a": {"kind": "vessel", "position": [0.0, 0.0, 8.0]},
                   "b": {"kind": "vessel", "position": [40.0, 0.0, 12.0]}}
    with pytest.raises(SceneError) as info:
        load_scene(d)
    msg = _one_line(str(info.value))
    assert msg.startswith("points.b.position = [40.0, 0.0, 12.0] m: 12.00 m above"), msg
    assert "cannot reach the water even stretched to max_strain: all of its 40.50 m" in msg
    assert "lines[0] ('span')" in msg

    d = copy.deepcopy(base)
    d["points"] = {"a": {"kind": "fixed", "position": [0.0, 0.0, -10.0]}}
    d["bodies"] = {"deck": {"kind": "fixed", "position": [5.0, 0.0, 40.0]}}
    d["lines"][0]["end_b"] = "deck@[0.0, 0.0, -10.0]"
    d["lines"][0]["sections"][0]["length"] = 40.0
    with pytest.raises(SceneError) as info:
        load_scene(d)
    msg = _one_line(str(info.value))
    assert msg.startswith("lines[0].end_b = 'deck@[0.0, 0.0, -10.0]': this point of the "
                          "fixed body is 30.00 m above the free surface"), msg

    deck = _write(tmp_path, """MoorDyn v2 input file: one chain
---------------------- LINE TYPES -----------------------------------
TypeName   Diam    Mass/m   EA        BA/-zeta  EI  Cd   Ca   CdAx  CaAx
(name)     (m)     (kg/m)   (N)       (N-s/-)   (-) (-)  (-)  (-)   (-)
chain      0.09    77.7     3.84e8    -1.0      0   1.2  1.0  0.4   0.5
---------------------- POINTS ---------------------------------------
ID  Attachment  X  Y  Z  M  V  CdA  Ca
(#) (word)      (m) (m) (m) (kg) (m^3) (m^2) (-)
1   Fixed       30  0  20   0 0 0 0
2   Vessel      0   0  0    0 0 0 0
---------------------- LINES ----------------------------------------
ID  LineType  AttachA  AttachB  UnstrLen  NumSegs  LineOutputs
(#) (name)    (ID)     (ID)     (m)       (-)      (-)
1   chain     1        2        36        12       -
---------------------- OPTIONS --------------------------------------
50        WtrDpth
------------------------- need this line -------------------------------------
""", "anchor_up.txt")
    with pytest.raises(SceneError) as info:
        load_scene(deck)
    msg = _one_line(str(info.value))
    assert msg.startswith(f"{deck}:9: '1   Fixed       30  0  20   0 0 0 0': end_a.position = "
                          "[30.0, 0.0, 20.0] m: 20.00 m above the free surface"), msg


def test_a_fairlead_above_the_surface_solves_with_no_message(tmp_path, capsys):
    """A fairlead 3 m above the surface (the line leaves the water to reach it), and the
    OC3 line hung from a point 20 m up: read, checked "ok", solved, no warning about the
    surface."""
    path = _write(tmp_path, FAIRLEAD_UP)
    assert main(["check", str(path)]) == 0
    assert capsys.readouterr().out.split()[-1] == "ok"
    sol = _solve_checked(path)
    assert sol.status == "converged" and sol.positions[-1, 2] == pytest.approx(3.0)
    assert not [w for w in sol.warnings if "free surface" in w]
    oc3 = copy.deepcopy(OC3)
    oc3["end_a"]["position"] = [-853.87, 20.0]  # end A above the water, the line hangs into it
    sol = _solve_checked(oc3)
    assert not [w for w in sol.warnings if "free surface" in w]


def test_a_scene_in_air_is_not_checked():
    d = two_point((0.0, 20.0), (25.0, 2.0), length=30.0)
    d["environment"]["water_density"] = 0.0
    sol = _solve_checked(d)
    assert sol.status == "converged" and not sol.warnings


# ----------------------------------------------------------------------------- after the solve

def test_a_line_left_mostly_in_air_is_warned():
    """End A 20 m up and end B at the surface, 102 m apart, 103 m of rope: it may reach the
    water, so it is read; the solve leaves most of it in air, and says how much and the
    weight counted short there, once."""
    d = two_point((0.0, 20.0), (100.0, 0.0), length=103.0, segments=30)
    scene = load_scene(d)
    sol = _solve_checked(scene)
    text = [w for w in sol.warnings if "free surface" in w]
    assert len(text) == 1, sol.warnings
    (w,) = text
    z = sol.positions[:, 1]
    assert np.mean(z > 0) > 0.5
    assert w.startswith("the line: ") and "m of its 103 m" in w and "up to z = +20 m" in w
    up = float(w.split(": ")[1].split(" m of")[0])
    assert 51.5 < up < 103.0
    short = float(w.split("counted ")[1].split(" N short")[0])
    assert short == pytest.approx(up * (20.0 * 9.80665 - 100.0), rel=1e-3)
    from symcable.api.above_water import check_above_water
    assert check_above_water(scene, sol) is sol  # each warning once


def test_a_line_of_several_left_mostly_in_air_is_warned_on_it_and_the_system():
    """The same rope between a vessel point 20 m up and a buoy at the surface, the buoy
    moored to the seabed: the warning names the line, on the line's solution and the
    system's."""
    d = {"model": "cable3d", "environment": {"depth": 50.0},
         "line_types": {"rope": {"EA": 1e7, "mass": 20.0, "diameter": 0.05}},
         "points": {"ship": {"kind": "vessel", "position": [0.0, 0.0, 20.0]},
                    "top": {"kind": "fixed", "position": [100.0, 0.0, 0.0]},
                    "anchor": {"kind": "fixed", "position": [140.0, 0.0, -50.0]}},
         "lines": [{"name": "span", "end_a": "ship", "end_b": "top",
                    "sections": [{"type": "rope", "length": 103.0, "segments": 30}]},
                   {"name": "riser", "end_a": "anchor", "end_b": "top",
                    "sections": [{"type": "rope", "length": 70.0, "segments": 10}]}]}
    sol = _solve_checked(d)
    mine = [w for w in sol.warnings if "free surface" in w]
    assert len(mine) == 1 and mine[0].startswith("lines[0] ('span'): "), sol.warnings
    assert mine[0] in sol.lines["span"].warnings
    assert not [w for w in sol.lines["riser"].warnings if "free surface" in w]


def test_a_free_body_floating_above_the_surface_is_refused(tmp_path):
    """The MoorDyn body floats to z = +4.4 m with its 300 m^3 counted in full: one
    SymcableError (not a ConvergenceError) naming the body, where it ended, its volume and
    what to change; with 250 m^3 it stays under (z = -0.5 m... ) and solves."""
    from symcable.api.above_water import AboveWaterError
    path = _write(tmp_path, body_deck(), "buoy.txt")
    with pytest.raises(SymcableError) as info:
        _solve_checked(path)
    assert isinstance(info.value, AboveWaterError)
    assert not isinstance(info.value, sc.ConvergenceError)
    msg = _one_line(str(info.value))
    assert msg.startswith("bodies.body1: the static solve floats it to z = +4.4"), msg
    assert "volume 300 m^3" in msg and "no waterplane" in msg and "kind = 'fixed'" in msg
    z = info.value.solution.bodies["body1"].position[2]
    assert 4.0 < z < 5.0
    ok = _solve_checked(_write(tmp_path, body_deck(length=215.0), "held.txt"))
    assert ok.bodies["body1"].position[2] < 0.0


def test_a_free_buoy_floating_above_the_surface_is_refused():
    from symcable.api.above_water import AboveWaterError
    with pytest.raises(AboveWaterError) as info:
        _solve_checked(buoy_scene(2.0))
    msg = _one_line(str(info.value))
    assert msg.startswith("points.buoy: the static solve floats it to z = +"), msg
    assert "volume 2 m^3" in msg and "volume = 0 for a point in air" in msg
    sol = _solve_checked(buoy_scene(0.0))  # a clump weight: no buoyancy, nothing to refuse
    assert sol.points["buoy"].position[2] < 0.0


def _lazy_wave(buoyant_length: float, model: str) -> dict:
    """A lazy wave in 100 m of water: 120 m of chain from the anchor, a buoyant section
    (390 N/m net buoyancy) of ``buoyant_length`` m, 60 m of chain up to a fairlead 30 m
    below the surface, 150 m away."""
    a, b = [0.0, -100.0], [150.0, -30.0]
    if model == "cable3d":
        a, b = [0.0, 0.0, -100.0], [150.0, 0.0, -30.0]
    return {"name": "lazy wave", "model": model, "environment": {"depth": 100.0},
            "line_types": {"chain": {"mass": 100.0, "diameter": 0.08, "EA": 5e8},
                           "float": {"mass": 250.0, "diameter": 0.6, "EA": 5e8}},
            "sections": [{"type": "chain", "length": 120.0, "segments": 24},
                         {"type": "float", "length": buoyant_length, "segments": 30},
                         {"type": "chain", "length": 60.0, "segments": 12}],
            "end_a": {"condition": "pinned", "position": a},
            "end_b": {"condition": "pinned", "position": b}}


@pytest.mark.parametrize("model", ["planar", "cable3d"])
def test_a_buoyant_section_floated_above_the_surface_is_refused(model):
    """150 m of the buoyant section lift its hump to z = +16 m, its buoyancy counted in full
    there (the fuzz study's lazy waves stood 4-95 m above z = 0, unwarned): refused in one
    line naming the section, where it ended and what to change. With 40 m the hump stays
    under water (the line's highest point is the fairlead) and the scene solves."""
    from symcable.api.above_water import AboveWaterError
    with pytest.raises(AboveWaterError) as info:
        _solve_checked(_lazy_wave(150.0, model))
    msg = _one_line(str(info.value))
    assert msg.startswith("the line: the static solve floats its buoyant sections[1]"), msg
    assert "net buoyancy 390.4 N/m" in msg and "above the free surface" in msg
    z = float(msg.split("to z = ")[1].split(" m")[0])
    top = float(np.max(info.value.solution.positions[:, -1]))
    assert z == pytest.approx(top, rel=1e-2) and 5.0 < z < 30.0
    sol = _solve_checked(_lazy_wave(40.0, model))
    assert sol.status == "converged"
    assert float(np.max(sol.positions[:, -1])) == pytest.approx(-30.0)
