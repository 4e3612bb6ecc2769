"""MoorDyn v2 rods (symcable/scene/moordyn_rods.py): a held rod (Fixed, Coupled, Body<N>)
holds the lines at its ends, which read as points ``R<ID>A``, ``R<ID>B``; a moving rod
(Free, Pinned) is refused in one line naming the deck line and the fix."""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import symcable as sc
from symcable.scene import moordyn_deck
from test_moordyn_bodies import deck as body_deck

REF = Path(__file__).resolve().parents[2] / "shared" / "reference" / "moordyn-chains"

_RODS = """---------------------- ROD TYPES ------------------------------------
TypeName      Diam     Mass/m    Cd     Ca      CdEnd    CaEnd
(name)        (m)      (kg/m)    (-)    (-)     (-)      (-)
spar          2.0      1.0e3     0.6    1.0     1.2      1.0
---------------------- RODS ----------------------------------------
ID   RodType  Attachment  Xa    Ya    Za    Xb    Yb    Zb   NumSegs  RodOutputs
(#)  (name)   (word/ID)   (m)   (m)   (m)   (m)   (m)   (m)  (-)       (-)
{rows}
"""


def _chain_on_rod(tmp_path, attachment: str, end: str = "A") -> Path:
    """WD0050_Chain with its vessel point replaced by the ``end`` end of a rod at the same
    place (a 10 m vertical rod from the point up, or down to it)."""
    text = (REF / "WD0050_Chain.txt").read_text()
    za, zb = (0.0, 10.0) if end == "A" else (-10.0, 0.0)
    rows = f"1    spar     {attachment}       0.0   0.0   {za}   0.0   0.0   {zb}  4        -"
    text = text.replace("2     Vessel    0.0     0.0     0.0     0      0       0      0\n", "")
    text = text.replace("1     chain      1        2         410",
                        f"1     chain      1        R1{end}       410")
    text = text.replace("---------------------- POINT PROPERTIES",
                        _RODS.format(rows=rows) + "---------------------- POINT PROPERTIES")
    path = tmp_path / f"rod_{attachment}_{end}.txt"
    path.write_text(text)
    return path


@pytest.mark.parametrize("attachment,end", [("Coupled", "A"), ("Fixed", "B"), ("Vessel", "A")])
def test_a_held_rod_holds_the_line_where_the_point_was(tmp_path, attachment, end):
    """The line ends at the rod's end, which is where the deck's vessel point was: the same
    scene, so the same static solution, bit for bit (same equations, same start)."""
    got = sc.solve_static(_chain_on_rod(tmp_path, attachment, end))
    want = sc.solve_static(REF / "WD0050_Chain.txt")
    assert got.fairlead_tension == want.fairlead_tension
    np.testing.assert_array_equal(got.positions, want.positions)
    notes = moordyn_deck(_chain_on_rod(tmp_path, attachment, end)).notes
    assert any("rod 1" in n and "not read" in n for n in notes)


def test_a_rod_on_a_body_is_a_pair_of_points_on_it(tmp_path):
    """A Body1 rod whose end R1A sits where the deck had a point on the body (body axes):
    the same static equilibrium of the free body as the deck with the point."""
    text = body_deck()
    with_point = tmp_path / "points.txt"
    with_point.write_text(text)
    # the first fairlead point (ID 2, on Body1 at (5, 0, -5)) becomes rod 1's A end
    lines = text.splitlines()
    k = next(i for i, ln in enumerate(lines) if ln.startswith("2  Body1"))
    x, y, z = lines[k].split()[2:5]
    del lines[k]
    text = "\n".join(lines) + "\n"
    text = text.replace("1  chain  1  2 ", "1  chain  1  R1A ")
    rows = f"1    spar     Body1       {x}   {y}   {z}   {x}   {y}   0.0  4        -"
    text = text.replace("---------------------- POINTS", _RODS.format(rows=rows)
                        + "---------------------- POINTS")
    with_rod = tmp_path / "rod.txt"
    with_rod.write_text(text)
    a, b = sc.solve_static(with_point), sc.solve_static(with_rod)
    # the same equations with the point named R1A instead of 2: agreement to the solver's
    # tolerance (1e-6 of the force scale), far below 1e-6 relative of the body's position
    np.testing.assert_allclose(b.bodies["body1"].position, a.bodies["body1"].position,
                               rtol=0, atol=1e-6)
    assert b.lines["line1"].fairlead_tension == pytest.approx(
        a.lines["line1"].fairlead_tension, rel=1e-6)


@pytest.mark.parametrize("attachment", ["Free", "Pinned", "Body1Pinned", "CoupledPinned"])
def test_a_moving_rod_is_refused_in_one_line(tmp_path, attachment):
    path = _chain_on_rod(tmp_path, attachment)
    with pytest.raises(sc.SceneError) as info:
        sc.load_scene(path)
    msg = str(info.value)
    assert "\n" not in msg and msg.startswith(f"{path}:")
    assert f"a {attachment} rod moves as a rigid body" in msg and "[bodies.NAME]" in msg


@pytest.mark.parametrize("edit,fragment", [
    (lambda t: t.replace("R1A       410", "R1C       410"), "a rod's end is R<ID>A or R<ID>B"),
    (lambda t: t.replace("R1A       410", "R2A       410"), "rod end R2A, which RODS"),
    (lambda t: t.replace("spar     Coupled", "pipe     Coupled"), "unknown rod type 'pipe'"),
    (lambda t: t.replace("spar     Coupled", "spar     Wobbly"), "unknown rod attachment"),
])
def test_bad_rod_rows_are_refused_in_one_line(tmp_path, edit, fragment):
    path = _chain_on_rod(tmp_path, "Coupled")
    path.write_text(edit(path.read_text()))
    with pytest.raises(sc.SceneError, match=fragment.replace("(", r"\(").replace(")", r"\)")
                       .replace("[", r"\[").replace("]", r"\]")):
        sc.load_scene(path)
