"""MoorDyn v2 decks with bodies (issue 13, item 6; symcable/scene/moordyn_bodies.py): the
BODIES table and points on bodies read into ``[bodies.body<ID>]`` and ``body<ID>@[x, y, z]``
line ends; a free body moored by three chains solves to the same equilibrium as the same
scene written in TOML, and to MoorDyn's own (its time run settled); a coupled
body is held; each deck not representable is one SceneError naming its line."""
from __future__ import annotations

import math

import numpy as np
import pytest

import symcable as sc
from symcable.errors import SceneError
from symcable.scene import load_scene, moordyn_deck
from test_bodies_moored import CHAIN, DEPTH, G, LENGTH, R_ANCHOR, R_FAIR, RHO, _moored

SEGMENTS = 10
#: the body of test_bodies_moored, MoorDyn-style: buoyancy at the reference point
MASS, VOLUME, CG_Z, INERTIA = 2.0e5, 250.0, -3.0, (4e6, 4e6, 1e6)


def deck(attachment: str = "Free", cda: str = "0", ca: str = "0") -> str:
    points = "\n".join(
        f"{2 * k + 1}  Fixed  {R_ANCHOR * math.cos(math.radians(120 * k)):.10f} "
        f"{R_ANCHOR * math.sin(math.radians(120 * k)):.10f} {-DEPTH}  0 0 0 0\n"
        f"{2 * k + 2}  Body1  {R_FAIR * math.cos(math.radians(120 * k)):.10f} "
        f"{R_FAIR * math.sin(math.radians(120 * k)):.10f} -5.0  0 0 0 0" for k in range(3))
    lines = "\n".join(f"{k + 1}  chain  {2 * k + 1}  {2 * k + 2}  {LENGTH}  {SEGMENTS}  -"
                      for k in range(3))
    return f"""MoorDyn v2 input file: a submerged buoy moored by three chains
---------------------- LINE TYPES -----------------------------------
TypeName   Diam    Mass/m   EA        BA/-zeta  EI  Cd   Ca   CdAx  CaAx
(name)     (m)     (kg/m)   (N)       (N-s/-)   (-) (-)  (-)  (-)   (-)
chain      {CHAIN['diameter']}    {CHAIN['mass']}     {CHAIN['EA']}   -1.0      0   1.2  1.0  0.4   0.5
---------------------- BODIES ---------------------------------------
ID  Attachment  X0  Y0  Z0     r0  p0  y0  Mass    CG     I                      Volume   CdA  Ca
(#) (word)      (m) (m) (m)    (deg)(deg)(deg)(kg) (m)    (kg-m^2)               (m^3)    (m^2) (-)
1   {attachment}  0   0   -30.0  0   0   0   {MASS}  {CG_Z}  {INERTIA[0]}|{INERTIA[1]}|{INERTIA[2]}  {VOLUME}  {cda}  {ca}
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
{RHO}     WtrDnsty
{G}       g
1e8       kBot
0.002     dtM
60        TmaxIC
1e-7      threshIC
------------------------- need this line -------------------------------------
"""


def _toml_twin() -> dict:
    """test_bodies_moored's scene with the deck's numbers: buoyancy at the reference point
    (MoorDyn's), the seabed's damping MoorDyn's default."""
    d = _moored(SEGMENTS)
    d["bodies"]["spar"]["center_of_buoyancy"] = [0.0, 0.0, 0.0]
    d["bodies"]["spar"]["inertia"] = list(INERTIA)
    return d


def test_body_deck_reads_into_bodies(tmp_path):
    path = tmp_path / "buoy.txt"
    path.write_text(deck(cda="20|30|10|1|1|1", ca="1.0|1.0|0.5"))
    d = moordyn_deck(path)
    body = d.scene["bodies"]["body1"]
    assert body == {"position": [0.0, 0.0, -30.0], "orientation": [0.0, 0.0, 0.0],
                    "kind": "free", "mass": MASS, "inertia": list(INERTIA), "volume": VOLUME,
                    "center_of_gravity": [0.0, 0.0, CG_Z], "center_of_buoyancy": [0.0, 0.0, 0.0],
                    "cd_area": [20.0, 30.0, 10.0], "ca_volume": [250.0, 250.0, 125.0]}
    assert d.scene["lines"][0]["end_b"].startswith("body1@[5.0, 0.0, -5.0")
    assert any("rotational drag" in n for n in d.notes)
    assert d.origin["bodies.body1"] == 9
    s = load_scene(path)
    assert s.bodies["body1"].is_free and len(s.lines) == 3


