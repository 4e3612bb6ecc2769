"""The command line on cable3d scenes: check, simulate, periodic and modes with --json,
--save and --plot (issue 12, item 6), and a scene of several lines in check and modes."""
from __future__ import annotations

import json

import pytest

from symcable.cli.main import main
from symcable.results.line3d import LineTrajectory
from symcable.scene import load_scene, scene_to_toml

from test_cable3d_api import _scene


@pytest.fixture
def scene_file(tmp_path):
    p = tmp_path / "line3d.toml"
    p.write_text(scene_to_toml(load_scene(_scene())))
    return p


def test_cli_simulate_periodic_modes(scene_file, tmp_path, capsys):
    assert main(["check", str(scene_file)]) == 0
    assert "cable3d" in capsys.readouterr().out
    save, plot = tmp_path / "run.npz", tmp_path / "run.png"
    assert main(["simulate", str(scene_file), "--duration", "16", "--save", str(save),
                 "--plot", str(plot)]) == 0
    out = capsys.readouterr().out
    assert "fairlead tension" in out and "kN" in out
    tr = LineTrajectory.load(save)
    assert tr.time[-1] == pytest.approx(16.0) and plot.stat().st_size > 10_000
    assert main(["periodic", str(scene_file), "--method", "shooting", "--json"]) == 0
    d = json.loads(capsys.readouterr().out)
    assert d["method"] == "shooting" and d["status"] == "converged" and d["stats"]["period"] == 8.0
    assert main(["modes", str(scene_file), "--n", "3", "--json", "--plot",
                 str(tmp_path / "modes.png")]) == 0
    d = json.loads(capsys.readouterr().out)
    assert len(d["frequencies"]) == 3 and len(d["shapes"][0][0]) == 3  # (x, y, z) per node
    assert (tmp_path / "modes.png").stat().st_size > 10_000


def test_cli_check_lists_points_and_lines(tmp_path, capsys):
    d = {"model": "cable3d", "environment": {"depth": 50.0},
         "line_types": {"rope": {"mass": 30.0, "diameter": 0.06, "EA": 1e7}},
         "points": {"anchor": {"kind": "fixed", "position": [0.0, 0.0, -50.0]},
                    "buoy": {"kind": "free", "position": [40.0, 0.0, -30.0], "mass": 100.0,
                             "volume": 0.5},
                    "fair": {"kind": "fixed", "position": [80.0, 0.0, -5.0]}},
         "lines": [{"name": "lower", "end_a": "anchor", "end_b": "buoy",
                    "sections": [{"type": "rope", "length": 50.0, "segments": 8}]},
                   {"name": "upper", "end_a": "buoy", "end_b": "fair",
                    "sections": [{"type": "rope", "length": 50.0, "segments": 8}]}]}
    p = tmp_path / "two.toml"
    p.write_text(scene_to_toml(load_scene(d)))
    assert main(["check", str(p)]) == 0
    out = capsys.readouterr().out
    assert "point      buoy: free" in out and "line       upper" in out
    assert main(["modes", str(p), "--n", "2", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["stats"]["lines"] == {"lower": [0, 9],
                                                                      "upper": [9, 18]}
