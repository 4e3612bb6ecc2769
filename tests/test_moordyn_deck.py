"""MoorDyn v2 decks read by load_scene (symcable.scene.moordyn): the three chain decks of
/work/shared/reference/moordyn-chains (from MoorDyn's validation tests, BSD-3), the round
trip, and one SceneError naming the deck's line for each deck not representable yet.

Layer 1 (unit) tests, except the last, which solves the WD0050 statics (about 1 s). Numbers
the loader only copies from the deck are compared exactly.
"""
from __future__ import annotations

import math
from pathlib import Path

import pytest

import symcable as sc
from symcable.cli.main import main
from symcable.errors import SceneError
from symcable.scene import EndCondition, Model, load_scene, moordyn_deck, scene_to_toml
from symcable.scene.moordyn import ZETA_FACTOR, is_moordyn_deck, parse_moordyn

REF = Path("/work/shared/reference/moordyn-chains")
#: deck -> (depth, anchor x, line length, segments), from the deck text
CHAINS = {"WD0050": (50.0, 400.0, 410.0, 41), "WD0200": (200.0, 700.0, 760.0, 76),
          "WD0600": (600.0, 1500.0, 1700.0, 170)}

pytestmark = pytest.mark.skipif(not REF.is_dir(), reason="reference decks not present")


def deck_text(name: str = "WD0050") -> str:
    return (REF / f"{name}_Chain.txt").read_text(encoding="utf-8")


def write(tmp_path: Path, text: str, name: str = "deck.txt") -> Path:
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    return path


@pytest.mark.parametrize("name", sorted(CHAINS))
def test_chain_decks_load_with_the_deck_numbers(name):
    depth, anchor_x, length, segments = CHAINS[name]
    s = load_scene(REF / f"{name}_Chain.txt")
    assert s.model is Model.CABLE3D and s.dim == 3
    assert s.name == f"{name}_Chain line 1"
    env = s.environment
    assert (env.depth, env.water_density, env.gravity, env.current) == \
        (depth, 1025.0, 9.80665, (0.0, 0.0, 0.0))  # no g option: MoorDyn's 9.80665, ours too
    sb = s.seabed
    assert (sb.stiffness, sb.damping, sb.friction) == (1.0e5, 1.0e4, 0.5)
    assert list(s.line_types) == ["chain"]
    lt = s.line_types["chain"]
    assert (lt.diameter, lt.mass, lt.EA, lt.EI) == (0.252, 390.0, 1.674e9, 0.0)
    # CdAx is per surface area pi d l in MoorDyn, cd_tangential per d l
    assert (lt.cd_normal, lt.ca_normal, lt.cd_tangential, lt.ca_tangential) == \
        (1.37, 1.0, math.pi * 0.64, 0.0)
    # BA/-zeta = -1.0: MoorDyn's BA = zeta ds sqrt(EA m), cable3d's zeta 2 ds sqrt(EA m)
    assert lt.damping == -1.0 * ZETA_FACTOR == -1.0  # the same zeta convention as MoorDyn
    assert lt.weight == pytest.approx((390.0 - 1025.0 * math.pi * 0.252**2 / 4) * 9.80665,
                                      rel=1e-15)
    (sec,) = s.sections
    assert (sec.line_type, sec.length, sec.segments) == (lt, length, segments)
    assert s.end_a.condition is s.end_b.condition is EndCondition.PINNED
    assert s.end_a.position == (anchor_x, 0.0, -depth)  # point 1, Fixed: AttachA
    assert s.end_b.position == (0.0, 0.0, 0.0)  # point 2, Vessel: AttachB, no motion
    assert s.end_a.motion is None and s.end_b.motion is None


@pytest.mark.parametrize("name", sorted(CHAINS))
def test_round_trip_through_dict_and_toml(name, tmp_path):
    s = load_scene(REF / f"{name}_Chain.txt")
    assert load_scene(s.to_dict()) == s
    assert load_scene(write(tmp_path, scene_to_toml(s), "s.toml")) == s


def test_deck_notes_name_what_was_ignored():
    deck = moordyn_deck(REF / "WD0050_Chain.txt")
    text = "\n".join(deck.notes)
    for key in ("writeLog", "cfl", "dtIC", "TmaxIC", "threshIC", "fileIC", "disableOutTime"):
        assert f"{key} = " in text
    assert "Vessel point 2 is end_b" in text
    assert deck.origin["sections[0]"] == 15 and deck.origin["end_a"] == 10
    assert moordyn_deck(sc.demo_scene_path("oc3")) is None  # a TOML scene is no deck


def test_detection_by_content(tmp_path):
    assert is_moordyn_deck(deck_text())
    assert not is_moordyn_deck("name = 'x'\n# --- LINES ---\n")  # no line names MoorDyn
    # any file name: the content decides
    s = load_scene(write(tmp_path, deck_text(), "chain.dat"))
    assert s.name == "chain line 1" and s.sections[0].segments == 41


