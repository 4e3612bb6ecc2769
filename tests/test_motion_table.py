"""Prescribed end motion from a table (issue 12, item 4: ``kind = "table"``, ``file``): rows
t x y z [rx ry rz] of the end's displacement from its position, linearly interpolated and
held outside the rows; a relative path is relative to the scene file. cable3d only."""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from symcable.api.cable3d_static import cable3d_mechanism
from symcable.errors import SceneError
from symcable.scene import load_scene, scene_to_toml
from symcable.solvers.equilibrium import solve_equilibrium
from symcable.solvers.integrate import integrate

#: ../shared beside the repository (as CI lays it out): the MoorDyn chain tests' fairlead heave
REF = str(Path(__file__).resolve().parents[2] / "shared" / "reference" / "moordyn-chains"
          / "ZZP1_A1.txt")


def _scene(motion: dict) -> dict:
    return {"model": "cable3d",
            "line_types": {"rope": {"mass": 20.0, "diameter": 0.05, "EA": 1e7}},
            "sections": [{"type": "rope", "length": 80.0, "segments": 12}],
            "end_a": {"condition": "pinned", "position": [0.0, 0.0, -50.0]},
            "end_b": {"condition": "pinned", "position": [40.0, 10.0, -10.0], "motion": motion}}


def _table(tmp_path, rows, name="motion.txt"):
    path = tmp_path / name
    np.savetxt(path, np.asarray(rows, float))
    return path


def test_table_loads_relative_to_the_scene_file(tmp_path):
    rows = [[0.0, 0.0, 0.0, 0.0, 0.1, 0.2, 0.3], [1.0, 0.5, -0.5, 1.0, 0.0, 0.0, 0.0],
            [3.0, 0.0, 0.0, 2.0, 0.0, 0.0, 0.0]]
    _table(tmp_path, rows)
    toml = tmp_path / "scene.toml"
    d = _scene({"kind": "table", "file": "motion.txt"})
    toml.write_text(scene_to_toml(load_scene(dict(d, end_b=dict(
        d["end_b"], motion={"kind": "table", "file": str(tmp_path / "motion.txt")})))))
    text = toml.read_text().replace(str(tmp_path / "motion.txt"), "motion.txt")
    toml.write_text(text)
    s = load_scene(toml)
    m = s.end_b.motion
    assert m.kind == "table" and m.period == 3.0 and len(m.samples) == 3
    assert m.samples[1] == (1.0, 0.5, -0.5, 1.0)  # rotations dropped
    assert m.amplitude == (0.5, 0.5, 2.0)
    assert load_scene(s.to_dict()).end_b.motion == m  # round trip (the absolute path)


@pytest.mark.parametrize("motion, fragment", [
    ({"kind": "table"}, "end_b.motion.file: required key missing"),
    ({"kind": "table", "file": "nowhere.txt"}, "end_b.motion.file = 'nowhere.txt'"),
    ({"kind": "table", "file": "FILE", "period": 10.0}, "end_b.motion.period"),
    ({"kind": "harmonic", "period": 10.0, "amplitude": [1.0, 0.0, 0.0], "file": "FILE"},
     "end_b.motion.file"),
])
def test_table_refusals(tmp_path, motion, fragment):
    path = _table(tmp_path, [[0.0, 0, 0, 0], [1.0, 0, 0, 1.0]])
    motion = {k: (str(path) if v == "FILE" else v) for k, v in motion.items()}
    with pytest.raises(SceneError) as info:
        load_scene(_scene(motion))
    assert fragment in str(info.value) and "\n" not in str(info.value)


def test_table_times_must_increase_and_planar_refuses(tmp_path):
    bad = _table(tmp_path, [[0.0, 0, 0, 0], [0.0, 0, 0, 1.0]], "bad.txt")
    with pytest.raises(SceneError, match="must increase"):
        load_scene(_scene({"kind": "table", "file": str(bad)}))
    good = _table(tmp_path, [[0.0, 0, 0, 0], [1.0, 0, 0, 1.0]])
    planar = {"line_types": {"c": {"mass": 50.0, "diameter": 0.1, "EA": 1e8}},
              "sections": [{"type": "c", "length": 100.0, "segments": 10}],
              "end_a": {"condition": "pinned", "position": [0.0, 0.0]},
              "end_b": {"condition": "pinned", "position": [90.0, 0.0],
                        "motion": {"kind": "table", "file": str(good)}}}
    with pytest.raises(SceneError, match="cable3d"):
        load_scene(planar)


def test_cable3d_end_follows_the_table():
    """The MoorDyn chain tests' fairlead heave (2 m, 10 s; -10 s to 20 s every 0.1 s) drives
    a cable3d end: at every saved step from t = -10 s the end sits at its position plus the
    table's displacement, linearly interpolated (to round-off)."""
    d = _scene({"kind": "table", "file": REF})
    # a chain heavy enough to stay taut (at 20 kg/m the rope goes slack on the downstroke
    # and the step's Newton fails on the snap, with a harmonic heave as with the table:
    # the open snap item of issue 12)
    d["line_types"]["rope"]["mass"] = 100.0
    s = load_scene(d)
    mech = cable3d_mechanism(s)
    eq = solve_equilibrium(mech)
    tr = integrate(mech, 12.0, 0.05, t0=-10.0, start=eq, p=mech.params.values)
    rows = np.loadtxt(REF)
    n = len(tr.time)
    end = np.asarray(tr.outputs["positions"]).reshape(n, -1, 3)[:, -1, :]
    want = np.array([40.0, 10.0, -10.0]) + np.stack(
        [np.interp(tr.time, rows[:, 0], rows[:, c]) for c in (1, 2, 3)], axis=1)
    np.testing.assert_allclose(end, want, atol=1e-12)