def test_same_equilibrium_as_the_toml_scene(tmp_path):
    """The deck and its TOML twin solve to the same body pose and fairlead tensions, to
    round-off (measured 0 m: the same scene after reading)."""
    path = tmp_path / "buoy.txt"
    path.write_text(deck())
    a = sc.solve_static(path, codegen=False)
    b = sc.solve_static(_toml_twin(), codegen=False)
    np.testing.assert_allclose(a.bodies["body1"].position, b.bodies["spar"].position,
                               atol=1e-9)
    np.testing.assert_allclose(a.bodies["body1"].roll_pitch_yaw,
                               b.bodies["spar"].roll_pitch_yaw, atol=1e-9)
    for k in range(3):
        assert a.lines[f"line{k + 1}"].fairlead_tension == pytest.approx(
            b.lines[f"chain{k}"].fairlead_tension, rel=1e-9)


def test_against_moordyn_static_body_position(tmp_path):
    """MoorDyn 2.7.2 runs the deck: its body's heave settles slowly (a lightly damped
    oscillation of period ~160 s after the initial-condition stage, which stops with the
    body still 5 cm off), so the deck is run with a heavy drag (CdA = 3000 m^2, no effect on
    statics) for 600 s in 1 s steps, and the mean of the body's position over the last 200 s
    is compared with symcable's static pose: within 5 mm (the oscillation left over that
    window spans 14 mm; averaged, and the lines' lumped-mass discretisations being the same,
    measured 0.04 mm in heave, 1e-11 m across)."""
    md = pytest.importorskip("moordyn")
    import os
    path = tmp_path / "buoy.txt"
    path.write_text(deck(cda="3000", ca="1.0"))
    st = sc.solve_static(path, codegen=False)
    cwd = os.getcwd()
    os.chdir(tmp_path)
    try:
        system = md.Create(str(path))
        assert md.Init(system, [], []) == 0
        body = md.GetBody(system, 1)
        z = []
        for k in range(600):
            md.Step(system, [], [], float(k), 1.0)
            if k >= 400:
                z.append(md.GetBodyState(body)[0][:3])
        md.Close(system)
    finally:
        os.chdir(cwd)
    mean = np.mean(np.asarray(z), axis=0)
    assert np.max(np.abs(mean - st.bodies["body1"].position)) < 5e-3, \
        (mean, st.bodies["body1"].position)


def test_coupled_body_is_held_and_refusals(tmp_path):
    path = tmp_path / "held.txt"
    path.write_text(deck("Coupled"))
    d = moordyn_deck(path)
    assert d.scene["bodies"]["body1"] == {"position": [0.0, 0.0, -30.0],
                                          "orientation": [0.0, 0.0, 0.0], "kind": "fixed"}
    assert any("held at its position" in n for n in d.notes)
    st = sc.solve_static(path, codegen=False)
    np.testing.assert_allclose(st.bodies["body1"].position, [0, 0, -30.0])
    cases = {
        "CoupledPinned": (deck("CoupledPinned"), "body attachment 'CoupledPinned' is not "
                          "representable"),
        "no body": (deck().replace("1   Free  ", "2   Free  "), "a point on a body that "
                    "BODIES does not define"),
        "bad CG": (deck().replace(f"{MASS}  {CG_Z}", f"{MASS}  1|2"), "CG = '1|2': 1 or 3"),
        "massless free": (deck().replace(f"  {MASS}  ", "  0  "), "Mass and I must be > 0"),
        "point mass": (deck().replace("-5.0  0 0 0 0", "-5.0  10 0 0 0", 1), "with mass, "
                       "volume or force"),
    }
    for name, (text, fragment) in cases.items():
        p = tmp_path / f"{name.replace(' ', '_')}.txt"
        p.write_text(text)
        with pytest.raises(SceneError) as info:
            load_scene(p)
        msg = str(info.value)
        assert "\n" not in msg and fragment in msg and msg.startswith(f"{p}:"), (name, msg)