def test_toml_files_load_as_before(tmp_path):
    s = load_scene(sc.demo_scene_path("oc3"))
    assert s.model is Model.PLANAR and s.name.startswith("OC3")
    with pytest.raises(SceneError, match="invalid TOML"):
        load_scene(write(tmp_path, "this is [not toml\n"))
    with pytest.raises(SceneError, match="scene file not found"):
        load_scene(tmp_path / "missing.txt")


def test_options_defaults_and_aliases(tmp_path):
    """No kBot/cBot/WtrDpth: MoorDyn's defaults (3e6 Pa/m, 3e5 Pa s/m, the deepest point);
    g, rho and FricDamp read (FricDamp as the friction's regularisation) or noted."""
    text = deck_text()
    for key in ("kBot", "cBot", "WtrDpth", "WtrDnsty"):
        text = "\n".join(ln for ln in text.splitlines() if key not in ln)
    text = text.replace("0.5                  FrictionCoefficient",
                        "0.3 FrictionCoefficient\n9.81 g\n1020 rho\n200 FricDamp\n7 fancyOption")
    deck = parse_moordyn(text, "x.txt")
    s = load_scene(deck.scene)
    assert (s.seabed.stiffness, s.seabed.damping, s.seabed.friction) == (3.0e6, 3.0e5, 0.3)
    assert (s.environment.depth, s.environment.gravity, s.environment.water_density) == \
        (50.0, 9.81, 1020.0)
    notes = "\n".join(deck.notes)
    assert "fancyOption = 7 ignored" in notes
    # MoorDyn's friction mu FricDamp |v| up to mu N: symcable's regularisation velocity N /
    # FricDamp with N = w ds, the chain's weight per segment (MoorDyn's source, Line.cpp)
    w = (390.0 - 1020.0 * math.pi * 0.252 ** 2 / 4) * 9.81
    assert s.seabed.friction_velocity == pytest.approx(w * 410.0 / 41 / 200.0, rel=1e-12)
    assert "FricDamp = 200 N s/m" in notes
    assert "WtrDpth missing" in notes and "MoorDyn's default 3e+06" in notes


def test_v1_column_names_and_positive_ba(tmp_path):
    text = deck_text().replace("TypeName   Diam    Mass/m     EA         BA/-zeta    EI         "
                               "Cd     Ca     CdAx    CaAx",
                               "Name Diam MassDen EA BA Cdn Can Cdt Cat")
    text = text.replace("-1.0        0          1.37   1.0    0.64    0.0",
                        "2.0e8   1.2  0.8  0.4  0.1")
    lt = load_scene(write(tmp_path, text)).line_types["chain"]
    assert (lt.damping, lt.EI, lt.cd_normal, lt.ca_normal, lt.cd_tangential, lt.ca_tangential) \
        == (2.0e8, 0.0, 1.2, 0.8, math.pi * 0.4, 0.1)


def test_bending_stiffness_is_read(tmp_path):
    """A line type's EI (N m^2) becomes the cable3d line type's EI (bending, moment-free
    ends), and the deck's static state bows less than with EI = 0 nowhere it matters: a
    chain of EI 1e5 N m^2 carries the same fairlead tension within 0.1 % (bending is tiny
    against its weight over 10 m segments)."""
    text = deck_text().replace("-1.0        0 ", "-1.0        1e5 ")
    scene = load_scene(write(tmp_path, text))
    assert scene.line_types["chain"].EI == 1e5
    import symcable as sc
    bent = sc.solve_static(scene, estimate=False, codegen=False).fairlead_tension
    flat = sc.solve_static(load_scene(write(tmp_path, deck_text(), "flat.txt")),
                           estimate=False, codegen=False).fairlead_tension
    assert abs(bent - flat) < 1e-3 * flat


_LINES = "---------------------- LINES"
_POINT3 = "3     Free      200    0.0     -30.0    0      0       0      0"

#: name -> (edit of the WD0050 deck, deck line the error names, fragment of the message)
REFUSALS = {
    # (several lines and free points load since scene version 2: tests/test_cable3d_points.py;
    # a free point no line uses is still refused)
    "free point on no line": (lambda t: t.replace(_LINES, f"{_POINT3}\n{_LINES}"), _POINT3,
                              "point 3 is not on the line"),
    "missing POINTS": (lambda t: t.replace("POINT PROPERTIES", "SOMETHING ELSE"), None,
                       "no POINTS section"),
    "missing LINE TYPES": (lambda t: t.replace("LINE TYPES", "NOTHING"), None,
                           "no LINE TYPES section"),
    "point with mass": (lambda t: t.replace("-50.0    0      0", "-50.0    900    0"),
                        "1     Fixed     400    0.0     -50.0    900", "with mass, volume"),
    "two vessels": (lambda t: t.replace("1     Fixed ", "1     Vessel "),
                    "2     Vessel    0.0", "both ends are vessel points"),
    "body point": (lambda t: t.replace("1     Fixed ", "1     Body1 "), "1     Body1",
                   "point on a body"),
    "rod attachment": (lambda t: t.replace("chain      1        2 ", "chain      R1A      2 "),
                       "1     chain      R1A", "rod end R1A, which RODS (a held rod) does not"),
    "rods": (lambda t: t.replace(_LINES, f"--- RODS ---\nID Type\n(#) (-)\n1 pipe 0 0 0\n{_LINES}"),
             "1 pipe 0 0 0", "a rod needs ID RodType Attachment Xa Ya Za Xb Yb Zb NumSegs"),
    "bathymetry": (lambda t: t.replace("1       disableOutTime", "bathy.txt SeafloorFile"),
                   "bathy.txt SeafloorFile", "a bathymetry file"),
    "nonlinear EA": (lambda t: t.replace("1.674e9 ", "ea.dat  "), "chain      0.252   390",
                     "a nonlinear or viscoelastic EA"),
    "unknown column": (lambda t: t.replace("CaAx", "Wobble"), "TypeName   Diam",
                       "column 'Wobble' unknown"),
    "unattached point": (lambda t: t.replace(_LINES, f"3 Fixed 5 5 -50 0 0 0 0\n{_LINES}"),
                         "3 Fixed 5 5 -50 0 0 0 0", "not on the line"),
    # checks of the scene loader, located on the deck line the key came from
    "negative gravity": (lambda t: t.replace("1       disableOutTime", "-9.81 g"), "-9.81 g",
                         "environment.gravity = -9.81 m/s^2: must be > 0"),
    "out of reach": (lambda t: t.replace("410       41", "300       41"),
                     "2     Vessel    0.0", "end_b.position = [0.0, 0.0, 0.0]: the ends are"),
}


@pytest.mark.parametrize("case", sorted(REFUSALS))
def test_each_refusal_is_one_line_naming_the_deck_line(case, tmp_path):
    edit, line, fragment = REFUSALS[case]
    text = edit(deck_text())
    assert text != deck_text()
    path = write(tmp_path, text)
    with pytest.raises(SceneError) as info:
        load_scene(path)
    msg = str(info.value)
    assert "\n" not in msg and fragment in msg, msg
    assert msg.startswith(str(path))
    if line is not None:
        n = text.splitlines().index(next(ln for ln in text.splitlines() if ln.startswith(line)))
        assert msg.startswith(f"{path}:{n + 1}: {text.splitlines()[n].strip()!r}: "), msg


def test_cli_check_shows_what_was_read(capsys):
    assert main(["check", str(REF / "WD0050_Chain.txt")]) == 0
    out = capsys.readouterr().out
    assert "WD0050_Chain line 1" in out and "model      cable3d" in out
    assert "410.000 m in 41 segments" in out and "EA 1.674e+09 N" in out
    assert "end_a      pinned at (400.000, 0.000, -50.000) m" in out
    assert "deck note  line 26: fileIC = WD0050_Chain.txt.ic ignored" in out
    assert out.rstrip().endswith("ok")


def test_wd0050_statics():
    """The deck as read solves: the fairlead tension is within 2 % of the quasi-static codes'
    991.6 kN in the reference README (measured 1005.6 kN, +1.4 %; MoorPy 1.0.x on the same
    deck, rigid seabed, gives 1002.0 kN, and this scene with kBot 1e7 1001.8 kN: the rest is
    the 0.13 m the chain sinks into a 1e5 Pa/m bed). Fairlead minus anchor tension is the
    submerged weight of the 50 m rise, w h, to the line's stretch (strain 6e-4)."""
    s = load_scene(REF / "WD0050_Chain.txt")
    st = sc.solve_static(s)
    assert st.status == "converged"
    assert st.fairlead_tension == pytest.approx(991.6e3, rel=0.02)
    w = s.line_types["chain"].weight
    assert st.fairlead_tension - st.anchor_tension == pytest.approx(w * 50.0, rel=5e-3)


def test_wd0050_statics_with_a_harmonic_vessel_motion():
    """A harmonic motion added to the vessel point (held in statics) gives the same static
    state, every output packed whole: the friction force's components are structurally zero
    at rest on some nodes there, and its packed outputs came short of their shapes (an
    IndexError from the unpacking; with a vector output last, misaligned values). Same
    solve, so the tensions agree to round-off (1e-9)."""
    plain = sc.solve_static(load_scene(REF / "WD0050_Chain.txt"))
    d = load_scene(REF / "WD0050_Chain.txt").to_dict()
    d["end_b"]["motion"] = {"kind": "harmonic", "amplitude": [0.0, 0.0, 1.0], "period": 10.0}
    moved = sc.solve_static(d)
    assert moved.status == "converged"
    assert moved.fairlead_tension == pytest.approx(plain.fairlead_tension, rel=1e-9)
    assert moved.anchor_tension == pytest.approx(plain.anchor_tension, rel=1e-9)
